//! The explicit Runge–Kutta method of order 8 of Dormand and Prince with Hairer's embedded
//! error estimators of orders 5 and 3 ("DOP853"), with adaptive step size, for the special
//! second-order systems x″ = F(x) with a quadrature q′ = Q(x) alongside, integrated until an
//! event function crosses zero.
//!
//! Hand-written rather than taken from a crate: the gradient-index lenses need the exact point
//! where a ray leaves the lens (event location), on small fixed-size states, millions of times
//! per image without allocation; the crates available either lack event location or bring a
//! linear-algebra stack for a five-component state. The coefficients are the published tableau
//! (Prince & Dormand, J. Comput. Appl. Math. 7, 1981; Hairer, Nørsett & Wanner, Solving
//! Ordinary Differential Equations I, 2nd ed. 1993, whose code DOP853 adds the estimators),
//! rounded to f64. Twelve stages a step: at tight tolerances the eighth
//! order needs several times fewer function evaluations than the fifth of Dormand–Prince
//! RK5(4).
//!
//! The method is the Runge–Kutta method applied to the first-order system (x, v, q)′ = (v,
//! F(x), Q(x)), computed in Nyström form (Hairer et al. §II.14): with Vⱼ = v + h Σₗ aⱼₗ Fₗ, the
//! stage positions are Xᵢ = x + cᵢ h v + h² Σₗ (a²)ᵢₗ Fₗ, so the stages need only positions and
//! the results are the same as the first-order form's to rounding.

use super::hermite_root;

/// The nonzero entries (i, j, aᵢⱼ) of the tableau's matrix a, stages counted from 0. The nodes
/// cᵢ = Σⱼ aᵢⱼ are 0, (2/3)c₂, (2/3)c₃, (6 − √6)/30, (6 + √6)/30, 1/3, 1/4, 4/13, 127/195, 3/5,
/// 6/7, 1.
const A_ENTRIES: [(usize, usize, f64); 50] = [
    (1, 0, 0.05260015195876773),
    (2, 0, 0.0197250569845379),
    (2, 1, 0.0591751709536137),
    (3, 0, 0.02958758547680685),
    (3, 2, 0.08876275643042054),
    (4, 0, 0.2413651341592667),
    (4, 2, -0.8845494793282861),
    (4, 3, 0.924834003261792),
    (5, 0, 0.037037037037037035),
    (5, 3, 0.17082860872947386),
    (5, 4, 0.12546768756682242),
    (6, 0, 0.037109375),
    (6, 3, 0.17025221101954405),
    (6, 4, 0.06021653898045596),
    (6, 5, -0.017578125),
    (7, 0, 0.03709200011850479),
    (7, 3, 0.17038392571223998),
    (7, 4, 0.10726203044637328),
    (7, 5, -0.015319437748624402),
    (7, 6, 0.008273789163814023),
    (8, 0, 0.6241109587160757),
    (8, 3, -3.3608926294469414),
    (8, 4, -0.868219346841726),
    (8, 5, 27.59209969944671),
    (8, 6, 20.154067550477894),
    (8, 7, -43.48988418106996),
    (9, 0, 0.47766253643826434),
    (9, 3, -2.4881146199716677),
    (9, 4, -0.590290826836843),
    (9, 5, 21.230051448181193),
    (9, 6, 15.279233632882423),
    (9, 7, -33.28821096898486),
    (9, 8, -0.020331201708508627),
    (10, 0, -0.9371424300859873),
    (10, 3, 5.186372428844064),
    (10, 4, 1.0914373489967295),
    (10, 5, -8.149787010746927),
    (10, 6, -18.52006565999696),
    (10, 7, 22.739487099350505),
    (10, 8, 2.4936055526796523),
    (10, 9, -3.0467644718982196),
    (11, 0, 2.273310147516538),
    (11, 3, -10.53449546673725),
    (11, 4, -2.0008720582248625),
    (11, 5, -17.9589318631188),
    (11, 6, 27.94888452941996),
    (11, 7, -2.8589982771350235),
    (11, 8, -8.87285693353063),
    (11, 9, 12.360567175794303),
    (11, 10, 0.6433927460157636),
];
/// The eighth-order weights b.
const B: [f64; 12] = spread(&[
    (0, 0.054293734116568765),
    (5, 4.450312892752409),
    (6, 1.8915178993145003),
    (7, -5.801203960010585),
    (8, 0.3111643669578199),
    (9, -0.1521609496625161),
    (10, 0.20136540080403034),
    (11, 0.04471061572777259),
]);

