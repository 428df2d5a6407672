//! Independent checks of the ideal thin lenses, mirrors and glenses (issue 20): rays from a
//! point are followed through a scene file's lens (`timbre::trajectories::trace`) and must pass
//! through the image point that the textbook imaging equations give, worked out here from the
//! lens's position in the scene (the object's transform applied by the test itself, with
//! Rodrigues' formula), not from the implementation.

mod common;

use glam::DVec3;
use timbre::trajectories::{self, Trajectory};

/// The trajectories of the scene `text`.
fn trace(text: &str) -> Vec<Trajectory> {
    let description = common::images::parse(text);
    trajectories::trace(common::rays::device(), &description).expect("trace")
}

/// A TOML vector with every digit of the f64s.
fn v(p: DVec3) -> String {
    format!("[{:?}, {:?}, {:?}]", p.x, p.y, p.z)
}

/// `d` rotated by `angle` (radians) about the unit `axis`, right-handed (Rodrigues).
fn rotate(d: DVec3, axis: DVec3, angle: f64) -> DVec3 {
    d * angle.cos() + axis.cross(d) * angle.sin() + axis * axis.dot(d) * (1.0 - angle.cos())
}

/// Distance from `q` to the line through `p` along `d`.
fn distance_to_line(q: DVec3, p: DVec3, d: DVec3) -> f64 {
    (q - p).cross(d.normalize()).length()
}

/// The direction each ray leaves its first surface in (from the point where it met it).
fn after_first_surface(t: &Trajectory) -> (DVec3, DVec3) {
    let s = t.points[1].position;
    let next = t.points.get(2).map_or(t.direction, |p| p.position - s);
    (s, next.normalize())
}

/// A scene of one surface on the plane z = 5, and the trajectory table `rays` (its keys).
fn on_plane_z5(name: &str, surface: &str, rays: &str) -> String {
    format!(
        "studio = \"none\"\n[[object]]\nname = \"{name}\"\nshadow_throwing = false\nshape = {{ type = \"plane\", point = [0, 0, 5], normal = [0, 0, 1] }}\nsurface = {surface}\n[[ray_trajectory]]\n{rays}\n"
    )
}

/// The object transform used below: rotated 35° about (1, 1, 0.3), then translated.
const AXIS: [f64; 3] = [1.0, 1.0, 0.3];
const ANGLE_DEG: f64 = 35.0;
const SHIFT: [f64; 3] = [0.4, -0.3, 6.0];

fn placed(p: DVec3) -> DVec3 {
    rotate(p, DVec3::from(AXIS).normalize(), ANGLE_DEG.to_radians()) + DVec3::from(SHIFT)
}

fn transform_toml() -> String {
    format!(
        "transform = {{ rotate = {{ axis = {}, angle_deg = {ANGLE_DEG:?} }}, translate = {} }}",
        v(DVec3::from(AXIS)),
        v(DVec3::from(SHIFT))
    )
}

