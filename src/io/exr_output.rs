//! OpenEXR output: one part with f32 channels R, G, B and, when rendered, the AOV layers
//! `depth.Z`, `normal.X/Y/Z` and `object.id` that are selected. The header records the samples
//! per pixel (`timbre.spp`), the seed (`timbre.seed`), the timbre version (`timbre.version`)
//! and, with `object.id`, the object names by id (`timbre.objects`).

use std::path::Path;

use exr::prelude::*;

use super::{OutputError, Provenance};
use crate::render::Image as Rendered;

pub fn write_exr(
    path: &Path,
    image: &Rendered,
    provenance: &Provenance,
) -> std::result::Result<(), OutputError> {
    let err = |source| OutputError::Exr {
        path: path.display().to_string(),
        source,
    };
    let channel = |name: &str, values: Vec<f32>| AnyChannel::new(name, FlatSamples::F32(values));
    let rgb = |k: usize| {
        image
            .pixels
            .iter()
            .map(|c| c[k] as f32)
            .collect::<Vec<f32>>()
    };
    let mut channels = vec![
        channel("R", rgb(0)),
        channel("G", rgb(1)),
        channel("B", rgb(2)),
    ];
    if let Some(a) = &image.aovs {
        let selected = provenance.aovs;
        if selected.depth {
            channels.push(channel("depth.Z", a.iter().map(|s| s.depth).collect()));
        }
        if selected.normal {
            for (k, axis) in ["X", "Y", "Z"].iter().enumerate() {
                let values = a.iter().map(|s| s.normal[k]).collect();
                channels.push(channel(&format!("normal.{axis}"), values));
            }
        }
        if selected.object {
            channels.push(channel("object.id", a.iter().map(|s| s.object).collect()));
        }
    }
    // EXR strings are byte strings; timbre writes UTF-8 (exr's `Text::from` takes Latin-1 only
    // and panics on other characters).
    let utf8_text = |s: &str| Text::from_bytes_unchecked(SmallVec::from_slice(s.as_bytes()));
    let mut attributes = LayerAttributes::default();
    let mut note =
        |key: &str, value: AttributeValue| attributes.other.insert(Text::from(key), value);
    note(
        "timbre.spp",
        AttributeValue::I32(provenance.spp.min(i32::MAX as u32) as i32),
    );
    note(
        "timbre.seed",
        AttributeValue::Text(Text::from(provenance.seed.to_string().as_str())),
    );
    note(
        "timbre.version",
        AttributeValue::Text(Text::from(env!("CARGO_PKG_VERSION"))),
    );
    if provenance.aovs.object && image.aovs.is_some() {
        let names = provenance
            .object_names
            .iter()
            .map(|n| utf8_text(n))
            .collect();
        note("timbre.objects", AttributeValue::TextVector(names));
    }
    // Tiles are compressed in parallel; with increasing line order the writer stores them in
    // order, so the file does not depend on which tile finished first.
    let encoding = Encoding {
        line_order: LineOrder::Increasing,
        ..Encoding::FAST_LOSSLESS
    };
    let layer = Layer::new(
        (image.width as usize, image.height as usize),
        attributes,
        encoding,
        AnyChannels::sort(SmallVec::from_vec(channels)),
    );
    let mut file = std::io::Cursor::new(Vec::new());
    exr::image::Image::from_layer(layer)
        .write()
        .to_buffered(&mut file)
        .map_err(err)?;
    let mut bytes = file.into_inner();
    sort_header_attributes(&mut bytes);
    crate::files::write_atomically(path, |out| out.write_all(&bytes)).map_err(|source| {
        OutputError::Write {
            path: path.display().to_string(),
            source,
        }
    })
}

/// Puts the header attributes of a single-part OpenEXR file in name order, as OpenEXR's own
/// library writes them. The exr crate writes custom attributes in `HashMap` order, which changes
/// from run to run; reordering keeps the header's length, so the chunk offsets stay valid.
fn sort_header_attributes(bytes: &mut [u8]) -> Option<()> {
    const START: usize = 8; // after the magic number and the version field
    let mut records: Vec<(&[u8], &[u8])> = Vec::new();
    let mut pos = START;
    while *bytes.get(pos)? != 0 {
        let name_end = pos + bytes[pos..].iter().position(|&b| b == 0)?;
        let type_end = name_end + 1 + bytes[name_end + 1..].iter().position(|&b| b == 0)?;
        let size = bytes.get(type_end + 1..type_end + 5)?;
        let end = type_end + 5 + u32::from_le_bytes(size.try_into().ok()?) as usize;
        records.push((&bytes[pos..name_end], bytes.get(pos..end)?));
        pos = end;
    }
    records.sort_by_key(|record| record.0);
    let sorted: Vec<u8> = records
        .iter()
        .flat_map(|record| record.1.iter().copied())
        .collect();
    bytes[START..pos].copy_from_slice(&sorted);
    Some(())
}
