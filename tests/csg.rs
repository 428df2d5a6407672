//! Constructive solid geometry (issue 21) against point-membership classification written
//! here: random trees of spheres, cylinders and half-spaces under union, intersection,
//! difference and inverse, nested; every crossing timbre reports along a random ray must be
//! where the independent membership test changes along it (found by marching and bisection),
//! with the normal pointing out of the solid; and thick lenses built by CSG image as the
//! lensmaker's equation says, and refract exactly as Snell's law traced here says.

mod common;

use glam::DVec3;
use proptest::prelude::*;
use timbre::geometry::{Csg, CsgOperation, Cylinder, Masked, Plane, Shape, Sphere};
use timbre::trajectories::{self, Trajectory};

use common::{point_in, unit_vector};

/// A solid as this test sees it, with its own membership formulas.
#[derive(Debug, Clone)]
enum Solid {
    Ball(DVec3, f64),
    Rod(DVec3, DVec3, f64),
    /// The half-space behind the plane through the point with the (unit) normal.
    HalfSpace(DVec3, DVec3),
    Union(Vec<Solid>),
    Intersection(Vec<Solid>),
    Difference(Vec<Solid>),
    Inverse(Box<Solid>),
}

impl Solid {
    fn inside(&self, p: DVec3) -> bool {
        match self {
            Solid::Ball(c, r) => (p - *c).length() < *r,
            Solid::Rod(a, b, r) => {
                let axis = *b - *a;
                let s = (p - *a).dot(axis) / axis.length_squared();
                let radial = (p - *a) - s * axis;
                (0.0..1.0).contains(&s) && radial.length() < *r
            }
            Solid::HalfSpace(q, n) => (p - *q).dot(*n) < 0.0,
            Solid::Union(m) => m.iter().any(|s| s.inside(p)),
            Solid::Intersection(m) => m.iter().all(|s| s.inside(p)),
            Solid::Difference(m) => m[0].inside(p) && !m[1..].iter().any(|s| s.inside(p)),
            Solid::Inverse(s) => !s.inside(p),
        }
    }

    /// Whether `p` is within `eps` of a leaf's surface (where membership is ambiguous).
    fn near_surface(&self, p: DVec3, eps: f64) -> bool {
        match self {
            Solid::Ball(c, r) => ((p - *c).length() - r).abs() < eps,
            Solid::Rod(a, b, r) => {
                let axis = (*b - *a).normalize();
                let s = (p - *a).dot(axis);
                let radial = ((p - *a) - s * axis).length();
                let len = (*b - *a).length();
                ((radial - r).abs() < eps && s > -eps && s < len + eps)
                    || ((s.abs() < eps || (s - len).abs() < eps) && radial < r + eps)
            }
            Solid::HalfSpace(q, n) => (p - *q).dot(*n).abs() < eps,
            Solid::Union(m) | Solid::Intersection(m) | Solid::Difference(m) => {
                m.iter().any(|s| s.near_surface(p, eps))
            }
            Solid::Inverse(s) => s.near_surface(p, eps),
        }
    }

    /// timbre's shape, or `None` where timbre refuses it (an empty intersection).
    fn shape(&self) -> Option<Shape> {
        let csg = |op, m: &[Solid]| {
            let members = m.iter().map(Solid::shape).collect::<Option<Vec<_>>>()?;
            match Csg::new(op, members) {
                Ok(c) => Some(Shape::Csg(c)),
                Err(e) => {
                    assert!(e.to_string().contains("is empty"), "{e}");
                    None
                }
            }
        };
        match self {
            Solid::Ball(c, r) => Some(Shape::Sphere(Sphere::new(*c, *r).unwrap())),
            Solid::Rod(a, b, r) => Some(Shape::Cylinder(Cylinder::new(*a, *b, *r).unwrap())),
            Solid::HalfSpace(q, n) => Some(Shape::Plane(
                Plane::new(*q, *n, n.any_orthogonal_vector()).unwrap(),
            )),
            Solid::Union(m) => csg(CsgOperation::Union, m),
            Solid::Intersection(m) => csg(CsgOperation::Intersection, m),
            Solid::Difference(m) => csg(CsgOperation::Difference, m),
            Solid::Inverse(s) => csg(CsgOperation::Inverse, std::slice::from_ref(s)),
        }
    }
}

