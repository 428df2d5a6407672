//! Which views of the scene to render and how they are combined into one image: one view,
//! anaglyphs, HDMI 1.4a frame packing, random-dot autostereograms (`stereo` makes the images).

use glam::DVec3;

/// How the two views are put side by side or on top of each other in one image (HDMI 1.4a).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Packing {
    /// Left view on the left, right view on the right.
    SideBySide,
    /// Left view on top, right view below.
    TopBottom,
}

/// What image to make of the scene.
#[derive(Debug, Clone, PartialEq, Default)]
pub enum Stereo {
    /// One view: the camera's.
    #[default]
    Mono,
    /// Red-blue anaglyph: the left eye's luminance in red, the right eye's in blue. With
    /// `colour`, a red-cyan colour anaglyph: red from the left eye, green and blue from the
    /// right.
    Anaglyph { eye_separation: DVec3, colour: bool },
    /// Both views in one image. Full resolution doubles the width (side by side) or the height
    /// (top and bottom); half resolution keeps the image size, each view squeezed to half by
    /// averaging pairs of columns or rows of a full-resolution render.
    FramePacking {
        eye_separation: DVec3,
        packing: Packing,
        half: bool,
    },
    /// A random-dot autostereogram of the depth of the surfaces seen through the pixel
    /// centres (see the `stereo::autostereogram` module). Depths (distances along the view
    /// direction) from `near` to `far` span the depth range; nearer ones count as near, farther
    /// ones and misses as far. Without `near` and `far`, the nearest depth seen and the median
    /// depth are used.
    Autostereogram {
        /// Eye separation in pixels; by default 2.5 inches at 72 dpi (180), at most a third
        /// of the width.
        eye_separation_px: Option<u32>,
        depth_of_field: f64,
        colour: bool,
        near: Option<f64>,
        far: Option<f64>,
    },
}

impl Stereo {
    /// The number of views rendered (for progress reports).
    pub fn views(&self) -> u32 {
        match self {
            Stereo::Mono | Stereo::Autostereogram { .. } => 1,
            Stereo::Anaglyph { .. } | Stereo::FramePacking { .. } => 2,
        }
    }

    /// The scene-file name of the output (`camera.stereo`).
    pub fn name(&self) -> &'static str {
        match self {
            Stereo::Mono => "none",
            Stereo::Anaglyph { colour: false, .. } => "anaglyph",
            Stereo::Anaglyph { colour: true, .. } => "colour-anaglyph",
            Stereo::FramePacking { packing, half, .. } => match (packing, half) {
                (Packing::SideBySide, false) => "side-by-side",
                (Packing::SideBySide, true) => "side-by-side-half",
                (Packing::TopBottom, false) => "top-bottom",
                (Packing::TopBottom, true) => "top-bottom-half",
            },
            Stereo::Autostereogram { .. } => "autostereogram",
        }
    }
}
