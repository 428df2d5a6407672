//! How to render a scene: image size, sampling and tracing limits (what `render` obeys).

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
    /// Worker threads; `None` for as many as the machine has cores.
    pub threads: Option<usize>,
}

/// Largest accepted maximum trace level. Tracing recurses once per level, so worker threads get
/// stacks sized for the level (see `render::render`).
pub const MAX_TRACE_LEVEL_LIMIT: u32 = 100_000;

/// Largest accepted image, in pixels (2³⁶, e.g. 262144 × 262144): single views are streamed to
/// their file in bounded memory, so the limit is one of sense (such a render takes days);
/// renders held in memory (stereo outputs) are limited by the memory there is.
pub const MAX_PIXELS: u64 = 1 << 36;

/// Largest accepted width or height (OpenEXR stores coordinates as 32-bit integers).
pub const MAX_SIDE: u32 = 1 << 24;

impl RenderSettings {
    /// Checks the limits a render must respect; the message says what is wrong.
    pub fn validate(&self) -> Result<(), String> {
        let pixels = self.width as u64 * self.height as u64;
        if self.width == 0 || self.height == 0 || self.spp == 0 || self.max_trace_level == 0 {
            return Err("width, height, spp and max_trace_level must be at least 1".into());
        }
        if self.width > MAX_SIDE || self.height > MAX_SIDE {
            return Err(format!(
                "an image of {}x{} pixels is wider or higher than the limit of {MAX_SIDE} pixels",
                self.width, self.height
            ));
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
            threads: None,
        }
    }
}
