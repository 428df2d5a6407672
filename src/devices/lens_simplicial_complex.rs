//! A lens simplicial complex (Dr TIM's `EditableLensSimplicialComplex` and
//! `IdealThinLensSimplicialComplex`): tetrahedral cells whose triangular faces are ideal thin
//! lenses, designed so that each cell, seen from outside through the lenses, appears as the
//! tetrahedron of the vertices' virtual-space positions (Courtial et al., "Ray-optical
//! transformation optics with ideal thin lenses makes omnidirectional lenses", Opt. Express 26,
//! 17872 (2018)).
//!
//! Faces are the triangles of the edges and cells the tetrahedra of four mutually joined
//! vertices that contain no other vertex, not even on their surface (Dr TIM's
//! `inferFacesFromEdges`, `inferSimplicesFromFaces`). In homogeneous coordinates X̃ = (X, 1), an ideal thin lens in the
//! plane φ·X̃ = 0 (unit normal n) is the elation L = I + u φᵀ with φ·u = 0: it fixes its plane
//! point by point, moves points along lines through its principal point C = u_xyz/u_w, and has
//! focal length f = 1/u_w for light crossing along n (1/z′ − 1/z = 1/f). Each cell K has a map
//! M_K to outside (virtual) space, the identity outside. As Dr TIM does, faces are worked out
//! from the outside inwards: the lens of the face between a known cell k and a new cell K
//! must image the physical position P of K's vertex off the face to Q = M_k⁻¹ V, where V is
//! that vertex's virtual position, which gives u = Q̃/(φ·Q̃) − P̃/(φ·P̃) and M_K = M_k L.
//! Every face, also those met from both sides, then needs M_K2⁻¹ M_K1 to be such a lens, and
//! every cell must take its vertices to their virtual positions; positions for which this
//! fails cannot be realised by ideal lenses and are refused.

use std::collections::{BTreeSet, HashMap, VecDeque};

use glam::{DMat4, DVec3, DVec4};
use serde::Deserialize;

use super::{EdgeDefaults, Edges, Face, LensDevice, LensType, Part};
use crate::keys::{Array, Coefficient, Positive, Vector};
use crate::math::Colour;
use crate::surfaces::ThinLens;

#[derive(Debug, Clone, PartialEq)]
pub struct LensSimplicialComplex {
    /// Physical-space vertex positions.
    pub vertices: Vec<DVec3>,
    /// Virtual-space positions of the same vertices.
    pub vertices_v: Vec<DVec3>,
    /// Pairs of vertex indices.
    pub edges: Vec<[usize; 2]>,
    pub lens_transmission_coefficient: f64,
    /// What each face is (Dr TIM's `lensTypeRepresentingFace`).
    pub lens_type: LensType,
    /// The radius of the edges and vertices of the virtual-space structure (Dr TIM's
    /// `vertexRadiusV`), shown in shiny red where given (Dr TIM's `showStructureV`).
    pub structure_v: Option<f64>,
}

/// Dr TIM's `EditableLensSimplicialComplex(description, parent, studio)`, an omnidirectional
/// lens (its `initialiseToOmnidirectionalLens()`): the physical-space vertices, ...
const DEFAULT_VERTICES: [[f64; 3]; 6] = [
    [-1.5, 1.1, 10.0],
    [1.0, 1.0, 10.0],
    [0.0, -0.5, 10.0],
    [0.0, 0.0, 10.6],
    [0.0, 0.0, 11.2],
    [0.0, 0.0, 12.0],
];

/// ... the virtual-space ones (the inner vertices raised by 0.2) ...
const DEFAULT_VERTICES_V: [[f64; 3]; 6] = [
    [-1.5, 1.1, 10.0],
    [1.0, 1.0, 10.0],
    [0.0, -0.5, 10.0],
    [0.0, 0.0, 10.8],
    [0.0, 0.0, 11.4],
    [0.0, 0.0, 12.0],
];

/// ... and the edges: those of the tetrahedral ideal-lens cloak (three base vertices 0–2, inner
/// vertices 3 and 4 and the top 5 on the axis), which Dr TIM's default complex shares.
pub(super) const CLOAK_EDGES: [[usize; 2]; 14] = [
    [0, 1],
    [1, 2],
    [2, 0],
    [3, 0],
    [3, 1],
    [3, 2],
    [4, 0],
    [4, 1],
    [4, 2],
    [5, 0],
    [5, 1],
    [5, 2],
    [3, 4],
    [4, 5],
];

