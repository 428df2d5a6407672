//! A linear phase, a prism or diffraction grating: φ = g·(u, v), a constant kick g (§6).

use glam::DVec2;
use serde::Deserialize;

use super::Phase;
use crate::keys::Vector2;

/// φ = gradient · (u, v).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinearPhase {
    pub gradient: DVec2,
}

impl LinearPhase {
    pub fn gradient(&self, _r: DVec2) -> DVec2 {
        self.gradient
    }
}

/// `phase = { type = "linear", gradient = [gu, gv] }`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LinearPhaseKeys {
    gradient: Vector2,
}

impl LinearPhaseKeys {
    pub fn build(self) -> Result<Phase, String> {
        Ok(Phase::Linear(LinearPhase {
            gradient: self.gradient.0,
        }))
    }
}
