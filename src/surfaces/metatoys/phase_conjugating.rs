//! Phase conjugation (§6): a phase-conjugating mirror reverses every ray, d′ = −d, so light
//! retraces its path whatever the angle of incidence (the surface reflects the wave with its
//! phase conjugated, which reverses the wave vector).

use crate::geometry::Interaction;
use crate::surfaces::Redirection;

#[derive(Debug, Clone, PartialEq)]
pub struct PhaseConjugating {
    /// Fraction of the light sent back, in [0, 1].
    pub reflection_coefficient: f64,
}

impl PhaseConjugating {
    pub fn redirect(&self, at: &Interaction) -> Redirection<'static> {
        Redirection::Leaves {
            direction: -at.ray.direction,
            factor: self.reflection_coefficient,
        }
    }
}
