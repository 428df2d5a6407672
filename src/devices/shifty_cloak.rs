//! Shifty cloaks (Dr TIM's `EditableCubicShiftyCloak` and `EditableSimpleTetrahedralShiftyCloak`,
//! "realised using homogeneous GCLAs"): a polyhedral shell of homogeneous planar imaging
//! surfaces round an empty inner polyhedron, the outer one scaled about the centre, that makes
//! the inner polyhedron, and anything in it, appear shifted by δ, while the space outside the
//! cloak is seen as it is.
//!
//! The shell is cut into frusta, one on each outer face, by the diagonal faces joining each outer
//! edge to the inner one in front of it. Each region is seen from outside through an affine map
//! V (its "virtual space"): outside V(x) = x, inside V(x) = x + δ, and in the frustum on the face
//! of outward unit normal n̂, a distance r from the centre c,
//!
//!   V(x) = x + (d(x)/h) δ,   d(x) = r − n̂·(x − c),   h = (1 − k) r,
//!
//! k being the ratio of the inner to the outer side length: d is the distance from the outer
//! face, h that of the inner face. Neighbouring maps agree on the faces between them (on a
//! diagonal face, which contains c, the two frusta's d/h are equal), so each face is the
//! homogeneous planar imaging surface ([`HomogeneousPlanarImaging`]) that images a point x of the
//! region behind it into V_front⁻¹(V_behind(x)) in front; Dr TIM's conjugate pairs (other
//! points) give its faces the same maps. A frustum's map is singular where n̂·δ = h (the inner face would appear in
//! the outer face's plane): refused.

use glam::DVec3;
use serde::Deserialize;

use super::{EdgeDefaults, Edges, LensDevice, Part};
use crate::geometry::{ConvexPolygon, Shape};
use crate::keys::{Coefficient, Direction, Positive, Vector, throughput};
use crate::surfaces::metatoys::{HomogeneousPlanarImaging, Transmission};
use crate::surfaces::{ConfocalLensletArrays, Surface};

/// The outer polyhedron of a shifty cloak.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Polyhedron {
    /// The cube of side `side_length_outside` (Dr TIM's `EditableCubicShiftyCloak`).
    Cube,
    /// The tetrahedron of four alternate corners of that cube
    /// (`EditableSimpleTetrahedralShiftyCloak`).
    Tetrahedron,
}

impl Polyhedron {
    /// The vertices, as signs along (û, v̂, ŵ) of the cube's corners.
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

#[derive(Debug, Clone, PartialEq)]
pub struct ShiftyCloak {
    pub polyhedron: Polyhedron,
    pub centre: DVec3,
    pub u_direction: DVec3,
    pub v_direction: DVec3,
    pub side_length_outside: f64,
    pub side_length_inside: f64,
    /// δ: the inner polyhedron's apparent shift.
    pub delta: DVec3,
    pub show_interfaces: bool,
    pub interface_transmission_coefficient: f64,
}

/// A region of space, as the cloak's faces divide it.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Region {
    Outside,
    Inside,
    /// The frustum on the outer face of this index.
    Frustum(usize),
}

/// A face of the outer polyhedron: its outward unit normal n̂, distance r from the centre and
/// its label, the signs of its centre along û, v̂ and ŵ (`+u`, `-u-v-w`).
struct OuterFace {
    vertices: Vec<usize>,
    normal: DVec3,
    distance: f64,
    label: String,
}

/// The cloak worked out: its vertices, outer faces and regions' maps.
struct Layout<'a> {
    cloak: &'a ShiftyCloak,
    outer: Vec<DVec3>,
    inner: Vec<DVec3>,
    labels: Vec<String>,
    faces: Vec<OuterFace>,
    /// The inner to the outer side length, k.
    k: f64,
}

/// `+u-v+w` for the signs of (u, v, w) components (zero components left out).
fn label(components: [f64; 3]) -> String {
    components
        .iter()
        .zip(["u", "v", "w"])
        .filter(|(c, _)| c.abs() > 1e-9)
        .map(|(c, axis)| format!("{}{axis}", if *c > 0.0 { '+' } else { '-' }))
        .collect()
}

