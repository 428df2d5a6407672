//! The appearance surfaces in whole scenes, traced through the library: a tinted solid's
//! Beer–Lambert absorption over the path inside (straight, oblique, around an object inside),
//! colour filters and semi-transparent surfaces against a backdrop of known colour.

use glam::DVec3;
use timbre::embree::Device;
use timbre::math::{Colour, Ray, ReferenceFrame};
use timbre::render::Tracer;
use timbre::scene::{Scene, file};
use timbre::trajectories::{self, End};

/// The backdrop: a plane at z = 10 facing the origin, showing this colour whatever the light.
const BACKDROP: [f64; 3] = [0.8, 0.6, 0.4];

/// The colours seen from the origin along `directions` in the scene of `objects` (TOML
/// `[[object]]` tables) before the backdrop, with nothing else (no studio, no lights).
fn seen(objects: &str, directions: &[DVec3]) -> Vec<Colour> {
    let [r, g, b] = BACKDROP;
    let text = format!(
        "studio = \"none\"\n\
         [[object]]\nname = \"backdrop\"\n\
         shape = {{ type = \"plane\", point = [0, 0, 10], normal = [0, 0, -1] }}\n\
         surface = {{ type = \"constant-colour\", colour = [{r}, {g}, {b}] }}\n{objects}"
    );
    let d = file::parse(&text, "appearance.toml").unwrap_or_else(|e| panic!("{e}\n{text}"));
    let device = Device::new("").unwrap();
    let scene = Scene::build(&device, &d).unwrap();
    let tracer = Tracer::new(&scene, &d.camera, false);
    directions
        .iter()
        .map(|&dir| {
            tracer.trace(
                &Ray::new(DVec3::ZERO, dir, 0.0),
                0.0,
                100,
                ReferenceFrame::Scene,
            )
        })
        .collect()
}

fn backdrop() -> Colour {
    Colour::from_array(BACKDROP)
}

/// exp(−a·d) of each channel.
fn kept(a: Colour, d: f64) -> Colour {
    Colour::new((-a.x * d).exp(), (-a.y * d).exp(), (-a.z * d).exp())
}

#[track_caller]
fn assert_close(got: Colour, expected: Colour) {
    assert!(
        (got - expected).abs().max_element() < 1e-9,
        "got {got}, expected {expected}"
    );
}

const A: [f64; 3] = [0.5, 1.0, 2.0];

/// A slab 0.7 thick (z from 4.65 to 5.35, wide enough for every ray here) of absorption
/// (0.5, 1, 2) per unit length.
const SLAB: &str = "[[object]]\nname = \"slab\"\nshadow_throwing = false\n\
    shape = { type = \"cuboid\", centre = [0, 0, 5], size = [40, 40, 0.7] }\n\
    surface = { type = \"tinted-solid\", absorption_coefficient = [0.5, 1, 2] }\n";

/// Straight through the slab the backdrop keeps exp(−a·0.7) of each channel; at 40° to the
/// slab's normal the path inside is 0.7 / cos 40°.
#[test]
fn a_tinted_slab_keeps_exp_minus_a_d_straight_and_obliquely() {
    let a = Colour::from_array(A);
    let theta = 40f64.to_radians();
    let oblique = DVec3::new(theta.sin(), 0.0, theta.cos());
    let colours = seen(SLAB, &[DVec3::Z, oblique]);
    assert_close(colours[0], backdrop() * kept(a, 0.7));
    assert_close(colours[1], backdrop() * kept(a, 0.7 / theta.cos()));
}

/// Coloured glass: a layer stack of a refracting surface (index ratio 1.5, transmission 0.9)
/// over a tinted solid, on the slab. At 40° the ray refracts to θ' with sin θ' = sin 40°/1.5
/// (Snell), crosses 0.7/cos θ' of the tint and leaves at 40° again, shifted sideways (the
/// backdrop shows one colour, so only the light kept counts): 0.9² exp(−a·0.7/cos θ').
#[test]
fn coloured_glass_refracts_and_absorbs_along_the_refracted_path() {
    let a = Colour::from_array(A);
    let glass = "[[object]]\nname = \"glass\"\nshadow_throwing = false\n\
        shape = { type = \"cuboid\", centre = [0, 0, 5], size = [40, 40, 0.7] }\n\
        surface = { type = \"layer-stack\", layers = [\
        { type = \"refractive\", index_ratio = 1.5, transmission_coefficient = 0.9 }, \
        { type = \"tinted-solid\", absorption_coefficient = [0.5, 1, 2] }] }\n";
    let theta = 40f64.to_radians();
    let inside = (theta.sin() / 1.5).asin();
    let oblique = DVec3::new(theta.sin(), 0.0, theta.cos());
    let colours = seen(glass, &[DVec3::Z, oblique]);
    assert_close(colours[0], backdrop() * 0.81 * kept(a, 0.7));
    assert_close(colours[1], backdrop() * 0.81 * kept(a, 0.7 / inside.cos()));
}