/// The eighth- minus the fifth-order weights: the first error estimate, O(h⁶).
const E5: [f64; 12] = spread(&[
    (0, 0.01312004499419488),
    (5, -1.2251564463762044),
    (6, -0.4957589496572502),
    (7, 1.6643771824549864),
    (8, -0.35032884874997366),
    (9, 0.3341791187130175),
    (10, 0.08192320648511571),
    (11, -0.022355307863886294),
]);

/// b minus the third-order weights (0.24409…, 0.73384…, 0.02205… at stages 0, 8 and 11): the
/// second error estimate, O(h⁴).
const E3: [f64; 12] = spread(&[
    (0, -0.18980075407240762),
    (5, 4.450312892752409),
    (6, 1.8915178993145003),
    (7, -5.801203960010585),
    (8, -0.4226823213237919),
    (9, -0.1521609496625161),
    (10, 0.20136540080403034),
    (11, 0.02265179219836082),
]);

const A: [[f64; 12]; 12] = matrix(&A_ENTRIES);
const C: [f64; 12] = row_sums(&A);
/// a², b a, e₅ a and e₃ a: the Nyström form's weights of the forces in the positions.
const A_SQUARED: [[f64; 12]; 12] = square(&A);
const B_A: [f64; 12] = times(&B, &A);
const E5_A: [f64; 12] = times(&E5, &A);
const E3_A: [f64; 12] = times(&E3, &A);

/// The nonzero entries (l, (a²)ᵢₗ) of the rows i = 2…11 of a² (row 1 is zero), and of the
/// weight vectors, as (index, weight) lists, so that the sums in a step skip the zeros. Entries
/// left out are zero, b a's to rounding (the tableau has Σᵢ bᵢ aᵢⱼ = bⱼ (1 − cⱼ)).
const S2: [(usize, f64); 1] = pick(&A_SQUARED[2], [0]);
const S3: [(usize, f64); 2] = pick(&A_SQUARED[3], [0, 1]);
const S4: [(usize, f64); 3] = pick(&A_SQUARED[4], [0, 1, 2]);
const S5: [(usize, f64); 3] = pick(&A_SQUARED[5], [0, 2, 3]);
const S6: [(usize, f64); 4] = pick(&A_SQUARED[6], [0, 2, 3, 4]);
const S7: [(usize, f64); 5] = pick(&A_SQUARED[7], [0, 2, 3, 4, 5]);
const S8: [(usize, f64); 6] = pick(&A_SQUARED[8], [0, 2, 3, 4, 5, 6]);
const S9: [(usize, f64); 7] = pick(&A_SQUARED[9], [0, 2, 3, 4, 5, 6, 7]);
const S10: [(usize, f64); 8] = pick(&A_SQUARED[10], [0, 2, 3, 4, 5, 6, 7, 8]);
const S11: [(usize, f64); 9] = pick(&A_SQUARED[11], [0, 2, 3, 4, 5, 6, 7, 8, 9]);
const WEIGHTED: [usize; 8] = [0, 5, 6, 7, 8, 9, 10, 11];
const B_TERMS: [(usize, f64); 8] = pick(&B, WEIGHTED);
const E5_TERMS: [(usize, f64); 8] = pick(&E5, WEIGHTED);
const E3_TERMS: [(usize, f64); 8] = pick(&E3, WEIGHTED);
const B_A_TERMS: [(usize, f64); 7] = pick(&B_A, [0, 5, 6, 7, 8, 9, 10]);
const E_A: [usize; 9] = [0, 3, 4, 5, 6, 7, 8, 9, 10];
const E5_A_TERMS: [(usize, f64); 9] = pick(&E5_A, E_A);
const E3_A_TERMS: [(usize, f64); 9] = pick(&E3_A, E_A);

