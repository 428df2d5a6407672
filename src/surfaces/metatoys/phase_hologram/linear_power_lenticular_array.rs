//! A lenticular array whose power grows linearly across it, Dr TIM's
//! `PhaseHologramOfLinearPowerLenticularArray`: cylindrical lenses side by side along the
//! direction û (at an angle α from u), each a strip of width p (the period) about its cylinder
//! axis, which is perpendicular to û. With u measured along û from c, a point on the 0th lens's
//! axis, the n-th lens's axis is at u_n = n p (n = floor(u/p + 1/2)) and its focal power is
//! P_n = (dP/du) u_n, so its phase is φ = −P_n (u − u_n)²/2 (the cylindrical lens of focal
//! length 1/P_n; the 0th lens has no power, and lenses at negative u_n diverge for dP/du > 0).

use std::f64::consts::FRAC_PI_2;

use glam::DVec2;
use serde::Deserialize;

use super::{CylindricalPhase, Phase};
use crate::keys::{Finite, Positive, Vector2};

/// Cylindrical lenses of width `period` with their axes at `centre` + n `period` û, û at
/// `u_angle` (radians) from u towards v, the n-th of power `power_gradient` · n `period`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinearPowerLenticularArrayPhase {
    pub centre: DVec2,
    pub u_angle: f64,
    pub period: f64,
    pub power_gradient: f64,
}

impl LinearPowerLenticularArrayPhase {
    /// The cylindrical lens whose strip holds `r`: its axis through `centre` + u_n û, its
    /// focal length 1/P_n (infinite, so no kick, for the 0th lens: 1/0 = ∞ in floating point).
    pub(super) fn lens(&self, r: DVec2) -> CylindricalPhase {
        let u_hat = DVec2::from_angle(self.u_angle);
        let u_n = self.period * ((r - self.centre).dot(u_hat) / self.period + 0.5).floor();
        CylindricalPhase {
            focal_length: 1.0 / (self.power_gradient * u_n),
            centre: self.centre + u_n * u_hat,
            axis_angle: self.u_angle + FRAC_PI_2,
        }
    }

    pub fn gradient(&self, r: DVec2) -> DVec2 {
        self.lens(r).gradient(r)
    }
}

/// `phase = { type = "linear-power-lenticular-array", power_gradient = dP/du, period = p,
/// centre = [u, v], u_angle_deg = α }`, with the defaults of Dr TIM's surface-property panel:
/// dP/du = 1, p = 1, the 0th lens's axis through (0, 0), û along u (α = 0).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LinearPowerLenticularArrayPhaseKeys {
    power_gradient: Option<Finite>,
    period: Option<Positive>,
    centre: Option<Vector2>,
    u_angle_deg: Option<Finite>,
}

impl LinearPowerLenticularArrayPhaseKeys {
    pub fn build(self) -> Result<Phase, String> {
        Ok(Phase::LinearPowerLenticularArray(
            LinearPowerLenticularArrayPhase {
                centre: self.centre.map_or(DVec2::ZERO, |c| c.0),
                u_angle: self.u_angle_deg.map_or(0.0, |a| a.0).to_radians(),
                period: self.period.map_or(1.0, |p| p.0),
                power_gradient: self.power_gradient.map_or(1.0, |p| p.0),
            },
        ))
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;
    use crate::surfaces::metatoys::hologram_direction;

    /// The n-th strip's phase, written along û: φ = −(dP/du) n p (u − n p)²/2; central
    /// differences away from the strip edges. And each strip is a cylindrical lens of focal
    /// length 1/(dP/du · n p): rays along the normal through it meet its axis line there
    /// (within the paraxial aberration s³/f² of a ray s from the axis).
    #[test]
    fn each_strip_is_a_cylindrical_lens_of_its_own_power() {
        let (c, alpha, p, g) = (DVec2::new(0.3, -0.2), 0.5f64, 0.25, 0.8);
        let array = LinearPowerLenticularArrayPhase {
            centre: c,
            u_angle: alpha,
            period: p,
            power_gradient: g,
        };
        let u_hat = DVec2::new(alpha.cos(), alpha.sin());
        let phase = |r: DVec2| {
            let u = (r - c).dot(u_hat);
            let n = (u / p).round();
            -g * n * p * (u - n * p).powi(2) / 2.0
        };
        let h = 1e-6;
        for k in 0..200 {
            let r = DVec2::new(-2.0 + 0.0213 * k as f64, 1.5 - 0.017 * k as f64);
            let u = (r - c).dot(u_hat) / p;
            if (u - u.floor() - 0.5).abs() < 1e-3 {
                continue;
            }
            let fd = DVec2::new(
                phase(r + DVec2::X * h) - phase(r - DVec2::X * h),
                phase(r + DVec2::Y * h) - phase(r - DVec2::Y * h),
            ) / (2.0 * h);
            assert!((array.gradient(r) - fd).length() < 1e-8, "{r}");
        }
        for n in [-3, -1, 1, 2, 5] {
            let f = 1.0 / (g * n as f64 * p);
            for s in [0.1, -0.05, 0.12] {
                // A point s from the n-th axis, anywhere along it.
                let r = c + (n as f64 * p + s) * u_hat + 0.7 * u_hat.perp();
                let out = hologram_direction(DVec3::Z, array.gradient(r)).unwrap();
                let at = r + DVec2::new(out.x, out.y) * f / out.z;
                let miss = (at - c).dot(u_hat) - n as f64 * p;
                assert!(
                    miss.abs() <= s.abs().powi(3) / (f * f),
                    "n = {n}, s = {s}: {miss}"
                );
                assert!((at - r).dot(u_hat.perp()).abs() < 1e-12);
            }
        }
        // The 0th strip has no power.
        assert_eq!(array.gradient(c + 0.1 * u_hat), DVec2::ZERO);
    }
}
