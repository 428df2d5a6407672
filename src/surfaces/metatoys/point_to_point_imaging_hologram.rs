//! The phase hologram that images one point into another, Dr TIM's
//! `Point2PointImagingPhaseHologram` (with the points its constructor calls the inside-space
//! and outside-space points): on a plane, the hologram of a lens; on any shape, since it needs
//! positions, not surface coordinates.
//!
//! At each surface point p (outward normal n̂) the hologram's kick is the tangential part of
//! ê′ − ê, where ê = (p − O)/|p − O| and ê′ = (I − p)/|I − p| are the directions from the
//! object O to p and from p to the image I, each turned to point outwards (reversed if its
//! component along n̂ is not positive; Dr TIM's "outwards-pointing straight-line
//! continuation"). A ray crossing outwards along ê (through O) so leaves along ê′, i.e. along
//! the line through I: towards I if I lies outside (a real image), away from it if I lies
//! inside (virtual). O is a real object where it lies inside (the light diverges from it) and
//! a virtual one where it lies outside (the light converges towards it), so holograms can be
//! chained. By reciprocity a ray crossing inwards through I leaves along the line through O.
//! The kick is a phase's gradient, ∇(σ′|I − p| + σ|p − O|) (σ, σ′ = ±1 the turns), the same
//! for light in either direction: this is a phase hologram, and where the new tangential part
//! exceeds 1 the wave is evanescent and the ray is reflected, as Dr TIM's `PhaseHologram` does
//! (without loss; here times the reflection coefficient, 1 by default).
//!
//! Dr TIM's `LensHologram` (and the disc `ThinLensPoint2PointImaging` made of it) is this
//! hologram imaging P − 2f â into P + 2f â (P the principal point, â the optical axis
//! pointing outwards): a lens of focal length f exactly for that pair of points and
//! paraxially for all (`type = "lens-hologram"`).

use glam::{DVec2, DVec3};
use serde::Deserialize;

use super::{Outgoing, hologram_direction, jacobian};
use crate::geometry::{Interaction, Transform};
use crate::keys::{Coefficient, Direction, NonZero, Vector, coefficient};
use crate::surfaces::{Redirection, Surface};

#[derive(Debug, Clone, PartialEq)]
pub struct PointToPointImagingHologram {
    /// O, imaged into `image_position` by light crossing outwards (Dr TIM's inside-space
    /// point).
    pub object_position: DVec3,
    /// I (Dr TIM's outside-space point).
    pub image_position: DVec3,
    /// Fraction of the light transmitted, in [0, 1].
    pub transmission_coefficient: f64,
    /// Fraction of the light reflected where the wave is evanescent, in [0, 1].
    pub reflection_coefficient: f64,
}

impl PointToPointImagingHologram {
    /// The kick at surface point `p` with outward unit normal `n`: the tangential part of
    /// ê′ − ê (see the module's notes); not finite at O or I themselves.
    pub fn kick(&self, p: DVec3, n: DVec3) -> DVec3 {
        let outwards = |v: DVec3| {
            let v = v.normalize();
            if v.dot(n) > 0.0 { v } else { -v }
        };
        let change = outwards(self.image_position - p) - outwards(p - self.object_position);
        change - change.dot(n) * n
    }

    pub fn redirect(&self, at: &Interaction) -> Redirection<'static> {
        let frame = at.frame();
        let kick = self.kick(at.local_point(), frame.w);
        if !kick.is_finite() {
            return Redirection::Lost;
        }
        let lambda = jacobian(&frame);
        let d = at.ray.direction;
        let kick = DVec2::new(kick.dot(frame.u), kick.dot(frame.v));
        let out = hologram_direction(lambda.transpose() * d, kick).map(|e| lambda * e);
        Outgoing::or_mirrored(out, d, frame.w)
            .leaves(self.transmission_coefficient, self.reflection_coefficient)
    }

    /// The hologram of an object placed by `t`: both points move with it (straight lines
    /// stay straight under any affine map, so the imaging does too).
    pub fn transformed(&self, t: &Transform) -> PointToPointImagingHologram {
        PointToPointImagingHologram {
            object_position: t.point(self.object_position),
            image_position: t.point(self.image_position),
            ..*self
        }
    }
}

/// Dr TIM's `SurfacePropertyPrimitive.DEFAULT_TRANSMISSION_COEFFICIENT`, with which its surface
/// panel makes the hologram.
const TRANSMISSION_COEFFICIENT: f64 = 0.96;

