//! Dr TIM's visual aids (issue 21): arrows, rulers, coordinate systems, the surface-coordinate
//! axes of a surface point, and Tim's head, checked through scene files against where their
//! parameters put them, worked out here.

mod common;

use glam::DVec3;
use timbre::geometry::Shape;
use timbre::scene::SceneDescription;

fn parse(text: &str) -> SceneDescription {
    common::images::parse(text)
}

fn parse_error(text: &str) -> String {
    timbre::scene::file::parse(text, "s.toml")
        .map(|_| ())
        .expect_err("an error")
        .to_string()
}

fn shape<'a>(scene: &'a SceneDescription, name: &str) -> &'a Shape {
    &scene
        .objects
        .iter()
        .find(|o| o.name == name)
        .unwrap_or_else(|| panic!("no object {name}"))
        .shape
}

/// The nearest hit distance of `shape` along o + t d.
fn hit(shape: &Shape, o: DVec3, d: DVec3) -> Option<f64> {
    shape.intersect(o, d, 0.0, f64::INFINITY).map(|h| h.0)
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() < 1e-9
}

fn object(shape: &str) -> String {
    format!(
        "studio = \"none\"\n[[object]]\nname = \"aid\"\nshape = {shape}\nsurface = {{ type = \"matt\", colour = [1, 1, 1] }}\n"
    )
}

#[test]
fn an_arrow_has_its_shaft_and_tip_where_its_keys_put_them() {
    // Along +x from 0 to 2: shaft radius 0.05, tip 0.5 long with a half angle of 20°.
    let scene = parse(&object(
        r#"{ type = "arrow", start = [0, 0, 0], end = [2, 0, 0], shaft_radius = 0.05, tip_length = 0.5, tip_angle_deg = 20 }"#,
    ));
    let arrow = shape(&scene, "aid");
    // From beyond the tip, along the axis: the apex.
    assert!(close(
        hit(arrow, DVec3::new(5.0, 0.0, 0.0), DVec3::NEG_X).unwrap(),
        3.0
    ));
    // Across the shaft: its radius.
    let t = hit(arrow, DVec3::new(1.0, 0.0, 5.0), DVec3::NEG_Z).unwrap();
    assert!(close(t, 5.0 - 0.05), "t {t}");
    // Across the tip, 0.2 behind the apex: the cone's radius there, 0.2 tan 20°.
    let t = hit(arrow, DVec3::new(1.8, 0.0, 5.0), DVec3::NEG_Z).unwrap();
    assert!(close(t, 5.0 - 0.2 * 20f64.to_radians().tan()), "t {t}");
    // Beyond the shaft's radius but inside the tip's base: only the tip's base is there.
    let t = hit(arrow, DVec3::new(0.0, 0.1, 0.0), DVec3::X).unwrap();
    assert!(close(t, 1.5), "t {t}");
    // Rays along an oblique arrow, inside its shaft, cross its surface exactly twice: in at the
    // back, out through the tip (no sliver where the shaft meets the tip).
    let (a, b) = (DVec3::new(0.3, -0.2, 0.1), DVec3::new(1.7, 0.9, 1.3));
    let oblique = parse(&object(&format!(
        "{{ type = \"arrow\", start = [{}, {}, {}], end = [{}, {}, {}] }}",
        a.x, a.y, a.z, b.x, b.y, b.z
    )));
    let oblique = shape(&oblique, "aid");
    let axis = (b - a).normalize();
    let (u, v) = axis.any_orthonormal_pair();
    for k in 0..400 {
        let r = 0.05 * (b - a).length() * (k as f64 / 400.0);
        let turn = 0.7 * k as f64;
        let o = a - axis + r * (turn.cos() * u + turn.sin() * v);
        let d = (axis + 1e-5 * (k % 3) as f64 * u).normalize();
        let (mut from, mut n) = (0.0, 0);
        while let Some((t, _)) = oblique.intersect(o, d, from, 10.0) {
            (from, n) = (t, n + 1);
        }
        assert_eq!(n, 2, "ray {k}");
    }
    // With Dr TIM's default proportions (shaft 3 %, tip 20 % at 20°) the shaft of a 2 long
    // arrow has radius 0.06.
    let scene = parse(&object(
        r#"{ type = "arrow", start = [0, 0, 0], end = [2, 0, 0] }"#,
    ));
    let t = hit(
        shape(&scene, "aid"),
        DVec3::new(1.0, 0.0, 5.0),
        DVec3::NEG_Z,
    )
    .unwrap();
    assert!(close(t, 5.0 - 0.06), "t {t}");
}

