//! Either-or surfaces and holey surfaces: a black-and-white picture, the mask, chooses one of
//! two surfaces at each point of the shape's surface coordinates (Dr TIM's `EitherOrSurface`);
//! a holey surface is one whose other choice is a hole (its `HoleySurface`).

use glam::DVec2;
use serde::Deserialize;

use super::{greys, part, parts_pictures, two_parts};
use crate::geometry::Interaction;
use crate::keys::{Array, NonZero, Vector2};
use crate::picture::{Picture, PictureFile};
use crate::surfaces::{Surface, SurfaceKeys, Transparent};

/// The blue level (of 1) below which a mask texel is dark, as Dr TIM's 127 of 255.
const DARK_BELOW: f64 = 127.0 / 255.0;

/// A mask on the rectangle `corner` to `corner + size` in surface coordinates (u, v), its
/// columns along u and its rows, from the top, along v (as picture surfaces map pictures).
#[derive(Debug, Clone, PartialEq)]
pub struct EitherOr {
    pub mask: Picture,
    pub corner: DVec2,
    /// Non-zero components; a negative one mirrors the mask along that coordinate.
    pub size: DVec2,
    /// `surfaces[0]` where the mask is dark (blue below 127/255), `surfaces[1]` where it is
    /// light; outside the rectangle the ray passes undeviated, as in Dr TIM.
    pub surfaces: Box<[Surface; 2]>,
}

/// What is outside the mask's rectangle, and in a holey surface's holes.
const HOLE: Surface = Surface::Transparent(Transparent {
    transmission_coefficient: 1.0,
});

impl EitherOr {
    /// The surface at the point the ray meets.
    pub fn surface_at(&self, at: &Interaction) -> &Surface {
        let p = (at.coordinates() - self.corner) / self.size;
        if !((0.0..1.0).contains(&p.x) && (0.0..1.0).contains(&p.y)) {
            return &HOLE;
        }
        let dark = self.mask.at(p.x, 1.0 - p.y).z < DARK_BELOW;
        &self.surfaces[usize::from(!dark)]
    }
}

/// The either-or surface of the mask keys either-or and holey surfaces share: `file`, and
/// the rectangle `corner` (default [0, 0]) and `size` (default [1, 1]), as a picture
/// surface's.
fn either_or(
    file: PictureFile,
    corner: Option<Vector2>,
    size: Option<Array<NonZero, 2>>,
    surfaces: [Surface; 2],
) -> Result<Surface, String> {
    Ok(Surface::EitherOr(EitherOr {
        mask: file.opened()?,
        corner: corner.map_or(DVec2::ZERO, |c| c.0),
        size: size.map_or(DVec2::ONE, |Array([u, v])| DVec2::new(u.0, v.0)),
        surfaces: Box::new(surfaces),
    }))
}

/// `type = "either-or"`: `surfaces = [DARK, LIGHT]` (default matt black and matt white: the
/// mask itself; Dr TIM's class has no GUI) and the mask keys.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EitherOrKeys {
    file: PictureFile,
    corner: Option<Vector2>,
    size: Option<Array<NonZero, 2>>,
    surfaces: Option<Box<[SurfaceKeys; 2]>>,
}

impl EitherOrKeys {
    /// The picture files it names: the mask's and its parts'.
    pub fn pictures(&mut self) -> Vec<&mut PictureFile> {
        let mut files = parts_pictures(&mut self.surfaces);
        files.push(&mut self.file);
        files
    }

    pub fn build(self) -> Result<Surface, String> {
        let surfaces = two_parts(self.surfaces, greys([0.0, 1.0], false), "either-or surface")?;
        either_or(self.file, self.corner, self.size, *surfaces)
    }
}

/// Which parts of a mask are holes.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(rename_all = "kebab-case")]
enum Holes {
    Dark,
    Light,
}

