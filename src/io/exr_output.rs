//! OpenEXR output: one part with f32 channels R, G, B and, when rendered, the AOV layers
//! `depth.Z`, `normal.X/Y/Z` and `object.id` that are selected. The header records the samples per pixel
//! (`timbre.spp`), the seed (`timbre.seed`) and the timbre version (`timbre.version`).

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
            channels.push(channel("depth.Z", a.depth.clone()));
        }
        if selected.normal {
            for (k, axis) in ["X", "Y", "Z"].iter().enumerate() {
                channels.push(channel(
                    &format!("normal.{axis}"),
                    a.normal.iter().map(|n| n[k]).collect(),
                ));
            }
        }
        if selected.object {
            channels.push(channel("object.id", a.object.clone()));
        }
    }
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
    let layer = Layer::new(
        (image.width as usize, image.height as usize),
        attributes,
        Encoding::FAST_LOSSLESS,
        AnyChannels::sort(SmallVec::from_vec(channels)),
    );
    exr::image::Image::from_layer(layer)
        .write()
        .to_file(path)
        .map_err(err)
}