/// The entries of `v` at `indices`, with their indices.
const fn pick<const M: usize>(v: &[f64; 12], indices: [usize; M]) -> [(usize, f64); M] {
    let mut terms = [(0, 0.0); M];
    let mut k = 0;
    while k < M {
        terms[k] = (indices[k], v[indices[k]]);
        k += 1;
    }
    terms
}

/// The entries (i, j, value) as a matrix.
const fn matrix<const M: usize>(entries: &[(usize, usize, f64); M]) -> [[f64; 12]; 12] {
    let mut m = [[0.0; 12]; 12];
    let mut k = 0;
    while k < M {
        m[entries[k].0][entries[k].1] = entries[k].2;
        k += 1;
    }
    m
}

/// The entries (j, value) as a vector.
const fn spread<const M: usize>(entries: &[(usize, f64); M]) -> [f64; 12] {
    let mut v = [0.0; 12];
    let mut k = 0;
    while k < M {
        v[entries[k].0] = entries[k].1;
        k += 1;
    }
    v
}

const fn row_sums(m: &[[f64; 12]; 12]) -> [f64; 12] {
    let mut c = [0.0; 12];
    let mut i = 0;
    while i < 12 {
        let mut j = 0;
        while j < 12 {
            c[i] += m[i][j];
            j += 1;
        }
        i += 1;
    }
    c
}

const fn square(m: &[[f64; 12]; 12]) -> [[f64; 12]; 12] {
    let mut p = [[0.0; 12]; 12];
    let mut i = 0;
    while i < 12 {
        p[i] = times(&m[i], m);
        i += 1;
    }
    p
}

/// The row vector w times the matrix m.
const fn times(w: &[f64; 12], m: &[[f64; 12]; 12]) -> [f64; 12] {
    let mut p = [0.0; 12];
    let mut j = 0;
    while j < 12 {
        let mut l = 0;
        while l < 12 {
            p[l] += w[j] * m[j][l];
            l += 1;
        }
        j += 1;
    }
    p
}

/// A point of the integration: position x, velocity v = x′ and the quadrature q.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Phase<const D: usize> {
    pub x: [f64; D],
    pub v: [f64; D],
    pub q: f64,
}

/// Adaptive DOP853 integration: each step's local error in each component (of x, v and q) is
/// kept below `absolute + relative·|yᵢ|`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Dop853 {
    pub relative: f64,
    pub absolute: f64,
    /// Most steps (accepted or rejected) before giving up.
    pub max_steps: usize,
    pub estimate: ErrorEstimate,
}

/// How a step's local error is estimated.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ErrorEstimate {
    /// Hairer's combination of the fifth- and third-order estimates, ‖e₅‖²/√(‖e₅‖² +
    /// ‖e₃‖²/100), which behaves as O(h⁸), the actual error, where F and Q are smooth (as in
    /// Hairer's DOP853).
    Combined,
    /// The fifth-order estimate ‖e₅‖ alone, O(h⁶). Where a derivative of F jumps within a step
    /// (a cubic spline's third derivative at its knots, making the step's error O(h³)), the
    /// combined estimate can be 80 times too small, this one at most 6 times.
    FifthOrder,
}

/// F and Q at the twelve stages of a step.
struct Stages<const D: usize> {
    force: [[f64; D]; 12],
    quadrature: [[f64; 1]; 12],
}

