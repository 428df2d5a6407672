//! Dr TIM's box cloaks (`EditableBoxCloak` and its `BoxCloakType`s, and
//! `EditableRochesterCloak`): their shared parameters and keys, and one file for each type.

mod affine;
mod cubic;
mod gclas_cloak;
mod octahedral;
mod prismatic;
mod rochester;

pub use cubic::BoxCloak;
pub use gclas_cloak::{GclasCloak, GclasCloakKeys, GclasTardisWindow, GclasTardisWindowKeys};
pub use octahedral::OctahedralBoxCloak;
pub use prismatic::PrismaticBoxCloak;
pub use rochester::RochesterCloak;

use glam::{DMat3, DVec3};
use serde::Deserialize;

use super::{EdgeDefaults, LensDevice, Part};
use crate::geometry::{ConvexPolygon, Shape, Transform};
use crate::keys::{Coefficient, Direction, Finite, Positive, Vector, throughput};
use crate::surfaces::{Surface, Transparent};

/// One of a box cloak's six directions, with Dr TIM's name for it.
#[derive(Debug, Clone, Copy)]
struct Axis {
    name: &'static str,
    v: DVec3,
}

impl std::ops::Neg for Axis {
    type Output = Axis;
    fn neg(self) -> Axis {
        let name = match self.name {
            "front" => "back",
            "back" => "front",
            "top" => "bottom",
            "bottom" => "top",
            "right" => "left",
            _ => "right",
        };
        Axis { name, v: -self.v }
    }
}

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
    /// The front, right and top directions, named.
    fn axes(&self) -> [Axis; 3] {
        [
            Axis {
                name: "front",
                v: self.front,
            },
            Axis {
                name: "right",
                v: self.right,
            },
            Axis {
                name: "top",
                v: self.top,
            },
        ]
    }

    /// The map from the cloak's own coordinates (its centre at the origin, half its side the
    /// unit of length) into the scene's, in which the cloaks work out their faces.
    fn place(&self) -> Transform {
        Transform::from_matrix(DMat3::from_diagonal(DVec3::splat(0.5 * self.side_length)))
            .expect("a positive side length")
            .then(&Transform::translation(self.centre))
    }

    /// Refuses a cloak whose faces cannot be traced accurately: p within 10⁻³ of 0 or 1, or a
    /// side length below 10⁻³ (1 + the centre's distance from the origin).
    pub(super) fn check_precision(&self) -> Result<(), String> {
        let p = self.inner_volume_size_factor_p;
        if !(1e-3..=0.999).contains(&p) {
            return Err(format!(
                "inner_volume_size_factor_p = {p} must lie between 0.001 and 0.999: the inner \
                 volume lies inside the outer one, and closer to either limit its faces would \
                 lie too close together to trace"
            ));
        }
        // Rays leaving a surface pass what lies within 1e-9 (1 + |x|) of it.
        let far = self.centre.length();
        if self.side_length < 1e-3 * (1.0 + far) {
            return Err(format!(
                "side_length = {} is too small for a cloak {far} from the origin: its faces \
                 would lie too close together for rays to tell them apart (at least 1e-3 of 1 \
                 plus that distance)",
                self.side_length
            ));
        }
        Ok(())
    }

    /// A face of the cloak (a glens or gCLAs), or its placeholder.
    pub fn face(
        &self,
        name: String,
        vertices: Vec<DVec3>,
        surface: Surface,
    ) -> Result<Part, String> {
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
                surface
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
            BoxCloakType::Octahedral => Box::new(OctahedralBoxCloak(parameters)),
            BoxCloakType::Prismatic => Box::new(PrismaticBoxCloak(parameters)),
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
        let [front, right, top] = directions(
            self.front_direction,
            self.right_direction,
            self.top_direction,
        )?;
        Ok(BoxCloakParameters {
            centre: self.centre.map_or(DEFAULT_CENTRE, |c| c.0),
            front,
            right,
            top,
            side_length: self.side_length.map_or(2.0, |s| s.0),
            inner_volume_size_factor_em: self.inner_volume_size_factor_em.map_or(em, |e| e.0),
            inner_volume_size_factor_p: self.inner_volume_size_factor_p.map_or(0.8, |p| p.0),
            interface_transmission_coefficient: throughput(self.interface_transmission_coefficient),
            show_placeholder_surfaces: self.show_placeholder_surfaces.unwrap_or(false),
        })
    }
}

/// Dr TIM's default centre of its box and gCLAs cloaks.
const DEFAULT_CENTRE: DVec3 = DVec3::new(0.0, 0.0, 10.0);

/// The unit front, right and top directions as Dr TIM's `setDirections` of its box and gCLAs
/// cloaks makes them: right loses its part along front, top keeps only its part along front ×
/// right. By default (0, 0, −1), (1, 0, 0) and (0, 1, 0).
fn directions(
    front: Option<Direction>,
    right: Option<Direction>,
    top: Option<Direction>,
) -> Result<[DVec3; 3], String> {
    let front = front.map_or(DVec3::NEG_Z, |d| d.0);
    let right = right
        .map_or(DVec3::X, |d| d.0)
        .reject_from_normalized(front);
    if right.length() <= 1e-12 {
        return Err("right_direction must not be along front_direction".into());
    }
    let right = right.normalize();
    let top = (top.map_or(DVec3::Y, |d| d.0)).project_onto_normalized(front.cross(right));
    if top.length() <= 1e-12 {
        return Err(
            "top_direction must not be perpendicular to both front_direction and right_direction"
                .into(),
        );
    }
    Ok([front, right, top.normalize()])
}

/// `lenses = { type = "rochester-cloak" }`: Dr TIM's `EditableRochesterCloak`, its defaults
/// those of `EditableRochesterCloak(parent, studio)`, the box cloak's but for
/// `inner_volume_size_factor_em` = −1.6.
#[derive(Debug, Deserialize)]
#[serde(transparent)]
pub struct RochesterCloakKeys(BoxCloakKeys);

impl RochesterCloakKeys {
    pub fn build(self) -> Result<Box<dyn LensDevice>, String> {
        if self.0.has_cloak_type() {
            return Err(
                "a rochester-cloak has no cloak_type (it is Dr TIM's box cloak of \
                        cloak_type = \"rochester\")"
                    .into(),
            );
        }
        let cloak = RochesterCloak(self.0.parameters(-1.6)?);
        cloak.parts(None)?;
        Ok(Box::new(cloak))
    }
}
