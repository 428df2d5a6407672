//! A sparse rectangular lenslet array, Dr TIM's `PhaseHologramOfSparseRectangularLensletArray`
//! (the surface of its `SparseRectangularLensletArray`): of the lenslets of a rectangular array
//! (periods p_u, p_v, one centred on c), only every n_u-th along u and n_v-th along v is there.
//! The lenslets present are centred on c + (i n_u p_u, j n_v p_v), each filling its
//! p_u × p_v aperture with the paraxial lens phase φ = −|r − c_ij|²/(2f) (the lenslet array's
//! lenses); between them there is nothing to change a ray's direction: no kick.
//!
//! **Dr TIM**: the space between the lenslets is a hole of the scene object
//! (`HoleySurface`), which rays cross without the transmission coefficient; here it is part of
//! the hologram with no phase, so rays cross it undeviated but are multiplied by the
//! surface's transmission coefficient (1 unless given). Dr TIM's `SparseRectangularLensletArray`
//! simulates diffractive blur by default (a random single-slit direction change); timbre does
//! not (see the rectangular lenslet array), and its coloured lenses are a layer of cyan glass
//! that this phase does not add.

use std::num::NonZeroU32;

use glam::DVec2;
use serde::Deserialize;

use super::rectangular_lenslet_array::nearest_lattice_point;
use super::{Phase, QuadraticPhase};
use crate::keys::{Array, NonZero, Positive, Vector2};

/// Lenslets of focal length `focal_length` and aperture `period` at `centre` +
/// (i every.x period.x, j every.y period.y); no phase elsewhere.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SparseRectangularLensletArrayPhase {
    pub focal_length: f64,
    pub period: DVec2,
    pub centre: DVec2,
    /// (n_u, n_v), whole numbers of at least 1.
    pub every: DVec2,
}

impl SparseRectangularLensletArrayPhase {
    pub fn gradient(&self, r: DVec2) -> DVec2 {
        let lenslet = nearest_lattice_point(r, self.centre, self.every * self.period);
        let s = (r - lenslet).abs();
        if s.x > 0.5 * self.period.x || s.y > 0.5 * self.period.y {
            return DVec2::ZERO;
        }
        QuadraticPhase {
            focal_length: self.focal_length,
            centre: lenslet,
        }
        .gradient(r)
    }
}

/// `phase = { type = "sparse-rectangular-lenslet-array", focal_length = f, period = [pu, pv],
/// centre = [u, v], every = [nu, nv] }`, with `SparseRectangularLensletArray`'s defaults: f = 1,
/// periods 0.1, a lenslet centred on (0, 0), every lenslet there (`every = [1, 1]`).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SparseRectangularLensletArrayPhaseKeys {
    focal_length: Option<NonZero>,
    period: Option<Array<Positive, 2>>,
    centre: Option<Vector2>,
    every: Option<Array<NonZeroU32, 2>>,
}

impl SparseRectangularLensletArrayPhaseKeys {
    pub fn build(self) -> Result<Phase, String> {
        Ok(Phase::SparseRectangularLensletArray(
            SparseRectangularLensletArrayPhase {
                focal_length: self.focal_length.map_or(1.0, |f| f.0),
                period: self
                    .period
                    .map_or(DVec2::splat(0.1), |Array([u, v])| DVec2::new(u.0, v.0)),
                centre: self.centre.map_or(DVec2::ZERO, |c| c.0),
                every: self.every.map_or(DVec2::ONE, |Array([u, v])| {
                    DVec2::new(f64::from(u.get()), f64::from(v.get()))
                }),
            },
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::surfaces::metatoys::phase_hologram::RectangularLensletArrayPhase;

    /// Every third lenslet along u and every second along v of a lenslet array is there, with
    /// the full array's kick; a point of a missing lenslet's cell gets none.
    #[test]
    fn only_every_nth_lenslet_is_there() {
        let (f, period, centre) = (0.8, DVec2::new(0.1, 0.2), DVec2::new(0.02, 0.05));
        let sparse = SparseRectangularLensletArrayPhase {
            focal_length: f,
            period,
            centre,
            every: DVec2::new(3.0, 2.0),
        };
        let full = RectangularLensletArrayPhase {
            focal_length: f,
            period,
            centre,
        };
        let mut present = 0;
        for i in -7..=7 {
            for j in -5..=5 {
                let cell = centre + DVec2::new(0.1 * i as f64, 0.2 * j as f64);
                for s in [
                    DVec2::ZERO,
                    DVec2::new(0.04, -0.07),
                    DVec2::new(-0.045, 0.09),
                ] {
                    let r = cell + s;
                    // The lenslet (i, j) is there if i is a multiple of 3 and j of 2.
                    if i % 3 == 0 && j % 2 == 0 {
                        assert_eq!(sparse.gradient(r), full.gradient(r), "({i}, {j}) {s}");
                        assert!((full.gradient(r) + s / f).length() < 1e-15);
                        present += 1;
                    } else {
                        assert_eq!(sparse.gradient(r), DVec2::ZERO, "({i}, {j}) {s}");
                    }
                }
            }
        }
        assert_eq!(present, 5 * 5 * 3);
    }

    /// The phase written out: −|r − c|²/(2f) within a present lenslet's aperture (lattice
    /// indices by rounding; `lenslet` gives the centre and the larger of |Δu|/p_u and
    /// |Δv|/p_v, at most 1/2 inside), 0 elsewhere; central differences away from the aperture
    /// edges.
    #[test]
    fn the_kick_is_the_gradient_of_the_sparse_phase() {
        let sparse = SparseRectangularLensletArrayPhase {
            focal_length: -0.6,
            period: DVec2::new(0.1, 0.15),
            centre: DVec2::new(0.01, 0.02),
            every: DVec2::new(2.0, 3.0),
        };
        let spacing = DVec2::new(0.2, 0.45);
        let lenslet = |r: DVec2| {
            let c =
                DVec2::new(0.01, 0.02) + ((r - DVec2::new(0.01, 0.02)) / spacing).round() * spacing;
            let s = (r - c) / DVec2::new(0.1, 0.15);
            (c, s.x.abs().max(s.y.abs()))
        };
        let phase = |r: DVec2| {
            let (c, half) = lenslet(r);
            if half > 0.5 {
                0.0
            } else {
                -(r - c).length_squared() / (2.0 * -0.6)
            }
        };
        let h = 1e-6;
        let mut inside = 0;
        for k in 0..500 {
            let r = DVec2::new(-1.0 + 0.00411 * k as f64, 0.7 - 0.00297 * k as f64);
            if (lenslet(r).1 - 0.5).abs() < 1e-3 {
                continue;
            }
            let fd = DVec2::new(
                phase(r + DVec2::X * h) - phase(r - DVec2::X * h),
                phase(r + DVec2::Y * h) - phase(r - DVec2::Y * h),
            ) / (2.0 * h);
            assert!((sparse.gradient(r) - fd).length() < 1e-8, "{r}");
            inside += usize::from(lenslet(r).1 < 0.5);
        }
        assert!(inside > 50 && inside < 300, "{inside}");
    }
}
