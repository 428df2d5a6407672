//! Generalised refraction by a thin phase hologram (§6): the tangential component of the ray
//! direction changes by the gradient of the hologram's phase.
//!
//! Derivation: a phase Φ(u, v) added across a surface adds ∇Φ to the tangential wave vector,
//! k′_t = k_t + ∇Φ (phase matching). With k = 2π/λ and the phase given as φ = Φ/k (an optical
//! path length, so holograms do not depend on the wavelength), the unit direction's tangential
//! part becomes d′_t = d_t + ∇φ, and its normal part keeps its sign with |d′| = 1. If
//! |d′_t| > 1 the transmitted wave is evanescent and the ray is reflected (as TIR, losslessly
//! unless a reflection coefficient is given, as in Dr TIM's `PhaseHologram`). The same kick
//! applied to −d′ gives −d, so the law is reciprocal.
//!
//! Each phase φ(u, v) is a kind in its own file (`phase = { type = "..." }`), in Cartesian
//! coordinates (u, v) of a flat surface measured from its reference point (a plane's point, a
//! disc's centre, a parallelogram's corner). Adding one: its struct with `gradient` and its
//! keys in a new file (their `build` returns the phase, or the message naming the key for
//! values that cannot go together), a line in [`PhaseKeys`] and a variant of [`Phase`].

mod crossed_linear_power_lenticular_arrays;
mod cylindrical;
mod cylindrical_lens_spiral;
mod lens;
mod linear;
mod linear_power_lenticular_array;
mod logarithmic_cylindrical_lens_spiral;
mod lohmann_cylindrical_lens_part;
mod lohmann_lens_part;
mod quadratic;
mod radial_lenticular_array;
mod rectangular_alvarez_lens_part_array;
mod rectangular_lenslet_array;
mod sparse_rectangular_lenslet_array;

pub use crossed_linear_power_lenticular_arrays::{
    CrossedLinearPowerLenticularArraysPhase, CrossedLinearPowerLenticularArraysPhaseKeys,
};
pub use cylindrical::{CylindricalPhase, CylindricalPhaseKeys};
pub use cylindrical_lens_spiral::{
    CylindricalLensSpiralPhase, CylindricalLensSpiralPhaseKeys, SpiralType,
};
pub use lens::{LensPhase, LensPhaseKeys};
pub use linear::{LinearPhase, LinearPhaseKeys};
pub use linear_power_lenticular_array::{
    LinearPowerLenticularArrayPhase, LinearPowerLenticularArrayPhaseKeys,
};
pub use logarithmic_cylindrical_lens_spiral::LogarithmicCylindricalLensSpiralPhaseKeys;
pub use lohmann_cylindrical_lens_part::{
    LohmannCylindricalLensPartPhase, LohmannCylindricalLensPartPhaseKeys,
};
pub use lohmann_lens_part::{LohmannLensPartPhase, LohmannLensPartPhaseKeys};
pub use quadratic::{QuadraticPhase, QuadraticPhaseKeys};
pub use radial_lenticular_array::{RadialLenticularArrayPhase, RadialLenticularArrayPhaseKeys};
pub use rectangular_alvarez_lens_part_array::{
    RectangularAlvarezLensPartArrayPhase, RectangularAlvarezLensPartArrayPhaseKeys,
};
pub use rectangular_lenslet_array::{
    RectangularLensletArrayPhase, RectangularLensletArrayPhaseKeys,
};
pub use sparse_rectangular_lenslet_array::{
    SparseRectangularLensletArrayPhase, SparseRectangularLensletArrayPhaseKeys,
};

use glam::{DVec2, DVec3};
use serde::Deserialize;

use super::{Outgoing, jacobian};
use crate::geometry::Interaction;
use crate::keys::{Coefficient, coefficient, kinds};
use crate::surfaces::{Redirection, Surface};

kinds! {
    /// A `phase` table: its `type` names the phase, its other keys are the phase's own.
    pub enum PhaseKeys -> Result<Phase, String> {
        Linear(LinearPhaseKeys),
        Quadratic(QuadraticPhaseKeys),
        Lens(LensPhaseKeys),
        Cylindrical(CylindricalPhaseKeys),
        RectangularLensletArray(RectangularLensletArrayPhaseKeys),
        SparseRectangularLensletArray(SparseRectangularLensletArrayPhaseKeys),
        RadialLenticularArray(RadialLenticularArrayPhaseKeys),
        LinearPowerLenticularArray(LinearPowerLenticularArrayPhaseKeys),
        CrossedLinearPowerLenticularArrays(CrossedLinearPowerLenticularArraysPhaseKeys),
        LohmannLensPart(LohmannLensPartPhaseKeys),
        LohmannCylindricalLensPart(LohmannCylindricalLensPartPhaseKeys),
        RectangularAlvarezLensPartArray(RectangularAlvarezLensPartArrayPhaseKeys),
        CylindricalLensSpiral(CylindricalLensSpiralPhaseKeys),
        LogarithmicCylindricalLensSpiral(LogarithmicCylindricalLensSpiralPhaseKeys),
    }
}

