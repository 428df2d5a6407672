//! Safe binding to Intel Embree through timbre's C shim (`vendor-headers/shim.{h,c}`).
//!
//! This module is the only place in timbre with `unsafe` code (the crate denies `unsafe_code`
//! everywhere else). Embree builds the BVH and traverses it in single precision; timbre's
//! analytic shapes are Embree *user geometry* whose intersection callbacks are the Rust
//! [`UserGeometry`] trait, evaluated in f64 on the exact ray.
//!
//! A committed [`Scene`] is immutable and shared by all render threads; queries are `&self`.
//!
//! # Callbacks never unwind into C
//!
//! Embree calls back into Rust: a user geometry's [`UserGeometry::bounds`] while a scene is
//! committed (possibly on Embree's own build threads), its [`UserGeometry::intersect`] during
//! every query (on the querying thread), and the device's error callback from any Embree call.
//! A panic must never unwind into Embree's C frames: that would be undefined behaviour, which
//! Rust prevents by aborting the whole process when a panic reaches the end of an `extern "C"`
//! function. So every callback runs its Rust code inside [`std::panic::catch_unwind`], and on a
//! panic
//!
//! - `intersect` (nearest-hit and occlusion queries) keeps the first payload in the query's own
//!   context, reports "no hit", and reports "no hit" without calling Rust for the rest of that
//!   query; [`Scene::intersect`], [`Scene::occluded`], [`Scene::intersect8`] and
//!   [`Scene::occluded8`] resume it with [`std::panic::resume_unwind`] as soon as Embree returns;
//! - `bounds` keeps the first payload with the user geometry and reports an empty box (Embree
//!   leaves the primitive out); [`SceneBuilder::commit`] resumes it once the build is done;
//! - the error callback keeps the payload with the device; the next check of the device's
//!   errors (after a scene is created, geometry is added or a scene is committed) resumes it.
//!
//! The caller thus sees an ordinary Rust panic with the original payload and message, on its
//! own thread, and no half-built result: a query that panicked returns nothing and a commit
//! that panicked drops its scene. [`UserGeometry`] implementations may therefore panic (on a
//! bug) like any Rust code; they are still expected not to.

use std::any::Any;
use std::cell::{Cell, RefCell};
use std::ffi::{CStr, CString, c_char, c_int, c_void};
use std::panic::{AssertUnwindSafe, catch_unwind, resume_unwind};
use std::ptr::NonNull;
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};

use glam::{DVec3, Vec3};
use thiserror::Error;

#[allow(
    non_camel_case_types,
    non_upper_case_globals,
    non_snake_case,
    dead_code
)]
mod ffi {
    include!(concat!(env!("OUT_DIR"), "/shim.rs"));
}

/// Geometry id Embree reports for "no hit".
const INVALID_ID: u32 = ffi::TIMBRE_INVALID_ID;

/// The payload of a panic caught in a callback, resumed once control is back in Rust.
type Payload = Box<dyn Any + Send>;

/// Locks `m`, also when a panic poisoned it (the data behind these locks stays valid).
fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(PoisonError::into_inner)
}

/// An error reported by Embree (through the device error callback) or by this binding.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum EmbreeError {
    #[error("Embree error {code}: {message}")]
    Device { code: i32, message: String },
    #[error("Embree could not create {0}")]
    Creation(&'static str),
    #[error("this Embree build lacks ray masks, which timbre needs for shadow-throwing flags")]
    NoRayMasks,
}

/// Axis-aligned bounding box in single precision, as Embree stores it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bounds {
    pub lower: Vec3,
    pub upper: Vec3,
}

impl Bounds {
    /// The f32 box that contains the f64 box `[lower, upper]` (rounded outwards).
    pub fn enclosing(lower: DVec3, upper: DVec3) -> Bounds {
        Bounds {
            lower: Vec3::new(f32_below(lower.x), f32_below(lower.y), f32_below(lower.z)),
            upper: Vec3::new(f32_above(upper.x), f32_above(upper.y), f32_above(upper.z)),
        }
    }
}

/// The largest f32 not above `x`. (Both neighbours are computed and one is selected, without
/// a branch: which way `x` was rounded is a coin toss that a branch predictor cannot learn.)
fn f32_below(x: f64) -> f32 {
    let f = x as f32;
    let down = f.next_down();
    if f as f64 > x { down } else { f }
}

