//! Chequerboard: two surfaces alternating on square tiles of the shape's surface coordinates.

use serde::Deserialize;

use super::{Surface, SurfaceKeys};
use crate::geometry::Interaction;
use crate::keys::Positive;

#[derive(Debug, Clone, PartialEq)]
pub struct Chequerboard {
    /// Side length of a tile, in the units of the surface coordinates.
    pub tile_width: f64,
    /// `surfaces[0]` on tiles with floor(u/width) + floor(v/width) even, `surfaces[1]` on odd.
    pub surfaces: Box<[Surface; 2]>,
}

impl Chequerboard {
    /// The surface of the tile at surface coordinates (u, v).
    pub fn tile(&self, u: f64, v: f64) -> &Surface {
        // Casts saturate, so astronomically distant points still get a tile. x / 1 is x: the
        // default width needs no division (whose latency showed in profiles).
        let w = self.tile_width;
        let tile = |x: f64| (if w == 1.0 { x } else { x / w }).floor() as i64;
        &self.surfaces[(tile(u).wrapping_add(tile(v)) & 1) as usize]
    }

    /// The surface of the tile the ray meets.
    pub fn tile_at(&self, at: &Interaction) -> &Surface {
        let uv = at.coordinates();
        self.tile(uv.x, uv.y)
    }
}

/// `type = "chequerboard"`: tiles of `tile_width` (1 when not given) with the two `surfaces`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ChequerboardKeys {
    tile_width: Option<Positive>,
    surfaces: Box<[SurfaceKeys; 2]>,
}

impl ChequerboardKeys {
    pub fn build(self) -> Result<Surface, String> {
        let [a, b] = *self.surfaces;
        if a.destination().is_some() || b.destination().is_some() {
            return Err("a teleporting surface cannot be a chequerboard tile".into());
        }
        Ok(Surface::Chequerboard(Chequerboard {
            tile_width: self.tile_width.map_or(1.0, |w| w.0),
            surfaces: Box::new([a.build()?, b.build()?]),
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Colour;

    #[test]
    fn tiles_alternate_across_every_boundary() {
        let c = Chequerboard {
            tile_width: 1.0,
            surfaces: Box::new([
                Surface::ConstantColour(Colour::ZERO),
                Surface::ConstantColour(Colour::ONE),
            ]),
        };
        let even = &c.surfaces[0];
        let odd = &c.surfaces[1];
        assert_eq!(c.tile(0.5, 0.5), even);
        assert_eq!(c.tile(1.5, 0.5), odd);
        assert_eq!(c.tile(-0.5, 0.5), odd);
        assert_eq!(c.tile(-0.5, -0.5), even);
        assert_eq!(c.tile(2.5, 7.5), odd);
    }
}