/// The hologram's phase φ(u, v), as an optical path length.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Phase {
    Linear(LinearPhase),
    Quadratic(QuadraticPhase),
    Lens(LensPhase),
    Cylindrical(CylindricalPhase),
    RectangularLensletArray(RectangularLensletArrayPhase),
    SparseRectangularLensletArray(SparseRectangularLensletArrayPhase),
    RadialLenticularArray(RadialLenticularArrayPhase),
    LinearPowerLenticularArray(LinearPowerLenticularArrayPhase),
    CrossedLinearPowerLenticularArrays(CrossedLinearPowerLenticularArraysPhase),
    LohmannLensPart(LohmannLensPartPhase),
    LohmannCylindricalLensPart(LohmannCylindricalLensPartPhase),
    RectangularAlvarezLensPartArray(RectangularAlvarezLensPartArrayPhase),
    CylindricalLensSpiral(CylindricalLensSpiralPhase),
}

impl Phase {
    /// ∇φ at surface position `r`.
    pub fn gradient(&self, r: DVec2) -> DVec2 {
        match self {
            Phase::Linear(p) => p.gradient(r),
            Phase::Quadratic(p) => p.gradient(r),
            Phase::Lens(p) => p.gradient(r),
            Phase::Cylindrical(p) => p.gradient(r),
            Phase::RectangularLensletArray(p) => p.gradient(r),
            Phase::SparseRectangularLensletArray(p) => p.gradient(r),
            Phase::RadialLenticularArray(p) => p.gradient(r),
            Phase::LinearPowerLenticularArray(p) => p.gradient(r),
            Phase::CrossedLinearPowerLenticularArrays(p) => p.gradient(r),
            Phase::LohmannLensPart(p) => p.gradient(r),
            Phase::LohmannCylindricalLensPart(p) => p.gradient(r),
            Phase::RectangularAlvarezLensPartArray(p) => p.gradient(r),
            Phase::CylindricalLensSpiral(p) => p.gradient(r),
        }
    }
}

#[derive(Debug, Clone, PartialEq)]
pub struct PhaseHologram {
    pub phase: Phase,
    /// Fraction of the light transmitted, in [0, 1].
    pub transmission_coefficient: f64,
    /// Fraction of the light reflected where the wave is evanescent, in [0, 1].
    pub reflection_coefficient: f64,
}

/// The unit direction leaving a hologram with phase gradient `kick` for the unit direction
/// `d`, both in the surface's local (u, v, w) frame; `None` if the wave is evanescent.
pub fn hologram_direction(d: DVec3, kick: DVec2) -> Option<DVec3> {
    let t = DVec2::new(d.x, d.y) + kick;
    let w2 = 1.0 - t.length_squared();
    (w2 > 0.0).then(|| DVec3::new(t.x, t.y, d.z.signum() * w2.sqrt()))
}

impl PhaseHologram {
    pub fn redirect(&self, at: &Interaction) -> Redirection<'static> {
        let frame = at.frame();
        let lambda = jacobian(&frame);
        let d = at.ray.direction;
        // Only flat shapes have the coordinates (checked when scenes are read).
        let Some(r) = at.plane_coordinates() else {
            return Redirection::Lost;
        };
        let out =
            hologram_direction(lambda.transpose() * d, self.phase.gradient(r)).map(|e| lambda * e);
        Outgoing::or_mirrored(out, d, frame.w)
            .leaves(self.transmission_coefficient, self.reflection_coefficient)
    }
}

/// `type = "phase-hologram"`: a `phase` table.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PhaseHologramKeys {
    phase: PhaseKeys,
    #[serde(alias = "transmission")]
    transmission_coefficient: Option<Coefficient>,
    #[serde(alias = "reflection")]
    reflection_coefficient: Option<Coefficient>,
}

