//! Two-sided: one surface for rays arriving from outside, another for rays from inside (Dr
//! TIM's `TwoSidedSurface`).

use glam::DVec3;
use serde::Deserialize;

use super::part;
use crate::geometry::Interaction;
use crate::math::Colour;
use crate::picture::PictureFile;
use crate::surfaces::{Coloured, Redirection, Surface, SurfaceKeys};

#[derive(Debug, Clone, PartialEq)]
pub struct TwoSided {
    /// `[inside, outside]`: the inside for rays travelling outwards, the outside for rays
    /// travelling inwards.
    pub sides: Box<[Surface; 2]>,
}

impl TwoSided {
    /// The side the ray meets: the outside if it travels inwards (against the outward normal).
    pub fn side(&self, at: &Interaction) -> &Surface {
        &self.sides[usize::from(at.ray.direction.dot(at.normal()) <= 0.0)]
    }

    pub fn redirect<'a>(
        &'a self,
        at: &Interaction,
        inside: &mut dyn FnMut(DVec3),
    ) -> Redirection<'a> {
        self.side(at).redirect(at, inside)
    }
}

/// `type = "two-sided"`: the `outside` surface for rays arriving from outside, the `inside`
/// one for rays from inside; where not given, those of Dr TIM's GUI: black matt inside, white
/// matt outside.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TwoSidedKeys {
    inside: Option<Box<SurfaceKeys>>,
    outside: Option<Box<SurfaceKeys>>,
}

impl TwoSidedKeys {
    /// The picture files its sides name.
    pub fn pictures(&mut self) -> Vec<&mut PictureFile> {
        [&mut self.inside, &mut self.outside]
            .into_iter()
            .flatten()
            .flat_map(|s| s.pictures())
            .collect()
    }

    pub fn build(self) -> Result<Surface, String> {
        let side = |keys: Option<Box<SurfaceKeys>>, grey: f64| match keys {
            None => Ok(Surface::Coloured(Coloured::matt(Colour::splat(grey)))),
            Some(keys) => part(*keys, "a side of a two-sided surface"),
        };
        Ok(Surface::TwoSided(TwoSided {
            sides: Box::new([side(self.inside, 0.0)?, side(self.outside, 1.0)?]),
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Shape, Sphere};
    use crate::surfaces::tests::meet;

    /// On a unit sphere, a ray from far outside meets the outside surface (red), a ray from
    /// the centre the inside one (blue); the defaults are black matt inside, white matt out.
    #[test]
    fn rays_from_outside_meet_the_outside_and_from_inside_the_inside() {
        let (red, blue) = (Colour::new(1.0, 0.0, 0.0), Colour::new(0.0, 0.0, 1.0));
        let two = Surface::TwoSided(TwoSided {
            sides: Box::new([Surface::ConstantColour(blue), Surface::ConstantColour(red)]),
        });
        let sphere = Shape::Sphere(Sphere::new(DVec3::ZERO, 1.0).unwrap());
        let from_outside = meet(&sphere, DVec3::new(0.1, 0.2, -4.0), DVec3::Z);
        let from_inside = meet(&sphere, DVec3::ZERO, DVec3::new(0.3, 0.1, -0.2));
        assert_eq!(
            two.redirect(&from_outside, &mut |_| {}),
            Redirection::Emits(red)
        );
        assert_eq!(
            two.redirect(&from_inside, &mut |_| {}),
            Redirection::Emits(blue)
        );
        let keys: TwoSidedKeys = toml::from_str("").unwrap();
        let Ok(Surface::TwoSided(default)) = keys.build() else {
            panic!("a two-sided surface")
        };
        assert_eq!(
            *default.sides,
            [
                Surface::Coloured(Coloured::matt(Colour::ZERO)),
                Surface::Coloured(Coloured::matt(Colour::ONE))
            ]
        );
    }
}
