//! Position-dependent colour: a colour that cycles through the hues with the distance of the
//! hit point from a centre, or from an axis (Dr TIM's `SurfaceColourPositionDependent`).

use std::f64::consts::TAU;

use glam::DVec3;
use serde::Deserialize;

use super::cycle;
use crate::geometry::{Interaction, Transform};
use crate::keys::{Direction, Positive, Vector};
use crate::math::Colour;
use crate::surfaces::{Coloured, Redirection, Surface};

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PositionDependentColour {
    /// Distance after which the colour repeats.
    pub period: f64,
    pub centre: DVec3,
    /// With a direction, the distance is measured from the line through `centre` along it
    /// (Dr TIM: from the hit point's part perpendicular to it); without, from `centre`.
    pub independent_direction: Option<DVec3>,
    /// Whether the colour is shown whatever the lighting (`Emits`), or lit with a white
    /// specular colour.
    pub glowing: bool,
}

impl PositionDependentColour {
    /// Dr TIM's colour at distance d: with phase φ = 2πd/period, each channel is
    /// 0.5 + 0.5 sin(φ + k·2π/3), k = 0, 1, 2 for red, green and blue.
    pub fn colour(&self, distance: f64) -> Colour {
        cycle(TAU * distance / self.period)
    }

    pub fn redirect(&self, at: &Interaction) -> Redirection<'static> {
        let r = at.local_point() - self.centre;
        let distance = match self.independent_direction {
            Some(a) => r.reject_from_normalized(a).length(),
            None => r.length(),
        };
        let c = self.colour(distance);
        if self.glowing {
            Redirection::Emits(c)
        } else {
            Redirection::Lit(Coloured::shiny(c))
        }
    }

    /// The colour field of an object placed by `t`: the centre and the direction move with it.
    pub fn transformed(&self, t: &Transform) -> PositionDependentColour {
        PositionDependentColour {
            centre: t.point(self.centre),
            independent_direction: self.independent_direction.map(|a| t.vector(a).normalize()),
            ..*self
        }
    }
}

/// `type = "position-dependent-colour"`: Dr TIM's class has no GUI; where not given, period 1,
/// centre at the origin, no independent direction, lit (not glowing).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PositionDependentColourKeys {
    period: Option<Positive>,
    centre: Option<Vector>,
    independent_direction: Option<Direction>,
    glowing: Option<bool>,
}

impl PositionDependentColourKeys {
    pub fn build(self) -> Result<Surface, String> {
        Ok(Surface::PositionDependentColour(PositionDependentColour {
            period: self.period.map_or(1.0, |p| p.0),
            centre: self.centre.map_or(DVec3::ZERO, |c| c.0),
            independent_direction: self.independent_direction.map(|d| d.0),
            glowing: self.glowing.unwrap_or(false),
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Plane, Shape};
    use crate::surfaces::tests::meet;

    /// The plane z = 0 seen from above; the colour at (x, y, 0).
    fn colour_at(field: &PositionDependentColour, x: f64, y: f64) -> Colour {
        let plane = Shape::Plane(Plane::new(DVec3::ZERO, DVec3::Z, DVec3::X).unwrap());
        match field.redirect(&meet(&plane, DVec3::new(x, y, 1.0), -DVec3::Z)) {
            Redirection::Emits(c) => c,
            other => panic!("glowing, not {other:?}"),
        }
    }

    /// Period 2 about the origin: at distance 0.5 (a quarter period) the phase is 90°, so
    /// (1, 0.5 + 0.5 cos 120°, 0.5 + 0.5 cos 240°) = (1, 0.25, 0.25), along any direction; at
    /// distance 2.5 the same again. With the independent direction y, the point (0.5, 7, 0) is
    /// 0.5 from the axis: the same colour.
    #[test]
    fn the_colour_follows_the_distance_from_the_centre_or_the_axis() {
        let mut field = PositionDependentColour {
            period: 2.0,
            centre: DVec3::ZERO,
            independent_direction: None,
            glowing: true,
        };
        let quarter = Colour::new(1.0, 0.25, 0.25);
        let near = |a: Colour| (a - quarter).abs().max_element() < 1e-12;
        assert!(near(colour_at(&field, 0.5, 0.0)));
        assert!(near(colour_at(&field, 0.3, 0.4)));
        assert!(near(colour_at(&field, 0.0, 2.5)));
        assert!(!near(colour_at(&field, 0.5, 7.0)));
        field.independent_direction = Some(DVec3::Y);
        assert!(near(colour_at(&field, 0.5, 7.0)));
    }
}
