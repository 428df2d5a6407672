//! Arrays of objects ([`ObjectArray`]) traced as Embree instances of one shared prototype BVH,
//! checked against the brute-force reference (`SceneGeometry::nearest_brute_force`, a plain f64
//! loop over every object and every element).
//!
//! # What may differ from the brute force, and how that is decided
//!
//! By the rules of `common::verdict`, shared with `tests/embree_vs_reference.rs`, applied to
//! every *element primitive* (object, element, primitive): element k of an object is its shape
//! moved by `offsets[k]`, and its exact answer is the shape's own f64 answer for the ray moved by
//! −`offsets[k]`. Marginal primitives (whose answer changes when the ray moves by a few f32
//! roundings, the instance translation included) and ties may go either way; everything else
//! must match. `excuses_are_rare_with_arrays` shows, on a deterministic sample, that the excuses
//! are seldom needed and that hits on many different elements (and on meshes inside instances)
//! occur, so the property is not vacuous.
//!
//! The other tests check exact, hand-computed answers: element frames and offsets
//! (`sphere_elements_have_their_own_frames`), a 1000 × 1000 array
//! (`a_million_element_array_is_traced_exactly`), planes and enormous members tested per element
//! outside the BVH, arrays without offsets or members, and an arrayed object next to a plain copy
//! of the same shape. `queries_from_beyond_embree_range_get_the_brute_force_answer` reproduces a
//! bug: a ray whose origin lies beyond ±1.844e18 makes Embree abort the process.

mod common;

use glam::{DVec2, DVec3};
use proptest::prelude::*;
use proptest::strategy::ValueTree;
use proptest::test_runner::TestRunner;

use common::rays::{Query, close, device, same_hit, sample_point, self_hit_margin, surface_point};
use common::rng::Rng;
use common::verdict::{self, ANALYTIC_T, Element, check_queries, elements};
use common::{
    config, cylinder_shape, disc_shape, log_uniform, mesh_parts, normal_vector,
    parallelogram_shape, point_in, sphere_shape, unit_vector,
};
use timbre::geometry::{
    AnalyticShape, Cylinder, Hit, ObjectArray, Plane, SceneGeometry, Shape, Sphere, TriangleMesh,
};
use timbre::math::Frame;

/// The surface frame at `p` of the element `h` hit: the object's shape's own frame, moved by
/// the element's offset.
fn element_frame(scene: &SceneGeometry, h: &Hit, p: DVec3) -> Frame {
    scene.shapes()[h.object].frame(p - scene.offset(h.object, h.element), h.prim)
}

/// The surface coordinates at `p` of the element `h` hit, as [`element_frame`].
fn element_coordinates(scene: &SceneGeometry, h: &Hit, p: DVec3) -> DVec2 {
    scene.shapes()[h.object].coordinates(p - scene.offset(h.object, h.element), h.prim)
}

fn sphere(c: DVec3, r: f64) -> Shape {
    Shape::Sphere(Sphere::new(c, r).unwrap())
}

// ---------------------------------------------------------------------------------------------
// Random scenes with arrays
// ---------------------------------------------------------------------------------------------

/// A small mesh (3–5 vertices within 0.8 of a point within `spread` of the origin).
fn mesh(spread: f64) -> impl Strategy<Value = Shape> {
    mesh_parts(spread, 0.8, 3..6, 1..5).prop_filter_map("no usable triangle", |(v, t)| {
        TriangleMesh::new(v, t).ok().map(Shape::TriangleMesh)
    })
}

/// A bounded shape within about `spread` of the origin, of size 0.01 to 3.
fn bounded_shape(spread: f64) -> impl Strategy<Value = Shape> {
    prop_oneof![
        4 => sphere_shape(spread, 1.0),
        3 => disc_shape(spread, 1.0),
        3 => cylinder_shape(spread, 3.0, 0.5),
        3 => parallelogram_shape(spread, 2.0),
        3 => mesh(spread),
    ]
}

fn plane(spread: f64) -> impl Strategy<Value = Shape> {
    (point_in(spread), normal_vector(), unit_vector())
        .prop_filter_map("u along the normal", |(p, n, u)| {
            Plane::new(p, n, u).ok().map(Shape::Plane)
        })
}

/// Objects in no array: mostly bounded shapes spread over the scene, sometimes a plane.
fn plain_shape() -> impl Strategy<Value = Shape> {
    prop_oneof![12 => bounded_shape(15.0), 1 => plane(20.0)]
}

/// An array member: a shape near the origin (the offsets place it), with planes if asked.
fn member_shape(planes: bool) -> impl Strategy<Value = Shape> {
    let plane_weight = if planes { 2 } else { 0 };
    prop_oneof![16 => bounded_shape(1.5), plane_weight => plane(1.5)]
}

/// Offsets on a 1-, 2- or 3-D grid: base + Σ i_k s_k with 0 ≤ i_k < n_k, the spacing vectors
/// s_k random (sometimes along an axis) of length 0.3 to 5 (so copies may overlap), at most 64,
/// 16² or 6³ elements. With `small`, at most 4 per dimension.
fn grid(small: bool) -> impl Strategy<Value = Vec<DVec3>> {
    (1..=3usize, point_in(10.0))
        .prop_flat_map(move |(dims, base)| {
            let max = if small { 4 } else { [64, 16, 6][dims - 1] };
            (
                Just(base),
                prop::collection::vec(
                    (normal_vector(), log_uniform(0.3, 5.0), 1..=max as u32),
                    dims,
                ),
            )
        })
        .prop_map(|(base, axes)| {
            let mut offsets = vec![base];
            for (direction, length, count) in axes {
                offsets = (0..count)
                    .flat_map(|i| {
                        offsets
                            .iter()
                            .map(move |&o| o + (i as f64 * length) * direction)
                    })
                    .collect();
            }
            offsets
        })
}

