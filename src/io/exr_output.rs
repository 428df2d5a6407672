//! OpenEXR output, one part of scanlines in increasing order, compressed block by block as the
//! rows arrive (the `exr` crate's chunk writer). Channels: f32 R, G, B; the AOV layers
//! `depth.Z`, `normal.X/Y/Z` and `object.id` that are selected; and in a part to be merged,
//! each pixel's exact sum of samples ([`crate::render::Sum`]) as four u32 words per colour,
//! least significant first: `timbre.sum.R.0` … `timbre.sum.B.3`. The display window is the
//! whole image, the data window the pixels held.
//!
//! Header attributes: samples per pixel of the render (`timbre.spp`), the samples held
//! (`timbre.samples`, "A..B"), the seed (`timbre.seed`), the scene's hash (`timbre.scene`), the
//! timbre version (`timbre.version`), the exposure (`timbre.exposure`, stops, a double; only
//! when not 0: the colour channels are the rendered values × 2^exposure, the sums are not
//! scaled) and, with `object.id`, the object names by id (`timbre.objects`).

use std::io::{Read, Seek, SeekFrom, Write};
use std::path::Path;

use exr::block::writer::ChunksWriter;
use exr::block::{BlockIndex, UncompressedBlock};
use exr::meta::attribute::{
    AttributeValue, ChannelDescription, IntegerBounds, LineOrder, SampleType, Text,
};
use exr::meta::header::{Header, LayerAttributes};
use exr::meta::{BlockDescription, Headers};
use exr::prelude::{Compression, SmallVec, Vec2};

use super::{Block, Finish, OutputError, Provenance};
use crate::files::AtomicFile;

/// Names of the channels of the exact sums, in the order of their words.
pub(super) fn sum_channel(colour: usize, word: usize) -> String {
    format!("timbre.sum.{}.{word}", ["R", "G", "B"][colour])
}

/// One channel's value at pixel `k` of a block, as little-endian bytes.
type Value = Box<dyn Fn(&Block, usize) -> [u8; 4]>;

/// The file's channels in name order (as OpenEXR stores them), with how to get each value.
fn channels(provenance: &Provenance) -> Vec<(String, SampleType, Value)> {
    let mut list: Vec<(String, SampleType, Value)> = Vec::new();
    let f32s = |v: f32| v.to_le_bytes();
    let gain = provenance.gain();
    for (k, name) in ["R", "G", "B"].iter().enumerate() {
        let get: Value = Box::new(move |b, i| f32s((gain * b.colours[i][k]) as f32));
        list.push((name.to_string(), SampleType::F32, get));
    }
    let aov = |b: &Block, i: usize| b.aovs.expect("a block with AOVs")[i];
    let a = provenance.aovs;
    if a.depth {
        list.push((
            "depth.Z".into(),
            SampleType::F32,
            Box::new(move |b, i| f32s(aov(b, i).depth)),
        ));
    }
    if a.normal {
        for (k, axis) in ["X", "Y", "Z"].iter().enumerate() {
            let get: Value = Box::new(move |b, i| f32s(aov(b, i).normal[k]));
            list.push((format!("normal.{axis}"), SampleType::F32, get));
        }
    }
    if a.object {
        list.push((
            "object.id".into(),
            SampleType::F32,
            Box::new(move |b, i| f32s(aov(b, i).object)),
        ));
    }
    if a.albedo {
        for (k, colour) in ["R", "G", "B"].iter().enumerate() {
            let get: Value = Box::new(move |b, i| f32s(aov(b, i).albedo[k]));
            list.push((format!("albedo.{colour}"), SampleType::F32, get));
        }
    }
    if provenance.sums {
        for colour in 0..3 {
            for word in 0..4 {
                let get: Value = Box::new(move |b, i| {
                    let sum = b.sums.expect("a block with sums")[i].0[colour];
                    ((sum >> (32 * word)) as u32).to_le_bytes()
                });
                list.push((sum_channel(colour, word), SampleType::U32, get));
            }
        }
    }
    list.sort_by(|a, b| a.0.cmp(&b.0));
    list
}

