//! The tracer end to end: surface laws seen through the camera, and runaway recursion.

mod common;

use glam::DVec3;
use timbre::embree::{Device, ExactRay};
use timbre::geometry::{SceneGeometry, Shape, Sphere};
use timbre::scene::{Scene, file};

use common::images::render_text;

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
surface = {{ type = "refractive", index_ratio = 1.5, transmission = 1 }}
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

/// A matt white floor seen from straight above, lit from the upper left (−x), with a small
/// ball hovering to the right of the view's centre.
fn ball_over_floor(shadow_throwing: bool) -> String {
    format!(
        r#"
studio = "none"
[render]
width = 11
height = 11
[camera]
type = "pinhole"
position = [0, 10, 0]
view_direction = [0, -1, 0]
up = [0, 0, 1]
horizontal_view_angle_deg = 40
[[light]]
type = "point"
position = [-100, 100, 0]
colour = [1, 1, 1]
[[object]]
name = "floor"
shape = {{ type = "plane", point = [0, 0, 0], normal = [0, 1, 0] }}
surface = {{ type = "matt", colour = [1, 1, 1] }}
[[object]]
name = "ball"
shadow_throwing = {shadow_throwing}
shape = {{ type = "sphere", centre = [1.2, 1, 0], radius = 0.3 }}
surface = {{ type = "constant_colour", colour = [0, 1, 0] }}
"#
    )
}

#[test]
fn only_shadow_throwing_objects_cast_shadows() {
    // The ball (seen at column 7) shadows the floor around x = 2.2 (column 8); a floor pixel to
    // the left (column 2) is lit either way.
    let (below, away) = ((8, 5), (2, 5));
    let with = render_text(&ball_over_floor(true));
    let without = render_text(&ball_over_floor(false));
    let lit = |c: DVec3| c.x > 0.5;
    assert!(lit(with.pixel(away.0, away.1)) && lit(without.pixel(away.0, away.1)));
    assert_eq!(
        with.pixel(below.0, below.1),
        DVec3::ZERO,
        "shadowed by a shadow-throwing ball"
    );
    assert!(
        lit(without.pixel(below.0, below.1)),
        "{}",
        without.pixel(below.0, below.1)
    );
}

#[test]
fn a_transparent_sheet_passes_light_undeviated_scaled_by_its_coefficient() {
    let plain = render_text(SCREEN);
    let sheet = format!(
        "{SCREEN}[[object]]\nshape = {{ type = \"parallelogram\", corner = [-0.2, -0.2, 5], \
         span_u = [0.4, 0, 0], span_v = [0, 0.4, 0] }}\n\
         surface = {{ type = \"transparent\", transmission_coefficient = 0.3 }}\n"
    );
    let image = render_text(&sheet);
    // The sheet covers the middle of the view (±0.2 at z = 5), not the corners.
    for (x, y) in [(20, 15), (20, 25), (0, 0)] {
        let expected = if (x, y) == (0, 0) { 1.0 } else { 0.3 };
        assert!(
            close(image.pixel(x, y), expected * plain.pixel(x, y)),
            "({x}, {y})"
        );
    }
}

#[test]
fn enormous_shapes_are_still_hit() {
    // Embree drops primitives whose bounds exceed about ±1.8e18; such shapes are intersected
    // outside the BVH instead.
    let device = Device::new("").unwrap();
    // A sphere of radius 1e19 around the camera.
    let huge = Shape::Sphere(Sphere::new(DVec3::ZERO, 1e19).unwrap());
    let geometry = SceneGeometry::build(&device, vec![(huge, true)], Vec::new()).unwrap();
    let hit = geometry
        .nearest(DVec3::ZERO, DVec3::Z, 0.0, f64::INFINITY)
        .unwrap();
    assert!((hit.t / 1e19 - 1.0).abs() < 1e-12, "{}", hit.t);
    assert!(geometry.shadowed(DVec3::ZERO, DVec3::Z, 0.0, 2e19));
    assert!(!geometry.shadowed(DVec3::ZERO, DVec3::Z, 0.0, 1e18));
}

/// Packets (8-wide Embree queries, as primary and shadow rays are traced) find exactly what
/// single rays find. Embree 3's "coherent" packet traversal missed the chequered disc of
/// scenes/shapes.toml (a primitive whose box has no depth) for these two rays from the fence
/// behind it, which changed pixels of a finite-aperture render once shadow rays went as packets.
#[test]
fn packets_find_what_single_rays_find() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/shapes.toml");
    let description = file::load(std::path::Path::new(path)).unwrap();
    let device = Device::new("").unwrap();
    let scene = Scene::build(&device, &description).unwrap();
    let g = &scene.scene_frame.geometry;
    let (t_min, to_light) = (1.5e-8, [604.029349543927, 604.0292459621895]);
    let rays = [
        ExactRay {
            origin: DVec3::new(-0.4966119824806931, -0.9250506197551259, 14.0),
            direction: DVec3::new(0.16637703459005884, 0.4981960741592588, -0.8509520280564119),
        },
        ExactRay {
            origin: DVec3::new(-0.4885447426105689, -0.927536714677648, 14.0),
            direction: DVec3::new(0.16636370741045353, 0.4982002754441378, -0.8509521739816136),
        },
    ];
    for (ray, lane) in rays
        .iter()
        .zip(g.nearest_packet(&rays, t_min, f64::INFINITY))
    {
        let single = g.nearest(ray.origin, ray.direction, t_min, f64::INFINITY);
        assert!(
            single.is_some_and(|h| (h.t - 3.5255).abs() < 1e-3),
            "{single:?}"
        );
        assert_eq!(lane, single);
    }
    let segments = [(rays[0], t_min, to_light[0]), (rays[1], t_min, to_light[1])];
    let packet = g.shadowed8(&segments);
    for (&(ray, t_min, t_max), lane) in segments.iter().zip(packet) {
        assert!(g.shadowed(ray.origin, ray.direction, t_min, t_max));
        assert!(lane, "a shadow ray of the packet missed the disc");
    }
}

