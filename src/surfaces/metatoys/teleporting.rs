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
//!
//! Holographic teleportation (Dr TIM's type HOLOGRAPHIC, after Bryngdahl, J. Opt. Soc. Am. 64,
//! 1092 (1974)) makes the link with two phase holograms. Where a ray meets the origin at P₁,
//! with P₂ the destination's point of the same surface coordinates and ĉ the unit vector from
//! P₁ to P₂, the origin's hologram turns a ray along its normal into ĉ (tangential kick ĉ
//! less its normal part, at P₁); the ray, so kicked, goes on to where it meets the destination,
//! Q, whose hologram turns a ray along ĉ into the destination's normal (kick −ĉ less its normal
//! part at P₂, applied at Q, as in Dr TIM). The defining property: a ray along the origin's
//! normal arrives at exactly P₂ and leaves along the destination's normal; other rays are
//! teleported imperfectly. As in Dr TIM, the passage between the holograms is not traced
//! (nothing blocks it, it takes no time); a kicked ray that misses the destination goes on
//! from P₁, and an evanescent wave is reflected by that hologram (carrying the reflection
//! coefficient, times the transmission coefficient at the second).

use glam::{DQuat, DVec2, DVec3};
use serde::Deserialize;

use super::{hologram_direction, jacobian};
use crate::geometry::{Exit, Interaction, Shape, Transform};
use crate::keys::{Coefficient, NonNegative, coefficient, throughput};
use crate::math::Colour;
use crate::math::Frame;
use crate::math::random::{ray_key, uniform_keyed};
use crate::surfaces::{Redirection, Surface, reflect};

/// How a teleporting surface sends rays to its destination.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Teleportation {
    /// Same surface coordinates, same local direction components.
    #[default]
    Perfect,
    /// Through a pair of phase holograms (see the module notes).
    Holographic,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Teleporting {
    /// The linked surface rays leave from (analytic shapes; meshes have no inverse
    /// coordinates), in the coordinates of the teleporting object. `None` until the scene
    /// file links the surface to the object its `destination` names, once every object is
    /// placed; a device's teleporting surfaces have theirs from the start, and move with it.
    pub destination: Option<Shape>,
    pub teleportation: Teleportation,
    /// Radius of the random surface-coordinate error (0 for perfect teleportation).
    pub positional_error: f64,
    /// Half-angle of the random direction error, in radians.
    pub angular_error: f64,
    /// Fraction of the light transmitted, in [0, 1].
    pub transmission_coefficient: f64,
    /// Fraction of the light reflected by a hologram that gives an evanescent wave
    /// (holographic teleportation), in [0, 1].
    pub reflection_coefficient: f64,
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
        let destination = self.destination.as_ref()?;
        let p = destination.point_at(c + shift)?;
        let f = destination.frame(p, 0);
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

    /// Holographic teleportation of a ray with unit direction `d` that meets the origin at
    /// `p`, with surface coordinates `c` and frame `frame` there.
    pub fn holographic(&self, p: DVec3, c: DVec2, d: DVec3, frame: &Frame) -> Redirection<'static> {
        let Some(destination) = &self.destination else {
            return Redirection::Lost;
        };
        let Some(p2) = destination.point_at(c) else {
            return Redirection::Lost;
        };
        let Some(design) = (p2 - p).try_normalize() else {
            return Redirection::Lost;
        };
        let tangential = |v: DVec3| DVec2::new(v.x, v.y);
        let (origin, exit) = (jacobian(frame), jacobian(&destination.frame(p2, 0)));
        let kick = tangential(origin.transpose() * design);
        let Some(between) = hologram_direction(origin.transpose() * d, kick).map(|e| origin * e)
        else {
            return Redirection::Leaves {
                direction: reflect(d, frame.w),
                factor: Colour::splat(self.reflection_coefficient),
            };
        };
        let Some((t, _)) = destination.intersect(p, between, 0.0, f64::INFINITY) else {
            return Redirection::Leaves {
                direction: between,
                factor: Colour::splat(self.transmission_coefficient),
            };
        };
        let kick = -tangential(exit.transpose() * design);
        let (direction, factor) = match hologram_direction(exit.transpose() * between, kick) {
            Some(e) => (exit * e, self.transmission_coefficient),
            None => (
                reflect(between, exit.z_axis),
                self.transmission_coefficient * self.reflection_coefficient,
            ),
        };
        let exit = Exit {
            point: p + t * between,
            direction,
            path: 0.0,
        };
        Redirection::Jumps {
            exit,
            factor: Colour::splat(factor),
        }
    }

    /// The surface of an object moved by `t`: its destination, if it has one yet, moved too.
    /// Surface coordinates are lengths, so a map that does not scale uniformly would send rays
    /// off the destination: it is refused.
    pub fn transformed(&self, t: &Transform) -> Result<Teleporting, String> {
        let destination = match &self.destination {
            Some(_) if t.uniform_scale().is_none() => {
                return Err(
                    "a device's teleporting surfaces can be rotated, scaled uniformly \
                            and moved, not stretched (their surface coordinates are lengths)"
                        .into(),
                );
            }
            Some(shape) => Some(t.shape(shape).map_err(|e| format!("destination: {e}"))?),
            None => None,
        };
        Ok(Teleporting {
            destination,
            ..self.clone()
        })
    }

    pub fn redirect(&self, at: &Interaction) -> Redirection<'static> {
        let d = at.ray.direction;
        let p = at.point();
        if self.teleportation == Teleportation::Holographic {
            return self.holographic(p, at.coordinates(), d, &at.frame());
        }
        let key = ray_key(p, d);
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
            factor: Colour::splat(self.transmission_coefficient),
        }
    }
}

