//! The octahedral box cloak (Dr TIM's `EditableBoxCloak` with `BoxCloakType.OCTAHEDRAL`, its
//! `OctahedralBoxCloakMaker`, "our first affine cloak"): a cube of side L = 2h about c, with an
//! inner octahedron whose vertices lie p h from c along the cube's axes, which, and anything
//! in it, is seen as the octahedron of vertices e h from c, while the space round the cloak is
//! seen as it is.
//!
//! The cube is cut into the octahedron, a pyramid on each face (its apex the octahedron's vertex
//! on that face's axis), a tetrahedron along each edge (the edge and the apexes of its two
//! faces) and one at each corner (the corner and the apexes of its three faces). Each region is
//! seen through an affine map: the identity outside, x ↦ c + (e/p)(x − c) inside, and in each
//! pyramid or tetrahedron the affine map that keeps its cube corners where they are and moves
//! its apexes c + p h n̂ to c + e h n̂. Neighbouring maps agree on the faces between them, so
//! each face is the homogeneous planar imaging surface (gCLAs, as Dr TIM's `GCLAsWithApertures`
//! of constant transmission) that images the region behind it into the one in front: Dr TIM's
//! exterior faces, "interior interfaces", "star prongs" and "innermost" octahedron faces.

use glam::{DMat4, DVec3};

use super::affine::{Keep, corner_label, corner_position};
use super::{Axis, BoxCloakParameters};
use crate::devices::affine_regions::Region;
use crate::devices::{EdgeDefaults, Edges, LensDevice, Part};

/// The octahedral box cloak.
#[derive(Debug, Clone, PartialEq)]
pub struct OctahedralBoxCloak(pub BoxCloakParameters);

impl OctahedralBoxCloak {
    /// The six axis directions, front, back, right, left, top, bottom.
    fn axes(&self) -> [Axis; 6] {
        let [front, right, top] = self.0.axes();
        [front, -front, right, -right, top, -top]
    }

    /// The cube's corner in the directions of the axes `n`.
    fn corner(&self, n: &[DVec3]) -> DVec3 {
        n.iter().sum::<DVec3>()
    }
}

impl LensDevice for OctahedralBoxCloak {
    /// The gCLAs `exterior face front` (and back, right, left, top, bottom), `interface between
    /// the front pyramid and the front right edge`, ..., `star prong between the top right front
    /// corner and the top right edge`, ... and `octahedron face top right front`, ...; with
    /// `edges` Dr TIM's frames: `cube vertex top right front`, `octahedron vertex front`, `cube
    /// edge ...`, `octahedron edge ...` and `star edge from the top right front corner to the
    /// front vertex`, ...
    fn parts(&self, edges: Option<&Edges>) -> Result<Vec<Part>, String> {
        self.parts_kept(edges, &|_, _| true)
    }

    fn edge_defaults(&self) -> EdgeDefaults {
        self.0.edge_defaults()
    }
}

