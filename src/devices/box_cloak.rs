//! The cubic box cloak (Dr TIM's `EditableBoxCloak` with `BoxCloakType.CUBIC`, its
//! `CubicBoxCloakMaker`): a cube of glenses of side L about c round an inner cube of side
//! p L (p = `inner_volume_size_factor_p`), which, and anything in it, is seen from outside as a
//! cube of side e L (e = `inner_volume_size_factor_em`), while the space outside the cloak is
//! seen as it is: a non-affine cloak.
//!
//! Its faces are those of a [`Shell`]: the outer and inner cube's and the diagonal faces that
//! cut the shell between them into six frusta. Each region is seen from outside through a
//! projective map V ("electromagnetic space"): the identity outside, the scaling x ↦ c + (e/p)
//! (x − c) inside, and in the frustum on the face of outward normal n̂ (a distance r = L/2 from
//! c) the homology with centre c and the outer face as its axis that sends the inner face onto
//! its image, which sends the point c + t u (t = n̂·u/r) to
//!
//!   c + t u / (1 − (μ − 1)(t − 1)),   μ − 1 = (e − p)/(e (p − 1)).
//!
//! Neighbouring maps agree on the faces between them, so each face is the glens
//! ([`Glens::imaging`]) that images a point x behind it into V_front⁻¹(V_behind(x)) in front,
//! the glens Dr TIM's conjugate pairs give it.

use glam::{DMat4, DVec3, DVec4};
use serde::Deserialize;

use super::polyhedral_shell::{AxisNames, Interface, Polyhedron, Region, Shell};
use super::{EdgeDefaults, Edges, LensDevice, Part};
use crate::geometry::{ConvexPolygon, Shape};
use crate::keys::{Coefficient, Direction, Finite, Positive, Vector, throughput};
use crate::surfaces::{Glens, Surface};

#[derive(Debug, Clone, PartialEq)]
pub struct BoxCloak {
    pub centre: DVec3,
    pub front_direction: DVec3,
    pub right_direction: DVec3,
    pub top_direction: DVec3,
    pub side_length: f64,
    /// e: the inner cube's apparent side, as a fraction of the side length.
    pub inner_volume_size_factor_em: f64,
    /// p: the inner cube's side, as a fraction of the side length.
    pub inner_volume_size_factor_p: f64,
    pub interface_transmission_coefficient: f64,
}

/// The box cloak's part names: `top right front`.
const NAMES: AxisNames = AxisNames {
    directions: [["top", "bottom"], ["right", "left"], ["front", "back"]],
    separator: " ",
};

impl BoxCloak {
    /// The cloak's shell, its axes those of Dr TIM's `EditableBoxCloak.setDirections`: front,
    /// right perpendicular to it, top perpendicular to both on the side of `top_direction`.
    fn shell(&self) -> Result<Shell, String> {
        let (e, p) = (
            self.inner_volume_size_factor_em,
            self.inner_volume_size_factor_p,
        );
        if !(p > 0.0 && p < 1.0) {
            return Err(format!(
                "inner_volume_size_factor_p = {p} must lie between 0 and 1: the inner cube lies \
                 inside the outer one"
            ));
        }
        if e.abs() <= 1e-9 || (e - 1.0).abs() <= 1e-9 {
            return Err(format!(
                "inner_volume_size_factor_em = {e} would show the inner cube as a point (0) or \
                 in the outer cube's faces (1): choose another"
            ));
        }
        let front = self.front_direction.normalize();
        let right = self.right_direction.reject_from_normalized(front);
        if right.length() <= 1e-12 {
            return Err("right_direction must not be along front_direction".into());
        }
        let right = right.normalize();
        let top = self
            .top_direction
            .project_onto_normalized(front.cross(right));
        if top.length() <= 1e-12 {
            return Err(
                "top_direction must not be perpendicular to both front_direction and right_direction"
                    .into(),
            );
        }
        Ok(Shell::new(
            Polyhedron::Cube,
            self.centre,
            [top.normalize(), right, front],
            self.side_length,
            p * self.side_length,
            &NAMES,
        ))
    }

    /// The map V through which `region` is seen from outside, in homogeneous coordinates.
    fn seen(&self, shell: &Shell, region: Region) -> DMat4 {
        let (e, p) = (
            self.inner_volume_size_factor_em,
            self.inner_volume_size_factor_p,
        );
        let about_centre = |m: DMat4| {
            DMat4::from_translation(self.centre) * m * DMat4::from_translation(-self.centre)
        };
        match region {
            Region::Outside => DMat4::IDENTITY,
            Region::Inside => about_centre(DMat4::from_scale(DVec3::splat(e / p))),
            Region::Frustum(f) => {
                let face = &shell.faces[f];
                let mu_1 = (e - p) / (e * (p - 1.0));
                // (u, 1) ↦ (u, 1 − (μ − 1)(n̂·u/r − 1)).
                let row = -mu_1 / face.distance * face.normal;
                about_centre(DMat4::from_cols(
                    DVec4::new(1.0, 0.0, 0.0, row.x),
                    DVec4::new(0.0, 1.0, 0.0, row.y),
                    DVec4::new(0.0, 0.0, 1.0, row.z),
                    DVec4::new(0.0, 0.0, 0.0, 1.0 + mu_1),
                ))
            }
        }
    }

