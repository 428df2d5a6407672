//! 8-bit PNG: each linear channel is clamped to [0, 1] and scaled by 255 (rounded), with no
//! gamma curve, as TIM writes its images. Rows are compressed as they arrive (the `png` crate's
//! stream writer). A PNG holds the file's pixels only: no AOVs, no sums, no display window.

use std::io::Write;
use std::path::Path;

use super::{Block, Finish, OutputError, Provenance};
use crate::files::AtomicFile;
use crate::math::Colour;
use crate::render::Image;

/// A linear colour as 8-bit RGB.
fn rgb8(c: &Colour) -> [u8; 3] {
    c.to_array()
        .map(|v| (v.clamp(0.0, 1.0) * 255.0).round() as u8)
}

/// The image as 8-bit RGB bytes.
pub fn to_rgb8(image: &Image) -> image::RgbImage {
    let bytes = image.pixels.iter().flat_map(rgb8).collect();
    image::RgbImage::from_raw(image.width, image.height, bytes).expect("3 bytes per pixel")
}

pub(super) fn write<E: From<OutputError>>(
    path: &Path,
    file: &mut AtomicFile,
    provenance: &Provenance,
    produce: impl FnOnce(&mut dyn FnMut(&Block) -> Result<(), OutputError>) -> Result<Finish, E>,
) -> Result<Finish, E> {
    let failed = |e: png::EncodingError| OutputError::write(path, std::io::Error::other(e));
    let b = provenance.bounds;
    let mut encoder = png::Encoder::new(file, b.width(), b.height());
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    // Fast DEFLATE: encoding keeps up with rendering.
    encoder.set_compression(png::Compression::Fast);
    let mut writer = encoder.write_header().map_err(failed)?;
    let mut stream = writer.stream_writer().map_err(failed)?;
    let mut row = Vec::with_capacity(3 * b.width() as usize);
    let finish = produce(&mut |block| {
        row.clear();
        row.extend(block.colours.iter().flat_map(rgb8));
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
