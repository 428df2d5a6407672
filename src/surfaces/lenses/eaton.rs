//! The Eaton lens (§3, Eqs 7–8): a perfect retro-reflector.
//!
//! A ray entering at P with direction d leaves from P mirrored in the line through the centre
//! C parallel to d, travelling back along −d.

use glam::DVec3;
use serde::Deserialize;

use super::{ClosedFormLensKeys, IndexProfile, LensLaw};
use crate::geometry::{Exit, Sphere};
use crate::surfaces::Surface;

/// The ray leaving the Eaton lens `lens` after entering at `p` with direction `d`.
pub fn eaton(lens: &Sphere, p: DVec3, d: DVec3) -> Exit {
    let d = d.normalize();
    let r = lens.centre() - p;
    let exit = p + 2.0 * (r - r.dot(d) * d); // Eq 7
    Exit::chord(p, exit, -d) // Eq 8
}

/// `type = "eaton-lens"`.
#[derive(Debug, Deserialize)]
#[serde(transparent)]
pub struct EatonLensKeys(ClosedFormLensKeys);

impl EatonLensKeys {
    pub fn build(self) -> Result<Surface, String> {
        self.0.build(LensLaw::Eaton, IndexProfile::Eaton)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Shape;
    use crate::surfaces::tests::{crosses, leaves, meet};
    use crate::surfaces::{Lens, Redirection};

    /// The Eaton lens is a retro-reflector: every ray leaves along −d. Where it leaves follows
    /// from the spherical symmetry: a ray's path in a spherically symmetric index is symmetric
    /// under the reflection in the line ℓ through C and the path's point nearest C, which maps
    /// the path onto itself run backwards, so it sends P to the exit P′ and d to the reversed
    /// exit direction, −d′ = d. A reflection in a line fixes only vectors along it, so ℓ is
    /// parallel to d and P′ is P mirrored in the line through C along d:
    /// P′ = 2 (C + ((P − C)·d̂) d̂) − P. A ray aimed at the centre comes straight back from
    /// where it entered.
    #[test]
    fn every_ray_is_retro_reflected() {
        let (centre, radius) = (DVec3::new(-1.0, 0.5, 3.0), 2.0);
        let shape = Shape::Sphere(Sphere::new(centre, radius).unwrap());
        let lens = Lens {
            transmission_coefficient: 0.85,
            ..Lens::new(LensLaw::Eaton)
        };
        for k in 0..10 {
            let turn = 0.7 * k as f64;
            let d = DVec3::new(turn.cos(), 0.3 * turn.sin(), turn.sin()).normalize();
            let b = radius * (k as f64 + 0.5) / 10.0;
            let at = meet(&shape, centre - 6.0 * d + b * d.any_orthonormal_vector(), d);
            let p = at.point();
            let (exit, factor) = crosses(lens.redirect(&at, &mut |_| {}));
            assert_eq!(factor, 0.85);
            assert!((exit.direction + d).length() < 1e-14, "{}", exit.direction);
            let mirrored = 2.0 * (centre + (p - centre).dot(d) * d) - p;
            assert!((exit.point - mirrored).length() < 1e-12, "{}", exit.point);
            assert!(((exit.point - centre).length() - radius).abs() < 1e-12);
        }
        // Aimed at the centre to rounding: it leaves from the entry point (as `Leaves` if the
        // exit computes to exactly the entry, else as `Crosses` a rounding error away).
        let d = DVec3::new(0.0, 0.6, -0.8);
        let at = meet(&shape, centre - 5.0 * d, d);
        let (point, out, factor) = match lens.redirect(&at, &mut |_| {}) {
            Redirection::Crosses { exit, factor } => (exit.point, exit.direction, factor.x),
            r => {
                let (out, factor) = leaves(r);
                (at.point(), out, factor)
            }
        };
        assert!((point - at.point()).length() < 1e-14, "{point}");
        assert!((out + d).length() < 1e-15 && factor == 0.85, "{out}");
    }
}
