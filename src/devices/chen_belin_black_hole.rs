//! The Chen–Belin black hole (Dr TIM's `EditableChenBelinBlackHole`): a sphere, the
//! "simulation sphere", filled with the refractive-index profile that Huanyang Chen proposed
//! and Jakub Belin modified to simulate the space round a black hole,
//! n = (jR + r)³ / (r² (r − R)) at distance r from the centre, R the horizon radius
//! ([`IndexProfile::ChenBelin`]). Rays follow the ray equation through it, integrated as the
//! gradient-index lenses' are; a ray that comes within the photon sphere moving inwards falls
//! into the horizon and is black (Dr TIM's black sphere at the horizon).

use glam::DVec3;
use serde::Deserialize;

use super::{Edges, LensDevice, Part};
use crate::geometry::{Shape, Sphere};
use crate::keys::{Coefficient, NonNegative, Positive, Vector};
use crate::surfaces::lenses::{GradientIndex, IndexProfile, LensLaw};
use crate::surfaces::{Lens, Surface};

#[derive(Debug, Clone, PartialEq)]
pub struct ChenBelinBlackHole {
    pub centre: DVec3,
    pub horizon_radius: f64,
    /// Belin's j (Dr TIM's `jParameter`): 1 is Chen's profile, 3/5 puts the photon sphere at
    /// 3 horizon radii, as for a Schwarzschild black hole.
    pub j_parameter: f64,
    pub simulation_sphere_radius: f64,
    pub simulation_sphere_surface_transmission_coefficient: f64,
}

impl LensDevice for ChenBelinBlackHole {
    /// The simulation sphere, `black hole`.
    fn parts(&self, edges: Option<&Edges>) -> Result<Vec<Part>, String> {
        if edges.is_some() {
            return Err("a Chen-Belin black hole has no edges to show (show_edges)".into());
        }
        let photon_sphere =
            IndexProfile::photon_sphere_radius(self.horizon_radius, self.j_parameter);
        if photon_sphere >= self.simulation_sphere_radius {
            return Err(format!(
                "the photon sphere (radius {photon_sphere}, for horizon_radius = {} and \
                 j_parameter = {}) must lie inside the simulation sphere (radius {})",
                self.horizon_radius, self.j_parameter, self.simulation_sphere_radius
            ));
        }
        let sphere = Sphere::new(self.centre, self.simulation_sphere_radius)
            .map_err(|e| format!("simulation sphere: {e}"))?;
        let profile = IndexProfile::ChenBelin {
            horizon: self.horizon_radius / self.simulation_sphere_radius,
            j: self.j_parameter,
        };
        Ok(vec![Part {
            name: "black hole".into(),
            shape: Shape::Sphere(sphere),
            surface: Surface::Lens(Lens {
                transmission_coefficient: self.simulation_sphere_surface_transmission_coefficient,
                ..Lens::new(LensLaw::GradientIndex(GradientIndex { profile }))
            }),
            edge: false,
        }])
    }
}

/// `lenses = { type = "chen-belin-black-hole" }`: Dr TIM's `EditableChenBelinBlackHole`, with
/// the defaults of its constructor `EditableChenBelinBlackHole(parent, studio)` for every key
/// not given. Its numerical parameters (simulation type, integration type, steps) are Dr
/// TIM's integrator's: timbre integrates with its own (docs/SCENE_FORMAT.md).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ChenBelinBlackHoleKeys {
    centre: Option<Vector>,
    horizon_radius: Option<Positive>,
    j_parameter: Option<NonNegative>,
    simulation_sphere_radius: Option<Positive>,
    simulation_sphere_surface_transmission_coefficient: Option<Coefficient>,
}

impl ChenBelinBlackHoleKeys {
    pub fn build(self) -> Result<Box<dyn LensDevice>, String> {
        Ok(Box::new(ChenBelinBlackHole {
            centre: self.centre.map_or(DVec3::new(0.0, 0.0, 10.0), |c| c.0),
            horizon_radius: self.horizon_radius.map_or(0.01, |r| r.0),
            j_parameter: self.j_parameter.map_or(0.6, |j| j.0),
            simulation_sphere_radius: self.simulation_sphere_radius.map_or(1.0, |r| r.0),
            simulation_sphere_surface_transmission_coefficient: crate::keys::throughput(
                self.simulation_sphere_surface_transmission_coefficient,
            ),
        }))
    }
}
