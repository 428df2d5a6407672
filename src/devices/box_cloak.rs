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
//! its image, which sends the point c + t u (n̂·u = r) to
//!
//!   c + t u / (1 − (μ − 1)(t − 1)),   μ − 1 = (e − p)/(e (p − 1)).
//!
//! Neighbouring maps agree on the faces between them, so each face is the glens
//! ([`Glens::imaging`]) that images a point x behind it into V_front⁻¹(V_behind(x)) in front,
//! the glens Dr TIM's conjugate pairs give it.

use glam::{DMat3, DMat4, DVec3, DVec4};
use serde::Deserialize;

use super::polyhedral_shell::{AxisNames, Interface, Polyhedron, Region, Shell};
use super::rochester_cloak::RochesterCloak;
use super::{EdgeDefaults, Edges, LensDevice, Part};
use crate::geometry::{ConvexPolygon, Shape, Transform};
use crate::keys::{Coefficient, Direction, Finite, Positive, Vector, throughput};
use crate::surfaces::{Glens, Surface, Transparent};

/// The parameters of Dr TIM's `EditableBoxCloak`, shared by its cloak types.
#[derive(Debug, Clone, PartialEq)]
pub struct BoxCloakParameters {
    pub centre: DVec3,
    /// Unit front, right and top directions, perpendicular as Dr TIM's
    /// `EditableBoxCloak.setDirections` makes them: right loses its part along front, top
    /// keeps only its part along front × right.
    pub front: DVec3,
    pub right: DVec3,
    pub top: DVec3,
    pub side_length: f64,
    /// e: the inner volume's apparent size, as a fraction of the side length.
    pub inner_volume_size_factor_em: f64,
    /// p: the inner volume's size, as a fraction of the side length.
    pub inner_volume_size_factor_p: f64,
    pub interface_transmission_coefficient: f64,
    /// Every glens replaced by a transparent sheet of the same transmission coefficient (Dr
    /// TIM's `showPlaceholderSurfaces`).
    pub show_placeholder_surfaces: bool,
}

impl BoxCloakParameters {
    /// Refuses a cloak whose faces f64 cannot place: p within 10⁻⁶ of 0 or 1, or a side length
    /// below 10⁻⁶ of the centre's distance from the origin.
    pub(super) fn check_precision(&self) -> Result<(), String> {
        let p = self.inner_volume_size_factor_p;
        if !(1e-6..=1.0 - 1e-6).contains(&p) {
            return Err(format!(
                "inner_volume_size_factor_p = {p} must lie between 0 and 1, at least 1e-6 from \
                 either: the inner volume lies inside the outer one"
            ));
        }
        let far = self.centre.length();
        if self.side_length < 1e-6 * far {
            return Err(format!(
                "side_length = {} is too small for a cloak {far} from the origin: its faces \
                 could not be placed accurately (at least 1e-6 of that distance)",
                self.side_length
            ));
        }
        Ok(())
    }

    /// A glens face of the cloak, or its placeholder.
    pub fn face(&self, name: String, vertices: Vec<DVec3>, glens: Glens) -> Result<Part, String> {
        Ok(Part {
            shape: Shape::ConvexPolygon(
                ConvexPolygon::new(vertices).map_err(|e| format!("{name}: {e}"))?,
            ),
            name,
            surface: if self.show_placeholder_surfaces {
                Surface::Transparent(Transparent {
                    transmission_coefficient: self.interface_transmission_coefficient,
                })
            } else {
                Surface::Glens(glens)
            },
            edge: false,
        })
    }

    /// Dr TIM's frames: hidden, radius 0.01 × the side length, `SurfaceColour.RED_SHINY`.
    pub fn edge_defaults(&self) -> EdgeDefaults {
        EdgeDefaults {
            radius: 0.01 * self.side_length,
            ..EdgeDefaults::HIDDEN_RED
        }
    }
}

/// The cubic box cloak.
#[derive(Debug, Clone, PartialEq)]
pub struct BoxCloak(pub BoxCloakParameters);

/// The box cloak's part names: `top right front`.
const NAMES: AxisNames = AxisNames {
    directions: [["top", "bottom"], ["right", "left"], ["front", "back"]],
    separator: " ",
};

impl BoxCloak {
    fn shell(&self) -> Result<Shell, String> {
        let BoxCloak(b) = self;
        b.check_precision()?;
        let (e, p) = (b.inner_volume_size_factor_em, b.inner_volume_size_factor_p);
        if e.abs() <= 1e-9 || (e - 1.0).abs() <= 1e-9 {
            return Err(format!(
                "inner_volume_size_factor_em = {e} would show the inner cube as a point (0) or \
                 in the outer cube's faces (1): choose another"
            ));
        }
        Ok(Shell::new(
            Polyhedron::Cube,
            b.centre,
            [b.top, b.right, b.front],
            b.side_length,
            p * b.side_length,
            &NAMES,
        ))
    }

