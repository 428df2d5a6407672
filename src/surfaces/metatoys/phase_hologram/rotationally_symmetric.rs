//! A rotationally symmetric phase, Dr TIM's `RotationallySymmetricPhaseHologram`: about a
//! centre, at distance r and angle ϑ (from u towards v), the azimuthal gradient
//! (1/r) ∂φ/∂ϑ = b r^(c−1) (Dr TIM's ∂Φ/∂ϑ = k b r^c) and the radial gradient ∂φ/∂r = s r^t.
//! Dr TIM's special cases: b = 0 and t = 1 is a lens, of focal length −1/s (Dr TIM's comment
//! says 1/s, but its kick s r r̂ bends rays away from the centre for s > 0, where its
//! `PhaseHologramOfLens` of focal length f kicks by −r/f); s = 0 and c = 0 a charge-b vortex
//! (φ = b ϑ); s = 0 and c = 2 an idealised moiré rotator.
//!
//! For b c ≠ 0 the azimuthal gradient is no phase's gradient (its curl, b c r^(c−2), does not
//! vanish): a real hologram needs a radial gradient with it. With `simulate_honestly` (Dr
//! TIM's default) the hologram is cut into `segments` sectors, in each of which the phase is
//! b r^c Δϑ (Δϑ the angle from the sector's bisector; the phase jumps where sectors meet),
//! which adds the radial gradient b c r^(c−1) Δϑ. Dr TIM adds b r^(c−1) Δϑ, without the
//! factor c, which is the sector phase's gradient only for c = 1 (for the moiré rotator's
//! c = 2 half of it); here it is the sector phase's.

use std::f64::consts::TAU;
use std::num::NonZeroU32;

use glam::DVec2;
use serde::Deserialize;

use super::Phase;
use crate::keys::{Finite, Vector2};

/// Dr TIM's gradients about a centre: b r^(c−1) along ϑ̂ and s r^t along r̂ (also those of
/// the pixels of an `AzimuthalPixelatedFresnelWedge`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AzimuthalRadial {
    /// b and c.
    pub azimuthal_coefficient: f64,
    pub azimuthal_exponent: f64,
    /// s and t.
    pub radial_coefficient: f64,
    pub radial_exponent: f64,
}

impl AzimuthalRadial {
    /// From the keys b, c, s and t, each 0 when not given (Dr TIM's defaults).
    pub fn from_keys(
        b: Option<Finite>,
        c: Option<Finite>,
        s: Option<Finite>,
        t: Option<Finite>,
    ) -> AzimuthalRadial {
        let or_zero = |x: Option<Finite>| x.map_or(0.0, |x| x.0);
        AzimuthalRadial {
            azimuthal_coefficient: or_zero(b),
            azimuthal_exponent: or_zero(c),
            radial_coefficient: or_zero(s),
            radial_exponent: or_zero(t),
        }
    }

    /// b r^(c−1) ϑ̂ + s r^t r̂ at `r` from the centre (ϑ̂ is r̂ turned by 90° from u towards
    /// v); zero at the centre, where r̂ has no direction. A part whose coefficient is 0 is left
    /// out (as in Dr TIM), so that no 0 · ∞ appears near the centre.
    pub fn kick(&self, r: DVec2) -> DVec2 {
        let length = r.length();
        if length == 0.0 {
            return DVec2::ZERO;
        }
        let part = |k: f64, e: f64| if k == 0.0 { 0.0 } else { k * length.powf(e) };
        let radial = r / length;
        part(self.azimuthal_coefficient, self.azimuthal_exponent - 1.0) * radial.perp()
            + part(self.radial_coefficient, self.radial_exponent) * radial
    }
}

/// Sectors of the honestly simulated hologram: how many, and the direction of the first's
/// bisector (radians from u towards v).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sectors {
    pub count: u32,
    pub direction: f64,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RotationallySymmetricPhase {
    pub centre: DVec2,
    pub gradients: AzimuthalRadial,
    /// `None`: the azimuthal gradient alone, not simulated honestly.
    pub sectors: Option<Sectors>,
}

