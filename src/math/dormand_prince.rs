//! The embedded Runge–Kutta pair of Dormand and Prince (RK5(4), "DOPRI5") with adaptive step
//! size, for autonomous systems y′ = f(y), integrated until an event function crosses zero.
//!
//! Hand-written rather than taken from a crate: the gradient-index lenses need the exact point
//! where a ray leaves the lens (event location), on small fixed-size states, millions of times
//! per image without allocation; the crates available either lack event location or bring a
//! linear-algebra stack for a six-component state. The coefficients are the standard tableau
//! (Dormand & Prince 1980).

/// Rows 2–7 of the tableau's matrix a; row 7 is also the fifth-order weights b ("first same as
/// last": the seventh stage is f at the new point, the next step's first).
const A: [&[f64]; 6] = [
    &[1.0 / 5.0],
    &[3.0 / 40.0, 9.0 / 40.0],
    &[44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0],
    &[
        19372.0 / 6561.0,
        -25360.0 / 2187.0,
        64448.0 / 6561.0,
        -212.0 / 729.0,
    ],
    &[
        9017.0 / 3168.0,
        -355.0 / 33.0,
        46732.0 / 5247.0,
        49.0 / 176.0,
        -5103.0 / 18656.0,
    ],
    &[
        35.0 / 384.0,
        0.0,
        500.0 / 1113.0,
        125.0 / 192.0,
        -2187.0 / 6784.0,
        11.0 / 84.0,
    ],
];

/// b − b̂: the fifth- minus the fourth-order weights, the local error estimate's coefficients.
const E: [f64; 7] = [
    71.0 / 57600.0,
    0.0,
    -71.0 / 16695.0,
    71.0 / 1920.0,
    -17253.0 / 339200.0,
    22.0 / 525.0,
    -1.0 / 40.0,
];

/// Adaptive Dormand–Prince integration: each step's local error in each component is kept
/// below `absolute + relative·|yᵢ|`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DormandPrince {
    pub relative: f64,
    pub absolute: f64,
    /// Most steps (accepted or rejected) before giving up.
    pub max_steps: usize,
}

/// One trial step: the new state, f there, and the error estimate relative to the tolerance
/// (accept when ≤ 1).
struct Step<const N: usize> {
    y: [f64; N],
    f: [f64; N],
    error: f64,
}

impl DormandPrince {
    /// Integrates y′ = f(y) from `y0`, starting with parameter step `h0`, until
    /// `event(y, f(y))`, which returns g and dg/dτ, crosses zero from below; returns the state
    /// at the crossing, located to rounding, or `None` if there is none within `max_steps`
    /// steps. The start counts as before the event (g is not evaluated there, so it may lie
    /// on the event surface).
    pub fn integrate_until<const N: usize>(
        &self,
        f: impl Fn(&[f64; N]) -> [f64; N],
        y0: [f64; N],
        h0: f64,
        event: impl Fn(&[f64; N], &[f64; N]) -> (f64, f64),
    ) -> Option<[f64; N]> {
        self.integrate_observed(f, y0, h0, event, |_| {})
    }

    /// [`Self::integrate_until`], showing `accepted` the state after each accepted step before
    /// the event (not the start, nor the state at the crossing).
    pub fn integrate_observed<const N: usize>(
        &self,
        f: impl Fn(&[f64; N]) -> [f64; N],
        y0: [f64; N],
        h0: f64,
        event: impl Fn(&[f64; N], &[f64; N]) -> (f64, f64),
        mut accepted: impl FnMut(&[f64; N]),
    ) -> Option<[f64; N]> {
        let (mut y, mut k1, mut h) = (y0, f(&y0), h0);
        for _ in 0..self.max_steps {
            let s = self.step(&f, &y, &k1, h);
            if !s.error.is_finite() || !s.y.iter().all(|v| v.is_finite()) {
                h *= 0.1;
                continue;
            }
            if s.error <= 1.0 {
                if event(&s.y, &s.f).0 >= 0.0 {
                    return Some(self.locate(&f, &y, &k1, h, &event));
                }
                (y, k1) = (s.y, s.f);
                accepted(&y);
            }
            // Standard step-size control: safety 0.9, growth limited to [0.2, 5].
            h *= (0.9 * s.error.powf(-0.2)).clamp(0.2, 5.0);
        }
        None
    }

