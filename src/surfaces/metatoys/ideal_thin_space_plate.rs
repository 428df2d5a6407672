//! An ideal thin space plate (Dr TIM's `IdealThinSpacePlateSurface`, planar form): a sheet that
//! adds a stretch of free space to every ray crossing it, so that an optical system can be made
//! shorter. With C the plate's `centre` and D the `distance_vector` (the extra distance along
//! its direction), a ray meeting the sheet at P travels on along its direction d to the plane
//! through C + D perpendicular to D, at Q; from Q it returns along the sheet's normal to the
//! sheet, at P′, and leaves P′ in its own direction d, having taken the time |Q − P|. For a flat
//! sheet through C with D along its normal, P′ = P + |D| d_t / |d_n|: the lateral shift of a
//! ray crossing |D| of free space.
//!
//! A ray travelling against D (d·D < 0) uses the plane through C − D, so it too crosses |D|
//! more of free space. **Dr TIM** finds Q on the plane through C + D in either direction along
//! the ray, which moves such rays backwards, as though the plate took space away from them;
//! timbre adds the space whichever way light crosses. Where the return along the normal does
//! not meet the sheet (past its edge), no light passes: Dr TIM's baffles.

use glam::DVec3;
use serde::Deserialize;

use crate::geometry::{Exit, Interaction, Transform};
use crate::keys::{Coefficient, Vector, throughput};
use crate::math::Colour;
use crate::surfaces::{Redirection, Surface};

#[derive(Debug, Clone, PartialEq)]
pub struct IdealThinSpacePlate {
    /// C, a point of the plate.
    pub centre: DVec3,
    /// D, the extra distance along its direction.
    pub distance_vector: DVec3,
    /// Fraction of the light transmitted, in [0, 1].
    pub transmission_coefficient: f64,
}

impl IdealThinSpacePlate {
    /// Q, where a ray from `p` along `d` meets the plane a distance |D| beyond the plate, on
    /// the side it travels to; `None` for a ray along that plane.
    pub fn far_point(&self, p: DVec3, d: DVec3) -> Option<DVec3> {
        let along = d.dot(self.distance_vector);
        if along == 0.0 {
            return None;
        }
        let offset = self.distance_vector * along.signum();
        let plane = self.centre + offset;
        let s = (plane - p).dot(offset) / d.dot(offset);
        (s >= 0.0 && s.is_finite()).then(|| p + s * d)
    }

    pub fn redirect(&self, at: &Interaction) -> Redirection<'static> {
        let (p, d) = (at.local_point(), at.ray.direction);
        let Some(q) = self.far_point(p, d) else {
            return Redirection::Lost;
        };
        // Back to the sheet along its normal, from Q's side (Dr TIM tries the inward normal
        // first, then the outward one).
        let n = at.normal();
        let back = [-n, n]
            .into_iter()
            .find_map(|m| Some(q + m * at.shape.intersect(q, m, 0.0, f64::INFINITY)?.0));
        let Some(exit) = back else {
            return Redirection::Lost;
        };
        Redirection::Jumps {
            exit: Exit {
                point: exit + at.offset,
                direction: d.normalize(),
                path: q.distance(p),
            },
            factor: Colour::splat(self.transmission_coefficient),
        }
    }

    /// The plate of an object placed by `t`, which must keep angles (a rotation, uniform
    /// scaling and translation) for its planes to stay perpendicular to D.
    pub fn transformed(&self, t: &Transform) -> Result<IdealThinSpacePlate, String> {
        t.uniform_scale().ok_or(
            "an ideal thin space plate adds distance perpendicular to its planes, which only \
             rotations, uniform scaling and translations keep, so it cannot be scaled \
             non-uniformly",
        )?;
        Ok(IdealThinSpacePlate {
            centre: t.point(self.centre),
            distance_vector: t.vector(self.distance_vector),
            ..*self
        })
    }
}

/// `type = "ideal-thin-space-plate"`: `centre` (a point of the plate) and `distance_vector` (the
/// extra distance along its direction), both required (Dr TIM's GUI has no space plate), and
/// `transmission_coefficient` (0.96).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IdealThinSpacePlateKeys {
    centre: Vector,
    distance_vector: Vector,
    #[serde(alias = "transmission")]
    transmission_coefficient: Option<Coefficient>,
}

impl IdealThinSpacePlateKeys {
    pub fn build(self) -> Result<Surface, String> {
        if self.distance_vector.0 == DVec3::ZERO {
            return Err("ideal-thin-space-plate: `distance_vector` must not be zero".into());
        }
        Ok(Surface::IdealThinSpacePlate(IdealThinSpacePlate {
            centre: self.centre.0,
            distance_vector: self.distance_vector.0,
            transmission_coefficient: throughput(self.transmission_coefficient),
        }))
    }
}
