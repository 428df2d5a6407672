//! `timbre render --denoise` and `timbre image denoise`: an OpenEXR render with the albedo and
//! normal AOVs in, its denoised picture out (a new file beside it, never in its place), with
//! Intel Open Image Denoise where timbre is built with the `denoise` feature.

use std::path::{Path, PathBuf};

use crate::{Failure, bad_input};

/// Where `--denoise` writes the denoised picture of `output`: `NAME.denoised.exr` beside it.
pub fn denoised_path(output: &Path) -> PathBuf {
    let stem = output.file_stem().unwrap_or_default().to_string_lossy();
    output.with_file_name(format!("{stem}.denoised.exr"))
}

/// Why this build cannot denoise, if it cannot.
pub fn unavailable() -> Option<&'static str> {
    (!cfg!(feature = "denoise")).then_some(
        "this timbre was built without Intel Open Image Denoise: install it with scripts/setup-oidn.sh, then build with OIDN_DIR=target/oidn cargo build --release --features denoise (README, \"Denoising\")",
    )
}

/// Writes the denoised picture of the OpenEXR file `input` (which has the channels R, G, B,
/// albedo.R/G/B and normal.X/Y/Z) to `output`: the same header and window, the colour
/// channels only, and `timbre.denoised` recording how.
#[cfg(feature = "denoise")]
pub fn denoise_file(input: &Path, output: &Path) -> Result<(), Failure> {
    use exr::prelude::{
        AnyChannel, AnyChannels, AttributeValue, FlatSamples, Image, Layer, Text, WritableImage,
        read_all_flat_layers_from_file,
    };
    use timbre::files::AtomicFile;

    let read = |e: exr::error::Error| bad_input(format!("{}: {e}", input.display()));
    let image = read_all_flat_layers_from_file(input).map_err(read)?;
    let [layer] = &image.layer_data[..] else {
        return Err(bad_input(format!(
            "{}: has {} layers; timbre denoises its own renders, of one layer",
            input.display(),
            image.layer_data.len()
        )));
    };
    let channel = |name: &str| -> Result<Vec<f32>, Failure> {
        let found = layer
            .channel_data
            .list
            .iter()
            .find(|c| c.name.to_string() == name);
        match found.map(|c| &c.sample_data) {
            Some(FlatSamples::F32(v)) => Ok(v.clone()),
            Some(FlatSamples::F16(v)) => Ok(v.iter().map(|h| h.to_f32()).collect()),
            _ => Err(bad_input(format!(
                "{}: has no 32- or 16-bit float channel {name}; denoising needs the colour and the albedo and normal AOVs (render with --denoise, or --aov albedo,normal)",
                input.display()
            ))),
        }
    };
    // Three floats a pixel, from the named channels.
    let interleaved = |names: [&str; 3]| -> Result<Vec<f32>, Failure> {
        let [a, b, c] = names.map(channel);
        let (a, b, c) = (a?, b?, c?);
        Ok((0..a.len()).flat_map(|i| [a[i], b[i], c[i]]).collect())
    };
    let colour = interleaved(["R", "G", "B"])?;
    let albedo = interleaved(["albedo.R", "albedo.G", "albedo.B"])?;
    let normal = interleaved(["normal.X", "normal.Y", "normal.Z"])?;
    let (width, height) = (layer.size.width(), layer.size.height());
    let denoised = timbre::denoise::denoise(width, height, &colour, &albedo, &normal)
        .map_err(crate::internal)?;

    let plane = |k: usize| FlatSamples::F32(denoised.iter().skip(k).step_by(3).copied().collect());
    let channels = AnyChannels::sort(smallvec::smallvec![
        AnyChannel::new("R", plane(0)),
        AnyChannel::new("G", plane(1)),
        AnyChannel::new("B", plane(2)),
    ]);
    let mut attributes = layer.attributes.clone();
    attributes.other.insert(
        Text::from("timbre.denoised"),
        AttributeValue::Text(Text::from(
            "Intel Open Image Denoise, RT filter (HDR), guided by albedo and normal",
        )),
    );
    let mut out = Image::from_layer(Layer::new(layer.size, attributes, layer.encoding, channels));
    out.attributes = image.attributes.clone();
    let written = |e: String| bad_input(format!("{}: {e}", output.display()));
    let mut file = AtomicFile::create(output).map_err(|e| written(e.to_string()))?;
    out.write()
        .to_buffered(&mut file)
        .map_err(|e| written(e.to_string()))?;
    file.commit().map_err(|e| written(e.to_string()))
}

/// [`denoise_file`] of a build without the `denoise` feature: the reason it cannot.
#[cfg(not(feature = "denoise"))]
pub fn denoise_file(_input: &Path, _output: &Path) -> Result<(), Failure> {
    Err(bad_input(unavailable().expect("built without denoising")))
}
