//! The Chen–Belin black hole (Dr TIM's `EditableChenBelinBlackHole`): a sphere, the
//! "simulation sphere", filled with the refractive-index profile that Huanyang Chen proposed
//! and Jakub Belin modified to simulate the space round a black hole,
//! n = (jR + r)³ / (r² (r − R)) at distance r from the centre, R the horizon radius
//! ([`IndexProfile::ChenBelin`]). Rays follow the ray equation through it, integrated as the
//! gradient-index lenses' are; a ray that comes within the photon sphere moving inwards falls
//! into the horizon and is black (Dr TIM's black sphere at the horizon).
//!
//! Dr TIM's other simulation, `SPHERICAL_SHELLS_CONSTANT_N` (its `SpaceAroundBlackHoleSphericalShells`,
//! a voxellated refractor), puts the profile in N − 1 concentric shells of constant index between
//! the horizon and the simulation sphere, equally thick, each with the profile's index at its
//! middle radius; here those are nested refractive spheres, lossless inside (Dr TIM's voxel
//! boundaries lose no light) and dimming only where light enters or leaves the simulation sphere.

use glam::DVec3;
use serde::Deserialize;

use super::{Edges, LensDevice, Part};
use crate::geometry::{Shape, Sphere};
use crate::keys::{Coefficient, NonNegative, Positive, Vector};
use crate::math::Colour;
use crate::surfaces::lenses::{GradientIndex, IndexProfile, LensLaw};
use crate::surfaces::{Coloured, Lens, Refractive, Surface};

/// How the profile is simulated (Dr TIM's `SphericallySymmetricRefractiveIndexDistributionSimulationType`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SimulationType {
    /// The smooth profile, its ray equation integrated (`SMOOTH_N`).
    SmoothN,
    /// Concentric shells of constant index (`SPHERICAL_SHELLS_CONSTANT_N`).
    SphericalShellsConstantN,
}

/// Most spherical layers (each is a sphere of the scene, and nested spheres are all visited
/// by a ray's hit test: a render's time grows as the square of their number).
const MAX_SPHERICAL_LAYERS: u32 = 10_000;

#[derive(Debug, Clone, PartialEq)]
pub struct ChenBelinBlackHole {
    pub centre: DVec3,
    pub horizon_radius: f64,
    /// Belin's j (Dr TIM's `jParameter`): 1 is Chen's profile, 3/5 puts the photon sphere at
    /// 3 horizon radii, as for a Schwarzschild black hole.
    pub j_parameter: f64,
    pub simulation_sphere_radius: f64,
    pub simulation_sphere_surface_transmission_coefficient: f64,
    pub simulation_type: SimulationType,
    /// N: the spheres bounding the shells, the horizon's included (Dr TIM's
    /// `numberOfSphericalLayers`), for the shell simulation.
    pub number_of_spherical_layers: u32,
}

impl ChenBelinBlackHole {
    /// n(r) = (jR + r)³ / (r² (r − R)).
    fn index(&self, r: f64) -> f64 {
        let big_r = self.horizon_radius;
        (self.j_parameter * big_r + r).powi(3) / (r * r * (r - big_r))
    }

    /// The shell simulation: spheres `shell K` (K = 1 … N − 1) of radius R + K ΔR, ΔR =
    /// (simulation sphere radius − R)/(N − 1), each with the index of the shell inside it,
    /// n(R + (K − ½) ΔR), over that of the shell outside it (1 beyond the simulation sphere),
    /// and the horizon, a black sphere of radius R.
    fn shells(&self) -> Result<Vec<Part>, String> {
        let (big_r, n) = (self.horizon_radius, self.number_of_spherical_layers);
        if self.simulation_sphere_radius <= big_r {
            return Err(format!(
                "the simulation sphere (radius {}) must be larger than the horizon (radius {big_r})",
                self.simulation_sphere_radius
            ));
        }
        let step = (self.simulation_sphere_radius - big_r) / (n - 1) as f64;
        let shell_index = |k: u32| match k < n {
            true => self.index(big_r + (k as f64 - 0.5) * step),
            false => 1.0,
        };
        let sphere = |name: String, radius: f64| {
            Sphere::new(self.centre, radius)
                .map(Shape::Sphere)
                .map_err(|e| format!("{name}: {e}"))
        };
        let mut parts = vec![Part {
            shape: sphere("horizon".into(), big_r)?,
            name: "horizon".into(),
            surface: Surface::Coloured(Coloured::matt(Colour::splat(0.0))),
            edge: false,
        }];
        for k in 1..n {
            let name = format!("shell {k}");
            parts.push(Part {
                shape: sphere(name.clone(), big_r + k as f64 * step)?,
                name,
                surface: Surface::Refractive(Refractive {
                    index_ratio: shell_index(k) / shell_index(k + 1),
                    transmission_coefficient: match k + 1 == n {
                        true => self.simulation_sphere_surface_transmission_coefficient,
                        false => 1.0,
                    },
                }),
                edge: false,
            });
        }
        Ok(parts)
    }
}

impl LensDevice for ChenBelinBlackHole {
    /// The simulation sphere, `black hole`; in the shell simulation the horizon, `horizon`, and
    /// the spheres `shell 1` … `shell N-1`.
    fn parts(&self, edges: Option<&Edges>) -> Result<Vec<Part>, String> {
        if edges.is_some() {
            return Err("a Chen-Belin black hole has no edges to show (show_edges)".into());
        }
        if self.simulation_type == SimulationType::SphericalShellsConstantN {
            return self.shells();
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
/// not given. Its integrator's parameters (integration type, steps) are Dr TIM's
/// integrator's: timbre integrates with its own (docs/SCENE_FORMAT.md).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ChenBelinBlackHoleKeys {
    centre: Option<Vector>,
    horizon_radius: Option<Positive>,
    j_parameter: Option<NonNegative>,
    simulation_sphere_radius: Option<Positive>,
    simulation_sphere_surface_transmission_coefficient: Option<Coefficient>,
    simulation_type: Option<SimulationType>,
    number_of_spherical_layers: Option<u32>,
}

impl ChenBelinBlackHoleKeys {
    pub fn build(self) -> Result<Box<dyn LensDevice>, String> {
        let simulation_type = self.simulation_type.unwrap_or(SimulationType::SmoothN);
        if let Some(n) = self.number_of_spherical_layers {
            if simulation_type != SimulationType::SphericalShellsConstantN {
                return Err(
                    "number_of_spherical_layers belongs to simulation_type = \"spherical-shells-constant-n\""
                        .into(),
                );
            }
            if !(2..=MAX_SPHERICAL_LAYERS).contains(&n) {
                return Err(format!(
                    "number_of_spherical_layers must be from 2 to {MAX_SPHERICAL_LAYERS}, not {n}"
                ));
            }
        }
        Ok(Box::new(ChenBelinBlackHole {
            centre: self.centre.map_or(DVec3::new(0.0, 0.0, 10.0), |c| c.0),
            horizon_radius: self.horizon_radius.map_or(0.01, |r| r.0),
            j_parameter: self.j_parameter.map_or(0.6, |j| j.0),
            simulation_sphere_radius: self.simulation_sphere_radius.map_or(1.0, |r| r.0),
            simulation_sphere_surface_transmission_coefficient: crate::keys::throughput(
                self.simulation_sphere_surface_transmission_coefficient,
            ),
            simulation_type,
            // Dr TIM's `simulationSphereNumberOfSphericalLayers`.
            number_of_spherical_layers: self.number_of_spherical_layers.unwrap_or(100),
        }))
    }
}
