//! The diffraction of a finite-aperture camera's circular entrance pupil (Dr TIM's
//! `CircularApertureDiffraction`, as `AnyFocusSurfaceCamera` and
//! `RelativisticAnyFocusSurfaceCamera` apply it when their `diffractiveAperture` is true).
//!
//! The far field of a circular aperture of radius r under normal, uniform illumination is the
//! Airy pattern I(θ) ∝ (2 J₁(x)/x)², x = 2π r sin θ / λ. Each camera ray leaving the pupil has
//! its tangential direction component (perpendicular to the view direction) changed by
//! sin θ = x λ / (2π r) in a uniformly random azimuth, x drawn from the pattern's radial density
//! p(x) = 2 J₁(x)² / x, whose cumulative distribution is P(x) = 1 − J₀(x)² − J₁(x)² (the
//! encircled energy: 83.8 % inside the first dark ring, x = 3.8317).
//!
//! Dr TIM draws x from a table of the inverse of P with linear interpolation; here x is drawn
//! exactly, by inverting P numerically (safeguarded Newton, to 10⁻¹² of x or better), with
//! J₀ and J₁ accurate to about 10⁻¹⁵ ([`bessel_j0_j1`]). 1 − P falls off slowly (≈ 2/(πx)), so a
//! few samples have large x: x beyond `x_max`, where the direction change alone would make the
//! ray evanescent, is no ray at all ([`airy_x`] says `None`).

use std::f64::consts::{FRAC_1_SQRT_2, PI};
use std::sync::OnceLock;

use crate::math::hermite_root;

/// Below this argument J₀ and J₁ come from Bessel's integral, above it from Hankel's
/// asymptotic expansion (whose smallest term, about e^{−2x}, is far below rounding there).
const ASYMPTOTIC_FROM: f64 = 25.0;

/// J₀(x), 1 − J₀(x) (without cancellation for small x) and J₁(x), for x ≥ 0.
#[derive(Debug, Clone, Copy)]
struct Bessel {
    j0: f64,
    one_minus_j0: f64,
    j1: f64,
}

/// J₀ and J₁ for x ≥ 0: below 25 by Bessel's integral J_n(x) = (1/π)∫₀^π cos(nτ − x sin τ) dτ
/// with the trapezoid rule, exact for a periodic integrand's Fourier modes up to twice the
/// number of intervals M: its error is J_{2M−n}(x) + J_{2M+n}(x) + …, below 10⁻³⁰ with
/// M = ⌈x⌉ + 16. The integrands are written with terms as small as x, so that 1 − J₀ and J₁
/// keep their relative precision as x → 0: 1 − J₀ = (1/π)∫₀^π 2 sin²((x sin τ)/2) dτ and
/// J₁ = (1/π)∫₀^π sin τ sin(x sin τ) dτ (cos(τ − φ) expanded; its part cos τ cos φ, odd about
/// τ = π/2, vanishes from integral and rule alike). Both are even about π/2: half the nodes
/// suffice. Above 25 by Hankel's expansion (Abramowitz & Stegun 9.2.5, 9.2.9, 9.2.10), summed
/// until its terms fall below 10⁻¹⁷.
fn bessel(x: f64) -> Bessel {
    if x >= ASYMPTOTIC_FROM {
        let (j0, j1) = hankel(x);
        return Bessel {
            j0,
            one_minus_j0: 1.0 - j0,
            j1,
        };
    }
    let m = x.ceil() as usize + 16;
    let h = PI / m as f64;
    let (mut a, mut b) = (0.0, 0.0);
    // Nodes k and m − k alike; the end nodes (φ = 0) add nothing.
    for k in (1..).take_while(|k| 2 * k <= m) {
        let weight = if 2 * k == m { 1.0 } else { 2.0 };
        let sin_tau = (k as f64 * h).sin();
        // sin(φ/2), cos(φ/2), φ = x sin τ.
        let (s, c) = (0.5 * x * sin_tau).sin_cos();
        a += weight * 2.0 * s * s;
        b += weight * sin_tau * 2.0 * s * c;
    }
    let one_minus_j0 = a / m as f64;
    Bessel {
        j0: 1.0 - one_minus_j0,
        one_minus_j0,
        j1: b / m as f64,
    }
}

