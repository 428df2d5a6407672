//! The glens, a generalised lens with different focal lengths on its two sides (Chaplain,
//! Courtial et al., JOSA A 33, 962 (2016); Dr TIM's `GlensSurface` with finite focal lengths
//! and `SimpleGlensHologram`).
//!
//! The optical axis â points into *positive* space; the focal lengths are f₋ (negative space)
//! and f₊ (positive space), and the nodal point, through which rays pass undeviated, is
//! N = P + (f₋ + f₊) â (P the principal point). A ray with direction d, d_a = d·â, meeting the
//! glens at S leaves with direction
//!
//!   d′ ∝ −(f_o/f_i) d + (d_a/f_i) (N − S),
//!
//! where (f_o, f_i) = (f₋, f₊) for light travelling into positive space (d_a > 0) and (f₊, f₋)
//! otherwise. On the plane through P perpendicular to â, it images every point Q to a point Q′
//! on the line through Q and N, their axial coordinates a, a′ (from P, along â) obeying
//! f₊/a′ + f₋/a = 1. The law keeps d·â there (light always goes on into the other space).
//! An ideal thin lens is the glens with f₋ = −f, f₊ = f.

use glam::DVec3;

use crate::geometry::Interaction;
use crate::surfaces::Redirection;

#[derive(Debug, Clone, PartialEq)]
pub struct Glens {
    pub principal_point: DVec3,
    /// Unit vector along the optical axis, pointing into positive space.
    pub optical_axis: DVec3,
    /// f₋, finite and non-zero.
    pub focal_length_negative: f64,
    /// f₊, finite and non-zero.
    pub focal_length_positive: f64,
    /// Fraction of the light transmitted, in [0, 1].
    pub transmission_coefficient: f64,
}

impl Glens {
    /// N = P + (f₋ + f₊) â.
    pub fn nodal_point(&self) -> DVec3 {
        self.principal_point
            + (self.focal_length_negative + self.focal_length_positive) * self.optical_axis
    }

    /// The direction (not normalised) a ray with direction `d` leaves in where it meets the
    /// glens at `s`; a ray along the glens plane (d_a = 0) continues undeviated.
    pub fn direction(&self, d: DVec3, s: DVec3) -> DVec3 {
        let da = d.dot(self.optical_axis);
        let (f_o, f_i) = if da > 0.0 {
            (self.focal_length_negative, self.focal_length_positive)
        } else if da < 0.0 {
            (self.focal_length_positive, self.focal_length_negative)
        } else {
            return d;
        };
        -(f_o / f_i) * d + (da / f_i) * (self.nodal_point() - s)
    }

    pub fn redirect(&self, at: &Interaction) -> Redirection<'static> {
        Redirection::Leaves {
            direction: self
                .direction(at.ray.direction, at.local_point())
                .normalize(),
            factor: self.transmission_coefficient,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::surfaces::ThinLens;

    #[test]
    fn a_glens_with_focal_lengths_minus_f_and_f_is_the_ideal_thin_lens() {
        let (p, a, f) = (DVec3::new(0.1, 0.2, 3.0), DVec3::new(0.0, 0.6, 0.8), 1.7);
        let glens = Glens {
            principal_point: p,
            optical_axis: a,
            focal_length_negative: -f,
            focal_length_positive: f,
            transmission_coefficient: 1.0,
        };
        assert_eq!(glens.nodal_point(), p);
        let lens = ThinLens {
            principal_point: p,
            optical_axis: -a,
            focal_length: f,
            gradient: None,
            transmission_coefficient: 1.0,
        };
        for (d, s) in [
            (DVec3::new(0.3, 0.1, 1.0), DVec3::new(0.5, 0.0, 3.0)),
            (DVec3::new(-0.2, -0.9, -0.4), DVec3::new(-1.0, 2.0, 1.5)),
        ] {
            let (g, l) = (
                glens.direction(d, s).normalize(),
                lens.direction(d, s).normalize(),
            );
            assert!((g - l).length() < 1e-15, "{g} {l}");
        }
    }
}
