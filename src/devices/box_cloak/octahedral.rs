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

use super::{Axis, BoxCloakParameters};
use crate::devices::{EdgeDefaults, Edges, LensDevice, Part};
use crate::surfaces::metatoys::{HomogeneousPlanarImaging, Transmission};
use crate::surfaces::{ConfocalLensletArrays, Surface};

/// The octahedral box cloak.
#[derive(Debug, Clone, PartialEq)]
pub struct OctahedralBoxCloak(pub BoxCloakParameters);

/// A region: its map V (seen from outside) and a point inside it.
struct Region {
    seen: DMat4,
    inside: DVec3,
}

/// The affine map (homogeneous coordinates) that sends the points `from` to `to`.
fn affine(from: [DVec3; 4], to: [DVec3; 4]) -> Option<DMat4> {
    let columns = |p: [DVec3; 4]| {
        DMat4::from_cols(
            p[0].extend(1.0),
            p[1].extend(1.0),
            p[2].extend(1.0),
            p[3].extend(1.0),
        )
    };
    let from = columns(from);
    let volume = from.determinant();
    (volume.abs()
        > 1e-12
            * from
                .abs()
                .to_cols_array()
                .iter()
                .fold(0.0, |m: f64, x| m.max(*x))
                .powi(3))
    .then(|| columns(to) * from.inverse())
}

impl OctahedralBoxCloak {
    /// The six axis directions, front, back, right, left, top, bottom.
    fn axes(&self) -> [Axis; 6] {
        let [front, right, top] = self.0.axes();
        [front, -front, right, -right, top, -top]
    }

    /// The octahedron's vertex on the axis `n`, in physical (`e` false) or electromagnetic space.
    fn apex(&self, n: DVec3, em: bool) -> DVec3 {
        let b = &self.0;
        let size = if em {
            b.inner_volume_size_factor_em
        } else {
            b.inner_volume_size_factor_p
        };
        size * n
    }

    /// The cube's corner in the directions of the axes `n`.
    fn corner(&self, n: &[DVec3]) -> DVec3 {
        n.iter().sum::<DVec3>()
    }

    /// The region fixing `fixed` cube corners (three of a face, or two or one) and moving the
    /// apexes on the axes `apexes` from physical to electromagnetic space.
    fn region(&self, fixed: &[DVec3], apexes: &[DVec3], name: &str) -> Result<Region, String> {
        let mut from: Vec<DVec3> = fixed.to_vec();
        let mut to = from.clone();
        from.extend(apexes.iter().map(|&n| self.apex(n, false)));
        to.extend(apexes.iter().map(|&n| self.apex(n, true)));
        let seen = affine(
            [from[0], from[1], from[2], from[3]],
            [to[0], to[1], to[2], to[3]],
        )
        .filter(|m| m.determinant().abs() > 1e-12)
        .ok_or_else(|| {
            format!(
                "inner_volume_size_factor_em = {} flattens the {name}: choose another (not 0, 1, 2 \
                 or 3)",
                self.0.inner_volume_size_factor_em
            )
        })?;
        Ok(Region {
            seen,
            inside: from.iter().sum::<DVec3>() / from.len() as f64,
        })
    }

