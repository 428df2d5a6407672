//! Placing shapes: an affine map x ↦ R·(S x) + t (scale per axis, then rotation about an axis,
//! then translation), composable for groups.
//!
//! Meshes, parallelograms and planes take any non-singular map. Spheres, discs and cylinders
//! stay what they are under similarity maps (rotation, uniform scale, translation, reflection)
//! and become [`Transformed`] shapes under any other; so does every other analytic shape under
//! any map. A map with negative determinant (a reflection) keeps the outward side outward: mesh
//! windings are reversed and a parallelogram's first span vector is negated.

use glam::{DAffine3, DMat3, DQuat, DVec3};
use serde::{Deserialize, Deserializer, de};

use super::{
    AnalyticShape, Cylinder, GeometryError, Parallelogram, Plane, Shape, Transformed,
    check_direction, check_point,
};
use crate::keys::{Finite, MAX_MAGNITUDE, Matrix, Vector};

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Transform {
    affine: DAffine3,
}

impl Default for Transform {
    fn default() -> Transform {
        Transform::IDENTITY
    }
}

impl Transform {
    pub const IDENTITY: Transform = Transform {
        affine: DAffine3::IDENTITY,
    };

    /// Scale by `scale` (per axis), then rotate by `angle` (radians, right-handed) about
    /// `axis`, then translate by `translation`.
    pub fn new(
        scale: DVec3,
        axis: DVec3,
        angle: f64,
        translation: DVec3,
    ) -> Result<Transform, GeometryError> {
        check_point("scale", scale)?;
        check_point("translation", translation)?;
        if !angle.is_finite() {
            return Err(GeometryError::NotPositive {
                what: "rotation angle (finite)",
                value: angle,
            });
        }
        if scale.abs().min_element() == 0.0 {
            return Err(GeometryError::Degenerate(format!(
                "singular transform: scale {scale} has a zero factor"
            )));
        }
        if scale.x * scale.y * scale.z == 0.0 {
            return Err(GeometryError::Degenerate(format!(
                "singular transform: the scale factors {scale} multiply to a number too \
                 small to hold (below 1e-308)"
            )));
        }
        let axis = if angle == 0.0 {
            DVec3::Z
        } else {
            check_direction("rotation axis", axis)?
        };
        Ok(Transform {
            affine: DAffine3::from_scale_rotation_translation(
                scale,
                DQuat::from_axis_angle(axis, angle),
                translation,
            ),
        })
    }

    /// The general linear map `m` (non-uniform scales, shears); it must be invertible.
    pub fn from_matrix(m: DMat3) -> Result<Transform, GeometryError> {
        super::check_invertible(m)?;
        Ok(Transform {
            affine: DAffine3::from_mat3(m),
        })
    }

    pub fn translation(t: DVec3) -> Transform {
        Transform {
            affine: DAffine3::from_translation(t),
        }
    }

    /// This map followed by `outer` (a group's transform applied to its members').
    pub fn then(&self, outer: &Transform) -> Transform {
        Transform {
            affine: outer.affine * self.affine,
        }
    }

    /// Checks a map made of several (an object's transform and its groups'), each within
    /// range, for what their product may break: matrix entries and translation of magnitude at
    /// most [`MAX_MAGNITUDE`], and an inverse.
    pub fn check_product(&self) -> Result<(), GeometryError> {
        let m = self.affine.matrix3;
        let largest = m.abs().to_cols_array().into_iter().fold(0.0, f64::max);
        let moved = self.affine.translation.abs().max_element();
        let refuse = |what: String| {
            Err(GeometryError::Degenerate(format!(
                "with the transforms of the groups around it, {what}"
            )))
        };
        if largest > MAX_MAGNITUDE || largest.is_nan() {
            refuse(format!(
                "the map scales by up to {largest:e}, more than {MAX_MAGNITUDE:e}"
            ))
        } else if moved > MAX_MAGNITUDE || moved.is_nan() {
            refuse(format!(
                "the map moves points by up to {moved:e}, more than {MAX_MAGNITUDE:e}"
            ))
        } else if super::check_invertible(m).is_err() {
            refuse(format!(
                "the map is singular (its determinant is {:e})",
                m.determinant()
            ))
        } else {
            Ok(())
        }
    }

