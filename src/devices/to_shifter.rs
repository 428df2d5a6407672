//! The transformation-optics shifter (Dr TIM's `SurfaceOfTOShifter` on the spherical shell its
//! `addSphericalShellSceneObjectAsSurface` makes): a shell between two concentric spheres whose
//! medium shows the inner sphere, and everything in it, shifted by δ ([`ToShifter`]). Dr TIM
//! has no editable object for it; the defaults are those of the outer device of its research
//! program `SphericalShiftyCloakVisualiser`.

use glam::DVec3;
use serde::Deserialize;

use super::{Edges, LensDevice, Part};
use crate::geometry::{Shape, Sphere};
use crate::keys::{Coefficient, Positive, Vector, throughput};
use crate::surfaces::{ShiftFunction, Surface, ToShifter};

/// The shifter's shell, as a device.
#[derive(Debug, Clone, PartialEq)]
pub struct ToShifterDevice(pub ToShifter);

impl LensDevice for ToShifterDevice {
    /// Dr TIM's `Outer sphere` and `Inner sphere`, `outer sphere` and `inner sphere` here,
    /// both with the shell's law.
    fn parts(&self, edges: Option<&Edges>) -> Result<Vec<Part>, String> {
        if edges.is_some() {
            return Err("a to-shifter has no edges to show (show_edges)".into());
        }
        let s = &self.0;
        [("outer sphere", s.radius), ("inner sphere", s.inner_radius)]
            .into_iter()
            .map(|(name, radius)| {
                Ok(Part {
                    shape: Shape::Sphere(
                        Sphere::new(s.centre, radius).map_err(|e| format!("{name}: {e}"))?,
                    ),
                    name: name.into(),
                    surface: Surface::ToShifter(s.clone()),
                    edge: false,
                })
            })
            .collect()
    }
}

/// `lenses = { type = "to-shifter" }`, with the parameters of Dr TIM's `SurfaceOfTOShifter`
/// and the defaults of `SphericalShiftyCloakVisualiser`'s outer device: centre (0, 0, 0),
/// radius 1, inner radius 0.5, δ = (0, 1, 0), quadratic, transmission 0.96 (its integrator's
/// parameters are not keys: the shell is traced exactly).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ToShifterKeys {
    centre: Option<Vector>,
    radius: Option<Positive>,
    inner_radius: Option<Positive>,
    delta: Option<Vector>,
    shift_function_type: Option<ShiftFunction>,
    transmission_coefficient: Option<Coefficient>,
}

impl ToShifterKeys {
    pub fn build(self) -> Result<Box<dyn LensDevice>, String> {
        let radius = self.radius.map_or(1.0, |r| r.0);
        let inner_radius = self.inner_radius.map_or(0.5, |r| r.0);
        // Light leaving a surface passes what lies within 1e-9 (1 + |x|) of it.
        if inner_radius >= radius * (1.0 - 1e-6) || inner_radius < 1e-6 * radius {
            return Err(format!(
                "inner_radius = {inner_radius} must lie between 1e-6 and 1 - 1e-6 times radius \
                 = {radius} (the shell between them must have a thickness and a core)"
            ));
        }
        let delta = self.delta.map_or(DVec3::Y, |d| d.0);
        // The shell's points are worked out from δ: beyond this their precision is lost.
        if delta.length() > 1e6 * radius {
            return Err(format!(
                "delta = {delta} is more than 1e6 times radius = {radius}: the shell's points \
                 would lose their precision"
            ));
        }
        Ok(Box::new(ToShifterDevice(ToShifter {
            centre: self.centre.map_or(DVec3::ZERO, |c| c.0),
            radius,
            inner_radius,
            delta,
            shift_function: self.shift_function_type.unwrap_or(ShiftFunction::Quadratic),
            transmission_coefficient: throughput(self.transmission_coefficient),
        })))
    }
}
