//! Ray rotation in the plane of incidence (Dr TIM's `RayRotatingInPlaneOfIncidence`, a
//! `RefractiveAngleFormulation`): the angle of incidence α (measured from the normal, always
//! positive) becomes α + θ, the ray staying in its plane of incidence and leaving on the side
//! it travels to. A positive θ turns the ray away from the normal.
//!
//! With d the unit ray direction, n the unit normal, t̂ the unit tangential part of d and
//! α = asin(d·t̂), the ray leaves in sign(d·n) cos(α + θ) n + sin(α + θ) t̂, carrying the
//! transmission coefficient. As in Dr TIM, the law is applied to the ray as traced (from the
//! camera); it is not reciprocal. At exactly normal incidence the plane of incidence is not
//! defined: the ray passes undeviated if θ = 0 and carries no light otherwise (Dr TIM's
//! direction there is not a number).

use glam::DVec3;
use serde::Deserialize;

use crate::geometry::Interaction;
use crate::keys::{Coefficient, Finite, throughput};
use crate::math::Colour;
use crate::surfaces::{Redirection, Surface};

#[derive(Debug, Clone, PartialEq)]
pub struct RayRotatingInPlaneOfIncidence {
    /// The rotation angle θ, in radians; positive away from the normal.
    pub angle: f64,
    /// Fraction of the light transmitted, in [0, 1].
    pub transmission_coefficient: f64,
}

/// The unit direction a ray of unit direction `d` leaves in, rotated by `angle` in its plane
/// of incidence at a surface with unit normal `n`; `None` at normal incidence with a non-zero
/// angle.
pub fn rotated_in_plane_of_incidence(d: DVec3, n: DVec3, angle: f64) -> Option<DVec3> {
    let cos = d.dot(n);
    let tangential = d - cos * n;
    let sin = tangential.length();
    if sin == 0.0 {
        return (angle == 0.0).then_some(d);
    }
    let alpha = sin.min(1.0).asin() + angle;
    Some(cos.signum() * alpha.cos() * n + alpha.sin() * (tangential / sin))
}

impl RayRotatingInPlaneOfIncidence {
    pub fn redirect(&self, at: &Interaction) -> Redirection<'static> {
        match rotated_in_plane_of_incidence(at.ray.direction, at.frame().w, self.angle) {
            Some(direction) => Redirection::Leaves {
                direction,
                factor: Colour::splat(self.transmission_coefficient),
            },
            None => Redirection::Lost,
        }
    }
}

/// `type = "ray-rotating-in-plane-of-incidence"`: `angle_deg` (Dr TIM's GUI default 0) and
/// the transmission coefficient (Dr TIM's default 0.96).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RayRotatingInPlaneOfIncidenceKeys {
    angle_deg: Option<Finite>,
    #[serde(alias = "transmission")]
    transmission_coefficient: Option<Coefficient>,
}

impl RayRotatingInPlaneOfIncidenceKeys {
    pub fn build(self) -> Result<Surface, String> {
        Ok(Surface::RayRotatingInPlaneOfIncidence(
            RayRotatingInPlaneOfIncidence {
                angle: self.angle_deg.map_or(0.0, |a| a.0).to_radians(),
                transmission_coefficient: throughput(self.transmission_coefficient),
            },
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit direction at `deg` degrees from +z, towards +x, along `sign` z.
    fn at(deg: f64, sign: f64) -> DVec3 {
        let a = deg.to_radians();
        DVec3::new(a.sin(), 0.0, sign * a.cos())
    }

    fn close(a: DVec3, b: DVec3) {
        assert!((a - b).length() < 1e-14, "{a} is not {b}");
    }

    #[test]
    fn the_angle_of_incidence_grows_by_the_rotation_angle_in_the_plane_of_incidence() {
        let r = |d, deg: f64| rotated_in_plane_of_incidence(d, DVec3::Z, deg.to_radians());
        // 30° becomes 50°, going outwards and inwards alike (the angle is from the normal).
        close(r(at(30.0, 1.0), 20.0).unwrap(), at(50.0, 1.0));
        close(r(at(30.0, -1.0), 20.0).unwrap(), at(50.0, -1.0));
        // A negative angle turns towards the normal: 30° − 30° is along it.
        close(r(at(30.0, 1.0), -30.0).unwrap(), DVec3::Z);
        // Nothing turns without an angle; at normal incidence only then does light pass.
        close(r(at(40.0, 1.0), 0.0).unwrap(), at(40.0, 1.0));
        close(r(DVec3::Z, 0.0).unwrap(), DVec3::Z);
        assert_eq!(r(DVec3::Z, 10.0), None);
        // The plane of incidence is kept: a ray in the y–z plane stays there.
        let d = DVec3::new(0.0, 0.5, 0.75f64.sqrt());
        let out = r(d, 15.0).unwrap();
        assert!(out.x.abs() < 1e-15 && (out.y.asin().to_degrees() - 45.0).abs() < 1e-12);
    }

    #[test]
    fn dr_tims_defaults_are_no_rotation_and_96_percent() {
        let keys: RayRotatingInPlaneOfIncidenceKeys = toml::from_str("").unwrap();
        let Surface::RayRotatingInPlaneOfIncidence(s) = keys.build().unwrap() else {
            panic!("the kind built")
        };
        assert_eq!((s.angle, s.transmission_coefficient), (0.0, 0.96));
    }
}
