//! METATOY surfaces (§4–6): thin sheets that change the direction of light rays in ways that
//! ordinary refraction cannot: interfaces between spaces with different optical metrics,
//! generalised confocal lenslet arrays, ray rotation and flipping, phase holograms, phase
//! conjugation, Lorentz- and Galileo-transform windows and teleportation. One law per file, each with a pure
//! direction-change function that works in the surface's local frame or on global vectors.
//!
//! The tracer follows rays backwards from the camera and applies each law to the traced ray.
//! For the transmitted rays of the reciprocal laws (metric refraction, gCLAs with the
//! reverse-order rule, rotation about the direction of crossing, flipping, phase holograms,
//! phase conjugation) this is exactly what light does, since a law that maps d to d′ then maps
//! −d′ to −d; the mirror fallback below is not reciprocal in general. The non-reciprocal
//! Lorentz and Galileo windows, the teleporter, ray rotation in the plane of incidence,
//! collineation surfaces and complex metarefraction (but by odd functions) are defined, as in
//! Dr TIM, by what the camera sees through them.
//!
//! Where a law has no transmitted ray (the "impossible" or evanescent cases), the ray is
//! reflected, as TIM does when refraction fails (total internal reflection, §4.1). As in Dr TIM
//! (`MetricInterface`, `PhaseHologram`: "don't multiply by the transmission coefficient, as this
//! is TIR"), that reflection is lossless unless the law is given a reflection coefficient; the
//! transmission coefficient applies to transmitted rays only.

mod collineation_surface;
mod complex_metarefraction;
mod confocal_lenslet_arrays;
mod derivative_control;
mod galileo_window;
mod gcla_transmission;
mod homogeneous_planar_imaging;
mod ideal_thin_space_plate;
mod idealised_dove_prism_array;
mod lorentz_window;
mod metric_interface;
mod phase_conjugating;
mod phase_hologram;
mod pixellation;
mod point_to_point_imaging_hologram;
mod ray_flipping;
mod ray_rotating;
mod ray_rotating_in_plane_of_incidence;
mod space_shifting;
mod teleporting;
mod variable_eta_confocal_lenslet_arrays;

pub use collineation_surface::{CollineationSurface, CollineationSurfaceKeys};
pub use complex_metarefraction::{
    ComplexFunction, ComplexMetarefraction, ComplexMetarefractionKeys, RefractiveComplexKeys,
};
pub use confocal_lenslet_arrays::{
    ConfocalLensletArrays, ConfocalLensletArraysKeys, Telescopelets,
};
pub use derivative_control::{
    CentralDirections, DerivativeControl, DerivativeControlKeys, ViewRotation,
};
pub use galileo_window::{GalileoWindow, GalileoWindowKeys, galileo_direction};
pub use gcla_transmission::{Apertures, Transmission};
pub use homogeneous_planar_imaging::{HomogeneousPlanarImaging, Telescopes};
pub use ideal_thin_space_plate::{IdealThinSpacePlate, IdealThinSpacePlateKeys};
pub use idealised_dove_prism_array::{IdealisedDovePrismArray, IdealisedDovePrismArrayKeys};
pub use lorentz_window::{LorentzWindow, LorentzWindowKeys};
pub use metric_interface::{
    MetricInterface, MetricInterfaceKeys, Refraction, metric_reflected_direction,
    metric_refracted_direction,
};
pub use phase_conjugating::{
    Conjugation, PhaseConjugating, PhaseConjugatingKeys, phase_conjugated,
};
pub use phase_hologram::{
    AzimuthalPixelatedFresnelWedgePhase, AzimuthalRadial, CylindricalPhase, LensPhase, LinearPhase,
    Phase, PhaseHologram, PhaseHologramKeys, PhaseKeys, PolynomialPhase, QuadraticPhase,
    RectangularLensletArrayPhase, RotationallySymmetricPhase, Sectors, hologram_direction,
};
pub use pixellation::{Blur, Pixellation, PixellationKeys, Pixels, single_slit_x};
pub use point_to_point_imaging_hologram::{
    LensHologramKeys, PointToPointImagingHologram, PointToPointImagingHologramKeys,
};
pub use ray_flipping::{RayFlipping, RayFlippingKeys, flipped};
pub use ray_rotating::{RayRotating, RayRotatingKeys, RotationAxis, rotated};
pub use ray_rotating_in_plane_of_incidence::{
    RayRotatingInPlaneOfIncidence, RayRotatingInPlaneOfIncidenceKeys, rotated_in_plane_of_incidence,
};
pub use space_shifting::{SpaceShifting, SpaceShiftingKeys};
pub use teleporting::{Teleportation, Teleporting, TeleportingKeys};
pub use variable_eta_confocal_lenslet_arrays::{
    VariableEtaConfocalLensletArrays, VariableEtaConfocalLensletArraysKeys,
};

use glam::{DMat3, DVec3};

use crate::math::Colour;
use crate::math::Frame;
use crate::surfaces::Redirection;

/// Whether a law's vectors and tensors are given in the global (x, y, z) basis or in the
/// surface's local (u, v, w) basis at each point (w the outward normal), which makes a curved
/// surface homogeneous (§4.3, §5.2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
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

/// A law's outgoing direction: transmitted, or reflected where the law has no transmitted ray.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Outgoing {
    Transmitted(DVec3),
    Reflected(DVec3),
}

impl Outgoing {
    /// `out` if the law gives one, else `d` mirrored in the surface with normal `n`.
    fn or_mirrored(out: Option<DVec3>, d: DVec3, n: DVec3) -> Outgoing {
        out.map_or_else(
            || Outgoing::Reflected(super::reflect(d, n)),
            Outgoing::Transmitted,
        )
    }

    pub fn direction(self) -> DVec3 {
        match self {
            Outgoing::Transmitted(d) | Outgoing::Reflected(d) => d,
        }
    }

    /// The ray leaving along this direction, carrying `transmission` of the light if it is
    /// transmitted and `reflection` if it is reflected.
    fn leaves(self, transmission: f64, reflection: f64) -> Redirection<'static> {
        let (direction, factor) = match self {
            Outgoing::Transmitted(d) => (d, transmission),
            Outgoing::Reflected(d) => (d, reflection),
        };
        Redirection::Leaves {
            direction,
            factor: Colour::splat(factor),
        }
    }
}

/// Whether `out` leaves the surface with normal `n` on the far side from where `d` arrived.
fn crosses(d: DVec3, out: DVec3, n: DVec3) -> bool {
    d.dot(n) * out.dot(n) > 0.0
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Total internal reflection carries the reflection coefficient, not the transmission
    /// coefficient: with the default 1 it loses no light.
    #[test]
    fn reflected_rays_carry_the_reflection_coefficient() {
        let d = DVec3::new(0.6, 0.0, 0.8);
        let leaves = |out| Outgoing::or_mirrored(out, d, DVec3::Z).leaves(0.96, 1.0);
        assert_eq!(
            leaves(None),
            Redirection::Leaves {
                direction: DVec3::new(0.6, 0.0, -0.8),
                factor: Colour::ONE
            }
        );
        assert_eq!(
            leaves(Some(d)),
            Redirection::Leaves {
                direction: d,
                factor: Colour::splat(0.96)
            }
        );
    }
}