/// A random scene: objects (shape, shadow-throwing), 1–3 arrays over some of them, and a seed
/// for its rays.
#[derive(Debug, Clone)]
struct Case {
    objects: Vec<(Shape, bool)>,
    arrays: Vec<ObjectArray>,
    seed: u64,
}

/// Scenes with 0–3 plain objects and 1–3 arrays of 1–3 members each; with `planes_in_arrays`,
/// array members may be planes (and the grids are small).
fn case(planes_in_arrays: bool) -> impl Strategy<Value = Case> {
    let array = (
        prop::collection::vec((member_shape(planes_in_arrays), any::<bool>()), 1..=3),
        grid(planes_in_arrays),
    );
    (
        prop::collection::vec((plain_shape(), any::<bool>()), 0..4),
        prop::collection::vec(array, 1..=3),
        any::<u64>(),
    )
        .prop_map(|(plain, arrays, seed)| {
            // Plain objects are interleaved with the arrays' members, so that array ranges do
            // not all start at 0.
            let mut objects = Vec::new();
            let mut ranges = Vec::new();
            let mut plain = plain.into_iter();
            for (members, offsets) in arrays {
                objects.extend(plain.next());
                let start = objects.len();
                objects.extend(members);
                ranges.push(ObjectArray {
                    objects: start..objects.len(),
                    offsets,
                });
            }
            objects.extend(plain);
            Case {
                objects,
                arrays: ranges,
                seed,
            }
        })
}

/// Draws rays for a scene: 15% random, 70% aimed at a point of a random element (an object
/// chosen uniformly, then one of its elements), 15% leaving the surface of a random element
/// with the tracer's self-hit margin (1e-9 × scale, 1e-5 × scale for meshes) as t_min.
struct RaySource<'a> {
    objects: &'a [(Shape, bool)],
    /// Elements of each object.
    by_object: Vec<Vec<Element>>,
    /// Bounds of all bounded elements, enlarged by 5.
    lo: DVec3,
    hi: DVec3,
}

