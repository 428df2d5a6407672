//! The tracer end to end: surface laws seen through the camera, and runaway recursion.

use glam::DVec3;
use timbre::embree::Device;
use timbre::render::{Image, render};
use timbre::scene::file::parse;
use timbre::scene::{Scene, SceneDescription};

fn render_text(toml: &str) -> Image {
    let d: SceneDescription = parse(toml, "test.toml").unwrap();
    let device = Device::new("").unwrap();
    let scene = Scene::build(&device, &d.objects, &d.lights).unwrap();
    render(&scene, &d.camera, &d.render, &|_| {}).unwrap()
}

const SKY: DVec3 = DVec3::new(0.5, 0.5, 1.0);

fn close(a: DVec3, b: DVec3) -> bool {
    (a - b).abs().max_element() < 1e-12
}

#[test]
fn a_mirror_at_45_degrees_shows_the_sky_scaled_by_its_reflection_coefficient() {
    // The mirror turns the camera's view (+z) upwards (+y), into the sky.
    let image = render_text(
        r#"
studio = "empty"
[render]
width = 9
height = 9
[[object]]
shape = { type = "parallelogram", corner = [-5, -5, 5], span_u = [10, 0, 0], span_v = [0, 10, 10] }
surface = { type = "mirror", reflection_coefficient = 0.9 }
"#,
    );
    assert!(close(image.pixel(4, 4), 0.9 * SKY), "{}", image.pixel(4, 4));
}

/// Sky behind, and a screen at z = 20 whose top half (y > 0) is red and bottom half blue.
const SCREEN: &str = r#"
studio = "none"
[render]
width = 41
height = 41
[camera]
type = "pinhole"
position = [0, 0, 0]
view_direction = [0, 0, 1]
up = [0, 1, 0]
horizontal_view_angle_deg = 10
[[object]]
name = "top"
shape = { type = "parallelogram", corner = [-50, 0, 20], span_u = [100, 0, 0], span_v = [0, 50, 0] }
surface = { type = "constant_colour", colour = [1, 0, 0] }
[[object]]
name = "bottom"
shape = { type = "parallelogram", corner = [-50, -50, 20], span_u = [100, 0, 0], span_v = [0, 50, 0] }
surface = { type = "constant_colour", colour = [0, 0, 1] }
"#;

fn ball(index_ratio: f64, transmission: f64) -> String {
    format!(
        "{SCREEN}[[object]]\nname = \"ball\"\nshape = {{ type = \"sphere\", centre = [0, 0, 5], radius = 1 }}\n\
         surface = {{ type = \"refractive\", index_ratio = {index_ratio}, transmission_coefficient = {transmission} }}\n"
    )
}

#[test]
fn a_refractive_ball_with_index_ratio_one_only_attenuates() {
    let plain = render_text(SCREEN);
    let image = render_text(&ball(1.0, 0.5));
    // Through the ball (two interfaces) the screen is seen undeviated at 0.5² of its brightness.
    for (x, y) in [(20, 20), (20, 15), (20, 25), (16, 20)] {
        assert!(
            close(image.pixel(x, y), 0.25 * plain.pixel(x, y)),
            "({x}, {y}): {}",
            image.pixel(x, y)
        );
    }
}

#[test]
fn a_glass_ball_lens_inverts_the_screen_behind_it() {
    let plain = render_text(SCREEN);
    let image = render_text(&ball(1.5, 1.0));
    // Slightly above the centre the camera sees the red top half directly, but the ball lens
    // (focal length 1.5 radii behind its centre, well before the screen) turns the view over.
    for (above, below) in [((20, 17), (20, 23)), ((20, 18), (20, 22))] {
        assert_eq!(plain.pixel(above.0, above.1), DVec3::X);
        assert_eq!(plain.pixel(below.0, below.1), DVec3::Z);
        assert_eq!(
            image.pixel(above.0, above.1),
            DVec3::Z,
            "inverted above the centre"
        );
        assert_eq!(
            image.pixel(below.0, below.1),
            DVec3::X,
            "inverted below the centre"
        );
    }
}

#[test]
fn total_internal_reflection_keeps_light_inside_a_denser_medium() {
    // Seen from inside a glass block (index 1.5) the ceiling at 60° incidence reflects totally:
    // the camera, looking up at 60° from the normal, sees the floor of the block (blue), not
    // the red sky above; at 30° the ray leaves the block and sees red.
    let scene = |angle_from_normal: f64| {
        let a = angle_from_normal.to_radians();
        format!(
            r#"
studio = "none"
[render]
width = 3
height = 3
[camera]
type = "pinhole"
position = [0, 0, 0]
view_direction = [{}, {}, 0]
up = [0, 0, 1]
horizontal_view_angle_deg = 0.01
[[object]]
name = "glass top"
shape = {{ type = "plane", point = [0, 1, 0], normal = [0, 1, 0] }}
surface = {{ type = "refractive", index_ratio = 1.5 }}
[[object]]
name = "red above"
shape = {{ type = "plane", point = [0, 5, 0], normal = [0, -1, 0] }}
surface = {{ type = "constant_colour", colour = [1, 0, 0] }}
[[object]]
name = "blue below"
shape = {{ type = "plane", point = [0, -1, 0], normal = [0, 1, 0] }}
surface = {{ type = "constant_colour", colour = [0, 0, 1] }}
"#,
            a.sin(),
            a.cos()
        )
    };
    assert_eq!(render_text(&scene(60.0)).pixel(1, 1), DVec3::Z);
    assert_eq!(render_text(&scene(30.0)).pixel(1, 1), DVec3::X);
}

#[test]
fn runaway_recursion_between_parallel_mirrors_ends_black_without_crashing() {
    // Every camera ray bounces between the two mirrors forever; with 20 000 levels (deeper than
    // a default 2 MiB thread stack allows) each one runs out of levels and returns black.
    let image = render_text(
        r#"
studio = "none"
[render]
width = 4
height = 4
max_trace_level = 20000
[[object]]
shape = { type = "plane", point = [0, 0, 2], normal = [0, 0, -1] }
surface = { type = "mirror" }
[[object]]
shape = { type = "plane", point = [0, 0, -1], normal = [0, 0, 1] }
surface = { type = "mirror" }
"#,
    );
    assert!(image.pixels.iter().all(|&c| c == DVec3::ZERO));
    assert_eq!(
        image.rays,
        16 * 20000,
        "each pixel traces one ray per level"
    );
}
