/* timbre's neutral interface to Embree. bindgen reads only this header; no Embree type or
 * struct layout appears here, so the Rust side is independent of the Embree major version. */
#ifndef TIMBRE_SHIM_H
#define TIMBRE_SHIM_H

#include <stddef.h>
#include <stdint.h>

/* Axis-aligned box in single precision, as Embree's BVH stores it. */
typedef struct {
    float lower[3];
    float upper[3];
} TimbreBounds;

/* One ray as Embree sees it (f32). `id` indexes the caller's per-ray data. */
typedef struct {
    float org[3];
    float dir[3];
    float tnear;
    float tfar;
    uint32_t mask;
    uint32_t id;
} TimbreRay;

/* The nearest hit Embree found; geom_id is TIMBRE_INVALID_ID for a miss. */
typedef struct {
    float t;
    uint32_t geom_id;
    uint32_t prim_id;
    uint32_t inst_id;
} TimbreHit;

#define TIMBRE_INVALID_ID 0xFFFFFFFFu

/* Callbacks into Rust. `geometry` is the user pointer given to timbre_scene_add_user,
 * `query` the pointer given to the ray query; `ray` is the ray in the user geometry's own
 * space; inside an instance it differs from the query's ray and `inst_id` is the instance's
 * geometry id in the top-level scene (else TIMBRE_INVALID_ID). */
typedef void (*TimbreBoundsFn)(const void *geometry, uint32_t prim, TimbreBounds *out);
/* Returns 1 and writes *t when the primitive is hit at tnear < t < tfar. */
typedef int (*TimbreIntersectFn)(const void *geometry, uint32_t geom_id, uint32_t prim,
                                 const void *query, const TimbreRay *ray, uint32_t inst_id,
                                 float *t);

/* A user geometry: its callbacks and the Rust object they receive as `geometry`. */
typedef struct {
    const void *geometry;
    TimbreBoundsFn bounds;
    TimbreIntersectFn intersect;
    TimbreIntersectFn occluded;
} TimbreUserGeometry;

typedef void (*TimbreErrorFn)(void *user, int code, const char *message);

/* Device */
void *timbre_device_new(const char *config, TimbreErrorFn on_error, void *error_user);
void timbre_device_release(void *device);
/* 1 when Embree was built with ray masks, which timbre needs for shadow rays. */
int timbre_device_ray_masks_supported(void *device);
/* Bit set of natively supported packet widths: 4, 8, 16 (bit value = width). */
uint32_t timbre_device_native_packets(void *device);
/* Version of the loaded Embree library as major * 10000 + minor * 100 + patch. */
uint32_t timbre_device_version(void *device);

/* Scenes. Geometry functions return the geometry id, or TIMBRE_INVALID_ID on error. */
void *timbre_scene_new(void *device);
void timbre_scene_release(void *scene);
void timbre_scene_commit(void *scene);
uint32_t timbre_scene_add_triangles(void *device, void *scene, const float *vertices,
                                    size_t vertex_count, const uint32_t *indices,
                                    size_t triangle_count, uint32_t mask);
/* `user` must outlive the scene; Embree hands it back to the callbacks. */
uint32_t timbre_scene_add_user(void *device, void *scene, uint32_t prim_count,
                               const TimbreUserGeometry *user, uint32_t mask);
/* An instance of `instanced_scene` translated by `translation` (x, y, z). */
uint32_t timbre_scene_add_instance(void *device, void *scene, void *instanced_scene,
                                   const float *translation, uint32_t mask);

/* Queries. `query` is passed unchanged to the user-geometry callbacks. */
void timbre_intersect1(void *scene, const void *query, const TimbreRay *ray, TimbreHit *hit);
int timbre_occluded1(void *scene, const void *query, const TimbreRay *ray);
/* Packet of 8 rays; lanes with valid[i] == 0 are ignored and get a miss. `coherent` != 0 traces
 * it with Embree's coherent-traversal hint. */
void timbre_intersect8(void *scene, const void *query, const int *valid, const TimbreRay *rays,
                       int coherent, TimbreHit *hits);
/* Occlusion of a packet of 8 rays: occluded[i] is 1 where lane i is blocked (0 where invalid);
 * `coherent` as for timbre_intersect8. */
void timbre_occluded8(void *scene, const void *query, const int *valid, const TimbreRay *rays,
                      int coherent, int *occluded);

#endif
