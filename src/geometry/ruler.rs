//! A ruler (Dr TIM's visual aid): a thin rod with tick marks at regular spacing, every
//! `major_every`-th one longer, one solid built by CSG.

use glam::DVec3;
use serde::Deserialize;

use super::{Csg, CsgOperation, Cylinder, GeometryError, Shape};
use crate::keys::{Positive, Vector};

/// The most ticks a ruler may have.
pub const MAX_TICKS: usize = 1000;

/// A ruler from `start` to `end` with ticks from `start` every `tick_spacing`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ruler {
    pub start: DVec3,
    pub end: DVec3,
    /// The rod's radius; ticks are two thirds as thick.
    pub radius: f64,
    pub tick_spacing: f64,
    /// Which way the ticks stick out (its part perpendicular to the rod counts).
    pub tick_direction: DVec3,
    /// How far a tick sticks out; major ticks half as far again.
    pub tick_length: f64,
    /// Every this many ticks (counted from the start, which has one) a major tick.
    pub major_every: u32,
}

impl Ruler {
    /// The union of the rod and the ticks, each a cylinder from the rod's axis outwards.
    pub fn shape(&self) -> Result<Shape, GeometryError> {
        super::check_point("ruler start", self.start)?;
        super::check_point("ruler end", self.end)?;
        super::check_positive("ruler tick spacing", self.tick_spacing)?;
        super::check_positive("ruler tick length", self.tick_length)?;
        let along = self.end - self.start;
        let length = along.length();
        let out = super::check_direction(
            "ruler tick direction",
            self.tick_direction.reject_from(along),
        )
        .map_err(|_| {
            GeometryError::Degenerate(
                "the ruler's tick direction must not be parallel to the ruler".into(),
            )
        })?;
        let ticks = (length / self.tick_spacing).floor() + 1.0;
        if ticks > MAX_TICKS as f64 {
            return Err(GeometryError::Degenerate(format!(
                "a ruler may have at most {MAX_TICKS} ticks, got {ticks}"
            )));
        }
        let ticks = ticks as usize;
        let mut parts = vec![Shape::Cylinder(Cylinder::new(
            self.start,
            self.end,
            self.radius,
        )?)];
        for k in 0..ticks {
            let at = self.start + (k as f64 * self.tick_spacing / length) * along;
            let major = self.major_every > 0 && (k as u32).is_multiple_of(self.major_every);
            let reach = self.radius + self.tick_length * if major { 1.5 } else { 1.0 };
            parts.push(Shape::Cylinder(Cylinder::new(
                at,
                at + reach * out,
                2.0 / 3.0 * self.radius,
            )?));
        }
        let ruler = Csg::new(CsgOperation::Union, parts)?;
        Ok(Shape::Csg(ruler.called("ruler")))
    }
}

/// `type = "ruler"`: a rod with tick marks every `tick_spacing` from `start` (radius 1/200 of its length, ticks four radii long, along y (or x for a rod along y), every tenth one major, where not given).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RulerKeys {
    start: Vector,
    end: Vector,
    tick_spacing: Positive,
    radius: Option<Positive>,
    tick_direction: Option<Vector>,
    tick_length: Option<Positive>,
    major_every: Option<u32>,
}

impl RulerKeys {
    pub fn build(self) -> Result<Shape, GeometryError> {
        let along = self.end.0 - self.start.0;
        let radius = self.radius.map_or(along.length() / 200.0, |r| r.0);
        let up = if along.reject_from(DVec3::Y).length() > 1e-6 * along.length() {
            DVec3::Y
        } else {
            DVec3::X
        };
        Ruler {
            start: self.start.0,
            end: self.end.0,
            radius,
            tick_spacing: self.tick_spacing.0,
            tick_direction: self.tick_direction.map_or(up, |d| d.0),
            tick_length: self.tick_length.map_or(4.0 * radius, |l| l.0),
            major_every: self.major_every.unwrap_or(10),
        }
        .shape()
    }
}
