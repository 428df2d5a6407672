//! Appearance: surfaces that choose between surfaces by position, and colour fields.

// Patterns and colour fields (issue 38, part 2).
mod striped;
mod surface_tiling;
mod time_dependent_colour;

pub use striped::{Striped, StripedKeys};
pub use surface_tiling::{SurfaceTiling, SurfaceTilingKeys};
pub use time_dependent_colour::{TimeDependentColour, TimeDependentColourKeys};

use super::{Coloured, Surface, SurfaceKeys};
use crate::math::Colour;
use crate::picture::PictureFile;

/// The number of the band of width `w` that x lies in, ⌊x/w⌋ (saturating far out).
fn band(x: f64, w: f64) -> i64 {
    (x / w).floor() as i64
}

/// The two surfaces of a two-part pattern, `kind` naming it in errors; where not given, shiny
/// surfaces of the `greys` levels.
fn two_parts(
    keys: Option<Box<[SurfaceKeys; 2]>>,
    greys: [f64; 2],
    kind: &str,
) -> Result<Box<[Surface; 2]>, String> {
    Ok(Box::new(match keys {
        None => greys.map(|grey| Surface::Coloured(Coloured::shiny(Colour::splat(grey)))),
        Some(keys) => {
            let [a, b] = *keys;
            if a.destination().is_some() || b.destination().is_some() {
                return Err(format!("a teleporting surface cannot be part of a {kind}"));
            }
            [a.build()?, b.build()?]
        }
    }))
}

/// The picture files two parts name.
fn parts_pictures(keys: &mut Option<Box<[SurfaceKeys; 2]>>) -> Vec<&mut PictureFile> {
    keys.iter_mut()
        .flat_map(|s| s.iter_mut())
        .flat_map(SurfaceKeys::pictures)
        .collect()
}
