//! Picture surfaces: a picture mapped onto the shape's surface coordinates (Dr TIM's
//! `PictureSurface`, `PictureSurfaceDiffuse` and `PictureSurfaceSpecular`).

use glam::DVec2;
use serde::Deserialize;

use super::{Coloured, Redirection, Surface};
use crate::geometry::Interaction;
use crate::keys::{Array, NonZero, Rgb, Vector2};
use crate::math::Colour;
use crate::picture::{Picture, PictureFile};

/// How a picture surface's texels are lit, after Dr TIM's three classes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Lighting {
    /// `PictureSurfaceDiffuse`: the texel is the diffuse colour, lit by the lights.
    Diffuse,
    /// `PictureSurfaceSpecular`: the texel is the specular colour, lit by the lights.
    Specular,
    /// `PictureSurface`: the texel is seen whatever the lighting.
    LightIndependent,
}

/// A picture whose rectangle `corner` to `corner + size` in surface coordinates (u, v) holds
/// the picture, u to its right and, as in Dr TIM, v down its rows from the top (upright on a
/// sphere, whose v grows from its top).
#[derive(Debug, Clone, PartialEq)]
pub struct PictureSurface {
    pub picture: Picture,
    pub corner: DVec2,
    /// Non-zero components; a negative one mirrors the picture along that coordinate.
    pub size: DVec2,
    /// Whether the picture repeats over the whole surface; if not, the surface is perfectly
    /// transparent outside the rectangle, as in Dr TIM.
    pub tiled: bool,
    pub lighting: Lighting,
    /// The colour the texel does not give: the specular colour of diffuse lighting, the
    /// diffuse colour of specular lighting.
    pub other: Colour,
}

impl PictureSurface {
    /// The picture coordinates of surface coordinates `uv`: [0, 1]² on the rectangle, from the
    /// picture's top-left corner.
    pub fn picture_coordinates(&self, uv: DVec2) -> DVec2 {
        (uv - self.corner) / self.size
    }

    pub fn redirect(&self, at: &Interaction) -> Redirection<'static> {
        let p = self.picture_coordinates(at.coordinates());
        let within = |t: f64| (0.0..1.0).contains(&t);
        let outside = !(within(p.x) && within(p.y));
        if outside && !self.tiled {
            return Redirection::Leaves {
                direction: at.ray.direction,
                factor: Colour::ONE,
            };
        }
        let texel = self.picture.at(p.x, 1.0 - p.y);
        match self.lighting {
            Lighting::Diffuse => Redirection::Lit(Coloured {
                diffuse: texel,
                specular: self.other,
            }),
            Lighting::Specular => Redirection::Lit(Coloured {
                diffuse: self.other,
                specular: texel,
            }),
            Lighting::LightIndependent => Redirection::Emits(texel),
        }
    }
}

/// `type = "picture"`: the picture in `file` (PNG, JPEG, OpenEXR, Radiance HDR) on the
/// rectangle from `corner` spanning `size` in the shape's surface coordinates, where not given
/// Dr TIM's GUI's "Picture": corner (0, 0), size (1, 1), tiled, diffuse lighting with a black
/// specular colour. `specular` (diffuse lighting) and `diffuse` (specular lighting) give the
/// other colour, black where not given. Dr TIM's `PictureSurfaceDiffuse` scales its indices by
/// width − 1 and height − 1 (the last column and row only on the far edges); timbre gives each
/// texel an equal share of the rectangle, as `PictureSurface` does.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PictureKeys {
    file: PictureFile,
    corner: Option<Vector2>,
    size: Option<Array<NonZero, 2>>,
    tiled: Option<bool>,
    lighting: Option<Lighting>,
    specular: Option<Rgb>,
    diffuse: Option<Rgb>,
}

impl PictureKeys {
    /// The picture file it names.
    pub fn pictures(&mut self) -> Vec<&mut PictureFile> {
        vec![&mut self.file]
    }

