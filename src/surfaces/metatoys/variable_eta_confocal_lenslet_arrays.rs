//! Confocal lenslet arrays whose η varies linearly across the sheet (Dr TIM's
//! `VariableEtaConfocalLensletArrays`, a `RefractiveAngleFormulation`): the ray stays in its
//! plane of incidence, and its angle of incidence α (from the normal, always positive) changes
//! as at CLAs with telescopes along the normal, whose η at a point Q is
//! η(Q) = η_P + (Q − P)·∇η, η_P being η at the point P for light crossing inwards:
//!
//! tan α′ = tan(α) / η(Q) crossing inwards (against the outward normal),
//! tan α′ = tan(α) · η(Q) crossing outwards,
//!
//! with α′ = atan(…) from −90° to 90° (a negative η turns the ray to the other side of the
//! normal), on the side the ray travels to, carrying the transmission coefficient. At a point
//! of constant η this is `confocal-lenslet-arrays` with â the inward normal, η_u = η_v = η and no
//! offset (Eq 39 with the slopes scaled alike). At normal incidence the ray passes undeviated.

use glam::DVec3;
use serde::Deserialize;

use crate::geometry::{Interaction, Transform};
use crate::keys::{Coefficient, Finite, Vector, throughput};
use crate::math::Colour;
use crate::surfaces::{Redirection, Surface};

#[derive(Debug, Clone, PartialEq)]
pub struct VariableEtaConfocalLensletArrays {
    /// η at `point_p` for light crossing inwards.
    pub inwards_eta_at_p: f64,
    pub point_p: DVec3,
    /// ∇η.
    pub grad_eta: DVec3,
    /// Fraction of the light transmitted, in [0, 1].
    pub transmission_coefficient: f64,
}

impl VariableEtaConfocalLensletArrays {
    /// η at the point `q`, for light crossing inwards.
    pub fn inwards_eta(&self, q: DVec3) -> f64 {
        self.inwards_eta_at_p + (q - self.point_p).dot(self.grad_eta)
    }

    /// The unit direction leaving for the unit direction `d` at the point `q` with outward unit
    /// normal `n`.
    pub fn refract(&self, d: DVec3, n: DVec3, q: DVec3) -> DVec3 {
        let cos = d.dot(n);
        let tangential = d - cos * n;
        let sin = tangential.length();
        if sin == 0.0 {
            return d;
        }
        let tan = sin / cos.abs();
        let eta = self.inwards_eta(q);
        let alpha = if cos > 0.0 { tan * eta } else { tan / eta }.atan();
        cos.signum() * alpha.cos() * n + alpha.sin() * (tangential / sin)
    }

    pub fn redirect(&self, at: &Interaction) -> Redirection<'static> {
        Redirection::Leaves {
            direction: self.refract(at.ray.direction.normalize(), at.normal(), at.local_point()),
            factor: Colour::splat(self.transmission_coefficient),
        }
    }

    /// The arrays of an object placed by `t`, which must keep angles (a rotation, uniform
    /// scaling by s and translation): P moves with it, and ∇η turns and shrinks by 1/s.
    pub fn transformed(&self, t: &Transform) -> Result<VariableEtaConfocalLensletArrays, String> {
        let s = t.uniform_scale().ok_or(
            "variable-eta confocal lenslet arrays work in the plane of incidence, which only \
             rotations, uniform scaling and translations keep, so they cannot be scaled \
             non-uniformly",
        )?;
        Ok(VariableEtaConfocalLensletArrays {
            point_p: t.point(self.point_p),
            grad_eta: t.vector(self.grad_eta) / (s * s),
            ..*self
        })
    }
}

/// `type = "variable-eta-confocal-lenslet-arrays"`: `inwards_eta_at_p` (Dr TIM's GUI default
/// 1), `point_p` ([0, 0, 0]), `grad_eta` ([1, 0, 0]) and `transmission_coefficient` (0.96).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VariableEtaConfocalLensletArraysKeys {
    inwards_eta_at_p: Option<Finite>,
    point_p: Option<Vector>,
    grad_eta: Option<Vector>,
    #[serde(alias = "transmission")]
    transmission_coefficient: Option<Coefficient>,
}

impl VariableEtaConfocalLensletArraysKeys {
    pub fn build(self) -> Result<Surface, String> {
        Ok(Surface::VariableEtaConfocalLensletArrays(
            VariableEtaConfocalLensletArrays {
                inwards_eta_at_p: self.inwards_eta_at_p.map_or(1.0, |e| e.0),
                point_p: self.point_p.map_or(DVec3::ZERO, |p| p.0),
                grad_eta: self.grad_eta.map_or(DVec3::X, |g| g.0),
                transmission_coefficient: throughput(self.transmission_coefficient),
            },
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn arrays() -> VariableEtaConfocalLensletArrays {
        VariableEtaConfocalLensletArrays {
            inwards_eta_at_p: 2.0,
            point_p: DVec3::new(1.0, 0.0, 0.0),
            grad_eta: DVec3::new(0.5, 0.0, 0.0),
            transmission_coefficient: 0.96,
        }
    }

    /// At x = 3, η = 2 + 0.5 · 2 = 3: a ray crossing inwards at 45° leaves at atan(1/3), one
    /// crossing outwards at 30° at atan(√3), in its plane of incidence (here y–z).
    #[test]
    fn the_tangent_of_the_angle_scales_by_the_local_eta() {
        let a = arrays();
        let q = DVec3::new(3.0, 0.0, 0.0);
        let inwards = a.refract(DVec3::new(0.0, 1.0, -1.0).normalize(), DVec3::Z, q);
        let alpha = (1.0f64 / 3.0).atan();
        assert!((inwards - DVec3::new(0.0, alpha.sin(), -alpha.cos())).length() < 1e-15);
        let outwards = a.refract(DVec3::new(0.0, 0.5, 0.75f64.sqrt()), DVec3::Z, q);
        let alpha = (30f64.to_radians().tan() * 3.0).atan();
        assert!((outwards - DVec3::new(0.0, alpha.sin(), alpha.cos())).length() < 1e-15);
        // Where η is negative (x < −3) the ray turns to the other side of the normal.
        let flipped = a.refract(
            DVec3::new(0.0, 1.0, -1.0).normalize(),
            DVec3::Z,
            -5.0 * DVec3::X,
        );
        assert!(flipped.y < 0.0 && flipped.z < 0.0);
    }

    #[test]
    fn dr_tims_gui_defaults() {
        let keys: VariableEtaConfocalLensletArraysKeys = toml::from_str("").unwrap();
        assert_eq!(
            keys.build().unwrap(),
            Surface::VariableEtaConfocalLensletArrays(VariableEtaConfocalLensletArrays {
                inwards_eta_at_p: 1.0,
                point_p: DVec3::ZERO,
                grad_eta: DVec3::X,
                transmission_coefficient: 0.96,
            })
        );
    }
}
