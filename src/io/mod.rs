//! Image output: PNG (8-bit, clamped, linear as TIM writes or sRGB-encoded) and OpenEXR (f32,
//! with optional AOV channels), chosen by the file extension; both scaled by the exposure. Images are streamed:
//! rows are encoded as they arrive, so memory does not grow with the image, and written
//! crash-safely ([`crate::files::AtomicFile`]). OpenEXR files can hold a part of a render (a
//! rectangle of the image, a range of its samples) with exact sums for `timbre merge`
//! ([`read_part`]).

mod exr_input;
mod exr_output;
mod png_output;

use std::ops::Range;
use std::path::Path;

use thiserror::Error;

use crate::files::AtomicFile;
use crate::math::Colour;
use crate::render::{AovSample, Image, PixelBounds, Sum};
use crate::scene::RenderSettings;
use crate::scene::settings::PngTransfer;

pub use exr_input::{PartError, PartReader, read_part};
pub use png_output::{encoded_rgb8, encoder as png_encoder, linear_from_srgb, to_rgb8};

/// Which AOV layers an EXR file gets.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct AovSelection {
    pub depth: bool,
    pub normal: bool,
    pub object: bool,
    pub albedo: bool,
}

impl AovSelection {
    pub fn any(&self) -> bool {
        self.depth || self.normal || self.object || self.albedo
    }
}

impl std::fmt::Display for AovSelection {
    /// The AOVs selected, as `--aov` names them ("depth,object"), or "none".
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let names: Vec<&str> = [
            (self.depth, "depth"),
            (self.normal, "normal"),
            (self.object, "object"),
            (self.albedo, "albedo"),
        ]
        .into_iter()
        .filter_map(|(on, name)| on.then_some(name))
        .collect();
        match names.is_empty() {
            true => write!(f, "none"),
            false => write!(f, "{}", names.join(",")),
        }
    }
}

/// What an output file holds and how it was made (recorded in EXR headers).
#[derive(Debug, Clone, PartialEq)]
pub struct Provenance {
    /// Size of the whole image (the EXR display window).
    pub width: u32,
    pub height: u32,
    /// The pixels in the file (the EXR data window): all, or a part.
    pub bounds: PixelBounds,
    /// Samples per pixel of the whole render.
    pub spp: u32,
    /// The samples of the per-pixel sequence this file holds (all: `0..spp`).
    pub samples: Range<u32>,
    pub seed: u64,
    /// The scene's hash ([`crate::scene::SceneDescription::hash`]), as hexadecimal.
    pub scene: String,
    pub aovs: AovSelection,
    /// Object names by index: the meaning of the `object.id` AOV.
    pub object_names: Vec<String>,
    /// Whether the file keeps each pixel's exact sum of samples (a part, to be merged).
    pub sums: bool,
    /// Exposure compensation in stops: the file's colours are the rendered ones × 2^exposure
    /// (exact sums are kept as rendered; `timbre merge` applies the parts' exposure).
    pub exposure: f64,
    /// How a PNG file encodes the values.
    pub png_transfer: PngTransfer,
}

impl Provenance {
    /// A whole render with `settings` of the scene with hash `scene`, without AOVs.
    pub fn whole(settings: &RenderSettings, scene: String) -> Provenance {
        Provenance {
            width: settings.width,
            height: settings.height,
            bounds: PixelBounds::full(settings.width, settings.height),
            spp: settings.spp,
            samples: 0..settings.spp,
            seed: settings.seed,
            scene,
            aovs: AovSelection::default(),
            object_names: Vec::new(),
            sums: false,
            exposure: settings.exposure,
            png_transfer: settings.png_transfer,
        }
    }

    /// The factor the file's colours are multiplied by: 2^exposure.
    pub fn gain(&self) -> f64 {
        self.exposure.exp2()
    }

    /// The samples held per pixel.
    pub fn count(&self) -> u32 {
        self.samples.end - self.samples.start
    }
}

/// Rows `y0..` of an output file's pixels: the colours, and the AOVs and exact sums where the
/// file has them, row-major over the file's columns.
pub struct Block<'a> {
    pub y0: u32,
    pub colours: &'a [Colour],
    pub aovs: Option<&'a [AovSample]>,
    pub sums: Option<&'a [Sum]>,
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

impl OutputError {
    fn write(path: &Path, source: std::io::Error) -> OutputError {
        OutputError::Write {
            path: path.display().to_string(),
            source,
        }
    }
}

/// Whether a streamed file is kept ([`write_streaming`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Finish {
    /// Publish the file (all its rows were written).
    Keep,
    /// Leave whatever was at the path before.
    Discard,
}

/// Streams an image file to `path` (PNG or OpenEXR by its extension): `produce` gets a function
/// that writes blocks of rows, top to bottom, covering `provenance.bounds`; the file is
/// published only if `produce` returns [`Finish::Keep`] and everything written succeeded.
/// `produce`'s own errors pass through (the file is then discarded).
pub fn write_streaming<E: From<OutputError>>(
    path: &Path,
    provenance: &Provenance,
    produce: impl FnOnce(&mut dyn FnMut(&Block) -> Result<(), OutputError>) -> Result<Finish, E>,
) -> Result<Finish, E> {
    let format = OutputFormat::from_path(path)?;
    let mut file = AtomicFile::create(path).map_err(|e| OutputError::write(path, e))?;
    let finish = match format {
        OutputFormat::Png => png_output::write(path, &mut file, provenance, produce)?,
        OutputFormat::Exr => exr_output::write(path, &mut file, provenance, produce)?,
    };
    if finish == Finish::Keep {
        file.commit().map_err(|e| OutputError::write(path, e))?;
    }
    Ok(finish)
}

/// Writes an image held in memory (`provenance` describes all of it).
pub fn write_image(path: &Path, image: &Image, provenance: &Provenance) -> Result<(), OutputError> {
    write_streaming(path, provenance, |write| {
        write(&Block {
            y0: 0,
            colours: &image.pixels,
            aovs: image.aovs.as_deref(),
            sums: None,
        })?;
        Ok::<_, OutputError>(Finish::Keep)
    })
    .map(drop)
}
