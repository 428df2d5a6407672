//! `timbre image info|convert|diff`: pbrt's imgtool for timbre's outputs. Pictures are read
//! through timbre's bounded picture reader (PNG, JPEG, OpenEXR, Radiance HDR) as linear values:
//! a PNG marked sRGB (`--png-transfer srgb`) is decoded back to linear, other PNGs' values are
//! taken as stored (timbre writes linear PNGs, as TIM does).

use std::path::{Path, PathBuf};

use clap::Subcommand;
use timbre::io::{AovSelection, OutputFormat, Provenance, linear_from_srgb, write_image};
use timbre::math::Colour;
use timbre::picture::Picture;
use timbre::render::{Image, PixelBounds};
use timbre::scene::settings::PngTransfer;

use crate::{Failure, bad_input};

#[derive(Subcommand)]
pub enum ImageCommand {
    /// Print a picture's size, format, the range and mean of its channels, and what timbre
    /// recorded in it (scene hash, seed, samples, version, exposure).
    Info { file: PathBuf },
    /// Write a picture in another format (by the output's extension, .png or .exr), with an
    /// exposure and a PNG transfer.
    Convert {
        input: PathBuf,
        output: PathBuf,
        /// Multiply the values by 2^STOPS.
        #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
        exposure: f64,
        /// How a PNG output encodes the values.
        #[arg(long, value_parser = ["linear", "srgb"], default_value = "linear")]
        png_transfer: String,
    },
    /// Compare two pictures of the same size: PSNR, mean and largest error, and how many
    /// pixels differ. Exits 1 if a given threshold is exceeded, 0 otherwise.
    Diff {
        a: PathBuf,
        b: PathBuf,
        /// A pixel differs where a channel differs by more than this.
        #[arg(long, default_value_t = 0.0)]
        tolerance: f64,
        /// Fail (exit 1) if any channel differs by more than this.
        #[arg(long)]
        max_error: Option<f64>,
        /// Fail (exit 1) if more than this many pixels differ.
        #[arg(long)]
        max_differing: Option<u64>,
    },
    /// Denoise an OpenEXR render that has the albedo and normal AOVs (`--aov albedo,normal`,
    /// a merged render's too) with Intel Open Image Denoise (a build with the `denoise`
    /// feature), into a new file: by default NAME.denoised.exr beside it.
    Denoise {
        input: PathBuf,
        #[arg(short, long)]
        output: Option<PathBuf>,
    },
}

pub fn run_image(command: ImageCommand) -> Result<(), Failure> {
    match command {
        ImageCommand::Info { file } => info(&file),
        ImageCommand::Convert {
            input,
            output,
            exposure,
            png_transfer,
        } => convert(&input, &output, exposure, &png_transfer),
        ImageCommand::Diff {
            a,
            b,
            tolerance,
            max_error,
            max_differing,
        } => diff(&a, &b, tolerance, max_error, max_differing),
        ImageCommand::Denoise { input, output } => {
            let output = output.unwrap_or_else(|| super::denoise::denoised_path(&input));
            if OutputFormat::from_path(&output).map_err(bad_input)? != OutputFormat::Exr {
                return Err(bad_input(format!(
                    "{}: the denoised picture is written in OpenEXR (-o NAME.exr)",
                    output.display()
                )));
            }
            let same = |a: &Path, b: &Path| a.canonicalize().ok() == b.canonicalize().ok();
            if output.exists() && same(&input, &output) {
                return Err(bad_input(format!(
                    "{}: the denoised picture goes into a new file, never over the render (-o NAME.exr)",
                    output.display()
                )));
            }
            super::denoise::denoise_file(&input, &output)?;
            out!("{} -> {}", input.display(), output.display());
            Ok(())
        }
    }
}

