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
use crate::keys::{Coefficient, Finite, coefficient};
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
            factor: self.transmission_coefficient,
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
            transmission_coefficient: coefficient(self.transmission_coefficient),
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
}
