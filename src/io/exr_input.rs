//! Reading back the parts timbre writes (OpenEXR files with exact sums, see
//! [`super::exr_output`]): their provenance from the header, then their rows, top to bottom,
//! one compressed block at a time, so memory does not grow with the part.

use std::fs::File;
use std::io::BufReader;
use std::path::Path;

use exr::block::reader::{AllChunksReader, Reader};
use exr::block::reader::{ChunksReader, SequentialBlockDecompressor};
use exr::meta::attribute::{AttributeValue, SampleType, Text};
use glam::Vec3;
use thiserror::Error;

use super::exr_output::sum_channel;
use super::{AovSelection, Provenance};
use crate::render::{AovSample, PixelBounds, Rows, Sum};
use crate::scene::settings::PngTransfer;

/// A part that cannot be used: unreadable, truncated, corrupted or not written by timbre.
#[derive(Debug, Error)]
#[error("{path}: {message}")]
pub struct PartError {
    pub path: String,
    pub message: String,
}

type Chunks = SequentialBlockDecompressor<AllChunksReader<BufReader<File>>>;

/// A part being read: its provenance, the timbre version that wrote it, and its rows.
pub struct PartReader {
    pub provenance: Provenance,
    pub version: String,
    path: String,
    chunks: Chunks,
    /// Byte offsets of the channels in a line, by name.
    channels: Vec<(String, usize)>,
    /// The next row expected.
    next_y: u32,
}

/// Opens the part at `path` and reads its header.
pub fn read_part(path: &Path) -> Result<PartReader, PartError> {
    let name = path.display().to_string();
    let fail = |message: String| PartError {
        path: name.clone(),
        message,
    };
    let file =
        crate::files::open_regular(path).map_err(|e| fail(format!("cannot open it: {e}")))?;
    let unreadable = |e: exr::error::Error| fail(format!("not a readable OpenEXR file ({e})"));
    let reader: Reader<_> = exr::block::read(BufReader::new(file), true).map_err(unreadable)?;
    let headers = reader.headers();
    let [header] = headers else {
        return Err(fail("a timbre part has one layer".into()));
    };
    let attribute = |key: &str| header.own_attributes.other.get(&Text::from(key));
    let text = |key: &str| match attribute(key) {
        Some(AttributeValue::Text(t)) => Ok(String::from_utf8_lossy(t.bytes()).into_owned()),
        _ => Err(fail(format!(
            "not a part written by timbre (no {key} in its header)"
        ))),
    };
    let version = text("timbre.version")?;
    let spp = match attribute("timbre.spp") {
        Some(AttributeValue::I32(n)) if *n > 0 => *n as u32,
        _ => return Err(fail("not a part written by timbre (no timbre.spp)".into())),
    };
    let samples = text("timbre.samples")?;
    let samples = samples
        .split_once("..")
        .and_then(|(a, b)| Some(a.parse::<u32>().ok()?..b.parse::<u32>().ok()?))
        .filter(|r| r.start < r.end && r.end <= spp)
        .ok_or_else(|| {
            fail(format!(
                "its sample range '{samples}' is not within 0..{spp}"
            ))
        })?;
    let seed = text("timbre.seed")?
        .parse()
        .map_err(|_| fail("its timbre.seed is not a number".into()))?;
    let display = header.shared_attributes.display_window;
    let position = header.own_attributes.layer_position;
    let size = header.layer_size;
    let (width, height) = (display.size.0 as u32, display.size.1 as u32);
    let bounds = PixelBounds {
        x0: position.0 as u32,
        x1: position.0 as u32 + size.0 as u32,
        y0: position.1 as u32,
        y1: position.1 as u32 + size.1 as u32,
    };
    if display.position != exr::math::Vec2(0, 0)
        || position.0 < 0
        || position.1 < 0
        || !PixelBounds::full(width, height).contains(&bounds)
    {
        return Err(fail(format!(
            "its data window {bounds} is not within its display window of {width}x{height}"
        )));
    }
    let names: Vec<String> = header
        .channels
        .list
        .iter()
        .map(|c| String::from_utf8_lossy(c.name.bytes()).into_owned())
        .collect();
    let has = |n: &str| names.iter().any(|m| m == n);
    let aovs = AovSelection {
        depth: has("depth.Z"),
        normal: has("normal.X"),
        object: has("object.id"),
        albedo: has("albedo.R"),
    };
    let sums = (0..3).all(|c| (0..4).all(|w| has(&sum_channel(c, w))));
    if !sums {
        return Err(fail(
            "it has no exact sums (timbre.sum channels): only parts written with --tile, \
             --pixel-bounds or --samples, and checkpoints, can be merged"
                .into(),
        ));
    }
    let exposure = match attribute("timbre.exposure") {
        None => 0.0,
        Some(AttributeValue::F64(x)) if (-30.0..=30.0).contains(x) => *x,
        Some(_) => {
            return Err(fail(
                "its timbre.exposure is not a number from -30 to 30".into(),
            ));
        }
    };
    let object_names = match attribute("timbre.objects") {
        Some(AttributeValue::TextVector(v)) => v
            .iter()
            .map(|t| String::from_utf8_lossy(t.bytes()).into_owned())
            .collect(),
        _ => Vec::new(),
    };
    let kinds_ok = header.channels.list.iter().all(|c| {
        let name = String::from_utf8_lossy(c.name.bytes());
        let want = if name.starts_with("timbre.sum.") {
            SampleType::U32
        } else {
            SampleType::F32
        };
        c.sample_type == want && c.sampling == exr::math::Vec2(1, 1)
    });
    if !kinds_ok || header.deep || !matches!(header.blocks, exr::meta::BlockDescription::ScanLines)
    {
        return Err(fail(
            "its channels or layout are not those timbre writes".into(),
        ));
    }
    let mut offset = 0;
    let channels = names
        .iter()
        .map(|n| {
            let at = offset;
            offset += 4 * size.0;
            (n.clone(), at)
        })
        .collect();
    let provenance = Provenance {
        width,
        height,
        bounds,
        spp,
        samples,
        seed,
        scene: text("timbre.scene")?,
        aovs,
        object_names,
        sums,
        exposure,
        // A part is OpenEXR; the merged file's own transfer is the default if it is a PNG.
        png_transfer: PngTransfer::Linear,
    };
    let chunks = reader
        .all_chunks(true)
        .map_err(unreadable)?
        .sequential_decompressor(true);
    Ok(PartReader {
        provenance,
        version,
        path: name,
        chunks,
        channels,
        next_y: bounds.y0,
    })
}

