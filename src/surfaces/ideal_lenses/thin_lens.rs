//! The ideal thin lens, spherical or cylindrical (Dr TIM's `IdealThinLensSurfaceSimple` and
//! `IdealThinCylindricalLensSurfaceSimple`).
//!
//! With principal point P, unit optical axis â and focal length f, a ray with direction d
//! meeting the lens at S leaves with direction
//!
//!   d′ ∝ d/|d·â| + (P − S)/f,
//!
//! the direction from S to the point P + f d/|d·â| of the focal plane (at axial distance f
//! beyond the lens) where the undeviated ray through P with the same direction meets it: rays
//! through P pass undeviated and parallel rays meet in the focal plane, for either sign of f
//! and either sign of â. A cylindrical lens has power only along its gradient direction ĝ
//! (perpendicular to â): only the ĝ component of P − S counts.

use glam::DVec3;
use serde::Deserialize;

use crate::geometry::{Interaction, Transform};
use crate::keys::{Coefficient, Direction, NonZero, Vector, throughput};
use crate::surfaces::{Redirection, Surface};

#[derive(Debug, Clone, PartialEq)]
pub struct ThinLens {
    /// The point P every undeviated ray passes through.
    pub principal_point: DVec3,
    /// Unit vector along the optical axis (its sign does not matter).
    pub optical_axis: DVec3,
    /// f: positive for a converging lens, negative for a diverging one; finite and non-zero.
    pub focal_length: f64,
    /// For a cylindrical lens, the unit direction ĝ (perpendicular to the axis) in which it has
    /// power; `None` for a spherical lens.
    pub gradient: Option<DVec3>,
    /// Fraction of the light transmitted, in [0, 1].
    pub transmission_coefficient: f64,
}

impl ThinLens {
    /// The lens of an object placed by `t` (a similarity map): its point and directions move
    /// with the shape, its focal length scales with it.
    pub fn transformed(&self, t: &Transform) -> Result<ThinLens, String> {
        Ok(ThinLens {
            principal_point: t.point(self.principal_point),
            optical_axis: super::direction(t, self.optical_axis),
            focal_length: self.focal_length * super::length_scale(t)?,
            gradient: self.gradient.map(|g| super::direction(t, g)),
            transmission_coefficient: self.transmission_coefficient,
        })
    }

    /// The direction (not normalised) a ray with direction `d` leaves in where it meets the
    /// lens at `s`; a ray along the lens plane (d·â = 0) continues undeviated.
    pub fn direction(&self, d: DVec3, s: DVec3) -> DVec3 {
        let da = d.dot(self.optical_axis).abs();
        if da == 0.0 {
            return d;
        }
        let to_centre = self.principal_point - s;
        let bend = match self.gradient {
            None => to_centre,
            Some(g) => to_centre.dot(g) * g,
        };
        d / da + bend / self.focal_length
    }

    pub fn redirect(&self, at: &Interaction) -> Redirection<'static> {
        super::leaving(
            at,
            |d, s| self.direction(d, s),
            self.transmission_coefficient,
        )
    }
}

/// The keys of the ideal thin cylindrical lens and of the ideal thin mirrors (Dr TIM's GUI
/// has none of them, so they have no defaults), and what the spherical lens's make.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ThinLensKeys {
    focal_length: NonZero,
    principal_point: Vector,
    optical_axis: Direction,
}

impl ThinLensKeys {
    /// The lens, cylindrical if a gradient direction is given (made perpendicular to the
    /// optical axis, along which it must not lie); `name` is the kind's, for errors.
    pub fn lens(
        self,
        name: &str,
        gradient: Option<Direction>,
        coefficient: f64,
    ) -> Result<ThinLens, String> {
        let a = self.optical_axis.0;
        let gradient = match gradient {
            None => None,
            Some(g) if a.cross(g.0).length() < 1e-9 => {
                return Err(format!(
                    "{name}: gradient_direction = {} must not be parallel to optical_axis = {a}",
                    g.0
                ));
            }
            Some(g) => Some((g.0 - g.0.dot(a) * a).normalize()),
        };
        Ok(ThinLens {
            principal_point: self.principal_point.0,
            optical_axis: a,
            focal_length: self.focal_length.0,
            gradient,
            transmission_coefficient: coefficient,
        })
    }
}

