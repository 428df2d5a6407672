//! Two crossed linear-power lenticular arrays in one hologram, Dr TIM's
//! `PhaseHologramOfCrossedLinearPowerLenticularArrays`: the phases of two
//! [linear-power lenticular arrays](super::LinearPowerLenticularArrayPhase) with the same point
//! c, period p and dP/du, one periodic along û (at α_u from u), the other along v̂ (at α_v):
//! φ = −P_m (u − u_m)²/2 − P_n (v − v_n)²/2 with u = (r − c)·û, v = (r − c)·v̂, u_m = m p,
//! v_n = n p, P_m = (dP/du) u_m and P_n = (dP/du) v_n.
//!
//! With Dr TIM's Alvarez focusing ("pixel focusing") each strip also gets the cubic phase of a
//! Lohmann cylindrical lens part of −dP/du about its axis, −(dP/du)(u − u_m)³/6 (and the same
//! in v), so that its power, −∂²φ/∂u² = P_m + (dP/du)(u − u_m) = (dP/du) u, is that of the
//! integral lens at every point of the strip, not only on its axis.

use glam::DVec2;
use serde::Deserialize;

use super::{LinearPowerLenticularArrayPhase, LohmannCylindricalLensPartPhase, Phase};
use crate::keys::{Finite, Positive, Vector2};

/// The arrays `u` and `v`, each with its own direction; with `alvarez_focusing`, each strip's
/// Lohmann term.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CrossedLinearPowerLenticularArraysPhase {
    pub u: LinearPowerLenticularArrayPhase,
    pub v: LinearPowerLenticularArrayPhase,
    pub alvarez_focusing: bool,
}

impl CrossedLinearPowerLenticularArraysPhase {
    pub fn gradient(&self, r: DVec2) -> DVec2 {
        [self.u, self.v]
            .iter()
            .map(|array| {
                let lens = array.lens(r);
                let cylindrical = lens.gradient(r);
                if self.alvarez_focusing {
                    let part = LohmannCylindricalLensPartPhase {
                        power_per_offset: -array.power_gradient,
                        centre: lens.centre,
                        u_angle: array.u_angle,
                    };
                    cylindrical + part.gradient(r)
                } else {
                    cylindrical
                }
            })
            .sum()
    }
}

/// `phase = { type = "crossed-linear-power-lenticular-arrays", power_gradient = dP/du,
/// period = p, centre = [u, v], u_angle_deg = α_u, v_angle_deg = α_v, alvarez_focusing = false }`,
/// with the defaults of Dr TIM's surface-property panel: dP/du = 1, p = 1, c = (0, 0), û along
/// u and v̂ along v (α_u = 0, α_v = 90), no Alvarez focusing.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CrossedLinearPowerLenticularArraysPhaseKeys {
    power_gradient: Option<Finite>,
    period: Option<Positive>,
    centre: Option<Vector2>,
    u_angle_deg: Option<Finite>,
    v_angle_deg: Option<Finite>,
    alvarez_focusing: Option<bool>,
}

impl CrossedLinearPowerLenticularArraysPhaseKeys {
    pub fn build(self) -> Result<Phase, String> {
        let array = |angle_deg: f64| LinearPowerLenticularArrayPhase {
            centre: self.centre.map_or(DVec2::ZERO, |c| c.0),
            u_angle: angle_deg.to_radians(),
            period: self.period.map_or(1.0, |p| p.0),
            power_gradient: self.power_gradient.map_or(1.0, |p| p.0),
        };
        Ok(Phase::CrossedLinearPowerLenticularArrays(
            CrossedLinearPowerLenticularArraysPhase {
                u: array(self.u_angle_deg.map_or(0.0, |a| a.0)),
                v: array(self.v_angle_deg.map_or(90.0, |a| a.0)),
                alvarez_focusing: self.alvarez_focusing.unwrap_or(false),
            },
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The crossed arrays' phase written out in the strips' coordinates, with and without the
    /// Alvarez term, differentiated by central differences away from the strip edges; with
    /// Alvarez focusing the power across a strip, −∂²φ/∂u² (second differences along û), is
    /// (dP/du) u at every point of it, the integral lens's.
    #[test]
    fn the_kick_is_the_gradient_of_both_arrays_phases() {
        let (c, p, g) = (DVec2::new(-0.1, 0.2), 0.3, 1.4);
        let (au, av) = (0.2f64, 1.9f64);
        let (u_hat, v_hat) = (DVec2::from_angle(au), DVec2::from_angle(av));
        let array = |angle: f64| LinearPowerLenticularArrayPhase {
            centre: c,
            u_angle: angle,
            period: p,
            power_gradient: g,
        };
        for alvarez in [false, true] {
            let crossed = CrossedLinearPowerLenticularArraysPhase {
                u: array(au),
                v: array(av),
                alvarez_focusing: alvarez,
            };
            let strip = |x: f64| {
                let n = (x / p).round();
                let d = x - n * p;
                let cubic = if alvarez { g * d.powi(3) / 6.0 } else { 0.0 };
                -g * n * p * d * d / 2.0 - cubic
            };
            let phase = |r: DVec2| strip((r - c).dot(u_hat)) + strip((r - c).dot(v_hat));
            let h = 1e-5;
            let mut checked = 0;
            for k in 0..300 {
                let r = DVec2::new(-2.0 + 0.0137 * k as f64, 1.7 - 0.0119 * k as f64);
                let near_edge = |x: f64| {
                    let t = x / p;
                    (t - t.floor() - 0.5).abs() < 1e-3
                };
                if near_edge((r - c).dot(u_hat)) || near_edge((r - c).dot(v_hat)) {
                    continue;
                }
                let fd = DVec2::new(
                    phase(r + DVec2::X * h) - phase(r - DVec2::X * h),
                    phase(r + DVec2::Y * h) - phase(r - DVec2::Y * h),
                ) / (2.0 * h);
                assert!((crossed.gradient(r) - fd).length() < 1e-8, "{alvarez} {r}");
                checked += 1;
            }
            assert!(checked > 280);
        }
        let pixel_focused = CrossedLinearPowerLenticularArraysPhase {
            u: array(au),
            v: array(au + std::f64::consts::FRAC_PI_2),
            alvarez_focusing: true,
        };
        for u in [0.5, 0.55, 0.65, -0.8, 1.3] {
            let r = c + u * u_hat + 0.05 * u_hat.perp();
            let h = 1e-4;
            let k = |x: f64| pixel_focused.gradient(r + x * u_hat).dot(u_hat);
            let power = -(k(h) - k(-h)) / (2.0 * h);
            assert!((power - g * u).abs() < 1e-6, "u = {u}: {power}");
        }
    }
}
