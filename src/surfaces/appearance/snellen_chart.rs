//! The Snellen chart (Dr TIM's `SnellenChart`, "Set Letters"): the classic rows of letters,
//! each row's letters as high as the row's Snellen fraction says, drawn in the shipped font.

use glam::DVec2;
use serde::Deserialize;

use super::{greys, parts_pictures, two_parts};
use crate::geometry::Interaction;
use crate::keys::{Positive, Vector2};
use crate::picture::PictureFile;
use crate::surfaces::text::{Line, font};
use crate::surfaces::{Surface, SurfaceKeys};
use ab_glyph::Font;

/// The classic chart's rows: the denominator of the Snellen fraction 20/N (feet; 6/(0.3 N) in
/// metres) and the row's letters. A row of 20/N is read by an eye of that acuity, whose
/// letters subtend 5 arcminutes × N/20 at the testing distance.
pub const ROWS: [(u32, &str); 8] = [
    (200, "E"),
    (100, "FP"),
    (70, "TOZ"),
    (50, "LPED"),
    (40, "PECFD"),
    (30, "EDFCZP"),
    (25, "FELOPZD"),
    (20, "DEFPOTEC"),
];

/// The gap above each row, and below the last, in letter heights of that row.
const GAP: f64 = 0.5;

#[derive(Debug, Clone, PartialEq)]
pub struct SnellenChart {
    pub lines: Vec<Line>,
    /// `surfaces[0]` on the letters, `surfaces[1]` elsewhere.
    pub surfaces: Box<[Surface; 2]>,
}

impl SnellenChart {
    /// The rows of a chart `height` high (and, as Dr TIM's, height/√2 wide) whose top left
    /// corner is at `corner` (u to the right, v up, as text), each row centred.
    pub fn lines(height: f64, corner: DVec2) -> Vec<Line> {
        let font = font();
        let cap = font
            .outline(font.glyph_id('E'))
            .map(|o| (o.bounds.max.y - o.bounds.min.y).abs() as f64)
            .expect("the shipped font has an E");
        let (ascent, descent) = (
            font.ascent_unscaled() as f64,
            font.descent_unscaled() as f64,
        );
        // Letter heights in units of the 20/20 row's, and the chart's height in those units.
        let sizes = ROWS.map(|(n, _)| n as f64 / 20.0);
        let total: f64 = sizes.iter().map(|h| (1.0 + GAP) * h).sum::<f64>() + GAP * sizes[7];
        let scale = height / total;
        let centre = corner.x + 0.5 * height / 2f64.sqrt();
        let mut top = corner.y;
        ROWS.iter()
            .zip(sizes)
            .map(|(&(_, letters), size)| {
                let h = size * scale;
                let baseline = top - (1.0 + GAP) * h;
                top = baseline;
                // The line's box reaches `descent` (negative) below the baseline, and is
                // ascent − descent high, in the font's units, of which `cap` is a letter's.
                let spaced: String = letters.chars().flat_map(|c| [c, ' ']).collect();
                let mut line = Line::new(
                    spaced.trim_end(),
                    [0.0, baseline + descent / cap * h],
                    (ascent - descent) / cap * h,
                );
                line.corner[0] = centre - 0.5 * line.width();
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

/// `type = "snellen-chart"`: the chart `height` high (default 1; it is height/√2 wide, as Dr
/// TIM's) with its top left corner at `corner` (default [0, 0]; u to the right, v up), letters
/// and paper `surfaces = [LETTERS, PAPER]` (default matt black and matt white).
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
            surfaces: two_parts(self.surfaces, greys([0.0, 1.0], false), "Snellen chart")?,
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The inked extent in v of a vertical line at u through `lines`, from v = 0 down to
    /// −height: the first and last inked v, sampled finely.
    fn inked_extent(lines: &[Line], u: f64, from: f64, to: f64) -> Option<(f64, f64)> {
        let n = 20000;
        let vs: Vec<f64> = (0..n)
            .map(|k| from + (to - from) * k as f64 / n as f64)
            .filter(|&v| lines.iter().any(|l| l.inked(u, v)))
            .collect();
        Some((*vs.first()?, *vs.last()?))
    }

    /// The top row's E (20/200) is ten times as high as the letters of the 20/20 row, and the
    /// chart's rows lie within its height: with the rows' heights 200/20, ..., 20/20 times h
    /// and gaps of half a row, h = 1/((1.5)(10 + 5 + 3.5 + 2.5 + 2 + 1.5 + 1.25 + 1) + 0.5).
    #[test]
    fn the_rows_have_the_snellen_sizes() {
        let lines = SnellenChart::lines(1.0, DVec2::ZERO);
        let h = 1.0 / (1.5 * (10.0 + 5.0 + 3.5 + 2.5 + 2.0 + 1.5 + 1.25 + 1.0) + 0.5);
        let centre = 0.5 / 2f64.sqrt();
        // The E's stem is left of its centre: scan a little left of the middle of the E.
        let e = &lines[0];
        let stem = e.corner[0] + 0.15 * e.width();
        let (top, bottom) = inked_extent(&lines[..1], stem, 0.0, -1.0).unwrap();
        assert!((top - -0.5 * 10.0 * h).abs() < 2e-3, "E's top {top}");
        assert!(
            (top - bottom - 10.0 * h).abs() < 2e-3,
            "E's height {}",
            top - bottom
        );
        // The last row: the D's stem.
        let d = &lines[7];
        let stem = d.corner[0] + 0.04 * d.width();
        let (top, bottom) = inked_extent(&lines[7..], stem, 0.0, -1.0).unwrap();
        assert!(
            (top - bottom - h).abs() < 2e-3,
            "D's height {}",
            top - bottom
        );
        assert!(bottom > -1.0 + 0.4 * h, "the last row within the chart");
        for line in &lines {
            let middle = line.corner[0] + 0.5 * line.width();
            assert!((middle - centre).abs() < 1e-12, "each row centred");
        }
    }
}
