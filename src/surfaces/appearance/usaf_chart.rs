//! The USAF 1951 resolution test chart (the target of Dr TIM's `EditableFramedUSAFTestChart`,
//! which shows a picture of it), drawn here from the standard's definition: in group g,
//! element e (1 to 6) resolves R = 2^(g + (e − 1)/6) line pairs per millimetre; it has three
//! bars of width w = 1/(2R) mm and length 5w, with gaps w, once horizontal and once vertical.

use glam::DVec2;
use serde::Deserialize;

use super::{greys, parts_pictures, two_parts};
use crate::geometry::Interaction;
use crate::keys::{Positive, Vector2};
use crate::picture::PictureFile;
use crate::surfaces::{Surface, SurfaceKeys};

/// The lowest and highest group a chart may hold.
const GROUPS: std::ops::RangeInclusive<i32> = -2..=9;

/// The width, in millimetres, of a bar of group `g`, element `e`.
pub fn bar_width(g: i32, e: i32) -> f64 {
    0.5 / 2f64.powf(g as f64 + (e - 1) as f64 / 6.0)
}

/// A rectangle of the chart, `min` to `max` in surface coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bar {
    pub min: DVec2,
    pub max: DVec2,
}

#[derive(Debug, Clone, PartialEq)]
pub struct UsafChart {
    pub bars: Vec<Bar>,
    /// `surfaces[0]` on the bars, `surfaces[1]` elsewhere.
    pub surfaces: Box<[Surface; 2]>,
}

impl UsafChart {
    /// The bars of groups `first` to `last`, laid out in millimetres with +x right and +y up:
    /// a column per group, largest on the left, with its elements 1 to 6 downwards, each
    /// element's vertical bars left of its horizontal ones (2w apart), elements 2w apart
    /// vertically and columns 4w₁ apart (w₁ the group's first element's bar width). Returns the
    /// bars and the chart's width, a margin of 2w of the first element of `first` included.
    fn layout(first: i32, last: i32) -> (Vec<Bar>, f64) {
        let margin = 2.0 * bar_width(first, 1);
        let mut bars = Vec::new();
        let mut x = margin;
        for g in first..=last {
            let mut top = -margin;
            for e in 1..=6 {
                let w = bar_width(g, e);
                let bottom = top - 5.0 * w;
                for k in 0..3 {
                    let k = k as f64;
                    // Vertical bars: w wide, 5w high.
                    bars.push(Bar {
                        min: DVec2::new(x + 2.0 * k * w, bottom),
                        max: DVec2::new(x + (2.0 * k + 1.0) * w, top),
                    });
                    // Horizontal bars: 5w wide, w high, from the top down.
                    bars.push(Bar {
                        min: DVec2::new(x + 7.0 * w, top - (2.0 * k + 1.0) * w),
                        max: DVec2::new(x + 12.0 * w, top - 2.0 * k * w),
                    });
                }
                top = bottom - 2.0 * w;
            }
            x += 16.0 * bar_width(g, 1);
        }
        (bars, x - 4.0 * bar_width(last, 1) + margin)
    }

    /// The surface at the point the ray meets.
    pub fn surface_at(&self, at: &Interaction) -> &Surface {
        let p = at.coordinates();
        let on_bar = self
            .bars
            .iter()
            .any(|b| p.x >= b.min.x && p.x < b.max.x && p.y >= b.min.y && p.y < b.max.y);
        &self.surfaces[usize::from(!on_bar)]
    }
}

/// `type = "usaf-chart"`: groups `groups = [FIRST, LAST]` (default [−2, 3], those of the
/// picture Dr TIM's chart shows), the chart `width` wide (default 1) in surface coordinates
/// with its top left corner at `corner` (default [0, 0]; u to the right, v up, as text), bars
/// and paper `surfaces = [BARS, PAPER]` (default matt black and matt white).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct UsafChartKeys {
    groups: Option<[i32; 2]>,
    width: Option<Positive>,
    corner: Option<Vector2>,
    surfaces: Option<Box<[SurfaceKeys; 2]>>,
}

impl UsafChartKeys {
    /// The picture files its surfaces name.
    pub fn pictures(&mut self) -> Vec<&mut PictureFile> {
        parts_pictures(&mut self.surfaces)
    }

    pub fn build(self) -> Result<Surface, String> {
        let [first, last] = self.groups.unwrap_or([-2, 3]);
        if !(GROUPS.contains(&first) && GROUPS.contains(&last) && first <= last) {
            return Err(format!(
                "expected groups [FIRST, LAST] with {} ≤ FIRST ≤ LAST ≤ {}, got [{first}, {last}]",
                GROUPS.start(),
                GROUPS.end()
            ));
        }
        let (bars, width_mm) = UsafChart::layout(first, last);
        let scale = self.width.map_or(1.0, |w| w.0) / width_mm;
        let corner = self.corner.map_or(DVec2::ZERO, |c| c.0);
        let place = |p: DVec2| corner + p * scale;
        Ok(Surface::UsafChart(UsafChart {
            bars: bars
                .into_iter()
                .map(|b| Bar {
                    min: place(b.min),
                    max: place(b.max),
                })
                .collect(),
            surfaces: two_parts(self.surfaces, greys([0.0, 1.0], false), "USAF chart")?,
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The standard's resolutions: group 0 element 1 is 1 line pair per mm (bars 0.5 mm),
    /// group 2 element 3 is 5.04 lp/mm (table value), group −2 element 1 0.25 lp/mm (2 mm).
    #[test]
    fn bar_widths_are_the_standards() {
        assert!((bar_width(0, 1) - 0.5).abs() < 1e-15);
        assert!((0.5 / bar_width(2, 3) - 5.04).abs() < 0.005);
        assert!((bar_width(-2, 1) - 2.0).abs() < 1e-15);
    }

    /// Each element has six bars, three 5w × w and three w × 5w (w its bar width), and any two
    /// bars are disjoint; the chart holds 36 elements for groups −2 to 3.
    #[test]
    fn every_element_has_three_bars_each_way_and_none_overlap() {
        let (bars, width) = UsafChart::layout(-2, 3);
        assert_eq!(bars.len(), 6 * 6 * 6);
        for (i, chunk) in bars.chunks(6).enumerate() {
            let (g, e) = (-2 + (i / 6) as i32, 1 + (i % 6) as i32);
            let w = bar_width(g, e);
            for (k, b) in chunk.iter().enumerate() {
                let size = b.max - b.min;
                let expected = if k % 2 == 0 {
                    DVec2::new(w, 5.0 * w)
                } else {
                    DVec2::new(5.0 * w, w)
                };
                assert!((size - expected).abs().max_element() < 1e-12, "{g} {e} {k}");
            }
        }
        for (i, a) in bars.iter().enumerate() {
            assert!(a.min.x > 0.0 && a.max.x < width);
            for b in &bars[i + 1..] {
                let apart = a.max.x <= b.min.x
                    || b.max.x <= a.min.x
                    || a.max.y <= b.min.y
                    || b.max.y <= a.min.y;
                assert!(apart, "{a:?} overlaps {b:?}");
            }
        }
    }

    #[test]
    fn groups_out_of_order_or_range_are_refused() {
        for groups in ["[3, 2]", "[-3, 0]", "[0, 10]"] {
            let keys: UsafChartKeys = toml::from_str(&format!("groups = {groups}")).unwrap();
            assert!(keys.build().unwrap_err().starts_with("expected groups"));
        }
    }
}
