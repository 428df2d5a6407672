//! Shapes in scene files (`shape = { type = ..., ... }`), including mesh files.

use std::path::Path;

use glam::DVec3;
use serde::Deserialize;

use super::placement::TransformSection;
use super::values::{Direction, Finite, Positive, Vector};
use crate::geometry::{
    BilinearSurface, ConvexPolygon, Csg, CsgOperation, Cuboid, Cylinder, Disc, FresnelLens,
    GeometryError, Masked, Parallelepiped, Parallelogram, Plane, PlatonicKind, PlatonicSolid,
    Shape, Sphere, SphericalLens, TriangleMesh, TriangularPrism, Wedge,
};
use crate::mesh;

#[derive(Debug, Deserialize)]
#[serde(tag = "type", rename_all = "kebab-case", deny_unknown_fields)]
pub(super) enum ShapeSection {
    Sphere {
        centre: Vector,
        radius: Positive,
    },
    Plane {
        point: Vector,
        normal: Vector,
        u_direction: Option<Vector>,
    },
    Disc {
        centre: Vector,
        normal: Vector,
        radius: Positive,
    },
    Cylinder {
        start: Vector,
        end: Vector,
        radius: Positive,
    },
    Parallelogram {
        corner: Vector,
        span_u: Vector,
        span_v: Vector,
    },
    Cuboid {
        centre: Vector,
        size: [Positive; 3],
    },
    Parallelepiped {
        centre: Vector,
        edges: [Vector; 3],
    },
    TriangularPrism {
        vertices: [Vector; 3],
        extrusion: Vector,
    },
    Wedge {
        apex_edge_centre: Vector,
        apex_edge_direction: Direction,
        bisector_direction: Direction,
        apex_angle_deg: Positive,
        leg_length: Positive,
        apex_edge_length: Positive,
    },
    PlatonicSolid {
        solid: SolidName,
        centre: Vector,
        radius: Positive,
    },
    ConvexPolygon {
        vertices: Vec<Vector>,
    },
    BilinearSurface {
        corners: [Vector; 4],
    },
    #[serde(alias = "triangle_mesh")]
    TriangleMesh {
        vertices: Vec<Vector>,
        triangles: Vec<[u32; 3]>,
    },
    /// A thick lens with spherical or flat surfaces.
    SphericalLens {
        centre: Vector,
        axis: Vector,
        front_radius: Option<Finite>,
        back_radius: Option<Finite>,
        thickness: Positive,
        aperture_radius: Positive,
    },
    /// A plano-convex Fresnel lens.
    FresnelLens {
        centre: Vector,
        axis: Vector,
        radius_of_curvature: Positive,
        aperture_radius: Positive,
        zones: u32,
        thickness: Positive,
    },
    /// Constructive solid geometry: inside any member.
    Union {
        of: Vec<ShapeSection>,
    },
    /// Inside every member.
    Intersection {
        of: Vec<ShapeSection>,
    },
    /// Inside the first member and outside the others.
    Difference {
        of: Vec<ShapeSection>,
    },
    /// Outside the member.
    Inverse {
        of: Box<ShapeSection>,
    },
    /// A surface where it lies inside a solid.
    Masked {
        of: Box<ShapeSection>,
        mask: Box<ShapeSection>,
    },
    /// A shape under its own transform (in the coordinates of the entry it is in).
    Transformed {
        of: Box<ShapeSection>,
        transform: TransformSection,
    },
    /// A mesh file (OBJ or PLY), relative to the scene file.
    Mesh {
        file: String,
        /// Shade with the file's vertex normals, if it has them.
        #[serde(default = "super::yes")]
        smooth: bool,
    },
}

/// A Platonic solid's name (of a `platonic-solid` shape or a `platonic-lens` device).
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub(super) enum SolidName {
    Tetrahedron,
    Cube,
    Octahedron,
    Dodecahedron,
    Icosahedron,
}

impl SolidName {
    pub(super) fn kind(self) -> PlatonicKind {
        match self {
            SolidName::Tetrahedron => PlatonicKind::Tetrahedron,
            SolidName::Cube => PlatonicKind::Cube,
            SolidName::Octahedron => PlatonicKind::Octahedron,
            SolidName::Dodecahedron => PlatonicKind::Dodecahedron,
            SolidName::Icosahedron => PlatonicKind::Icosahedron,
        }
    }
}

impl ShapeSection {
    /// The shape, or for a mesh file one shape per object or group in the file, with the part's
    /// name ("" for a single part). Mesh paths are relative to `dir`.
    pub(super) fn build(self, dir: &Path) -> Result<Vec<(String, Shape)>, String> {
        let shape = match self {
            ShapeSection::Mesh { file, smooth } => return load_mesh(&dir.join(file), smooth),
            other => other.build_analytic(),
        };
        shape
            .map(|s| vec![(String::new(), s)])
            .map_err(|e| e.to_string())
    }

