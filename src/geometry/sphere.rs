//! Sphere: |p − centre| = radius.

use glam::{DMat3, DVec2, DVec3};
use serde::Deserialize;

use super::{AnalyticShape, ConvexSolid, GeometryError, Shape, Span};
use crate::keys::{Positive, Vector};
use crate::math::{Frame, circle_crossings, nearest_in};

#[derive(Debug, Clone, PartialEq)]
pub struct Sphere {
    centre: DVec3,
    radius: f64,
    /// The sphere's own x, y (pole) and z (zero longitude) axes as columns, once it has been
    /// rotated (its surface coordinates turn with it); `None`: the world's.
    axes: Option<DMat3>,
}

impl Sphere {
    pub fn new(centre: DVec3, radius: f64) -> Result<Sphere, GeometryError> {
        super::check_point("sphere centre", centre)?;
        super::check_positive("sphere radius", radius)?;
        Ok(Sphere {
            centre,
            radius,
            axes: None,
        })
    }

    pub fn centre(&self) -> DVec3 {
        self.centre
    }

    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// The sphere moved to `centre` with radius `radius`, its axes kept.
    pub fn placed(&self, centre: DVec3, radius: f64) -> Result<Sphere, GeometryError> {
        Ok(Sphere {
            axes: self.axes,
            ..Sphere::new(centre, radius)?
        })
    }

    /// The same sphere with its axes (and so its surface-coordinate pattern) turned by the
    /// orthogonal matrix `rotation`.
    pub fn rotated(mut self, rotation: DMat3) -> Sphere {
        self.axes = Some(rotation * self.axes.unwrap_or(DMat3::IDENTITY));
        self
    }

    fn pole(&self) -> DVec3 {
        self.axes.map_or(DVec3::Y, |a| a.y_axis)
    }
}

impl AnalyticShape for Sphere {
    /// Nearest t in (t_min, t_max) with |o + t d − c| = r.
    fn intersect(
        &self,
        origin: DVec3,
        direction: DVec3,
        t_min: f64,
        t_max: f64,
    ) -> Option<(f64, u32)> {
        let (t0, t1) = circle_crossings(origin - self.centre, direction, self.radius)?;
        nearest_in([t0, t1], t_min, t_max).map(|t| (t, 0))
    }

    fn frame(&self, p: DVec3, _part: u32) -> Frame {
        let w = p - self.centre;
        Frame::from_normal_and_u(w, self.pole().cross(w))
    }

    /// (r φ, r θ): arc lengths along longitude φ (about the pole, y unless rotated) and polar
    /// angle θ (from the pole).
    fn coordinates(&self, p: DVec3, _part: u32) -> DVec2 {
        let mut d = (p - self.centre) / self.radius;
        if let Some(axes) = self.axes {
            d = axes.transpose() * d;
        }
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
        Some(self.centre + self.radius * self.axes.map_or(d, |a| a * d))
    }

    /// (∂p/∂(r φ), ∂p/∂(r θ)) = (sin θ φ̂, θ̂): along the parallel (growing longitude) and the
    /// meridian (away from the pole), in the sphere's axes; `None` at the poles.
    fn coordinate_axes(&self, p: DVec3, _part: u32) -> Option<[DVec3; 2]> {
        let axes = self.axes.unwrap_or(DMat3::IDENTITY);
        let [along_phi, along_theta] =
            unit_sphere_axes(axes.transpose() * (p - self.centre) / self.radius)?;
        Some([axes * along_phi, axes * along_theta])
    }

    fn is_charted(&self) -> bool {
        true
    }

    fn bounds(&self) -> Option<(DVec3, DVec3)> {
        Some((
            self.centre - DVec3::splat(self.radius),
            self.centre + DVec3::splat(self.radius),
        ))
    }

    fn solid(&self) -> Option<&dyn ConvexSolid> {
        Some(self)
    }
}

/// On the unit sphere with the pole along y and longitude φ = atan2(x, z), the point
/// d = (sin θ sin φ, cos θ, sin θ cos φ): its derivatives (∂d/∂φ, ∂d/∂θ) =
/// ((sin θ cos φ, 0, −sin θ sin φ), (cos θ sin φ, −sin θ, cos θ cos φ)), from d itself
/// (sin θ = |(d_x, d_z)|); `None` at the poles, where φ is no coordinate.
pub(super) fn unit_sphere_axes(d: DVec3) -> Option<[DVec3; 2]> {
    let s = DVec2::new(d.x, d.z).length();
    (s > 0.0).then(|| {
        [
            DVec3::new(d.z, 0.0, -d.x),
            DVec3::new(d.y * d.x / s, -s, d.y * d.z / s),
        ]
    })
}

impl ConvexSolid for Sphere {
    fn chord(&self, origin: DVec3, direction: DVec3) -> Option<Span> {
        let (t0, t1) = circle_crossings(origin - self.centre, direction, self.radius)?;
        Some(Span {
            enter: (t0, 0),
            exit: (t1, 0),
        })
    }

    fn contains(&self, p: DVec3) -> bool {
        (p - self.centre).length_squared() <= self.radius * self.radius
    }
}

/// `type = "sphere"`: Dr TIM's GUI's new sphere (`EditableScaledParametrisedSphere`), centre
/// (0, 0, 10) and radius 1, where not given.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SphereKeys {
    centre: Option<Vector>,
    radius: Option<Positive>,
}

impl SphereKeys {
    pub fn build(self) -> Result<Shape, GeometryError> {
        Ok(Shape::Sphere(Sphere::new(
            self.centre.map_or(DVec3::new(0.0, 0.0, 10.0), |c| c.0),
            self.radius.map_or(1.0, |r| r.0),
        )?))
    }
}