fn leaf() -> impl Strategy<Value = Solid> {
    prop_oneof![
        (point_in(1.5), 0.3..1.5f64).prop_map(|(c, r)| Solid::Ball(c, r)),
        (point_in(1.5), point_in(1.5), 0.2..0.8f64)
            .prop_filter("a long enough axis", |(a, b, _)| a.distance(*b) > 0.3)
            .prop_map(|(a, b, r)| Solid::Rod(a, b, r)),
        (point_in(1.0), unit_vector()).prop_map(|(q, n)| Solid::HalfSpace(q, n)),
    ]
}

fn solid() -> impl Strategy<Value = Solid> {
    leaf().prop_recursive(3, 16, 3, |inner| {
        prop_oneof![
            prop::collection::vec(inner.clone(), 2..4).prop_map(Solid::Union),
            prop::collection::vec(inner.clone(), 2..4).prop_map(Solid::Intersection),
            prop::collection::vec(inner.clone(), 2..4).prop_map(Solid::Difference),
            inner.prop_map(|s| Solid::Inverse(Box::new(s))),
        ]
    })
}

/// Where membership changes along o + t d for 0 < t < `far`: marched in steps of `step`, each
/// change refined by bisection.
fn reference_crossings(s: &Solid, o: DVec3, d: DVec3, far: f64, step: f64) -> Vec<f64> {
    let at = |t: f64| s.inside(o + t * d);
    let mut out = Vec::new();
    let (mut t0, mut in0) = (0.0, at(0.0));
    while t0 < far {
        let t1 = t0 + step;
        let in1 = at(t1);
        if in1 != in0 {
            let (mut a, mut b) = (t0, t1);
            for _ in 0..60 {
                let m = 0.5 * (a + b);
                if at(m) == in0 { a = m } else { b = m }
            }
            // The last step may end past `far`, where timbre's crossings are not asked for.
            if 0.5 * (a + b) < far {
                out.push(0.5 * (a + b));
            }
        }
        (t0, in0) = (t1, in1);
    }
    out
}

/// Every crossing timbre reports along o + t d for 0 < t < `far`, with its outward normal.
fn timbre_crossings(shape: &Shape, o: DVec3, d: DVec3, far: f64) -> Vec<(f64, DVec3)> {
    let mut out = Vec::new();
    let mut from = 0.0;
    while let Some((t, part)) = shape.intersect(o, d, from, far) {
        out.push((t, shape.frame(o + t * d, part).w));
        from = t;
        assert!(out.len() < 1000, "no progress");
    }
    out
}

proptest! {
    #![proptest_config(common::config(1024))]

    #[test]
    fn crossings_are_where_membership_changes_and_normals_point_out(
        s in solid(),
        o in point_in(4.0),
        target in point_in(1.5),
    ) {
        let Some(shape) = s.shape() else { return Ok(()) };
        let Some(d) = (target - o).try_normalize() else { return Ok(()) };
        let far = 12.0;
        let got = timbre_crossings(&shape, o, d, far);
        let reference = reference_crossings(&s, o, d, far, 1e-3);
        // Every crossing timbre reports is a change of membership, and its normal points
        // from inside to outside.
        for &(t, w) in &got {
            let p = o + t * d;
            let (before, after) = (s.inside(p - 1e-7 * d), s.inside(p + 1e-7 * d));
            let grazing = w.dot(d).abs() < 1e-3;
            if grazing || s.near_surface(p - 1e-7 * d, 1e-9) || s.near_surface(p + 1e-7 * d, 1e-9) {
                continue;
            }
            prop_assert!(before != after, "t {} is no crossing ({:?})", t, got);
            prop_assert_eq!(w.dot(d) < 0.0, after, "normal {} at t {} of {:?}", w, t, got);
            prop_assert!(s.inside(p - 1e-6 * w) && !s.inside(p + 1e-6 * w), "w {} at {}", w, p);
        }
        // Every change of membership the marching finds is a crossing timbre reports.
        for &r in &reference {
            let p = o + r * d;
            let robust = s.inside(p - 1e-6 * d) != s.inside(p + 1e-6 * d);
            let nearest = got.iter().map(|c| (c.0 - r).abs()).fold(f64::INFINITY, f64::min);
            prop_assert!(!robust || nearest < 1e-9, "missed {} (got {:?})", r, got);
        }
    }

    #[test]
    fn contains_is_point_membership(s in solid(), points in prop::collection::vec(point_in(3.0), 64)) {
        let Some(Shape::Csg(csg)) = s.shape() else { return Ok(()) };
        for p in points {
            if !s.near_surface(p, 1e-12) {
                prop_assert_eq!(csg.contains(p), s.inside(p), "{}", p);
            }
        }
    }
}

