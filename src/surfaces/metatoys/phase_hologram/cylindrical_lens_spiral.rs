//! A cylindrical lens wound into a spiral, Dr TIM's `PhaseHologramOfCylindricalLensSpiral`
//! (the lenses of its adaptive spiral lens, `research/adaptiveFresnelLens`).
//!
//! About the centre c, with ρ and θ the polar coordinates of r − c (θ from u towards v), the
//! lens's centre line is the spiral r(ψ) with ψ = θ + δ + 2πn (δ the rotation angle, n the
//! winding):
//!
//! - Archimedean: r(ψ) = bψ, the lens's focal length f₁/r (f₁ at r = 1);
//! - logarithmic: r(ψ) = exp(bψ), focal length f₁ everywhere;
//! - hyperbolic: r(ψ) = −1/(bψ), focal length f₁ r.
//!
//! A point belongs to the winding n whose centre line is nearest along the radius, r_n =
//! r(θ + δ + 2πn) (the windings meet midway between consecutive centre lines, as in Dr TIM),
//! and gets that winding's cylindrical-lens phase in the radial distance d = ρ − r_n:
//! φ = −d²/(2f_n), f_n the focal length at r_n. With Alvarez (Lohmann) winding focusing
//! (Archimedean and logarithmic spirals only) a cubic term makes each winding's radial power
//! grow across it: φ = −d² r_n/(2f₁) − d³/(3f₁) (Archimedean), φ = −d²/(2f₁) − d³/(6f₁r_n)
//! (logarithmic). The kick is the exact gradient of φ, r_n varying with θ:
//! ∇d = r̂ − (r_n′/ρ) θ̂ and ∇r_n = (r_n′/ρ) θ̂, r_n′ = dr/dψ.
//!
//! Two spirals of focal lengths f₁ and −f₁, the second rotated by δ, add up to a lens of focal
//! length about f₁/(bδ) (Dr TIM's `SpiralLensVisualiser`, its `calculateF`), for each of the
//! three spirals: where their windings pair up, their radial kicks add up to about −ρbδ/f₁
//! (exactly (r_n(θ) − r_n(θ + δ))/f₁ = r_n(1 − e^{bδ})/f₁ for the logarithmic spiral).
//!
//! **Dr TIM**: its logarithmic kick leaves δ out of one of the two r_n it uses (exact for
//! δ = 0), and its Archimedean kick without winding focusing leaves out the term from the
//! change of the winding's focal length with θ (−d² b θ̂/(2f₁ρ), of second order in d), so
//! that it is not the gradient of a phase; timbre's kicks are the exact gradients of the phases
//! above (the same as Dr TIM's in its other cases). Dr TIM ignores winding focusing for
//! hyperbolic spirals; timbre refuses it.

use std::f64::consts::TAU;

use glam::DVec2;
use serde::Deserialize;

use super::Phase;
use crate::keys::{Finite, NonZero, Vector2};

/// The shape of the spiral's centre line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SpiralType {
    /// r = bψ.
    Archimedean,
    /// r = exp(bψ).
    Logarithmic,
    /// r = −1/(bψ).
    Hyperbolic,
}

impl SpiralType {
    /// The centre line's radius at the unbounded angle ψ, and its derivative dr/dψ.
    fn radius(self, b: f64, psi: f64) -> (f64, f64) {
        match self {
            SpiralType::Archimedean => (b * psi, b),
            SpiralType::Logarithmic => {
                let r = (b * psi).exp();
                (r, b * r)
            }
            SpiralType::Hyperbolic => {
                let r = -1.0 / (b * psi);
                (r, b * r * r)
            }
        }
    }

    /// The unbounded angle ψ at which the centre line has radius ρ (the inverse of `radius`).
    fn angle(self, b: f64, rho: f64) -> f64 {
        match self {
            SpiralType::Archimedean => rho / b,
            SpiralType::Logarithmic => rho.ln() / b,
            SpiralType::Hyperbolic => -1.0 / (b * rho),
        }
    }
}

/// A cylindrical lens along the spiral `spiral` of parameter `b`, rotated by `rotation`
/// (radians), about `centre`, with focal length `focal_length` (f₁).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CylindricalLensSpiralPhase {
    pub spiral: SpiralType,
    pub focal_length: f64,
    pub b: f64,
    pub rotation: f64,
    pub alvarez_winding_focusing: bool,
    pub centre: DVec2,
}