/// Inside a solid 2 thick (z from 4 to 6), a constant-colour ball of radius 0.3 about
/// (0, 0, 5) is seen through 0.7 of the tint; a transparent ball (radius 0.5, about (1, 0, 5))
/// takes its diameter out of the tinted path of a ray through its centre, which keeps
/// exp(−a·(2 − 1)) of the backdrop; a ray that misses both crosses the full 2.
#[test]
fn objects_inside_a_tinted_solid_are_seen_through_the_tint_before_them() {
    let a = Colour::from_array(A);
    let ball = Colour::new(0.2, 0.9, 0.5);
    let objects = "[[object]]\nname = \"block\"\nshadow_throwing = false\n\
         shape = { type = \"cuboid\", centre = [0, 0, 5], size = [40, 40, 2] }\n\
         surface = { type = \"tinted-solid\", absorption_coefficient = [0.5, 1, 2] }\n\
         [[object]]\nname = \"ball\"\n\
         shape = { type = \"sphere\", centre = [0, 0, 5], radius = 0.3 }\n\
         surface = { type = \"constant-colour\", colour = [0.2, 0.9, 0.5] }\n\
         [[object]]\nname = \"bubble\"\nshadow_throwing = false\n\
         shape = { type = \"sphere\", centre = [1, 0, 5], radius = 0.5 }\n\
         surface = { type = \"transparent\", transmission_coefficient = 1 }\n";
    let through_bubble = DVec3::new(1.0, 0.0, 5.0);
    let beside = DVec3::new(-1.0, 0.0, 5.0);
    let colours = seen(objects, &[DVec3::Z, through_bubble, beside]);
    assert_close(colours[0], ball * kept(a, 0.7));
    // Along the slanted line the block is 2 × |d| / d_z thick, the bubble's chord 1.
    let slant = through_bubble.length() / 5.0;
    assert_close(colours[1], backdrop() * kept(a, 2.0 * slant - 1.0));
    assert_close(
        colours[2],
        backdrop() * kept(a, 2.0 * beside.length() / 5.0),
    );
}

/// A colour filter passes its channels of the backdrop; a semi-transparent red surface
/// (T = 0.75) shows a quarter red and three quarters of the backdrop; two filters in a layer
/// stack pass the product of their channels; an average of a filter and a colour shows their
/// mean.
#[test]
fn filters_and_semi_transparent_panes_mix_the_backdrop_as_stated() {
    let pane = |z: f64, surface: &str| {
        format!(
            "[[object]]\nname = \"pane {z}\"\nshadow_throwing = false\n\
             shape = {{ type = \"parallelogram\", corner = [-1, -1, {z}], span_u = [2, 0, 0], span_v = [0, 2, 0] }}\n\
             surface = {surface}\n"
        )
    };
    let check = |surface: &str, expected: Colour| {
        let got = seen(&pane(5.0, surface), &[DVec3::Z])[0];
        assert_close(got, expected);
    };
    check(
        "{ type = \"colour-filter\", transmission = [0, 1, 0.5] }",
        backdrop() * Colour::new(0.0, 1.0, 0.5),
    );
    check(
        "{ type = \"semi-transparent\", surface = { type = \"constant-colour\", colour = [1, 0, 0] } }",
        0.25 * Colour::X + 0.75 * backdrop(),
    );
    check(
        "{ type = \"layer-stack\", layers = [{ type = \"colour-filter\", transmission = [0.5, 1, 1] }, { type = \"colour-filter\", transmission = [1, 0.5, 0] }] }",
        backdrop() * Colour::new(0.5, 0.5, 0.0),
    );
    check(
        "{ type = \"average\", surfaces = [{ type = \"colour-filter\", transmission = [1, 1, 1] }, { type = \"constant-colour\", colour = [0, 0, 1] }] }",
        0.5 * backdrop() + 0.5 * Colour::Z,
    );
}