impl RotationallySymmetricPhase {
    pub fn gradient(&self, r: DVec2) -> DVec2 {
        let r = r - self.centre;
        let kick = self.gradients.kick(r);
        let (b, c) = (
            self.gradients.azimuthal_coefficient,
            self.gradients.azimuthal_exponent,
        );
        match self.sectors {
            Some(sectors) if b * c != 0.0 && r != DVec2::ZERO => {
                let width = TAU / f64::from(sectors.count);
                let turned = DVec2::from_angle(-sectors.direction).rotate(r);
                let angle = turned.y.atan2(turned.x);
                let from_bisector = angle - width * (angle / width + 0.5).floor();
                let length = r.length();
                kick + b * c * length.powf(c - 1.0) * from_bisector * (r / length)
            }
            _ => kick,
        }
    }
}

/// `phase = { type = "rotationally-symmetric", centre = [u0, v0], azimuthal_coefficient = b,
/// azimuthal_exponent = c, radial_coefficient = s, radial_exponent = t, simulate_honestly =
/// true, segments = n, segment_direction_deg = ψ }`. Defaults, Dr TIM's: b = c = s = t = 0,
/// honestly in 8 segments, the first's bisector along u (Dr TIM's d₀ = x̂); centre (0, 0).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RotationallySymmetricPhaseKeys {
    centre: Option<Vector2>,
    azimuthal_coefficient: Option<Finite>,
    azimuthal_exponent: Option<Finite>,
    radial_coefficient: Option<Finite>,
    radial_exponent: Option<Finite>,
    simulate_honestly: Option<bool>,
    segments: Option<NonZeroU32>,
    segment_direction_deg: Option<Finite>,
}

