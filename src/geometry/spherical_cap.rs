//! Spherical cap: the part of a sphere's surface within an angle θ₀ (the half angle) of the
//! direction from the sphere's centre to the cap's centre (the pole), i.e. on the pole's side
//! of the rim's plane. An open surface, not a solid (a solid segment is the intersection of a
//! sphere and the half-space behind a plane).

use glam::{DVec2, DVec3};
use serde::Deserialize;

use super::axial::Axis;
use super::{AnalyticShape, GeometryError, Shape};
use crate::keys::{Finite, Vector};
use crate::math::{Frame, circle_crossings, nearest_in};

#[derive(Debug, Clone, PartialEq)]
pub struct SphericalCap {
    /// From the sphere's centre, w towards the pole.
    axis: Axis,
    radius: f64,
    /// θ₀, and the rim's distance from the centre along the axis (R cos θ₀) and from the
    /// axis (R sin θ₀).
    half_angle: f64,
    rim_height: f64,
    rim_radius: f64,
}

impl SphericalCap {
    /// The cap of the sphere about `sphere_centre` through `cap_centre` (its pole), of half
    /// angle `half_angle_deg` in degrees (0 < θ₀ ≤ 180; 90 is a hemisphere).
    pub fn new(
        sphere_centre: DVec3,
        cap_centre: DVec3,
        half_angle_deg: f64,
    ) -> Result<SphericalCap, GeometryError> {
        if !(half_angle_deg > 0.0 && half_angle_deg <= 180.0) {
            return Err(GeometryError::OutOfRange {
                what: "spherical-cap half_angle_deg",
                range: "greater than 0 and at most 180".into(),
                value: half_angle_deg,
            });
        }
        let (axis, r) = SphericalCap::pole(sphere_centre, cap_centre)?;
        let (sin, cos) = half_angle_deg.to_radians().sin_cos();
        Ok(SphericalCap {
            axis,
            radius: r,
            half_angle: half_angle_deg.to_radians(),
            rim_height: r * cos,
            rim_radius: r * sin,
        })
    }

    /// The cap of the sphere about `sphere_centre` through `cap_centre` whose rim is a
    /// circle of radius `aperture_radius` (at most the sphere's radius), on the pole's side of
    /// the centre: at most a hemisphere.
    pub fn with_aperture_radius(
        sphere_centre: DVec3,
        cap_centre: DVec3,
        aperture_radius: f64,
    ) -> Result<SphericalCap, GeometryError> {
        super::check_positive("spherical-cap aperture_radius", aperture_radius)?;
        let (axis, r) = SphericalCap::pole(sphere_centre, cap_centre)?;
        if aperture_radius > r {
            return Err(GeometryError::OutOfRange {
                what: "spherical-cap aperture_radius",
                range: format!("at most the sphere's radius, |cap_centre − sphere_centre| = {r}"),
                value: aperture_radius,
            });
        }
        let rim_height = ((r - aperture_radius) * (r + aperture_radius)).sqrt();
        Ok(SphericalCap {
            axis,
            radius: r,
            half_angle: aperture_radius.atan2(rim_height),
            rim_height,
            rim_radius: aperture_radius,
        })
    }

    /// The axis from the sphere's centre to the pole, and the sphere's radius.
    fn pole(sphere_centre: DVec3, cap_centre: DVec3) -> Result<(Axis, f64), GeometryError> {
        super::check_point("spherical-cap sphere_centre", sphere_centre)?;
        super::check_point("spherical-cap cap_centre", cap_centre)?;
        let r = (cap_centre - sphere_centre).length();
        if r == 0.0 || !r.is_finite() {
            return Err(GeometryError::Degenerate(
                "spherical-cap cap_centre and sphere_centre coincide (or are too far apart)".into(),
            ));
        }
        let pole = (cap_centre - sphere_centre) / r;
        Ok((Axis::new(sphere_centre, pole, None), r))
    }

    pub fn sphere_centre(&self) -> DVec3 {
        self.axis.origin
    }

    /// The pole, the cap's centre on the sphere.
    pub fn cap_centre(&self) -> DVec3 {
        self.axis.world(DVec3::new(0.0, 0.0, self.radius))
    }

    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// θ₀ in radians.
    pub fn half_angle(&self) -> f64 {
        self.half_angle
    }
}