#[test]
fn solids_glued_face_to_face_have_no_surface_between_them() {
    let rod = |z0: f64, z1: f64, r: f64| {
        Shape::Cylinder(
            Cylinder::new(DVec3::new(0.0, 0.0, z0), DVec3::new(0.0, 0.0, z1), r).unwrap(),
        )
    };
    let glued = Shape::Csg(
        Csg::new(
            CsgOperation::Union,
            vec![rod(0.0, 1.0, 0.5), rod(1.0, 2.0, 0.3)],
        )
        .unwrap(),
    );
    let o = DVec3::new(0.1, 0.1, -5.0);
    let ts: Vec<f64> = timbre_crossings(&glued, o, DVec3::Z, 20.0)
        .iter()
        .map(|c| c.0)
        .collect();
    assert_eq!(ts, [5.0, 7.0]);
    // Beside the thinner rod the step between the two is a surface, facing +z.
    let o = DVec3::new(0.4, 0.0, 5.0);
    let c = timbre_crossings(&glued, o, DVec3::NEG_Z, 20.0);
    assert_eq!(c.iter().map(|c| c.0).collect::<Vec<_>>(), [4.0, 5.0]);
    assert_eq!(c[0].1, DVec3::Z);
    // A tube: coincident end caps of the outer and inner cylinders leave only the ring.
    let tube = Shape::Csg(
        Csg::new(
            CsgOperation::Difference,
            vec![rod(0.0, 1.0, 0.5), rod(0.0, 1.0, 0.3)],
        )
        .unwrap(),
    );
    assert!(timbre_crossings(&tube, DVec3::new(0.1, 0.0, -5.0), DVec3::Z, 20.0).is_empty());
    let ring: Vec<f64> = timbre_crossings(&tube, DVec3::new(0.4, 0.0, -5.0), DVec3::Z, 20.0)
        .iter()
        .map(|c| c.0)
        .collect();
    assert_eq!(ring, [5.0, 6.0]);
}

#[test]
fn bad_members_and_counts_are_refused_clearly() {
    let ball = || Shape::Sphere(Sphere::new(DVec3::ZERO, 1.0).unwrap());
    let disc = Shape::Disc(timbre::geometry::Disc::new(DVec3::ZERO, DVec3::Z, 1.0).unwrap());
    let e = Csg::new(CsgOperation::Union, vec![ball(), disc]).unwrap_err();
    assert!(
        e.to_string()
            .contains("member 2 of the union (disc) does not enclose a solid"),
        "{e}"
    );
    let e = Csg::new(CsgOperation::Difference, vec![ball()]).unwrap_err();
    assert!(e.to_string().contains("at least two members"), "{e}");
    let e = Csg::new(CsgOperation::Inverse, vec![ball(), ball()]).unwrap_err();
    assert!(e.to_string().contains("exactly one member"), "{e}");
    let far = Shape::Sphere(Sphere::new(DVec3::new(5.0, 0.0, 0.0), 1.0).unwrap());
    let e = Csg::new(CsgOperation::Intersection, vec![ball(), far]).unwrap_err();
    assert!(e.to_string().contains("empty"), "{e}");
}

/// The scene of a thick lens from `shape` (glass of index `n`) and rays parallel to the axis
/// z at the heights `heights` (along x).
fn lens_trajectories(shape: &str, n: f64, heights: &[f64]) -> Vec<Trajectory> {
    let mut text = format!(
        "studio = \"none\"\n[[object]]\nname = \"lens\"\nshape = {shape}\nsurface = {{ type = \"refractive\", index_ratio = {n:?} }}\n"
    );
    for h in heights {
        text.push_str(&format!(
            "[[ray_trajectory]]\nstart = [{h:?}, 0, 0]\ndirection = [0, 0, 1]\n"
        ));
    }
    let description = common::images::parse(&text);
    trajectories::trace(common::rays::device(), &description).expect("trace")
}

/// Where a ray leaving `p` along `d` crosses the axis (its z there; the ray is in the xz plane).
fn axis_crossing(p: DVec3, d: DVec3) -> f64 {
    p.z - p.x * d.z / d.x
}