/// Packets of 1 to 8 nearly parallel rays (`spread` apart, from one origin or nearby ones, drawn
/// in the boxes `origins` and towards `targets`) find what the rays find one by one in the scene
/// `text`, and so do packets of shadow rays; `exact_ties` asks for the same hit to the bit, else
/// for the same object at the same distance (a ray through an edge two triangles share may
/// name either). Returns the number of rays that hit something.
fn packets_agree_with_single_rays(
    text: &str,
    origins: [DVec3; 2],
    targets: [DVec3; 2],
    exact_ties: bool,
) -> u32 {
    let description = file::parse(text, "packets.toml").unwrap();
    let device = Device::new("").unwrap();
    let scene = Scene::build(&device, &description).unwrap();
    let g = &scene.scene_frame.geometry;
    let mut state = 0x2545_f491_4f6c_dd1d_u64;
    let mut random = move || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut within =
        |[lo, hi]: [DVec3; 2]| lo + (hi - lo) * DVec3::new(random(), random(), random());
    let mut hits = 0;
    for packet in 0..3000 {
        let (origin, towards) = (within(origins), within(targets));
        let spread = 10f64.powf(-8.0 + 6.0 * within([DVec3::ZERO, DVec3::ONE]).x);
        let jitter: Vec<DVec3> = (0..8)
            .map(|_| within([DVec3::ZERO, DVec3::ONE]) * spread * (packet % 2) as f64)
            .collect();
        let rays: Vec<ExactRay> = (0..1 + packet % 8)
            .map(|i| {
                let o = origin + jitter[i];
                let d = towards + DVec3::new((i % 4) as f64, (i / 4) as f64, 0.0) * spread - o;
                ExactRay {
                    origin: o,
                    direction: d.normalize(),
                }
            })
            .collect();
        for (ray, lane) in rays.iter().zip(g.nearest_packet(&rays, 0.0, f64::INFINITY)) {
            let single = g.nearest(ray.origin, ray.direction, 0.0, f64::INFINITY);
            let same = match (lane, single) {
                _ if exact_ties => lane == single,
                (Some(a), Some(b)) => a.object == b.object && (a.t - b.t).abs() <= 1e-12 * b.t,
                (a, b) => a == b,
            };
            assert!(
                same,
                "packet {packet}: {ray:?}: {lane:?} against {single:?}"
            );
            hits += single.is_some() as u32;
        }
        let segments: Vec<(ExactRay, f64, f64)> = rays
            .iter()
            .map(|&ray| (ray, 1e-9, 100.0 * within([DVec3::ZERO, DVec3::ONE]).x))
            .collect();
        for (&(ray, t_min, t_max), lane) in segments.iter().zip(g.shadowed8(&segments)) {
            let single = g.shadowed(ray.origin, ray.direction, t_min, t_max);
            assert_eq!(lane, single, "packet {packet}: {ray:?} to {t_max}");
        }
    }
    hits
}

/// 13 500 rays in a box, in packets, hit something in a fair share of cases.
fn fair_share(hits: u32) {
    assert!((1000..12500).contains(&hits), "{hits} of 13 500 rays hit");
}

