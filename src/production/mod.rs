//! Production renders: a single-view render streamed to its output in bounded memory, optionally
//! as a part of the image (pixel bounds, a range of samples) to be merged with others, with
//! checkpoints it can be resumed from ([`checkpoint`]), and the merging of parts ([`merge()`]).
//!
//! Every pixel's samples are summed exactly ([`crate::render::Sum`]), so parts and checkpoints
//! add up to the same bits as one uninterrupted render.

pub mod checkpoint;
pub mod merge;
pub mod plan;

use std::ops::Range;
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use thiserror::Error;

use crate::cameras::Camera;
use crate::io::{self, Block, Finish, OutputError, PartError, Provenance};
use crate::math::Colour;
use crate::render::{self, PixelBounds, RenderError, Rows, Samples};
use crate::scene::{RenderSettings, Scene};

pub use merge::merge;
pub use plan::{Checkpoints, Part, Stopping};

/// Why a production render or a merge failed.
#[derive(Debug, Error)]
pub enum JobError {
    #[error(transparent)]
    Output(#[from] OutputError),
    #[error(transparent)]
    Render(#[from] RenderError),
    #[error(transparent)]
    Part(#[from] PartError),
    /// A checkpoint that cannot be continued.
    #[error("{path}: {message}")]
    Checkpoint { path: String, message: String },
    /// Parts that do not make up one image.
    #[error("{0}")]
    Merge(String),
}

/// Checkpointing of a render.
#[derive(Debug, Clone, PartialEq)]
pub struct Checkpointing {
    /// Time between checkpoints (`None`: only when signalled, and when the unsaved work grows
    /// past [`UNSAVED_LIMIT`]).
    pub interval: Option<Duration>,
    /// Continue from the checkpoint there is (if any).
    pub resume: bool,
}

/// Bytes of finished, unsaved work after which a checkpoint is written whatever the interval,
/// so that memory stays bounded.
pub const UNSAVED_LIMIT: usize = 64 << 20;

/// One render of a single view: which pixels and samples, into which file.
#[derive(Debug, Clone)]
pub struct Job {
    pub output: PathBuf,
    /// What the output holds (its bounds and samples are the part rendered).
    pub provenance: Provenance,
    pub checkpointing: Option<Checkpointing>,
}

/// Signals to a running job, set from outside (signal handlers).
#[derive(Debug, Default)]
pub struct Signals {
    /// Stop as soon as possible (saving a checkpoint, if checkpointing).
    pub stop: Arc<AtomicBool>,
    /// Save a checkpoint now, and go on.
    pub checkpoint: Arc<AtomicBool>,
}

/// Bytes a production render of an image `width` pixels wide needs at its peak, roughly
/// (generously): the bands and tiles in flight, the output's block being encoded, and with
/// checkpointing the group being gathered, the one read back and the unsaved work.
pub fn memory_needed(width: u32, threads: usize, checkpointing: bool) -> u64 {
    // Sums, AOVs and colours of a pixel, and its encoded channels (up to 20 of 4 bytes).
    const PER_PIXEL: u64 = 48 + 20 + 24 + 80;
    let rows = 2 * render::BAND as u64 + 16 + checkpointing as u64 * 2 * checkpoint::GROUP as u64;
    let tiles = 8 * threads.max(2) as u64 * render::TILE_W as u64 * render::BAND as u64;
    (rows * width as u64 + tiles) * PER_PIXEL + checkpointing as u64 * UNSAVED_LIMIT as u64
}

/// How a job ended.
#[derive(Debug, Clone, PartialEq)]
pub enum Done {
    /// The output was written.
    Written {
        rays: u64,
        /// Groups of rows taken from a checkpoint.
        resumed_groups: usize,
    },
    /// Stopped by a signal; the output was not written. The checkpoint directory, if any,
    /// holds the work done.
    Stopped { checkpoint: Option<PathBuf> },
}

/// Checks that a part (or checkpoint) written by timbre `version` with `got` belongs to the
/// same render as `want` (the same image, scene, sampling and channels); the message names the
/// first difference.
pub fn compare(got: &Provenance, version: &str, want: &Provenance) -> Result<(), String> {
    let ours = env!("CARGO_PKG_VERSION");
    if version != ours {
        return Err(format!(
            "it was written by timbre {version}, this is timbre {ours}"
        ));
    }
    if (got.width, got.height) != (want.width, want.height) {
        return Err(format!(
            "its image is {}x{}, not {}x{}",
            got.width, got.height, want.width, want.height
        ));
    }
    if got.scene != want.scene {
        return Err(format!(
            "it is of another scene or trace settings (scene hash {}, not {})",
            got.scene, want.scene
        ));
    }
    if got.seed != want.seed {
        return Err(format!("its seed is {}, not {}", got.seed, want.seed));
    }
    if got.aovs != want.aovs {
        return Err(format!(
            "its AOVs are {}, not {} (--aov)",
            got.aovs, want.aovs
        ));
    }
    Ok(())
}

/// Rows of `bounds` from `y0`, of one group (see [`checkpoint::GROUP`]).
fn group_of(bounds: &PixelBounds, y: u32) -> u32 {
    bounds.y0 + (y - bounds.y0) / checkpoint::GROUP * checkpoint::GROUP
}

/// Renders `job` (a single view of `scene` through `camera` with `settings`), streaming it to
/// its output; `progress` is told the pixels of each finished band, and `observe` its first
/// row and its pixels' values as written (row by row across the job's bounds), band after
/// band, top to bottom.
pub fn run(
    scene: &Scene,
    camera: &Camera,
    settings: &RenderSettings,
    job: &Job,
    signals: &Signals,
    progress: &dyn Fn(u64),
    observe: &mut dyn FnMut(u32, &[Colour]),
) -> Result<Done, JobError> {
    let p = &job.provenance;
    let bounds = p.bounds;
    let count = p.count();
    let dir = job
        .checkpointing
        .as_ref()
        .map(|_| checkpoint::directory(&job.output));
    let resume = job.checkpointing.as_ref().is_some_and(|c| c.resume);
    let kept = match &dir {
        Some(dir) if checkpoint::has_groups(dir) => {
            if !resume {
                return Err(JobError::Checkpoint {
                    path: dir.display().to_string(),
                    message: "a checkpoint of an earlier render is there: continue it with \
                              --resume, or delete it to start again"
                        .into(),
                });
            }
            checkpoint::load(dir, p)?
        }
        _ => Default::default(),
    };
    if let Some(dir) = &dir {
        std::fs::create_dir_all(dir).map_err(|e| JobError::Checkpoint {
            path: dir.display().to_string(),
            message: format!("cannot be created: {e}"),
        })?;
    }
    let first = |y: u32| {
        kept.get(&group_of(&bounds, y))
            .map_or(p.samples.start, |k| k.samples.end)
    };
    let samples = Samples {
        spp: p.spp,
        start: p.samples.start,
        end: p.samples.end,
        first: &first,
        sums: p.sums || dir.is_some(),
    };
    let interval = job.checkpointing.as_ref().and_then(|c| c.interval);
    let mut last_save = Instant::now();
    // The group being gathered (for the checkpoint), the one read back from the checkpoint,
    // and finished groups not yet saved.
    let mut gathering: Option<Rows> = None;
    let mut restored: Option<(u32, Rows)> = None;
    let mut unsaved: Vec<Rows> = Vec::new();
    let per_pixel = size_of::<render::Sum>() + size_of::<render::AovSample>();
    let unsaved_bytes =
        |rows: &[Rows]| rows.iter().map(|r| r.sums.len() * per_pixel).sum::<usize>();
    let save = |unsaved: &mut Vec<Rows>| -> Result<(), JobError> {
        if let Some(dir) = &dir {
            for rows in unsaved.drain(..) {
                checkpoint::save(dir, &rows, p)?;
            }
        }
        Ok(())
    };
    let mut rays = 0;
    // The colours of a band added to earlier samples, in one buffer for all.
    let mut colours = Vec::new();
    let stop = &signals.stop;
    let finish = io::write_streaming(&job.output, p, |write| {
        let mut sink = |mut rows: Rows| -> Result<(), JobError> {
            let group = group_of(&bounds, rows.bounds.y0);
            // The rendered means are the whole story unless samples are added to kept ones.
            let mut means = &rows.means;
            if let Some(k) = kept.get(&group) {
                if restored.as_ref().is_none_or(|r| r.0 != group) {
                    restored = Some((group, checkpoint::read(k)?));
                }
                let (_, from) = restored.as_ref().expect("just read");
                for y in rows.bounds.y0..rows.bounds.y1 {
                    rows.add_row(from, y);
                }
                colours.clear();
                colours.extend(rows.sums.iter().map(|s| s.mean(count)));
                means = &colours;
            }
            write(&Block {
                y0: rows.bounds.y0,
                colours: means,
                aovs: rows.aovs.as_deref(),
                sums: p.sums.then_some(&rows.sums[..]),
            })?;
            observe(rows.bounds.y0, means);
            rays += rows.rays;
            progress(rows.bounds.pixels());
            if dir.is_some() {
                // Groups kept whole (nothing added) need no saving again.
                let unchanged = kept
                    .get(&group)
                    .is_some_and(|k| k.samples.end == p.samples.end);
                let g = gathering.get_or_insert_with(|| {
                    let y1 = (group + checkpoint::GROUP).min(bounds.y1);
                    Rows::new(bounds.x0, bounds.x1, group, y1, rows.aovs.is_some())
                });
                g.copy_rows(&rows);
                if rows.bounds.y1 == g.bounds.y1 {
                    let g = gathering.take().expect("a group");
                    if !unchanged {
                        unsaved.push(g);
                    }
                }
                let due = interval.is_some_and(|i| last_save.elapsed() >= i)
                    || signals.checkpoint.swap(false, Ordering::Relaxed)
                    || unsaved_bytes(&unsaved) > UNSAVED_LIMIT;
                if due {
                    save(&mut unsaved)?;
                    last_save = Instant::now();
                }
            }
            Ok(())
        };
        let outcome =
            render::render_rows(scene, camera, settings, bounds, &samples, stop, &mut sink)??;
        Ok::<_, JobError>(if outcome.complete {
            Finish::Keep
        } else {
            Finish::Discard
        })
    })?;
    if finish == Finish::Discard {
        save(&mut unsaved)?;
        return Ok(Done::Stopped { checkpoint: dir });
    }
    if let Some(dir) = &dir {
        checkpoint::remove(dir).map_err(|e| JobError::Checkpoint {
            path: dir.display().to_string(),
            message: format!("the render is written, but its checkpoint cannot be removed: {e}"),
        })?;
    }
    Ok(Done::Written {
        rays,
        resumed_groups: kept.len(),
    })
}

/// The rows of tile `k` of `n` (0-based) of an image `height` rows high: horizontal strips
/// as even as can be.
pub fn tile_rows(k: u32, n: u32, height: u32) -> Range<u32> {
    let at = |i: u32| (i as u64 * height as u64 / n as u64) as u32;
    at(k)..at(k + 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tiles_cut_the_rows_into_strips_that_differ_by_at_most_one_row() {
        for (n, height) in [(1, 1), (3, 72), (4, 10), (7, 7), (5, 1 << 24)] {
            let strips: Vec<Range<u32>> = (0..n).map(|k| tile_rows(k, n, height)).collect();
            assert_eq!(strips[0].start, 0);
            assert_eq!(strips[n as usize - 1].end, height);
            assert!(strips.windows(2).all(|w| w[0].end == w[1].start));
            let sizes: Vec<u32> = strips.iter().map(|s| s.end - s.start).collect();
            let (min, max) = (sizes.iter().min().unwrap(), sizes.iter().max().unwrap());
            assert!(*min >= 1 && max - min <= 1, "{n} of {height}: {sizes:?}");
        }
    }
}
