//! An analytic shape under a general affine map x ↦ A x + b (non-uniform scales, shears):
//! exact, not meshed. A ray is taken into the shape's own space (o′ = A⁻¹(o − b),
//! d′ = A⁻¹d, not normalised, so t is the same on both sides), and the shape's outward normal
//! comes back by the inverse transpose, A⁻ᵀ n, which is outward for either sign of det A.
//! Tangents map by A itself; the frame's u is A u′ made perpendicular to the normal.

use glam::{DAffine3, DMat3, DVec2, DVec3};
use serde::Deserialize;

use super::{AnalyticShape, ConvexSolid, GeometryError, Shape, ShapeKeys, Span, TransformKeys};
use crate::math::Frame;

#[derive(Debug, Clone, PartialEq)]
pub struct Transformed {
    inner: Box<Shape>,
    to_world: DAffine3,
    to_local: DAffine3,
    /// A⁻ᵀ, which maps normals.
    normals: DMat3,
}

impl Transformed {
    /// `inner` (an analytic shape, not a mesh or a CSG shape, which transform otherwise)
    /// mapped by `map`, which must be invertible.
    pub fn new(inner: Shape, map: DAffine3) -> Result<Transformed, GeometryError> {
        let (inner, map) = match inner {
            Shape::Transformed(t) => (*t.inner, map * t.to_world),
            Shape::TriangleMesh(_) | Shape::Csg(_) | Shape::Masked(_) => {
                return Err(GeometryError::Degenerate(format!(
                    "a {} is transformed piece by piece, not as a whole",
                    inner.kind()
                )));
            }
            other => (other, map),
        };
        super::check_invertible(map.matrix3)?;
        super::check_point("translation", map.translation)?;
        let to_local = map.inverse();
        Ok(Transformed {
            inner: Box::new(inner),
            to_world: map,
            to_local,
            normals: to_local.matrix3.transpose(),
        })
    }

    /// The shape in its own space.
    pub fn inner(&self) -> &Shape {
        &self.inner
    }

    /// The map from the shape's own space to the world.
    pub fn map(&self) -> DAffine3 {
        self.to_world
    }

    fn local(&self, p: DVec3) -> DVec3 {
        self.to_local.transform_point3(p)
    }
}

impl AnalyticShape for Transformed {
    fn intersect(
        &self,
        origin: DVec3,
        direction: DVec3,
        t_min: f64,
        t_max: f64,
    ) -> Option<(f64, u32)> {
        self.inner.intersect(
            self.local(origin),
            self.to_local.transform_vector3(direction),
            t_min,
            t_max,
        )
    }

    fn frame(&self, p: DVec3, part: u32) -> Frame {
        let f = self.inner.frame(self.local(p), part);
        Frame::from_normal_and_u(self.normals * f.w, self.to_world.transform_vector3(f.u))
    }

    /// The shape's own surface coordinates (the pattern stretches with the shape).
    fn coordinates(&self, p: DVec3, part: u32) -> DVec2 {
        self.inner.coordinates(self.local(p), part)
    }

    fn point_at(&self, c: DVec2) -> Option<DVec3> {
        self.inner
            .point_at(c)
            .map(|q| self.to_world.transform_point3(q))
    }

    /// Cartesian coordinates in the world along the mapped frame's u and v, from the image of
    /// the flat shape's own reference point.
    fn plane_coordinates(&self, p: DVec3, part: u32) -> Option<DVec2> {
        let q = self.local(p);
        let c = self.inner.plane_coordinates(q, part)?;
        let own = self.inner.frame(q, part);
        let reference = self
            .to_world
            .transform_point3(q - c.x * own.u - c.y * own.v);
        let f = self.frame(p, part);
        Some(DVec2::new(
            (p - reference).dot(f.u),
            (p - reference).dot(f.v),
        ))
    }

    fn is_flat(&self) -> bool {
        self.inner.is_flat()
    }

    /// The shape's own axes mapped by the linear part A (the coordinates are the shape's own:
    /// ∂(A p′ + b)/∂c = A ∂p′/∂c).
    fn coordinate_axes(&self, p: DVec3, part: u32) -> Option<[DVec3; 2]> {
        let axes = self.inner.coordinate_axes(self.local(p), part)?;
        Some(axes.map(|a| self.to_world.transform_vector3(a)))
    }

    fn is_charted(&self) -> bool {
        self.inner.is_charted()
    }

    /// The box around the images of the corners of the shape's own box.
    fn bounds(&self) -> Option<(DVec3, DVec3)> {
        let (lo, hi) = self.inner.bounds()?;
        let corners = (0..8).map(|i| {
            let pick = |bit: usize, a: f64, b: f64| if i & bit == 0 { a } else { b };
            self.to_world.transform_point3(DVec3::new(
                pick(1, lo.x, hi.x),
                pick(2, lo.y, hi.y),
                pick(4, lo.z, hi.z),
            ))
        });
        Some(
            corners.fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(a, b), c| {
                (a.min(c), b.max(c))
            }),
        )
    }

    fn solid(&self) -> Option<&dyn ConvexSolid> {
        self.inner
            .analytic_solid()
            .map(|_| self as &dyn ConvexSolid)
    }
}

/// A linear map keeps a convex solid convex, and t along the line.
impl ConvexSolid for Transformed {
    fn chord(&self, origin: DVec3, direction: DVec3) -> Option<Span> {
        self.inner.analytic_solid()?.chord(
            self.local(origin),
            self.to_local.transform_vector3(direction),
        )
    }

    fn contains(&self, p: DVec3) -> bool {
        self.inner
            .analytic_solid()
            .is_some_and(|s| s.contains(self.local(p)))
    }
}

/// `type = "transformed"`: a shape under its own transform (in the coordinates of the entry it
/// is in).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TransformedKeys {
    of: Box<ShapeKeys>,
    transform: TransformKeys,
}

impl TransformedKeys {
    pub fn build(self) -> Result<Shape, GeometryError> {
        self.transform.build()?.shape(&self.of.build()?)
    }
}
