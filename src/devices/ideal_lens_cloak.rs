//! The tetrahedral ideal-lens cloak (Dr TIM's `EditableIdealLensCloak`; Tyc et al.,
//! "Omnidirectional transformation-optics cloak made from lenses and glenses", JOSA A 33, 1032
//! (2016); Courtial et al., Opt. Express 26, 17872 (2018)): a tetrahedron of height h on an
//! equilateral base of circumradius R, with a lower and an upper inner vertex on its axis, h₁
//! and h₂ above the base, its 16 faces ideal thin lenses. It is the lens simplicial complex
//! (`lens_simplicial_complex.rs`) whose outer vertices stay put and whose inner vertices are
//! seen from outside (in "EM space") at heights h₁′ (`height_lower_inner_vertex_e`) and
//!
//!   h₂′ = h₂ h₁′ (h₁ − h) / (h₁ (h₁′ − h) − h₂ (h₁′ − h₁)),
//!
//! the height at which base centre, lower and upper inner vertex and top have the same
//! cross-ratio in both spaces. This is the EM-space position Dr TIM's closed-form focal lengths
//! (`addLenses`) imply; the unit tests check every lens against those expressions. The lower
//! inner pyramid (the cell on the base) appears squashed into the height h₁′: as h₁′ → 0 it
//! becomes invisible, the cloaked region.
//!
//! Vertices: 0 back, 1 left, 2 right (the base), 3 lower inner, 4 upper inner, 5 top.

use glam::DVec3;
use serde::Deserialize;

use super::lens_simplicial_complex::{CLOAK_EDGES, face_name};
use super::{EdgeDefaults, Edges, LensDevice, LensSimplicialComplex, LensType, Part};
use crate::keys::{Coefficient, Direction, Finite, Positive, Vector};

#[derive(Debug, Clone, PartialEq)]
pub struct IdealLensCloak {
    pub base_centre: DVec3,
    pub front_direction: DVec3,
    pub right_direction: DVec3,
    pub top_direction: DVec3,
    /// R: distance of the base vertices from the base centre.
    pub base_radius: f64,
    /// h: height of the top vertex above the base.
    pub height: f64,
    /// h₁ (0 < h₁ < h₂).
    pub height_lower_inner_vertex_p: f64,
    /// h₂ (h₁ < h₂ < h).
    pub height_upper_inner_vertex_p: f64,
    /// h₁′: the lower inner vertex's height in EM space.
    pub height_lower_inner_vertex_e: f64,
    pub interface_transmission_coefficient: f64,
    /// What each lens is (Dr TIM's `lensElementType`).
    pub lens_element_type: LensType,
}

/// Dr TIM's frames of the ideal-lens cloaks: hidden, radius 0.02, `SurfaceColour.RED_SHINY`.
pub(super) const CLOAK_FRAMES: EdgeDefaults = EdgeDefaults {
    radius: 0.02,
    ..EdgeDefaults::HIDDEN_RED
};

/// Dr TIM's names of the faces, by their vertices.
const FACES: [([usize; 3], &str); 16] = [
    ([0, 1, 2], "base outer lens"),
    ([1, 2, 5], "front outer lens"),
    ([0, 1, 5], "left outer lens"),
    ([0, 2, 5], "right outer lens"),
    ([1, 2, 4], "front upper inner pyramid lens"),
    ([0, 1, 4], "left upper inner pyramid lens"),
    ([0, 2, 4], "right upper inner pyramid lens"),
    ([1, 2, 3], "front lower inner pyramid lens"),
    ([0, 1, 3], "left lower inner pyramid lens"),
    ([0, 2, 3], "right lower inner pyramid lens"),
    ([0, 4, 5], "back upper vertical lens"),
    ([1, 4, 5], "left upper vertical lens"),
    ([2, 4, 5], "right upper vertical lens"),
    ([0, 3, 4], "back lower vertical lens"),
    ([1, 3, 4], "left lower vertical lens"),
    ([2, 3, 4], "right lower vertical lens"),
];

/// A cloak's unit front, right and top directions and its upper inner vertex's EM-space height
/// h₂′, checked.
pub(super) struct Layout {
    pub front: DVec3,
    pub right: DVec3,
    pub top: DVec3,
    pub h2e: f64,
}

impl IdealLensCloak {
    /// The directions and h₂′ of this cloak (and of a polygonal one with its parameters).
    pub(super) fn layout(&self) -> Result<Layout, String> {
        let h2e = upper_inner_height_e(
            self.height,
            self.height_lower_inner_vertex_p,
            self.height_upper_inner_vertex_p,
            self.height_lower_inner_vertex_e,
        )?;
        let (front, right, top) = axes(
            self.front_direction,
            self.right_direction,
            self.top_direction,
        )?;
        Ok(Layout {
            front,
            right,
            top,
            h2e,
        })
    }
}

