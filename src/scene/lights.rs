//! The scene's lights (TIM's studio lighting): an ambient light and point lights; how they
//! shade coloured surfaces is `render::shading`.

use glam::DVec3;

use crate::math::Colour;

#[derive(Debug, Clone, PartialEq)]
pub struct PointLight {
    pub position: DVec3,
    pub colour: Colour,
    pub phong_exponent: f64,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Lights {
    pub ambient: Colour,
    pub points: Vec<PointLight>,
}

impl Lights {
    /// No light at all: coloured surfaces are black.
    pub fn none() -> Lights {
        Lights {
            ambient: Colour::ZERO,
            points: Vec::new(),
        }
    }
}
