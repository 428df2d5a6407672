//! Phase holograms of lenslet arrays, lenticular arrays, Alvarez–Lohmann lens parts and
//! cylindrical-lens spirals (issue 37) as scene files give them: `timbre check` refuses bad
//! values (exit 2, one line, at the phase's table), and the research scene
//! `scenes/research/SpiralLensVisualiser.toml` (Dr TIM's spiral-lens visualiser) sends rays
//! where a lens of Dr TIM's combined focal length f/(bδ) would, traced by `timbre trace`.

mod common;

use std::f64::consts::TAU;
use std::path::Path;

use glam::DVec3;
use tempfile::TempDir;

use common::cli::{path_str, timbre, write};

/// A scene with one disc whose surface is a phase hologram of `phase` (the inside of the
/// `phase = { … }` table), the surface table on line 4, column 11.
fn hologram_scene(phase: &str) -> String {
    format!(
        "[[object]]\nname = \"hologram\"\n\
         shape = {{ type = \"disc\", centre = [0, 0, 5], normal = [0, 0, -1], radius = 1 }}\n\
         surface = {{ type = \"phase-hologram\", phase = {{ {phase} }} }}\n"
    )
}

#[test]
fn bad_phase_values_are_refused_at_the_phase_hologram() {
    let dir = TempDir::new().unwrap();
    for (phase, message) in [
        (
            r#"type = "rectangular-lenslet-array", period = [0.1, 0]"#,
            "expected a positive number of at most 1e15, got 0",
        ),
        (
            r#"type = "rectangular-lenslet-array", focal_length = 0"#,
            "expected a non-zero number, got 0",
        ),
        (
            r#"type = "sparse-rectangular-lenslet-array", every = [3, 0]"#,
            "expected a whole number from 1 to 4294967295, got 0",
        ),
        (
            r#"type = "radial-lenticular-array", number_of_lenses = 2.5"#,
            "expected a whole number from 1 to 4294967295, got 2.5",
        ),
        (
            r#"type = "linear-power-lenticular-array", period = -1"#,
            "expected a positive number of at most 1e15, got -1",
        ),
        (
            r#"type = "crossed-linear-power-lenticular-arrays", alvarez_focusing = 1"#,
            "expected a boolean, got 1",
        ),
        (
            r#"type = "lohmann-lens-part", centre = [0, 0]"#,
            "missing field `power_per_offset`",
        ),
        (
            r#"type = "lohmann-cylindrical-lens-part", power_per_offset = 1, u_angle_deg = "x""#,
            "expected a number, got the text \"x\"",
        ),
        (
            r#"type = "rectangular-alvarez-lens-part-array", power_per_offset = 1, period = [0.1]"#,
            "expected an array of 2 values, got 1 value",
        ),
        (
            r#"type = "cylindrical-lens-spiral", spiral = "fermat", focal_length = 1, b = 1"#,
            "unknown variant `fermat`, expected one of `archimedean`, `logarithmic`, `hyperbolic`",
        ),
        (
            r#"type = "cylindrical-lens-spiral", spiral = "logarithmic", focal_length = 1, b = 0"#,
            "expected a non-zero number, got 0",
        ),
        (
            r#"type = "cylindrical-lens-spiral", spiral = "hyperbolic", focal_length = 1, b = 0.1, alvarez_winding_focusing = true"#,
            "object 'hologram': alvarez_winding_focusing = true: a hyperbolic spiral has no winding focusing",
        ),
        (
            r#"type = "logarithmic-cylindrical-lens-spiral", focal_length = 1, a = -1, b = 1"#,
            "expected a positive number of at most 1e15, got -1",
        ),
    ] {
        let path = write(&dir, "bad.toml", hologram_scene(phase));
        let run = timbre(dir.path(), &["check", path_str(&path)]);
        run.assert_bad_input(&[&format!("{}:4:11: ", path.display()), message]);
        assert_eq!(run.stderr.lines().count(), 1, "{}", run.stderr);
        for rust in ["u32", "f64", "NonZero", "Positive", "struct", "Some("] {
            assert!(!run.stderr.contains(rust), "{}", run.stderr);
        }
    }
}

/// The last direction and the points of one ray of `timbre trace --json`.
struct Traced {
    direction: DVec3,
    objects: Vec<String>,
    points: Vec<DVec3>,
}

fn vector(value: &serde_json::Value) -> DVec3 {
    let v: Vec<f64> = value
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    DVec3::from_slice(&v)
}

