//! Rendering: primary rays from the camera, traced in parallel over image tiles.

mod sampling;
mod tracer;

pub use sampling::{pixel_offset, uniform};
pub use tracer::{Interaction, Tracer};

use glam::Vec3;
use rayon::prelude::*;

use crate::cameras::PinholeCamera;
use crate::scene::Scene;
use crate::surfaces::Colour;

/// Side length of the square tiles that are rendered in parallel.
const TILE: u32 = 32;

/// How to render: image size, sampling and tracing limits.
#[derive(Debug, Clone, PartialEq)]
pub struct RenderSettings {
    pub width: u32,
    pub height: u32,
    /// Samples (primary rays) per pixel.
    pub spp: u32,
    pub seed: u64,
    /// Maximum number of surfaces a ray path may meet; a ray that runs out of levels is black.
    pub max_trace_level: u32,
    /// Scene-wide switch for hard shadows.
    pub shadows: bool,
    /// Also record depth, normal and object id of the surface seen through each pixel centre.
    pub aovs: bool,
}

/// Largest accepted maximum trace level. Tracing recurses once per level, so worker threads get
/// stacks sized for the level (see [`render`]).
pub const MAX_TRACE_LEVEL_LIMIT: u32 = 100_000;

/// Largest accepted image, in pixels (16384 × 16384): the f64 image alone then needs 6 GiB.
pub const MAX_PIXELS: u64 = 1 << 28;

/// Stack bytes a worker needs per trace level (measured about 700; generous for safety).
const STACK_PER_LEVEL: usize = 4 << 10;

impl RenderSettings {
    /// Checks the limits a render must respect; the message says what is wrong.
    pub fn validate(&self) -> Result<(), String> {
        let pixels = self.width as u64 * self.height as u64;
        if self.width == 0 || self.height == 0 || self.spp == 0 || self.max_trace_level == 0 {
            return Err("width, height, spp and max_trace_level must be at least 1".into());
        }
        if pixels > MAX_PIXELS {
            return Err(format!(
                "an image of {}x{} pixels is larger than the limit of {MAX_PIXELS} pixels",
                self.width, self.height
            ));
        }
        if self.max_trace_level > MAX_TRACE_LEVEL_LIMIT {
            return Err(format!(
                "max_trace_level {} is above the limit of {MAX_TRACE_LEVEL_LIMIT}",
                self.max_trace_level
            ));
        }
        Ok(())
    }
}

impl Default for RenderSettings {
    fn default() -> Self {
        RenderSettings {
            width: 640,
            height: 480,
            spp: 1,
            seed: 0,
            max_trace_level: 100,
            shadows: true,
            aovs: false,
        }
    }
}

/// Arbitrary output variables of the surface seen through each pixel centre.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Aovs {
    /// Distance from the camera; infinite where nothing is hit.
    pub depth: Vec<f32>,
    /// Outward surface normal; zero where nothing is hit.
    pub normal: Vec<Vec3>,
    /// Object index in the scene; −1 where nothing is hit.
    pub object: Vec<f32>,
}

/// A rendered image: linear RGB, row-major from the top-left pixel.
#[derive(Debug, Clone, PartialEq)]
pub struct Image {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<Colour>,
    pub aovs: Option<Aovs>,
    /// Rays traced (primary, secondary and shadow).
    pub rays: u64,
}

impl Image {
    pub fn pixel(&self, x: u32, y: u32) -> Colour {
        self.pixels[y as usize * self.width as usize + x as usize]
    }
}

/// One tile's results, in the tile's own row-major order.
struct Tile {
    x0: u32,
    y0: u32,
    w: u32,
    pixels: Vec<Colour>,
    aovs: Aovs,
    rays: u64,
}

/// Primary rays are traced in packets of BLOCK_W × BLOCK_H neighbouring pixels (8 = Embree's
/// native AVX2 packet width).
const BLOCK_W: u32 = 4;
const BLOCK_H: u32 = 2;