    pub fn point(&self, p: DVec3) -> DVec3 {
        self.affine.transform_point3(p)
    }

    pub fn vector(&self, v: DVec3) -> DVec3 {
        self.affine.transform_vector3(v)
    }

    fn linear(&self) -> DMat3 {
        self.affine.matrix3
    }

    /// Image of a surface normal (inverse transpose), not normalised.
    pub fn normal(&self, n: DVec3) -> DVec3 {
        self.linear().inverse().transpose() * n
    }

    pub fn is_identity(&self) -> bool {
        self.affine == DAffine3::IDENTITY
    }

    /// The scale factor s > 0 when the linear part is s × an orthogonal matrix.
    pub fn uniform_scale(&self) -> Option<f64> {
        let m = self.linear();
        let mtm = m.transpose() * m;
        let s2 = mtm.x_axis.x;
        let identity = DMat3::IDENTITY * s2;
        (mtm - identity)
            .to_cols_array()
            .iter()
            .all(|e| e.abs() <= 1e-12 * s2)
            .then(|| s2.sqrt())
    }

    /// The orthogonal part R of a similarity map with uniform scale `k` (R = linear part / k,
    /// a rotation or a reflection), or `None` when it turns nothing (a uniform scale by k > 0).
    fn rotation(&self, k: f64) -> Option<DMat3> {
        let m = self.linear();
        (m != DMat3::from_diagonal(DVec3::splat(m.x_axis.x)) || m.x_axis.x <= 0.0)
            .then(|| m * (1.0 / k))
    }

    /// The shape placed by this map. Spheres, discs and cylinders stay themselves under
    /// similarity maps, turning their surface-coordinate patterns with them; under any other
    /// map they, like every other analytic shape but planes and parallelograms, become
    /// [`Transformed`]. A CSG shape is transformed leaf by leaf.
    pub fn shape(&self, shape: &Shape) -> Result<Shape, GeometryError> {
        if self.is_identity() {
            return Ok(shape.clone());
        }
        let general = || Transformed::new(shape.clone(), self.affine).map(Shape::Transformed);
        Ok(match shape {
            Shape::Sphere(s) => match self.uniform_scale() {
                None => general()?,
                Some(k) => {
                    let moved = s.placed(self.point(s.centre()), k * s.radius())?;
                    Shape::Sphere(match self.rotation(k) {
                        Some(r) => moved.rotated(r),
                        None => moved,
                    })
                }
            },
            Shape::Disc(d) => match self.uniform_scale() {
                None => general()?,
                Some(k) => {
                    let turned = match self.rotation(k) {
                        Some(r) => d.clone().rotated(r),
                        None => d.clone(),
                    };
                    Shape::Disc(turned.placed(self.point(d.centre()), k * d.radius())?)
                }
            },
            Shape::Cylinder(c) => match self.uniform_scale() {
                None => general()?,
                Some(k) => {
                    let moved =
                        Cylinder::new(self.point(c.start()), self.point(c.end()), k * c.radius())?;
                    let r = self.rotation(k).unwrap_or(DMat3::IDENTITY);
                    Shape::Cylinder(moved.across_from(c, r))
                }
            },
            Shape::Plane(p) => Shape::Plane(Plane::new(
                self.point(p.point()),
                self.normal(p.frame(p.point(), 0).w),
                self.vector(p.frame(p.point(), 0).u),
            )?),
            Shape::Parallelogram(p) => {
                let (corner, u, v) = (
                    self.point(p.corner()),
                    self.vector(p.span_u()),
                    self.vector(p.span_v()),
                );
                Shape::Parallelogram(if self.reflects() {
                    Parallelogram::new(corner + u, -u, v)?
                } else {
                    Parallelogram::new(corner, u, v)?
                })
            }
            Shape::Csg(c) => Shape::Csg(c.map_leaves(|leaf| self.shape(leaf))?),
            Shape::Masked(m) => Shape::Masked(m.map(|s| self.shape(s))?),
            Shape::TriangleMesh(m) => Shape::TriangleMesh(m.transformed(self)?),
            _ => general()?,
        })
    }

