//! Transparent pass-through: the ray continues undeviated, scaled by a transmission coefficient.

use super::Redirection;
use crate::geometry::Interaction;

#[derive(Debug, Clone, PartialEq)]
pub struct Transparent {
    /// Fraction of the light transmitted, in [0, 1].
    pub transmission_coefficient: f64,
}

impl Transparent {
    pub fn redirect(&self, at: &Interaction) -> Redirection<'static> {
        Redirection::Leaves {
            direction: at.ray.direction,
            factor: self.transmission_coefficient,
        }
    }
}