/// `type = "ideal-thin-lens"`: the lens of Dr TIM's `EditableThinLens` as its GUI makes it,
/// where not given: focal length 1, principal point (0, 0, 10), optical axis along −z,
/// transmission coefficient 0.96.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IdealThinLensKeys {
    focal_length: Option<NonZero>,
    principal_point: Option<Vector>,
    optical_axis: Option<Direction>,
    #[serde(alias = "transmission")]
    transmission_coefficient: Option<Coefficient>,
}

impl IdealThinLensKeys {
    pub fn build(self) -> Result<Surface, String> {
        let lens = ThinLensKeys {
            focal_length: self.focal_length.unwrap_or(NonZero(1.0)),
            principal_point: self
                .principal_point
                .unwrap_or(Vector(DVec3::new(0.0, 0.0, 10.0))),
            optical_axis: self.optical_axis.unwrap_or(Direction(DVec3::NEG_Z)),
        };
        let coefficient = throughput(self.transmission_coefficient);
        Ok(Surface::IdealThinLens(lens.lens(
            "ideal-thin-lens",
            None,
            coefficient,
        )?))
    }
}

/// `type = "ideal-thin-cylindrical-lens"`: power along `gradient_direction` only.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IdealThinCylindricalLensKeys {
    #[serde(flatten)]
    lens: ThinLensKeys,
    gradient_direction: Direction,
    #[serde(alias = "transmission")]
    transmission_coefficient: Option<Coefficient>,
}

impl IdealThinCylindricalLensKeys {
    pub fn build(self) -> Result<Surface, String> {
        let coefficient = throughput(self.transmission_coefficient);
        let gradient = Some(self.gradient_direction);
        let lens = self
            .lens
            .lens("ideal-thin-cylindrical-lens", gradient, coefficient)?;
        Ok(Surface::IdealThinLens(lens))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lens(f: f64, gradient: Option<DVec3>) -> ThinLens {
        ThinLens {
            principal_point: DVec3::new(0.3, -0.2, 1.0),
            optical_axis: DVec3::Z,
            focal_length: f,
            gradient,
            transmission_coefficient: 1.0,
        }
    }

    #[test]
    fn rays_through_the_principal_point_are_undeviated() {
        for f in [2.0, -0.5] {
            let l = lens(f, None);
            let d = DVec3::new(0.4, 0.1, -0.9).normalize();
            let out = l.direction(d, l.principal_point).normalize();
            assert!((out - d).length() < 1e-15, "{out}");
        }
    }

    /// Parallel rays meet in the focal plane, z = 1 + f for rays travelling along +z; the
    /// point is where the chief ray (through P) meets it.
    #[test]
    fn parallel_rays_meet_in_the_focal_plane() {
        let l = lens(2.0, None);
        let d = DVec3::new(0.2, -0.1, 1.0);
        let chief = l.principal_point + d * (2.0 / d.z);
        for (x, y) in [(1.0, 0.0), (-0.7, 0.4), (0.0, 2.5)] {
            let s = DVec3::new(x, y, 1.0);
            let out = l.direction(d, s);
            let meet = s + out * ((chief.z - s.z) / out.z);
            assert!((meet - chief).length() < 1e-14, "{meet} {chief}");
        }
    }

    #[test]
    fn a_cylindrical_lens_bends_only_along_its_gradient() {
        let l = lens(1.5, Some(DVec3::X));
        let d = DVec3::new(0.1, 0.2, 1.0);
        let s = DVec3::new(1.3, 0.8, 1.0);
        let out = l.direction(d, s);
        // Along y (no power) the direction is unchanged, along x it focuses.
        assert!((out.y / out.z - d.y / d.z).abs() < 1e-15);
        let chief_x = l.principal_point.x + 1.5 * d.x / d.z;
        assert!((s.x + out.x * 1.5 / out.z - chief_x).abs() < 1e-15);
    }
}