impl CylindricalLensSpiralPhase {
    /// The winding's radial power P = 1/f_n at r_n and dP/dr_n.
    fn power(&self, r_n: f64) -> (f64, f64) {
        let f1 = self.focal_length;
        match self.spiral {
            SpiralType::Archimedean => (r_n / f1, 1.0 / f1),
            SpiralType::Logarithmic => (1.0 / f1, 0.0),
            SpiralType::Hyperbolic => (1.0 / (f1 * r_n), -1.0 / (f1 * r_n * r_n)),
        }
    }

    /// The coefficient A of the winding-focusing term −A d³ at r_n, and dA/dr_n.
    fn winding_focusing(&self, r_n: f64) -> (f64, f64) {
        let f1 = self.focal_length;
        match (self.alvarez_winding_focusing, self.spiral) {
            (true, SpiralType::Archimedean) => (1.0 / (3.0 * f1), 0.0),
            (true, SpiralType::Logarithmic) => {
                (1.0 / (6.0 * f1 * r_n), -1.0 / (6.0 * f1 * r_n * r_n))
            }
            _ => (0.0, 0.0),
        }
    }

    /// The winding whose centre line is nearest to `r` along the radius: its radius r_n and
    /// dr/dψ there.
    fn winding(&self, rho: f64, theta: f64) -> (f64, f64) {
        let psi0 = theta + self.rotation;
        let n = ((self.spiral.angle(self.b, rho) - psi0) / TAU).floor();
        let below = self.spiral.radius(self.b, psi0 + TAU * n);
        let above = self.spiral.radius(self.b, psi0 + TAU * (n + 1.0));
        if (rho - below.0).abs() <= (rho - above.0).abs() {
            below
        } else {
            above
        }
    }

    pub fn gradient(&self, r: DVec2) -> DVec2 {
        let s = r - self.centre;
        let rho = s.length();
        if rho == 0.0 {
            return DVec2::ZERO;
        }
        let (r_hat, theta_hat) = (s / rho, s.perp() / rho);
        let (r_n, dr_n) = self.winding(rho, s.y.atan2(s.x));
        let d = rho - r_n;
        let (p, dp) = self.power(r_n);
        let (a, da) = self.winding_focusing(r_n);
        let grad_r_n = dr_n / rho * theta_hat;
        -(d * p + 3.0 * a * d * d) * (r_hat - grad_r_n)
            - (0.5 * d * d * dp + d * d * d * da) * grad_r_n
    }
}

/// `phase = { type = "cylindrical-lens-spiral", spiral = "logarithmic", focal_length = f₁,
/// b = b, rotation_angle_deg = δ, alvarez_winding_focusing = false, centre = [u, v] }`
/// (`spiral`, `focal_length` and `b` required; δ = 0, no winding focusing and centre (0, 0)
/// when not given, as in Dr TIM's constructor without winding focusing).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CylindricalLensSpiralPhaseKeys {
    spiral: SpiralType,
    focal_length: NonZero,
    b: NonZero,
    rotation_angle_deg: Option<Finite>,
    alvarez_winding_focusing: Option<bool>,
    centre: Option<Vector2>,
}

impl CylindricalLensSpiralPhaseKeys {
    pub fn build(self) -> Result<Phase, String> {
        let alvarez_winding_focusing = self.alvarez_winding_focusing.unwrap_or(false);
        if alvarez_winding_focusing && self.spiral == SpiralType::Hyperbolic {
            return Err(
                "alvarez_winding_focusing = true: a hyperbolic spiral has no winding \
                 focusing (Dr TIM's is for Archimedean and logarithmic spirals)"
                    .to_string(),
            );
        }
        Ok(Phase::CylindricalLensSpiral(CylindricalLensSpiralPhase {
            spiral: self.spiral,
            focal_length: self.focal_length.0,
            b: self.b.0,
            rotation: self.rotation_angle_deg.map_or(0.0, |a| a.0).to_radians(),
            alvarez_winding_focusing,
            centre: self.centre.map_or(DVec2::ZERO, |c| c.0),
        }))
    }
}

#[cfg(test)]
mod tests {
    use std::f64::consts::PI;

    use super::*;

    /// Dr TIM's spiral centre lines, written out: r(ψ) for each type.
    fn centre_line(spiral: SpiralType, b: f64, psi: f64) -> f64 {
        match spiral {
            SpiralType::Archimedean => b * psi,
            SpiralType::Logarithmic => (b * psi).exp(),
            SpiralType::Hyperbolic => -1.0 / (b * psi),
        }
    }