/// The smallest f32 not below `x` (branch-free, as [`f32_below`]).
fn f32_above(x: f64) -> f32 {
    let f = x as f32;
    let up = f.next_up();
    if (f as f64) < x { up } else { f }
}

/// A ray in f64 as timbre traces it; Embree receives it rounded to f32.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ExactRay {
    pub origin: DVec3,
    pub direction: DVec3,
}

impl ExactRay {
    /// A ray to fill unused places with (a packet's inactive lanes).
    pub const PLACEHOLDER: ExactRay = ExactRay {
        origin: DVec3::ZERO,
        direction: DVec3::Z,
    };
}

/// Analytic primitives whose intersections Embree delegates to Rust.
pub trait UserGeometry: Send + Sync {
    /// Number of primitives; Embree asks for each one's bounds and intersections.
    fn primitive_count(&self) -> u32;
    /// Bounds of primitive `prim`.
    fn bounds(&self, prim: u32) -> Bounds;
    /// Nearest intersection of primitive `prim` with the ray at `t_near < t < t_far`: its
    /// distance and which part of the primitive it is on (returned in [`RawHit::part`]).
    fn intersect(&self, prim: u32, ray: &ExactRay, t_near: f64, t_far: f64) -> Option<(f64, u32)>;
}

/// The nearest hit of a query. `t` is exact (f64, computed by the user geometry on the exact
/// ray) when `exact`; otherwise (triangles) it is Embree's f32 distance and the caller
/// recomputes the hit in f64.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RawHit {
    pub geom_id: u32,
    pub prim_id: u32,
    /// The instance (geometry id in the top-level scene) the hit lies in, if any.
    pub inst_id: Option<u32>,
    pub t: f64,
    pub exact: bool,
    /// The part of the primitive the user geometry reported (0 for triangles).
    pub part: u32,
}

struct DeviceInner {
    raw: NonNull<c_void>,
    /// What Embree's error callback reported since the last check.
    reports: Box<Mutex<Reports>>,
}

/// The first error Embree reported, and a panic caught in the error callback.
#[derive(Default)]
struct Reports {
    error: Option<EmbreeError>,
    panic: Option<Payload>,
}

impl Reports {
    /// Resumes a caught panic, else takes the error.
    fn take(reports: &Mutex<Reports>) -> Option<EmbreeError> {
        let mut r = lock(reports);
        let error = r.error.take();
        if let Some(payload) = r.panic.take() {
            // The error belongs to the failed call: it must not surface in a later one.
            drop(r);
            drop(error);
            resume_unwind(payload);
        }
        error
    }
}

// SAFETY: an Embree device is thread-safe (Embree's API documentation: all API calls on a
// device may be made from any thread); the reports are behind a Mutex.
unsafe impl Send for DeviceInner {}
// SAFETY: as above.
unsafe impl Sync for DeviceInner {}

impl Drop for DeviceInner {
    fn drop(&mut self) {
        // SAFETY: `raw` came from timbre_device_new and is released exactly once, after every
        // Scene holding an Arc to this device has been dropped.
        unsafe { ffi::timbre_device_release(self.raw.as_ptr()) }
    }
}

impl DeviceInner {
    /// Returns the error Embree reported since the last check, or resumes a panic caught in
    /// the error callback.
    fn check(&self) -> Result<(), EmbreeError> {
        Reports::take(&self.reports).map_or(Ok(()), Err)
    }
}

/// Receives errors from Embree's device error callback. Never unwinds (see the module docs).
unsafe extern "C" fn on_device_error(user: *mut c_void, code: c_int, message: *const c_char) {
    // SAFETY: `user` is the address of the device's boxed reports, which live as long as the
    // device; `message` is a NUL-terminated string owned by Embree for the call's duration.
    let (reports, message) =
        unsafe { (&*(user as *const Mutex<Reports>), CStr::from_ptr(message)) };
    let recorded = catch_unwind(|| {
        let message = message.to_string_lossy().into_owned();
        lock(reports)
            .error
            .get_or_insert(EmbreeError::Device { code, message });
    });
    if let Err(payload) = recorded {
        lock(reports).panic.get_or_insert(payload);
    }
}

/// An Embree device: the factory for scenes.
#[derive(Clone)]
pub struct Device {
    inner: Arc<DeviceInner>,
}

