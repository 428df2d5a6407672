//! A polyhedral shell, the geometry of Dr TIM's shifty cloaks (`EditableCubicShiftyCloak`,
//! `EditableSimpleTetrahedralShiftyCloak`) and its cubic box cloak (`CubicBoxCloakMaker`): an
//! outer polyhedron about a centre c, the same polyhedron scaled about c inside it, and the
//! diagonal faces joining each outer edge to the inner edge in front of it, which cut the shell
//! between them into frusta, one on each outer face. A cloak built on it sees each [`Region`]
//! through a map of its own and makes each face the interface that images the region behind
//! it into the one in front.

use glam::DVec3;

use super::{Edges, Part};

/// The outer polyhedron of a shell.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Polyhedron {
    /// The cube of the outer side length, its faces normal to the three axes.
    Cube,
    /// The tetrahedron of four alternate corners of that cube.
    Tetrahedron,
}

impl Polyhedron {
    /// The vertices, as signs along the three axes of the cube's corners.
    fn corners(self) -> Vec<[f64; 3]> {
        match self {
            Polyhedron::Cube => (0..8)
                .map(|i| [4, 2, 1].map(|bit| if i & bit == 0 { -1.0 } else { 1.0 }))
                .collect(),
            Polyhedron::Tetrahedron => vec![
                [1.0, 1.0, 1.0],
                [1.0, -1.0, -1.0],
                [-1.0, 1.0, -1.0],
                [-1.0, -1.0, 1.0],
            ],
        }
    }

    /// The faces, each its vertices in order round it.
    fn faces(self) -> Vec<Vec<usize>> {
        match self {
            Polyhedron::Cube => vec![
                vec![4, 5, 7, 6],
                vec![0, 1, 3, 2],
                vec![2, 3, 7, 6],
                vec![0, 1, 5, 4],
                vec![1, 3, 7, 5],
                vec![0, 2, 6, 4],
            ],
            Polyhedron::Tetrahedron => {
                vec![vec![1, 2, 3], vec![0, 2, 3], vec![0, 1, 3], vec![0, 1, 2]]
            }
        }
    }
}

/// A region of space, as the shell's faces divide it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Region {
    Outside,
    Inside,
    /// The frustum on the outer face of this index.
    Frustum(usize),
}

/// A face of the outer polyhedron: its outward unit normal n̂, distance r from the centre and
/// its label (the names of the axes along which its centre lies: `+u`, `-u-v-w`, `front`).
pub struct OuterFace {
    vertices: Vec<usize>,
    pub normal: DVec3,
    pub distance: f64,
    pub label: String,
}

