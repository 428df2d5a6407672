//! Surface of a tinted solid: light crossing a thickness d inside keeps exp(−a·d) of each
//! channel (Beer–Lambert), with no refraction (Dr TIM's `SurfaceOfTintedSolid`).

use serde::Deserialize;

use crate::geometry::Interaction;
use crate::keys::{Array, NonNegative};
use crate::math::Colour;
use crate::surfaces::{Redirection, Surface};

#[derive(Debug, Clone, PartialEq)]
pub struct TintedSolid {
    /// Absorption coefficient of each channel, per unit length.
    pub absorption: Colour,
}

impl TintedSolid {
    /// Dr TIM's rule: a ray leaving the solid (travelling along the outward normal) has come
    /// from its own start, the entry point of a ray traced on from there, and keeps exp(−a·t)
    /// over that distance t; a ray entering goes on undeviated and the tracer attenuates it
    /// over the distance to its next hit, unless that hit is this object's own exit.
    pub fn redirect(&self, at: &Interaction) -> Redirection<'static> {
        let d = at.ray.direction;
        if d.dot(at.normal()) > 0.0 {
            let t = at.hit.t;
            Redirection::Leaves {
                direction: d,
                factor: Colour::new(
                    (-self.absorption.x * t).exp(),
                    (-self.absorption.y * t).exp(),
                    (-self.absorption.z * t).exp(),
                ),
            }
        } else {
            Redirection::Absorbs {
                absorption: self.absorption,
                direction: d,
                factor: Colour::ONE,
            }
        }
    }
}

/// `type = "tinted-solid"`: Dr TIM's `SurfaceOfTintedSolid`, whose GUI offers none, so
/// `absorption_coefficient` (red, green, blue, per unit length, non-negative) is required.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TintedSolidKeys {
    absorption_coefficient: Array<NonNegative, 3>,
}

impl TintedSolidKeys {
    pub fn build(self) -> Result<Surface, String> {
        let [r, g, b] = self.absorption_coefficient.0.map(|a| a.0);
        Ok(Surface::TintedSolid(TintedSolid {
            absorption: Colour::new(r, g, b),
        }))
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;
    use crate::geometry::{Shape, Sphere};
    use crate::surfaces::tests::meet;

    /// A ray from the centre of a unit sphere travels 1 inside before it leaves: red with
    /// a = ln 2 keeps exactly 1/2, green with a = 0 all, blue with a = 2 keeps e⁻².
    #[test]
    fn a_ray_leaving_keeps_exp_minus_a_t_of_each_channel() {
        let solid = TintedSolid {
            absorption: Colour::new(std::f64::consts::LN_2, 0.0, 2.0),
        };
        let sphere = Shape::Sphere(Sphere::new(DVec3::ZERO, 1.0).unwrap());
        let d = DVec3::new(0.3, -0.4, 0.5).normalize();
        let Redirection::Leaves { direction, factor } =
            solid.redirect(&meet(&sphere, DVec3::ZERO, d))
        else {
            panic!("a leaving ray goes on")
        };
        assert!((direction - d).length() < 1e-15);
        assert!((factor.x - 0.5).abs() < 1e-15, "{factor}");
        assert_eq!(factor.y, 1.0);
        assert!((factor.z - (-2.0f64).exp()).abs() < 1e-15, "{factor}");
    }

    /// A ray arriving from outside enters undeviated, absorbed from there by the tracer.
    #[test]
    fn a_ray_entering_is_absorbed_on_its_way() {
        let a = Colour::new(0.1, 0.2, 0.3);
        let solid = TintedSolid { absorption: a };
        let sphere = Shape::Sphere(Sphere::new(DVec3::ZERO, 1.0).unwrap());
        let at = meet(&sphere, DVec3::new(0.2, 0.1, -5.0), DVec3::Z);
        assert_eq!(
            solid.redirect(&at),
            Redirection::Absorbs {
                absorption: a,
                direction: at.ray.direction,
                factor: Colour::ONE
            }
        );
    }

    #[test]
    fn negative_absorption_is_refused() {
        let e = toml::from_str::<TintedSolidKeys>("absorption_coefficient = [1, -1, 0]")
            .unwrap_err()
            .to_string();
        assert!(e.contains("expected a number from 0"), "{e}");
        assert!(toml::from_str::<TintedSolidKeys>("").is_err());
    }
}
