//! General linear maps of analytic shapes (issue 21): a sphere and a capped cylinder under
//! random non-singular affine maps (shears, non-uniform scales, reflections) against the
//! implicit functions of the mapped shapes, written here: the hit solves them, the normal is
//! their gradient (by finite differences), and the frame stays orthonormal and right-handed.

mod common;

use glam::{DAffine3, DMat3, DVec3};
use proptest::prelude::*;
use timbre::geometry::{Cylinder, Shape, Sphere, Transform, Transformed};

use common::point_in;

/// A random affine map whose linear part has singular values well away from zero.
fn affine() -> impl Strategy<Value = DAffine3> {
    (
        prop::array::uniform9(-1.0..1.0f64),
        point_in(2.0),
        prop::bool::ANY,
    )
        .prop_map(|(m, b, mirror)| {
            let m = DMat3::from_cols_array(&m) * 0.5 + DMat3::IDENTITY;
            let m = if mirror {
                m * DMat3::from_diagonal(DVec3::new(1.0, 1.0, -1.0))
            } else {
                m
            };
            DAffine3 {
                matrix3: m,
                translation: b,
            }
        })
        .prop_filter("well conditioned", |a| {
            let m = a.matrix3;
            let s = (m.transpose() * m).determinant().abs().sqrt();
            s > 0.2
        })
}

/// F(p) < 0 inside the mapped unit sphere: |A⁻¹(p − b)|² − 1.
fn sphere_f(a: &DAffine3, p: DVec3) -> f64 {
    let q = a.matrix3.inverse() * (p - a.translation);
    q.length_squared() - 1.0
}

fn gradient(f: impl Fn(DVec3) -> f64, p: DVec3) -> DVec3 {
    let h = 1e-6;
    DVec3::new(
        f(p + DVec3::X * h) - f(p - DVec3::X * h),
        f(p + DVec3::Y * h) - f(p - DVec3::Y * h),
        f(p + DVec3::Z * h) - f(p - DVec3::Z * h),
    ) / (2.0 * h)
}

proptest! {
    #![proptest_config(common::config(512))]

    #[test]
    fn a_mapped_sphere_is_the_ellipsoid_its_implicit_function_says(
        a in affine(),
        o in point_in(6.0),
        target in point_in(0.57),
    ) {
        let shape = Shape::Transformed(
            Transformed::new(Shape::Sphere(Sphere::new(DVec3::ZERO, 1.0).unwrap()), a).unwrap(),
        );
        let target = a.transform_point3(target);
        let Some(d) = (target - o).try_normalize() else { return Ok(()) };
        // The line through a point inside meets the ellipsoid; from outside the origin it
        // enters first.
        prop_assume!(sphere_f(&a, o) > 1e-3);
        let (t, part) = shape.intersect(o, d, 0.0, f64::INFINITY).expect("aimed inside");
        let p = o + t * d;
        prop_assert!(sphere_f(&a, p).abs() < 1e-9, "F = {} at t {}", sphere_f(&a, p), t);
        // Entering: just before, outside; just after, inside.
        prop_assert!(sphere_f(&a, o + (t - 1e-6) * d) > 0.0 && sphere_f(&a, o + (t + 1e-6) * d) < 0.0);
        let f = shape.frame(p, part);
        let g = gradient(|q| sphere_f(&a, q), p).normalize();
        prop_assert!((f.w - g).length() < 1e-6, "w {} gradient {}", f.w, g);
        prop_assert!((f.u.cross(f.v) - f.w).length() < 1e-12 && f.u.dot(f.w).abs() < 1e-12);
        // The surface coordinates are the sphere's own at the point mapped back.
        let local = a.inverse().transform_point3(p);
        let own = Shape::Sphere(Sphere::new(DVec3::ZERO, 1.0).unwrap()).coordinates(local, 0);
        prop_assert!((shape.coordinates(p, part) - own).length() < 1e-12);
    }

    #[test]
    fn a_sheared_cylinder_keeps_its_caps_flat_and_its_mantle_quadric(
        a in affine(),
        o in point_in(6.0),
        target in point_in(0.5),
    ) {
        // The unit cylinder from z = −1 to 1: inside where x² + y² < 1 and |z| < 1.
        let cylinder = Shape::Cylinder(Cylinder::new(DVec3::NEG_Z, DVec3::Z, 1.0).unwrap());
        let shape = Transform::from_matrix(a.matrix3)
            .unwrap()
            .then(&Transform::translation(a.translation))
            .shape(&cylinder)
            .unwrap();
        let local = |p: DVec3| a.inverse().transform_point3(p);
        let inside = |p: DVec3| {
            let q = local(p);
            q.x * q.x + q.y * q.y < 1.0 && q.z.abs() < 1.0
        };
        let target = a.transform_point3(target);
        let Some(d) = (target - o).try_normalize() else { return Ok(()) };
        prop_assume!(!inside(o));
        let (t, part) = shape.intersect(o, d, 0.0, f64::INFINITY).expect("aimed inside");
        let p = o + t * d;
        prop_assert!(!inside(p - 1e-7 * d) && inside(p + 1e-7 * d), "t {}", t);
        // The normal points out of the mapped solid, along the gradient of the implicit
        // function of the piece hit: the mantle x² + y² − 1 or a cap ±z − 1 (local).
        let w = shape.frame(p, part).w;
        prop_assert!(!inside(p + 1e-6 * w) && inside(p - 1e-6 * w), "w {}", w);
        let q = local(p);
        let g = if (q.z.abs() - 1.0).abs() < 1e-9 {
            gradient(|x| q.z.signum() * local(x).z - 1.0, p)
        } else {
            gradient(|x| local(x).truncate().length_squared() - 1.0, p)
        };
        prop_assert!((w - g.normalize()).length() < 1e-6, "w {} gradient {}", w, g);
    }
}

