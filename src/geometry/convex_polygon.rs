//! Convex polygon (Dr TIM's `ParametrisedConvexPolygon`): a flat, open polygon given by its
//! vertices in order, counter-clockwise seen from the outward side.

use glam::{DVec2, DVec3};
use serde::Deserialize;

use super::plane::plane_distance;
use super::{AnalyticShape, GeometryError, Shape};
use crate::keys::Vector;
use crate::math::Frame;

#[derive(Debug, Clone, PartialEq)]
pub struct ConvexPolygon {
    vertices: Vec<DVec3>,
    /// w the outward normal, u along the first edge.
    frame: Frame,
}

impl ConvexPolygon {
    /// The polygon with these vertices (at least three, coplanar to 1e-9 of the polygon's size,
    /// no two in a row the same, and turning the same way at every vertex, once round).
    pub fn new(vertices: Vec<DVec3>) -> Result<ConvexPolygon, GeometryError> {
        let n = vertices.len();
        if n < 3 {
            return Err(GeometryError::Degenerate(format!(
                "a convex polygon needs at least 3 vertices, got {n}"
            )));
        }
        for &v in &vertices {
            super::check_point("convex polygon vertex", v)?;
        }
        let next = |i: usize| vertices[(i + 1) % n];
        let (lo, hi) = super::point_bounds(&vertices);
        let size = (hi - lo).length();
        if let Some(i) = (0..n).find(|&i| next(i).distance(vertices[i]) <= 1e-12 * size) {
            return Err(GeometryError::Degenerate(format!(
                "convex polygon vertices {i} and {} (counting from 0) coincide",
                (i + 1) % n
            )));
        }
        // Newell's normal: twice the vector area, along the normal the vertex order gives.
        let area: DVec3 = (0..n)
            .map(|i| (vertices[i] - vertices[0]).cross(next(i) - vertices[0]))
            .sum();
        if area.length() <= 1e-12 * size * size || !area.is_finite() {
            return Err(GeometryError::Degenerate(
                "the convex polygon's vertices are collinear (it has no area)".into(),
            ));
        }
        let normal = area.normalize();
        let centroid = vertices.iter().sum::<DVec3>() / n as f64;
        for (i, &v) in vertices.iter().enumerate() {
            let off = (v - centroid).dot(normal);
            if off.abs() > 1e-9 * size {
                return Err(GeometryError::Degenerate(format!(
                    "convex polygon vertex {i} (counting from 0) is {:.3e} off the plane of \
                     the others: the vertices must be coplanar",
                    off.abs()
                )));
            }
        }
        let mut turning = 0.0;
        for (i, &vertex) in vertices.iter().enumerate() {
            let (e1, e2) = (next(i) - vertex, next(i + 1) - next(i));
            let turn = e1.cross(e2).dot(normal).atan2(e1.dot(e2));
            if turn < -1e-9 {
                return Err(GeometryError::Degenerate(format!(
                    "the convex polygon is not convex: it turns the other way at vertex {} \
                     (counting from 0)",
                    (i + 1) % n
                )));
            }
            turning += turn;
        }
        if (turning - std::f64::consts::TAU).abs() > 1e-6 {
            return Err(GeometryError::Degenerate(
                "the convex polygon is not convex: its edges cross (they wind round more than \
                 once)"
                    .into(),
            ));
        }
        let frame = Frame::from_normal_and_u(normal, vertices[1] - vertices[0]);
        Ok(ConvexPolygon { vertices, frame })
    }

    pub fn vertices(&self) -> &[DVec3] {
        &self.vertices
    }

    /// Whether point `p` of the polygon's plane is inside it (or on its edges).
    fn inside(&self, p: DVec3) -> bool {
        let n = self.vertices.len();
        (0..n).all(|i| {
            let (a, b) = (self.vertices[i], self.vertices[(i + 1) % n]);
            (b - a).cross(p - a).dot(self.frame.w) >= 0.0
        })
    }
}

impl AnalyticShape for ConvexPolygon {
    fn intersect(
        &self,
        origin: DVec3,
        direction: DVec3,
        t_min: f64,
        t_max: f64,
    ) -> Option<(f64, u32)> {
        let t = plane_distance(self.vertices[0], self.frame.w, origin, direction)?;
        (t > t_min && t < t_max && self.inside(origin + t * direction)).then_some((t, 0))
    }

    /// w the outward normal (by the vertex order), u along the first edge (vertex 0 to 1).
    fn frame(&self, _p: DVec3, _part: u32) -> Frame {
        self.frame
    }

    /// Cartesian coordinates along u and v from vertex 0.
    fn coordinates(&self, p: DVec3, _part: u32) -> DVec2 {
        let d = p - self.vertices[0];
        DVec2::new(d.dot(self.frame.u), d.dot(self.frame.v))
    }

    /// The point with coordinates `c`; `None` outside the polygon.
    fn point_at(&self, c: DVec2) -> Option<DVec3> {
        let p = self.vertices[0] + c.x * self.frame.u + c.y * self.frame.v;
        self.inside(p).then_some(p)
    }

    fn is_flat(&self) -> bool {
        true
    }

    /// The surface coordinates, which are Cartesian.
    fn plane_coordinates(&self, p: DVec3, part: u32) -> Option<DVec2> {
        Some(self.coordinates(p, part))
    }

    fn bounds(&self) -> Option<(DVec3, DVec3)> {
        Some(super::point_bounds(&self.vertices))
    }
}

/// `type = "convex-polygon"`: Dr TIM's `EditableParametrisedConvexPolygon(parent, studio)`,
/// the square with corners (±1, ±1, 10) and normal (0, 0, 1), where not given (its corners in
/// the order that gives that normal).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ConvexPolygonKeys {
    vertices: Option<Vec<Vector>>,
}

impl ConvexPolygonKeys {
    pub fn build(self) -> Result<Shape, GeometryError> {
        let vertices = match self.vertices {
            Some(v) => v.into_iter().map(|v| v.0).collect(),
            None => [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
                .map(|(x, y)| DVec3::new(x, y, 10.0))
                .to_vec(),
        };
        Ok(Shape::ConvexPolygon(ConvexPolygon::new(vertices)?))
    }
}
