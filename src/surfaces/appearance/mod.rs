//! How surfaces look and combine, after Dr TIM's surface appearance families: colour filters,
//! tinted solids, glowing clouds, semi-transparent surfaces, averages, two-sided surfaces and
//! layer stacks; patterns that choose between surfaces by position (stripes, tilings) and
//! colour fields.

mod average;
mod colour_filter;
mod glowing_cloud;
mod layer_stack;
mod semi_transparent;
mod striped;
mod surface_tiling;
mod time_dependent_colour;
mod tinted_solid;
mod two_sided;

pub use average::{AverageKeys, Mix};
pub use colour_filter::{ColourFilter, ColourFilterKeys};
pub use glowing_cloud::{GlowingCloud, GlowingCloudKeys};
pub use layer_stack::{LayerStack, LayerStackKeys};
pub use semi_transparent::SemiTransparentKeys;
pub use striped::{Striped, StripedKeys};
pub use surface_tiling::{SurfaceTiling, SurfaceTilingKeys};
pub use time_dependent_colour::{TimeDependentColour, TimeDependentColourKeys};
pub use tinted_solid::{TintedSolid, TintedSolidKeys};
pub use two_sided::{TwoSided, TwoSidedKeys};

use super::{Coloured, Surface, SurfaceKeys};
use crate::math::Colour;
use crate::picture::PictureFile;

/// A surface that is part of another (`role` says which), built; a teleporting part is
/// refused, as it needs a destination that only a whole object can have.
fn part(keys: SurfaceKeys, role: &str) -> Result<Surface, String> {
    if keys.destination().is_some() {
        return Err(format!("a teleporting surface cannot be {role}"));
    }
    keys.build()
}

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
            let role = format!("part of a {kind}");
            [part(a, &role)?, part(b, &role)?]
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
