//! A radial lenticular array, Dr TIM's `PhaseHologramOfRadialLenticularArray`: n cylindrical
//! lenses of focal length f whose cylinder axes are radial lines through the centre c, at
//! angles ψ_i = ψ_0 + 2πi/n from u (towards v). Each lens covers the sector of angles within
//! π/n of its axis (Dr TIM's i = floor(θ/(2π/n) + 1/2), θ ∈ (−π, π] measured from the 0th axis)
//! and has the cylindrical lens's phase about its axis, φ = −(m_i·(r − c))²/(2f) with m_i the
//! in-plane direction perpendicular to it: the kick points back to the sector's axis.
//!
//! **Dr TIM**: its number of lenses is any real number (a non-integer n leaves a narrower
//! sector at θ = π); here it is a whole number.

use std::f64::consts::TAU;
use std::num::NonZeroU32;

use glam::DVec2;
use serde::Deserialize;

use super::{CylindricalPhase, Phase};
use crate::keys::{Finite, NonZero, Vector2};

/// `number_of_lenses` cylindrical lenses of focal length `focal_length` with their axes through
/// `centre`, the 0th at `axis_angle` (radians) from u towards v.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RadialLenticularArrayPhase {
    pub focal_length: f64,
    pub centre: DVec2,
    pub number_of_lenses: u32,
    pub axis_angle: f64,
}

impl RadialLenticularArrayPhase {
    pub fn gradient(&self, r: DVec2) -> DVec2 {
        let step = TAU / f64::from(self.number_of_lenses);
        // θ from the 0th axis, in (−π, π].
        let s = DVec2::from_angle(-self.axis_angle).rotate(r - self.centre);
        let i = (s.y.atan2(s.x) / step + 0.5).floor();
        CylindricalPhase {
            focal_length: self.focal_length,
            centre: self.centre,
            axis_angle: self.axis_angle + i * step,
        }
        .gradient(r)
    }
}

/// `phase = { type = "radial-lenticular-array", focal_length = f, number_of_lenses = n,
/// centre = [u, v], axis_angle_deg = ψ0 }`, with the defaults of Dr TIM's surface-property
/// panel: f = 1, n = 4, the 0th axis along u (ψ0 = 0), centred on (0, 0).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RadialLenticularArrayPhaseKeys {
    focal_length: Option<NonZero>,
    number_of_lenses: Option<NonZeroU32>,
    centre: Option<Vector2>,
    axis_angle_deg: Option<Finite>,
}

impl RadialLenticularArrayPhaseKeys {
    pub fn build(self) -> Result<Phase, String> {
        Ok(Phase::RadialLenticularArray(RadialLenticularArrayPhase {
            focal_length: self.focal_length.map_or(1.0, |f| f.0),
            number_of_lenses: self.number_of_lenses.map_or(4, NonZeroU32::get),
            centre: self.centre.map_or(DVec2::ZERO, |c| c.0),
            axis_angle: self.axis_angle_deg.map_or(0.0, |a| a.0).to_radians(),
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The phase of the lens whose sector holds r, written in polar coordinates about the
    /// centre: a point at distance ρ and angle θ from the sector's axis is ρ sin(θ) from it, so
    /// φ = −ρ² sin²(θ − ψ_i)/(2f); differentiated by central differences away from the sector
    /// edges. On an axis the kick vanishes; elsewhere it points back towards the sector's axis.
    #[test]
    fn each_sector_is_a_cylindrical_lens_about_its_radial_axis() {
        let (f, n, c, psi0) = (-1.3, 5u32, DVec2::new(0.2, -0.1), 0.4f64);
        let array = RadialLenticularArrayPhase {
            focal_length: f,
            centre: c,
            number_of_lenses: n,
            axis_angle: psi0,
        };
        let step = TAU / n as f64;
        let axis = |theta: f64| psi0 + ((theta - psi0) / step).round() * step;
        let phase = |r: DVec2| {
            let s = r - c;
            let theta = s.y.atan2(s.x);
            -(s.length() * (theta - axis(theta)).sin()).powi(2) / (2.0 * f)
        };
        let h = 1e-6;
        let mut checked = 0;
        for k in 0..300 {
            let theta = 0.0731 * k as f64 - 7.0;
            let rho = 0.05 + 0.01 * (k % 37) as f64;
            let r = c + rho * DVec2::from_angle(theta);
            let off = (theta - axis(theta)).rem_euclid(TAU);
            let off = if off > std::f64::consts::PI {
                off - TAU
            } else {
                off
            };
            if (off.abs() - step / 2.0).abs() < 1e-3 {
                continue;
            }
            let fd = DVec2::new(
                phase(r + DVec2::X * h) - phase(r - DVec2::X * h),
                phase(r + DVec2::Y * h) - phase(r - DVec2::Y * h),
            ) / (2.0 * h);
            let kick = array.gradient(r);
            assert!((kick - fd).length() < 1e-8, "θ = {theta}: {kick} {fd}");
            // Towards the axis for f > 0, away from it for f < 0: along ∓ the offset's side.
            let across = DVec2::from_angle(axis(theta)).perp();
            assert!(kick.dot(across) * off.signum() * f.signum() <= 0.0);
            checked += 1;
        }
        assert!(checked > 280, "{checked}");
        // On the axes themselves: no kick.
        for i in 0..n {
            let r = c + 0.3 * DVec2::from_angle(psi0 + i as f64 * step);
            assert!(array.gradient(r).length() < 1e-15, "{i}");
        }
    }
}
