//! Phase conjugation (§6). The surface conjugates the phase of the light, which reverses the
//! wave vector's components that the surface sees, as in Dr TIM's `PhaseConjugating`:
//! - reflective (a phase-conjugating mirror): every ray is reversed, d′ = −d, so light retraces
//!   its path whatever the angle of incidence;
//! - transmissive: only the tangential part is reversed and the ray crosses the surface,
//!   d′ = d∥ − d⊥ with d∥ = (d·n) n along the normal and d⊥ = d − d∥ tangential (a rotation by
//!   180° about the normal).
//!
//! Both laws are their own inverses and reciprocal: −d′ is sent to −d.

use glam::DVec3;
use serde::Deserialize;

use crate::geometry::Interaction;
use crate::keys::{Coefficient, throughput};
use crate::math::Colour;
use crate::surfaces::{Redirection, Surface};

/// Whether the phase-conjugated light is reflected or transmitted.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Conjugation {
    #[default]
    Reflective,
    Transmissive,
}

#[derive(Debug, Clone, PartialEq)]
pub struct PhaseConjugating {
    pub conjugation: Conjugation,
    /// Fraction of the light sent on (reflected or transmitted, as the surface does), in
    /// [0, 1].
    pub coefficient: f64,
}

/// The direction leaving a phase-conjugating surface with unit normal `n` for the direction
/// `d`.
pub fn phase_conjugated(d: DVec3, n: DVec3, conjugation: Conjugation) -> DVec3 {
    match conjugation {
        Conjugation::Reflective => -d,
        Conjugation::Transmissive => 2.0 * d.dot(n) * n - d,
    }
}

impl PhaseConjugating {
    pub fn redirect(&self, at: &Interaction) -> Redirection<'static> {
        Redirection::Leaves {
            direction: phase_conjugated(at.ray.direction, at.normal(), self.conjugation),
            factor: Colour::splat(self.coefficient),
        }
    }
}

/// `type = "phase-conjugating"`: a reflective one (the default) takes a reflection
/// coefficient, a transmissive one a transmission coefficient.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PhaseConjugatingKeys {
    mode: Option<Conjugation>,
    #[serde(alias = "reflection")]
    reflection_coefficient: Option<Coefficient>,
    #[serde(alias = "transmission")]
    transmission_coefficient: Option<Coefficient>,
}

impl PhaseConjugatingKeys {
    pub fn build(self) -> Result<Surface, String> {
        let conjugation = self.mode.unwrap_or_default();
        let (given, wrong) = match conjugation {
            Conjugation::Reflective => (
                self.reflection_coefficient,
                self.transmission_coefficient.map(|_| {
                    "a reflective one has a reflection_coefficient, not a transmission_coefficient"
                }),
            ),
            Conjugation::Transmissive => (
                self.transmission_coefficient,
                self.reflection_coefficient.map(|_| {
                    "a transmissive one (mode = \"transmissive\") has a transmission_coefficient, not a reflection_coefficient"
                }),
            ),
        };
        if let Some(wrong) = wrong {
            return Err(format!("phase-conjugating: {wrong}"));
        }
        Ok(Surface::PhaseConjugating(PhaseConjugating {
            conjugation,
            coefficient: throughput(given),
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Transmissive: the normal component is kept and the tangential one reversed, on a
    /// tilted surface, whichever way the ray crosses; d∥ and d⊥ are computed here by
    /// projection, independently of the law's formula.
    #[test]
    fn transmission_reverses_the_tangential_part_only() {
        let n = DVec3::new(1.0, -2.0, 2.0) / 3.0;
        for d in [
            DVec3::new(0.3, 0.4, 0.866),
            DVec3::new(-0.5, 0.1, -0.7),
            DVec3::new(0.0, 0.6, 0.8),
        ] {
            let d = d.normalize();
            let along = d.project_onto_normalized(n);
            let across = d.reject_from_normalized(n);
            let out = phase_conjugated(d, n, Conjugation::Transmissive);
            assert!((out - (along - across)).length() < 1e-15, "{d}: {out}");
            assert!(out.dot(n) * d.dot(n) > 0.0, "crosses");
            let back = phase_conjugated(-out, n, Conjugation::Transmissive);
            assert!((back + d).length() < 1e-15, "reciprocal");
            assert_eq!(phase_conjugated(d, n, Conjugation::Reflective), -d);
        }
    }
}
