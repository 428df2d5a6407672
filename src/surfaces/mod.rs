//! Surface properties: what happens to light where a ray meets a surface. One law per file;
//! each gives the colour seen along the incoming ray, tracing further rays where the law
//! redirects light.

mod chequerboard;
mod coloured;
pub mod lenses;
pub mod metatoys;
mod reflective;
mod refractive;
mod transparent;

pub use chequerboard::Chequerboard;
pub use coloured::Coloured;
pub use lenses::Lens;
pub use metatoys::{
    ConfocalLensletArrays, LorentzWindow, MetricInterface, PhaseConjugating, PhaseHologram,
    RayFlipping, RayRotating, Teleporting,
};
pub use reflective::{Mirror, reflect};
pub use refractive::{Refractive, refract};
pub use transparent::Transparent;

use crate::geometry::Shape;
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
    /// §3's lenses; the surface of a sphere.
    Lens(Lens),
    /// §4: refraction between spaces with different optical metrics.
    MetricInterface(MetricInterface),
    /// §5: generalised confocal lenslet arrays.
    ConfocalLensletArrays(ConfocalLensletArrays),
    RayRotating(RayRotating),
    RayFlipping(RayFlipping),
    /// Flat surfaces only.
    PhaseHologram(PhaseHologram),
    PhaseConjugating(PhaseConjugating),
    LorentzWindow(LorentzWindow),
    Teleporting(Teleporting),
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
            Surface::Lens(s) => s.colour(tracer, at),
            Surface::MetricInterface(s) => s.colour(tracer, at),
            Surface::ConfocalLensletArrays(s) => s.colour(tracer, at),
            Surface::RayRotating(s) => s.colour(tracer, at),
            Surface::RayFlipping(s) => s.colour(tracer, at),
            Surface::PhaseHologram(s) => s.colour(tracer, at),
            Surface::PhaseConjugating(s) => s.colour(tracer, at),
            Surface::LorentzWindow(s) => s.colour(tracer, at),
            Surface::Teleporting(s) => s.colour(tracer, at),
        }
    }

    /// Whether the law works on `shape`: §3's lenses, also as chequerboard tiles, need a
    /// sphere's centre and radius; phase holograms need a flat shape's coordinates.
    pub fn check_shape(&self, shape: &Shape) -> Result<(), String> {
        match (self, shape) {
            (Surface::Lens(_), Shape::Sphere(_)) => Ok(()),
            (Surface::Lens(l), _) => Err(format!(
                "a {} surface needs a sphere shape (its centre and radius)",
                l.law.name()
            )),
            (Surface::PhaseHologram(_), Shape::Plane(_) | Shape::Disc(_))
            | (Surface::PhaseHologram(_), Shape::Parallelogram(_)) => Ok(()),
            (Surface::PhaseHologram(_), _) => Err(
                "a phase-hologram surface needs a flat shape (plane, disc or parallelogram)"
                    .to_string(),
            ),
            (Surface::Chequerboard(c), _) => {
                c.surfaces.iter().try_for_each(|s| s.check_shape(shape))
            }
            _ => Ok(()),
        }
    }
}
