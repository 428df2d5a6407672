//! The Maxwell-fisheye lens (§3, Eqs 9–10): the part of Maxwell's fisheye, truncated at the
//! radius where each surface point is imaged onto its antipode.
//!
//! A ray entering at P leaves from the antipode P′ = C + (C − P), its direction's component
//! perpendicular to R = C − P reversed.

use glam::DVec3;
use serde::Deserialize;

use super::{ClosedFormLensKeys, IndexProfile, LensLaw};
use crate::geometry::{Exit, Sphere};
use crate::surfaces::Surface;

/// The ray leaving the Maxwell-fisheye lens `lens` after entering at `p` with direction `d`.
pub fn maxwell_fisheye(lens: &Sphere, p: DVec3, d: DVec3) -> Exit {
    let d = d.normalize();
    let r = lens.centre() - p;
    let exit = lens.centre() + r; // Eq 9
    let r_hat = r.normalize();
    let direction = 2.0 * d.dot(r_hat) * r_hat - d; // Eq 10
    Exit::chord(p, exit, direction)
}

/// `type = "maxwell-fisheye-lens"`.
#[derive(Debug, Deserialize)]
#[serde(transparent)]
pub struct MaxwellFisheyeLensKeys(ClosedFormLensKeys);

impl MaxwellFisheyeLensKeys {
    pub fn build(self) -> Result<Surface, String> {
        self.0
            .build(LensLaw::MaxwellFisheye, IndexProfile::MaxwellFisheye)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Shape;
    use crate::surfaces::Lens;
    use crate::surfaces::tests::{crosses, meet};

    /// The truncated Maxwell fisheye images every surface point onto its antipode: all rays
    /// entering at P, whatever their direction, leave from 2C − P. Their direction follows
    /// from the spherical symmetry: the path is symmetric under the reflection in the line ℓ
    /// through C and its point nearest C, which sends P to the exit P′ = 2C − P, so ℓ is
    /// perpendicular to r̂ = (C − P)/R (in the plane of incidence), and sends d to the reversed
    /// exit direction −d′. Hence d′ keeps d's component along r̂ (the inward normal at P is
    /// the outward normal at P′: the ray leaves at the angle to the normal it entered at, as
    /// n r sin θ = const with n = 1 at the surface also says) and reverses its component
    /// along the surface.
    #[test]
    fn every_ray_from_a_surface_point_leaves_from_its_antipode() {
        let (centre, radius) = (DVec3::new(0.3, 0.2, -1.0), 1.2);
        let shape = Shape::Sphere(Sphere::new(centre, radius).unwrap());
        let lens = Lens::new(LensLaw::MaxwellFisheye);
        // Entry P, and rays arriving there from many directions.
        let r_hat = DVec3::new(-0.48, 0.6, 0.64); // (P − C)/R, unit
        let p = centre + radius * r_hat;
        let (t1, t2) = r_hat.any_orthonormal_pair();
        for k in 0..16 {
            let (tilt, turn) = (0.1 * k as f64, 1.3 * k as f64);
            let d = -tilt.cos() * r_hat + tilt.sin() * (turn.cos() * t1 + turn.sin() * t2);
            let at = meet(&shape, p - 3.0 * d, d);
            assert!((at.point() - p).length() < 1e-12);
            let (exit, factor) = crosses(lens.redirect(&at, &mut |_| {}));
            assert_eq!(factor, 1.0);
            assert!(
                (exit.point - (2.0 * centre - p)).length() < 1e-12,
                "{}",
                exit.point
            );
            let inward = -r_hat;
            let (along, across) = (d.dot(inward), d - d.dot(inward) * inward);
            assert!((exit.direction.dot(inward) - along).abs() < 1e-14);
            let exit_across = exit.direction - exit.direction.dot(inward) * inward;
            assert!(
                (exit_across + across).length() < 1e-14,
                "{}",
                exit.direction
            );
        }
    }
}
