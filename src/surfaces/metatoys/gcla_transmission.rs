//! The transmission coefficient of gCLAs whose lenslets have rectangular apertures (Dr TIM's
//! `GCLAsWithApertures` with its `GCLAsTransmissionCoefficientCalculationMethodType`, and
//! `transmissionCoefficient/GCLAsTransmissionCoefficientCalculator`; Maceina, Juzeliūnas and
//! Courtial, Opt. Commun. 284, 5008 (2011)).
//!
//! In the (t, a) projection (t = u or v), with all transverse lengths in units of f₁, the focal
//! length of the lenslet met first: lenslet 1's aperture is [α₁ − σ₁/2, α₁ + σ₁/2] about its
//! axis; lenslet 2, of focal length f₂ = −η f₁, has its axis at δ and its aperture
//! [δ + α₂ − σ₂/2, δ + α₂ + σ₂/2]. Rays of slope s = d_t/d_a entering lenslet 1 at height h
//! pass through s in the common focal plane and reach lenslet 2's plane at s − η (s − h). The
//! fraction of the light that gets through is the overlap of aperture 2 with the image of
//! aperture 1 (of width |η σ₁|), divided by |η σ₁|; the coefficient is the product of the u and
//! v projections'. A ray meeting lenslet 2 first sees the telescope reversed: η → 1/η,
//! δ → δ/η, α₁ → −α₂/η, α₂ → −α₁/η, σ₁ → −σ₂/η, σ₂ → −σ₁/η (lengths now in units of f₂).

use glam::DVec2;

/// Lenslet apertures: widths σ and offsets α of the aperture centres from the lenslets' own
/// axes, along (u, v), in units of f₁ (Dr TIM's `sigma1U`… and `alpha1U`…).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Apertures {
    pub sigma1: DVec2,
    pub sigma2: DVec2,
    pub alpha1: DVec2,
    pub alpha2: DVec2,
}

impl Default for Apertures {
    /// Dr TIM's: centred apertures as wide as f₁.
    fn default() -> Apertures {
        Apertures {
            sigma1: DVec2::ONE,
            sigma2: DVec2::ONE,
            alpha1: DVec2::ZERO,
            alpha2: DVec2::ZERO,
        }
    }
}

/// How the fraction of the light the telescopes pass on is found.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Transmission {
    /// The given coefficient, whatever the ray (Dr TIM's `CONSTANT`).
    Constant(f64),
    /// The overlap of the apertures for this ray (Dr TIM's `GEOMETRIC`).
    Geometric(Apertures),
    /// The best case over all directions, with apertures of equal widths: min(1, 1/|η|) in each
    /// projection (Dr TIM's `GEOMETRIC_BEST`; see `best_case`).
    GeometricBest,
}

/// The transmission coefficient in one projection, for a ray of slope `slope` = d_t/d_a
/// meeting lenslet 1 first (see the module notes).
pub fn projection_transmission(
    eta: f64,
    delta: f64,
    (alpha1, alpha2): (f64, f64),
    (sigma1, sigma2): (f64, f64),
    slope: f64,
) -> f64 {
    let image = |h: f64| slope - eta * (slope - h);
    let (a, b) = (image(alpha1 - 0.5 * sigma1), image(alpha1 + 0.5 * sigma1));
    let (c, d) = (delta + alpha2 - 0.5 * sigma2, delta + alpha2 + 0.5 * sigma2);
    let overlap = a.max(b).min(c.max(d)) - a.min(b).max(c.min(d));
    overlap.max(0.0) / (eta * sigma1).abs()
}

/// The apertures as a ray meeting lenslet 2 first sees them (see the module notes).
pub fn reversed(apertures: &Apertures, eta: DVec2) -> Apertures {
    Apertures {
        sigma1: -apertures.sigma2 / eta,
        sigma2: -apertures.sigma1 / eta,
        alpha1: -apertures.alpha2 / eta,
        alpha2: -apertures.alpha1 / eta,
    }
}

