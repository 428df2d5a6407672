//! Cone: the points within the half angle α of the axis from the apex, up to the height H
//! along the axis; a closed solid capped by its base disc, or `open` (the mantle only).
//!
//! In the cone's own coordinates (x, y across the axis, z along it from the apex), along a
//! line q + s d re-origined at its point nearest the apex, the double cone x² + y² = k² z²
//! (k = tan α) is the quadratic a s² + 2 b s + c = 0 with a = d⊥² − k² d_z²,
//! b = q⊥·d⊥ − k² q_z d_z and c = q⊥² − k² q_z². Its discriminant b² − a c is computed as
//! k² |q_z d⊥ − d_z q⊥|² − (q⊥ × d⊥)², the same without the large, nearly cancelling terms.

use glam::{DVec2, DVec3};
use serde::Deserialize;

use super::axial::{Axis, Line};
use super::{AnalyticShape, ConvexSolid, GeometryError, Shape, Span};
use crate::keys::{Finite, Vector};
use crate::math::{Frame, quadratic_roots};

#[derive(Debug, Clone, PartialEq)]
pub struct Cone {
    /// From the apex, w along the axis into the cone.
    axis: Axis,
    /// tan, sin and cos of the half angle.
    tan: f64,
    sin: f64,
    cos: f64,
    height: f64,
    open: bool,
}

impl Cone {
    /// The cone with apex `apex`, axis direction `axis` (from the apex into the cone, any
    /// length), half angle `half_angle_deg` in degrees (0 < α < 90) and height `height`
    /// along the axis; with its base disc unless `open`.
    pub fn new(
        apex: DVec3,
        axis: DVec3,
        half_angle_deg: f64,
        height: f64,
        open: bool,
    ) -> Result<Cone, GeometryError> {
        super::check_point("cone apex", apex)?;
        let axis = super::check_direction("cone axis", axis)?;
        if !(half_angle_deg > 0.0 && half_angle_deg < 90.0) {
            return Err(GeometryError::OutOfRange {
                what: "cone half_angle_deg",
                range: "between 0 and 90 (both excluded)".into(),
                value: half_angle_deg,
            });
        }
        super::check_positive("cone height", height)?;
        let (sin, cos) = half_angle_deg.to_radians().sin_cos();
        Ok(Cone {
            axis: Axis::new(apex, axis, None),
            tan: sin / cos,
            sin,
            cos,
            height,
            open,
        })
    }

    pub fn apex(&self) -> DVec3 {
        self.axis.origin
    }

    /// Unit vector from the apex into the cone.
    pub fn axis(&self) -> DVec3 {
        self.axis.frame.w
    }

    pub fn height(&self) -> f64 {
        self.height
    }

    /// The base's radius, H tan α.
    pub fn base_radius(&self) -> f64 {
        self.height * self.tan
    }

    pub fn is_open(&self) -> bool {
        self.open
    }

    /// "cone", or for the mantle alone what makes it one.
    pub fn kind(&self) -> &'static str {
        if self.open {
            "cone with open = true"
        } else {
            "cone"
        }
    }

    /// The span (in s) of `line` inside the unbounded solid cone x² + y² ≤ k² z², z ≥ 0; its
    /// finite ends are on the mantle (part 0).
    fn nappe(&self, line: &Line) -> Option<Span> {
        let (q, d) = (line.q, line.d);
        let k2 = self.tan * self.tan;
        let (qp, dp) = (q.truncate(), d.truncate());
        let a = dp.length_squared() - k2 * d.z * d.z;
        let b = qp.dot(dp) - k2 * q.z * d.z;
        let c = qp.length_squared() - k2 * q.z * q.z;
        let ahead = |s: f64| Span {
            enter: (s, 0),
            exit: (f64::INFINITY, Span::NO_PART),
        };
        let behind = |s: f64| Span {
            enter: (f64::NEG_INFINITY, Span::NO_PART),
            exit: (s, 0),
        };
        if a == 0.0 {
            // Along a generator: c + 2 b s = 0 once; inside beyond it towards the nappe.
            let s = -c / (2.0 * b);
            return match (s.is_finite(), b < 0.0, d.z > 0.0) {
                (true, true, true) => Some(ahead(s)),
                (true, false, false) => Some(behind(s)),
                _ => None,
            };
        }
        let disc = k2 * (q.z * dp - d.z * qp).length_squared() - qp.perp_dot(dp).powi(2);
        if a > 0.0 && disc < 0.0 {
            return None;
        }
        let (s0, s1) = quadratic_roots(a, b, c, disc);
        if a > 0.0 {
            // Shallower than the cone: inside between the crossings, if on this nappe.
            (s0 < s1 && q.z + 0.5 * (s0 + s1) * d.z >= 0.0).then_some(Span {
                enter: (s0, 0),
                exit: (s1, 0),
            })
        } else if d.z > 0.0 {
            // Steeper: inside this nappe from the second crossing on (or before the first).
            Some(ahead(s1))
        } else {
            Some(behind(s0))
        }
    }
}

