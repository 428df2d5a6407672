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

/// What every analytic shape gives: exact f64 hits of its one primitive, the surface frame and
/// coordinates, and bounds. A new shape implements it in its own file and is added to
/// [`Shape`] and to `dispatch!` below, one line each.
pub trait AnalyticShape {
    /// The nearest t in (t_min, t_max) where `origin + t direction` meets the surface.
    fn intersect(&self, origin: DVec3, direction: DVec3, t_min: f64, t_max: f64) -> Option<f64>;

    /// The surface frame at surface point `p` (u, v, w; w the outward normal).
    fn frame(&self, p: DVec3) -> Frame;

    /// The surface coordinates of surface point `p` (units of length; see each shape).
    fn coordinates(&self, p: DVec3) -> DVec2;

    /// The point with surface coordinates `c` (the inverse of [`Self::coordinates`]), or
    /// `None` if no point of the shape has them.
    fn point_at(&self, c: DVec2) -> Option<DVec3>;

    /// Cartesian coordinates of `p` along the frame's u and v from a flat shape's reference
    /// point; `None` for curved shapes.
    fn plane_coordinates(&self, _p: DVec3) -> Option<DVec2> {
        None
    }

    /// Axis-aligned bounds, or `None` for unbounded shapes.
    fn bounds(&self) -> Option<(DVec3, DVec3)>;
}

/// `$analytic` with `$s` bound to the analytic shape inside a [`Shape`], or `$mesh` with `$m`
/// bound to its triangle mesh: the one list of the shapes that every `Shape` method uses.
macro_rules! dispatch {
    ($shape:expr, $s:ident => $analytic:expr, $m:ident => $mesh:expr) => {
        match $shape {
            Shape::Sphere($s) => $analytic,
            Shape::Plane($s) => $analytic,
            Shape::Disc($s) => $analytic,
            Shape::Cylinder($s) => $analytic,
            Shape::Parallelogram($s) => $analytic,
            Shape::TriangleMesh($m) => $mesh,
        }
    };
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
        dispatch!(self,
            s => s.intersect(origin, direction, t_min, t_max).map(|t| (t, 0)),
            m => m.intersect(origin, direction, t_min, t_max))
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
        dispatch!(self,
            s => s.intersect(origin, direction, t_min, t_max),
            m => m.intersect_triangle(prim, origin, direction, t_min, t_max))
    }

    /// Surface frame at surface point `p` of primitive `prim`.
    pub fn frame(&self, p: DVec3, prim: u32) -> Frame {
        dispatch!(self, s => s.frame(p), m => m.frame(p, prim))
    }

    /// Surface coordinates of surface point `p` (units of length; see each shape).
    pub fn coordinates(&self, p: DVec3) -> DVec2 {
        dispatch!(self, s => s.coordinates(p), m => m.coordinates(p))
    }

    /// The point with surface coordinates `c` (inverse of [`Self::coordinates`]; a cylinder's
    /// mantle), or `None` if no point of the shape has them, or for meshes.
    pub fn point_at(&self, c: DVec2) -> Option<DVec3> {
        dispatch!(self, s => s.point_at(c), _m => None)
    }

    /// Cartesian coordinates of `p` along the frame's u and v, from a flat shape's reference
    /// point (a plane's point, a disc's centre, a parallelogram's corner); `None` for curved
    /// shapes and meshes.
    pub fn plane_coordinates(&self, p: DVec3) -> Option<DVec2> {
        dispatch!(self, s => s.plane_coordinates(p), _m => None)
    }

    /// Axis-aligned bounds, or `None` for unbounded shapes.
    pub fn bounds(&self) -> Option<(DVec3, DVec3)> {
        dispatch!(self, s => s.bounds(), m => Some(m.bounds()))
    }
}