/// Dr TIM's physical-space structure of its simplicial complexes: shown, radius 0.021,
/// `SurfaceColour.BLUE_SHINY`.
pub(super) const STRUCTURE: EdgeDefaults = EdgeDefaults {
    shown: true,
    radius: 0.021,
    colour: Colour::new(0.0, 0.0, 1.0),
};

/// Most vertices and edges a complex may have (Dr TIM's have tens): finding its faces and
/// cells takes time that grows faster than their numbers.
const MAX_VERTICES: usize = 500;
const MAX_EDGES: usize = 2000;

/// Tolerance of the consistency checks, in coordinates scaled to the complex's size.
const TOLERANCE: f64 = 1e-9;

/// A face's lens: `None` where the cells on either side see space alike (no lens is needed).
type FaceLens = Option<ThinLens>;

impl LensDevice for LensSimplicialComplex {
    /// The faces `face I-J-K` (vertex indices, from 0) that need a lens; with `edges`, the
    /// edges `edge I-J` and the vertices `vertex I` (Dr TIM's physical-space structure); with
    /// `structure_v`, the same at the virtual positions, `virtual edge I-J` and `virtual vertex
    /// I`.
    fn parts(&self, edges: Option<&Edges>) -> Result<Vec<Part>, String> {
        let mut complex = Complex::new(&self.vertices, &self.vertices_v, &self.edges)?;
        complex.maps = complex.cell_maps()?;
        complex.check_vertices()?;
        let mut parts = Vec::new();
        for (f, face) in complex.faces.iter().enumerate() {
            // A triangle of edges that bounds no cell has outside space on both sides.
            if complex.sides[f].is_empty() {
                continue;
            }
            let Some(lens) = complex.lens(f)? else {
                continue;
            };
            let lens = ThinLens {
                transmission_coefficient: self.lens_transmission_coefficient,
                ..lens
            };
            let corners = Face::Triangle(face.map(|i| self.vertices[i]));
            parts.extend(self.lens_type.part(face_name(*face), corners, lens)?);
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

/// A simplicial complex (Dr TIM's `SimplicialComplex`, its faces and cells inferred from its
/// edges) in coordinates centred on the physical vertices and scaled by their extent, with the
/// cells' maps to outside space where a kind of face has worked them out.
pub(super) struct Complex {
    pub centre: DVec3,
    pub scale: f64,
    /// The physical and virtual positions, scaled.
    pub p: Vec<DVec3>,
    pub v: Vec<DVec3>,
    pub edges: BTreeSet<[usize; 2]>,
    pub faces: Vec<[usize; 3]>,
    /// The cells on either side of each face (one for a face on the outside, none for a
    /// triangle of edges that bounds no cell).
    pub sides: Vec<Vec<usize>>,
    pub cells: Vec<[usize; 4]>,
    /// The four faces of each cell.
    cell_faces: Vec<[usize; 4]>,
    maps: Vec<DMat4>,
}

impl Complex {
    /// The faces and cells of the complex of these physical and virtual vertex positions and
    /// edges.
    pub fn new(
        vertices: &[DVec3],
        vertices_v: &[DVec3],
        edge_list: &[[usize; 2]],
    ) -> Result<Complex, String> {
        let n = vertices.len();
        if vertices_v.len() != n {
            return Err(format!(
                "there are {n} vertices but {} vertices_v",
                vertices_v.len()
            ));
        }
        if n > MAX_VERTICES || edge_list.len() > MAX_EDGES {
            return Err(format!(
                "a complex may have at most {MAX_VERTICES} vertices and {MAX_EDGES} edges, not {n} and {}",
                edge_list.len()
            ));
        }
        let mut edges = BTreeSet::new();
        for &[i, j] in edge_list {
            if i >= n || j >= n || i == j {
                return Err(format!(
                    "edge [{i}, {j}] must join two different vertices of the {n}"
                ));
            }
            edges.insert([i.min(j), i.max(j)]);
        }
        let centre = vertices.iter().sum::<DVec3>() / n.max(1) as f64;
        let scale = vertices
            .iter()
            .map(|p| (*p - centre).length())
            .fold(0.0, f64::max);
        if scale == 0.0 {
            return Err("the vertices must not all coincide".into());
        }
        let p: Vec<DVec3> = vertices.iter().map(|x| (*x - centre) / scale).collect();
        let v: Vec<DVec3> = vertices_v.iter().map(|x| (*x - centre) / scale).collect();
        let joined = |i: usize, j: usize| edges.contains(&[i.min(j), i.max(j)]);
        let mut faces = Vec::new();
        for &[i, j] in &edges {
            for k in j + 1..n {
                if joined(i, k) && joined(j, k) {
                    if (p[j] - p[i]).cross(p[k] - p[i]).length() <= TOLERANCE {
                        return Err(format!("face {i}-{j}-{k}: its vertices are in a line"));
                    }
                    faces.push([i, j, k]);
                }
            }
        }
        let mut cells = Vec::new();
        for &[i, j, k] in &faces {
            for l in k + 1..n {
                let cell = [i, j, k, l];
                if joined(i, l)
                    && joined(j, l)
                    && joined(k, l)
                    && volume(&p, cell).abs() > TOLERANCE
                    && !(0..n).any(|x| !cell.contains(&x) && inside(&p, cell, p[x]))
                {
                    cells.push(cell);
                }
            }
        }
        let index: HashMap<[usize; 3], usize> = faces
            .iter()
            .enumerate()
            .map(|(f, face)| (*face, f))
            .collect();
        let mut sides = vec![Vec::new(); faces.len()];
        let mut cell_faces = Vec::with_capacity(cells.len());
        for (k, &[i, j, l, m]) in cells.iter().enumerate() {
            let own = [[i, j, l], [i, j, m], [i, l, m], [j, l, m]].map(|face| index[&face]);
            for f in own {
                sides[f].push(k);
            }
            cell_faces.push(own);
        }
        if let Some(f) = (0..faces.len()).find(|&f| sides[f].len() > 2) {
            return Err(format!(
                "{} is a face of more than two cells, which overlap",
                face_name(faces[f])
            ));
        }
        Ok(Complex {
            centre,
            scale,
            p,
            v,
            edges,
            faces,
            sides,
            cells,
            cell_faces,
            maps: Vec::new(),
        })
    }

    /// With `edges`, the edges `edge I-J` and the vertices `vertex I` at `vertices` (Dr TIM's
    /// physical-space structure); with `structure_v`, the same of that radius in shiny red at
    /// `vertices_v`, `virtual edge I-J` and `virtual vertex I`.
    pub fn structure(
        &self,
        edges: Option<&Edges>,
        structure_v: Option<f64>,
        vertices: &[DVec3],
        vertices_v: &[DVec3],
    ) -> Result<Vec<Part>, String> {
        // Dr TIM's `SurfaceColour.RED_SHINY`.
        let structure_v = structure_v.map(|radius| Edges {
            radius,
            surface: EdgeDefaults::HIDDEN_RED.surface(),
        });
        let structures = [
            (edges, vertices, ""),
            (structure_v.as_ref(), vertices_v, "virtual "),
        ];
        let mut parts = Vec::new();
        for (shown, positions, space) in structures {
            let Some(e) = shown else { continue };
            for &[i, j] in &self.edges {
                let name = format!("{space}edge {i}-{j}");
                parts.push(e.part(name, positions[i], positions[j])?);
            }
            for (i, &at) in positions.iter().enumerate() {
                parts.push(e.vertex(format!("{space}vertex {i}"), at)?);
            }
        }
        Ok(parts)
    }

    /// Whether vertex `x` lies on the outside of the complex.
    pub fn on_outside(&self, x: usize) -> bool {
        self.sides
            .iter()
            .zip(&self.faces)
            .any(|(s, f)| s.len() == 1 && f.contains(&x))
    }

    /// The cells' maps to outside space, worked out from the outside inwards.
    fn cell_maps(&self) -> Result<Vec<DMat4>, String> {
        let mut maps: Vec<Option<DMat4>> = vec![None; self.cells.len()];
        let mut queue = VecDeque::new();
        // (face, known side: a cell or the outside)
        let mut next: Vec<(usize, Option<usize>)> = (0..self.faces.len())
            .filter(|&f| self.sides[f].len() == 1)
            .map(|f| (f, None))
            .collect();
        loop {
            for (f, known) in next.drain(..) {
                let outer = known.map_or(DMat4::IDENTITY, |k| maps[k].expect("known"));
                for &k in &self.sides[f] {
                    if Some(k) != known && maps[k].is_none() {
                        maps[k] = Some(outer * self.lens_into(f, k, outer)?);
                        queue.push_back(k);
                    }
                }
            }
            let Some(k) = queue.pop_front() else { break };
            next = self.cell_faces[k]
                .into_iter()
                .filter(|&f| self.sides[f].len() == 2)
                .map(|f| (f, Some(k)))
                .collect();
        }
        maps.into_iter()
            .enumerate()
            .map(|(k, m)| {
                m.ok_or_else(|| format!("cell {:?} cannot be reached from outside", self.cells[k]))
            })
            .collect()
    }

    /// The lens of face `f` that images the vertex of cell `k` off the face to where the map
    /// `outer` of the other side needs it: the elation I + u φᵀ taking P̃ to Q̃ = outer⁻¹ Ṽ.
    fn lens_into(&self, f: usize, k: usize, outer: DMat4) -> Result<DMat4, String> {
        let face = self.faces[f];
        let d = self.cells[k]
            .into_iter()
            .find(|x| !face.contains(x))
            .expect("a cell has a vertex off each of its faces");
        let phi = self.plane(f);
        let p = self.p[d].extend(1.0);
        let q = outer.inverse() * self.v[d].extend(1.0);
        let (zp, zq) = (phi.dot(p), phi.dot(q));
        if zq.abs() <= TOLERANCE * q.length() {
            return Err(format!(
                "{}: vertex {d}'s virtual position, seen through the lenses outside this face, would lie in the face's plane, where no lens can image it",
                face_name(face)
            ));
        }
        let u = q / zq - p / zp;
        Ok(DMat4::IDENTITY + outer_product(u, phi))
    }

    /// φ = (n, −n·A) of face `f`'s plane, n its unit normal (either way).
    pub fn plane(&self, f: usize) -> DVec4 {
        let [a, b, c] = self.faces[f].map(|i| self.p[i]);
        let n = (b - a).cross(c - a).normalize();
        n.extend(-n.dot(a))
    }

    /// Refuses virtual positions the cells' maps do not reach.
    fn check_vertices(&self) -> Result<(), String> {
        for (k, cell) in self.cells.iter().enumerate() {
            for &x in cell {
                let w = self.maps[k] * self.p[x].extend(1.0);
                let image = w.truncate() / w.w;
                if !(image - self.v[x])
                    .length()
                    .le(&(TOLERANCE * (1.0 + self.v[x].length())))
                {
                    return Err(format!(
                        "vertex {x}: the lenses image it to {}, not to its virtual position {} (in cell {cell:?}); {}",
                        self.centre + self.scale * image,
                        self.centre + self.scale * self.v[x],
                        if self.on_outside(x) {
                            "vertices on the outside of the complex must keep their physical positions"
                        } else {
                            "ideal lenses cannot realise these virtual positions"
                        }
                    ));
                }
            }
        }
        Ok(())
    }

    /// Face `f`'s lens: M₂⁻¹ M₁ (cell 1 to the other side) must be an elation of its plane.
    fn lens(&self, f: usize) -> Result<FaceLens, String> {
        let face = self.faces[f];
        let k1 = self.sides[f][0];
        let m2 = self.sides[f]
            .get(1)
            .map_or(DMat4::IDENTITY, |&k| self.maps[k]);
        let l = m2.inverse() * self.maps[k1];
        // φ with n pointing out of cell 1, so that f = 1/u_w for light leaving cell 1.
        let mut phi = self.plane(f);
        let d = self.cells[k1]
            .into_iter()
            .find(|x| !face.contains(x))
            .expect("a vertex off the face");
        if phi.dot(self.p[d].extend(1.0)) > 0.0 {
            phi = -phi;
        }
        let a = self.p[face[0]].extend(1.0);
        let s = (l * a).w;
        let name = face_name(face);
        let refuse = |why: &str| {
            format!(
                "{name}: the cells on either side would need it to {why}, which no ideal thin lens does; ideal lenses cannot realise these virtual vertex positions"
            )
        };
        if s.abs() <= TOLERANCE {
            return Err(refuse("move its own plane"));
        }
        let nl = l * (1.0 / s) - DMat4::IDENTITY;
        let off = (self.p[face[0]] + phi.truncate()).extend(1.0);
        let u = nl * off;
        let residue = nl - outer_product(u, phi);
        let largest = residue
            .to_cols_array()
            .iter()
            .fold(0.0f64, |m, x| m.max(x.abs()));
        if largest > TOLERANCE * (1.0 + u.length()) {
            return Err(refuse("map its own plane differently on either side"));
        }
        if u.length() <= TOLERANCE {
            return Ok(None);
        }
        if phi.dot(u).abs() > TOLERANCE * u.length() {
            return Err(refuse("image through a centre off its plane (a homology)"));
        }
        if u.w.abs() <= TOLERANCE * u.length() {
            return Err(refuse("shift space parallel to its plane"));
        }
        Ok(Some(ThinLens {
            principal_point: self.centre + self.scale * (u.truncate() / u.w),
            optical_axis: phi.truncate(),
            focal_length: self.scale / u.w,
            gradient: None,
            transmission_coefficient: 1.0,
        }))
    }
}

/// `face I-J-K`, how parts and messages name a face.
pub(super) fn face_name(face: [usize; 3]) -> String {
    format!("face {}-{}-{}", face[0], face[1], face[2])
}

/// u φᵀ.
fn outer_product(u: DVec4, phi: DVec4) -> DMat4 {
    DMat4::from_cols(u * phi.x, u * phi.y, u * phi.z, u * phi.w)
}

/// Six times the signed volume of the tetrahedron `cell`.
fn volume(p: &[DVec3], cell: [usize; 4]) -> f64 {
    let [a, b, c, d] = cell.map(|i| p[i]);
    (b - a).cross(c - a).dot(d - a)
}

/// Whether `x` is inside the tetrahedron `cell` or on its surface (Dr TIM's
/// `pointIsInsideSimplex`): a cell with another vertex on a face or edge is no simplex of the
/// complex.
fn inside(p: &[DVec3], cell: [usize; 4], x: DVec3) -> bool {
    let whole = volume(p, cell);
    (0..4).all(|i| {
        let mut corners = cell.map(|j| p[j]);
        corners[i] = x;
        let [a, b, c, d] = corners;
        (b - a).cross(c - a).dot(d - a) / whole >= -TOLERANCE
    })
}

/// `lenses = { type = "lens-simplicial-complex" }`: Dr TIM's
/// `EditableLensSimplicialComplex`, its vertices in physical and virtual space and its edges,
/// Dr TIM's omnidirectional lens where not given.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LensSimplicialComplexKeys {
    vertices: Option<Vec<Vector>>,
    vertices_v: Option<Vec<Vector>>,
    edges: Option<Vec<Array<usize, 2>>>,
    lens_transmission_coefficient: Option<Coefficient>,
    lens_type_representing_face: Option<LensType>,
    show_structure_v: Option<bool>,
    vertex_radius_v: Option<Positive>,
}

impl LensSimplicialComplexKeys {
    pub fn build(self) -> Result<Box<dyn LensDevice>, String> {
        let points = |v: Option<Vec<Vector>>, default: [[f64; 3]; 6]| match v {
            Some(v) => v.into_iter().map(|p| p.0).collect(),
            None => default.map(DVec3::from).to_vec(),
        };
        // Dr TIM's `vertexRadiusV`.
        let radius_v = self.vertex_radius_v.map_or(0.02, |r| r.0);
        Ok(Box::new(LensSimplicialComplex {
            vertices: points(self.vertices, DEFAULT_VERTICES),
            vertices_v: points(self.vertices_v, DEFAULT_VERTICES_V),
            edges: self.edges.map_or(CLOAK_EDGES.to_vec(), |e| {
                e.into_iter().map(|e| e.0).collect()
            }),
            // Dr TIM's is always `DEFAULT_TRANSMISSION_COEFFICIENT`.
            lens_transmission_coefficient: crate::keys::throughput(
                self.lens_transmission_coefficient,
            ),
            lens_type: self.lens_type_representing_face.unwrap_or_default(),
            structure_v: self.show_structure_v.unwrap_or(true).then_some(radius_v),
        }))
    }
}
