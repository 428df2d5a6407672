//! Dr TIM's gCLA cloak objects, the box cloaks of gCLAs under the names and defaults of its
//! older editable objects (the central octahedron's or prism's size a in electromagnetic and a′
//! in physical space, in units of half the side, are the box cloak's e and p), with their
//! frames shown:
//!
//! * `EditableGCLAsCloak`: the octahedral or square-prismatic cloak;
//! * `EditableGCLAsTardisWindow`: the sixth of the octahedral cloak behind its front face, a
//!   window through which the space behind appears scaled by a/a′ (its `CLOAK_SIDE`), or the
//!   four of its faces that a limited field of view needs (`CLOAK_SIDE_MINIMUM`).

use glam::DVec3;
use serde::Deserialize;

use super::{BoxCloakParameters, DEFAULT_CENTRE, OctahedralBoxCloak, PrismaticBoxCloak};
use crate::devices::{EdgeDefaults, Edges, LensDevice, Part};
use crate::keys::{Coefficient, Direction, Finite, Positive, Vector, throughput};

/// Dr TIM's `GCLACloakType`.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(rename_all = "kebab-case")]
enum GclaCloakType {
    Octahedral,
    Prismatic,
}

/// Dr TIM's `GCLATardisWindowType`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
enum GclaTardisWindowType {
    /// The cloak's faces behind its front face.
    CloakSide,
    /// Four of them, for a limited field of view.
    CloakSideMinimum,
}

/// Dr TIM's frames of its gCLA objects: shown, radius 0.01 × the side length (its
/// `frameRadiusOverSideLength`), `SurfaceColour.GREY50_SHINY`.
fn frames(side_length: f64) -> EdgeDefaults {
    EdgeDefaults {
        radius: 0.01 * side_length,
        ..EdgeDefaults::SHOWN_GREY
    }
}

/// The gCLAs cloak: an octahedral or prismatic box cloak with frames of its own defaults.
#[derive(Debug)]
pub struct GclasCloak {
    cloak: Box<dyn LensDevice>,
    side_length: f64,
}

impl LensDevice for GclasCloak {
    /// The octahedral or prismatic box cloak's parts.
    fn parts(&self, edges: Option<&Edges>) -> Result<Vec<Part>, String> {
        self.cloak.parts(edges)
    }

    fn edge_defaults(&self) -> EdgeDefaults {
        frames(self.side_length)
    }
}

/// The faces of the minimum Tardis window (Dr TIM's four visible ones).
const MINIMUM: [&str; 4] = [
    "exterior face front",
    "interface between the front pyramid and the front top edge",
    "star prong between the top right front corner and the front top edge",
    "octahedron face top right front",
];

/// The Tardis window: the octahedral cloak's faces and frames on its front side.
#[derive(Debug)]
pub struct GclasTardisWindow {
    cloak: OctahedralBoxCloak,
    minimum: bool,
}

impl GclasTardisWindow {
    /// Whether the window has the cloak's face or frame `name` of these vertices (in the
    /// cloak's own coordinates, front the unit f̂): the faces through the octahedron's front
    /// vertex and the exterior front face (or the four of [`MINIMUM`]), and the frames on the
    /// front side of the cloak's middle plane.
    fn keeps(&self, name: &str, vertices: &[DVec3]) -> bool {
        let b = &self.cloak.0;
        let front = |v: &DVec3| v.dot(b.front);
        if vertices.len() < 3 {
            return vertices.iter().all(|v| front(v) > -1e-9);
        }
        if self.minimum {
            return MINIMUM.contains(&name);
        }
        let apex = b.apex(b.front, false);
        vertices.iter().any(|v| v.distance(apex) < 1e-9)
            || vertices.iter().all(|v| (front(v) - 1.0).abs() < 1e-9)
    }
}

impl LensDevice for GclasTardisWindow {
    /// The octahedral cloak's `exterior face front`, its four `interface between the front
    /// pyramid and the front ... edge`, eight `star prong between the ... front corner and the
    /// front ... edge` and four `octahedron face ... front` (or the four of the minimum window);
    /// with `edges` its frames on the front side: `cube vertex ... front`, `cube edge ...`,
    /// `octahedron vertex ...` and `octahedron edge ...` but the back ones, `star edge from the
    /// ... front corner to the ... vertex`.
    fn parts(&self, edges: Option<&Edges>) -> Result<Vec<Part>, String> {
        self.cloak
            .parts_kept(edges, &|name, vertices| self.keeps(name, vertices))
    }