#[test]
fn a_ruler_has_a_tick_every_spacing_and_longer_major_ticks() {
    // From x = 0 to 1, ticks every 0.1 sticking out along +y, 0.05 long (major ones 0.075),
    // every 5th major; rod radius 0.01, ticks 2/3 as thick.
    let scene = parse(&object(
        r#"{ type = "ruler", start = [0, 0, 0], end = [1, 0, 0], tick_spacing = 0.1, tick_direction = [0, 1, 0], radius = 0.01, tick_length = 0.05, major_every = 5 }"#,
    ));
    let ruler = shape(&scene, "aid");
    // Lines along x at a height every tick reaches, and one only the major ticks reach: the
    // ticks' near faces are 0.1 apart, 2/3 of the rod's radius before each tick's centre.
    let faces = |height: f64| {
        let mut out = Vec::new();
        let mut from = -1.0;
        let o = DVec3::new(-1.0, height, 0.0);
        while let Some((t, _)) = ruler.intersect(o, DVec3::X, from, 3.0) {
            out.push(t - 1.0);
            from = t;
        }
        out
    };
    let every = faces(0.05);
    let r = 0.01 * 2.0 / 3.0;
    assert_eq!(every.len(), 22, "{every:?}");
    for (k, pair) in every.chunks(2).enumerate() {
        assert!(close(pair[0], 0.1 * k as f64 - r) && close(pair[1], 0.1 * k as f64 + r));
    }
    let major = faces(0.07);
    assert_eq!(major.len(), 6, "{major:?}");
    for (k, pair) in major.chunks(2).enumerate() {
        assert!(close(pair[0], 0.5 * k as f64 - r), "{major:?}");
    }
}

#[test]
fn the_surface_axes_stand_on_the_surface_point_with_those_coordinates() {
    // A sphere of radius 2 about c: surface coordinates (r φ, r θ) with φ the longitude about
    // +y from +z towards +x and θ the polar angle from +y (SCENE_FORMAT.md).
    let c = DVec3::new(1.0, -1.0, 10.0);
    let (phi, theta) = (-2.5f64, 1.1f64);
    let text = format!(
        "studio = \"none\"\n[[object]]\nname = \"ball\"\nshape = {{ type = \"sphere\", centre = [1, -1, 10], radius = 2 }}\nsurface = {{ type = \"matt\", colour = [1, 1, 1] }}\nsurface_axes = {{ coordinates = [{:?}, {:?}], length = 0.5 }}\n",
        2.0 * phi,
        2.0 * theta
    );
    let scene = parse(&text);
    let n = DVec3::new(
        theta.sin() * phi.sin(),
        theta.cos(),
        theta.sin() * phi.cos(),
    );
    let p = c + 2.0 * n;
    // The normal arrow: its tip 0.5 out along the outward normal.
    let normal = shape(&scene, "ball/normal");
    let t = hit(normal, p + 2.0 * n, -n).unwrap();
    assert!(close(t, 1.5), "t {t}");
    // The u arrow along the direction of increasing longitude, the v arrow towards the pole
    // (û × v̂ = n̂).
    let east = DVec3::new(phi.cos(), 0.0, -phi.sin());
    let north = n.cross(east);
    for (name, axis) in [("ball/u axis", east), ("ball/v axis", north)] {
        let t = hit(shape(&scene, name), p + 2.0 * axis, -axis).unwrap();
        assert!(close(t, 1.5), "{name}: t {t}");
    }
    assert_eq!(scene.objects.len(), 4);
}

#[test]
fn a_coordinate_system_points_along_its_axes() {
    let scene = parse(
        "studio = \"none\"\n[[device]]\nname = \"xyz\"\naid = { type = \"coordinate-system\", origin = [1, 2, 3], axes = [[0, 1, 0], [-1, 0, 0], [0, 0, 1]], length = 2 }\n",
    );
    let o = DVec3::new(1.0, 2.0, 3.0);
    for (name, axis) in [
        ("xyz/x axis", DVec3::Y),
        ("xyz/y axis", DVec3::NEG_X),
        ("xyz/z axis", DVec3::Z),
    ] {
        let t = hit(shape(&scene, name), o + 5.0 * axis, -axis).unwrap();
        assert!(close(t, 3.0), "{name}: t {t}");
    }
}

