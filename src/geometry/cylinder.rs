//! Cylinder from `start` to `end` with end caps (discs) of the same radius.
//!
//! The textbook quadratic for a line and an infinite cylinder loses precision on long, thin
//! cylinders (large |o − start| along the axis, tiny radius): it subtracts nearly equal
//! squares. Here the axial components of the origin offset and the direction are removed first,
//! so the quadratic only sees the perpendicular geometry, and it is solved about the line's
//! closest point to the axis, which keeps precision when the cylinder is seen broadside from afar.

use glam::{DMat3, DVec2, DVec3};
use serde::Deserialize;

use super::{
    AnalyticShape, ConvexSolid, Csg, CsgOperation, EllipticCylinder, GeometryError, Shape, Span,
};
use crate::keys::{Finite, Positive, Vector};
use crate::math::{Frame, circle_crossings, nearest_in};

#[derive(Debug, Clone, PartialEq)]
pub struct Cylinder {
    start: DVec3,
    end: DVec3,
    radius: f64,
    /// Unit vector from start to end.
    axis: DVec3,
    length: f64,
    /// Unit vectors across the axis: the directions of angles 0 and 90° of the surface
    /// coordinates.
    across: (DVec3, DVec3),
}

impl Cylinder {
    pub fn new(start: DVec3, end: DVec3, radius: f64) -> Result<Cylinder, GeometryError> {
        super::check_point("cylinder start", start)?;
        super::check_point("cylinder end", end)?;
        super::check_positive("cylinder radius", radius)?;
        let length = (end - start).length();
        if length == 0.0 || !length.is_finite() {
            return Err(GeometryError::Degenerate(
                "cylinder start and end coincide (or are too far apart)".into(),
            ));
        }
        let axis = (end - start) / length;
        let f = Frame::from_normal(axis);
        Ok(Cylinder {
            start,
            end,
            radius,
            axis,
            length,
            across: (f.u, f.v),
        })
    }

    /// This cylinder (the image of `original` under a map whose orthogonal part is
    /// `rotation`) with `original`'s directions across the axis turned by `rotation`, so its
    /// surface-coordinate pattern turns with it.
    pub fn across_from(mut self, original: &Cylinder, rotation: DMat3) -> Cylinder {
        self.across = (rotation * original.across.0, rotation * original.across.1);
        self
    }

    pub fn start(&self) -> DVec3 {
        self.start
    }

    pub fn end(&self) -> DVec3 {
        self.end
    }

    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// Unit vector from start to end.
    pub fn axis(&self) -> DVec3 {
        self.axis
    }

    /// The part surface point `p` belongs to (whichever it is nearer to): `Ok` with the unit
    /// radial direction on the mantle, `Err` with the cap's outward axis (∓axis) on a cap.
    fn part_at(&self, p: DVec3) -> Result<DVec3, DVec3> {
        let s = (p - self.start).dot(self.axis);
        let radial = (p - self.start) - s * self.axis;
        let to_mantle = (radial.length() - self.radius).abs();
        if to_mantle <= s.abs().min((s - self.length).abs()) {
            Ok(radial.normalize())
        } else if s < 0.5 * self.length {
            Err(-self.axis)
        } else {
            Err(self.axis)
        }
    }
}

impl AnalyticShape for Cylinder {
    fn intersect(
        &self,
        origin: DVec3,
        direction: DVec3,
        t_min: f64,
        t_max: f64,
    ) -> Option<(f64, u32)> {
        let a = self.axis;
        let oc = origin - self.start;
        let (oc_axial, d_axial) = (oc.dot(a), direction.dot(a));
        let oc_perp = oc - oc_axial * a;
        let d_perp = direction - d_axial * a;
        let within = |t: f64| {
            let s = oc_axial + t * d_axial;
            (0.0..=self.length).contains(&s)
        };
        let mantle = circle_crossings(oc_perp, d_perp, self.radius)
            .map_or([f64::NAN; 2], |(t0, t1)| [t0, t1]);
        let mantle = mantle.into_iter().filter(|&t| within(t));
        let caps = [0.0, self.length].into_iter().filter_map(|s| {
            let t = (s - oc_axial) / d_axial;
            let r = oc_perp + t * d_perp;
            (t.is_finite() && r.length_squared() <= self.radius * self.radius).then_some(t)
        });
        nearest_in(mantle.chain(caps), t_min, t_max).map(|t| (t, 0))
    }

    /// Frame at a surface point: on the mantle w is radial, u = axis × w, v = axis; on a cap w
    /// is ∓axis. A point belongs to whichever part it is nearer to.
    fn frame(&self, p: DVec3, _part: u32) -> Frame {
        match self.part_at(p) {
            Ok(w) => Frame {
                u: self.axis.cross(w),
                v: self.axis,
                w,
            },
            Err(n) => Frame::from_normal(n),
        }
    }

    /// The frame's w alone (shading needs no more).
    fn normal(&self, p: DVec3, _part: u32) -> DVec3 {
        self.part_at(p).unwrap_or_else(|n| n.normalize())
    }