impl Device {
    /// Creates a device with an Embree configuration string (e.g. `"threads=2"`, or `""`).
    pub fn new(config: &str) -> Result<Device, EmbreeError> {
        let config = CString::new(config).map_err(|_| EmbreeError::Creation("a device"))?;
        let reports = Box::new(Mutex::new(Reports::default()));
        let reports_ptr = &*reports as *const Mutex<Reports> as *mut c_void;
        // SAFETY: the config string outlives the call; the reports are boxed (stable address)
        // and moved into DeviceInner, which outlives the device.
        let raw =
            unsafe { ffi::timbre_device_new(config.as_ptr(), Some(on_device_error), reports_ptr) };
        let Some(raw) = NonNull::new(raw) else {
            let reported = Reports::take(&reports);
            return Err(reported.unwrap_or(EmbreeError::Creation("a device")));
        };
        let inner = Arc::new(DeviceInner { raw, reports });
        inner.check()?;
        // SAFETY: `raw` is a live device.
        if unsafe { ffi::timbre_device_ray_masks_supported(raw.as_ptr()) } == 0 {
            return Err(EmbreeError::NoRayMasks);
        }
        Ok(Device { inner })
    }

    /// Version of the Embree library in use, e.g. "3.13.5".
    pub fn version(&self) -> String {
        // SAFETY: the device is live.
        let v = unsafe { ffi::timbre_device_version(self.inner.raw.as_ptr()) };
        format!("{}.{}.{}", v / 10000, v / 100 % 100, v % 100)
    }

    /// Packet widths (4, 8, 16) that this CPU and Embree build trace natively.
    pub fn native_packet_widths(&self) -> Vec<u32> {
        // SAFETY: the device is live.
        let bits = unsafe { ffi::timbre_device_native_packets(self.inner.raw.as_ptr()) };
        [4, 8, 16].into_iter().filter(|w| bits & w != 0).collect()
    }

    /// Starts building a scene on this device.
    pub fn scene_builder(&self) -> Result<SceneBuilder, EmbreeError> {
        // SAFETY: the device is live.
        let raw = unsafe { ffi::timbre_scene_new(self.inner.raw.as_ptr()) };
        self.inner.check()?;
        let raw = NonNull::new(raw).ok_or(EmbreeError::Creation("a scene"))?;
        Ok(SceneBuilder {
            scene: Scene {
                raw,
                device: self.inner.clone(),
                user: Vec::new(),
                children: Vec::new(),
                instance_offsets: Vec::new(),
                triangles: false,
            },
        })
    }
}

/// A user geometry's Rust object together with the C record the shim hands to Embree.
struct UserEntry {
    record: Box<ffi::TimbreUserGeometry>,
    registered: Box<Registered>,
}

/// What the callbacks receive as `geometry`: the Rust object and where `user_bounds` keeps a
/// panic caught while the scene is committed (on Embree's build threads, hence the Mutex).
struct Registered {
    geometry: Box<dyn UserGeometry>,
    bounds_panic: Mutex<Option<Payload>>,
}

/// A scene under construction. Add geometry, then [`SceneBuilder::commit`].
pub struct SceneBuilder {
    scene: Scene,
}

impl SceneBuilder {
    fn id(&self, id: u32, what: &'static str) -> Result<u32, EmbreeError> {
        self.scene.device.check()?;
        if id == INVALID_ID {
            Err(EmbreeError::Creation(what))
        } else {
            Ok(id)
        }
    }

    /// Adds a native triangle mesh; returns its geometry id. Rays hit it when
    /// `ray_mask & mask != 0`.
    pub fn add_triangles(
        &mut self,
        vertices: &[Vec3],
        triangles: &[[u32; 3]],
        mask: u32,
    ) -> Result<u32, EmbreeError> {
        let n = vertices.len() as u32;
        if triangles.iter().flatten().any(|&i| i >= n) {
            return Err(EmbreeError::Creation(
                "a triangle mesh with out-of-range indices",
            ));
        }
        let flat: Vec<f32> = vertices.iter().flat_map(|v| v.to_array()).collect();
        // SAFETY: `flat` holds 3 floats per vertex and `triangles` 3 in-range indices per
        // triangle; the shim copies both into Embree-owned (padded) buffers before returning.
        let id = unsafe {
            ffi::timbre_scene_add_triangles(
                self.scene.device.raw.as_ptr(),
                self.scene.raw.as_ptr(),
                flat.as_ptr(),
                vertices.len(),
                triangles.as_ptr() as *const u32,
                triangles.len(),
                mask,
            )
        };
        self.scene.triangles = true;
        self.id(id, "a triangle mesh")
    }