#[test]
fn a_thick_lens_built_by_csg_focuses_where_the_lensmakers_equation_says() {
    // Biconvex, plano-convex and meniscus lenses, both as timbre's spherical lens and as the
    // intersection of spheres (and a half-space) written out by hand.
    let n = 1.5;
    let cases = [
        // (R1, R2, thickness, the same lens as explicit CSG)
        (
            3.0,
            Some(-4.0),
            0.6,
            r#"{ type = "intersection", of = [{ type = "sphere", centre = [0, 0, 12.7], radius = 3 }, { type = "sphere", centre = [0, 0, 6.3], radius = 4 }, { type = "cylinder", start = [0, 0, 5], end = [0, 0, 15], radius = 1 }] }"#,
        ),
        (
            2.5,
            None,
            0.5,
            r#"{ type = "intersection", of = [{ type = "sphere", centre = [0, 0, 12.25], radius = 2.5 }, { type = "plane", point = [0, 0, 10.25], normal = [0, 0, 1] }, { type = "cylinder", start = [0, 0, 5], end = [0, 0, 15], radius = 1 }] }"#,
        ),
        (
            2.0,
            Some(4.0),
            0.5,
            r#"{ type = "difference", of = [{ type = "intersection", of = [{ type = "sphere", centre = [0, 0, 11.75], radius = 2 }, { type = "cylinder", start = [0, 0, 5], end = [0, 0, 15], radius = 1 }] }, { type = "sphere", centre = [0, 0, 14.25], radius = 4 }] }"#,
        ),
    ];
    for (r1, r2, d, explicit) in cases.into_iter().chain(concave_cases()) {
        let inverse_r2 = r2.map_or(0.0, |r: f64| 1.0 / r);
        // Lensmaker's equation for a thick lens, and the back focal distance from the back
        // vertex (Hecht, Optics, §6.2).
        let power = (n - 1.0) * (1.0 / r1 - inverse_r2 + (n - 1.0) * d * inverse_r2 / (n * r1));
        let f = 1.0 / power;
        let back_vertex = 10.0 + 0.5 * d;
        let expected = back_vertex + f * (1.0 - (n - 1.0) * d / (n * r1));
        let back = r2.map_or(String::new(), |r| format!(", back_radius = {r:?}"));
        let spherical = format!(
            "{{ type = \"spherical-lens\", centre = [0, 0, 10], axis = [0, 0, 1], front_radius = {r1:?}{back}, thickness = {d:?}, aperture_radius = 1 }}"
        );
        // Along the axis from far in front, the lens begins at its front vertex (no material
        // in front of a concave surface's sphere).
        let s = common::images::parse(&format!(
            "studio = \"none\"\n[[object]]\nshape = {spherical}\nsurface = {{ type = \"matt\", colour = [1, 1, 1] }}\n"
        ));
        let first = s.objects[0]
            .shape
            .intersect(DVec3::new(0.0, 0.0, -20.0), DVec3::Z, 0.0, 100.0);
        assert!(
            (first.unwrap().0 - (30.0 - 0.5 * d)).abs() < 1e-12,
            "{spherical}: {first:?}"
        );
        for shape in [spherical.as_str(), explicit] {
            // Paraxial rays: spherical aberration is of order (h/R)², below 1e-6 here.
            for t in lens_trajectories(shape, n, &[1e-3, -2e-3]) {
                // Start, entry, exit, and the end of the escaping ray.
                assert_eq!(t.points.len(), 4, "{shape}: {:?}", t.points);
                let z = axis_crossing(t.points[2].position, t.direction);
                assert!(
                    (z - expected).abs() < 1e-5 * f.abs(),
                    "{shape}: focus at z = {z}, expected {expected}"
                );
            }
        }
    }
}

