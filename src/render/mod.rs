//! Rendering: primary rays from the camera, traced in parallel over tiles of the image and
//! handed over in bands of whole rows, top to bottom ([`render_rows`]), or kept in memory
//! ([`render`]).

mod pipeline;
mod sampling;
pub mod shading;
mod sum;
mod tracer;

pub use pipeline::{Outcome, TILE_W};
pub use sampling::pixel_offset;
pub use sum::Sum;
pub use tracer::{Found, Tracer};

use std::sync::atomic::AtomicBool;

use glam::{DVec3, Vec3};
use thiserror::Error;

use crate::cameras::Camera;
use crate::math::random::uniform;
use crate::math::{Colour, Ray, ReferenceFrame};
use crate::scene::settings::MAX_TRACE_LEVEL_LIMIT;
use crate::scene::{RenderSettings, Scene};

/// Stack bytes a worker needs per trace level (measured about 700; generous for safety).
const STACK_PER_LEVEL: usize = 4 << 10;

/// Arbitrary output variables of the surface seen through one pixel centre.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AovSample {
    /// Distance from the camera along the ray (from its Lorentz-transformed start in the scene
    /// frame if it meets no camera-frame object); infinite where nothing is hit.
    pub depth: f32,
    /// Outward surface normal; zero where nothing is hit.
    pub normal: Vec3,
    /// Object index in the scene; −1 where nothing is hit.
    pub object: f32,
    /// The albedo (a denoiser's guide): see [`ALBEDO_SAMPLES`] and [`Tracer::albedo`]; zero
    /// unless asked for.
    pub albedo: Vec3,
}

/// The albedo AOV of a pixel is the mean over its first `min(spp, ALBEDO_SAMPLES)` samples
/// (the same in every part of a render, whichever samples the part renders).
pub const ALBEDO_SAMPLES: u32 = 16;

impl AovSample {
    pub const MISS: AovSample = AovSample {
        depth: f32::INFINITY,
        normal: Vec3::ZERO,
        object: -1.0,
        albedo: Vec3::ZERO,
    };
}

/// A rendered image: linear RGB, row-major from the top-left pixel.
#[derive(Debug, Clone, PartialEq)]
pub struct Image {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<Colour>,
    /// Per-pixel AOVs, when the settings asked for them.
    pub aovs: Option<Vec<AovSample>>,
    /// Rays traced (primary, secondary and shadow).
    pub rays: u64,
}

impl Image {
    pub fn pixel(&self, x: u32, y: u32) -> Colour {
        self.pixels[y as usize * self.width as usize + x as usize]
    }
}

/// Why a render could not run.
#[derive(Debug, Error)]
pub enum RenderError {
    #[error("could not start the render threads: {0}")]
    Threads(std::io::Error),
    /// The image's buffers could not be allocated.
    #[error(
        "not enough memory for a {width}x{height} image ({bytes} bytes of buffers); render a smaller image"
    )]
    Memory { width: u32, height: u32, bytes: u64 },
}

/// A buffer of `n` copies of `value`, or `None` where the memory cannot be had (instead of
/// aborting the process).
fn buffer<T: Clone>(n: usize, value: T) -> Option<Vec<T>> {
    let mut v = Vec::new();
    v.try_reserve_exact(n).ok()?;
    v.resize(n, value);
    Some(v)
}

/// Rows per band: the image is handed over in bands of whole rows, from the top of the bounds.
/// A multiple of BLOCK_H.
pub const BAND: u32 = 8;

/// Primary rays are traced in packets of BLOCK_W × BLOCK_H neighbouring pixels (8 = Embree's
/// native AVX2 packet width).
const BLOCK_W: u32 = 4;
const BLOCK_H: u32 = 2;

/// A rectangle of pixels of the full image: columns `x0..x1` and rows `y0..y1` (half-open, as
/// pbrt's `--pixelbounds`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PixelBounds {
    pub x0: u32,
    pub x1: u32,
    pub y0: u32,
    pub y1: u32,
}

impl PixelBounds {
    /// All pixels of a `width` × `height` image.
    pub fn full(width: u32, height: u32) -> PixelBounds {
        PixelBounds {
            x0: 0,
            x1: width,
            y0: 0,
            y1: height,
        }
    }

    pub fn width(&self) -> u32 {
        self.x1 - self.x0
    }

