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
