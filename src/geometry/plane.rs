//! Infinite plane through `point` with outward normal `normal`. Unbounded, so it is not put in
//! Embree's BVH: the scene intersects planes directly (see `geometry::SceneGeometry`).

use glam::{DVec2, DVec3};
use serde::Deserialize;

use super::{AnalyticShape, ConvexSolid, GeometryError, Shape, Span};
use crate::keys::Vector;
use crate::math::Frame;

#[derive(Debug, Clone, PartialEq)]
pub struct Plane {
    point: DVec3,
    /// Surface frame: w is the unit outward normal, u and v the in-plane coordinate axes.
    frame: Frame,
}

impl Plane {
    /// A plane whose surface coordinate u runs along the in-plane part of `u_direction`.
    pub fn new(point: DVec3, normal: DVec3, u_direction: DVec3) -> Result<Plane, GeometryError> {
        super::check_point("plane point", point)?;
        let normal = super::check_direction("plane normal", normal)?;
        super::check_across("plane u_direction", u_direction, normal, "the normal")?;
        Ok(Plane {
            point,
            frame: Frame::from_normal_and_u(normal, u_direction),
        })
    }

    pub fn point(&self) -> DVec3 {
        self.point
    }
}

impl AnalyticShape for Plane {
    /// Surface frame: w is the unit outward normal, u and v the in-plane coordinate axes.
    fn frame(&self, _p: DVec3, _part: u32) -> Frame {
        self.frame
    }

    /// The t where the line meets the plane, if in (t_min, t_max).
    #[inline]
    fn intersect(
        &self,
        origin: DVec3,
        direction: DVec3,
        t_min: f64,
        t_max: f64,
    ) -> Option<(f64, u32)> {
        let t = plane_distance(self.point, self.frame.w, origin, direction)?;
        (t > t_min && t < t_max).then_some((t, 0))
    }

    /// In-plane Cartesian coordinates along u and v, measured from `point`.
    fn coordinates(&self, p: DVec3, _part: u32) -> DVec2 {
        let d = p - self.point;
        DVec2::new(d.dot(self.frame.u), d.dot(self.frame.v))
    }

    /// The point with coordinates `c`.
    fn point_at(&self, c: DVec2) -> Option<DVec3> {
        Some(self.point + c.x * self.frame.u + c.y * self.frame.v)
    }

    /// None: a plane is unbounded.
    fn bounds(&self) -> Option<(DVec3, DVec3)> {
        None
    }

    fn is_flat(&self) -> bool {
        true
    }

    /// The surface coordinates, which are Cartesian.
    fn plane_coordinates(&self, p: DVec3, part: u32) -> Option<DVec2> {
        Some(self.coordinates(p, part))
    }

    fn solid(&self) -> Option<&dyn ConvexSolid> {
        Some(self)
    }
}

/// The half-space behind the plane (opposite its normal).
impl ConvexSolid for Plane {
    fn chord(&self, origin: DVec3, direction: DVec3) -> Option<Span> {
        let outwards = direction.dot(self.frame.w);
        match plane_distance(self.point, self.frame.w, origin, direction) {
            Some(t) if outwards > 0.0 => Some(Span {
                enter: (f64::NEG_INFINITY, Span::NO_PART),
                exit: (t, 0),
            }),
            Some(t) => Some(Span {
                enter: (t, 0),
                exit: (f64::INFINITY, Span::NO_PART),
            }),
            None => self.contains(origin).then_some(Span {
                enter: (f64::NEG_INFINITY, Span::NO_PART),
                exit: (f64::INFINITY, Span::NO_PART),
            }),
        }
    }

    fn contains(&self, p: DVec3) -> bool {
        (p - self.point).dot(self.frame.w) <= 0.0
    }
}

/// Distance along the line o + t d to the plane through `point` with normal `n`; `None` when the
/// line is parallel to the plane.
pub fn plane_distance(point: DVec3, n: DVec3, origin: DVec3, direction: DVec3) -> Option<f64> {
    let dn = direction.dot(n);
    if dn == 0.0 {
        return None;
    }
    let t = (point - origin).dot(n) / dn;
    t.is_finite().then_some(t)
}

/// `type = "plane"`: `u_direction` (any tangent when not given) sets the surface coordinates;
/// Dr TIM's GUI's new plane (`EditableParametrisedPlane`), through (0, 0, 10) with normal
/// (0, 0, 1), where not given.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlaneKeys {
    point: Option<Vector>,
    normal: Option<Vector>,
    u_direction: Option<Vector>,
}

impl PlaneKeys {
    pub fn build(self) -> Result<Shape, GeometryError> {
        let point = self.point.map_or(DVec3::new(0.0, 0.0, 10.0), |p| p.0);
        let normal = self.normal.map_or(DVec3::Z, |n| n.0);
        let u = self
            .u_direction
            .map_or_else(|| normal.any_orthogonal_vector(), |u| u.0);
        Ok(Shape::Plane(Plane::new(point, normal, u)?))
    }
}
