//! Ray flipping: a sheet of confocal cylindrical-lens telescopes with inverting magnification
//! reverses the component of a ray's direction perpendicular to the cylinder axes (the flip
//! axis) and in the surface, and keeps the other two.
//!
//! The paper gives no formula; this is the gCLA law (Eq 39) with â = n̂, η = −1 across the
//! cylinder axes and η = 1 (no telescope) along them: d′ = d − 2 (d·p̂) p̂, where p̂ is the
//! tangent perpendicular to the flip axis. It is its own inverse, hence reciprocal.

use glam::DVec3;
use serde::Deserialize;

use crate::geometry::Interaction;
use crate::keys::{Coefficient, Finite, throughput};
use crate::math::Colour;
use crate::math::Frame;
use crate::surfaces::{Redirection, Surface};

#[derive(Debug, Clone, PartialEq)]
pub struct RayFlipping {
    /// Angle of the flip axis from the surface's u direction, towards v, in radians.
    pub flip_axis_angle: f64,
    /// Fraction of the light transmitted, in [0, 1].
    pub transmission_coefficient: f64,
}

/// `d` with its component along the unit tangent `p` (perpendicular to the flip axis) reversed.
pub fn flipped(d: DVec3, p: DVec3) -> DVec3 {
    d - 2.0 * d.dot(p) * p
}

impl RayFlipping {
    /// The unit tangent perpendicular to the flip axis at a point with surface frame `frame`.
    pub fn flipped_tangent(&self, frame: &Frame) -> DVec3 {
        let (s, c) = self.flip_axis_angle.sin_cos();
        -s * frame.u + c * frame.v
    }

    pub fn redirect(&self, at: &Interaction) -> Redirection<'static> {
        Redirection::Leaves {
            direction: flipped(at.ray.direction, self.flipped_tangent(&at.frame())),
            factor: Colour::splat(self.transmission_coefficient),
        }
    }
}

/// `type = "ray-flipping"`: the flip axis at `flip_axis_angle_deg` (0 when not given) from u.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RayFlippingKeys {
    flip_axis_angle_deg: Option<Finite>,
    #[serde(alias = "transmission")]
    transmission_coefficient: Option<Coefficient>,
}

impl RayFlippingKeys {
    pub fn build(self) -> Result<Surface, String> {
        Ok(Surface::RayFlipping(RayFlipping {
            flip_axis_angle: self.flip_axis_angle_deg.map_or(0.0, |a| a.0).to_radians(),
            transmission_coefficient: throughput(self.transmission_coefficient),
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Plane, Shape, Sphere};
    use crate::surfaces::tests::{leaves, meet};

    #[test]
    fn flipping_about_u_reverses_the_v_component_only() {
        let flip = RayFlipping {
            flip_axis_angle: 0.0,
            transmission_coefficient: 1.0,
        };
        let frame = Frame::from_normal_and_u(DVec3::Z, DVec3::X);
        let d = DVec3::new(0.3, 0.4, 0.866);
        let out = flipped(d, flip.flipped_tangent(&frame));
        assert!(
            (out - DVec3::new(0.3, -0.4, 0.866)).length() < 1e-15,
            "{out}"
        );
        assert!((flipped(out, DVec3::Y) - d).length() < 1e-15);
    }

    /// Ray flipping through `redirect` with the flip axis 30° from u towards v, on the plane
    /// z = 0 (u = x, v = y) and on a sphere (its frame at the hit): the components along the
    /// flip axis and along the normal are kept (the ray crosses), the one across the axis in
    /// the surface is reversed, and flipping the flipped ray again, at the same point, gives
    /// back the ray.
    #[test]
    fn flipping_twice_is_the_identity_and_the_flip_axis_component_is_kept() {
        let psi = 30f64.to_radians();
        let flip = RayFlipping {
            flip_axis_angle: psi,
            transmission_coefficient: 0.75,
        };
        let plane = Shape::Plane(Plane::new(DVec3::ZERO, DVec3::Z, DVec3::X).unwrap());
        let sphere = Shape::Sphere(Sphere::new(DVec3::new(2.0, 0.0, 0.0), 1.0).unwrap());
        for (shape, origin, d) in [
            (
                &plane,
                DVec3::new(0.4, -0.2, 2.0),
                DVec3::new(0.3, 0.4, -0.866),
            ),
            (
                &plane,
                DVec3::new(-0.4, 0.2, -2.0),
                DVec3::new(-0.5, 0.1, 0.8),
            ),
            (
                &sphere,
                DVec3::new(0.0, 0.3, 0.4),
                DVec3::new(1.0, -0.1, 0.2),
            ),
        ] {
            let at = meet(shape, origin, d);
            let d = d.normalize();
            let frame = at.frame();
            let axis = psi.cos() * frame.u + psi.sin() * frame.v;
            let across = frame.w.cross(axis);
            let (out, factor) = leaves(flip.redirect(&at));
            assert_eq!(factor, 0.75);
            assert!((out.dot(axis) - d.dot(axis)).abs() < 1e-15, "{out}");
            assert!((out.dot(frame.w) - d.dot(frame.w)).abs() < 1e-15, "{out}");
            assert!((out.dot(across) + d.dot(across)).abs() < 1e-15, "{out}");
            let again = meet(shape, at.point() - out, out);
            assert!((again.point() - at.point()).length() < 1e-14);
            let (twice, _) = leaves(flip.redirect(&again));
            assert!((twice - d).length() < 1e-15, "{twice}");
        }
    }
}
