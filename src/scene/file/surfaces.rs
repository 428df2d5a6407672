//! Surface properties in scene files (`surface = { type = ..., ... }`).

use serde::Deserialize;

use super::values::{Coefficient, Finite, InnerRadius, LensDistance, Positive, Rgb};
use crate::surfaces::lenses::{Ggrin, GradientIndex, IndexProfile, Lens, LensLaw, TableProfile};
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
    #[serde(rename = "luneburg-lens", alias = "luneburg_lens")]
    LuneburgLens {
        method: Option<Method>,
        #[serde(flatten)]
        options: LensOptions,
    },
    #[serde(rename = "eaton-lens", alias = "eaton_lens")]
    EatonLens {
        method: Option<Method>,
        #[serde(flatten)]
        options: LensOptions,
    },
    #[serde(rename = "maxwell-fisheye-lens", alias = "maxwell_fisheye_lens")]
    MaxwellFisheyeLens {
        method: Option<Method>,
        #[serde(flatten)]
        options: LensOptions,
    },
    #[serde(rename = "ggrin-lens", alias = "ggrin_lens")]
    GgrinLens {
        r: LensDistance,
        r_prime: LensDistance,
        phi_deg: Finite,
        #[serde(flatten)]
        options: LensOptions,
    },
    #[serde(rename = "gradient-index-lens", alias = "gradient_index_lens")]
    GradientIndexLens {
        rho: Vec<Finite>,
        n: Vec<Finite>,
        #[serde(flatten)]
        options: LensOptions,
    },
}

/// How a Luneburg, Eaton or Maxwell-fisheye lens is rendered.
#[derive(Debug, Clone, Copy, Default, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub(super) enum Method {
    /// The paper's closed-form entry-to-exit map.
    #[default]
    Mapping,
    /// The ray equation integrated through the index profile.
    Integration,
}

/// The keys every lens has.
#[derive(Debug, Deserialize)]
pub(super) struct LensOptions {
    invisible_radius: Option<InnerRadius>,
    index_ratio: Option<Positive>,
    #[serde(alias = "transmission")]
    transmission_coefficient: Option<Coefficient>,
}

impl LensOptions {
    fn lens(self, law: LensLaw) -> Surface {
        Surface::Lens(Lens {
            law,
            invisible_radius: self.invisible_radius.map_or(0.0, |r| r.0),
            index_ratio: self.index_ratio.map_or(1.0, |n| n.0),
            transmission_coefficient: self.transmission_coefficient.map_or(1.0, |c| c.0),
        })
    }
}

impl Method {
    /// The closed-form `mapping`, or integration through `profile`.
    fn law(self, mapping: LensLaw, profile: IndexProfile) -> LensLaw {
        match self {
            Method::Mapping => mapping,
            Method::Integration => LensLaw::GradientIndex(GradientIndex { profile }),
        }
    }
}

impl SurfaceSection {
    /// The surface; an error for a table profile that is not one.
    pub(super) fn build(self) -> Result<Surface, String> {
        Ok(match self {
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
                    surfaces: Box::new([a.build()?, b.build()?]),
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
            SurfaceSection::LuneburgLens { method, options } => options.lens(
                method
                    .unwrap_or_default()
                    .law(LensLaw::Luneburg, IndexProfile::Luneburg),
            ),
            SurfaceSection::EatonLens { method, options } => options.lens(
                method
                    .unwrap_or_default()
                    .law(LensLaw::Eaton, IndexProfile::Eaton),
            ),
            SurfaceSection::MaxwellFisheyeLens { method, options } => options.lens(
                method
                    .unwrap_or_default()
                    .law(LensLaw::MaxwellFisheye, IndexProfile::MaxwellFisheye),
            ),
            SurfaceSection::GgrinLens {
                r,
                r_prime,
                phi_deg,
                options,
            } => options.lens(LensLaw::Ggrin(Ggrin {
                r: r.0,
                r_prime: r_prime.0,
                phi: phi_deg.0.to_radians(),
            })),
            SurfaceSection::GradientIndexLens { rho, n, options } => {
                let values = |v: Vec<Finite>| v.into_iter().map(|x| x.0).collect();
                let table = TableProfile::new(values(rho), values(n))
                    .map_err(|e| format!("gradient-index-lens profile: {e}"))?;
                options.lens(LensLaw::GradientIndex(GradientIndex {
                    profile: IndexProfile::Table(table),
                }))
            }
        })
    }
}
