//! How surfaces look and combine, after Dr TIM's surface appearance families: colour filters,
//! tinted solids, glowing clouds, semi-transparent surfaces, averages, two-sided surfaces and
//! layer stacks; patterns that choose between surfaces by position (stripes, tilings, masks,
//! test charts) and colour fields (by time, position, surface coordinates; rainbows).

mod average;
mod colour_filter;
mod either_or;
mod glowing_cloud;
mod hue_brightness_gradient;
mod layer_stack;
mod position_dependent_colour;
mod rainbow;
mod semi_transparent;
mod snellen_chart;
mod striped;
mod surface_tiling;
mod time_dependent_colour;
mod tinted_solid;
mod two_sided;
mod usaf_chart;

pub use average::{AverageKeys, Mix};
pub use colour_filter::{ColourFilter, ColourFilterKeys};
pub use either_or::{EitherOr, EitherOrKeys, HoleyKeys};
pub use glowing_cloud::{GlowingCloud, GlowingCloudKeys};
pub use hue_brightness_gradient::{HueBrightnessGradient, HueBrightnessGradientKeys};
pub use layer_stack::{LayerStack, LayerStackKeys};
pub use position_dependent_colour::{PositionDependentColour, PositionDependentColourKeys};
pub use rainbow::{Rainbow, RainbowKeys};
pub use semi_transparent::SemiTransparentKeys;
pub use snellen_chart::{SnellenChart, SnellenChartKeys};
pub use striped::{Striped, StripedKeys};
pub use surface_tiling::{SurfaceTiling, SurfaceTilingKeys};
pub use time_dependent_colour::{TimeDependentColour, TimeDependentColourKeys};
pub use tinted_solid::{TintedSolid, TintedSolidKeys};
pub use two_sided::{TwoSided, TwoSidedKeys};
pub use usaf_chart::{UsafChart, UsafChartKeys};

use super::{Coloured, Surface, SurfaceKeys};
use crate::math::Colour;
use crate::picture::PictureFile;

/// A surface that is part of another (`role` says which), built; a teleporting part is
/// refused, as it needs a destination that only a whole object can have.
pub(super) fn part(keys: SurfaceKeys, role: &str) -> Result<Surface, String> {
    if keys.destination().is_some() {
        return Err(format!("a teleporting surface cannot be {role}"));
    }
    keys.build()
}

/// The number of the band of width `w` that x lies in, ⌊x/w⌋ (saturating far out).
fn band(x: f64, w: f64) -> i64 {
    (x / w).floor() as i64
}

/// The two surfaces of a two-part pattern, `kind` naming it in errors; where not given,
/// `defaults`.
fn two_parts(
    keys: Option<Box<[SurfaceKeys; 2]>>,
    defaults: [Surface; 2],
    kind: &str,
) -> Result<Box<[Surface; 2]>, String> {
    Ok(Box::new(match keys {
        None => defaults,
        Some(keys) => {
            let [a, b] = *keys;
            let role = format!("part of a {kind}");
            [part(a, &role)?, part(b, &role)?]
        }
    }))
}

/// Two surfaces of the `greys` levels, `shiny` or matt.
fn greys(greys: [f64; 2], shiny: bool) -> [Surface; 2] {
    greys.map(|grey| {
        let c = Colour::splat(grey);
        Surface::Coloured(if shiny {
            Coloured::shiny(c)
        } else {
            Coloured::matt(c)
        })
    })
}

/// The picture files two parts name.
fn parts_pictures(keys: &mut Option<Box<[SurfaceKeys; 2]>>) -> Vec<&mut PictureFile> {
    keys.iter_mut()
        .flat_map(|s| s.iter_mut())
        .flat_map(SurfaceKeys::pictures)
        .collect()
}

/// Dr TIM's cycle of colours at phase φ: each channel k = 0, 1, 2 (red, green, blue) is
/// 0.5 + 0.5 sin(φ + k·2π/3) (`SurfaceColourTimeDependent`, `SurfaceColourPositionDependent`).
fn cycle(phase: f64) -> Colour {
    use std::f64::consts::TAU;
    Colour::from_array([0.0, 1.0, 2.0].map(|k| 0.5 + 0.5 * (phase + k * TAU / 3.0).sin()))
}

/// The colour of hue `h` (in turns, taken modulo 1: 0 red, 1/3 green, 2/3 blue), saturation
/// `s` and lightness `l`, by the HSL formula Dr TIM's `DoubleColour.getColourFromHSL` uses:
/// with q = l(1 + s) for l < 1/2, else l + s − ls, and p = 2l − q, each channel is
/// p + (q − p)·6t, q, p + (q − p)(2/3 − t)·6 or p as its hue offset t (h + 1/3, h, h − 1/3,
/// modulo 1) lies below 1/6, 1/2, 2/3 or above. Dr TIM wraps the offsets only once, which
/// differs where |h| > 1.
fn hsl(h: f64, s: f64, l: f64) -> Colour {
    let q = if l < 0.5 {
        l * (1.0 + s)
    } else {
        l + s - l * s
    };
    let p = 2.0 * l - q;
    let channel = |t: f64| {
        let t = t.rem_euclid(1.0);
        if t < 1.0 / 6.0 {
            p + (q - p) * 6.0 * t
        } else if t < 0.5 {
            q
        } else if t < 2.0 / 3.0 {
            p + (q - p) * (2.0 / 3.0 - t) * 6.0
        } else {
            p
        }
    };
    Colour::new(channel(h + 1.0 / 3.0), channel(h), channel(h - 1.0 / 3.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The textbook HSL colours: pure red, green and blue at hue 0, 1/3, 2/3 with full
    /// saturation and lightness 1/2; yellow at 1/6; white at lightness 1, black at 0; grey
    /// without saturation; pink (1, 0.5, 0.5) at lightness 3/4; a hue one turn on is the same.
    #[test]
    fn hsl_gives_the_textbook_colours() {
        let cases = [
            ((0.0, 1.0, 0.5), Colour::new(1.0, 0.0, 0.0)),
            ((1.0 / 3.0, 1.0, 0.5), Colour::new(0.0, 1.0, 0.0)),
            ((2.0 / 3.0, 1.0, 0.5), Colour::new(0.0, 0.0, 1.0)),
            ((1.0 / 6.0, 1.0, 0.5), Colour::new(1.0, 1.0, 0.0)),
            ((0.3, 1.0, 1.0), Colour::ONE),
            ((0.3, 1.0, 0.0), Colour::ZERO),
            ((0.3, 0.0, 0.4), Colour::splat(0.4)),
            ((0.0, 1.0, 0.75), Colour::new(1.0, 0.5, 0.5)),
            ((1.0 + 2.0 / 3.0, 1.0, 0.5), Colour::new(0.0, 0.0, 1.0)),
        ];
        for ((h, s, l), expected) in cases {
            let got = hsl(h, s, l);
            assert!(
                (got - expected).abs().max_element() < 1e-12,
                "hsl({h}, {s}, {l}) = {got}"
            );
        }
    }
}
