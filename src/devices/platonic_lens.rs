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
//! from `basis_vector_1` and `basis_vector_2` (the third their cross product). As in Dr TIM,
//! the solid itself is shown too (`show_platonic_solid`, Dr TIM's `EditablePlatonicSolid` with
//! its defaults): its vertices and edges as the device's edges, and its faces transparent,
//! passing on 75 % of the light and throwing shadows (Dr TIM's `Transparent(0.75, true)`).

use glam::{DMat3, DVec3};
use serde::Deserialize;

use super::{EdgeDefaults, Edges, LensDevice, Part};
use crate::geometry::{PlatonicKind, PlatonicSolid, Shape, Transform, TriangleMesh};
use crate::keys::{Coefficient, Direction, NonZero, Positive, Vector};
use crate::surfaces::{Surface, ThinLens, Transparent};

/// The transmission coefficient of the faces of Dr TIM's default `EditablePlatonicSolid`.
const FACE_TRANSMISSION_COEFFICIENT: f64 = 0.75;

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
    /// Dr TIM's `showPlatonicSolid`: the solid's vertices and edges (with the device's edges)
    /// and its transparent faces.
    pub show_platonic_solid: bool,
    /// Dr TIM's `showLensEdges`: the edges inside the solid, from its centre to its vertices
    /// (with the device's edges).
    pub show_lens_edges: bool,
}

impl PlatonicLens {
    /// The orthonormal basis the vertex tables are read along.
    fn basis(&self) -> Result<DMat3, String> {
        let x = self.basis_vector_1.normalize();
        let y = self.basis_vector_2.reject_from_normalized(x);
        if y.length() <= 1e-9 * self.basis_vector_2.length() {
            return Err(format!(
                "basis_vector_2 = {} must not be parallel to basis_vector_1 = {}",
                self.basis_vector_2, self.basis_vector_1
            ));
        }
        let y = y.normalize();
        Ok(DMat3::from_cols(x, y, x.cross(y)))
    }

    /// The solid's vertices, placed.
    pub fn vertices(&self) -> Result<Vec<DVec3>, String> {
        let basis = self.basis()?;
        Ok(self
            .platonic_solid
            .vertices()
            .into_iter()
            .map(|v| self.centre + self.radius * (basis * v))
            .collect())
    }

    /// The solid's faces, placed.
    fn faces(&self) -> Result<Shape, String> {
        let solid = PlatonicSolid::new(self.platonic_solid, DVec3::ZERO, self.radius)
            .map_err(|e| e.to_string())?;
        Transform::from_matrix(self.basis()?)
            .map(|turn| turn.then(&Transform::translation(self.centre)))
            .and_then(|place| place.shape(&Shape::PlatonicSolid(solid)))
            .map_err(|e| format!("the Platonic solid: {e}"))
    }
}

impl LensDevice for PlatonicLens {
    /// `lens i-j` for every edge i-j of the solid (vertex indices as in
    /// [`PlatonicKind::vertices`]); with `show_platonic_solid` its `faces` and, with `edges`,
    /// its `vertex i` and `edge i-j`; with `show_lens_edges` and `edges`, Dr TIM's inner edges
    /// (`inner edge i`, from the centre to vertex i).
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
        if let Some(e) = edges_shown.filter(|_| self.show_lens_edges) {
            for (i, &vertex) in v.iter().enumerate() {
                parts.push(e.part(format!("inner edge {i}"), c, vertex)?);
            }
        }
        if self.show_platonic_solid {
            if let Some(e) = edges_shown {
                for &[i, j] in &joined {
                    parts.push(e.part(format!("edge {i}-{j}"), v[i], v[j])?);
                }
                for (i, &vertex) in v.iter().enumerate() {
                    parts.push(e.vertex(format!("vertex {i}"), vertex)?);
                }
            }
            parts.push(Part {
                name: "faces".into(),
                shape: self.faces()?,
                surface: Surface::Transparent(Transparent {
                    transmission_coefficient: FACE_TRANSMISSION_COEFFICIENT,
                }),
                edge: true,
            });
        }
        Ok(parts)
    }

    /// Dr TIM's Platonic solid: its edges shown, radius 0.01, `SurfaceColour.RED_SHINY`.
    fn edge_defaults(&self) -> EdgeDefaults {
        EdgeDefaults {
            shown: true,
            ..EdgeDefaults::HIDDEN_RED
        }
    }
}

/// `lenses = { type = "platonic-lens" }`: Dr TIM's `EditablePlatonicLens`, with the defaults
/// of its constructor `EditablePlatonicLens(parent, studio)` (and of the solid's,
/// `EditablePlatonicSolid(parent, studio)`) for every key not given.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlatonicLensKeys {
    platonic_solid: Option<PlatonicKind>,
    centre: Option<Vector>,
    radius: Option<Positive>,
    basis_vector_1: Option<Direction>,
    basis_vector_2: Option<Direction>,
    focal_length: Option<NonZero>,
    lens_transmission_coefficient: Option<Coefficient>,
    show_platonic_solid: Option<bool>,
    show_lens_edges: Option<bool>,
}

impl PlatonicLensKeys {
    pub fn build(self) -> Result<Box<dyn LensDevice>, String> {
        Ok(Box::new(PlatonicLens {
            platonic_solid: self.platonic_solid.unwrap_or(PlatonicKind::Tetrahedron),
            centre: self.centre.map_or(DVec3::new(0.0, 0.0, 10.0), |c| c.0),
            radius: self.radius.map_or(1.0, |r| r.0),
            basis_vector_1: self.basis_vector_1.map_or(DVec3::X, |b| b.0),
            basis_vector_2: self.basis_vector_2.map_or(DVec3::Y, |b| b.0),
            focal_length: self.focal_length.map_or(1.0, |f| f.0),
            lens_transmission_coefficient: crate::keys::throughput(
                self.lens_transmission_coefficient,
            ),
            show_platonic_solid: self.show_platonic_solid.unwrap_or(true),
            show_lens_edges: self.show_lens_edges.unwrap_or(true),
        }))
    }
}
