//! The ideal thin mirror, spherical or cylindrical (Dr TIM's
//! `IdealThinSphericalMirrorSurfaceSimple` and `IdealThinCylindricalMirrorSurfaceSimple`): the
//! ideal thin lens of the same focal length, followed by a reflection of the outgoing direction
//! in the plane perpendicular to the optical axis, d″ = d′ − 2 (d′·â) â. Rays through the
//! principal point are mirrored, and parallel rays meet in the focal plane at distance f in
//! front of the mirror (f > 0: concave, f < 0: convex).

use serde::Deserialize;

use super::ThinLens;
use super::thin_lens::ThinLensKeys;
use crate::geometry::Interaction;
use crate::keys::{Coefficient, Direction, throughput};
use crate::surfaces::{Redirection, Surface};

#[derive(Debug, Clone, PartialEq)]
pub struct ThinMirror {
    /// The lens whose outgoing rays are mirrored; its transmission coefficient is the mirror's
    /// reflection coefficient.
    pub lens: ThinLens,
}

impl ThinMirror {
    /// The direction (not normalised) a ray with direction `d` leaves in where it meets the
    /// mirror at `s`.
    pub fn direction(&self, d: glam::DVec3, s: glam::DVec3) -> glam::DVec3 {
        let out = self.lens.direction(d, s);
        let a = self.lens.optical_axis;
        out - 2.0 * out.dot(a) * a
    }

    pub fn redirect(&self, at: &Interaction) -> Redirection<'static> {
        super::leaving(
            at,
            |d, s| self.direction(d, s),
            self.lens.transmission_coefficient,
        )
    }
}

/// `type = "ideal-thin-mirror"`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IdealThinMirrorKeys {
    #[serde(flatten)]
    lens: ThinLensKeys,
    #[serde(alias = "reflection")]
    reflection_coefficient: Option<Coefficient>,
}

impl IdealThinMirrorKeys {
    pub fn build(self) -> Result<Surface, String> {
        let coefficient = throughput(self.reflection_coefficient);
        let lens = self.lens.lens("ideal-thin-mirror", None, coefficient)?;
        Ok(Surface::IdealThinMirror(ThinMirror { lens }))
    }
}

/// `type = "ideal-thin-cylindrical-mirror"`: power along `gradient_direction` only.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IdealThinCylindricalMirrorKeys {
    #[serde(flatten)]
    lens: ThinLensKeys,
    gradient_direction: Direction,
    #[serde(alias = "reflection")]
    reflection_coefficient: Option<Coefficient>,
}

impl IdealThinCylindricalMirrorKeys {
    pub fn build(self) -> Result<Surface, String> {
        let coefficient = throughput(self.reflection_coefficient);
        let gradient = Some(self.gradient_direction);
        let lens = self
            .lens
            .lens("ideal-thin-cylindrical-mirror", gradient, coefficient)?;
        Ok(Surface::IdealThinMirror(ThinMirror { lens }))
    }
}