/// What timbre wrote into a file beside its pixels: (key, value) pairs of an OpenEXR header's
/// `timbre.*` attributes or a PNG's text chunks, and whether a PNG is marked sRGB.
fn recorded(path: &Path) -> (Vec<(String, String)>, bool) {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("exr") => {
            let Ok(meta) = exr::meta::MetaData::read_from_file(path, false) else {
                return (Vec::new(), false);
            };
            let mut pairs: Vec<(String, String)> = meta
                .headers
                .iter()
                .flat_map(|h| h.own_attributes.other.iter())
                .filter(|(k, _)| k.to_string().starts_with("timbre."))
                .map(|(k, v)| (k.to_string(), attribute(v)))
                .collect();
            pairs.sort();
            (pairs, false)
        }
        Some("png") => {
            let Ok(file) = std::fs::File::open(path) else {
                return (Vec::new(), false);
            };
            let Ok(reader) = png::Decoder::new(std::io::BufReader::new(file)).read_info() else {
                return (Vec::new(), false);
            };
            let info = reader.info();
            let pairs = info
                .uncompressed_latin1_text
                .iter()
                .map(|t| (t.keyword.clone(), t.text.clone()))
                .collect();
            (pairs, info.srgb.is_some())
        }
        _ => (Vec::new(), false),
    }
}

/// An OpenEXR attribute's value as text.
fn attribute(v: &exr::meta::attribute::AttributeValue) -> String {
    use exr::meta::attribute::AttributeValue as A;
    match v {
        A::Text(t) => t.to_string(),
        A::I32(i) => i.to_string(),
        A::F32(f) => f.to_string(),
        A::F64(f) => f.to_string(),
        other => format!("{other:?}"),
    }
}

/// The picture at `path` as linear values.
fn read(path: &Path) -> Result<Picture, Failure> {
    let picture = Picture::load(path).map_err(bad_input)?;
    if !recorded(path).1 {
        return Ok(picture);
    }
    let texels = (0..picture.height())
        .flat_map(|y| (0..picture.width()).map(move |x| (x, y)))
        .map(|(x, y)| {
            picture
                .texel(x, y)
                .to_array()
                .map(|v| linear_from_srgb(v) as f32)
        })
        .collect();
    Ok(Picture::new(picture.width(), picture.height(), texels))
}

/// The texels of a picture, row by row from the top.
fn texels(p: &Picture) -> impl Iterator<Item = Colour> + '_ {
    (0..p.height()).flat_map(move |y| (0..p.width()).map(move |x| p.texel(x, y)))
}

fn info(path: &Path) -> Result<(), Failure> {
    let picture = read(path)?;
    let (pairs, srgb) = recorded(path);
    let (mut lo, mut hi, mut sum) = (Colour::INFINITY, Colour::NEG_INFINITY, Colour::ZERO);
    for c in texels(&picture) {
        (lo, hi, sum) = (lo.min(c), hi.max(c), sum + c);
    }
    let mean = sum / (picture.width() as f64 * picture.height() as f64);
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
    out!(
        "{}: {}x{} {ext}",
        path.display(),
        picture.width(),
        picture.height()
    );
    if srgb {
        out!("  transfer:   sRGB (decoded to linear below)");
    }
    for (name, k) in [("red", 0), ("green", 1), ("blue", 2)] {
        out!(
            "  {name:<6}      min {:.6}, max {:.6}, mean {:.6}",
            lo[k],
            hi[k],
            mean[k]
        );
    }
    for (key, value) in pairs {
        out!("  {key}: {value}");
    }
    Ok(())
}

fn convert(input: &Path, output: &Path, exposure: f64, transfer: &str) -> Result<(), Failure> {
    OutputFormat::from_path(output).map_err(bad_input)?;
    if !(-30.0..=30.0).contains(&exposure) {
        return Err(bad_input(format!(
            "--exposure must be from -30 to 30 stops, got {exposure}"
        )));
    }
    let picture = read(input)?;
    let (width, height) = (picture.width(), picture.height());
    let image = Image {
        width,
        height,
        pixels: texels(&picture).collect(),
        aovs: None,
        rays: 0,
    };
    let (pairs, _) = recorded(input);
    let value = |key: &str| pairs.iter().find(|(k, _)| k == key).map(|(_, v)| v.clone());
    let spp = value("timbre.spp")
        .and_then(|v| v.parse().ok())
        .unwrap_or(1);
    let provenance = Provenance {
        width,
        height,
        bounds: PixelBounds::full(width, height),
        spp,
        samples: 0..spp,
        seed: value("timbre.seed")
            .and_then(|v| v.parse().ok())
            .unwrap_or(0),
        scene: value("timbre.scene").unwrap_or_default(),
        aovs: AovSelection::default(),
        object_names: Vec::new(),
        sums: false,
        exposure,
        png_transfer: PngTransfer::named(transfer).expect("clap checks the name"),
    };
    write_image(output, &image, &provenance).map_err(bad_input)?;
    out!("{}x{} -> {}", width, height, output.display());
    Ok(())
}

