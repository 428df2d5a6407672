//! Parallelogram: corner + α span_u + β span_v with α, β ∈ [0, 1].

use glam::{DVec2, DVec3};
use serde::Deserialize;

use super::plane::plane_distance;
use super::{AnalyticShape, GeometryError, Shape};
use crate::keys::Vector;
use crate::math::Frame;

#[derive(Debug, Clone, PartialEq)]
pub struct Parallelogram {
    corner: DVec3,
    span_u: DVec3,
    span_v: DVec3,
    /// w = span_u × span_v normalised (the outward side), u along span_u.
    frame: Frame,
}

impl Parallelogram {
    pub fn new(
        corner: DVec3,
        span_u: DVec3,
        span_v: DVec3,
    ) -> Result<Parallelogram, GeometryError> {
        super::check_point("parallelogram corner", corner)?;
        super::check_point("parallelogram span vector", span_u)?;
        super::check_point("parallelogram span vector", span_v)?;
        let normal = span_u.cross(span_v);
        if normal.length() <= 1e-12 * span_u.length() * span_v.length() || !normal.is_finite() {
            return Err(GeometryError::Degenerate(
                "parallelogram span vectors are zero or parallel".into(),
            ));
        }
        Ok(Parallelogram {
            corner,
            span_u,
            span_v,
            frame: Frame::from_normal_and_u(normal, span_u),
        })
    }

    /// (α, β) with p = corner + α span_u + β span_v, for p in the plane.
    fn span_coordinates(&self, p: DVec3) -> DVec2 {
        let d = p - self.corner;
        let (uu, uv, vv) = (
            self.span_u.length_squared(),
            self.span_u.dot(self.span_v),
            self.span_v.length_squared(),
        );
        let (du, dv) = (d.dot(self.span_u), d.dot(self.span_v));
        let det = uu * vv - uv * uv;
        DVec2::new((du * vv - dv * uv) / det, (dv * uu - du * uv) / det)
    }

    pub fn corner(&self) -> DVec3 {
        self.corner
    }

    pub fn span_u(&self) -> DVec3 {
        self.span_u
    }

    pub fn span_v(&self) -> DVec3 {
        self.span_v
    }
}

impl AnalyticShape for Parallelogram {
    fn intersect(
        &self,
        origin: DVec3,
        direction: DVec3,
        t_min: f64,
        t_max: f64,
    ) -> Option<(f64, u32)> {
        let t = plane_distance(self.corner, self.frame.w, origin, direction)?;
        if !(t > t_min && t < t_max) {
            return None;
        }
        let ab = self.span_coordinates(origin + t * direction);
        ((0.0..=1.0).contains(&ab.x) && (0.0..=1.0).contains(&ab.y)).then_some((t, 0))
    }

    /// Coordinates along the span vectors in units of length: (α |span_u|, β |span_v|).
    fn coordinates(&self, p: DVec3, _part: u32) -> DVec2 {
        self.span_coordinates(p) * DVec2::new(self.span_u.length(), self.span_v.length())
    }

    /// The point with coordinates `c` (inverse of [`Self::coordinates`]); `None` outside.
    fn point_at(&self, c: DVec2) -> Option<DVec3> {
        let ab = c / DVec2::new(self.span_u.length(), self.span_v.length());
        ((0.0..=1.0).contains(&ab.x) && (0.0..=1.0).contains(&ab.y))
            .then(|| self.corner + ab.x * self.span_u + ab.y * self.span_v)
    }

    fn is_flat(&self) -> bool {
        true
    }

    /// Cartesian coordinates along the frame's u and v from the corner.
    fn plane_coordinates(&self, p: DVec3, _part: u32) -> Option<DVec2> {
        let d = p - self.corner;
        Some(DVec2::new(d.dot(self.frame.u), d.dot(self.frame.v)))
    }

    /// w = span_u × span_v normalised (the outward side), u along span_u.
    fn frame(&self, _p: DVec3, _part: u32) -> Frame {
        self.frame
    }

    fn bounds(&self) -> Option<(DVec3, DVec3)> {
        let corners = [
            self.corner,
            self.corner + self.span_u,
            self.corner + self.span_v,
            self.corner + self.span_u + self.span_v,
        ];
        let lo = corners.iter().fold(DVec3::INFINITY, |a, &b| a.min(b));
        let hi = corners.iter().fold(DVec3::NEG_INFINITY, |a, &b| a.max(b));
        Some((lo, hi))
    }
}

/// `type = "parallelogram"`: Dr TIM's GUI's new rectangle
/// (`EditableScaledParametrisedCentredParallelogram`: centre (0, 0, 10), width (3, 0, 0),
/// height (0, 2, 0)) where not given: corner (−1.5, −1, 10), spans (3, 0, 0) and (0, 2, 0).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParallelogramKeys {
    corner: Option<Vector>,
    span_u: Option<Vector>,
    span_v: Option<Vector>,
}

impl ParallelogramKeys {
    pub fn build(self) -> Result<Shape, GeometryError> {
        Ok(Shape::Parallelogram(Parallelogram::new(
            self.corner.map_or(DVec3::new(-1.5, -1.0, 10.0), |c| c.0),
            self.span_u.map_or(DVec3::new(3.0, 0.0, 0.0), |s| s.0),
            self.span_v.map_or(DVec3::new(0.0, 2.0, 0.0), |s| s.0),
        )?))
    }
}