/// Diverging lenses, with concave surfaces as steep as the aperture allows (|R| close to it),
/// where the rim must end at the lens: plano-concave and biconcave, and the same by hand.
fn concave_cases() -> [(f64, Option<f64>, f64, &'static str); 2] {
    [
        (
            -1.05,
            None,
            0.4,
            r#"{ type = "intersection", of = [{ type = "inverse", of = { type = "sphere", centre = [0, 0, 8.75], radius = 1.05 } }, { type = "plane", point = [0, 0, 10.2], normal = [0, 0, 1] }, { type = "cylinder", start = [0, 0, 8.9], end = [0, 0, 10.3], radius = 1 }] }"#,
        ),
        (
            -1.2,
            Some(1.2),
            0.1,
            r#"{ type = "difference", of = [{ type = "cylinder", start = [0, 0, 9], end = [0, 0, 11], radius = 1 }, { type = "sphere", centre = [0, 0, 8.75], radius = 1.2 }, { type = "sphere", centre = [0, 0, 11.25], radius = 1.2 }] }"#,
        ),
    ]
}

/// The refracted unit direction of unit `d` at a surface with unit normal `n` (either side),
/// going from index `n1` to `n2` (vector form of Snell's law).
fn snell(d: DVec3, normal: DVec3, n1: f64, n2: f64) -> DVec3 {
    let n = if d.dot(normal) < 0.0 { normal } else { -normal };
    let mu = n1 / n2;
    let cos_i = -d.dot(n);
    let cos_t = (1.0 - mu * mu * (1.0 - cos_i * cos_i)).sqrt();
    mu * d + (mu * cos_i - cos_t) * n
}

/// The nearest point where o + t d (t > 0) meets the sphere (c, r), on the side `sign` says
/// (−1 the nearer root, +1 the farther).
fn sphere_hit(o: DVec3, d: DVec3, c: DVec3, r: f64, sign: f64) -> DVec3 {
    let b = (o - c).dot(d);
    let q = (o - c).length_squared() - r * r;
    o + (-b + sign * (b * b - q).sqrt()) * d
}

#[test]
fn rays_far_from_the_axis_refract_exactly_as_snells_law_says() {
    // A biconvex lens (R1 = 3 centred at z = 12.7, R2 = −4 centred at z = 6.3); a ray at
    // height 0.7 traced here by Snell's law at both spheres.
    let (n, h) = (1.5, 0.7);
    let (c1, c2) = (DVec3::new(0.0, 0.0, 12.7), DVec3::new(0.0, 0.0, 6.3));
    let o = DVec3::new(h, 0.0, 0.0);
    let p1 = sphere_hit(o, DVec3::Z, c1, 3.0, -1.0);
    let d1 = snell(DVec3::Z, (p1 - c1).normalize(), 1.0, n);
    let p2 = sphere_hit(p1, d1, c2, 4.0, 1.0);
    let d2 = snell(d1, (p2 - c2).normalize(), n, 1.0);
    let shape = r#"{ type = "spherical-lens", centre = [0, 0, 10], axis = [0, 0, 1], front_radius = 3, back_radius = -4, thickness = 0.6, aperture_radius = 1 }"#;
    let t = &lens_trajectories(shape, n, &[h])[0];
    assert!(
        (t.points[1].position - p1).length() < 1e-12,
        "{:?}",
        t.points
    );
    assert!(
        (t.points[2].position - p2).length() < 1e-12,
        "{:?}",
        t.points
    );
    assert!(
        (t.direction - d2).length() < 1e-12,
        "{} vs {d2}",
        t.direction
    );
}

#[test]
fn a_hollow_glass_shell_refracts_at_its_inner_surface_out_of_the_glass() {
    // The difference of concentric spheres (radii 2 and 1.2 about z = 10): where the ray
    // meets the inner sphere it leaves the glass (into the cavity) and re-enters it; with
    // the inner surface's normal on the wrong side the index ratios would be swapped there.
    let n = 1.5;
    let c = DVec3::new(0.0, 0.0, 10.0);
    let o = DVec3::new(0.6, 0.0, 0.0);
    let p1 = sphere_hit(o, DVec3::Z, c, 2.0, -1.0);
    let d1 = snell(DVec3::Z, (p1 - c).normalize(), 1.0, n);
    let p2 = sphere_hit(p1, d1, c, 1.2, -1.0);
    let d2 = snell(d1, (p2 - c).normalize(), n, 1.0);
    let p3 = sphere_hit(p2, d2, c, 1.2, 1.0);
    let d3 = snell(d2, (p3 - c).normalize(), 1.0, n);
    let p4 = sphere_hit(p3, d3, c, 2.0, 1.0);
    let d4 = snell(d3, (p4 - c).normalize(), n, 1.0);
    let shell = r#"{ type = "difference", of = [{ type = "sphere", centre = [0, 0, 10], radius = 2 }, { type = "sphere", centre = [0, 0, 10], radius = 1.2 }] }"#;
    let t = &lens_trajectories(shell, n, &[0.6])[0];
    for (got, expected) in t.points[1..5].iter().zip([p1, p2, p3, p4]) {
        assert!((got.position - expected).length() < 1e-12, "{:?}", t.points);
    }
    assert!(
        (t.direction - d4).length() < 1e-12,
        "{} vs {d4}",
        t.direction
    );
}

#[test]
fn check_reports_each_kind_of_shape() {
    let dir = tempfile::TempDir::new().unwrap();
    let scene = common::cli::write(
        dir.path(),
        "s.toml",
        r#"studio = "none"
[[object]]
shape = { type = "spherical-lens", centre = [0, 0, 10], axis = [0, 0, 1], front_radius = 3, thickness = 0.5, aperture_radius = 1 }
surface = { type = "refractive", index_ratio = 1.5 }
[[object]]
shape = { type = "difference", of = [{ type = "sphere", centre = [3, 0, 10], radius = 1 }, { type = "plane", point = [3, 0, 10], normal = [0, 1, 0] }] }
surface = { type = "matt", colour = [1, 1, 1] }
[[object]]
shape = { type = "sphere", centre = [0, 0, 0], radius = 1 }
surface = { type = "matt", colour = [1, 1, 1] }
transform = { scale = [1, 2, 3], translate = [-3, 0, 10] }
[[object]]
shape = { type = "tube", start = [0, 5, 10], end = [0, 6, 10], outer_radius = 1, inner_radius = 0.5 }
surface = { type = "matt", colour = [1, 1, 1] }
"#,
    );
    let run = common::cli::timbre(dir.path(), &["check", common::cli::path_str(&scene)]);
    run.assert_success();
    assert_eq!(
        run.field("shapes"),
        "1 spherical-lens, 1 difference, 1 transformed sphere, 1 tube"
    );
}

proptest! {
    #![proptest_config(common::config(256))]

    #[test]
    fn a_plane_masked_by_a_cylinder_is_a_disc_and_by_its_inverse_a_plane_with_a_hole(
        o in point_in(4.0),
        target in point_in(1.5),
    ) {
        let Some(d) = (target - o).try_normalize() else { return Ok(()) };
        let (c, n) = (DVec3::new(0.2, -0.1, 0.3), DVec3::new(1.0, 2.0, 2.0) / 3.0);
        let plane = Shape::Plane(Plane::new(c, n, DVec3::X).unwrap());
        let rod = Shape::Cylinder(Cylinder::new(c - 2.0 * n, c + 2.0 * n, 1.1).unwrap());
        let hole = Shape::Csg(Csg::new(CsgOperation::Inverse, vec![rod.clone()]).unwrap());
        let disc = Shape::Disc(timbre::geometry::Disc::new(c, n, 1.1).unwrap());
        let window = Shape::Masked(Masked::new(plane.clone(), rod).unwrap());
        let holed = Shape::Masked(Masked::new(plane.clone(), hole).unwrap());
        let hit = |s: &Shape| s.intersect(o, d, 0.0, f64::INFINITY).map(|h| h.0);
        let on_plane = hit(&plane);
        // Away from the rim, where membership is ambiguous.
        let rim = on_plane.is_some_and(|t| ((o + t * d - c).reject_from(n).length() - 1.1).abs() < 1e-9);
        if !rim {
            prop_assert_eq!(hit(&window), hit(&disc));
            prop_assert_eq!(hit(&holed), on_plane.filter(|_| hit(&disc).is_none()));
        }
        if let Some((t, part)) = window.intersect(o, d, 0.0, f64::INFINITY) {
            prop_assert_eq!(window.frame(o + t * d, part).w, n.normalize());
        }
    }
}

#[test]
fn masks_that_are_not_solids_or_leave_nothing_are_refused() {
    let plane = || Shape::Plane(Plane::new(DVec3::ZERO, DVec3::Z, DVec3::X).unwrap());
    let disc = Shape::Disc(timbre::geometry::Disc::new(DVec3::ZERO, DVec3::Z, 1.0).unwrap());
    let e = Masked::new(plane(), disc).unwrap_err();
    assert!(
        e.to_string()
            .contains("mask (disc) does not enclose a solid"),
        "{e}"
    );
    let ball = Shape::Sphere(Sphere::new(DVec3::new(0.0, 0.0, 5.0), 1.0).unwrap());
    let small = Shape::Sphere(Sphere::new(DVec3::ZERO, 1.0).unwrap());
    let e = Masked::new(small, ball).unwrap_err();
    assert!(e.to_string().contains("does not overlap"), "{e}");
}
