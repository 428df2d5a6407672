//! Dr TIM's `EditableGCLAsCloak`: the octahedral or square-prismatic cloak of gCLAs, the box
//! cloak of the same type under the names and defaults of Dr TIM's older editable object (the
//! central octahedron's or prism's size a in electromagnetic and a′ in physical space, in
//! units of half the side, are the box cloak's e and p), with its frames shown.

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

    /// Dr TIM's frames: shown, radius 0.01 × the side length (its `frameRadiusOverSideLength`),
    /// `SurfaceColour.GREY50_SHINY`.
    fn edge_defaults(&self) -> EdgeDefaults {
        EdgeDefaults {
            radius: 0.01 * self.side_length,
            ..EdgeDefaults::SHOWN_GREY
        }
    }
}

/// The keys of Dr TIM's `EditableGCLAsCloak`.
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
}

impl GclasCloakKeys {
    /// `lenses = { type = "gclas-cloak" }`, with the defaults of Dr TIM's
    /// `EditableGCLAsCloak(parent, studio)`: an octahedral cloak of side 1 about (0, 0, 10),
    /// a = 0.07, a′ = 0.7, transmission 0.96.
    pub fn build(self) -> Result<Box<dyn LensDevice>, String> {
        let [front, right, top] = super::directions(
            self.front_direction,
            self.right_direction,
            self.top_direction,
        )?;
        let parameters = BoxCloakParameters {
            centre: self.centre.map_or(DEFAULT_CENTRE, |c| c.0),
            front,
            right,
            top,
            side_length: self.side_length.map_or(1.0, |s| s.0),
            inner_volume_size_factor_em: self.a.map_or(0.07, |a| a.0),
            inner_volume_size_factor_p: self.a_prime.map_or(0.7, |a| a.0),
            interface_transmission_coefficient: throughput(self.gclas_transmission_coefficient),
            show_placeholder_surfaces: false,
        };
        let side_length = parameters.side_length;
        let cloak: Box<dyn LensDevice> = match self.cloak_type.unwrap_or(GclaCloakType::Octahedral)
        {
            GclaCloakType::Octahedral => Box::new(OctahedralBoxCloak(parameters)),
            GclaCloakType::Prismatic => Box::new(PrismaticBoxCloak(parameters)),
        };
        // Refuse bad parameters when the scene is read, in the gCLAs cloak's names.
        cloak.parts(None).map_err(|e| {
            e.replace("inner_volume_size_factor_em", "a")
                .replace("inner_volume_size_factor_p", "a_prime")
        })?;
        Ok(Box::new(GclasCloak { cloak, side_length }))
    }
}
