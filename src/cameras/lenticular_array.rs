//! Dr TIM's `LenticularArrayCamera` (Blair, Courtial): the picture to print behind an array of
//! cylindrical lenslets, each N pixels wide and of focal length f, so that through the array
//! each viewing direction sees its own view of the scene. Pixel column k of a lenslet
//! (0 ≤ k < N, from the left) lies x_k = (k + ½) p − N p/2 from the lenslet's axis (p the pixel
//! pitch); the lenslet shows it to an observer on the other side of its axis, who looks through
//! the print along the direction tilted towards the right by α_k = atan(x_k / f). So the column
//! records the orthographic view along cos α_k v̂ + sin α_k r̂ (v̂ the view direction, r̂ the
//! camera's right).

use serde::Deserialize;

use crate::keys::Positive;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LenticularArray {
    /// N, from 1.
    pub pixels_per_cylindrical_lens: u32,
    /// f, > 0.
    pub cylindrical_lenslet_focal_length: f64,
}

impl LenticularArray {
    /// (cos α, sin α) of the view direction of pixel column `column` (from the left, counting
    /// from 0) at pitch `pitch`.
    pub fn tilt(&self, column: i64, pitch: f64) -> (f64, f64) {
        let n = self.pixels_per_cylindrical_lens as i64;
        let k = column.rem_euclid(n) as f64;
        let x = (k + 0.5) * pitch - 0.5 * n as f64 * pitch;
        let alpha = x.atan2(self.cylindrical_lenslet_focal_length);
        (alpha.cos(), alpha.sin())
    }
}

/// `lenticular_array = { ... }` of an orthographic camera, with the values of Dr TIM's
/// `LenticularArrayCameraDemo` (it has no editable camera): 10 pixels per lenslet, focal length
/// 0.025.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LenticularArrayKeys {
    pixels_per_cylindrical_lens: Option<u32>,
    cylindrical_lenslet_focal_length: Option<Positive>,
}

impl LenticularArrayKeys {
    pub fn build(&self) -> Result<LenticularArray, String> {
        let n = self.pixels_per_cylindrical_lens.unwrap_or(10);
        if n == 0 || n > 100_000 {
            return Err(format!(
                "lenticular_array: pixels_per_cylindrical_lens = {n} must be from 1 to 100000"
            ));
        }
        Ok(LenticularArray {
            pixels_per_cylindrical_lens: n,
            cylindrical_lenslet_focal_length: self
                .cylindrical_lenslet_focal_length
                .map_or(0.025, |f| f.0),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Dr TIM's view directions for 4 pixels a lenslet at pitch 1 and f = 2: offsets −1.5,
    /// −0.5, 0.5, 1.5 from the axis, tilted by atan(offset/2), repeating lenslet after lenslet.
    #[test]
    fn each_column_of_a_lenslet_looks_along_its_own_tilt() {
        let array = LenticularArray {
            pixels_per_cylindrical_lens: 4,
            cylindrical_lenslet_focal_length: 2.0,
        };
        for (column, offset) in [
            (0, -1.5),
            (1, -0.5),
            (2, 0.5),
            (3, 1.5),
            (4, -1.5),
            (-1, 1.5),
        ] {
            let (c, s) = array.tilt(column, 1.0);
            let alpha = f64::atan(offset / 2.0);
            assert!((c - alpha.cos()).abs() < 1e-15 && (s - alpha.sin()).abs() < 1e-15);
        }
    }
}
