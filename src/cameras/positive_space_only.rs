//! Dr TIM's `PositiveSpaceOnlyOrthographicCamera` (Courtial): an orthographic view down the
//! axis of a negative-space-wedge star that shows only the space the wedges leave, stretched
//! to fill the picture, as a top view in the higher-dimensional space whose cone the star
//! simulates would. With N wedges cutting out the deficit angle δ, the star's wedges are
//! centred on the azimuths k w (w = 2π/N, from wedge 0) and the space left between wedges k and
//! k + 1 is the sector of angle ℓ = (2π − δ)/N about the azimuth c = (k + ½) w. The pixel at
//! polar coordinates (r, φ) about the axis, φ in that gap's whole sector of w, is seen by the
//! orthographic ray from the point that the stretching method maps it to:
//!
//! - stretching the angle (Dr TIM's `STRETCH_ANGLE`): (r, c + (φ − c) ℓ/w);
//! - stretching the width (`STRETCH_WIDTH`): the component along the sector's centre line kept,
//!   the component across it scaled by tan(ℓ/2)/tan(w/2).

use std::f64::consts::TAU;

use serde::Deserialize;

/// How the space left between the wedges is stretched to fill the picture (Dr TIM's
/// `LeftoverSpaceStretchingMethodType`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Stretching {
    StretchAngle,
    StretchWidth,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PositiveSpaceOnly {
    /// δ, radians, in (0, 2π).
    pub deficit_angle: f64,
    /// N ≥ 1.
    pub number_of_negative_space_wedges: u32,
    pub stretching: Stretching,
}

impl PositiveSpaceOnly {
    /// The point (in the detector plane, about the star's axis, x towards wedge 0's centre)
    /// whose ray the pixel at (x, y) shows.
    pub fn remap(&self, x: f64, y: f64) -> (f64, f64) {
        let w = TAU / self.number_of_negative_space_wedges as f64;
        let left = (TAU - self.deficit_angle) / self.number_of_negative_space_wedges as f64;
        let phi = y.atan2(x);
        let centre = (phi / w).floor() * w + 0.5 * w;
        match self.stretching {
            Stretching::StretchAngle => {
                let r = x.hypot(y);
                let (sin, cos) = (centre + (phi - centre) * left / w).sin_cos();
                (r * cos, r * sin)
            }
            Stretching::StretchWidth => {
                let (sin, cos) = centre.sin_cos();
                let along = x * cos + y * sin;
                let across = (-x * sin + y * cos) * (0.5 * left).tan() / (0.5 * w).tan();
                (along * cos - across * sin, along * sin + across * cos)
            }
        }
    }
}

/// `positive_space_only = { ... }` of an orthographic camera, with the defaults of Dr TIM's
/// `EditableNegativeSpaceWedgeStar` (δ = 340°, N = 100) and of its trajectory plotter
/// (stretching the angle).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PositiveSpaceOnlyKeys {
    deficit_angle_deg: Option<crate::keys::Finite>,
    number_of_negative_space_wedges: Option<u32>,
    leftover_space_stretching_method: Option<Stretching>,
}

impl PositiveSpaceOnlyKeys {
    pub fn build(&self) -> Result<PositiveSpaceOnly, String> {
        let deficit = self.deficit_angle_deg.map_or(340.0, |d| d.0);
        if !(deficit > 0.0 && deficit < 360.0) {
            return Err(format!(
                "positive_space_only: deficit_angle_deg must be between 0 and 360, got {deficit}"
            ));
        }
        let n = self.number_of_negative_space_wedges.unwrap_or(100);
        if n == 0 || n > 5_000 {
            return Err(format!(
                "positive_space_only: number_of_negative_space_wedges = {n} must be from 1 to 5000"
            ));
        }
        Ok(PositiveSpaceOnly {
            deficit_angle: deficit.to_radians(),
            number_of_negative_space_wedges: n,
            stretching: self
                .leftover_space_stretching_method
                .unwrap_or(Stretching::StretchAngle),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The gap between wedges 0 and 1 of 4 wedges cutting out 240° is 30° wide about 45°: the
    /// pixel sector from 0° to 90° maps onto 30° to 60°, its edges onto the gap's edges, its
    /// centre line onto itself, by either method.
    #[test]
    fn each_sector_of_pixels_maps_onto_the_gap_about_its_centre() {
        for stretching in [Stretching::StretchAngle, Stretching::StretchWidth] {
            let camera = PositiveSpaceOnly {
                deficit_angle: 240f64.to_radians(),
                number_of_negative_space_wedges: 4,
                stretching,
            };
            let azimuth = |phi: f64| {
                let (s, c) = phi.to_radians().sin_cos();
                let (x, y) = camera.remap(2.0 * c, 2.0 * s);
                y.atan2(x).to_degrees()
            };
            assert!((azimuth(45.0) - 45.0).abs() < 1e-12);
            assert!((azimuth(1e-9) - 30.0).abs() < 1e-6, "{}", azimuth(1e-9));
            assert!((azimuth(90.0 - 1e-9) - 60.0).abs() < 1e-6);
            assert!((azimuth(135.0) - 135.0).abs() < 1e-12);
            for phi in [10.0, 20.0, 70.0] {
                let a = azimuth(phi);
                assert!(a > 30.0 && a < 60.0, "{phi} -> {a}");
            }
        }
        // Below azimuth 0 and with an odd number of wedges: 5 wedges cutting out 200° leave
        // gaps of 32° centred on 36° + 72° k; the pixel at −100° lies in the sector from −144°
        // to −72°, centred on −108°, and is stretched onto −108° + 8° × 32/72.
        let camera = PositiveSpaceOnly {
            deficit_angle: 200f64.to_radians(),
            number_of_negative_space_wedges: 5,
            stretching: Stretching::StretchAngle,
        };
        let (s, c) = (-100f64).to_radians().sin_cos();
        let (x, y) = camera.remap(c, s);
        let expected = -108.0 + 8.0 * 32.0 / 72.0;
        assert!((y.atan2(x).to_degrees() - expected).abs() < 1e-9);
        // Stretching the angle keeps the distance from the axis.
        let camera = PositiveSpaceOnly {
            deficit_angle: 240f64.to_radians(),
            number_of_negative_space_wedges: 4,
            stretching: Stretching::StretchAngle,
        };
        let (x, y) = camera.remap(0.3, 1.7);
        assert!((x.hypot(y) - 0.3f64.hypot(1.7)).abs() < 1e-12);
    }
}
