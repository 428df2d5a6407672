//! The `clas` device (Dr TIM's `EditableCLAs`), traced: confocal lenslet arrays are an array of
//! small telescopes, and the baffles between the telescopes absorb the light that crosses from
//! one into a neighbour.
//!
//! The facts checked, derived here and not taken from timbre: a ray that meets lenslet 1 at r
//! from its centre with slope t (its direction's part across the arrays over its part along
//! them) leaves lenslet 1 with the slope t − r/f₁ (an ideal thin lens sends the ray towards the
//! point where the parallel ray through its centre meets the focal plane), meets lenslet 2 of
//! the same telescope at r + (f₁ + f₂)(t − r/f₁) from its centre, and leaves it with the slope
//! t − r/f₁ − (r + (f₁ + f₂)(t − r/f₁))/f₂ = −(f₁/f₂) t = t/η, η = −f₂/f₁ (the gCLAs' Eq 39 with
//! no offset), whatever r. With f₁ = f₂ = f it meets lenslet 2 at 2ft − r, so it stays in its
//! telescope (of width p) if |2ft − r| ≤ p/2: of the rays with slope t spread evenly across a
//! lenslet, the fraction 1 − 2f|t|/p does.

mod common;

use glam::DVec3;
use timbre::trajectories::{self, End};

/// A ray's trace: the names of the objects it met (without the device's name) and where, how
/// it ended, where it last met a surface, and its final direction.
struct Traced {
    met: Vec<String>,
    at: Vec<DVec3>,
    end: End,
    last: DVec3,
    direction: DVec3,
}

/// The ray from `start` along `direction` through the device `d` with the keys `keys` (inside
/// `lenses = { type = "clas", ... }`).
fn trace(keys: &str, start: DVec3, direction: DVec3) -> Traced {
    let v = |p: DVec3| format!("[{:?}, {:?}, {:?}]", p.x, p.y, p.z);
    let text = format!(
        "studio = \"none\"\n[[device]]\nname = \"d\"\nlenses = {{ type = \"clas\"{keys} }}\n\n\
         [[ray_trajectory]]\nstart = {}\ndirection = {}\nmax_interactions = 10\n",
        v(start),
        v(direction)
    );
    let description = common::images::parse(&text);
    let mut traced =
        trajectories::trace(common::rays::device(), &description).expect("the ray traced");
    let t = traced.remove(0);
    let hits: Vec<_> = t.points.iter().filter(|p| p.object.is_some()).collect();
    Traced {
        met: hits
            .iter()
            .map(|p| {
                let name = &description.objects[p.object.unwrap()].name;
                name.strip_prefix("d/").unwrap().to_string()
            })
            .collect(),
        at: hits.iter().map(|p| p.position).collect(),
        end: t.end,
        last: hits.last().map_or(t.points[0].position, |p| p.position),
        direction: t.direction,
    }
}

/// The ray that meets the plane z = `z` at `at` with slope `t` = (dx/d(−z), dy/d(−z)),
/// travelling towards −z: its start, 1 above, and direction.
fn ray_through(at: DVec3, t: (f64, f64)) -> (DVec3, DVec3) {
    let d = DVec3::new(t.0, t.1, -1.0);
    (at - d, d.normalize())
}

/// The slope of a direction travelling towards −z.
fn slope(d: DVec3) -> (f64, f64) {
    assert!(d.z < 0.0, "{d} does not travel towards −z");
    (d.x / -d.z, d.y / -d.z)
}

#[track_caller]
fn slopes_close(got: (f64, f64), expected: (f64, f64)) {
    assert!(
        (got.0 - expected.0).abs() < 1e-9 && (got.1 - expected.1).abs() < 1e-9,
        "slope {got:?}, expected {expected:?}"
    );
}

/// Dr TIM's default CLAs (centre (0, 0, 5), normal +z, f₁ = f₂ = 0.1, periods 0.1, baffles):
/// rays through the centre along the normal, either way, pass both arrays undeviated; a ray
/// parallel to the normal through the central lenslet passes through the centre (the central
/// telescope's common focus) and leaves parallel to the normal, mirrored through it.
#[test]
fn rays_through_the_default_devices_centre_pass() {
    let centre = DVec3::new(0.0, 0.0, 5.0);
    for d in [DVec3::NEG_Z, DVec3::Z] {
        let r = trace("", centre - 3.0 * d, d);
        let expected = if d.z < 0.0 {
            ["lenslet array 1", "lenslet array 2"]
        } else {
            ["lenslet array 2", "lenslet array 1"]
        };
        assert_eq!(r.met, expected);
        assert_eq!(r.end, End::Escaped);
        assert!((r.direction - d).length() < 1e-12, "{}", r.direction);
    }
    let r = trace("", DVec3::new(0.03, -0.02, 6.0), DVec3::NEG_Z);
    assert_eq!(r.met, ["lenslet array 1", "lenslet array 2"]);
    assert_eq!(r.end, End::Escaped);
    assert!(
        (r.at[1] - DVec3::new(-0.03, 0.02, 4.9)).length() < 1e-9,
        "{}",
        r.at[1]
    );
    assert!((0.5 * (r.at[0] + r.at[1]) - centre).length() < 1e-9);
    assert!(
        (r.direction - DVec3::NEG_Z).length() < 1e-9,
        "{}",
        r.direction
    );
}

