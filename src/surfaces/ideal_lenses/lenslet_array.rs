//! A rectangular array of ideal thin lenses (Dr TIM's `RectangularIdealThinLensletArraySimple`):
//! the surface is divided into cells of `period` along two directions u and v, and the ray is
//! bent by the ideal thin lens of the cell it meets, whose principal point is the cell's centre
//! and whose optical axis is the surface normal at the hit.
//!
//! With the array's centre C (a lenslet's principal point), the unit directions û, v̂ made
//! perpendicular to the surface normal n at the hit, and r = S − C = α û + β v̂ + γ n (the
//! coordinates in that basis, which need not be orthogonal, as Dr TIM's `toBasis`), the cell
//! centres are at u_c = p_u ⌊α/p_u + ½⌋ (likewise v), and the lenslet's principal point is
//! C + u_c û + v_c v̂. Where û and v̂ become parallel on a curved surface there is no lenslet
//! (the ray is lost).
//!
//! Optionally (Dr TIM's `RectangularIdealThinLensletArray`), each lenslet's aperture diffracts:
//! the outgoing direction is blurred by single-slit diffraction at the wavelength `lambda` for
//! slits as wide as the periods, along the surface's u and v (`metatoys::Pixels`).

use glam::{DVec2, DVec3};
use serde::Deserialize;

use super::ThinLens;
use crate::geometry::{Interaction, Transform};
use crate::keys::{Coefficient, Direction, NonZero, Positive, Vector, throughput};
use crate::math::{Colour, HE_NE_WAVELENGTH};
use crate::surfaces::metatoys::{Blur, Pixels};
use crate::surfaces::{Redirection, Surface};

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
    /// The wavelength for which diffractive blur is simulated, if it is.
    pub lambda: Option<f64>,
}

impl LensletArray {
    /// The array of an object placed by `t` (a similarity map): its centre and directions move
    /// with the shape, its period and focal length scale with it.
    pub fn transformed(&self, t: &Transform) -> Result<LensletArray, String> {
        let s = super::length_scale(t)?;
        Ok(LensletArray {
            centre: t.point(self.centre),
            u: super::direction(t, self.u),
            v: super::direction(t, self.v),
            period: self.period * s,
            focal_length: self.focal_length * s,
            ..*self
        })
    }

    /// The lenslet met at `s`, where the surface normal is `n`.
    pub fn lenslet(&self, s: DVec3, n: DVec3) -> ThinLens {
        let along = |a: DVec3| (a - a.dot(n) * n).normalize_or_zero();
        let (u, v) = (along(self.u), along(self.v));
        let r = s - self.centre;
        // (α, β) from the Gram system [1 g; g 1] (α, β) = (r·û, r·v̂), g = û·v̂.
        let g = u.dot(v);
        let det = 1.0 - g * g;
        let (ru, rv) = (r.dot(u), r.dot(v));
        let (alpha, beta) = ((ru - g * rv) / det, (rv - g * ru) / det);
        let cell = |x: f64, p: f64| p * (x / p + 0.5).floor();
        ThinLens {
            principal_point: self.centre
                + cell(alpha, self.period.x) * u
                + cell(beta, self.period.y) * v,
            optical_axis: n,
            focal_length: self.focal_length,
            gradient: None,
            transmission_coefficient: self.transmission_coefficient,
        }
    }

    pub fn redirect(&self, at: &Interaction) -> Redirection<'static> {
        let s = at.local_point();
        let lens = self.lenslet(s, at.normal());
        let direction = lens.direction(at.ray.direction, s).normalize();
        match self.lambda {
            None => Redirection::Leaves {
                direction,
                factor: Colour::splat(self.transmission_coefficient),
            },
            // An evanescent result is reflected without loss, as in Dr TIM.
            Some(lambda) => Pixels {
                size: self.period,
                lambda,
                blur: Some(Blur::SingleSlit),
                ray_offset: false,
                sides: None,
            }
            .spread(at, direction, self.transmission_coefficient, 1.0),
        }
    }
}

