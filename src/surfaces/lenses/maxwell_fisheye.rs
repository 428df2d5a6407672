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
