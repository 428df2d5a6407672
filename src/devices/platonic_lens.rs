//! The Platonic lens (Dr TIM's `EditablePlatonicLens`, "a 3D generalisation of the star of
//! lenses"): for every edge of a Platonic solid, the triangle spanned by the edge and the
//! solid's centre is an ideal thin lens of focal length f, its principal point at the centre
//! and its optical axis normal to the triangle.
//!
//! The lenses that meet along the line from the centre to a vertex form a lens star about it:
//! equally spaced round it (by the solid's symmetry), with their principal points on it, so a
//! ray that goes once round that line, through each of them, closes on itself
//! ([`super::LensStar`]).
//!
//! The solid is Dr TIM's (`PlatonicSolidType`): circumradius `radius` about `centre`, in the
//! orientation of its vertex tables, read along the orthonormal basis made from
//! `basis_vector_1` and `basis_vector_2` (the third their cross product). Its vertices are
//! worked out here exactly: the tetrahedron with a vertex on +z, the cube's (±1, ±1, ±1)/√3,
//! the octahedron's ±x, ±y, ±z, the icosahedron with vertices on ±z and two rings of five at
//! z = ±1/√5 (the upper ring at azimuths 72°k, the lower at 36° + 72°k), and the dodecahedron
//! as the icosahedron's dual (its face centres, normalised). The edges join the vertices at the
//! shortest distance.

use glam::DVec3;

use super::{Edges, Part};
use crate::geometry::{Shape, TriangleMesh};
use crate::surfaces::{Surface, ThinLens};

/// The five Platonic solids.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlatonicSolid {
    Tetrahedron,
    Cube,
    Octahedron,
    Dodecahedron,
    Icosahedron,
}

impl PlatonicSolid {
    /// The vertices, at distance 1 from the origin.
    pub fn vertices(self) -> Vec<DVec3> {
        match self {
            PlatonicSolid::Tetrahedron => {
                let (a, b) = (2f64.sqrt() / 3.0, (2.0f64 / 3.0).sqrt());
                vec![
                    DVec3::Z,
                    DVec3::new(-a, -b, -1.0 / 3.0),
                    DVec3::new(-a, b, -1.0 / 3.0),
                    DVec3::new(2.0 * a, 0.0, -1.0 / 3.0),
                ]
            }
            PlatonicSolid::Cube => (0..8)
                .map(|i| {
                    let sign = |bit: u32| if i & (1 << bit) == 0 { -1.0 } else { 1.0 };
                    DVec3::new(sign(2), sign(1), sign(0)) / 3f64.sqrt()
                })
                .collect(),
            PlatonicSolid::Octahedron => {
                vec![
                    DVec3::X,
                    -DVec3::X,
                    DVec3::Y,
                    -DVec3::Y,
                    DVec3::Z,
                    -DVec3::Z,
                ]
            }
            PlatonicSolid::Icosahedron => {
                let (z, r) = (1.0 / 5f64.sqrt(), 2.0 / 5f64.sqrt());
                let ring = |z: f64, offset_deg: f64| {
                    (0..5).map(move |k| {
                        let (sin, cos) = (offset_deg + 72.0 * k as f64).to_radians().sin_cos();
                        DVec3::new(r * cos, r * sin, z)
                    })
                };
                [DVec3::Z, -DVec3::Z]
                    .into_iter()
                    .chain(ring(z, 0.0))
                    .chain(ring(-z, 36.0))
                    .collect()
            }
            PlatonicSolid::Dodecahedron => {
                let v = PlatonicSolid::Icosahedron.vertices();
                let e = edges(&v);
                let joined = |i: usize, j: usize| e.contains(&[i.min(j), i.max(j)]);
                let mut centres = Vec::new();
                for &[i, j] in &e {
                    for k in j + 1..v.len() {
                        if joined(i, k) && joined(j, k) {
                            centres.push((v[i] + v[j] + v[k]).normalize());
                        }
                    }
                }
                centres
            }
        }
    }
}

/// The pairs of `vertices` (i < j) at the shortest distance between any two of them.
fn edges(vertices: &[DVec3]) -> Vec<[usize; 2]> {
    let pairs =
        || (0..vertices.len()).flat_map(move |i| (i + 1..vertices.len()).map(move |j| [i, j]));
    let length = |[i, j]: [usize; 2]| vertices[i].distance(vertices[j]);
    let shortest = pairs().map(length).fold(f64::INFINITY, f64::min);
    pairs()
        .filter(|&p| length(p) < shortest * (1.0 + 1e-9))
        .collect()
}

#[derive(Debug, Clone, PartialEq)]
pub struct PlatonicLens {
    pub platonic_solid: PlatonicSolid,
    pub centre: DVec3,
    /// The circumradius (positive).
    pub radius: f64,
    /// The directions the vertex tables' x and y are read along (not parallel; made
    /// orthonormal).
    pub basis_vector_1: DVec3,
    pub basis_vector_2: DVec3,
    /// f of every lens; non-zero.
    pub focal_length: f64,
    pub lens_transmission_coefficient: f64,
}