    pub fn height(&self) -> u32 {
        self.y1 - self.y0
    }

    pub fn pixels(&self) -> u64 {
        self.width() as u64 * self.height() as u64
    }

    /// Whether there are no pixels inside.
    pub fn is_empty(&self) -> bool {
        self.x0 >= self.x1 || self.y0 >= self.y1
    }

    /// Whether `other` lies inside.
    pub fn contains(&self, other: &PixelBounds) -> bool {
        self.x0 <= other.x0 && other.x1 <= self.x1 && self.y0 <= other.y0 && other.y1 <= self.y1
    }
}

impl std::fmt::Display for PixelBounds {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{},{},{},{}", self.x0, self.x1, self.y0, self.y1)
    }
}

/// Finished whole rows of a render: the mean colour of each pixel's samples, the exact sum of
/// them ([`Sum`]) where it is kept, and, if asked for, its AOVs, row-major over `bounds`.
#[derive(Debug, Clone, PartialEq)]
pub struct Rows {
    pub bounds: PixelBounds,
    /// Empty unless the render keeps them ([`Samples::sums`], or samples added to earlier ones).
    pub sums: Vec<Sum>,
    /// The mean of the samples rendered here, computed from the sums (or, for one sample,
    /// without them: [`Sum::mean_of_one`]) by the thread that rendered them; empty in rows
    /// that were not rendered (read from a checkpoint or a file).
    pub means: Vec<Colour>,
    pub aovs: Option<Vec<AovSample>>,
    /// Rays traced for these rows.
    pub rays: u64,
}

impl Rows {
    /// Empty (zero) rows `y0..y1` of columns `x0..x1`.
    pub fn new(x0: u32, x1: u32, y0: u32, y1: u32, aovs: bool) -> Rows {
        let bounds = PixelBounds { x0, x1, y0, y1 };
        let n = bounds.pixels() as usize;
        Rows {
            bounds,
            sums: vec![Sum::default(); n],
            means: Vec::new(),
            aovs: aovs.then(|| vec![AovSample::MISS; n]),
            rays: 0,
        }
    }

    /// Rows `at` of a render, to be filled in tile by tile: means, the sums if `sums`, the AOVs
    /// if `aovs`.
    fn rendered(at: PixelBounds, sums: bool, aovs: bool) -> Rows {
        let n = at.pixels() as usize;
        Rows {
            bounds: at,
            sums: vec![Sum::default(); if sums { n } else { 0 }],
            means: vec![Colour::ZERO; n],
            aovs: aovs.then(|| vec![AovSample::MISS; n]),
            rays: 0,
        }
    }

    /// Index of pixel (x, y) (absolute image coordinates inside the bounds).
    pub fn index(&self, x: u32, y: u32) -> usize {
        let b = &self.bounds;
        (y - b.y0) as usize * b.width() as usize + (x - b.x0) as usize
    }

    /// Copies in whole rows of the same columns (`other` lies inside these rows).
    pub fn copy_rows(&mut self, other: &Rows) {
        let k = self.index(self.bounds.x0, other.bounds.y0);
        let n = other.sums.len();
        self.sums[k..k + n].copy_from_slice(&other.sums);
        if let (Some(to), Some(from)) = (self.aovs.as_mut(), other.aovs.as_ref()) {
            to[k..k + n].copy_from_slice(from);
        }
    }

    /// Adds the sums of row `y` of `other` (whose columns lie inside these) to those of the same
    /// pixels here, and takes its AOVs (those of a pixel are the same in every part of a render).
    pub fn add_row(&mut self, other: &Rows, y: u32) {
        let b = other.bounds;
        let (i, j) = (self.index(b.x0, y), other.index(b.x0, y));
        let w = b.width() as usize;
        for (s, o) in self.sums[i..i + w].iter_mut().zip(&other.sums[j..j + w]) {
            s.add(o);
        }
        if let (Some(to), Some(from)) = (self.aovs.as_mut(), other.aovs.as_ref()) {
            to[i..i + w].copy_from_slice(&from[j..j + w]);
        }
    }

