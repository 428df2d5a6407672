//! Elliptic cylinder from `start` to `end`: (x/a)² + (y/b)² = 1 in its own coordinates (x
//! along the direction of the semi-axis a across the axis, y along the axis × that, z along
//! the axis from `start`), for 0 ≤ z ≤ L; a closed solid capped by two elliptic discs, or
//! `open` (the mantle only). With a = b it is a circular cylinder: the open one of scene files.
//!
//! A line is scaled across the axis into the unit circle's space (t along it unchanged) and
//! met there as a cylinder is.

use glam::{DVec2, DVec3};
use serde::Deserialize;

use super::axial::{Axis, Line};
use super::{AnalyticShape, ConvexSolid, GeometryError, Shape, Span};
use crate::keys::{Vector, Vector2};
use crate::math::{Frame, circle_crossings};

#[derive(Debug, Clone, PartialEq)]
pub struct EllipticCylinder {
    /// From `start`, w along the axis to `end`, u along the semi-axis a.
    axis: Axis,
    length: f64,
    semi_axes: DVec2,
    open: bool,
}

impl EllipticCylinder {
    /// The elliptic cylinder from `start` to `end` with semi-axes `semi_axes` = (a, b): a
    /// along the part of `a_direction` across the axis, or without it along the first of the
    /// disc axes for a normal along the axis (as a cylinder's angle 0); with its end caps
    /// unless `open`.
    pub fn new(
        start: DVec3,
        end: DVec3,
        semi_axes: DVec2,
        a_direction: Option<DVec3>,
        open: bool,
    ) -> Result<EllipticCylinder, GeometryError> {
        super::check_point("elliptic-cylinder start", start)?;
        super::check_point("elliptic-cylinder end", end)?;
        if !(semi_axes.is_finite() && semi_axes.min_element() > 0.0) {
            return Err(GeometryError::NotAllPositive {
                what: "elliptic-cylinder semi_axes",
                value: format!("{semi_axes}"),
            });
        }
        let length = (end - start).length();
        if length == 0.0 || !length.is_finite() {
            return Err(GeometryError::Degenerate(
                "elliptic-cylinder start and end coincide (or are too far apart)".into(),
            ));
        }
        let axis = (end - start) / length;
        if let Some(a) = a_direction {
            super::check_across("elliptic-cylinder a_direction", a, axis, "the axis")?;
        }
        Ok(EllipticCylinder {
            axis: Axis::new(start, axis, a_direction),
            length,
            semi_axes,
            open,
        })
    }

    pub fn start(&self) -> DVec3 {
        self.axis.origin
    }

    /// Unit vector from start to end.
    pub fn axis(&self) -> DVec3 {
        self.axis.frame.w
    }

    /// Unit vector along the semi-axis a.
    pub fn a_direction(&self) -> DVec3 {
        self.axis.frame.u
    }

    pub fn length(&self) -> f64 {
        self.length
    }

    pub fn semi_axes(&self) -> DVec2 {
        self.semi_axes
    }

    pub fn is_open(&self) -> bool {
        self.open
    }

    /// "elliptic-cylinder", or for the mantle alone what makes it one.
    pub fn kind(&self) -> &'static str {
        match (self.open, self.semi_axes.x == self.semi_axes.y) {
            (true, true) => "cylinder with open = true",
            (true, false) => "elliptic-cylinder with open = true",
            (false, _) => "elliptic-cylinder",
        }
    }

    /// The span (in s) of `line` inside the unbounded elliptic cylinder; its finite ends are
    /// on the mantle (part 0).
    fn inside(&self, line: &Line) -> Option<Span> {
        let scale = DVec3::new(1.0 / self.semi_axes.x, 1.0 / self.semi_axes.y, 0.0);
        let q = line.q * scale;
        Some(match circle_crossings(q, line.d * scale, 1.0) {
            Some((s0, s1)) => Span {
                enter: (s0, 0),
                exit: (s1, 0),
            },
            // Parallel to the axis: inside throughout or never.
            None if q.length_squared() < 1.0 => Span {
                enter: (f64::NEG_INFINITY, Span::NO_PART),
                exit: (f64::INFINITY, Span::NO_PART),
            },
            None => return None,
        })
    }
}

impl AnalyticShape for EllipticCylinder {
    fn intersect(
        &self,
        origin: DVec3,
        direction: DVec3,
        t_min: f64,
        t_max: f64,
    ) -> Option<(f64, u32)> {
        let line = self.axis.line(origin, direction);
        let inside = self.inside(&line)?;
        line.nearest_hit(
            inside,
            Some((0.0, 1)),
            (self.length, 2),
            self.open,
            t_min,
            t_max,
        )
    }

