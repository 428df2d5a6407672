//! Property tests: `SceneGeometry` (Embree's f32 BVH with f64 callbacks and f64 re-computation)
//! against brute force over random scenes and rays; Embree instancing and errors through
//! `timbre::embree` directly.
//!
//! # What may differ, and how that is decided
//!
//! By the rules of `common::verdict`, shared with `tests/arrays.rs`: Embree traverses in f32
//! and decides triangle hits in f32, so a primitive whose answer changes when the ray moves by a
//! few f32 roundings (or, for analytic shapes, when t_min and t_max move by two roundings) may
//! be found or missed, and primitives at the same distance (within `TIE` when a triangle is
//! involved) may be reported either way; everything else must match the exact f64 answers.
//! `excuses_are_rare` counts how often each excuse is used on a deterministic sample: another
//! primitive at the same distance (repeated triangles of the random meshes) for under 1% of the
//! nearest-hit answers, near ties and marginal primitives for under 0.2%, and shadow answers
//! could go either way for under 2%.
//!
//! `hits_beyond_t_max_within_f32_rounding_are_not_reported`,
//! `grazing_ray_leaving_a_triangle_does_not_hit_it_again` and
//! `rays_leaving_meshes_match_brute_force` guard against bugs these tests found and that have
//! been fixed (hits outside (t_min, t_max) after the f64 recompute; grazing self-hits on meshes).

mod common;

use std::sync::{Arc, OnceLock};

use glam::{DVec3, Vec3};
use proptest::prelude::*;
use proptest::strategy::ValueTree;
use proptest::test_runner::TestRunner;

use common::rays::{Query, close, device, sample_point, self_hit_margin, surface_point};
use common::rng::Rng;
use common::verdict::{self, Answers, check_nearest, check_queries, elements};
use common::{
    config, cylinder_shape, disc_shape, mesh_parts, normal_vector, parallelogram_shape, point_in,
    sphere_shape, unit_vector,
};
use timbre::embree::{Bounds, Device, EmbreeError, ExactRay, UserGeometry};
use timbre::geometry::{Plane, SceneGeometry, Shape, Sphere, TriangleMesh};

// ---------------------------------------------------------------------------------------------
// Random scenes
// ---------------------------------------------------------------------------------------------

fn mesh() -> impl Strategy<Value = Shape> {
    mesh_parts(5.0, 1.5, 3..7, 1..7).prop_filter_map("no usable triangle", |(v, t)| {
        TriangleMesh::new(v, t).ok().map(Shape::TriangleMesh)
    })
}

fn shape() -> impl Strategy<Value = Shape> {
    prop_oneof![
        4 => sphere_shape(6.0, 2.5),
        3 => disc_shape(6.0, 2.5),
        3 => cylinder_shape(6.0, 8.0, 1.5),
        3 => parallelogram_shape(6.0, 4.0),
        3 => mesh(),
        1 => (point_in(6.0), normal_vector(), unit_vector())
            .prop_map(|(p, n, u)| Shape::Plane(Plane::new(p, n, u).unwrap())),
    ]
}

/// A random scene (objects with shadow-throwing flags) and a seed for its rays.
fn scene_case() -> impl Strategy<Value = (Vec<(Shape, bool)>, u64)> {
    (
        prop::collection::vec((shape(), any::<bool>()), 1..13),
        any::<u64>(),
    )
}

/// Which rays a scene check draws.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Rays {
    /// Random rays, rays aimed at objects, and rays leaving analytic shapes' surfaces.
    General,
    /// Rays leaving a point of a triangle mesh in a random direction.
    LeavingMeshes,
}

/// A ray leaving a point of `shape` in a random direction, with the tracer's self-hit margin
/// as t_min: 1e-9 × scale for analytic shapes, 1e-5 × scale for meshes (Embree tests triangles
/// in f32).
fn leaving_query(shape: &Shape, rng: &mut Rng, t_max: f64) -> Query {
    let origin = surface_point(shape, rng);
    Query {
        origin,
        direction: rng.unit(),
        t_min: self_hit_margin(shape, origin),
        t_max,
    }
}