impl Dop853 {
    /// Integrates x″ = F(x), q′ = Q(x) from `start`, where `field(x)` = (F(x), Q(x)), with
    /// first step `h0`, until `event(phase)`, which returns g and dg/dt, crosses zero from
    /// below; returns the phase at the crossing, located to rounding, or `None` if there is
    /// none within `max_steps` steps. The start counts as before the event (g is not evaluated
    /// there, so it may lie on the event surface, but then the first step must end before the
    /// event). `accepted` is shown the phase after each accepted step before the event (not
    /// the start, nor the phase at the crossing).
    pub fn integrate_until<const D: usize>(
        &self,
        field: impl Fn(&[f64; D]) -> ([f64; D], f64),
        start: Phase<D>,
        h0: f64,
        event: impl Fn(&Phase<D>) -> (f64, f64),
        mut accepted: impl FnMut(&Phase<D>),
    ) -> Option<Phase<D>> {
        let (mut y, mut first, mut h) = (start, field(&start.x), h0);
        let mut rejected = false;
        for _ in 0..self.max_steps {
            let k = stages(&field, &y, first, h);
            let y_new = advance(&y, h, &k);
            let error = self.error(&y, &y_new, h, &k);
            if !error.is_finite() {
                (h, rejected) = (0.1 * h, true);
                continue;
            }
            // Step-size control (Hairer et al. §II.4, Eq. 4.13) for an error estimate of
            // order 8 (or 6): safety 0.9, growth limited to [1/3, 6], and none right after a
            // rejection.
            let root = match self.estimate {
                ErrorEstimate::Combined => error.sqrt().sqrt().sqrt(),
                ErrorEstimate::FifthOrder => error.sqrt().cbrt(),
            };
            let factor = (0.9 / root).clamp(1.0 / 3.0, 6.0);
            if error > 1.0 {
                (h, rejected) = (h * factor.min(1.0), true);
                continue;
            }
            let end = event(&y_new);
            if end.0 >= 0.0 {
                return Some(self.locate(&field, &y, first, h, end, &event));
            }
            (y, first) = (y_new, field(&y_new.x));
            accepted(&y);
            h *= if rejected { factor.min(1.0) } else { factor };
            rejected = false;
        }
        None
    }

    /// The phase where g crosses zero upwards within the step of length `h` from `y` (before
    /// the event; `end` is g and dg/dt at the step's end): Newton's method on the step length,
    /// each trial a full step from `y`, kept inside the bracket by bisection, from the root of
    /// the cubic Hermite interpolant of g over the step; the last correction, once below
    /// 1e-8 of the step, by Taylor expansion.
    fn locate<const D: usize>(
        &self,
        field: &impl Fn(&[f64; D]) -> ([f64; D], f64),
        y: &Phase<D>,
        first: ([f64; D], f64),
        h: f64,
        end: (f64, f64),
        event: &impl Fn(&Phase<D>) -> (f64, f64),
    ) -> Phase<D> {
        let start = event(y);
        let (mut lo, mut hi) = (0.0, h);
        let mut s = h * hermite_root(start.0, h * start.1, end.0, h * end.1);
        let mut best = *y;
        for _ in 0..100 {
            best = advance(y, s, &stages(field, y, first, s));
            let (g, dg) = event(&best);
            if g < 0.0 {
                lo = s;
            } else {
                hi = s;
            }
            let newton = s - g / dg;
            if g == 0.0 || hi - lo <= 4.0 * f64::EPSILON * hi {
                break;
            }
            let delta = newton - s;
            if delta.abs() <= 1e-8 * s && newton > lo && newton < hi {
                // Newton's next step is off by about δ²g″/g′, below rounding here: go the
                // last δ along the second-order Taylor polynomial (its error O(δ³)) instead of
                // taking another full step.
                let (force, quadrature) = field(&best.x);
                for ((x, v), f) in best.x.iter_mut().zip(&mut best.v).zip(force) {
                    *x += delta * (*v + 0.5 * delta * f);
                    *v += delta * f;
                }
                best.q += delta * quadrature;
                break;
            }
            s = if newton > lo && newton < hi {
                newton
            } else {
                0.5 * (lo + hi)
            };
        }
        best
    }