    /// On the mantle (part 0): w along the gradient (x/a², y/b²), u = axis × w (around the
    /// axis), v = the axis. On the cap at `start` (part 1): w = −axis, u = û, v = −v̂; on the
    /// cap at `end` (part 2): w = axis, u = û, v = v̂ (û along a, v̂ = axis × û).
    fn frame(&self, p: DVec3, part: u32) -> Frame {
        let f = self.axis.frame;
        match part {
            1 => Frame {
                u: f.u,
                v: -f.v,
                w: -f.w,
            },
            2 => f,
            _ => {
                let c = self.axis.local(p);
                let s2 = self.semi_axes * self.semi_axes;
                let n = (c.truncate() / s2).try_normalize().unwrap_or(DVec2::X);
                Frame {
                    u: self.axis.world_vector(DVec3::new(-n.y, n.x, 0.0)),
                    v: f.w,
                    w: self.axis.world_vector(n.extend(0.0)),
                }
            }
        }
    }

    /// (ρ φ, z) on every part: z the distance along the axis from `start`, φ =
    /// atan2(y/b, x/a) ∈ (−π, π] the ellipse's parametric angle (the point is
    /// (a cos φ, b sin φ) across the axis), ρ = (a b)^½, the radius of the circle of the same
    /// area (for a = b = r the cylinder's r φ).
    fn coordinates(&self, p: DVec3, _part: u32) -> DVec2 {
        let c = self.axis.local(p);
        let (a, b) = (self.semi_axes.x, self.semi_axes.y);
        DVec2::new((a * b).sqrt() * (c.y / b).atan2(c.x / a), c.z)
    }

    /// The mantle point with coordinates `c`; `None` beyond the ends.
    fn point_at(&self, c: DVec2) -> Option<DVec3> {
        let (a, b) = (self.semi_axes.x, self.semi_axes.y);
        let phi = c.x / (a * b).sqrt();
        if !(0.0..=self.length).contains(&c.y) || !phi.is_finite() {
            return None;
        }
        let (s, co) = phi.sin_cos();
        Some(self.axis.world(DVec3::new(a * co, b * s, c.y)))
    }

    /// On the mantle (∂p/∂(ρ φ), ∂p/∂z) = ((−a sin φ, b cos φ, 0)/ρ, axis); `None` on the caps,
    /// where z is constant.
    fn coordinate_axes(&self, p: DVec3, part: u32) -> Option<[DVec3; 2]> {
        if part != 0 {
            return None;
        }
        let (a, b) = (self.semi_axes.x, self.semi_axes.y);
        let c = self.axis.local(p);
        let q = DVec2::new(c.x / a, c.y / b).try_normalize()?;
        let around = DVec3::new(-a * q.y, b * q.x, 0.0) / (a * b).sqrt();
        Some([self.axis.world_vector(around), self.axis.frame.w])
    }

    /// The mantle alone has coordinate axes: charted if open.
    fn is_charted(&self) -> bool {
        self.open
    }

    /// The box around the two end ellipses.
    fn bounds(&self) -> Option<(DVec3, DVec3)> {
        let (a, b) = (self.semi_axes.x, self.semi_axes.y);
        let (lo0, hi0) = self.axis.ellipse_bounds(0.0, a, b);
        let (lo1, hi1) = self.axis.ellipse_bounds(self.length, a, b);
        Some((lo0.min(lo1), hi0.max(hi1)))
    }

    fn solid(&self) -> Option<&dyn ConvexSolid> {
        (!self.open).then_some(self as &dyn ConvexSolid)
    }
}

impl ConvexSolid for EllipticCylinder {
    /// The span inside the unbounded elliptic cylinder, cut at the end planes.
    fn chord(&self, origin: DVec3, direction: DVec3) -> Option<Span> {
        let line = self.axis.line(origin, direction);
        line.cut(self.inside(&line)?, Some((0.0, 1)), Some((self.length, 2)))
    }

    fn contains(&self, p: DVec3) -> bool {
        let c = self.axis.local(p);
        (0.0..=self.length).contains(&c.z)
            && (c.truncate() / self.semi_axes).length_squared() <= 1.0
    }
}

/// `type = "elliptic-cylinder"`: `open`, the mantle alone without the end caps.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EllipticCylinderKeys {
    start: Vector,
    end: Vector,
    semi_axes: Vector2,
    a_direction: Option<Vector>,
    #[serde(default)]
    open: bool,
}

impl EllipticCylinderKeys {
    pub fn build(self) -> Result<Shape, GeometryError> {
        Ok(Shape::EllipticCylinder(EllipticCylinder::new(
            self.start.0,
            self.end.0,
            self.semi_axes.0,
            self.a_direction.map(|a| a.0),
            self.open,
        )?))
    }
}
