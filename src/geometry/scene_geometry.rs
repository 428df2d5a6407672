//! The scene's ray–geometry queries: [`SceneGeometry`] puts the bounded shapes into one Embree
//! BVH (analytic shapes as user geometry, meshes as native triangles; arrays as instances of a
//! shared prototype), tests unbounded planes directly, and recomputes Embree's f32 hits in f64.

use std::ops::Range;
use std::sync::Arc;

use glam::DVec3;

use super::{AnalyticShape, Interaction, Shape};
use crate::embree::{self, Bounds, Device, EmbreeError, ExactRay, UserGeometry};
use crate::math::Ray;

/// Embree silently drops primitives whose bounds reach beyond about ±1.8e18, so shapes that
/// extend beyond this are intersected directly, like the unbounded planes.
const EMBREE_EXTENT: f64 = 1e18;

/// Largest coordinate magnitude of `shape` moved by any of `offsets`, or `None` if unbounded.
fn extent(shape: &Shape, offsets: &[DVec3]) -> Option<f64> {
    let (lo, hi) = shape.bounds()?;
    let reach = lo.abs().max(hi.abs()).max_element();
    let furthest = offsets
        .iter()
        .map(|o| o.abs().max_element())
        .fold(0.0, f64::max);
    Some(reach + furthest)
}

/// Ray masks: every object is visible; shadow rays only see shadow-throwing objects.
const VISIBLE: u32 = 1;
const SHADOW_THROWING: u32 = 2;

/// The nearest intersection of a ray with the scene.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hit {
    /// Index of the object (in the order given to [`SceneGeometry::build`]).
    pub object: usize,
    /// Which copy of an object in an array was hit (index into the array's offsets; 0 for
    /// objects in no array).
    pub element: u32,
    /// Primitive within the object: a mesh's triangle, or the part of an analytic shape
    /// (a face, a piece of a CSG solid; 0 for shapes of one part).
    pub prim: u32,
    /// Distance along the ray direction.
    pub t: f64,
}

/// Objects repeated at translations: element k of each member is the member's shape moved by
/// `offsets[k]`. Traced as Embree instances of one shared BVH holding the members once.
#[derive(Debug, Clone, PartialEq)]
pub struct ObjectArray {
    /// The members: a range of object indices.
    pub objects: Range<usize>,
    pub offsets: Vec<DVec3>,
}

/// Analytic shapes registered with Embree as one user geometry (one primitive per shape).
struct AnalyticGroup {
    shapes: Arc<[Shape]>,
    members: Vec<usize>,
    /// Added to every bound: instances see the ray through an f32-rounded translation.
    pad: f64,
}

impl UserGeometry for AnalyticGroup {
    fn primitive_count(&self) -> u32 {
        self.members.len() as u32
    }

    fn bounds(&self, prim: u32) -> Bounds {
        let (lo, hi) = self.shapes[self.members[prim as usize]]
            .bounds()
            .expect("only bounded shapes are put in Embree");
        Bounds::enclosing(lo - self.pad, hi + self.pad)
    }

    fn intersect(&self, prim: u32, ray: &ExactRay, t_near: f64, t_far: f64) -> Option<(f64, u32)> {
        self.shapes[self.members[prim as usize]].intersect(ray.origin, ray.direction, t_near, t_far)
    }
}

/// What an Embree geometry id stands for.
enum Geometry {
    /// User geometry: primitive i is object `members[i]`.
    Analytic(Vec<usize>),
    /// Native triangles of one mesh object.
    Mesh(usize),
    /// Element `element` of array `array`.
    Instance { array: usize, element: u32 },
}

/// The geometry of one Embree scene (the top level, or an array's shared prototype) and the
/// table from its geometry ids to objects.
struct Level {
    bvh: Arc<embree::Scene>,
    geometries: Vec<Geometry>,
}

