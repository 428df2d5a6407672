//! Image output: PNG (8-bit, clamped, no gamma curve, as TIM writes) and OpenEXR (f32, values
//! unchanged, with optional AOV channels), chosen by the file extension.

mod exr_output;
mod png_output;

use std::path::Path;

use thiserror::Error;

use crate::render::Image;

pub use exr_output::write_exr;
pub use png_output::{to_rgb8, write_png};

/// How an image was made, recorded in EXR headers.
#[derive(Debug, Clone, PartialEq)]
pub struct Provenance {
    pub spp: u32,
    pub seed: u64,
}

#[derive(Debug, Error)]
pub enum OutputError {
    #[error("unsupported output format '{0}': use a .png or .exr file name")]
    UnsupportedFormat(String),
    #[error("could not write PNG '{path}': {source}")]
    Png { path: String, source: image::ImageError },
    #[error("could not write OpenEXR '{path}': {source}")]
    Exr { path: String, source: exr::error::Error },
}

/// Writes `image` to `path` as PNG or OpenEXR according to the extension.
pub fn write_image(path: &Path, image: &Image, provenance: &Provenance) -> Result<(), OutputError> {
    let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("png") => write_png(path, image),
        Some("exr") => write_exr(path, image, provenance),
        _ => Err(OutputError::UnsupportedFormat(path.display().to_string())),
    }
}
