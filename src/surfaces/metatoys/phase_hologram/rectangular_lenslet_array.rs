//! A rectangular array of thin lenslets, Dr TIM's `PhaseHologramOfRectangularLensletArray`
//! (and `PhaseHologramOfRectangularLensletArrayParametrised`, the same array in the surface's
//! own coordinates, which is what timbre's phases always use).
//!
//! The lenslets are centred on the lattice points c + (i p_u, j p_v); each point (u, v) belongs
//! to the lenslet whose centre is nearest in u and in v (its cell, a p_u × p_v rectangle centred
//! on the lenslet), and gets that lenslet's paraxial lens phase (Dr TIM's, as in
//! `PhaseHologramOfLens`): φ = −|r − c_ij|²/(2f), kick −(r − c_ij)/f. A bundle along the normal
//! through one lenslet converges to that lenslet's own focal point, f behind its centre; at a
//! cell edge the kick jumps to the neighbour's.
//!
//! **Dr TIM**: its offsets (u_offset, v_offset) shift the cells, but its kick subtracts the
//! offset a second time, so for non-zero offsets each lenslet's optical centre lies an offset
//! away from the middle of its cell (the lens heights it draws, `lensHeight`, have the lenslet
//! in the middle). timbre centres every lenslet in its cell: Dr TIM's centre plus offset is
//! timbre's `centre`. Dr TIM can also simulate diffractive blur (`simulateDiffractiveBlur`, off
//! in `EditableRectangularLensletArray`): a random direction change drawn with `Math.random()`
//! from the far field of a single slit of the lenslet's width. timbre's holograms are geometrical
//! optics and have no wavelength, so they do not simulate it: a timbre render is Dr TIM's with
//! `simulateDiffractiveBlur = false`.

use glam::DVec2;
use serde::Deserialize;

use super::{Phase, QuadraticPhase};
use crate::keys::{Array, NonZero, Positive, Vector2};

/// Lenslets of focal length `focal_length` centred on `centre` + (i period.x, j period.y).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RectangularLensletArrayPhase {
    pub focal_length: f64,
    pub period: DVec2,
    pub centre: DVec2,
}

/// The point of the lattice `centre` + (i period.x, j period.y) whose cell holds `r`: the
/// nearest in u and in v (Dr TIM's `period·floor(u/period + 1/2)`, a point midway between two
/// going to the one above).
pub(super) fn nearest_lattice_point(r: DVec2, centre: DVec2, period: DVec2) -> DVec2 {
    centre + ((r - centre) / period + 0.5).floor() * period
}

impl RectangularLensletArrayPhase {
    pub fn gradient(&self, r: DVec2) -> DVec2 {
        QuadraticPhase {
            focal_length: self.focal_length,
            centre: nearest_lattice_point(r, self.centre, self.period),
        }
        .gradient(r)
    }
}

/// `phase = { type = "rectangular-lenslet-array", focal_length = f, period = [pu, pv],
/// centre = [u, v] }`, with `EditableRectangularLensletArray`'s defaults: f = 1, periods 0.1,
/// a lenslet centred on (0, 0).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RectangularLensletArrayPhaseKeys {
    focal_length: Option<NonZero>,
    period: Option<Array<Positive, 2>>,
    centre: Option<Vector2>,
}

impl RectangularLensletArrayPhaseKeys {
    pub fn build(self) -> Result<Phase, String> {
        Ok(Phase::RectangularLensletArray(
            RectangularLensletArrayPhase {
                focal_length: self.focal_length.map_or(1.0, |f| f.0),
                period: self
                    .period
                    .map_or(DVec2::splat(0.1), |Array([u, v])| DVec2::new(u.0, v.0)),
                centre: self.centre.map_or(DVec2::ZERO, |c| c.0),
            },
        ))
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;
    use crate::surfaces::metatoys::hologram_direction;

    /// A lenslet's phase, written out: φ = −|r − c|²/(2f) about the lenslet centre c (found
    /// here by rounding cell indices), differentiated by central differences away from the cell
    /// edges.
    #[test]
    fn the_kick_is_the_gradient_of_each_lenslets_phase() {
        let array = RectangularLensletArrayPhase {
            focal_length: -0.7,
            period: DVec2::new(0.1, 0.25),
            centre: DVec2::new(0.03, -0.02),
        };
        let phase = |r: DVec2| {
            let i = ((r.x - 0.03) / 0.1).round();
            let j = ((r.y + 0.02) / 0.25).round();
            let c = DVec2::new(0.03 + 0.1 * i, -0.02 + 0.25 * j);
            -(r - c).length_squared() / (2.0 * -0.7)
        };
        let h = 1e-6;
        let mut checked = 0;
        for k in 0..400 {
            let r = DVec2::new(-1.0 + 0.0173 * k as f64, 0.9 - 0.0091 * k as f64);
            let (fu, fv) = (((r.x - 0.03) / 0.1).fract(), ((r.y + 0.02) / 0.25).fract());
            let near_edge = |f: f64| (f.abs() - 0.5).abs() < 1e-3;
            if near_edge(fu) || near_edge(fv) {
                continue;
            }
            let fd = DVec2::new(
                phase(r + DVec2::X * h) - phase(r - DVec2::X * h),
                phase(r + DVec2::Y * h) - phase(r - DVec2::Y * h),
            ) / (2.0 * h);
            assert!((array.gradient(r) - fd).length() < 1e-8, "{r}");
            checked += 1;
        }
        assert!(checked > 350);
    }

    /// A parallel bundle along the normal through each lenslet converges to that lenslet's own
    /// focal point, f behind its centre: followed in straight lines from the hologram to the
    /// focal plane z = f, each ray arrives within the paraxial lens's spherical aberration
    /// (a ray at distance s from the axis of a thin lens with the kick −s/f crosses the focal
    /// plane at s − s/√(1 − s²/f²) ≈ −s³/(2f²) from the axis) of its lenslet's focus, and far
    /// from every other lenslet's.
    #[test]
    fn a_bundle_through_each_lenslet_meets_its_own_focus() {
        let f = 1.0;
        let array = RectangularLensletArrayPhase {
            focal_length: f,
            period: DVec2::new(0.1, 0.1),
            centre: DVec2::ZERO,
        };
        for (i, j) in [(0, 0), (1, 0), (-3, 2), (7, -5)] {
            let c = DVec2::new(0.1 * i as f64, 0.1 * j as f64);
            for (a, b) in [(0.0, 0.0), (0.049, 0.0), (-0.03, 0.045), (0.049, -0.049)] {
                let s = DVec2::new(a, b);
                let out = hologram_direction(DVec3::Z, array.gradient(c + s)).unwrap();
                // Straight on to the plane z = f.
                let at = c + s + DVec2::new(out.x, out.y) * f / out.z;
                let miss = (at - c).length();
                let bound = s.length().powi(3) / (f * f) + 1e-15;
                assert!(
                    miss <= bound,
                    "lenslet ({i}, {j}), s = {s}: {miss} > {bound}"
                );
            }
        }
        // Just across a cell edge the ray belongs to the neighbour and goes to its focus.
        let r = DVec2::new(0.051, 0.0);
        let out = hologram_direction(DVec3::Z, array.gradient(r)).unwrap();
        let at = r + DVec2::new(out.x, out.y) * f / out.z;
        assert!((at - DVec2::new(0.1, 0.0)).length() < 1e-3, "{at}");
    }
}