    /// The step's error relative to the tolerance (accept when ≤ 1), as [`Self::estimate`]
    /// says, in the root-mean-square norm over the components.
    fn error<const D: usize>(&self, y: &Phase<D>, y_new: &Phase<D>, h: f64, k: &Stages<D>) -> f64 {
        // The estimates' x, v and q parts: h² Σ (e a)ⱼ Fⱼ, h Σ eⱼ Fⱼ, h Σ eⱼ Qⱼ.
        let (x5, x3) = (sum(&E5_A_TERMS, &k.force), sum(&E3_A_TERMS, &k.force));
        let (v5, v3) = (sum(&E5_TERMS, &k.force), sum(&E3_TERMS, &k.force));
        let (q5, q3) = (sum(&E5_TERMS, &k.quadrature), sum(&E3_TERMS, &k.quadrature));
        let scale = |a: f64, b: f64| h / (self.absolute + self.relative * a.abs().max(b.abs()));
        let (mut sum5, mut sum3) = (0.0, 0.0);
        for d in 0..D {
            let (sx, sv) = (h * scale(y.x[d], y_new.x[d]), scale(y.v[d], y_new.v[d]));
            sum5 += (x5[d] * sx).powi(2) + (v5[d] * sv).powi(2);
            sum3 += (x3[d] * sx).powi(2) + (v3[d] * sv).powi(2);
        }
        let sq = scale(y.q, y_new.q);
        sum5 += (q5[0] * sq).powi(2);
        sum3 += (q3[0] * sq).powi(2);
        let n = (2 * D + 1) as f64;
        match self.estimate {
            ErrorEstimate::FifthOrder => (sum5 / n).sqrt(),
            ErrorEstimate::Combined => {
                let denominator = sum5 + 0.01 * sum3;
                if denominator > 0.0 {
                    sum5 / (n * denominator).sqrt()
                } else {
                    0.0
                }
            }
        }
    }
}

/// F and Q at the stages of one step of length `h` from `y`, where (F, Q)(y.x) = `first`.
#[inline(always)]
fn stages<const D: usize>(
    field: &impl Fn(&[f64; D]) -> ([f64; D], f64),
    y: &Phase<D>,
    first: ([f64; D], f64),
    h: f64,
) -> Stages<D> {
    let mut k = Stages {
        force: [[0.0; D]; 12],
        quadrature: [[0.0]; 12],
    };
    (k.force[0], k.quadrature[0][0]) = first;
    let mut stage = |i: usize, terms: &[(usize, f64)]| {
        let mut x = y.x;
        let forces = sum_slice(terms, &k.force);
        for d in 0..D {
            x[d] += C[i] * h * y.v[d] + h * h * forces[d];
        }
        (k.force[i], k.quadrature[i][0]) = field(&x);
    };
    stage(1, &[]);
    stage(2, &S2);
    stage(3, &S3);
    stage(4, &S4);
    stage(5, &S5);
    stage(6, &S6);
    stage(7, &S7);
    stage(8, &S8);
    stage(9, &S9);
    stage(10, &S10);
    stage(11, &S11);
    k
}

/// The phase a step of length `h` from `y` with stages `k` ends at.
#[inline(always)]
fn advance<const D: usize>(y: &Phase<D>, h: f64, k: &Stages<D>) -> Phase<D> {
    let (mut x, mut v) = (sum(&B_A_TERMS, &k.force), sum(&B_TERMS, &k.force));
    for d in 0..D {
        x[d] = y.x[d] + h * y.v[d] + h * h * x[d];
        v[d] = y.v[d] + h * v[d];
    }
    Phase {
        x,
        v,
        q: y.q + h * sum(&B_TERMS, &k.quadrature)[0],
    }
}

/// Σ wⱼ kⱼ over the entries (j, wⱼ) of `terms` (fixed in number, so that it unrolls).
#[inline(always)]
fn sum<const D: usize, const M: usize>(terms: &[(usize, f64); M], k: &[[f64; D]; 12]) -> [f64; D] {
    sum_slice(terms, k)
}

/// [`sum`] over a list, unrolled where inlined with its length known.
#[inline(always)]
fn sum_slice<const D: usize>(terms: &[(usize, f64)], k: &[[f64; D]; 12]) -> [f64; D] {
    let mut total = [0.0; D];
    for &(j, w) in terms {
        for d in 0..D {
            total[d] += w * k[j][d];
        }
    }
    total
}

#[cfg(test)]
mod tests {
    use super::*;

    const SOLVER: Dop853 = Dop853 {
        relative: 1e-12,
        absolute: 1e-12,
        max_steps: 100_000,
        estimate: ErrorEstimate::Combined,
    };

