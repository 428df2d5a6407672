//! Mirror: specular reflection, r = d − 2 (d·n) n, scaled by a reflection coefficient.

use glam::DVec3;
use serde::Deserialize;

use super::{Redirection, Surface};
use crate::geometry::Interaction;
use crate::keys::{Coefficient, throughput};
use crate::math::Colour;

#[derive(Debug, Clone, PartialEq)]
pub struct Mirror {
    /// Fraction of the light that is reflected, in [0, 1].
    pub reflection_coefficient: f64,
}

/// Mirror image of direction `d` in a surface with unit normal `n` (either orientation).
pub fn reflect(d: DVec3, n: DVec3) -> DVec3 {
    d - 2.0 * d.dot(n) * n
}

impl Mirror {
    pub fn redirect(&self, at: &Interaction) -> Redirection<'static> {
        Redirection::Leaves {
            direction: reflect(at.ray.direction, at.normal()),
            factor: Colour::splat(self.reflection_coefficient),
        }
    }
}

/// `type = "mirror"`: Dr TIM's `Reflective`, reflecting `DEFAULT_TRANSMISSION_COEFFICIENT`
/// (0.96) of the light where not given, as its GUI makes it.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MirrorKeys {
    #[serde(alias = "reflection")]
    reflection_coefficient: Option<Coefficient>,
}

impl MirrorKeys {
    pub fn build(self) -> Result<Surface, String> {
        Ok(Surface::Mirror(Mirror {
            reflection_coefficient: throughput(self.reflection_coefficient),
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Plane, Shape, Sphere};
    use crate::surfaces::tests::{leaves, meet};

    #[test]
    fn angle_of_incidence_equals_angle_of_reflection() {
        let n = DVec3::Y;
        let d = DVec3::new(1.0, -1.0, 0.0).normalize();
        let r = reflect(d, n);
        assert!((r - DVec3::new(1.0, 1.0, 0.0).normalize()).length() < 1e-15);
        // The same for the opposite normal orientation, and reflecting twice restores d.
        assert!((reflect(d, -n) - r).length() < 1e-15);
        assert!((reflect(r, n) - d).length() < 1e-15);
    }

    #[test]
    fn normal_incidence_reverses_the_ray() {
        let n = DVec3::new(1.0, 2.0, 2.0) / 3.0;
        assert!((reflect(-n, n) - n).length() < 1e-15);
    }

    /// The law of reflection through `Mirror::redirect`, on a tilted plane (from either side)
    /// and on a sphere (from outside and from inside): the reflected ray makes the same angle
    /// with the normal as the incident one, returns to the side it came from, lies in the plane
    /// of incidence (spanned by d and the normal) and goes on along the surface the way d did;
    /// it carries the reflection coefficient. The normals are worked out here from the shapes'
    /// definitions.
    #[test]
    fn redirect_reflects_by_the_law_of_reflection_on_a_plane_and_a_sphere() {
        let mirror = Mirror {
            reflection_coefficient: 0.8,
        };
        let n_plane = DVec3::new(1.0, 2.0, 2.0) / 3.0;
        let plane =
            Shape::Plane(Plane::new(DVec3::new(0.2, -0.1, 0.4), n_plane, DVec3::X).unwrap());
        let centre = DVec3::new(1.0, 0.5, -2.0);
        let sphere = Shape::Sphere(Sphere::new(centre, 1.5).unwrap());
        let cases = [
            (
                &plane,
                DVec3::new(3.0, 4.0, 5.0),
                DVec3::new(-0.4, -0.7, -0.6),
            ),
            (
                &plane,
                DVec3::new(-2.0, -3.0, -1.0),
                DVec3::new(0.5, 0.6, 0.3),
            ),
            (
                &sphere,
                DVec3::new(-3.0, 1.2, -1.0),
                DVec3::new(1.0, -0.1, -0.2),
            ),
            (
                &sphere,
                DVec3::new(1.2, 0.3, -2.1),
                DVec3::new(0.3, 0.8, -0.5),
            ),
        ];
        for (shape, origin, d) in cases {
            let at = meet(shape, origin, d);
            let d = d.normalize();
            let n = match shape {
                Shape::Sphere(_) => (at.point() - centre) / 1.5,
                _ => n_plane,
            };
            let (out, factor) = leaves(mirror.redirect(&at));
            assert_eq!(factor, 0.8);
            assert!((out.length() - 1.0).abs() < 1e-14, "{out}");
            let incidence = d.dot(n).abs().acos();
            let reflection = out.dot(n).abs().acos();
            assert!(
                (incidence - reflection).abs() < 1e-12,
                "{incidence} {reflection}"
            );
            assert!(out.dot(n) * d.dot(n) < 0.0, "back to the side it came from");
            assert!(
                out.dot(d.cross(n)).abs() < 1e-14,
                "in the plane of incidence"
            );
            assert!(out.cross(n).dot(d.cross(n)) > 0.0, "on along the surface");
        }
    }
}