fn random_query(shapes: &[Shape], rays: Rays, rng: &mut Rng) -> Query {
    let origin = rng.point(10.0);
    let t_max = if rng.f() < 0.25 {
        rng.range(0.0, 25.0)
    } else {
        f64::INFINITY
    };
    let is_mesh = |s: &&Shape| matches!(s, Shape::TriangleMesh(_));
    let (meshes, analytic): (Vec<&Shape>, Vec<&Shape>) = shapes.iter().partition(is_mesh);
    let leaving_from = match rays {
        Rays::LeavingMeshes => meshes,
        Rays::General => analytic,
    };
    let kind = if rays == Rays::LeavingMeshes {
        1.0
    } else {
        rng.f()
    };
    if kind < 0.3 {
        Query {
            origin,
            direction: rng.unit(),
            t_min: 0.0,
            t_max,
        }
    } else if kind < 0.8 || leaving_from.is_empty() {
        let target = sample_point(&shapes[rng.index(shapes.len())], rng);
        Query {
            origin,
            direction: (target - origin).normalize(),
            t_min: 0.0,
            t_max,
        }
    } else {
        leaving_query(leaving_from[rng.index(leaving_from.len())], rng, t_max)
    }
}

// ---------------------------------------------------------------------------------------------
// The checks (the rules are those of `common::verdict`)
// ---------------------------------------------------------------------------------------------

/// Tally of verdicts over a run, and two counts of this test's own.
#[derive(Debug, Default)]
struct Tally {
    verdicts: verdict::Tally,
    /// Shadow rays whose only hits are on objects that throw no shadow.
    masked_only: usize,
    /// Shadow rays with no robust hit of a shadow-throwing object but some non-robust
    /// shadow-throwing primitive: those whose answer may go either way.
    shadow_either_way: usize,
}

/// Runs every check on one scene with `rays` single rays and `packets` packets; returns the tally.
fn check_scene(
    objects: &[(Shape, bool)],
    seed: u64,
    kinds: Rays,
    rays: usize,
    packets: usize,
) -> Result<Tally, String> {
    let scene =
        SceneGeometry::build(device(), objects.to_vec(), Vec::new()).map_err(|e| e.to_string())?;
    let shapes: Vec<Shape> = objects.iter().map(|o| o.0.clone()).collect();
    let (mut masked_only, mut shadow_either_way) = (0, 0);
    let verdicts = check_queries(
        &scene,
        objects,
        &elements(objects, &[]),
        &mut Rng(seed),
        rays,
        packets,
        |rng| random_query(&shapes, kinds, rng),
        |answers, _| {
            let hit = answers.all.iter().any(|a| a.t.is_some());
            let masked = answers
                .all
                .iter()
                .all(|a| a.t.is_none() || (answers.robust(a) && !a.shadow_throwing));
            masked_only += usize::from(masked && hit);
            let throwers = || answers.all.iter().filter(|a| a.shadow_throwing);
            let robust_hit = throwers().any(|a| a.t.is_some() && answers.robust(a));
            let fragile = throwers().any(|a| !answers.robust(a));
            shadow_either_way += usize::from(!robust_hit && fragile);
        },
    )?;
    Ok(Tally {
        verdicts,
        masked_only,
        shadow_either_way,
    })
}

proptest! {
    #![proptest_config(config(256))]

    /// `nearest`, `shadowed` and `nearest8` against brute force on random scenes.
    #[test]
    fn scene_queries_match_brute_force((objects, seed) in scene_case()) {
        check_scene(&objects, seed, Rays::General, 32, 4).map_err(TestCaseError::fail)?;
    }
}