impl AnalyticShape for Cone {
    fn intersect(
        &self,
        origin: DVec3,
        direction: DVec3,
        t_min: f64,
        t_max: f64,
    ) -> Option<(f64, u32)> {
        let line = self.axis.line(origin, direction);
        let inside = self.nappe(&line)?;
        line.nearest_hit(inside, None, (self.height, 1), self.open, t_min, t_max)
    }

    /// On the mantle (part 0): w = cos α r̂ − sin α â (r̂ radial, â the axis), u = â × r̂
    /// (around the axis), v = sin α r̂ + cos α â (along the mantle away from the apex). On the
    /// base (part 1): w = â, u and v the disc axes for that normal.
    fn frame(&self, p: DVec3, part: u32) -> Frame {
        if part == 1 {
            return self.axis.frame;
        }
        let r = self
            .axis
            .local(p)
            .truncate()
            .try_normalize()
            .unwrap_or(DVec2::X);
        let (s, c) = (self.sin, self.cos);
        Frame {
            u: self.axis.world_vector(DVec3::new(-r.y, r.x, 0.0)),
            v: self.axis.world_vector(DVec3::new(s * r.x, s * r.y, c)),
            w: self.axis.world_vector(DVec3::new(c * r.x, c * r.y, -s)),
        }
    }

    /// (R φ, z) on both parts: z the distance along the axis from the apex, φ the angle
    /// around it from û towards v̂ (the disc axes for a normal along the axis), R the base's
    /// radius.
    fn coordinates(&self, p: DVec3, _part: u32) -> DVec2 {
        let c = self.axis.local(p);
        DVec2::new(self.base_radius() * c.y.atan2(c.x), c.z)
    }

    /// The mantle point with coordinates `c`; `None` beyond the apex or the base.
    fn point_at(&self, c: DVec2) -> Option<DVec3> {
        let phi = c.x / self.base_radius();
        if !(0.0..=self.height).contains(&c.y) || !phi.is_finite() {
            return None;
        }
        let (s, co) = phi.sin_cos();
        let r = c.y * self.tan;
        Some(self.axis.world(DVec3::new(r * co, r * s, c.y)))
    }

    /// On the mantle, where p = (z tan α cos φ, z tan α sin φ, z): (∂p/∂(R φ), ∂p/∂z) =
    /// ((z/H)(−sin φ, cos φ, 0), (tan α cos φ, tan α sin φ, 1)); `None` at the apex and on the
    /// base, where z is constant.
    fn coordinate_axes(&self, p: DVec3, part: u32) -> Option<[DVec3; 2]> {
        if part != 0 {
            return None;
        }
        let c = self.axis.local(p);
        let r = c.truncate().try_normalize()?;
        Some([
            self.axis
                .world_vector(DVec3::new(-r.y, r.x, 0.0) * (c.z / self.height)),
            self.axis
                .world_vector(DVec3::new(self.tan * r.x, self.tan * r.y, 1.0)),
        ])
    }

    /// The mantle alone has coordinate axes: charted if open.
    fn is_charted(&self) -> bool {
        self.open
    }

    /// The box around the apex and the base disc (the solid is their convex hull).
    fn bounds(&self) -> Option<(DVec3, DVec3)> {
        let r = self.base_radius();
        let (lo, hi) = self.axis.ellipse_bounds(self.height, r, r);
        Some((lo.min(self.apex()), hi.max(self.apex())))
    }

    fn solid(&self) -> Option<&dyn ConvexSolid> {
        (!self.open).then_some(self as &dyn ConvexSolid)
    }
}

impl ConvexSolid for Cone {
    /// The span inside the unbounded cone, cut at the base's plane.
    fn chord(&self, origin: DVec3, direction: DVec3) -> Option<Span> {
        let line = self.axis.line(origin, direction);
        line.cut(self.nappe(&line)?, None, Some((self.height, 1)))
    }

    fn contains(&self, p: DVec3) -> bool {
        let c = self.axis.local(p);
        (0.0..=self.height).contains(&c.z)
            && c.truncate().length_squared() <= self.tan * self.tan * c.z * c.z
    }
}

/// `type = "cone"`: `open`, the mantle alone without the base; Dr TIM's GUI's new cone
/// (`EditableParametrisedCone`), apex (0, 0, 10), axis (0, 0, 1), half angle 45°, height 1,
/// closed, where not given.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ConeKeys {
    apex: Option<Vector>,
    axis: Option<Vector>,
    half_angle_deg: Option<Finite>,
    height: Option<Finite>,
    #[serde(default)]
    open: bool,
}

impl ConeKeys {
    pub fn build(self) -> Result<Shape, GeometryError> {
        Ok(Shape::Cone(Cone::new(
            self.apex.map_or(DVec3::new(0.0, 0.0, 10.0), |a| a.0),
            self.axis.map_or(DVec3::Z, |a| a.0),
            self.half_angle_deg.map_or(45.0, |a| a.0),
            self.height.map_or(1.0, |h| h.0),
            self.open,
        )?))
    }
}
