//! `timbre render --denoise` and `timbre image denoise` (Intel Open Image Denoise): with the
//! `denoise` feature, the denoised picture is nearer a converged render than the noisy one, and
//! the render itself is kept as it would be without denoising; without it, a clear refusal.

mod common;

use tempfile::TempDir;

use common::cli::{timbre, write};

/// The studio through a finite aperture focused on the lattice's middle: noisy at few samples.
const FINITE_APERTURE: &str = r#"
studio = "lattice"
[camera]
type = "finite-aperture"
aperture_radius = 0.1
focus_distance = 8
"#;

#[cfg(feature = "denoise")]
mod with_oidn {
    use super::*;
    use std::path::Path;

    use exr::prelude::{FlatSamples, read_all_flat_layers_from_file};

    /// The named f32 channels of an OpenEXR file, in the order asked.
    fn channels(path: &Path, names: &[&str]) -> Vec<Vec<f32>> {
        let image = read_all_flat_layers_from_file(path).unwrap();
        let layer = &image.layer_data[0];
        names
            .iter()
            .map(|name| {
                let c = layer
                    .channel_data
                    .list
                    .iter()
                    .find(|c| c.name.to_string() == *name);
                match c.map(|c| &c.sample_data) {
                    Some(FlatSamples::F32(v)) => v.clone(),
                    _ => panic!("{}: no f32 channel {name}", path.display()),
                }
            })
            .collect()
    }

    /// Mean squared error of the RGB of two files.
    fn mse(a: &Path, b: &Path) -> f64 {
        let (a, b) = (channels(a, &["R", "G", "B"]), channels(b, &["R", "G", "B"]));
        let n = a[0].len() * 3;
        a.iter()
            .flatten()
            .zip(b.iter().flatten())
            .map(|(x, y)| (*x as f64 - *y as f64).powi(2))
            .sum::<f64>()
            / n as f64
    }

    fn render(dir: &Path, out: &str, spp: &str, more: &[&str]) {
        write(dir, "scene.toml", FINITE_APERTURE);
        let mut args = vec!["render", "scene.toml", "--width", "160", "--height", "120"];
        args.extend(["--spp", spp, "-q", "-o", out]);
        args.extend(more);
        timbre(dir, &args).assert_success();
    }

    #[test]
    fn the_denoised_picture_is_nearer_the_converged_one_and_the_render_is_kept() {
        let dir = TempDir::new().unwrap();
        let d = dir.path();
        render(d, "noisy.exr", "4", &["--denoise"]);
        render(d, "plain.exr", "4", &["--aov", "albedo,normal"]);
        render(d, "converged.exr", "256", &[]);
        // The render is what it is without --denoise (with the guides it was denoised by).
        let guides = [
            "R", "G", "B", "albedo.R", "albedo.G", "albedo.B", "normal.X", "normal.Y", "normal.Z",
        ];
        assert_eq!(
            channels(&d.join("noisy.exr"), &guides),
            channels(&d.join("plain.exr"), &guides)
        );
        // Denoising removes at least half the squared error of 4 samples against 256 (3 dB).
        let converged = d.join("converged.exr");
        let raw = mse(&d.join("noisy.exr"), &converged);
        let denoised = mse(&d.join("noisy.denoised.exr"), &converged);
        assert!(
            denoised < 0.5 * raw,
            "mean squared error: denoised {denoised}, raw {raw}"
        );
        // The same from the file, by `timbre image denoise`, into a file of its own.
        timbre(d, &["image", "denoise", "plain.exr", "-o", "again.exr"]).assert_success();
        assert_eq!(
            channels(&d.join("again.exr"), &["R", "G", "B"]),
            channels(&d.join("noisy.denoised.exr"), &["R", "G", "B"])
        );
    }

    #[test]
    fn denoising_needs_the_guides_and_a_file_of_its_own() {
        let dir = TempDir::new().unwrap();
        let d = dir.path();
        render(d, "bare.exr", "1", &[]);
        timbre(d, &["image", "denoise", "bare.exr"]).assert_bad_input(&[
            "bare.exr",
            "albedo",
            "--aov albedo,normal",
        ]);
        render(d, "guided.exr", "1", &["--aov", "albedo,normal"]);
        timbre(d, &["image", "denoise", "guided.exr", "-o", "guided.exr"])
            .assert_bad_input(&["never over the render"]);
        timbre(d, &["render", "-o", "out.png", "--denoise"]).assert_bad_input(&["OpenEXR"]);
    }
}

#[cfg(not(feature = "denoise"))]
#[test]
fn without_the_feature_denoising_is_refused_with_how_to_build_it() {
    let dir = TempDir::new().unwrap();
    let d = dir.path();
    write(d, "scene.toml", FINITE_APERTURE);
    let args = [
        "render",
        "scene.toml",
        "--width",
        "16",
        "--spp",
        "2",
        "-o",
        "out.exr",
        "--denoise",
    ];
    timbre(d, &args).assert_bad_input(&["--denoise", "setup-oidn.sh", "--features denoise"]);
    assert!(!d.join("out.exr").exists());
    timbre(d, &["image", "denoise", "out.exr"]).assert_bad_input(&["--features denoise"]);
}