/// Guards against a vacuous test: on a deterministic sample, most answers agree exactly with the
/// brute force; the excuses (ties, marginal primitives) are rare; packets agree with single rays;
/// hits, misses and mask-only shadow rays all occur.
#[test]
fn excuses_are_rare() {
    let mut runner = TestRunner::deterministic();
    let mut total = Tally::default();
    for _ in 0..300 {
        let (objects, seed) = scene_case().new_tree(&mut runner).unwrap().current();
        let t = check_scene(&objects, seed, Rays::General, 32, 4)
            .unwrap_or_else(|e| panic!("{e}\n{objects:?}"));
        total.verdicts.add(&t.verdicts);
        total.masked_only += t.masked_only;
        total.shadow_either_way += t.shadow_either_way;
    }
    println!("verdicts [same, equal tie, near tie, marginal]: {total:?}");
    let v = &total.verdicts;
    let rays: usize = v.nearest.iter().sum();
    let lanes: usize = v.packet.iter().sum();
    assert!(v.hits > rays / 3 && v.hits < rays * 9 / 10, "{total:?}");
    // Equal distances on different primitives come from repeated and coplanar triangles of
    // the random meshes (either may be reported; before tests/common/verdict.rs these counted
    // as the same answer and had no bound at all). The excuses that accept another distance
    // (near ties, marginal primitives) had a shared bound of rays/200 and now have rays/500.
    assert!(v.nearest[1] <= rays / 100, "{total:?}");
    assert!(v.packet[1] <= lanes / 100, "{total:?}");
    assert!(v.nearest[2] + v.nearest[3] <= rays / 500, "{total:?}");
    assert!(v.packet[2] + v.packet[3] <= lanes / 500, "{total:?}");
    assert!(v.shadowed[3] <= rays / 50, "{total:?}");
    assert!(total.shadow_either_way <= rays / 50, "{total:?}");
    assert!(v.packet_differs <= lanes / 200, "{total:?}");
    assert!(total.masked_only >= rays / 50, "{total:?}");
}

/// Rays leaving random meshes' surfaces (the tracer's secondary and shadow rays, with its 1e-5
/// scale self-hit margin), 300 deterministic scenes × 64 rays, all checks as above. Kept out of
/// the random test so that a failure here is reproducible rather than intermittent.
/// Guards against self-hits below t_min on rays leaving a triangle at grazing angles (see
/// `grazing_ray_leaving_a_triangle_does_not_hit_it_again`).
#[test]
fn rays_leaving_meshes_match_brute_force() {
    let mut runner = TestRunner::deterministic();
    let mut failures = Vec::new();
    let mut scenes = 0;
    while scenes < 300 {
        let (objects, seed) = scene_case().new_tree(&mut runner).unwrap().current();
        if !objects
            .iter()
            .any(|o| matches!(o.0, Shape::TriangleMesh(_)))
        {
            continue;
        }
        scenes += 1;
        if let Err(e) = check_scene(&objects, seed, Rays::LeavingMeshes, 64, 8) {
            failures.push(e);
        }
    }
    assert!(
        failures.is_empty(),
        "{} of 300 scenes fail, e.g. {}",
        failures.len(),
        failures[0]
    );
}

// ---------------------------------------------------------------------------------------------
// Long, thin cylinders through Embree
// ---------------------------------------------------------------------------------------------

/// TIM's lattice (48 cylinders of radius 0.02, lengths 2 to 30, at distances 10 to 40 from the
/// camera at the origin), as the studio builds it.
fn lattice() -> Vec<(Shape, bool)> {
    timbre::scene::studio::lattice()
        .into_iter()
        .map(|o| (o.shape, o.shadow_throwing))
        .collect()
}

fn lattice_scene() -> &'static (Vec<(Shape, bool)>, SceneGeometry) {
    static SCENE: OnceLock<(Vec<(Shape, bool)>, SceneGeometry)> = OnceLock::new();
    SCENE.get_or_init(|| {
        let objects = lattice();
        let scene =
            SceneGeometry::build(device(), objects.clone(), Vec::new()).expect("lattice builds");
        (objects, scene)
    })
}