    /// Copies a tile (inside these rows, rendered with the same sums kept or not) in.
    fn insert(&mut self, at: PixelBounds, tile: &pipeline::Tile) {
        let w = at.width() as usize;
        for (r, y) in (at.y0..at.y1).enumerate() {
            let k = self.index(at.x0, y);
            let row = r * w..(r + 1) * w;
            self.means[k..k + w].copy_from_slice(&tile.means[row.clone()]);
            if !tile.sums.is_empty() {
                self.sums[k..k + w].copy_from_slice(&tile.sums[row]);
            }
            if let (Some(to), Some(from)) = (self.aovs.as_mut(), tile.aovs.as_ref()) {
                to[k..k + w].copy_from_slice(&from[r * w..(r + 1) * w]);
            }
        }
    }
}

/// Which samples a render adds to each pixel: samples `first(y)..end` of the per-pixel sample
/// sequence of a `spp`-sample render, `y` being the first row of each band. AOVs are recorded
/// for the bands whose samples start at `start` (others take theirs from earlier work).
pub struct Samples<'a> {
    /// Samples per pixel of the whole render (a single sample goes through the pixel centre).
    pub spp: u32,
    pub start: u32,
    pub end: u32,
    pub first: &'a (dyn Fn(u32) -> u32 + Sync),
    /// Whether every band keeps the exact sums of its samples (for checkpoints, or a file of
    /// sums); bands whose samples are added to earlier ones keep them anyway.
    pub sums: bool,
}

/// Distance along a chief ray to the scene's focus surface, if it has one and the ray meets it.
fn focus_distance(scene: &Scene, origin: DVec3, direction: DVec3) -> Option<f64> {
    let surface = scene.focus_surface.as_ref()?;
    surface
        .nearest(origin, direction, 0.0, f64::INFINITY)
        .map(|h| h.t)
}

/// The camera-frame ray through the centre of pixel (x, y) of a `width` × `height` image,
/// from the centre of the pupil (what the AOVs record).
pub fn centre_ray(scene: &Scene, camera: &Camera, width: u32, height: u32, x: u32, y: u32) -> Ray {
    let focus = |origin, direction| focus_distance(scene, origin, direction);
    camera.ray(width, height, (x as f64, y as f64), [0.0; 2], &focus)
}