/// A glowing cloud (Dr TIM's `SurfaceOfGlowingCloud`), a ball of radius 1 about (0, 0, 5) with
/// glow (0, 0.5, 1) and 1/e distance 4: the backdrop seen through its centre gains
/// glow × (1 − e^(−2/4)) on entering and nothing on leaving; a ray that ends on a constant-colour
/// ball inside it still gains the glow of the cloud's whole depth along it (Dr TIM's "cloud"
/// ignores other objects), and one that misses the cloud gains nothing.
#[test]
fn a_glowing_cloud_adds_glow_by_its_whole_depth() {
    let glow = Colour::new(0.0, 0.5, 1.0);
    let objects = "[[object]]\nname = \"cloud\"\nshadow_throwing = false\n\
        shape = { type = \"sphere\", centre = [0, 0, 5], radius = 1 }\n\
        surface = { type = \"glowing-cloud\", glow_colour = [0, 0.5, 1], one_over_e_distance = 4 }\n\
        [[object]]\nname = \"core\"\n\
        shape = { type = \"sphere\", centre = [0, 0.5, 5], radius = 0.2 }\n\
        surface = { type = \"constant-colour\", colour = [0.3, 0.3, 0.3] }\n";
    // Through the core's centre, the cloud's chord is 2 √(1 − sin²) at the line's distance
    // from the cloud's centre.
    let to_core = DVec3::new(0.0, 0.5, 5.0);
    let distance = 5.0 * to_core.normalize().cross(DVec3::Z).length();
    let chord = 2.0 * (1.0 - distance * distance).sqrt();
    let colours = seen(objects, &[DVec3::Z, to_core, DVec3::new(0.0, -2.0, 5.0)]);
    assert_close(colours[0], backdrop() + glow * (1.0 - (-0.5f64).exp()));
    assert_close(
        colours[1],
        Colour::splat(0.3) + glow * (1.0 - (-chord / 4.0).exp()),
    );
    assert_close(colours[2], backdrop());
}

/// A ray trajectory along +z goes straight through a semi-transparent red pane (the
/// transparent part, the only one that sends it on), a tinted slab, a glowing cloud and a
/// two-sided pane whose outside is a colour filter, and ends on the backdrop: every point on
/// the z axis, at the surfaces' z in order.
#[test]
fn trajectories_go_straight_through_the_see_through_appearances() {
    let objects = format!(
        "{SLAB}\
         [[object]]\nname = \"semi\"\n\
         shape = {{ type = \"parallelogram\", corner = [-1, -1, 2], span_u = [2, 0, 0], span_v = [0, 2, 0] }}\n\
         surface = {{ type = \"semi-transparent\", surface = {{ type = \"shiny\", colour = [1, 0, 0] }} }}\n\
         [[object]]\nname = \"cloud\"\n\
         shape = {{ type = \"sphere\", centre = [0, 0, 7], radius = 0.5 }}\n\
         surface = {{ type = \"glowing-cloud\", glow_colour = [1, 1, 1], one_over_e_distance = 1 }}\n\
         [[object]]\nname = \"two-sided\"\n\
         shape = {{ type = \"disc\", centre = [0, 0, 9], normal = [0, 0, -1], radius = 1 }}\n\
         surface = {{ type = \"two-sided\", outside = {{ type = \"colour-filter\", transmission = [1, 0, 0] }} }}\n\
         [[ray_trajectory]]\nstart = [0, 0, 0]\ndirection = [0, 0, 1]\n"
    );
    let [r, g, b] = BACKDROP;
    let text = format!(
        "studio = \"none\"\n[[object]]\nname = \"backdrop\"\n\
         shape = {{ type = \"plane\", point = [0, 0, 10], normal = [0, 0, -1] }}\n\
         surface = {{ type = \"constant-colour\", colour = [{r}, {g}, {b}] }}\n{objects}"
    );
    let d = file::parse(&text, "trajectory.toml").unwrap_or_else(|e| panic!("{e}\n{text}"));
    let traced = trajectories::trace(&Device::new("").unwrap(), &d).unwrap();
    let ray = &traced[0];
    assert_eq!(ray.end, End::Absorbed);
    let z: Vec<f64> = ray.points.iter().map(|p| p.position.z).collect();
    let expected = [0.0, 2.0, 4.65, 5.35, 6.5, 7.5, 9.0, 10.0];
    assert_eq!(z.len(), expected.len(), "{z:?}");
    for (p, e) in ray.points.iter().zip(expected) {
        assert!(
            (p.position - DVec3::new(0.0, 0.0, e)).length() < 1e-9,
            "{:?}",
            ray.points
        );
    }
}