    /// Whether the map reverses orientation (a reflection).
    pub fn reflects(&self) -> bool {
        self.linear().determinant() < 0.0
    }
}

/// A `transform` table: `matrix` (a general linear map, given by its rows) first, then
/// `scale`, then `rotate`, then `translate`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TransformKeys {
    matrix: Option<Matrix>,
    scale: Option<Scale>,
    rotate: Option<RotateKeys>,
    translate: Option<Vector>,
}

/// A rotation by `angle_deg` (degrees, right-handed) about `axis`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RotateKeys {
    axis: Vector,
    angle_deg: Finite,
}

/// A scale factor: one number (uniform) or three (per axis).
#[derive(Debug)]
struct Scale(DVec3);

impl<'de> Deserialize<'de> for Scale {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        #[derive(Deserialize)]
        #[serde(untagged)]
        enum Either {
            Uniform(f64),
            PerAxis([f64; 3]),
        }
        let v = match Either::deserialize(d).map_err(|_| {
            de::Error::custom("expected a scale factor or three of them, [sx, sy, sz]")
        })? {
            Either::Uniform(s) => DVec3::splat(s),
            Either::PerAxis(s) => DVec3::from(s),
        };
        if v.abs().max_element() <= MAX_MAGNITUDE {
            Ok(Scale(v))
        } else {
            Err(de::Error::custom(format!(
                "expected finite scale factors of magnitude at most 1e15, got {v}"
            )))
        }
    }
}

