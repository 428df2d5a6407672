//! Time-dependent colour: a colour that cycles through the hues with the time the ray meets
//! the surface (Dr TIM's `SurfaceColourTimeDependent`, "Coloured (time-dependent)" in its GUI).

use std::f64::consts::TAU;

use serde::Deserialize;

use super::cycle;
use crate::geometry::Interaction;
use crate::keys::Positive;
use crate::math::Colour;
use crate::surfaces::{Coloured, Redirection, Surface};

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TimeDependentColour {
    /// Time after which the colour repeats.
    pub period: f64,
    /// Whether the colour is shown whatever the lighting (`Emits`), or lit as a shiny surface.
    pub glowing: bool,
}

impl TimeDependentColour {
    /// Dr TIM's colour at time t: with phase φ = 2πt/period, each channel is
    /// 0.5 + 0.5 sin(φ + k·2π/3), k = 0, 1, 2 for red, green and blue.
    pub fn colour(&self, time: f64) -> Colour {
        cycle(TAU * time / self.period)
    }

    /// The colour at the time the ray meets the surface: its time, less the distance it went
    /// (c = 1; rays are traced backwards, so the light left the surface that much earlier).
    pub fn redirect(&self, at: &Interaction) -> Redirection<'static> {
        let c = self.colour(at.ray.time - at.hit.t);
        if self.glowing {
            Redirection::Emits(c)
        } else {
            Redirection::Lit(Coloured::shiny(c))
        }
    }
}

/// `type = "time-dependent-colour"`: where not given, Dr TIM's GUI's: period 1, glowing (light
/// source independent).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TimeDependentColourKeys {
    period: Option<Positive>,
    glowing: Option<bool>,
}

impl TimeDependentColourKeys {
    pub fn build(self) -> Result<Surface, String> {
        Ok(Surface::TimeDependentColour(TimeDependentColour {
            period: self.period.map_or(1.0, |p| p.0),
            glowing: self.glowing.unwrap_or(true),
        }))
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;
    use crate::geometry::{Interaction, Plane, Shape};
    use crate::math::Ray;

    /// With period 2: at t = 0 the phase is 0, so (0.5, 0.5 + 0.5 sin 120°, 0.5 + 0.5 sin 240°)
    /// = (0.5, 0.9330, 0.0670); at t = 0.5 it is 90°, so (1, 0.5 + 0.5 cos 120°, 0.5 + 0.5 cos
    /// 240°) = (1, 0.25, 0.25); a period later the same again.
    #[test]
    fn the_colour_at_two_times_is_dr_tims() {
        let s = TimeDependentColour {
            period: 2.0,
            glowing: true,
        };
        let h = 3f64.sqrt() / 4.0;
        let close = |a: Colour, b: Colour| (a - b).abs().max_element() < 1e-12;
        assert!(close(s.colour(0.0), Colour::new(0.5, 0.5 + h, 0.5 - h)));
        assert!(close(s.colour(0.5), Colour::new(1.0, 0.25, 0.25)));
        assert!(close(s.colour(2.5), Colour::new(1.0, 0.25, 0.25)));
        // At the time the ray meets the surface: a ray at time 1.5 one unit away meets it at
        // 0.5 (as Dr TIM's advanced ray does). Glowing emits, otherwise lit as shiny.
        let plane = Shape::Plane(Plane::new(DVec3::ZERO, DVec3::Z, DVec3::X).unwrap());
        let ray = Ray::new(DVec3::new(0.0, 0.0, 1.0), -DVec3::Z, 1.5);
        let (t, prim) = plane
            .intersect(ray.origin, ray.direction, 0.0, 9.0)
            .unwrap();
        let at = Interaction::on(&plane, ray, t, prim);
        let Redirection::Emits(c) = s.redirect(&at) else {
            panic!("a glowing colour emits")
        };
        assert!(close(c, Colour::new(1.0, 0.25, 0.25)));
        let lit = TimeDependentColour {
            glowing: false,
            ..s
        };
        let Redirection::Lit(c) = lit.redirect(&at) else {
            panic!("a non-glowing colour is lit")
        };
        assert!(close(c.diffuse, Colour::new(1.0, 0.25, 0.25)) && c.specular == Colour::ONE);
    }
}