impl ShiftyCloak {
    fn layout(&self) -> Result<Layout<'_>, String> {
        let (outside, inside) = (self.side_length_outside, self.side_length_inside);
        if inside >= outside {
            return Err(format!(
                "side_length_inside ({inside}) must be less than side_length_outside ({outside})"
            ));
        }
        // Dr TIM's `calculateUVWHats`.
        let u = self.u_direction.normalize();
        let v = self.v_direction.reject_from_normalized(u);
        if v.length() <= 1e-12 {
            return Err("v_direction must not be along u_direction".into());
        }
        let v = v.normalize();
        let w = u.cross(v);
        let corners = self.polyhedron.corners();
        let at =
            |s: &[f64; 3], side: f64| self.centre + 0.5 * side * (s[0] * u + s[1] * v + s[2] * w);
        let outer: Vec<DVec3> = corners.iter().map(|s| at(s, outside)).collect();
        let inner = corners.iter().map(|s| at(s, inside)).collect();
        let k = inside / outside;
        let faces = self
            .polyhedron
            .faces()
            .into_iter()
            .map(|vertices| {
                let mean = |i: usize| {
                    vertices.iter().map(|&j| corners[j][i]).sum::<f64>() / vertices.len() as f64
                };
                let label = label([mean(0), mean(1), mean(2)]);
                let [a, b, c] = [0, 1, 2].map(|i| outer[vertices[i]]);
                let mut normal = (b - a).cross(c - b).normalize();
                if normal.dot(a - self.centre) < 0.0 {
                    normal = -normal;
                }
                let distance = normal.dot(a - self.centre);
                // h − n̂·δ, relative to h: the frustum's map is singular at 0.
                let h = (1.0 - k) * distance;
                if ((h - normal.dot(self.delta)) / h).abs() <= 1e-9 {
                    return Err(format!(
                        "delta's component along the {label} face's normal equals the distance \
                         between the outer and inner {label} faces, {h}: the inner face would \
                         appear in the outer face's plane"
                    ));
                }
                Ok(OuterFace {
                    vertices,
                    normal,
                    distance,
                    label,
                })
            })
            .collect::<Result<_, String>>()?;
        Ok(Layout {
            cloak: self,
            outer,
            inner,
            labels: corners.iter().map(|s| label(*s)).collect(),
            faces,
            k,
        })
    }
}

