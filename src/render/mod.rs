//! Rendering: primary rays from the camera, traced in parallel over bands of image rows.

mod sampling;
pub mod shading;
mod tracer;

pub use sampling::pixel_offset;
pub use tracer::{Found, Tracer};

use glam::Vec3;
use rayon::prelude::*;
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
}

impl AovSample {
    const MISS: AovSample = AovSample {
        depth: f32::INFINITY,
        normal: Vec3::ZERO,
        object: -1.0,
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
    Threads(#[from] rayon::ThreadPoolBuildError),
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

/// Rows per band: the image is rendered in parallel in bands of whole rows, each written in
/// place. A multiple of BLOCK_H.
const BAND: u32 = 8;

/// Primary rays are traced in packets of BLOCK_W × BLOCK_H neighbouring pixels (8 = Embree's
/// native AVX2 packet width).
const BLOCK_W: u32 = 4;
const BLOCK_H: u32 = 2;

/// Renders the rows from `y0` into `pixels` (and `aovs`, if asked for); returns the rays traced.
fn render_band(
    scene: &Scene,
    camera: &Camera,
    s: &RenderSettings,
    y0: u32,
    pixels: &mut [Colour],
    mut aovs: Option<&mut [AovSample]>,
) -> u64 {
    let tracer = Tracer::new(scene, camera, s.shadows);
    let rows = (pixels.len() / s.width as usize) as u32;
    let focus = |origin, direction| {
        let surface = scene.focus_surface.as_ref()?;
        surface
            .nearest(origin, direction, 0.0, f64::INFINITY)
            .map(|h| h.t)
    };
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
    for by in (y0..y0 + rows).step_by(BLOCK_H as usize) {
        for bx in (0..s.width).step_by(BLOCK_W as usize) {
            let mut block = [(0u32, 0u32); 8];
            let mut n = 0;
            for y in by..(by + BLOCK_H).min(y0 + rows) {
                for x in bx..(bx + BLOCK_W).min(s.width) {
                    block[n] = (x, y);
                    n += 1;
                }
            }
            let block = &block[..n];
            let mut sums = [Colour::ZERO; 8];
            let mut firsts = [None; 8];
            for sample in 0..s.spp {
                let rays: [Ray; 8] = std::array::from_fn(|i| {
                    let (x, y) = block.get(i).copied().unwrap_or(block[0]);
                    sample_ray(x, y, sample)
                });
                // The surfaces met are kept for the AOVs of a single sample.
                let record = (aovs.is_some() && s.spp == 1).then_some(&mut firsts[..]);
                tracer.trace_packet(&rays[..n], s.max_trace_level, &mut sums, record);
            }
            for (i, &(x, y)) in block.iter().enumerate() {
                let k = (y - y0) as usize * s.width as usize + x as usize;
                pixels[k] = sums[i] / s.spp as f64;
                if let Some(aovs) = aovs.as_deref_mut() {
                    // The surface seen through the pixel centre (the sample itself when spp = 1).
                    let found = if s.spp == 1 {
                        firsts[i]
                    } else {
                        let ray =
                            camera.ray(s.width, s.height, (x as f64, y as f64), [0.0; 2], &focus);
                        tracer.first(&ray, 0.0, ReferenceFrame::Camera)
                    };
                    aovs[k] = found.map_or(AovSample::MISS, |f| {
                        let (object, normal) = tracer.identify(&f);
                        AovSample {
                            depth: f.hit.t as f32,
                            normal: normal.as_vec3(),
                            object: object as f32,
                        }
                    });
                }
            }
        }
    }
    tracer.rays_traced()
}

/// Renders `scene` through `camera` on `settings.threads` threads. `progress` is called with the number of pixels of each finished band of rows. The result
/// does not depend on the number of threads.
///
/// Tracing recurses once per trace level, so the work runs on a pool of its own whose stacks fit
/// `settings.max_trace_level` (levels above [`MAX_TRACE_LEVEL_LIMIT`] count as the limit; call
/// [`RenderSettings::validate`] first to reject them).
pub fn render(
    scene: &Scene,
    camera: &Camera,
    settings: &RenderSettings,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Image, RenderError> {
    let s = &RenderSettings {
        max_trace_level: settings.max_trace_level.min(MAX_TRACE_LEVEL_LIMIT),
        ..settings.clone()
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(s.threads.unwrap_or(0)) // 0: rayon's default, one per core
        .stack_size((1 << 20) + s.max_trace_level as usize * STACK_PER_LEVEL)
        .build()?;

    let n = s.width as usize * s.height as usize;
    let band = BAND as usize * s.width as usize;
    let out_of_memory = || RenderError::Memory {
        width: s.width,
        height: s.height,
        bytes: n as u64 * (size_of::<Colour>() + s.aovs as usize * size_of::<AovSample>()) as u64,
    };
    let mut pixels = buffer(n, Colour::ZERO).ok_or_else(out_of_memory)?;
    let mut aovs = match s.aovs {
        true => Some(buffer(n, AovSample::MISS).ok_or_else(out_of_memory)?),
        false => None,
    };
    let rays = pool.install(|| {
        let aov_bands: Vec<Option<&mut [AovSample]>> = match aovs.as_mut() {
            Some(a) => a.chunks_mut(band).map(Some).collect(),
            None => (0..n.div_ceil(band)).map(|_| None).collect(),
        };
        pixels
            .par_chunks_mut(band)
            .zip(aov_bands)
            .enumerate()
            .map(|(i, (pixels, aovs))| {
                let rays = render_band(scene, camera, s, i as u32 * BAND, pixels, aovs);
                progress(pixels.len() as u64);
                rays
            })
            .sum()
    });
    Ok(Image {
        width: s.width,
        height: s.height,
        pixels,
        aovs,
        rays,
    })
}
