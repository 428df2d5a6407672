//! 8-bit PNG: each linear channel is clamped to [0, 1] and scaled by 255 (rounded), with no
//! gamma curve, as TIM writes its images.

use std::path::Path;

use image::codecs::png::PngEncoder;
use image::{ExtendedColorType, ImageEncoder};

use super::OutputError;
use crate::render::Image;

/// The image as 8-bit RGB bytes.
pub fn to_rgb8(image: &Image) -> image::RgbImage {
    let bytes = image
        .pixels
        .iter()
        .flat_map(|c| c.to_array())
        .map(|v| (v.clamp(0.0, 1.0) * 255.0).round() as u8)
        .collect();
    image::RgbImage::from_raw(image.width, image.height, bytes).expect("3 bytes per pixel")
}

/// Writes `image` as an 8-bit PNG, crash-safely ([`crate::files::write_atomically`]).
pub fn write_png(path: &Path, image: &Image) -> Result<(), OutputError> {
    let rgb = to_rgb8(image);
    crate::files::write_atomically(path, |out| {
        PngEncoder::new(out)
            .write_image(
                rgb.as_raw(),
                rgb.width(),
                rgb.height(),
                ExtendedColorType::Rgb8,
            )
            .map_err(std::io::Error::other)
    })
    .map_err(|source| OutputError::Write {
        path: path.display().to_string(),
        source,
    })
}
