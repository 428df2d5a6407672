//! Ray rotation (TIM's "Rotating" surface, the default METATOY window): the direction of a
//! transmitted ray is rotated by an angle α about the surface normal, or about any other axis
//! direction.
//!
//! The sense: a light ray is rotated by α, right-handed, about the axis oriented along the
//! direction in which it crosses the sheet, sign(d·n) â. The sheet is then reciprocal: if it
//! turns d into R d it turns −R d into −d, so a ray traced backwards from the camera turns the
//! same way. About the normal (â = n) the ray always crosses; about another axis a ray whose
//! rotated direction would not leave through the far side is reflected instead (losslessly
//! unless a reflection coefficient is given).
//!
//! Dr TIM's `RayRotating` with angle θ multiplies the tangential direction, as the complex
//! number d_u + i d_v, by e^{−iθ} for a ray crossing along the outward normal and by e^{iθ}
//! against it: a rotation by −θ about the crossing direction, so α = −θ. Its
//! `RayRotatingAboutArbitraryAxisDirection` rotates by its angle as α here.

use glam::{DQuat, DVec3};
use serde::Deserialize;

use super::{Basis, Outgoing, crosses};
use crate::geometry::Interaction;
use crate::keys::{Coefficient, Direction, Finite, coefficient, throughput};
use crate::math::Frame;
use crate::surfaces::{Redirection, Surface};

/// The axis rays are rotated about.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RotationAxis {
    /// The surface normal.
    Normal,
    /// A direction (any length, non-zero) in the given basis.
    Direction(DVec3, Basis),
}

#[derive(Debug, Clone, PartialEq)]
pub struct RayRotating {
    /// The rotation angle α, in radians.
    pub angle: f64,
    pub axis: RotationAxis,
    /// Fraction of the light transmitted, in [0, 1].
    pub transmission_coefficient: f64,
    /// Fraction of the light reflected where the rotated ray would not cross, in [0, 1].
    pub reflection_coefficient: f64,
}

/// `d` rotated by `angle` (right-handed) about the unit vector `axis` oriented along the
/// crossing direction at a surface with unit normal `n`; `None` if it does not cross.
pub fn rotated(d: DVec3, axis: DVec3, angle: f64, n: DVec3) -> Option<DVec3> {
    let axis = if d.dot(n) < 0.0 { -axis } else { axis };
    let out = DQuat::from_axis_angle(axis, angle) * d;
    crosses(d, out, n).then_some(out)
}

impl RayRotating {
    /// The rotation angle of TIM's "Rotating" METATOY window (Dr TIM's θ = 60°), in degrees.
    pub const DEFAULT_ANGLE_DEG: f64 = -60.0;

    /// The unit direction a ray with direction `d` leaves in where the surface frame is
    /// `frame`.
    pub fn outgoing(&self, d: DVec3, frame: &Frame) -> Outgoing {
        let axis = match self.axis {
            RotationAxis::Normal => frame.w,
            RotationAxis::Direction(a, basis) => basis.to_global(a, frame).normalize(),
        };
        Outgoing::or_mirrored(rotated(d, axis, self.angle, frame.w), d, frame.w)
    }

    pub fn redirect(&self, at: &Interaction) -> Redirection<'static> {
        self.outgoing(at.ray.direction, &at.frame())
            .leaves(self.transmission_coefficient, self.reflection_coefficient)
    }
}

/// `type = "ray-rotating"`: the angle in degrees (Dr TIM's default when not given) about the
/// normal, or about `axis` in `basis`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RayRotatingKeys {
    angle_deg: Option<Finite>,
    axis: Option<Direction>,
    basis: Option<Basis>,
    #[serde(alias = "transmission")]
    transmission_coefficient: Option<Coefficient>,
    #[serde(alias = "reflection")]
    reflection_coefficient: Option<Coefficient>,
}