    /// Adds user geometry; returns its geometry id.
    pub fn add_user(
        &mut self,
        geometry: Box<dyn UserGeometry>,
        mask: u32,
    ) -> Result<u32, EmbreeError> {
        let prims = geometry.primitive_count();
        let registered = Box::new(Registered {
            geometry,
            bounds_panic: Mutex::new(None),
        });
        let entry = UserEntry {
            record: Box::new(ffi::TimbreUserGeometry {
                geometry: &*registered as *const Registered as *const c_void,
                bounds: Some(user_bounds),
                intersect: Some(user_intersect),
                occluded: Some(user_intersect),
            }),
            registered,
        };
        // SAFETY: the record and the geometry it points to are boxed and kept in the scene,
        // so they outlive every callback Embree makes for this geometry.
        let id = unsafe {
            ffi::timbre_scene_add_user(
                self.scene.device.raw.as_ptr(),
                self.scene.raw.as_ptr(),
                prims,
                &*entry.record,
                mask,
            )
        };
        self.scene.user.push(entry);
        self.id(id, "a user geometry")
    }

    /// Adds an instance of a committed scene translated by `translation`; returns its geometry
    /// id. User-geometry callbacks inside it receive the exact f64 ray shifted by the exact
    /// translation (Embree itself traverses with the translation rounded to f32).
    pub fn add_instance(
        &mut self,
        instanced: Arc<Scene>,
        translation: DVec3,
        mask: u32,
    ) -> Result<u32, EmbreeError> {
        if !Arc::ptr_eq(&instanced.device, &self.scene.device) {
            return Err(EmbreeError::Creation(
                "an instance of a scene from another device",
            ));
        }
        let t = translation.as_vec3().to_array();
        // SAFETY: `instanced` is a committed scene on the same device, kept alive by this
        // scene's `children`; `t` holds the 3 floats the shim reads.
        let id = unsafe {
            ffi::timbre_scene_add_instance(
                self.scene.device.raw.as_ptr(),
                self.scene.raw.as_ptr(),
                instanced.raw.as_ptr(),
                t.as_ptr(),
                mask,
            )
        };
        self.scene.children.push(instanced);
        let id = self.id(id, "an instance")?;
        let offsets = &mut self.scene.instance_offsets;
        if offsets.len() <= id as usize {
            offsets.resize(id as usize + 1, DVec3::ZERO);
        }
        offsets[id as usize] = translation;
        Ok(id)
    }

    /// Builds the BVH. Call outside rayon tasks (Embree builds with its own threads).
    ///
    /// A panic in a [`UserGeometry::bounds`] is resumed here, after the build.
    pub fn commit(self) -> Result<Scene, EmbreeError> {
        // SAFETY: the scene is live and all its geometry's data outlives it.
        unsafe { ffi::timbre_scene_commit(self.scene.raw.as_ptr()) };
        // Embree's error (if any) is taken first, so that a resumed panic leaves none behind
        // to surface in a later, unrelated call.
        let checked = self.scene.device.check();
        for entry in &self.scene.user {
            if let Some(payload) = lock(&entry.registered.bounds_panic).take() {
                resume_unwind(payload);
            }
        }
        checked?;
        Ok(self.scene)
    }
}

/// A committed Embree scene, read-only and shareable across threads.
pub struct Scene {
    raw: NonNull<c_void>,
    device: Arc<DeviceInner>,
    user: Vec<UserEntry>,
    children: Vec<Arc<Scene>>,
    /// Exact translation of each instance, by geometry id (zero for other geometry).
    instance_offsets: Vec<DVec3>,
    /// Whether it holds triangle meshes (see [`Scene::coherent`]).
    triangles: bool,
}

// SAFETY: a committed Embree scene may be queried from many threads at once (Embree API manual,
// rtcCommitScene); the user geometry it calls back into is Send + Sync.
unsafe impl Send for Scene {}
// SAFETY: as above.
unsafe impl Sync for Scene {}

