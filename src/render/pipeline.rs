//! The render loop: worker threads render tiles of the image in any order; the calling thread
//! receives them, puts them back in order and hands over whole bands of rows, top to bottom, as
//! they complete. Workers stay at most a small window of tiles ahead of the oldest tile not yet
//! handed over, so memory is bounded by the image's width, not its size.

use std::collections::BTreeMap;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::mpsc;
use std::sync::{Condvar, Mutex};
use std::time::Duration;

use super::{AovSample, BAND, PixelBounds, Rows, Sum};
use crate::math::Colour;

/// Columns per tile (a multiple of the ray packets' width): a tile is big enough (16 Ki
/// pixels) that handing it over costs little, and bands of images up to this wide are one
/// tile, handed on without a copy.
pub const TILE_W: u32 = 2048;

/// A rendered tile: its means, sums (if kept) and AOVs, row-major, and the rays traced.
pub(super) struct Tile {
    pub sums: Vec<Sum>,
    pub means: Vec<Colour>,
    pub aovs: Option<Vec<AovSample>>,
    pub rays: u64,
}

/// How far a render got.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Outcome {
    /// Rays traced in the bands handed over.
    pub rays: u64,
    /// Whether every band was handed over (false when stopped early).
    pub complete: bool,
}

/// The tiles of `bounds`: bands of BAND rows from the top, each split into tiles of TILE_W
/// columns; tile `i` is band `i / per_band`, column tile `i % per_band`.
struct Tiling {
    bounds: PixelBounds,
    per_band: u64,
    count: u64,
}

impl Tiling {
    fn new(bounds: PixelBounds) -> Tiling {
        let per_band = bounds.width().div_ceil(TILE_W) as u64;
        let bands = bounds.height().div_ceil(BAND) as u64;
        Tiling {
            bounds,
            per_band,
            count: per_band * bands,
        }
    }

    /// The pixels of tile `i`.
    fn tile(&self, i: u64) -> PixelBounds {
        let b = &self.bounds;
        let (band, column) = ((i / self.per_band) as u32, (i % self.per_band) as u32);
        let x0 = b.x0 + column * TILE_W;
        let y0 = b.y0 + band * BAND;
        PixelBounds {
            x0,
            x1: (x0 + TILE_W).min(b.x1),
            y0,
            y1: (y0 + BAND).min(b.y1),
        }
    }
}

/// Renders the tiles of `bounds` with `render_tile` (bands have AOVs if `aovs`) on `threads` threads of `stack` bytes and
/// hands the finished bands, in order, to `sink`. Stops early, after the bands in flight,
/// when `stop` is set or `sink` fails (its error is returned). Fails only if a thread cannot
/// be started.
pub(super) fn run<E: Send>(
    bounds: PixelBounds,
    threads: usize,
    stack: usize,
    aovs: bool,
    stop: &AtomicBool,
    render_tile: &(dyn Fn(PixelBounds) -> Tile + Sync),
    sink: &mut dyn FnMut(Rows) -> Result<(), E>,
) -> std::io::Result<Result<Outcome, E>> {
    let tiling = Tiling::new(bounds);
    let window = 8 * threads.max(2) as u64;
    let next = AtomicU64::new(0);
    // Tiles handed over so far, and the condition workers wait on to move their window.
    let handed = Mutex::new(0u64);
    let moved = Condvar::new();
    let failed = AtomicBool::new(false);
    let halt = || stop.load(Ordering::Relaxed) || failed.load(Ordering::Relaxed);
    std::thread::scope(|scope| -> std::io::Result<Result<Outcome, E>> {
        let (send, receive) = mpsc::channel::<(u64, Tile)>();
        // Workers already started stop if another cannot be.
        let stopped = |e| {
            failed.store(true, Ordering::Relaxed);
            e
        };
        for _ in 0..threads.max(1) {
            let send = send.clone();
            let (next, handed, moved, tiling, halt) = (&next, &handed, &moved, &tiling, &halt);
            std::thread::Builder::new()
                .stack_size(stack)
                .spawn_scoped(scope, move || {
                    loop {
                        if halt() {
                            return;
                        }
                        let i = next.fetch_add(1, Ordering::Relaxed);
                        if i >= tiling.count {
                            return;
                        }
                        let mut done = handed.lock().unwrap_or_else(|e| e.into_inner());
                        while i >= *done + window && !halt() {
                            // With a timeout: a stop is noticed even if no tile moves on.
                            done = moved
                                .wait_timeout(done, Duration::from_millis(20))
                                .unwrap_or_else(|e| e.into_inner())
                                .0;
                        }
                        drop(done);
                        if halt() {
                            return;
                        }
                        if send.send((i, render_tile(tiling.tile(i)))).is_err() {
                            return;
                        }
                    }
                })
                .map_err(stopped)?;
        }
        drop(send);
        let mut waiting = BTreeMap::new();
        let mut expected = 0u64;
        let mut band: Option<Rows> = None;
        let mut rays = 0;
        let mut result = Ok(());
        // Ends when every worker has finished (and dropped its sender).
        for (i, tile) in receive.iter() {
            if result.is_err() {
                continue;
            }
            waiting.insert(i, tile);
            while let Some(tile) = waiting.remove(&expected) {
                let at = tiling.tile(expected);
                if tiling.per_band == 1 {
                    // (A band kept from a checkpoint has no AOVs rendered: they come later.)
                    let n = tile.means.len();
                    band = Some(Rows {
                        bounds: at,
                        sums: tile.sums,
                        means: tile.means,
                        aovs: tile.aovs.or_else(|| aovs.then(|| vec![AovSample::MISS; n])),
                        rays: tile.rays,
                    });
                } else {
                    let rows = band.get_or_insert_with(|| {
                        let rows = PixelBounds {
                            x0: bounds.x0,
                            x1: bounds.x1,
                            ..at
                        };
                        Rows::rendered(rows, !tile.sums.is_empty(), aovs)
                    });
                    rows.insert(at, &tile);
                    rows.rays += tile.rays;
                }
                expected += 1;
                if at.x1 == bounds.x1 {
                    let rows = band.take().expect("a band in progress");
                    let band_rays = rows.rays;
                    if let Err(e) = sink(rows) {
                        failed.store(true, Ordering::Relaxed);
                        result = Err(e);
                        break;
                    }
                    rays += band_rays;
                }
                *handed.lock().unwrap_or_else(|e| e.into_inner()) = expected;
                moved.notify_all();
            }
        }
        moved.notify_all();
        Ok(result.map(|()| Outcome {
            rays,
            complete: expected == tiling.count,
        }))
    })
}