    /// The interface with these vertices between regions `r1` and `r2`, as gCLAs imaging the
    /// one behind it into the one in front.
    fn interface(
        &self,
        name: String,
        vertices: Vec<DVec3>,
        r1: &Region,
        r2: &Region,
    ) -> Result<Part, String> {
        let normal = (vertices[1] - vertices[0])
            .cross(vertices[2] - vertices[0])
            .normalize();
        // The normal points to the region in front.
        let (front, behind) = if normal.dot(r1.inside - vertices[0]) > 0.0 {
            (r1, r2)
        } else {
            (r2, r1)
        };
        let inside_position = vertices[0] - normal;
        let image = front.seen.inverse() * behind.seen * inside_position.extend(1.0);
        let place = self.0.place();
        let imaging = HomogeneousPlanarImaging {
            point_on_plane: vertices[0],
            a: normal,
            inside_position,
            outside_position: image.truncate() / image.w,
        }
        .transformed(&place);
        let vertices = vertices.iter().map(|&v| place.point(v)).collect();
        let transmission = Transmission::Constant(self.0.interface_transmission_coefficient);
        let arrays = ConfocalLensletArrays::imaging(imaging, transmission)
            .map_err(|e| format!("{name}: {e}"))?;
        self.0
            .face(name, vertices, Surface::ConfocalLensletArrays(arrays))
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
        let b = &self.0;
        b.check_precision()?;
        let (e, p) = (b.inner_volume_size_factor_em, b.inner_volume_size_factor_p);
        let axes = self.axes();
        let inside = Region {
            seen: DMat4::from_scale(DVec3::splat(e / p)),
            inside: DVec3::ZERO,
        };
        // e = 0 shows the octahedron as a point, e = 1 its apexes in the cube's faces, e = 2
        // and 3 flatten the edges' and corners' tetrahedra; within 1e-4 of them the maps lose
        // the cloak's accuracy.
        if let Some(k) = [0.0, 1.0, 2.0, 3.0]
            .into_iter()
            .find(|k: &f64| (e - k).abs() < 1e-4)
        {
            return Err(format!(
                "inner_volume_size_factor_em = {e} is within 1e-4 of {k}, which flattens the \
                 octahedral cloak's regions (0, 1, 2 and 3 all do): choose another"
            ));
        }
        // Perpendicular pairs of axes: the cube's edges, each once.
        let perpendicular = |i: usize, j: usize| i / 2 != j / 2;
        let third = |i: usize, j: usize| (0..3).find(|&k| k != i / 2 && k != j / 2).unwrap();
        let mut parts = Vec::new();
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
            let pyramid = self.region(&face[..3], &[n.v], &format!("{} pyramid", n.name))?;
            let outside = Region {
                seen: DMat4::IDENTITY,
                inside: 2.0 * n.v,
            };
            parts.push(self.interface(
                format!("exterior face {}", n.name),
                face.to_vec(),
                &outside,
                &pyramid,
            )?);
            for m in &others {
                let w = axes[2 * third(i, axes.iter().position(|a| a.name == m.name).unwrap())].v;
                let (a, c) = (self.corner(&[n.v, m.v, w]), self.corner(&[n.v, m.v, -w]));
                let edge =
                    self.region(&[a, c], &[n.v, m.v], &format!("{} {} edge", n.name, m.name))?;
                parts.push(self.interface(
                    format!(
                        "interface between the {} pyramid and the {} {} edge",
                        n.name, n.name, m.name
                    ),
                    vec![self.apex(n.v, false), a, c],
                    &pyramid,
                    &edge,
                )?);
            }
        }
        // The corners: star prongs to the edges' tetrahedra, octahedron faces to the inside.
        for signs in 0..8 {
            let pick = |k: usize| axes[2 * k + ((signs >> k) & 1)];
            let three = [pick(0), pick(1), pick(2)];
            let corner = self.corner(&[three[0].v, three[1].v, three[2].v]);
            let label = format!("{} {} {}", three[2].name, three[1].name, three[0].name);
            let region = self.region(
                &[corner],
                &[three[0].v, three[1].v, three[2].v],
                &format!("{label} corner"),
            )?;
            for (x, y) in [(0, 1), (1, 2), (0, 2)] {
                let z = 3 - x - y;
                let (nx, ny) = (three[x], three[y]);
                let edge = self.region(
                    &[corner, self.corner(&[nx.v, ny.v, -three[z].v])],
                    &[nx.v, ny.v],
                    &format!("{} {} edge", nx.name, ny.name),
                )?;
                parts.push(self.interface(
                    format!(
                        "star prong between the {label} corner and the {} {} edge",
                        nx.name, ny.name
                    ),
                    vec![corner, self.apex(nx.v, false), self.apex(ny.v, false)],
                    &region,
                    &edge,
                )?);
            }
            parts.push(self.interface(
                format!("octahedron face {label}"),
                three.iter().map(|a| self.apex(a.v, false)).collect(),
                &region,
                &inside,
            )?);
        }
        if let Some(e) = edges {
            parts.extend(self.frames(e)?);
        }
        Ok(parts)
    }

    fn edge_defaults(&self) -> EdgeDefaults {
        self.0.edge_defaults()
    }
}

impl OctahedralBoxCloak {
    /// Dr TIM's frames: spheres at the cube's and the octahedron's vertices, cylinders along
    /// their edges and from each cube corner to the octahedron's three vertices next to it.
    fn frames(&self, e: &Edges) -> Result<Vec<Part>, String> {
        let axes = self.axes();
        let place = self.0.place();
        let edge = |name: String, a: DVec3, b: DVec3| e.part(name, place.point(a), place.point(b));
        let vertex = |name: String, at: DVec3| e.vertex(name, place.point(at));
        let mut parts = Vec::new();
        for a in &axes {
            parts.push(vertex(
                format!("octahedron vertex {}", a.name),
                self.apex(a.v, false),
            )?);
        }
        for (i, a) in axes.iter().enumerate() {
            for bb in axes
                .iter()
                .skip(i + 1)
                .filter(|bb| bb.v.dot(a.v).abs() < 0.5)
            {
                parts.push(edge(
                    format!("octahedron edge {} {}", a.name, bb.name),
                    self.apex(a.v, false),
                    self.apex(bb.v, false),
                )?);
            }
        }
        for signs in 0..8 {
            let three = |signs: usize| [0, 1, 2].map(|k| axes[2 * k + ((signs >> k) & 1)]);
            let corner = |t: [Axis; 3]| self.corner(&t.map(|a| a.v));
            let label = |t: [Axis; 3]| format!("{} {} {}", t[2].name, t[1].name, t[0].name);
            let here = three(signs);
            parts.push(vertex(
                format!("cube vertex {}", label(here)),
                corner(here),
            )?);
            for (k, a) in here.iter().enumerate() {
                parts.push(edge(
                    format!(
                        "star edge from the {} corner to the {} vertex",
                        label(here),
                        a.name
                    ),
                    corner(here),
                    self.apex(a.v, false),
                )?);
                // Each cube edge once, from its end on the front, right or top side.
                if (signs >> k) & 1 == 0 {
                    let there = three(signs | 1 << k);
                    parts.push(edge(
                        format!("cube edge {} to {}", label(here), label(there)),
                        corner(here),
                        corner(there),
                    )?);
                }
            }
        }
        Ok(parts)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec4;

    #[test]
    fn an_affine_map_from_four_pairs_sends_them() {
        let from = [DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z];
        let to = [
            DVec3::new(1.0, 2.0, 3.0),
            DVec3::new(2.0, 2.0, 3.0),
            DVec3::new(1.0, 4.0, 3.0),
            DVec3::new(0.0, 0.0, 0.0),
        ];
        let m = affine(from, to).unwrap();
        for (f, t) in from.iter().zip(&to) {
            let image = m * f.extend(1.0);
            assert!((image - DVec4::from((*t, 1.0))).length() < 1e-12);
        }
        assert!(
            affine(
                [DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::new(1.0, 1.0, 0.0)],
                to
            )
            .is_none()
        );
    }
}