impl LensDevice for IdealLensCloak {
    /// The lenses, named as in Dr TIM (`base outer lens`, ...), and with `edges` its frames
    /// `edge I-J` (vertex numbers above).
    fn parts(&self, edges: Option<&Edges>) -> Result<Vec<Part>, String> {
        let (h, h1, h2, h1e) = (
            self.height,
            self.height_lower_inner_vertex_p,
            self.height_upper_inner_vertex_p,
            self.height_lower_inner_vertex_e,
        );
        let Layout {
            front,
            right,
            top,
            h2e,
        } = self.layout()?;
        let (sin, cos) = 120f64.to_radians().sin_cos();
        let r = self.base_radius;
        let c = self.base_centre;
        let base = [
            c - r * front,
            c - r * sin * right - r * cos * front,
            c + r * sin * right - r * cos * front,
        ];
        let above = |height: f64| c + height * top;
        let vertices = vec![base[0], base[1], base[2], above(h1), above(h2), above(h)];
        let mut vertices_v = vertices.clone();
        vertices_v[3] = above(h1e);
        vertices_v[4] = above(h2e);
        let complex = LensSimplicialComplex {
            vertices,
            vertices_v,
            edges: CLOAK_EDGES.to_vec(),
            lens_transmission_coefficient: self.interface_transmission_coefficient,
            lens_type: self.lens_element_type,
            structure_v: None,
        };
        let mut parts = complex.parts(edges)?;
        rename(
            &mut parts,
            FACES.iter().map(|(f, name)| (*f, name.to_string())),
        );
        Ok(parts)
    }

    fn edge_defaults(&self) -> EdgeDefaults {
        CLOAK_FRAMES
    }
}

/// h₂′, the EM-space height of the upper inner vertex (module comment), after checking that
/// 0 < h₁ < h₂ < h.
fn upper_inner_height_e(h: f64, h1: f64, h2: f64, h1e: f64) -> Result<f64, String> {
    if !(0.0 < h1 && h1 < h2 && h2 < h) {
        return Err(format!(
            "the inner vertices must lie inside, 0 < height_lower_inner_vertex_p < height_upper_inner_vertex_p < height, got {h1}, {h2} and {h}"
        ));
    }
    let denominator = h1 * (h1e - h) - h2 * (h1e - h1);
    if denominator.abs() <= 1e-12 * h * h {
        return Err(format!(
            "with height_lower_inner_vertex_e = {h1e} the upper inner vertex would be seen at infinity"
        ));
    }
    Ok(h2 * h1e * (h1 - h) / denominator)
}

/// Unit front, right and top directions: top as given, then front and right made
/// perpendicular to it and to each other, in this order (Dr TIM's `setDirections`).
fn axes(front: DVec3, right: DVec3, top: DVec3) -> Result<(DVec3, DVec3, DVec3), String> {
    let top = top.normalize();
    let front = front.reject_from_normalized(top);
    let right = right.reject_from_normalized(top).reject_from(front);
    if front.length() <= 1e-12 || right.length() <= 1e-12 {
        return Err(
            "front_direction, right_direction and top_direction must not lie in one plane".into(),
        );
    }
    Ok((front.normalize(), right.normalize(), top))
}

/// Gives the faces named in `names` (by their vertices, in any order) those names.
pub(super) fn rename(parts: &mut [Part], names: impl Iterator<Item = ([usize; 3], String)>) {
    for (mut face, name) in names {
        face.sort_unstable();
        let complex_name = face_name(face);
        if let Some(p) = parts.iter_mut().find(|p| p.name == complex_name) {
            p.name = name;
        }
    }
}

/// The keys of the tetrahedral and the polygonal ideal-lens cloak, with the defaults of Dr
/// TIM's constructors `EditableIdealLensCloak(parent, studio)` and
/// `EditablePolygonalIdealLensCloak(parent, studio)` (the same for these keys): a regular
/// tetrahedron of height 2 standing on y = −1 at z = 10, its lower inner vertex seen 1 below the
/// base.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CloakKeys {
    base_centre: Option<Vector>,
    front_direction: Option<Direction>,
    right_direction: Option<Direction>,
    top_direction: Option<Direction>,
    base_radius: Option<Positive>,
    height: Option<Positive>,
    height_lower_inner_vertex_p: Option<Finite>,
    height_upper_inner_vertex_p: Option<Finite>,
    height_lower_inner_vertex_e: Option<Finite>,
    interface_transmission_coefficient: Option<Coefficient>,
    lens_element_type: Option<LensType>,
}

