//! Image output: PNG (8-bit, clamped, no gamma curve, as TIM writes) and OpenEXR (f32, values
//! unchanged, with optional AOV channels), chosen by the file extension; written crash-safely
//! ([`crate::files`]).

mod exr_output;
mod png_output;

use std::path::Path;

use thiserror::Error;

use crate::render::Image;

pub use exr_output::write_exr;
pub use png_output::{to_rgb8, write_png};

/// Which AOV layers an EXR file gets (when the image has them).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct AovSelection {
    pub depth: bool,
    pub normal: bool,
    pub object: bool,
}

/// How an image was made (recorded in EXR headers) and which AOVs to write.
#[derive(Debug, Clone, PartialEq)]
pub struct Provenance {
    pub spp: u32,
    pub seed: u64,
    pub aovs: AovSelection,
    /// Object names by index: the meaning of the `object.id` AOV.
    pub object_names: Vec<String>,
}

/// Output file formats.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OutputFormat {
    Png,
    Exr,
}

impl OutputFormat {
    /// The format named by the file extension.
    pub fn from_path(path: &Path) -> Result<OutputFormat, OutputError> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("png") => Ok(OutputFormat::Png),
            Some("exr") => Ok(OutputFormat::Exr),
            _ => Err(OutputError::UnsupportedFormat(path.display().to_string())),
        }
    }
}

#[derive(Debug, Error)]
pub enum OutputError {
    #[error("{0}: unsupported output format; use a .png or .exr file name")]
    UnsupportedFormat(String),
    #[error("could not encode OpenEXR '{path}': {source}")]
    Exr {
        path: String,
        source: exr::error::Error,
    },
    /// Writing failed (a full disk, a read-only file system, an I/O error); the file that was
    /// at `path` before is unchanged.
    #[error("could not write '{path}': {source}; any previous file there is unchanged")]
    Write {
        path: String,
        source: std::io::Error,
    },
}

/// Writes `image` to `path` as PNG or OpenEXR according to the extension.
pub fn write_image(path: &Path, image: &Image, provenance: &Provenance) -> Result<(), OutputError> {
    match OutputFormat::from_path(path)? {
        OutputFormat::Png => write_png(path, image),
        OutputFormat::Exr => write_exr(path, image, provenance),
    }
}