    /// A face of the shell as the glens imaging the region behind it into the one in front.
    fn interface(&self, shell: &Shell, face: Interface) -> Result<Part, String> {
        let imaging = self.seen(shell, face.front).inverse() * self.seen(shell, face.behind);
        let glens = Glens::imaging(
            face.vertices[0],
            face.normal,
            imaging,
            self.interface_transmission_coefficient,
        )
        .map_err(|e| format!("{}: {e}", face.name))?;
        Ok(Part {
            shape: Shape::ConvexPolygon(
                ConvexPolygon::new(face.vertices).map_err(|e| format!("{}: {e}", face.name))?,
            ),
            name: face.name,
            surface: Surface::Glens(glens),
            edge: false,
        })
    }
}

impl LensDevice for BoxCloak {
    /// The glenses `outer face in front direction`, `inner face in front direction` (and
    /// `back`, `top`, `bottom`, `right`, `left`) and `diagonal face between the top and front
    /// faces`, ...; with `edges` Dr TIM's frames, `outer vertex top right front`, `inner vertex
    /// ...`, `outer edge ... to ...`, `inner edge ...` and `diagonal edge at top right front`.
    fn parts(&self, edges: Option<&Edges>) -> Result<Vec<Part>, String> {
        let shell = self.shell()?;
        let mut parts = shell
            .interfaces()
            .into_iter()
            .map(|face| self.interface(&shell, face))
            .collect::<Result<Vec<_>, _>>()?;
        if let Some(e) = edges {
            parts.extend(shell.frames(e)?);
        }
        Ok(parts)
    }

    /// Dr TIM's frames: hidden, radius 0.01 × the side length, `SurfaceColour.RED_SHINY`.
    fn edge_defaults(&self) -> EdgeDefaults {
        EdgeDefaults {
            radius: 0.01 * self.side_length,
            ..EdgeDefaults::HIDDEN_RED
        }
    }
}

/// Dr TIM's `BoxCloakType`.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(rename_all = "kebab-case")]
enum BoxCloakType {
    Cubic,
    Octahedral,
    Prismatic,
    Rochester,
}

/// `lenses = { type = "box-cloak" }`, with the defaults of Dr TIM's `EditableBoxCloak(parent,
/// studio)`: a cubic cloak of side 2 about (0, 0, 10), its inner cube of side 0.8 × 2 seen as
/// one of side 0.4 × 2.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoxCloakKeys {
    centre: Option<Vector>,
    front_direction: Option<Direction>,
    right_direction: Option<Direction>,
    top_direction: Option<Direction>,
    side_length: Option<Positive>,
    inner_volume_size_factor_em: Option<Finite>,
    inner_volume_size_factor_p: Option<Finite>,
    interface_transmission_coefficient: Option<Coefficient>,
    cloak_type: Option<BoxCloakType>,
}

impl BoxCloakKeys {
    pub fn build(self) -> Result<Box<dyn LensDevice>, String> {
        let maker = match self.cloak_type.unwrap_or(BoxCloakType::Cubic) {
            BoxCloakType::Cubic => None,
            BoxCloakType::Octahedral => Some(("octahedral", "OctahedralBoxCloakMaker")),
            BoxCloakType::Prismatic => Some(("prismatic", "PrismaticBoxCloakMaker")),
            BoxCloakType::Rochester => Some(("rochester", "RochesterCloakMaker")),
        };
        if let Some((name, maker)) = maker {
            return Err(format!(
                "cloak_type = \"{name}\" (Dr TIM's {maker}) is not built yet: only \"cubic\" is"
            ));
        }
        let cloak = BoxCloak {
            centre: self.centre.map_or(DVec3::new(0.0, 0.0, 10.0), |c| c.0),
            front_direction: self.front_direction.map_or(DVec3::NEG_Z, |d| d.0),
            right_direction: self.right_direction.map_or(DVec3::X, |d| d.0),
            top_direction: self.top_direction.map_or(DVec3::Y, |d| d.0),
            side_length: self.side_length.map_or(2.0, |s| s.0),
            inner_volume_size_factor_em: self.inner_volume_size_factor_em.map_or(0.4, |e| e.0),
            inner_volume_size_factor_p: self.inner_volume_size_factor_p.map_or(0.8, |p| p.0),
            interface_transmission_coefficient: throughput(self.interface_transmission_coefficient),
        };
        // Refuse bad parameters when the scene is read.
        cloak.parts(None)?;
        Ok(Box::new(cloak))
    }
}
