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
//! The solid is Dr TIM's (`PlatonicSolidType`, [`PlatonicKind`]): circumradius `radius` about
//! `centre`, in the orientation of its vertex tables, read along the orthonormal basis made
//! from `basis_vector_1` and `basis_vector_2` (the third their cross product).

use glam::DVec3;
use serde::Deserialize;

use super::{Edges, LensDevice, Part};
use crate::geometry::{PlatonicKind, Shape, TriangleMesh};
use crate::keys::{Coefficient, Direction, NonZero, Positive, Vector};
use crate::surfaces::{Surface, ThinLens};

#[derive(Debug, Clone, PartialEq)]
pub struct PlatonicLens {
    pub platonic_solid: PlatonicKind,
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
}

impl LensDevice for PlatonicLens {
    /// `lens i-j` for every edge i-j of the solid (vertex indices as in
    /// [`PlatonicKind::vertices`]) and, with `edges`, Dr TIM's inner edges (`inner edge i`,
    /// from the centre to vertex i) and outer edges (`edge i-j`).
    fn parts(&self, edges_shown: Option<&Edges>) -> Result<Vec<Part>, String> {
        let v = self.vertices()?;
        let c = self.centre;
        let joined = self.platonic_solid.edges();
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

/// `lenses = { type = "platonic-lens" }`: Dr TIM's `EditablePlatonicLens`; the vertex tables'
/// x and y along x and y when not given.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlatonicLensKeys {
    platonic_solid: PlatonicKind,
    centre: Vector,
    radius: Positive,
    basis_vector_1: Option<Direction>,
    basis_vector_2: Option<Direction>,
    focal_length: NonZero,
    lens_transmission_coefficient: Option<Coefficient>,
}

impl PlatonicLensKeys {
    pub fn build(self) -> Result<Box<dyn LensDevice>, String> {
        Ok(Box::new(PlatonicLens {
            platonic_solid: self.platonic_solid,
            centre: self.centre.0,
            radius: self.radius.0,
            basis_vector_1: self.basis_vector_1.map_or(DVec3::X, |b| b.0),
            basis_vector_2: self.basis_vector_2.map_or(DVec3::Y, |b| b.0),
            focal_length: self.focal_length.0,
            lens_transmission_coefficient: crate::keys::coefficient(
                self.lens_transmission_coefficient,
            ),
        }))
    }
}
