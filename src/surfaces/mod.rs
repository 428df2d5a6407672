//! Surface properties: what happens to light where a ray meets a surface. One law per file;
//! each gives the colour seen along the incoming ray, tracing further rays where the law
//! redirects light.

mod chequerboard;
mod coloured;
mod reflective;
mod refractive;
mod transparent;

pub use chequerboard::Chequerboard;
pub use coloured::Coloured;
pub use reflective::{Mirror, reflect};
pub use refractive::{Refractive, refract};
pub use transparent::Transparent;

use crate::render::{Interaction, Tracer};

/// Linear RGB radiance, unbounded (clamped only when written to PNG).
pub type Colour = glam::DVec3;

#[derive(Debug, Clone, PartialEq)]
pub enum Surface {
    /// Diffuse and specular colours lit by the scene's lights.
    Coloured(Coloured),
    /// Emits its colour whatever the lighting (TIM's sky).
    ConstantColour(Colour),
    Chequerboard(Chequerboard),
    Mirror(Mirror),
    Refractive(Refractive),
    Transparent(Transparent),
}

impl Surface {
    /// The colour seen along `at.ray` where it meets this surface.
    pub fn colour(&self, tracer: &Tracer, at: &Interaction) -> Colour {
        match self {
            Surface::Coloured(s) => s.colour(tracer, at),
            Surface::ConstantColour(c) => *c,
            Surface::Chequerboard(s) => s.colour(tracer, at),
            Surface::Mirror(s) => s.colour(tracer, at),
            Surface::Refractive(s) => s.colour(tracer, at),
            Surface::Transparent(s) => s.colour(tracer, at),
        }
    }
}