/// A ray from `origin` aimed inside lattice cylinder k at axial fraction s, radial fraction rho,
/// angle phi.
fn check_lattice_ray(
    k: usize,
    origin: DVec3,
    s: f64,
    rho: f64,
    phi: f64,
) -> Result<(), TestCaseError> {
    let (objects, scene) = lattice_scene();
    let Shape::Cylinder(c) = &objects[k].0 else {
        unreachable!()
    };
    let e1 = c.axis().any_orthonormal_vector();
    let e2 = c.axis().cross(e1);
    let target = c.start()
        + s * (c.end() - c.start())
        + c.radius() * rho * (phi.cos() * e1 + phi.sin() * e2);
    let q = Query {
        origin,
        direction: (target - origin).normalize(),
        t_min: 0.0,
        t_max: f64::INFINITY,
    };
    let got = scene.nearest(q.origin, q.direction, q.t_min, q.t_max);
    prop_assert!(got.is_some(), "ray aimed inside cylinder {} missed", k);
    let answers = Answers::new(objects, &elements(objects, &[]), q);
    let brute = scene.nearest_brute_force(q.origin, q.direction, q.t_min, q.t_max);
    check_nearest(&answers, brute, got).map_err(TestCaseError::fail)?;
    prop_assert!(scene.shadowed(q.origin, q.direction, q.t_min, q.t_max));
    Ok(())
}

proptest! {
    #![proptest_config(config(1000))]

    /// Rays from near the camera aimed strictly inside a lattice cylinder (within 0.999 r of
    /// the axis) always hit a cylinder through Embree, and the answer matches brute force.
    #[test]
    fn thin_lattice_cylinders_are_not_missed(
        k in 0..48usize,
        origin in point_in(0.1),
        s in 0.0005..0.9995f64,
        rho in 0.0..0.999f64,
        phi in 0.0..std::f64::consts::TAU,
    ) {
        check_lattice_ray(k, origin, s, rho, phi)?;
    }
}

// ---------------------------------------------------------------------------------------------
// Contract at the ends of the interval
// ---------------------------------------------------------------------------------------------

/// `nearest` promises t_min < t < t_max. A sphere whose surface lies just before the f32 rounding
/// of t_max (but beyond t_max itself) must not be reported, nor make the ray shadowed.
/// (Embree sees t_max rounded to f32; the exact distance must still be checked against t_max.)
#[test]
fn hits_beyond_t_max_within_f32_rounding_are_not_reported() {
    // Ray from the origin along +z; the sphere's near surface is at t = 10 − 1e-7.
    let t_hit = 10.0 - 1e-7;
    let sphere = Sphere::new(DVec3::new(0.0, 0.0, t_hit + 1.0), 1.0).unwrap();
    let scene =
        SceneGeometry::build(device(), vec![(Shape::Sphere(sphere), true)], Vec::new()).unwrap();
    let t_max = 10.0 - 2e-7; // rounds to 10.0f32, beyond the hit
    assert!(t_max < t_hit && t_max as f32 as f64 > t_hit);
    let (o, d) = (DVec3::ZERO, DVec3::Z);
    assert_eq!(scene.nearest_brute_force(o, d, 0.0, t_max), None);
    let mut failures = Vec::new();
    if let Some(h) = scene.nearest(o, d, 0.0, t_max) {
        failures.push(format!("nearest: {h:?}"));
    }
    if let Some(h) = scene.nearest8(o, &[d], 0.0, t_max)[0] {
        failures.push(format!("nearest8: {h:?}"));
    }
    if scene.shadowed(o, d, 0.0, t_max) {
        failures.push("shadowed".into());
    }
    assert!(
        failures.is_empty(),
        "hits beyond t_max = {t_max} reported: {failures:?}"
    );
    // With t_max beyond the hit it is found, exactly.
    assert_eq!(scene.nearest(o, d, 0.0, 10.0).map(|h| h.t), Some(t_hit));
}

// ---------------------------------------------------------------------------------------------
// Embree instancing through timbre::embree
// ---------------------------------------------------------------------------------------------

