//! Spherically symmetric refractive-index profiles n(ρ), ρ = r/R, of the gradient-index
//! lenses, with n∇n = ∇(n²)/2, the force of the ray equation in Hamiltonian form.
//!
//! - Luneburg: n = √(2 − ρ²);
//! - Eaton: n = √(2/ρ − 1), singular at the centre;
//! - Maxwell-fisheye lens: n = 2/(1 + ρ²), Maxwell's fisheye truncated at ρ = 1 (§3);
//! - a table n(ρᵢ), interpolated by a cubic spline with n′(0) = 0 (a smooth spherically
//!   symmetric profile has no slope at its centre) and the not-a-knot condition at the surface
//!   end, which imposes nothing on the data there.
//!
//! - the Chen–Belin black hole (Dr TIM's `SurfaceOfChenBelinMetricSpace`, after Huanyang Chen's
//!   profile as Jakub Belin modified it): n = (jh + ρ)³ / (ρ² (ρ − h)), with h the horizon
//!   radius in units of R, singular at the horizon.
//!
//! The Luneburg, Eaton and Maxwell-fisheye profiles have n(1) = 1, matching the surrounding
//! medium. Beyond ρ = 1 each profile is continued by its own formula (the table by its last
//! cubic), which the integrator's trial stages may sample just outside the surface.

#[derive(Debug, Clone, PartialEq)]
pub enum IndexProfile {
    Luneburg,
    Eaton,
    MaxwellFisheye,
    Table(TableProfile),
    /// The horizon radius h (in units of R, 0 < h) and Belin's j ≥ 0 (j = 1 is Chen's
    /// profile).
    ChenBelin {
        horizon: f64,
        j: f64,
    },
}

impl IndexProfile {
    /// n at ρ = r/R.
    pub fn n(&self, rho: f64) -> f64 {
        match self {
            IndexProfile::Luneburg => (2.0 - rho * rho).sqrt(),
            IndexProfile::Eaton => (2.0 / rho - 1.0).sqrt(),
            IndexProfile::MaxwellFisheye => 2.0 / (1.0 + rho * rho),
            IndexProfile::Table(t) => t.eval(rho).0,
            &IndexProfile::ChenBelin { horizon, j } => {
                (j * horizon + rho).powi(3) / (rho * rho * (rho - horizon))
            }
        }
    }

    /// n′/n of the Chen–Belin profile at ρ: d ln n/dρ = 3/(ρ + jh) − 2/ρ − 1/(ρ − h).
    fn chen_belin_log_slope(horizon: f64, j: f64, rho: f64) -> f64 {
        3.0 / (rho + j * horizon) - 2.0 / rho - 1.0 / (rho - horizon)
    }

    /// The radius within which every ray falls into the horizon: for a profile with a horizon
    /// (Chen–Belin), half-way between the horizon and the photon sphere, where nρ (the largest
    /// angular momentum a ray there can have) is least. Inside the photon sphere nρ grows
    /// inwards, so a ray moving inwards there never turns back. `None` for the others.
    pub fn absorbing_radius(&self) -> Option<f64> {
        match *self {
            IndexProfile::ChenBelin { horizon, j } => {
                Some(0.5 * (horizon + Self::photon_sphere_radius(horizon, j)))
            }
            _ => None,
        }
    }

    /// The photon sphere of the Chen–Belin profile, in units of R: where d(nρ)/dρ = 0, i.e.
    /// 3/(ρ + jh) = 1/ρ + 1/(ρ − h), the larger root of ρ² − 2(1 + j)hρ + jh² = 0:
    /// ρ = h (1 + j + √(1 + j + j²)). 3h for Belin's j = 3/5, (2 + √3)h for Chen's j = 1.
    pub fn photon_sphere_radius(horizon: f64, j: f64) -> f64 {
        horizon * (1.0 + j + (1.0 + j + j * j).sqrt())
    }

    /// n² and the factor φ with n∇n = ∇(n²)/2 = φ x at a point x (in units of R, relative to
    /// the centre) with |x|² = `rho_squared`: by spherical symmetry φ = n n′(ρ)/ρ, the force of
    /// the ray equation in Hamiltonian form per unit distance from the centre.
    pub fn n_squared_and_force(&self, rho_squared: f64) -> (f64, f64) {
        match self {
            IndexProfile::Luneburg => (2.0 - rho_squared, -1.0),
            IndexProfile::Eaton => {
                let rho = rho_squared.sqrt();
                (2.0 / rho - 1.0, -1.0 / (rho_squared * rho))
            }
            IndexProfile::MaxwellFisheye => {
                let inverse = 1.0 / (1.0 + rho_squared);
                let n = 2.0 * inverse;
                (n * n, -8.0 * inverse * inverse * inverse)
            }
            IndexProfile::Table(t) => {
                let rho = rho_squared.sqrt();
                let (n, slope) = t.eval(rho);
                let force = if rho == 0.0 { 0.0 } else { n * slope / rho };
                (n * n, force)
            }
            &IndexProfile::ChenBelin { horizon, j } => {
                let rho = rho_squared.sqrt();
                let n2 = self.n(rho).powi(2);
                (n2, n2 * Self::chen_belin_log_slope(horizon, j, rho) / rho)
            }
        }
    }

