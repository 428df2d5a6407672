//! Layer stack: thin layers of different surfaces at the same point, met in order (Dr TIM's
//! `SurfacePropertyLayerStack` with its `InsideOfSurfacePropertyLayerStack`).

use serde::Deserialize;

use super::{EitherOr, SnellenChart, Striped, SurfaceTiling, UsafChart, part};
use crate::geometry::{Hit, Interaction};
use crate::math::Colour;
use crate::picture::PictureFile;
use crate::surfaces::metatoys::Pixels;
use crate::surfaces::{
    Coloured, ConfocalLensletArrays, Pixellation, Redirection, Surface, SurfaceKeys, Text,
};

/// Most passes through the layers of one stack at one point; a ray still inside after them
/// (bouncing between two mirror layers) is lost.
const MAX_PASSES: usize = 100;

#[derive(Debug, Clone, PartialEq)]
pub struct LayerStack {
    /// The first is met first by rays arriving from outside, the last by rays from inside.
    pub layers: Box<[Surface]>,
}

impl LayerStack {
    /// A ray arriving from outside meets layer 0 (from inside, the last); a layer that sends
    /// it on inwards (against the outward normal) passes it to the next layer, outwards to the
    /// previous one, until it leaves past either end with the product of the layers' factors.
    /// A layer that colours the ray ends it, its colours scaled by the factor so far (and
    /// shaded as seen along the arriving ray).
    pub fn redirect(&self, at: &Interaction) -> Redirection<'static> {
        let normal = at.normal();
        let inwards = |d: glam::DVec3| d.dot(normal) <= 0.0;
        let n = self.layers.len();
        let mut k = if inwards(at.ray.direction) { 0 } else { n - 1 };
        let mut here = *at;
        let mut factor = Colour::ONE;
        for _ in 0..MAX_PASSES {
            match self.layers[k].redirect(&here, &mut |_| {}) {
                Redirection::Lit(c) => {
                    return Redirection::Lit(Coloured {
                        diffuse: factor * c.diffuse,
                        specular: factor * c.specular,
                    });
                }
                Redirection::Emits(c) => return Redirection::Emits(factor * c),
                Redirection::Leaves {
                    direction,
                    factor: f,
                } => {
                    factor *= f;
                    let next = if inwards(direction) {
                        k.checked_add(1).filter(|&k| k < n)
                    } else {
                        k.checked_sub(1)
                    };
                    let Some(next) = next else {
                        return Redirection::Leaves { direction, factor };
                    };
                    k = next;
                    // The same point, met along the new direction.
                    here = Interaction {
                        ray: at.ray.continued(at.hit.t, direction),
                        hit: Hit { t: 0.0, ..at.hit },
                        ..*at
                    };
                }
                // Only the last layer may absorb: the ray goes on into the solid.
                Redirection::Absorbs {
                    absorption,
                    direction,
                    factor: f,
                } => {
                    return Redirection::Absorbs {
                        absorption,
                        direction,
                        factor: factor * f,
                    };
                }
                // Refused when the stack is built (see `check_layer`).
                Redirection::Lost
                | Redirection::Crosses { .. }
                | Redirection::Jumps { .. }
                | Redirection::Glows { .. }
                | Redirection::Mixes(_) => return Redirection::Lost,
            }
        }
        Redirection::Lost
    }
}

