//! A rectangular array of ideal thin lenses (Dr TIM's `RectangularIdealThinLensletArraySimple`):
//! the surface is divided into cells of `period` along two directions u and v, and the ray is
//! bent by the ideal thin lens of the cell it meets, whose principal point is the cell's centre
//! and whose optical axis is the surface normal at the hit.
//!
//! With the array's centre C (a lenslet's principal point), the unit directions û, v̂ made
//! perpendicular to the surface normal n at the hit, and r = S − C, the cell centres are at
//! u_c = p_u ⌊(r·û)/p_u + ½⌋ (likewise v), and the lenslet's principal point is
//! C + u_c û + v_c v̂.

use glam::{DVec2, DVec3};

use crate::geometry::Interaction;
use crate::surfaces::Redirection;

use super::ThinLens;

#[derive(Debug, Clone, PartialEq)]
pub struct LensletArray {
    /// The principal point of one lenslet.
    pub centre: DVec3,
    /// Unit vectors along the array's rows and columns.
    pub u: DVec3,
    pub v: DVec3,
    /// The lenslets' widths along u and v (positive).
    pub period: DVec2,
    /// The lenslets' focal length, finite and non-zero.
    pub focal_length: f64,
    pub transmission_coefficient: f64,
}

impl LensletArray {
    /// The lenslet met at `s`, where the surface normal is `n`.
    pub fn lenslet(&self, s: DVec3, n: DVec3) -> ThinLens {
        let along = |a: DVec3| (a - a.dot(n) * n).normalize_or_zero();
        let (u, v) = (along(self.u), along(self.v));
        let r = s - self.centre;
        let cell = |x: f64, p: f64| p * (x / p + 0.5).floor();
        ThinLens {
            principal_point: self.centre
                + cell(r.dot(u), self.period.x) * u
                + cell(r.dot(v), self.period.y) * v,
            optical_axis: n,
            focal_length: self.focal_length,
            gradient: None,
            transmission_coefficient: self.transmission_coefficient,
        }
    }

    pub fn redirect(&self, at: &Interaction) -> Redirection<'static> {
        let s = at.local_point();
        let lens = self.lenslet(s, at.frame().w);
        Redirection::Leaves {
            direction: lens.direction(at.ray.direction, s).normalize(),
            factor: self.transmission_coefficient,
        }
    }
}
