//! The Snellen chart of Dr TIM's `SnellenChart` with its set letters ("Set Letters"): nine
//! rows of letters from 6/60 to 6/3, drawn in the shipped font.

use glam::DVec2;
use serde::Deserialize;

use super::{parts_pictures, two_parts};
use crate::geometry::Interaction;
use crate::keys::{Positive, Vector2};
use crate::math::Colour;
use crate::picture::PictureFile;
use crate::surfaces::text::{Line, font};
use crate::surfaces::{Coloured, Surface, SurfaceKeys};
use ab_glyph::Font;

/// Dr TIM's rows: the letters, and each row's letter size relative to the top row's (its
/// `calculateTextHeight`: 10, 6, 4, 2, 1.5, then (12 − row)/6, all over 10), i.e. Snellen
/// fractions 6/60, 6/36, 6/24, 6/12, 6/9, 6/6, 6/5, 6/4 and 6/3.
pub const ROWS: [(&str, f64); 9] = [
    ("Z", 1.0),
    ("LP", 0.6),
    ("EFL", 0.4),
    ("VREH", 0.2),
    ("HLDCK", 0.15),
    ("LPKFPC", 0.1),
    ("EPZNHDP", 5.0 / 60.0),
    ("ZCPFHRVR", 4.0 / 60.0),
    ("KPVNHFEZ", 3.0 / 60.0),
];

/// The top row's letter height as a fraction of the chart's height: Dr TIM's 87.3 mm on an
/// A3 sheet 420 mm high (6/60 at 6 m).
const TOP_LETTER: f64 = 87.3 / 420.0;

/// The width of the chart as a fraction of its height, Dr TIM's 1/1.4.
pub const WIDTH: f64 = 1.0 / 1.4;

#[derive(Debug, Clone, PartialEq)]
pub struct SnellenChart {
    pub lines: Vec<Line>,
    /// `surfaces[0]` on the letters, `surfaces[1]` elsewhere.
    pub surfaces: Box<[Surface; 2]>,
}

impl SnellenChart {
    /// The rows of a chart `height` high whose top left corner is at `corner` (u to the right,
    /// v up, as text), laid out as Dr TIM's `textCentre` does: row k's centre lies below the
    /// chart's top by the sum, over the rows down to it, of height/30 and half the heights of
    /// each row and the one above; each row centred across the chart's width, its letters
    /// (capitals, whose height is the row's letter size) two spaces apart.
    pub fn lines(height: f64, corner: DVec2) -> Vec<Line> {
        let font = font();
        let cap = font
            .outline(font.glyph_id('Z'))
            .map(|o| (o.bounds.max.y - o.bounds.min.y).abs() as f64)
            .expect("the shipped font has a Z");
        let (ascent, descent) = (
            font.ascent_unscaled() as f64,
            font.descent_unscaled() as f64,
        );
        let centre_u = corner.x + 0.5 * WIDTH * height;
        let (mut below_top, mut above) = (0.0, 0.0);
        ROWS.iter()
            .map(|&(letters, scale)| {
                let size = scale * TOP_LETTER * height;
                below_top += height / 30.0 + 0.5 * above + 0.5 * size;
                above = size;
                let baseline = corner.y - below_top - 0.5 * size;
                let spaced: String = letters.chars().flat_map(|c| [c, ' ', ' ']).collect();
                // The line's box reaches `descent` (negative) below the baseline and is
                // ascent − descent high, in the font's units, of which `cap` is a capital's.
                let mut line = Line::new(
                    spaced.trim_end(),
                    [0.0, baseline + descent / cap * size],
                    (ascent - descent) / cap * size,
                );
                line.corner[0] = centre_u - 0.5 * line.width();
                line
            })
            .collect()
    }

    /// The surface at the point the ray meets.
    pub fn surface_at(&self, at: &Interaction) -> &Surface {
        let uv = at.coordinates();
        let inked = self.lines.iter().any(|l| l.inked(uv.x, uv.y));
        &self.surfaces[usize::from(!inked)]
    }
}

/// `type = "snellen-chart"`: the chart `height` high (default 1; it is height/1.4 wide, as Dr
/// TIM's) with its top left corner at `corner` (default [0, 0]; u to the right, v up), letters
/// and paper `surfaces = [LETTERS, PAPER]` (default Dr TIM's matt black letters on shiny
/// white).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SnellenChartKeys {
    height: Option<Positive>,
    corner: Option<Vector2>,
    surfaces: Option<Box<[SurfaceKeys; 2]>>,
}

impl SnellenChartKeys {
    /// The picture files its surfaces name.
    pub fn pictures(&mut self) -> Vec<&mut PictureFile> {
        parts_pictures(&mut self.surfaces)
    }

    pub fn build(self) -> Result<Surface, String> {
        let height = self.height.map_or(1.0, |h| h.0);
        let corner = self.corner.map_or(DVec2::ZERO, |c| c.0);
        Ok(Surface::SnellenChart(SnellenChart {
            lines: SnellenChart::lines(height, corner),
            surfaces: two_parts(
                self.surfaces,
                [
                    Surface::Coloured(Coloured::matt(Colour::ZERO)),
                    Surface::Coloured(Coloured::shiny(Colour::ONE)),
                ],
                "Snellen chart",
            )?,
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The first and last inked v along the vertical line at u through `line`, sampled finely
    /// between v = 0 and −1.
    fn inked_extent(line: &Line, u: f64) -> Option<(f64, f64)> {
        let n = 40000;
        let vs: Vec<f64> = (0..n)
            .map(|k| -(k as f64) / n as f64)
            .filter(|&v| line.inked(u, v))
            .collect();
        Some((*vs.first()?, *vs.last()?))
    }

    /// Dr TIM's sizes on a chart 1 high: the top Z is 87.3/420 high with its top 1/30 below the
    /// chart's; the last row's K is 3/60 of that, its centre below the top by the sum of the
    /// nine gaps of 1/30 and of each row's height (half of the last); every row is centred
    /// across the 1/1.4 width.
    #[test]
    fn the_rows_have_dr_tims_sizes_and_places() {
        let lines = SnellenChart::lines(1.0, DVec2::ZERO);
        let top = 87.3 / 420.0;
        let z = &lines[0];
        // The Z's diagonal crosses its middle column; its top and bottom bars span it.
        let (zt, zb) = inked_extent(z, z.corner[0] + 0.5 * z.width()).unwrap();
        assert!((zt - -1.0 / 30.0).abs() < 1e-3, "Z's top {zt}");
        assert!((zt - zb - top).abs() < 1e-3, "Z's height {}", zt - zb);
        let k = &lines[8];
        let size = top * 3.0 / 60.0;
        // The K's stem (Arial's, so Liberation Sans's, from 0.075 to 0.165 em) at the left of
        // its line, whose height is 1.117 em.
        let em = k.height / 1.117;
        let (kt, kb) = inked_extent(k, k.corner[0] + 0.12 * em).unwrap();
        assert!((kt - kb - size).abs() < 2e-4, "K's height {}", kt - kb);
        let sizes: f64 = ROWS.iter().map(|(_, s)| s * top).sum();
        let centre = -(9.0 / 30.0 + sizes - 0.5 * size);
        assert!(
            (0.5 * (kt + kb) - centre).abs() < 2e-4,
            "K's centre {}",
            0.5 * (kt + kb)
        );
        for line in &lines {
            let middle = line.corner[0] + 0.5 * line.width();
            assert!((middle - 0.5 / 1.4).abs() < 1e-12, "each row centred");
        }
    }
}
