//! Gradient-index volumes (`type = "gradient-index-volume"`) in whole scenes, against
//! constructions done another way:
//!
//! * a Luneburg profile filling its own sphere renders as the paper's closed-form Luneburg lens
//!   (Eqs 5–6), placed by a transform and in an array;
//! * a constant index renders as a `refractive` block of the same index (Snell's law at each
//!   face, total internal reflection inside), a rotated cuboid;
//! * a profile in layers renders as nested `refractive` spheres;
//! * a trajectory through a gradient-index rod draws its curved path, on the sinusoid the
//!   closed form gives;
//! * refusals, located at their line.

mod common;

use glam::DVec3;
use tempfile::TempDir;
use timbre::trajectories;

use common::cli::assert_refused_at_line;
use common::images::{differing, parse, render_text};

fn scene(object: &str) -> String {
    format!(
        "studio = \"lattice\"\n[render]\nwidth = 160\nheight = 120\nmax_trace_level = 200\n[camera]\nposition = [0.3, 0.4, 0]\nview_direction = [0, 0, 1]\nhorizontal_view_angle_deg = 40\n[[object]]\nname = \"volume\"\nshadow_throwing = false\n{object}"
    )
}

/// A Luneburg profile in a sphere of its own radius is §3's Luneburg lens: the integrated
/// volume renders as the closed-form map, here on a sphere moved and scaled by a transform,
/// with the profile's centre and radius moving with it, and on an array of two copies.
#[test]
fn a_luneburg_profile_in_its_sphere_renders_as_the_closed_form_lens() {
    let place = "transform = { scale = 0.8, translate = [0.2, -0.1, 5] }\narray = { vectors = [[0.9, 0.3, 1]], counts = [2] }\nshape = { type = \"sphere\", centre = [0, 0, 0], radius = 1 }\n";
    let lens = render_text(&scene(&format!(
        "{place}surface = {{ type = \"luneburg-lens\", transmission_coefficient = 0.9 }}\n"
    )));
    let volume = render_text(&scene(&format!(
        "{place}surface = {{ type = \"gradient-index-volume\", transmission_coefficient = 0.9, index = {{ type = \"radial\", centre = [0, 0, 0], profile = \"luneburg\" }} }}\n"
    )));
    let plain = render_text(&scene(&format!(
        "{place}surface = {{ type = \"transparent\", transmission_coefficient = 0.9 }}\n"
    )));
    // Rounding can flip a pixel whose ray passes a lattice cylinder's edge.
    assert!(
        differing(&lens, &volume) <= 3,
        "{}",
        differing(&lens, &volume)
    );
    assert!(differing(&lens, &plain) > 1000);
}

/// A constant index is a block of glass: a rotated cuboid of n = 1.5 renders as a
/// `refractive` one (Snell's law at every face, total internal reflection inside), given the
/// same transmission.
#[test]
fn a_constant_index_renders_as_a_refractive_block() {
    let place = "shape = { type = \"cuboid\", centre = [0, 0, 0], size = [1.5, 1, 1] }\ntransform = { rotate = { axis = [1, 1, 0], angle_deg = 30 }, translate = [0, 0, 5] }\n";
    let glass = render_text(&scene(&format!(
        "{place}surface = {{ type = \"refractive\", index_ratio = 1.5, transmission_coefficient = 1 }}\n"
    )));
    let volume = render_text(&scene(&format!(
        "{place}surface = {{ type = \"gradient-index-volume\", transmission_coefficient = 1, index = {{ type = \"constant\", n = 1.5 }} }}\n"
    )));
    let air = render_text(&scene(&format!(
        "{place}surface = {{ type = \"transparent\", transmission_coefficient = 1 }}\n"
    )));
    assert!(
        differing(&glass, &volume) <= 3,
        "{}",
        differing(&glass, &volume)
    );
    assert!(differing(&glass, &air) > 1000);
}

/// Layers (Dr TIM's voxellated refractor on concentric spheres, as its layered Luneburg
/// lens): a Luneburg profile in four spherical layers of separation 0.25 renders as four
/// nested `refractive` spheres whose index ratios are those of the layers' middles,
/// n_k = √(2 − ((k + ½)/4)²), across each sphere.
#[test]
fn a_profile_in_layers_renders_as_nested_refractive_spheres() {
    let n = |k: f64| (2.0 - ((k + 0.5) * 0.25f64).powi(2)).sqrt();
    // The outermost sphere is the scene's own object, the three inside it follow.
    let mut spheres = format!(
        "shape = {{ type = \"sphere\", centre = [0, 0, 5], radius = 1 }}\nsurface = {{ type = \"refractive\", index_ratio = {:?}, transmission_coefficient = 1 }}\n",
        n(3.0)
    );
    for (k, radius) in [(2.0, 0.75), (1.0, 0.5), (0.0, 0.25)] {
        let outside = n(k + 1.0);
        spheres += &format!(
            "[[object]]\nname = \"sphere {k}\"\nshadow_throwing = false\nshape = {{ type = \"sphere\", centre = [0, 0, 5], radius = {radius} }}\nsurface = {{ type = \"refractive\", index_ratio = {:?}, transmission_coefficient = 1 }}\n",
            n(k) / outside
        );
    }
    let object = "shape = { type = \"sphere\", centre = [0, 0, 5], radius = 1 }\n";
    let layers = render_text(&scene(&format!(
        "{object}surface = {{ type = \"gradient-index-volume\", transmission_coefficient = 1, index = {{ type = \"radial\", centre = [0, 0, 5], profile = \"luneburg\", layer_separation = 0.25 }} }}\n"
    )));
    let smooth = render_text(&scene(&format!(
        "{object}surface = {{ type = \"gradient-index-volume\", transmission_coefficient = 1, index = {{ type = \"radial\", centre = [0, 0, 5], profile = \"luneburg\" }} }}\n"
    )));
    let nested = render_text(&scene(&spheres));
    assert!(
        differing(&layers, &nested) <= 3,
        "{}",
        differing(&layers, &nested)
    );
    assert!(differing(&layers, &smooth) > 500);
}

