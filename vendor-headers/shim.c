/* timbre's Embree shim: the only C in the project. It adapts Embree 3 or 4 to shim.h. */
#include "shim.h"

#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#if defined(TIMBRE_EMBREE4)
#include <embree4/rtcore.h>
#else
#include <embree3/rtcore.h>
#endif

/* Embree's packet layout is structure-of-arrays: field k of lane i of an N-wide packet. */
#define LANE_F(base, k, N, i) (((float *)(base))[(k) * (N) + (i)])
#define LANE_U(base, k, N, i) (((unsigned *)(base))[(k) * (N) + (i)])
enum { ORG_X, ORG_Y, ORG_Z, TNEAR, DIR_X, DIR_Y, DIR_Z, TIME, TFAR, MASK, ID, FLAGS };
enum { NG_X, NG_Y, NG_Z, HIT_U, HIT_V, PRIM_ID, GEOM_ID, INST_ID };

/* Embree >= 4.3 built with instance arrays (the default, and PyPI's embreex build of 4.4) has an
 * instance primitive id after the instance ids, as the last member of RTCHit, RTCHitN and
 * RTCRayQueryContext, and writes it on every query. Headers older than 4.3 (embree4-sys ships
 * 4.2's) or configured without instance arrays lack the field: their structs are then too small
 * for such a library, which would write past them. So, without RTC_GEOMETRY_INSTANCE_ARRAY,
 * timbre leaves room for the field after each of those structs (the 4.3+ layout exactly: the
 * structs' sizes are multiples of their alignment, so the room follows the last member). */