impl Drop for Scene {
    fn drop(&mut self) {
        // SAFETY: `raw` is released once; Embree keeps instanced scenes alive by reference
        // counting, and our own `children` are dropped after this call.
        unsafe { ffi::timbre_scene_release(self.raw.as_ptr()) }
    }
}

/// The latest user-geometry hit a callback accepted for one ray: its exact distance, the part
/// of the primitive, and the (instance, geometry, primitive) ids.
#[derive(Clone, Copy)]
struct BestHit {
    t: f64,
    part: u32,
    ids: (u32, u32, u32),
}

type Best = Cell<BestHit>;

fn no_best() -> Best {
    Cell::new(BestHit {
        t: f64::INFINITY,
        part: 0,
        ids: (INVALID_ID, INVALID_ID, INVALID_ID),
    })
}

/// Per-query data handed through Embree to the callbacks: the exact rays (indexed by the
/// Embree ray id), the queried scene's exact instance translations, per ray, the best
/// user-geometry hit so far, and a panic caught in a callback.
struct Query<'a> {
    rays: &'a [ExactRay],
    instance_offsets: &'a [DVec3],
    best: &'a [Best],
    panic: RefCell<Option<Payload>>,
}

impl<'a> Query<'a> {
    fn new(rays: &'a [ExactRay], instance_offsets: &'a [DVec3], best: &'a [Best]) -> Self {
        Query {
            rays,
            instance_offsets,
            best,
            panic: RefCell::new(None),
        }
    }

    /// Resumes a panic that a callback caught during the query (call after Embree returns).
    fn resume_panic(self) {
        if let Some(payload) = self.panic.into_inner() {
            resume_unwind(payload);
        }
    }
}

fn to_embree(ray: &ExactRay, t_near: f64, t_far: f64, mask: u32, id: u32) -> ffi::TimbreRay {
    ffi::TimbreRay {
        org: ray.origin.as_vec3().to_array(),
        dir: ray.direction.as_vec3().to_array(),
        // Rounded inwards, so user-geometry callbacks, which compare exact f64 distances with
        // these bounds, never accept a hit outside (t_near, t_far).
        tnear: f32_above(t_near),
        tfar: f32_below(t_far),
        mask,
        id,
    }
}

impl Scene {
    /// Whether its packets take Embree's coherent-traversal hint: only a scene of triangles
    /// alone. Embree traverses the triangles of a ROBUST scene with a conservative frustum test,
    /// but user geometry and instances with one that misses thin boxes (a field of discs facing
    /// an axis, an array of flat mesh tiles; `tests/tracing.rs`). On the 1M-triangle anchor
    /// mesh the hint makes primary and shadow packets 30 % faster; for user geometry alone the
    /// incoherent traversal is 2–3 % faster anyway (docs/PERFORMANCE.md).
    fn coherent(&self) -> bool {
        self.triangles && self.user.is_empty() && self.children.is_empty()
    }

    fn finish(raw: &ffi::TimbreHit, best: BestHit) -> Option<RawHit> {
        if raw.geom_id == INVALID_ID {
            return None;
        }
        let inst_id = (raw.inst_id != INVALID_ID).then_some(raw.inst_id);
        let exact = best.ids == (raw.inst_id, raw.geom_id, raw.prim_id);
        Some(RawHit {
            geom_id: raw.geom_id,
            prim_id: raw.prim_id,
            inst_id,
            t: if exact { best.t } else { raw.t as f64 },
            exact,
            part: if exact { best.part } else { 0 },
        })
    }

    /// Nearest hit along `ray` with `t_near < t < t_far` among geometry whose mask shares a
    /// bit with `mask`.
    pub fn intersect(&self, ray: &ExactRay, t_near: f64, t_far: f64, mask: u32) -> Option<RawHit> {
        let best = [no_best()];
        let query = Query::new(std::slice::from_ref(ray), &self.instance_offsets, &best);
        let r = to_embree(ray, t_near, t_far, mask, 0);
        let mut hit = ffi::TimbreHit {
            t: 0.0,
            geom_id: INVALID_ID,
            prim_id: 0,
            inst_id: 0,
        };
        // SAFETY: the scene is committed; `query` outlives the call and is only read through
        // shared references by callbacks on this thread.
        unsafe {
            ffi::timbre_intersect1(
                self.raw.as_ptr(),
                &query as *const Query as *const c_void,
                &r,
                &mut hit,
            )
        };
        query.resume_panic();
        Self::finish(&hit, best[0].get())
    }