/// (J₀(x), J₁(x)) for large x by Hankel's asymptotic expansion
/// J_ν(x) = √(2/(πx)) (P_ν cos ω − Q_ν sin ω), ω = x − νπ/2 − π/4.
fn hankel(x: f64) -> (f64, f64) {
    // P_ν and Q_ν: the even and odd terms a_k(ν)/x^k with alternating signs, a_k(ν) =
    // (μ − 1²)(μ − 3²)…(μ − (2k − 1)²) / (k! 8^k), μ = 4ν².
    let p_q = |mu: f64| {
        let (mut p, mut q) = (1.0, 0.0);
        let mut term = 1.0;
        for k in 1..60 {
            term *= (mu - ((2 * k - 1) as f64).powi(2)) / (8.0 * k as f64 * x);
            let signed = if (k / 2) % 2 == 0 { term } else { -term };
            if k % 2 == 0 {
                p += signed;
            } else {
                q += signed;
            }
            if term.abs() < 1e-17 {
                break;
            }
        }
        (p, q)
    };
    // cos and sin of ω₀ = x − π/4 from those of x, which are exact to rounding, so that the
    // phase does not lose π/4's last bits to x's; ω₁ = ω₀ − π/2.
    let (s, c) = x.sin_cos();
    let (cos0, sin0) = ((c + s) * FRAC_1_SQRT_2, (s - c) * FRAC_1_SQRT_2);
    let (cos1, sin1) = (sin0, -cos0);
    let amplitude = (2.0 / (PI * x)).sqrt();
    let (p0, q0) = p_q(0.0);
    let (p1, q1) = p_q(4.0);
    (
        amplitude * (p0 * cos0 - q0 * sin0),
        amplitude * (p1 * cos1 - q1 * sin1),
    )
}

/// (J₀(x), J₁(x)), the Bessel functions of the first kind of orders 0 and 1, for x ≥ 0.
pub fn bessel_j0_j1(x: f64) -> (f64, f64) {
    let b = bessel(x);
    (b.j0, b.j1)
}

/// P(x) = 1 − J₀(x)² − J₁(x)², the share of an Airy pattern's power inside x = 2π r sin θ / λ.
pub fn encircled_energy(x: f64) -> f64 {
    let b = bessel(x);
    b.one_minus_j0 * (1.0 + b.j0) - b.j1 * b.j1
}

/// Most iterations of the root search: from the table's guess one Newton step usually does;
/// where P is flat (at a zero of J₁) steps slow to bisection's pace, about 60 for f64's precision.
const MAX_ITERATIONS: u32 = 200;

/// The step of [`table`]'s nodes in x.
const TABLE_STEP: f64 = 0.125;

/// (P, p) at the nodes x = k/8 up to [`ASYMPTOTIC_FROM`], computed once: brackets of the root
/// and first guesses (by Hermite interpolation, good to about 10⁻⁸) for [`airy_x`].
fn table() -> &'static [(f64, f64)] {
    static TABLE: OnceLock<Vec<(f64, f64)>> = OnceLock::new();
    TABLE.get_or_init(|| {
        let nodes = (ASYMPTOTIC_FROM / TABLE_STEP) as usize;
        (0..=nodes)
            .map(|k| {
                let x = k as f64 * TABLE_STEP;
                let (_, j1) = bessel_j0_j1(x);
                let p = if x > 0.0 { 2.0 * j1 * j1 / x } else { 0.0 };
                (encircled_energy(x), p)
            })
            .collect()
    })
}

