//! The appearance of a mesh part from its file's material (Wavefront MTL; no Dr TIM class:
//! Dr TIM reads no mesh files). An opaque material (`d` = 1) is simply [`Coloured`] (`Kd`,
//! `Ks`); a partly transparent one is this kind: its colour weighted by `d`, mixed with a
//! straight, lossless pass weighted by 1 − `d` (MTL's "dissolve"; `Ni` is not used for
//! refraction). A material with a texture (`map_Kd`) is [`Textured`]: `Kd` times the texel
//! at the hit's texture coordinates.

use super::{Coloured, Redirection, Surface, Transparent, Weighted};
use crate::geometry::{Interaction, Shape};
use crate::math::Colour;
use crate::mesh::Material;
use crate::picture::Picture;

/// A mesh's own vertex colours (PLY `red green blue`), interpolated barycentrically at the
/// hit: a matt surface of that colour (black on a shape without them).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VertexColours;

impl VertexColours {
    pub fn redirect(&self, at: &Interaction) -> Redirection<'static> {
        let colour = match at.shape {
            Shape::TriangleMesh(m) => m.colour_at(at.local_point(), at.hit.prim),
            _ => None,
        };
        Redirection::Lit(Coloured::matt(colour.unwrap_or(Colour::ZERO)))
    }
}

/// A textured material: its colours, the diffuse one multiplied by the picture's texel at the
/// hit's surface coordinates (a mesh's interpolated texture coordinates).
#[derive(Debug, Clone, PartialEq)]
pub struct Textured {
    pub coloured: Coloured,
    pub picture: Picture,
}

impl Textured {
    pub fn redirect(&self, at: &Interaction) -> Redirection<'static> {
        let c = at.coordinates();
        Redirection::Lit(Coloured {
            diffuse: self.coloured.diffuse * self.picture.at(c.x, c.y),
            specular: self.coloured.specular,
        })
    }
}

/// A dissolved (partly transparent) material: the parts [`Surface::redirect`] mixes.
#[derive(Debug, Clone, PartialEq)]
pub struct Dissolved {
    pub parts: Box<[Weighted; 2]>,
}

/// The surface a mesh part with `material` shows, with its texture's picture if it has one.
pub fn from_material(material: &Material, texture: Option<Picture>) -> Surface {
    let coloured = Coloured {
        diffuse: material.diffuse,
        specular: material.specular,
    };
    let opaque = match texture {
        Some(picture) => Surface::Textured(Textured { coloured, picture }),
        None => Surface::Coloured(coloured),
    };
    if material.dissolve == 1.0 {
        return opaque;
    }
    let d = material.dissolve;
    Surface::Dissolved(Dissolved {
        parts: Box::new([
            Weighted {
                weight: Colour::splat(d),
                surface: opaque,
            },
            Weighted {
                weight: Colour::splat(1.0 - d),
                surface: Surface::Transparent(Transparent {
                    transmission_coefficient: 1.0,
                }),
            },
        ]),
    })
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;

    fn material(dissolve: f64) -> Material {
        Material {
            name: "m".into(),
            diffuse: DVec3::new(0.5, 0.25, 1.0),
            specular: DVec3::new(0.1, 0.2, 0.3),
            dissolve,
            diffuse_map: None,
        }
    }

    #[test]
    fn an_opaque_material_is_its_kd_and_ks() {
        assert_eq!(
            from_material(&material(1.0), None),
            Surface::Coloured(Coloured {
                diffuse: DVec3::new(0.5, 0.25, 1.0),
                specular: DVec3::new(0.1, 0.2, 0.3),
            })
        );
    }

    #[test]
    fn a_dissolved_material_mixes_its_colour_and_a_straight_pass_by_d() {
        let Surface::Dissolved(d) = from_material(&material(0.25), None) else {
            panic!("not dissolved");
        };
        assert_eq!(d.parts[0].weight, Colour::splat(0.25));
        assert_eq!(d.parts[1].weight, Colour::splat(0.75));
        assert!(matches!(d.parts[0].surface, Surface::Coloured(c) if c.diffuse.x == 0.5));
        assert_eq!(
            d.parts[1].surface,
            Surface::Transparent(Transparent {
                transmission_coefficient: 1.0
            })
        );
    }
}
