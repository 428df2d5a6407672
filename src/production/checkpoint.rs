//! Checkpoints: the finished work of a render, kept beside its output in a directory
//! `OUTPUT.checkpoint/`, one part file per group of [`GROUP`] rows (`rows-Y.exr`, Y its first
//! row): each pixel's exact sums and its AOVs, with the render's provenance. Every file is
//! written crash-safely, so a checkpoint is always a set of whole groups; a render resumed
//! from it adds what is missing — rows not yet rendered, samples beyond those kept — and comes
//! out exactly as if it had never stopped.

use std::collections::BTreeMap;
use std::ops::Range;
use std::path::{Path, PathBuf};

use super::JobError;
use crate::io::{self, Finish, Provenance, read_part};
use crate::render::{PixelBounds, Rows};

/// Rows per checkpoint file (a multiple of the render's bands), counted from the top of the
/// rendered bounds.
pub const GROUP: u32 = 32;

/// The checkpoint directory of an output file.
pub fn directory(output: &Path) -> PathBuf {
    let mut name = output.as_os_str().to_owned();
    name.push(".checkpoint");
    PathBuf::from(name)
}

/// The first row of the group a checkpoint file holds, from its name (`rows-Y.exr`).
fn group_row(path: &Path) -> Option<u32> {
    let name = path.file_name()?.to_str()?;
    name.strip_prefix("rows-")?
        .strip_suffix(".exr")?
        .parse()
        .ok()
}

/// Whether the directory `dir` holds any saved group.
pub fn has_groups(dir: &Path) -> bool {
    std::fs::read_dir(dir)
        .is_ok_and(|entries| entries.flatten().any(|e| group_row(&e.path()).is_some()))
}

/// A group kept in a checkpoint: its file and the samples it holds.
#[derive(Debug, Clone)]
pub struct Kept {
    pub path: PathBuf,
    pub samples: Range<u32>,
}

/// The groups of a checkpoint that a render with `expected` provenance can continue, by first
/// row; the checkpoint's stale temporary files are removed first ([`crate::files`]). Files of another scene, size, seed, version or sampling are refused, naming the
/// difference.
pub fn load(dir: &Path, expected: &Provenance) -> Result<BTreeMap<u32, Kept>, JobError> {
    // Temporary files of a run killed while it saved a group.
    crate::files::remove_all_stale(dir);
    let mut kept = BTreeMap::new();
    let unreadable = |e: std::io::Error| JobError::Checkpoint {
        path: dir.display().to_string(),
        message: format!("cannot be read: {e}"),
    };
    for entry in std::fs::read_dir(dir).map_err(unreadable)? {
        let path = entry.map_err(unreadable)?.path();
        let Some(y0) = group_row(&path) else {
            continue; // temporary files of an interrupted write, and anything else
        };
        let part = read_part(&path).map_err(JobError::Part)?;
        let refuse = |message: String| JobError::Checkpoint {
            path: path.display().to_string(),
            message,
        };
        super::compare(&part.provenance, &part.version, expected)
            .map_err(|m| refuse(format!("is a checkpoint of another render: {m}")))?;
        let (got, want) = (&part.provenance, expected);
        let b = want.bounds;
        let rows = PixelBounds {
            x0: b.x0,
            x1: b.x1,
            y0,
            y1: (y0 + GROUP).min(b.y1),
        };
        if got.bounds != rows || y0 < b.y0 || (y0 - b.y0) % GROUP != 0 {
            return Err(refuse(format!(
                "holds pixels {} where this render's group at row {y0} is {rows} of {b}",
                got.bounds
            )));
        }
        if got.spp != want.spp && (got.spp == 1 || want.spp == 1) {
            return Err(refuse(format!(
                "was rendered with {} sample(s) per pixel and this render has {}: a single \
                 sample goes through each pixel centre, several are spread over the pixel, so \
                 one cannot continue the other",
                got.spp, want.spp
            )));
        }
        if got.samples.start != want.samples.start {
            return Err(refuse(format!(
                "holds samples from {}, this render's start at {} (--samples)",
                got.samples.start, want.samples.start
            )));
        }
        if got.samples.end > want.samples.end {
            return Err(refuse(format!(
                "holds samples {}..{}, more than this render's {}..{} (--spp, --samples)",
                got.samples.start, got.samples.end, want.samples.start, want.samples.end
            )));
        }
        kept.insert(
            y0,
            Kept {
                path,
                samples: got.samples.clone(),
            },
        );
    }
    Ok(kept)
}

/// Reads the rows of a kept group.
pub fn read(kept: &Kept) -> Result<Rows, JobError> {
    let mut part = read_part(&kept.path).map_err(JobError::Part)?;
    let b = part.provenance.bounds;
    let mut all = Rows::new(b.x0, b.x1, b.y0, b.y1, part.provenance.aovs.any());
    while let Some(rows) = part.next_rows().map_err(JobError::Part)? {
        all.copy_rows(&rows);
    }
    Ok(all)
}

/// Writes a finished group (crash-safely) into the checkpoint directory `dir`.
pub fn save(dir: &Path, rows: &Rows, provenance: &Provenance) -> Result<(), JobError> {
    let path = dir.join(format!("rows-{}.exr", rows.bounds.y0));
    let count = provenance.count();
    let colours: Vec<_> = rows.sums.iter().map(|s| s.mean(count)).collect();
    let provenance = Provenance {
        bounds: rows.bounds,
        sums: true,
        ..provenance.clone()
    };
    io::write_streaming(&path, &provenance, |write| {
        write(&io::Block {
            y0: rows.bounds.y0,
            colours: &colours,
            aovs: rows.aovs.as_deref(),
            sums: Some(&rows.sums),
        })?;
        Ok::<_, JobError>(Finish::Keep)
    })
    .map(drop)
}

/// Removes a finished render's checkpoint (its files, then the directory).
pub fn remove(dir: &Path) -> std::io::Result<()> {
    match std::fs::remove_dir_all(dir) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(()),
        other => other,
    }
}