/// Renders the pixels `tile` with samples `samples` (`sums`: keeping their sums; `aovs`: also
/// the AOVs).
fn render_tile(
    scene: &Scene,
    camera: &Camera,
    s: &RenderSettings,
    samples: std::ops::Range<u32>,
    sums: bool,
    aovs: bool,
    tile: PixelBounds,
) -> pipeline::Tile {
    let tracer = Tracer::new(scene, camera, s.shadows);
    let albedo_tracer = (aovs && s.albedo).then(|| Tracer::albedo(scene, camera));
    let n = tile.pixels() as usize;
    let mut out = pipeline::Tile {
        sums: vec![Sum::default(); if sums { n } else { 0 }],
        means: vec![Colour::ZERO; n],
        aovs: aovs.then(|| vec![AovSample::MISS; n]),
        rays: 0,
    };
    // One sample's mean needs no sum.
    let one = samples.len() == 1;
    let focus = |origin, direction| focus_distance(scene, origin, direction);
    // The ray of one sample (pixel offset and pupil point from the sample's random numbers).
    let sample_ray = |x: u32, y: u32, sample: u32| {
        let (dx, dy) = pixel_offset(s.seed, x, y, sample, s.spp);
        let pupil = if camera.aperture_radius() > 0.0 {
            [
                uniform(s.seed, x, y, sample, 2),
                uniform(s.seed, x, y, sample, 3),
            ]
        } else {
            [0.0; 2]
        };
        camera.ray(
            s.width,
            s.height,
            (x as f64 + dx, y as f64 + dy),
            pupil,
            &focus,
        )
    };
    // The same diffracted by the aperture, if it diffracts (from the sample's next random
    // numbers); none where that makes it evanescent (the sample is black).
    let diffracts = camera.diffraction().is_some();
    let diffracted_ray = |x: u32, y: u32, sample: u32| {
        let random = [
            uniform(s.seed, x, y, sample, 4),
            uniform(s.seed, x, y, sample, 5),
        ];
        camera.diffracted(sample_ray(x, y, sample), random)
    };
    // A single sample is recorded as it is traced for the AOVs; with more, or with a diffracting
    // aperture (which may lose the sample), the pixel centre is traced once more for them.
    let record_first = aovs && s.spp == 1 && samples.start == 0 && !diffracts;
    for by in (tile.y0..tile.y1).step_by(BLOCK_H as usize) {
        for bx in (tile.x0..tile.x1).step_by(BLOCK_W as usize) {
            let mut block = [(0u32, 0u32); 8];
            let mut n = 0;
            for y in by..(by + BLOCK_H).min(tile.y1) {
                for x in bx..(bx + BLOCK_W).min(tile.x1) {
                    block[n] = (x, y);
                    n += 1;
                }
            }
            let block = &block[..n];
            let mut block_sums = [Sum::default(); 8];
            let mut last = [Colour::ZERO; 8];
            let mut firsts = [None; 8];
            for sample in samples.clone() {
                // Written field by field: rays built by a closure, or copied whole, went through
                // the stack and stalled on store forwarding.
                let mut rays = [Ray::new(DVec3::ZERO, DVec3::Z, 0.0); 8];
                let mut colours = [Colour::ZERO; 8];
                if !diffracts {
                    for (ray, &(x, y)) in rays.iter_mut().zip(block) {
                        let r = sample_ray(x, y, sample);
                        (ray.origin, ray.direction, ray.time) = (r.origin, r.direction, r.time);
                    }
                    let record = (record_first && sample == 0).then_some(&mut firsts[..]);
                    tracer.trace_packet(&rays[..n], s.max_trace_level, &mut colours, record);
                } else {
                    // The block's pixel of each ray traced: samples lost to diffraction are not
                    // (nor recorded: record_first is false).
                    let mut lanes = [0; 8];
                    let mut traced = 0;
                    for (i, &(x, y)) in block.iter().enumerate() {
                        if let Some(r) = diffracted_ray(x, y, sample) {
                            rays[traced] = r;
                            lanes[traced] = i;
                            traced += 1;
                        }
                    }
                    let mut found = [Colour::ZERO; 8];
                    tracer.trace_packet(&rays[..traced], s.max_trace_level, &mut found, None);
                    for (&lane, colour) in lanes[..traced].iter().zip(found) {
                        colours[lane] = colour;
                    }
                }
                if one && !sums {
                    last = colours;
                } else {
                    for (sum, colour) in block_sums.iter_mut().zip(colours) {
                        sum.add_colour(colour);
                    }
                }
            }
            for (i, &(x, y)) in block.iter().enumerate() {
                let k = (y - tile.y0) as usize * tile.width() as usize + (x - tile.x0) as usize;
                out.means[k] = if one && !sums {
                    Sum::mean_of_one(last[i])
                } else {
                    block_sums[i].mean(samples.len() as u32)
                };
                if sums {
                    out.sums[k] = block_sums[i];
                }
                if let Some(aovs) = out.aovs.as_mut() {
                    // The surface seen through the pixel centre (the sample itself when spp = 1).
                    let found = if record_first {
                        firsts[i]
                    } else {
                        let ray = centre_ray(scene, camera, s.width, s.height, x, y);
                        tracer.first(&ray, 0.0, ReferenceFrame::Camera)
                    };
                    aovs[k] = found.map_or(AovSample::MISS, |f| {
                        let (object, normal) = tracer.identify(&f);
                        AovSample {
                            depth: f.hit.t as f32,
                            normal: normal.as_vec3(),
                            object: object as f32,
                            albedo: Vec3::ZERO,
                        }
                    });
                    if let Some(albedo_tracer) = &albedo_tracer {
                        let n = s.spp.min(ALBEDO_SAMPLES);
                        let sum: Colour = (0..n)
                            .filter_map(|sample| diffracted_ray(x, y, sample))
                            .map(|ray| {
                                albedo_tracer.trace(
                                    &ray,
                                    0.0,
                                    s.max_trace_level,
                                    ReferenceFrame::Camera,
                                )
                            })
                            .sum();
                        aovs[k].albedo =
                            (sum / n as f64).clamp(Colour::ZERO, Colour::ONE).as_vec3();
                    }
                }
            }
        }
    }
    out.rays = tracer.rays_traced();
    out
}

