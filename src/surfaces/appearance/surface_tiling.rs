//! Surface tiling: two surfaces alternating on rectangular tiles of the shape's surface
//! coordinates, with their own widths in u and v (Dr TIM's `SurfaceTiling`; the chequerboard is
//! its square case).

use serde::Deserialize;

use super::{band, greys, parts_pictures, two_parts};
use crate::geometry::Interaction;
use crate::keys::Positive;
use crate::picture::PictureFile;
use crate::surfaces::{Surface, SurfaceKeys};

#[derive(Debug, Clone, PartialEq)]
pub struct SurfaceTiling {
    /// Widths of a tile in u and in v, in the units of the surface coordinates.
    pub widths: [f64; 2],
    /// `surfaces[0]` where ⌊u/width_u⌋ + ⌊v/width_v⌋ is even, `surfaces[1]` where it is odd.
    pub surfaces: Box<[Surface; 2]>,
}

impl SurfaceTiling {
    /// The surface of the tile at surface coordinates (u, v).
    pub fn tile(&self, u: f64, v: f64) -> &Surface {
        let [wu, wv] = self.widths;
        &self.surfaces[(band(u, wu).wrapping_add(band(v, wv)) & 1) as usize]
    }

    /// The surface of the tile the ray meets.
    pub fn tile_at(&self, at: &Interaction) -> &Surface {
        let uv = at.coordinates();
        self.tile(uv.x, uv.y)
    }
}

/// `type = "surface-tiling"`: tiles `width_u` by `width_v` of the two `surfaces`, where not
/// given Dr TIM's GUI's "Tiled" (`EditableSurfaceTiling` in `SurfacePropertyPanel`): widths 1,
/// shiny grey 0.5 and shiny white.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SurfaceTilingKeys {
    width_u: Option<Positive>,
    width_v: Option<Positive>,
    surfaces: Option<Box<[SurfaceKeys; 2]>>,
}

impl SurfaceTilingKeys {
    /// The picture files its tiles name.
    pub fn pictures(&mut self) -> Vec<&mut PictureFile> {
        parts_pictures(&mut self.surfaces)
    }

    pub fn build(self) -> Result<Surface, String> {
        let width = |w: Option<Positive>| w.map_or(1.0, |w| w.0);
        Ok(Surface::SurfaceTiling(SurfaceTiling {
            widths: [width(self.width_u), width(self.width_v)],
            surfaces: two_parts(self.surfaces, greys([0.5, 1.0], true), "surface tiling")?,
        }))
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;
    use crate::geometry::{Plane, Shape};
    use crate::math::Colour;
    use crate::surfaces::Redirection;
    use crate::surfaces::tests::meet;

    /// Dr TIM's rule, signum(((|u/w_u| mod 2) − 1)·((|v/w_v| mod 2) − 1)·u·v) > 0 for the first
    /// surface, worked by hand with w_u = 0.5, w_v = 2 on the plane z = 0 (u = x, v = y):
    /// (0.2, 1.0): (0.4 − 1)(0.5 − 1)·0.2·1 > 0, first; (0.7, 1.0): (1.4 − 1)(0.5 − 1) < 0,
    /// second; (0.2, 2.5): (0.4 − 1)(1.25 − 1) < 0, second; (−0.2, 1.0):
    /// (0.4 − 1)(0.5 − 1)(−0.2) < 0, second; (−0.2, −1.0): > 0, first; (0.7, 2.5): first.
    #[test]
    fn tiles_follow_dr_tims_rule_with_separate_widths() {
        let (first, second) = (Colour::X, Colour::Y);
        let tiling = Surface::SurfaceTiling(SurfaceTiling {
            widths: [0.5, 2.0],
            surfaces: Box::new([
                Surface::ConstantColour(first),
                Surface::ConstantColour(second),
            ]),
        });
        let plane = Shape::Plane(Plane::new(DVec3::ZERO, DVec3::Z, DVec3::X).unwrap());
        let seen = |x: f64, y: f64| {
            let at = meet(&plane, DVec3::new(x, y, 3.0), -DVec3::Z);
            match tiling.redirect(&at, &mut |_| {}) {
                Redirection::Emits(c) if c == first => 1,
                Redirection::Emits(c) if c == second => 2,
                other => panic!("{other:?}"),
            }
        };
        assert_eq!(seen(0.2, 1.0), 1);
        assert_eq!(seen(0.7, 1.0), 2);
        assert_eq!(seen(0.2, 2.5), 2);
        assert_eq!(seen(-0.2, 1.0), 2);
        assert_eq!(seen(-0.2, -1.0), 1);
        assert_eq!(seen(0.7, 2.5), 1);
        // Either side of u = 0.5 (not of v = 1, inside a tile 2 high) and of v = 2.
        let e = 1e-6;
        assert_eq!((seen(0.5 - e, 0.9), seen(0.5 + e, 0.9)), (1, 2));
        assert_eq!((seen(0.3, 1.0 - e), seen(0.3, 1.0 + e)), (1, 1));
        assert_eq!((seen(0.3, 2.0 - e), seen(0.3, 2.0 + e)), (1, 2));
    }

    #[test]
    fn defaults_are_dr_tims_tiled_surface() {
        let keys: SurfaceTilingKeys = toml::from_str("width_v = 3").unwrap();
        let Surface::SurfaceTiling(t) = keys.build().unwrap() else {
            panic!("not a tiling")
        };
        assert_eq!(t.widths, [1.0, 3.0]);
        assert_eq!(
            *t.surfaces,
            [0.5, 1.0]
                .map(|g| Surface::Coloured(crate::surfaces::Coloured::shiny(Colour::splat(g))))
        );
        assert!(toml::from_str::<SurfaceTilingKeys>("width_u = 0").is_err());
    }
}
