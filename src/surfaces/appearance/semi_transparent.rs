//! Semi-transparent: a surface that lets a fraction of the light through undeviated (Dr TIM's
//! `SemiTransparent`).

use serde::Deserialize;

use super::{Mix, part};
use crate::keys::Coefficient;
use crate::math::Colour;
use crate::picture::PictureFile;
use crate::surfaces::{Surface, SurfaceKeys, Transparent, Weighted};

/// Dr TIM's semi-transparent surfaces' transmission coefficient (`SemiTransparent`'s ready-made
/// ones; its GUI offers none).
const DEFAULT_TRANSMISSION: f64 = 0.75;

/// `type = "semi-transparent"`: of the light, a fraction T (`transmission_coefficient`,
/// default 0.75) passes undeviated and 1 − T is `surface`'s. Dr TIM's `SemiTransparent` instead
/// adds all of the surface's light to T times the light behind, which can exceed what either
/// gives; timbre's fractions add up to 1.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SemiTransparentKeys {
    surface: Box<SurfaceKeys>,
    #[serde(alias = "transmission")]
    transmission_coefficient: Option<Coefficient>,
}

impl SemiTransparentKeys {
    /// The picture files its surface names.
    pub fn pictures(&mut self) -> Vec<&mut PictureFile> {
        self.surface.pictures()
    }

    pub fn build(self) -> Result<Surface, String> {
        let t = self
            .transmission_coefficient
            .map_or(DEFAULT_TRANSMISSION, |t| t.0);
        let surface = part(*self.surface, "semi-transparent")?;
        let clear = Surface::Transparent(Transparent {
            transmission_coefficient: 1.0,
        });
        Ok(Surface::SemiTransparent(Mix {
            parts: Box::new([
                Weighted {
                    weight: Colour::splat(1.0 - t),
                    surface,
                },
                Weighted {
                    weight: Colour::splat(t),
                    surface: clear,
                },
            ]),
        }))
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;
    use crate::geometry::{Plane, Shape};
    use crate::surfaces::Redirection;
    use crate::surfaces::tests::meet;

    /// With T = 0.75 (the default), a quarter of the light is the red surface's and three
    /// quarters pass straight through, whole.
    #[test]
    fn a_fraction_t_passes_and_one_minus_t_is_the_surfaces() {
        let keys: SemiTransparentKeys =
            toml::from_str(r#"surface = { type = "constant-colour", colour = [1, 0, 0] }"#)
                .unwrap();
        let semi = keys.build().unwrap();
        let plane = Shape::Plane(Plane::new(DVec3::ZERO, DVec3::Z, DVec3::X).unwrap());
        let d = DVec3::new(0.1, 0.2, -1.0);
        let at = meet(&plane, DVec3::new(0.0, 0.0, 2.0), d);
        let Redirection::Mixes(parts) = semi.redirect(&at, &mut |_| {}) else {
            panic!("a mix")
        };
        assert_eq!(parts.len(), 2);
        assert_eq!(parts[0].weight, Colour::splat(0.25));
        assert_eq!(
            parts[0].surface.redirect(&at, &mut |_| {}),
            Redirection::Emits(Colour::new(1.0, 0.0, 0.0))
        );
        assert_eq!(parts[1].weight, Colour::splat(0.75));
        assert_eq!(
            parts[1].surface.redirect(&at, &mut |_| {}),
            Redirection::Leaves {
                direction: d.normalize(),
                factor: Colour::ONE
            }
        );
    }

    #[test]
    fn bad_semi_transparent_surfaces_are_refused() {
        let e = toml::from_str::<SemiTransparentKeys>(
            "surface = { type = \"mirror\" }\ntransmission_coefficient = 1.5",
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("expected a coefficient between 0 and 1"), "{e}");
        let keys: SemiTransparentKeys =
            toml::from_str(r#"surface = { type = "teleporting", destination = "x" }"#).unwrap();
        assert_eq!(
            keys.build().unwrap_err(),
            "a teleporting surface cannot be semi-transparent"
        );
    }
}
