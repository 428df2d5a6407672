//! Surface of a glowing cloud: light passes undeviated, and a ray entering the object gains
//! glow in proportion to how much of the object lies along it (Dr TIM's
//! `SurfaceOfGlowingCloud`).

use serde::Deserialize;

use crate::geometry::Interaction;
use crate::keys::{Positive, Rgb};
use crate::math::Colour;
use crate::surfaces::{Redirection, Surface};

#[derive(Debug, Clone, PartialEq)]
pub struct GlowingCloud {
    /// The colour a cloud of infinite depth adds.
    pub glow: Colour,
    /// The depth over which 1 − 1/e of the glow is added.
    pub one_over_e_distance: f64,
}

impl GlowingCloud {
    /// Dr TIM's rule: a ray entering (against the outward normal) gains
    /// glow × (1 − exp(−t / L)), t the distance to where it meets the same object's shape
    /// again, whatever lies between (the "cloud": other objects are ignored, and overlapping
    /// clouds each add their whole depth); without such a point, all of the glow. A ray
    /// leaving gains nothing. Either way it goes on undeviated, undimmed.
    pub fn redirect(&self, at: &Interaction) -> Redirection<'static> {
        let d = at.ray.direction;
        if d.dot(at.normal()) > 0.0 {
            return Redirection::Glows {
                glow: Colour::ZERO,
                factor: Colour::ONE,
            };
        }
        let depth = at
            .shape
            .intersect(at.local_point(), d, at.self_hit_margin(), f64::INFINITY)
            .map_or(f64::INFINITY, |(t, _)| t);
        Redirection::Glows {
            glow: self.glow * -(-depth / self.one_over_e_distance).exp_m1(),
            factor: Colour::ONE,
        }
    }
}

/// `type = "glowing-cloud"`: Dr TIM's `SurfaceOfGlowingCloud`, which its GUI does not offer,
/// so `glow_colour` and `one_over_e_distance` are required.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GlowingCloudKeys {
    glow_colour: Rgb,
    one_over_e_distance: Positive,
}

impl GlowingCloudKeys {
    pub fn build(self) -> Result<Surface, String> {
        Ok(Surface::GlowingCloud(GlowingCloud {
            glow: self.glow_colour.0,
            one_over_e_distance: self.one_over_e_distance.0,
        }))
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;
    use crate::geometry::{Plane, Shape, Sphere};
    use crate::surfaces::tests::meet;

    fn cloud() -> GlowingCloud {
        GlowingCloud {
            glow: Colour::new(1.0, 0.5, 0.0),
            one_over_e_distance: 2.0,
        }
    }

    /// A ray through the centre of a sphere of radius 1 crosses a depth of 2 = L: it gains
    /// (1 − 1/e) of the glow; a ray at impact parameter 0.6 crosses the chord 2 × 0.8 = 1.6;
    /// leaving, it gains nothing.
    #[test]
    fn a_ray_entering_gains_glow_by_the_depth_of_its_chord() {
        let sphere = Shape::Sphere(Sphere::new(DVec3::new(0.0, 0.0, 5.0), 1.0).unwrap());
        let glows = |origin: DVec3, d: DVec3| match cloud().redirect(&meet(&sphere, origin, d)) {
            Redirection::Glows { glow, .. } => glow,
            other => panic!("{other:?}"),
        };
        let through_centre = glows(DVec3::ZERO, DVec3::Z);
        let e = (1.0 - (-1.0f64).exp()) * Colour::new(1.0, 0.5, 0.0);
        assert!(
            (through_centre - e).abs().max_element() < 1e-12,
            "{through_centre}"
        );
        let offset = glows(DVec3::new(0.6, 0.0, 0.0), DVec3::Z);
        let e = (1.0 - (-0.8f64).exp()) * Colour::new(1.0, 0.5, 0.0);
        assert!((offset - e).abs().max_element() < 1e-12, "{offset}");
        assert_eq!(
            glows(DVec3::new(0.0, 0.0, 5.0), DVec3::X),
            Colour::ZERO,
            "leaving"
        );
    }

    /// An open shape that the ray never meets again glows with the whole glow colour.
    #[test]
    fn without_a_far_side_the_whole_glow_is_added() {
        let plane = Shape::Plane(Plane::new(DVec3::ZERO, DVec3::Z, DVec3::X).unwrap());
        let at = meet(&plane, DVec3::new(0.0, 0.0, 3.0), -DVec3::Z);
        assert_eq!(
            cloud().redirect(&at),
            Redirection::Glows {
                glow: Colour::new(1.0, 0.5, 0.0),
                factor: Colour::ONE,
            }
        );
    }
}