impl OctahedralBoxCloak {
    /// The parts [`LensDevice::parts`] lists that `keep` keeps.
    pub(super) fn parts_kept(
        &self,
        edges: Option<&Edges>,
        keep: Keep,
    ) -> Result<Vec<Part>, String> {
        let b = &self.0;
        b.check_precision()?;
        let (e, p) = (b.inner_volume_size_factor_em, b.inner_volume_size_factor_p);
        let axes = self.axes();
        let inside = Region {
            seen: DMat4::from_scale(DVec3::splat(e / p)),
            inside: DVec3::ZERO,
        };
        // e = 0 shows the octahedron as a point, e = 1 its apexes in the cube's faces, e = 2
        // and 3 flatten the edges' and corners' tetrahedra.
        b.check_em(&[0.0, 1.0, 2.0, 3.0])?;
        // Perpendicular pairs of axes: the cube's edges, each once.
        let perpendicular = |i: usize, j: usize| i / 2 != j / 2;
        let third = |i: usize, j: usize| (0..3).find(|&k| k != i / 2 && k != j / 2).unwrap();
        let mut parts = Vec::new();
        let mut add = |name: String, vertices: Vec<DVec3>, r1: &Region, r2: &Region| {
            if keep(&name, &vertices) {
                parts.push(b.gclas_interface(name, vertices, r1, r2)?);
            }
            Ok::<(), String>(())
        };
        for (i, n) in axes.iter().enumerate() {
            let others: Vec<&Axis> = axes
                .iter()
                .enumerate()
                .filter(|&(j, _)| perpendicular(i, j))
                .map(|(_, a)| a)
                .collect();
            // others: u, −u, v, −v.
            let (u, v) = (others[0].v, others[2].v);
            let face = [
                self.corner(&[n.v, u, v]),
                self.corner(&[n.v, -u, v]),
                self.corner(&[n.v, -u, -v]),
                self.corner(&[n.v, u, -v]),
            ];
            let pyramid = b.region(&face[..3], &[n.v], &format!("{} pyramid", n.name))?;
            let outside = Region::outside(n.v);
            add(
                format!("exterior face {}", n.name),
                face.to_vec(),
                &outside,
                &pyramid,
            )?;
            for m in &others {
                let w = axes[2 * third(i, axes.iter().position(|a| a.name == m.name).unwrap())].v;
                let (a, c) = (self.corner(&[n.v, m.v, w]), self.corner(&[n.v, m.v, -w]));
                let edge =
                    b.region(&[a, c], &[n.v, m.v], &format!("{} {} edge", n.name, m.name))?;
                add(
                    format!(
                        "interface between the {} pyramid and the {} {} edge",
                        n.name, n.name, m.name
                    ),
                    vec![b.apex(n.v, false), a, c],
                    &pyramid,
                    &edge,
                )?;
            }
        }
        // The corners: star prongs to the edges' tetrahedra, octahedron faces to the inside.
        for three in b.corners() {
            let corner = corner_position(three);
            let label = corner_label(three);
            let region = b.region(
                &[corner],
                &[three[0].v, three[1].v, three[2].v],
                &format!("{label} corner"),
            )?;
            for (x, y) in [(0, 1), (1, 2), (0, 2)] {
                let z = 3 - x - y;
                let (nx, ny) = (three[x], three[y]);
                let edge = b.region(
                    &[corner, self.corner(&[nx.v, ny.v, -three[z].v])],
                    &[nx.v, ny.v],
                    &format!("{} {} edge", nx.name, ny.name),
                )?;
                add(
                    format!(
                        "star prong between the {label} corner and the {} {} edge",
                        nx.name, ny.name
                    ),
                    vec![corner, b.apex(nx.v, false), b.apex(ny.v, false)],
                    &region,
                    &edge,
                )?;
            }
            add(
                format!("octahedron face {label}"),
                three.iter().map(|a| b.apex(a.v, false)).collect(),
                &region,
                &inside,
            )?;
        }
        if let Some(e) = edges {
            parts.extend(self.frames(e, keep)?);
        }
        Ok(parts)
    }
}

impl OctahedralBoxCloak {
    /// Dr TIM's frames that `keep` keeps: spheres at the cube's and the octahedron's vertices,
    /// cylinders along their edges and from each cube corner to the octahedron's three vertices
    /// next to it.
    fn frames(&self, e: &Edges, keep: Keep) -> Result<Vec<Part>, String> {
        let b = &self.0;
        let axes = self.axes();
        let place = b.place();
        let mut parts = Vec::new();
        let mut edge = |name: String, a: DVec3, c: DVec3| {
            if keep(&name, &[a, c]) {
                parts.push(e.part(name, place.point(a), place.point(c))?);
            }
            Ok::<(), String>(())
        };
        for (i, a) in axes.iter().enumerate() {
            for c in axes.iter().skip(i + 1).filter(|c| c.v.dot(a.v).abs() < 0.5) {
                edge(
                    format!("octahedron edge {} {}", a.name, c.name),
                    b.apex(a.v, false),
                    b.apex(c.v, false),
                )?;
            }
        }
        for corner in b.corners() {
            for a in corner {
                edge(
                    format!(
                        "star edge from the {} corner to the {} vertex",
                        corner_label(corner),
                        a.name
                    ),
                    corner_position(corner),
                    b.apex(a.v, false),
                )?;
            }
        }
        for a in &axes {
            let (name, at) = (format!("octahedron vertex {}", a.name), b.apex(a.v, false));
            if keep(&name, &[at]) {
                parts.push(e.vertex(name, place.point(at))?);
            }
        }
        parts.extend(b.cube_frames(e, keep)?);
        Ok(parts)
    }
}