    /// ρn² and its derivative d(ρn²)/dρ = n² + 2ρnn′ at ρ, the potential of the ray equation
    /// after the Levi-Civita transformation (see `gradient_index`). Both stay finite at the
    /// centre where n² has a pole like 1/ρ (Eaton's), and ρn² is 0 there for a profile finite
    /// there.
    pub fn rho_n_squared(&self, rho: f64) -> (f64, f64) {
        match self {
            IndexProfile::Luneburg => (rho * (2.0 - rho * rho), 2.0 - 3.0 * rho * rho),
            IndexProfile::Eaton => (2.0 - rho, -1.0),
            IndexProfile::MaxwellFisheye => {
                let s = 1.0 + rho * rho;
                (
                    4.0 * rho / (s * s),
                    4.0 * (1.0 - 3.0 * rho * rho) / (s * s * s),
                )
            }
            IndexProfile::Table(t) => {
                let (n, slope) = t.eval(rho);
                (rho * n * n, n * (n + 2.0 * rho * slope))
            }
            &IndexProfile::ChenBelin { horizon, j } => {
                let n2 = self.n(rho).powi(2);
                (
                    rho * n2,
                    n2 * (1.0 + 2.0 * rho * Self::chen_belin_log_slope(horizon, j, rho)),
                )
            }
        }
    }

    /// Whether n is smooth inside the lens: the built-in formulas are; a table's spline is C²,
    /// its third derivative jumping at the knots.
    pub fn is_smooth(&self) -> bool {
        !matches!(self, IndexProfile::Table(_))
    }

    pub fn name(&self) -> &'static str {
        match self {
            IndexProfile::Luneburg => "luneburg",
            IndexProfile::Eaton => "eaton",
            IndexProfile::MaxwellFisheye => "maxwell-fisheye",
            IndexProfile::Table(_) => "table",
            IndexProfile::ChenBelin { .. } => "chen-belin",
        }
    }
}

/// A tabulated profile n(ρᵢ), interpolated by a C² cubic spline.
#[derive(Debug, Clone, PartialEq)]
pub struct TableProfile {
    rho: Vec<f64>,
    n: Vec<f64>,
    /// The spline's second derivatives at the knots.
    curvature: Vec<f64>,
}

/// Spline samples per table interval checked for a positive n.
const POSITIVITY_SAMPLES: usize = 16;

impl TableProfile {
    /// The spline through (ρᵢ, nᵢ). ρ must rise strictly from 0 to 1, and n (at the knots and
    /// in between) must be positive and finite.
    pub fn new(rho: Vec<f64>, n: Vec<f64>) -> Result<TableProfile, String> {
        if rho.len() != n.len() {
            return Err(format!(
                "rho has {} values but n has {}",
                rho.len(),
                n.len()
            ));
        }
        if rho.len() < 2 || rho[0] != 0.0 || rho[rho.len() - 1] != 1.0 {
            return Err("rho must run from 0 (the centre) to 1 (the surface)".into());
        }
        if let Some(i) = rho
            .windows(2)
            .position(|w| w[0].partial_cmp(&w[1]) != Some(std::cmp::Ordering::Less))
        {
            return Err(format!(
                "rho must increase strictly (rho[{}] = {} follows {})",
                i + 1,
                rho[i + 1],
                rho[i]
            ));
        }
        if let Some(i) = n.iter().position(|v| !(v.is_finite() && *v > 0.0)) {
            return Err(format!("n[{i}] = {} is not a positive number", n[i]));
        }
        let curvature = spline_curvature(&rho, &n);
        let table = TableProfile { rho, n, curvature };
        for (i, w) in table.rho.windows(2).enumerate() {
            for k in 1..POSITIVITY_SAMPLES {
                let x = w[0] + (w[1] - w[0]) * k as f64 / POSITIVITY_SAMPLES as f64;
                if table.eval(x).0 <= 0.0 {
                    return Err(format!(
                        "the interpolated n is not positive between rho = {} and {} (table entries {i} and {}); add points there",
                        w[0],
                        w[1],
                        i + 1
                    ));
                }
            }
        }
        Ok(table)
    }