/// The unit sphere as Embree user geometry; inside an instance Embree hands it the ray in the
/// instance's space, with an unnormalised direction, and t stays the world distance parameter.
struct UnitSphere;

impl UserGeometry for UnitSphere {
    fn primitive_count(&self) -> u32 {
        1
    }

    fn bounds(&self, _prim: u32) -> Bounds {
        Bounds::enclosing(DVec3::splat(-1.0), DVec3::splat(1.0))
    }

    /// Part 1 on the upper half (z > 0), part 0 on the lower.
    fn intersect(&self, _prim: u32, ray: &ExactRay, t_near: f64, t_far: f64) -> Option<(f64, u32)> {
        let t = unit_sphere_hit(ray.origin, ray.direction, t_near, t_far)?;
        Some((t, (ray.origin.z + t * ray.direction.z > 0.0) as u32))
    }
}

/// Nearest t in (t_near, t_far) with |o + t d| = 1 (d need not be a unit vector).
fn unit_sphere_hit(o: DVec3, d: DVec3, t_near: f64, t_far: f64) -> Option<f64> {
    let (a, b, c) = (d.dot(d), o.dot(d), o.dot(o) - 1.0);
    let disc = b * b - a * c;
    if disc < 0.0 {
        return None;
    }
    [(-b - disc.sqrt()) / a, (-b + disc.sqrt()) / a]
        .into_iter()
        .find(|&t| t > t_near && t < t_far)
}

/// Corners of the instanced scene's square (two triangles) in the plane z = 0.
const SQUARE: [Vec3; 4] = [
    Vec3::new(2.0, 0.0, 0.0),
    Vec3::new(3.0, 0.0, 0.0),
    Vec3::new(3.0, 1.0, 0.0),
    Vec3::new(2.0, 1.0, 0.0),
];

/// An instance placement: a translation, exact in f64 (timbre's instances only translate;
/// Embree traverses with it rounded to f32, the callbacks get the exact one).
#[derive(Debug, Clone, Copy)]
struct Affine {
    t: DVec3,
}

impl Affine {
    /// The ray in the instanced scene's space (same t).
    fn local_ray(&self, o: DVec3, d: DVec3) -> (DVec3, DVec3) {
        (o - self.t, d)
    }
}

fn affine() -> impl Strategy<Value = Affine> {
    point_in(5.0).prop_map(|t| Affine { t })
}

/// A reference hit of the instanced world: (t, instance index, 0 = sphere / 1 = square, robust).
fn instance_hits(instances: &[Affine], o: DVec3, d: DVec3) -> Vec<(f64, usize, usize, bool)> {
    let mut out = Vec::new();
    for (k, a) in instances.iter().enumerate() {
        let (lo, ld) = a.local_ray(o, d);
        // Sphere: robust when the local line passes well inside (incidence cos > 0.3) or well
        // outside the unit sphere, from an origin not near it.
        let closest = lo - (lo.dot(ld) / ld.dot(ld)) * ld;
        let sphere_robust = closest.length() < 0.95 || closest.length() > 1.001;
        if let Some(t) = unit_sphere_hit(lo, ld, 0.0, f64::INFINITY) {
            let robust = sphere_robust && (lo.length() - 1.0).abs() > 1e-3;
            out.push((t, k, 0, robust));
        }
        // Square: robust when the crossing is well inside or outside it, at an incidence cos
        // above 0.05 (f32 errors in t grow as 1/cos).
        let t = -lo.z / ld.z;
        let p = lo + t * ld;
        let margin = (p.x - 2.0).min(3.0 - p.x).min(p.y).min(1.0 - p.y);
        if t.is_finite() && t > 0.0 && margin > -1e-3 {
            out.push((
                t,
                k,
                1,
                margin > 1e-3 && ld.z.abs() > 0.05 * ld.length() && t > 1e-3,
            ));
        }
    }
    out
}

