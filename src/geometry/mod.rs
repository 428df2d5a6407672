//! Shapes, exact in f64 (one file each), the scene's ray–geometry queries
//! ([`SceneGeometry`], on Embree), and where a ray meets a surface ([`Interaction`]).
//!
//! Every shape gives the nearest hit distance along a ray, the surface frame (u, v, w; w the
//! outward normal) at a surface point, and 2D surface coordinates (for chequerboards).

mod arrow;
mod axial;
mod bilinear_surface;
mod cell_walk;
mod cone;
mod convex_polygon;
mod csg;
mod cuboid;
mod cylinder;
mod disc;
mod ellipsoid;
mod elliptic_cylinder;
mod interaction;
mod lens_surface;
mod lenses;
mod lenslet_array;
mod masked;
mod paraboloid;
mod parallelepiped;
mod parallelogram;
mod plane;
mod platonic_solid;
mod polyhedron;
mod ruler;
mod scene_geometry;
mod sphere;
mod spherical_cap;
mod transform;
mod transformed;
mod triangle_mesh;
mod triangular_prism;
mod view_rotator;
mod wedge;

use glam::{DMat3, DVec2, DVec3};
use thiserror::Error;

pub use arrow::{Arrow, ArrowKeys};
pub use bilinear_surface::{BilinearSurface, BilinearSurfaceKeys};
pub use cone::{Cone, ConeKeys};
pub use convex_polygon::{ConvexPolygon, ConvexPolygonKeys};
pub use csg::{Csg, CsgOperation, DifferenceKeys, IntersectionKeys, InverseKeys, UnionKeys};
pub use cuboid::{Cuboid, CuboidKeys};
pub use cylinder::{Cylinder, CylinderKeys, TubeKeys};
pub use disc::{Disc, DiscKeys};
pub use ellipsoid::{Ellipsoid, EllipsoidKeys};
pub use elliptic_cylinder::{EllipticCylinder, EllipticCylinderKeys};
pub use interaction::{Exit, Interaction};
pub use lens_surface::{
    Ellipse, LensSurface, LensSurfaceKeys, PlaneSection, RefractiveIndex, lens_surface,
};
pub use lenses::{FresnelLens, FresnelLensKeys, SphericalLens, SphericalLensKeys};
pub use lenslet_array::{LensletArray, LensletArraySpec};
pub use masked::{Masked, MaskedKeys};
pub use paraboloid::{Paraboloid, ParaboloidKeys};
pub use parallelepiped::{Parallelepiped, ParallelepipedKeys};
pub use parallelogram::{Parallelogram, ParallelogramKeys};
pub use plane::{Plane, PlaneKeys};
pub use platonic_solid::{PlatonicKind, PlatonicSolid, PlatonicSolidKeys};
pub use polyhedron::{Polyhedral, Polyhedron};
pub use ruler::{Ruler, RulerKeys};
pub use scene_geometry::{Hit, ObjectArray, SceneGeometry};
pub use sphere::{Sphere, SphereKeys};
pub use spherical_cap::{SphericalCap, SphericalCapKeys};
pub use transform::{Transform, TransformKeys};
pub use transformed::{Transformed, TransformedKeys};
pub use triangle_mesh::{MeshKeys, TriangleMesh, TriangleMeshKeys};
pub use triangular_prism::{TriangularPrism, TriangularPrismKeys};
pub use view_rotator::{ViewRotator, ViewRotatorSpec};
pub use wedge::{Wedge, WedgeKeys};

use std::path::Path;

use crate::keys::kinds;
use crate::math::Frame;

