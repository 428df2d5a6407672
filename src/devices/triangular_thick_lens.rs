//! Dr TIM's `TriangularThickLens` (sceneObjects/TriangularThickLens.java): "a lens with a
//! triangular aperture and spherical surfaces, both with the same radius of curvature", of
//! glass of refractive index n (Dr TIM's research program `LensCloak` builds its cloaks from
//! them).
//!
//! The radius of curvature comes from the thin-lens lensmaker's equation with surfaces of
//! radii R and −R, 1/f = (n − 1) 2/R: R = 2 f (n − 1) (Dr TIM notes that the finite thickness
//! is not taken into account, so the lens's focal length differs from f by the thick-lens
//! term). The optical axis â is normal to the triangle of the corners, (c₂ − c₁) × (c₃ − c₁)
//! normalised, through the principal point P (in the triangle's plane); the aperture radius a
//! is the distance from P to the farthest corner, which must not exceed |R|.
//!
//! - f > 0 (biconvex): the intersection of the two balls of radius R centred at P ± z â,
//!   z = √(R² − a²) − d/2, so the lens is d thick (`thickness_at_thinnest_point`) at the
//!   distance a from the axis;
//! - f < 0 (biconcave): the outside of the two balls of radius |R| centred at P ± z â,
//!   z = |R| + d/2 (d thick on the axis), between the planes across the axis through their
//!   centres;
//!
//! in both cases cut to the triangular prism on the triangle along the axis. Its surface is
//! `refractive` with index ratio n and transmission coefficient 1 (Dr TIM's `Refractive(n, 1,
//! true)`), its only part `lens`.

use glam::DVec3;
use serde::Deserialize;

use super::{Edges, LensDevice, Part};
use crate::geometry::{
    Csg, CsgOperation, GeometryError, RefractiveIndex, Shape, Sphere, TriangularPrism,
};
use crate::keys::{NonZero, Positive, Vector};
use crate::surfaces::{Refractive, Surface};

#[derive(Debug, Clone, PartialEq)]
pub struct TriangularThickLens {
    /// f ≠ 0.
    pub focal_length: f64,
    /// In the plane of the corners.
    pub principal_point: DVec3,
    pub corners: [DVec3; 3],
    /// n > 1.
    pub refractive_index: f64,
    /// d > 0: at the corner farthest from the axis (f > 0), on the axis (f < 0).
    pub thickness_at_thinnest_point: f64,
}

impl TriangularThickLens {
    /// R = 2 f (n − 1).
    pub fn radius_of_curvature(&self) -> f64 {
        2.0 * self.focal_length * (self.refractive_index - 1.0)
    }

    /// The unit optical axis, normal to the corners' triangle.
    pub fn axis(&self) -> DVec3 {
        let [c1, c2, c3] = self.corners;
        (c2 - c1).cross(c3 - c1).normalize_or_zero()
    }

    /// The lens as one solid.
    pub fn shape(&self) -> Result<Shape, String> {
        let (p, d) = (self.principal_point, self.thickness_at_thinnest_point);
        let axis = self.axis();
        if axis == DVec3::ZERO {
            return Err("the corners are repeated or collinear".into());
        }
        let a = self
            .corners
            .iter()
            .map(|c| (*c - p).length())
            .fold(0.0, f64::max);
        let r = self.radius_of_curvature();
        if r.abs() < a {
            return Err(format!(
                "the radius of curvature 2 f (n − 1) = {r} of the lens surfaces is less than \
                 the aperture radius {a} (the distance from the principal point to the \
                 farthest corner)"
            ));
        }
        let ball = |centre: DVec3| Sphere::new(centre, r.abs()).map(Shape::Sphere);
        let inverse = |s: Shape| Csg::new(CsgOperation::Inverse, vec![s]).map(Shape::Csg);
        let prism = |half: f64| {
            TriangularPrism::new(self.corners.map(|c| c - half * axis), 2.0 * half * axis)
                .map(Shape::TriangularPrism)
        };
        let members = |z: f64| -> Result<Vec<Shape>, GeometryError> {
            let (front, back) = (p + z * axis, p - z * axis);
            if r > 0.0 {
                // The lens is 2 (R − √(R² − a²)) + d thick on the axis; the prism reaches
                // beyond it.
                Ok(vec![ball(front)?, ball(back)?, prism(2.0 * (r - z))?])
            } else {
                // The prism between the planes through the balls' centres.
                Ok(vec![
                    inverse(ball(front)?)?,
                    inverse(ball(back)?)?,
                    prism(z)?,
                ])
            }
        };
        let z = if r > 0.0 {
            (r * r - a * a).sqrt() - 0.5 * d
        } else {
            r.abs() + 0.5 * d
        };
        let lens = members(z)
            .and_then(|m| Csg::new(CsgOperation::Intersection, m))
            .map_err(|e| e.to_string())?;
        Ok(Shape::Csg(lens))
    }
}