/// The EXR header of a file with `provenance`.
fn header(provenance: &Provenance, channels: &[(String, SampleType, Value)]) -> Header {
    let p = provenance;
    let b = p.bounds;
    // A part (to be merged) keeps its place in the whole picture; a picture of some pixels
    // only (a crop) is a picture of its own, from the origin.
    let (origin, display) = if p.sums {
        (
            Vec2(b.x0 as i32, b.y0 as i32),
            (p.width as usize, p.height as usize),
        )
    } else {
        (Vec2(0, 0), (b.width() as usize, b.height() as usize))
    };
    // EXR strings are byte strings; timbre writes UTF-8 (exr's `Text::from` takes Latin-1 only
    // and panics on other characters).
    let text = |s: &str| Text::from_bytes_unchecked(SmallVec::from_slice(s.as_bytes()));
    let mut attributes = LayerAttributes {
        layer_position: origin,
        ..LayerAttributes::default()
    };
    let mut note = |key: &str, value| attributes.other.insert(Text::from(key), value);
    note(
        "timbre.spp",
        AttributeValue::I32(p.spp.min(i32::MAX as u32) as i32),
    );
    note(
        "timbre.samples",
        AttributeValue::Text(text(&format!("{}..{}", p.samples.start, p.samples.end))),
    );
    note(
        "timbre.seed",
        AttributeValue::Text(text(&p.seed.to_string())),
    );
    note("timbre.scene", AttributeValue::Text(text(&p.scene)));
    note(
        "timbre.version",
        AttributeValue::Text(text(env!("CARGO_PKG_VERSION"))),
    );
    // Written only when set, so that files without it are as they were.
    if p.exposure != 0.0 {
        note("timbre.exposure", AttributeValue::F64(p.exposure));
    }
    if p.aovs.object {
        let names = p.object_names.iter().map(|n| text(n)).collect();
        note("timbre.objects", AttributeValue::TextVector(names));
    }
    let descriptions = channels
        .iter()
        .map(|(name, kind, _)| ChannelDescription::named(text(name), *kind))
        .collect();
    // Parts, with their sum words, compress better with ZIP; images are quicker with RLE.
    let compression = if p.sums {
        Compression::ZIP16
    } else {
        Compression::RLE
    };
    let mut header = Header::new(
        Text::from(""),
        (b.width() as usize, b.height() as usize),
        descriptions,
    )
    .with_encoding(
        compression,
        BlockDescription::ScanLines,
        LineOrder::Increasing,
    )
    .with_attributes(attributes)
    .with_display_window(IntegerBounds::new((0, 0), display));
    header.own_attributes.layer_name = None;
    header
}

