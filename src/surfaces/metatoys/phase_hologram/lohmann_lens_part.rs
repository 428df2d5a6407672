//! One part of an Alvarez–Lohmann lens, Dr TIM's `PhaseHologramOfLohmannLensPart`: the cubic
//! phase φ = a (u³/6 + u v²/2), with (u, v) measured from the part's principal point c along û
//! (at an angle α from the surface's u, towards v) and v̂ ⊥ û; kick a ((u² + v²)/2 û + u v v̂).
//!
//! Two parts, +a and −a, their principal points offset by Δ along û (the +a part's by +Δ/2,
//! the other's by −Δ/2), add up to φ(a, u − Δ/2, v) − φ(a, u + Δ/2, v)
//! = −a Δ (u² + v²)/2 − a Δ³/24: a lens of power 1/f = a Δ (Lohmann's form of Alvarez's lens;
//! a is Dr TIM's `focalPowerOverDeltaU`). An offset along v̂ instead gives oblique
//! astigmatism.

use glam::DVec2;
use serde::Deserialize;

use super::Phase;
use crate::keys::{Finite, Vector2};

/// φ = `power_per_offset` (u³/6 + u v²/2) about `centre`, û at `u_angle` (radians) from u.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LohmannLensPartPhase {
    pub power_per_offset: f64,
    pub centre: DVec2,
    pub u_angle: f64,
}

impl LohmannLensPartPhase {
    pub fn gradient(&self, r: DVec2) -> DVec2 {
        let u_hat = DVec2::from_angle(self.u_angle);
        let v_hat = u_hat.perp();
        let s = r - self.centre;
        let (u, v) = (s.dot(u_hat), s.dot(v_hat));
        self.power_per_offset * (0.5 * (u * u + v * v) * u_hat + u * v * v_hat)
    }
}

/// `phase = { type = "lohmann-lens-part", power_per_offset = a, centre = [u, v],
/// u_angle_deg = α }` (a required; centre (0, 0) and α = 0 when not given).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LohmannLensPartPhaseKeys {
    power_per_offset: Finite,
    centre: Option<Vector2>,
    u_angle_deg: Option<Finite>,
}

impl LohmannLensPartPhaseKeys {
    pub fn build(self) -> Result<Phase, String> {
        Ok(Phase::LohmannLensPart(LohmannLensPartPhase {
            power_per_offset: self.power_per_offset.0,
            centre: self.centre.map_or(DVec2::ZERO, |c| c.0),
            u_angle: self.u_angle_deg.map_or(0.0, |a| a.0).to_radians(),
        }))
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;
    use crate::surfaces::metatoys::hologram_direction;

    #[test]
    fn the_kick_is_the_gradient_of_the_cubic_phase() {
        let (a, c, alpha) = (1.7, DVec2::new(0.2, -0.4), -0.6f64);
        let part = LohmannLensPartPhase {
            power_per_offset: a,
            centre: c,
            u_angle: alpha,
        };
        let phase = |r: DVec2| {
            let s = r - c;
            let u = s.x * alpha.cos() + s.y * alpha.sin();
            let v = -s.x * alpha.sin() + s.y * alpha.cos();
            a * (u.powi(3) / 6.0 + u * v * v / 2.0)
        };
        let h = 1e-5;
        for k in 0..100 {
            let r = DVec2::new(-1.0 + 0.021 * k as f64, 0.8 - 0.013 * k as f64);
            let fd = DVec2::new(
                phase(r + DVec2::X * h) - phase(r - DVec2::X * h),
                phase(r + DVec2::Y * h) - phase(r - DVec2::Y * h),
            ) / (2.0 * h);
            assert!((part.gradient(r) - fd).length() < 1e-9, "{r}");
        }
    }

    /// The Alvarez lens (L. W. Alvarez, US patent 3,305,294, 1967): two plates of thickness
    /// t(x, y) = A (x y² + x³/3) and −t, of refractive index n, shifted by +δ and −δ along x,
    /// add up to t(x − δ, y) − t(x + δ, y) = −2Aδ (x² + y²) − 2Aδ³/3: the thickness profile of a
    /// thin lens of power P = 4Aδ(n − 1) (a lens's optical path (n − 1)t = −(x² + y²)/(2f)).
    /// A plate's optical path is (n − 1)A (x y² + x³/3), which is the Lohmann part's phase
    /// a (u³/6 + u v²/2) for a = 2(n − 1)A, so the textbook formula says: parts of ±a shifted
    /// by ±s have P = 4Aδ(n − 1) = 2 a s, i.e. a times the whole offset Δ = 2s between them.
    ///
    /// Checked on rays along the normal through the two parts, without a gap between them (the
    /// kicks add): each leaves as from a thin lens of focal length f = 1/(2as), its direction's
    /// tangential part −ρ/f, exactly, so it meets the axis at f √(1 − ρ²/f²); the power is
    /// proportional to s.
    #[test]
    fn two_parts_shifted_by_plus_and_minus_s_are_a_lens_of_power_2as() {
        let (a, c, alpha) = (1.5, DVec2::new(0.1, 0.3), 0.3f64);
        let u_hat = DVec2::from_angle(alpha);
        for s in [0.01, 0.05, -0.08, 0.2] {
            let plus = LohmannLensPartPhase {
                power_per_offset: a,
                centre: c + s * u_hat,
                u_angle: alpha,
            };
            let minus = LohmannLensPartPhase {
                power_per_offset: -a,
                centre: c - s * u_hat,
                u_angle: alpha,
            };
            let f = 1.0 / (2.0 * a * s);
            for (rho, theta) in [(0.05, 0.0), (0.2, 1.0), (0.3, -2.5), (0.11, 3.0)] {
                let offset = rho * DVec2::from_angle(theta);
                let r = c + offset;
                let kick = plus.gradient(r) + minus.gradient(r);
                let out = hologram_direction(DVec3::Z, kick).unwrap();
                let tangential = DVec2::new(out.x, out.y);
                assert!(
                    (tangential + offset / f).length() < 1e-12,
                    "s = {s}, ρ = {rho}"
                );
                // Where it meets the axis through c (behind the hologram for f > 0, where it
                // seems to come from in front for f < 0).
                let z = -rho * rho / tangential.dot(offset) * out.z;
                assert!((z - f * (1.0 - rho * rho / (f * f)).sqrt()).abs() < 1e-9 * f.abs());
            }
        }
    }
}