impl CloakKeys {
    pub(super) fn cloak(self) -> IdealLensCloak {
        let length = |x: Option<Positive>, default: f64| x.map_or(default, |x| x.0);
        let height = |x: Option<Finite>, default: f64| x.map_or(default, |x| x.0);
        IdealLensCloak {
            base_centre: self
                .base_centre
                .map_or(DVec3::new(0.0, -1.0, 10.0), |c| c.0),
            front_direction: self.front_direction.map_or(DVec3::NEG_Z, |d| d.0),
            right_direction: self.right_direction.map_or(DVec3::X, |d| d.0),
            top_direction: self.top_direction.map_or(DVec3::Y, |d| d.0),
            base_radius: length(self.base_radius, 2.0 * 2.0 / 3.0),
            height: length(self.height, 2.0),
            height_lower_inner_vertex_p: height(self.height_lower_inner_vertex_p, 2.0 / 3.0),
            height_upper_inner_vertex_p: height(self.height_upper_inner_vertex_p, 2.0 * 2.0 / 3.0),
            height_lower_inner_vertex_e: height(self.height_lower_inner_vertex_e, -1.0),
            interface_transmission_coefficient: crate::keys::throughput(
                self.interface_transmission_coefficient,
            ),
            lens_element_type: self.lens_element_type.unwrap_or_default(),
        }
    }
}

/// `lenses = { type = "ideal-lens-cloak" }`: Dr TIM's `EditableIdealLensCloak`.
#[derive(Debug, Deserialize)]
#[serde(transparent)]
pub struct IdealLensCloakKeys(CloakKeys);

impl IdealLensCloakKeys {
    pub fn build(self) -> Result<Box<dyn LensDevice>, String> {
        Ok(Box::new(self.0.cloak()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cloak(h1e: f64) -> IdealLensCloak {
        // Dr TIM's default (a regular tetrahedron), but with the EM-space height h1e.
        IdealLensCloak {
            base_centre: DVec3::new(0.0, -1.0, 10.0),
            front_direction: DVec3::new(0.0, 0.0, -1.0),
            right_direction: DVec3::X,
            top_direction: DVec3::Y,
            base_radius: 4.0 / 3.0,
            height: 2.0,
            height_lower_inner_vertex_p: 2.0 / 3.0,
            height_upper_inner_vertex_p: 4.0 / 3.0,
            height_lower_inner_vertex_e: h1e,
            interface_transmission_coefficient: 0.96,
            lens_element_type: LensType::IdealThinLens,
        }
    }

    /// Every lens against the focal lengths and nodal points of Dr TIM's
    /// `EditableIdealLensCloak.addLenses` (h₃ = h, f₀₀ the base lens's focal length, which
    /// images the lower inner vertex from h₁ to h₁′ through the base centre). Focal lengths are
    /// compared in magnitude: their signs follow each code's own choice of the faces' normals.
    #[test]
    fn the_lenses_are_dr_tims() {
        for h1e in [-1.0, 0.1 * 2.0 / 3.0, 0.3, 1.0] {
            let c = cloak(h1e);
            let (h1, h2, h3, r) = (2.0 / 3.0, 4.0 / 3.0, 2.0, 4.0 / 3.0);
            // The base lens images h₁ to h₁′ (both measured into the tetrahedron, axis down).
            let f00 = h1 * h1e / (h1e - h1);
            let k = f00 * (h1 - h3) + h1 * h3;
            let s3 = 3f64.sqrt();
            let expected = [
                ("base outer lens", f00, 0.0),
                (
                    "front outer lens",
                    (h3 - h2) * k * r / (h1 * h2 * (4.0 * h3 * h3 + r * r).sqrt()),
                    h3,
                ),
                (
                    "front upper inner pyramid lens",
                    f00 * (h1 - h2) * (h2 - h3) * r / (h1 * h3 * (4.0 * h2 * h2 + r * r).sqrt()),
                    h2,
                ),
                (
                    "front lower inner pyramid lens",
                    -(h1 - h2) * k * r / (h2 * h3 * (4.0 * h1 * h1 + r * r).sqrt()),
                    h1,
                ),
                (
                    "back upper vertical lens",
                    (h2 - h3) * k * r / (2.0 * s3 * h1 * h2 * h3),
                    h3,
                ),
                (
                    "back lower vertical lens",
                    -(h1 - h2) * k * r / (2.0 * s3 * h1 * h2 * h3),
                    h1,
                ),
            ];
            let parts = c.parts(None).unwrap();
            for (name, f, nodal_height) in expected {
                let nodal = DVec3::new(0.0, -1.0 + nodal_height, 10.0);
                crate::devices::checks::lens(&parts, name, f, nodal, &format!("h1e = {h1e}"));
            }
        }
    }
}