impl TransformKeys {
    /// The map: `matrix`, then `scale`, then `rotate`, then `translate`.
    pub fn build(self) -> Result<Transform, GeometryError> {
        let (axis, angle) = self
            .rotate
            .map_or((DVec3::Z, 0.0), |r| (r.axis.0, r.angle_deg.0.to_radians()));
        let placed = Transform::new(
            self.scale.map_or(DVec3::ONE, |s| s.0),
            axis,
            angle,
            self.translate.map_or(DVec3::ZERO, |t| t.0),
        )?;
        match self.matrix {
            Some(m) => Ok(Transform::from_matrix(m.0)?.then(&placed)),
            None => Ok(placed),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Disc, Sphere};
    use std::f64::consts::FRAC_PI_2;

    #[test]
    fn scale_then_rotate_then_translate() {
        let t = Transform::new(DVec3::new(2.0, 3.0, 4.0), DVec3::Z, FRAC_PI_2, DVec3::X).unwrap();
        // (1,1,1) -> scaled (2,3,4) -> rotated 90° about z (-3,2,4) -> translated (-2,2,4).
        assert!(
            (t.point(DVec3::ONE) - DVec3::new(-2.0, 2.0, 4.0)).length() < 1e-12,
            "{}",
            t.point(DVec3::ONE)
        );
        let g = t.then(&Transform::translation(DVec3::Y));
        assert!((g.point(DVec3::ONE) - DVec3::new(-2.0, 3.0, 4.0)).length() < 1e-12);
    }

    #[test]
    fn singular_maps_are_refused_and_non_uniform_ones_become_general_transforms() {
        let e = Transform::new(DVec3::new(1.0, 0.0, 1.0), DVec3::Z, 0.0, DVec3::ZERO);
        assert!(e.unwrap_err().to_string().contains("singular"));
        let squash = Transform::new(DVec3::new(1.0, 2.0, 1.0), DVec3::Z, 0.3, DVec3::ZERO).unwrap();
        let sphere = Shape::Sphere(Sphere::new(DVec3::ZERO, 1.0).unwrap());
        assert!(matches!(squash.shape(&sphere), Ok(Shape::Transformed(_))));
        let uniform = Transform::new(DVec3::splat(-2.0), DVec3::X, 1.0, DVec3::Z).unwrap();
        let Shape::Sphere(s) = uniform.shape(&sphere).unwrap() else {
            unreachable!()
        };
        assert!((s.radius() - 2.0).abs() < 1e-12 && (s.centre() - DVec3::Z).length() < 1e-12);
    }

    #[test]
    fn rotations_turn_the_surface_coordinates_of_spheres_discs_and_cylinders() {
        // A quarter turn about z takes the world point q to R q; the turned shape's surface
        // coordinates at R q are the original's at q.
        let turn = Transform::new(DVec3::ONE, DVec3::Z, FRAC_PI_2, DVec3::ZERO).unwrap();
        let q = DVec3::new(0.6, 0.0, 0.8);
        let shapes = [
            Shape::Sphere(Sphere::new(DVec3::ZERO, 1.0).unwrap()),
            Shape::Disc(Disc::new(DVec3::ZERO, DVec3::Y, 2.0).unwrap()),
            Shape::Cylinder(Cylinder::new(DVec3::NEG_Y, DVec3::Y, 1.0).unwrap()),
        ];
        for shape in shapes {
            let turned = turn.shape(&shape).unwrap();
            let (before, after) = (
                shape.coordinates(q, 0),
                turned.coordinates(turn.point(q), 0),
            );
            assert!(
                (before - after).length() < 1e-12,
                "{shape:?}: {before} -> {after}"
            );
            // Without the turn of the pattern, a point's coordinates would change: the
            // original's coordinates at R q differ.
            assert!((shape.coordinates(turn.point(q), 0) - before).length() > 0.1);
            // Then a uniform scale and a shift (a group's transform): the pattern stays turned,
            // the coordinates scale, and the frame stays right-handed.
            let then = Transform::new(DVec3::splat(2.0), DVec3::Z, 0.0, DVec3::new(1.0, 2.0, 3.0))
                .unwrap();
            let at = turn.then(&then).point(q);
            let twice = then.shape(&turned).unwrap();
            let scaled = twice.coordinates(at, 0);
            assert!(
                (2.0 * before - scaled).length() < 1e-12,
                "{shape:?}: {scaled}"
            );
            let f = twice.frame(at, 0);
            assert!((f.u.cross(f.v) - f.w).length() < 1e-12, "{f:?}");
        }
        // A mirrored disc keeps a right-handed frame.
        let mirror =
            Transform::new(DVec3::new(1.0, 1.0, -1.0), DVec3::Z, 0.0, DVec3::ZERO).unwrap();
        let disc = Shape::Disc(Disc::new(DVec3::ZERO, DVec3::new(0.0, 1.0, 1.0), 2.0).unwrap());
        let f = mirror
            .shape(&turn.shape(&disc).unwrap())
            .unwrap()
            .frame(DVec3::ZERO, 0);
        assert!((f.u.cross(f.v) - f.w).length() < 1e-12, "{f:?}");
    }

    #[test]
    fn planes_keep_their_normals_under_shear_like_scaling() {
        // The plane x + y = 0 with normal (1,1,0); scaling x by 2 maps it to x/2 + y = 0,
        // whose normal is (1/2, 1, 0).
        let plane =
            Shape::Plane(Plane::new(DVec3::ZERO, DVec3::new(1.0, 1.0, 0.0), DVec3::Z).unwrap());
        let t = Transform::new(DVec3::new(2.0, 1.0, 1.0), DVec3::Z, 0.0, DVec3::ZERO).unwrap();
        let Shape::Plane(p) = t.shape(&plane).unwrap() else {
            unreachable!()
        };
        let expected = DVec3::new(0.5, 1.0, 0.0).normalize();
        assert!((p.frame(p.point(), 0).w - expected).length() < 1e-12);
    }

    #[test]
    fn a_reflection_keeps_a_parallelogram_facing_outwards() {
        let p = Parallelogram::new(DVec3::ZERO, DVec3::X, DVec3::Y).unwrap();
        let mirror =
            Transform::new(DVec3::new(1.0, 1.0, -1.0), DVec3::Z, 0.0, DVec3::ZERO).unwrap();
        let Shape::Parallelogram(q) = mirror.shape(&Shape::Parallelogram(p)).unwrap() else {
            unreachable!()
        };
        // The mirror image of a surface facing +z (at z = 0) faces -z.
        assert!((q.frame(q.corner(), 0).w - DVec3::NEG_Z).length() < 1e-12);
        assert_eq!(q.bounds(), Some((DVec3::ZERO, DVec3::new(1.0, 1.0, 0.0))));
    }
}