/// `type = "ideal-thin-lenslet-array"`: lenslets of `focal_length` on the lattice of `period`
/// along `u_direction` and `v_direction` (not parallel) about `centre`; with
/// `simulate_diffractive_blur` (false, the behaviour of Dr TIM's `…Simple` array) blurred for
/// the wavelength `lambda` (632.8e-9, Dr TIM's GUI's).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IdealThinLensletArrayKeys {
    focal_length: Option<NonZero>,
    centre: Option<Vector>,
    u_direction: Option<Direction>,
    v_direction: Option<Direction>,
    period: Option<[NonZero; 2]>,
    #[serde(alias = "transmission")]
    transmission_coefficient: Option<Coefficient>,
    simulate_diffractive_blur: Option<bool>,
    lambda: Option<Positive>,
}

impl IdealThinLensletArrayKeys {
    pub fn build(self) -> Result<Surface, String> {
        // Dr TIM's `EditableRectangularLensletArray(parent, studio)`: centred on (0, 0, 10),
        // spanned by x and y, lenslets of focal length 1 and period 0.1 × 0.1.
        let u = self.u_direction.map_or(DVec3::X, |d| d.0);
        let v = self.v_direction.map_or(DVec3::Y, |d| d.0);
        let [pu, pv] = self.period.map_or([0.1, 0.1], |p| p.map(|p| p.0));
        if pu <= 0.0 || pv <= 0.0 {
            return Err(format!(
                "ideal-thin-lenslet-array: period = [{pu}, {pv}] must be positive"
            ));
        }
        if u.cross(v).length() < 1e-9 {
            return Err(format!(
                "ideal-thin-lenslet-array: v_direction = {v} must not be parallel to u_direction = {u}"
            ));
        }
        Ok(Surface::IdealThinLensletArray(LensletArray {
            centre: self.centre.map_or(DVec3::new(0.0, 0.0, 10.0), |c| c.0),
            u,
            v,
            period: DVec2::new(pu, pv),
            focal_length: self.focal_length.map_or(1.0, |f| f.0),
            transmission_coefficient: throughput(self.transmission_coefficient),
            lambda: self
                .simulate_diffractive_blur
                .unwrap_or(false)
                .then(|| self.lambda.map_or(HE_NE_WAVELENGTH, |l| l.0)),
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A parallel beam along the axis is focused, cell by cell, a focal length behind each
    /// lenslet's centre.
    #[test]
    fn each_cell_focuses_on_its_own_centre() {
        let array = LensletArray {
            centre: DVec3::new(0.25, 0.0, 2.0),
            u: DVec3::X,
            v: DVec3::new(0.0, 1.0, 0.5),
            period: DVec2::new(1.0, 0.5),
            focal_length: 0.4,
            transmission_coefficient: 1.0,
            lambda: None,
        };
        for (s, cell) in [
            (DVec3::new(1.2, -0.3, 2.0), DVec3::new(1.25, -0.5, 2.0)),
            (DVec3::new(-0.4, 0.74, 2.0), DVec3::new(-0.75, 0.5, 2.0)),
            (DVec3::new(0.3, 0.1, 2.0), DVec3::new(0.25, 0.0, 2.0)),
        ] {
            let lens = array.lenslet(s, DVec3::Z);
            assert!(
                (lens.principal_point - cell).length() < 1e-15,
                "{s}: {}",
                lens.principal_point
            );
            let out = lens.direction(DVec3::Z, s);
            let focus = s + out * (0.4 / out.z);
            assert!(
                (focus - (cell + 0.4 * DVec3::Z)).length() < 1e-15,
                "{focus}"
            );
        }
    }

    /// With oblique directions the cells are those of the (û, v̂) lattice: S = (1, −1, 0) has
    /// coordinates (2, −√2) along û = x̂ and v̂ = (x̂ + ŷ)/√2, so it lies in cell (2, −1),
    /// whose centre is 2û − v̂ (Dr TIM's `toBasis`, not the projections r·û, r·v̂).
    #[test]
    fn oblique_directions_make_an_oblique_lattice() {
        let v = DVec3::new(1.0, 1.0, 0.0).normalize();
        let array = LensletArray {
            centre: DVec3::ZERO,
            u: DVec3::X,
            v,
            period: DVec2::ONE,
            focal_length: 1.0,
            transmission_coefficient: 1.0,
            lambda: None,
        };
        let lens = array.lenslet(DVec3::new(1.0, -1.0, 0.0), DVec3::Z);
        let expected = 2.0 * DVec3::X - v;
        assert!(
            (lens.principal_point - expected).length() < 1e-15,
            "{}",
            lens.principal_point
        );
    }
}
