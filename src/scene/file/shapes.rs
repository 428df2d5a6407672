//! Shapes in scene files (`shape = { type = ..., ... }`), including mesh files.

use std::path::Path;

use glam::{DVec2, DVec3};
use serde::Deserialize;

use super::placement::TransformSection;
use super::values::{Direction, Finite, Positive, Vector, Vector2};
use crate::geometry::{
    Arrow, BilinearSurface, Cone, ConvexPolygon, Csg, CsgOperation, Cuboid, Cylinder, Disc,
    Ellipsoid, EllipticCylinder, FresnelLens, GeometryError, Masked, Paraboloid, Parallelepiped,
    Parallelogram, Plane, PlatonicKind, PlatonicSolid, Ruler, Shape, Sphere, SphericalCap,
    SphericalLens, TriangleMesh, TriangularPrism, Wedge, check_positive,
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
        /// The mantle alone, without the end caps.
        #[serde(default)]
        open: bool,
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
    Cone {
        apex: Vector,
        axis: Vector,
        half_angle_deg: Finite,
        height: Finite,
        /// The mantle alone, without the base.
        #[serde(default)]
        open: bool,
    },
    Ellipsoid {
        centre: Vector,
        semi_axes: Vector,
    },
    Paraboloid {
        vertex: Vector,
        axis: Vector,
        focal_length: Finite,
        height: Finite,
        /// The curved surface alone, without the cap.
        #[serde(default)]
        open: bool,
    },
    /// Its size by exactly one of `aperture_radius` and `half_angle_deg`.
    SphericalCap {
        sphere_centre: Vector,
        cap_centre: Vector,
        aperture_radius: Option<Finite>,
        half_angle_deg: Option<Finite>,
    },
    EllipticCylinder {
        start: Vector,
        end: Vector,
        semi_axes: Vector2,
        a_direction: Option<Vector>,
        /// The mantle alone, without the end caps.
        #[serde(default)]
        open: bool,
    },
    /// Dr TIM's arrow: a shaft and a conical tip at `end`.
    Arrow {
        start: Vector,
        end: Vector,
        shaft_radius: Option<Positive>,
        tip_length: Option<Positive>,
        tip_angle_deg: Option<Finite>,
    },
    /// A rod with tick marks every `tick_spacing` from `start`.
    Ruler {
        start: Vector,
        end: Vector,
        tick_spacing: Positive,
        radius: Option<Positive>,
        tick_direction: Option<Vector>,
        tick_length: Option<Positive>,
        major_every: Option<u32>,
    },
    /// A hollow cylinder: the difference of two with the same ends.
    Tube {
        start: Vector,
        end: Vector,
        outer_radius: Finite,
        inner_radius: Finite,
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
            ShapeSection::Cylinder {
                start,
                end,
                radius,
                open,
            } => {
                let closed = Cylinder::new(start.0, end.0, radius.0)?;
                if open {
                    Shape::EllipticCylinder(EllipticCylinder::new(
                        closed.start(),
                        closed.end(),
                        DVec2::splat(closed.radius()),
                        None,
                        true,
                    )?)
                } else {
                    Shape::Cylinder(closed)
                }
            }
            ShapeSection::Cone {
                apex,
                axis,
                half_angle_deg,
                height,
                open,
            } => Shape::Cone(Cone::new(apex.0, axis.0, half_angle_deg.0, height.0, open)?),
            ShapeSection::Ellipsoid { centre, semi_axes } => {
                Shape::Ellipsoid(Ellipsoid::new(centre.0, semi_axes.0)?)
            }
            ShapeSection::Paraboloid {
                vertex,
                axis,
                focal_length,
                height,
                open,
            } => Shape::Paraboloid(Paraboloid::new(
                vertex.0,
                axis.0,
                focal_length.0,
                height.0,
                open,
            )?),
            ShapeSection::SphericalCap {
                sphere_centre,
                cap_centre,
                aperture_radius,
                half_angle_deg,
            } => Shape::SphericalCap(match (aperture_radius, half_angle_deg) {
                (Some(r), None) => {
                    SphericalCap::with_aperture_radius(sphere_centre.0, cap_centre.0, r.0)?
                }
                (None, Some(angle)) => SphericalCap::new(sphere_centre.0, cap_centre.0, angle.0)?,
                _ => {
                    return Err(GeometryError::Degenerate(
                        "a spherical-cap needs exactly one of aperture_radius and half_angle_deg"
                            .into(),
                    ));
                }
            }),
            ShapeSection::EllipticCylinder {
                start,
                end,
                semi_axes,
                a_direction,
                open,
            } => Shape::EllipticCylinder(EllipticCylinder::new(
                start.0,
                end.0,
                semi_axes.0,
                a_direction.map(|a| a.0),
                open,
            )?),
            ShapeSection::Tube {
                start,
                end,
                outer_radius,
                inner_radius,
            } => tube(start.0, end.0, outer_radius.0, inner_radius.0)?,
            ShapeSection::Arrow {
                start,
                end,
                shaft_radius,
                tip_length,
                tip_angle_deg,
            } => {
                let default = Arrow::with_default_proportions(start.0, end.0);
                Arrow {
                    shaft_radius: shaft_radius.map_or(default.shaft_radius, |r| r.0),
                    tip_length: tip_length.map_or(default.tip_length, |l| l.0),
                    tip_angle_deg: tip_angle_deg.map_or(default.tip_angle_deg, |a| a.0),
                    ..default
                }
                .shape()?
            }
            ShapeSection::Ruler {
                start,
                end,
                tick_spacing,
                radius,
                tick_direction,
                tick_length,
                major_every,
            } => {
                let along = end.0 - start.0;
                let radius = radius.map_or(along.length() / 200.0, |r| r.0);
                let up = if along.reject_from(DVec3::Y).length() > 1e-6 * along.length() {
                    DVec3::Y
                } else {
                    DVec3::X
                };
                Ruler {
                    start: start.0,
                    end: end.0,
                    radius,
                    tick_spacing: tick_spacing.0,
                    tick_direction: tick_direction.map_or(up, |d| d.0),
                    tick_length: tick_length.map_or(4.0 * radius, |l| l.0),
                    major_every: major_every.unwrap_or(10),
                }
                .shape()?
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

/// The hollow cylinder between the radii: the outer cylinder less the inner one, whose caps
/// lie in the outer one's planes (the spans of a line through the hole cancel exactly there,
/// so the hole has no cap).
fn tube(start: DVec3, end: DVec3, outer: f64, inner: f64) -> Result<Shape, GeometryError> {
    check_positive("tube outer_radius", outer)?;
    check_positive("tube inner_radius", inner)?;
    if inner >= outer {
        return Err(GeometryError::OutOfRange {
            what: "tube inner_radius",
            range: format!("less than outer_radius ({outer})"),
            value: inner,
        });
    }
    let cylinder = |r| Cylinder::new(start, end, r).map(Shape::Cylinder);
    let tube = Csg::new(
        CsgOperation::Difference,
        vec![cylinder(outer)?, cylinder(inner)?],
    )?;
    Ok(Shape::Csg(tube.called("tube")))
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
