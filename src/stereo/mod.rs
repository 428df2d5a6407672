//! Stereo outputs: red-blue and colour anaglyphs, HDMI 1.4a 3D-TV frame packing (§6) and
//! random-dot autostereograms.
//!
//! The two eyes are the camera with its pupil moved by ∓s/2 (s, the eye separation, points from
//! the left eye to the right, in the camera frame). Both image each pixel onto the same point of
//! the camera's focus surface, so the eyes converge there: objects on it have no parallax.

pub mod autostereogram;

use std::sync::atomic::AtomicBool;

use glam::DVec3;

pub use autostereogram::Autostereogram;

use crate::cameras::Camera;
use crate::math::Colour;
use crate::render::{Image, PixelBounds, RenderError, render_part};
use crate::scene::{Packing, RenderSettings, Scene, Stereo};

/// Relative luminance of linear RGB (ITU-R BT.709).
pub const LUMINANCE: Colour = Colour::new(0.2126, 0.7152, 0.0722);

/// Checks the output against the image size; the message says what is wrong.
pub fn validate(stereo: &Stereo, width: u32, height: u32) -> Result<(), String> {
    match stereo {
        Stereo::FramePacking {
            packing: Packing::SideBySide,
            half: true,
            ..
        } if width % 2 == 1 => Err(format!(
            "half-resolution side-by-side frame packing needs an even width, got {width}"
        )),
        Stereo::FramePacking {
            packing: Packing::TopBottom,
            half: true,
            ..
        } if height % 2 == 1 => Err(format!(
            "half-resolution top-bottom frame packing needs an even height, got {height}"
        )),
        Stereo::Autostereogram {
            eye_separation_px: None,
            ..
        } if width < 6 => Err(format!(
            "an autostereogram needs an image at least 6 pixels wide, got {width}"
        )),
        Stereo::Autostereogram { .. } => autostereogram(stereo, width, 0)
            .expect("an autostereogram")
            .validate(width)
            .map_err(|m| format!("autostereogram (eye_separation_px): {m}")),
        _ => Ok(()),
    }
}

/// The autostereogram options for an image `width` pixels wide, with random dots from
/// `seed`; `None` unless this is an autostereogram.
pub fn autostereogram(stereo: &Stereo, width: u32, seed: u64) -> Option<Autostereogram> {
    match *stereo {
        Stereo::Autostereogram {
            eye_separation_px,
            depth_of_field,
            colour,
            ..
        } => Some(Autostereogram {
            eye_separation: eye_separation_px.unwrap_or(180.min(width / 3)),
            depth_of_field,
            seed,
            colour,
        }),
        _ => None,
    }
}

/// Bytes the image `stereo` asks for needs in memory while it is rendered and combined, at its
/// peak, roughly, for `pixels` pixels a view: each view's f64 colours (24 bytes a pixel) and,
/// with `aovs`, AOVs (32); two views' combination copies both and makes the output (up to
/// twice a view); an autostereogram renders the depth AOV whatever `aovs`, and keeps three f64
/// depths (8 each) and its output (24).
pub fn memory_needed(aovs: bool, stereo: &Stereo, pixels: u64) -> u64 {
    let aov = size_of::<crate::render::AovSample>() as u64;
    let view = 24 + aov * aovs as u64;
    pixels
        * match stereo {
            Stereo::Mono => view,
            Stereo::Anaglyph { .. } | Stereo::FramePacking { .. } => 2 * view + 4 * 24,
            Stereo::Autostereogram { .. } => 24 + aov + 3 * 8 + 24,
        }
}

