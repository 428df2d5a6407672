//! Sphere: |p − centre| = radius.

use glam::{DVec2, DVec3};

use super::{AnalyticShape, GeometryError};
use crate::math::{Frame, circle_crossings, nearest_in};

#[derive(Debug, Clone, PartialEq)]
pub struct Sphere {
    centre: DVec3,
    radius: f64,
}

impl Sphere {
    pub fn new(centre: DVec3, radius: f64) -> Result<Sphere, GeometryError> {
        super::check_point("sphere centre", centre)?;
        super::check_positive("sphere radius", radius)?;
        Ok(Sphere { centre, radius })
    }

    pub fn centre(&self) -> DVec3 {
        self.centre
    }

    pub fn radius(&self) -> f64 {
        self.radius
    }
}

impl AnalyticShape for Sphere {
    /// Nearest t in (t_min, t_max) with |o + t d − c| = r.
    fn intersect(&self, origin: DVec3, direction: DVec3, t_min: f64, t_max: f64) -> Option<f64> {
        let (t0, t1) = circle_crossings(origin - self.centre, direction, self.radius)?;
        nearest_in([t0, t1], t_min, t_max)
    }

    fn frame(&self, p: DVec3) -> Frame {
        let w = p - self.centre;
        Frame::from_normal_and_u(w, DVec3::Y.cross(w))
    }

    /// (r φ, r θ): arc lengths along longitude φ (about y) and polar angle θ (from +y).
    fn coordinates(&self, p: DVec3) -> DVec2 {
        let d = (p - self.centre) / self.radius;
        let phi = d.x.atan2(d.z);
        let theta = d.y.clamp(-1.0, 1.0).acos();
        self.radius * DVec2::new(phi, theta)
    }

    /// The point with surface coordinates `c` (inverse of [`Self::coordinates`]); `None` if
    /// the polar angle is outside [0, π].
    fn point_at(&self, c: DVec2) -> Option<DVec3> {
        let (phi, theta) = (c.x / self.radius, c.y / self.radius);
        if !(0.0..=std::f64::consts::PI).contains(&theta) || !phi.is_finite() {
            return None;
        }
        let d = DVec3::new(
            theta.sin() * phi.sin(),
            theta.cos(),
            theta.sin() * phi.cos(),
        );
        Some(self.centre + self.radius * d)
    }

    fn bounds(&self) -> Option<(DVec3, DVec3)> {
        Some((
            self.centre - DVec3::splat(self.radius),
            self.centre + DVec3::splat(self.radius),
        ))
    }
}