/// `type = "teleporting"`: the surface is linked to the object named `destination` once
/// every object is placed. Errors apply to perfect teleportation, hologram reflections to
/// holographic.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TeleportingKeys {
    pub destination: String,
    teleportation: Option<Teleportation>,
    positional_error: Option<NonNegative>,
    angular_error_deg: Option<NonNegative>,
    #[serde(alias = "transmission")]
    transmission_coefficient: Option<Coefficient>,
    #[serde(alias = "reflection")]
    reflection_coefficient: Option<Coefficient>,
}

impl TeleportingKeys {
    pub fn build(self) -> Result<Surface, String> {
        let positional_error = self.positional_error.map_or(0.0, |e| e.0);
        let angular_error_deg = self.angular_error_deg.map_or(0.0, |a| a.0);
        if angular_error_deg > 180.0 {
            return Err(format!(
                "teleporting: angular_error_deg = {angular_error_deg} is more than 180"
            ));
        }
        let teleportation = self.teleportation.unwrap_or_default();
        match teleportation {
            Teleportation::Perfect if self.reflection_coefficient.is_some() => {
                return Err("teleporting: reflection_coefficient applies to teleportation = \"holographic\" only (perfect teleportation reflects nothing)".into());
            }
            Teleportation::Holographic if positional_error > 0.0 || angular_error_deg > 0.0 => {
                return Err("teleporting: positional_error and angular_error_deg apply to perfect teleportation only, not to teleportation = \"holographic\"".into());
            }
            Teleportation::Perfect | Teleportation::Holographic => {}
        }
        Ok(Surface::Teleporting(Teleporting {
            destination: None,
            teleportation,
            positional_error,
            angular_error: angular_error_deg.to_radians(),
            transmission_coefficient: throughput(self.transmission_coefficient),
            reflection_coefficient: coefficient(self.reflection_coefficient),
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Parallelogram;

    fn parallelogram(corner: DVec3, span_u: DVec3, span_v: DVec3) -> Shape {
        Shape::Parallelogram(Parallelogram::new(corner, span_u, span_v).unwrap())
    }

    /// Holographic teleportation from the 2 × 1 rectangle z = 0 to a tilted, moved 1.5 × 1
    /// one. The Bryngdahl pair's defining property: a ray along the origin's normal arrives at
    /// exactly the point with its surface coordinates and leaves along the destination's
    /// normal. An oblique ray is kicked by the same tangential vectors at both holograms
    /// (phase matching, checked here with the plane's equation), so it arrives elsewhere:
    /// the teleportation is imperfect. A kick past grazing is reflected, without loss.
    #[test]
    fn holographic_teleporting_images_normal_rays_point_to_point() {
        let origin = parallelogram(DVec3::ZERO, 2.0 * DVec3::X, DVec3::Y);
        let tilt = DQuat::from_axis_angle(DVec3::new(1.0, 1.0, 0.0).normalize(), 0.4);
        let destination = parallelogram(
            DVec3::new(0.2, -0.3, 4.0),
            tilt * DVec3::new(1.5, 0.0, 0.0),
            tilt * DVec3::Y,
        );
        let teleporter = Teleporting {
            destination: Some(destination.clone()),
            teleportation: Teleportation::Holographic,
            positional_error: 0.0,
            angular_error: 0.0,
            transmission_coefficient: 0.9,
            reflection_coefficient: 1.0,
        };
        let n2 = tilt * DVec3::Z;
        let frame = Frame::from_normal_and_u(DVec3::Z, DVec3::X);
        for c in [
            DVec2::new(0.4, 0.3),
            DVec2::new(1.1, 0.7),
            DVec2::new(0.7, 0.5),
        ] {
            let p1 = origin.point_at(c).unwrap();
            let Redirection::Jumps { exit, factor } =
                teleporter.holographic(p1, c, DVec3::Z, &frame)
            else {
                panic!("c {c}: not teleported")
            };
            assert_eq!(factor, Colour::splat(0.9));
            let p2 = destination.point_at(c).unwrap();
            assert!((exit.point - p2).length() < 1e-14, "c {c}: {}", exit.point);
            assert!((destination.coordinates(exit.point, 0) - c).length() < 1e-14);
            assert!((exit.direction - n2).length() < 1e-15, "{}", exit.direction);

            let d = DVec3::new(0.03, -0.02, 1.0).normalize();
            let Redirection::Jumps { exit, .. } = teleporter.holographic(p1, c, d, &frame) else {
                panic!("c {c}: oblique ray not teleported")
            };
            let design = (p2 - p1).normalize();
            let t = DVec2::new(d.x + design.x, d.y + design.y);
            let between = DVec3::new(t.x, t.y, (1.0 - t.length_squared()).sqrt());
            let q = p1 + between * (p2 - p1).dot(n2) / between.dot(n2);
            assert!((exit.point - q).length() < 1e-12, "{} {q}", exit.point);
            assert!((exit.point - p2).length() > 0.05, "imperfect");
            let kick = exit.direction - between + design;
            assert!(
                kick.cross(n2).length() < 1e-12,
                "phase matching at the second"
            );
            assert!((exit.direction.length() - 1.0).abs() < 1e-15);
        }

        let c = DVec2::new(1.4, 0.5);
        let d = DVec3::new(0.9, 0.0, 0.1).normalize();
        assert_eq!(
            teleporter.holographic(origin.point_at(c).unwrap(), c, d, &frame),
            Redirection::Leaves {
                direction: DVec3::new(d.x, d.y, -d.z),
                factor: Colour::ONE
            }
        );
    }

    /// The angular error is uniform over the cone's solid angle: every angle is within σ, and
    /// cos α is uniform on [cos σ, 1] (mean 1 − (1 − cos σ)/2, a quarter of them within σ/2
    /// for small σ).
    #[test]
    fn angular_errors_fill_the_cone_uniformly() {
        let sigma = 5f64.to_radians();
        let window = Teleporting {
            destination: Some(Shape::Parallelogram(
                Parallelogram::new(DVec3::ZERO, DVec3::X, DVec3::Y).unwrap(),
            )),
            teleportation: Teleportation::Perfect,
            positional_error: 0.0,
            angular_error: sigma,
            transmission_coefficient: 1.0,
            reflection_coefficient: 1.0,
        };
        let frame = Frame::from_normal_and_u(DVec3::Z, DVec3::X);
        let d = DVec3::new(0.03, -0.02, 1.0).normalize();
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
