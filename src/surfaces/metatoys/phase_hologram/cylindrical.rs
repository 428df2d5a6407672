//! A cylindrical lens's paraxial phase, Dr TIM's `PhaseHologramOfCylindricalLens`, with its
//! axis at an angle ψ from u: φ = −(m·(r − c))²/(2f), m the in-plane unit vector perpendicular
//! to the axis.

use glam::DVec2;
use serde::Deserialize;

use super::Phase;
use crate::keys::{Finite, NonZero, Vector2};

/// φ = −(m·(r − centre))²/(2 focal_length), m ⊥ the cylinder axis, which is at `axis_angle`
/// (radians) from u towards v.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CylindricalPhase {
    pub focal_length: f64,
    pub centre: DVec2,
    pub axis_angle: f64,
}

impl CylindricalPhase {
    pub fn gradient(&self, r: DVec2) -> DVec2 {
        let (s, c) = self.axis_angle.sin_cos();
        let m = DVec2::new(-s, c);
        -m.dot(r - self.centre) * m / self.focal_length
    }
}

/// `phase = { type = "cylindrical", focal_length = f, centre = [u, v], axis_angle_deg = ψ }`
/// (centre (0, 0) and ψ = 0 when not given).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CylindricalPhaseKeys {
    focal_length: NonZero,
    centre: Option<Vector2>,
    axis_angle_deg: Option<Finite>,
}

impl CylindricalPhaseKeys {
    pub fn build(self) -> Result<Phase, String> {
        Ok(Phase::Cylindrical(CylindricalPhase {
            focal_length: self.focal_length.0,
            centre: self.centre.map_or(DVec2::ZERO, |c| c.0),
            axis_angle: self.axis_angle_deg.map_or(0.0, |a| a.0).to_radians(),
        }))
    }
}
