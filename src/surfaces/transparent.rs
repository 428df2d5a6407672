//! Transparent pass-through: the ray continues undeviated, scaled by a transmission coefficient.

use super::Colour;
use crate::render::{Interaction, Tracer};

#[derive(Debug, Clone, PartialEq)]
pub struct Transparent {
    /// Fraction of the light transmitted, in [0, 1].
    pub transmission_coefficient: f64,
}

impl Transparent {
    pub fn colour(&self, tracer: &Tracer, at: &Interaction) -> Colour {
        self.transmission_coefficient * tracer.trace_from(at, at.ray.direction)
    }
}
