//! Shapes, exact in f64 (one file each), the scene's ray–geometry queries
//! ([`SceneGeometry`], on Embree), and where a ray meets a surface ([`Interaction`]).
//!
//! Every shape gives the nearest hit distance along a ray, the surface frame (u, v, w; w the
//! outward normal) at a surface point, and 2D surface coordinates (for chequerboards).

mod cylinder;
mod disc;
mod interaction;
mod parallelogram;
mod plane;
mod scene_geometry;
mod sphere;
mod transform;
mod triangle_mesh;

use glam::{DVec2, DVec3};
use thiserror::Error;

pub use cylinder::Cylinder;
pub use disc::Disc;
pub use interaction::{Exit, Interaction};
pub use parallelogram::Parallelogram;
pub use plane::Plane;
pub use scene_geometry::{Hit, ObjectArray, SceneGeometry};
pub use sphere::Sphere;
pub use transform::Transform;
pub use triangle_mesh::TriangleMesh;

use crate::math::Frame;

/// Invalid shape parameters.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum GeometryError {
    #[error("{what} must be a positive finite number, got {value}")]
    NotPositive { what: &'static str, value: f64 },
    #[error("{what} must be finite, got {value}")]
    NotFinite { what: &'static str, value: DVec3 },
    #[error("{what} must be a non-zero vector")]
    ZeroVector { what: &'static str },
    #[error("degenerate geometry: {0}")]
    Degenerate(String),
}

fn check_positive(what: &'static str, value: f64) -> Result<(), GeometryError> {
    if value > 0.0 && value.is_finite() {
        Ok(())
    } else {
        Err(GeometryError::NotPositive { what, value })
    }
}

fn check_point(what: &'static str, value: DVec3) -> Result<(), GeometryError> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(GeometryError::NotFinite { what, value })
    }
}

/// A finite, non-zero vector, normalised.
fn check_direction(what: &'static str, value: DVec3) -> Result<DVec3, GeometryError> {
    check_point(what, value)?;
    value
        .try_normalize()
        .ok_or(GeometryError::ZeroVector { what })
}

/// A geometric shape.
#[derive(Debug, Clone, PartialEq)]
pub enum Shape {
    Sphere(Sphere),
    Plane(Plane),
    Disc(Disc),
    Cylinder(Cylinder),
    Parallelogram(Parallelogram),
    TriangleMesh(TriangleMesh),
}

impl Shape {
    /// Nearest hit (t, primitive) with t_min < t < t_max; primitives are a mesh's triangles,
    /// every other shape has the single primitive 0.
    pub fn intersect(
        &self,
        origin: DVec3,
        direction: DVec3,
        t_min: f64,
        t_max: f64,
    ) -> Option<(f64, u32)> {
        match self {
            Shape::TriangleMesh(m) => m.intersect(origin, direction, t_min, t_max),
            _ => self
                .intersect_primitive(0, origin, direction, t_min, t_max)
                .map(|t| (t, 0)),
        }
    }

    /// Nearest hit of primitive `prim`.
    pub fn intersect_primitive(
        &self,
        prim: u32,
        origin: DVec3,
        direction: DVec3,
        t_min: f64,
        t_max: f64,
    ) -> Option<f64> {
        match self {
            Shape::Sphere(s) => s.intersect(origin, direction, t_min, t_max),
            Shape::Plane(s) => s.intersect(origin, direction, t_min, t_max),
            Shape::Disc(s) => s.intersect(origin, direction, t_min, t_max),
            Shape::Cylinder(s) => s.intersect(origin, direction, t_min, t_max),
            Shape::Parallelogram(s) => s.intersect(origin, direction, t_min, t_max),
            Shape::TriangleMesh(m) => m.intersect_triangle(prim, origin, direction, t_min, t_max),
        }
    }

    /// Surface frame at surface point `p` of primitive `prim`.
    pub fn frame(&self, p: DVec3, prim: u32) -> Frame {
        match self {
            Shape::Sphere(s) => s.frame(p),
            Shape::Plane(s) => s.frame(),
            Shape::Disc(s) => s.frame(),
            Shape::Cylinder(s) => s.frame(p),
            Shape::Parallelogram(s) => s.frame(),
            Shape::TriangleMesh(m) => m.frame(p, prim),
        }
    }

    /// Surface coordinates of surface point `p` (units of length; see each shape).
    pub fn coordinates(&self, p: DVec3) -> DVec2 {
        match self {
            Shape::Sphere(s) => s.coordinates(p),
            Shape::Plane(s) => s.coordinates(p),
            Shape::Disc(s) => s.coordinates(p),
            Shape::Cylinder(s) => s.coordinates(p),
            Shape::Parallelogram(s) => s.coordinates(p),
            Shape::TriangleMesh(m) => m.coordinates(p),
        }
    }

    /// The point with surface coordinates `c` (inverse of [`Self::coordinates`]; a cylinder's
    /// mantle), or `None` if no point of the shape has them, or for meshes.
    pub fn point_at(&self, c: DVec2) -> Option<DVec3> {
        match self {
            Shape::Sphere(s) => s.point_at(c),
            Shape::Plane(s) => Some(s.point_at(c)),
            Shape::Disc(s) => s.point_at(c),
            Shape::Cylinder(s) => s.point_at(c),
            Shape::Parallelogram(s) => s.point_at(c),
            Shape::TriangleMesh(_) => None,
        }
    }

    /// Cartesian coordinates of `p` along the frame's u and v, from a flat shape's reference
    /// point (a plane's point, a disc's centre, a parallelogram's corner); `None` for curved
    /// shapes and meshes.
    pub fn plane_coordinates(&self, p: DVec3) -> Option<DVec2> {
        match self {
            Shape::Plane(s) => Some(s.coordinates(p)),
            Shape::Disc(s) => Some(s.coordinates(p)),
            Shape::Parallelogram(s) => Some(s.plane_coordinates(p)),
            _ => None,
        }
    }

    /// Axis-aligned bounds, or `None` for unbounded shapes.
    pub fn bounds(&self) -> Option<(DVec3, DVec3)> {
        match self {
            Shape::Sphere(s) => Some(s.bounds()),
            Shape::Plane(_) => None,
            Shape::Disc(s) => Some(s.bounds()),
            Shape::Cylinder(s) => Some(s.bounds()),
            Shape::Parallelogram(s) => Some(s.bounds()),
            Shape::TriangleMesh(m) => Some(m.bounds()),
        }
    }
}