#if defined(TIMBRE_EMBREE4) && !defined(RTC_GEOMETRY_INSTANCE_ARRAY)
#define INST_PRIM_ROOM(N) unsigned inst_prim_room[RTC_MAX_INSTANCE_LEVEL_COUNT][N];
#define INIT_INST_PRIM_ROOM(x) memset((x)->inst_prim_room, 0xFF, sizeof((x)->inst_prim_room))
/* The room is where a 4.3+ library puts instPrimID: right after instID. */
#define ROOM_FOLLOWS_INST_ID(wrapper, inner, member_offset, inst_id)                            \
    _Static_assert(offsetof(wrapper, inst_prim_room) ==                                         \
                       offsetof(wrapper, inner) + (member_offset) + sizeof(inst_id),           \
                   #wrapper ": no room for instPrimID right after instID")
#else
#define INST_PRIM_ROOM(N)
#define INIT_INST_PRIM_ROOM(x) ((void)0)
#define ROOM_FOLLOWS_INST_ID(wrapper, inner, member_offset, inst_id)                            \
    _Static_assert(1, "no room needed")
#endif

/* Ray/hit structs with that room (see INST_PRIM_ROOM). Any other RTCRayHitN a query passes to
 * Embree 4 needs the same (RTCRay alone, as occlusion queries pass, has no hit and needs none). */
typedef struct {
    struct RTCRayHit rh;
    INST_PRIM_ROOM(1)
} RayHit1;
typedef struct {
    struct RTCRayHit8 rh;
    INST_PRIM_ROOM(8)
} RayHit8;
ROOM_FOLLOWS_INST_ID(RayHit1, rh,
                     offsetof(struct RTCRayHit, hit) + offsetof(struct RTCHit, instID),
                     ((struct RTCHit *)0)->instID);
ROOM_FOLLOWS_INST_ID(RayHit8, rh,
                     offsetof(struct RTCRayHit8, hit) + offsetof(struct RTCHit8, instID),
                     ((struct RTCHit8 *)0)->instID);

/* The ray-query context extended with timbre's per-query pointer. */
typedef struct {
#if defined(TIMBRE_EMBREE4)
    struct RTCRayQueryContext base;
    INST_PRIM_ROOM(1)
#else
    struct RTCIntersectContext base;
#endif
    const void *query;
} TimbreContext;
#if defined(TIMBRE_EMBREE4)
ROOM_FOLLOWS_INST_ID(TimbreContext, base, offsetof(struct RTCRayQueryContext, instID),
                     ((struct RTCRayQueryContext *)0)->instID);
#endif

static void init_context(TimbreContext *ctx, const void *query) {
#if defined(TIMBRE_EMBREE4)
    rtcInitRayQueryContext(&ctx->base);
    INIT_INST_PRIM_ROOM(ctx);
#else
    rtcInitIntersectContext(&ctx->base);
#endif
    ctx->query = query;
}

static void read_lane(const void *ray, unsigned N, unsigned i, TimbreRay *out) {
    out->org[0] = LANE_F(ray, ORG_X, N, i);
    out->org[1] = LANE_F(ray, ORG_Y, N, i);
    out->org[2] = LANE_F(ray, ORG_Z, N, i);
    out->dir[0] = LANE_F(ray, DIR_X, N, i);
    out->dir[1] = LANE_F(ray, DIR_Y, N, i);
    out->dir[2] = LANE_F(ray, DIR_Z, N, i);
    out->tnear = LANE_F(ray, TNEAR, N, i);
    out->tfar = LANE_F(ray, TFAR, N, i);
    out->mask = LANE_U(ray, MASK, N, i);
    out->id = LANE_U(ray, ID, N, i);
}

static void user_bounds(const struct RTCBoundsFunctionArguments *args) {
    const TimbreUserGeometry *user = (const TimbreUserGeometry *)args->geometryUserPtr;
    TimbreBounds b;
    user->bounds(user->geometry, args->primID, &b);
    args->bounds_o->lower_x = b.lower[0];
    args->bounds_o->lower_y = b.lower[1];
    args->bounds_o->lower_z = b.lower[2];
    args->bounds_o->upper_x = b.upper[0];
    args->bounds_o->upper_y = b.upper[1];
    args->bounds_o->upper_z = b.upper[2];
}

static void user_intersect(const struct RTCIntersectFunctionNArguments *args) {
    const TimbreUserGeometry *user = (const TimbreUserGeometry *)args->geometryUserPtr;
    const TimbreContext *ctx = (const TimbreContext *)args->context;
    const unsigned N = args->N;
    void *ray = args->rayhit;
    void *hit = (float *)args->rayhit + 12 * N;
    for (unsigned i = 0; i < N; i++) {
        if (args->valid[i] == 0) continue;
        TimbreRay r;
        read_lane(ray, N, i, &r);
        float t;
        if (!user->intersect(user->geometry, args->geomID, args->primID, ctx->query, &r,
                             ctx->base.instID[0], &t))
            continue;
        LANE_F(ray, TFAR, N, i) = t;
        /* timbre recomputes normals in f64; Embree only needs a well-formed hit. */
        LANE_F(hit, NG_X, N, i) = 0.0f;
        LANE_F(hit, NG_Y, N, i) = 0.0f;
        LANE_F(hit, NG_Z, N, i) = 1.0f;
        LANE_F(hit, HIT_U, N, i) = 0.0f;
        LANE_F(hit, HIT_V, N, i) = 0.0f;
        LANE_U(hit, PRIM_ID, N, i) = args->primID;
        LANE_U(hit, GEOM_ID, N, i) = args->geomID;
        LANE_U(hit, INST_ID, N, i) = ctx->base.instID[0];
#if defined(TIMBRE_EMBREE4) && defined(RTC_GEOMETRY_INSTANCE_ARRAY)
        LANE_U(hit, INST_ID + RTC_MAX_INSTANCE_LEVEL_COUNT, N, i) = ctx->base.instPrimID[0];
#endif
    }
}

static void user_occluded(const struct RTCOccludedFunctionNArguments *args) {
    const TimbreUserGeometry *user = (const TimbreUserGeometry *)args->geometryUserPtr;
    const TimbreContext *ctx = (const TimbreContext *)args->context;
    const unsigned N = args->N;
    for (unsigned i = 0; i < N; i++) {
        if (args->valid[i] == 0) continue;
        TimbreRay r;
        read_lane(args->ray, N, i, &r);
        float t;
        if (user->occluded(user->geometry, args->geomID, args->primID, ctx->query, &r,
                            ctx->base.instID[0], &t))
            LANE_F(args->ray, TFAR, N, i) = -INFINITY; /* Embree's "occluded" marker */
    }
}

/* A device with the Rust error sink that Embree reports to. */
typedef struct {
    RTCDevice device;
    TimbreErrorFn on_error;
    void *error_user;
} Device;

static void device_error(void *user, enum RTCError code, const char *message) {
    const Device *d = (const Device *)user;
    if (d->on_error) d->on_error(d->error_user, (int)code, message ? message : "");
}

void *timbre_device_new(const char *config, TimbreErrorFn on_error, void *error_user) {
    Device *d = (Device *)malloc(sizeof(Device));
    if (!d) return NULL;
    d->on_error = on_error;
    d->error_user = error_user;
    d->device = rtcNewDevice(config);
    if (!d->device) {
        /* rtcNewDevice reports through the thread-local error of a NULL device. */
        if (on_error) on_error(error_user, (int)rtcGetDeviceError(NULL), "rtcNewDevice failed");
        free(d);
        return NULL;
    }
    rtcSetDeviceErrorFunction(d->device, device_error, d);
    return d;
}

void timbre_device_release(void *device) {
    Device *d = (Device *)device;
    rtcReleaseDevice(d->device);
    free(d);
}

int timbre_device_ray_masks_supported(void *device) {
    return rtcGetDeviceProperty(((Device *)device)->device, RTC_DEVICE_PROPERTY_RAY_MASK_SUPPORTED) != 0;
}

uint32_t timbre_device_native_packets(void *device) {
    RTCDevice dev = ((Device *)device)->device;
    uint32_t bits = 0;
    if (rtcGetDeviceProperty(dev, RTC_DEVICE_PROPERTY_NATIVE_RAY4_SUPPORTED)) bits |= 4;
    if (rtcGetDeviceProperty(dev, RTC_DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED)) bits |= 8;
    if (rtcGetDeviceProperty(dev, RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED)) bits |= 16;
    return bits;
}

uint32_t timbre_device_version(void *device) {
    return (uint32_t)rtcGetDeviceProperty(((Device *)device)->device, RTC_DEVICE_PROPERTY_VERSION);
}

void *timbre_scene_new(void *device) {
    RTCScene scene = rtcNewScene(((Device *)device)->device);
    if (scene) rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
    return scene;
}

void timbre_scene_release(void *scene) { rtcReleaseScene((RTCScene)scene); }

void timbre_scene_commit(void *scene) { rtcCommitScene((RTCScene)scene); }

static uint32_t attach(RTCScene scene, RTCGeometry geometry, uint32_t mask) {
    rtcSetGeometryMask(geometry, mask);
    rtcCommitGeometry(geometry);
    uint32_t id = rtcAttachGeometry(scene, geometry);
    rtcReleaseGeometry(geometry);
    return id;
}

uint32_t timbre_scene_add_triangles(void *device, void *scene, const float *vertices,
                                    size_t vertex_count, const uint32_t *indices,
                                    size_t triangle_count, uint32_t mask) {
    RTCGeometry g = rtcNewGeometry(((Device *)device)->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    if (!g) return TIMBRE_INVALID_ID;
    /* Embree's own buffers are padded so that the last vertex can be read with a 16-byte load. */
    float *v = (float *)rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                3 * sizeof(float), vertex_count);
    uint32_t *ix = (uint32_t *)rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                       3 * sizeof(uint32_t), triangle_count);
    if (!v || !ix) {
        rtcReleaseGeometry(g);
        return TIMBRE_INVALID_ID;
    }
    memcpy(v, vertices, 3 * sizeof(float) * vertex_count);
    memcpy(ix, indices, 3 * sizeof(uint32_t) * triangle_count);
    return attach((RTCScene)scene, g, mask);
}