/// The x with P(x) = `u` (uniform in [0, 1): x then has the density 2 J₁(x)²/x), or `None`
/// if that x exceeds `x_max`. P is inverted by Newton's method (P′ = p) kept inside a bracket
/// that bisection shrinks where Newton's step leaves it, from a bracket and a first guess that
/// a table of P and p at x = k/8 up to 25 gives (beyond it, the bracket doubles), until x is
/// known to 10⁻¹² of itself or better; for u > ½ the complement 1 − P = J₀² + J₁² is matched
/// to 1 − u, which keeps its precision as u nears 1.
pub fn airy_x(u: f64, x_max: f64) -> Option<f64> {
    if u <= 0.0 {
        return Some(0.0);
    }
    let upper = u > 0.5;
    // f(x), increasing, zero at the root; f′(x) = p(x) = 2 J₁²/x; and f″/f′ = p′/p =
    // 2 J₁′/J₁ − 1/x with J₁′ = J₀ − J₁/x (A & S 9.1.27), which bounds Newton's next error.
    let f = |x: f64| {
        let b = bessel(x);
        let value = if upper {
            (1.0 - u) - (b.j0 * b.j0 + b.j1 * b.j1)
        } else {
            b.one_minus_j0 * (1.0 + b.j0) - b.j1 * b.j1 - u
        };
        let slope = if x > 0.0 { 2.0 * b.j1 * b.j1 / x } else { 0.0 };
        let bend = 2.0 * (b.j0 - b.j1 / x) / b.j1 - 1.0 / x;
        (value, slope, bend)
    };
    // A bracket [lo, hi], f(lo) < 0 ≤ f(hi), and a first guess.
    let table = table();
    let k = table.partition_point(|&(p, _)| p <= u);
    let (mut lo, mut hi, mut x);
    if k < table.len() {
        // P(lo) ≤ u < P(hi): the root of the cubic Hermite interpolant of P between them.
        let ((p0, d0), (p1, d1)) = (table[k - 1], table[k]);
        let (d0, d1) = (d0 * TABLE_STEP, d1 * TABLE_STEP);
        // The root t ∈ [0, 1] of H(t) − u.
        let t = hermite_root(p0 - u, d0, p1 - u, d1);
        lo = (k - 1) as f64 * TABLE_STEP;
        hi = k as f64 * TABLE_STEP;
        x = lo + t * TABLE_STEP;
        if lo >= x_max {
            return None;
        }
        if hi > x_max {
            if f(x_max).0 < 0.0 {
                return None;
            }
            hi = x_max;
        }
    } else {
        // Beyond the table, the bracket doubles up to x_max; 1 − P ≈ 2/(πx) guesses.
        lo = ASYMPTOTIC_FROM;
        hi = ASYMPTOTIC_FROM;
        loop {
            if lo >= x_max {
                return None;
            }
            hi = (2.0 * hi).min(x_max);
            if f(hi).0 >= 0.0 {
                break;
            }
            lo = hi;
        }
        x = 2.0 / (PI * (1.0 - u));
    }
    if !(x > lo && x < hi) {
        x = 0.5 * (lo + hi);
    }
    for _ in 0..MAX_ITERATIONS {
        let (value, slope, bend) = f(x);
        if value == 0.0 {
            return Some(x);
        }
        if value < 0.0 {
            lo = x;
        } else {
            hi = x;
        }
        let newton = x - value / slope;
        let inside = newton > lo && newton < hi;
        // Newton's error after a step δ is about (f″/2f′) δ²: done if that is below 10⁻¹³ x
        // (and δ is small enough for the estimate to hold).
        let step = (newton - x).abs();
        if inside && (bend * step).abs() <= 0.1 && (bend * step * step).abs() <= 2e-13 * newton {
            return Some(newton);
        }
        let next = if inside { newton } else { 0.5 * (lo + hi) };
        let tolerance = 1e-12 * next;
        if (next - x).abs() <= tolerance || hi - lo <= tolerance {
            return Some(next);
        }
        x = next;
    }
    Some(x)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::random::uniform;

    /// Abramowitz & Stegun, Table 9.1, and the first zeros of J₀ and J₁ (Table 9.5).
    #[test]
    fn bessel_functions_match_the_tables() {
        for (x, j0, j1) in [
            (0.0, 1.0, 0.0),
            (1.0, 0.7651976866, 0.4400505857),
            (5.0, -0.1775967713, -0.3275791376),
            (10.0, -0.2459357645, 0.0434727462),
        ] {
            let (a, b) = bessel_j0_j1(x);
            assert!((a - j0).abs() < 1e-10, "J0({x}) = {a}, not {j0}");
            assert!((b - j1).abs() < 1e-10, "J1({x}) = {b}, not {j1}");
        }
        // Zeros: j₀,₁, j₁,₁, j₀,₂, j₁,₂, and in the asymptotic range j₀,₁₀, j₁,₁₀, j₀,₂₀.
        for (x, order) in [
            (2.4048255577, 0),
            (3.8317059702, 1),
            (5.5200781103, 0),
            (7.0155866698, 1),
            (30.6346064684, 0),
            (32.1896799110, 1),
            (62.0484691902, 0),
        ] {
            let (j0, j1) = bessel_j0_j1(x);
            let value = if order == 0 { j0 } else { j1 };
            assert!(value.abs() < 1e-10, "J{order}({x}) = {value}");
        }
    }

    /// The two methods are independent; where they meet, and beyond, they agree to rounding.
    #[test]
    fn bessels_integral_and_hankels_expansion_agree() {
        for i in 0..200 {
            let x = ASYMPTOTIC_FROM + 0.173 * i as f64;
            let (j0, j1) = hankel(x);
            // The plain integral, at all nodes of its own trapezoid rule (M = ⌈x⌉ + 25).
            let m = x.ceil() as usize + 25;
            let integral = |n: f64| {
                (0..=m)
                    .map(|k| {
                        let tau = k as f64 * PI / m as f64;
                        let w = if k == 0 || k == m { 0.5 } else { 1.0 };
                        w * (n * tau - x * tau.sin()).cos()
                    })
                    .sum::<f64>()
                    / m as f64
            };
            assert!((j0 - integral(0.0)).abs() < 1e-14, "J0({x})");
            assert!((j1 - integral(1.0)).abs() < 1e-14, "J1({x})");
        }
    }

    /// A & S 9.1.27: J₁′ = J₀ − J₁/x, so d/dx (1 − J₀² − J₁²) = 2 J₁²/x: P's slope, by
    /// finite differences, is the density the sampler claims.
    #[test]
    fn the_encircled_energy_grows_by_the_airy_density() {
        for x in [0.3, 1.0, 2.0, 3.0, 6.0, 12.0, 24.9, 25.1, 40.0] {
            let h = 1e-5;
            let slope = (encircled_energy(x + h) - encircled_energy(x - h)) / (2.0 * h);
            let (_, j1) = bessel_j0_j1(x);
            assert!((slope - 2.0 * j1 * j1 / x).abs() < 1e-8, "p({x})");
        }
        // Small x: P ≈ x²/4 − x⁴/32, without cancellation.
        let x: f64 = 1e-4;
        let small = x * x / 4.0 - x.powi(4) / 32.0;
        assert!((encircled_energy(x) / small - 1.0).abs() < 1e-9);
    }

    /// The famous encircled energies: 1 − J₀(x)² inside the dark rings, 83.78 % inside the
    /// first (3.8317), 90.99 % inside the second (7.0156); the median is 1.68022474619 (P = ½;
    /// from mpmath at 30 digits).
    #[test]
    fn samples_follow_the_airy_distribution() {
        assert!((encircled_energy(3.8317059702) - 0.8378).abs() < 1e-4);
        assert!((encircled_energy(7.0155866698) - 0.9099).abs() < 1e-4);
        let median = airy_x(0.5, f64::INFINITY).unwrap();
        assert!((median - 1.680_224_746_194_2).abs() < 1e-11, "{median}");
        let n = 20_000;
        let xs: Vec<f64> = (0..n)
            .map(|s| airy_x(uniform(5, 1, 2, s, 4), 1e6).expect("within x_max"))
            .collect();
        for (edge, expected) in [
            (3.8317059702, 0.8378),
            (7.0155866698, 0.9099),
            (median, 0.5),
        ] {
            let share = xs.iter().filter(|&&x| x < edge).count() as f64 / n as f64;
            let sigma = (expected * (1.0 - expected) / n as f64).sqrt();
            assert!(
                (share - expected).abs() < 4.0 * sigma,
                "x < {edge}: {share} against {expected}"
            );
        }
    }

    /// The inverse is exact: P(x(u)) = u, also near 0 and 1, across both methods' ranges.
    #[test]
    fn the_inverse_is_exact() {
        for u in [
            1e-12, 1e-6, 0.01, 0.2, 0.5, 0.5001, 0.8378, 0.9, 0.97, 0.99, 0.999, 0.999_999,
        ] {
            let x = airy_x(u, f64::INFINITY).unwrap();
            let b = bessel(x);
            let (p, q) = (encircled_energy(x), b.j0 * b.j0 + b.j1 * b.j1);
            // P near 0 to its relative precision, 1 − P near 1 to its own.
            let error = if u > 0.5 {
                (q - (1.0 - u)) / (1.0 - u)
            } else {
                (p - u) / u
            };
            assert!(error.abs() < 1e-10, "u = {u}: x = {x}, error {error}");
        }
        // Where P is flat: u = P at the second zero of J₁, where P′ = 0.
        let u = encircled_energy(7.0155866698);
        let x = airy_x(u, f64::INFINITY).unwrap();
        assert!((x - 7.0155866698).abs() < 1e-4, "{x}");
        assert_eq!(airy_x(0.0, 1.0), Some(0.0));
    }

    /// A draw beyond x_max is no ray; below it, the same x whatever x_max.
    #[test]
    fn draws_beyond_x_max_are_none() {
        let u = 0.99;
        let x = airy_x(u, f64::INFINITY).unwrap();
        assert!(x > 60.0, "1 − P ≈ 2/(πx): {x}");
        assert_eq!(airy_x(u, 0.9 * x), None);
        let again = airy_x(u, 1.1 * x).unwrap();
        assert!((again - x).abs() < 1e-11 * x, "{again} against {x}");
        assert_eq!(airy_x(0.5, 1.0), None);
    }
}
