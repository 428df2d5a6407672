//! A space-shifting plane (Dr TIM's `EditableSpaceShiftingPlane`): a sheet that images every
//! point of the space behind it to the same point shifted by the `image_space_offset` O, so
//! that light crossing it leaves in its own direction along its line shifted by O.
//!
//! A ray traced from the camera that meets the sheet at P in direction d, crossing along the
//! outward normal n (d·n > 0), goes on along the line P + t d − O: where it meets the sheet's
//! plane, at P′ = P + (O·n / d·n) d − O (Dr TIM's point where the line meets the plane shifted
//! by O, less O). The camera sees a point Y behind the sheet at Y + O. Light is reversible, so a
//! ray crossing against n (d·n < 0) goes on along its line moved by +O: from that side the
//! space behind is seen moved by −O. **Dr TIM** moves every ray's line by −O whichever way it
//! crosses, which is not reversible (a sheet that shows one side moved by O must show the other
//! moved back); the two agree for a camera on the side n points away from, as in Dr TIM's
//! default (normal (0, 0, 1), camera looking along +z). P′ is found on the shape along its normal, as the ideal thin space plate's
//! return is; where the shifted line leaves the shape's edge (past a finite sheet), no light
//! passes. On a curved shape each point acts as its tangent plane.

use glam::DVec3;
use serde::Deserialize;

use crate::geometry::{Exit, Interaction, Transform};
use crate::keys::{Coefficient, Vector};
use crate::math::Colour;
use crate::surfaces::{Redirection, Surface};

#[derive(Debug, Clone, PartialEq)]
pub struct SpaceShifting {
    /// O, the offset of image space relative to object space for rays crossing along the
    /// outward normal.
    pub image_space_offset: DVec3,
    /// Fraction of the light transmitted, in [0, 1].
    pub transmission_coefficient: f64,
}

impl SpaceShifting {
    /// P′, where a ray meeting the sheet at `p` in direction `d` (sheet normal `n`) leaves it:
    /// on the tangent plane at `p`, on the ray's line shifted by ±O. `None` for a ray along the
    /// sheet.
    fn shifted_point(&self, p: DVec3, d: DVec3, n: DVec3) -> Option<DVec3> {
        let across = d.dot(n);
        if across == 0.0 {
            return None;
        }
        let offset = self.image_space_offset * across.signum();
        Some(p + offset.dot(n) / across * d - offset)
    }

    pub fn redirect(&self, at: &Interaction) -> Redirection<'static> {
        let (p, d, n) = (at.local_point(), at.ray.direction, at.normal());
        let factor = Colour::splat(self.transmission_coefficient);
        if self.image_space_offset == DVec3::ZERO {
            return Redirection::Leaves {
                direction: d.normalize(),
                factor,
            };
        }
        let Some(shifted) = self.shifted_point(p, d, n) else {
            return Redirection::Lost;
        };
        // Onto the shape along its normal, from a point a jump's length off the sheet.
        // (At least a billionth of the point's distance from the origin, which rounding keeps.)
        let lift =
            (shifted.distance(p) + self.image_space_offset.length()).max(1e-9 * (1.0 + p.length()));
        let on_shape = [n, -n].into_iter().find_map(|m| {
            let from = shifted + lift * m;
            let (t, _) = at.shape.intersect(from, -m, 0.0, 2.0 * lift)?;
            Some(from - t * m)
        });
        let Some(exit) = on_shape else {
            return Redirection::Lost;
        };
        Redirection::Jumps {
            exit: Exit {
                point: exit + at.offset,
                direction: d.normalize(),
                // Dr TIM leaves the ray's time as it was.
                path: 0.0,
            },
            factor,
        }
    }

    /// The sheet of an object placed by `t`: an image Y + O of Y is placed at t(Y) + t(O)
    /// (the linear part of `t` acting on O), whatever the transform.
    pub fn transformed(&self, t: &Transform) -> SpaceShifting {
        SpaceShifting {
            image_space_offset: t.vector(self.image_space_offset),
            ..*self
        }
    }
}

/// `type = "space-shifting"`: `image_space_offset` (default (0, 0, 0), Dr TIM's
/// `EditableSpaceShiftingPlane`) and `transmission_coefficient` (1: Dr TIM's sheet passes all
/// the light on).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpaceShiftingKeys {
    image_space_offset: Option<Vector>,
    #[serde(alias = "transmission")]
    transmission_coefficient: Option<Coefficient>,
}

impl SpaceShiftingKeys {
    pub fn build(self) -> Result<Surface, String> {
        Ok(Surface::SpaceShifting(SpaceShifting {
            image_space_offset: self.image_space_offset.map_or(DVec3::ZERO, |o| o.0),
            transmission_coefficient: self.transmission_coefficient.map_or(1.0, |c| c.0),
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Parallelogram, Shape};
    use crate::math::Ray;

    /// A 2 × 2 sheet in the plane z = 1 (normal +z) shifting by O = (0.3, −0.2, 0.5).
    fn sheet() -> (Shape, SpaceShifting) {
        let shape = Parallelogram::new(
            DVec3::new(-1.0, -1.0, 1.0),
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(0.0, 2.0, 0.0),
        )
        .unwrap();
        let law = SpaceShifting {
            image_space_offset: DVec3::new(0.3, -0.2, 0.5),
            transmission_coefficient: 0.7,
        };
        (Shape::Parallelogram(shape), law)
    }

    /// The ray leaves on the sheet, in its own direction, on its line moved by −O (along the
    /// normal) or +O (against it): every point Y of the line it then follows is seen along the
    /// camera's line at Y ± O.
    #[test]
    fn rays_leave_on_their_line_shifted_by_the_offset() {
        let (shape, law) = sheet();
        for (origin, direction, sign) in [
            (DVec3::ZERO, DVec3::new(0.1, 0.2, 1.0), 1.0),
            (DVec3::new(0.2, 0.1, 3.0), DVec3::new(-0.3, 0.1, -1.0), -1.0),
        ] {
            let ray = Ray::new(origin, direction, 0.0);
            let (t, prim) = shape
                .intersect(ray.origin, ray.direction, 0.0, 10.0)
                .unwrap();
            let at = Interaction::on(&shape, ray, t, prim);
            let Redirection::Jumps { exit, factor } = law.redirect(&at) else {
                panic!("no jump")
            };
            assert_eq!(factor, Colour::splat(0.7));
            assert!((exit.direction - ray.direction).length() < 1e-15);
            assert!((exit.point.z - 1.0).abs() < 1e-14, "{}", exit.point);
            // exit + O·sign lies on the incoming line.
            let back = exit.point + sign * law.image_space_offset - ray.origin;
            assert!(back.cross(ray.direction).length() < 1e-14, "{back}");
        }
    }

    /// Past the sheet's edge no light passes; along it neither.
    #[test]
    fn rays_shifted_past_the_edge_are_lost() {
        let (shape, law) = sheet();
        let ray = Ray::new(DVec3::new(0.0, 0.9, 0.0), DVec3::new(0.0, 0.0, 1.0), 0.0);
        let at = Interaction::on(&shape, ray, 1.0, 0);
        // P′ = P + (O·n / d·n) d − O = (−0.3, 1.1, 1), past the edge y = 1.
        assert_eq!(law.redirect(&at), Redirection::Lost);
        assert_eq!(
            law.shifted_point(DVec3::ZERO, DVec3::X, DVec3::Z),
            None,
            "a ray along the sheet"
        );
    }
}