/// Through one telescope the slope is divided by η = −f₂/f₁, wherever the ray meets lenslet 1:
/// at a lenslet centre (0.1, 0.2) or off it, for f₁ = f₂ (η = −1, the direction mirrored), a
/// Keplerian f₂ = f₁/2 (η = −1/2) and a Galilean f₂ = −f₁/2 (η = 1/2, array 2 between array
/// 1 and the common focal plane).
#[test]
fn a_telescope_divides_the_slope_by_eta() {
    let t = (0.1, -0.05);
    for (f2, eta) in [(0.1, -1.0), (0.05, -0.5), (-0.05, 0.5)] {
        let keys = format!(", f2 = {f2:?}");
        for offset in [DVec3::ZERO, DVec3::new(0.02, 0.015, 0.0)] {
            let at = DVec3::new(0.1, 0.2, 5.1) + offset;
            let (start, d) = ray_through(at, t);
            let r = trace(&keys, start, d);
            assert_eq!(r.met, ["lenslet array 1", "lenslet array 2"], "f2 = {f2}");
            assert_eq!(r.end, End::Escaped);
            // Lenslet 2 met where the slope t − r/f₁ takes the ray from lenslet 1.
            let t1 = (t.0 - offset.x / 0.1, t.1 - offset.y / 0.1);
            let depth = 0.1 + f2;
            let expected = at + depth * DVec3::new(t1.0, t1.1, -1.0);
            assert!((r.last - expected).length() < 1e-9, "{} {expected}", r.last);
            slopes_close(slope(r.direction), (t.0 / eta, t.1 / eta));
        }
    }
}

/// A ray that crosses from its telescope into the neighbour's meets the baffle between them and
/// is absorbed there; without baffles it goes on through the neighbour's lenslet 2, which sends
/// it off in a direction no telescope law gives (here the slope 0.4, not −0.6).
#[test]
fn a_ray_into_the_neighbouring_telescope_is_absorbed_by_the_baffle() {
    // Lenslet 1 met 0.04 from its centre with slope 0.6: inside the slope is 0.6 − 0.4 = 0.2,
    // so it reaches x = 0.05 (the baffle plane between the lenslets at 0 and 0.1) at depth
    // 0.05, z = 5.05, and would meet lenslet array 2 at x = 0.08.
    let (start, d) = ray_through(DVec3::new(0.04, 0.0, 5.1), (0.6, 0.0));
    let r = trace("", start, d);
    // The baffle planes x = −0.45, …, 0.45: x = 0.05 is the sixth.
    assert_eq!(r.met, ["lenslet array 1", "baffle u 6"]);
    assert_eq!(r.end, End::Absorbed);
    assert!(
        (r.last - DVec3::new(0.05, 0.0, 5.05)).length() < 1e-9,
        "{}",
        r.last
    );
    let r = trace(", show_baffles = false", start, d);
    assert_eq!(r.met, ["lenslet array 1", "lenslet array 2"]);
    assert_eq!(r.end, End::Escaped);
    assert!((r.last - DVec3::new(0.08, 0.0, 4.9)).length() < 1e-9);
    // Lenslet 2 centred on x = 0.1: 0.2 − (0.08 − 0.1)/0.1 = 0.4.
    slopes_close(slope(r.direction), (0.4, 0.0));
    // Across v likewise, at the baffle y = −0.05 (the fifth).
    let (start, d) = ray_through(DVec3::new(0.3, -0.04, 5.1), (0.0, -0.6));
    let r = trace("", start, d);
    assert_eq!(r.met, ["lenslet array 1", "baffle v 5"]);
    assert_eq!(r.end, End::Absorbed);
}