impl RotationallySymmetricPhaseKeys {
    pub fn build(self) -> Result<Phase, String> {
        let sectors = Sectors {
            count: self.segments.map_or(8, NonZeroU32::get),
            direction: self.segment_direction_deg.map_or(0.0, |a| a.0).to_radians(),
        };
        Ok(Phase::RotationallySymmetric(RotationallySymmetricPhase {
            centre: self.centre.map_or(DVec2::ZERO, |c| c.0),
            gradients: AzimuthalRadial::from_keys(
                self.azimuthal_coefficient,
                self.azimuthal_exponent,
                self.radial_coefficient,
                self.radial_exponent,
            ),
            sectors: self.simulate_honestly.unwrap_or(true).then_some(sectors),
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn phase(
        b: f64,
        c: f64,
        s: f64,
        t: f64,
        sectors: Option<Sectors>,
    ) -> RotationallySymmetricPhase {
        RotationallySymmetricPhase {
            centre: DVec2::new(0.4, -0.3),
            gradients: AzimuthalRadial {
                azimuthal_coefficient: b,
                azimuthal_exponent: c,
                radial_coefficient: s,
                radial_exponent: t,
            },
            sectors,
        }
    }

    /// The gradient at `r` by central differences of `phi`.
    fn numeric(phi: impl Fn(DVec2) -> f64, r: DVec2) -> DVec2 {
        let h = 1e-6;
        DVec2::new(
            phi(r + h * DVec2::X) - phi(r - h * DVec2::X),
            phi(r + h * DVec2::Y) - phi(r - h * DVec2::Y),
        ) / (2.0 * h)
    }

    /// Points round the centre at radii 0.3 to 2.4, in `n` directions starting at `from`
    /// (radians).
    fn around(centre: DVec2, n: usize, from: f64) -> impl Iterator<Item = DVec2> {
        (0..n).flat_map(move |k| {
            let angle = from + TAU * k as f64 / n as f64;
            (1..=8).map(move |i| centre + 0.3 * i as f64 * DVec2::from_angle(angle))
        })
    }

    /// Where the gradients are a phase's, they are its derivatives: a charge-b vortex
    /// φ = b ϑ (c = 0) with the radial phase s r^(t+1)/(t+1), written out here; and in each
    /// sector of the honest simulation, the sector phase b r^c Δϑ (Δϑ from the sector's
    /// bisector, 6 sectors, the first's at 20°) plus the radial phase.
    #[test]
    fn the_gradients_are_the_derivatives_of_the_vortex_and_the_sector_phases() {
        let vortex = phase(3.0, 0.0, 0.2, 1.5, None);
        let centre = vortex.centre;
        let polar = |r: DVec2| {
            let d = r - centre;
            (d.length(), d.y.atan2(d.x))
        };
        let radial = |r: DVec2| 0.2 * polar(r).0.powf(2.5) / 2.5;
        // Away from the vortex's cut at ϑ = ±π.
        for r in around(centre, 12, -2.9) {
            let phi = |r: DVec2| 3.0 * polar(r).1 + radial(r);
            let (g, n) = (vortex.gradient(r), numeric(phi, r));
            assert!(g.distance(n) < 1e-7, "at {r}: {g} against {n}");
        }
        let (b, c, width, bisector) = (0.3, 2.0, TAU / 6.0, 20f64.to_radians());
        let honest = phase(
            b,
            c,
            0.2,
            1.5,
            Some(Sectors {
                count: 6,
                direction: bisector,
            }),
        );
        // Within 0.4 of a sector's half width from each bisector: inside one sector.
        for k in 0..6 {
            for offset in [-0.4, 0.0, 0.4] {
                let start = bisector + width * (k as f64 + offset * 0.5);
                for r in around(centre, 1, start) {
                    let phi = |r: DVec2| {
                        let (length, angle) = polar(r);
                        let from_bisector =
                            (angle - bisector - width * k as f64 + TAU + 0.5 * width)
                                .rem_euclid(TAU)
                                - 0.5 * width;
                        b * length.powf(c) * from_bisector + radial(r)
                    };
                    let (g, n) = (honest.gradient(r), numeric(phi, r));
                    assert!(g.distance(n) < 1e-6, "at {r}: {g} against {n}");
                }
            }
        }
    }

    /// Without the honest simulation the azimuthal gradient b r^(c−1) ϑ̂ of the moiré rotator
    /// (c = 2) is no phase's: its circulation round a circle of radius ρ, 2π b ρ^c (by the
    /// trapezium rule here), does not vanish.
    #[test]
    fn the_bare_azimuthal_gradient_circulates() {
        let (b, rho) = (0.3, 1.5);
        let rotator = phase(b, 2.0, 0.0, 0.0, None);
        let n = 720;
        let circulation: f64 = (0..n)
            .map(|k| {
                let angle = TAU * k as f64 / n as f64;
                let step = rho * TAU / n as f64 * DVec2::from_angle(angle).perp();
                rotator
                    .gradient(rotator.centre + rho * DVec2::from_angle(angle))
                    .dot(step)
            })
            .sum();
        assert!(
            (circulation - TAU * b * rho * rho).abs() < 1e-9,
            "{circulation}"
        );
    }

    /// b = 0, t = 1 and s = −1/f is a lens of focal length f: a ray along the normal at a
    /// small distance r from the centre leaves towards the axis point at distance f.
    #[test]
    fn a_radial_gradient_linear_in_r_is_a_lens_of_focal_length_minus_one_over_s() {
        let f = 2.5;
        let lens = phase(0.0, 0.0, -1.0 / f, 1.0, None);
        for angle in [0.0, 1.0, 2.5, 4.0] {
            let r = 1e-4 * DVec2::from_angle(angle);
            let t = lens.gradient(lens.centre + r);
            // Tangential t, normal (1 − |t|²)^½: the axis is reached after a normal distance
            // |r| (1 − |t|²)^½ / |t| along −r̂.
            assert!((t.normalize() + r.normalize()).length() < 1e-12);
            let z = r.length() * (1.0 - t.length_squared()).sqrt() / t.length();
            assert!((z - f).abs() < 1e-8 * f, "{z}");
        }
    }
}
