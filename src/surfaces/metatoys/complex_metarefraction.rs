//! Complex-function metarefraction (Dr TIM's `Metarefractive` with the
//! `surfaces/metarefraction/` classes; Constable, Hamilton and Courtial, "Complex
//! representation of light-ray-direction changes"): the tangential part of the unit ray
//! direction, in the surface's local (u, v) basis, is the complex number c = d_u + i d_v; the
//! sheet maps it by a complex function, c′ = f(c) for rays crossing inwards (against the outward
//! normal) and c′ = g(c) for rays crossing outwards, and the ray leaves on the far side with
//! direction (Re c′, Im c′, ±√(1 − |c′|²)). Where |c′| > 1 (infinite too: ln 0, a negative
//! power of 0) the wave is evanescent and the ray is reflected (losslessly unless a reflection
//! coefficient is given); where c′ is not a number no light passes.
//!
//! The functions (f inwards, g outwards; principal branches):
//! - `multiplication`: f(c) = k c, g(c) = c / k. A real k is Snell's law for the index ratio
//!   n_outside / n_inside = k; k = e^{iφ} rotates the direction about the normal by φ.
//! - `addition`: f(c) = c + k, g(c) = c − k (a phase gradient, as a linear phase hologram).
//! - `conjugation`: f = g = conjugate (a flip of the v component, `ray-flipping` about u).
//! - `power`: f(c) = c^p, g(c) = c^(1/p).
//! - `exp`: f = ln, g = exp; `sin`: f = arcsin, g = sin; `cos`: f = arccos, g = cos.
//! - `julia-set`: f(c) = z_N / s, z₀ = s c, z_{k+1} = z_k² + C; it has no inverse, and rays
//!   crossing outwards carry no light (Dr TIM sends them along the normal).
//!
//! Dr TIM's complex refractive index (`RefractiveComplex`) is `multiplication` by the inverse of
//! the complex ratio n_inside / n_outside (`type = "refractive-complex"`).

use glam::DVec3;
use num_complex::Complex64;
use serde::Deserialize;

use super::{Outgoing, jacobian};
use crate::geometry::Interaction;
use crate::keys::{Coefficient, NonZero, Vector2, coefficient, throughput};
use crate::surfaces::{Redirection, Surface, reflect};

/// Most iterations of a Julia-set transform (each ray computes them all).
const MAX_ITERATIONS: u32 = 1000;

/// The complex function pair of a metarefracting sheet (see the module notes).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ComplexFunction {
    Multiplication(Complex64),
    Addition(Complex64),
    Conjugation,
    Power(f64),
    Exp,
    Sin,
    Cos,
    JuliaSet {
        constant: Complex64,
        iterations: u32,
        normalisation: f64,
    },
}

impl ComplexFunction {
    /// c′ for a ray crossing inwards (f) or outwards (g); `None` where there is none.
    pub fn map(&self, c: Complex64, inwards: bool) -> Option<Complex64> {
        use ComplexFunction::*;
        Some(match (*self, inwards) {
            (Multiplication(k), true) => c * k,
            (Multiplication(k), false) => c / k,
            (Addition(k), true) => c + k,
            (Addition(k), false) => c - k,
            (Conjugation, _) => c.conj(),
            (Power(p), true) => c.powf(p),
            (Power(p), false) => c.powf(1.0 / p),
            (Exp, true) => c.ln(),
            (Exp, false) => c.exp(),
            (Sin, true) => c.asin(),
            (Sin, false) => c.sin(),
            (Cos, true) => c.acos(),
            (Cos, false) => c.cos(),
            (
                JuliaSet {
                    constant,
                    iterations,
                    normalisation,
                },
                true,
            ) => {
                let z = (0..iterations).fold(c * normalisation, |z, _| z * z + constant);
                z / normalisation
            }
            (JuliaSet { .. }, false) => return None,
        })
    }
}

/// The sheet: its function pair and coefficients.
#[derive(Debug, Clone, PartialEq)]
pub struct ComplexMetarefraction {
    pub function: ComplexFunction,
    /// Fraction of the light transmitted, in [0, 1].
    pub transmission_coefficient: f64,
    /// Fraction of the light reflected where the wave is evanescent, in [0, 1].
    pub reflection_coefficient: f64,
}

impl ComplexMetarefraction {
    /// The local direction leaving for the unit local direction `d` (w along the outward
    /// normal); `Err(())` where the wave is evanescent, `Ok(None)` where no ray leaves.
    fn refract(&self, d: DVec3) -> Result<Option<DVec3>, ()> {
        let outwards = d.z > 0.0;
        let Some(c) = self.function.map(Complex64::new(d.x, d.y), !outwards) else {
            return Ok(None);
        };
        if c.is_nan() {
            return Ok(None);
        }
        // An infinite c′ (ln 0, a negative power of 0) is evanescent, as in Dr TIM.
        let normal2 = 1.0 - c.norm_sqr();
        if normal2 < 0.0 {
            return Err(());
        }
        let normal = if outwards { 1.0 } else { -1.0 } * normal2.sqrt();
        Ok(Some(DVec3::new(c.re, c.im, normal)))
    }