/// How two pictures differ.
#[derive(Debug, PartialEq)]
pub struct Difference {
    /// Peak signal-to-noise ratio in dB for a peak of 1 (infinite for equal pictures).
    pub psnr: f64,
    pub mean_error: f64,
    pub max_error: f64,
    /// Where the largest error is, (x, y).
    pub at: (u32, u32),
    /// Pixels with a channel that differs by more than the tolerance.
    pub differing: u64,
}

/// The difference of `a` and `b` (of the same size) channel by channel.
pub fn difference(a: &Picture, b: &Picture, tolerance: f64) -> Difference {
    let (mut squares, mut sum, mut max, mut at, mut differing) = (0.0, 0.0, 0.0, (0, 0), 0);
    for y in 0..a.height() {
        for x in 0..a.width() {
            let e = (a.texel(x, y) - b.texel(x, y)).abs();
            squares += e.length_squared();
            sum += e.element_sum();
            if e.max_element() > max {
                (max, at) = (e.max_element(), (x, y));
            }
            differing += u64::from(e.max_element() > tolerance);
        }
    }
    let values = 3.0 * a.width() as f64 * a.height() as f64;
    Difference {
        psnr: -10.0 * (squares / values).log10(),
        mean_error: sum / values,
        max_error: max,
        at,
        differing,
    }
}

fn diff(
    a: &Path,
    b: &Path,
    tolerance: f64,
    max_error: Option<f64>,
    max_differing: Option<u64>,
) -> Result<(), Failure> {
    if tolerance.is_nan() || tolerance < 0.0 {
        return Err(bad_input(format!(
            "--tolerance must be a number of at least 0, got {tolerance}"
        )));
    }
    let (pa, pb) = (read(a)?, read(b)?);
    if (pa.width(), pa.height()) != (pb.width(), pb.height()) {
        return Err(bad_input(format!(
            "{} is {}x{} but {} is {}x{}: only pictures of the same size compare",
            a.display(),
            pa.width(),
            pa.height(),
            b.display(),
            pb.width(),
            pb.height()
        )));
    }
    let d = difference(&pa, &pb, tolerance);
    let pixels = pa.width() as u64 * pa.height() as u64;
    out!(
        "PSNR {:.2} dB, mean error {:.6}, max error {:.6} at ({}, {}), {} of {pixels} pixels differ by more than {tolerance}",
        d.psnr,
        d.mean_error,
        d.max_error,
        d.at.0,
        d.at.1,
        d.differing
    );
    let too_large = max_error.is_some_and(|m| d.max_error > m);
    let too_many = max_differing.is_some_and(|m| d.differing > m);
    if too_large || too_many {
        return Err(Failure {
            code: 1,
            message: "the pictures differ by more than the thresholds allow".into(),
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two 2 × 1 pictures differing by 0.1 in one channel of one pixel: MSE = 0.01/6, so the
    /// PSNR is 10 log10(600) = 27.78 dB; the mean error 0.1/6; one pixel differs beyond 0.05,
    /// none beyond 0.2.
    #[test]
    fn psnr_and_errors_by_their_definitions() {
        let a = Picture::new(2, 1, vec![[0.5; 3], [0.2; 3]]);
        let b = Picture::new(2, 1, vec![[0.5; 3], [0.2, 0.3, 0.2]]);
        let d = difference(&a, &b, 0.05);
        assert!((d.psnr - 10.0 * 600f64.log10()).abs() < 1e-5, "{d:?}");
        assert!((d.mean_error - 0.1 / 6.0).abs() < 1e-7);
        assert!((d.max_error - 0.1).abs() < 1e-7);
        assert_eq!((d.at, d.differing), ((1, 0), 1));
        assert_eq!(difference(&a, &b, 0.2).differing, 0);
        assert_eq!(difference(&a, &a, 0.0).psnr, f64::INFINITY);
    }
}