    pub fn build(self) -> Result<Surface, String> {
        let lighting = self.lighting.unwrap_or(Lighting::Diffuse);
        let other = match (lighting, self.specular, self.diffuse) {
            (Lighting::Diffuse, c, None) | (Lighting::Specular, None, c) => {
                c.map_or(Colour::ZERO, |c| c.0)
            }
            (Lighting::LightIndependent, None, None) => Colour::ZERO,
            _ => {
                return Err(
                    "`specular` goes with lighting = \"diffuse\" (the default), `diffuse` with \
                     lighting = \"specular\", neither with \"light-independent\""
                        .into(),
                );
            }
        };
        let size = self
            .size
            .map_or(DVec2::ONE, |Array([u, v])| DVec2::new(u.0, v.0));
        Ok(Surface::Picture(PictureSurface {
            picture: self.file.opened()?,
            corner: self.corner.map_or(DVec2::ZERO, |c| c.0),
            size,
            tiled: self.tiled.unwrap_or(true),
            lighting,
            other,
        }))
    }
}

#[cfg(test)]
mod tests {
    use std::f64::consts::PI;

    use glam::DVec3;

    use super::*;
    use crate::geometry::{Plane, Shape, Sphere};
    use crate::surfaces::tests::meet;

    /// A 2 × 2 picture: red top left, green top right, blue bottom left, white bottom right.
    fn quarters() -> Picture {
        Picture::new(
            2,
            2,
            vec![
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [0.0, 0.0, 1.0],
                [1.0, 1.0, 1.0],
            ],
        )
    }

    const RED: Colour = Colour::new(1.0, 0.0, 0.0);
    const GREEN: Colour = Colour::new(0.0, 1.0, 0.0);
    const BLUE: Colour = Colour::new(0.0, 0.0, 1.0);

    fn surface(tiled: bool, lighting: Lighting) -> PictureSurface {
        PictureSurface {
            picture: quarters(),
            corner: DVec2::new(1.0, -1.0),
            size: DVec2::new(2.0, 4.0),
            tiled,
            lighting,
            other: Colour::splat(0.25),
        }
    }

    /// On the plane z = 0 (u = x, v = y) the rectangle from (1, −1) of size (2, 4) holds the
    /// picture, its top row at v = −1: (1.5, 0) is in its top-left quarter (red), (2.5, 0) top
    /// right (green), (1.5, 2) bottom left (blue), (2.9, 2.9) bottom right (white). Tiled,
    /// (3.5, 0) is the next repeat's top left, (−0.5, −4) = (1.5, 0) − (2, 4) too; not tiled,
    /// a ray there goes on undeviated with all its light.
    #[test]
    fn the_rectangle_holds_the_picture_rows_down_v() {
        let plane = Shape::Plane(Plane::new(DVec3::ZERO, DVec3::Z, DVec3::X).unwrap());
        let d = DVec3::new(0.1, 0.2, -1.0).normalize();
        let at = |x: f64, y: f64| meet(&plane, DVec3::new(x, y, 0.0) - 3.0 * d, d);
        let tiled = surface(true, Lighting::LightIndependent);
        let emits = |s: &PictureSurface, x, y| s.redirect(&at(x, y));
        assert_eq!(emits(&tiled, 1.5, 0.0), Redirection::Emits(RED));
        assert_eq!(emits(&tiled, 2.5, 0.0), Redirection::Emits(GREEN));
        assert_eq!(emits(&tiled, 1.5, 2.0), Redirection::Emits(BLUE));
        assert_eq!(emits(&tiled, 2.9, 2.9), Redirection::Emits(Colour::ONE));
        assert_eq!(emits(&tiled, 3.5, 0.0), Redirection::Emits(RED));
        assert_eq!(emits(&tiled, -0.5, -4.0), Redirection::Emits(RED));
        let single = surface(false, Lighting::LightIndependent);
        assert_eq!(emits(&single, 1.5, 0.0), Redirection::Emits(RED));
        for (x, y) in [(3.5, 2.0), (0.9, 0.0), (1.5, 3.1), (1.5, -1.1)] {
            match emits(&single, x, y) {
                Redirection::Leaves { direction, factor } => {
                    assert!((direction - d).length() < 1e-15);
                    assert_eq!(factor, Colour::ONE);
                }
                other => panic!("({x}, {y}): {other:?}"),
            }
        }
    }

