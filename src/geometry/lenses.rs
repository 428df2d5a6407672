//! Lens-shaped solids built by constructive solid geometry: thick spherical lenses (biconvex,
//! plano-convex, meniscus, ...) and Fresnel lenses with spherical zones.
//!
//! Sign convention (the usual one of lens design): the axis points from the front vertex to
//! the back vertex, the way light goes through; a surface's radius of curvature is positive
//! when its centre of curvature lies behind its vertex (+axis side). A biconvex lens has
//! R₁ > 0 and R₂ < 0; `None` is a flat surface.

use glam::DVec3;
use serde::Deserialize;

use super::{Csg, CsgOperation, Cylinder, GeometryError, Plane, Shape, Sphere};
use crate::keys::{Finite, Positive, Vector};

/// A thick lens with spherical (or flat) surfaces.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SphericalLens {
    /// The midpoint between the two vertices.
    pub centre: DVec3,
    /// From the front vertex to the back vertex (normalised here).
    pub axis: DVec3,
    /// R₁ of the front surface; `None`: flat.
    pub front_radius: Option<f64>,
    /// R₂ of the back surface; `None`: flat.
    pub back_radius: Option<f64>,
    /// The distance between the vertices.
    pub thickness: f64,
    /// The radius of the cylindrical rim.
    pub aperture_radius: f64,
}

/// How far a surface of radius `r` (signed, `None` flat) lies behind its vertex at distance
/// `h` from the axis.
fn sag(r: Option<f64>, h: f64) -> f64 {
    r.map_or(0.0, |r| r - r.signum() * (r * r - h * h).sqrt())
}

/// The solid on the lens's side of a surface with vertex `vertex` and radius `r` (`None`
/// flat), the lens lying on the `inwards` side of the vertex.
fn surface_side(
    vertex: DVec3,
    inwards: DVec3,
    axis: DVec3,
    r: Option<f64>,
) -> Result<Shape, GeometryError> {
    let Some(r) = r else {
        return Ok(Shape::Plane(Plane::new(
            vertex,
            -inwards,
            axis.any_orthogonal_vector(),
        )?));
    };
    let sphere = Shape::Sphere(Sphere::new(vertex + r * axis, r.abs())?);
    // The lens is inside the sphere when the centre of curvature is on the lens's side.
    if (r * axis).dot(inwards) > 0.0 {
        Ok(sphere)
    } else {
        Ok(Shape::Csg(Csg::new(CsgOperation::Inverse, vec![sphere])?))
    }
}

impl SphericalLens {
    /// The lens as the intersection of its two surfaces' sides and its rim.
    pub fn shape(&self) -> Result<Shape, GeometryError> {
        super::check_point("lens centre", self.centre)?;
        let axis = super::check_direction("lens axis", self.axis)?;
        super::check_positive("lens thickness", self.thickness)?;
        super::check_positive("lens aperture radius", self.aperture_radius)?;
        let a = self.aperture_radius;
        for (what, r) in [
            ("front radius of curvature", self.front_radius),
            ("back radius of curvature", self.back_radius),
        ] {
            if let Some(r) = r
                && !(r.is_finite() && r.abs() >= a)
            {
                return Err(GeometryError::Degenerate(format!(
                    "the lens's {what} must be finite and at least the aperture radius {a} in \
                     size, got {r}"
                )));
            }
        }
        // The axial thickness changes monotonically from the centre to the rim.
        let edge = self.thickness - sag(self.front_radius, a) + sag(self.back_radius, a);
        if edge <= 0.0 {
            return Err(GeometryError::Degenerate(format!(
                "the lens's surfaces meet inside its aperture: its thickness at the rim would \
                 be {edge}"
            )));
        }
        let half = 0.5 * self.thickness;
        let (front, back) = (self.centre - half * axis, self.centre + half * axis);
        // The rim reaches just beyond the lens's extent along the axis, no further: beyond a
        // concave surface's rim its side is all space but a sliver outside the sphere, which
        // begins √(R² − a²) beyond the rim's plane; the margin stays below half of that.
        let margin = |r: Option<f64>, concave: bool| match r {
            Some(r) if concave => (0.01 * a).min(0.5 * (r * r - a * a).max(0.0).sqrt()),
            _ => 0.01 * a,
        };
        let (f, b) = (self.front_radius, self.back_radius);
        let (first, last) = (
            front + (sag(f, a).min(0.0) - margin(f, f.is_some_and(|r| r < 0.0))) * axis,
            back + (sag(b, a).max(0.0) + margin(b, b.is_some_and(|r| r > 0.0))) * axis,
        );
        let rim = Cylinder::new(first, last, a)?;
        let lens = Csg::new(
            CsgOperation::Intersection,
            vec![
                surface_side(front, axis, axis, self.front_radius)?,
                surface_side(back, -axis, axis, self.back_radius)?,
                Shape::Cylinder(rim),
            ],
        )?;
        Ok(Shape::Csg(lens.called("spherical-lens")))
    }
}

