//! Rainbow: a surface that adds the colours of a primary rainbow to the light behind it (Dr
//! TIM's `Rainbow`).

use glam::DVec3;
use serde::Deserialize;

use super::hsl;
use crate::geometry::{Interaction, Transform};
use crate::keys::{Coefficient, Vector};
use crate::math::Colour;
use crate::surfaces::{Redirection, Surface};

/// The angle, in degrees, between the sunlight's direction and the line of sight at which a
/// primary rainbow is brightest, as in Dr TIM (42.5°).
const RAINBOW_ANGLE: f64 = 42.5;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rainbow {
    pub saturation: f64,
    pub lightness: f64,
    /// Where the sunlight comes from.
    pub light_source_position: DVec3,
}

impl Rainbow {
    /// Dr TIM's rule: with θ the angle in degrees between the direction from the light source
    /// to the hit point and the ray's direction, the rainbow's lightness is
    /// L' = lightness·exp(−(θ − 42.5)⁶/2); the ray goes on undeviated carrying 1 − L' of the
    /// light behind, and the colour of hue (41 − θ)/2.5, the saturation and lightness L' is
    /// added.
    pub fn redirect(&self, at: &Interaction) -> Redirection<'static> {
        let d = at.ray.direction.normalize();
        let from_light = (at.local_point() - self.light_source_position).normalize();
        let theta = from_light.dot(d).clamp(-1.0, 1.0).acos().to_degrees();
        let lightness = self.lightness * (-(theta - RAINBOW_ANGLE).powi(6) / 2.0).exp();
        Redirection::Glows {
            glow: hsl((41.0 - theta) / 2.5, self.saturation, lightness),
            factor: Colour::splat(1.0 - lightness),
        }
    }

    /// The rainbow of an object placed by `t`: the light source moves with it.
    pub fn transformed(&self, t: &Transform) -> Rainbow {
        Rainbow {
            light_source_position: t.point(self.light_source_position),
            ..*self
        }
    }
}

/// `type = "rainbow"`: where not given, Dr TIM's `Rainbow.BRIGHT_RAINBOW` (it has no GUI):
/// saturation 1, lightness 0.35, light source at (100, 300, −500).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RainbowKeys {
    saturation: Option<Coefficient>,
    lightness: Option<Coefficient>,
    light_source_position: Option<Vector>,
}

impl RainbowKeys {
    pub fn build(self) -> Result<Surface, String> {
        Ok(Surface::Rainbow(Rainbow {
            saturation: self.saturation.map_or(1.0, |s| s.0),
            lightness: self.lightness.map_or(0.35, |l| l.0),
            light_source_position: self
                .light_source_position
                .map_or(DVec3::new(100.0, 300.0, -500.0), |p| p.0),
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Plane, Shape};
    use crate::surfaces::tests::meet;

    /// The light at the origin, the hit point (0, 0, 10) straight along +z from it, and the ray
    /// arriving there along a direction at θ degrees from +z.
    fn redirection_at_angle(theta_degrees: f64) -> Redirection<'static> {
        let rainbow = Rainbow {
            saturation: 1.0,
            lightness: 0.35,
            light_source_position: DVec3::ZERO,
        };
        let plane =
            Shape::Plane(Plane::new(DVec3::new(0.0, 0.0, 10.0), DVec3::Z, DVec3::X).unwrap());
        // The hit point (0, 0, 10) lies along +z from the light; a ray arriving there with
        // direction at angle θ from +z, in the x-z plane.
        let theta = theta_degrees.to_radians();
        let direction = DVec3::new(theta.sin(), 0.0, theta.cos());
        let at = meet(&plane, DVec3::new(0.0, 0.0, 10.0) - direction, direction);
        rainbow.redirect(&at)
    }

    /// At 42.5° the rainbow has its whole lightness 0.35 and hue (41 − 42.5)/2.5 = −0.6 ≡ 0.4
    /// (between green and cyan): by the textbook HSL formula, q = 0.7 and p = 0, so red 0,
    /// green 0.7 and blue 0.7·6·(0.4 − 1/3) = 0.28; the light behind keeps 1 − 0.35. At 30° the
    /// lightness has the factor exp(−12.5⁶/2): no rainbow, all light passes.
    #[test]
    fn the_bow_lies_at_forty_two_and_a_half_degrees() {
        let Redirection::Glows { glow, factor } = redirection_at_angle(42.5) else {
            panic!("a rainbow glows");
        };
        assert!(
            (factor - Colour::splat(0.65)).abs().max_element() < 1e-9,
            "{factor}"
        );
        let expected = Colour::new(0.0, 0.7, 0.7 * 6.0 * (0.4 - 1.0 / 3.0));
        assert!((glow - expected).abs().max_element() < 1e-9, "{glow}");
        let Redirection::Glows { glow, factor } = redirection_at_angle(30.0) else {
            panic!("a rainbow glows");
        };
        assert!(glow.max_element() < 1e-12 && (factor - Colour::ONE).max_element().abs() < 1e-12);
    }

    /// The hue (41 − θ)/2.5 turns once across 2.5°: at 41° it is 0, pure red; at 42.25° it is
    /// −0.5 ≡ 1/2, cyan.
    #[test]
    fn the_hue_runs_through_a_full_turn_across_the_bow() {
        let hue_colour = |theta: f64| match redirection_at_angle(theta) {
            Redirection::Glows { glow, .. } => glow / glow.max_element(),
            _ => panic!("a rainbow glows"),
        };
        let red = hue_colour(41.0);
        assert!(red.x > 0.99 && red.y < 1e-9 && red.z < 1e-9, "{red}");
        let cyan = hue_colour(42.25);
        assert!(cyan.x < 1e-9 && cyan.y > 0.99 && cyan.z > 0.99, "{cyan}");
    }
}
