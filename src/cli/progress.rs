//! How the `timbre` command shows progress: a spinner while a scene loads and its BVH is
//! built, and `--progress json` lines for schedulers and logs.

use std::io::IsTerminal;
use std::time::Instant;

use indicatif::{ProgressBar, ProgressFinish};
use serde::Serialize;

/// One `--progress json` line: pixels done of all (of every view), the fraction done, the
/// seconds since rendering started and the estimated seconds left (none before any pixel).
#[derive(Serialize)]
pub struct ProgressLine {
    pub done_pixels: u64,
    pub total_pixels: u64,
    pub fraction: f64,
    pub elapsed_s: f64,
    pub eta_s: Option<f64>,
}

/// Progress as JSON lines: at the start, at most one a second, and at the end.
pub struct JsonProgress {
    pub total: u64,
    pub start: Instant,
    /// Pixels done, and when the last line was printed.
    pub state: std::sync::Mutex<(u64, Instant)>,
}

impl JsonProgress {
    pub fn new(total: u64) -> JsonProgress {
        let start = Instant::now();
        let progress = JsonProgress {
            total,
            start,
            state: std::sync::Mutex::new((0, start)),
        };
        progress.print(0);
        progress
    }

    pub fn add(&self, pixels: u64) {
        let mut state = self.state.lock().unwrap_or_else(|e| e.into_inner());
        state.0 += pixels;
        if state.0 >= self.total || state.1.elapsed().as_secs_f64() >= 1.0 {
            self.print(state.0);
            state.1 = Instant::now();
        }
    }

    fn print(&self, done: u64) {
        use std::io::Write as _;
        let elapsed = self.start.elapsed().as_secs_f64();
        let line = ProgressLine {
            done_pixels: done,
            total_pixels: self.total,
            fraction: done as f64 / self.total.max(1) as f64,
            elapsed_s: elapsed,
            eta_s: (done > 0).then(|| elapsed * (self.total - done) as f64 / done as f64),
        };
        if let Ok(text) = serde_json::to_string(&line) {
            let _ = writeln!(std::io::stderr(), "{text}");
        }
    }
}

/// A spinner saying what is going on (loading meshes, building the BVH can take seconds), on a
/// terminal only.
pub fn spinner(quiet: bool, message: &'static str) -> ProgressBar {
    if quiet || !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    // Cleared also when dropped early, by an error.
    let spinner = ProgressBar::new_spinner().with_finish(ProgressFinish::AndClear);
    spinner.set_message(message);
    spinner.enable_steady_tick(std::time::Duration::from_millis(100));
    spinner
}
