//! An arrow (Dr TIM's visual aid): a cylindrical shaft and a conical tip, one solid built by
//! CSG.

use glam::DVec3;
use serde::Deserialize;

use super::{Cone, Csg, CsgOperation, Cylinder, GeometryError, Shape};
use crate::keys::{Finite, Positive, Vector};

/// An arrow from `start` to the tip at `end`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Arrow {
    pub start: DVec3,
    pub end: DVec3,
    pub shaft_radius: f64,
    /// The tip's length along the arrow.
    pub tip_length: f64,
    /// The tip cone's half angle, in degrees.
    pub tip_angle_deg: f64,
}

impl Arrow {
    /// Dr TIM's proportions: a shaft radius of 3 % and a tip of 20 % of the length, with a
    /// half angle of 20°.
    pub fn with_default_proportions(start: DVec3, end: DVec3) -> Arrow {
        let length = start.distance(end);
        Arrow {
            start,
            end,
            shaft_radius: 0.03 * length,
            tip_length: 0.2 * length,
            tip_angle_deg: 20.0,
        }
    }

    /// The union of the shaft (up to just inside the tip's base) and the tip.
    pub fn shape(&self) -> Result<Shape, GeometryError> {
        super::check_point("arrow start", self.start)?;
        super::check_point("arrow end", self.end)?;
        let along = self.end - self.start;
        let length = along.length();
        if !(length > 0.0 && self.tip_length < length) {
            return Err(GeometryError::Degenerate(format!(
                "an arrow needs an end away from its start and a tip shorter than the arrow \
                 ({}), got tip length {}",
                length, self.tip_length
            )));
        }
        // The shaft reaches a hundredth of the tip's length into it: faces that only meet
        // would leave slivers of surface where their distances round apart.
        let base = self.end - (0.99 * self.tip_length / length) * along;
        let arrow = Csg::new(
            CsgOperation::Union,
            vec![
                Shape::Cylinder(Cylinder::new(self.start, base, self.shaft_radius)?),
                Shape::Cone(Cone::new(
                    self.end,
                    -along,
                    self.tip_angle_deg,
                    self.tip_length,
                    false,
                )?),
            ],
        )?;
        Ok(Shape::Csg(arrow.called("arrow")))
    }
}

/// `type = "arrow"`: Dr TIM's arrow, a shaft and a conical tip at `end`, of Dr TIM's proportions where not given,
/// from (0, 0, 10) to (1, 0, 10) (Dr TIM's GUI's new arrow) where these are not given.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ArrowKeys {
    start: Option<Vector>,
    end: Option<Vector>,
    shaft_radius: Option<Positive>,
    tip_length: Option<Positive>,
    tip_angle_deg: Option<Finite>,
}

impl ArrowKeys {
    pub fn build(self) -> Result<Shape, GeometryError> {
        let default = Arrow::with_default_proportions(
            self.start.map_or(DVec3::new(0.0, 0.0, 10.0), |s| s.0),
            self.end.map_or(DVec3::new(1.0, 0.0, 10.0), |e| e.0),
        );
        Arrow {
            shaft_radius: self.shaft_radius.map_or(default.shaft_radius, |r| r.0),
            tip_length: self.tip_length.map_or(default.tip_length, |l| l.0),
            tip_angle_deg: self.tip_angle_deg.map_or(default.tip_angle_deg, |a| a.0),
            ..default
        }
        .shape()
    }
}