uint32_t timbre_scene_add_user(void *device, void *scene, uint32_t prim_count,
                               const TimbreUserGeometry *user, uint32_t mask) {
    RTCGeometry g = rtcNewGeometry(((Device *)device)->device, RTC_GEOMETRY_TYPE_USER);
    if (!g) return TIMBRE_INVALID_ID;
    rtcSetGeometryUserPrimitiveCount(g, prim_count);
    rtcSetGeometryUserData(g, (void *)user);
    rtcSetGeometryBoundsFunction(g, user_bounds, NULL);
    rtcSetGeometryIntersectFunction(g, user_intersect);
    rtcSetGeometryOccludedFunction(g, user_occluded);
    return attach((RTCScene)scene, g, mask);
}

uint32_t timbre_scene_add_instance(void *device, void *scene, void *instanced_scene,
                                   const float *translation, uint32_t mask) {
    RTCGeometry g = rtcNewGeometry(((Device *)device)->device, RTC_GEOMETRY_TYPE_INSTANCE);
    if (!g) return TIMBRE_INVALID_ID;
    rtcSetGeometryInstancedScene(g, (RTCScene)instanced_scene);
    rtcSetGeometryTimeStepCount(g, 1);
    /* RTC_FORMAT_FLOAT3X4_ROW_MAJOR: the 3x4 matrix [I | t] row by row. */
    const float transform[12] = {1, 0, 0, translation[0], 0, 1, 0, translation[1],
                                 0, 0, 1, translation[2]};
    rtcSetGeometryTransform(g, 0, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, transform);
    return attach((RTCScene)scene, g, mask);
}

