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