    /// Dr TIM's focal length of the winding at ψ (its `calculateF`): f₁/r(ψ) (Archimedean),
    /// f₁ (logarithmic), f₁ r(ψ) (hyperbolic).
    fn focal_length(spiral: SpiralType, f1: f64, b: f64, psi: f64) -> f64 {
        match spiral {
            SpiralType::Archimedean => f1 / centre_line(spiral, b, psi),
            SpiralType::Logarithmic => f1,
            SpiralType::Hyperbolic => f1 * centre_line(spiral, b, psi),
        }
    }

    /// The windings at the point's angle θ (from atan2, in (−π, π]), by brute force over those
    /// that exist there, nearest along the radius first: their numbers n and centre-line radii
    /// r(θ + δ + 2πn).
    fn windings(p: &CylindricalLensSpiralPhase, r: DVec2) -> Vec<(f64, f64)> {
        let s = r - p.centre;
        let theta = s.y.atan2(s.x);
        let mut all: Vec<(f64, f64)> = (-300..300)
            .map(|n| {
                let psi = theta + p.rotation + TAU * n as f64;
                (n as f64, centre_line(p.spiral, p.b, psi))
            })
            .filter(|(_, r_n)| r_n.is_finite() && *r_n > 0.0)
            .collect();
        let rho = s.length();
        all.sort_by(|a, b| (rho - a.1).abs().total_cmp(&(rho - b.1).abs()));
        all
    }

    /// The phase of winding n as a function of position, written with Dr TIM's focal length:
    /// −d²/(2f(ψ)) plus, with winding focusing, −d³/(3f₁) (Archimedean) or −d³/(6f₁r_n)
    /// (logarithmic), where ψ = θ + δ + 2πn, r_n = r(ψ) and d = ρ − r_n.
    fn phase(p: &CylindricalLensSpiralPhase, n: f64, r: DVec2) -> f64 {
        let s = r - p.centre;
        let psi = s.y.atan2(s.x) + p.rotation + TAU * n;
        let r_n = centre_line(p.spiral, p.b, psi);
        let d = s.length() - r_n;
        let f = focal_length(p.spiral, p.focal_length, p.b, psi);
        let cubic = match (p.alvarez_winding_focusing, p.spiral) {
            (true, SpiralType::Archimedean) => d.powi(3) / (3.0 * p.focal_length),
            (true, SpiralType::Logarithmic) => d.powi(3) / (6.0 * p.focal_length * r_n),
            _ => 0.0,
        };
        -d * d / (2.0 * f) - cubic
    }

    fn spirals() -> Vec<CylindricalLensSpiralPhase> {
        let mut all = Vec::new();
        for (spiral, b, f1) in [
            (SpiralType::Archimedean, 0.02, 0.3),
            (SpiralType::Logarithmic, 0.05, -0.4),
            (SpiralType::Logarithmic, -0.03, 0.2),
            (SpiralType::Hyperbolic, 0.5, 0.25),
        ] {
            for alvarez in [false, true] {
                if alvarez && spiral == SpiralType::Hyperbolic {
                    continue;
                }
                all.push(CylindricalLensSpiralPhase {
                    spiral,
                    focal_length: f1,
                    b,
                    rotation: 0.4,
                    alvarez_winding_focusing: alvarez,
                    centre: DVec2::new(0.1, -0.05),
                });
            }
        }
        all
    }

    /// The kick is the gradient of the nearest winding's phase (central differences of the
    /// phase written out above, at points not within the step of a winding boundary or of the
    /// angle θ = ±π, where atan2 jumps).
    #[test]
    fn the_kick_is_the_gradient_of_the_nearest_windings_phase() {
        for p in spirals() {
            let h = 1e-7;
            let mut checked = 0;
            for k in 0..400 {
                let theta = -3.1 + 0.0155 * k as f64;
                let rho = 0.15 + 0.0021 * k as f64;
                let r = p.centre + rho * DVec2::from_angle(theta);
                let near = windings(&p, r);
                let gap = ((rho - near[1].1).abs() - (rho - near[0].1).abs()).abs();
                if gap < 1e-4 {
                    continue;
                }
                let n = near[0].0;
                let fd = DVec2::new(
                    phase(&p, n, r + DVec2::X * h) - phase(&p, n, r - DVec2::X * h),
                    phase(&p, n, r + DVec2::Y * h) - phase(&p, n, r - DVec2::Y * h),
                ) / (2.0 * h);
                let kick = p.gradient(r);
                assert!(
                    (kick - fd).length() < 1e-6 * (1.0 + fd.length()),
                    "{p:?} at ρ = {rho}, θ = {theta}: {kick} against {fd}"
                );
                checked += 1;
            }
            assert!(checked > 350, "{p:?}: {checked}");
        }
    }

