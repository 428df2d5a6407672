//! Paraboloid of revolution: x² + y² = 4 f z in its own coordinates (z along the axis from
//! the vertex, f the focal length, so the focus is at z = f), up to the height H; a closed
//! solid capped by the disc at z = H, or `open` (the curved surface only: a dish).
//!
//! Along a line q + s d re-origined at its point nearest the vertex, the surface is the
//! quadratic a s² + 2 b s + c = 0 with a = d⊥², b = q⊥·d⊥ − 2 f d_z and c = q⊥² − 4 f q_z,
//! whose discriminant b² − a c is computed as 4 f (f d_z² − d_z q⊥·d⊥ + q_z d⊥²) −
//! (q⊥ × d⊥)², the same without the nearly cancelling (q⊥·d⊥)² − q⊥² d⊥².

use glam::{DVec2, DVec3};
use serde::Deserialize;

use super::axial::{Axis, Line};
use super::{AnalyticShape, ConvexSolid, GeometryError, Shape, Span};
use crate::keys::{Finite, Vector};
use crate::math::{Frame, quadratic_roots};

#[derive(Debug, Clone, PartialEq)]
pub struct Paraboloid {
    /// From the vertex, w along the axis into the bowl.
    axis: Axis,
    focal_length: f64,
    height: f64,
    open: bool,
}

impl Paraboloid {
    /// The paraboloid with vertex `vertex`, axis direction `axis` (from the vertex into the
    /// bowl, any length), focal length `focal_length` and height `height` along the axis;
    /// with its cap unless `open`.
    pub fn new(
        vertex: DVec3,
        axis: DVec3,
        focal_length: f64,
        height: f64,
        open: bool,
    ) -> Result<Paraboloid, GeometryError> {
        super::check_point("paraboloid vertex", vertex)?;
        let axis = super::check_direction("paraboloid axis", axis)?;
        super::check_positive("paraboloid focal_length", focal_length)?;
        super::check_positive("paraboloid height", height)?;
        Ok(Paraboloid {
            axis: Axis::new(vertex, axis, None),
            focal_length,
            height,
            open,
        })
    }

    pub fn vertex(&self) -> DVec3 {
        self.axis.origin
    }

    /// Unit vector from the vertex into the bowl.
    pub fn axis(&self) -> DVec3 {
        self.axis.frame.w
    }

    pub fn focal_length(&self) -> f64 {
        self.focal_length
    }

    pub fn height(&self) -> f64 {
        self.height
    }

    /// The rim's radius, (4 f H)^½.
    pub fn rim_radius(&self) -> f64 {
        2.0 * (self.focal_length * self.height).sqrt()
    }

    pub fn is_open(&self) -> bool {
        self.open
    }

    /// "paraboloid", or for the curved surface alone what makes it one.
    pub fn kind(&self) -> &'static str {
        if self.open {
            "paraboloid with open = true"
        } else {
            "paraboloid"
        }
    }

    /// The span (in s) of `line` inside the unbounded solid x² + y² ≤ 4 f z; its finite ends
    /// are on the curved surface (part 0).
    fn inside(&self, line: &Line) -> Option<Span> {
        let (q, d, f) = (line.q, line.d, self.focal_length);
        let (qp, dp) = (q.truncate(), d.truncate());
        let a = dp.length_squared();
        let b = qp.dot(dp) - 2.0 * f * d.z;
        let c = qp.length_squared() - 4.0 * f * q.z;
        if a == 0.0 {
            // Along the axis: c + 2 b s = 0 once; inside beyond it, deeper into the bowl.
            let s = -c / (2.0 * b);
            let span = if d.z > 0.0 {
                Span {
                    enter: (s, 0),
                    exit: (f64::INFINITY, Span::NO_PART),
                }
            } else {
                Span {
                    enter: (f64::NEG_INFINITY, Span::NO_PART),
                    exit: (s, 0),
                }
            };
            return s.is_finite().then_some(span);
        }
        let disc = 4.0 * f * (f * d.z * d.z - d.z * qp.dot(dp) + q.z * a) - qp.perp_dot(dp).powi(2);
        if disc < 0.0 {
            return None;
        }
        let (s0, s1) = quadratic_roots(a, b, c, disc);
        (s0 < s1).then_some(Span {
            enter: (s0, 0),
            exit: (s1, 0),
        })
    }
}

impl AnalyticShape for Paraboloid {
    fn intersect(
        &self,
        origin: DVec3,
        direction: DVec3,
        t_min: f64,
        t_max: f64,
    ) -> Option<(f64, u32)> {
        let line = self.axis.line(origin, direction);
        let inside = self.inside(&line)?;
        line.nearest_hit(inside, None, (self.height, 1), self.open, t_min, t_max)
    }

