//! A window that changes ray directions like a Galilean transformation: Dr TIM's
//! `GalileoTransformInterface`, the non-relativistic counterpart of the Lorentz window.
//!
//! Dr TIM's law is d′ = d̂ + β_DrTIM, with β_DrTIM the apparent velocity of the world seen
//! through the surface (in units of c). As for the Lorentz window, `beta` here is the velocity
//! of the virtual camera, β = −β_DrTIM, so d′ ∝ d̂ − β: the backwards-traced direction of a
//! camera moving at β if light travelled at c in the camera frame and its velocity added
//! classically, the first order in β of the Lorentz window's Eq 4. (A Galilean *camera*,
//! `transformation = "galileo"`, keeps light at c in the scene frame instead, which gives
//! different directions.) Only directions change; the law is not reciprocal and acts on rays
//! from either side. A ray for which d̂ = β (possible only for |β| = 1) has no direction and is
//! lost.

use glam::DVec3;
use serde::Deserialize;

use super::Basis;
use crate::geometry::Interaction;
use crate::keys::{Coefficient, Vector, throughput};
use crate::math::Colour;
use crate::surfaces::{Redirection, Surface};

#[derive(Debug, Clone, PartialEq)]
pub struct GalileoWindow {
    /// The velocity of the virtual camera (Dr TIM's β is −β), in `basis`.
    pub beta: DVec3,
    pub basis: Basis,
    /// Fraction of the light transmitted, in [0, 1].
    pub transmission_coefficient: f64,
}

/// The unit direction d̂ − β a traced ray with direction `d` leaves in, for the global `beta`.
pub fn galileo_direction(d: DVec3, beta: DVec3) -> DVec3 {
    (d.normalize() - beta).try_normalize().unwrap_or(DVec3::NAN)
}

impl GalileoWindow {
    pub fn redirect(&self, at: &Interaction) -> Redirection<'static> {
        Redirection::Leaves {
            direction: galileo_direction(
                at.ray.direction,
                self.basis.to_global(self.beta, &at.frame()),
            ),
            factor: Colour::splat(self.transmission_coefficient),
        }
    }
}

/// `type = "galileo-window"`: the virtual camera's velocity `beta` (in units of c; Dr TIM's
/// GUI's 0 where not given), in the global or local `basis`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GalileoWindowKeys {
    beta: Option<Vector>,
    basis: Option<Basis>,
    #[serde(alias = "transmission")]
    transmission_coefficient: Option<Coefficient>,
}

impl GalileoWindowKeys {
    pub fn build(self) -> Result<Surface, String> {
        Ok(Surface::GalileoWindow(GalileoWindow {
            beta: self.beta.map_or(DVec3::ZERO, |b| b.0),
            basis: self.basis.unwrap_or_default(),
            transmission_coefficient: throughput(self.transmission_coefficient),
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Classical aberration: a camera moving at β along z, with light travelling at c in its
    /// own frame, traces the ray it receives from the angle θ′ back along
    /// (sin θ′, 0, cos θ′) − (0, 0, β), at tan θ = sin θ′/(cos θ′ − β).
    #[test]
    fn traced_directions_subtract_the_velocity() {
        let beta = 0.5;
        for theta_deg in [0.0_f64, 30.0, 90.0, 150.0] {
            let t = theta_deg.to_radians();
            let out = galileo_direction(DVec3::new(t.sin(), 0.0, t.cos()), DVec3::Z * beta);
            let angle = out.x.atan2(out.z);
            let expected = t.sin().atan2(t.cos() - beta);
            assert!((angle - expected).abs() < 1e-14, "{theta_deg}: {angle}");
        }
        assert!(galileo_direction(DVec3::Z, DVec3::Z).is_nan());
        assert_eq!(galileo_direction(DVec3::Y, DVec3::ZERO), DVec3::Y);
    }

    /// Dr TIM's d′ = d̂ + β_DrTIM with β_DrTIM = −β.
    #[test]
    fn dr_tims_beta_is_minus_the_camera_velocity() {
        let beta = DVec3::new(0.3, -0.5, 1.4);
        let d = DVec3::new(0.2, 0.9, 0.1);
        let dr_tim = (d.normalize() + -beta).normalize();
        assert!((galileo_direction(d, beta) - dr_tim).length() < 1e-15);
    }
}
