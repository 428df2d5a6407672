//! Refraction by Snell's law, n₁ sin θ₁ = n₂ sin θ₂, with total internal reflection.
//!
//! `index_ratio` is n_inside / n_outside, where "outside" is the side the outward normal points
//! to. Transmitted (or totally internally reflected) light is scaled by the transmission
//! coefficient; Fresnel reflection is not modelled, as in TIM.

use glam::DVec3;
use serde::Deserialize;

use super::mirror::reflect;
use super::{Redirection, Surface};
use crate::geometry::Interaction;
use crate::keys::{Coefficient, Positive, coefficient};

#[derive(Debug, Clone, PartialEq)]
pub struct Refractive {
    /// n_inside / n_outside.
    pub index_ratio: f64,
    /// Fraction of the light transmitted, in [0, 1].
    pub transmission_coefficient: f64,
}

/// Direction of the ray refracted at a surface with unit outward normal `n` and
/// n_inside / n_outside = `index_ratio`; `None` for total internal reflection.
/// The tangential component of the direction is scaled by n₁/n₂ (Snell's law in vector form);
/// the result is a unit vector when `d` is.
pub fn refract(d: DVec3, n: DVec3, index_ratio: f64) -> Option<DVec3> {
    // Orient the normal against the incoming ray; η = n₁/n₂ for the side the ray comes from.
    let entering = d.dot(n) < 0.0;
    let (n, eta) = if entering {
        (n, 1.0 / index_ratio)
    } else {
        (-n, index_ratio)
    };
    let cos_i = -d.dot(n);
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i);
    if sin2_t > 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some(eta * d + (eta * cos_i - cos_t) * n)
}

impl Refractive {
    pub fn redirect(&self, at: &Interaction) -> Redirection<'static> {
        let d = at.ray.direction;
        let n = at.normal();
        Redirection::Leaves {
            direction: refract(d, n, self.index_ratio).unwrap_or_else(|| reflect(d, n)),
            factor: self.transmission_coefficient,
        }
    }
}

/// `type = "refractive"`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RefractiveKeys {
    index_ratio: Positive,
    #[serde(alias = "transmission")]
    transmission_coefficient: Option<Coefficient>,
}

impl RefractiveKeys {
    pub fn build(self) -> Result<Surface, String> {
        Ok(Surface::Refractive(Refractive {
            index_ratio: self.index_ratio.0,
            transmission_coefficient: coefficient(self.transmission_coefficient),
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Direction in the x–y plane at angle θ to −y (travelling downwards onto the plane y = 0).
    fn downwards(theta: f64) -> DVec3 {
        DVec3::new(theta.sin(), -theta.cos(), 0.0)
    }

    #[test]
    fn snells_law_entering_glass() {
        // Air to glass (n = 1.5) at 30°: sin θ₂ = sin 30° / 1.5 = 1/3.
        let t = refract(downwards(30f64.to_radians()), DVec3::Y, 1.5).unwrap();
        assert!((t.x - 1.0 / 3.0).abs() < 1e-15, "{t}");
        assert!(t.y < 0.0 && (t.length() - 1.0).abs() < 1e-15);
    }

    #[test]
    fn snells_law_leaving_glass() {
        // Inside the glass (the ray travels along the outward normal's side): sin θ₂ = 1.5 sin θ₁.
        let d = -downwards(20f64.to_radians()); // upwards, towards the outside
        let t = refract(d, DVec3::Y, 1.5).unwrap();
        assert!((t.x.abs() - 1.5 * 20f64.to_radians().sin()).abs() < 1e-15);
        assert!(t.y > 0.0);
    }

    #[test]
    fn critical_angle_separates_refraction_from_tir() {
        let critical = (1.0f64 / 1.5).asin(); // 41.81°
        let up = |theta: f64| -downwards(theta);
        let grazing = refract(up(critical - 1e-9), DVec3::Y, 1.5).unwrap();
        assert!(
            grazing.y.abs() < 1e-3,
            "just below the critical angle the ray leaves grazing"
        );
        assert_eq!(refract(up(critical + 1e-9), DVec3::Y, 1.5), None);
    }

    #[test]
    fn index_ratio_one_is_undeviated_and_normal_incidence_is_undeviated() {
        let d = DVec3::new(0.3, -0.8, 0.52).normalize();
        assert!((refract(d, DVec3::Y, 1.0).unwrap() - d).length() < 1e-15);
        assert!((refract(-DVec3::Y, DVec3::Y, 2.4).unwrap() + DVec3::Y).length() < 1e-15);
    }
}