impl Layout<'_> {
    /// Where a point x of `region` is seen from outside, V(x).
    fn seen(&self, region: Region, x: DVec3) -> DVec3 {
        let delta = self.cloak.delta;
        match region {
            Region::Outside => x,
            Region::Inside => x + delta,
            Region::Frustum(f) => {
                let face = &self.faces[f];
                let d = face.distance - face.normal.dot(x - self.cloak.centre);
                x + d / ((1.0 - self.k) * face.distance) * delta
            }
        }
    }

    /// The point of `region` seen at y, V⁻¹(y): in a frustum d(x)(1 − n̂·δ/h) = d(y).
    fn at(&self, region: Region, y: DVec3) -> DVec3 {
        let delta = self.cloak.delta;
        match region {
            Region::Outside => y,
            Region::Inside => y - delta,
            Region::Frustum(f) => {
                let face = &self.faces[f];
                let h = (1.0 - self.k) * face.distance;
                let d_y = face.distance - face.normal.dot(y - self.cloak.centre);
                y - d_y / (h - face.normal.dot(delta)) * delta
            }
        }
    }

    /// The face with these vertices between `front` (the side its outward normal `normal`
    /// points to) and `behind`, as gCLAs imaging behind into front.
    fn interface(
        &self,
        name: String,
        vertices: Vec<DVec3>,
        normal: DVec3,
        front: Region,
        behind: Region,
    ) -> Result<Part, String> {
        let point_on_plane = vertices[0];
        let inside_position = point_on_plane - self.cloak.side_length_outside * normal;
        let imaging = HomogeneousPlanarImaging {
            point_on_plane,
            a: normal,
            inside_position,
            outside_position: self.at(front, self.seen(behind, inside_position)),
        };
        let transmission = Transmission::Constant(self.cloak.interface_transmission_coefficient);
        let arrays = ConfocalLensletArrays::imaging(imaging, transmission)
            .map_err(|e| format!("{name}: {e}"))?;
        Ok(Part {
            shape: Shape::ConvexPolygon(
                ConvexPolygon::new(vertices).map_err(|e| format!("{name}: {e}"))?,
            ),
            name,
            surface: Surface::ConfocalLensletArrays(arrays),
            edge: false,
        })
    }

    /// The outer, inner and diagonal faces.
    fn interfaces(&self) -> Result<Vec<Part>, String> {
        let mut parts = Vec::new();
        for (f, face) in self.faces.iter().enumerate() {
            let corners =
                |positions: &[DVec3]| face.vertices.iter().map(|&i| positions[i]).collect();
            parts.push(self.interface(
                format!("outer face in {} direction", face.label),
                corners(&self.outer),
                face.normal,
                Region::Outside,
                Region::Frustum(f),
            )?);
            parts.push(self.interface(
                format!("inner face in {} direction", face.label),
                corners(&self.inner),
                face.normal,
                Region::Frustum(f),
                Region::Inside,
            )?);
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
            parts.push(self.interface(
                format!(
                    "diagonal face between the {} and {} faces",
                    self.faces[f].label, self.faces[g].label
                ),
                vec![a, b, self.inner[j], self.inner[i]],
                normal,
                Region::Frustum(front),
                Region::Frustum(behind),
            )?);
        }
        Ok(parts)
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

    /// Dr TIM's frames: spheres at the vertices, cylinders along the outer, inner and diagonal
    /// edges.
    fn frames(&self, e: &Edges) -> Result<Vec<Part>, String> {
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

impl LensDevice for ShiftyCloak {
    /// With `show_interfaces`, the faces `outer face in +u direction`, `inner face in +u
    /// direction`, `diagonal face between the +u and +v faces`, ... (the tetrahedron's
    /// `outer face in -u-v-w direction`, ...); with `edges` the frames `outer vertex +u+v+w`,
    /// `inner vertex ...`, `outer edge +u+v-w to +u+v+w`, `inner edge ...`, `diagonal edge at
    /// +u+v+w`.
    fn parts(&self, edges: Option<&Edges>) -> Result<Vec<Part>, String> {
        let layout = self.layout()?;
        let mut parts = if self.show_interfaces {
            layout.interfaces()?
        } else {
            Vec::new()
        };
        if let Some(e) = edges {
            parts.extend(layout.frames(e)?);
        }
        Ok(parts)
    }

    /// Dr TIM's frames: shown, radius 0.01, `SurfaceColour.GREY50_SHINY`.
    fn edge_defaults(&self) -> EdgeDefaults {
        EdgeDefaults::SHOWN_GREY
    }
}

/// The keys of both shifty cloaks, with the defaults of Dr TIM's constructors
/// `EditableCubicShiftyCloak(parent, studio)` and `EditableSimpleTetrahedralShiftyCloak(parent,
/// studio)` (the same): a cloak of side 1 about (0, 0, 10), its inner cube or tetrahedron of
/// side 0.5 seen shifted by (1, 0, 0).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShiftyCloakKeys {
    centre: Option<Vector>,
    u_direction: Option<Direction>,
    v_direction: Option<Direction>,
    side_length_outside: Option<Positive>,
    side_length_inside: Option<Positive>,
    delta: Option<Vector>,
    show_interfaces: Option<bool>,
    interface_transmission_coefficient: Option<Coefficient>,
}

impl ShiftyCloakKeys {
    fn cloak(self, polyhedron: Polyhedron) -> Result<Box<dyn LensDevice>, String> {
        let cloak = ShiftyCloak {
            polyhedron,
            centre: self.centre.map_or(DVec3::new(0.0, 0.0, 10.0), |c| c.0),
            u_direction: self.u_direction.map_or(DVec3::X, |d| d.0),
            v_direction: self.v_direction.map_or(DVec3::Y, |d| d.0),
            side_length_outside: self.side_length_outside.map_or(1.0, |s| s.0),
            side_length_inside: self.side_length_inside.map_or(0.5, |s| s.0),
            delta: self.delta.map_or(DVec3::X, |d| d.0),
            show_interfaces: self.show_interfaces.unwrap_or(true),
            interface_transmission_coefficient: throughput(self.interface_transmission_coefficient),
        };
        // Refuse bad parameters when the scene is read.
        cloak.layout()?;
        Ok(Box::new(cloak))
    }
}

/// `lenses = { type = "cubic-shifty-cloak" }`: Dr TIM's `EditableCubicShiftyCloak`.
#[derive(Debug, Deserialize)]
#[serde(transparent)]
pub struct CubicShiftyCloakKeys(ShiftyCloakKeys);

impl CubicShiftyCloakKeys {
    pub fn build(self) -> Result<Box<dyn LensDevice>, String> {
        self.0.cloak(Polyhedron::Cube)
    }
}

/// `lenses = { type = "simple-tetrahedral-shifty-cloak" }`: Dr TIM's
/// `EditableSimpleTetrahedralShiftyCloak`.
#[derive(Debug, Deserialize)]
#[serde(transparent)]
pub struct SimpleTetrahedralShiftyCloakKeys(ShiftyCloakKeys);

impl SimpleTetrahedralShiftyCloakKeys {
    pub fn build(self) -> Result<Box<dyn LensDevice>, String> {
        self.0.cloak(Polyhedron::Tetrahedron)
    }
}