    /// The map V through which `region` is seen from outside, in homogeneous coordinates of
    /// the cloak's own: the centre at the origin, the half side 1.
    fn seen(&self, shell: &Shell, region: Region) -> DMat4 {
        let BoxCloak(b) = self;
        let (e, p) = (b.inner_volume_size_factor_em, b.inner_volume_size_factor_p);
        match region {
            Region::Outside => DMat4::IDENTITY,
            Region::Inside => DMat4::from_scale(DVec3::splat(e / p)),
            Region::Frustum(f) => {
                let n = shell.faces[f].normal;
                let mu_1 = (e - p) / (e * (p - 1.0));
                // (u, 1) ↦ (u, 1 − (μ − 1)(n̂·u − 1)).
                DMat4::from_cols(
                    DVec4::new(1.0, 0.0, 0.0, -mu_1 * n.x),
                    DVec4::new(0.0, 1.0, 0.0, -mu_1 * n.y),
                    DVec4::new(0.0, 0.0, 1.0, -mu_1 * n.z),
                    DVec4::new(0.0, 0.0, 0.0, 1.0 + mu_1),
                )
            }
        }
    }

    /// A face of the shell as the glens imaging the region behind it into the one in front,
    /// worked out in the cloak's own coordinates and placed.
    fn interface(&self, shell: &Shell, face: Interface) -> Result<Part, String> {
        let BoxCloak(b) = self;
        let h = 0.5 * b.side_length;
        let imaging = self.seen(shell, face.front).inverse() * self.seen(shell, face.behind);
        let placed = Transform::from_matrix(DMat3::from_diagonal(DVec3::splat(h)))
            .map_err(|e| e.to_string())?
            .then(&Transform::translation(b.centre));
        let glens = Glens::imaging(
            (face.vertices[0] - b.centre) / h,
            face.normal,
            imaging,
            1.0,
            b.interface_transmission_coefficient,
        )
        .and_then(|g| g.transformed(&placed))
        .map_err(|e| format!("{}: {e}", face.name))?;
        b.face(face.name, face.vertices, glens)
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

    fn edge_defaults(&self) -> EdgeDefaults {
        self.0.edge_defaults()
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

/// The keys of Dr TIM's `EditableBoxCloak` and `EditableRochesterCloak`.
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
    show_placeholder_surfaces: Option<bool>,
    cloak_type: Option<BoxCloakType>,
}

impl BoxCloakKeys {
    /// `lenses = { type = "box-cloak" }`, with the defaults of Dr TIM's
    /// `EditableBoxCloak(parent, studio)`: a cubic cloak of side 2 about (0, 0, 10), its inner
    /// cube of side 0.8 × 2 seen as one of side 0.4 × 2.
    pub fn build(self) -> Result<Box<dyn LensDevice>, String> {
        let cloak_type = self.cloak_type.unwrap_or(BoxCloakType::Cubic);
        let parameters = self.parameters(0.4)?;
        let cloak: Box<dyn LensDevice> = match cloak_type {
            BoxCloakType::Cubic => Box::new(BoxCloak(parameters)),
            BoxCloakType::Rochester => Box::new(RochesterCloak(parameters)),
            BoxCloakType::Octahedral | BoxCloakType::Prismatic => {
                let (name, maker) = if let BoxCloakType::Octahedral = cloak_type {
                    ("octahedral", "OctahedralBoxCloakMaker")
                } else {
                    ("prismatic", "PrismaticBoxCloakMaker")
                };
                return Err(format!(
                    "cloak_type = \"{name}\" (Dr TIM's {maker}) is not built yet: \"cubic\" \
                     and \"rochester\" are"
                ));
            }
        };
        // Refuse bad parameters when the scene is read.
        cloak.parts(None)?;
        Ok(cloak)
    }

    /// Whether `cloak_type` is given.
    pub(super) fn has_cloak_type(&self) -> bool {
        self.cloak_type.is_some()
    }

    /// The parameters, Dr TIM's defaults where not given (`em` for
    /// `inner_volume_size_factor_em`, the one default in which its box and Rochester cloaks
    /// differ).
    pub(super) fn parameters(self, em: f64) -> Result<BoxCloakParameters, String> {
        let front = self.front_direction.map_or(DVec3::NEG_Z, |d| d.0);
        let right = self
            .right_direction
            .map_or(DVec3::X, |d| d.0)
            .reject_from_normalized(front);
        if right.length() <= 1e-12 {
            return Err("right_direction must not be along front_direction".into());
        }
        let right = right.normalize();
        let top = (self.top_direction.map_or(DVec3::Y, |d| d.0))
            .project_onto_normalized(front.cross(right));
        if top.length() <= 1e-12 {
            return Err(
                "top_direction must not be perpendicular to both front_direction and right_direction"
                    .into(),
            );
        }
        Ok(BoxCloakParameters {
            centre: self.centre.map_or(DVec3::new(0.0, 0.0, 10.0), |c| c.0),
            front,
            right,
            top: top.normalize(),
            side_length: self.side_length.map_or(2.0, |s| s.0),
            inner_volume_size_factor_em: self.inner_volume_size_factor_em.map_or(em, |e| e.0),
            inner_volume_size_factor_p: self.inner_volume_size_factor_p.map_or(0.8, |p| p.0),
            interface_transmission_coefficient: throughput(self.interface_transmission_coefficient),
            show_placeholder_surfaces: self.show_placeholder_surfaces.unwrap_or(false),
        })
    }
}