    /// The state where g crosses zero upwards within the step of length `h` from `y` (before
    /// the event): Newton's method on the step length, each trial a full step from `y`, kept
    /// inside the bracket by bisection.
    fn locate<const N: usize>(
        &self,
        f: &impl Fn(&[f64; N]) -> [f64; N],
        y: &[f64; N],
        k1: &[f64; N],
        h: f64,
        event: &impl Fn(&[f64; N], &[f64; N]) -> (f64, f64),
    ) -> [f64; N] {
        let (mut lo, mut hi) = (0.0, h);
        let mut h = 0.5 * h;
        let mut best = *y;
        for _ in 0..100 {
            let s = self.step(f, y, k1, h);
            let (g, dg) = event(&s.y, &s.f);
            best = s.y;
            if g == 0.0 {
                break;
            }
            if g < 0.0 {
                lo = h;
            } else {
                hi = h;
            }
            if hi - lo <= 4.0 * f64::EPSILON * hi {
                break;
            }
            let newton = h - g / dg;
            h = if newton > lo && newton < hi {
                newton
            } else {
                0.5 * (lo + hi)
            };
        }
        best
    }

    /// One Dormand–Prince step of length `h` from `y`, where f(y) = `k1`.
    fn step<const N: usize>(
        &self,
        f: &impl Fn(&[f64; N]) -> [f64; N],
        y: &[f64; N],
        k1: &[f64; N],
        h: f64,
    ) -> Step<N> {
        let mut k = [[0.0; N]; 7];
        k[0] = *k1;
        let mut y_new = *y;
        for (stage, a) in A.iter().enumerate() {
            let mut yi = *y;
            for (j, &aij) in a.iter().enumerate() {
                for (v, kj) in yi.iter_mut().zip(&k[j]) {
                    *v += h * aij * kj;
                }
            }
            k[stage + 1] = f(&yi);
            y_new = yi;
        }
        let mut sum = 0.0;
        for i in 0..N {
            let err: f64 = h * (0..7).map(|j| E[j] * k[j][i]).sum::<f64>();
            let scale = self.absolute + self.relative * y[i].abs().max(y_new[i].abs());
            sum += (err / scale).powi(2);
        }
        Step {
            y: y_new,
            f: k[6],
            error: (sum / N as f64).sqrt(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SOLVER: DormandPrince = DormandPrince {
        relative: 1e-12,
        absolute: 1e-12,
        max_steps: 100_000,
    };

    #[test]
    fn harmonic_oscillator_reaches_its_event_at_the_exact_phase() {
        // y = (cos τ, −sin τ); stop where the first component falls through −0.5 (g = −y₀ − ½
        // crosses zero upwards), at τ = 2π/3, where y₁ = −sin(2π/3).
        let f = |y: &[f64; 2]| [y[1], -y[0]];
        let event = |y: &[f64; 2], dy: &[f64; 2]| (-y[0] - 0.5, -dy[0]);
        let y = SOLVER.integrate_until(f, [1.0, 0.0], 1e-3, event).unwrap();
        assert!((y[0] + 0.5).abs() < 1e-14, "{y:?}");
        assert!((y[1] + (3f64.sqrt() / 2.0)).abs() < 1e-10, "{y:?}");
    }

    #[test]
    fn exponential_growth_is_accurate_to_the_tolerance() {
        // y′ = y from 1 until y = e⁵: the state is exact and the step controller has coped
        // with a solution growing by 150 times.
        let y = SOLVER
            .integrate_until(
                |y: &[f64; 2]| [y[0], 1.0],
                [1.0, 0.0],
                0.1,
                |y, dy| (y[1] - 5.0, dy[1]),
            )
            .unwrap();
        assert!((y[0] / 5f64.exp() - 1.0).abs() < 1e-10, "{y:?}");
    }

    #[test]
    fn no_event_within_the_step_limit_is_none() {
        let solver = DormandPrince {
            max_steps: 50,
            ..SOLVER
        };
        let never = |y: &[f64; 1], _: &[f64; 1]| (-1.0 - y[0].abs(), 0.0);
        assert_eq!(
            solver.integrate_until(|_: &[f64; 1]| [1.0], [0.0], 1e-3, never),
            None
        );
    }
}
