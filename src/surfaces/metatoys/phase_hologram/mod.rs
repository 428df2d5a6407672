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
//! Each phase φ(u, v) is a kind in its own file (`phase = { type = "..." }`), a function of
//! the surface's coordinates: on a flat part (a flat shape, a polyhedron's face) its Cartesian
//! plane coordinates measured from its reference point (a plane's point, a disc's centre, a
//! parallelogram's corner), along the frame's u and v; on a curved one the shape's surface
//! coordinates (c₁, c₂) (a sphere's (r φ, r θ), a cylinder's (r φ, z), ...). Adding one: its
//! struct with `gradient` and its keys in a new file (their `build` returns the phase, or the
//! message naming the key for values that cannot go together), a line in [`PhaseKeys`] and a
//! variant of [`Phase`].
//!
//! On a curved surface the kick is the surface gradient of φ. Moving along the surface by
//! dp = e₁ dc₁ + e₂ dc₂, with the coordinate axes eᵢ = ∂p/∂cᵢ, changes the phase by
//! dφ = ∂ᵢφ dcᵢ, so phase matching asks for a tangential kick t with t·eᵢ = ∂ᵢφ (i = 1, 2).
//! Writing t = tʲ eⱼ gives gᵢⱼ tʲ = ∂ᵢφ with the metric gᵢⱼ = eᵢ·eⱼ, so t = gⁱʲ ∂ⱼφ eᵢ
//! (g⁻¹'s components gⁱʲ). In the orthonormal frame (û, v̂) at the point, with A the matrix
//! whose columns are the axes' components (eᵢ = A₁ᵢ û + A₂ᵢ v̂), g = AᵀA and t's
//! components are A g⁻¹ ∂φ = A⁻ᵀ ∂φ, which [`surface_kick`] computes. Only for orthonormal
//! axes is it ∂ᵢφ eᵢ, what Dr TIM's holograms on parametrised surfaces use
//! (`PhaseHologramOfRectangularLensletArrayParametrised`: the derivatives times
//! `getSurfaceCoordinateAxes`); a sphere's axes (sin θ φ̂, θ̂), a cone's, a paraboloid's or a
//! stretched shape's are not.

mod azimuthal_pixelated_fresnel_wedge;
mod crossed_linear_power_lenticular_arrays;
mod cylindrical;
mod cylindrical_lens_spiral;
mod lens;
mod linear;
mod linear_power_lenticular_array;
mod logarithmic_cylindrical_lens_spiral;
mod lohmann_cylindrical_lens_part;
mod lohmann_lens_part;
mod polynomial;
mod quadratic;
mod radial_lenticular_array;
mod rectangular_alvarez_lens_part_array;
mod rectangular_lenslet_array;
mod rotationally_symmetric;
mod sparse_rectangular_lenslet_array;

pub use azimuthal_pixelated_fresnel_wedge::{
    AzimuthalPixelatedFresnelWedgePhase, AzimuthalPixelatedFresnelWedgePhaseKeys,
};
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
pub use polynomial::{PolynomialPhase, PolynomialPhaseKeys};
pub use quadratic::{QuadraticPhase, QuadraticPhaseKeys};
pub use radial_lenticular_array::{RadialLenticularArrayPhase, RadialLenticularArrayPhaseKeys};
pub use rectangular_alvarez_lens_part_array::{
    RectangularAlvarezLensPartArrayPhase, RectangularAlvarezLensPartArrayPhaseKeys,
};
pub use rectangular_lenslet_array::{
    RectangularLensletArrayPhase, RectangularLensletArrayPhaseKeys,
};
pub use rotationally_symmetric::{
    AzimuthalRadial, RotationallySymmetricPhase, RotationallySymmetricPhaseKeys, Sectors,
};
pub use sparse_rectangular_lenslet_array::{
    SparseRectangularLensletArrayPhase, SparseRectangularLensletArrayPhaseKeys,
};

use glam::{DMat2, DVec2, DVec3};
use serde::Deserialize;

use super::{Outgoing, jacobian};
use crate::geometry::Interaction;
use crate::keys::{Coefficient, coefficient, kinds};
use crate::math::Frame;
use crate::surfaces::{Redirection, Surface};

