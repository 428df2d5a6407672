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