impl PlatonicLens {
    /// The solid's vertices, placed.
    pub fn vertices(&self) -> Result<Vec<DVec3>, String> {
        let x = self.basis_vector_1.normalize();
        let y = self.basis_vector_2.reject_from_normalized(x);
        if y.length() <= 1e-9 * self.basis_vector_2.length() {
            return Err(format!(
                "basis_vector_2 = {} must not be parallel to basis_vector_1 = {}",
                self.basis_vector_2, self.basis_vector_1
            ));
        }
        let y = y.normalize();
        let z = x.cross(y);
        Ok(self
            .platonic_solid
            .vertices()
            .into_iter()
            .map(|v| self.centre + self.radius * (v.x * x + v.y * y + v.z * z))
            .collect())
    }

    /// `lens i-j` for every edge i-j of the solid (vertex indices as in
    /// [`PlatonicSolid::vertices`]) and, with `edges`, Dr TIM's inner edges (`inner edge i`,
    /// from the centre to vertex i) and outer edges (`edge i-j`).
    pub fn parts(&self, edges_shown: Option<&Edges>) -> Result<Vec<Part>, String> {
        let v = self.vertices()?;
        let c = self.centre;
        let joined = edges(&self.platonic_solid.vertices());
        let mut parts = Vec::new();
        for &[i, j] in &joined {
            let name = format!("lens {i}-{j}");
            parts.push(Part {
                shape: Shape::TriangleMesh(
                    TriangleMesh::new(vec![c, v[i], v[j]], vec![[0, 1, 2]])
                        .map_err(|e| format!("{name}: {e}"))?,
                ),
                surface: Surface::IdealThinLens(ThinLens {
                    principal_point: c,
                    optical_axis: (v[i] - c).cross(v[j] - c).normalize(),
                    focal_length: self.focal_length,
                    gradient: None,
                    transmission_coefficient: self.lens_transmission_coefficient,
                }),
                edge: false,
                name,
            });
        }
        if let Some(e) = edges_shown {
            for (i, &vertex) in v.iter().enumerate() {
                parts.push(e.part(format!("inner edge {i}"), c, vertex)?);
            }
            for &[i, j] in &joined {
                parts.push(e.part(format!("edge {i}-{j}"), v[i], v[j])?);
            }
        }
        Ok(parts)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SOLIDS: [(PlatonicSolid, usize, usize, usize); 5] = [
        // (solid, vertices, edges, edges at a vertex)
        (PlatonicSolid::Tetrahedron, 4, 6, 3),
        (PlatonicSolid::Cube, 8, 12, 3),
        (PlatonicSolid::Octahedron, 6, 12, 4),
        (PlatonicSolid::Dodecahedron, 20, 30, 3),
        (PlatonicSolid::Icosahedron, 12, 30, 5),
    ];

    /// Euler's V − E + F = 2 with F = 2E/(sides of a face), the vertex degrees, unit
    /// circumradius and a centred solid.
    #[test]
    fn the_solids_have_their_counts_and_are_regular() {
        for (solid, n_vertices, n_edges, degree) in SOLIDS {
            let v = solid.vertices();
            let e = edges(&v);
            assert_eq!((v.len(), e.len()), (n_vertices, n_edges), "{solid:?}");
            for (i, p) in v.iter().enumerate() {
                assert!((p.length() - 1.0).abs() < 1e-15, "{solid:?} {p}");
                assert_eq!(e.iter().filter(|p| p.contains(&i)).count(), degree);
            }
            assert!(v.iter().sum::<DVec3>().length() < 1e-14, "{solid:?}");
        }
    }

    /// Dr TIM's tables (`PlatonicSolidType`, six digits from Mathematica) for one vertex of
    /// each solid whose orientation is not fixed by its symmetry axes alone.
    #[test]
    fn the_orientation_is_dr_tims() {
        for (solid, vertex) in [
            (
                PlatonicSolid::Tetrahedron,
                DVec3::new(-0.471405, 0.816497, -0.333333),
            ),
            (
                PlatonicSolid::Icosahedron,
                DVec3::new(-0.723607, -0.525731, 0.447214),
            ),
            (
                PlatonicSolid::Icosahedron,
                DVec3::new(0.723607, 0.525731, -0.447214),
            ),
            (
                PlatonicSolid::Dodecahedron,
                DVec3::new(-0.303531, -0.934172, 0.187592),
            ),
            (
                PlatonicSolid::Dodecahedron,
                DVec3::new(0.491123, 0.356822, 0.794654),
            ),
            (
                PlatonicSolid::Dodecahedron,
                DVec3::new(0.607062, 0.0, -0.794654),
            ),
        ] {
            let nearest = solid
                .vertices()
                .into_iter()
                .map(|p| p.distance(vertex))
                .fold(f64::INFINITY, f64::min);
            assert!(nearest < 1e-6, "{solid:?} {vertex}: {nearest}");
        }
    }
}