/// Renders the image `stereo` asks for: one view or two, combined. `progress` counts the
/// pixels of every view. AOVs (if the settings ask for them) are kept for single views only.
pub fn render_stereo(
    scene: &Scene,
    camera: &Camera,
    settings: &RenderSettings,
    stereo: &Stereo,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Image, RenderError> {
    let never = AtomicBool::new(false);
    let image = render_stereo_until(scene, camera, settings, stereo, &never, progress)?;
    Ok(image.expect("a render that is never stopped finishes"))
}

/// [`render_stereo`], or `None` if `stop` was set before it finished.
pub fn render_stereo_until(
    scene: &Scene,
    camera: &Camera,
    settings: &RenderSettings,
    stereo: &Stereo,
    stop: &AtomicBool,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Option<Image>, RenderError> {
    let whole = PixelBounds::full(settings.width, settings.height);
    let render = |camera: &Camera, settings: &RenderSettings| {
        render_part(scene, camera, settings, whole, stop, progress)
    };
    // Both eyes use the same random numbers (pixel offsets, pupil points), so their noise is
    // correlated, not independent.
    let views = |s: DVec3| -> Result<Option<(Image, Image)>, RenderError> {
        let Some(left) = render(&camera.eye(-0.5 * s), settings)? else {
            return Ok(None);
        };
        Ok(render(&camera.eye(0.5 * s), settings)?.map(|right| (left, right)))
    };
    Ok(match stereo {
        Stereo::Mono => render(camera, settings)?,
        Stereo::Anaglyph {
            eye_separation,
            colour,
        } => views(*eye_separation)?.map(|(left, right)| anaglyph(&left, &right, *colour)),
        Stereo::FramePacking {
            eye_separation,
            packing,
            half,
        } => views(*eye_separation)?.map(|(left, right)| pack(&left, &right, *packing, *half)),
        Stereo::Autostereogram { near, far, .. } => {
            // Only the depth of the surface seen through each pixel centre is used.
            let with_depth = RenderSettings {
                aovs: true,
                spp: 1,
                ..settings.clone()
            };
            render(camera, &with_depth)?.map(|image| {
                let depth = depth_map(&image, camera, *near, *far);
                let options =
                    autostereogram(stereo, image.width, settings.seed).expect("an autostereogram");
                Image {
                    pixels: options.render(&depth, image.width, image.height),
                    aovs: None,
                    ..image
                }
            })
        }
    })
}

/// The anaglyph of two views of the same size: red-blue from the luminances, or red-cyan
/// colour.
pub fn anaglyph(left: &Image, right: &Image, colour: bool) -> Image {
    let pixels = left
        .pixels
        .iter()
        .zip(&right.pixels)
        .map(|(l, r)| {
            if colour {
                Colour::new(l.x, r.y, r.z)
            } else {
                Colour::new(l.dot(LUMINANCE), 0.0, r.dot(LUMINANCE))
            }
        })
        .collect();
    Image {
        width: left.width,
        height: left.height,
        pixels,
        aovs: None,
        rays: left.rays + right.rays,
    }
}

/// Two views of the same size packed into one frame.
pub fn pack(left: &Image, right: &Image, packing: Packing, half: bool) -> Image {
    let (w, h) = (left.width as usize, left.height as usize);
    let (views, width, height) = match (packing, half) {
        (Packing::SideBySide, false) => ([left.clone(), right.clone()], 2 * w, h),
        (Packing::TopBottom, false) => ([left.clone(), right.clone()], w, 2 * h),
        (Packing::SideBySide, true) => ([squeeze(left, 2, 1), squeeze(right, 2, 1)], w, h),
        (Packing::TopBottom, true) => ([squeeze(left, 1, 2), squeeze(right, 1, 2)], w, h),
    };
    let mut pixels = vec![Colour::ZERO; width * height];
    for (k, view) in views.iter().enumerate() {
        let (vw, vh) = (view.width as usize, view.height as usize);
        // The right view starts after the left one: to its right, or below it.
        let (x0, y0) = match packing {
            Packing::SideBySide => (k * vw, 0),
            Packing::TopBottom => (0, k * vh),
        };
        for y in 0..vh {
            let row = (y0 + y) * width + x0;
            pixels[row..row + vw].copy_from_slice(&view.pixels[y * vw..(y + 1) * vw]);
        }
    }
    Image {
        width: width as u32,
        height: height as u32,
        pixels,
        aovs: None,
        rays: left.rays + right.rays,
    }
}

/// The image with each `fx` × `fy` block of pixels averaged into one (sizes divisible).
fn squeeze(image: &Image, fx: usize, fy: usize) -> Image {
    let (w, h) = (image.width as usize / fx, image.height as usize / fy);
    let mut pixels = Vec::with_capacity(w * h);
    for y in 0..h {
        for x in 0..w {
            let mut sum = Colour::ZERO;
            for j in 0..fy {
                for i in 0..fx {
                    sum += image.pixels[(fy * y + j) * image.width as usize + fx * x + i];
                }
            }
            pixels.push(sum / (fx * fy) as f64);
        }
    }
    Image {
        width: w as u32,
        height: h as u32,
        pixels,
        aovs: None,
        rays: image.rays,
    }
}

/// Depth z ∈ [0, 1] (1 near, 0 far) per pixel: the distance of the surface seen through the
/// pixel centre along the view direction, mapped linearly from [far, near] to [0, 1]. A missing
/// `near` is the nearest depth seen, a missing `far` the median of the depths seen (misses are
/// far, but do not count for the median). For a moving camera the depth is measured along the
/// scene-frame ray (from its Lorentz-transformed start), projected on the camera-frame view
/// direction: an approximation.
fn depth_map(image: &Image, camera: &Camera, near: Option<f64>, far: Option<f64>) -> Vec<f64> {
    let aovs = image.aovs.as_ref().expect("rendered with AOVs");
    let (w, h) = (image.width, image.height);
    let along: Vec<f64> = aovs
        .iter()
        .enumerate()
        .map(|(k, a)| {
            let (x, y) = ((k % w as usize) as f64, (k / w as usize) as f64);
            let (_, chief) = camera.chief_ray(w, h, x, y);
            a.depth as f64 * chief.normalize().dot(camera.view_direction())
        })
        .collect();
    let mut seen: Vec<f64> = along.iter().copied().filter(|d| d.is_finite()).collect();
    seen.sort_by(f64::total_cmp);
    let near = near.unwrap_or(seen.first().copied().unwrap_or(0.0));
    let far = far.unwrap_or(seen.get(seen.len() / 2).copied().unwrap_or(1.0));
    let range = (far - near).max(f64::MIN_POSITIVE);
    along
        .iter()
        .map(|&d| {
            if d.is_finite() {
                ((far - d) / range).clamp(0.0, 1.0)
            } else {
                0.0
            }
        })
        .collect()
}
