//! Dr TIM's `AzimuthalPixelatedFresnelWedge`: a hologram of rectangular pixels, each a Fresnel
//! wedge (a constant kick, a prism) with the rotationally symmetric gradients
//! b r^(c−1) ϑ̂ + s r^t r̂ (as `RotationallySymmetricPhaseHologram`'s, without the honest
//! simulation) at the pixel's centre. The pixel centres are the centre plus whole multiples of
//! the pixel's sides, along u and v, so the centre is the middle of a pixel; a point belongs
//! to the nearest centre along each side.
//!
//! Dr TIM gives the sides as two span vectors and finds the pixel by projecting onto them,
//! which is right only for orthogonal spans: here the sides are along u and v. Its central
//! pixel, at r = 0 where r̂ has no direction, gets a direction change of NaN; here it passes
//! rays unchanged. Its optional diffractive blur (a random angle from the pixel's
//! single-slit diffraction) is not simulated.

use glam::DVec2;
use serde::Deserialize;

use super::Phase;
use super::rotationally_symmetric::AzimuthalRadial;
use crate::keys::{Array, Finite, Positive, Vector2};

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AzimuthalPixelatedFresnelWedgePhase {
    pub centre: DVec2,
    pub gradients: AzimuthalRadial,
    /// The pixel's sides along u and v.
    pub pixel_size: DVec2,
}

impl AzimuthalPixelatedFresnelWedgePhase {
    pub fn gradient(&self, r: DVec2) -> DVec2 {
        let r = r - self.centre;
        let pixel_centre = self.pixel_size * (r / self.pixel_size + 0.5).floor();
        self.gradients.kick(pixel_centre)
    }
}

/// `phase = { type = "azimuthal-pixelated-fresnel-wedge", pixel_size = [wu, wv], centre =
/// [u0, v0], azimuthal_coefficient = b, azimuthal_exponent = c, radial_coefficient = s,
/// radial_exponent = t }` (b, c, s, t 0 and the centre (0, 0) when not given, as for the
/// rotationally symmetric phase).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AzimuthalPixelatedFresnelWedgePhaseKeys {
    pixel_size: Array<Positive, 2>,
    centre: Option<Vector2>,
    azimuthal_coefficient: Option<Finite>,
    azimuthal_exponent: Option<Finite>,
    radial_coefficient: Option<Finite>,
    radial_exponent: Option<Finite>,
}

impl AzimuthalPixelatedFresnelWedgePhaseKeys {
    pub fn build(self) -> Result<Phase, String> {
        let [wu, wv] = self.pixel_size.0.map(|w| w.0);
        Ok(Phase::AzimuthalPixelatedFresnelWedge(
            AzimuthalPixelatedFresnelWedgePhase {
                centre: self.centre.map_or(DVec2::ZERO, |c| c.0),
                gradients: AzimuthalRadial::from_keys(
                    self.azimuthal_coefficient,
                    self.azimuthal_exponent,
                    self.radial_coefficient,
                    self.radial_exponent,
                ),
                pixel_size: DVec2::new(wu, wv),
            },
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// With c = 2 and t = 1 the gradients are linear: b (−y, x) + s (x, y) at (x, y) from the
    /// centre, written out here at the pixel's centre, which is (i wu, j wv) for the point
    /// (x, y) with |x − i wu| < wu/2 and |y − j wv| < wv/2. Every point of a pixel gets its
    /// centre's kick; the central pixel none.
    #[test]
    fn each_pixel_is_a_prism_with_the_kick_at_its_centre() {
        let (b, s, size, centre) = (0.2, -0.1, DVec2::new(0.5, 0.25), DVec2::new(0.1, 0.2));
        let wedge = AzimuthalPixelatedFresnelWedgePhase {
            centre,
            gradients: AzimuthalRadial {
                azimuthal_coefficient: b,
                azimuthal_exponent: 2.0,
                radial_coefficient: s,
                radial_exponent: 1.0,
            },
            pixel_size: size,
        };
        for i in -3..=3 {
            for j in -3..=3 {
                let (x, y) = (i as f64 * size.x, j as f64 * size.y);
                let expected = b * DVec2::new(-y, x) + s * DVec2::new(x, y);
                for (fu, fv) in [(0.0, 0.0), (0.49, -0.49), (-0.49, 0.3), (0.2, 0.49)] {
                    let r = centre + DVec2::new(x + fu * size.x, y + fv * size.y);
                    let g = wedge.gradient(r);
                    assert!(g.distance(expected) < 1e-15, "pixel ({i}, {j}) at {r}: {g}");
                }
            }
        }
        assert_eq!(wedge.gradient(centre + 0.1 * size), DVec2::ZERO);
    }
}
