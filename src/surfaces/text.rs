//! Text: letters of the shipped font (Liberation Sans, OFL; `assets/fonts`) drawn in the
//! shape's surface coordinates, one surface on the letters and another around them.
//!
//! Each line is rasterised once, when the scene is built, into a coverage bitmap of
//! [`PIXELS_PER_LINE`] rows per line height (ab_glyph's exact area coverage of the glyph
//! outlines); a point is on a letter where its pixel is at least half covered. At 256 rows a
//! line, letter edges are placed to within 1/512 of the line height, far finer than any
//! rendered pixel of a label; an exact point-in-outline test would cost a curve walk per hit.

use ab_glyph::{Font, FontRef, Glyph, PxScale, ScaleFont};
use serde::Deserialize;

use super::{Coloured, Surface, SurfaceKeys, Transparent};
use crate::geometry::Interaction;
use crate::keys::{Array, Finite, Positive, Rgb};
use crate::math::Colour;

/// Liberation Sans Regular 2.1.5 (SIL Open Font License 1.1, `assets/fonts/OFL.txt`).
const FONT: &[u8] = include_bytes!("../../assets/fonts/LiberationSans-Regular.ttf");

/// Bitmap rows per line height.
pub const PIXELS_PER_LINE: f32 = 256.0;

/// The most characters a text may have: each takes about 32 KB of bitmap (and four times that
/// while it is drawn), so a label of this many takes about 32 MB.
pub const MAX_CHARACTERS: usize = 1000;

/// The shipped font.
pub fn font() -> FontRef<'static> {
    FontRef::try_from_slice(FONT).expect("the shipped font parses")
}

/// One line of text, rasterised.
#[derive(Debug, Clone, PartialEq)]
pub struct Line {
    /// Surface coordinates of the bottom left corner of the line's box (its descent below).
    pub corner: [f64; 2],
    /// The line's height (the font's ascent minus descent) in surface-coordinate units.
    pub height: f64,
    /// Width of the bitmap in pixels; its rows number [`PIXELS_PER_LINE`].
    columns: usize,
    /// Row by row from the top: whether each pixel is on a letter.
    ink: Vec<bool>,
}

impl Line {
    /// `text` with the bottom left corner of its box at `corner` and the given line `height`.
    pub fn new(text: &str, corner: [f64; 2], height: f64) -> Line {
        let font = font();
        let scaled = font.as_scaled(PxScale::from(PIXELS_PER_LINE));
        let mut x = 0.0f32;
        let mut glyphs = Vec::new();
        let mut previous = None;
        for c in text.chars() {
            let id = font.glyph_id(c);
            if let Some(p) = previous {
                x += scaled.kern(p, id);
            }
            glyphs.push(Glyph {
                id,
                scale: PxScale::from(PIXELS_PER_LINE),
                position: ab_glyph::point(x, scaled.ascent()),
            });
            x += scaled.h_advance(id);
            previous = Some(id);
        }
        let columns = x.ceil().max(1.0) as usize;
        let rows = PIXELS_PER_LINE as usize;
        let mut coverage = vec![0.0f32; columns * rows];
        for glyph in glyphs {
            if let Some(outline) = font.outline_glyph(glyph) {
                let b = outline.px_bounds();
                outline.draw(|gx, gy, c| {
                    let (px, py) = (b.min.x as i64 + gx as i64, b.min.y as i64 + gy as i64);
                    if (0..columns as i64).contains(&px) && (0..rows as i64).contains(&py) {
                        coverage[py as usize * columns + px as usize] += c;
                    }
                });
            }
        }
        Line {
            corner,
            height,
            columns,
            ink: coverage.into_iter().map(|c| c >= 0.5).collect(),
        }
    }

    /// The line's width (its advance) in surface-coordinate units.
    pub fn width(&self) -> f64 {
        self.columns as f64 * self.height / PIXELS_PER_LINE as f64
    }

    /// Whether surface coordinates (u, v) lie on a letter.
    pub fn inked(&self, u: f64, v: f64) -> bool {
        let scale = PIXELS_PER_LINE as f64 / self.height;
        let x = (u - self.corner[0]) * scale;
        let y = (self.corner[1] + self.height - v) * scale;
        if !(x >= 0.0 && y >= 0.0 && x < self.columns as f64 && y < PIXELS_PER_LINE as f64) {
            return false;
        }
        self.ink[y as usize * self.columns + x as usize]
    }
}

/// Lines of text: `surfaces[0]` on the letters, `surfaces[1]` elsewhere.
#[derive(Debug, Clone, PartialEq)]
pub struct Text {
    pub lines: Vec<Line>,
    pub surfaces: Box<[Surface; 2]>,
}

impl Text {
    /// The surface at the point the ray meets.
    pub fn surface_at(&self, at: &Interaction) -> &Surface {
        let uv = at.coordinates();
        let inked = self.lines.iter().any(|l| l.inked(uv.x, uv.y));
        &self.surfaces[usize::from(!inked)]
    }