#[test]
fn singular_maps_are_refused() {
    let sphere = Shape::Sphere(Sphere::new(DVec3::ZERO, 1.0).unwrap());
    let flat = DAffine3::from_mat3(DMat3::from_diagonal(DVec3::new(1.0, 1.0, 0.0)));
    let e = Transformed::new(sphere, flat).unwrap_err();
    assert!(e.to_string().contains("singular"), "{e}");
    let e = Transform::from_matrix(DMat3::from_cols(DVec3::X, DVec3::X, DVec3::Z)).unwrap_err();
    assert!(e.to_string().contains("singular"), "{e}");
}

#[test]
fn a_non_uniformly_scaled_sphere_renders_like_the_ellipsoid() {
    // The same matt body in the empty studio: an ellipsoid with semi-axes (0.9, 0.5, 0.7),
    // turned about (1, 1, 0), and the unit sphere scaled by (0.9, 0.5, 0.7) and turned alike.
    let scene = |shape: &str, scale: &str| {
        format!(
            "studio = \"empty\"\n[render]\nwidth = 160\nheight = 120\nspp = 1\n[[object]]\nshape = {shape}\nsurface = {{ type = \"shiny\", colour = [0.8, 0.3, 0.2] }}\ntransform = {{ {scale}rotate = {{ axis = [1, 1, 0], angle_deg = 35 }}, translate = [0.3, -0.2, 8] }}\n"
        )
    };
    let ellipsoid = common::images::render_text(&scene(
        r#"{ type = "ellipsoid", centre = [0, 0, 0], semi_axes = [0.9, 0.5, 0.7] }"#,
        "",
    ));
    let sphere = common::images::render_text(&scene(
        r#"{ type = "sphere", centre = [0, 0, 0], radius = 1 }"#,
        "scale = [0.9, 0.5, 0.7], ",
    ));
    // The body covers thousands of pixels; at most a few on its outline may round the other
    // way.
    assert!(common::images::differing(&ellipsoid, &sphere) <= 5);
    let without = common::images::render_text(&scene(
        r#"{ type = "sphere", centre = [0, 0, 0], radius = 0.7 }"#,
        "",
    ));
    assert!(common::images::differing(&ellipsoid, &without) > 500);
}
