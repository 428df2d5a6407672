//! A simplicial complex of homogeneous planar imaging surfaces (Dr TIM's
//! `EditableHomogeneousPlanarImagingSurfaceSimplicialComplex` and
//! `HomogeneousPlanarImagingSurfaceSimplicialComplex`): tetrahedral cells, found from the edges
//! as for the [lens simplicial complex](super::LensSimplicialComplex), whose triangular faces
//! are gCLAs ([`HomogeneousPlanarImaging`]) such that each cell, seen from outside, appears as the
//! tetrahedron of its vertices' virtual positions.
//!
//! A homogeneous planar imaging surface is an affine map that fixes its plane, so each cell K
//! is seen through the affine map M_K that takes its four vertices to their virtual positions,
//! and outside space through the identity. Two cells sharing a face agree on its three vertices
//! and so on its plane, and the face is the imaging surface M_front⁻¹ M_behind: Dr TIM's
//! construction from the outside inwards gives the same surfaces, since its conjugate pairs are
//! vertices and their virtual positions seen through the faces in front. So every choice of
//! virtual positions is realised, provided the vertices on the outside stay where they are
//! (the outside is seen as it is) and no cell is seen flat.

use glam::{DMat3, DVec3};
use serde::Deserialize;

use super::lens_simplicial_complex::{Complex, STRUCTURE, face_name};
use super::{EdgeDefaults, Edges, LensDevice, Part};
use crate::geometry::{Shape, TriangleMesh};
use crate::keys::{Array, Coefficient, Positive, Vector, throughput};
use crate::surfaces::metatoys::{HomogeneousPlanarImaging, Transmission};
use crate::surfaces::{ConfocalLensletArrays, Surface};

#[derive(Debug, Clone, PartialEq)]
pub struct HomogeneousPlanarImagingSurfaceSimplicialComplex {
    /// Physical-space vertex positions.
    pub vertices: Vec<DVec3>,
    /// Virtual-space positions of the same vertices.
    pub vertices_v: Vec<DVec3>,
    /// Pairs of vertex indices.
    pub edges: Vec<[usize; 2]>,
    pub imaging_element_transmission_coefficient: f64,
    /// Whether the faces are there (Dr TIM's `showImagingElements`).
    pub show_imaging_elements: bool,
    /// The radius of the virtual-space structure, shown in shiny red where given.
    pub structure_v: Option<f64>,
}

/// An affine map x ↦ L x + t.
#[derive(Debug, Clone, Copy)]
struct Affine {
    linear: DMat3,
    shift: DVec3,
}

impl Affine {
    const IDENTITY: Affine = Affine {
        linear: DMat3::IDENTITY,
        shift: DVec3::ZERO,
    };

    fn apply(&self, x: DVec3) -> DVec3 {
        self.linear * x + self.shift
    }

    fn inverse_apply(&self, y: DVec3) -> DVec3 {
        self.linear.inverse() * (y - self.shift)
    }
}

/// Tolerance of the checks, in coordinates scaled to the complex's size.
const TOLERANCE: f64 = 1e-9;

impl HomogeneousPlanarImagingSurfaceSimplicialComplex {
    /// Each cell's map to outside space, after checking the outside vertices stay put.
    fn cell_maps(&self, complex: &Complex) -> Result<Vec<Affine>, String> {
        for x in 0..complex.p.len() {
            let moved = (complex.v[x] - complex.p[x]).length() > TOLERANCE;
            if moved && !complex.cells.iter().any(|c| c.contains(&x)) {
                return Err(format!(
                    "vertex {x} is in no cell of the complex, so nothing can show it at its virtual position {} (its physical one is {})",
                    self.vertices_v[x], self.vertices[x]
                ));
            }
            if moved && complex.on_outside(x) {
                return Err(format!(
                    "vertex {x} is on the outside of the complex, so its virtual position must be its physical one, {}, not {}",
                    self.vertices[x], self.vertices_v[x]
                ));
            }
        }
        complex
            .cells
            .iter()
            .map(|&[a, b, c, d]| {
                let span = |q: &[DVec3]| DMat3::from_cols(q[b] - q[a], q[c] - q[a], q[d] - q[a]);
                let (physical, seen) = (span(&complex.p), span(&complex.v));
                // Six times the scaled volume of the cell seen from outside.
                if seen.determinant().abs() <= TOLERANCE {
                    return Err(format!(
                        "the virtual positions of cell {a}-{b}-{c}-{d} lie in a plane: it would be seen flat"
                    ));
                }
                let linear = seen * physical.inverse();
                Ok(Affine {
                    linear,
                    shift: complex.v[a] - linear * complex.p[a],
                })
            })
            .collect()
    }
}