/// Refuses a layer that does not keep the ray at the point where it met the stack: one that
/// crosses the object or jumps elsewhere, absorbs (but as the innermost layer) or glows along
/// the way inside, or mixes several ways.
fn check_layer(layer: &Surface) -> Result<(), String> {
    let refuse = || {
        Err(format!(
            "a {} surface cannot be a layer of a layer stack (a layer must colour the ray or \
             send it on from the same point in one direction, without a ray offset; a tinted \
             solid may be the last layer)",
            layer.kind()
        ))
    };
    match layer {
        Surface::Lens(_)
        | Surface::ToShifter(_)
        | Surface::GradientIndexVolume(_)
        | Surface::Teleporting(_)
        | Surface::IdealisedDovePrismArray(_)
        | Surface::IdealThinSpacePlate(_)
        | Surface::SpaceShifting(_)
        | Surface::CollineationSurface(_)
        | Surface::TintedSolid(_)
        | Surface::GlowingCloud(_)
        | Surface::LightRayField(_)
        | Surface::SemiTransparent(_)
        | Surface::Average(_)
        | Surface::Rainbow(_)
        | Surface::Dissolved(_) => refuse(),
        // A ray offset moves the ray off the point.
        Surface::ConfocalLensletArrays(ConfocalLensletArrays {
            pixels: Some(Pixels {
                ray_offset: true, ..
            }),
            ..
        })
        | Surface::Pixellation(Pixellation {
            pixels: Pixels {
                ray_offset: true, ..
            },
        }) => refuse(),
        Surface::Chequerboard(c) => c.surfaces.iter().try_for_each(check_layer),
        Surface::TwoSided(t) => t.sides.iter().try_for_each(check_layer),
        Surface::LayerStack(s) => s.layers.iter().try_for_each(check_layer),
        Surface::Text(Text { surfaces, .. })
        | Surface::EitherOr(EitherOr { surfaces, .. })
        | Surface::UsafChart(UsafChart { surfaces, .. })
        | Surface::SnellenChart(SnellenChart { surfaces, .. }) => {
            surfaces.iter().try_for_each(check_layer)
        }
        Surface::Striped(Striped { surfaces, .. })
        | Surface::SurfaceTiling(SurfaceTiling { surfaces, .. }) => {
            surfaces.iter().try_for_each(check_layer)
        }
        Surface::Coloured(_)
        | Surface::ConstantColour(_)
        | Surface::Mirror(_)
        | Surface::Refractive(_)
        | Surface::Transparent(_)
        | Surface::ColourFilter(_)
        | Surface::MetricInterface(_)
        | Surface::ConfocalLensletArrays(_)
        | Surface::RayRotating(_)
        | Surface::RayRotatingInPlaneOfIncidence(_)
        | Surface::DerivativeControl(_)
        | Surface::Pixellation(_)
        | Surface::ComplexMetarefraction(_)
        | Surface::VariableEtaConfocalLensletArrays(_)
        | Surface::RayFlipping(_)
        | Surface::PhaseHologram(_)
        | Surface::PointToPointImagingHologram(_)
        | Surface::PhaseConjugating(_)
        | Surface::LorentzWindow(_)
        | Surface::GalileoWindow(_)
        | Surface::IdealThinLens(_)
        | Surface::IdealThinMirror(_)
        | Surface::IdealThinLensletArray(_)
        | Surface::Glens(_)
        | Surface::TimeDependentColour(_)
        | Surface::PositionDependentColour(_)
        | Surface::HueBrightnessGradient(_)
        | Surface::Picture(_)
        | Surface::ImageSky(_)
        | Surface::Textured(_)
        | Surface::VertexColours(_) => Ok(()),
    }
}

/// `type = "layer-stack"`: `layers` (at least one), the first met first from outside.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LayerStackKeys {
    layers: Vec<SurfaceKeys>,
}

impl LayerStackKeys {
    /// The picture files its layers name.
    pub fn pictures(&mut self) -> Vec<&mut PictureFile> {
        self.layers
            .iter_mut()
            .flat_map(SurfaceKeys::pictures)
            .collect()
    }

