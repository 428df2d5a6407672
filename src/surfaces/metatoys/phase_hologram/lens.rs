//! The exact lens phase: φ = −sign(f)(√(|r − c|² + f²) − |f|), the phase difference between a
//! plane wave along the normal and a spherical wave about the focal point at distance f from c.
//! Its kick −sign(f)(r − c)/√(|r − c|² + f²) is the tangential part of the unit vector from r
//! towards the focal point (away from it for f < 0), so a bundle along the normal meets the
//! focus exactly, and rays from a focal point leave exactly parallel, at any aperture.

use glam::DVec2;
use serde::Deserialize;

use super::Phase;
use crate::keys::{NonZero, Vector2};

/// φ = −sign(focal_length)(√(|r − centre|² + focal_length²) − |focal_length|).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LensPhase {
    pub focal_length: f64,
    pub centre: DVec2,
}

impl LensPhase {
    pub fn gradient(&self, r: DVec2) -> DVec2 {
        let f = self.focal_length;
        let r = r - self.centre;
        -r / (f * (1.0 + r.length_squared() / (f * f)).sqrt())
    }
}

/// `phase = { type = "lens", focal_length = f, centre = [u, v] }` (centre (0, 0) when not
/// given).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LensPhaseKeys {
    focal_length: NonZero,
    centre: Option<Vector2>,
}

impl LensPhaseKeys {
    pub fn build(self) -> Result<Phase, String> {
        Ok(Phase::Lens(LensPhase {
            focal_length: self.focal_length.0,
            centre: self.centre.map_or(DVec2::ZERO, |c| c.0),
        }))
    }
}
