//! Surface properties in scene files (`surface = { type = ..., ... }`).

use serde::Deserialize;

use super::values::{Coefficient, Positive, Rgb};
use crate::surfaces::{Chequerboard, Colour, Coloured, Mirror, Refractive, Surface, Transparent};

#[derive(Debug, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub(super) enum SurfaceSection {
    Coloured {
        diffuse: Rgb,
        specular: Option<Rgb>,
    },
    Shiny {
        colour: Rgb,
    },
    Matt {
        colour: Rgb,
    },
    ConstantColour {
        colour: Rgb,
    },
    Chequerboard {
        tile_width: Option<Positive>,
        surfaces: Box<[SurfaceSection; 2]>,
    },
    Mirror {
        #[serde(alias = "reflection")]
        reflection_coefficient: Option<Coefficient>,
    },
    Refractive {
        index_ratio: Positive,
        #[serde(alias = "transmission")]
        transmission_coefficient: Option<Coefficient>,
    },
    Transparent {
        #[serde(alias = "transmission")]
        transmission_coefficient: Option<Coefficient>,
    },
}

impl SurfaceSection {
    pub(super) fn build(self) -> Surface {
        match self {
            SurfaceSection::Coloured { diffuse, specular } => Surface::Coloured(Coloured {
                diffuse: diffuse.0,
                specular: specular.map_or(Colour::ZERO, |s| s.0),
            }),
            SurfaceSection::Shiny { colour } => Surface::Coloured(Coloured::shiny(colour.0)),
            SurfaceSection::Matt { colour } => Surface::Coloured(Coloured::matt(colour.0)),
            SurfaceSection::ConstantColour { colour } => Surface::ConstantColour(colour.0),
            SurfaceSection::Chequerboard {
                tile_width,
                surfaces,
            } => {
                let [a, b] = *surfaces;
                Surface::Chequerboard(Chequerboard {
                    tile_width: tile_width.map_or(1.0, |w| w.0),
                    surfaces: Box::new([a.build(), b.build()]),
                })
            }
            SurfaceSection::Mirror {
                reflection_coefficient,
            } => Surface::Mirror(Mirror {
                reflection_coefficient: reflection_coefficient.map_or(1.0, |c| c.0),
            }),
            SurfaceSection::Refractive {
                index_ratio,
                transmission_coefficient,
            } => Surface::Refractive(Refractive {
                index_ratio: index_ratio.0,
                transmission_coefficient: transmission_coefficient.map_or(1.0, |c| c.0),
            }),
            SurfaceSection::Transparent {
                transmission_coefficient,
            } => Surface::Transparent(Transparent {
                transmission_coefficient: transmission_coefficient.map_or(1.0, |c| c.0),
            }),
        }
    }
}