/// The most zones a Fresnel lens may have.
pub const MAX_FRESNEL_ZONES: u32 = 1000;

/// A plano-convex Fresnel lens: a flat plate whose front carries `zones` rings of equal width,
/// each with the slope of a plano-convex lens of radius of curvature R at the same distance
/// from the axis, but only as high as the step it ends in (so the lens stays thin).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FresnelLens {
    /// The centre of the plate (midway between its faces), on the axis.
    pub centre: DVec3,
    /// From the zoned front to the flat back (normalised here).
    pub axis: DVec3,
    /// R of the convex zones (> 0).
    pub radius_of_curvature: f64,
    pub aperture_radius: f64,
    pub zones: u32,
    /// The thickness of the plate under the zones.
    pub thickness: f64,
}

impl FresnelLens {
    /// The union of the plate and the zones; zone k lies between radii k a / N and
    /// (k + 1) a / N, under the sphere of radius R whose surface meets the plate's front at
    /// the zone's outer edge.
    pub fn shape(&self) -> Result<Shape, GeometryError> {
        super::check_point("lens centre", self.centre)?;
        let axis = super::check_direction("lens axis", self.axis)?;
        super::check_positive("lens thickness", self.thickness)?;
        super::check_positive("lens aperture radius", self.aperture_radius)?;
        let (r, a, n) = (self.radius_of_curvature, self.aperture_radius, self.zones);
        if !(r.is_finite() && r >= a) {
            return Err(GeometryError::Degenerate(format!(
                "the Fresnel lens's radius of curvature must be finite and at least its \
                 aperture radius {a}, got {r}"
            )));
        }
        if !(1..=MAX_FRESNEL_ZONES).contains(&n) {
            return Err(GeometryError::Degenerate(format!(
                "a Fresnel lens needs 1 to {MAX_FRESNEL_ZONES} zones, got {n}"
            )));
        }
        let half = 0.5 * self.thickness;
        let front = self.centre - half * axis;
        let u = axis.any_orthogonal_vector();
        // The rims reach well beyond the plate and the zones on both sides.
        let reach = half + sag(Some(r), a) + a;
        let rim = |radius: f64| {
            Cylinder::new(
                self.centre - reach * axis,
                self.centre + reach * axis,
                radius,
            )
            .map(Shape::Cylinder)
        };
        let plate = Csg::new(
            CsgOperation::Intersection,
            vec![
                Shape::Plane(Plane::new(front, -axis, u)?),
                Shape::Plane(Plane::new(self.centre + half * axis, axis, u)?),
                rim(a)?,
            ],
        )?;
        let mut parts = vec![Shape::Csg(plate)];
        for k in 0..n {
            let (inner, outer) = (a * k as f64 / n as f64, a * (k + 1) as f64 / n as f64);
            let vertex = front - sag(Some(r), outer) * axis;
            let mut zone = vec![
                Shape::Sphere(Sphere::new(vertex + r * axis, r)?),
                Shape::Plane(Plane::new(front, axis, u)?),
                rim(outer)?,
            ];
            if k > 0 {
                zone.push(Shape::Csg(Csg::new(
                    CsgOperation::Inverse,
                    vec![rim(inner)?],
                )?));
            }
            parts.push(Shape::Csg(Csg::new(CsgOperation::Intersection, zone)?));
        }
        let lens = Csg::new(CsgOperation::Union, parts)?;
        Ok(Shape::Csg(lens.called("fresnel-lens")))
    }
}

/// `type = "spherical-lens"`: a [`SphericalLens`] (a radius not given: a flat surface).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SphericalLensKeys {
    centre: Vector,
    axis: Vector,
    front_radius: Option<Finite>,
    back_radius: Option<Finite>,
    thickness: Positive,
    aperture_radius: Positive,
}

impl SphericalLensKeys {
    pub fn build(self) -> Result<Shape, GeometryError> {
        SphericalLens {
            centre: self.centre.0,
            axis: self.axis.0,
            front_radius: self.front_radius.map(|r| r.0),
            back_radius: self.back_radius.map(|r| r.0),
            thickness: self.thickness.0,
            aperture_radius: self.aperture_radius.0,
        }
        .shape()
    }
}

