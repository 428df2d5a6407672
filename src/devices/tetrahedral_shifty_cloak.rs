//! The tetrahedral shifty cloak (Dr TIM's `EditableTetrahedralShiftyCloak`): a
//! [homogeneous planar imaging surface simplicial complex](super::HomogeneousPlanarImagingSurfaceSimplicialComplex)
//! of an outer tetrahedron, four alternate corners of the cube of side `side_length` about the
//! centre along u, v and w, and an inner one from the cube of side `side_length_i`, whose
//! vertices are seen shifted by δ, so that the inner tetrahedron and what it holds appear
//! shifted by δ and the space round the cloak as it is.
//!
//! Dr TIM's two configurations: the *asymmetric* one takes the inner tetrahedron from the same
//! corners as the outer one, each inner vertex j moved 1 % further from outer vertex j + 1 (mod
//! 4) and joined to the other three outer vertices; the *symmetric* one takes the other four
//! corners (the inner tetrahedron inverted), each joined to the three outer vertices it does not
//! face. The complex's cells are found from these edges.

use glam::DVec3;
use serde::Deserialize;

use super::{
    EdgeDefaults, Edges, HomogeneousPlanarImagingSurfaceSimplicialComplex, LensDevice, Part,
};
use crate::keys::{Coefficient, Direction, Positive, Vector, throughput};

#[derive(Debug, Clone, PartialEq)]
pub struct TetrahedralShiftyCloak {
    pub centre: DVec3,
    /// Unit vectors along the cube's edges (Dr TIM uses them as given, normalised).
    pub u: DVec3,
    pub v: DVec3,
    pub w: DVec3,
    pub asymmetric_configuration: bool,
    pub side_length: f64,
    pub side_length_i: f64,
    pub delta: DVec3,
    pub show_interfaces: bool,
    pub interface_transmission_coefficient: f64,
}

/// The cube corners of the outer tetrahedron (signs along u, v, w), Dr TIM's vertices 0 to 3.
const CORNERS: [[f64; 3]; 4] = [
    [1.0, 1.0, 1.0],
    [1.0, -1.0, -1.0],
    [-1.0, 1.0, -1.0],
    [-1.0, -1.0, 1.0],
];

impl TetrahedralShiftyCloak {
    /// The largest `side_length_i` Dr TIM allows (it reduces larger ones to it; here they are
    /// refused): 0.96 of the side length, or of a third of it in the symmetric configuration.
    fn largest_inner_side(&self) -> f64 {
        let s = 0.96 * self.side_length;
        if self.asymmetric_configuration {
            s
        } else {
            s / 3.0
        }
    }

    /// The simplicial complex: vertices 0–3 outer, 4–7 inner (Dr TIM's numbering and edges).
    fn complex(&self) -> HomogeneousPlanarImagingSurfaceSimplicialComplex {
        let corner = |s: [f64; 3], side: f64| {
            self.centre + 0.5 * side * (s[0] * self.u + s[1] * self.v + s[2] * self.w)
        };
        let mut vertices: Vec<DVec3> = CORNERS
            .iter()
            .map(|&s| corner(s, self.side_length))
            .collect();
        let mut edges = vec![[0, 1], [1, 2], [2, 0], [0, 3], [1, 3], [2, 3]];
        edges.extend([[4, 5], [5, 6], [6, 4], [4, 7], [5, 7], [6, 7]]);
        if self.asymmetric_configuration {
            for (j, &s) in CORNERS.iter().enumerate() {
                let from = vertices[(j + 1) % 4];
                vertices.push(from + 1.01 * (corner(s, self.side_length_i) - from));
            }
            for i in 0..4 {
                for j in 0..4 {
                    if i != (j + 1) % 4 {
                        edges.push([i, 4 + j]);
                    }
                }
            }
        } else {
            for s in CORNERS {
                vertices.push(corner(s.map(|x| -x), self.side_length_i));
            }
            // Inner vertex 4 + j is the corner opposite outer vertex j.
            for i in 0..4 {
                for j in 0..4 {
                    if i != j {
                        edges.push([i, 4 + j]);
                    }
                }
            }
        }
        let vertices_v = vertices
            .iter()
            .enumerate()
            .map(|(i, &x)| if i < 4 { x } else { x + self.delta })
            .collect();
        HomogeneousPlanarImagingSurfaceSimplicialComplex {
            vertices,
            vertices_v,
            edges,
            imaging_element_transmission_coefficient: self.interface_transmission_coefficient,
            show_imaging_elements: self.show_interfaces,
            structure_v: None,
        }
    }
}

impl LensDevice for TetrahedralShiftyCloak {
    /// The complex's faces `face I-J-K`, and with `edges` (Dr TIM's frames) its edges `edge
    /// I-J` and vertices `vertex I` (0–3 outer, 4–7 inner).
    fn parts(&self, edges: Option<&Edges>) -> Result<Vec<Part>, String> {
        self.complex().parts(edges)
    }

    /// Dr TIM's frames: shown, radius 0.01, `SurfaceColour.GREY50_SHINY`.
    fn edge_defaults(&self) -> EdgeDefaults {
        EdgeDefaults::SHOWN_GREY
    }
}

/// `lenses = { type = "tetrahedral-shifty-cloak" }`: Dr TIM's `EditableTetrahedralShiftyCloak`,
/// with the defaults of its constructor `(parent, studio)`: about (0, 0, 10), u, v, w along x,
/// y, z, asymmetric, side lengths 1 and 0.3, no shift.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TetrahedralShiftyCloakKeys {
    centre: Option<Vector>,
    u: Option<Direction>,
    v: Option<Direction>,
    w: Option<Direction>,
    asymmetric_configuration: Option<bool>,
    side_length: Option<Positive>,
    side_length_i: Option<Positive>,
    delta: Option<Vector>,
    show_interfaces: Option<bool>,
    interface_transmission_coefficient: Option<Coefficient>,
}

impl TetrahedralShiftyCloakKeys {
    pub fn build(self) -> Result<Box<dyn LensDevice>, String> {
        let direction =
            |d: Option<Direction>, default: DVec3| d.map_or(default, |d| d.0.normalize());
        let cloak = TetrahedralShiftyCloak {
            centre: self.centre.map_or(DVec3::new(0.0, 0.0, 10.0), |c| c.0),
            u: direction(self.u, DVec3::X),
            v: direction(self.v, DVec3::Y),
            w: direction(self.w, DVec3::Z),
            asymmetric_configuration: self.asymmetric_configuration.unwrap_or(true),
            side_length: self.side_length.map_or(1.0, |s| s.0),
            side_length_i: self.side_length_i.map_or(0.3, |s| s.0),
            delta: self.delta.map_or(DVec3::ZERO, |d| d.0),
            show_interfaces: self.show_interfaces.unwrap_or(true),
            interface_transmission_coefficient: throughput(self.interface_transmission_coefficient),
        };
        if cloak.u.cross(cloak.v).dot(cloak.w).abs() < 1e-6 {
            return Err("u, v and w must not lie in one plane".into());
        }
        let largest = cloak.largest_inner_side();
        if cloak.side_length_i > largest {
            return Err(format!(
                "side_length_i is {}, but it can be at most {largest} (0.96 × side_length{}, \
                 as Dr TIM restricts it)",
                cloak.side_length_i,
                if cloak.asymmetric_configuration {
                    ""
                } else {
                    " / 3 in the symmetric configuration"
                }
            ));
        }
        Ok(Box::new(cloak))
    }
}
