//! What a production job is made of, from what the command line asks for: the part of the image
//! (`--tile K/N` or `--pixel-bounds`) and of the samples (`--samples A..B`), checkpointing
//! (`--checkpoint-interval`, `--resume`) and what the output records; and the signals a job
//! obeys. Errors name the command line's options.

use std::ops::Range;
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::AtomicUsize;
use std::time::Duration;

use super::{Checkpointing, Job, Signals, tile_rows};
use crate::io::{AovSelection, Provenance};
use crate::render::PixelBounds;
use crate::scene::RenderSettings;

/// The part of a render a job makes; `None`s are all of it.
#[derive(Debug, Clone, Default)]
pub struct Part {
    /// Horizontal strip K of N (0-based).
    pub tile: Option<(u32, u32)>,
    /// A rectangle of pixels (with no tile).
    pub pixels: Option<PixelBounds>,
    /// A rectangle of pixels written as a picture of its own, not a part (with no tile, pixels
    /// or samples).
    pub crop: Option<PixelBounds>,
    /// Samples A to B − 1 of each pixel's sequence.
    pub samples: Option<Range<u32>>,
}

/// How often a job saves a checkpoint (`None`: only when stopped or asked to), and whether it
/// resumes from one; `None` for no checkpoints.
#[derive(Debug, Clone, Copy, Default)]
pub struct Checkpoints {
    pub interval: Option<f64>,
    pub resume: bool,
}

impl Job {
    /// The job of rendering `part` of the render `settings` describe into `output`, with
    /// `checkpoints`, recording the scene's hash `scene` and the AOVs `aovs`.
    pub fn plan(
        output: PathBuf,
        settings: &RenderSettings,
        part: &Part,
        checkpoints: Checkpoints,
        scene: String,
        aovs: AovSelection,
    ) -> Result<Job, String> {
        let s = settings;
        let full = PixelBounds::full(s.width, s.height);
        let bounds = match (part.tile, part.pixels.or(part.crop)) {
            (Some((k, n)), _) => {
                if n > s.height {
                    return Err(format!(
                        "--tile {k}/{n}: an image {} rows high cannot be cut into {n} strips",
                        s.height
                    ));
                }
                let rows = tile_rows(k, n, s.height);
                PixelBounds {
                    y0: rows.start,
                    y1: rows.end,
                    ..full
                }
            }
            (None, Some(b)) if !full.contains(&b) => {
                let option = if part.crop.is_some() {
                    "--crop"
                } else {
                    "--pixel-bounds"
                };
                return Err(format!(
                    "{option} {b} is not within the {}x{} image",
                    s.width, s.height
                ));
            }
            (None, Some(b)) => b,
            (None, None) => full,
        };
        let samples = match &part.samples {
            Some(r) if r.end > s.spp => {
                return Err(format!(
                    "--samples {}..{} goes beyond the {} samples per pixel of the render (--spp)",
                    r.start, r.end, s.spp
                ));
            }
            Some(r) => r.clone(),
            None => 0..s.spp,
        };
        let checkpointing = match (checkpoints.interval, checkpoints.resume) {
            // A millisecond to about 32 years: what a Duration holds, and more than a render
            // takes.
            (Some(i), _) if !(1e-3..=1e9).contains(&i) => {
                let shown = if i.abs() < 1e15 {
                    i.to_string()
                } else {
                    format!("{i:e}")
                };
                return Err(format!(
                    "--checkpoint-interval must be from 0.001 to 1000000000 seconds, got {shown}"
                ));
            }
            (None, false) => None,
            (interval, resume) => Some(Checkpointing {
                interval: interval.map(Duration::from_secs_f64),
                resume,
            }),
        };
        Ok(Job {
            output,
            provenance: Provenance {
                width: s.width,
                height: s.height,
                // Asked for a part, a part it is (to be merged), even if it is all of the image.
                sums: part.tile.is_some() || part.pixels.is_some() || part.samples.is_some(),
                bounds,
                spp: s.spp,
                samples,
                seed: s.seed,
                scene,
                aovs,
                object_names: Vec::new(),
                exposure: s.exposure,
                png_transfer: s.png_transfer,
            },
            checkpointing,
        })
    }

    /// What part of the whole render of `settings` the job is: " (pixels x0,x1,y0,y1)" and
    /// " (samples A..B)", each empty where the part is the whole.
    pub fn part_names(&self, settings: &RenderSettings) -> (String, String) {
        let p = &self.provenance;
        let pixels = match p.bounds == PixelBounds::full(settings.width, settings.height) {
            true => String::new(),
            false => format!(" (pixels {})", p.bounds),
        };
        let samples = match p.count() == settings.spp {
            true => String::new(),
            false => format!(" (samples {}..{})", p.samples.start, p.samples.end),
        };
        (pixels, samples)
    }
}

/// Signals a render obeys. SIGUSR1 (a scheduler's warning that time runs out) asks for a
/// checkpoint: handled from the start, so that it does not end the process while the scene
/// loads. SIGINT and SIGTERM stop a production job ([`Signals::stop`]; a second one ends the
/// process at once), handled by [`Stopping::handle`] once the render is known to be one; the
/// number of the stopping signal is kept for the exit code. One serves every frame of a movie.
pub struct Stopping {
    pub signals: Signals,
    which: Arc<AtomicUsize>,
    handled: std::sync::atomic::AtomicBool,
}

impl Stopping {
    pub fn new() -> std::io::Result<Stopping> {
        let signals = Signals::default();
        signal_hook::flag::register(signal_hook::consts::SIGUSR1, signals.checkpoint.clone())?;
        Ok(Stopping {
            signals,
            which: Arc::new(AtomicUsize::new(0)),
            handled: Default::default(),
        })
    }

    /// Stops on SIGINT and SIGTERM from now on (the handlers are installed once).
    pub fn handle(&self) -> std::io::Result<()> {
        use signal_hook::consts::{SIGINT, SIGTERM};
        use signal_hook::flag;
        use std::sync::atomic::Ordering::Relaxed;
        if self.handled.load(Relaxed) {
            return Ok(());
        }
        let stop = &self.signals.stop;
        for signal in [SIGINT, SIGTERM] {
            flag::register_conditional_shutdown(signal, 128 + signal, stop.clone())?;
            flag::register(signal, stop.clone())?;
            flag::register_usize(signal, self.which.clone(), signal as usize)?;
        }
        self.handled.store(true, Relaxed);
        Ok(())
    }

    /// The exit code of a process the signal that stopped the job ended: 128 + its number, as
    /// shells report it.
    pub fn exit_code(&self) -> u8 {
        128 + self
            .which
            .load(std::sync::atomic::Ordering::Relaxed)
            .min(127) as u8
    }
}