static void to_embree_ray(const TimbreRay *r, struct RTCRay *out) {
    out->org_x = r->org[0];
    out->org_y = r->org[1];
    out->org_z = r->org[2];
    out->dir_x = r->dir[0];
    out->dir_y = r->dir[1];
    out->dir_z = r->dir[2];
    out->tnear = r->tnear;
    out->tfar = r->tfar;
    out->time = 0.0f;
    out->mask = r->mask;
    out->id = r->id;
    out->flags = 0;
}

void timbre_intersect1(void *scene, const void *query, const TimbreRay *ray, TimbreHit *hit) {
    TimbreContext ctx;
    init_context(&ctx, query);
    RayHit1 padded;
    INIT_INST_PRIM_ROOM(&padded);
    struct RTCRayHit *rh = &padded.rh;
    to_embree_ray(ray, &rh->ray);
    rh->hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh->hit.primID = RTC_INVALID_GEOMETRY_ID;
    rh->hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
#if defined(TIMBRE_EMBREE4)
    struct RTCIntersectArguments args;
    rtcInitIntersectArguments(&args);
    args.context = &ctx.base;
    rtcIntersect1((RTCScene)scene, rh, &args);
#else
    rtcIntersect1((RTCScene)scene, &ctx.base, rh);
#endif
    hit->t = rh->ray.tfar;
    hit->geom_id = rh->hit.geomID;
    hit->prim_id = rh->hit.primID;
    hit->inst_id = rh->hit.instID[0];
}

int timbre_occluded1(void *scene, const void *query, const TimbreRay *ray) {
    TimbreContext ctx;
    init_context(&ctx, query);
    struct RTCRay r;
    to_embree_ray(ray, &r);
#if defined(TIMBRE_EMBREE4)
    struct RTCOccludedArguments args;
    rtcInitOccludedArguments(&args);
    args.context = &ctx.base;
    rtcOccluded1((RTCScene)scene, &r, &args);
#else
    rtcOccluded1((RTCScene)scene, &ctx.base, &r);
#endif
    return r.tfar < 0.0f;
}

