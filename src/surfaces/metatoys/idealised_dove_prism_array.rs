//! An idealised Dove-prism array (Dr TIM's `IdealisedDovePrismArray`): a partial idealisation
//! of an array of Dove prisms side by side, each of which inverts the view along one direction
//! (its complete idealisation, without the stripes, is `ray-flipping`).
//!
//! With â the unit inversion direction, which is also the direction in which the array is
//! periodic with period p, and C the centre of Dove prism 0, a ray meeting the sheet at P goes
//! through prism n = ⌊(P − C)·â / p + ½⌋, whose centre is Cₙ = C + n p â. The ray leaves
//! mirrored in that prism's mid-plane: from P + 2 ((Cₙ − P)·â) â, with its direction's
//! component along â reversed, d − 2 (d·â) â, carrying the transmission coefficient. The
//! inversion direction should lie in the sheet (Dr TIM's); on a curved sheet, or for an â
//! out of its plane, the new position can lie off it, as in Dr TIM. Like `ray-flipping` the law
//! is reciprocal: a ray sent back from the new position along the reversed new direction
//! returns to P along −d.

use glam::DVec3;
use serde::Deserialize;

use crate::geometry::{Exit, Interaction, Transform};
use crate::keys::{Coefficient, Direction, Positive, Vector, throughput};
use crate::math::Colour;
use crate::surfaces::{Redirection, Surface};

#[derive(Debug, Clone, PartialEq)]
pub struct IdealisedDovePrismArray {
    /// The centre of Dove prism 0, C.
    pub centre: DVec3,
    /// The unit inversion direction â.
    pub inversion_direction: DVec3,
    /// The period p along â.
    pub period: f64,
    /// Fraction of the light transmitted, in [0, 1].
    pub transmission_coefficient: f64,
}

impl IdealisedDovePrismArray {
    /// Where a ray meeting the sheet at `p` with direction `d` leaves, and in which direction.
    pub fn mirrored(&self, p: DVec3, d: DVec3) -> (DVec3, DVec3) {
        let a = self.inversion_direction;
        let n = ((p - self.centre).dot(a) / self.period + 0.5).floor();
        let centre_n = self.centre + n * self.period * a;
        (p + 2.0 * (centre_n - p).dot(a) * a, d - 2.0 * d.dot(a) * a)
    }

    pub fn redirect(&self, at: &Interaction) -> Redirection<'static> {
        let (point, direction) = self.mirrored(at.local_point(), at.ray.direction);
        Redirection::Jumps {
            exit: Exit::chord(at.point(), point + at.offset, direction),
            factor: Colour::splat(self.transmission_coefficient),
        }
    }

    /// The array of an object placed by `t`, which must keep angles (a rotation, uniform
    /// scaling and translation) for the prisms to stay mirrors.
    pub fn transformed(&self, t: &Transform) -> Result<IdealisedDovePrismArray, String> {
        let scale = t.uniform_scale().ok_or(
            "an idealised Dove-prism array mirrors rays, which only rotations, uniform scaling \
             and translations keep, so it cannot be scaled non-uniformly",
        )?;
        Ok(IdealisedDovePrismArray {
            centre: t.point(self.centre),
            inversion_direction: t.vector(self.inversion_direction).normalize(),
            period: self.period * scale,
            ..*self
        })
    }
}

/// `type = "idealised-dove-prism-array"`: `centre` (of Dove prism 0; Dr TIM's GUI default the
/// origin), `inversion_direction` ([1, 0, 0]), `period` (0.1) and `transmission_coefficient`
/// (0.96).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IdealisedDovePrismArrayKeys {
    centre: Option<Vector>,
    inversion_direction: Option<Direction>,
    period: Option<Positive>,
    #[serde(alias = "transmission")]
    transmission_coefficient: Option<Coefficient>,
}

impl IdealisedDovePrismArrayKeys {
    pub fn build(self) -> Result<Surface, String> {
        Ok(Surface::IdealisedDovePrismArray(IdealisedDovePrismArray {
            centre: self.centre.map_or(DVec3::ZERO, |c| c.0),
            inversion_direction: self
                .inversion_direction
                .map_or(DVec3::X, |d| d.0.normalize()),
            period: self.period.map_or(0.1, |p| p.0),
            transmission_coefficient: throughput(self.transmission_coefficient),
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn array() -> IdealisedDovePrismArray {
        IdealisedDovePrismArray {
            centre: DVec3::new(0.05, 0.0, 0.0),
            inversion_direction: DVec3::X,
            period: 0.2,
            transmission_coefficient: 0.96,
        }
    }

    /// Prism 0 spans x from −0.05 to 0.15 (centre 0.05), prism 1 from 0.15 to 0.35 (centre
    /// 0.25): a ray at x = 0.3 leaves at 0.2, one at x = 0.1 at 0.0, one at −0.2 (prism −1,
    /// centre −0.15) at −0.1; y and z stay, and only d's x component turns.
    #[test]
    fn each_prism_mirrors_the_ray_about_its_own_centre() {
        let d = DVec3::new(0.3, -0.4, 0.866);
        for (x, expected) in [(0.3, 0.2), (0.1, 0.0), (-0.2, -0.1), (0.05, 0.05)] {
            let (p, e) = array().mirrored(DVec3::new(x, 0.7, 2.0), d);
            assert!(
                (p - DVec3::new(expected, 0.7, 2.0)).length() < 1e-15,
                "{x}: {p}"
            );
            assert_eq!(e, DVec3::new(-0.3, -0.4, 0.866));
        }
    }

    /// Sent back along the reversed new direction from the new position, a ray returns to its
    /// start along the reversed old direction.
    #[test]
    fn the_array_is_reciprocal() {
        let d = DVec3::new(-0.2, 0.1, 0.97);
        for x in [-0.43, -0.1, 0.02, 0.14, 0.37] {
            let p = DVec3::new(x, -0.3, 1.0);
            let (q, e) = array().mirrored(p, d);
            let (back, reversed) = array().mirrored(q, -e);
            assert!((back - p).length() < 1e-15 && (reversed + d).length() < 1e-15);
        }
    }

    #[test]
    fn dr_tims_gui_defaults() {
        let keys: IdealisedDovePrismArrayKeys = toml::from_str("").unwrap();
        assert_eq!(
            keys.build().unwrap(),
            Surface::IdealisedDovePrismArray(IdealisedDovePrismArray {
                centre: DVec3::ZERO,
                inversion_direction: DVec3::X,
                period: 0.1,
                transmission_coefficient: 0.96,
            })
        );
    }
}
