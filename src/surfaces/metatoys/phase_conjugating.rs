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

use crate::geometry::Interaction;
use crate::surfaces::Redirection;

/// Whether the phase-conjugated light is reflected or transmitted.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
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
            factor: self.coefficient,
        }
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
