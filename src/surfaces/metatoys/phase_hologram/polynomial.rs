//! A polynomial phase, Dr TIM's `PhaseHologramWithPolynomialPhase`: φ = Σᵢⱼ aᵢⱼ uⁱ vʲ in the
//! coordinates (u, v) measured from a centre, with the gradient
//! (Σ i aᵢⱼ uⁱ⁻¹ vʲ, Σ j aᵢⱼ uⁱ vʲ⁻¹).
//!
//! Dr TIM lists the coefficients by degree, a[n][m] multiplying x^m y^(n−m) (here
//! `coefficients[m][n − m]`), and returns this gradient as the direction change, so its
//! optical path is the polynomial itself; its class comment's Φ = (π/λ) Σ … (half the phase
//! its code applies) is a slip.

use glam::DVec2;
use serde::Deserialize;

use super::Phase;
use crate::keys::{Finite, Vector2};

/// φ = Σᵢⱼ `coefficients[i][j]` (u − u₀)ⁱ (v − v₀)ʲ, (u₀, v₀) = `centre`.
#[derive(Debug, Clone, PartialEq)]
pub struct PolynomialPhase {
    pub coefficients: Vec<Vec<f64>>,
    pub centre: DVec2,
}

impl PolynomialPhase {
    pub fn gradient(&self, r: DVec2) -> DVec2 {
        let r = r - self.centre;
        let mut gradient = DVec2::ZERO;
        for (i, row) in self.coefficients.iter().enumerate() {
            for (j, &a) in row.iter().enumerate() {
                // Only the terms with the variable (0 · u⁻¹ is no number at u = 0).
                if i > 0 {
                    gradient.x += a * i as f64 * r.x.powi(i as i32 - 1) * r.y.powi(j as i32);
                }
                if j > 0 {
                    gradient.y += a * j as f64 * r.x.powi(i as i32) * r.y.powi(j as i32 - 1);
                }
            }
        }
        gradient
    }
}

/// `phase = { type = "polynomial", coefficients = [[a00, a01, ...], [a10, ...], ...],
/// centre = [u0, v0] }`: `coefficients[i][j]` multiplies uⁱ vʲ (rows of any length; `[]` is a
/// constant phase, Dr TIM's phase without coefficients); centre (0, 0) when not given.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PolynomialPhaseKeys {
    coefficients: Vec<Vec<Finite>>,
    centre: Option<Vector2>,
}

impl PolynomialPhaseKeys {
    pub fn build(self) -> Result<Phase, String> {
        Ok(Phase::Polynomial(PolynomialPhase {
            coefficients: self
                .coefficients
                .into_iter()
                .map(|row| row.into_iter().map(|a| a.0).collect())
                .collect(),
            centre: self.centre.map_or(DVec2::ZERO, |c| c.0),
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The gradient of φ = 0.5 − 2 v + 3 u + 0.25 u v² − 1.5 u³ + 0.75 u² v about (0.3, −0.2),
    /// written out here, against central differences of it, at points on a grid (including
    /// the centre's lines, where u or v vanish).
    #[test]
    fn the_gradient_is_the_derivative_of_the_polynomial() {
        let centre = DVec2::new(0.3, -0.2);
        let phase = PolynomialPhase {
            coefficients: vec![
                vec![0.5, -2.0],
                vec![3.0, 0.0, 0.25],
                vec![0.0, 0.75],
                vec![-1.5],
            ],
            centre,
        };
        let written = |r: DVec2| {
            let (u, v) = (r.x - centre.x, r.y - centre.y);
            0.5 - 2.0 * v + 3.0 * u + 0.25 * u * v * v - 1.5 * u * u * u + 0.75 * u * u * v
        };
        let h = 1e-5;
        for i in -4..=4 {
            for j in -4..=4 {
                let r = centre + 0.4 * DVec2::new(i as f64, j as f64);
                let numeric = DVec2::new(
                    written(r + h * DVec2::X) - written(r - h * DVec2::X),
                    written(r + h * DVec2::Y) - written(r - h * DVec2::Y),
                ) / (2.0 * h);
                let g = phase.gradient(r);
                assert!(g.distance(numeric) < 1e-8, "at {r}: {g} against {numeric}");
            }
        }
        let constant = PolynomialPhase {
            coefficients: vec![],
            centre,
        };
        assert_eq!(constant.gradient(DVec2::ONE), DVec2::ZERO);
    }
}