impl LensDevice for HomogeneousPlanarImagingSurfaceSimplicialComplex {
    /// With `show_imaging_elements`, the faces `face I-J-K` (each, as in Dr TIM, also one with
    /// the same map on both sides: gCLAs with η = 1 and δ = 0, which pass light on undeviated
    /// but dimmed); with `edges` and `structure_v`, the physical and virtual structures as the
    /// lens simplicial complex's.
    fn parts(&self, edges: Option<&Edges>) -> Result<Vec<Part>, String> {
        let complex = Complex::new(&self.vertices, &self.vertices_v, &self.edges)?;
        let maps = self.cell_maps(&complex)?;
        let mut parts = Vec::new();
        for (f, face) in complex.faces.iter().enumerate() {
            if !self.show_imaging_elements || complex.sides[f].is_empty() {
                continue;
            }
            // The normal points out of the first cell, which is behind the face.
            let behind = complex.sides[f][0];
            let front = complex.sides[f]
                .get(1)
                .map_or(Affine::IDENTITY, |&k| maps[k]);
            let off_face = complex.cells[behind]
                .into_iter()
                .find(|x| !face.contains(x))
                .expect("a cell has a vertex off each of its faces");
            let mut normal = complex.plane(f).truncate();
            if normal.dot(complex.p[off_face] - complex.p[face[0]]) > 0.0 {
                normal = -normal;
            }
            let inside = complex.p[off_face];
            let outside = front.inverse_apply(maps[behind].apply(inside));
            let unscaled = |x: DVec3| complex.centre + complex.scale * x;
            let name = face_name(*face);
            let imaging = HomogeneousPlanarImaging {
                point_on_plane: self.vertices[face[0]],
                a: normal,
                inside_position: unscaled(inside),
                outside_position: unscaled(outside),
            };
            let arrays = ConfocalLensletArrays::imaging(
                imaging,
                Transmission::Constant(self.imaging_element_transmission_coefficient),
            )
            .map_err(|e| format!("{name}: {e}"))?;
            let triangle =
                TriangleMesh::new(face.map(|i| self.vertices[i]).to_vec(), vec![[0, 1, 2]])
                    .map_err(|e| format!("{name}: {e}"))?;
            parts.push(Part {
                name,
                shape: Shape::TriangleMesh(triangle),
                surface: Surface::ConfocalLensletArrays(arrays),
                edge: false,
            });
        }
        parts.extend(complex.structure(
            edges,
            self.structure_v,
            &self.vertices,
            &self.vertices_v,
        )?);
        Ok(parts)
    }

    /// Dr TIM's physical-space structure: shown, radius 0.021, `SurfaceColour.BLUE_SHINY`.
    fn edge_defaults(&self) -> EdgeDefaults {
        STRUCTURE
    }
}

/// Dr TIM's `EditableHomogeneousPlanarImagingSurfaceSimplicialComplex(description, parent,
/// studio)`: a tetrahedron (0 back left, 1 back right, 2 front, on y = 0; 3 the top) with an
/// inner vertex 4, seen at (2, 0.75, 13) ...
const DEFAULT_VERTICES: [[f64; 3]; 5] = [
    [-1.0, 0.0, 11.0],
    [1.0, 0.0, 11.0],
    [0.0, 0.0, 9.0],
    [0.0, 1.0, 10.0],
    [0.0, 0.5, 10.0],
];

const DEFAULT_VERTEX_4_V: [f64; 3] = [2.0, 0.75, 13.0];

/// ... joined to every outer vertex.
const DEFAULT_EDGES: [[usize; 2]; 10] = [
    [0, 1],
    [1, 2],
    [2, 0],
    [0, 3],
    [1, 3],
    [2, 3],
    [0, 4],
    [1, 4],
    [2, 4],
    [3, 4],
];

/// `lenses = { type = "homogeneous-planar-imaging-surface-simplicial-complex" }`: Dr TIM's
/// `EditableHomogeneousPlanarImagingSurfaceSimplicialComplex`, its default where not given.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HomogeneousPlanarImagingSurfaceSimplicialComplexKeys {
    vertices: Option<Vec<Vector>>,
    vertices_v: Option<Vec<Vector>>,
    edges: Option<Vec<Array<usize, 2>>>,
    imaging_element_transmission_coefficient: Option<Coefficient>,
    show_imaging_elements: Option<bool>,
    show_structure_v: Option<bool>,
    vertex_radius_v: Option<Positive>,
}

impl HomogeneousPlanarImagingSurfaceSimplicialComplexKeys {
    pub fn build(self) -> Result<Box<dyn LensDevice>, String> {
        let given = |v: Option<Vec<Vector>>| v.map(|v| v.into_iter().map(|p| p.0).collect());
        let vertices: Vec<DVec3> =
            given(self.vertices).unwrap_or_else(|| DEFAULT_VERTICES.map(DVec3::from).to_vec());
        let vertices_v = given(self.vertices_v).unwrap_or_else(|| {
            let mut v = DEFAULT_VERTICES.map(DVec3::from).to_vec();
            v[4] = DEFAULT_VERTEX_4_V.into();
            v
        });
        Ok(Box::new(HomogeneousPlanarImagingSurfaceSimplicialComplex {
            vertices,
            vertices_v,
            edges: self.edges.map_or(DEFAULT_EDGES.to_vec(), |e| {
                e.into_iter().map(|e| e.0).collect()
            }),
            imaging_element_transmission_coefficient: throughput(
                self.imaging_element_transmission_coefficient,
            ),
            show_imaging_elements: self.show_imaging_elements.unwrap_or(true),
            // Dr TIM's `showVerticesV`, `showEdgesV` and `vertexRadiusV`.
            structure_v: self
                .show_structure_v
                .unwrap_or(true)
                .then_some(self.vertex_radius_v.map_or(0.02, |r| r.0)),
        }))
    }
}