    /// The nodes cᵢ as published (see [`A_ENTRIES`]).
    fn nodes() -> [f64; 12] {
        let c4 = (6.0 - 6f64.sqrt()) / 30.0;
        let c3 = 2.0 / 3.0 * c4;
        [
            0.0,
            2.0 / 3.0 * c3,
            c3,
            c4,
            (6.0 + 6f64.sqrt()) / 30.0,
            1.0 / 3.0,
            0.25,
            4.0 / 13.0,
            127.0 / 195.0,
            0.6,
            6.0 / 7.0,
            1.0,
        ]
    }

    #[test]
    fn tableau_rows_sum_to_the_published_nodes() {
        for (i, (c, published)) in C.iter().zip(nodes()).enumerate() {
            assert!((c - published).abs() < 1e-14, "row {i}: {c}");
        }
    }

    #[test]
    fn weights_integrate_polynomials_to_their_orders() {
        // Σ wᵢ cᵢ^(q−1) = 1/q for q up to the weights' order (b: 8, the differences b − b̂: 0
        // up to their orders, 5 and 3), and not beyond for the estimates, which must not
        // vanish.
        let moment = |w: &[f64; 12], q: i32| -> f64 {
            w.iter()
                .zip(nodes())
                .map(|(wj, c)| wj * c.powi(q - 1))
                .sum()
        };
        for q in 1..=8 {
            assert!((moment(&B, q) - 1.0 / q as f64).abs() < 1e-14, "b, q = {q}");
        }
        for q in 1..=5 {
            assert!(moment(&E5, q).abs() < 1e-13, "e5, q = {q}");
        }
        for q in 1..=3 {
            assert!(moment(&E3, q).abs() < 1e-13, "e3, q = {q}");
        }
        assert!(moment(&E5, 6).abs() > 1e-5 && moment(&E3, 4).abs() > 1e-3);
    }

    #[test]
    fn the_sparse_weight_lists_hold_every_nonzero_weight() {
        let rows: [&[(usize, f64)]; 12] =
            [&[], &[], &S2, &S3, &S4, &S5, &S6, &S7, &S8, &S9, &S10, &S11];
        for (i, row) in rows.iter().enumerate() {
            let listed = row.iter().map(|&(l, _)| l).collect::<Vec<_>>();
            for l in (0..12).filter(|l| !listed.contains(l)) {
                assert_eq!(A_SQUARED[i][l], 0.0, "a² at ({i}, {l})");
            }
        }
        let full = [B, E5, E3, B_A, E5_A, E3_A];
        let listed: [&[(usize, f64)]; 6] = [
            &B_TERMS,
            &E5_TERMS,
            &E3_TERMS,
            &B_A_TERMS,
            &E5_A_TERMS,
            &E3_A_TERMS,
        ];
        for (k, (full, terms)) in full.iter().zip(listed).enumerate() {
            let listed = terms.iter().map(|&(l, _)| l).collect::<Vec<_>>();
            for l in (0..12).filter(|l| !listed.contains(l)) {
                assert!(full[l].abs() < 1e-15, "vector {k} at {l}: {}", full[l]);
            }
        }
    }

    /// x″ = −x, q′ = x²: x = cos t, v = −sin t, q = t/2 + sin 2t / 4 from (1, 0, 0).
    fn oscillator(x: &[f64; 1]) -> ([f64; 1], f64) {
        ([-x[0]], x[0] * x[0])
    }

