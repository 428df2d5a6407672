//! METATOY surfaces (§4–6): thin sheets that change the direction of light rays in ways that
//! ordinary refraction cannot: interfaces between spaces with different optical metrics,
//! generalised confocal lenslet arrays, ray rotation and flipping, phase holograms, phase
//! conjugation, Lorentz-transform windows and teleportation. One law per file, each with a pure
//! direction-change function that works in the surface's local frame or on global vectors.
//!
//! The tracer follows rays backwards from the camera and applies each law to the traced ray.
//! For the transmitted rays of the reciprocal laws (metric refraction, gCLAs with the
//! reverse-order rule, rotation about the direction of crossing, flipping, phase holograms,
//! phase conjugation) this is exactly what light does, since a law that maps d to d′ then maps
//! −d′ to −d; the mirror fallback below is not reciprocal in general. The non-reciprocal
//! Lorentz window and teleporter are defined by what the camera sees through them.
//!
//! Where a law has no transmitted ray (the "impossible" or evanescent cases), the ray is
//! reflected, as TIM does when refraction fails (total internal reflection, §4.1).

mod confocal_lenslet_arrays;
mod lorentz_window;
mod metric_interface;
mod phase_conjugating;
mod phase_hologram;
mod ray_flipping;
mod ray_rotating;
mod teleporting;

pub use confocal_lenslet_arrays::{ConfocalLensletArrays, Telescopelets};
pub use lorentz_window::LorentzWindow;
pub use metric_interface::{
    MetricInterface, Refraction, metric_reflected_direction, metric_refracted_direction,
};
pub use phase_conjugating::PhaseConjugating;
pub use phase_hologram::{Phase, PhaseHologram, hologram_direction};
pub use ray_flipping::{RayFlipping, flipped};
pub use ray_rotating::{RayRotating, RotationAxis, rotated};
pub use teleporting::Teleporting;

use glam::{DMat3, DVec3};

use crate::math::Frame;

/// Whether a law's vectors and tensors are given in the global (x, y, z) basis or in the
/// surface's local (u, v, w) basis at each point (w the outward normal), which makes a curved
/// surface homogeneous (§4.3, §5.2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Basis {
    #[default]
    Global,
    Local,
}

impl Basis {
    /// `v` in global coordinates, at a point with surface frame `frame`.
    pub fn to_global(self, v: DVec3, frame: &Frame) -> DVec3 {
        match self {
            Basis::Global => v,
            Basis::Local => jacobian(frame) * v,
        }
    }
}

/// Eq 38: Λ = (û v̂ ŵ), whose columns are the local basis vectors in global coordinates; a
/// local vector v is Λ v globally, a global one is Λᵀ v locally.
pub fn jacobian(frame: &Frame) -> DMat3 {
    DMat3::from_cols(frame.u, frame.v, frame.w)
}

/// The direction `out` if the law gives one, else `d` mirrored in the surface with normal `n`.
fn or_reflected(out: Option<DVec3>, d: DVec3, n: DVec3) -> DVec3 {
    out.unwrap_or_else(|| super::reflect(d, n))
}

/// Whether `out` leaves the surface with normal `n` on the far side from where `d` arrived.
fn crosses(d: DVec3, out: DVec3, n: DVec3) -> bool {
    d.dot(n) * out.dot(n) > 0.0
}
