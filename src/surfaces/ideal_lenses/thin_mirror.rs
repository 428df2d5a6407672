//! The ideal thin mirror, spherical or cylindrical (Dr TIM's
//! `IdealThinSphericalMirrorSurfaceSimple` and `IdealThinCylindricalMirrorSurfaceSimple`): the
//! ideal thin lens of the same focal length, followed by a reflection of the outgoing direction
//! in the plane perpendicular to the optical axis, d″ = d′ − 2 (d′·â) â. Rays through the
//! principal point are mirrored, and parallel rays meet in the focal plane at distance f in
//! front of the mirror (f > 0: concave, f < 0: convex).

use crate::geometry::Interaction;
use crate::surfaces::Redirection;

use super::ThinLens;

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