/// A white plane seen through Dr TIM's default CLAs (f = 0.1, p = 0.1) by an orthographic
/// camera whose rays have the slope t = 0.2 across u and none across v: without baffles every
/// ray gets through to the white plane, with them only those that stay in their telescope,
/// whose lenslet-1 offset r (from the lenslet centre, across u) has |2ft − r| = |0.04 − r| ≤
/// 0.05, the fraction 1 − 2ft/p = 0.6 of them. The rest of the picture is the baffles' black.
#[test]
fn the_baffles_remove_the_light_that_crosses_into_neighbouring_telescopes() {
    let (width, height) = (141, 101);
    let picture = |baffles: bool| {
        // Pixel centres 0.005 apart on the camera's plane, perpendicular to (0.2, 0, −1); the
        // rays meet lenslet array 1 (z = 5.1) about (0, 0.0012), within ±0.36 across u and
        // ±0.25 across v (y offset so that no ray runs along a baffle plane).
        common::images::render_text(&format!(
            r#"studio = "none"
[render]
width = {width}
height = {height}
spp = 1

[camera]
type = "orthographic"
position = [-0.98, 0.0012, 10]
view_direction = [0.2, 0, -1]
up = [0, 1, 0]
view_width = 0.7

[[object]]
name = "white"
shape = {{ type = "plane", point = [0, 0, 0], normal = [0, 0, 1] }}
surface = {{ type = "constant-colour", colour = [1, 1, 1] }}

[[device]]
name = "d"
lenses = {{ type = "clas", show_baffles = {baffles} }}
"#
        ))
    };
    // Which columns are white: a column's rays all have the same x where they meet lenslet
    // array 1, so they are all white or all black.
    let white_columns = |baffles: bool| {
        let image = picture(baffles);
        (0..width)
            .filter(|&x| {
                let column: Vec<DVec3> = (0..height).map(|y| image.pixel(x, y)).collect();
                for c in &column {
                    assert!(
                        (*c - DVec3::ONE).length() < 1e-6 || c.length() < 1e-6,
                        "neither white nor black: {c}"
                    );
                }
                let white = (column[0] - DVec3::ONE).length() < 1e-6;
                assert!(
                    column
                        .iter()
                        .all(|c| ((*c - DVec3::ONE).length() < 1e-6) == white)
                );
                white
            })
            .count()
    };
    assert_eq!(white_columns(false), width as usize);
    // The columns' rays from the plane through the camera's position, 0.005 apart along its
    // right direction (1, 0, 0.2)/√1.04 up to sign, meet z = 5.1 at x = ±√1.04 · 0.005 (k − 70):
    // a symmetric set, so the count does not depend on which way the columns run.
    let expected = (0..width)
        .filter(|&k| {
            let x = 1.04f64.sqrt() * 0.005 * (k as f64 - 70.0);
            let r = x - 0.1 * (x / 0.1).round();
            (0.04 - r).abs() <= 0.05
        })
        .count();
    assert!(
        (expected as f64 / width as f64 - 0.6).abs() < 0.05,
        "{expected}"
    );
    assert_eq!(white_columns(true), expected);
}

/// Dr TIM's default object by its type alone: its parts by name, the arrays where
/// `EditableCLAs(description, parent, studio)` puts them (at 5 ± 0.1 along z, the unit square)
/// and the baffles in the planes x, y = 0.05 + 0.1k between them.
#[test]
fn the_device_named_by_its_type_alone_is_dr_tims_default() {
    let d = common::images::parse(
        "studio = \"none\"\n[[device]]\nname = \"d\"\nlenses = { type = \"clas\" }\n",
    );
    let names: Vec<&str> = d.objects.iter().map(|o| o.name.as_str()).collect();
    let mut expected = vec!["d/lenslet array 1".to_string(), "d/lenslet array 2".into()];
    for family in ["u", "v"] {
        expected.extend((1..=10).map(|i| format!("d/baffle {family} {i}")));
    }
    assert_eq!(names, expected);
    for (o, z) in d.objects.iter().zip([5.1, 4.9]) {
        let (lo, hi) = o.shape.bounds().unwrap();
        assert!((lo - DVec3::new(-0.5, -0.5, z)).length() < 1e-12, "{lo}");
        assert!((hi - DVec3::new(0.5, 0.5, z)).length() < 1e-12, "{hi}");
    }
    for (i, o) in d.objects[2..12].iter().enumerate() {
        let (lo, hi) = o.shape.bounds().unwrap();
        let x = -0.45 + 0.1 * i as f64;
        assert!(
            (lo - DVec3::new(x, -0.5, 4.9001)).length() < 1e-12,
            "{}: {lo}",
            o.name
        );
        assert!(
            (hi - DVec3::new(x, 0.5, 5.0999)).length() < 1e-12,
            "{}: {hi}",
            o.name
        );
        assert!(!o.shadow_throwing);
    }
}

/// Keys that cannot make CLAs are refused at the device's table, naming the key, with the
/// file and line.
#[test]
fn impossible_clas_are_refused_with_file_and_line() {
    let dir = tempfile::tempdir().unwrap();
    for (keys, needles) in [
        (
            "span_vector_u = [0, 0, 3]",
            &["span_vector_u", "no part perpendicular"][..],
        ),
        ("f2 = -0.1", &["show_baffles", "no room for baffles"][..]),
        ("period_u = 0", &["expected a positive number"][..]),
        ("f1 = 0", &["expected a non-zero number"][..]),
        (
            "lenslet_array_type = \"lens-hologram\", simulate_diffractive_blur = true",
            &["simulate_diffractive_blur", "do not simulate diffraction"][..],
        ),
        (
            "lenslet_array_type = \"shiny\"",
            &["unknown variant `shiny`", "semitransparent-plane"][..],
        ),
    ] {
        let text = format!(
            "studio = \"none\"\n\n[[device]]\nname = \"c\"\nlenses = {{ type = \"clas\", {keys} }}\n"
        );
        let path = common::cli::write(dir.path(), "bad.toml", text);
        let run = common::cli::timbre(dir.path(), &["check", common::cli::path_str(&path)]);
        run.assert_bad_input(needles);
        assert_eq!(common::cli::location(&run.stderr, &path).0, 5, "{keys}");
    }
}