impl LensDevice for TriangularThickLens {
    /// `lens`; no edges.
    fn parts(&self, edges: Option<&Edges>) -> Result<Vec<Part>, String> {
        if edges.is_some() {
            return Err("a triangular thick lens has no edges to show (show_edges)".into());
        }
        Ok(vec![Part {
            name: "lens".into(),
            shape: self.shape()?,
            surface: Surface::Refractive(Refractive {
                index_ratio: self.refractive_index,
                transmission_coefficient: 1.0,
            }),
            edge: false,
        }])
    }
}

/// `lenses = { type = "triangular-thick-lens" }`: Dr TIM's `TriangularThickLens` (no
/// defaults: it has no editable form).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TriangularThickLensKeys {
    focal_length: NonZero,
    principal_point: Vector,
    corner1: Vector,
    corner2: Vector,
    corner3: Vector,
    refractive_index: RefractiveIndex,
    thickness_at_thinnest_point: Positive,
}

impl TriangularThickLensKeys {
    pub fn build(self) -> Result<Box<dyn LensDevice>, String> {
        Ok(Box::new(TriangularThickLens {
            focal_length: self.focal_length.0,
            principal_point: self.principal_point.0,
            corners: [self.corner1.0, self.corner2.0, self.corner3.0],
            refractive_index: self.refractive_index.0,
            thickness_at_thinnest_point: self.thickness_at_thinnest_point.0,
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lens(f: f64) -> TriangularThickLens {
        TriangularThickLens {
            focal_length: f,
            principal_point: DVec3::ZERO,
            corners: [
                DVec3::new(1.0, 0.0, 0.0),
                DVec3::new(-0.5, 0.8, 0.0),
                DVec3::new(-0.5, -0.8, 0.0),
            ],
            refractive_index: 1.5,
            thickness_at_thinnest_point: 0.01,
        }
    }

    /// The lens's thickness along the axis (z) at (x, y).
    fn thickness(shape: &Shape, x: f64, y: f64) -> f64 {
        let o = DVec3::new(x, y, -10.0);
        let (t0, _) = shape.intersect(o, DVec3::Z, 0.0, 100.0).unwrap();
        let (t1, _) = shape.intersect(o, DVec3::Z, t0 + 1e-9, 100.0).unwrap();
        t1 - t0
    }

    #[test]
    fn thinnest_where_dr_tim_says() {
        // f = 2: R = 2, a = 1 (the corner (1, 0, 0)): d at that corner, thicker inside.
        let convex = lens(2.0).shape().unwrap();
        assert!((thickness(&convex, 1.0 - 1e-9, 0.0) - 0.01).abs() < 1e-6);
        let centre = 2.0 * (2.0 - 3f64.sqrt()) + 0.01;
        assert!((thickness(&convex, 0.0, 0.0) - centre).abs() < 1e-12);
        // f = −2: d on the axis.
        let concave = lens(-2.0).shape().unwrap();
        assert!((thickness(&concave, 0.0, 0.0) - 0.01).abs() < 1e-12);
        // Outside the triangle, nothing.
        for s in [&convex, &concave] {
            assert!(
                s.intersect(DVec3::new(-0.6, 0.0, -10.0), DVec3::Z, 0.0, 100.0)
                    .is_none()
            );
        }
    }

    #[test]
    fn a_radius_of_curvature_below_the_aperture_is_refused() {
        // f = 0.9: R = 0.9 < a = 1.
        assert!(
            lens(0.9)
                .shape()
                .unwrap_err()
                .contains("less than the aperture radius")
        );
    }
}
