//! Three arrows along the axes of a coordinate system, red, green and blue (Dr TIM's object
//! coordinate system, `EditableObjectCoordinateSystem`, whose arrows have shafts of radius
//! 0.025 and tips 0.1 long with a half angle of 30°; also the surface-coordinate axes of a
//! surface point: û, v̂ and the outward normal, the paper's §4.4 footnote).

use glam::DVec3;
use serde::Deserialize;

use super::Part;
use crate::geometry::Arrow;
use crate::keys::{Array, Direction, Positive, Vector};
use crate::math::Colour;
use crate::surfaces::{Coloured, Surface};

/// Arrows of length `length` from `origin` along each of `axes`, named by `names`.
#[derive(Debug, Clone, PartialEq)]
pub struct CoordinateSystem {
    pub origin: DVec3,
    pub axes: [DVec3; 3],
    pub names: [&'static str; 3],
    pub length: f64,
    pub shaft_radius: f64,
    pub tip_length: f64,
}

/// The tips' half angle, Dr TIM's: a tip is tan 30° ≈ 0.58 times its length in radius at its
/// base, wider than the shafts of the defaults.
const TIP_ANGLE_DEG: f64 = 30.0;

impl CoordinateSystem {
    pub fn parts(&self) -> Result<Vec<Part>, String> {
        let colours = [
            Colour::new(1.0, 0.0, 0.0),
            Colour::new(0.0, 1.0, 0.0),
            Colour::new(0.0, 0.0, 1.0),
        ];
        (0..3)
            .map(|i| {
                let direction = self.axes[i].try_normalize().ok_or_else(|| {
                    format!("the {} direction must be a non-zero vector", self.names[i])
                })?;
                let shape = Arrow {
                    start: self.origin,
                    end: self.origin + self.length * direction,
                    shaft_radius: self.shaft_radius,
                    tip_length: self.tip_length,
                    tip_angle_deg: TIP_ANGLE_DEG,
                }
                .shape()
                .map_err(|e| format!("{}: {e}", self.names[i]))?;
                Ok(Part {
                    name: self.names[i].to_string(),
                    shape,
                    surface: Surface::Coloured(Coloured::shiny(colours[i])),
                    edge: true,
                })
            })
            .collect()
    }
}

/// `aid = { type = "coordinate-system" }`: x, y and z at the origin, of length 1, with shafts
/// 1/40 of it and tips 1/10 of it (Dr TIM's 0.025 and 0.1 at length 1), where not given.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CoordinateSystemKeys {
    origin: Option<Vector>,
    axes: Option<Array<Direction, 3>>,
    length: Option<Positive>,
    shaft_radius: Option<Positive>,
}

impl CoordinateSystemKeys {
    pub fn build(self) -> Result<Vec<Part>, String> {
        let length = self.length.map_or(1.0, |l| l.0);
        CoordinateSystem {
            origin: self.origin.map_or(DVec3::ZERO, |o| o.0),
            axes: self
                .axes
                .map_or([DVec3::X, DVec3::Y, DVec3::Z], |a| a.0.map(|d| d.0)),
            names: ["x axis", "y axis", "z axis"],
            length,
            shaft_radius: self.shaft_radius.map_or(0.025 * length, |r| r.0),
            tip_length: 0.1 * length,
        }
        .parts()
        .map_err(|e| format!("coordinate-system: {e}"))
    }
}
