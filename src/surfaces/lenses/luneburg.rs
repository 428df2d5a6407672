//! The Luneburg lens (§3, Eqs 5–6): every parallel bundle is focused onto the far surface.
//!
//! A ray entering at P with direction d leaves from the point of the surface that lies in the
//! direction of d from the centre C, travelling along C − P.

use glam::DVec3;
use serde::Deserialize;

use super::{ClosedFormLensKeys, IndexProfile, LensLaw};
use crate::geometry::{Exit, Sphere};
use crate::surfaces::Surface;

/// The ray leaving the Luneburg lens `lens` after entering at `p` with direction `d`.
pub fn luneburg(lens: &Sphere, p: DVec3, d: DVec3) -> Exit {
    let c = lens.centre();
    let exit = c + lens.radius() * d.normalize(); // Eq 5
    let direction = (c - p).normalize(); // Eq 6
    Exit::chord(p, exit, direction)
}

/// `type = "luneburg-lens"`.
#[derive(Debug, Deserialize)]
#[serde(transparent)]
pub struct LuneburgLensKeys(ClosedFormLensKeys);

impl LuneburgLensKeys {
    pub fn build(self) -> Result<Surface, String> {
        self.0.build(LensLaw::Luneburg, IndexProfile::Luneburg)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Shape;
    use crate::surfaces::Lens;
    use crate::surfaces::tests::{crosses, meet, meet_copy};

    /// A Luneburg lens focuses every parallel bundle onto the far surface: a ray entering
    /// parallel to d leaves from C + R d̂, the point where the axis through the centre along d
    /// meets the far side. Its direction there follows from the same property by reversibility:
    /// light sent back from the exit along −e is a ray of a parallel bundle along −e, which the
    /// lens focuses onto C − R ê, and that must be the entry point P; so ê = (C − P)/R.
    /// Checked for rays across the aperture and in several planes of incidence, on the lens
    /// and on an array copy of it (whose centre is C + offset).
    #[test]
    fn a_parallel_bundle_is_focused_on_the_far_surface() {
        let (centre, radius) = (DVec3::new(0.5, -1.0, 2.0), 1.5);
        let shape = Shape::Sphere(Sphere::new(centre, radius).unwrap());
        let lens = Lens {
            transmission_coefficient: 0.9,
            ..Lens::new(LensLaw::Luneburg)
        };
        let d = DVec3::new(0.3, -0.2, 1.0).normalize();
        let (e1, e2) = d.any_orthonormal_pair();
        for offset in [DVec3::ZERO, DVec3::new(10.0, 0.0, -4.0)] {
            let c = centre + offset;
            for k in 0..12 {
                let (b, turn) = (radius * (k as f64 + 0.5) / 12.0, 2.4 * k as f64);
                let across = b * (turn.cos() * e1 + turn.sin() * e2);
                let at = if offset == DVec3::ZERO {
                    meet(&shape, c - 5.0 * d + across, d)
                } else {
                    meet_copy(&shape, offset, c - 5.0 * d + across, d)
                };
                let p = at.point();
                let (exit, factor) = crosses(lens.redirect(&at, &mut |_| {}));
                assert_eq!(factor, 0.9);
                assert!(
                    (exit.point - (c + radius * d)).length() < 1e-12,
                    "b = {b}: {}",
                    exit.point
                );
                assert!((exit.direction - (c - p) / radius).length() < 1e-12);
            }
        }
    }
}