    /// Whether anything with a matching mask lies on `ray` at `t_near < t < t_far`.
    pub fn occluded(&self, ray: &ExactRay, t_near: f64, t_far: f64, mask: u32) -> bool {
        let best = [no_best()];
        let query = Query::new(std::slice::from_ref(ray), &self.instance_offsets, &best);
        let r = to_embree(ray, t_near, t_far, mask, 0);
        // SAFETY: as in `intersect`.
        let occluded = unsafe {
            ffi::timbre_occluded1(
                self.raw.as_ptr(),
                &query as *const Query as *const c_void,
                &r,
            ) != 0
        };
        query.resume_panic();
        occluded
    }

    /// Nearest hits of up to 8 rays traced as one packet (native on AVX2); lanes
    /// beyond `rays.len()` are inactive. All rays share `t_near`, `t_far` and `mask`.
    pub fn intersect8(
        &self,
        rays: &[ExactRay],
        t_near: f64,
        t_far: f64,
        mask: u32,
    ) -> [Option<RawHit>; 8] {
        assert!(rays.len() <= 8, "a packet holds at most 8 rays");
        let best: [Best; 8] = std::array::from_fn(|_| no_best());
        let query = Query::new(rays, &self.instance_offsets, &best);
        let (packet, valid) = packet8(rays.len(), |i| (&rays[i], t_near, t_far), mask);
        let mut hits = [ffi::TimbreHit {
            t: 0.0,
            geom_id: INVALID_ID,
            prim_id: 0,
            inst_id: 0,
        }; 8];
        // SAFETY: the three arrays have 8 elements as the shim expects; `query` outlives the
        // call. Embree requires 32-byte alignment only for its own packet struct, which the shim
        // builds on its stack.
        unsafe {
            ffi::timbre_intersect8(
                self.raw.as_ptr(),
                &query as *const Query as *const c_void,
                valid.as_ptr(),
                packet.as_ptr(),
                self.coherent() as c_int,
                hits.as_mut_ptr(),
            )
        };
        query.resume_panic();
        std::array::from_fn(|i| Self::finish(&hits[i], best[i].get()))
    }

    /// Whether anything with a matching mask lies on each of up to 8 rays within its
    /// interval (t_near, t_far), traced as one packet (shadow rays of neighbouring pixels);
    /// lanes beyond `rays.len()` are false.
    ///
    /// # Panics
    /// If there are more than 8 rays, or not one interval per ray.
    pub fn occluded8(&self, rays: &[ExactRay], intervals: &[(f64, f64)], mask: u32) -> [bool; 8] {
        assert!(rays.len() <= 8, "a packet holds at most 8 rays");
        assert_eq!(rays.len(), intervals.len(), "one interval per ray");
        let best: [Best; 8] = std::array::from_fn(|_| no_best());
        let query = Query::new(rays, &self.instance_offsets, &best);
        let (packet, valid) = packet8(
            rays.len(),
            |i| (&rays[i], intervals[i].0, intervals[i].1),
            mask,
        );
        let mut occluded: [c_int; 8] = [0; 8];
        // SAFETY: the three arrays have 8 elements as the shim expects; `query` outlives the
        // call (as in `intersect8`).
        unsafe {
            ffi::timbre_occluded8(
                self.raw.as_ptr(),
                &query as *const Query as *const c_void,
                valid.as_ptr(),
                packet.as_ptr(),
                self.coherent() as c_int,
                occluded.as_mut_ptr(),
            )
        };
        query.resume_panic();
        occluded.map(|o| o != 0)
    }
}

/// An 8-wide packet and its valid mask: lane i < `n` is `lane(i)` = (ray, t_near, t_far),
/// with id i (the index of its exact ray in the query); the others are inactive.
fn packet8<'a>(
    n: usize,
    lane: impl Fn(usize) -> (&'a ExactRay, f64, f64),
    mask: u32,
) -> ([ffi::TimbreRay; 8], [c_int; 8]) {
    let (mut packet, mut valid) = (
        [to_embree(&ExactRay::PLACEHOLDER, 0.0, f64::INFINITY, mask, 0); 8],
        [0; 8],
    );
    for i in 0..n {
        let (ray, t_near, t_far) = lane(i);
        (packet[i], valid[i]) = (to_embree(ray, t_near, t_far, mask, i as u32), -1);
    }
    (packet, valid)
}

