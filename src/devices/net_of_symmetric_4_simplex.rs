//! The net of a symmetric 4-simplex (Dr TIM's `EditableNetOfSymmetric4Simplex`, on its
//! `EditableNetOf4Simplex`): the 4-simplex's five tetrahedra unfolded into 3D space, optically
//! glued into its 3D surface. The inner tetrahedron is regular, inscribed in the cube of side
//! e/√2 (edge length e) about `centroid` whose face normals are the three `normal_to_enclosing_
//! cube_*` directions: vertices c + h(n̂₁ + n̂₂ + n̂₃), c + h(n̂₁ − n̂₂ − n̂₃), c + h(−n̂₁ + n̂₂ − n̂₃),
//! c + h(−n̂₁ − n̂₂ + n̂₃), h = e/(2√2). On the face opposite vertex k sits an outer tetrahedron
//! whose fourth vertex is the face's centroid plus `outer_tetrahedron_height_factor` times the
//! vector from vertex k to it; with the factor 1 all five are regular (a regular 4-simplex), with
//! ½ they fill the cube.
//!
//! Round each of the inner tetrahedron's six edges the inner tetrahedron (dihedral angle
//! atan 2√2) and two outer ones (atan(2√2 × factor) each) leave the apex angle
//! ν = 2π − atan 2√2 − 2 atan(2√2 × factor) empty, which a mirrored space-cancelling wedge
//! ([`MirroredSpaceCancellingWedge`]) cancels, its legs (of the distance from the edge to the
//! outer tetrahedra's fourth vertices, times the leg-length factor) on the two outer tetrahedra's
//! facing faces.

use glam::DVec3;
use serde::Deserialize;

use super::mirrored_space_cancelling_wedge::MirroredSpaceCancellingWedge;
use super::net::{self, CYAN_GLASS, TINY};
use super::space_cancelling_wedge::Gluing;
use super::{EdgeDefaults, Edges, LensDevice, Part};
use crate::keys::{Coefficient, Direction, Positive, Rgb, Vector, throughput};
use crate::math::Colour;

#[derive(Debug, Clone, PartialEq)]
pub struct NetOfSymmetric4Simplex {
    pub centroid: DVec3,
    pub edge_length: f64,
    pub outer_tetrahedron_height_factor: f64,
    /// Unit vectors (Dr TIM normalises them and uses them as given).
    pub normals_to_enclosing_cube: [DVec3; 3],
    pub show_space_cancelling_wedges: bool,
    pub space_cancelling_wedge_leg_length_factor: f64,
    pub space_cancelling_wedge_surface_transmission_coefficient: f64,
    pub gluing: Gluing,
    pub number_of_negative_space_wedges: u32,
    pub show_net_faces: bool,
    /// Whether the wedges' edges are shown (Dr TIM's `showSpaceCancellingWedgeEdges`).
    pub show_space_cancelling_wedge_edges: bool,
    /// Their radius, where given (else 10⁻⁴ less than the net's edges').
    pub space_cancelling_wedge_edge_radius: Option<f64>,
    pub net_face_transmission: Colour,
}

/// The inner tetrahedron's edges, as Dr TIM lists them.
const INNER_EDGES: [[usize; 2]; 6] = [[0, 1], [0, 2], [0, 3], [1, 2], [2, 3], [3, 1]];

impl NetOfSymmetric4Simplex {
    /// The eight vertices: the inner tetrahedron's 0 to 3, then the outer vertex above the face
    /// opposite each of them (4 + k above the face opposite k).
    fn vertices(&self) -> [DVec3; 8] {
        let h = 0.5 * self.edge_length / std::f64::consts::SQRT_2;
        let [n1, n2, n3] = self.normals_to_enclosing_cube.map(|n| h * n);
        let c = self.centroid;
        let inner = [
            c + n1 + n2 + n3,
            c + n1 - n2 - n3,
            c - n1 + n2 - n3,
            c - n1 - n2 + n3,
        ];
        let outer = |k: usize| {
            let face = (inner.iter().sum::<DVec3>() - inner[k]) / 3.0;
            face + self.outer_tetrahedron_height_factor * (face - inner[k])
        };
        [
            inner[0],
            inner[1],
            inner[2],
            inner[3],
            outer(0),
            outer(1),
            outer(2),
            outer(3),
        ]
    }