/// The best-case coefficient in one projection: min(1, 1/|η|), the largest value of
/// [`projection_transmission`] for σ₁ = σ₂. Dr TIM's documentation gives this, but its code
/// returns min(1, |η|), which is not the maximum of its own geometric coefficient (at η = 2,
/// 1 against the geometric 0.5); timbre follows the geometry.
pub fn best_case(eta: f64) -> f64 {
    1f64.min(1.0 / eta.abs())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The telescope traced ray by ray with thin-lens optics: `n` rays of slope `s` spread
    /// evenly over lenslet 1's aperture, each carried through the lenses in turn (lens at a = 0,
    /// focal length 1, axis at 0), refracted (slope′ = slope − h/f), carried to lenslet 2 at
    /// a = 1 + f₂ (f₂ = −η), kept if they land inside aperture 2; the fraction kept. The
    /// landing height is the formula's image of h; what this checks independently is the
    /// overlap and its normalisation (the vignetting), for apertures of every order.
    fn traced(eta: f64, delta: f64, alpha: (f64, f64), sigma: (f64, f64), s: f64) -> f64 {
        let n = 100_000;
        let f2 = -eta;
        let kept = (0..n)
            .filter(|&i| {
                let h = alpha.0 + sigma.0 * ((i as f64 + 0.5) / n as f64 - 0.5);
                let after = s - h; // slope after lens 1 (f₁ = 1)
                let at2 = h + after * (1.0 + f2);
                (at2 - delta - alpha.1).abs() < 0.5 * sigma.1.abs()
            })
            .count();
        kept as f64 / n as f64
    }

    #[test]
    fn the_overlap_formula_is_the_fraction_of_traced_rays_that_pass() {
        for (eta, delta, alpha, sigma) in [
            (1.0, 0.0, (0.0, 0.0), (1.0, 1.0)),
            (2.0, 0.0, (0.0, 0.0), (1.0, 1.0)),
            (-0.5, 0.1, (0.1, -0.2), (1.0, 0.8)),
            (-2.0, 0.3, (0.0, 0.2), (0.5, 1.5)),
            (0.7, -0.4, (-0.1, 0.0), (1.2, 0.6)),
        ] {
            for s in [-0.8, -0.3, 0.0, 0.2, 0.5, 1.1] {
                let formula = projection_transmission(eta, delta, alpha, sigma, s);
                let rays = traced(eta, delta, alpha, sigma, s);
                assert!(
                    (formula - rays).abs() < 1e-4,
                    "η {eta}, δ {delta}, α {alpha:?}, σ {sigma:?}, s {s}: {formula} vs {rays}"
                );
            }
        }
    }

    /// A ray meeting lenslet 2 first crosses the same telescope backwards: traced with lens 2
    /// (focal length f₂ = −η, axis at δ, aperture centre δ + α₂) first and lens 1 a distance
    /// f₁ + f₂ behind it, in lengths of f₁ and slopes measured against −â (so a transverse
    /// direction component keeps its sign while d·â changes sign); the reversed parameters
    /// give the same fraction.
    #[test]
    fn reversed_apertures_describe_the_telescope_crossed_backwards() {
        let (eta, delta) = (DVec2::new(-1.5, 0.6), DVec2::new(0.2, -0.1));
        let apertures = Apertures {
            sigma1: DVec2::new(1.0, 0.9),
            sigma2: DVec2::new(1.2, 1.0),
            alpha1: DVec2::new(0.1, 0.0),
            alpha2: DVec2::new(-0.2, 0.1),
        };
        let r = reversed(&apertures, eta);
        let n = 100_000;
        for s in [-0.4, 0.0, 0.3] {
            for (i, (eta, delta)) in [(eta.x, delta.x), (eta.y, delta.y)].into_iter().enumerate() {
                let (sigma1, sigma2) = (apertures.sigma1[i], apertures.sigma2[i]);
                let (alpha1, alpha2) = (apertures.alpha1[i], apertures.alpha2[i]);
                let f2 = -eta;
                // Lens 2 first: heights x measured from lens 1's axis, in units of f₁.
                let kept = (0..n)
                    .filter(|&k| {
                        let x = delta + alpha2 + sigma2 * ((k as f64 + 0.5) / n as f64 - 0.5);
                        let after = s - (x - delta) / f2;
                        let at1 = x + after * (1.0 + f2);
                        (at1 - alpha1).abs() < 0.5 * sigma1
                    })
                    .count() as f64
                    / n as f64;
                // In units of f₂ the slope is the same, δ → δ/η.
                let formula = projection_transmission(
                    1.0 / eta,
                    delta / eta,
                    (r.alpha1[i], r.alpha2[i]),
                    (r.sigma1[i], r.sigma2[i]),
                    s,
                );
                assert!(
                    (formula - kept).abs() < 1e-4,
                    "{i} {s}: {formula} vs {kept}"
                );
            }
        }
    }

    #[test]
    fn the_best_case_is_the_largest_geometric_coefficient() {
        for eta in [-3.0, -1.0, -0.4, 0.5, 1.0, 2.0] {
            let best = (-200..=200)
                .map(|k| {
                    projection_transmission(eta, 0.0, (0.0, 0.0), (1.0, 1.0), k as f64 / 100.0)
                })
                .fold(0.0, f64::max);
            assert!((best - best_case(eta)).abs() < 1e-12, "η {eta}: {best}");
        }
    }
}
