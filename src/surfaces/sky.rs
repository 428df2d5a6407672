//! The image sky: an equirectangular picture at infinity, the texel picked by the direction of
//! the ray (not where it meets the sky sphere), as renderers' environment maps are. Dr TIM's
//! standard sky is a constant colour; its `EditableSky` picture skies put a `PictureSurface`
//! on a sky sphere.

use std::f64::consts::{PI, TAU};

use glam::DVec3;
use serde::Deserialize;

use super::{Redirection, Surface};
use crate::geometry::Interaction;
use crate::keys::{Finite, NonNegative};
use crate::math::Colour;
use crate::picture::{Picture, PictureFile};

/// The largest number below 1, so that straight up is the top row, not the next repeat's
/// bottom one.
const BELOW_ONE: f64 = 1.0 - f64::EPSILON / 2.0;

/// An equirectangular sky: +y is the top row, the picture's centre lies in direction +z (the
/// default camera's), +x at 3/4 of its width, so that from inside it reads unmirrored (x is to
/// the right of a camera looking along +z with +y up).
#[derive(Debug, Clone, PartialEq)]
pub struct ImageSky {
    pub picture: Picture,
    /// Radians about +y (right-handed: the centre moves from +z towards +x).
    pub rotation: f64,
    /// Factor of the texels' values.
    pub intensity: f64,
}

impl ImageSky {
    /// The picture coordinates (u right, v up, [0, 1]²) of the sky in direction `d`.
    pub fn coordinates(&self, d: DVec3) -> (f64, f64) {
        let azimuth = d.x.atan2(d.z) - self.rotation;
        let elevation = d.y.atan2(d.x.hypot(d.z));
        (0.5 + azimuth / TAU, (0.5 + elevation / PI).min(BELOW_ONE))
    }

    /// The sky's colour in direction `d`.
    pub fn colour(&self, d: DVec3) -> Colour {
        let (u, v) = self.coordinates(d);
        self.intensity * self.picture.at(u, v)
    }

    pub fn redirect(&self, at: &Interaction) -> Redirection<'static> {
        Redirection::Emits(self.colour(at.ray.direction))
    }
}

/// The scene file's `[sky]` table: `image` (PNG, JPEG, OpenEXR, Radiance HDR), `rotation` in
/// degrees about +y (0 where not given) and `intensity`, the texels' factor (1).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SkyKeys {
    pub image: PictureFile,
    rotation: Option<Finite>,
    intensity: Option<NonNegative>,
}

impl SkyKeys {
    pub fn build(self) -> Result<Surface, String> {
        Ok(Surface::ImageSky(ImageSky {
            picture: self.image.opened()?,
            rotation: self.rotation.map_or(0.0, |r| r.0.to_radians()),
            intensity: self.intensity.map_or(1.0, |i| i.0),
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 9 × 3 picture whose texel in column c, row r (from the top) has red c and green r.
    fn numbered() -> ImageSky {
        let texels = (0..3)
            .flat_map(|r| (0..9).map(move |c| [c as f32, r as f32, 0.0]))
            .collect();
        ImageSky {
            picture: Picture::new(9, 3, texels),
            rotation: 0.0,
            intensity: 1.0,
        }
    }

    /// (column, row) of the texel the sky shows in direction `d`.
    fn texel(sky: &ImageSky, d: DVec3) -> (f64, f64) {
        let c = sky.colour(d);
        (c.x, c.y)
    }

    /// +z is the centre texel (u = 1/2: column 4 of 9, row 1 of 3). From inside, with x to
    /// the right of the camera looking along +z, the picture's right lies towards +x: +x is
    /// u = 3/4 (column 6.75 → 6), −x u = 1/4 (2.25 → 2), −z the seam (column 0). Straight up
    /// is the top row, straight down the bottom row; 45° up along +z is v = 3/4 (row 2.25
    /// from the bottom, the top row).
    #[test]
    fn directions_pick_the_texels_worked_out_by_hand() {
        let sky = numbered();
        assert_eq!(texel(&sky, DVec3::Z), (4.0, 1.0));
        assert_eq!(texel(&sky, DVec3::X), (6.0, 1.0));
        assert_eq!(texel(&sky, -DVec3::X), (2.0, 1.0));
        assert_eq!(texel(&sky, -DVec3::Z), (0.0, 1.0));
        assert_eq!(texel(&sky, DVec3::Y).1, 0.0);
        assert_eq!(texel(&sky, -DVec3::Y).1, 2.0);
        assert_eq!(texel(&sky, DVec3::new(0.0, 1.0, 1.0)), (4.0, 0.0));
        assert_eq!(texel(&sky, DVec3::new(0.0, -1.0, 1.0)), (4.0, 2.0));
        // A ray's length does not matter, only its direction.
        assert_eq!(texel(&sky, DVec3::new(3.0, 0.0, 0.0)), (6.0, 1.0));
    }

    /// Rotating by 90° about +y brings the centre from +z to +x; the intensity scales.
    #[test]
    fn rotation_and_intensity() {
        let sky = ImageSky {
            rotation: 90f64.to_radians(),
            intensity: 2.0,
            ..numbered()
        };
        assert_eq!(sky.colour(DVec3::X), Colour::new(8.0, 2.0, 0.0));
        assert_eq!(sky.colour(DVec3::Z), Colour::new(4.0, 2.0, 0.0));
    }
}