/// Embree asks for a primitive's bounds while building the BVH. Never unwinds (see the module
/// docs).
unsafe extern "C" fn user_bounds(geometry: *const c_void, prim: u32, out: *mut ffi::TimbreBounds) {
    // SAFETY: `geometry` is the boxed `Registered` of `add_user`, alive as long as the scene;
    // `out` is a valid out-pointer supplied by the shim.
    let (registered, out) = unsafe { (&*(geometry as *const Registered), &mut *out) };
    // Asserted unwind-safe: after a panic the scene is dropped unused (`commit` resumes it).
    let b = catch_unwind(AssertUnwindSafe(|| registered.geometry.bounds(prim))).unwrap_or_else(
        |payload| {
            lock(&registered.bounds_panic).get_or_insert(payload);
            // Empty (lower above upper): Embree leaves the primitive out.
            Bounds {
                lower: Vec3::ONE,
                upper: Vec3::NEG_ONE,
            }
        },
    );
    out.lower = b.lower.to_array();
    out.upper = b.upper.to_array();
}

/// Embree asks whether a ray hits a primitive (for both nearest-hit and occlusion queries).
/// Never unwinds (see the module docs): a panic is kept in the query and reported as no hit.
unsafe extern "C" fn user_intersect(
    geometry: *const c_void,
    geom_id: u32,
    prim: u32,
    query: *const c_void,
    ray: *const ffi::TimbreRay,
    inst_id: u32,
    t_out: *mut f32,
) -> c_int {
    // SAFETY: `geometry` as in `user_bounds`; `query` is the `Query` passed by
    // `Scene::intersect*`/`occluded` on this same thread, alive for the whole query; `ray` is a
    // valid pointer supplied by the shim.
    let (registered, query, ray) = unsafe {
        (
            &*(geometry as *const Registered),
            &*(query as *const Query),
            &*ray,
        )
    };
    if query.panic.borrow().is_some() {
        return 0;
    }
    // Asserted unwind-safe: after a panic the query's results are discarded unread
    // (`Query::resume_panic` runs before them).
    let hit = catch_unwind(AssertUnwindSafe(|| {
        intersect_exact(&*registered.geometry, geom_id, prim, query, ray, inst_id)
    }));
    match hit {
        Ok(Some(t)) => {
            // Rounded up, so that tfar never cuts off the accepted hit itself; t < tfar, hence
            // the rounded value is at most tfar.
            // SAFETY: valid out-pointer from the shim.
            unsafe { *t_out = f32_above(t) };
            1
        }
        Ok(None) => 0,
        Err(payload) => {
            query.panic.borrow_mut().get_or_insert(payload);
            0
        }
    }
}

/// The body of `user_intersect`: the exact distance at which `ray` hits primitive `prim`, if it
/// does and beats the query's best hit so far (which it then becomes).
fn intersect_exact(
    geometry: &dyn UserGeometry,
    geom_id: u32,
    prim: u32,
    query: &Query,
    ray: &ffi::TimbreRay,
    inst_id: u32,
) -> Option<f64> {
    let id = ray.id as usize;
    // The exact ray, in the instance's space when inside one (instances only translate).
    let offset = match inst_id {
        INVALID_ID => Some(DVec3::ZERO),
        i => query.instance_offsets.get(i as usize).copied(),
    };
    let exact = query.rays.get(id).zip(offset).map(|(r, o)| ExactRay {
        origin: r.origin - o,
        direction: r.direction,
    });
    let embree_ray = ExactRay {
        origin: Vec3::from(ray.org).as_dvec3(),
        direction: Vec3::from(ray.dir).as_dvec3(),
    };
    let r = exact.unwrap_or(embree_ray);
    // On the exact ray, a hit must also beat the exact distance of the hit accepted so far:
    // Embree's f32 tfar cannot separate hits less than an f32 step apart.
    let best = exact.and_then(|_| query.best.get(id));
    let t_far = best.map_or(ray.tfar as f64, |b| b.get().t.min(ray.tfar as f64));
    let (t, part) = geometry.intersect(prim, &r, ray.tnear as f64, t_far)?;
    if let Some(best) = best {
        best.set(BestHit {
            t,
            part,
            ids: (inst_id, geom_id, prim),
        });
    }
    Some(t)
}