    pub fn redirect(&self, at: &Interaction) -> Redirection<'static> {
        let frame = at.frame();
        let lambda = jacobian(&frame);
        let d = at.ray.direction;
        match self.refract(lambda.transpose() * d.normalize()) {
            Ok(Some(local)) => Outgoing::Transmitted(lambda * local),
            Ok(None) => return Redirection::Lost,
            Err(()) => Outgoing::Reflected(reflect(d, frame.w)),
        }
        .leaves(self.transmission_coefficient, self.reflection_coefficient)
    }
}

/// A complex number, written `[re, im]`.
fn complex(v: Vector2) -> Complex64 {
    Complex64::new(v.0.x, v.0.y)
}

/// The `function` table.
#[derive(Debug, Deserialize)]
#[serde(tag = "type", rename_all = "kebab-case", deny_unknown_fields)]
enum FunctionKeys {
    Multiplication {
        inwards_factor: Vector2,
    },
    Addition {
        inwards_offset: Vector2,
    },
    Conjugation {},
    Power {
        inwards_exponent: NonZero,
    },
    Exp {},
    Sin {},
    Cos {},
    JuliaSet {
        constant: Vector2,
        iterations: u32,
        normalisation: Option<NonZero>,
    },
}

impl FunctionKeys {
    fn build(self) -> Result<ComplexFunction, String> {
        Ok(match self {
            FunctionKeys::Multiplication { inwards_factor } => {
                let k = complex(inwards_factor);
                if k == Complex64::new(0.0, 0.0) {
                    return Err("multiplication: `inwards_factor` must not be 0".into());
                }
                ComplexFunction::Multiplication(k)
            }
            FunctionKeys::Addition { inwards_offset } => {
                ComplexFunction::Addition(complex(inwards_offset))
            }
            FunctionKeys::Conjugation {} => ComplexFunction::Conjugation,
            FunctionKeys::Power { inwards_exponent } => ComplexFunction::Power(inwards_exponent.0),
            FunctionKeys::Exp {} => ComplexFunction::Exp,
            FunctionKeys::Sin {} => ComplexFunction::Sin,
            FunctionKeys::Cos {} => ComplexFunction::Cos,
            FunctionKeys::JuliaSet {
                constant,
                iterations,
                normalisation,
            } => {
                if iterations > MAX_ITERATIONS {
                    return Err(format!(
                        "julia-set: `iterations` = {iterations} is more than {MAX_ITERATIONS}"
                    ));
                }
                ComplexFunction::JuliaSet {
                    constant: complex(constant),
                    iterations,
                    normalisation: normalisation.map_or(1.0, |s| s.0),
                }
            }
        })
    }
}

/// `type = "complex-metarefraction"`: `function` (table, required), `transmission_coefficient`
/// (0.96, Dr TIM's default) and `reflection_coefficient` (1).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ComplexMetarefractionKeys {
    function: FunctionKeys,
    #[serde(alias = "transmission")]
    transmission_coefficient: Option<Coefficient>,
    #[serde(alias = "reflection")]
    reflection_coefficient: Option<Coefficient>,
}

impl ComplexMetarefractionKeys {
    pub fn build(self) -> Result<Surface, String> {
        Ok(Surface::ComplexMetarefraction(ComplexMetarefraction {
            function: self.function.build()?,
            transmission_coefficient: throughput(self.transmission_coefficient),
            reflection_coefficient: coefficient(self.reflection_coefficient),
        }))
    }
}

/// `type = "refractive-complex"` (Dr TIM's `RefractiveComplex`): `index_ratio = [re, im]`,
/// the complex ratio n_inside / n_outside (non-zero; Dr TIM's GUI default 1), and the
/// coefficients; a multiplication by its inverse.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RefractiveComplexKeys {
    index_ratio: Option<Vector2>,
    #[serde(alias = "transmission")]
    transmission_coefficient: Option<Coefficient>,
    #[serde(alias = "reflection")]
    reflection_coefficient: Option<Coefficient>,
}

impl RefractiveComplexKeys {
    pub fn build(self) -> Result<Surface, String> {
        let n = self.index_ratio.map_or(Complex64::new(1.0, 0.0), complex);
        if n == Complex64::new(0.0, 0.0) {
            return Err("refractive-complex: `index_ratio` must not be 0".into());
        }
        Ok(Surface::ComplexMetarefraction(ComplexMetarefraction {
            function: ComplexFunction::Multiplication(n.inv()),
            transmission_coefficient: throughput(self.transmission_coefficient),
            reflection_coefficient: coefficient(self.reflection_coefficient),
        }))
    }
}
