//! Dr TIM's `PhaseHologramOfLogarithmicCylindricalLensSpiral_02`: a cylindrical lens of focal
//! length f wound into the logarithmic spiral r = a exp(bθ) about the centre, with the phase
//! −(ρ − r_n)²/(2f) of the winding nearest along the radius. It is the logarithmic
//! [cylindrical-lens spiral](super::CylindricalLensSpiralPhase) rotated by δ = ln(a)/b
//! (a exp(bψ) = exp(b(ψ + ln(a)/b))), without winding focusing; these keys make that phase.

use glam::DVec2;
use serde::Deserialize;

use super::{CylindricalLensSpiralPhase, Phase, SpiralType};
use crate::keys::{NonZero, Positive, Vector2};

/// `phase = { type = "logarithmic-cylindrical-lens-spiral", focal_length = f, a = a, b = b,
/// centre = [u, v] }` (f, a and b required; centre (0, 0) when not given).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LogarithmicCylindricalLensSpiralPhaseKeys {
    focal_length: NonZero,
    a: Positive,
    b: NonZero,
    centre: Option<Vector2>,
}

impl LogarithmicCylindricalLensSpiralPhaseKeys {
    pub fn build(self) -> Result<Phase, String> {
        Ok(Phase::CylindricalLensSpiral(CylindricalLensSpiralPhase {
            spiral: SpiralType::Logarithmic,
            focal_length: self.focal_length.0,
            b: self.b.0,
            rotation: self.a.0.ln() / self.b.0,
            alvarez_winding_focusing: false,
            centre: self.centre.map_or(DVec2::ZERO, |c| c.0),
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The centre line r = a exp(bθ), written out: on it (at θ = 0.3 and its next windings
    /// out and in, a exp(b(θ ± 2π))) the kick vanishes, and a ray along the normal a small
    /// radial distance d from it gets the radial kick −d/f of a cylindrical lens of focal
    /// length f.
    #[test]
    fn the_centre_line_is_r_equals_a_exp_b_theta() {
        let keys: LogarithmicCylindricalLensSpiralPhaseKeys =
            toml::from_str("focal_length = 0.2\na = 1.3\nb = 0.04\ncentre = [0.1, 0.2]").unwrap();
        let phase = keys.build().unwrap();
        let theta = 0.3f64;
        let direction = DVec2::from_angle(theta);
        for turns in [-1.0, 0.0, 1.0] {
            let r_n = 1.3 * (0.04 * (theta + std::f64::consts::TAU * turns)).exp();
            let on = DVec2::new(0.1, 0.2) + r_n * direction;
            assert!(phase.gradient(on).length() < 1e-14, "{turns}");
            let d = 1e-3;
            let radial = phase.gradient(on + d * direction).dot(direction);
            assert!((radial + d / 0.2).abs() < 1e-12, "{turns}: {radial}");
        }
    }
}
