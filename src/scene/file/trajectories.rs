//! The `[[ray_trajectory]]` tables: rays traced through the scene and drawn into it.

use std::ops::Range;

use serde::{Deserialize, Deserializer, de};

use super::parts::Spanned;
use super::{SceneFileError, Source};
use crate::keys::{Direction, Positive, Rgb, Vector};
use crate::math::Colour;
use crate::scene::{RayTrajectory, Spread};

/// Most rays one source may start, and most surfaces one ray may meet: far more than a
/// picture can show. The points of all trajectories together are limited by
/// `trajectories::MAX_POINTS` when they are traced.
const MAX_COUNT: u32 = 10_000;

/// A number of rays or interactions: a whole number from 1 to [`MAX_COUNT`].
#[derive(Debug, Clone, Copy)]
struct Count(u32);

impl<'de> Deserialize<'de> for Count {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let n = i64::deserialize(d)?;
        match u32::try_from(n) {
            Ok(n) if (1..=MAX_COUNT).contains(&n) => Ok(Count(n)),
            _ => Err(de::Error::custom(format!(
                "expected a whole number from 1 to {MAX_COUNT}, got {n}"
            ))),
        }
    }
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct TrajectorySection {
    name: Option<String>,
    start: Vector,
    direction: Direction,
    cone_half_angle_deg: Option<Spanned<Positive>>,
    bundle_radius: Option<Spanned<Positive>>,
    waist_radius: Option<Spanned<Positive>>,
    rays: Option<Spanned<Count>>,
    radius: Option<Positive>,
    colour: Option<Rgb>,
    max_interactions: Option<Count>,
    joints: Option<bool>,
}

impl TrajectorySection {
    /// The source, the `number`th (from 1) in the file, whose table is at `span`.
    pub(super) fn build(
        self,
        source: &Source,
        span: Range<usize>,
        number: usize,
    ) -> Result<RayTrajectory, SceneFileError> {
        let at = |s: Option<Range<usize>>, m: String| {
            source.error(
                Some(s.unwrap_or(span.clone())),
                format!("ray_trajectory: {m}"),
            )
        };
        let rays = self.rays.as_ref().map_or(1, |r| r.get_ref().0);
        let spread = match (self.cone_half_angle_deg, self.bundle_radius) {
            (Some(a), Some(_)) => {
                return Err(at(
                    Some(a.span()),
                    "give cone_half_angle_deg (a cone of rays) or bundle_radius (parallel rays), not both".into(),
                ));
            }
            (Some(a), None) if a.get_ref().0 >= 180.0 => {
                return Err(at(
                    Some(a.span()),
                    format!(
                        "cone_half_angle_deg must be below 180, got {}",
                        a.get_ref().0
                    ),
                ));
            }
            (Some(a), None) => match &self.waist_radius {
                Some(w) => Spread::Hyperboloid {
                    half_angle: a.get_ref().0.to_radians(),
                    waist_radius: w.get_ref().0,
                    rays,
                },
                None => Spread::Cone {
                    half_angle: a.get_ref().0.to_radians(),
                    rays,
                },
            },
            (None, _) if self.waist_radius.is_some() => {
                return Err(at(
                    self.waist_radius.as_ref().map(Spanned::span),
                    "waist_radius makes a hyperboloid of skew rays: it needs cone_half_angle_deg, the rays' angle to direction".into(),
                ));
            }
            (None, Some(r)) => Spread::Bundle {
                radius: r.get_ref().0,
                rays,
            },
            (None, None) if rays > 1 => {
                return Err(at(
                    self.rays.map(|r| r.span()),
                    format!(
                        "rays = {rays} needs cone_half_angle_deg (and waist_radius) or bundle_radius to spread them"
                    ),
                ));
            }
            (None, None) => Spread::Single,
        };
        Ok(RayTrajectory {
            name: self
                .name
                .unwrap_or_else(|| format!("ray_trajectory {number}")),
            start: self.start.0,
            direction: self.direction.0,
            spread,
            radius: self.radius.map_or(0.005, |r| r.0),
            colour: self.colour.map_or(Colour::new(1.0, 0.0, 0.0), |c| c.0),
            max_interactions: self.max_interactions.map_or(100, |m| m.0),
            joints: self.joints.unwrap_or(true),
        })
    }
}