impl RayRotatingKeys {
    pub fn build(self) -> Result<Surface, String> {
        let axis = match (self.axis, self.basis) {
            (None, None) => RotationAxis::Normal,
            (None, Some(_)) => {
                return Err("ray-rotating: basis applies to an axis, but none is given".into());
            }
            (Some(a), b) => RotationAxis::Direction(a.0, b.unwrap_or_default()),
        };
        Ok(Surface::RayRotating(RayRotating {
            angle: self
                .angle_deg
                .map_or(RayRotating::DEFAULT_ANGLE_DEG, |a| a.0)
                .to_radians(),
            axis,
            transmission_coefficient: throughput(self.transmission_coefficient),
            reflection_coefficient: coefficient(self.reflection_coefficient),
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Plane, Shape, Sphere};
    use crate::surfaces::tests::{leaves, meet};

    #[test]
    fn rotation_about_the_normal_turns_the_tangential_part_and_keeps_the_normal_part() {
        let d = DVec3::new(0.6, 0.0, 0.8);
        let out = rotated(d, DVec3::Z, 90f64.to_radians(), DVec3::Z).unwrap();
        assert!((out - DVec3::new(0.0, 0.6, 0.8)).length() < 1e-15, "{out}");
        // Crossing the other way, the sense reverses (reciprocity): back along −out gives −d.
        let back = rotated(-out, DVec3::Z, 90f64.to_radians(), DVec3::Z).unwrap();
        assert!((back + d).length() < 1e-15, "{back}");
    }

    /// Dr TIM's METATOY window: `RayRotating` with θ = 60° on a pane with (u, v, w) = (x, y, z),
    /// seen from the inside. A ray traced from the camera crosses along w, so its d_u + i d_v
    /// is divided by e^{iθ}: (0.6, 0, 0.8) leaves along (0.6 cos θ, −0.6 sin θ, 0.8), turned
    /// from +x towards −y.
    #[test]
    fn the_default_turns_a_traced_ray_as_dr_tims_window_does() {
        let frame = Frame::from_normal_and_u(DVec3::Z, DVec3::X);
        assert_eq!(frame.v, DVec3::Y);
        let window = RayRotating {
            angle: RayRotating::DEFAULT_ANGLE_DEG.to_radians(),
            axis: RotationAxis::Normal,
            transmission_coefficient: 0.96,
            reflection_coefficient: 1.0,
        };
        let theta = 60f64.to_radians();
        let want = DVec3::new(0.6 * theta.cos(), -0.6 * theta.sin(), 0.8);
        let Outgoing::Transmitted(out) = window.outgoing(DVec3::new(0.6, 0.0, 0.8), &frame) else {
            panic!("reflected")
        };
        assert!((out - want).length() < 1e-15, "{out}");
    }

    #[test]
    fn a_rotation_that_turns_the_ray_back_is_refused() {
        // 120° about x turns a ray along +z back towards the side it came from.
        let d = DVec3::new(0.0, 0.0, 1.0);
        assert_eq!(rotated(d, DVec3::X, 120f64.to_radians(), DVec3::Z), None);
        assert!(rotated(d, DVec3::X, 60f64.to_radians(), DVec3::Z).is_some());
    }

    #[test]
    fn an_axis_in_the_local_basis_is_read_along_the_surface_frame() {
        // A tilted frame: w along (0, 1, 1), u along x.
        let frame = Frame::from_normal_and_u(DVec3::new(0.0, 1.0, 1.0), DVec3::X);
        let local = DVec3::new(0.3, -0.2, 0.9);
        let global = local.x * frame.u + local.y * frame.v + local.z * frame.w;
        let rotating = |axis| RayRotating {
            angle: 0.7,
            axis,
            transmission_coefficient: 1.0,
            reflection_coefficient: 1.0,
        };
        let d = DVec3::new(0.1, 0.5, 0.8).normalize();
        let turned = |axis| rotating(axis).outgoing(d, &frame).direction();
        let by_local = turned(RotationAxis::Direction(local, Basis::Local));
        let by_global = turned(RotationAxis::Direction(global, Basis::Global));
        assert!(
            (by_local - by_global).length() < 1e-15,
            "{by_local} {by_global}"
        );
        // Reading the local components as global ones would be another rotation.
        let wrong = turned(RotationAxis::Direction(local, Basis::Global));
        assert!((wrong - by_global).length() > 1e-3);
        assert!((by_global.dot(global.normalize()) - d.dot(global.normalize())).abs() < 1e-15);
    }

    /// Ray rotation about the normal through `redirect`, on a tilted plane and on a sphere
    /// (normal (P − C)/R), crossing either way: the tangential part t = d − (d·n̂) n̂ turns by
    /// α right-handed about the crossing direction m̂ = sign(d·n̂) n̂, by Rodrigues' formula
    /// for a vector perpendicular to the axis, t′ = t cos α + (m̂ × t) sin α, while the normal
    /// part is kept, as for a transmitted ray; the ray carries the transmission coefficient.
    #[test]
    fn the_tangential_part_turns_by_the_angle_about_the_normal() {
        let alpha = 50f64.to_radians();
        let window = RayRotating {
            angle: alpha,
            axis: RotationAxis::Normal,
            transmission_coefficient: 0.8,
            reflection_coefficient: 1.0,
        };
        let n_plane = DVec3::new(0.0, 1.0, 1.0).normalize();
        let plane = Shape::Plane(Plane::new(DVec3::new(1.0, 0.0, 0.0), n_plane, DVec3::X).unwrap());
        let centre = DVec3::new(0.0, -1.0, 2.0);
        let sphere = Shape::Sphere(Sphere::new(centre, 1.5).unwrap());
        let cases = [
            (
                &plane,
                DVec3::new(1.2, 2.0, 2.5),
                DVec3::new(0.2, -0.5, -0.8),
            ),
            (
                &plane,
                DVec3::new(1.2, -2.0, -2.5),
                DVec3::new(-0.3, 0.6, 0.7),
            ),
            (
                &sphere,
                DVec3::new(-3.0, -0.5, 2.3),
                DVec3::new(1.0, 0.1, -0.1),
            ),
            (
                &sphere,
                DVec3::new(0.2, -1.1, 2.0),
                DVec3::new(0.4, 0.5, 0.6),
            ),
        ];
        for (shape, origin, d) in cases {
            let at = meet(shape, origin, d);
            let d = d.normalize();
            let n = match shape {
                Shape::Sphere(_) => (at.point() - centre) / 1.5,
                _ => n_plane,
            };
            let m = d.dot(n).signum() * n;
            let t = d - d.dot(n) * n;
            let expected = d.dot(n) * n + t * alpha.cos() + m.cross(t) * alpha.sin();
            let (out, factor) = leaves(window.redirect(&at));
            assert_eq!(factor, 0.8);
            assert!((out - expected).length() < 1e-14, "{d}: {out} {expected}");
            assert!((out.length() - 1.0).abs() < 1e-14);
        }
    }
}