/// The research scene with rays along +z from `starts` (z = −1) added, traced.
fn trace_research_scene(starts: &[DVec3]) -> Vec<Traced> {
    let scene =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/research/SpiralLensVisualiser.toml");
    let mut text = std::fs::read_to_string(&scene).unwrap();
    for (k, s) in starts.iter().enumerate() {
        text.push_str(&format!(
            "\n[[ray_trajectory]]\nname = \"ray {k}\"\nstart = [{}, {}, {}]\ndirection = [0, 0, 1]\nmax_interactions = 10\n",
            s.x, s.y, s.z
        ));
    }
    let dir = TempDir::new().unwrap();
    let path = write(&dir, "scene.toml", text);
    timbre(dir.path(), &["check", path_str(&path)]).assert_success();
    let run = timbre(dir.path(), &["trace", "--json", path_str(&path)]);
    run.assert_success();
    let json: serde_json::Value = serde_json::from_str(&run.stdout).unwrap();
    json["rays"]
        .as_array()
        .unwrap()
        .iter()
        .map(|ray| {
            let points = ray["points"].as_array().unwrap();
            Traced {
                direction: vector(&ray["direction"]),
                objects: points
                    .iter()
                    .map(|p| p["object"].as_str().unwrap_or("").to_string())
                    .collect(),
                points: points.iter().map(|p| vector(&p["position"])).collect(),
            }
        })
        .collect()
}

/// Dr TIM's spiral lens with `SpiralLensVisualiser`'s defaults: logarithmic spirals
/// r = exp(b(θ + δ + 2πn)) with b = 0.01, focal lengths f = 0.1 (δ = 0) and −f (δ = 30°), on
/// two discs 1e-8 apart at z = 0. A ray along the axis direction through a point of spiral 1's
/// centre line (ρ = exp(b(θ + 2πn))) gets no kick from spiral 1 there (the kick of a
/// cylindrical lens vanishes on its axis), and from spiral 2 that of a cylindrical lens of focal
/// length −f at radial distance d = ρ − r₂ from its centre line r₂(θ) = ρ e^{bδ}: the gradient
/// of d²/(2f), (d/f)(r̂ − (dr₂/dθ)/ρ θ̂) = (d/f)(r̂ − b e^{bδ} θ̂). So the ray leaves with the
/// radial slope −ρ(e^{bδ} − 1)/f and heads for the axis as a lens of focal length
/// f/(e^{bδ} − 1) would send it: Dr TIM's combined focal length F = f/(bδ) (its `calculateF`)
/// to within bδ/2 (0.26 %), for every winding and angle.
#[test]
fn the_spiral_lens_visualiser_scene_focuses_like_a_lens_of_focal_length_f_over_b_delta() {
    let (f, b, delta) = (0.1, 0.01, 30f64.to_radians());
    let big_f = f / (b * delta);
    let cases: Vec<(f64, f64)> = vec![(0.0, -5.0), (1.745, -5.0), (-2.356, -12.0), (3.0, -25.0)];
    let starts: Vec<DVec3> = cases
        .iter()
        .map(|&(theta, n)| {
            let rho = (b * (theta + TAU * n)).exp();
            DVec3::new(rho * theta.cos(), rho * theta.sin(), -1.0)
        })
        .collect();
    let rays = trace_research_scene(&starts);
    assert_eq!(rays.len(), cases.len());
    for (ray, ((theta, _), start)) in rays.iter().zip(cases.iter().zip(&starts)) {
        assert_eq!(
            ray.objects[1..3],
            ["spiral-lens 1".to_string(), "spiral-lens 2".to_string()],
            "{:?}",
            ray.objects
        );
        // It crossed both discs where it started, along +z.
        assert!((ray.points[2] - DVec3::new(start.x, start.y, 1e-8)).length() < 1e-12);
        let rho = start.truncate().length();
        let (r_hat, theta_hat) = (
            DVec3::new(theta.cos(), theta.sin(), 0.0),
            DVec3::new(-theta.sin(), theta.cos(), 0.0),
        );
        let d = rho - rho * (b * delta).exp();
        let kick = d / f * (r_hat - b * (b * delta).exp() * theta_hat);
        let expected = kick + (1.0 - kick.length_squared()).sqrt() * DVec3::Z;
        // The direction it left the second disc in (and the one it arrived in at the head).
        let leaving = (ray.points[3] - ray.points[2]).normalize();
        assert!((leaving - expected).length() < 1e-9, "{leaving} {expected}");
        assert!((ray.direction - expected).length() < 1e-12);
        // Where its radial distance would reach 0 going straight on.
        let z = -rho * leaving.z / leaving.dot(r_hat);
        assert!(
            (z / big_f - 1.0).abs() < b * delta,
            "θ = {theta}: {z} against {big_f}"
        );
    }
}