    /// n and dn/dρ at `rho` (the end cubics continue beyond the table).
    fn eval(&self, rho: f64) -> (f64, f64) {
        let last = self.rho.len() - 2;
        let i = self.rho.partition_point(|&x| x <= rho).clamp(1, last + 1) - 1;
        let (x0, x1) = (self.rho[i], self.rho[i + 1]);
        let (y0, y1) = (self.n[i], self.n[i + 1]);
        let (m0, m1) = (self.curvature[i], self.curvature[i + 1]);
        let h = x1 - x0;
        let (a, b) = (x1 - rho, rho - x0);
        let (c0, c1) = (y0 / h - m0 * h / 6.0, y1 / h - m1 * h / 6.0);
        let n = (m0 * a.powi(3) + m1 * b.powi(3)) / (6.0 * h) + c0 * a + c1 * b;
        let slope = (m1 * b * b - m0 * a * a) / (2.0 * h) + c1 - c0;
        (n, slope)
    }
}

/// Second derivatives Mᵢ of the cubic spline through (xᵢ, yᵢ) with slope 0 at the first knot
/// and, at the last, the not-a-knot condition (M = 0 for two knots): a tridiagonal system
/// solved by the Thomas algorithm.
fn spline_curvature(x: &[f64], y: &[f64]) -> Vec<f64> {
    let n = x.len();
    let h: Vec<f64> = x.windows(2).map(|w| w[1] - w[0]).collect();
    let secant = |i: usize| (y[i + 1] - y[i]) / h[i];
    // Rows i = 0..n−1 of  sub Mᵢ₋₁ + diag Mᵢ + sup Mᵢ₊₁ = rhs.
    let mut diag = vec![1.0; n];
    let mut sup = vec![0.0; n];
    let mut rhs = vec![0.0; n];
    let mut sub = vec![0.0; n];
    (diag[0], sup[0], rhs[0]) = (2.0 * h[0], h[0], 6.0 * secant(0));
    for i in 1..n - 1 {
        sub[i] = h[i - 1];
        diag[i] = 2.0 * (h[i - 1] + h[i]);
        sup[i] = h[i];
        rhs[i] = 6.0 * (secant(i) - secant(i - 1));
    }
    if n >= 3 {
        // Not-a-knot at the last interior knot (the third derivative is continuous there):
        // hₙ₋₂ Mₙ₋₃ − (hₙ₋₃ + hₙ₋₂) Mₙ₋₂ + hₙ₋₃ Mₙ₋₁ = 0, with Mₙ₋₃ eliminated by row n − 2.
        let (a, b, c, r) = (sub[n - 2], diag[n - 2], sup[n - 2], rhs[n - 2]);
        let (p, q, s) = (h[n - 2], -(h[n - 3] + h[n - 2]), h[n - 3]);
        (sub[n - 1], diag[n - 1], rhs[n - 1]) = (q - p * b / a, s - p * c / a, -p * r / a);
    } // With two knots, the last row is M = 0 (diag 1, rhs 0, as initialised).
    for i in 1..n {
        let w = sub[i] / diag[i - 1];
        diag[i] -= w * sup[i - 1];
        rhs[i] -= w * rhs[i - 1];
    }
    let mut m = vec![0.0; n];
    m[n - 1] = rhs[n - 1] / diag[n - 1];
    for i in (0..n - 1).rev() {
        m[i] = (rhs[i] - sup[i] * m[i + 1]) / diag[i];
    }
    m
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;

    fn luneburg_table(points: usize) -> TableProfile {
        let rho: Vec<f64> = (0..points)
            .map(|i| i as f64 / (points - 1) as f64)
            .collect();
        let n = rho.iter().map(|r| IndexProfile::Luneburg.n(*r)).collect();
        TableProfile::new(rho, n).unwrap()
    }

    #[test]
    fn spline_passes_through_the_table_and_approximates_a_smooth_profile() {
        let t = luneburg_table(41);
        for (r, n) in t.rho.iter().zip(&t.n) {
            assert!((t.eval(*r).0 - n).abs() < 1e-14);
        }
        for k in 0..=1000 {
            let rho = k as f64 / 1000.0;
            let (n, slope) = t.eval(rho);
            let exact_slope = -rho / (2.0 - rho * rho).sqrt();
            assert!((n - IndexProfile::Luneburg.n(rho)).abs() < 1e-6, "{rho}");
            assert!((slope - exact_slope).abs() < 2e-3, "{rho}: {slope}");
        }
        assert_eq!(t.eval(0.0).1, 0.0, "no slope at the centre");
    }

    #[test]
    fn spline_is_continuous_with_continuous_slope_at_the_knots() {
        let t = TableProfile::new(vec![0.0, 0.3, 0.5, 1.0], vec![2.0, 1.4, 1.6, 1.0]).unwrap();
        for &k in &t.rho[1..3] {
            let (below, above) = (t.eval(k - 1e-9), t.eval(k + 1e-9));
            assert!((below.0 - above.0).abs() < 1e-8 && (below.1 - above.1).abs() < 1e-6);
        }
    }

    #[test]
    fn force_is_half_the_gradient_of_n_squared() {
        let profiles = [
            IndexProfile::Luneburg,
            IndexProfile::Eaton,
            IndexProfile::MaxwellFisheye,
            IndexProfile::Table(luneburg_table(11)),
        ];
        let x = DVec3::new(0.3, -0.4, 0.2);
        for p in &profiles {
            let n2 = |x: DVec3| p.n(x.length()).powi(2) / 2.0;
            let h = 1e-6;
            let numeric = DVec3::new(
                n2(x + DVec3::X * h) - n2(x - DVec3::X * h),
                n2(x + DVec3::Y * h) - n2(x - DVec3::Y * h),
                n2(x + DVec3::Z * h) - n2(x - DVec3::Z * h),
            ) / (2.0 * h);
            let (n2, factor) = p.n_squared_and_force(x.length_squared());
            assert!((factor * x - numeric).length() < 1e-7, "{}", p.name());
            assert!((n2 - p.n(x.length()).powi(2)).abs() < 1e-14, "{}", p.name());
        }
    }

    #[test]
    fn rho_n_squared_and_its_slope_follow_n() {
        let profiles = [
            IndexProfile::Luneburg,
            IndexProfile::Eaton,
            IndexProfile::MaxwellFisheye,
            IndexProfile::Table(luneburg_table(11)),
        ];
        for p in &profiles {
            for rho in [0.1, 0.37, 0.8, 1.0] {
                let value = |r: f64| r * p.n(r).powi(2);
                let h = 1e-6;
                let numeric = (value(rho + h) - value(rho - h)) / (2.0 * h);
                let (v, slope) = p.rho_n_squared(rho);
                assert!((v - value(rho)).abs() < 1e-14, "{} {rho}", p.name());
                assert!((slope - numeric).abs() < 1e-7, "{} {rho}", p.name());
            }
        }
        assert_eq!(IndexProfile::Eaton.rho_n_squared(0.0), (2.0, -1.0));
        assert_eq!(IndexProfile::Luneburg.rho_n_squared(0.0).0, 0.0);
    }

    /// Chen's and Belin's photon spheres are where n ρ is least (a central difference of n ρ
    /// vanishes there, and it is larger on either side): (2 + √3)h for j = 1, 3h for j = 3/5,
    /// as Dr TIM's comments say; and the force is n n′/ρ, n′ by a central difference.
    #[test]
    fn the_chen_belin_photon_sphere_is_where_n_rho_is_least() {
        let h = 0.02;
        for (j, expected) in [(1.0, (2.0 + 3f64.sqrt()) * h), (0.6, 3.0 * h)] {
            let profile = IndexProfile::ChenBelin { horizon: h, j };
            let r = IndexProfile::photon_sphere_radius(h, j);
            assert!((r - expected).abs() < 1e-15, "{r}");
            let n_rho = |x: f64| profile.n(x) * x;
            let e = 1e-6;
            assert!(((n_rho(r + e) - n_rho(r - e)) / (2.0 * e)).abs() < 1e-7);
            assert!(n_rho(0.9 * r) > n_rho(r) && n_rho(1.1 * r) > n_rho(r));
            for rho in [0.05, 0.1, 0.5, 1.0] {
                let slope = (profile.n(rho + e) - profile.n(rho - e)) / (2.0 * e);
                let (n2, force) = profile.n_squared_and_force(rho * rho);
                assert!((n2 - profile.n(rho).powi(2)).abs() < 1e-12 * n2);
                let want = profile.n(rho) * slope / rho;
                assert!(
                    (force - want).abs() < 1e-6 * want.abs(),
                    "{rho}: {force} {want}"
                );
            }
        }
    }

    #[test]
    fn bad_tables_are_rejected() {
        let bad = [
            (vec![0.0, 1.0], vec![1.0]),
            (vec![0.0], vec![1.0]),
            (vec![0.1, 1.0], vec![1.0, 1.0]),
            (vec![0.0, 0.9], vec![1.0, 1.0]),
            (vec![0.0, 0.5, 0.5, 1.0], vec![1.0; 4]),
            (vec![0.0, 1.0], vec![1.0, f64::NAN]),
            (vec![0.0, 1.0], vec![0.0, 1.0]),
            // Positive at the knots but not between them.
            (vec![0.0, 0.1, 0.2, 1.0], vec![0.05, 3.0, 0.05, 1.0]),
        ];
        for (rho, n) in bad {
            assert!(
                TableProfile::new(rho.clone(), n.clone()).is_err(),
                "{rho:?} {n:?}"
            );
        }
    }
}