    /// ν for the wedge round each inner edge.
    pub fn apex_angle(&self) -> f64 {
        let atan = |x: f64| x.atan();
        let r = 2.0 * std::f64::consts::SQRT_2;
        2.0 * std::f64::consts::PI - atan(r) - 2.0 * atan(r * self.outer_tetrahedron_height_factor)
    }
}

impl LensDevice for NetOfSymmetric4Simplex {
    /// The wedges round the inner edges (`wedge at edge I-J/PART`, I and J the inner vertices
    /// 0 to 3); with `edges`, the net's vertices (`vertex K`, the outer ones 4 to 7, K − 4 the
    /// inner vertex opposite) and edges (`edge I-K`); with `show_net_faces`, its faces
    /// (`face I-J-K`) but for those a shown wedge surface stands in for
    /// (see `devices/net.rs`).
    fn parts(&self, edges: Option<&Edges>) -> Result<Vec<Part>, String> {
        let [n1, n2, n3] = self.normals_to_enclosing_cube;
        // Dr TIM uses them as given, but only perpendicular ones make the inner tetrahedron
        // regular, which the wedges' angle assumes: others would leave the net open.
        if [n1.dot(n2), n2.dot(n3), n3.dot(n1)]
            .iter()
            .any(|c| c.abs() > 1e-9)
        {
            return Err(
                "the normals to the enclosing cube (normal_to_enclosing_cube_1, _2, _3) \
                        must be perpendicular to each other: only then is the inner tetrahedron \
                        regular, as the wedges' angle assumes"
                    .into(),
            );
        }
        let wedge_edges = net::wedge_edges(
            self.show_space_cancelling_wedge_edges,
            self.space_cancelling_wedge_edge_radius,
            edges,
        )?;
        let v = self.vertices();
        let mut parts = Vec::new();
        for [i, j] in INNER_EDGES {
            // An outer tetrahedron on a face containing the edge: above the face opposite a
            // vertex k other than i and j.
            let k = (0..4).find(|&k| k != i && k != j).expect("four vertices");
            let other = v[4 + k];
            let axis = v[j] - v[i];
            let leg = (other - v[i]).reject_from(axis).length();
            let mid = 0.5 * (v[i] + v[j]);
            let wedge = MirroredSpaceCancellingWedge {
                apex_angle: self.apex_angle(),
                apex_edge_centre: mid,
                apex_edge_direction: axis,
                bisector_direction: mid - self.centroid,
                leg_length: leg * self.space_cancelling_wedge_leg_length_factor,
                apex_edge_length: axis.length(),
                show_surfaces: self.show_space_cancelling_wedges,
                surface_transmission_coefficient: self
                    .space_cancelling_wedge_surface_transmission_coefficient,
                gluing: self.gluing,
                number_of_negative_space_wedges: self.number_of_negative_space_wedges,
            };
            parts.extend(
                wedge.parts_named(&format!("wedge at edge {i}-{j}/"), wedge_edges.as_ref())?,
            );
        }
        // The outer tetrahedra's edges: from the three vertices of the face each sits on.
        let outer_edges =
            (0..4).flat_map(|k| (0..4).filter(move |&f| f != k).map(move |f| [f, 4 + k]));
        if let Some(e) = edges {
            let vertices = Edges {
                radius: e.radius + TINY,
                surface: e.surface.clone(),
            };
            for (k, &p) in v.iter().enumerate() {
                parts.push(vertices.vertex(format!("vertex {k}"), p)?);
            }
            for [a, b] in INNER_EDGES.into_iter().chain(outer_edges.clone()) {
                parts.push(e.part(format!("edge {a}-{b}"), v[a], v[b])?);
            }
        }
        if !self.show_net_faces {
            return Ok(parts);
        }
        let mut faces = Vec::new();
        for k in 0..4 {
            let face: Vec<usize> = (0..4).filter(|&f| f != k).collect();
            faces.push(net::face(
                format!("face {}-{}-{}", face[0], face[1], face[2]),
                face.iter().map(|&f| v[f]).collect(),
                self.net_face_transmission,
            )?);
            for (a, b) in [(face[0], face[1]), (face[1], face[2]), (face[2], face[0])] {
                faces.push(net::face(
                    format!("face {a}-{b}-{}", 4 + k),
                    vec![v[a], v[b], v[4 + k]],
                    self.net_face_transmission,
                )?);
            }
        }
        Ok(net::with_faces(parts, faces))
    }