    pub fn build(self) -> Result<Surface, String> {
        if self.layers.is_empty() {
            return Err("a layer stack needs at least one layer".into());
        }
        let last = self.layers.len() - 1;
        let layers = self
            .layers
            .into_iter()
            .enumerate()
            .map(|(k, keys)| {
                let layer = part(keys, "a layer of a layer stack")?;
                // The innermost layer may be a tinted solid: the stack's inside absorbs.
                if !(k == last && matches!(layer, Surface::TintedSolid(_))) {
                    check_layer(&layer)?;
                }
                Ok(layer)
            })
            .collect::<Result<_, String>>()?;
        Ok(Surface::LayerStack(LayerStack { layers }))
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;
    use crate::geometry::{Plane, Shape};
    use crate::surfaces::Mirror;
    use crate::surfaces::tests::meet;

    fn filter(r: f64, g: f64, b: f64) -> Surface {
        Surface::ColourFilter(crate::surfaces::ColourFilter {
            transmission: Colour::new(r, g, b),
        })
    }

    fn plane() -> Shape {
        Shape::Plane(Plane::new(DVec3::ZERO, DVec3::Z, DVec3::X).unwrap())
    }

    /// Two filters in a stack pass the product of their channels, from either side.
    #[test]
    fn filters_in_a_stack_multiply() {
        let stack = LayerStack {
            layers: Box::new([filter(0.5, 1.0, 0.2), filter(0.5, 0.1, 1.0)]),
        };
        let plane = plane();
        for z in [2.0, -2.0] {
            let d = DVec3::new(0.1, 0.3, -z);
            let at = meet(&plane, DVec3::new(0.0, 0.0, z), d);
            let Redirection::Leaves { direction, factor } = stack.redirect(&at) else {
                panic!("the ray goes through")
            };
            assert!((direction - d.normalize()).length() < 1e-15);
            assert_eq!(factor, Colour::new(0.25, 0.1, 0.2));
        }
    }

    /// A red filter over a mirror: a ray from outside passes the filter, is reflected, passes
    /// the filter again on its way out, so keeps 0.5² of red and 0.9 of it is reflected; a
    /// ray from inside meets the mirror first, is reflected back inside and never meets the
    /// filter. A ray from outside on a stack of a filter over a colour sees the colour through
    /// the filter once.
    #[test]
    fn a_filter_over_a_mirror_filters_twice() {
        let mirror = Surface::Mirror(Mirror {
            reflection_coefficient: 0.9,
        });
        let stack = LayerStack {
            layers: Box::new([filter(0.5, 0.0, 0.0), mirror]),
        };
        let plane = plane();
        let d = DVec3::new(0.3, 0.0, -1.0).normalize();
        let at = meet(&plane, DVec3::new(0.0, 0.0, 2.0), d);
        let Redirection::Leaves { direction, factor } = stack.redirect(&at) else {
            panic!("reflected")
        };
        assert!((direction - DVec3::new(d.x, d.y, -d.z)).length() < 1e-15);
        assert!(
            (factor - Colour::new(0.225, 0.0, 0.0)).length() < 1e-15,
            "{factor}"
        );
        let at = meet(&plane, DVec3::new(0.0, 0.0, -2.0), -d);
        let Redirection::Leaves { direction, factor } = stack.redirect(&at) else {
            panic!("reflected")
        };
        assert!((direction - DVec3::new(-d.x, -d.y, d.z)).length() < 1e-15);
        assert_eq!(factor, Colour::splat(0.9));

        let green = Colour::new(0.0, 1.0, 0.0);
        let stack = LayerStack {
            layers: Box::new([filter(1.0, 0.5, 1.0), Surface::ConstantColour(green)]),
        };
        let at = meet(&plane, DVec3::new(0.0, 0.0, 2.0), d);
        assert_eq!(stack.redirect(&at), Redirection::Emits(0.5 * green));
    }

    /// A layer that lets rays in but mirrors them from inside (two-sided), over a mirror:
    /// a ray that enters bounces between the two for ever, and is lost after the bounded
    /// number of passes.
    #[test]
    fn a_ray_trapped_between_mirror_layers_is_lost() {
        let mirror = Surface::Mirror(Mirror {
            reflection_coefficient: 1.0,
        });
        let one_way = Surface::TwoSided(super::super::TwoSided {
            sides: Box::new([mirror.clone(), filter(1.0, 1.0, 1.0)]),
        });
        let stack = LayerStack {
            layers: Box::new([one_way, mirror]),
        };
        let plane = plane();
        let at = meet(
            &plane,
            DVec3::new(0.0, 0.0, 2.0),
            DVec3::new(0.2, 0.0, -1.0),
        );
        assert_eq!(stack.redirect(&at), Redirection::Lost);
    }

    #[test]
    fn layers_that_leave_the_point_are_refused() {
        let build = |text: &str| {
            toml::from_str::<LayerStackKeys>(text)
                .map_err(|e| e.to_string())?
                .build()
        };
        assert!(
            build("layers = []")
                .unwrap_err()
                .contains("at least one layer")
        );
        let tint = r#"{ type = "tinted-solid", absorption_coefficient = [1, 1, 1] }"#;
        assert!(build(&format!(r#"layers = [{{ type = "mirror" }}, {tint}]"#)).is_ok());
        let e = build(&format!(r#"layers = [{tint}, {{ type = "mirror" }}]"#)).unwrap_err();
        assert!(
            e.starts_with("a tinted-solid surface cannot be a layer"),
            "{e}"
        );
        let e = build(
            r#"layers = [{ type = "chequerboard", surfaces = [{ type = "mirror" }, { type = "semi-transparent", surface = { type = "mirror" } }] }]"#,
        )
        .unwrap_err();
        assert!(
            e.starts_with("a semi-transparent surface cannot be a layer"),
            "{e}"
        );
        let e = build(r#"layers = [{ type = "teleporting", destination = "x" }]"#).unwrap_err();
        assert_eq!(
            e,
            "a teleporting surface cannot be a layer of a layer stack"
        );
    }
}
