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
//! Phases, in Cartesian coordinates (u, v) of a flat surface measured from its reference point
//! (a plane's point, a disc's centre, a parallelogram's corner):
//! - linear (a prism): φ = g·(u, v), a constant kick g;
//! - quadratic (a thin lens of focal length f about a centre c): φ = −|r − c|²/(2f), kick
//!   −(r − c)/f, which focuses a parallel bundle at distance f (paraxially; exactly in the
//!   limit of small apertures), Dr TIM's `PhaseHologramOfLens`;
//! - lens (the exact lens phase): φ = −sign(f)(√(|r − c|² + f²) − |f|), the phase difference
//!   between a plane wave along the normal and a spherical wave about the focal point at
//!   distance f from c. Its kick −sign(f)(r − c)/√(|r − c|² + f²) is the tangential part of
//!   the unit vector from r towards the focal point (away from it for f < 0), so a bundle along
//!   the normal meets the focus exactly, and rays from a focal point leave exactly parallel,
//!   at any aperture;
//! - cylindrical (a cylindrical lens with its axis at an angle ψ from u): φ = −(m·(r − c))²/(2f)
//!   with m the in-plane unit vector perpendicular to the axis.

use glam::{DVec2, DVec3};
use serde::Deserialize;

use super::{Outgoing, jacobian};
use crate::geometry::Interaction;
use crate::keys::{Coefficient, Finite, NonZero, Vector2, coefficient};
use crate::surfaces::{Redirection, Surface};

/// The hologram's phase φ(u, v), as an optical path length.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Phase {
    /// φ = gradient · (u, v).
    Linear { gradient: DVec2 },
    /// φ = −|r − centre|²/(2 focal_length).
    Quadratic { focal_length: f64, centre: DVec2 },
    /// φ = −sign(focal_length)(√(|r − centre|² + focal_length²) − |focal_length|).
    Lens { focal_length: f64, centre: DVec2 },
    /// φ = −(m·(r − centre))²/(2 focal_length), m ⊥ the cylinder axis, which is at
    /// `axis_angle` (radians) from u towards v.
    Cylindrical {
        focal_length: f64,
        centre: DVec2,
        axis_angle: f64,
    },
}

impl Phase {
    /// ∇φ at surface position `r`.
    pub fn gradient(&self, r: DVec2) -> DVec2 {
        match *self {
            Phase::Linear { gradient } => gradient,
            Phase::Quadratic {
                focal_length,
                centre,
            } => -(r - centre) / focal_length,
            Phase::Lens {
                focal_length,
                centre,
            } => {
                let r = r - centre;
                -r / (focal_length
                    * (1.0 + r.length_squared() / (focal_length * focal_length)).sqrt())
            }
            Phase::Cylindrical {
                focal_length,
                centre,
                axis_angle,
            } => {
                let (s, c) = axis_angle.sin_cos();
                let m = DVec2::new(-s, c);
                -m.dot(r - centre) * m / focal_length
            }
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
            phase: self.phase.build(),
            transmission_coefficient: coefficient(self.transmission_coefficient),
            reflection_coefficient: coefficient(self.reflection_coefficient),
        }))
    }
}

/// A [`Phase`] in the scene file: centres (0, 0) and the cylinder axis angle (degrees) 0 when
/// not given.
#[derive(Debug, Deserialize)]
#[serde(tag = "type", rename_all = "kebab-case", deny_unknown_fields)]
enum PhaseKeys {
    Linear {
        gradient: Vector2,
    },
    Quadratic {
        focal_length: NonZero,
        centre: Option<Vector2>,
    },
    Lens {
        focal_length: NonZero,
        centre: Option<Vector2>,
    },
    Cylindrical {
        focal_length: NonZero,
        centre: Option<Vector2>,
        axis_angle_deg: Option<Finite>,
    },
}

impl PhaseKeys {
    fn build(self) -> Phase {
        let centre = |c: Option<Vector2>| c.map_or(DVec2::ZERO, |c| c.0);
        match self {
            PhaseKeys::Linear { gradient } => Phase::Linear {
                gradient: gradient.0,
            },
            PhaseKeys::Quadratic {
                focal_length,
                centre: c,
            } => Phase::Quadratic {
                focal_length: focal_length.0,
                centre: centre(c),
            },
            PhaseKeys::Lens {
                focal_length,
                centre: c,
            } => Phase::Lens {
                focal_length: focal_length.0,
                centre: centre(c),
            },
            PhaseKeys::Cylindrical {
                focal_length,
                centre: c,
                axis_angle_deg,
            } => Phase::Cylindrical {
                focal_length: focal_length.0,
                centre: centre(c),
                axis_angle: axis_angle_deg.map_or(0.0, |a| a.0).to_radians(),
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Disc, Plane, Shape, Sphere};
    use crate::surfaces::tests::{leaves, meet};

    #[test]
    fn the_cylindrical_kick_is_across_the_axis_only() {
        let phase = Phase::Cylindrical {
            focal_length: 2.0,
            centre: DVec2::ZERO,
            axis_angle: 0.0,
        };
        // Axis along u: only the v offset matters.
        assert_eq!(phase.gradient(DVec2::new(5.0, 1.0)), DVec2::new(0.0, -0.5));
    }

    /// Rays from the focal point (c, −f) leave the exact lens phase exactly along the normal,
    /// up to 72° off axis; the quadratic phase bends them by 10° or more from ρ = f on.
    #[test]
    fn the_exact_lens_phase_makes_rays_from_the_focal_point_parallel() {
        let (f, centre) = (2.0, DVec2::new(0.3, -0.4));
        let exact = Phase::Lens {
            focal_length: f,
            centre,
        };
        let paraxial = Phase::Quadratic {
            focal_length: f,
            centre,
        };
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
        let diverging = Phase::Lens {
            focal_length: -f,
            centre,
        };
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
            phase: Phase::Linear {
                gradient: DVec2::new(lambda / period_u, lambda / period_v),
            },
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