/// `type = "fresnel-lens"`: a plano-convex [`FresnelLens`].
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FresnelLensKeys {
    centre: Vector,
    axis: Vector,
    radius_of_curvature: Positive,
    aperture_radius: Positive,
    zones: u32,
    thickness: Positive,
}

impl FresnelLensKeys {
    pub fn build(self) -> Result<Shape, GeometryError> {
        FresnelLens {
            centre: self.centre.0,
            axis: self.axis.0,
            radius_of_curvature: self.radius_of_curvature.0,
            aperture_radius: self.aperture_radius.0,
            zones: self.zones,
            thickness: self.thickness.0,
        }
        .shape()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lens(front: Option<f64>, back: Option<f64>, thickness: f64) -> SphericalLens {
        SphericalLens {
            centre: DVec3::new(0.0, 0.0, 10.0),
            axis: DVec3::Z,
            front_radius: front,
            back_radius: back,
            thickness,
            aperture_radius: 1.0,
        }
    }

    #[test]
    fn the_axial_thickness_and_the_rim_are_where_the_parameters_put_them() {
        for l in [
            lens(Some(3.0), Some(-3.0), 0.5),
            lens(Some(3.0), None, 0.4),
            lens(Some(2.0), Some(4.0), 0.3),
            lens(Some(-2.0), Some(2.0), 0.2),
        ] {
            let s = l.shape().unwrap();
            let on_axis = |o: DVec3, d: DVec3| s.intersect(o, d, 0.0, 100.0).unwrap().0;
            // Along the axis from both sides: the vertices, `thickness` apart.
            let front = on_axis(DVec3::ZERO, DVec3::Z);
            let back = 20.0 - on_axis(DVec3::new(0.0, 0.0, 20.0), DVec3::NEG_Z);
            assert!((front - (10.0 - 0.5 * l.thickness)).abs() < 1e-12, "{l:?}");
            assert!((back - front - l.thickness).abs() < 1e-12, "{l:?}");
            // From the side, at mid-height between the rim's ends: the rim at r = 1.
            let z = 10.0 + 0.5 * (sag(l.back_radius, 1.0) + sag(l.front_radius, 1.0));
            let t = on_axis(DVec3::new(5.0, 0.0, z), DVec3::NEG_X);
            assert!((t - 4.0).abs() < 1e-12, "{l:?}: t {t}");
        }
    }

    #[test]
    fn nothing_lies_beyond_a_hemispherical_concave_surface() {
        // R = −a: the front surface is a hemisphere whose rim plane holds its centre, z = 8.85.
        let s = lens(Some(-1.0), None, 0.3).shape().unwrap();
        for z in [8.849, 8.84, 8.5, 7.9] {
            for r in [0.0, 0.5, 0.999, 0.9999999] {
                assert!(!s.contains(DVec3::new(r, 0.0, z)), "({r}, 0, {z})");
            }
        }
        assert!(s.contains(DVec3::new(0.99999, 0.0, 8.86)));
    }

    #[test]
    fn surfaces_that_meet_inside_the_aperture_are_refused() {
        let e = lens(Some(1.5), Some(-1.5), 0.5).shape().unwrap_err();
        assert!(e.to_string().contains("meet inside its aperture"), "{e}");
        let e = lens(Some(0.5), None, 2.0).shape().unwrap_err();
        assert!(
            e.to_string().contains("at least the aperture radius"),
            "{e}"
        );
    }

    #[test]
    fn every_fresnel_zone_ends_in_a_step_as_high_as_its_sag_difference() {
        let f = FresnelLens {
            centre: DVec3::ZERO,
            axis: DVec3::Z,
            radius_of_curvature: 4.0,
            aperture_radius: 2.0,
            zones: 4,
            thickness: 0.1,
        };
        let s = f.shape().unwrap();
        for k in 0..4 {
            // Just outside zone k's inner edge the surface is highest: the plate's front
            // (z = -0.05) minus the zone's sag difference.
            let h = 0.5 * k as f64 + 1e-9;
            let (t, _) = s
                .intersect(DVec3::new(h, 0.0, -10.0), DVec3::Z, 0.0, 100.0)
                .unwrap();
            let height = sag(Some(4.0), 0.5 * (k + 1) as f64) - sag(Some(4.0), h);
            assert!((t - (10.0 - 0.05 - height)).abs() < 1e-9, "zone {k}: t {t}");
        }
    }
}