/// Packets find flat primitives facing the axes, whose boxes are thin or of no depth, as single
/// rays do. Embree's coherent-traversal hint would break this in the first three scenes (seen
/// from behind, the disc of `packets_find_what_single_rays_find`; discs at a coordinate that is
/// no f32, seen from just above; an array of flat mesh tiles): for user geometry and instances
/// its frustum test is not conservative. The last scene, of triangles alone, takes the hint:
/// there Embree's robust frustum test loses no hit, though a ray through an edge two triangles
/// share may name either.
#[test]
fn packets_of_flat_primitives_find_what_single_rays_find() {
    let matt = "surface = { type = \"matt\", colour = [1, 1, 1] }";
    let far_triangle = format!(
        "[[object]]\nshape = {{ type = \"triangle-mesh\", vertices = [[50, 50, 50], [51, 50, 50], [50, 51, 50]], triangles = [[0, 1, 2]] }}\n{matt}\n"
    );
    let mixed = format!(
        r#"studio = "none"
[[object]]
shape = {{ type = "disc", centre = [0, 0.55, 11], normal = [0, 0, -1], radius = 0.5 }}
{matt}
[[object]]
shape = {{ type = "disc", centre = [1.2, 0, 8], normal = [1, 0, 0], radius = 0.9 }}
{matt}
[[object]]
shape = {{ type = "parallelogram", corner = [-2, -0.8, 5], span_u = [1.5, 0, 0], span_v = [0, 0, 4] }}
{matt}
[[object]]
shape = {{ type = "convex-polygon", vertices = [[-1, 0.3, 9], [-0.2, 0.3, 9], [-0.4, 1.2, 9]] }}
{matt}
[[object]]
shape = {{ type = "disc", centre = [0, -0.5, 7], normal = [0, 1, 0], radius = 0.05 }}
{matt}
array = {{ vectors = [[0.17, 0, 0], [0, 0, 0.13]], counts = [12, 9], centred = true }}
{far_triangle}"#
    );
    let (behind, front) = (
        [DVec3::new(-2.0, -1.5, 14.0), DVec3::new(2.0, 1.5, 14.0)],
        [DVec3::new(-2.0, -1.5, 0.0), DVec3::new(2.0, 1.5, 0.0)],
    );
    let scene_targets = [DVec3::new(-2.0, -1.25, 5.0), DVec3::new(2.0, 1.25, 11.0)];
    fair_share(packets_agree_with_single_rays(
        &mixed,
        behind,
        scene_targets,
        true,
    ));
    fair_share(packets_agree_with_single_rays(
        &mixed,
        front,
        scene_targets,
        true,
    ));

    // 64 discs facing z at z = 0.0501236, seen at grazing angles from just above them.
    let mut field = String::from("studio = \"none\"\n");
    for i in 0..8 {
        for j in 0..8 {
            let (x, y) = (-1.0 + 2.0 * i as f64 / 7.0, -1.0 + 2.0 * j as f64 / 7.0);
            field += &format!(
                "[[object]]\nshape = {{ type = \"disc\", centre = [{x}, {y}, 0.0501236], normal = [0, 0, 1], radius = 0.12 }}\n{matt}\n"
            );
        }
    }
    let plane = [
        DVec3::new(-1.1, -1.1, 0.0501236),
        DVec3::new(1.1, 1.1, 0.0501236),
    ];
    let above = [DVec3::new(-1.0, -1.0, 0.0502), DVec3::new(1.0, 1.0, 0.0602)];
    fair_share(packets_agree_with_single_rays(
        &(field + &far_triangle),
        above,
        plane,
        true,
    ));

    // An 8 x 8 array of 2-triangle tiles at z = 20.969, seen from z = 26.73.
    let tiles = format!(
        "studio = \"none\"\n[[object]]\nshape = {{ type = \"triangle-mesh\", vertices = [[0, 0, 20.969], [0.2, 0, 20.969], [0.2, 0.2, 20.969], [0, 0.2, 20.969]], triangles = [[0, 1, 2], [0, 2, 3]] }}\n{matt}\narray = {{ vectors = [[0.25, 0, 0], [0, 0.25, 0]], counts = [8, 8] }}\n"
    );
    let tile_plane = [DVec3::new(-0.1, -0.1, 20.969), DVec3::new(2.1, 2.1, 20.969)];
    let tile_origins = [DVec3::new(-1.0, -1.0, 26.73), DVec3::new(3.0, 3.0, 26.73)];
    fair_share(packets_agree_with_single_rays(
        &tiles,
        tile_origins,
        tile_plane,
        true,
    ));

    // The same tiles as one mesh of triangles alone (coherent packets): the same hits, up to
    // which of two triangles a ray through their shared edge names.
    let (mut vertices, mut triangles) = (Vec::new(), Vec::new());
    for i in 0..8 {
        for j in 0..8 {
            let (x, y, k) = (0.25 * i as f64, 0.25 * j as f64, vertices.len());
            for (dx, dy) in [(0.0, 0.0), (0.2, 0.0), (0.2, 0.2), (0.0, 0.2)] {
                vertices.push(format!("[{}, {}, 0.0501236]", x + dx, y + dy));
            }
            triangles.push(format!(
                "[{k}, {}, {}], [{k}, {}, {}]",
                k + 1,
                k + 2,
                k + 2,
                k + 3
            ));
        }
    }
    let mesh = format!(
        "studio = \"none\"\n[[object]]\nshape = {{ type = \"triangle-mesh\", vertices = [{}], triangles = [{}] }}\n{matt}\n",
        vertices.join(", "),
        triangles.join(", ")
    );
    let mesh_plane = [
        DVec3::new(-0.1, -0.1, 0.0501236),
        DVec3::new(2.1, 2.1, 0.0501236),
    ];
    let mesh_above = [DVec3::new(-1.0, -1.0, 0.0502), DVec3::new(3.0, 3.0, 0.2)];
    fair_share(packets_agree_with_single_rays(
        &mesh, mesh_above, mesh_plane, false,
    ));
}
