//! A thin lens's paraxial phase, Dr TIM's `PhaseHologramOfLens`: φ = −|r − c|²/(2f) about a
//! centre c, kick −(r − c)/f, which focuses a parallel bundle at distance f (paraxially; exactly
//! in the limit of small apertures).

use glam::DVec2;
use serde::Deserialize;

use super::Phase;
use crate::keys::{NonZero, Vector2};

/// φ = −|r − centre|²/(2 focal_length).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct QuadraticPhase {
    pub focal_length: f64,
    pub centre: DVec2,
}

impl QuadraticPhase {
    pub fn gradient(&self, r: DVec2) -> DVec2 {
        -(r - self.centre) / self.focal_length
    }
}

/// `phase = { type = "quadratic", focal_length = f, centre = [u, v] }` (centre (0, 0) when not
/// given).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct QuadraticPhaseKeys {
    focal_length: NonZero,
    centre: Option<Vector2>,
}

impl QuadraticPhaseKeys {
    pub fn build(self) -> Result<Phase, String> {
        Ok(Phase::Quadratic(QuadraticPhase {
            focal_length: self.focal_length.0,
            centre: self.centre.map_or(DVec2::ZERO, |c| c.0),
        }))
    }
}