/// A trajectory along a gradient-index rod (n² = 2 − ρ²/R², ρ from the axis y) draws its
/// curved path: in τ (dτ = ds/n) the distance from the axis oscillates as x = x₀ cos(τ/R), the
/// height grows as y = p_y τ, so every drawn point satisfies x = x₀ cos(y/(R p_y)); it leaves
/// the top of the rod parallel to the axis again only where cos = ±1.
#[test]
fn a_trajectory_through_a_rod_draws_its_sinusoid() {
    let text = "studio = \"none\"\n[[object]]\nname = \"rod\"\nshape = { type = \"cylinder\", start = [0, 0, 0], end = [0, 3, 0], radius = 0.5 }\nsurface = { type = \"gradient-index-volume\", index = { type = \"cylindrical\", point = [0, 0, 0], axis = [0, 1, 0], radius = 0.6, profile = \"luneburg\" } }\n[[ray_trajectory]]\nname = \"ray\"\nstart = [0.3, -1, 0]\ndirection = [0, 1, 0]\n";
    let description = parse(text);
    let traced = trajectories::trace(common::rays::device(), &description).unwrap();
    let points: Vec<DVec3> = traced[0].points.iter().map(|p| p.position).collect();
    // Enters the bottom at x₀ = 0.3 along the axis: n(x₀)² = 2 − 0.25 and p = n(x₀) ŷ.
    let (x0, r) = (0.3f64, 0.6f64);
    let py = (2.0 - (x0 / r) * (x0 / r)).sqrt();
    let inside: Vec<&DVec3> = points
        .iter()
        .filter(|p| p.y > 1e-9 && p.y < 3.0 - 1e-9)
        .collect();
    assert!(inside.len() > 5, "{points:?}");
    for p in inside {
        let x = x0 * (p.y / (r * py)).cos();
        assert!(
            (p.x - x).abs() < 1e-9 && p.z.abs() < 1e-12,
            "{p} vs x = {x}"
        );
    }
    let top = points
        .iter()
        .find(|p| (p.y - 3.0).abs() < 1e-9)
        .expect("leaves the top");
    assert!((top.x - x0 * (3.0 / (r * py)).cos()).abs() < 1e-9, "{top}");
}

/// Bad volumes are refused at their line: a profile and a table both, neither, a table that
/// does not start at 0, an unknown index type or profile, a zero axis, a non-uniform scaling of
/// a profile, and a shape that bounds no convex solid.
#[test]
fn bad_gradient_index_volumes_are_refused() {
    let dir = TempDir::new().unwrap();
    let object = |surface: &str, extra: &str| {
        format!(
            "studio = \"none\"\n[[object]]\nname = \"v\"\nshape = {{ type = \"sphere\", centre = [0, 0, 5], radius = 1 }}\n{extra}surface = {surface}\n"
        )
    };
    for (surface, extra, needle) in [
        (
            r#"{ type = "gradient-index-volume", index = { type = "radial", centre = [0, 0, 5], profile = "luneburg", rho = [0, 1], n = [1, 1] } }"#,
            "",
            "not both",
        ),
        (
            r#"{ type = "gradient-index-volume", index = { type = "radial", centre = [0, 0, 5] } }"#,
            "",
            "give the index's `profile`",
        ),
        (
            r#"{ type = "gradient-index-volume", index = { type = "planar", point = [0, 0, 5], normal = [0, 1, 0], rho = [0.1, 1], n = [1, 1] } }"#,
            "",
            "rho must run from 0",
        ),
        (
            r#"{ type = "gradient-index-volume", index = { type = "spherical", centre = [0, 0, 5] } }"#,
            "",
            "unknown variant `spherical`",
        ),
        (
            r#"{ type = "gradient-index-volume", index = { type = "radial", centre = [0, 0, 0], profile = "eaton" } }"#,
            "",
            "unknown variant `eaton`",
        ),
        (
            r#"{ type = "gradient-index-volume", index = { type = "cylindrical", point = [0, 0, 0], axis = [0, 0, 0], profile = "luneburg" } }"#,
            "",
            "zero vector",
        ),
        (
            r#"{ type = "gradient-index-volume", index = { type = "radial", centre = [0, 0, 0], profile = "luneburg" } }"#,
            "transform = { scale = [1, 2, 1] }\n",
            "cannot be scaled non-uniformly",
        ),
        (
            r#"{ type = "gradient-index-volume" }"#,
            "",
            "missing field `index`",
        ),
        (
            r#"{ type = "gradient-index-volume", index = { type = "radial", centre = [0, 0, 5], profile = "luneburg", layer_separation = 1e-9 } }"#,
            "",
            "is below 1e-4",
        ),
    ] {
        // The transform, where given, is at line 5; else the surface is.
        assert_refused_at_line(dir.path(), &object(surface, extra), &[needle], 5);
    }
    assert_refused_at_line(
        dir.path(),
        "studio = \"none\"\n[[object]]\nname = \"sheet\"\nshape = { type = \"disc\", centre = [0, 0, 5], normal = [0, 0, 1], radius = 1 }\nsurface = { type = \"gradient-index-volume\", index = { type = \"constant\", n = 1.5 } }\n",
        &["needs a convex solid shape"],
        5,
    );
}