/// The names of the axes' two directions, and what joins them in a label: `[["+u", "-u"],
/// ...]` and `""` make `+u-v+w`.
pub struct AxisNames {
    pub directions: [[&'static str; 2]; 3],
    pub separator: &'static str,
}

impl AxisNames {
    /// The label of a point with these components along the axes (zero components left out).
    fn label(&self, components: [f64; 3]) -> String {
        components
            .iter()
            .zip(self.directions)
            .filter(|(c, _)| c.abs() > 1e-9)
            .map(|(c, [plus, minus])| if *c > 0.0 { plus } else { minus })
            .collect::<Vec<_>>()
            .join(self.separator)
    }
}

/// The shell worked out: its vertices and outer faces.
pub struct Shell {
    pub outer: Vec<DVec3>,
    pub inner: Vec<DVec3>,
    labels: Vec<String>,
    pub faces: Vec<OuterFace>,
}

/// An interface of the shell: its name, its vertices, the unit normal on the side of the
/// region in front and the regions in front and behind.
pub struct Interface {
    pub name: String,
    pub vertices: Vec<DVec3>,
    pub normal: DVec3,
    pub front: Region,
    pub behind: Region,
}

impl Shell {
    /// The shell about `centre` with unit, mutually perpendicular `axes`, the outer polyhedron
    /// of side `outside` (its cube's), the inner one of side `inside`.
    pub fn new(
        polyhedron: Polyhedron,
        centre: DVec3,
        axes: [DVec3; 3],
        outside: f64,
        inside: f64,
        names: &AxisNames,
    ) -> Shell {
        let corners = polyhedron.corners();
        let at = |s: &[f64; 3], side: f64| {
            centre + 0.5 * side * (s[0] * axes[0] + s[1] * axes[1] + s[2] * axes[2])
        };
        let outer: Vec<DVec3> = corners.iter().map(|s| at(s, outside)).collect();
        let inner = corners.iter().map(|s| at(s, inside)).collect();
        let faces = polyhedron
            .faces()
            .into_iter()
            .map(|vertices| {
                let mean = |i: usize| {
                    vertices.iter().map(|&j| corners[j][i]).sum::<f64>() / vertices.len() as f64
                };
                let label = names.label([mean(0), mean(1), mean(2)]);
                let [a, b, c] = [0, 1, 2].map(|i| outer[vertices[i]]);
                let mut normal = (b - a).cross(c - b).normalize();
                if normal.dot(a - centre) < 0.0 {
                    normal = -normal;
                }
                let distance = normal.dot(a - centre);
                OuterFace {
                    vertices,
                    normal,
                    distance,
                    label,
                }
            })
            .collect();
        Shell {
            outer,
            inner,
            labels: corners.iter().map(|s| names.label(*s)).collect(),
            faces,
        }
    }

    /// The outer, inner and diagonal faces: `outer face in +u direction`, `inner face in +u
    /// direction`, `diagonal face between the +u and +v faces`, ...
    pub fn interfaces(&self) -> Vec<Interface> {
        let mut interfaces = Vec::new();
        for (f, face) in self.faces.iter().enumerate() {
            let corners =
                |positions: &[DVec3]| face.vertices.iter().map(|&i| positions[i]).collect();
            interfaces.push(Interface {
                name: format!("outer face in {} direction", face.label),
                vertices: corners(&self.outer),
                normal: face.normal,
                front: Region::Outside,
                behind: Region::Frustum(f),
            });
            interfaces.push(Interface {
                name: format!("inner face in {} direction", face.label),
                vertices: corners(&self.inner),
                normal: face.normal,
                front: Region::Frustum(f),
                behind: Region::Inside,
            });
        }
        for (i, j, f, g) in self.edges() {
            let (a, b) = (self.outer[i], self.outer[j]);
            let normal = (b - a).cross(self.inner[i] - a).normalize();
            // Face f's centre lies in the frustum on it, off the diagonal plane.
            let centre_f = self.faces[f]
                .vertices
                .iter()
                .map(|&v| self.outer[v])
                .sum::<DVec3>()
                / self.faces[f].vertices.len() as f64;
            let towards_f = normal.dot(centre_f - a) > 0.0;
            // The normal points to the front frustum.
            let (front, behind) = if towards_f { (f, g) } else { (g, f) };
            interfaces.push(Interface {
                name: format!(
                    "diagonal face between the {} and {} faces",
                    self.faces[f].label, self.faces[g].label
                ),
                vertices: vec![a, b, self.inner[j], self.inner[i]],
                normal,
                front: Region::Frustum(front),
                behind: Region::Frustum(behind),
            });
        }
        interfaces
    }

    /// The outer polyhedron's edges (i < j) with the two faces that meet there.
    fn edges(&self) -> Vec<(usize, usize, usize, usize)> {
        let mut edges = Vec::new();
        for (f, face) in self.faces.iter().enumerate() {
            let n = face.vertices.len();
            for s in 0..n {
                let (i, j) = (face.vertices[s], face.vertices[(s + 1) % n]);
                let (i, j) = (i.min(j), i.max(j));
                if edges.iter().any(|&(a, b, _, _)| (a, b) == (i, j)) {
                    continue;
                }
                let g = self
                    .faces
                    .iter()
                    .enumerate()
                    .position(|(g, other)| {
                        g != f && other.vertices.contains(&i) && other.vertices.contains(&j)
                    })
                    .expect("every edge of a closed polyhedron joins two faces");
                edges.push((i, j, f, g));
            }
        }
        edges
    }

    /// Dr TIM's frames: spheres at the vertices (`outer vertex +u+v+w`, `inner vertex ...`),
    /// cylinders along the outer, inner and diagonal edges (`outer edge +u+v-w to +u+v+w`,
    /// `inner edge ...`, `diagonal edge at +u+v+w`).
    pub fn frames(&self, e: &Edges) -> Result<Vec<Part>, String> {
        let mut parts = Vec::new();
        for (name, positions) in [("outer", &self.outer), ("inner", &self.inner)] {
            for (i, &at) in positions.iter().enumerate() {
                parts.push(e.vertex(format!("{name} vertex {}", self.labels[i]), at)?);
            }
        }
        for (i, j, _, _) in self.edges() {
            let (a, b) = (&self.labels[i], &self.labels[j]);
            parts.push(e.part(
                format!("outer edge {a} to {b}"),
                self.outer[i],
                self.outer[j],
            )?);
            parts.push(e.part(
                format!("inner edge {a} to {b}"),
                self.inner[i],
                self.inner[j],
            )?);
        }
        for (i, label) in self.labels.iter().enumerate() {
            parts.push(e.part(
                format!("diagonal edge at {label}"),
                self.inner[i],
                self.outer[i],
            )?);
        }
        Ok(parts)
    }
}
