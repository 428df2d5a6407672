//! Platonic solids (Dr TIM's `PlatonicSolidType`), of circumradius `radius` about `centre`, in
//! the orientation of Dr TIM's vertex tables. The vertices are worked out here exactly: the
//! tetrahedron with a vertex on +z, the cube's (±1, ±1, ±1)/√3, the octahedron's ±x, ±y, ±z,
//! the icosahedron with vertices on ±z and two rings of five at z = ±1/√5 (the upper ring at
//! azimuths 72°k, the lower at 36° + 72°k), and the dodecahedron as the icosahedron's dual (its
//! face centres, normalised). The edges join the vertices at the shortest distance; the faces
//! are the planes through three vertices with every vertex on or behind them.

use glam::DVec3;
use serde::Deserialize;

use super::polyhedron::{Face, Polyhedral, Polyhedron};
use super::{GeometryError, Shape};
use crate::keys::{Positive, Vector};

/// The five Platonic solids.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum PlatonicKind {
    Tetrahedron,
    Cube,
    Octahedron,
    Dodecahedron,
    Icosahedron,
}

impl PlatonicKind {
    /// The vertices, at distance 1 from the origin.
    pub fn vertices(self) -> Vec<DVec3> {
        match self {
            PlatonicKind::Tetrahedron => {
                let (a, b) = (2f64.sqrt() / 3.0, (2.0f64 / 3.0).sqrt());
                vec![
                    DVec3::Z,
                    DVec3::new(-a, -b, -1.0 / 3.0),
                    DVec3::new(-a, b, -1.0 / 3.0),
                    DVec3::new(2.0 * a, 0.0, -1.0 / 3.0),
                ]
            }
            PlatonicKind::Cube => (0..8)
                .map(|i| {
                    let sign = |bit: u32| if i & (1 << bit) == 0 { -1.0 } else { 1.0 };
                    DVec3::new(sign(2), sign(1), sign(0)) / 3f64.sqrt()
                })
                .collect(),
            PlatonicKind::Octahedron => {
                vec![
                    DVec3::X,
                    -DVec3::X,
                    DVec3::Y,
                    -DVec3::Y,
                    DVec3::Z,
                    -DVec3::Z,
                ]
            }
            PlatonicKind::Icosahedron => {
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
            PlatonicKind::Dodecahedron => {
                let v = PlatonicKind::Icosahedron.vertices();
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

    /// The edges: pairs of vertices (i < j, numbered as in [`Self::vertices`]).
    pub fn edges(self) -> Vec<[usize; 2]> {
        edges(&self.vertices())
    }

    /// The faces: the vertices of each (ascending), the faces in the order of their vertex
    /// lists.
    fn faces(self) -> Vec<Vec<usize>> {
        let v = self.vertices();
        let n = v.len();
        let mut faces: Vec<Vec<usize>> = Vec::new();
        for i in 0..n {
            for j in i + 1..n {
                for k in j + 1..n {
                    let normal = (v[j] - v[i]).cross(v[k] - v[i]).normalize();
                    let heights: Vec<f64> = v.iter().map(|&p| normal.dot(p - v[i])).collect();
                    let supporting =
                        heights.iter().all(|&h| h <= 1e-9) || heights.iter().all(|&h| h >= -1e-9);
                    let on: Vec<usize> = (0..n).filter(|&m| heights[m].abs() <= 1e-9).collect();
                    if supporting && !faces.contains(&on) {
                        faces.push(on);
                    }
                }
            }
        }
        faces
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

/// A Platonic solid as a shape. Each face's surface coordinates start at its lowest-numbered
/// vertex (or its lower-numbered neighbour on the face), u along the edge between them.
#[derive(Debug, Clone, PartialEq)]
pub struct PlatonicSolid {
    kind: PlatonicKind,
    centre: DVec3,
    radius: f64,
    polyhedron: Polyhedron,
}

impl PlatonicSolid {
    pub fn new(
        kind: PlatonicKind,
        centre: DVec3,
        radius: f64,
    ) -> Result<PlatonicSolid, GeometryError> {
        super::check_point("Platonic solid centre", centre)?;
        super::check_positive("Platonic solid radius", radius)?;
        let unit = kind.vertices();
        let vertices = placed(&unit, centre, radius);
        let edges = kind.edges();
        let faces = kind
            .faces()
            .into_iter()
            .map(|face| {
                let first = face[0];
                let along: Vec<DVec3> = face[1..]
                    .iter()
                    .filter(|&&j| edges.contains(&[first, j]))
                    .map(|&j| radius * (unit[j] - unit[first]))
                    .collect();
                Face::new(vertices[first], along[0], along[1], centre)
            })
            .collect();
        Ok(PlatonicSolid {
            kind,
            centre,
            radius,
            polyhedron: Polyhedron::new(faces, &vertices),
        })
    }

    pub fn kind(&self) -> PlatonicKind {
        self.kind
    }

    /// The vertices, placed.
    pub fn vertices(&self) -> Vec<DVec3> {
        placed(&self.kind.vertices(), self.centre, self.radius)
    }
}

/// The unit solid's vertices `unit` scaled by `radius` and moved to `centre`.
fn placed(unit: &[DVec3], centre: DVec3, radius: f64) -> Vec<DVec3> {
    unit.iter().map(|&v| centre + radius * v).collect()
}

impl Polyhedral for PlatonicSolid {
    fn polyhedron(&self) -> &Polyhedron {
        &self.polyhedron
    }
}

/// `type = "platonic-solid"`: `solid` names it, `radius` is its circumradius; Dr TIM's
/// `EditablePlatonicSolid(parent, studio)`, a tetrahedron of radius 1 about (0, 0, 10), where
/// not given.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlatonicSolidKeys {
    solid: Option<PlatonicKind>,
    centre: Option<Vector>,
    radius: Option<Positive>,
}

impl PlatonicSolidKeys {
    pub fn build(self) -> Result<Shape, GeometryError> {
        Ok(Shape::PlatonicSolid(PlatonicSolid::new(
            self.solid.unwrap_or(PlatonicKind::Tetrahedron),
            self.centre.map_or(DVec3::new(0.0, 0.0, 10.0), |c| c.0),
            self.radius.map_or(1.0, |r| r.0),
        )?))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SOLIDS: [(PlatonicKind, usize, usize, usize, usize); 5] = [
        // (solid, vertices, edges, edges at a vertex, faces)
        (PlatonicKind::Tetrahedron, 4, 6, 3, 4),
        (PlatonicKind::Cube, 8, 12, 3, 6),
        (PlatonicKind::Octahedron, 6, 12, 4, 8),
        (PlatonicKind::Dodecahedron, 20, 30, 3, 12),
        (PlatonicKind::Icosahedron, 12, 30, 5, 20),
    ];

    /// Euler's V − E + F = 2, the vertex degrees, unit circumradius and a centred solid.
    #[test]
    fn the_solids_have_their_counts_and_are_regular() {
        for (solid, n_vertices, n_edges, degree, n_faces) in SOLIDS {
            let v = solid.vertices();
            let e = edges(&v);
            let f = solid.faces();
            assert_eq!(
                (v.len(), e.len(), f.len()),
                (n_vertices, n_edges, n_faces),
                "{solid:?}"
            );
            for (i, p) in v.iter().enumerate() {
                assert!((p.length() - 1.0).abs() < 1e-15, "{solid:?} {p}");
                assert_eq!(e.iter().filter(|p| p.contains(&i)).count(), degree);
            }
            assert!(v.iter().sum::<DVec3>().length() < 1e-14, "{solid:?}");
            // Every face has as many vertices as edges: 2E = F × sides.
            let sides = f[0].len();
            assert!(f.iter().all(|face| face.len() == sides), "{solid:?}");
            assert_eq!(2 * n_edges, n_faces * sides, "{solid:?}");
        }
    }

    /// Dr TIM's tables (`PlatonicSolidType`, six digits from Mathematica) for one vertex of
    /// each solid whose orientation is not fixed by its symmetry axes alone.
    #[test]
    fn the_orientation_is_dr_tims() {
        for (solid, vertex) in [
            (
                PlatonicKind::Tetrahedron,
                DVec3::new(-0.471405, 0.816497, -0.333333),
            ),
            (
                PlatonicKind::Icosahedron,
                DVec3::new(-0.723607, -0.525731, 0.447214),
            ),
            (
                PlatonicKind::Icosahedron,
                DVec3::new(0.723607, 0.525731, -0.447214),
            ),
            (
                PlatonicKind::Dodecahedron,
                DVec3::new(-0.303531, -0.934172, 0.187592),
            ),
            (
                PlatonicKind::Dodecahedron,
                DVec3::new(0.491123, 0.356822, 0.794654),
            ),
            (
                PlatonicKind::Dodecahedron,
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