fn check_instances(a: Affine, b: Affine, seed: u64) -> Result<(), TestCaseError> {
    let dev = device();
    let mut inner = dev.scene_builder().unwrap();
    let sphere_id = inner.add_user(Box::new(UnitSphere), 1).unwrap();
    let square_id = inner
        .add_triangles(&SQUARE, &[[0, 1, 2], [0, 2, 3]], 1)
        .unwrap();
    let inner = Arc::new(inner.commit().unwrap());
    let mut top = dev.scene_builder().unwrap();
    let ids = [
        top.add_instance(inner.clone(), a.t, 1).unwrap(),
        top.add_instance(inner, b.t, 1).unwrap(),
    ];
    let top = top.commit().unwrap();
    let instances = [a, b];
    let mut rng = Rng(seed);
    for _ in 0..16 {
        // Aim at a point of one instance's sphere or square, or anywhere.
        let origin = rng.point(12.0);
        let k = rng.index(2);
        let local = match rng.index(3) {
            0 => 0.9 * rng.f().cbrt() * rng.unit(),
            1 => DVec3::new(rng.range(2.0, 3.0), rng.range(0.0, 1.0), 0.0),
            _ => rng.point(4.0),
        };
        let target = local + instances[k].t;
        let d = (target - origin).normalize();
        let got = top.intersect(
            &ExactRay {
                origin,
                direction: d,
            },
            0.0,
            f64::INFINITY,
            1,
        );
        let hits = instance_hits(&instances, origin, d);
        let first = hits.iter().min_by(|x, y| x.0.total_cmp(&y.0));
        match got {
            None => prop_assert!(
                hits.iter().all(|h| !h.3),
                "missed robust instance hits {:?} (ray {} {})",
                hits,
                origin,
                d
            ),
            Some(h) => {
                // User geometry in an instance gets the exact ray: its distance is exact.
                prop_assert_eq!(h.exact, h.geom_id == sphere_id, "{:?}", h);
                let inst = ids.iter().position(|&id| Some(id) == h.inst_id);
                prop_assert!(inst.is_some(), "hit {:?} names no instance of {:?}", h, ids);
                let part = if h.geom_id == sphere_id { 0 } else { 1 };
                prop_assert!(h.geom_id == sphere_id || h.geom_id == square_id, "{:?}", h);
                prop_assert!(part == 0 || h.prim_id < 2, "{:?}", h);
                // The reported instance and part are hit at the reported distance (a
                // non-robust, e.g. grazing, hit anywhere on the part) ...
                let matched = hits.iter().find(|r| {
                    r.1 == inst.unwrap() && r.2 == part && (close(r.0, h.t, 1e-4) || !r.3)
                });
                prop_assert!(matched.is_some(), "hit {:?} matches none of {:?}", h, hits);
                // ... the world hit point maps onto the untransformed surface ...
                let p = origin + h.t * d;
                let local = p - instances[inst.unwrap()].t;
                let scale = 1.0 + local.abs().max_element();
                if part == 0 {
                    prop_assert!(
                        (local.length() - 1.0).abs() < 1e-4 * scale,
                        "{} off the sphere",
                        local
                    );
                    // The part the user geometry reported comes back with the hit.
                    prop_assert_eq!(h.part, (local.z > 0.0) as u32, "{:?} at {}", h, local);
                } else {
                    let margin = (local.x - 2.0)
                        .min(3.0 - local.x)
                        .min(local.y)
                        .min(1.0 - local.y);
                    prop_assert!(
                        local.z.abs() < 1e-4 * scale && margin > -1e-3,
                        "{} off the square",
                        local
                    );
                }
                // ... and nothing robust is nearer.
                let f = first.unwrap();
                prop_assert!(
                    !(f.3 && f.0 < h.t && !close(f.0, h.t, 1e-3)),
                    "hit {:?} behind {:?}",
                    h,
                    f
                );
            }
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(config(256))]

    /// Two translated instances of one scene holding a user geometry (unit sphere) and native
    /// triangles (a square): hits land where the translations say, with the right instance and
    /// geometry ids.
    #[test]
    fn instances_hit_where_their_transforms_say(
        a in affine(),
        b in affine(),
        seed in any::<u64>(),
    ) {
        check_instances(a, b, seed)?;
    }
}

// ---------------------------------------------------------------------------------------------
// Errors
// ---------------------------------------------------------------------------------------------

/// Embree rejects a malformed device configuration (an integer option with a non-integer value),
/// and timbre turns that into an `Err` with Embree's error code. (Embree 3.13 ignores unknown
/// option names such as `unknown_option=1` on their own; it is `threads=abc` that fails.)
#[test]
fn embree_errors_surface_as_err() {
    match Device::new("threads=abc,unknown_option=1") {
        Err(EmbreeError::Device { code, message }) => {
            assert_ne!(code, 0, "RTC_ERROR_NONE is not an error");
            let shown = EmbreeError::Device { code, message }.to_string();
            assert!(shown.starts_with("Embree error"), "{shown}");
        }
        Err(other) => panic!("expected an Embree device error, got {other:?}"),
        Ok(_) => panic!("Embree accepted threads=abc"),
    }
    // The binding's own checks also return errors rather than passing bad data to Embree.
    let mut builder = device().scene_builder().unwrap();
    let out_of_range = builder.add_triangles(&[Vec3::ZERO, Vec3::X, Vec3::Y], &[[0, 1, 3]], 1);
    assert!(
        matches!(out_of_range, Err(EmbreeError::Creation(_))),
        "{out_of_range:?}"
    );
    // The device and builder stay usable after an error.
    builder
        .add_triangles(&[Vec3::ZERO, Vec3::X, Vec3::Y], &[[0, 1, 2]], 1)
        .unwrap();
    builder.commit().unwrap();
}

/// A ray leaving a triangle at a grazing angle, with the tracer's self-hit margin for meshes
/// (1e-5 × scale) as t_min (found by `scene_queries_match_brute_force`). Exactly, the ray meets
/// the triangle's plane only at t ≈ 0, so nothing lies in (t_min, ∞).
/// (Embree's f32 test finds the triangle beyond t_min; the exact recomputation rejects it and the
/// query must go on rather than fall back to the plane distance, t ≈ −4e-13.)
#[test]
fn grazing_ray_leaving_a_triangle_does_not_hit_it_again() {
    let vertices = vec![
        DVec3::new(
            -1.1402061843837985,
            0.48339898009918864,
            -0.9932700096540684,
        ),
        DVec3::new(0.6642619332805989, -0.9393043833448341, 0.0),
        DVec3::new(-1.2538070698428352, 0.0, 1.036532670241837),
    ];
    let mesh = TriangleMesh::new(vertices, vec![[1, 2, 0]]).unwrap();
    let o = DVec3::new(-0.23243426322928, -0.3701800733029964, 0.009849319556553437);
    let d = DVec3::new(-0.8109102226486831, 0.399282452571179, 0.4277828115675142);
    let t_min = 1.3701800733029966e-5;
    let n = mesh.frame(mesh.vertices()[0], 0).w;
    println!(
        "cos to the normal {:e}, origin off the plane {:e}",
        d.dot(n),
        (o - mesh.vertices()[0]).dot(n)
    );
    let scene = SceneGeometry::build(
        device(),
        vec![(Shape::TriangleMesh(mesh), true)],
        Vec::new(),
    )
    .unwrap();
    assert_eq!(scene.nearest_brute_force(o, d, t_min, f64::INFINITY), None);
    let mut failures = Vec::new();
    if let Some(h) = scene.nearest(o, d, t_min, f64::INFINITY) {
        failures.push(format!("nearest: {h:?}"));
    }
    if let Some(h) = scene.nearest8(o, &[d], t_min, f64::INFINITY)[0] {
        failures.push(format!("nearest8: {h:?}"));
    }
    if scene.shadowed(o, d, t_min, f64::INFINITY) {
        failures.push("shadowed".into());
    }
    assert!(
        failures.is_empty(),
        "self-hits below t_min reported: {failures:?}"
    );
}