impl PhaseHologramKeys {
    pub fn build(self) -> Result<Surface, String> {
        Ok(Surface::PhaseHologram(PhaseHologram {
            phase: self.phase.build()?,
            transmission_coefficient: coefficient(self.transmission_coefficient),
            reflection_coefficient: coefficient(self.reflection_coefficient),
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Disc, Plane, Shape, Sphere};
    use crate::surfaces::tests::{leaves, meet};

    #[test]
    fn the_cylindrical_kick_is_across_the_axis_only() {
        let phase = Phase::Cylindrical(CylindricalPhase {
            focal_length: 2.0,
            centre: DVec2::ZERO,
            axis_angle: 0.0,
        });
        // Axis along u: only the v offset matters.
        assert_eq!(phase.gradient(DVec2::new(5.0, 1.0)), DVec2::new(0.0, -0.5));
    }

    /// Rays from the focal point (c, −f) leave the exact lens phase exactly along the normal,
    /// up to 72° off axis; the quadratic phase bends them by 10° or more from ρ = f on.
    #[test]
    fn the_exact_lens_phase_makes_rays_from_the_focal_point_parallel() {
        let (f, centre) = (2.0, DVec2::new(0.3, -0.4));
        let exact = Phase::Lens(LensPhase {
            focal_length: f,
            centre,
        });
        let paraxial = Phase::Quadratic(QuadraticPhase {
            focal_length: f,
            centre,
        });
        for k in 1..=30 {
            let rho = 0.2 * k as f64;
            let azimuth = 0.7 * k as f64;
            let r = centre + rho * DVec2::new(azimuth.cos(), azimuth.sin());
            let d = DVec3::new(r.x - centre.x, r.y - centre.y, f).normalize();
            let out = hologram_direction(d, exact.gradient(r)).unwrap();
            assert!((out - DVec3::Z).length() < 1e-15, "ρ = {rho}: {out}");
            if rho >= f {
                let bent = hologram_direction(d, paraxial.gradient(r))
                    .map_or(90.0, |e| e.angle_between(DVec3::Z).to_degrees());
                assert!(bent > 10.0, "ρ = {rho}: {bent}°");
            }
        }
        // A diverging lens: a ray along the normal leaves as if from the focal point in front.
        let diverging = Phase::Lens(LensPhase {
            focal_length: -f,
            centre,
        });
        let r = centre + DVec2::new(3.0, 0.0);
        let out = hologram_direction(DVec3::Z, diverging.gradient(r)).unwrap();
        assert!(
            (out - DVec3::new(3.0, 0.0, f).normalize()).length() < 1e-15,
            "{out}"
        );
    }

    #[test]
    fn evanescent_waves_are_refused_and_the_side_is_kept() {
        assert_eq!(hologram_direction(DVec3::Z, DVec2::new(1.5, 0.0)), None);
        let out = hologram_direction(-DVec3::Z, DVec2::new(0.6, 0.0)).unwrap();
        assert!((out - DVec3::new(0.6, 0.0, -0.8)).length() < 1e-15, "{out}");
    }

    /// A linear phase is a diffraction grating. A grating of period Λ has the phase
    /// Φ = 2π u/Λ, i.e. the optical path φ = Φ/k = (λ/Λ) u, so ∇φ = λ/Λ; its first order
    /// obeys the grating equation sin θ′ = sin θ + λ/Λ (angles from the normal, in the plane
    /// of incidence across the grooves), and a second grating along v, of period Λ_v, adds
    /// λ/Λ_v to the direction cosine along v. Checked through `redirect` on the plane z = 0
    /// (u = x, v = y) for light arriving from either side, and on a disc; where
    /// |sin θ + λ/Λ| > 1 the wave is evanescent and the ray is reflected (mirror image) with
    /// the reflection coefficient.
    #[test]
    fn a_linear_phase_diffracts_by_the_grating_equation() {
        let (lambda, period_u, period_v) = (0.5e-6, 2e-6, 5e-6);
        let hologram = PhaseHologram {
            phase: Phase::Linear(LinearPhase {
                gradient: DVec2::new(lambda / period_u, lambda / period_v),
            }),
            transmission_coefficient: 0.9,
            reflection_coefficient: 0.4,
        };
        let plane =
            Shape::Plane(Plane::new(DVec3::new(0.3, 0.2, 0.0), DVec3::Z, DVec3::X).unwrap());
        let disc = Shape::Disc(Disc::new(DVec3::ZERO, DVec3::new(0.0, 0.6, 0.8), 3.0).unwrap());
        for shape in [&plane, &disc] {
            let frame = shape.frame(DVec3::ZERO, 0);
            for (deg, side) in [(0.0f64, -1.0f64), (20.0, -1.0), (-40.0, 1.0), (30.0, 1.0)] {
                let theta = deg.to_radians();
                let d = theta.sin() * frame.u + side * theta.cos() * frame.w;
                let (out, factor) = leaves(hologram.redirect(&meet(shape, -2.0 * d, d)));
                assert_eq!(factor, 0.9);
                assert!((out.length() - 1.0).abs() < 1e-15);
                let sin_out = out.dot(frame.u);
                assert!((sin_out - (theta.sin() + lambda / period_u)).abs() < 1e-15);
                assert!((out.dot(frame.v) - lambda / period_v).abs() < 1e-15);
                assert!(out.dot(frame.w) * side > 0.0, "transmitted");
            }
            // sin θ = 0.9: 0.9 + 0.25 > 1, evanescent.
            let d = 0.9 * frame.u - (1.0f64 - 0.81).sqrt() * frame.w;
            let (out, factor) = leaves(hologram.redirect(&meet(shape, -2.0 * d, d)));
            assert_eq!(factor, 0.4);
            assert!(
                (out - (d - 2.0 * d.dot(frame.w) * frame.w)).length() < 1e-15,
                "{out}"
            );
        }
        // A curved shape has no Cartesian coordinates for the phase: no light.
        let sphere = Shape::Sphere(Sphere::new(DVec3::ZERO, 1.0).unwrap());
        let at = meet(&sphere, DVec3::new(0.1, 0.0, -3.0), DVec3::Z);
        assert_eq!(hologram.redirect(&at), Redirection::Lost);
    }
}
