//! Sample positions within a pixel.

use crate::math::random::uniform;

/// Offset of a sample from its pixel centre, in pixels. A single sample per pixel goes
/// through the centre (as in TIM); more samples are jittered uniformly over the pixel.
pub fn pixel_offset(seed: u64, x: u32, y: u32, sample: u32, spp: u32) -> (f64, f64) {
    if spp <= 1 {
        return (0.0, 0.0);
    }
    (
        uniform(seed, x, y, sample, 0) - 0.5,
        uniform(seed, x, y, sample, 1) - 0.5,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn offsets_stay_inside_the_pixel() {
        for s in 0..1000 {
            let (dx, dy) = pixel_offset(1, 0, 0, s, 16);
            assert!((-0.5..0.5).contains(&dx) && (-0.5..0.5).contains(&dy));
        }
        assert_eq!(pixel_offset(1, 5, 5, 0, 1), (0.0, 0.0));
    }
}
