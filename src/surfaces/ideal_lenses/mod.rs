//! Ideal thin lenses and what generalises them: surfaces that image every point of space
//! exactly, whatever the shape they sit on (Dr TIM's `IdealThinLensSurface`, `GlensSurface`
//! and their cylindrical, mirror and lenslet-array relatives).
//!
//! Each law is a pure function of the ray direction d and the point S where the ray meets the
//! surface, in the object's own coordinates ([`Interaction::local_point`]), so it is well
//! defined on any shape: on a plane through the principal point, perpendicular to the optical
//! axis, it is the textbook element; elsewhere it still sends every ray through the principal
//! (nodal) point undeviated and makes parallel rays meet in the focal plane. Like Dr TIM, the
//! law is applied to the backward-traced ray; on the lens plane that is exactly what light does
//! (the laws are reciprocal there).
//!
//! Positions and directions are given like the shape's own (before the object's transform,
//! which moves them with the shape, [`Surface::transformed`](super::Surface::transformed)).
//!
//! [`Interaction::local_point`]: crate::geometry::Interaction::local_point

mod glens;
mod lenslet_array;
mod thin_lens;
mod thin_mirror;

use glam::DVec3;

use crate::geometry::{Interaction, Transform};
use crate::surfaces::Redirection;

pub use glens::{Focus, Glens, GlensKeys};
pub use lenslet_array::{IdealThinLensletArrayKeys, LensletArray};
pub use thin_lens::{IdealThinCylindricalLensKeys, IdealThinLensKeys, ThinLens};
pub use thin_mirror::{IdealThinCylindricalMirrorKeys, IdealThinMirrorKeys, ThinMirror};

/// The ray met at `at` leaves along `law(d, S)` (S the hit in the object's own positions),
/// carrying `factor` of the light.
fn leaving(
    at: &Interaction,
    law: impl Fn(DVec3, DVec3) -> DVec3,
    factor: f64,
) -> Redirection<'static> {
    Redirection::Leaves {
        direction: law(at.ray.direction, at.local_point()).normalize(),
        factor: crate::math::Colour::splat(factor),
    }
}

/// The factor by which `t` scales lengths, for the focal lengths and periods of a law placed by
/// it: only a similarity map (rotation, uniform scale, translation) has one.
fn length_scale(t: &Transform) -> Result<f64, String> {
    t.uniform_scale().ok_or_else(|| {
        "an ideal lens's focal length is defined only under rotations, uniform scaling and translations, so it cannot be scaled non-uniformly".to_string()
    })
}

/// The unit direction `a` placed by `t`.
fn direction(t: &Transform, a: DVec3) -> DVec3 {
    t.vector(a).normalize()
}