/// Rays from `q` through a tilted square lens (focal length `f`, principal point off the
/// square's centre, optical axis given with either sign) pass through, or come from, the image
/// the thin-lens equation 1/o + 1/i = 1/f gives on the line from `q` through the principal
/// point P, with o and i measured along the axis from the lens plane (o on the side light
/// comes from, i on the side it goes to; i < 0 is a virtual image on the object's side).
fn check_thin_lens_images(f: f64, q_local: DVec3, axis_sign: f64) {
    let p_local = DVec3::new(0.15, -0.1, 0.0);
    let text = format!(
        "studio = \"none\"
[[object]]
name = \"lens\"
shadow_throwing = false
shape = {{ type = \"parallelogram\", corner = [-1, -1, 0], span_u = [2, 0, 0], span_v = [0, 2, 0] }}
surface = {{ type = \"ideal-thin-lens\", focal_length = {f:?}, principal_point = {}, optical_axis = [0, 0, {axis_sign:?}] }}
{}
[[ray_trajectory]]
start = {}
direction = {}
cone_half_angle_deg = 9
rays = 12
",
        v(p_local),
        transform_toml(),
        v(placed(q_local)),
        v(placed(p_local) - placed(q_local)),
    );
    let (p, q) = (placed(p_local), placed(q_local));
    let a = placed(DVec3::Z) - placed(DVec3::ZERO);
    let o = (p - q).dot(a).abs();
    let i = 1.0 / (1.0 / f - 1.0 / o);
    let image = p + (p - q) * (i / o);
    let traced = trace(&text);
    assert_eq!(traced.len(), 12);
    for t in &traced {
        let (s, out) = after_first_surface(t);
        let miss = distance_to_line(image, s, out);
        assert!(
            miss < 1e-9 * (1.0 + image.length()),
            "f = {f}, Q = {q}: the ray from {s} along {out} misses the image {image} by {miss}"
        );
        // Light goes on through the lens, whatever the image.
        assert!(out.dot(a).signum() == (p - q).dot(a).signum());
    }
}

#[test]
fn a_point_is_imaged_where_the_thin_lens_equation_says_for_both_signs_of_f() {
    // Real image (o > f), virtual image (o < f), a diverging lens; off-axis, oblique.
    check_thin_lens_images(1.5, DVec3::new(0.6, 0.3, -4.0), 1.0);
    check_thin_lens_images(2.0, DVec3::new(-0.5, 0.4, -1.2), -1.0);
    check_thin_lens_images(-1.0, DVec3::new(0.2, -0.7, -3.0), 1.0);
    // From the other side.
    check_thin_lens_images(0.8, DVec3::new(0.3, 0.2, 2.5), -1.0);
}

/// A glens with focal lengths f₋ and f₊ images Q to the point Q′ on the line through Q and the
/// nodal point N = P + (f₋ + f₊) â whose axial coordinate a′ (from P, along â) satisfies
/// f₊/a′ + f₋/a = 1 (Chaplain et al. 2016), a being Q's; light from negative space.
#[test]
fn a_glens_images_through_its_nodal_point_by_the_glens_equation() {
    let (f_neg, f_pos) = (-1.2, 2.0);
    let p = DVec3::new(0.2, 0.1, 5.0);
    let q = DVec3::new(-0.4, 0.3, 1.0);
    let text = on_plane_z5(
        "glens",
        &format!(
            "{{ type = \"glens\", principal_point = {}, optical_axis = [0, 0, 1], focal_length_negative = {f_neg:?}, focal_length_positive = {f_pos:?} }}",
            v(p)
        ),
        &format!(
            "start = {}\ndirection = [0.1, -0.05, 1]\ncone_half_angle_deg = 12\nrays = 10",
            v(q)
        ),
    );
    let n = p + (f_neg + f_pos) * DVec3::Z;
    let a = q.z - p.z;
    let a_image = f_pos / (1.0 - f_neg / a);
    let image = q + (n - q) * ((a_image - a) / (n.z - q.z));
    for t in &trace(&text) {
        let (s, out) = after_first_surface(t);
        let miss = distance_to_line(image, s, out);
        assert!(miss < 1e-9, "misses the image {image} by {miss}");
    }
    // A ray aimed at the nodal point goes on undeviated.
    let text = text.replace(
        "direction = [0.1, -0.05, 1]\ncone_half_angle_deg = 12\nrays = 10",
        &format!("direction = {}", v(n - q)),
    );
    let (_, out) = after_first_surface(&trace(&text)[0]);
    assert!((out - (n - q).normalize()).length() < 1e-12, "{out}");
}

/// A homogeneous glens (focal lengths infinite, f₋/f₊ = ρ) is the limit of the glens equation
/// f₊/a′ + f₋/a = 1 with f₊ → ∞: a′ = −a/ρ, and the nodal point at infinity along n̂, so Q
/// is imaged to Q′ = Q + ((a′ − a)/(n̂·â)) n̂, wherever the rays cross the glens.
#[test]
fn a_homogeneous_glens_images_by_the_limit_of_the_glens_equation() {
    let ratio = -0.5;
    let n = DVec3::new(0.2, -0.1, 1.0).normalize();
    let q = DVec3::new(0.3, 0.4, 2.0);
    let text = on_plane_z5(
        "homogeneous glens",
        &format!(
            "{{ type = \"glens\", optical_axis = [0, 0, 1], nodal_direction = {}, focal_length_ratio = {ratio:?} }}",
            v(n)
        ),
        &format!(
            "start = {}\ndirection = [0.1, 0.2, 1]\ncone_half_angle_deg = 20\nrays = 10",
            v(q)
        ),
    );
    let a = q.z - 5.0;
    let a_image = -a / ratio;
    let image = q + n * ((a_image - a) / n.z);
    for t in &trace(&text) {
        let (s, out) = after_first_surface(t);
        let miss = distance_to_line(image, s, out);
        assert!(miss < 1e-9, "misses the image {image} by {miss}");
    }
}

/// A concave ideal mirror (f > 0) sends a parallel bundle through one point of the focal plane
/// a distance f in front of it: where the reflected chief ray (through the principal point)
/// meets that plane.
#[test]
fn an_ideal_mirror_focuses_parallel_light_in_front_of_it() {
    let f = 2.5;
    let d = DVec3::new(0.15, -0.1, 1.0).normalize();
    let text = format!(
        "studio = \"none\"
[[object]]
name = \"mirror\"
shape = {{ type = \"disc\", centre = [0, 0, 4], normal = [0, 0, -1], radius = 1.5 }}
surface = {{ type = \"ideal-thin-mirror\", focal_length = {f:?}, principal_point = [0, 0, 4], optical_axis = [0, 0, 1] }}
[[ray_trajectory]]
start = [0, 0, 0]
direction = {}
bundle_radius = 0.8
rays = 9
",
        v(d)
    );
    let chief_reflected = DVec3::new(d.x, d.y, -d.z);
    let focus = DVec3::new(0.0, 0.0, 4.0) + chief_reflected * (f / d.z);
    for t in &trace(&text) {
        let (s, out) = after_first_surface(t);
        assert!(out.z < 0.0, "reflected back: {out}");
        let miss = distance_to_line(focus, s, out);
        assert!(miss < 1e-9, "misses the focus {focus} by {miss}");
    }
}

/// A cylindrical lens with power along x focuses a point source into a line parallel to y:
/// rays from Q pass through x = x′, z = z′ of the thin-lens image, at any y.
#[test]
fn a_cylindrical_lens_images_a_point_to_a_line() {
    let f = 1.0;
    let q = DVec3::new(0.3, 0.2, 2.0);
    let text = on_plane_z5(
        "cylindrical lens",
        &format!(
            "{{ type = \"ideal-thin-cylindrical-lens\", focal_length = {f:?}, principal_point = [0, 0, 5], optical_axis = [0, 0, 1], gradient_direction = [1, 0, 0.3] }}"
        ),
        &format!(
            "start = {}\ndirection = [0, 0, 1]\ncone_half_angle_deg = 15\nrays = 8",
            v(q)
        ),
    );
    let o = 5.0 - q.z;
    let i = 1.0 / (1.0 / f - 1.0 / o);
    let x_image = -q.x * i / o;
    for t in &trace(&text) {
        let (s, out) = after_first_surface(t);
        let at = s + out * (i / out.z);
        assert!((at.x - x_image).abs() < 1e-12, "{at} {x_image}");
        // No power along y: the y slope is unchanged.
        assert!((out.y / out.z - (s.y - q.y) / (s.z - q.z)).abs() < 1e-12);
    }
}

/// An array of lenses: each copy's principal point moves with the copy, so a ray through the
/// second copy's principal point is undeviated, and a ray elsewhere is bent.
#[test]
fn array_copies_of_a_lens_have_their_own_principal_points() {
    let text = "studio = \"none\"
[[object]]
name = \"lens\"
shadow_throwing = false
shape = { type = \"disc\", centre = [0, 0, 3], normal = [0, 0, 1], radius = 0.9 }
surface = { type = \"ideal-thin-lens\", focal_length = 1, principal_point = [0, 0, 3], optical_axis = [0, 0, 1] }
array = { vectors = [[2, 0, 0]], counts = [2] }
[[ray_trajectory]]
start = [1.0, 0.5, 0]
direction = [1.0, -0.5, 3]
[[ray_trajectory]]
start = [1.0, 0.5, 0]
direction = [1.3, -0.5, 3]
";
    let traced = trace(text);
    let (s, out) = after_first_surface(&traced[0]);
    assert!((s - DVec3::new(2.0, 0.0, 3.0)).length() < 1e-12, "{s}");
    assert!((out - DVec3::new(1.0, -0.5, 3.0).normalize()).length() < 1e-12);
    let (_, out) = after_first_surface(&traced[1]);
    assert!((out - DVec3::new(1.3, -0.5, 3.0).normalize()).length() > 1e-3);
}

/// Where a lenslet array's directions, made perpendicular to the surface normal, are parallel
/// there is no lattice: the ray is lost (the law's direction is not a number), not traced on
/// as a NaN ray.
#[test]
fn a_lenslet_array_without_a_lattice_at_the_hit_loses_the_ray() {
    let text = on_plane_z5(
        "array",
        "{ type = \"ideal-thin-lenslet-array\", focal_length = 1, centre = [0, 0, 5], u_direction = [1, 0, 0], v_direction = [1, 0, 1], period = [0.5, 0.5] }",
        "start = [0.1, 0.2, 0]\ndirection = [0, 0, 1]",
    );
    let t = &trace(&text)[0];
    assert_eq!(t.end, trajectories::End::Lost, "{t:?}");
    assert_eq!(t.points.len(), 2);
}

#[test]
fn bad_ideal_lens_tables_are_rejected_with_the_line() {
    let scene = |surface: &str| {
        format!(
            "studio = \"none\"\n[[object]]\nshape = {{ type = \"plane\", point = [0, 0, 5], normal = [0, 0, 1] }}\nsurface = {surface}\n"
        )
    };
    for (surface, message) in [
        (
            "{ type = \"ideal-thin-lens\", focal_length = 0, principal_point = [0, 0, 5], optical_axis = [0, 0, 1] }",
            "non-zero",
        ),
        (
            "{ type = \"ideal-thin-lens\", focal_length = 1e-20, principal_point = [0, 0, 5], optical_axis = [0, 0, 1] }",
            "magnitude at least 1e-15",
        ),
        (
            // Dr TIM has no ideal thin mirror with defaults (its lens has them).
            "{ type = \"ideal-thin-mirror\", focal_length = 1, optical_axis = [0, 0, 1] }",
            "principal_point",
        ),
        (
            "{ type = \"ideal-thin-cylindrical-lens\", focal_length = 1, principal_point = [0, 0, 5], optical_axis = [0, 0, 1], gradient_direction = [0, 0, 2] }",
            "must not be parallel",
        ),
        (
            "{ type = \"glens\", principal_point = [0, 0, 5], optical_axis = [0, 0, 0], focal_length_negative = -1, focal_length_positive = 1 }",
            "zero vector",
        ),
        (
            "{ type = \"glens\", principal_point = [0, 0, 5], optical_axis = [0, 0, 1], focal_length_negative = -1, focal_length_ratio = 2 }",
            "not a mixture",
        ),
        (
            "{ type = \"glens\", optical_axis = [0, 0, 1], nodal_direction = [1, 0, 0], focal_length_ratio = 2 }",
            "must not lie in the glens's plane",
        ),
        (
            "{ type = \"ideal-thin-lenslet-array\", focal_length = 1, centre = [0, 0, 5], u_direction = [1, 0, 0], v_direction = [0, 1, 0], period = [1, -1] }",
            "positive",
        ),
    ] {
        let e = timbre::scene::file::parse(&scene(surface), "lens.toml")
            .expect_err(surface)
            .to_string();
        assert!(e.starts_with("lens.toml:4:"), "{e}");
        assert!(e.contains(message), "{e}");
    }
    // Scaling a lens non-uniformly would leave its focal length undefined.
    let e = timbre::scene::file::parse(
        &format!(
            "{}transform = {{ scale = [1, 2, 1] }}\n",
            scene("{ type = \"ideal-thin-lens\", focal_length = 1, principal_point = [0, 0, 5], optical_axis = [0, 0, 1] }")
        ),
        "lens.toml",
    )
    .expect_err("non-uniform scale")
    .to_string();
    assert!(e.contains("non-uniformly"), "{e}");
}
