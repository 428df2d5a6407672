//! Chequerboard: two surfaces alternating on square tiles of the shape's surface coordinates.

use serde::Deserialize;

use super::{Coloured, Surface, SurfaceKeys};
use crate::geometry::Interaction;
use crate::keys::Positive;
use crate::math::Colour;

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

/// `type = "chequerboard"`: tiles of `tile_width` with the two `surfaces`, where not given
/// those of Dr TIM's GUI's tiled surface: width 1, `SurfaceColour.GREY50_SHINY` and
/// `SurfaceColour.WHITE_SHINY`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ChequerboardKeys {
    tile_width: Option<Positive>,
    surfaces: Option<Box<[SurfaceKeys; 2]>>,
}

impl ChequerboardKeys {
    /// The picture files its tiles name.
    pub fn pictures(&mut self) -> Vec<&mut crate::picture::PictureFile> {
        self.surfaces
            .iter_mut()
            .flat_map(|s| s.iter_mut())
            .flat_map(SurfaceKeys::pictures)
            .collect()
    }

    pub fn build(self) -> Result<Surface, String> {
        let surfaces = match self.surfaces {
            None => [0.5, 1.0].map(|grey| Surface::Coloured(Coloured::shiny(Colour::splat(grey)))),
            Some(keys) => {
                let [a, b] = *keys;
                if a.destination().is_some() || b.destination().is_some() {
                    return Err("a teleporting surface cannot be a chequerboard tile".into());
                }
                [a.build()?, b.build()?]
            }
        };
        Ok(Surface::Chequerboard(Chequerboard {
            tile_width: self.tile_width.map_or(1.0, |w| w.0),
            surfaces: Box::new(surfaces),
        }))
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;
    use crate::geometry::{Plane, Shape};
    use crate::math::Colour;
    use crate::surfaces::tests::meet;
    use crate::surfaces::{Mirror, Redirection};

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

    /// `Surface::redirect` on a chequerboard on the plane z = 0 (u = x, v = y), tiles 0.5
    /// wide: a red constant colour on the tile at the origin's upper right, a mirror on its
    /// neighbours. Just either side of each tile edge (along u, along v, and across the axes
    /// into negative coordinates) the two surfaces swap; the mirror tile reflects as a mirror
    /// (z reversed) and the colour tile emits its colour.
    #[test]
    fn adjacent_tiles_give_the_two_surfaces() {
        let red = Colour::new(1.0, 0.0, 0.0);
        let board = Surface::Chequerboard(Chequerboard {
            tile_width: 0.5,
            surfaces: Box::new([
                Surface::ConstantColour(red),
                Surface::Mirror(Mirror {
                    reflection_coefficient: 0.9,
                }),
            ]),
        });
        let plane = Shape::Plane(Plane::new(DVec3::ZERO, DVec3::Z, DVec3::X).unwrap());
        let d = DVec3::new(0.3, -0.2, -0.9).normalize();
        let redirect = |x: f64, y: f64| {
            let target = DVec3::new(x, y, 0.0);
            let at = meet(&plane, target - 2.0 * d, d);
            assert!((at.point() - target).length() < 1e-12);
            board.redirect(&at, &mut |_| {})
        };
        // Which of the two laws answered: the colour, or the mirror image of d (z reversed).
        let is_colour = |r: Redirection| r == Redirection::Emits(red);
        let is_mirrored = |r: Redirection| {
            matches!(r, Redirection::Leaves { direction, factor }
                if factor == Colour::splat(0.9) && (direction - DVec3::new(d.x, d.y, -d.z)).length() < 1e-15)
        };
        let e = 1e-6;
        let pairs = [
            // Across u = 0.5 and u = 0 (into negative u), at v = 0.2.
            ((0.5 - e, 0.2), (0.5 + e, 0.2)),
            ((e, 0.2), (-e, 0.2)),
            // Across v = 0.5 and v = 0, at u = 0.2.
            ((0.2, 0.5 - e), (0.2, 0.5 + e)),
            ((0.2, e), (0.2, -e)),
            // Far from the origin: tile (4, −3) is odd, its neighbour (5, −3) even.
            ((2.5 - e, -1.3), (2.5 + e, -1.3)),
        ];
        for (k, (p, q)) in pairs.into_iter().enumerate() {
            // The first of each pair is on a colour tile, except far out.
            let (on_colour, on_mirror) = if k < 4 { (p, q) } else { (q, p) };
            let a = redirect(on_colour.0, on_colour.1);
            assert!(is_colour(a), "{on_colour:?}: {a:?}");
            let b = redirect(on_mirror.0, on_mirror.1);
            assert!(is_mirrored(b), "{on_mirror:?}: {b:?}");
        }
        // Diagonal neighbours are alike.
        assert!(is_colour(redirect(0.7, 0.7)));
        assert!(is_colour(redirect(-0.2, -0.2)));
    }
}