/// Renders the pixels `bounds` of `scene` through `camera` with `samples`, on
/// `settings.threads` threads, and hands finished bands of rows to `sink`, top to bottom; the
/// memory used depends on the width of `bounds`, not on its height. Stops early (after the
/// bands in flight) when `stop` is set or `sink` fails. The sums do not depend on the number
/// of threads, nor on how the pixels and samples are split between renders.
///
/// Tracing recurses once per trace level, so the work runs on threads whose stacks fit
/// `settings.max_trace_level` (levels above [`MAX_TRACE_LEVEL_LIMIT`] count as the limit; call
/// [`RenderSettings::validate`] first to reject them).
pub fn render_rows<E: Send>(
    scene: &Scene,
    camera: &Camera,
    settings: &RenderSettings,
    bounds: PixelBounds,
    samples: &Samples,
    stop: &AtomicBool,
    sink: &mut dyn FnMut(Rows) -> Result<(), E>,
) -> Result<Result<Outcome, E>, RenderError> {
    let s = &RenderSettings {
        max_trace_level: settings.max_trace_level.min(MAX_TRACE_LEVEL_LIMIT),
        spp: samples.spp,
        ..settings.clone()
    };
    let threads = s
        .threads
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    let stack = (1 << 20) + s.max_trace_level as usize * STACK_PER_LEVEL;
    let tile = |t: PixelBounds| {
        let band_y0 = bounds.y0 + (t.y0 - bounds.y0) / BAND * BAND;
        let first = (samples.first)(band_y0);
        let fresh = first == samples.start;
        let aovs = s.aovs && fresh;
        render_tile(
            scene,
            camera,
            s,
            first..samples.end,
            samples.sums || !fresh,
            aovs,
            t,
        )
    };
    if bounds.is_empty() {
        return Ok(Ok(Outcome {
            rays: 0,
            complete: true,
        }));
    }
    pipeline::run(bounds, threads, stack, s.aovs, stop, &tile, sink).map_err(RenderError::Threads)
}

/// Renders the whole of `scene` through `camera` into memory, on `settings.threads` threads.
/// `progress` is called with the number of pixels of each finished band of rows. The result
/// does not depend on the number of threads.
pub fn render(
    scene: &Scene,
    camera: &Camera,
    settings: &RenderSettings,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Image, RenderError> {
    let bounds = PixelBounds::full(settings.width, settings.height);
    let never = AtomicBool::new(false);
    let image = render_part(scene, camera, settings, bounds, &never, progress)?;
    Ok(image.expect("a render that is never stopped finishes"))
}

/// Renders the pixels `bounds` of the `settings.width` × `settings.height` image of `scene`
/// into memory, as an image of the size of `bounds` (the same values as those pixels of the
/// whole image); `None` if `stop` was set before it finished. `progress` as for [`render`].
pub fn render_part(
    scene: &Scene,
    camera: &Camera,
    settings: &RenderSettings,
    bounds: PixelBounds,
    stop: &AtomicBool,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Option<Image>, RenderError> {
    let (width, height) = (bounds.width(), bounds.height());
    let n = bounds.pixels() as usize;
    let out_of_memory = || RenderError::Memory {
        width,
        height,
        bytes: n as u64
            * (size_of::<Colour>() + settings.aovs as usize * size_of::<AovSample>()) as u64,
    };
    let mut pixels = buffer(n, Colour::ZERO).ok_or_else(out_of_memory)?;
    let mut aovs = match settings.aovs {
        true => Some(buffer(n, AovSample::MISS).ok_or_else(out_of_memory)?),
        false => None,
    };
    let samples = Samples {
        spp: settings.spp,
        start: 0,
        end: settings.spp,
        first: &|_| 0,
        sums: false,
    };
    let mut sink = |rows: Rows| -> Result<(), std::convert::Infallible> {
        let k = (rows.bounds.y0 - bounds.y0) as usize * width as usize;
        pixels[k..k + rows.means.len()].copy_from_slice(&rows.means);
        if let (Some(to), Some(from)) = (aovs.as_mut(), rows.aovs) {
            to[k..k + from.len()].copy_from_slice(&from);
        }
        progress(rows.bounds.pixels());
        Ok(())
    };
    let outcome = render_rows(scene, camera, settings, bounds, &samples, stop, &mut sink)?;
    let Ok(outcome) = outcome;
    Ok(outcome.complete.then_some(Image {
        width,
        height,
        pixels,
        aovs,
        rays: outcome.rays,
    }))
}
