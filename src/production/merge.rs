//! `timbre merge`: parts of one render (rectangles of the image, ranges of its samples, as
//! written with `--tile`, `--pixel-bounds` and `--samples`) assembled into the whole image.
//! Each pixel's exact sums are added over the parts that hold it, so the result is bit for bit
//! the single render's. The parts must make up the image exactly: every sample of every pixel
//! in exactly one part, all of the same scene, size and sampling. Rows are streamed: memory
//! grows with the image's width and the number of parts, not with the image.

use std::path::Path;

use super::{JobError, compare};
use crate::io::{self, Block, Finish, PartReader, Provenance, read_part};
use crate::render::{BAND, PixelBounds, Rows};

/// What a merge put together.
#[derive(Debug, Clone, PartialEq)]
pub struct Merged {
    pub width: u32,
    pub height: u32,
    pub spp: u32,
    pub parts: usize,
}

/// The boundaries of the cells the parts cut an axis into.
fn cuts(bounds: &[PixelBounds], size: u32, edges: fn(&PixelBounds) -> [u32; 2]) -> Vec<u32> {
    let mut cuts: Vec<u32> = bounds.iter().flat_map(edges).chain([0, size]).collect();
    cuts.sort_unstable();
    cuts.dedup();
    cuts
}

/// Checks that the parts hold every sample of every pixel exactly once; the message names the
/// pixels and samples missing or held twice.
fn check_coverage(
    parts: &[(String, Provenance)],
    width: u32,
    height: u32,
    spp: u32,
) -> Result<(), String> {
    let bounds: Vec<PixelBounds> = parts.iter().map(|(_, p)| p.bounds).collect();
    let xs = cuts(&bounds, width, |b| [b.x0, b.x1]);
    let ys = cuts(&bounds, height, |b| [b.y0, b.y1]);
    for y in ys.windows(2) {
        for x in xs.windows(2) {
            let cell = PixelBounds {
                x0: x[0],
                x1: x[1],
                y0: y[0],
                y1: y[1],
            };
            let mut holding: Vec<&(String, Provenance)> = parts
                .iter()
                .filter(|(_, p)| p.bounds.contains(&cell))
                .collect();
            holding.sort_by_key(|(_, p)| p.samples.start);
            let mut next = 0;
            let mut previous: Option<&str> = None;
            for (name, p) in holding {
                if p.samples.start < next {
                    return Err(format!(
                        "{name} and {} overlap: both hold samples {}..{} of pixels {cell} \
                         (x0,x1,y0,y1)",
                        previous.unwrap_or("another part"),
                        p.samples.start,
                        next.min(p.samples.end)
                    ));
                }
                if p.samples.start > next {
                    break;
                }
                next = p.samples.end;
                previous = Some(name);
            }
            if next < spp {
                return Err(format!(
                    "a gap: no part holds samples {next}..{spp} of pixels {cell} (x0,x1,y0,y1)"
                ));
            }
        }
    }
    Ok(())
}

/// A part being read, with the rows of its current block.
struct Open {
    reader: PartReader,
    rows: Option<Rows>,
}

impl Open {
    /// The part's rows holding row `y` (reading on as needed; rows come top to bottom).
    fn rows_at(&mut self, y: u32) -> Result<&Rows, JobError> {
        while self.rows.as_ref().is_none_or(|r| r.bounds.y1 <= y) {
            self.rows = Some(
                self.reader
                    .next_rows()?
                    .ok_or_else(|| JobError::Merge(format!("a part ended before row {y}")))?,
            );
        }
        Ok(self.rows.as_ref().expect("read"))
    }
}

/// Merges the parts at `paths` into the image at `output` (PNG or OpenEXR); see the module
/// docs. Nothing is written unless the parts make up the image.
pub fn merge(output: &Path, paths: &[&Path]) -> Result<Merged, JobError> {
    if paths.is_empty() {
        return Err(JobError::Merge("no parts to merge".into()));
    }
    let mut open = Vec::new();
    for path in paths {
        let reader = read_part(path)?;
        open.push(Open { reader, rows: None });
    }
    let first = open[0].reader.provenance.clone();
    let named: Vec<(String, Provenance)> = paths
        .iter()
        .zip(&open)
        .map(|(path, o)| (path.display().to_string(), o.reader.provenance.clone()))
        .collect();
    for ((name, p), o) in named.iter().zip(&open) {
        compare(p, &o.reader.version, &first).map_err(|m| {
            JobError::Merge(format!(
                "{name} is not a part of the same render as {}: {m}",
                named[0].0
            ))
        })?;
        if p.exposure != first.exposure {
            return Err(JobError::Merge(format!(
                "{name} was written with an exposure of {} stops, {} with {}",
                p.exposure, named[0].0, first.exposure
            )));
        }
        if p.spp != first.spp {
            return Err(JobError::Merge(format!(
                "{name} is a part of a render of {} samples per pixel, {} of {}",
                p.spp, named[0].0, first.spp
            )));
        }
    }
    let (width, height, spp) = (first.width, first.height, first.spp);
    check_coverage(&named, width, height, spp).map_err(JobError::Merge)?;
    let provenance = Provenance {
        bounds: PixelBounds::full(width, height),
        samples: 0..spp,
        sums: false,
        ..first
    };
    let aovs = provenance.aovs.any();
    io::write_streaming(output, &provenance, |write| {
        for y0 in (0..height).step_by(BAND as usize) {
            let y1 = (y0 + BAND).min(height);
            let mut rows = Rows::new(0, width, y0, y1, aovs);
            for y in y0..y1 {
                for part in open.iter_mut() {
                    let b = part.reader.provenance.bounds;
                    if !(b.y0..b.y1).contains(&y) {
                        continue;
                    }
                    rows.add_row(part.rows_at(y)?, y);
                }
            }
            let colours: Vec<_> = rows.sums.iter().map(|s| s.mean(spp)).collect();
            write(&Block {
                y0,
                colours: &colours,
                aovs: rows.aovs.as_deref(),
                sums: None,
            })?;
        }
        Ok::<_, JobError>(Finish::Keep)
    })?;
    Ok(Merged {
        width,
        height,
        spp,
        parts: paths.len(),
    })
}
