//! A ruler (Dr TIM's visual aid): a thin rod with tick marks at regular spacing, every
//! `major_every`-th one longer, one solid built by CSG.

use glam::DVec3;

use super::{Csg, CsgOperation, Cylinder, GeometryError, Shape};

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