    /// On the curved surface (part 0): w along (x, y, −2 f) (away from the focus's side),
    /// u along the surface in the direction of increasing x (∂p/∂x), v = w × u. On the cap
    /// (part 1): w = the axis, u and v the disc axes û, v̂ for that normal.
    fn frame(&self, p: DVec3, part: u32) -> Frame {
        if part == 1 {
            return self.axis.frame;
        }
        let c = self.axis.local(p);
        let two_f = 2.0 * self.focal_length;
        Frame::from_normal_and_u(
            self.axis.world_vector(DVec3::new(c.x, c.y, -two_f)),
            self.axis.world_vector(DVec3::new(1.0, 0.0, c.x / two_f)),
        )
    }

    /// (x, y) on both parts: the point's Cartesian coordinates across the axis, along û and
    /// v̂ (the disc axes for a normal along the axis) from the axis.
    fn coordinates(&self, p: DVec3, _part: u32) -> DVec2 {
        self.axis.local(p).truncate()
    }

    /// The point of the curved surface with coordinates `c`; `None` beyond the rim.
    fn point_at(&self, c: DVec2) -> Option<DVec3> {
        let z = c.length_squared() / (4.0 * self.focal_length);
        (z <= self.height).then(|| self.axis.world(c.extend(z)))
    }

    /// (∂p/∂x, ∂p/∂y): (û + x/(2f) axis, v̂ + y/(2f) axis) on the curved surface
    /// (z = (x² + y²)/(4f)), û and v̂ on the cap.
    fn coordinate_axes(&self, p: DVec3, part: u32) -> Option<[DVec3; 2]> {
        let slope = if part == 1 {
            DVec2::ZERO
        } else {
            self.axis.local(p).truncate() / (2.0 * self.focal_length)
        };
        Some([
            self.axis.world_vector(DVec3::new(1.0, 0.0, slope.x)),
            self.axis.world_vector(DVec3::new(0.0, 1.0, slope.y)),
        ])
    }

    fn is_charted(&self) -> bool {
        true
    }

    /// Exact: along each world axis e, the farthest point is on the rim, or where the surface
    /// faces e: with a = e·axis and s = |e across the axis|, e·(p − vertex) = a z + 2 (f z)^½ s
    /// is largest at z = H unless a < 0 and z = f s² / a² < H, where it is f s² / |a|.
    fn bounds(&self) -> Option<(DVec3, DVec3)> {
        let (f, h) = (self.focal_length, self.height);
        let frame = &self.axis.frame;
        let across = (frame.u * frame.u + frame.v * frame.v).sqrt();
        let reach = |a: f64, s: f64| {
            if a < 0.0 && f * s * s < h * a * a {
                f * s * s / -a
            } else {
                h * a + self.rim_radius() * s
            }
        };
        let (mut lo, mut hi) = (self.vertex(), self.vertex());
        for i in 0..3 {
            hi[i] += reach(frame.w[i], across[i]);
            lo[i] -= reach(-frame.w[i], across[i]);
        }
        Some((lo, hi))
    }

    fn solid(&self) -> Option<&dyn ConvexSolid> {
        (!self.open).then_some(self as &dyn ConvexSolid)
    }
}

impl ConvexSolid for Paraboloid {
    /// The span inside the unbounded paraboloid, cut at the cap's plane.
    fn chord(&self, origin: DVec3, direction: DVec3) -> Option<Span> {
        let line = self.axis.line(origin, direction);
        line.cut(self.inside(&line)?, None, Some((self.height, 1)))
    }

    fn contains(&self, p: DVec3) -> bool {
        let c = self.axis.local(p);
        c.z <= self.height && c.truncate().length_squared() <= 4.0 * self.focal_length * c.z
    }
}

/// `type = "paraboloid"`: `open`, the curved surface alone without the cap; Dr TIM's GUI's
/// new paraboloid (`EditableParametrisedParaboloid`: vertex (0, 0, 10), w along (0, 1, 0),
/// w = a u² + b v² with a = b = 1, so f = 1/(4a) = 0.25, height 1, and no cap) where not
/// given.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParaboloidKeys {
    vertex: Option<Vector>,
    axis: Option<Vector>,
    focal_length: Option<Finite>,
    height: Option<Finite>,
    open: Option<bool>,
}

impl ParaboloidKeys {
    pub fn build(self) -> Result<Shape, GeometryError> {
        Ok(Shape::Paraboloid(Paraboloid::new(
            self.vertex.map_or(DVec3::new(0.0, 0.0, 10.0), |v| v.0),
            self.axis.map_or(DVec3::Y, |a| a.0),
            self.focal_length.map_or(0.25, |f| f.0),
            self.height.map_or(1.0, |h| h.0),
            self.open.unwrap_or(true),
        )?))
    }
}
