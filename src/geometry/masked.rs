//! A surface cut to the part of it inside a solid, the *mask* (Dr TIM's masked objects; with an
//! inverse as the mask, a surface with holes): a disc with a square window, a plane with
//! round holes. The mask itself is invisible.

use glam::{DVec2, DVec3};
use serde::Deserialize;

use super::{AnalyticShape, GeometryError, Shape, ShapeKeys};
use crate::math::Frame;

#[derive(Debug, Clone, PartialEq)]
pub struct Masked {
    surface: Box<Shape>,
    mask: Box<Shape>,
}

impl Masked {
    /// `surface` (an analytic shape) where it lies inside `mask` (a solid).
    pub fn new(surface: Shape, mask: Shape) -> Result<Masked, GeometryError> {
        if matches!(surface, Shape::TriangleMesh(_)) {
            return Err(GeometryError::Degenerate(
                "a mesh cannot be masked (only analytic shapes can)".into(),
            ));
        }
        if !mask.is_solid() {
            return Err(GeometryError::Degenerate(format!(
                "the mask ({}) does not enclose a solid",
                mask.kind()
            )));
        }
        let masked = Masked {
            surface: Box::new(surface),
            mask: Box::new(mask),
        };
        if let Some((lo, hi)) = masked.bounds()
            && lo.cmpgt(hi).any()
        {
            return Err(GeometryError::Degenerate(
                "the mask does not overlap the surface: nothing of it is left".into(),
            ));
        }
        Ok(masked)
    }

    pub fn surface(&self) -> &Shape {
        &self.surface
    }

    pub fn mask(&self) -> &Shape {
        &self.mask
    }

    /// The same surface and mask, each mapped by `f`: how a transform reaches them.
    pub fn map(
        &self,
        mut f: impl FnMut(&Shape) -> Result<Shape, GeometryError>,
    ) -> Result<Masked, GeometryError> {
        Masked::new(f(&self.surface)?, f(&self.mask)?)
    }
}

impl AnalyticShape for Masked {
    /// The nearest crossing of the surface that lies inside the mask.
    fn intersect(
        &self,
        origin: DVec3,
        direction: DVec3,
        t_min: f64,
        t_max: f64,
    ) -> Option<(f64, u32)> {
        // Every crossing lies beyond the one before, and a surface has finitely many.
        let mut from = t_min;
        loop {
            let (t, part) = self.surface.intersect(origin, direction, from, t_max)?;
            if self.mask.contains(origin + t * direction) {
                return Some((t, part));
            }
            from = t;
        }
    }

    fn frame(&self, p: DVec3, part: u32) -> Frame {
        self.surface.frame(p, part)
    }

    fn coordinates(&self, p: DVec3, part: u32) -> DVec2 {
        self.surface.coordinates(p, part)
    }

    fn plane_coordinates(&self, p: DVec3, part: u32) -> Option<DVec2> {
        self.surface.plane_coordinates(p, part)
    }

    fn is_flat(&self) -> bool {
        self.surface.is_flat()
    }

    fn coordinate_axes(&self, p: DVec3, part: u32) -> Option<[DVec3; 2]> {
        self.surface.coordinate_axes(p, part)
    }

    fn is_charted(&self) -> bool {
        self.surface.is_charted()
    }

    /// The surface's bounds, cut to the mask's where it has them.
    fn bounds(&self) -> Option<(DVec3, DVec3)> {
        match (self.surface.bounds(), self.mask.bounds()) {
            (Some((a, b)), Some((c, d))) => Some((a.max(c), b.min(d))),
            (one, None) | (None, one) => one,
        }
    }
}

/// `type = "masked"`: the surface `of` where it lies inside the solid `mask`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaskedKeys {
    of: Box<ShapeKeys>,
    mask: Box<ShapeKeys>,
}

impl MaskedKeys {
    pub fn build(self) -> Result<Shape, GeometryError> {
        Ok(Shape::Masked(Masked::new(
            self.of.build()?,
            self.mask.build()?,
        )?))
    }
}