/// `type = "point-to-point-imaging-hologram"`: `object_position` and `image_position`
/// (required: Dr TIM's panel puts both at the origin, a hologram that changes nothing),
/// `transmission_coefficient` (0.96, Dr TIM's) and `reflection_coefficient` (1).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PointToPointImagingHologramKeys {
    object_position: Vector,
    image_position: Vector,
    #[serde(alias = "transmission")]
    transmission_coefficient: Option<Coefficient>,
    #[serde(alias = "reflection")]
    reflection_coefficient: Option<Coefficient>,
}

impl PointToPointImagingHologramKeys {
    pub fn build(self) -> Result<Surface, String> {
        let (object, image) = (self.object_position.0, self.image_position.0);
        if object == image {
            return Err(format!(
                "object_position and image_position are the same point {object}: such a \
                 hologram would change no ray's direction"
            ));
        }
        Ok(hologram(
            object,
            image,
            self.transmission_coefficient,
            self.reflection_coefficient,
        ))
    }
}

/// The surface imaging `object` into `image`, with the coefficients' defaults.
fn hologram(
    object: DVec3,
    image: DVec3,
    transmission: Option<Coefficient>,
    reflection: Option<Coefficient>,
) -> Surface {
    Surface::PointToPointImagingHologram(PointToPointImagingHologram {
        object_position: object,
        image_position: image,
        transmission_coefficient: transmission.map_or(TRANSMISSION_COEFFICIENT, |c| c.0),
        reflection_coefficient: coefficient(reflection),
    })
}

/// `type = "lens-hologram"`, Dr TIM's `LensHologram`: `principal_point` P, `optical_axis` â
/// (pointing outwards: to the side the outward normal points to) and `focal_length` f, all
/// required (Dr TIM's editors give none); the point-to-point imaging hologram of P − 2f â into
/// P + 2f â, with `transmission_coefficient` (0.96) and `reflection_coefficient` (1).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LensHologramKeys {
    principal_point: Vector,
    optical_axis: Direction,
    focal_length: NonZero,
    #[serde(alias = "transmission")]
    transmission_coefficient: Option<Coefficient>,
    #[serde(alias = "reflection")]
    reflection_coefficient: Option<Coefficient>,
}

