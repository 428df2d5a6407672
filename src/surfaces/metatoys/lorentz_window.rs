//! A window that changes ray directions like a Lorentz transformation (§6): looking through it
//! shows the scene as a camera moving with velocity β sees it (relativistic aberration, Eq 4).
//!
//! The paper gives no formula; this follows from its stated behaviour: the direction of each ray
//! traced back through the window changes as the camera's backwards-traced rays do on entering
//! the scene frame (§2.1, Eq 4), d′ ∝ d + (γ − 1)(β̂·d)β̂ − γ|d|β. The window changes only
//! directions, not times or positions, so unlike a moving camera it shows no light-travel-time
//! effects. The law is not reciprocal (aberration by β does not undo itself for reversed rays);
//! it is applied to rays arriving from either side, and the ray continues in the new direction
//! whichever side of the window that points to.
//!
//! β here is the velocity of the virtual camera, in the global basis or in the surface's local
//! (u, v, w) basis at each point (`basis`, as Dr TIM's class allows). Dr TIM's `LorentzTransformInterface` takes
//! the apparent velocity of the world seen through the surface, which is −β: its
//! d′ ∝ d⊥/γ + d∥ + β_DrTIM (for unit d, parts along and across β) is the same direction with
//! β_DrTIM = −β.

use glam::DVec3;
use serde::Deserialize;

use super::{Basis, jacobian};
use crate::geometry::Interaction;
use crate::keys::{Coefficient, Vector, throughput};
use crate::math::Colour;
use crate::math::LorentzTransform;
use crate::surfaces::{Redirection, Surface};

#[derive(Debug, Clone, PartialEq)]
pub struct LorentzWindow {
    /// The boost of the virtual camera, velocity β (|β| < 1; Dr TIM's β is −β).
    pub boost: LorentzTransform,
    /// The basis β is given in.
    pub basis: Basis,
    /// Fraction of the light transmitted, in [0, 1].
    pub transmission_coefficient: f64,
}

impl LorentzWindow {
    /// The unit direction a traced ray with direction `d` leaves in (β global).
    pub fn direction(&self, d: DVec3) -> DVec3 {
        self.boost.backwards_direction(d).normalize()
    }

    /// The direction a ray leaves in at `at`: in the local basis, the boost is applied to the
    /// ray's local components (the frame is orthonormal, so that is the boost by the global
    /// β = Λβ_local, Eq 38).
    pub fn redirect(&self, at: &Interaction) -> Redirection<'static> {
        let d = at.ray.direction;
        let direction = match self.basis {
            Basis::Global => self.direction(d),
            Basis::Local => {
                let l = jacobian(&at.frame());
                l * self.direction(l.transpose() * d)
            }
        };
        Redirection::Leaves {
            direction,
            factor: Colour::splat(self.transmission_coefficient),
        }
    }
}

/// `type = "lorentz-window"`: the window's velocity `beta` (in units of c, magnitude below 1;
/// Dr TIM's GUI's 0 where not given), in the global (default) or local `basis`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LorentzWindowKeys {
    beta: Option<Vector>,
    basis: Option<Basis>,
    #[serde(alias = "transmission")]
    transmission_coefficient: Option<Coefficient>,
}

impl LorentzWindowKeys {
    pub fn build(self) -> Result<Surface, String> {
        let beta = self.beta.map_or(glam::DVec3::ZERO, |b| b.0);
        Ok(Surface::LorentzWindow(LorentzWindow {
            boost: LorentzTransform::new(beta).ok_or_else(|| {
                format!(
                    "lorentz-window: beta = {beta} must have magnitude below 1 (the speed of light)"
                )
            })?,
            basis: self.basis.unwrap_or_default(),
            transmission_coefficient: throughput(self.transmission_coefficient),
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The aberration formula: light reaching an observer moving with speed β along z from the
    /// angle θ′ to its motion came, in the frame it left, from θ with
    /// cos θ = (cos θ′ − β)/(1 − β cos θ′); the azimuth is unchanged. Traced rays point
    /// towards where the light came from.
    #[test]
    fn traced_directions_follow_the_aberration_formula() {
        let beta = 0.8;
        let window = LorentzWindow {
            boost: LorentzTransform::new(DVec3::new(0.0, 0.0, beta)).unwrap(),
            basis: Basis::Global,
            transmission_coefficient: 1.0,
        };
        for k in 0..50 {
            let (theta, azimuth) = (0.06 * k as f64, 0.4 * k as f64);
            let d = DVec3::new(
                theta.sin() * azimuth.cos(),
                theta.sin() * azimuth.sin(),
                theta.cos(),
            );
            let out = window.direction(d);
            let cos_expected = (theta.cos() - beta) / (1.0 - beta * theta.cos());
            assert!((out.z - cos_expected).abs() < 1e-14, "θ′ = {theta}: {out}");
            if k > 0 {
                assert!((out.y.atan2(out.x) - azimuth.sin().atan2(azimuth.cos())).abs() < 1e-12);
            }
        }
        // Looking forwards, the view widens: a ray 10° off the motion was traced from farther.
        let d = DVec3::new(10f64.to_radians().sin(), 0.0, 10f64.to_radians().cos());
        assert!(window.direction(d).z < d.z);
    }

    /// Dr TIM's definition, d′ ∝ d⊥/γ + d∥ + β_DrTIM, gives the same directions with
    /// β_DrTIM = −β.
    #[test]
    fn dr_tims_beta_is_minus_the_camera_velocity() {
        let beta = DVec3::new(0.3, -0.5, 0.4);
        let window = LorentzWindow {
            boost: LorentzTransform::new(beta).unwrap(),
            basis: Basis::Global,
            transmission_coefficient: 1.0,
        };
        let gamma = 1.0 / (1.0 - beta.length_squared()).sqrt();
        for d in [
            DVec3::Z,
            DVec3::new(0.6, 0.0, -0.8),
            DVec3::new(0.2, 0.9, 0.1),
        ] {
            let d = d.normalize();
            let along = d.project_onto(beta);
            let dr_tim = ((d - along) / gamma + along - beta).normalize();
            assert!((window.direction(d) - dr_tim).length() < 1e-15, "{d}");
        }
    }
}
