//! Coloured surface, lit by the scene's lights: ambient × diffuse colour plus, for each point
//! light, a two-sided Lambert term and a Phong specular term (shaded by `render::shading`).

use crate::math::Colour;

#[derive(Debug, Clone, PartialEq)]
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