kinds! {
    /// A `shape` table: its `type` names the shape, its other keys are the shape's own (read by
    /// the shape's `...Keys`, in the shape's file). A mesh file is loaded by
    /// [`MeshKeys::load`]; as a member of another shape it is an error.
    pub enum ShapeKeys -> Result<Shape, GeometryError> {
        Sphere(SphereKeys),
        Plane(PlaneKeys),
        Disc(DiscKeys),
        Cylinder(CylinderKeys),
        Parallelogram(ParallelogramKeys),
        Cuboid(CuboidKeys),
        Parallelepiped(ParallelepipedKeys),
        TriangularPrism(TriangularPrismKeys),
        Wedge(WedgeKeys),
        PlatonicSolid(PlatonicSolidKeys),
        ConvexPolygon(ConvexPolygonKeys),
        BilinearSurface(BilinearSurfaceKeys),
        Cone(ConeKeys),
        Ellipsoid(EllipsoidKeys),
        Paraboloid(ParaboloidKeys),
        SphericalCap(SphericalCapKeys),
        EllipticCylinder(EllipticCylinderKeys),
        Arrow(ArrowKeys),
        Ruler(RulerKeys),
        Tube(TubeKeys),
        #[serde(alias = "triangle_mesh")]
        TriangleMesh(TriangleMeshKeys),
        SphericalLens(SphericalLensKeys),
        FresnelLens(FresnelLensKeys),
        LensSurface(LensSurfaceKeys),
        Union(UnionKeys),
        Intersection(IntersectionKeys),
        Difference(DifferenceKeys),
        Inverse(InverseKeys),
        Masked(MaskedKeys),
        Transformed(TransformedKeys),
        Mesh(MeshKeys),
    }
}

impl ShapeKeys {
    /// The shape, or for a mesh file (relative to `dir`) one shape per object or group in the
    /// file, each with the part's name ("" for a single part).
    pub fn parts(self, dir: &Path) -> Result<Vec<(String, Shape)>, String> {
        if let ShapeKeys::Mesh(mesh) = self {
            return mesh.load(dir);
        }
        let shape = self.build().map_err(|e| e.to_string())?;
        Ok(vec![(String::new(), shape)])
    }
}