    fn build_analytic(self) -> Result<Shape, GeometryError> {
        Ok(match self {
            ShapeSection::Sphere { centre, radius } => {
                Shape::Sphere(Sphere::new(centre.0, radius.0)?)
            }
            ShapeSection::Plane {
                point,
                normal,
                u_direction,
            } => {
                let u = u_direction.map_or_else(|| normal.0.any_orthogonal_vector(), |u| u.0);
                Shape::Plane(Plane::new(point.0, normal.0, u)?)
            }
            ShapeSection::Disc {
                centre,
                normal,
                radius,
            } => Shape::Disc(Disc::new(centre.0, normal.0, radius.0)?),
            ShapeSection::Cylinder { start, end, radius } => {
                Shape::Cylinder(Cylinder::new(start.0, end.0, radius.0)?)
            }
            ShapeSection::Parallelogram {
                corner,
                span_u,
                span_v,
            } => Shape::Parallelogram(Parallelogram::new(corner.0, span_u.0, span_v.0)?),
            ShapeSection::Cuboid { centre, size } => {
                let [x, y, z] = size.map(|s| s.0);
                Shape::Cuboid(Cuboid::new(centre.0, DVec3::new(x, y, z))?)
            }
            ShapeSection::Parallelepiped { centre, edges } => {
                Shape::Parallelepiped(Parallelepiped::new(centre.0, edges.map(|e| e.0))?)
            }
            ShapeSection::TriangularPrism {
                vertices,
                extrusion,
            } => Shape::TriangularPrism(TriangularPrism::new(vertices.map(|v| v.0), extrusion.0)?),
            ShapeSection::Wedge {
                apex_edge_centre,
                apex_edge_direction,
                bisector_direction,
                apex_angle_deg,
                leg_length,
                apex_edge_length,
            } => Shape::Wedge(Wedge::new(
                apex_edge_centre.0,
                apex_edge_direction.0,
                bisector_direction.0,
                apex_angle_deg.0.to_radians(),
                leg_length.0,
                apex_edge_length.0,
            )?),
            ShapeSection::PlatonicSolid {
                solid,
                centre,
                radius,
            } => Shape::PlatonicSolid(PlatonicSolid::new(solid.kind(), centre.0, radius.0)?),
            ShapeSection::ConvexPolygon { vertices } => Shape::ConvexPolygon(ConvexPolygon::new(
                vertices.into_iter().map(|v| v.0).collect(),
            )?),
            ShapeSection::BilinearSurface { corners } => {
                Shape::BilinearSurface(BilinearSurface::new(corners.map(|c| c.0))?)
            }
            ShapeSection::TriangleMesh {
                vertices,
                triangles,
            } => Shape::TriangleMesh(TriangleMesh::new(
                vertices.into_iter().map(|v| v.0).collect(),
                triangles,
            )?),
            ShapeSection::SphericalLens {
                centre,
                axis,
                front_radius,
                back_radius,
                thickness,
                aperture_radius,
            } => SphericalLens {
                centre: centre.0,
                axis: axis.0,
                front_radius: front_radius.map(|r| r.0),
                back_radius: back_radius.map(|r| r.0),
                thickness: thickness.0,
                aperture_radius: aperture_radius.0,
            }
            .shape()?,
            ShapeSection::FresnelLens {
                centre,
                axis,
                radius_of_curvature,
                aperture_radius,
                zones,
                thickness,
            } => FresnelLens {
                centre: centre.0,
                axis: axis.0,
                radius_of_curvature: radius_of_curvature.0,
                aperture_radius: aperture_radius.0,
                zones,
                thickness: thickness.0,
            }
            .shape()?,
            ShapeSection::Union { of } => csg(CsgOperation::Union, of)?,
            ShapeSection::Intersection { of } => csg(CsgOperation::Intersection, of)?,
            ShapeSection::Difference { of } => csg(CsgOperation::Difference, of)?,
            ShapeSection::Inverse { of } => csg(CsgOperation::Inverse, vec![*of])?,
            ShapeSection::Masked { of, mask } => {
                Shape::Masked(Masked::new(of.member("masked")?, mask.member("masked")?)?)
            }
            ShapeSection::Transformed { of, transform } => {
                transform.build()?.shape(&of.member("transformed")?)?
            }
            ShapeSection::Mesh { .. } => unreachable!("mesh files are loaded by `build`"),
        })
    }

    /// The analytic shape a CSG operation or a transform takes (mesh files are refused).
    fn member(self, of: &str) -> Result<Shape, GeometryError> {
        match self {
            ShapeSection::Mesh { file, .. } => Err(GeometryError::Degenerate(format!(
                "a mesh file ('{file}') cannot be a member of a {of} shape"
            ))),
            other => other.build_analytic(),
        }
    }
}

/// `operation` on the members' shapes.
fn csg(operation: CsgOperation, of: Vec<ShapeSection>) -> Result<Shape, GeometryError> {
    let members = of
        .into_iter()
        .map(|m| m.member(operation.name()))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(Shape::Csg(Csg::new(operation, members)?))
}

/// The parts of a mesh file as triangle meshes.
fn load_mesh(path: &Path, smooth: bool) -> Result<Vec<(String, Shape)>, String> {
    let meshes = mesh::load(path).map_err(|e| e.to_string())?;
    let single = meshes.len() == 1;
    meshes
        .into_iter()
        .enumerate()
        .filter(|(_, m)| !m.triangles.is_empty())
        .map(|(i, m)| {
            let name = match (single, m.name.is_empty()) {
                (true, _) => String::new(),
                (false, true) => format!("part {}", i + 1),
                (false, false) => m.name.clone(),
            };
            let normals = m.normals.filter(|_| smooth);
            let part = if single {
                String::new()
            } else {
                format!(" (part '{name}')")
            };
            TriangleMesh::with_normals(m.vertices, m.triangles, normals)
                .map(|t| (name, Shape::TriangleMesh(t)))
                .map_err(|e| format!("{}{part}: {e}", path.display()))
        })
        .collect()
}
