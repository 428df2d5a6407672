//! Striped: two surfaces alternating on stripes across the shape's surface coordinate u
//! (Dr TIM's `Striped`).

use serde::Deserialize;

use super::{band, greys, parts_pictures, two_parts};
use crate::geometry::Interaction;
use crate::keys::Positive;
use crate::picture::PictureFile;
use crate::surfaces::{Surface, SurfaceKeys};

#[derive(Debug, Clone, PartialEq)]
pub struct Striped {
    /// Width of a stripe, in the units of the surface coordinates.
    pub width: f64,
    /// As Dr TIM's: `surfaces[0]` where ⌊u/width⌋ is odd, `surfaces[1]` where it is even.
    pub surfaces: Box<[Surface; 2]>,
}

impl Striped {
    /// The surface of the stripe at surface coordinate u.
    pub fn stripe(&self, u: f64) -> &Surface {
        &self.surfaces[1 - (band(u, self.width) & 1) as usize]
    }

    /// The surface of the stripe the ray meets.
    pub fn stripe_at(&self, at: &Interaction) -> &Surface {
        self.stripe(at.coordinates().x)
    }
}

/// `type = "striped"`: stripes of `width` with the two `surfaces`, where not given Dr TIM's
/// `Striped()`'s: width 1, shiny black and shiny grey 0.9.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StripedKeys {
    width: Option<Positive>,
    surfaces: Option<Box<[SurfaceKeys; 2]>>,
}

impl StripedKeys {
    /// The picture files its stripes name.
    pub fn pictures(&mut self) -> Vec<&mut PictureFile> {
        parts_pictures(&mut self.surfaces)
    }

    pub fn build(self) -> Result<Surface, String> {
        Ok(Surface::Striped(Striped {
            width: self.width.map_or(1.0, |w| w.0),
            surfaces: two_parts(self.surfaces, greys([0.0, 0.9], true), "striped surface")?,
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

    /// Dr TIM's rule, signum(((|u/w| mod 2) − 1)·u) > 0 for the first surface, worked by hand
    /// for w = 0.5: u = 0.7 gives (1.4 − 1)·0.7 > 0, first; u = 0.2 gives (0.4 − 1)·0.2 < 0,
    /// second; u = −0.2 gives (0.4 − 1)·(−0.2) > 0, first; u = −0.7 gives (1.4 − 1)·(−0.7) < 0,
    /// second. v does not matter. Met on the plane z = 0 (u = x, v = y).
    #[test]
    fn stripes_follow_dr_tims_rule_either_side_of_each_boundary() {
        let (first, second) = (Colour::X, Colour::Y);
        let striped = Surface::Striped(Striped {
            width: 0.5,
            surfaces: Box::new([
                Surface::ConstantColour(first),
                Surface::ConstantColour(second),
            ]),
        });
        let plane = Shape::Plane(Plane::new(DVec3::ZERO, DVec3::Z, DVec3::X).unwrap());
        let seen = |x: f64, y: f64| {
            let at = meet(&plane, DVec3::new(x, y, 3.0), -DVec3::Z);
            striped.redirect(&at, &mut |_| {})
        };
        let e = 1e-6;
        for y in [-3.3, 0.1, 40.0] {
            assert_eq!(seen(0.7, y), Redirection::Emits(first));
            assert_eq!(seen(0.2, y), Redirection::Emits(second));
            assert_eq!(seen(-0.2, y), Redirection::Emits(first));
            assert_eq!(seen(-0.7, y), Redirection::Emits(second));
            // Either side of the boundaries u = 0.5, 0 and −0.5.
            assert_eq!(seen(0.5 - e, y), Redirection::Emits(second));
            assert_eq!(seen(0.5 + e, y), Redirection::Emits(first));
            assert_eq!(seen(e, y), Redirection::Emits(second));
            assert_eq!(seen(-e, y), Redirection::Emits(first));
            assert_eq!(seen(-0.5 + e, y), Redirection::Emits(first));
            assert_eq!(seen(-0.5 - e, y), Redirection::Emits(second));
        }
    }

    #[test]
    fn defaults_are_dr_tims_and_teleporting_stripes_are_refused() {
        let keys: StripedKeys = toml::from_str("").unwrap();
        let Surface::Striped(s) = keys.build().unwrap() else {
            panic!("not striped")
        };
        assert_eq!(s.width, 1.0);
        assert_eq!(
            *s.surfaces,
            [0.0, 0.9]
                .map(|g| Surface::Coloured(crate::surfaces::Coloured::shiny(Colour::splat(g))))
        );
        let keys: Result<StripedKeys, _> = toml::from_str(
            "surfaces = [{ type = \"teleporting\", destination = \"x\" }, { type = \"mirror\" }]",
        );
        let err = keys.unwrap().build().unwrap_err();
        assert!(err.contains("teleporting"), "{err}");
    }
}