#[test]
fn tims_head_faces_its_front_direction() {
    // Facing +x, top +y, radius 2 at c: the nose (radius 0.4) sits on the head's surface
    // straight ahead, the eyes above it, the right eye on Tim's right (−z when facing +x).
    let scene = parse(
        "studio = \"none\"\n[[device]]\nname = \"tim\"\naid = { type = \"tim-head\", centre = [0, 1, 5], radius = 2, front_direction = [1, 0, 0] }\n",
    );
    let c = DVec3::new(0.0, 1.0, 5.0);
    let centre_of = |name: &str| {
        let (lo, hi) = shape(&scene, name).bounds().unwrap();
        0.5 * (lo + hi)
    };
    assert!((centre_of("tim/nose") - (c + DVec3::new(2.0, 0.0, 0.0))).length() < 1e-9);
    assert!((centre_of("tim/head") - c).length() < 1e-9);
    let (right, left) = (centre_of("tim/right eye"), centre_of("tim/left eye"));
    assert!(
        (right - (c + 2.0 * DVec3::new(0.9, 0.25, -0.25))).length() < 1e-9,
        "{right}"
    );
    assert!(
        (left - (c + 2.0 * DVec3::new(0.9, 0.25, 0.25))).length() < 1e-9,
        "{left}"
    );
    let names: Vec<&str> = scene.objects.iter().map(|o| o.name.as_str()).collect();
    for part in [
        "head",
        "cap",
        "visor",
        "nose",
        "left iris",
        "right pupil",
        "upper lip",
        "left ear",
    ] {
        assert!(names.contains(&format!("tim/{part}").as_str()), "{names:?}");
    }
}

#[test]
fn bad_aids_are_refused_clearly() {
    let e = parse_error(&object(
        r#"{ type = "arrow", start = [0, 0, 0], end = [1, 0, 0], tip_length = 2 }"#,
    ));
    assert!(
        e.contains("s.toml:4:") && e.contains("tip shorter than the arrow"),
        "{e}"
    );
    let e = parse_error(&object(
        r#"{ type = "ruler", start = [0, 0, 0], end = [10, 0, 0], tick_spacing = 0.001 }"#,
    ));
    assert!(e.contains("at most 1000 ticks"), "{e}");
    let e = parse_error(&object(
        r#"{ type = "ruler", start = [0, 0, 0], end = [1, 0, 0], tick_spacing = 1e-300 }"#,
    ));
    assert!(e.contains("at most 1000 ticks"), "{e}");
    let e = parse_error(&object(
        r#"{ type = "ruler", start = [0, 0, 0], end = [1, 0, 0], tick_spacing = 0.1, tick_direction = [2, 0, 0] }"#,
    ));
    assert!(e.contains("not be parallel to the ruler"), "{e}");
    let e = parse_error(
        "studio = \"none\"\n[[device]]\nname = \"d\"\nshow_edges = true\naid = { type = \"tim-head\", centre = [0, 0, 5] }\n",
    );
    assert!(
        e.contains("s.toml:5:") && e.contains("belong to lens devices"),
        "{e}"
    );
    let e = parse_error("studio = \"none\"\n[[device]]\nname = \"d\"\n");
    assert!(
        e.contains("s.toml:2:") && e.contains("exactly one of a `lenses` table"),
        "{e}"
    );
    let csg = "studio = \"none\"\n[[object]]\nname = \"b\"\nshape = { type = \"union\", of = [{ type = \"sphere\", centre = [0, 0, 5], radius = 1 }, { type = \"sphere\", centre = [1, 0, 5], radius = 1 }] }\nsurface = { type = \"matt\", colour = [1, 1, 1] }\nsurface_axes = { coordinates = [0, 1] }\n";
    let e = parse_error(csg);
    assert!(
        e.contains("s.toml:6:") && e.contains("has no point with surface coordinates"),
        "{e}"
    );
}