impl AnalyticShape for SphericalCap {
    /// The sphere's crossings on the pole's side of the rim's plane.
    fn intersect(
        &self,
        origin: DVec3,
        direction: DVec3,
        t_min: f64,
        t_max: f64,
    ) -> Option<(f64, u32)> {
        let offset = origin - self.axis.origin;
        let (t0, t1) = circle_crossings(offset, direction, self.radius)?;
        let pole = self.axis.frame.w;
        let on_cap = |&t: &f64| (offset + t * direction).dot(pole) >= self.rim_height;
        nearest_in([t0, t1].into_iter().filter(on_cap), t_min, t_max).map(|t| (t, 0))
    }

    /// As a sphere's: w away from the centre (the convex side), u = pole × w (around the
    /// pole), v = w × u.
    fn frame(&self, p: DVec3, _part: u32) -> Frame {
        let w = p - self.axis.origin;
        Frame::from_normal_and_u(w, self.axis.frame.w.cross(w))
    }

    /// (R φ, R θ): θ ∈ [0, θ₀] the angle from the pole, φ ∈ (−π, π] the angle around it from
    /// û towards v̂ (the disc axes for a normal along the pole).
    fn coordinates(&self, p: DVec3, _part: u32) -> DVec2 {
        let c = self.axis.local(p);
        let phi = c.y.atan2(c.x);
        let theta = c.truncate().length().atan2(c.z);
        self.radius * DVec2::new(phi, theta)
    }

    /// The point with coordinates `c`; `None` beyond the rim.
    fn point_at(&self, c: DVec2) -> Option<DVec3> {
        let (phi, theta) = (c.x / self.radius, c.y / self.radius);
        if !(0.0..=self.half_angle).contains(&theta) || !phi.is_finite() {
            return None;
        }
        let (s, co) = theta.sin_cos();
        let e = DVec3::new(s * phi.cos(), s * phi.sin(), co);
        Some(self.axis.world(self.radius * e))
    }

    /// (∂p/∂(R φ), ∂p/∂(R θ)): a sphere's, about the cap's axis; `None` at the pole.
    fn coordinate_axes(&self, p: DVec3, _part: u32) -> Option<[DVec3; 2]> {
        // The sphere's (x, pole, z) with longitude atan2(x, z) are the cap's (v̂, axis, û),
        // whose longitude is atan2(v̂, û).
        let e = self.axis.local(p) / self.radius;
        let axes = super::sphere::unit_sphere_axes(DVec3::new(e.y, e.z, e.x))?;
        Some(axes.map(|a| self.axis.world_vector(DVec3::new(a.z, a.x, a.y))))
    }

    fn is_charted(&self) -> bool {
        true
    }

    /// Exact: along each world axis e, the farthest point is the sphere's (centre + R e) if it
    /// is on the cap, and otherwise on the rim.
    fn bounds(&self) -> Option<(DVec3, DVec3)> {
        let f = &self.axis.frame;
        let across = (f.u * f.u + f.v * f.v).sqrt();
        let (r, h) = (self.radius, self.rim_height);
        let reach = |n: f64, s: f64| {
            if r * n >= h {
                r
            } else {
                h * n + self.rim_radius * s
            }
        };
        let (mut lo, mut hi) = (self.axis.origin, self.axis.origin);
        for i in 0..3 {
            hi[i] += reach(f.w[i], across[i]);
            lo[i] -= reach(-f.w[i], across[i]);
        }
        Some((lo, hi))
    }
}

/// `type = "spherical-cap"`: its size by at most one of `aperture_radius` and
/// `half_angle_deg`; Dr TIM's GUI's new spherical cap (`EditableSphericalCap`), sphere centre
/// (0, 0, 15), cap centre (0, 0, 10), aperture radius 1, where not given.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SphericalCapKeys {
    sphere_centre: Option<Vector>,
    cap_centre: Option<Vector>,
    aperture_radius: Option<Finite>,
    half_angle_deg: Option<Finite>,
}

impl SphericalCapKeys {
    pub fn build(self) -> Result<Shape, GeometryError> {
        let centre = self
            .sphere_centre
            .map_or(DVec3::new(0.0, 0.0, 15.0), |c| c.0);
        let cap = self.cap_centre.map_or(DVec3::new(0.0, 0.0, 10.0), |c| c.0);
        Ok(Shape::SphericalCap(
            match (self.aperture_radius, self.half_angle_deg) {
                (r, None) => {
                    SphericalCap::with_aperture_radius(centre, cap, r.map_or(1.0, |r| r.0))?
                }
                (None, Some(angle)) => SphericalCap::new(centre, cap, angle.0)?,
                (Some(_), Some(_)) => {
                    return Err(GeometryError::Degenerate(
                        "a spherical-cap takes one of aperture_radius and half_angle_deg, not both"
                            .into(),
                    ));
                }
            },
        ))
    }
}
