//! Transparent pass-through: the ray continues undeviated, scaled by a transmission coefficient.

use serde::Deserialize;

use super::{Redirection, Surface};
use crate::geometry::Interaction;
use crate::keys::{Coefficient, throughput};
use crate::math::Colour;

#[derive(Debug, Clone, PartialEq)]
pub struct Transparent {
    /// Fraction of the light transmitted, in [0, 1].
    pub transmission_coefficient: f64,
}

impl Transparent {
    pub fn redirect(&self, at: &Interaction) -> Redirection<'static> {
        Redirection::Leaves {
            direction: at.ray.direction,
            factor: Colour::splat(self.transmission_coefficient),
        }
    }
}

/// `type = "transparent"`: Dr TIM's `Transparent`, with its GUI's transmission coefficient
/// 0.96 where not given.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TransparentKeys {
    #[serde(alias = "transmission")]
    transmission_coefficient: Option<Coefficient>,
}

impl TransparentKeys {
    pub fn build(self) -> Result<Surface, String> {
        Ok(Surface::Transparent(Transparent {
            transmission_coefficient: throughput(self.transmission_coefficient),
        }))
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;
    use crate::geometry::{Plane, Shape, Sphere};
    use crate::surfaces::tests::{leaves, meet};

    /// A transparent surface changes nothing but the amount of light: the ray goes on in the
    /// same direction, on a plane and on a sphere, entering or leaving, with the transmission
    /// coefficient as the factor.
    #[test]
    fn redirect_leaves_the_direction_unchanged() {
        let clear = Transparent {
            transmission_coefficient: 0.7,
        };
        let plane =
            Shape::Plane(Plane::new(DVec3::ZERO, DVec3::new(0.0, 1.0, 1.0), DVec3::X).unwrap());
        let sphere = Shape::Sphere(Sphere::new(DVec3::new(1.0, 2.0, 3.0), 1.0).unwrap());
        for (shape, origin, d) in [
            (
                &plane,
                DVec3::new(0.3, 2.0, 2.0),
                DVec3::new(0.1, -0.5, -0.8),
            ),
            (
                &plane,
                DVec3::new(0.3, -2.0, -2.0),
                DVec3::new(0.1, 0.5, 0.8),
            ),
            (
                &sphere,
                DVec3::new(-2.0, 2.3, 3.1),
                DVec3::new(1.0, 0.0, 0.0),
            ),
            (
                &sphere,
                DVec3::new(1.0, 2.0, 3.0),
                DVec3::new(0.3, -0.6, 0.2),
            ),
        ] {
            let at = meet(shape, origin, d);
            let (out, factor) = leaves(clear.redirect(&at));
            assert!((out - d.normalize()).length() < 1e-15, "{out}");
            assert_eq!(factor, 0.7);
        }
    }
}
