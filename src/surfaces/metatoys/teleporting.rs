//! Teleporting surfaces (§6): a ray that hits the surface leaves from the point with the same
//! surface coordinates on a linked destination surface, with the same direction components in
//! the destination's local (u, v, w) basis as it had in the origin's.
//!
//! The paper gives no formula; this is the law its name describes. A ray meeting the origin
//! from outside (against w) leaves the destination against w′, so the destination continues
//! the origin's view like a window that has been moved. Traced backwards from the camera, the
//! view through the origin is the scene as seen through the destination. A point without a
//! counterpart (beyond the destination's edge) sends no light: the ray is absorbed.
//!
//! An imperfect teleporter adds, per ray, a random surface-coordinate offset uniform within a
//! disc of radius `positional_error`, and turns the direction by a random angle uniform within
//! a cone of half-angle `angular_error` (uniform over the cone's solid angle, kept on the same
//! side of the destination). The noise is keyed by the ray, so renders are reproducible.

use glam::{DQuat, DVec2, DVec3};

use crate::geometry::Exit;
use crate::geometry::Interaction;
use crate::geometry::Shape;
use crate::math::Frame;
use crate::math::random::uniform_keyed;
use crate::surfaces::Redirection;

#[derive(Debug, Clone, PartialEq)]
pub struct Teleporting {
    /// The linked surface rays leave from (analytic shapes; meshes have no inverse
    /// coordinates).
    pub destination: Shape,
    /// Radius of the random surface-coordinate error (0 for perfect teleportation).
    pub positional_error: f64,
    /// Half-angle of the random direction error, in radians.
    pub angular_error: f64,
    /// Fraction of the light transmitted, in [0, 1].
    pub transmission_coefficient: f64,
}

impl Teleporting {
    /// Where and in which direction a ray leaves the destination, having hit the origin at
    /// surface coordinates `c` with unit direction `d` where the origin's frame is `frame`;
    /// `noise` gives four uniform numbers in [0, 1) for the errors. `None` if the destination
    /// has no point with those coordinates.
    pub fn teleport(
        &self,
        c: DVec2,
        d: DVec3,
        frame: &Frame,
        noise: impl Fn(u32) -> f64,
    ) -> Option<(DVec3, DVec3)> {
        let shift = if self.positional_error > 0.0 {
            let (r, phi) = (noise(0).sqrt(), std::f64::consts::TAU * noise(1));
            self.positional_error * r * DVec2::new(phi.cos(), phi.sin())
        } else {
            DVec2::ZERO
        };
        let p = self.destination.point_at(c + shift)?;
        let f = self.destination.frame(p, 0);
        let local = DVec3::new(d.dot(frame.u), d.dot(frame.v), d.dot(frame.w));
        let mut out = local.x * f.u + local.y * f.v + local.z * f.w;
        if self.angular_error > 0.0 {
            // Uniform over the cap: cos α uniform in [cos σ, 1].
            let cos_a = 1.0 - noise(2) * (1.0 - self.angular_error.cos());
            let azimuth = std::f64::consts::TAU * noise(3);
            let (p1, _) = out.any_orthonormal_pair();
            let tilt = DQuat::from_axis_angle(out, azimuth) * p1;
            let turned = DQuat::from_axis_angle(tilt, cos_a.clamp(-1.0, 1.0).acos()) * out;
            out = if turned.dot(f.w) * out.dot(f.w) < 0.0 {
                turned - 2.0 * turned.dot(f.w) * f.w
            } else {
                turned
            };
        }
        Some((p, out))
    }

    pub fn redirect(&self, at: &Interaction) -> Redirection<'static> {
        let d = at.ray.direction;
        let p = at.point();
        let key = [
            p.x.to_bits(),
            p.y.to_bits(),
            p.z.to_bits(),
            d.x.to_bits(),
            d.y.to_bits(),
            d.z.to_bits(),
        ];
        let Some((point, direction)) =
            self.teleport(at.coordinates(), d, &at.frame(), |i| uniform_keyed(&key, i))
        else {
            return Redirection::Lost;
        };
        let exit = Exit {
            point,
            direction: direction.normalize(),
            path: 0.0,
        };
        Redirection::Jumps {
            exit,
            factor: self.transmission_coefficient,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Parallelogram;

    /// The angular error is uniform over the cone's solid angle: every angle is within σ, and
    /// cos α is uniform on [cos σ, 1] (mean 1 − (1 − cos σ)/2, a quarter of them within σ/2
    /// for small σ).
    #[test]
    fn angular_errors_fill_the_cone_uniformly() {
        let sigma = 5f64.to_radians();
        let window = Teleporting {
            destination: Shape::Parallelogram(
                Parallelogram::new(DVec3::ZERO, DVec3::X, DVec3::Y).unwrap(),
            ),
            positional_error: 0.0,
            angular_error: sigma,
            transmission_coefficient: 1.0,
        };
        let frame = Frame::from_normal_and_u(DVec3::Z, DVec3::X);
        let d = DVec3::new(0.2, -0.1, 0.9).normalize();
        let n = 20_000;
        let mut cosines = Vec::with_capacity(n);
        let mut azimuths = DVec3::ZERO;
        for i in 0..n {
            let key = [i as u64];
            let (p, out) = window
                .teleport(DVec2::new(0.5, 0.5), d, &frame, |k| uniform_keyed(&key, k))
                .unwrap();
            assert_eq!(p, DVec3::new(0.5, 0.5, 0.0));
            assert!((out.length() - 1.0).abs() < 1e-12);
            cosines.push(out.dot(d));
            azimuths += (out - d).normalize();
        }
        assert!(cosines.iter().all(|&c| c >= sigma.cos() - 1e-12));
        let mean = cosines.iter().sum::<f64>() / n as f64;
        let expected = 1.0 - (1.0 - sigma.cos()) / 2.0;
        assert!(
            (mean - expected).abs() < 0.02 * (1.0 - sigma.cos()),
            "{mean} {expected}"
        );
        let half = cosines
            .iter()
            .filter(|&&c| c >= (sigma / 2.0).cos())
            .count();
        assert!((half as f64 / n as f64 - 0.25).abs() < 0.02, "{half}");
        assert!(
            azimuths.length() / (n as f64) < 0.05,
            "errors have no preferred direction"
        );
    }
}
