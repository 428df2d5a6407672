//! Ellipsoid with semi-axes a, b, c along x, y, z: ((x − x₀)/a)² + ((y − y₀)/b)² +
//! ((z − z₀)/c)² = 1. A line is scaled axis by axis into the unit sphere's space (t along it
//! unchanged) and met there as a sphere is.

use glam::{DVec2, DVec3};
use serde::Deserialize;

use super::{AnalyticShape, ConvexSolid, GeometryError, Shape, Span};
use crate::keys::Vector;
use crate::math::{Frame, circle_crossings};

#[derive(Debug, Clone, PartialEq)]
pub struct Ellipsoid {
    centre: DVec3,
    semi_axes: DVec3,
    /// (a b c)^⅓, the radius of the sphere of the same volume: the scale of the surface
    /// coordinates.
    mean_radius: f64,
}

impl Ellipsoid {
    pub fn new(centre: DVec3, semi_axes: DVec3) -> Result<Ellipsoid, GeometryError> {
        super::check_point("ellipsoid centre", centre)?;
        if !(semi_axes.is_finite() && semi_axes.min_element() > 0.0) {
            return Err(GeometryError::NotAllPositive {
                what: "ellipsoid semi_axes",
                value: format!("{semi_axes}"),
            });
        }
        Ok(Ellipsoid {
            centre,
            semi_axes,
            mean_radius: semi_axes.element_product().cbrt(),
        })
    }

    pub fn centre(&self) -> DVec3 {
        self.centre
    }

    pub fn semi_axes(&self) -> DVec3 {
        self.semi_axes
    }

    /// The point `p` in the unit sphere's space.
    fn unit(&self, p: DVec3) -> DVec3 {
        (p - self.centre) / self.semi_axes
    }
}

impl AnalyticShape for Ellipsoid {
    fn intersect(
        &self,
        origin: DVec3,
        direction: DVec3,
        t_min: f64,
        t_max: f64,
    ) -> Option<(f64, u32)> {
        self.chord(origin, direction)?.nearest(t_min, t_max)
    }

    /// w along the gradient ((x − x₀)/a², (y − y₀)/b², (z − z₀)/c²); u along the surface
    /// in the direction of increasing longitude (∂p/∂φ, see the coordinates), as a sphere's
    /// (any direction across w at the poles); v = w × u.
    fn frame(&self, p: DVec3, _part: u32) -> Frame {
        let q = p - self.centre;
        let s2 = self.semi_axes * self.semi_axes;
        Frame::from_normal_and_u(q / s2, DVec3::new(s2.x * q.z, 0.0, -s2.z * q.x))
    }

    /// (ρ φ, ρ θ) with ρ = (a b c)^⅓ and the sphere's angles of the point scaled into the unit
    /// sphere, (x′, y′, z′) = ((x − x₀)/a, (y − y₀)/b, (z − z₀)/c): the longitude
    /// φ = atan2(x′, z′) ∈ (−π, π] about y and the polar angle θ ∈ [0, π] from +y. For
    /// a = b = c = r they are the sphere's.
    fn coordinates(&self, p: DVec3, _part: u32) -> DVec2 {
        let e = self.unit(p);
        let phi = e.x.atan2(e.z);
        let theta = DVec2::new(e.x, e.z).length().atan2(e.y);
        self.mean_radius * DVec2::new(phi, theta)
    }

    /// The point with coordinates `c`; `None` if the polar angle is outside [0, π].
    fn point_at(&self, c: DVec2) -> Option<DVec3> {
        let (phi, theta) = (c.x / self.mean_radius, c.y / self.mean_radius);
        if !(0.0..=std::f64::consts::PI).contains(&theta) || !phi.is_finite() {
            return None;
        }
        let e = DVec3::new(
            theta.sin() * phi.sin(),
            theta.cos(),
            theta.sin() * phi.cos(),
        );
        Some(self.centre + self.semi_axes * e)
    }

    /// The unit sphere's (∂/∂φ, ∂/∂θ) at the scaled point, stretched by the semi-axes and
    /// divided by ρ; `None` at the poles.
    fn coordinate_axes(&self, p: DVec3, _part: u32) -> Option<[DVec3; 2]> {
        let axes = super::sphere::unit_sphere_axes(self.unit(p).normalize())?;
        Some(axes.map(|a| self.semi_axes * a / self.mean_radius))
    }

    fn is_charted(&self) -> bool {
        true
    }

    fn bounds(&self) -> Option<(DVec3, DVec3)> {
        Some((self.centre - self.semi_axes, self.centre + self.semi_axes))
    }

    fn solid(&self) -> Option<&dyn ConvexSolid> {
        Some(self)
    }
}

impl ConvexSolid for Ellipsoid {
    fn chord(&self, origin: DVec3, direction: DVec3) -> Option<Span> {
        let (t0, t1) = circle_crossings(self.unit(origin), direction / self.semi_axes, 1.0)?;
        Some(Span {
            enter: (t0, 0),
            exit: (t1, 0),
        })
    }

    fn contains(&self, p: DVec3) -> bool {
        self.unit(p).length_squared() <= 1.0
    }
}

/// `type = "ellipsoid"`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EllipsoidKeys {
    centre: Vector,
    semi_axes: Vector,
}

impl EllipsoidKeys {
    pub fn build(self) -> Result<Shape, GeometryError> {
        Ok(Shape::Ellipsoid(Ellipsoid::new(
            self.centre.0,
            self.semi_axes.0,
        )?))
    }
}
