//! Pictures read from files (PNG, JPEG, OpenEXR, Radiance HDR): the texels of picture surfaces,
//! mesh textures and image skies, shared behind an `Arc` so that copies of a surface cost
//! nothing.
//!
//! Values are taken as the file holds them, as Dr TIM's `PictureSurface` does: 8- and 16-bit
//! channels scaled to [0, 1] without undoing any transfer curve (timbre writes linear PNGs, as
//! TIM does, so a picture rendered by timbre reads back as it was rendered), floating-point
//! channels (OpenEXR, HDR) as they are. Alpha is ignored.

use std::io::Cursor;
use std::path::Path;
use std::sync::Arc;

use image::{ImageFormat, ImageReader};
use thiserror::Error;

use crate::math::Colour;

/// Largest picture file that is read, in bytes.
pub const MAX_FILE_BYTES: u64 = 1 << 30;

/// Most texels a picture may have (16 384 × 16 384, 3 GiB of texels).
pub const MAX_TEXELS: u64 = 1 << 28;

/// Bytes of memory a picture of `texels` texels holds.
pub const fn bytes(texels: u64) -> u64 {
    texels * size_of::<[f32; 3]>() as u64
}

/// A picture that could not be read: the file and what was wrong.
#[derive(Debug, Error)]
#[error("{path}: {message}")]
pub struct PictureError {
    pub path: String,
    pub message: String,
}

/// Linear RGB texels, row-major from the top-left corner.
#[derive(Clone)]
pub struct Picture {
    width: u32,
    height: u32,
    texels: Arc<[[f32; 3]]>,
}

/// A picture shows its size and a digest of its texels (FNV-1a over their mixed bits, as a
/// mesh's), not the texels
/// one by one: the scene hash, taken from the scene's Debug text, stays fast and still tells
/// pictures apart.
impl std::fmt::Debug for Picture {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let digest = self
            .texels
            .iter()
            .flatten()
            .fold(0xcbf2_9ce4_8422_2325u64, |h, v| {
                (h ^ crate::math::random::mix(u64::from(v.to_bits())))
                    .wrapping_mul(0x0000_0100_0000_01b3)
            });
        write!(f, "Picture({}x{}, {digest:016x})", self.width, self.height)
    }
}

impl PartialEq for Picture {
    /// The same picture: the same texels, shared (pictures are compared by identity, as
    /// comparing millions of texels would be pointless).
    fn eq(&self, other: &Picture) -> bool {
        Arc::ptr_eq(&self.texels, &other.texels)
    }
}

impl Picture {
    /// A picture of `width` × `height` texels, row-major from the top left.
    pub fn new(width: u32, height: u32, texels: Vec<[f32; 3]>) -> Picture {
        assert_eq!(texels.len() as u64, width as u64 * height as u64);
        assert!(width > 0 && height > 0);
        Picture {
            width,
            height,
            texels: texels.into(),
        }
    }

