//! Disc: the points of a plane within `radius` of `centre`.

use glam::{DMat3, DVec2, DVec3};
use serde::Deserialize;

use super::plane::plane_distance;
use super::{AnalyticShape, GeometryError, Shape};
use crate::keys::{Positive, Vector};
use crate::math::Frame;

#[derive(Debug, Clone, PartialEq)]
pub struct Disc {
    centre: DVec3,
    radius: f64,
    /// w is the unit outward normal; u, v span the disc.
    frame: Frame,
}

impl Disc {
    pub fn new(centre: DVec3, normal: DVec3, radius: f64) -> Result<Disc, GeometryError> {
        super::check_point("disc centre", centre)?;
        let normal = super::check_direction("disc normal", normal)?;
        super::check_positive("disc radius", radius)?;
        Ok(Disc {
            centre,
            radius,
            frame: Frame::from_normal(normal),
        })
    }

    /// The same disc with its frame (and so its surface-coordinate pattern) turned by the
    /// orthogonal matrix `rotation`.
    /// A reflection (det < 0) keeps the frame right-handed: v̂ = n̂ × û.
    pub fn rotated(mut self, rotation: DMat3) -> Disc {
        let (u, w) = (rotation * self.frame.u, rotation * self.frame.w);
        self.frame = Frame {
            u,
            v: w.cross(u),
            w,
        };
        self
    }

    /// The disc moved to `centre` with radius `radius`, its frame kept.
    pub fn placed(self, centre: DVec3, radius: f64) -> Result<Disc, GeometryError> {
        Ok(Disc {
            frame: self.frame,
            ..Disc::new(centre, self.frame.w, radius)?
        })
    }

    pub fn centre(&self) -> DVec3 {
        self.centre
    }

    pub fn radius(&self) -> f64 {
        self.radius
    }
}

impl AnalyticShape for Disc {
    fn intersect(
        &self,
        origin: DVec3,
        direction: DVec3,
        t_min: f64,
        t_max: f64,
    ) -> Option<(f64, u32)> {
        let t = plane_distance(self.centre, self.frame.w, origin, direction)?;
        let inside =
            (origin + t * direction - self.centre).length_squared() <= self.radius * self.radius;
        (t > t_min && t < t_max && inside).then_some((t, 0))
    }

    /// Cartesian coordinates along u and v from the centre.
    fn coordinates(&self, p: DVec3, _part: u32) -> DVec2 {
        let d = p - self.centre;
        DVec2::new(d.dot(self.frame.u), d.dot(self.frame.v))
    }

    /// The point with coordinates `c`; `None` outside the disc.
    fn point_at(&self, c: DVec2) -> Option<DVec3> {
        (c.length_squared() <= self.radius * self.radius)
            .then(|| self.centre + c.x * self.frame.u + c.y * self.frame.v)
    }

    /// w is the unit outward normal; u, v span the disc.
    fn frame(&self, _p: DVec3, _part: u32) -> Frame {
        self.frame
    }

    fn bounds(&self) -> Option<(DVec3, DVec3)> {
        // Extent along each axis: r·sqrt(1 − n_i²).
        let n = self.frame.w;
        let e = self.radius * (DVec3::ONE - n * n).max(DVec3::ZERO).sqrt();
        Some((self.centre - e, self.centre + e))
    }

    fn is_flat(&self) -> bool {
        true
    }

    /// The surface coordinates, which are Cartesian.
    fn plane_coordinates(&self, p: DVec3, part: u32) -> Option<DVec2> {
        Some(self.coordinates(p, part))
    }
}

/// `type = "disc"`: Dr TIM's GUI's new disc (`EditableScaledParametrisedDisc`), centre
/// (0, 0, 10), normal (0, 0, 1), radius 1, where not given.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DiscKeys {
    centre: Option<Vector>,
    normal: Option<Vector>,
    radius: Option<Positive>,
}

impl DiscKeys {
    pub fn build(self) -> Result<Shape, GeometryError> {
        Ok(Shape::Disc(Disc::new(
            self.centre.map_or(DVec3::new(0.0, 0.0, 10.0), |c| c.0),
            self.normal.map_or(DVec3::Z, |n| n.0),
            self.radius.map_or(1.0, |r| r.0),
        )?))
    }
}