    /// Dr TIM's local focal length as a function of the winding's angle ψ: a ray along the
    /// normal at radial distance d from the centre line gets the radial kick −d/f(ψ), with
    /// f(ψ) = f₁/r(ψ) (Archimedean: f₁ at r = 1), f₁ (logarithmic), f₁ r(ψ) (hyperbolic).
    #[test]
    fn each_windings_radial_focal_length_is_dr_tims() {
        for p in spirals()
            .into_iter()
            .filter(|p| !p.alvarez_winding_focusing)
        {
            for k in 0..60 {
                let theta = -3.0 + 0.1 * k as f64;
                // A winding that exists at θ (ψ < 0 on the hyperbolic spiral with b > 0).
                let turns = (k % 5) as f64 + 1.0;
                let turns = if p.spiral == SpiralType::Hyperbolic {
                    -turns
                } else {
                    turns
                };
                let psi = theta + p.rotation + TAU * turns;
                let r_n = centre_line(p.spiral, p.b, psi);
                let d = 1e-3 * r_n;
                let rho = r_n + d;
                let r = p.centre + rho * DVec2::from_angle(theta);
                let radial = p.gradient(r).dot(DVec2::from_angle(theta));
                let f = focal_length(p.spiral, p.focal_length, p.b, psi);
                assert!(
                    (radial + d / f).abs() < 1e-10 * (d / f).abs(),
                    "{:?}, ψ = {psi}: {radial} against {}",
                    p.spiral,
                    -d / f
                );
            }
        }
    }

    /// Dr TIM's spiral lens: two logarithmic spirals of focal lengths f and −f, the second
    /// rotated by δ, make a lens of focal length F = f/(bδ) (`SpiralLensVisualiser`'s
    /// `calculateF`). Where the two spirals' windings pair up (r₂ = r₁ e^{bδ}), a ray along
    /// the normal gets the radial kick (r₁ − r₂)/f = −r₁(e^{bδ} − 1)/f, which is −ρ/F to
    /// within the winding's half-width (r₁/ρ between 2/(1 + e^{2πb}) and 2e^{2πb}/(1 + e^{2πb}))
    /// and bδ/2; where they do not (a fraction δ/2π of the turn), r₂ = r₁ e^{b(δ − 2π)} and
    /// the kick points outwards.
    #[test]
    fn two_rotated_logarithmic_spirals_are_a_lens_of_focal_length_f_over_b_delta() {
        let (f, b, delta) = (0.1, 0.01, 30f64.to_radians());
        let one = CylindricalLensSpiralPhase {
            spiral: SpiralType::Logarithmic,
            focal_length: f,
            b,
            rotation: 0.0,
            alvarez_winding_focusing: false,
            centre: DVec2::ZERO,
        };
        let two = CylindricalLensSpiralPhase {
            focal_length: -f,
            rotation: delta,
            ..one
        };
        let big_f = f / (b * delta);
        let e = (TAU * b).exp();
        let (low, high) = (2.0 / (1.0 + e), 2.0 * e / (1.0 + e));
        let (mut paired, mut total) = (0, 0);
        for k in 0..2000 {
            let theta = -PI + TAU * (k as f64 + 0.5) / 2000.0;
            let rho = 0.2 + 0.8 * ((k * 7919) % 2000) as f64 / 2000.0;
            let r = rho * DVec2::from_angle(theta);
            let radial = (one.gradient(r) + two.gradient(r)).dot(DVec2::from_angle(theta));
            total += 1;
            if radial < 0.0 {
                paired += 1;
                let ratio = -radial * big_f / rho;
                let scale = (b * delta).exp_m1() / (b * delta);
                assert!(
                    ratio >= low * scale - 1e-12 && ratio <= high * scale + 1e-12,
                    "ρ = {rho}, θ = {theta}: {ratio}"
                );
            } else {
                let outwards = radial * f / rho;
                let scale = -(b * (delta - TAU)).exp_m1();
                assert!(
                    outwards >= low * scale * 0.99 && outwards <= high * scale * 1.01,
                    "ρ = {rho}, θ = {theta}: {outwards}"
                );
            }
        }
        let fraction = paired as f64 / total as f64;
        assert!((fraction - (1.0 - delta / TAU)).abs() < 0.02, "{fraction}");
    }
}