kinds! {
    /// A `phase` table: its `type` names the phase, its other keys are the phase's own.
    pub enum PhaseKeys -> Result<Phase, String> {
        Linear(LinearPhaseKeys),
        Quadratic(QuadraticPhaseKeys),
        Lens(LensPhaseKeys),
        Cylindrical(CylindricalPhaseKeys),
        Polynomial(PolynomialPhaseKeys),
        RotationallySymmetric(RotationallySymmetricPhaseKeys),
        AzimuthalPixelatedFresnelWedge(AzimuthalPixelatedFresnelWedgePhaseKeys),
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
#[derive(Debug, Clone, PartialEq)]
pub enum Phase {
    Linear(LinearPhase),
    Quadratic(QuadraticPhase),
    Lens(LensPhase),
    Cylindrical(CylindricalPhase),
    Polynomial(PolynomialPhase),
    RotationallySymmetric(RotationallySymmetricPhase),
    AzimuthalPixelatedFresnelWedge(AzimuthalPixelatedFresnelWedgePhase),
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
            Phase::Polynomial(p) => p.gradient(r),
            Phase::RotationallySymmetric(p) => p.gradient(r),
            Phase::AzimuthalPixelatedFresnelWedge(p) => p.gradient(r),
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

/// The tangential kick, in the local (u, v) frame `frame`, of the phase gradient
/// (∂φ/∂c₁, ∂φ/∂c₂) in surface coordinates whose axes are `axes` = (∂p/∂c₁, ∂p/∂c₂):
/// gⁱʲ ∂ⱼφ eᵢ, with components A⁻ᵀ ∂φ (see the module's notes); `None` where the axes are
/// parallel or zero (no chart: a pole, an apex).
pub fn surface_kick(axes: [DVec3; 2], frame: &Frame, gradient: DVec2) -> Option<DVec2> {
    let along = |e: DVec3| DVec2::new(e.dot(frame.u), e.dot(frame.v));
    let a = DMat2::from_cols(along(axes[0]), along(axes[1]));
    let kick = (a.determinant() != 0.0).then(|| a.transpose().inverse() * gradient)?;
    kick.is_finite().then_some(kick)
}

impl PhaseHologram {
    pub fn redirect(&self, at: &Interaction) -> Redirection<'static> {
        let frame = at.frame();
        let lambda = jacobian(&frame);
        let d = at.ray.direction;
        // The plane coordinates of a flat part, else the surface coordinates through their
        // axes (shapes with parts that have neither are refused when scenes are read).
        let kick = match at.plane_coordinates() {
            Some(r) => Some(self.phase.gradient(r)),
            None => at
                .coordinate_axes()
                .and_then(|axes| surface_kick(axes, &frame, self.phase.gradient(at.coordinates()))),
        };
        // A kick that is no number (a phase's exponent overflowing) passes no light.
        let Some(kick) = kick.filter(|k| k.is_finite()) else {
            return Redirection::Lost;
        };
        let out = hologram_direction(lambda.transpose() * d, kick).map(|e| lambda * e);
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
    use glam::{DAffine3, DMat3};

    use crate::geometry::{
        BilinearSurface, Cone, Cylinder, Disc, Ellipsoid, EllipticCylinder, Paraboloid, Plane,
        Shape, Sphere, Transformed,
    };
    use crate::surfaces::tests::{leaves, line_miss, meet};

    /// A hologram of `phase` passing all light (and half of it where it reflects).
    fn hologram(phase: Phase) -> PhaseHologram {
        PhaseHologram {
            phase,
            transmission_coefficient: 1.0,
            reflection_coefficient: 0.5,
        }
    }

    /// The hit point and the direction leaving `shape` at its point with surface coordinates
    /// `c`, for a ray arriving there along the unit vector `d` (started just before the
    /// point), which must be transmitted.
    fn leaving(h: &PhaseHologram, shape: &Shape, c: DVec2, d: DVec3) -> (DVec3, DVec3) {
        let p = shape.point_at(c).unwrap();
        let at = meet(shape, p - 1e-3 * d, d);
        assert!(at.point().distance(p) < 1e-9);
        let (out, factor) = leaves(h.redirect(&at));
        assert_eq!(factor, 1.0, "{} at {c}: reflected", shape.kind());
        (p, out)
    }

    /// A phase linear in the first coordinate, φ = g c₁, is an azimuthal phase ℓ ϑ (ϑ the
    /// angle about the axis) with ℓ = g R on a sphere of radius R (c₁ = R ϑ) and on a cone of
    /// base radius R (c₁ = R ϑ). Such a phase adds ℓ to every ray's angular momentum about the
    /// axis, (r × d)·â: the kick's azimuthal part (1/ρ) ∂φ/∂ϑ, at distance ρ from the axis
    /// (the textbook fact behind the orbital angular momentum ℓħ of a vortex beam). Only the
    /// metric gets this right: the sphere's axis ∂p/∂c₁ = sin θ ϑ̂ is not a unit vector, and
    /// ∂φ/∂c₁ along it would add ℓ sin²θ.
    #[test]
    fn an_azimuthal_phase_adds_its_angular_momentum_on_a_sphere_and_a_cone() {
        let g = 0.1;
        let h = hologram(Phase::Linear(LinearPhase {
            gradient: DVec2::new(g, 0.0),
        }));
        let (centre, r) = (DVec3::new(0.5, -1.0, 2.0), 1.5);
        let sphere = Shape::Sphere(Sphere::new(centre, r).unwrap());
        let (apex, axis, height) = (DVec3::new(1.0, 0.0, -1.0), DVec3::new(0.0, 0.6, 0.8), 2.0);
        let cone = Shape::Cone(Cone::new(apex, axis, 35.0, height, true).unwrap());
        let base = height * 35f64.to_radians().tan();
        for (shape, origin, pole, ell) in [
            (&sphere, centre, DVec3::Y, g * r),
            (&cone, apex, axis, g * base),
        ] {
            for k in 0..40 {
                let t = k as f64;
                let c = match shape {
                    Shape::Sphere(_) => r * DVec2::new(0.37 * t - 7.0, 0.3 + 0.063 * t),
                    _ => DVec2::new(base * (0.37 * t - 7.0), 1.0 + 0.024 * t),
                };
                let p = shape.point_at(c).unwrap();
                let n = shape.normal(p, 0);
                let tilt = DVec3::new((0.7 * t).sin(), (1.3 * t).cos(), (0.3 * t).sin());
                let d = (-n + 0.5 * tilt.reject_from_normalized(n)).normalize();
                let (p, out) = leaving(&h, shape, c, d);
                let momentum = |d: DVec3| (p - origin).cross(d).dot(pole);
                let added = momentum(out) - momentum(d);
                assert!(
                    (added - ell).abs() < 1e-12,
                    "{}: {added} against {ell}",
                    shape.kind()
                );
            }
        }
    }

    /// Phase matching on charts whose axes are neither unit vectors nor orthogonal (a
    /// paraboloid's (x, y), a bilinear patch's, an ellipsoid's angles, a sheared sphere's):
    /// along each coordinate the kick t changes the phase as φ does, t·∂p/∂cᵢ = ∂φ/∂cᵢ, with
    /// both sides by central differences (of `point_at`, and of the lens phase written out
    /// here).
    #[test]
    fn the_kick_matches_the_phase_along_both_coordinates_of_skew_charts() {
        let (f, c0) = (6.0, DVec2::new(0.2, -0.1));
        let h = hologram(Phase::Lens(LensPhase {
            focal_length: f,
            centre: c0,
        }));
        let phase = |c: DVec2| -((c - c0).length_squared() + f * f).sqrt();
        let shear = DAffine3::from_mat3_translation(
            DMat3::from_cols(
                DVec3::new(1.0, 0.2, 0.0),
                DVec3::new(0.5, 1.5, -0.3),
                DVec3::new(0.0, 0.4, 0.8),
            ),
            DVec3::new(1.0, 2.0, 3.0),
        );
        let sphere = Shape::Sphere(Sphere::new(DVec3::ZERO, 1.0).unwrap());
        let shapes = [
            Shape::Paraboloid(
                Paraboloid::new(DVec3::ZERO, DVec3::new(0.2, 1.0, 0.1), 0.7, 2.0, true).unwrap(),
            ),
            Shape::BilinearSurface(
                BilinearSurface::new([
                    DVec3::ZERO,
                    DVec3::new(2.0, 0.0, 0.3),
                    DVec3::new(2.5, 1.5, -0.4),
                    DVec3::new(0.0, 1.0, 0.5),
                ])
                .unwrap(),
            ),
            Shape::Ellipsoid(Ellipsoid::new(DVec3::ONE, DVec3::new(1.0, 2.0, 0.5)).unwrap()),
            Shape::Transformed(Transformed::new(sphere, shear).unwrap()),
        ];
        let step = 1e-5;
        for shape in &shapes {
            for k in 0..25 {
                let t = k as f64;
                let c = match shape {
                    Shape::BilinearSurface(_) => DVec2::new(0.1 + 0.07 * t, 0.05 + 0.035 * t),
                    Shape::Paraboloid(_) => DVec2::new(0.11 * t - 1.3, 1.2 - 0.09 * t),
                    _ => DVec2::new(0.2 * t - 2.5, 0.8 + 0.06 * t),
                };
                let p = shape.point_at(c).unwrap();
                let n = shape.normal(p, 0);
                let d = (n + 0.2 * DVec3::new((2.0 * t).sin(), 0.5, (3.0 * t).cos())).normalize();
                let (_, out) = leaving(&h, shape, c, d);
                let kick = (out - d).reject_from_normalized(n);
                for e in [DVec2::X, DVec2::Y] {
                    let along = |s: f64| shape.point_at(c + s * step * e).unwrap();
                    let axis = (along(1.0) - along(-1.0)) / (2.0 * step);
                    let change = (phase(c + step * e) - phase(c - step * e)) / (2.0 * step);
                    assert!(
                        (kick.dot(axis) - change).abs() < 1e-7,
                        "{} at {c}: {} against {change}",
                        shape.kind(),
                        kick.dot(axis)
                    );
                }
            }
        }
    }

    /// The exact lens phase on a cylinder (an open one, radius R; coordinates (R ϑ, z), the
    /// arc along the circumference and the height) focuses a bundle arriving along the normal
    /// at the points of one generator (ϑ = 0), which is straight, as a flat lens does: to the
    /// point at distance f inside along that normal, level with the centre z₀ (or, for
    /// f < 0, away from the point at |f| outside).
    #[test]
    fn a_lens_phase_on_a_cylinder_focuses_a_generator_s_bundle() {
        let (r, z0) = (3.0, 1.5);
        let cylinder = Shape::EllipticCylinder(
            EllipticCylinder::new(
                DVec3::new(0.5, -1.0, 0.0),
                DVec3::new(0.5, 3.0, 1.0),
                DVec2::splat(r),
                None,
                true,
            )
            .unwrap(),
        );
        let centre = cylinder.point_at(DVec2::new(0.0, z0)).unwrap();
        let normal = cylinder.normal(centre, 0);
        for f in [2.0, -2.0] {
            let h = hologram(Phase::Lens(LensPhase {
                focal_length: f,
                centre: DVec2::new(0.0, z0),
            }));
            let focus = centre - f * normal;
            for k in 0..=20 {
                let z = 0.1 + 0.19 * k as f64;
                let (p, out) = leaving(&h, &cylinder, DVec2::new(0.0, z), -normal);
                let (miss, along) = line_miss(p, out, focus);
                assert!(miss < 1e-12, "f = {f}, z = {z}: misses by {miss}");
                assert!(along * f >= 0.0, "f = {f}, z = {z}: {along}");
            }
        }
    }

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
        // A closed cylinder's cap has neither plane coordinates nor coordinate axes: no light.
        let cylinder = Shape::Cylinder(Cylinder::new(DVec3::ZERO, DVec3::Z, 1.0).unwrap());
        let at = meet(&cylinder, DVec3::new(0.1, 0.0, -3.0), DVec3::Z);
        assert_eq!(hologram.redirect(&at), Redirection::Lost);
    }
}