    /// (r φ, s): arc length around the axis and distance along it from `start`.
    fn coordinates(&self, p: DVec3, _part: u32) -> DVec2 {
        let (u, v) = self.across;
        let d = p - self.start;
        DVec2::new(self.radius * d.dot(v).atan2(d.dot(u)), d.dot(self.axis))
    }

    /// The mantle point with surface coordinates `c` (inverse of [`Self::coordinates`]);
    /// `None` beyond the ends.
    fn point_at(&self, c: DVec2) -> Option<DVec3> {
        let angle = c.x / self.radius;
        if !(0.0..=self.length).contains(&c.y) || !angle.is_finite() {
            return None;
        }
        let (u, v) = self.across;
        let (s, co) = angle.sin_cos();
        Some(self.start + c.y * self.axis + self.radius * (co * u + s * v))
    }

    fn bounds(&self) -> Option<(DVec3, DVec3)> {
        // Each end disc extends r·sqrt(1 − a_i²) along axis i.
        let a = self.axis;
        let e = self.radius * (DVec3::ONE - a * a).max(DVec3::ZERO).sqrt();
        Some((self.start.min(self.end) - e, self.start.max(self.end) + e))
    }

    fn solid(&self) -> Option<&dyn ConvexSolid> {
        Some(self)
    }
}

impl ConvexSolid for Cylinder {
    /// The stretch inside the infinite cylinder, cut to the slab between the end planes.
    fn chord(&self, origin: DVec3, direction: DVec3) -> Option<Span> {
        let a = self.axis;
        let oc = origin - self.start;
        let (oc_axial, d_axial) = (oc.dot(a), direction.dot(a));
        let oc_perp = oc - oc_axial * a;
        let d_perp = direction - d_axial * a;
        let (t0, t1) = match circle_crossings(oc_perp, d_perp, self.radius) {
            Some(ts) => ts,
            // Parallel to the axis (or as good as): inside the mantle throughout or never.
            None if oc_perp.length_squared() < self.radius * self.radius => {
                (f64::NEG_INFINITY, f64::INFINITY)
            }
            None => return None,
        };
        let (s0, s1) = (
            (0.0 - oc_axial) / d_axial,
            (self.length - oc_axial) / d_axial,
        );
        let slab = if d_axial == 0.0 {
            if !(0.0..=self.length).contains(&oc_axial) {
                return None;
            }
            (f64::NEG_INFINITY, f64::INFINITY)
        } else {
            (s0.min(s1), s0.max(s1))
        };
        let enter = t0.max(slab.0);
        let exit = t1.min(slab.1);
        (enter < exit).then_some(Span {
            enter: (enter, 0),
            exit: (exit, 0),
        })
    }

    fn contains(&self, p: DVec3) -> bool {
        let d = p - self.start;
        let s = d.dot(self.axis);
        (0.0..=self.length).contains(&s)
            && (d - s * self.axis).length_squared() <= self.radius * self.radius
    }
}

/// `type = "cylinder"`: `open`, the mantle alone without the end caps (an [`EllipticCylinder`](super::EllipticCylinder) with equal semi-axes);
/// Dr TIM's GUI's new cylinder (`EditableParametrisedCylinder`, with its end caps), from
/// (−1, 0, 10) to (1, 0, 10) with radius 1, where not given.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CylinderKeys {
    start: Option<Vector>,
    end: Option<Vector>,
    radius: Option<Positive>,
    #[serde(default)]
    open: bool,
}

impl CylinderKeys {
    pub fn build(self) -> Result<Shape, GeometryError> {
        let closed = Cylinder::new(
            self.start.map_or(DVec3::new(-1.0, 0.0, 10.0), |p| p.0),
            self.end.map_or(DVec3::new(1.0, 0.0, 10.0), |p| p.0),
            self.radius.map_or(1.0, |r| r.0),
        )?;
        if !self.open {
            return Ok(Shape::Cylinder(closed));
        }
        Ok(Shape::EllipticCylinder(EllipticCylinder::new(
            closed.start(),
            closed.end(),
            DVec2::splat(closed.radius()),
            None,
            true,
        )?))
    }
}

/// `type = "tube"`: the hollow cylinder between the radii, the outer cylinder less the inner
/// one, whose caps lie in the outer one's planes (the spans of a line through the hole cancel
/// exactly there, so the hole has no cap).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TubeKeys {
    start: Vector,
    end: Vector,
    outer_radius: Finite,
    inner_radius: Finite,
}

impl TubeKeys {
    pub fn build(self) -> Result<Shape, GeometryError> {
        let (outer, inner) = (self.outer_radius.0, self.inner_radius.0);
        super::check_positive("tube outer_radius", outer)?;
        super::check_positive("tube inner_radius", inner)?;
        if inner >= outer {
            return Err(GeometryError::OutOfRange {
                what: "tube inner_radius",
                range: format!("less than outer_radius ({outer})"),
                value: inner,
            });
        }
        let cylinder = |r| Cylinder::new(self.start.0, self.end.0, r).map(Shape::Cylinder);
        let tube = Csg::new(
            CsgOperation::Difference,
            vec![cylinder(outer)?, cylinder(inner)?],
        )?;
        Ok(Shape::Csg(tube.called("tube")))
    }
}