/* Fills an 8-wide packet (structure of arrays) and its valid mask from timbre's rays. */
static void to_embree_packet8(const int *valid, const TimbreRay *rays, int *valid8,
                              struct RTCRay8 *out) {
    for (unsigned i = 0; i < 8; i++) {
        const TimbreRay *r = &rays[i];
        valid8[i] = valid[i] ? -1 : 0;
        out->org_x[i] = r->org[0];
        out->org_y[i] = r->org[1];
        out->org_z[i] = r->org[2];
        out->dir_x[i] = r->dir[0];
        out->dir_y[i] = r->dir[1];
        out->dir_z[i] = r->dir[2];
        out->tnear[i] = r->tnear;
        out->tfar[i] = r->tfar;
        out->time[i] = 0.0f;
        out->mask[i] = r->mask;
        out->id[i] = r->id;
        out->flags[i] = 0;
    }
}

/* Embree's hint for a packet: coherent (neighbouring rays, traversed together with frustum
 * culling) or not. */
#if defined(TIMBRE_EMBREE4)
#define PACKET_FLAGS(coherent) \
    ((coherent) ? RTC_RAY_QUERY_FLAG_COHERENT : RTC_RAY_QUERY_FLAG_INCOHERENT)
#else
#define PACKET_FLAGS(coherent) \
    ((coherent) ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT)
#endif

void timbre_intersect8(void *scene, const void *query, const int *valid, const TimbreRay *rays,
                       int coherent, TimbreHit *hits) {
    TimbreContext ctx;
    init_context(&ctx, query);
    /* Embree requires the packet and its valid mask to be 32-byte aligned. */
    _Alignas(32) RayHit8 padded;
    INIT_INST_PRIM_ROOM(&padded);
    struct RTCRayHit8 *rh = &padded.rh;
    _Alignas(32) int valid8[8];
    to_embree_packet8(valid, rays, valid8, &rh->ray);
    for (unsigned i = 0; i < 8; i++) {
        rh->hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
        rh->hit.primID[i] = RTC_INVALID_GEOMETRY_ID;
        rh->hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
    }
#if defined(TIMBRE_EMBREE4)
    struct RTCIntersectArguments args;
    rtcInitIntersectArguments(&args);
    args.context = &ctx.base;
    args.flags = PACKET_FLAGS(coherent);
    rtcIntersect8(valid8, (RTCScene)scene, rh, &args);
#else
    ctx.base.flags = PACKET_FLAGS(coherent);
    rtcIntersect8(valid8, (RTCScene)scene, &ctx.base, rh);
#endif
    for (unsigned i = 0; i < 8; i++) {
        hits[i].t = rh->ray.tfar[i];
        hits[i].geom_id = valid[i] ? rh->hit.geomID[i] : TIMBRE_INVALID_ID;
        hits[i].prim_id = rh->hit.primID[i];
        hits[i].inst_id = rh->hit.instID[0][i];
    }
}

void timbre_occluded8(void *scene, const void *query, const int *valid, const TimbreRay *rays,
                      int coherent, int *occluded) {
    TimbreContext ctx;
    init_context(&ctx, query);
    _Alignas(32) struct RTCRay8 r;
    _Alignas(32) int valid8[8];
    to_embree_packet8(valid, rays, valid8, &r);
#if defined(TIMBRE_EMBREE4)
    struct RTCOccludedArguments args;
    rtcInitOccludedArguments(&args);
    args.context = &ctx.base;
    args.flags = PACKET_FLAGS(coherent);
    rtcOccluded8(valid8, (RTCScene)scene, &r, &args);
#else
    ctx.base.flags = PACKET_FLAGS(coherent);
    rtcOccluded8(valid8, (RTCScene)scene, &ctx.base, &r);
#endif
    for (unsigned i = 0; i < 8; i++) occluded[i] = valid[i] && r.tfar[i] < 0.0f;
}