    /// Reads a picture file, its format told by its extension (`.png`, `.jpg`/`.jpeg`,
    /// `.exr`, `.hdr`, any case). Refuses files that are not regular, larger than
    /// [`MAX_FILE_BYTES`], of more than [`MAX_TEXELS`] texels, or whose texels would need more
    /// memory than can be had.
    pub fn load(path: &Path) -> Result<Picture, PictureError> {
        let fail = |message: String| PictureError {
            path: path.display().to_string(),
            message,
        };
        let format = format(path).ok_or_else(|| {
            fail(
                "unknown picture format: the file name must end in .png, .jpg, .jpeg, .exr or .hdr"
                    .into(),
            )
        })?;
        let file =
            crate::files::read_regular(path, MAX_FILE_BYTES).map_err(|e| fail(e.to_string()))?;
        let reader = || ImageReader::with_format(Cursor::new(&file[..]), format);
        let (width, height) = reader()
            .into_dimensions()
            .map_err(|e| fail(format!("not a readable {format:?} picture: {e}")))?;
        let texels = width as u64 * height as u64;
        if texels == 0 {
            return Err(fail("the picture has no texels".into()));
        }
        if texels > MAX_TEXELS {
            return Err(fail(format!(
                "the picture has {width}x{height} texels, more than the {MAX_TEXELS} a picture may have"
            )));
        }
        // Decoding holds the file's own pixels beside the texels made from them.
        let needs = 2 * bytes(texels);
        if let Some(available) = crate::memory::available(crate::memory::PLAIN_RESERVE)
            && needs > available
        {
            return Err(fail(format!(
                "the {width}x{height} picture needs about {:.2} GiB of memory to read, but only {:.2} GiB can be had here",
                needs as f64 / f64::from(1 << 30),
                available as f64 / f64::from(1 << 30)
            )));
        }
        let mut reader = reader();
        reader.no_limits();
        let image = reader
            .decode()
            .map_err(|e| fail(format!("not a readable {format:?} picture: {e}")))?;
        let rgb = image.into_rgb32f();
        let texels = rgb.pixels().map(|p| p.0).collect();
        Ok(Picture::new(width, height, texels))
    }

    pub fn width(&self) -> u32 {
        self.width
    }

    pub fn height(&self) -> u32 {
        self.height
    }

    /// Bytes of memory the texels take.
    pub fn bytes(&self) -> u64 {
        bytes(self.texels.len() as u64)
    }

    /// The texel in column `x` (from the left) and row `y` (from the top).
    pub fn texel(&self, x: u32, y: u32) -> Colour {
        let [r, g, b] = self.texels[y as usize * self.width as usize + x as usize];
        Colour::new(r as f64, g as f64, b as f64)
    }

    /// The texel at picture coordinates (`u`, `v`): the picture spans [0, 1]² with u to the
    /// right and v upwards (v = 0 the bottom edge), and repeats outside it. The nearest texel:
    /// the one whose square contains the point.
    pub fn at(&self, u: f64, v: f64) -> Colour {
        // Casts saturate (NaN becomes 0), so any coordinates name a texel.
        let index = |t: f64, n: u32| ((t - t.floor()) * n as f64).min(n as f64 - 1.0) as u32;
        let x = index(u, self.width);
        let y = self.height - 1 - index(v, self.height);
        self.texel(x, y)
    }
}

/// A picture file named by a scene file's key (`file = "NAME"`, relative to the scene file):
/// the name as given, and the picture once the scene-file reader has opened it (it finds these
/// through `SurfaceKeys::pictures` before the surface is built, so that confinement and sharing
/// are the reader's).
#[derive(Debug, Clone)]
pub struct PictureFile {
    pub name: String,
    pub picture: Option<Picture>,
}

impl<'de> serde::Deserialize<'de> for PictureFile {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<PictureFile, D::Error> {
        Ok(PictureFile {
            name: String::deserialize(d)?,
            picture: None,
        })
    }
}

impl PictureFile {
    /// The picture, once opened; an error naming the file if it was not (a key the reader
    /// does not know to open).
    pub fn opened(self) -> Result<Picture, String> {
        self.picture
            .ok_or_else(|| format!("the picture file '{}' was not opened", self.name))
    }
}

