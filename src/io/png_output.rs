//! 8-bit PNG: each channel (× 2^exposure) is clamped to [0, 1], encoded by the transfer
//! (`linear`: the value itself, as TIM writes its images, marked gamma 1 by a gAMA chunk;
//! `srgb`: the sRGB curve, marked by an sRGB chunk) and scaled by 255 (rounded). The scene's
//! hash, the seed and the timbre version go into tEXt chunks (`timbre.scene`, `timbre.seed`,
//! `timbre.version`), as into OpenEXR headers. Rows are compressed as they arrive (the `png`
//! crate's stream writer). A PNG holds the file's pixels only: no AOVs, no sums, no display
//! window.

use std::io::Write;
use std::path::Path;

use super::{Block, Finish, OutputError, Provenance};
use crate::files::AtomicFile;
use crate::math::Colour;
use crate::render::Image;
use crate::scene::settings::PngTransfer;

/// The sRGB transfer curve (IEC 61966-2-1) of a linear value in [0, 1].
fn srgb(v: f64) -> f64 {
    if v <= 0.003_130_8 {
        12.92 * v
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    }
}

/// The linear value of an sRGB-encoded value in [0, 1]: the inverse of the sRGB transfer curve
/// (IEC 61966-2-1) a PNG with `png_transfer = "srgb"` is written with.
pub fn linear_from_srgb(v: f64) -> f64 {
    if v <= 0.040_45 {
        v / 12.92
    } else {
        ((v + 0.055) / 1.055).powf(2.4)
    }
}

/// A linear colour as 8-bit RGB by `transfer`.
fn rgb8(c: &Colour, transfer: PngTransfer) -> [u8; 3] {
    c.to_array().map(|v| {
        let v = v.clamp(0.0, 1.0);
        let v = match transfer {
            PngTransfer::Linear => v,
            PngTransfer::Srgb => srgb(v),
        };
        (v * 255.0).round() as u8
    })
}

/// The image as 8-bit RGB bytes, linear (as a PNG is by default).
pub fn to_rgb8(image: &Image) -> image::RgbImage {
    encoded_rgb8(image, PngTransfer::Linear)
}

/// The image as 8-bit RGB bytes by `transfer`.
pub fn encoded_rgb8(image: &Image, transfer: PngTransfer) -> image::RgbImage {
    let bytes = image
        .pixels
        .iter()
        .flat_map(|c| rgb8(c, transfer))
        .collect();
    image::RgbImage::from_raw(image.width, image.height, bytes).expect("3 bytes per pixel")
}

/// A PNG encoder of 8-bit RGB whose colour chunk says `transfer`: gAMA 1 (linear) or sRGB.
pub fn encoder<W: Write>(
    out: W,
    width: u32,
    height: u32,
    transfer: PngTransfer,
) -> png::Encoder<'static, W> {
    let mut encoder = png::Encoder::new(out, width, height);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    match transfer {
        PngTransfer::Linear => encoder.set_source_gamma(png::ScaledFloat::new(1.0)),
        PngTransfer::Srgb => encoder.set_source_srgb(png::SrgbRenderingIntent::Perceptual),
    }
    encoder
}

pub(super) fn write<E: From<OutputError>>(
    path: &Path,
    file: &mut AtomicFile,
    provenance: &Provenance,
    produce: impl FnOnce(&mut dyn FnMut(&Block) -> Result<(), OutputError>) -> Result<Finish, E>,
) -> Result<Finish, E> {
    let failed = |e: png::EncodingError| OutputError::write(path, std::io::Error::other(e));
    let b = provenance.bounds;
    let transfer = provenance.png_transfer;
    let mut encoder = encoder(file, b.width(), b.height(), transfer);
    for (key, text) in [
        ("timbre.scene", provenance.scene.clone()),
        ("timbre.seed", provenance.seed.to_string()),
        ("timbre.version", env!("CARGO_PKG_VERSION").to_string()),
    ] {
        encoder.add_text_chunk(key.into(), text).map_err(failed)?;
    }
    // Fast DEFLATE: encoding keeps up with rendering.
    encoder.set_compression(png::Compression::Fast);
    let mut writer = encoder.write_header().map_err(failed)?;
    let mut stream = writer.stream_writer().map_err(failed)?;
    let mut row = Vec::with_capacity(3 * b.width() as usize);
    let gain = provenance.gain();
    let finish = produce(&mut |block| {
        row.clear();
        row.extend(
            block
                .colours
                .iter()
                .flat_map(|&c| rgb8(&(gain * c), transfer)),
        );
        stream
            .write_all(&row)
            .map_err(|e| OutputError::write(path, e))
    })?;
    if finish == Finish::Keep {
        stream.finish().map_err(failed)?;
        writer.finish().map_err(failed)?;
    }
    Ok(finish)
}