    #[test]
    fn the_nystrom_form_is_the_runge_kutta_step_of_the_first_order_system() {
        // The step computed from the tableau as written, on y = (x, v, q), y′ = (v, −x, x²).
        let f = |y: [f64; 3]| [y[1], -y[0], y[0] * y[0]];
        let (y0, h) = ([0.3, -0.8, 0.1], 0.7);
        let mut k = [[0.0; 3]; 12];
        for i in 0..12 {
            let mut yi = y0;
            for (j, kj) in k.iter().enumerate().take(i) {
                for d in 0..3 {
                    yi[d] += h * A[i][j] * kj[d];
                }
            }
            k[i] = f(yi);
        }
        let first_order: Vec<f64> = (0..3)
            .map(|d| y0[d] + h * (0..12).map(|j| B[j] * k[j][d]).sum::<f64>())
            .collect();
        let start = Phase {
            x: [y0[0]],
            v: [y0[1]],
            q: y0[2],
        };
        let nystrom = advance(
            &start,
            h,
            &stages(&oscillator, &start, oscillator(&[y0[0]]), h),
        );
        let nystrom = [nystrom.x[0], nystrom.v[0], nystrom.q];
        for d in 0..3 {
            assert!(
                (nystrom[d] - first_order[d]).abs() < 1e-15,
                "{nystrom:?} {first_order:?}"
            );
        }
    }

    #[test]
    fn fixed_steps_on_the_harmonic_oscillator_converge_with_order_8() {
        // To t = 2 in n equal steps: the global error of an eighth-order method falls 2⁸ = 256
        // times when n doubles (from 4 to 8 steps, before rounding).
        let error = |n: usize| {
            let h = 2.0 / n as f64;
            let mut y = Phase {
                x: [1.0],
                v: [0.0],
                q: 0.0,
            };
            for _ in 0..n {
                y = advance(&y, h, &stages(&oscillator, &y, oscillator(&y.x), h));
            }
            let q = 1.0 + 4f64.sin() / 4.0;
            (y.x[0] - 2f64.cos()).abs() + (y.v[0] + 2f64.sin()).abs() + (y.q - q).abs()
        };
        let ratio = error(4) / error(8);
        assert!((200.0..330.0).contains(&ratio), "ratio {ratio}");
        assert!(error(16) < 1e-11, "{}", error(16));
    }

    #[test]
    fn harmonic_oscillator_reaches_its_event_at_the_exact_phase() {
        // Stop where x falls through −0.5 (g = −x − ½ crosses zero upwards), at t = 2π/3,
        // where v = −sin(2π/3) and q = π/3 + sin(4π/3)/4.
        let event = |y: &Phase<1>| (-y.x[0] - 0.5, -y.v[0]);
        let start = Phase {
            x: [1.0],
            v: [0.0],
            q: 0.0,
        };
        let mut steps = 0;
        let y = SOLVER
            .integrate_until(oscillator, start, 1e-3, event, |_| steps += 1)
            .unwrap();
        let q = std::f64::consts::FRAC_PI_3 - 3f64.sqrt() / 8.0;
        assert!((y.x[0] + 0.5).abs() < 1e-15, "{y:?}");
        assert!((y.v[0] + (3f64.sqrt() / 2.0)).abs() < 1e-12, "{y:?}");
        assert!((y.q - q).abs() < 1e-12, "{y:?}");
        assert!(steps < 20, "{steps} steps");
    }

    #[test]
    fn exponential_growth_is_accurate_to_the_tolerance() {
        // x″ = x, q′ = 1 from x = 1, v = 0 until q = t = 5: x = cosh 5, and the step controller
        // has coped with a solution growing by 74 times.
        let start = Phase {
            x: [1.0],
            v: [0.0],
            q: 0.0,
        };
        let y = SOLVER
            .integrate_until(
                |x: &[f64; 1]| (*x, 1.0),
                start,
                0.1,
                |y| (y.q - 5.0, 1.0),
                |_| {},
            )
            .unwrap();
        assert!((y.x[0] / 5f64.cosh() - 1.0).abs() < 1e-11, "{y:?}");
        assert!((y.v[0] / 5f64.sinh() - 1.0).abs() < 1e-11, "{y:?}");
    }

    #[test]
    fn no_event_within_the_step_limit_is_none() {
        let solver = Dop853 {
            max_steps: 50,
            ..SOLVER
        };
        let start = Phase {
            x: [0.0],
            v: [1.0],
            q: 0.0,
        };
        let never = |y: &Phase<1>| (-1.0 - y.x[0].abs(), 0.0);
        assert_eq!(
            solver.integrate_until(|_: &[f64; 1]| ([0.0], 0.0), start, 1e-3, never, |_| {}),
            None
        );
    }
}