    /// A negative size mirrors: with size (−2, 4) from corner (1, −1) the rectangle spans x
    /// from 1 down to −1, the picture's left column at x = 0.5, its right at x = −0.5.
    #[test]
    fn a_negative_size_mirrors_the_picture() {
        let s = PictureSurface {
            size: DVec2::new(-2.0, 4.0),
            ..surface(false, Lighting::LightIndependent)
        };
        // u' = (x − 1)/(−2): x = 0.5 gives 0.25 (left column), x = −0.5 gives 0.75 (right).
        assert_eq!(
            s.picture_coordinates(DVec2::new(0.5, 0.0)),
            DVec2::new(0.25, 0.25)
        );
        let plane = Shape::Plane(Plane::new(DVec3::ZERO, DVec3::Z, DVec3::X).unwrap());
        let at = |x: f64| meet(&plane, DVec3::new(x, 0.0, 1.0), -DVec3::Z);
        assert_eq!(s.redirect(&at(0.5)), Redirection::Emits(RED));
        assert_eq!(s.redirect(&at(-0.5)), Redirection::Emits(GREEN));
    }

    /// Diffuse lighting: the texel is the diffuse colour, `other` the specular; specular
    /// lighting the other way round. On the unit sphere (u = φ, v = θ from +y) with the
    /// picture on the whole of it (corner (−π, 0), size (2π, π)), the point (0.3, 0.2, 0.933)
    /// has φ > 0 (the right half) and θ < π/2 (the top half): green.
    #[test]
    fn lighting_puts_the_texel_where_its_class_does() {
        let plane = Shape::Plane(Plane::new(DVec3::ZERO, DVec3::Z, DVec3::X).unwrap());
        let at = meet(&plane, DVec3::new(1.5, 0.0, 1.0), -DVec3::Z);
        let quarter = Colour::splat(0.25);
        assert_eq!(
            surface(true, Lighting::Diffuse).redirect(&at),
            Redirection::Lit(Coloured {
                diffuse: RED,
                specular: quarter
            })
        );
        assert_eq!(
            surface(true, Lighting::Specular).redirect(&at),
            Redirection::Lit(Coloured {
                diffuse: quarter,
                specular: RED
            })
        );
        let sphere = Shape::Sphere(Sphere::new(DVec3::ZERO, 1.0).unwrap());
        let hit = meet(&sphere, DVec3::new(0.3, 0.2, 5.0), -DVec3::Z);
        let s = PictureSurface {
            corner: DVec2::new(-PI, 0.0),
            size: DVec2::new(2.0 * PI, PI),
            ..surface(false, Lighting::LightIndependent)
        };
        assert_eq!(s.redirect(&hit), Redirection::Emits(GREEN));
    }

    fn keys(text: &str) -> Result<Surface, String> {
        let mut keys: PictureKeys = toml::from_str(text).map_err(|e| e.to_string())?;
        keys.file.picture = Some(quarters());
        keys.build()
    }

    /// Dr TIM's GUI defaults; the colour keys only with their lighting; zero sizes refused.
    #[test]
    fn keys_default_to_dr_tims_gui() {
        let Surface::Picture(p) = keys("file = \"q.png\"").unwrap() else {
            panic!("a picture surface")
        };
        assert_eq!(
            (p.corner, p.size, p.tiled, p.lighting, p.other),
            (
                DVec2::ZERO,
                DVec2::ONE,
                true,
                Lighting::Diffuse,
                Colour::ZERO
            )
        );
        let Surface::Picture(p) =
            keys("file = \"q.png\"\nlighting = \"specular\"\ndiffuse = [0.5, 0.5, 0.5]").unwrap()
        else {
            panic!("a picture surface")
        };
        assert_eq!(p.other, Colour::splat(0.5));
        for bad in [
            "lighting = \"specular\"\nspecular = [1, 1, 1]",
            "diffuse = [1, 1, 1]",
            "lighting = \"light-independent\"\nspecular = [1, 1, 1]",
        ] {
            let e = keys(&format!("file = \"q.png\"\n{bad}")).unwrap_err();
            assert!(e.contains("`specular` goes with"), "{e}");
        }
        let e = keys("file = \"q.png\"\nsize = [1, 0]").unwrap_err();
        assert!(e.contains("non-zero"), "{e}");
        let e = keys("file = \"q.png\"\nlighting = \"bright\"").unwrap_err();
        assert!(e.contains("light-independent"), "{e}");
    }
}
