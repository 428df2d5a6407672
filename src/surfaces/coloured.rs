//! Coloured surface, lit by the scene's lights: ambient × diffuse colour plus, for each point
//! light, a two-sided Lambert term and a Phong specular term (shaded by `render::shading`).

use serde::Deserialize;

use super::Surface;
use crate::keys::Rgb;
use crate::math::Colour;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Coloured {
    pub diffuse: Colour,
    pub specular: Colour,
}

impl Coloured {
    /// "Shiny": white specular reflection.
    pub fn shiny(diffuse: Colour) -> Coloured {
        Coloured {
            diffuse,
            specular: Colour::ONE,
        }
    }

    /// "Matt": no specular reflection.
    pub fn matt(diffuse: Colour) -> Coloured {
        Coloured {
            diffuse,
            specular: Colour::ZERO,
        }
    }
}

/// `type = "coloured"`: a diffuse colour and a specular one (none when not given).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ColouredKeys {
    diffuse: Rgb,
    specular: Option<Rgb>,
}

impl ColouredKeys {
    pub fn build(self) -> Result<Surface, String> {
        Ok(Surface::Coloured(Coloured {
            diffuse: self.diffuse.0,
            specular: self.specular.map_or(Colour::ZERO, |s| s.0),
        }))
    }
}

/// `type = "shiny"`: [`Coloured::shiny`].
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShinyKeys {
    colour: Rgb,
}

impl ShinyKeys {
    pub fn build(self) -> Result<Surface, String> {
        Ok(Surface::Coloured(Coloured::shiny(self.colour.0)))
    }
}

/// `type = "matt"`: [`Coloured::matt`].
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MattKeys {
    colour: Rgb,
}

impl MattKeys {
    pub fn build(self) -> Result<Surface, String> {
        Ok(Surface::Coloured(Coloured::matt(self.colour.0)))
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;
    use crate::geometry::{Shape, Sphere};
    use crate::surfaces::Redirection;
    use crate::surfaces::tests::meet;

    /// A coloured surface ends the ray, to be shaded by the lights: `Surface::redirect` answers
    /// `Lit` with the surface's own colours, from outside and from inside a sphere.
    #[test]
    fn a_coloured_surface_is_lit() {
        let sphere = Shape::Sphere(Sphere::new(DVec3::new(0.0, 1.0, 0.0), 1.0).unwrap());
        for coloured in [
            Coloured::shiny(Colour::new(0.2, 0.4, 0.6)),
            Coloured::matt(Colour::new(0.9, 0.1, 0.0)),
        ] {
            let surface = Surface::Coloured(coloured);
            for (origin, d) in [
                (DVec3::new(-3.0, 1.2, 0.1), DVec3::X),
                (DVec3::new(0.0, 1.0, 0.0), DVec3::new(0.2, 0.3, -0.5)),
            ] {
                let at = meet(&sphere, origin, d);
                match surface.redirect(&at, &mut |_| {}) {
                    Redirection::Lit(c) => assert_eq!(c, coloured),
                    other => panic!("{other:?}"),
                }
            }
        }
    }
}