impl PartReader {
    /// The next rows of the part (a block of the file), top to bottom; `None` after the last.
    pub fn next_rows(&mut self) -> Result<Option<Rows>, PartError> {
        let fail = |message: String| PartError {
            path: self.path.clone(),
            message,
        };
        let Some(block) = self.chunks.decompress_next_block() else {
            return if self.next_y == self.provenance.bounds.y1 {
                Ok(None)
            } else {
                Err(fail(format!(
                    "it ends before row {}: truncated",
                    self.next_y
                )))
            };
        };
        let block = block.map_err(|e| {
            fail(format!(
                "a block cannot be read ({e}): corrupted or truncated"
            ))
        })?;
        let b = self.provenance.bounds;
        let y0 = b.y0 + block.index.pixel_position.1 as u32;
        let lines = block.index.pixel_size.1 as u32;
        if y0 != self.next_y || block.index.pixel_size.0 as u32 != b.width() {
            return Err(fail(format!(
                "its blocks are not in order (row {y0}, expected {})",
                self.next_y
            )));
        }
        self.next_y = y0 + lines;
        let width = b.width() as usize;
        let line_bytes = self.channels.len() * 4 * width;
        let mut rows = Rows::new(b.x0, b.x1, y0, y0 + lines, self.provenance.aovs.any());
        let channel = |name: &str| {
            self.channels
                .iter()
                .find(|(n, _)| n == name)
                .map(|(_, at)| *at)
        };
        let word = |line: usize, at: usize, x: usize| {
            let i = line * line_bytes + at + 4 * x;
            u32::from_le_bytes(block.data[i..i + 4].try_into().expect("4 bytes"))
        };
        let sum_at: Vec<usize> = (0..3)
            .flat_map(|c| (0..4).map(move |w| (c, w)))
            .map(|(c, w)| channel(&sum_channel(c, w)).expect("checked when opened"))
            .collect();
        let aov_at = |name: &str| channel(name);
        let (depth, nx, ny, nz, object) = (
            aov_at("depth.Z"),
            aov_at("normal.X"),
            aov_at("normal.Y"),
            aov_at("normal.Z"),
            aov_at("object.id"),
        );
        let albedo = ["albedo.R", "albedo.G", "albedo.B"].map(aov_at);
        let f = |line, at: Option<usize>, x, default: f32| {
            at.map_or(default, |at| f32::from_bits(word(line, at, x)))
        };
        for line in 0..lines as usize {
            for x in 0..width {
                let k = line * width + x;
                let mut sum = Sum::default();
                for c in 0..3 {
                    sum.0[c] = (0..4).fold(0u128, |s, w| {
                        s | (word(line, sum_at[4 * c + w], x) as u128) << (32 * w)
                    }) as i128;
                }
                rows.sums[k] = sum;
                if let Some(aovs) = rows.aovs.as_mut() {
                    aovs[k] = AovSample {
                        depth: f(line, depth, x, f32::INFINITY),
                        normal: Vec3::new(
                            f(line, nx, x, 0.0),
                            f(line, ny, x, 0.0),
                            f(line, nz, x, 0.0),
                        ),
                        object: f(line, object, x, -1.0),
                        albedo: Vec3::from_array(albedo.map(|at| f(line, at, x, 0.0))),
                    };
                }
            }
        }
        Ok(Some(rows))
    }
}
