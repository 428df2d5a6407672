//! How surfaces look and combine, after Dr TIM's surface appearance families: colour filters,
//! tinted solids, glowing clouds, semi-transparent surfaces, averages, two-sided surfaces and
//! layer stacks.

mod average;
mod colour_filter;
mod glowing_cloud;
mod layer_stack;
mod semi_transparent;
mod tinted_solid;
mod two_sided;

pub use average::{AverageKeys, Mix};
pub use colour_filter::{ColourFilter, ColourFilterKeys};
pub use glowing_cloud::{GlowingCloud, GlowingCloudKeys};
pub use layer_stack::{LayerStack, LayerStackKeys};
pub use semi_transparent::SemiTransparentKeys;
pub use tinted_solid::{TintedSolid, TintedSolidKeys};
pub use two_sided::{TwoSided, TwoSidedKeys};

use super::{Surface, SurfaceKeys};

/// A surface that is part of another (`role` says which), built; a teleporting part is
/// refused, as it needs a destination that only a whole object can have.
fn part(keys: SurfaceKeys, role: &str) -> Result<Surface, String> {
    if keys.destination().is_some() {
        return Err(format!("a teleporting surface cannot be {role}"));
    }
    keys.build()
}