    /// The text's letters and background from the keys' surfaces, where not given Dr TIM's
    /// `SurfaceColour.BLACK_SHINY` letters on a background that passes every ray on unchanged.
    pub fn new(
        lines: Vec<Line>,
        colour: Option<Rgb>,
        background: Option<SurfaceKeys>,
    ) -> Result<Text, String> {
        let background = match background {
            None => Surface::Transparent(Transparent {
                transmission_coefficient: 1.0,
            }),
            Some(keys) => super::appearance::part(keys, "a text background")?,
        };
        let ink = Surface::Coloured(Coloured::shiny(colour.map_or(Colour::ZERO, |c| c.0)));
        Ok(Text {
            lines,
            surfaces: Box::new([ink, background]),
        })
    }
}

/// `type = "text"`: Dr TIM's `EditableText`. `text` (default Dr TIM's "Hello, world!"), lines
/// separated by newlines, each `height` high (default 1) in surface-coordinate units, the box
/// of the last line with its bottom left corner at `corner` (default [0, 0]); the letters
/// `colour` (default black, shiny), elsewhere `background` (default: fully transparent).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TextKeys {
    text: Option<String>,
    height: Option<Positive>,
    corner: Option<Array<Finite, 2>>,
    colour: Option<Rgb>,
    background: Option<Box<SurfaceKeys>>,
}

impl TextKeys {
    /// The picture files its background names.
    pub fn pictures(&mut self) -> Vec<&mut crate::picture::PictureFile> {
        self.background
            .iter_mut()
            .flat_map(|s| s.pictures())
            .collect()
    }

    pub fn build(self) -> Result<Surface, String> {
        let text = self.text.unwrap_or_else(|| "Hello, world!".into());
        if text.trim().is_empty() {
            return Err("the text is empty".into());
        }
        let characters = text.chars().count();
        if characters > MAX_CHARACTERS {
            return Err(format!(
                "a text may have at most {MAX_CHARACTERS} characters, got {characters}"
            ));
        }
        let height = self.height.map_or(1.0, |h| h.0);
        let [u, v] = self.corner.map_or([0.0; 2], |c| c.0.map(|x| x.0));
        let count = text.lines().count();
        let lines = text
            .lines()
            .enumerate()
            .map(|(k, line)| Line::new(line, [u, v + (count - 1 - k) as f64 * height], height))
            .collect();
        Ok(Surface::Text(Text::new(
            lines,
            self.colour,
            self.background.map(|b| *b),
        )?))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Liberation Sans is metric-compatible with Arial, whose "l" (2048 units an em) is a bar
    /// from x = 136 to 272 units (0.0664 to 0.1328 em), 1466 units (0.716 em) high, and whose
    /// line height, ascent − descent, is 1854 + 434 units (0.905 + 0.212 = 1.117 em).
    #[test]
    fn the_bar_of_an_l_is_ink_and_far_away_is_not() {
        let em = 1.0 / 1.117; // surface units per em for a line 1 high
        let line = Line::new("l", [2.0, 3.0], 1.0);
        let baseline = 3.0 + 0.212 * em;
        let middle = 2.0 + 0.0996 * em;
        assert!(line.inked(middle, baseline + 0.3 * em));
        assert!(line.inked(middle, baseline + 0.7 * em));
        assert!(!line.inked(middle, baseline + 0.8 * em), "above the l");
        assert!(
            !line.inked(middle, baseline - 0.05 * em),
            "below the baseline"
        );
        assert!(
            !line.inked(middle + 0.1 * em, baseline + 0.3 * em),
            "right of the bar"
        );
        assert!(!line.inked(10.0, 3.5) && !line.inked(-1.0, 3.5));
    }

    /// Arial's (so Liberation Sans's) advance of every digit is 0.556 em: "0123" is four of
    /// them, twice "01"'s width; the width scales with the line height.
    #[test]
    fn advance_grows_with_the_text_and_the_height() {
        let em = 1.0 / 1.117;
        let w = |s: &str, h: f64| Line::new(s, [0.0, 0.0], h).width();
        assert!((w("01", 1.0) - 2.0 * 0.556 * em).abs() < 0.01);
        assert!((w("0123", 1.0) - 4.0 * 0.556 * em).abs() < 0.01);
        assert!((w("0123", 3.0) - 3.0 * w("0123", 1.0)).abs() < 0.02);
    }

    /// Moving the corner moves the letters with it.
    #[test]
    fn the_corner_places_the_text() {
        let a = Line::new("I", [0.0, 0.0], 1.0);
        let b = Line::new("I", [5.0, -2.0], 1.0);
        for (u, v) in [(0.15, 0.5), (0.15, 0.3), (0.5, 0.5), (0.1, 0.95)] {
            assert_eq!(a.inked(u, v), b.inked(u + 5.0, v - 2.0));
        }
        // Arial's "I" stem runs from 191 to 385 units (0.093 to 0.188 em): its middle is ink.
        let em = 1.0 / 1.117;
        assert!(a.inked(0.14 * em, 0.5));
        assert!(!a.inked(0.14 * em + 5.0, 0.5));
    }

    #[test]
    fn lines_stack_downwards_from_the_first_and_empty_text_is_refused() {
        let keys: TextKeys = toml::from_str("text = \"l\\nl\"\ncorner = [0, 0]").unwrap();
        let Surface::Text(t) = keys.build().unwrap() else {
            panic!("a text surface")
        };
        assert_eq!(t.lines[0].corner, [0.0, 1.0]);
        assert_eq!(t.lines[1].corner, [0.0, 0.0]);
        let keys: TextKeys = toml::from_str("text = \" \"").unwrap();
        assert_eq!(keys.build().unwrap_err(), "the text is empty");
    }
}
