//! Colour filter: the ray goes on undeviated, each colour channel scaled by its own
//! transmission coefficient (Dr TIM's `ColourFilter`).

use serde::Deserialize;

use crate::geometry::Interaction;
use crate::keys::Rgb;
use crate::math::Colour;
use crate::surfaces::{Redirection, Surface};

#[derive(Debug, Clone, PartialEq)]
pub struct ColourFilter {
    /// The fraction of each channel (red, green, blue) passed on.
    pub transmission: Colour,
}

impl ColourFilter {
    pub fn redirect(&self, at: &Interaction) -> Redirection<'static> {
        Redirection::Leaves {
            direction: at.ray.direction,
            factor: self.transmission,
        }
    }
}

/// `type = "colour-filter"`: Dr TIM's `ColourFilter`, with the GUI's colour white (a filter
/// that passes everything) where `transmission` is not given. Like Dr TIM's, a transmission
/// above 1 makes the light brighter.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ColourFilterKeys {
    transmission: Option<Rgb>,
}

impl ColourFilterKeys {
    pub fn build(self) -> Result<Surface, String> {
        Ok(Surface::ColourFilter(ColourFilter {
            transmission: self.transmission.map_or(Colour::ONE, |t| t.0),
        }))
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;
    use crate::geometry::{Plane, Shape, Sphere};
    use crate::surfaces::tests::meet;

    /// A cyan filter passes no red and all green and blue, in the ray's own direction, whichever
    /// side of a plane or sphere the ray meets.
    #[test]
    fn the_ray_goes_on_undeviated_with_the_filters_channels() {
        let cyan = ColourFilter {
            transmission: Colour::new(0.0, 1.0, 0.5),
        };
        let plane = Shape::Plane(Plane::new(DVec3::ZERO, DVec3::Z, DVec3::X).unwrap());
        let sphere = Shape::Sphere(Sphere::new(DVec3::ZERO, 1.0).unwrap());
        for (shape, origin, d) in [
            (
                &plane,
                DVec3::new(0.0, 0.0, 3.0),
                DVec3::new(0.2, 0.1, -1.0),
            ),
            (
                &plane,
                DVec3::new(0.0, 0.0, -3.0),
                DVec3::new(0.2, 0.1, 1.0),
            ),
            (&sphere, DVec3::ZERO, DVec3::new(0.3, -0.4, 0.5)),
        ] {
            let at = meet(shape, origin, d);
            assert_eq!(
                cyan.redirect(&at),
                Redirection::Leaves {
                    direction: d.normalize(),
                    factor: Colour::new(0.0, 1.0, 0.5)
                }
            );
        }
    }

    #[test]
    fn the_default_filter_passes_everything() {
        let keys: ColourFilterKeys = toml::from_str("").unwrap();
        assert_eq!(
            keys.build(),
            Ok(Surface::ColourFilter(ColourFilter {
                transmission: Colour::ONE
            }))
        );
    }
}