/// Invalid shape parameters.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum GeometryError {
    #[error("{what} must be a positive finite number, got {value}")]
    NotPositive { what: &'static str, value: f64 },
    #[error("{what} must be finite, got {value}")]
    NotFinite { what: &'static str, value: DVec3 },
    #[error("{what} must be a non-zero vector")]
    ZeroVector { what: &'static str },
    #[error("{what} must all be positive finite numbers, got {value}")]
    NotAllPositive { what: &'static str, value: String },
    #[error("{what} must be {range}, got {value}")]
    OutOfRange {
        what: &'static str,
        range: String,
        value: f64,
    },
    #[error("degenerate geometry: {0}")]
    Degenerate(String),
}

pub(crate) fn check_positive(what: &'static str, value: f64) -> Result<(), GeometryError> {
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

/// A finite linear map with an inverse that does not lose all precision.
fn check_invertible(m: DMat3) -> Result<(), GeometryError> {
    let size = m
        .to_cols_array()
        .iter()
        .fold(0.0, |a: f64, e| a.max(e.abs()));
    if m.is_finite() && m.determinant().abs() > 1e-12 * size.powi(3) {
        Ok(())
    } else {
        Err(GeometryError::Degenerate(format!(
            "singular transform: the matrix {:?} (rows) has no inverse",
            m.transpose().to_cols_array_2d()
        )))
    }
}

/// A finite, non-zero vector, normalised.
fn check_direction(what: &'static str, value: DVec3) -> Result<DVec3, GeometryError> {
    check_point(what, value)?;
    value
        .try_normalize()
        .ok_or(GeometryError::ZeroVector { what })
}

/// The smallest box around `points`.
fn point_bounds(points: &[DVec3]) -> (DVec3, DVec3) {
    points
        .iter()
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &p| {
            (lo.min(p), hi.max(p))
        })
}

/// A finite vector `u` with a part across the unit vector `axis` (what it must not be parallel
/// to is named `to`).
fn check_across(
    what: &'static str,
    u: DVec3,
    axis: DVec3,
    to: &'static str,
) -> Result<(), GeometryError> {
    check_point(what, u)?;
    if u.reject_from_normalized(axis).length() <= 1e-12 * u.length() {
        return Err(GeometryError::Degenerate(format!(
            "{what} must not be zero or parallel to {to}"
        )));
    }
    Ok(())
}

/// What every analytic shape gives: exact f64 hits, the surface frame and coordinates, and
/// bounds. A new shape implements it in its own file and is added to [`Shape`] and to
/// `dispatch!` below, one line each.
///
/// A shape may have several *parts* (the faces of a polyhedron, the pieces of a CSG solid):
/// `intersect` says which part it met, and the frame and coordinates there are the part's.
pub trait AnalyticShape {
    /// The nearest t in (t_min, t_max) where `origin + t direction` meets the surface, and the
    /// part met there (0 for shapes of one part). `direction` need not be a unit vector (a
    /// linear map hands its shape a stretched one); t is in units of it.
    fn intersect(
        &self,
        origin: DVec3,
        direction: DVec3,
        t_min: f64,
        t_max: f64,
    ) -> Option<(f64, u32)>;

    /// The surface frame at surface point `p` of part `part` (u, v, w; w the outward normal).
    fn frame(&self, p: DVec3, part: u32) -> Frame;

    /// The outward normal at surface point `p` of part `part`: the frame's w, exactly (shapes
    /// whose u and v cost something to compute give it alone).
    fn normal(&self, p: DVec3, part: u32) -> DVec3 {
        self.frame(p, part).w
    }

    /// The surface coordinates of surface point `p` of part `part` (units of length; see each
    /// shape).
    fn coordinates(&self, p: DVec3, part: u32) -> DVec2;

    /// The point with surface coordinates `c` (the inverse of [`Self::coordinates`]), or
    /// `None` if no point of the shape has them (or the shape has several parts).
    fn point_at(&self, _c: DVec2) -> Option<DVec3> {
        None
    }

    /// Cartesian coordinates of `p` along the frame's u and v from a flat shape's reference
    /// point; `None` for curved shapes.
    fn plane_coordinates(&self, _p: DVec3, _part: u32) -> Option<DVec2> {
        None
    }

    /// Whether the shape is flat (one plane), with [`Self::plane_coordinates`] everywhere.
    fn is_flat(&self) -> bool {
        false
    }

    /// The surface-coordinate axes at surface point `p` of part `part`: ∂p/∂c₁ and ∂p/∂c₂,
    /// the tangent vectors along which the [`Self::coordinates`] (c₁, c₂) grow (Dr TIM's
    /// `ParametrisedObject.getSurfaceCoordinateAxes`), in general neither unit vectors nor
    /// orthogonal. `None` where the coordinates are no chart (at a pole; on a cap where one of
    /// them is constant), and for shapes that do not give them.
    fn coordinate_axes(&self, _p: DVec3, _part: u32) -> Option<[DVec3; 2]> {
        None
    }

    /// Whether every part has [`Self::plane_coordinates`] or [`Self::coordinate_axes`]
    /// (except at isolated points, such as a sphere's poles): the coordinates a phase
    /// hologram's phase is given in.
    fn is_charted(&self) -> bool {
        self.is_flat()
    }

    /// Axis-aligned bounds, or `None` for unbounded shapes.
    fn bounds(&self) -> Option<(DVec3, DVec3)>;

    /// The convex solid this shape bounds, if it is one; constructive solid geometry combines
    /// only these (and its own results).
    fn solid(&self) -> Option<&dyn ConvexSolid> {
        None
    }
}

/// A shape that is the whole surface of a convex solid (a sphere, a capped cylinder, a
/// polyhedron; a plane bounds the half-space behind it).
pub trait ConvexSolid {
    /// Where the whole line `origin + t direction` (every real t) is inside the solid:
    /// entering and leaving, each with the part crossed; `None` if the line misses it. A
    /// half-space's span reaches ±∞ (part [`Span::NO_PART`] there).
    fn chord(&self, origin: DVec3, direction: DVec3) -> Option<Span>;

    /// Whether `p` is inside (points on the surface may go either way).
    fn contains(&self, p: DVec3) -> bool;
}

/// A stretch of a line inside a solid: from `enter` to `exit` (distances along the line, the
/// first below the second), with the parts of the surface crossed there.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Span {
    pub enter: (f64, u32),
    pub exit: (f64, u32),
}

impl Span {
    /// The part at an infinite end, where no surface is crossed.
    pub const NO_PART: u32 = u32::MAX;

    /// The nearer of the span's two crossings inside (t_min, t_max).
    pub fn nearest(&self, t_min: f64, t_max: f64) -> Option<(f64, u32)> {
        [self.enter, self.exit]
            .into_iter()
            .find(|&(t, part)| t > t_min && t < t_max && part != Span::NO_PART)
    }
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
            Shape::Cuboid($s) => $analytic,
            Shape::Parallelepiped($s) => $analytic,
            Shape::TriangularPrism($s) => $analytic,
            Shape::Wedge($s) => $analytic,
            Shape::PlatonicSolid($s) => $analytic,
            Shape::ConvexPolygon($s) => $analytic,
            Shape::BilinearSurface($s) => $analytic,
            Shape::Cone($s) => $analytic,
            Shape::Ellipsoid($s) => $analytic,
            Shape::Paraboloid($s) => $analytic,
            Shape::SphericalCap($s) => $analytic,
            Shape::EllipticCylinder($s) => $analytic,
            Shape::LensSurface($s) => $analytic,
            Shape::LensletArray($s) => $analytic,
            Shape::ViewRotator($s) => $analytic,
            Shape::Csg($s) => $analytic,
            Shape::Transformed($s) => $analytic,
            Shape::Masked($s) => $analytic,
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
    Cuboid(Cuboid),
    Parallelepiped(Parallelepiped),
    TriangularPrism(TriangularPrism),
    Wedge(Wedge),
    PlatonicSolid(PlatonicSolid),
    ConvexPolygon(ConvexPolygon),
    BilinearSurface(BilinearSurface),
    Cone(Cone),
    Ellipsoid(Ellipsoid),
    Paraboloid(Paraboloid),
    SphericalCap(SphericalCap),
    /// An elliptic cylinder, or a circular one without its end caps.
    EllipticCylinder(EllipticCylinder),
    /// Dr TIM's lens surface (the convex solid of one of positive focal length).
    LensSurface(LensSurface),
    /// A sheet of glass shaped into spherical lenslets (Dr TIM's `RefractiveLensletArray`).
    LensletArray(LensletArray),
    /// The glass of a refractive view rotator (Dr TIM's `RefractiveViewRotator`).
    ViewRotator(Box<ViewRotator>),
    /// Solids combined by constructive solid geometry.
    Csg(Csg),
    /// An analytic shape under a general linear map.
    Transformed(Transformed),
    /// A surface cut to the part inside a solid.
    Masked(Masked),
    TriangleMesh(TriangleMesh),
}

impl Shape {
    /// Nearest hit (t, primitive) with t_min < t < t_max; primitives are a mesh's triangles,
    /// or an analytic shape's parts.
    #[inline]
    pub fn intersect(
        &self,
        origin: DVec3,
        direction: DVec3,
        t_min: f64,
        t_max: f64,
    ) -> Option<(f64, u32)> {
        dispatch!(self,
            s => s.intersect(origin, direction, t_min, t_max),
            m => m.intersect(origin, direction, t_min, t_max))
    }

    /// Nearest hit of primitive `prim` (a mesh's triangle; an analytic shape as a whole).
    pub fn intersect_primitive(
        &self,
        prim: u32,
        origin: DVec3,
        direction: DVec3,
        t_min: f64,
        t_max: f64,
    ) -> Option<f64> {
        dispatch!(self,
            s => s.intersect(origin, direction, t_min, t_max).map(|h| h.0),
            m => m.intersect_triangle(prim, origin, direction, t_min, t_max))
    }

    /// Surface frame at surface point `p` of primitive `prim`.
    #[inline]
    pub fn frame(&self, p: DVec3, prim: u32) -> Frame {
        dispatch!(self, s => s.frame(p, prim), m => m.frame(p, prim))
    }

    /// Outward normal at surface point `p` of primitive `prim`: [`Self::frame`]'s w.
    #[inline]
    pub fn normal(&self, p: DVec3, prim: u32) -> DVec3 {
        dispatch!(self, s => s.normal(p, prim), m => m.frame(p, prim).w)
    }

    /// The frame a surface law sees for a ray arriving along `direction` at surface point `p`
    /// of primitive `prim`: [`Self::frame`], except that a mesh's interpolated (smooth) normal
    /// gives way to the triangle's own where the two disagree about the side the ray comes
    /// from, or where reflecting about the smooth normal would send the ray through the
    /// triangle (at silhouettes). Surface laws tell inside from outside by w, so that decision
    /// follows the geometry.
    pub fn frame_along(&self, p: DVec3, prim: u32, direction: DVec3) -> Frame {
        let f = self.frame(p, prim);
        let Shape::TriangleMesh(m) = self else {
            return f;
        };
        let g = m.face_normal(prim);
        let from_front = direction.dot(g) < 0.0;
        let reflected = direction - 2.0 * direction.dot(f.w) * f.w;
        if (direction.dot(f.w) < 0.0) == from_front && (reflected.dot(g) > 0.0) == from_front {
            f
        } else {
            Frame::from_normal_and_u(g, f.u)
        }
    }

    /// The outward normal w of [`Self::frame_along`], without the rest of the frame (shading
    /// needs no more): for a mesh without vertex normals, the triangle's own normal whichever
    /// way the ray comes, as `frame_along` has it on both of its branches.
    #[inline]
    pub fn normal_along(&self, p: DVec3, prim: u32, direction: DVec3) -> DVec3 {
        match self {
            Shape::TriangleMesh(m) if m.normals().is_none() => m.face_normal(prim).normalize(),
            Shape::TriangleMesh(_) => self.frame_along(p, prim, direction).w,
            shape => shape.normal(p, prim),
        }
    }

    /// Surface coordinates of surface point `p` of primitive `prim` (units of length; see
    /// each shape).
    pub fn coordinates(&self, p: DVec3, prim: u32) -> DVec2 {
        dispatch!(self, s => s.coordinates(p, prim), m => m.coordinates(p, prim))
    }

    /// The point with surface coordinates `c` (inverse of [`Self::coordinates`]; a cylinder's
    /// mantle), or `None` if no point of the shape has them, or for meshes.
    pub fn point_at(&self, c: DVec2) -> Option<DVec3> {
        dispatch!(self, s => s.point_at(c), _m => None)
    }

    /// Cartesian coordinates of `p` along the frame's u and v, from a flat shape's reference
    /// point (a plane's point, a disc's centre, a parallelogram's corner); `None` for curved
    /// shapes and meshes.
    pub fn plane_coordinates(&self, p: DVec3, prim: u32) -> Option<DVec2> {
        dispatch!(self, s => s.plane_coordinates(p, prim), _m => None)
    }

    /// The surface-coordinate axes ∂p/∂c₁, ∂p/∂c₂ at surface point `p` of primitive `prim`
    /// (see [`AnalyticShape::coordinate_axes`]); `None` for meshes.
    pub fn coordinate_axes(&self, p: DVec3, prim: u32) -> Option<[DVec3; 2]> {
        dispatch!(self, s => s.coordinate_axes(p, prim), _m => None)
    }

    /// Whether every part has plane coordinates or coordinate axes (see
    /// [`AnalyticShape::is_charted`]); meshes have neither.
    pub fn is_charted(&self) -> bool {
        dispatch!(self, s => s.is_charted(), _m => false)
    }

    /// Axis-aligned bounds, or `None` for unbounded shapes.
    pub fn bounds(&self) -> Option<(DVec3, DVec3)> {
        dispatch!(self, s => s.bounds(), m => Some(m.bounds()))
    }

    /// Whether the shape is flat (see [`AnalyticShape::is_flat`]); meshes count as curved.
    pub fn is_flat(&self) -> bool {
        dispatch!(self, s => s.is_flat(), _m => false)
    }

    /// The convex solid the shape bounds, if it is one.
    pub fn analytic_solid(&self) -> Option<&dyn ConvexSolid> {
        dispatch!(self, s => s.solid(), _m => None)
    }

    /// Whether the shape bounds a solid that constructive solid geometry can combine: a
    /// convex solid or a CSG result.
    pub fn is_solid(&self) -> bool {
        matches!(self, Shape::Csg(_)) || self.analytic_solid().is_some()
    }

    /// Whether `p` is inside the solid the shape bounds (false for shapes that bound none;
    /// points on the surface may go either way).
    pub fn contains(&self, p: DVec3) -> bool {
        match self {
            Shape::Csg(c) => c.contains(p),
            s => s.analytic_solid().is_some_and(|s| s.contains(p)),
        }
    }

    /// The shape's kind as scene files name it ("sphere", "union", ...; "cone with open =
    /// true" for an open one), for reports.
    pub fn kind(&self) -> &'static str {
        match self {
            Shape::Sphere(_) => "sphere",
            Shape::Plane(_) => "plane",
            Shape::Disc(_) => "disc",
            Shape::Cylinder(_) => "cylinder",
            Shape::Parallelogram(_) => "parallelogram",
            Shape::Cuboid(_) => "cuboid",
            Shape::Parallelepiped(_) => "parallelepiped",
            Shape::TriangularPrism(_) => "triangular-prism",
            Shape::Wedge(_) => "wedge",
            Shape::PlatonicSolid(_) => "platonic-solid",
            Shape::ConvexPolygon(_) => "convex-polygon",
            Shape::BilinearSurface(_) => "bilinear-surface",
            Shape::Csg(c) => c.kind(),
            Shape::Cone(c) => c.kind(),
            Shape::Ellipsoid(_) => "ellipsoid",
            Shape::Paraboloid(p) => p.kind(),
            Shape::SphericalCap(_) => "spherical-cap",
            Shape::EllipticCylinder(e) => e.kind(),
            Shape::LensSurface(_) => "lens-surface",
            Shape::LensletArray(_) => "refractive-lenslet-array",
            Shape::ViewRotator(_) => "refractive-view-rotator",
            Shape::Transformed(t) => t.inner().kind(),
            Shape::Masked(_) => "masked",
            Shape::TriangleMesh(_) => "triangle mesh",
        }
    }
}

#[cfg(test)]
mod tests {
    use glam::{DAffine3, DMat3, DVec2, DVec3};

    use super::*;

    /// The curved shapes with coordinate axes, each with a box of surface coordinates inside
    /// its chart (away from poles, seams and rims).
    fn charted_shapes() -> Vec<(Shape, DVec2, DVec2)> {
        let turn = DMat3::from_axis_angle(DVec3::new(1.0, 2.0, -0.5).normalize(), 0.7);
        let sphere = Sphere::new(DVec3::new(0.3, -0.2, 1.0), 1.5).unwrap();
        let shear = DAffine3::from_mat3_translation(
            DMat3::from_cols(
                DVec3::new(1.0, 0.2, 0.0),
                DVec3::new(0.5, 1.5, -0.3),
                DVec3::new(0.0, 0.4, 0.8),
            ),
            DVec3::new(1.0, 2.0, 3.0),
        );
        let r = 1.5;
        vec![
            (
                Shape::Sphere(sphere.clone().rotated(turn)),
                DVec2::new(-2.5 * r, 0.3 * r),
                DVec2::new(2.5 * r, 2.8 * r),
            ),
            (
                Shape::Ellipsoid(Ellipsoid::new(DVec3::ONE, DVec3::new(1.0, 2.0, 0.5)).unwrap()),
                DVec2::new(-2.5, 0.3),
                DVec2::new(2.5, 2.8),
            ),
            (
                Shape::Paraboloid(
                    Paraboloid::new(DVec3::ZERO, DVec3::new(0.2, 1.0, 0.1), 0.7, 2.0, false)
                        .unwrap(),
                ),
                DVec2::splat(-1.5),
                DVec2::splat(1.5),
            ),
            (
                Shape::SphericalCap(
                    SphericalCap::new(DVec3::ZERO, DVec3::new(0.0, 0.6, 0.8), 80.0).unwrap(),
                ),
                DVec2::new(-3.0, 0.1),
                DVec2::new(3.0, 1.3),
            ),
            (
                Shape::EllipticCylinder(
                    EllipticCylinder::new(
                        DVec3::ZERO,
                        DVec3::new(0.0, 0.0, 3.0),
                        DVec2::new(1.0, 0.5),
                        Some(DVec3::new(1.0, 1.0, 0.0)),
                        true,
                    )
                    .unwrap(),
                ),
                DVec2::new(-2.0, 0.1),
                DVec2::new(2.0, 2.9),
            ),
            (
                Shape::Cone(
                    Cone::new(DVec3::ONE, DVec3::new(0.0, -1.0, 1.0), 30.0, 2.0, true).unwrap(),
                ),
                DVec2::new(-3.0, 0.2),
                DVec2::new(3.0, 1.9),
            ),
            (
                Shape::BilinearSurface(
                    BilinearSurface::new([
                        DVec3::ZERO,
                        DVec3::new(2.0, 0.0, 0.3),
                        DVec3::new(2.5, 1.5, -0.4),
                        DVec3::new(0.0, 1.0, 0.5),
                    ])
                    .unwrap(),
                ),
                DVec2::splat(0.05),
                DVec2::new(1.9, 1.0),
            ),
            (
                Shape::Transformed(Transformed::new(Shape::Sphere(sphere), shear).unwrap()),
                DVec2::new(-2.5 * r, 0.3 * r),
                DVec2::new(2.5 * r, 2.8 * r),
            ),
        ]
    }

    /// The coordinate axes are the derivatives of `point_at`, the inverse of `coordinates`
    /// (central differences, a construction of the same vectors another way), and tangent.
    #[test]
    fn coordinate_axes_are_the_derivatives_of_the_surface_point() {
        let h = 1e-5;
        for (shape, lo, hi) in charted_shapes() {
            assert!(shape.is_charted(), "{}", shape.kind());
            for i in 0..=6 {
                for j in 0..=6 {
                    let c = lo + (hi - lo) * DVec2::new(i as f64, j as f64) / 6.0;
                    let p = shape.point_at(c).unwrap();
                    assert!(
                        shape.coordinates(p, 0).distance(c) < 1e-9,
                        "{}",
                        shape.kind()
                    );
                    let axes = shape.coordinate_axes(p, 0).unwrap();
                    let n = shape.normal(p, 0);
                    for (k, e) in [DVec2::X, DVec2::Y].into_iter().enumerate() {
                        let at = |s: f64| shape.point_at(c + s * h * e).unwrap();
                        let derivative = (at(1.0) - at(-1.0)) / (2.0 * h);
                        assert!(
                            axes[k].distance(derivative) < 1e-7 * (1.0 + derivative.length()),
                            "{} at {c}: axis {k} {} against {derivative}",
                            shape.kind(),
                            axes[k]
                        );
                        assert!(axes[k].dot(n).abs() < 1e-12 * (1.0 + axes[k].length()));
                    }
                }
            }
        }
    }

    /// Shapes with a part without a chart (a closed cylinder's or cone's caps, on which one
    /// coordinate is constant) and meshes are not charted; flat shapes and polyhedra are, by
    /// their plane coordinates.
    #[test]
    fn shapes_with_caps_of_constant_coordinates_are_not_charted() {
        let cylinder = Cylinder::new(DVec3::ZERO, DVec3::Z, 1.0).unwrap();
        assert!(!Shape::Cylinder(cylinder).is_charted());
        let cone = |open| Cone::new(DVec3::ZERO, DVec3::Z, 30.0, 1.0, open).unwrap();
        assert!(!Shape::Cone(cone(false)).is_charted());
        assert!(Shape::Cone(cone(true)).is_charted());
        let cuboid = Cuboid::new(DVec3::ZERO, DVec3::ONE).unwrap();
        assert!(Shape::Cuboid(cuboid).is_charted());
        let disc = Disc::new(DVec3::ZERO, DVec3::Z, 1.0).unwrap();
        assert!(Shape::Disc(disc).is_charted());
    }
}