    fn edge_defaults(&self) -> EdgeDefaults {
        net::NET_EDGES
    }
}

/// `lenses = { type = "net-of-symmetric-four-simplex" }`: Dr TIM's
/// `EditableNetOfSymmetric4Simplex`, with the defaults of its constructor
/// `EditableNetOfSymmetric4Simplex(parent, studio)`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NetOfSymmetric4SimplexKeys {
    centroid: Option<Vector>,
    edge_length: Option<Positive>,
    outer_tetrahedron_height_factor: Option<Positive>,
    normal_to_enclosing_cube_1: Option<Direction>,
    normal_to_enclosing_cube_2: Option<Direction>,
    normal_to_enclosing_cube_3: Option<Direction>,
    show_space_cancelling_wedges: Option<bool>,
    space_cancelling_wedge_leg_length_factor: Option<Positive>,
    space_cancelling_wedge_surface_transmission_coefficient: Option<Coefficient>,
    gluing_type: Option<Gluing>,
    number_of_negative_space_wedges: Option<u32>,
    show_net_faces: Option<bool>,
    show_space_cancelling_wedge_edges: Option<bool>,
    space_cancelling_wedge_edge_radius: Option<Positive>,
    net_face_transmission: Option<Rgb>,
}

impl NetOfSymmetric4SimplexKeys {
    pub fn build(self) -> Result<Box<dyn LensDevice>, String> {
        let gluing = self.gluing_type.unwrap_or(Gluing::Perfect);
        MirroredSpaceCancellingWedge::check_gluing(gluing)?;
        let normal = |d: Option<Direction>, default: DVec3| d.map_or(default, |d| d.0.normalize());
        Ok(Box::new(NetOfSymmetric4Simplex {
            centroid: self.centroid.map_or(DVec3::new(0.0, 0.0, 10.0), |c| c.0),
            edge_length: self.edge_length.map_or(1.0, |e| e.0),
            outer_tetrahedron_height_factor: self
                .outer_tetrahedron_height_factor
                .map_or(1.0, |f| f.0),
            normals_to_enclosing_cube: [
                normal(self.normal_to_enclosing_cube_1, DVec3::X),
                normal(self.normal_to_enclosing_cube_2, DVec3::Y),
                normal(self.normal_to_enclosing_cube_3, DVec3::Z),
            ],
            show_space_cancelling_wedges: self.show_space_cancelling_wedges.unwrap_or(true),
            space_cancelling_wedge_leg_length_factor: self
                .space_cancelling_wedge_leg_length_factor
                .map_or(1.0, |k| k.0),
            space_cancelling_wedge_surface_transmission_coefficient: throughput(
                self.space_cancelling_wedge_surface_transmission_coefficient,
            ),
            gluing,
            number_of_negative_space_wedges: self.number_of_negative_space_wedges.unwrap_or(1),
            show_net_faces: self.show_net_faces.unwrap_or(false),
            show_space_cancelling_wedge_edges: self
                .show_space_cancelling_wedge_edges
                .unwrap_or(false),
            space_cancelling_wedge_edge_radius: self
                .space_cancelling_wedge_edge_radius
                .map(|r| r.0),
            net_face_transmission: self.net_face_transmission.map_or(CYAN_GLASS, |t| t.0),
        }))
    }
}
