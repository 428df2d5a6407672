//! Hue–brightness gradient: a lit surface whose diffuse colour shows its surface coordinates,
//! lightness along u and hue along v (Dr TIM's `HueBrightnessGradientSurface`).

use serde::Deserialize;

use super::hsl;
use crate::geometry::Interaction;
use crate::keys::Rgb;
use crate::math::Colour;
use crate::surfaces::{Coloured, Redirection, Surface};

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HueBrightnessGradient {
    pub specular: Colour,
}

impl HueBrightnessGradient {
    /// The diffuse colour of hue v (in turns), saturation 1 and lightness u, at surface
    /// coordinates (u, v), lit by the lights.
    pub fn redirect(&self, at: &Interaction) -> Redirection<'static> {
        let uv = at.coordinates();
        Redirection::Lit(Coloured {
            diffuse: hsl(uv.y, 1.0, uv.x).max(Colour::ZERO),
            specular: self.specular,
        })
    }
}

/// `type = "hue-brightness-gradient"`: `specular` where not given white, as Dr TIM's
/// constructor without a colour (the one its research programs use).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HueBrightnessGradientKeys {
    specular: Option<Rgb>,
}

impl HueBrightnessGradientKeys {
    pub fn build(self) -> Result<Surface, String> {
        Ok(Surface::HueBrightnessGradient(HueBrightnessGradient {
            specular: self.specular.map_or(Colour::ONE, |c| c.0),
        }))
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;
    use crate::geometry::{Plane, Shape};
    use crate::surfaces::tests::meet;

    /// On the plane z = 0 with u along x and v along y: at (0.5, 0) lightness 1/2 and hue 0,
    /// pure red; at (0.5, 1/3) pure green; at (1, ·) white; at (0, ·) black.
    #[test]
    fn lightness_runs_along_u_and_hue_along_v() {
        let plane = Shape::Plane(Plane::new(DVec3::ZERO, DVec3::Z, DVec3::X).unwrap());
        let surface = HueBrightnessGradient {
            specular: Colour::ONE,
        };
        let diffuse = |u: f64, v: f64| {
            let at = meet(&plane, DVec3::new(u, v, 1.0), -DVec3::Z);
            match surface.redirect(&at) {
                Redirection::Lit(c) => c.diffuse,
                other => panic!("lit, not {other:?}"),
            }
        };
        let near = |a: Colour, b: Colour| (a - b).abs().max_element() < 1e-9;
        assert!(near(diffuse(0.5, 0.0), Colour::new(1.0, 0.0, 0.0)));
        assert!(near(diffuse(0.5, 1.0 / 3.0), Colour::new(0.0, 1.0, 0.0)));
        assert!(near(diffuse(1.0, 0.7), Colour::ONE));
        assert!(near(diffuse(0.0, 0.7), Colour::ZERO));
    }
}
