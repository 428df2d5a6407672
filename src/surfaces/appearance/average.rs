//! Average: the sum of several surfaces' light at the same point, each weighted (Dr TIM's
//! `SurfacePropertyAverage` and `SurfacePropertyAverageWeighted`).

use serde::Deserialize;

use super::part;
use crate::geometry::Transform;
use crate::keys::NonNegative;
use crate::math::Colour;
use crate::picture::PictureFile;
use crate::surfaces::{Redirection, Surface, SurfaceKeys, Weighted};

/// Surfaces whose light is added, each weighted per channel (averages, semi-transparent
/// surfaces).
#[derive(Debug, Clone, PartialEq)]
pub struct Mix {
    pub parts: Box<[Weighted]>,
}

impl Mix {
    pub fn redirect(&self) -> Redirection<'_> {
        Redirection::Mixes(&self.parts)
    }

    /// The same mix on an object placed by `t` (each part placed by it).
    pub fn transformed(&self, t: &Transform) -> Result<Mix, String> {
        let parts = self.parts.iter().map(|p| {
            Ok(Weighted {
                weight: p.weight,
                surface: p.surface.transformed(t)?,
            })
        });
        Ok(Mix {
            parts: parts.collect::<Result<_, String>>()?,
        })
    }
}

/// `type = "average"`: the light of `surfaces` (at least one) added with `weights` (one
/// non-negative number per surface). Without `weights` each surface counts 1/n, a true
/// average; Dr TIM's unweighted `SurfacePropertyAverage` sums its parts instead (weights 1),
/// which `weights = [1, 1, ...]` gives.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AverageKeys {
    surfaces: Vec<SurfaceKeys>,
    weights: Option<Vec<NonNegative>>,
}

impl AverageKeys {
    /// The picture files its surfaces name.
    pub fn pictures(&mut self) -> Vec<&mut PictureFile> {
        self.surfaces
            .iter_mut()
            .flat_map(SurfaceKeys::pictures)
            .collect()
    }

    pub fn build(self) -> Result<Surface, String> {
        let n = self.surfaces.len();
        if n == 0 {
            return Err("an average needs at least one surface".into());
        }
        let weights: Vec<f64> = match self.weights {
            None => vec![1.0 / n as f64; n],
            Some(w) if w.len() == n => w.into_iter().map(|w| w.0).collect(),
            Some(w) => {
                return Err(format!(
                    "an average of {n} surfaces needs {n} weights, got {}",
                    w.len()
                ));
            }
        };
        let parts = self.surfaces.into_iter().zip(weights).map(|(keys, w)| {
            Ok(Weighted {
                weight: Colour::splat(w),
                surface: part(keys, "part of an average")?,
            })
        });
        Ok(Surface::Average(Mix {
            parts: parts.collect::<Result<_, String>>()?,
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn build(text: &str) -> Result<Surface, String> {
        toml::from_str::<AverageKeys>(text)
            .map_err(|e| e.to_string())?
            .build()
    }

    /// Two surfaces without weights count half each; with weights, as given.
    #[test]
    fn weights_are_one_over_n_unless_given() {
        let red = r#"{ type = "constant-colour", colour = [1, 0, 0] }"#;
        let mirror = r#"{ type = "mirror" }"#;
        let Ok(Surface::Average(mix)) = build(&format!("surfaces = [{red}, {mirror}]")) else {
            panic!("an average")
        };
        assert_eq!(mix.parts.len(), 2);
        assert!(mix.parts.iter().all(|p| p.weight == Colour::splat(0.5)));
        assert_eq!(
            mix.parts[0].surface,
            Surface::ConstantColour(Colour::new(1.0, 0.0, 0.0))
        );
        let Ok(Surface::Average(mix)) = build(&format!(
            "surfaces = [{red}, {mirror}]\nweights = [1, 0.25]"
        )) else {
            panic!("an average")
        };
        assert_eq!(mix.parts[0].weight, Colour::ONE);
        assert_eq!(mix.parts[1].weight, Colour::splat(0.25));
        assert_eq!(mix.redirect(), Redirection::Mixes(&mix.parts));
    }

    #[test]
    fn bad_averages_are_refused() {
        let matt = r#"{ type = "matt", colour = [1, 1, 1] }"#;
        let e = build(&format!("surfaces = [{matt}, {matt}]\nweights = [1]")).unwrap_err();
        assert_eq!(e, "an average of 2 surfaces needs 2 weights, got 1");
        assert!(build("surfaces = []").unwrap_err().contains("at least one"));
        let e = build(&format!("surfaces = [{matt}]\nweights = [-1]")).unwrap_err();
        assert!(e.contains("expected a number from 0"), "{e}");
        let e = build(r#"surfaces = [{ type = "teleporting", destination = "x" }]"#).unwrap_err();
        assert_eq!(e, "a teleporting surface cannot be part of an average");
    }
}