/// Adds `members` (bounded, fitting in Embree) to `builder`: meshes as native triangles,
/// analytic shapes as one user geometry per shadow flag; records them in `geometries`.
fn add_objects(
    builder: &mut embree::SceneBuilder,
    geometries: &mut Vec<Geometry>,
    shapes: &Arc<[Shape]>,
    shadow_throwing: &[bool],
    members: impl Iterator<Item = usize>,
    pad: f64,
) -> Result<(), EmbreeError> {
    let mut analytic: [Vec<usize>; 2] = Default::default();
    for i in members {
        match &shapes[i] {
            Shape::TriangleMesh(m) => {
                let vertices: Vec<_> = m.vertices().iter().map(|v| v.as_vec3()).collect();
                let id =
                    builder.add_triangles(&vertices, m.triangles(), mask(shadow_throwing[i]))?;
                set_geometry(geometries, id, Geometry::Mesh(i));
            }
            _ => analytic[shadow_throwing[i] as usize].push(i),
        }
    }
    for (shadow, members) in analytic.into_iter().enumerate() {
        if members.is_empty() {
            continue;
        }
        let group = AnalyticGroup {
            shapes: shapes.clone(),
            members: members.clone(),
            pad,
        };
        let id = builder.add_user(Box::new(group), mask(shadow == 1))?;
        set_geometry(geometries, id, Geometry::Analytic(members));
    }
    Ok(())
}

fn mask(shadow_throwing: bool) -> u32 {
    VISIBLE | (SHADOW_THROWING * shadow_throwing as u32)
}

/// All objects of a scene, ready for ray queries from many threads.
pub struct SceneGeometry {
    shapes: Arc<[Shape]>,
    shadow_throwing: Vec<bool>,
    arrays: Vec<ObjectArray>,
    /// The array each object belongs to, if any.
    array_of: Vec<Option<usize>>,
    /// (object, element) pairs not in the BVH (unbounded planes, enormous shapes), tested on
    /// every query.
    unbounded: Vec<(usize, u32)>,
    top: Level,
    /// Each array's prototype (`None` when none of its members is in Embree).
    prototypes: Vec<Option<Level>>,
    /// Whether the BVH holds triangles, whose hits Embree decides in f32.
    has_meshes: bool,
}

impl SceneGeometry {
    /// Builds the BVH over `objects` (shape, shadow-throwing), with the members of each of
    /// `arrays` repeated at its offsets as Embree instances.
    ///
    /// # Panics
    /// If an array's object range reaches beyond `objects` or overlaps another array's.
    pub fn build(
        device: &Device,
        objects: Vec<(Shape, bool)>,
        arrays: Vec<ObjectArray>,
    ) -> Result<SceneGeometry, EmbreeError> {
        let shadow_throwing: Vec<bool> = objects.iter().map(|o| o.1).collect();
        let shapes: Arc<[Shape]> = objects.into_iter().map(|o| o.0).collect();
        let mut array_of = vec![None; shapes.len()];
        for (a, array) in arrays.iter().enumerate() {
            for slot in &mut array_of[array.objects.clone()] {
                assert!(slot.is_none(), "object in two arrays");
                *slot = Some(a);
            }
        }
        let fits = |i: usize, offsets: &[DVec3]| {
            extent(&shapes[i], offsets).is_some_and(|e| e <= EMBREE_EXTENT)
        };

        let mut unbounded = Vec::new();
        let mut prototypes = Vec::with_capacity(arrays.len());
        let mut builder = device.scene_builder()?;
        let mut top_geometries = Vec::new();
        for (a, array) in arrays.iter().enumerate() {
            let (inside, outside): (Vec<usize>, Vec<usize>) = array
                .objects
                .clone()
                .partition(|&i| fits(i, &array.offsets));
            for i in outside {
                unbounded.extend((0..array.offsets.len() as u32).map(|k| (i, k)));
            }
            if inside.is_empty() || array.offsets.is_empty() {
                prototypes.push(None);
                continue;
            }
            // Instances see the ray through an f32 translation: pad the analytic bounds by a
            // few f32 steps of the largest coordinate involved.
            let reach = inside
                .iter()
                .filter_map(|&i| extent(&shapes[i], &array.offsets));
            let pad = 1e-6 * (1.0 + reach.fold(0.0, f64::max));
            let mut proto = device.scene_builder()?;
            let mut geometries = Vec::new();
            add_objects(
                &mut proto,
                &mut geometries,
                &shapes,
                &shadow_throwing,
                inside.iter().copied(),
                pad,
            )?;
            let bvh = Arc::new(proto.commit()?);
            let instance_mask = mask(inside.iter().any(|&i| shadow_throwing[i]));
            for (k, &offset) in array.offsets.iter().enumerate() {
                let id = builder.add_instance(bvh.clone(), offset, instance_mask)?;
                let element = k as u32;
                set_geometry(
                    &mut top_geometries,
                    id,
                    Geometry::Instance { array: a, element },
                );
            }
            prototypes.push(Some(Level { bvh, geometries }));
        }
        let (inside, outside): (Vec<usize>, Vec<usize>) = (0..shapes.len())
            .filter(|&i| array_of[i].is_none())
            .partition(|&i| fits(i, &[]));
        unbounded.extend(outside.into_iter().map(|i| (i, 0)));
        add_objects(
            &mut builder,
            &mut top_geometries,
            &shapes,
            &shadow_throwing,
            inside.into_iter(),
            0.0,
        )?;
        let has_meshes = std::iter::once(&top_geometries)
            .chain(prototypes.iter().flatten().map(|p| &p.geometries))
            .flatten()
            .any(|g| matches!(g, Geometry::Mesh(_)));
        Ok(SceneGeometry {
            shapes,
            shadow_throwing,
            arrays,
            array_of,
            unbounded,
            top: Level {
                bvh: Arc::new(builder.commit()?),
                geometries: top_geometries,
            },
            prototypes,
            has_meshes,
        })
    }