fn render_tile(
    scene: &Scene,
    camera: &PinholeCamera,
    s: &RenderSettings,
    x0: u32,
    y0: u32,
) -> Tile {
    let tracer = Tracer::new(scene, s.shadows);
    let (w, h) = (TILE.min(s.width - x0), TILE.min(s.height - y0));
    let n = (w * h) as usize;
    let mut tile = Tile {
        x0,
        y0,
        w,
        pixels: vec![Colour::ZERO; n],
        aovs: Aovs::default(),
        rays: 0,
    };
    if s.aovs {
        tile.aovs = Aovs {
            depth: vec![0.0; n],
            normal: vec![Vec3::ZERO; n],
            object: vec![0.0; n],
        };
    }
    let shapes = scene.geometry.shapes();
    for by in (y0..y0 + h).step_by(BLOCK_H as usize) {
        for bx in (x0..x0 + w).step_by(BLOCK_W as usize) {
            let block: Vec<(u32, u32)> = (by..(by + BLOCK_H).min(y0 + h))
                .flat_map(|y| (bx..(bx + BLOCK_W).min(x0 + w)).map(move |x| (x, y)))
                .collect();
            let mut sums = [Colour::ZERO; 8];
            let mut hits = [None; 8];
            for sample in 0..s.spp {
                let rays: Vec<_> = block
                    .iter()
                    .map(|&(x, y)| {
                        let (dx, dy) = pixel_offset(s.seed, x, y, sample, s.spp);
                        camera.ray(s.width, s.height, x as f64 + dx, y as f64 + dy)
                    })
                    .collect();
                for (i, (colour, hit)) in tracer
                    .trace_packet(&rays, s.max_trace_level)
                    .into_iter()
                    .enumerate()
                {
                    sums[i] += colour;
                    if s.spp == 1 {
                        hits[i] = hit;
                    }
                }
            }
            for (i, &(x, y)) in block.iter().enumerate() {
                let k = ((y - y0) * w + (x - x0)) as usize;
                tile.pixels[k] = sums[i] / s.spp as f64;
                if s.aovs {
                    // The surface seen through the pixel centre (the sample itself when spp = 1).
                    let ray = camera.ray(s.width, s.height, x as f64, y as f64);
                    let hit = if s.spp == 1 {
                        hits[i]
                    } else {
                        tracer.nearest(&ray, 0.0)
                    };
                    tile.aovs.depth[k] = hit.map_or(f32::INFINITY, |h| h.t as f32);
                    tile.aovs.normal[k] = hit.map_or(Vec3::ZERO, |h| {
                        shapes[h.object].frame(ray.at(h.t), h.prim).w.as_vec3()
                    });
                    tile.aovs.object[k] = hit.map_or(-1.0, |h| h.object as f32);
                }
            }
        }
    }
    tile.rays = tracer.rays_traced();
    tile
}

/// Renders `scene` through `camera` with as many threads as the current rayon pool has.
/// `progress` is called with the number of pixels of each finished tile. The result does not
/// depend on the number of threads.
///
/// Tracing recurses once per trace level, so the work runs on a pool whose stacks fit
/// `settings.max_trace_level` (levels above [`MAX_TRACE_LEVEL_LIMIT`] count as the limit; call
/// [`RenderSettings::validate`] first to reject them).
pub fn render(
    scene: &Scene,
    camera: &PinholeCamera,
    settings: &RenderSettings,
    progress: &(dyn Fn(u64) + Sync),
) -> Image {
    let s = &RenderSettings {
        max_trace_level: settings.max_trace_level.min(MAX_TRACE_LEVEL_LIMIT),
        ..settings.clone()
    };
    let stack = (1 << 20) + s.max_trace_level as usize * STACK_PER_LEVEL;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(rayon::current_num_threads())
        .stack_size(stack)
        .build();
    match pool {
        Ok(pool) => pool.install(|| render_on_current_pool(scene, camera, s, progress)),
        // Without a pool of our own (thread creation refused), fall back to the caller's.
        Err(_) => render_on_current_pool(scene, camera, s, progress),
    }
}

fn render_on_current_pool(
    scene: &Scene,
    camera: &PinholeCamera,
    s: &RenderSettings,
    progress: &(dyn Fn(u64) + Sync),
) -> Image {
    let origins: Vec<(u32, u32)> = (0..s.height)
        .step_by(TILE as usize)
        .flat_map(|y| (0..s.width).step_by(TILE as usize).map(move |x| (x, y)))
        .collect();
    let tiles: Vec<Tile> = origins
        .par_iter()
        .map(|&(x0, y0)| {
            let tile = render_tile(scene, camera, s, x0, y0);
            progress(tile.pixels.len() as u64);
            tile
        })
        .collect();

    let n = s.width as usize * s.height as usize;
    let mut image = Image {
        width: s.width,
        height: s.height,
        pixels: vec![Colour::ZERO; n],
        aovs: s.aovs.then(|| Aovs {
            depth: vec![0.0; n],
            normal: vec![Vec3::ZERO; n],
            object: vec![0.0; n],
        }),
        rays: 0,
    };
    for tile in tiles {
        image.rays += tile.rays;
        for (k, colour) in tile.pixels.into_iter().enumerate() {
            let (x, y) = (tile.x0 + k as u32 % tile.w, tile.y0 + k as u32 / tile.w);
            let i = y as usize * s.width as usize + x as usize;
            image.pixels[i] = colour;
            if let Some(a) = &mut image.aovs {
                a.depth[i] = tile.aovs.depth[k];
                a.normal[i] = tile.aovs.normal[k];
                a.object[i] = tile.aovs.object[k];
            }
        }
    }
    image
}