impl<'a> RaySource<'a> {
    fn new(objects: &'a [(Shape, bool)], elements: &[Element]) -> RaySource<'a> {
        let mut by_object = vec![Vec::new(); objects.len()];
        let (mut lo, mut hi) = (DVec3::splat(-5.0), DVec3::splat(5.0));
        for e in elements {
            by_object[e.object].push(*e);
            if let Some((a, b)) = objects[e.object].0.bounds() {
                lo = lo.min(a + e.offset - 5.0);
                hi = hi.max(b + e.offset + 5.0);
            }
        }
        RaySource {
            objects,
            by_object,
            lo,
            hi,
        }
    }

    /// A random element (of an object with elements).
    fn element(&self, rng: &mut Rng) -> Option<Element> {
        let candidates: Vec<&Vec<Element>> =
            self.by_object.iter().filter(|e| !e.is_empty()).collect();
        if candidates.is_empty() {
            return None;
        }
        let es = candidates[rng.index(candidates.len())];
        Some(es[rng.index(es.len())])
    }

    fn query(&self, rng: &mut Rng) -> Query {
        let t_max = if rng.f() < 0.25 {
            rng.range(0.0, 40.0)
        } else {
            f64::INFINITY
        };
        let kind = rng.f();
        let random = Query {
            origin: rng.point_in_box(self.lo, self.hi),
            direction: rng.unit(),
            t_min: 0.0,
            t_max,
        };
        let Some(e) = self.element(rng) else {
            return random;
        };
        let shape = &self.objects[e.object].0;
        if kind < 0.15 {
            random
        } else if kind < 0.85 {
            let target = sample_point(shape, rng) + e.offset;
            let origin = if rng.f() < 0.7 {
                target + rng.range(0.5, 30.0) * rng.unit()
            } else {
                random.origin
            };
            Query {
                direction: (target - origin)
                    .try_normalize()
                    .unwrap_or(random.direction),
                origin,
                ..random
            }
        } else {
            let origin = surface_point(shape, rng) + e.offset;
            Query {
                origin,
                t_min: self_hit_margin(shape, origin),
                ..random
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// The checks (the rules are those of `common::verdict`)
// ---------------------------------------------------------------------------------------------

/// Tally of verdicts over a run, and where the hits were.
#[derive(Debug, Default)]
struct Tally {
    verdicts: verdict::Tally,
    /// Hits on an element of an array with index > 0.
    later_elements: usize,
    /// Hits on meshes inside arrays (native triangles in an instance).
    array_meshes: usize,
    /// Hits on objects in no array.
    plain: usize,
}

impl Tally {
    fn add(&mut self, t: &Tally) {
        self.verdicts.add(&t.verdicts);
        self.later_elements += t.later_elements;
        self.array_meshes += t.array_meshes;
        self.plain += t.plain;
    }
}

/// Runs every check on one scene with `rays` single rays and `packets` packets of up to 8.
fn check_scene(
    objects: &[(Shape, bool)],
    arrays: &[ObjectArray],
    seed: u64,
    rays: usize,
    packets: usize,
) -> Result<Tally, String> {
    let scene = SceneGeometry::build(device(), objects.to_vec(), arrays.to_vec())
        .map_err(|e| e.to_string())?;
    let elements = elements(objects, arrays);
    let source = RaySource::new(objects, &elements);
    let in_array = |object: usize| arrays.iter().any(|a| a.objects.contains(&object));
    let (mut later_elements, mut array_meshes, mut plain) = (0, 0, 0);
    let verdicts = check_queries(
        &scene,
        objects,
        &elements,
        &mut Rng(seed),
        rays,
        packets,
        |rng| source.query(rng),
        |answers, got| {
            if let Some(h) = got {
                later_elements += usize::from(h.element > 0);
                array_meshes += usize::from(in_array(h.object) && answers.is_mesh(h.object));
                plain += usize::from(!in_array(h.object));
            }
        },
    )?;
    Ok(Tally {
        verdicts,
        later_elements,
        array_meshes,
        plain,
    })
}

proptest! {
    #![proptest_config(config(200))]

    /// `nearest`, each lane of `nearest8` and `shadowed` against brute force on random scenes
    /// with 1–3 arrays (1-, 2- and 3-D grids of up to a few hundred elements) of spheres, discs,
    /// cylinders, parallelograms and small meshes, plus a few plain objects.
    #[test]
    fn array_queries_match_brute_force(c in case(false)) {
        check_scene(&c.objects, &c.arrays, c.seed, 32, 4).map_err(TestCaseError::fail)?;
    }

    /// As above with planes among the array members (unbounded, so tested directly per
    /// element, next to the instanced members of the same array).
    #[test]
    fn arrays_with_planes_match_brute_force(c in case(true)) {
        check_scene(&c.objects, &c.arrays, c.seed, 32, 4).map_err(TestCaseError::fail)?;
    }
}

/// Guards against a vacuous property: on a deterministic sample, most answers agree exactly
/// with the brute force (same object, element, primitive and t); the excuses are rare; packets
/// agree with single rays; hits on later elements, on meshes inside instances and on plain
/// objects all occur, as do shadowed and unshadowed rays.
#[test]
fn excuses_are_rare_with_arrays() {
    let mut runner = TestRunner::deterministic();
    let mut total = Tally::default();
    let strategy = case(false);
    for _ in 0..400 {
        let c = strategy.new_tree(&mut runner).unwrap().current();
        let t = check_scene(&c.objects, &c.arrays, c.seed, 32, 4)
            .unwrap_or_else(|e| panic!("{e}\n{c:?}"));
        total.add(&t);
    }
    println!("verdicts [same, equal tie, near tie, marginal]: {total:?}");
    let rays: usize = total.verdicts.nearest.iter().sum();
    let lanes: usize = total.verdicts.packet.iter().sum();
    assert!(
        total.verdicts.hits > rays / 3 && total.verdicts.hits < rays * 19 / 20,
        "{total:?}"
    );
    // Equal distances on different element primitives come from overlapping coplanar copies
    // and coplanar triangles of the random meshes; near ties and marginal primitives are rare.
    assert!(total.verdicts.nearest[1] <= rays / 50, "{total:?}");
    assert!(total.verdicts.packet[1] <= lanes / 50, "{total:?}");
    assert!(
        total.verdicts.nearest[2] + total.verdicts.nearest[3] <= rays / 500,
        "{total:?}"
    );
    assert!(
        total.verdicts.packet[2] + total.verdicts.packet[3] <= lanes / 500,
        "{total:?}"
    );
    assert!(total.verdicts.shadowed[3] <= rays / 200, "{total:?}");
    assert!(total.verdicts.packet_differs <= lanes / 50, "{total:?}");
    assert!(total.later_elements > total.verdicts.hits / 3, "{total:?}");
    assert!(total.array_meshes > total.verdicts.hits / 50, "{total:?}");
    assert!(total.plain > total.verdicts.hits / 50, "{total:?}");
    assert!(
        total.verdicts.shadowed_rays > rays / 5
            && total.verdicts.shadowed_rays < total.verdicts.hits,
        "{total:?}"
    );
}

// ---------------------------------------------------------------------------------------------
// Element frames
// ---------------------------------------------------------------------------------------------

/// A sphere element's frame is its own: the normal at a hit on element k points from the
/// element's centre (the sphere's centre moved by offsets[k]), `offset` gives offsets[k], and a
/// ray aimed at element k (from above a flat grid, so nothing else is in the way) reports k.
#[test]
fn sphere_elements_have_their_own_frames() {
    let (centre, r) = (DVec3::new(0.3, -0.2, 0.1), 0.4);
    let a = DVec3::new(1.5, 0.2, 0.0);
    let b = DVec3::new(-0.3, 1.4, 0.0);
    let offsets: Vec<DVec3> = (0..5)
        .flat_map(|j| (0..7).map(move |i| DVec3::new(-4.0, 2.0, 0.0) + i as f64 * a + j as f64 * b))
        .collect();
    let objects = vec![
        (sphere(DVec3::new(0.0, 0.0, -30.0), 1.0), true),
        (sphere(centre, r), true),
        (sphere(DVec3::new(0.0, 0.0, -40.0), 1.0), false),
    ];
    let arrays = vec![ObjectArray {
        objects: 1..2,
        offsets: offsets.clone(),
    }];
    let scene = SceneGeometry::build(device(), objects, arrays).unwrap();
    assert_eq!(scene.offset(0, 0), DVec3::ZERO);
    assert_eq!(scene.offset(2, 0), DVec3::ZERO);
    let mut rng = Rng(7);
    for _ in 0..500 {
        let k = rng.index(offsets.len());
        let c = centre + offsets[k];
        // From above (elevation 60° to 89°) at a point within 0.9 r of the centre: the ray
        // passes neighbours (1.4 or more apart) well above their tops.
        let (elevation, azimuth) = (
            rng.range(60f64, 89.0).to_radians(),
            rng.range(0.0, std::f64::consts::TAU),
        );
        let up = DVec3::new(
            elevation.cos() * azimuth.cos(),
            elevation.cos() * azimuth.sin(),
            elevation.sin(),
        );
        let origin = c + rng.range(2.0, 20.0) * up;
        let phi = rng.range(0.0, std::f64::consts::TAU);
        let target = c + 0.9 * r * rng.f().sqrt() * DVec3::new(phi.cos(), phi.sin(), 0.0);
        let d = (target - origin).normalize();
        let hit = scene
            .nearest(origin, d, 0.0, f64::INFINITY)
            .unwrap_or_else(|| panic!("ray at element {k} missed"));
        assert_eq!(
            (hit.object, hit.element, hit.prim),
            (1, k as u32, 0),
            "{hit:?}"
        );
        let brute = scene.nearest_brute_force(origin, d, 0.0, f64::INFINITY);
        assert!(
            brute.is_some_and(|b| (b.object, b.element, b.prim) == (1, k as u32, 0)
                && close(b.t, hit.t, ANALYTIC_T)),
            "{hit:?} vs brute force {brute:?}"
        );
        assert_eq!(scene.offset(hit.object, hit.element), offsets[k]);
        let p = origin + hit.t * d;
        assert!(
            ((p - c).length() - r).abs() < 1e-12,
            "{p} not on element {k}"
        );
        let frame = element_frame(&scene, &hit, p);
        let expected = (p - c).normalize();
        assert!(
            (frame.w - expected).length() < 1e-12,
            "{frame:?} at {p}, element {k}"
        );
        assert!(frame.u.dot(frame.w).abs() < 1e-12 && frame.v.dot(frame.w).abs() < 1e-12);
        // The same as the frame and coordinates of a sphere placed there on its own.
        let moved = Sphere::new(c, r).unwrap();
        assert!(
            (frame.u - moved.frame(p, 0).u).length() < 1e-12,
            "{frame:?}"
        );
        let (uv, expected_uv): (DVec2, DVec2) = (
            element_coordinates(&scene, &hit, p),
            moved.coordinates(p, 0),
        );
        assert!((uv - expected_uv).length() < 1e-9, "{uv} vs {expected_uv}");
        // A shadow ray towards the element is shadowed, one stopping short of it is not.
        assert!(scene.shadowed(origin, d, 0.0, f64::INFINITY));
        assert!(!scene.shadowed(origin, d, 0.0, 0.999 * hit.t));
    }
    // A packet from high above aimed at the tops of 8 elements reports each of them.
    let origin = DVec3::new(1.0, 4.0, 60.0);
    let ks = [0usize, 6, 7, 13, 17, 21, 29, 34];
    let tops: Vec<DVec3> = ks
        .iter()
        .map(|&k| centre + offsets[k] + r * DVec3::Z)
        .collect();
    let dirs: Vec<DVec3> = tops.iter().map(|&p| (p - origin).normalize()).collect();
    let lanes = scene.nearest8(origin, &dirs, 0.0, f64::INFINITY);
    for (i, lane) in lanes.iter().enumerate() {
        let hit = lane.unwrap_or_else(|| panic!("lane {i} missed"));
        assert_eq!((hit.object, hit.element), (1, ks[i] as u32), "{hit:?}");
        assert!(close(hit.t, (tops[i] - origin).length(), 1e-12), "{hit:?}");
        assert_eq!(
            scene.nearest(origin, dirs[i], 0.0, f64::INFINITY),
            Some(hit)
        );
        let w = element_frame(&scene, &hit, origin + hit.t * dirs[i]).w;
        assert!((w - DVec3::Z).length() < 1e-6, "{w}");
    }
}

// ---------------------------------------------------------------------------------------------
// A large array
// ---------------------------------------------------------------------------------------------

/// A 1000 × 1000 array (1,000,000 elements) of one small sphere (radius 0.25 at the origin,
/// offsets (i, j, 0) for element 1000 i + j) builds, and rays aimed at specific elements report
/// exactly that element at the exact distance, as brute force does.
#[test]
fn a_million_element_array_is_traced_exactly() {
    const N: usize = 1000;
    let r = 0.25;
    let offsets: Vec<DVec3> = (0..N)
        .flat_map(|i| (0..N).map(move |j| DVec3::new(i as f64, j as f64, 0.0)))
        .collect();
    let objects = vec![(sphere(DVec3::ZERO, r), true)];
    let arrays = vec![ObjectArray {
        objects: 0..1,
        offsets,
    }];
    let scene = SceneGeometry::build(device(), objects, arrays).unwrap();
    let element = |i: u32, j: u32| i * N as u32 + j;
    assert_eq!(
        scene.offset(0, element(123, 456)),
        DVec3::new(123.0, 456.0, 0.0)
    );
    let hit = |object, element, t| Hit {
        object,
        element,
        prim: 0,
        t,
    };
    // (origin, direction, t_min, expected hit): straight down onto (123, 456), up from below
    // onto the last element, out of element (700, 3) from its centre, along a row from outside
    // the grid (the first element in the way), and between two rows (nothing).
    let cases = [
        (
            DVec3::new(123.0, 456.0, 10.0),
            DVec3::NEG_Z,
            Some(hit(0, element(123, 456), 9.75)),
        ),
        (
            DVec3::new(999.0, 999.0, -5.0),
            DVec3::Z,
            Some(hit(0, element(999, 999), 4.75)),
        ),
        (
            DVec3::new(700.0, 3.0, 0.0),
            DVec3::Y,
            Some(hit(0, element(700, 3), 0.25)),
        ),
        (
            DVec3::new(-2.0, 456.0, 0.0),
            DVec3::X,
            Some(hit(0, element(0, 456), 1.75)),
        ),
        (
            DVec3::new(1002.0, 0.0, 0.1),
            DVec3::NEG_X,
            Some(hit(0, element(999, 0), 3.0 - (r * r - 0.1f64 * 0.1).sqrt())),
        ),
        (DVec3::new(-2.0, 456.5, 0.0), DVec3::X, None),
    ];
    for (origin, d, expected) in cases {
        let got = scene.nearest(origin, d, 0.0, f64::INFINITY);
        let brute = scene.nearest_brute_force(origin, d, 0.0, f64::INFINITY);
        assert_eq!(brute, expected, "brute force, ray {origin} {d}");
        assert_eq!(got, expected, "ray {origin} {d}");
        assert_eq!(
            scene.nearest8(origin, &[d], 0.0, f64::INFINITY)[0],
            expected
        );
        assert_eq!(
            scene.shadowed(origin, d, 0.0, f64::INFINITY),
            expected.is_some()
        );
        if let Some(h) = expected {
            assert!(!scene.shadowed(origin, d, 0.0, h.t - 1e-9));
            assert_eq!(scene.nearest(origin, d, 0.0, h.t), None);
        }
    }
    // Oblique rays from high above onto the tops of chosen elements, traced one by one and as
    // one packet: each reports its element at the exact distance.
    let origin = DVec3::new(480.0, 530.0, 700.0);
    let targets = [
        (123, 456),
        (0, 0),
        (999, 999),
        (1, 998),
        (500, 500),
        (480, 531),
        (777, 13),
        (42, 600),
    ];
    let tops: Vec<DVec3> = targets
        .iter()
        .map(|&(i, j)| DVec3::new(i as f64, j as f64, r))
        .collect();
    let dirs: Vec<DVec3> = tops.iter().map(|&p| (p - origin).normalize()).collect();
    let lanes = scene.nearest8(origin, &dirs, 0.0, f64::INFINITY);
    for (k, &(i, j)) in targets.iter().enumerate() {
        let single = scene.nearest(origin, dirs[k], 0.0, f64::INFINITY);
        let brute = scene.nearest_brute_force(origin, dirs[k], 0.0, f64::INFINITY);
        let h = single.unwrap_or_else(|| panic!("ray at ({i}, {j}) missed"));
        assert_eq!(
            (h.object, h.element, h.prim),
            (0, element(i, j), 0),
            "{h:?}"
        );
        assert!(close(h.t, (tops[k] - origin).length(), 1e-12), "{h:?}");
        assert_eq!(brute, single, "({i}, {j})");
        assert_eq!(lanes[k], single, "packet lane {k}");
    }
}

// ---------------------------------------------------------------------------------------------
// Planes, enormous shapes and empty arrays
// ---------------------------------------------------------------------------------------------

/// A stack of floors: the plane z = 0 in an array with offsets (0, 0, 2k), k < 5, next to a
/// sphere member of the same array (which goes into Embree). Hits report the right floor, and
/// random rays match brute force exactly.
#[test]
fn planes_in_an_array_are_intersected_per_element() {
    let floor = Shape::Plane(Plane::new(DVec3::ZERO, DVec3::Z, DVec3::X).unwrap());
    let objects = vec![
        (sphere(DVec3::new(0.0, 0.0, 20.0), 1.0), true),
        (floor, false),
        (sphere(DVec3::new(3.0, 0.0, 1.0), 0.5), true),
    ];
    let offsets: Vec<DVec3> = (0..5)
        .map(|k| DVec3::new(0.0, 0.0, 2.0 * k as f64))
        .collect();
    let arrays = vec![ObjectArray {
        objects: 1..3,
        offsets,
    }];
    let scene = SceneGeometry::build(device(), objects.clone(), arrays.clone()).unwrap();
    let hit = |object, element, t| {
        Some(Hit {
            object,
            element,
            prim: 0,
            t,
        })
    };
    let o = DVec3::new(0.0, 0.0, 7.5);
    assert_eq!(
        scene.nearest(o, DVec3::NEG_Z, 0.0, f64::INFINITY),
        hit(1, 3, 1.5)
    );
    assert_eq!(
        scene.nearest(o, DVec3::NEG_Z, 2.0, f64::INFINITY),
        hit(1, 2, 3.5)
    );
    assert_eq!(
        scene.nearest(o, DVec3::Z, 0.0, f64::INFINITY),
        hit(1, 4, 0.5)
    );
    assert_eq!(
        scene.nearest(o, DVec3::Z, 0.6, f64::INFINITY),
        hit(0, 0, 11.5)
    );
    let below = DVec3::new(0.0, 0.0, -1.0);
    assert_eq!(
        scene.nearest(below, DVec3::Z, 0.0, f64::INFINITY),
        hit(1, 0, 1.0)
    );
    assert_eq!(scene.nearest(below, DVec3::NEG_Z, 0.0, f64::INFINITY), None);
    assert_eq!(
        scene.nearest8(o, &[DVec3::NEG_Z, DVec3::Z, DVec3::Y], 0.0, f64::INFINITY)[..3],
        [hit(1, 3, 1.5), hit(1, 4, 0.5), None]
    );
    // The sphere's elements sit between the floors: element 2 is centred at (3, 0, 5).
    let above = DVec3::new(3.0, 0.0, 5.75);
    let h = scene
        .nearest(above, DVec3::NEG_Z, 0.0, f64::INFINITY)
        .unwrap();
    assert_eq!((h.object, h.element), (2, 2), "{h:?}");
    assert!(close(h.t, 0.25, 1e-12), "{h:?}");
    // Planes throw no shadow here; the sphere elements and the plain sphere do.
    assert!(!scene.shadowed(o, DVec3::NEG_Z, 0.0, f64::INFINITY));
    assert!(scene.shadowed(o, DVec3::Z, 0.0, f64::INFINITY));
    assert!(scene.shadowed(above, DVec3::NEG_Z, 0.0, f64::INFINITY));
    // Frames and coordinates are the floor's own, moved by the element's offset.
    let p = o + 1.5 * DVec3::NEG_Z;
    let h = hit(1, 3, 1.5).unwrap();
    assert_eq!(element_frame(&scene, &h, p).w, DVec3::Z);
    let q = DVec3::new(1.25, -2.5, 6.0);
    assert!((element_coordinates(&scene, &h, q) - DVec2::new(1.25, -2.5)).length() < 1e-15);
    // Random rays: everything here is analytic (exact in f64); only a ray grazing a bounding box
    // could need an excuse, and none of this sample does.
    let t = check_scene(&objects, &arrays, 11, 2000, 100).unwrap();
    assert_eq!(t.verdicts.nearest[1..], [0, 0, 0], "{t:?}");
    assert_eq!(t.verdicts.packet[1..], [0, 0, 0], "{t:?}");
}

/// Members whose copies reach beyond Embree's range (extent over 1e18) are intersected directly
/// per element, like planes; an ordinary array next to them stays in Embree.
#[test]
fn enormous_array_members_are_intersected_per_element() {
    // Within Embree's range of ray origins (±1.844e18), but the copies reach beyond 1e18.
    let far = DVec3::new(1.5e18, 0.0, 0.0);
    let objects = vec![
        (sphere(DVec3::ZERO, 1.0), true),
        (
            Shape::Cylinder(
                Cylinder::new(DVec3::new(5.0, 0.0, 0.0), DVec3::new(5.0, 0.0, 2.0), 0.5).unwrap(),
            ),
            false,
        ),
        (sphere(DVec3::new(0.0, 5.0, 0.0), 0.5), true),
    ];
    let arrays = vec![
        ObjectArray {
            objects: 0..2,
            offsets: vec![DVec3::ZERO, far, DVec3::new(0.0, 0.0, -3.0)],
        },
        ObjectArray {
            objects: 2..3,
            offsets: vec![DVec3::ZERO, DVec3::new(0.0, 2.0, 0.0)],
        },
    ];
    let scene = SceneGeometry::build(device(), objects, arrays).unwrap();
    let hit = |object, element, t| {
        Some(Hit {
            object,
            element,
            prim: 0,
            t,
        })
    };
    let down = DVec3::NEG_Z;
    let cases = [
        (DVec3::new(0.0, 0.0, 10.0), down, hit(0, 0, 9.0)),
        (far + DVec3::new(0.0, 0.0, 10.0), down, hit(0, 1, 9.0)),
        (DVec3::new(0.0, 0.0, -10.0), DVec3::Z, hit(0, 2, 6.0)),
        (DVec3::new(5.0, 0.0, 10.0), down, hit(1, 0, 8.0)),
        (DVec3::new(5.0, 0.0, 0.0), down, hit(1, 2, 1.0)),
        (DVec3::new(0.0, 5.0, 10.0), down, hit(2, 0, 9.5)),
        (DVec3::new(0.0, 7.0, 10.0), down, hit(2, 1, 9.5)),
        (DVec3::new(0.0, 9.0, 10.0), down, None),
    ];
    for (origin, d, expected) in cases {
        assert_eq!(
            scene.nearest_brute_force(origin, d, 0.0, f64::INFINITY),
            expected,
            "brute force {origin}"
        );
        assert_eq!(
            scene.nearest(origin, d, 0.0, f64::INFINITY),
            expected,
            "{origin}"
        );
        assert_eq!(
            scene.nearest8(origin, &[d], 0.0, f64::INFINITY)[0],
            expected
        );
        let throws = expected.is_some_and(|h| h.object != 1);
        assert_eq!(
            scene.shadowed(origin, d, 0.0, f64::INFINITY),
            throws,
            "{origin}"
        );
    }
}

/// An array with an empty list of offsets has no elements: none of its members (a sphere, a
/// plane, a mesh) is hit or throws a shadow, as brute force says; an array without members is
/// harmless; plain objects are unaffected.
#[test]
fn an_array_without_offsets_has_no_elements() {
    let mesh = TriangleMesh::new(
        vec![
            DVec3::new(-2.0, -2.0, 3.0),
            DVec3::new(2.0, -2.0, 3.0),
            DVec3::new(0.0, 2.0, 3.0),
        ],
        vec![[0, 1, 2]],
    )
    .unwrap();
    let objects = vec![
        (sphere(DVec3::ZERO, 1.0), true),
        (
            Shape::Plane(Plane::new(DVec3::new(0.0, 0.0, -5.0), DVec3::Z, DVec3::X).unwrap()),
            true,
        ),
        (Shape::TriangleMesh(mesh), true),
        (sphere(DVec3::new(0.0, 0.0, 10.0), 1.0), false),
    ];
    let arrays = vec![
        ObjectArray {
            objects: 0..3,
            offsets: Vec::new(),
        },
        ObjectArray {
            objects: 4..4,
            offsets: vec![DVec3::ONE, DVec3::ZERO],
        },
    ];
    let scene = SceneGeometry::build(device(), objects.clone(), arrays.clone()).unwrap();
    assert_eq!(scene.arrays(), &arrays[..]);
    let o = DVec3::new(0.1, 0.2, 0.3);
    assert_eq!(scene.nearest(o, DVec3::NEG_Z, 0.0, f64::INFINITY), None);
    assert_eq!(
        scene.nearest_brute_force(o, DVec3::NEG_Z, 0.0, f64::INFINITY),
        None
    );
    assert!(!scene.shadowed(o, DVec3::NEG_Z, 0.0, f64::INFINITY));
    let up = (DVec3::new(0.0, 0.0, 10.0) - o).normalize();
    let h = scene
        .nearest(o, up, 0.0, f64::INFINITY)
        .expect("the plain sphere");
    assert_eq!((h.object, h.element, h.prim), (3, 0, 0));
    assert_eq!(
        scene.nearest_brute_force(o, up, 0.0, f64::INFINITY),
        Some(h)
    );
    assert!(!scene.shadowed(o, up, 0.0, f64::INFINITY));
    let mut rng = Rng(5);
    for _ in 0..500 {
        let origin = 3.0 * rng.unit();
        let d = rng.unit();
        let got = scene.nearest(origin, d, 0.0, f64::INFINITY);
        assert!(got.is_none_or(|h| h.object == 3), "{got:?}");
        assert_eq!(
            got,
            scene.nearest_brute_force(origin, d, 0.0, f64::INFINITY)
        );
        assert_eq!(scene.nearest8(origin, &[d, -d], 0.0, f64::INFINITY)[0], got);
        assert!(!scene.shadowed(origin, d, 0.0, f64::INFINITY));
    }
}

// ---------------------------------------------------------------------------------------------
// An object in an array next to a plain copy of the same shape
// ---------------------------------------------------------------------------------------------

/// The same sphere and the same mesh (a square) are placed once as plain objects and again as
/// members of an array whose offsets move them elsewhere: hits, frames, offsets and shadows tell
/// the plain copies from the array elements.
#[test]
fn an_array_element_and_a_plain_copy_are_told_apart() {
    let ball = sphere(DVec3::ZERO, 0.5);
    let square = Shape::TriangleMesh(
        TriangleMesh::new(
            vec![
                DVec3::new(2.6, -0.4, 0.0),
                DVec3::new(3.4, -0.4, 0.0),
                DVec3::new(3.4, 0.4, 0.0),
                DVec3::new(2.6, 0.4, 0.0),
            ],
            vec![[0, 1, 2], [0, 2, 3]],
        )
        .unwrap(),
    );
    let offsets = vec![
        DVec3::new(0.0, 4.0, 0.0),
        DVec3::new(0.0, 8.0, 0.0),
        DVec3::new(10.0, 0.0, 0.0),
    ];
    let objects = vec![
        (ball.clone(), false),
        (ball, true),
        (square.clone(), true),
        (square, false),
    ];
    let arrays = vec![ObjectArray {
        objects: 1..3,
        offsets: offsets.clone(),
    }];
    let scene = SceneGeometry::build(device(), objects.clone(), arrays.clone()).unwrap();
    assert_eq!(scene.offset(0, 0), DVec3::ZERO);
    assert_eq!(scene.offset(3, 0), DVec3::ZERO);
    for (k, &o) in offsets.iter().enumerate() {
        assert_eq!(scene.offset(1, k as u32), o);
        assert_eq!(scene.offset(2, k as u32), o);
    }
    // (x, y) of a ray straight down from z = 10 -> (object, element, t).
    type Expected = (usize, u32, f64);
    let cases: [((f64, f64), Expected); 9] = [
        ((0.0, 0.0), (0, 0, 9.5)),
        ((0.0, 4.0), (1, 0, 9.5)),
        ((0.0, 8.0), (1, 1, 9.5)),
        ((10.0, 0.0), (1, 2, 9.5)),
        ((3.1, 0.2), (3, 0, 10.0)),
        ((3.1, 4.2), (2, 0, 10.0)),
        ((2.8, 7.7), (2, 1, 10.0)),
        ((13.3, -0.1), (2, 2, 10.0)),
        ((0.2, 4.1), (1, 0, 10.0 - (0.25f64 - 0.05).sqrt())),
    ];
    let origins: Vec<DVec3> = cases
        .iter()
        .map(|&((x, y), _)| DVec3::new(x, y, 10.0))
        .collect();
    for (&origin, &(_, (object, element, t))) in origins.iter().zip(&cases) {
        let d = DVec3::NEG_Z;
        let h = scene
            .nearest(origin, d, 0.0, f64::INFINITY)
            .unwrap_or_else(|| panic!("ray from {origin} missed"));
        assert_eq!(
            (h.object, h.element),
            (object, element),
            "ray from {origin}: {h:?}"
        );
        assert!(close(h.t, t, 1e-12), "ray from {origin}: {h:?}");
        let brute = scene
            .nearest_brute_force(origin, d, 0.0, f64::INFINITY)
            .unwrap();
        assert_eq!(
            (brute.object, brute.element, brute.prim),
            (h.object, h.element, h.prim)
        );
        assert!(close(brute.t, h.t, 1e-12));
        // Only the array's members throw shadows.
        assert_eq!(
            scene.shadowed(origin, d, 0.0, f64::INFINITY),
            objects[object].1,
            "ray from {origin}"
        );
        // The frame is the hit element's own.
        let p = origin + h.t * d;
        let w = element_frame(&scene, &h, p).w;
        let expected = match object {
            0 | 1 => (p - scene.offset(object, element)).normalize(),
            _ => DVec3::Z,
        };
        assert!((w - expected).length() < 1e-12, "{w} vs {expected} at {p}");
    }
    // The off-centre hit on element 0 has the element's normal, not the plain sphere's.
    let p = DVec3::new(0.2, 4.1, (0.25f64 - 0.05).sqrt());
    let h = scene
        .nearest(DVec3::new(0.2, 4.1, 10.0), DVec3::NEG_Z, 0.0, f64::INFINITY)
        .unwrap();
    let w = element_frame(&scene, &h, p).w;
    assert!(
        (w - DVec3::new(0.4, 0.2, p.z / 0.5)).length() < 1e-12,
        "{w}"
    );
    assert!((w - p.normalize()).length() > 0.1);
    // The same rays as one packet from a common origin.
    let origin = DVec3::new(5.0, 4.0, 30.0);
    let dirs: Vec<DVec3> = cases[..8]
        .iter()
        .map(|&((x, y), _)| (DVec3::new(x, y, 0.0) - origin).normalize())
        .collect();
    let lanes = scene.nearest8(origin, &dirs, 0.0, f64::INFINITY);
    for (i, (&d, &((_, _), (object, element, _)))) in dirs.iter().zip(&cases).enumerate() {
        let h = lanes[i].unwrap_or_else(|| panic!("lane {i} missed"));
        assert_eq!((h.object, h.element), (object, element), "lane {i}: {h:?}");
        let single = scene.nearest(origin, d, 0.0, f64::INFINITY).unwrap();
        assert_eq!(
            (single.object, single.element, single.prim),
            (h.object, h.element, h.prim)
        );
        assert!(close(single.t, h.t, 1e-12));
    }
    // Random rays: every rule of the property test.
    let t = check_scene(&objects, &arrays, 3, 2000, 100).unwrap();
    assert!(t.verdicts.nearest[2] + t.verdicts.nearest[3] <= 10, "{t:?}");
}

// ---------------------------------------------------------------------------------------------
// Misuse
// ---------------------------------------------------------------------------------------------

#[test]
#[should_panic(expected = "object in two arrays")]
fn an_object_in_two_arrays_is_rejected() {
    let objects = vec![
        (sphere(DVec3::ZERO, 1.0), true),
        (sphere(DVec3::X, 1.0), true),
    ];
    let arrays = vec![
        ObjectArray {
            objects: 0..2,
            offsets: vec![DVec3::ZERO],
        },
        ObjectArray {
            objects: 1..2,
            offsets: vec![DVec3::Y],
        },
    ];
    let _ = SceneGeometry::build(device(), objects, arrays);
}

// ---------------------------------------------------------------------------------------------
// Rays from beyond Embree's range
// ---------------------------------------------------------------------------------------------

/// Queries whose ray origin lies beyond Embree's range (|coordinate| > 1.844e18, Embree's
/// `FLT_LARGE`) still get the brute-force answer: the scene supports shapes out there (enormous
/// shapes and array elements with enormous offsets are intersected directly), and a hit out
/// there (e.g. a grazing hit on a plane) is where the tracer's next ray or shadow ray starts.
///
/// The queries run in a child process (this test binary re-run on this one test), since the
/// Embree build in use aborts the whole process on such a ray (`Assertion 'ray.valid()' failed`
/// in `bvh_intersector1.cpp`), which would take every other test of this binary down with it.
#[test]
fn queries_from_beyond_embree_range_get_the_brute_force_answer() {
    const CHILD: &str = "TIMBRE_ARRAYS_TEST_CHILD";
    if std::env::var_os(CHILD).is_some() {
        queries_from_beyond_embree_range();
        return;
    }
    let out = std::process::Command::new(std::env::current_exe().unwrap())
        .args([
            "--exact",
            "queries_from_beyond_embree_range_get_the_brute_force_answer",
            "--nocapture",
            "--test-threads=1",
        ])
        .env(CHILD, "1")
        .output()
        .expect("the test binary runs");
    assert!(
        out.status.success(),
        "queries from beyond ±1.844e18 failed ({}):\n{}\n{}",
        out.status,
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
}

fn queries_from_beyond_embree_range() {
    // A unit sphere at the origin (in the BVH), the floor z = −10 (tested directly) and an
    // array of small spheres whose second element is 4e18 away (tested directly).
    let floor = Shape::Plane(Plane::new(DVec3::new(0.0, 0.0, -10.0), DVec3::Z, DVec3::X).unwrap());
    let objects = vec![
        (sphere(DVec3::ZERO, 1.0), true),
        (floor, true),
        (sphere(DVec3::new(0.0, 5.0, 0.0), 0.5), true),
    ];
    let far = DVec3::new(4e18, 0.0, 0.0);
    let arrays = vec![ObjectArray {
        objects: 2..3,
        offsets: vec![DVec3::ZERO, far],
    }];
    let scene = SceneGeometry::build(device(), objects, arrays).unwrap();
    // Each query from `origin` along `d` beyond `t_min`, against brute force.
    let check = |origin: DVec3, d: DVec3, t_min: f64, expected: Option<(usize, u32)>| {
        let brute = scene.nearest_brute_force(origin, d, t_min, f64::INFINITY);
        assert_eq!(
            brute.map(|h| (h.object, h.element)),
            expected,
            "brute force {origin}"
        );
        let same = |h: Option<Hit>| same_hit(h, brute, ANALYTIC_T);
        println!("nearest from {origin} along {d}");
        let got = scene.nearest(origin, d, t_min, f64::INFINITY);
        assert!(same(got), "{got:?} vs brute force {brute:?}");
        let lane = scene.nearest8(origin, &[d], t_min, f64::INFINITY)[0];
        assert!(same(lane), "{lane:?} vs brute force {brute:?}");
        println!("shadowed from {origin} along {d}");
        let shadowed = scene.shadowed(origin, d, t_min, f64::INFINITY);
        assert_eq!(shadowed, brute.is_some(), "{origin}");
    };
    // Back towards the sphere at the origin, from 2e18 away.
    check(DVec3::new(2e18, 0.0, 0.0), DVec3::NEG_X, 0.0, Some((0, 0)));
    // Down onto the far array element, from just above it.
    check(
        far + DVec3::new(0.0, 5.0, 10.0),
        DVec3::NEG_Z,
        0.0,
        Some((2, 1)),
    );
    // The tracer's pattern: a grazing camera ray meets the floor about 1e19 away, and the
    // shadow ray towards a light starts there (with the tracer's self-hit margin, 1e-9 of the
    // coordinates' scale, as t_min).
    let d = DVec3::new(1.0, 0.0, -1e-18).normalize();
    let h = scene
        .nearest(2.0 * DVec3::Z, d, 0.0, f64::INFINITY)
        .unwrap();
    assert_eq!((h.object, h.element), (1, 0), "{h:?}");
    let p = 2.0 * DVec3::Z + h.t * d;
    assert!(p.x > 1e19, "{p}");
    check(p, DVec3::Z, 1e-9 * (1.0 + p.abs().max_element()), None);
    check(p, -d, 1e-9 * (1.0 + p.abs().max_element()), None);
}
