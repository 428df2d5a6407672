//! Constant colour: the surface emits its colour whatever the lighting (TIM's sky), as
//! `Surface::ConstantColour`.

use serde::Deserialize;

use super::Surface;
use crate::keys::Rgb;

/// `type = "constant-colour"`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ConstantColourKeys {
    colour: Rgb,
}

impl ConstantColourKeys {
    pub fn build(self) -> Result<Surface, String> {
        Ok(Surface::ConstantColour(self.colour.0))
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use crate::geometry::{Plane, Shape};
    use crate::math::Colour;
    use crate::surfaces::tests::meet;
    use crate::surfaces::{Redirection, Surface};

    /// A constant-colour surface emits its colour whatever the lighting and wherever it is
    /// seen from: `Surface::redirect` answers `Emits` with the colour, from either side.
    #[test]
    fn a_constant_colour_surface_emits_its_colour() {
        let colour = Colour::new(0.1, 0.5, 0.25);
        let sky = Surface::ConstantColour(colour);
        let plane =
            Shape::Plane(Plane::new(DVec3::new(0.0, 0.0, 10.0), DVec3::Z, DVec3::X).unwrap());
        for d in [DVec3::new(0.2, 0.1, 1.0), DVec3::new(-0.4, 0.3, -1.0)] {
            let at = meet(&plane, DVec3::new(0.0, 0.0, 10.0) - 4.0 * d, d);
            assert_eq!(sky.redirect(&at, &mut |_| {}), Redirection::Emits(colour));
        }
    }
}