    fn edge_defaults(&self) -> EdgeDefaults {
        frames(self.cloak.0.side_length)
    }
}

/// The keys of Dr TIM's `EditableGCLAsCloak` and `EditableGCLAsTardisWindow`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GclasCloakKeys {
    centre: Option<Vector>,
    front_direction: Option<Direction>,
    right_direction: Option<Direction>,
    top_direction: Option<Direction>,
    side_length: Option<Positive>,
    a: Option<Finite>,
    a_prime: Option<Finite>,
    gclas_transmission_coefficient: Option<Coefficient>,
    cloak_type: Option<GclaCloakType>,
    tardis_window_type: Option<GclaTardisWindowType>,
}

impl GclasCloakKeys {
    /// `lenses = { type = "gclas-cloak" }`, with the defaults of Dr TIM's
    /// `EditableGCLAsCloak(parent, studio)`: an octahedral cloak of side 1 about (0, 0, 10),
    /// a = 0.07, a′ = 0.7, transmission 0.96.
    pub fn build(self) -> Result<Box<dyn LensDevice>, String> {
        if self.tardis_window_type.is_some() {
            return Err(
                "tardis_window_type belongs to a gclas-tardis-window (a gclas-cloak has a \
                 cloak_type)"
                    .into(),
            );
        }
        let cloak_type = self.cloak_type.unwrap_or(GclaCloakType::Octahedral);
        let parameters = self.parameters()?;
        let side_length = parameters.side_length;
        let cloak: Box<dyn LensDevice> = match cloak_type {
            GclaCloakType::Octahedral => Box::new(OctahedralBoxCloak(parameters)),
            GclaCloakType::Prismatic => Box::new(PrismaticBoxCloak(parameters)),
        };
        checked(cloak.as_ref())?;
        Ok(Box::new(GclasCloak { cloak, side_length }))
    }

    /// The parameters, as a box cloak's, Dr TIM's defaults where not given.
    fn parameters(self) -> Result<BoxCloakParameters, String> {
        let [front, right, top] = super::directions(
            self.front_direction,
            self.right_direction,
            self.top_direction,
        )?;
        Ok(BoxCloakParameters {
            centre: self.centre.map_or(DEFAULT_CENTRE, |c| c.0),
            front,
            right,
            top,
            side_length: self.side_length.map_or(1.0, |s| s.0),
            inner_volume_size_factor_em: self.a.map_or(0.07, |a| a.0),
            inner_volume_size_factor_p: self.a_prime.map_or(0.7, |a| a.0),
            interface_transmission_coefficient: throughput(self.gclas_transmission_coefficient),
            show_placeholder_surfaces: false,
        })
    }
}

/// Refuses bad parameters when the scene is read, in the gCLA objects' names.
fn checked(device: &dyn LensDevice) -> Result<(), String> {
    device.parts(None).map(|_| ()).map_err(|e| {
        e.replace("inner_volume_size_factor_em", "a")
            .replace("inner_volume_size_factor_p", "a_prime")
    })
}

/// `lenses = { type = "gclas-tardis-window" }`: Dr TIM's `EditableGCLAsTardisWindow`, the
/// gCLAs cloak's keys and defaults (its octahedral type) with `tardis_window_type` for its
/// `cloak_type`, by default `"cloak-side"`.
#[derive(Debug, Deserialize)]
#[serde(transparent)]
pub struct GclasTardisWindowKeys(GclasCloakKeys);

impl GclasTardisWindowKeys {
    pub fn build(self) -> Result<Box<dyn LensDevice>, String> {
        let keys = self.0;
        if keys.cloak_type.is_some() {
            return Err(
                "a gclas-tardis-window has no cloak_type (it is a side of the octahedral \
                 gclas-cloak): its tardis_window_type is \"cloak-side\" or \
                 \"cloak-side-minimum\""
                    .into(),
            );
        }
        let minimum = keys.tardis_window_type == Some(GclaTardisWindowType::CloakSideMinimum);
        let window = GclasTardisWindow {
            cloak: OctahedralBoxCloak(keys.parameters()?),
            minimum,
        };
        checked(&window)?;
        Ok(Box::new(window))
    }
}
