//! Transparent pass-through: the ray continues undeviated, scaled by a transmission coefficient.

use serde::Deserialize;

use super::{Redirection, Surface};
use crate::geometry::Interaction;
use crate::keys::{Coefficient, coefficient};

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

/// `type = "transparent"`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TransparentKeys {
    #[serde(alias = "transmission")]
    transmission_coefficient: Option<Coefficient>,
}

impl TransparentKeys {
    pub fn build(self) -> Result<Surface, String> {
        Ok(Surface::Transparent(Transparent {
            transmission_coefficient: coefficient(self.transmission_coefficient),
        }))
    }
}