/// The picture format a file's extension names.
fn format(path: &Path) -> Option<ImageFormat> {
    let ext = path.extension()?.to_str()?.to_ascii_lowercase();
    Some(match ext.as_str() {
        "png" => ImageFormat::Png,
        "jpg" | "jpeg" => ImageFormat::Jpeg,
        "exr" => ImageFormat::OpenExr,
        "hdr" => ImageFormat::Hdr,
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 3 × 2 picture whose texels are numbered 0..6 from the top left (in red).
    fn numbered() -> Picture {
        Picture::new(3, 2, (0..6).map(|k| [k as f32, 0.0, 0.0]).collect())
    }

    /// (u, v) = (0, 0) is the bottom-left corner and v points up: the texel whose square holds
    /// the point, repeated outside [0, 1]².
    #[test]
    fn coordinates_name_the_texel_whose_square_holds_them() {
        let p = numbered();
        let at = |u, v| p.at(u, v).x;
        assert_eq!(at(0.1, 0.1), 3.0); // bottom row, left
        assert_eq!(at(0.1, 0.9), 0.0); // top row, left
        assert_eq!(at(0.5, 0.9), 1.0);
        assert_eq!(at(0.9, 0.2), 5.0);
        assert_eq!(at(1.0 / 3.0 + 1e-9, 0.49), 4.0);
        assert_eq!(at(1.0 / 3.0 - 1e-9, 0.51), 0.0);
        // Repeated: u + 1 and v − 2 are the same texel.
        assert_eq!(at(1.1, -1.9), 3.0);
        assert_eq!(at(-0.1, 0.9), 2.0);
        // The edges u = 1, v = 1 belong to the next repeat; NaN names a texel, not a panic.
        assert_eq!(at(1.0, 0.0), 3.0);
        assert!(p.at(f64::NAN, f64::INFINITY).x.is_finite());
    }

    /// Debug text is short and tells pictures apart by their texels.
    #[test]
    fn debug_text_is_a_digest() {
        let a = format!("{:?}", numbered());
        assert!(a.starts_with("Picture(3x2, ") && a.len() < 40, "{a}");
        let mut texels: Vec<[f32; 3]> = (0..6).map(|k| [k as f32, 0.0, 0.0]).collect();
        texels[5][2] = 1e-30;
        assert_ne!(a, format!("{:?}", Picture::new(3, 2, texels)));
        assert_eq!(a, format!("{:?}", numbered()));
    }

    /// A PNG written here (8-bit RGB) reads back texel for texel as value/255, top row first.
    #[test]
    fn a_png_reads_back_as_its_values() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("p.png");
        let pixels: Vec<u8> = vec![255, 0, 0, 0, 51, 0, 0, 0, 102, 7, 8, 9];
        image::save_buffer(&path, &pixels, 2, 2, image::ExtendedColorType::Rgb8).unwrap();
        let p = Picture::load(&path).unwrap();
        assert_eq!((p.width(), p.height()), (2, 2));
        assert_eq!(p.texel(0, 0), Colour::new(1.0, 0.0, 0.0));
        // Texels are single precision.
        assert!((p.texel(1, 0) - Colour::new(0.0, 0.2, 0.0)).length() < 1e-7);
        assert!((p.texel(0, 1) - Colour::new(0.0, 0.0, 0.4)).length() < 1e-7);
        assert!((p.texel(1, 1) - Colour::new(7.0, 8.0, 9.0) / 255.0).length() < 1e-7);
    }

    /// A picture that declares 100 000 × 100 000 texels in a file of a few hundred bytes is
    /// refused from its header, before anything is decoded; one whose data ends early is
    /// refused as unreadable.
    #[test]
    fn bombs_and_truncated_pictures_are_refused() {
        let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/pictures");
        let e = Picture::load(&data.join("huge-dimensions.png"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("100000x100000 texels, more than the"), "{e}");
        let e = Picture::load(&data.join("truncated.png"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("not a readable Png picture"), "{e}");
    }

    #[test]
    fn bad_files_are_refused_with_the_path_and_why() {
        let dir = tempfile::tempdir().unwrap();
        let text = dir.path().join("not.png");
        std::fs::write(&text, "hello").unwrap();
        let e = Picture::load(&text).unwrap_err().to_string();
        assert!(
            e.starts_with(&text.display().to_string()) && e.contains("not a readable"),
            "{e}"
        );
        let e = Picture::load(&dir.path().join("x.gif"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("unknown picture format"), "{e}");
        let e = Picture::load(&dir.path().join("missing.png"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("missing.png"), "{e}");
        let e = Picture::load(dir.path()).unwrap_err().to_string();
        assert!(
            e.contains("unknown picture format") || e.contains("directory"),
            "{e}"
        );
    }
}
