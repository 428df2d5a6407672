//! A rectangular array of Alvarez–Lohmann lens parts, Dr TIM's
//! `PhaseHologramOfRectangularAlvarezLensPartArray`: the cells of a rectangular lattice (periods
//! p_u, p_v, one cell centred on c) each hold a [Lohmann lens part](super::LohmannLensPartPhase)
//! with û along the surface's u, whose principal point is the cell's centre plus an offset o:
//! φ = a (u³/6 + u v²/2) with (u, v) = r − (c_ij + o). Two such arrays, +a and −a, with offsets
//! ±s (and no gap between them) are an array of lenslets of power 2 a s_u (offsets along u;
//! offsets along v make them astigmatic), the adaptive lenslet arrays of Dr TIM's
//! `AlvarezTelescopeArrayExplorer`.
//!
//! **Dr TIM**: its optional diffractive blur (a random single-slit direction change) is not
//! simulated (see the rectangular lenslet array).

use glam::DVec2;
use serde::Deserialize;

use super::rectangular_lenslet_array::nearest_lattice_point;
use super::{LohmannLensPartPhase, Phase};
use crate::keys::{Array, Finite, Positive, Vector2};

/// Lohmann lens parts of `power_per_offset` in the cells of the lattice `centre` +
/// (i period.x, j period.y), each centred on its cell's centre plus `offset`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RectangularAlvarezLensPartArrayPhase {
    pub power_per_offset: f64,
    pub period: DVec2,
    pub centre: DVec2,
    pub offset: DVec2,
}

impl RectangularAlvarezLensPartArrayPhase {
    pub fn gradient(&self, r: DVec2) -> DVec2 {
        LohmannLensPartPhase {
            power_per_offset: self.power_per_offset,
            centre: nearest_lattice_point(r, self.centre, self.period) + self.offset,
            u_angle: 0.0,
        }
        .gradient(r)
    }
}

/// `phase = { type = "rectangular-alvarez-lens-part-array", power_per_offset = a,
/// period = [pu, pv], centre = [u, v], offset = [ou, ov] }` (a and the periods required; a
/// cell centred on (0, 0) and no offset when not given).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RectangularAlvarezLensPartArrayPhaseKeys {
    power_per_offset: Finite,
    period: Array<Positive, 2>,
    centre: Option<Vector2>,
    offset: Option<Vector2>,
}

impl RectangularAlvarezLensPartArrayPhaseKeys {
    pub fn build(self) -> Result<Phase, String> {
        let Array([pu, pv]) = self.period;
        Ok(Phase::RectangularAlvarezLensPartArray(
            RectangularAlvarezLensPartArrayPhase {
                power_per_offset: self.power_per_offset.0,
                period: DVec2::new(pu.0, pv.0),
                centre: self.centre.map_or(DVec2::ZERO, |c| c.0),
                offset: self.offset.map_or(DVec2::ZERO, |o| o.0),
            },
        ))
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;
    use crate::surfaces::metatoys::hologram_direction;

    /// Two arrays, +a with offset (+s, 0) and −a with offset (−s, 0), without a gap: in every
    /// cell a lenslet of power 2as centred on the cell (the Alvarez lens, derived in
    /// `lohmann_lens_part`'s test), so a bundle along the normal through each cell meets the
    /// cell's own focal point, 1/(2as) behind its centre (the kick is −(r − c_ij)·2as exactly,
    /// so the ray at distance ρ crosses the cell's axis at f √(1 − ρ²/f²)).
    #[test]
    fn two_offset_arrays_are_a_lenslet_array_of_power_2as() {
        let (a, s, period, centre) = (40.0, 0.01, DVec2::new(0.1, 0.15), DVec2::new(0.5, 0.2));
        let plus = RectangularAlvarezLensPartArrayPhase {
            power_per_offset: a,
            period,
            centre,
            offset: DVec2::new(s, 0.0),
        };
        let minus = RectangularAlvarezLensPartArrayPhase {
            power_per_offset: -a,
            offset: DVec2::new(-s, 0.0),
            ..plus
        };
        let f = 1.0 / (2.0 * a * s);
        for (i, j) in [(0, 0), (3, -1), (-5, 4)] {
            let cell = centre + DVec2::new(i as f64, j as f64) * period;
            for d in [
                DVec2::new(0.04, 0.0),
                DVec2::new(-0.02, 0.07),
                DVec2::new(0.049, -0.074),
            ] {
                let kick = plus.gradient(cell + d) + minus.gradient(cell + d);
                assert!((kick + d / f).length() < 1e-12, "({i}, {j}) {d}: {kick}");
                let out = hologram_direction(DVec3::Z, kick).unwrap();
                let rho = d.length();
                let z = rho / DVec2::new(out.x, out.y).length() * out.z;
                assert!((z - f * (1.0 - rho * rho / (f * f)).sqrt()).abs() < 1e-9);
            }
        }
    }

    /// One array's phase written out: a (u³/6 + u v²/2) about its cell's centre (indices by
    /// rounding) plus the offset; central differences away from the cell edges.
    #[test]
    fn the_kick_is_the_gradient_of_each_cells_cubic_phase() {
        let (a, period, centre, offset) = (
            -7.0,
            DVec2::new(0.2, 0.1),
            DVec2::new(0.03, -0.04),
            DVec2::new(0.02, -0.01),
        );
        let array = RectangularAlvarezLensPartArrayPhase {
            power_per_offset: a,
            period,
            centre,
            offset,
        };
        let phase = |r: DVec2| {
            let cell = centre + ((r - centre) / period).round() * period;
            let s = r - cell - offset;
            a * (s.x.powi(3) / 6.0 + s.x * s.y * s.y / 2.0)
        };
        let h = 1e-6;
        for k in 0..300 {
            let r = DVec2::new(-0.9 + 0.0061 * k as f64, 0.8 - 0.0053 * k as f64);
            let t = (r - centre) / period;
            if (t - t.round()).abs().max_element() > 0.499 {
                continue;
            }
            let fd = DVec2::new(
                phase(r + DVec2::X * h) - phase(r - DVec2::X * h),
                phase(r + DVec2::Y * h) - phase(r - DVec2::Y * h),
            ) / (2.0 * h);
            assert!((array.gradient(r) - fd).length() < 1e-8, "{r}");
        }
    }
}