    pub fn shapes(&self) -> &[Shape] {
        &self.shapes
    }

    pub fn arrays(&self) -> &[ObjectArray] {
        &self.arrays
    }

    /// The translation of `element` of `object` (zero for objects in no array).
    pub fn offset(&self, object: usize, element: u32) -> DVec3 {
        self.array_of[object].map_or(DVec3::ZERO, |a| self.arrays[a].offsets[element as usize])
    }

    /// Where `ray` meets the scene at `hit`, for the object's surface law.
    pub fn interaction(&self, ray: Ray, hit: Hit) -> Interaction<'_> {
        Interaction {
            ray,
            hit,
            shape: &self.shapes[hit.object],
            offset: self.offset(hit.object, hit.element),
        }
    }

    /// Turns Embree's hit into an exact f64 hit.
    fn resolve(&self, raw: embree::RawHit, origin: DVec3, direction: DVec3, t_min: f64) -> Hit {
        let (geometries, element) = match raw.inst_id {
            Some(i) => match self.top.geometries[i as usize] {
                Geometry::Instance { array, element } => (
                    &self.prototypes[array]
                        .as_ref()
                        .expect("instances have a prototype")
                        .geometries,
                    element,
                ),
                _ => unreachable!("instance ids name instances"),
            },
            None => (&self.top.geometries, 0),
        };
        let (object, prim) = match &geometries[raw.geom_id as usize] {
            Geometry::Analytic(members) => (members[raw.prim_id as usize], raw.part),
            Geometry::Mesh(object) => (*object, raw.prim_id),
            Geometry::Instance { .. } => unreachable!("Embree reports the instanced geometry"),
        };
        let t = if raw.exact {
            raw.t
        } else {
            // Recompute near Embree's f32 distance; a grazing hit that f64 just misses keeps
            // the f32 distance (triangles: the distance to the triangle's plane).
            let shape = &self.shapes[object];
            let origin = origin - self.offset(object, element);
            let window = 1e-4 * (1.0 + raw.t.abs());
            let exact = shape.intersect_primitive(
                prim,
                origin,
                direction,
                (raw.t - window).max(t_min),
                f64::INFINITY,
            );
            let on_plane = || match shape {
                Shape::TriangleMesh(m) => m.plane_distance(prim, origin, direction),
                _ => None,
            };
            exact.or_else(on_plane).unwrap_or(raw.t)
        };
        Hit {
            object,
            element,
            prim,
            t,
        }
    }

    /// Nearest hit on any object with t_min < t < t_max.
    pub fn nearest(&self, origin: DVec3, direction: DVec3, t_min: f64, t_max: f64) -> Option<Hit> {
        if !embree_can_trace(origin) {
            return self.brute_force(origin, direction, t_min, t_max, false);
        }
        let ray = ExactRay { origin, direction };
        let raw = self.top.bvh.intersect(&ray, t_min, t_max, VISIBLE);
        self.complete(raw, &ray, t_min, t_max)
    }

    /// Resolves Embree's nearest hit (`raw`, found with `mask`) in f64 and keeps it only inside
    /// (t_min, t_max). Embree sees t_min and t_max rounded to f32 and decides triangle hits in
    /// f32, so a hit may fall outside the interval once recomputed: beyond t_max nothing is
    /// nearer, so there is no hit; at or before t_min (a ray leaving a triangle at a grazing
    /// angle finds that triangle again) the query continues beyond Embree's distance.
    fn first_hit(
        &self,
        mut raw: Option<embree::RawHit>,
        ray: &ExactRay,
        t_min: f64,
        t_max: f64,
        mask: u32,
    ) -> Option<Hit> {
        loop {
            let r = raw?;
            let hit = self.resolve(r, ray.origin, ray.direction, t_min);
            if hit.t > t_min && hit.t < t_max {
                return Some(hit);
            }
            let beyond = (r.t as f32).next_up() as f64;
            if hit.t >= t_max || beyond >= t_max {
                return None;
            }
            raw = self.top.bvh.intersect(ray, beyond.max(t_min), t_max, mask);
        }
    }

    /// Nearest hit of (object, element) with t_min < t < t_max, intersected directly.
    #[inline]
    fn intersect_element(
        &self,
        (object, element): (usize, u32),
        ray: &ExactRay,
        t_min: f64,
        t_max: f64,
    ) -> Option<Hit> {
        let origin = ray.origin - self.offset(object, element);
        let hit = match &self.shapes[object] {
            // Inlined: the usual unbounded shape, which every ray tests.
            Shape::Plane(p) => p.intersect(origin, ray.direction, t_min, t_max),
            s => s.intersect(origin, ray.direction, t_min, t_max),
        };
        hit.map(|(t, prim)| Hit {
            object,
            element,
            prim,
            t,
        })
    }

    /// Resolves Embree's hit in f64 and lets the unbounded objects compete with it.
    fn complete(
        &self,
        raw: Option<embree::RawHit>,
        ray: &ExactRay,
        t_min: f64,
        t_max: f64,
    ) -> Option<Hit> {
        let mut best = self.first_hit(raw, ray, t_min, t_max, VISIBLE);
        for &e in &self.unbounded {
            let t_max = best.map_or(t_max, |h| h.t);
            best = self.intersect_element(e, ray, t_min, t_max).or(best);
        }
        best
    }

    /// Nearest hits of up to 8 rays from a common origin (primary rays of neighbouring pixels),
    /// as [`Self::nearest_packet`].
    pub fn nearest8(
        &self,
        origin: DVec3,
        directions: &[DVec3],
        t_min: f64,
        t_max: f64,
    ) -> [Option<Hit>; 8] {
        let n = directions.len().min(8);
        let rays: [ExactRay; 8] = std::array::from_fn(|i| ExactRay {
            origin,
            direction: directions.get(i).copied().unwrap_or(DVec3::Z),
        });
        self.nearest_packet(&rays[..n], t_min, t_max)
    }

    /// Nearest hits of up to 8 rays traced as one Embree packet (nearby rays: neighbouring
    /// pixels, a finite aperture's samples); entries beyond `rays.len()` are `None`.
    pub fn nearest_packet(&self, rays: &[ExactRay], t_min: f64, t_max: f64) -> [Option<Hit>; 8] {
        let rays = &rays[..rays.len().min(8)];
        if !rays.iter().all(|r| embree_can_trace(r.origin)) {
            return std::array::from_fn(|i| {
                let r = rays.get(i)?;
                self.nearest(r.origin, r.direction, t_min, t_max)
            });
        }
        let raw = self.top.bvh.intersect8(rays, t_min, t_max, VISIBLE);
        let mut hits = [None; 8];
        for ((hit, r), &raw) in hits.iter_mut().zip(rays).zip(&raw) {
            *hit = self.complete(raw, r, t_min, t_max);
        }
        hits
    }

    /// Whether a shadow-throwing object lies on the ray with t_min < t < t_max.
    #[inline]
    pub fn shadowed(&self, origin: DVec3, direction: DVec3, t_min: f64, t_max: f64) -> bool {
        if !embree_can_trace(origin) {
            return self
                .brute_force(origin, direction, t_min, t_max, true)
                .is_some();
        }
        let ray = ExactRay { origin, direction };
        self.unbounded_blocks(&ray, t_min, t_max)
            || (self.top.bvh.occluded(&ray, t_min, t_max, SHADOW_THROWING)
                && self.confirmed(&ray, t_min, t_max))
    }

    /// [`Self::shadowed`] of up to 8 segments (ray, t_min, t_max), the BVH's part traced as one
    /// Embree packet (shadow rays of neighbouring pixels); lanes beyond `segments.len()` are
    /// false.
    pub fn shadowed8(&self, segments: &[(ExactRay, f64, f64)]) -> [bool; 8] {
        let segments = &segments[..segments.len().min(8)];
        let mut blocked = [false; 8];
        // The lanes left to the BVH, their rays and intervals.
        let (mut lanes, mut n) = ([0; 8], 0);
        let (mut rays, mut intervals) = ([ExactRay::PLACEHOLDER; 8], [(0.0, 0.0); 8]);
        for (i, &(ray, t_min, t_max)) in segments.iter().enumerate() {
            if !embree_can_trace(ray.origin) {
                blocked[i] = self
                    .brute_force(ray.origin, ray.direction, t_min, t_max, true)
                    .is_some();
            } else if self.unbounded_blocks(&ray, t_min, t_max) {
                blocked[i] = true;
            } else {
                (lanes[n], rays[n], intervals[n]) = (i, ray, (t_min, t_max));
                n += 1;
            }
        }
        if n > 0 {
            let occluded = self
                .top
                .bvh
                .occluded8(&rays[..n], &intervals[..n], SHADOW_THROWING);
            for k in 0..n {
                let (t_min, t_max) = intervals[k];
                blocked[lanes[k]] = occluded[k] && self.confirmed(&rays[k], t_min, t_max);
            }
        }
        blocked
    }

    /// Whether a shadow-throwing object outside the BVH lies on the ray with t_min < t < t_max.
    fn unbounded_blocks(&self, ray: &ExactRay, t_min: f64, t_max: f64) -> bool {
        self.unbounded.iter().any(|&e| {
            self.shadow_throwing[e.0] && self.intersect_element(e, ray, t_min, t_max).is_some()
        })
    }

    /// Confirms an occlusion Embree reported on the segment. User-geometry callbacks decide
    /// exactly in f64; triangles are decided in f32 (see `first_hit`), so with meshes an
    /// any-hit is confirmed by an exact nearest-hit query.
    fn confirmed(&self, ray: &ExactRay, t_min: f64, t_max: f64) -> bool {
        !self.has_meshes || {
            let raw = self.top.bvh.intersect(ray, t_min, t_max, SHADOW_THROWING);
            self.first_hit(raw, ray, t_min, t_max, SHADOW_THROWING)
                .is_some()
        }
    }

    /// Reference intersector: a plain f64 loop over all objects and array elements, for tests.
    pub fn nearest_brute_force(
        &self,
        origin: DVec3,
        direction: DVec3,
        t_min: f64,
        t_max: f64,
    ) -> Option<Hit> {
        self.brute_force(origin, direction, t_min, t_max, false)
    }

    /// Nearest hit by a plain f64 loop over all objects (only the shadow-throwing ones when
    /// `shadow_only`) and array elements.
    fn brute_force(
        &self,
        origin: DVec3,
        direction: DVec3,
        t_min: f64,
        t_max: f64,
        shadow_only: bool,
    ) -> Option<Hit> {
        let ray = ExactRay { origin, direction };
        let mut best: Option<Hit> = None;
        for object in (0..self.shapes.len()).filter(|&i| !shadow_only || self.shadow_throwing[i]) {
            let elements = self.array_of[object].map_or(1, |a| self.arrays[a].offsets.len());
            for element in 0..elements as u32 {
                let t_max = best.map_or(t_max, |h| h.t);
                best = self
                    .intersect_element((object, element), &ray, t_min, t_max)
                    .or(best);
            }
        }
        best
    }
}

/// Embree rejects rays whose origin lies beyond about ±1.8e18 (Debian's build aborts the process
/// on an assertion); such rays (e.g. from a grazing hit on a distant plane) are traced by brute
/// force.
fn embree_can_trace(origin: DVec3) -> bool {
    origin.abs().max_element() <= EMBREE_EXTENT
}

fn set_geometry(geometries: &mut Vec<Geometry>, id: u32, g: Geometry) {
    let id = id as usize;
    while geometries.len() <= id {
        geometries.push(Geometry::Analytic(Vec::new()));
    }
    geometries[id] = g;
}