/// `type = "holey"`: `surface` (required) with holes where the mask is `holes = "dark"` (the
/// default, Dr TIM's `surfaceTypeCorrespondingToHole` 0) or `"light"`, and the mask keys.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HoleyKeys {
    file: PictureFile,
    corner: Option<Vector2>,
    size: Option<Array<NonZero, 2>>,
    surface: Box<SurfaceKeys>,
    holes: Option<Holes>,
}

impl HoleyKeys {
    /// The picture files it names: the mask's and the surface's.
    pub fn pictures(&mut self) -> Vec<&mut PictureFile> {
        std::iter::once(&mut self.file)
            .chain(self.surface.pictures())
            .collect()
    }

    pub fn build(self) -> Result<Surface, String> {
        let surface = part(*self.surface, "a holey surface")?;
        let surfaces = match self.holes.unwrap_or(Holes::Dark) {
            Holes::Dark => [HOLE, surface],
            Holes::Light => [surface, HOLE],
        };
        either_or(self.file, self.corner, self.size, surfaces)
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;
    use crate::geometry::{Plane, Shape};
    use crate::math::Colour;
    use crate::surfaces::Coloured;
    use crate::surfaces::tests::meet;

    /// A 2 × 1 mask: black on the left, white on the right, on the rectangle from (1, 1)
    /// spanning (2, 1) of the plane z = 0 (u along x, v along y).
    fn mask_surface(surfaces: [Surface; 2]) -> EitherOr {
        EitherOr {
            mask: Picture::new(2, 1, vec![[0.0; 3], [1.0; 3]]),
            corner: DVec2::ONE,
            size: DVec2::new(2.0, 1.0),
            surfaces: Box::new(surfaces),
        }
    }

    fn surface_at(e: &EitherOr, x: f64, y: f64) -> Surface {
        let plane = Shape::Plane(Plane::new(DVec3::ZERO, DVec3::Z, DVec3::X).unwrap());
        e.surface_at(&meet(&plane, DVec3::new(x, y, 1.0), -DVec3::Z))
            .clone()
    }

    fn grey(g: f64) -> Surface {
        Surface::Coloured(Coloured::matt(Colour::splat(g)))
    }

    /// The left half of the rectangle (x from 1 to 2) is the mask's black column, the right
    /// half its white one; outside, the ray passes.
    #[test]
    fn the_mask_chooses_the_surface_and_outside_passes() {
        let e = mask_surface([grey(0.2), grey(0.8)]);
        assert_eq!(surface_at(&e, 1.5, 1.5), grey(0.2));
        assert_eq!(surface_at(&e, 2.5, 1.5), grey(0.8));
        assert_eq!(surface_at(&e, 0.5, 1.5), HOLE);
        assert_eq!(surface_at(&e, 1.5, 2.5), HOLE);
    }

    /// A holey mirror with dark holes: a hole on the left, the mirror on the right; with light
    /// holes the other way round.
    #[test]
    fn holes_are_where_the_mask_says() {
        let keys = |holes: &str| -> HoleyKeys {
            toml::from_str(&format!(
                "file = \"m.png\"\nsurface = {{ type = \"mirror\" }}\nholes = \"{holes}\""
            ))
            .unwrap()
        };
        for (holes, left_is_hole) in [("dark", true), ("light", false)] {
            let mut k = keys(holes);
            k.file.picture = Some(Picture::new(2, 1, vec![[0.0; 3], [1.0; 3]]));
            k.corner = Some(Vector2(DVec2::ONE));
            k.size = Some(Array([NonZero(2.0), NonZero(1.0)]));
            let Surface::EitherOr(e) = k.build().unwrap() else {
                panic!("an either-or surface")
            };
            assert_eq!(surface_at(&e, 1.5, 1.5) == HOLE, left_is_hole, "{holes}");
            assert_eq!(surface_at(&e, 2.5, 1.5) == HOLE, !left_is_hole, "{holes}");
        }
    }
}
