//! One part of an Alvarez–Lohmann cylindrical lens, Dr TIM's
//! `PhaseHologramOfLohmannCylindricalLensPart`: φ = a u³/6, with u measured from a point c of
//! the part's principal axis (which runs along v̂) along û, at an angle α from the surface's u
//! towards v; kick a u²/2 û.
//!
//! Two parts, +a and −a, offset by Δ along û (the +a part by +Δ/2), add up to
//! a ((u − Δ/2)³ − (u + Δ/2)³)/6 = −a Δ u²/2 − a Δ³/24: a cylindrical lens focusing along û, of
//! power 1/f = a Δ (a is Dr TIM's `focalPowerOverDeltaU`).

use glam::DVec2;
use serde::Deserialize;

use super::Phase;
use crate::keys::{Finite, Vector2};

/// φ = `power_per_offset` u³/6, u along û (at `u_angle` radians from u) from `centre`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LohmannCylindricalLensPartPhase {
    pub power_per_offset: f64,
    pub centre: DVec2,
    pub u_angle: f64,
}

impl LohmannCylindricalLensPartPhase {
    pub fn gradient(&self, r: DVec2) -> DVec2 {
        let u_hat = DVec2::from_angle(self.u_angle);
        let u = (r - self.centre).dot(u_hat);
        0.5 * self.power_per_offset * u * u * u_hat
    }
}

/// `phase = { type = "lohmann-cylindrical-lens-part", power_per_offset = a, centre = [u, v],
/// u_angle_deg = α }` (a required; centre (0, 0) and α = 0 when not given).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LohmannCylindricalLensPartPhaseKeys {
    power_per_offset: Finite,
    centre: Option<Vector2>,
    u_angle_deg: Option<Finite>,
}

impl LohmannCylindricalLensPartPhaseKeys {
    pub fn build(self) -> Result<Phase, String> {
        Ok(Phase::LohmannCylindricalLensPart(
            LohmannCylindricalLensPartPhase {
                power_per_offset: self.power_per_offset.0,
                centre: self.centre.map_or(DVec2::ZERO, |c| c.0),
                u_angle: self.u_angle_deg.map_or(0.0, |a| a.0).to_radians(),
            },
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The gradient of a u³/6 by central differences; and the pair ±a offset by ±s is the
    /// cylindrical lens of power 2as (the 1D Alvarez lens: t(x − δ) − t(x + δ) = −2Aδx² − …
    /// for plates of thickness ±A x³/3, a = 2(n − 1)A as for the spherical part): its kick is
    /// −2as (u-offset) û, nothing along the axis.
    #[test]
    fn the_pair_is_a_cylindrical_lens_of_power_2as() {
        let (a, c, alpha) = (-2.3, DVec2::new(0.4, 0.1), 1.1f64);
        let part = LohmannCylindricalLensPartPhase {
            power_per_offset: a,
            centre: c,
            u_angle: alpha,
        };
        let u_hat = DVec2::new(alpha.cos(), alpha.sin());
        let phase = |r: DVec2| a * (r - c).dot(u_hat).powi(3) / 6.0;
        let h = 1e-5;
        for k in 0..100 {
            let r = DVec2::new(-1.0 + 0.021 * k as f64, 0.8 - 0.013 * k as f64);
            let fd = DVec2::new(
                phase(r + DVec2::X * h) - phase(r - DVec2::X * h),
                phase(r + DVec2::Y * h) - phase(r - DVec2::Y * h),
            ) / (2.0 * h);
            assert!((part.gradient(r) - fd).length() < 1e-9, "{r}");
        }
        let s = 0.07;
        let plus = LohmannCylindricalLensPartPhase {
            centre: c + s * u_hat,
            ..part
        };
        let minus = LohmannCylindricalLensPartPhase {
            power_per_offset: -a,
            centre: c - s * u_hat,
            ..part
        };
        for (x, y) in [(0.1, 0.0), (-0.3, 2.0), (0.25, -1.0)] {
            let r = c + x * u_hat + y * u_hat.perp();
            let kick = plus.gradient(r) + minus.gradient(r);
            assert!((kick + 2.0 * a * s * x * u_hat).length() < 1e-14, "{kick}");
        }
    }
}