impl LensHologramKeys {
    pub fn build(self) -> Result<Surface, String> {
        let (p, to_focus) = (
            self.principal_point.0,
            2.0 * self.focal_length.0 * self.optical_axis.0,
        );
        Ok(hologram(
            p - to_focus,
            p + to_focus,
            self.transmission_coefficient,
            self.reflection_coefficient,
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Plane, Shape, Sphere};
    use crate::surfaces::tests::{leaves, line_miss, meet};

    fn point_to_point(object: DVec3, image: DVec3) -> PointToPointImagingHologram {
        PointToPointImagingHologram {
            object_position: object,
            image_position: image,
            transmission_coefficient: 0.9,
            reflection_coefficient: 0.4,
        }
    }

    /// The ray from `from` through the point `p` of `shape`, and where it leaves: the hit
    /// point and the direction, which must be transmitted.
    fn through(h: &PointToPointImagingHologram, shape: &Shape, from: DVec3, p: DVec3) -> DVec3 {
        let at = meet(shape, from, p - from);
        assert!(at.point().distance(p) < 1e-9, "{} against {p}", at.point());
        let (out, factor) = leaves(h.redirect(&at));
        assert_eq!(factor, 0.9, "reflected at {p}");
        out
    }

    /// On a plane (normal +z): every ray from the object O (inside, z < 0) through a grid of
    /// points leaves exactly along the line to the image I, towards a real image (outside,
    /// z > 0), away from a virtual one (inside); and every ray from a real image back through
    /// the plane leaves towards O (reciprocity).
    #[test]
    fn on_a_plane_rays_from_the_object_leave_along_lines_through_the_image() {
        let plane = Shape::Plane(Plane::new(DVec3::ZERO, DVec3::Z, DVec3::X).unwrap());
        let object = DVec3::new(0.3, -0.2, -4.0);
        for (image, real) in [
            (DVec3::new(-0.5, 0.4, 6.0), true),
            (DVec3::new(1.0, 0.5, -2.0), false),
            (DVec3::new(0.2, -1.0, -9.0), false),
        ] {
            let h = point_to_point(object, image);
            for i in -5..=5 {
                for j in -5..=5 {
                    let p = DVec3::new(0.7 * i as f64, 0.6 * j as f64, 0.0);
                    let out = through(&h, &plane, object, p);
                    let (miss, along) = line_miss(p, out, image);
                    assert!(miss < 1e-12 * (1.0 + along.abs()), "{p}: misses by {miss}");
                    assert_eq!(along > 0.0, real, "{p}: {along}");
                    if real {
                        let back = through(&h, &plane, image, p);
                        let (miss, along) = line_miss(p, back, object);
                        assert!(miss < 1e-12 * along, "{p}: back misses by {miss}");
                    }
                }
            }
        }
    }

    /// On a sphere with the object inside: every ray from O, through points all over the
    /// sphere, leaves along the line through I; towards I where I lies outside the tangent
    /// plane at the point (a real image there), away from it where I lies inside; for an image
    /// inside the sphere, away from it everywhere.
    #[test]
    fn on_a_sphere_rays_from_the_object_leave_along_lines_through_the_image() {
        let (centre, radius) = (DVec3::new(0.5, -0.5, 8.0), 2.0);
        let sphere = Shape::Sphere(Sphere::new(centre, radius).unwrap());
        let object = centre + DVec3::new(0.3, 0.4, -0.6);
        for image in [
            centre + DVec3::new(-1.0, 2.0, 6.0),
            centre + DVec3::new(0.5, -0.4, 0.2),
        ] {
            let h = point_to_point(object, image);
            let mut real = 0;
            for k in 0..400 {
                // Points spread over the sphere (a Fibonacci lattice).
                let z = 1.0 - (2.0 * k as f64 + 1.0) / 400.0;
                let angle = 2.399_963 * k as f64;
                let s = (1.0 - z * z).sqrt();
                let n = DVec3::new(s * angle.cos(), s * angle.sin(), z);
                let p = centre + radius * n;
                let out = through(&h, &sphere, object, p);
                let (miss, along) = line_miss(p, out, image);
                assert!(miss < 1e-12 * (1.0 + along.abs()), "{p}: misses by {miss}");
                let outside = (image - p).dot(n) > 0.0;
                assert_eq!(along > 0.0, outside, "{p}: {along}");
                real += usize::from(outside);
            }
            assert!(real > 0 || (image - centre).length() < radius);
        }
    }

    /// A ray whose new tangential part would exceed 1 is reflected in the surface, carrying
    /// the reflection coefficient, as Dr TIM's phase holograms reflect evanescent waves.
    #[test]
    fn an_evanescent_wave_is_reflected() {
        let plane = Shape::Plane(Plane::new(DVec3::ZERO, DVec3::Z, DVec3::X).unwrap());
        // A lens of focal length 1 (O and I at ∓2 on the axis): at x = 4 the kick is about
        // −1.8 along x, so a ray arriving with d_x = −0.5 is evanescent.
        let h = point_to_point(DVec3::new(0.0, 0.0, -2.0), DVec3::new(0.0, 0.0, 2.0));
        let p = DVec3::new(4.0, 0.0, 0.0);
        let d = DVec3::new(-0.5, 0.0, 0.75f64.sqrt());
        let (out, factor) = leaves(h.redirect(&meet(&plane, p - d, d)));
        assert_eq!(factor, 0.4);
        assert!((out - DVec3::new(-0.5, 0.0, -(0.75f64.sqrt()))).length() < 1e-15);
    }

    /// A lens hologram of focal length f (here on the plane z = 1 with its axis along +z) is a
    /// thin lens paraxially: a ray parallel to the axis at a small height h crosses the axis
    /// at distance f behind the principal point (to within the aberration, of order h²/f),
    /// behind it for f > 0 and, extended backwards, in front for f < 0; the default
    /// transmission is Dr TIM's 0.96.
    #[test]
    fn a_lens_hologram_focuses_paraxial_rays_at_its_focal_length() {
        let plane = Shape::Plane(Plane::new(DVec3::Z, DVec3::Z, DVec3::X).unwrap());
        for f in [3.0, -2.0] {
            let keys: LensHologramKeys = toml::from_str(&format!(
                "principal_point = [0.5, -0.5, 1]\noptical_axis = [0, 0, 2]\nfocal_length = {f}\n"
            ))
            .unwrap();
            let Ok(Surface::PointToPointImagingHologram(h)) = keys.build() else {
                panic!()
            };
            for k in 1..=10 {
                let height = 1e-4 * k as f64;
                let p = DVec3::new(0.5 + 0.6 * height, -0.5 + 0.8 * height, 1.0);
                let (out, factor) = leaves(h.redirect(&meet(&plane, p - DVec3::Z, DVec3::Z)));
                assert_eq!(factor, 0.96);
                let (miss, along) = line_miss(p, out, DVec3::new(0.5, -0.5, 1.0 + f));
                assert!(miss < 1e-6 * height, "f = {f}, h = {height}: {miss}");
                assert!(along * f > 0.0);
            }
        }
    }

    #[test]
    fn the_same_point_twice_is_an_error() {
        let keys: PointToPointImagingHologramKeys =
            toml::from_str("object_position = [1, 2, 3]\nimage_position = [1, 2, 3]\n").unwrap();
        let e = keys.build().unwrap_err();
        assert!(
            e.contains("object_position and image_position are the same"),
            "{e}"
        );
    }
}