pub(super) fn write<E: From<OutputError>>(
    path: &Path,
    file: &mut AtomicFile,
    provenance: &Provenance,
    produce: impl FnOnce(&mut dyn FnMut(&Block) -> Result<(), OutputError>) -> Result<Finish, E>,
) -> Result<Finish, E> {
    // Failed writes (a full disk) are write errors, the rest encoding errors.
    let err = |source| match source {
        exr::error::Error::Io(e) => OutputError::write(path, e),
        source => OutputError::Exr {
            path: path.display().to_string(),
            source,
        },
    };
    let channels = channels(provenance);
    let header = header(provenance, &channels);
    let lines_per_block = header.compression.scan_lines_per_block();
    let headers: Headers = SmallVec::from_elem(header, 1);
    let bounds = provenance.bounds;
    let width = bounds.width() as usize;
    let bytes_per_line = width * 4 * channels.len();
    let mut produced = None;
    let written = exr::block::write(&mut *file, headers.clone(), true, |_, chunks| {
        // Lines of the block being filled, and their first row.
        let mut data = Vec::with_capacity(bytes_per_line * lines_per_block);
        let mut block_y0 = bounds.y0;
        let mut write_block = |data: &mut Vec<u8>, y0: u32| -> exr::error::UnitResult {
            let lines = data.len() / bytes_per_line;
            let relative_y = (y0 - bounds.y0) as usize;
            let block = UncompressedBlock {
                index: BlockIndex {
                    layer: 0,
                    pixel_position: Vec2(0, relative_y),
                    pixel_size: Vec2(width, lines),
                    level: Vec2(0, 0),
                },
                data: std::mem::take(data),
            };
            chunks.write_chunk(
                relative_y / lines_per_block,
                block.compress_to_chunk(&headers)?,
            )
        };
        let mut add = |block: &Block| -> Result<(), OutputError> {
            let rows = block.colours.len() / width.max(1);
            for r in 0..rows {
                for (_, _, value) in &channels {
                    for x in 0..width {
                        data.extend_from_slice(&value(block, r * width + x));
                    }
                }
                if data.len() == bytes_per_line * lines_per_block {
                    write_block(&mut data, block_y0).map_err(err)?;
                    block_y0 += lines_per_block as u32;
                }
            }
            Ok(())
        };
        let finish = produce(&mut add);
        let keep = matches!(finish, Ok(Finish::Keep));
        produced = Some(finish);
        if !keep {
            return Err(exr::error::Error::Aborted);
        }
        if !data.is_empty() {
            write_block(&mut data, block_y0)?;
        }
        Ok(())
    });
    match produced {
        Some(Ok(Finish::Keep)) => {
            written.map_err(err)?;
            sort_header(file).map_err(|e| OutputError::write(path, e))?;
            Ok(Finish::Keep)
        }
        Some(finish) => finish,
        None => Err(err(written.expect_err("the header failed")).into()),
    }
}

/// Puts the header attributes of the single-part OpenEXR file written so far in name order,
/// as OpenEXR's own library writes them. The exr crate writes custom attributes in `HashMap`
/// order, which changes from run to run; reordering keeps the header's length, so the chunk
/// offsets stay valid.
fn sort_header(file: &mut AtomicFile) -> std::io::Result<()> {
    let file = file.written()?;
    let mut bytes = Vec::new();
    let mut want = 1 << 16;
    let sorted = loop {
        bytes.clear();
        file.seek(SeekFrom::Start(0))?;
        Read::by_ref(file).take(want).read_to_end(&mut bytes)?;
        if let Some(sorted) = sorted_attributes(&bytes) {
            break sorted;
        }
        if (bytes.len() as u64) < want {
            return Err(std::io::Error::other(
                "the OpenEXR header written is incomplete",
            ));
        }
        want *= 4;
    };
    file.seek(SeekFrom::Start(HEADER_START as u64))?;
    file.write_all(&sorted)?;
    file.seek(SeekFrom::End(0))?;
    Ok(())
}

/// Where the attributes start: after the magic number and the version field.
const HEADER_START: usize = 8;

/// The attribute records of the header at the start of `bytes`, sorted by name; `None` if
/// `bytes` ends before the header does.
fn sorted_attributes(bytes: &[u8]) -> Option<Vec<u8>> {
    let mut records: Vec<(&[u8], &[u8])> = Vec::new();
    let mut pos = HEADER_START;
    while *bytes.get(pos)? != 0 {
        let name_end = pos + bytes.get(pos..)?.iter().position(|&b| b == 0)?;
        let type_end = name_end + 1 + bytes.get(name_end + 1..)?.iter().position(|&b| b == 0)?;
        let size = bytes.get(type_end + 1..type_end + 5)?;
        let end = type_end + 5 + u32::from_le_bytes(size.try_into().ok()?) as usize;
        records.push((&bytes[pos..name_end], bytes.get(pos..end)?));
        pos = end;
    }
    records.sort_by_key(|record| record.0);
    Some(
        records
            .iter()
            .flat_map(|record| record.1.iter().copied())
            .collect(),
    )
}
