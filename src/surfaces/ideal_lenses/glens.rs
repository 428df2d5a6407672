//! The glens, a generalised lens with different focal lengths on its two sides (Chaplain,
//! Courtial et al., JOSA A 33, 962 (2016); Dr TIM's `GlensSurface`, and with finite focal
//! lengths its `SimpleGlensHologram`).
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
//!
//! A *homogeneous* glens is the limit of infinite focal lengths with their ratio f₋/f₊ = ρ
//! fixed (Dr TIM's `GlensSurface` with g = ∞): the same law with (f₋, f₊) → (ρ, 1) and
//! N − S → (ρ + 1) n̂/(n̂·â), for the nodal direction n̂ along which rays pass undeviated. It
//! does not depend on where the ray meets it.

use glam::{DMat3, DMat4, DVec3};
use serde::Deserialize;

use crate::geometry::{Interaction, Transform};
use crate::keys::{Coefficient, Direction, NonZero, Vector, throughput};
use crate::surfaces::{Redirection, Surface};

/// A glens's focal lengths and nodal point, finite or at infinity.
#[derive(Debug, Clone, PartialEq)]
pub enum Focus {
    /// f₋ and f₊, finite and non-zero, with the principal point P.
    Finite {
        principal_point: DVec3,
        focal_length_negative: f64,
        focal_length_positive: f64,
    },
    /// A homogeneous glens: f₋/f₊ = `ratio` (finite, non-zero) and the unit nodal direction
    /// (not perpendicular to the optical axis).
    Homogeneous { nodal_direction: DVec3, ratio: f64 },
}

#[derive(Debug, Clone, PartialEq)]
pub struct Glens {
    /// Unit vector along the optical axis, pointing into positive space.
    pub optical_axis: DVec3,
    pub focus: Focus,
    /// Fraction of the light transmitted, in [0, 1].
    pub transmission_coefficient: f64,
}

impl Glens {
    /// The glens of an object placed by `t` (a similarity map): its point and directions move
    /// with the shape, its focal lengths scale with it.
    pub fn transformed(&self, t: &Transform) -> Result<Glens, String> {
        let s = super::length_scale(t)?;
        let focus = match self.focus {
            Focus::Finite {
                principal_point,
                focal_length_negative,
                focal_length_positive,
            } => Focus::Finite {
                principal_point: t.point(principal_point),
                focal_length_negative: focal_length_negative * s,
                focal_length_positive: focal_length_positive * s,
            },
            Focus::Homogeneous {
                nodal_direction,
                ratio,
            } => Focus::Homogeneous {
                nodal_direction: super::direction(t, nodal_direction),
                ratio,
            },
        };
        Ok(Glens {
            optical_axis: super::direction(t, self.optical_axis),
            focus,
            transmission_coefficient: self.transmission_coefficient,
        })
    }

    /// The glens in the plane through `point` normal to `optical_axis` that images negative
    /// space into positive space by the projective map `h` (homogeneous coordinates, lengths of
    /// order 1: a device works it out in its own units), which must fix that plane point by
    /// point: a central collineation, whose centre is the nodal point, f₋ the axial coordinate
    /// of the plane it sends to infinity and f₊ that of the plane it brings from there (an
    /// affine `h` makes a homogeneous glens, the identity one of ratio −1). Dr TIM's
    /// `GlensSurface.setParametersUsingTwoConjugatePairs` finds the same glens from two of
    /// `h`'s conjugate pairs.
    pub fn imaging(
        point: DVec3,
        optical_axis: DVec3,
        h: DMat4,
        transmission_coefficient: f64,
    ) -> Result<Glens, String> {
        let a = optical_axis.normalize();
        // In coordinates y = x − point, scaled so that h fixes the plane's points with λ = 1
        // (h Y = λ Y there); the tolerances below take lengths of order 1.
        let to = DMat4::from_translation(point);
        let h = to.inverse() * h * to;
        let lambda = h.w_axis.w;
        let (u, v) = a.any_orthonormal_pair();
        let fixed = lambda.abs()
            > 1e-12
                * h.abs()
                    .to_cols_array()
                    .iter()
                    .fold(0.0, |m: f64, x| m.max(*x))
            && [DVec3::ZERO, u, v].iter().all(|&y| {
                let image = h * y.extend(1.0) / lambda;
                (image - y.extend(1.0)).length() <= 1e-9
            });
        if !fixed {
            return Err(format!(
                "the imaging does not fix the glens's plane through {point} normal to {a}"
            ));
        }
        let h = h / lambda;
        // h − I = c wᵀ: its largest column is along the centre c.
        let rest = h - DMat4::IDENTITY;
        let centre = [rest.x_axis, rest.y_axis, rest.z_axis, rest.w_axis]
            .into_iter()
            .max_by(|p, q| p.length().total_cmp(&q.length()))
            .expect("four columns");
        let homogeneous = |nodal_direction: DVec3| -> Result<Focus, String> {
            // Axial coordinates scale by k; the ratio f₋/f₊ is −1/k.
            let image = h * a.extend(1.0);
            let k = (image.truncate() / image.w).dot(a);
            if !k.is_finite() || k.abs() <= 1e-12 || nodal_direction.dot(a).abs() <= 1e-12 {
                return Err(format!(
                    "the imaging at the glens's plane through {point} is singular or a shear"
                ));
            }
            Ok(Focus::Homogeneous {
                nodal_direction,
                ratio: -1.0 / k,
            })
        };
        let focus = if centre.length() <= 1e-12 {
            homogeneous(a)?
        } else if centre.w.abs() <= 1e-12 * centre.truncate().length() {
            homogeneous(centre.truncate().normalize())?
        } else {
            let nodal = centre.truncate() / centre.w;
            let infinity = h * a.extend(0.0);
            let f_pos = (infinity.truncate() / infinity.w).dot(a);
            let f_sum = nodal.dot(a);
            let f_neg = f_sum - f_pos;
            if !(f_pos.is_finite() && f_pos != 0.0 && f_neg.is_finite() && f_neg != 0.0) {
                return Err(format!(
                    "the imaging at the glens's plane through {point} has a focal length of 0"
                ));
            }
            Focus::Finite {
                principal_point: point + nodal - f_sum * a,
                focal_length_negative: f_neg,
                focal_length_positive: f_pos,
            }
        };
        Ok(Glens {
            optical_axis: a,
            focus,
            transmission_coefficient,
        })
    }

    /// The glens in the plane through `point` normal to `optical_axis` (pointing into positive
    /// space) that images `q_neg` to `q_pos` and `r_neg` to `r_pos`, as Dr TIM's
    /// `GlensSurface.setParametersUsingTwoConjugatePairs` finds it: where the lines Q₋Q₊ and
    /// R₋R₊ are parallel, the homogeneous glens of the pair Q; otherwise the nodal point N is
    /// where those lines meet, and the focal lengths follow from the pair Q by the glens
    /// equation with f₋ + f₊ = (N − P)·â. Lines that do not meet are refused.
    pub fn from_conjugate_pairs(
        point: DVec3,
        optical_axis: DVec3,
        (q_neg, q_pos): (DVec3, DVec3),
        (r_neg, r_pos): (DVec3, DVec3),
        transmission_coefficient: f64,
    ) -> Result<Glens, String> {
        let a = optical_axis.normalize();
        let (q, r) = ((q_pos - q_neg).normalize(), (r_pos - r_neg).normalize());
        let scale = [q_neg, q_pos, r_neg, r_pos]
            .iter()
            .fold(0.0_f64, |m, x| m.max((*x - point).length()));
        let (a_neg, a_pos) = ((q_neg - point).dot(a), (q_pos - point).dot(a));
        let none =
            || format!("no glens through {point} images {q_neg} to {q_pos} and {r_neg} to {r_pos}");
        if !(q.is_finite() && r.is_finite()) {
            return Err(none());
        }
        let focus = if q.cross(r).length_squared() < 1e-10 {
            // Homogeneous: the lines through Q₊R₊ and Q₋R₋ must meet the plane together.
            let meet = |p: DVec3, d: DVec3| point_on_plane(p, d, point, a);
            let consistent = match (meet(q_pos, r_pos - q_pos), meet(q_neg, r_neg - q_neg)) {
                (Some(on_pos), Some(on_neg)) => (on_pos - on_neg).length() <= 1e-9 * scale,
                (None, None) => {
                    (r_pos - q_pos)
                        .normalize()
                        .cross((r_neg - q_neg).normalize())
                        .length()
                        < 1e-9
                }
                _ => false,
            };
            if !consistent || a_neg == 0.0 || a_pos == 0.0 || a_neg == a_pos {
                return Err(format!("{}: no homogeneous one", none()));
            }
            Focus::Homogeneous {
                nodal_direction: q,
                ratio: -a_neg / a_pos,
            }
        } else {
            // The point nearest both lines, Σᵢ (I − vᵢvᵢᵀ) N = Σᵢ (I − vᵢvᵢᵀ) pᵢ.
            let across = |v: DVec3| DMat3::IDENTITY - DMat3::from_cols(v * v.x, v * v.y, v * v.z);
            let nodal = (across(q) + across(r)).inverse() * (across(q) * q_neg + across(r) * r_neg);
            let miss = (nodal - q_neg)
                .reject_from_normalized(q)
                .length()
                .max((nodal - r_neg).reject_from_normalized(r).length());
            if miss > 1e-9 * scale {
                return Err(format!(
                    "no glens through {point} images {q_neg} to {q_pos} and {r_neg} to {r_pos}: \
                     the lines through them miss each other by {miss}"
                ));
            }
            let principal_point = nodal - (nodal - point).dot(a) * a;
            let n = (nodal - principal_point).dot(a);
            // On the line through N, x₊ − N = k (x₋ − N), so with b₋ = a₋ − n the glens
            // equation f₊/a₊ + f₋/a₋ = 1 and f₋ + f₊ = n give f₊ = a₊/(1 − k) = (n + k b₋)/(1 − k):
            // Dr TIM's f₊ = a₊ (n − a₋)/(a₊ − a₋), but defined also where the pair lies in the
            // plane through N parallel to the glens (a₊ = a₋ = n, where Dr TIM's divides 0 by 0).
            // The pair further from N, Dr TIM's the pair Q.
            let (x_neg, x_pos) = if (r_neg - nodal).length() > (q_neg - nodal).length() {
                (r_neg, r_pos)
            } else {
                (q_neg, q_pos)
            };
            let off = x_neg - nodal;
            let k = (x_pos - nodal).dot(off) / off.length_squared();
            let b_neg = (x_neg - principal_point).dot(a) - n;
            let focal_length_positive = (n + k * b_neg) / (1.0 - k);
            let focal_length_negative = n - focal_length_positive;
            if !(focal_length_negative.is_finite()
                && focal_length_positive.is_finite()
                && focal_length_negative != 0.0
                && focal_length_positive != 0.0)
            {
                return Err(none());
            }
            Focus::Finite {
                principal_point,
                focal_length_negative,
                focal_length_positive,
            }
        };
        let glens = Glens {
            optical_axis: a,
            focus,
            transmission_coefficient,
        };
        // Both pairs must be imaged (as Dr TIM checks).
        for (x_neg, x_pos) in [(q_neg, q_pos), (r_neg, r_pos)] {
            let image = glens.image(x_neg, point, true);
            if image.is_none_or(|i| (i - x_pos).length() > 1e-9 * scale) {
                return Err(format!("{}: the pairs do not fit one glens", none()));
            }
        }
        Ok(glens)
    }

    /// The image of `object` (in negative space if `into_positive`, else in positive space),
    /// in the glens's plane through `point`: on the line through the object and N, its axial
    /// coordinate a′ from a by f₊/a′ + f₋/a = 1 (Dr TIM's `getImagePosition`). `None` where it
    /// is at infinity (the object in the focal plane).
    pub fn image(&self, object: DVec3, point: DVec3, into_positive: bool) -> Option<DVec3> {
        let a = (object - point).dot(self.optical_axis);
        let image = match self.focus {
            Focus::Finite {
                focal_length_negative,
                focal_length_positive,
                ..
            } => {
                let f = if into_positive {
                    focal_length_negative
                } else {
                    focal_length_positive
                };
                let nodal = self.nodal_point().expect("finite");
                object + (object - nodal) * (a / (f - a))
            }
            Focus::Homogeneous {
                nodal_direction,
                ratio,
            } => {
                let f = if into_positive { ratio } else { 1.0 };
                let nodal =
                    (ratio + 1.0) / nodal_direction.dot(self.optical_axis) * nodal_direction;
                object - nodal * (a / f)
            }
        };
        image.is_finite().then_some(image)
    }

    /// N = P + (f₋ + f₊) â, for finite focal lengths.
    pub fn nodal_point(&self) -> Option<DVec3> {
        match self.focus {
            Focus::Finite {
                principal_point,
                focal_length_negative,
                focal_length_positive,
            } => Some(
                principal_point
                    + (focal_length_negative + focal_length_positive) * self.optical_axis,
            ),
            Focus::Homogeneous { .. } => None,
        }
    }

    /// The direction (not normalised) a ray with direction `d` leaves in where it meets the
    /// glens at `s`; a ray along the glens plane (d_a = 0) continues undeviated.
    pub fn direction(&self, d: DVec3, s: DVec3) -> DVec3 {
        let a = self.optical_axis;
        // (f₋, f₊) and N − S, or their homogeneous limits (in units of f₊).
        let (f_neg, f_pos, to_nodal) = match self.focus {
            Focus::Finite {
                principal_point,
                focal_length_negative: f_neg,
                focal_length_positive: f_pos,
            } => (f_neg, f_pos, principal_point + (f_neg + f_pos) * a - s),
            Focus::Homogeneous {
                nodal_direction: n,
                ratio,
            } => (ratio, 1.0, (ratio + 1.0) / n.dot(a) * n),
        };
        let da = d.dot(a);
        let (f_o, f_i) = if da > 0.0 {
            (f_neg, f_pos)
        } else if da < 0.0 {
            (f_pos, f_neg)
        } else {
            return d;
        };
        -(f_o / f_i) * d + (da / f_i) * to_nodal
    }

    pub fn redirect(&self, at: &Interaction) -> Redirection<'static> {
        super::leaving(
            at,
            |d, s| self.direction(d, s),
            self.transmission_coefficient,
        )
    }
}

/// Where the line through `p` along `d` meets the plane through `point` normal to `a`; `None`
/// where it runs along the plane.
fn point_on_plane(p: DVec3, d: DVec3, point: DVec3, a: DVec3) -> Option<DVec3> {
    let along = d.dot(a);
    (along.abs() > 1e-12 * d.length()).then(|| p + d * ((point - p).dot(a) / along))
}

/// `type = "glens"`: finite focal lengths with a principal point, or (homogeneous) a nodal
/// direction and the ratio f₋/f₊, both of which must then be given, and none of the other
/// set. The finite set and the axis take the defaults of Dr TIM's `EditableGlens(parent,
/// studio)` where not given: principal point (0, 0, 5), f₋ = −2.5, f₊ = 2.5, axis along z.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GlensKeys {
    optical_axis: Option<Direction>,
    principal_point: Option<Vector>,
    focal_length_negative: Option<NonZero>,
    focal_length_positive: Option<NonZero>,
    nodal_direction: Option<Direction>,
    focal_length_ratio: Option<NonZero>,
    #[serde(alias = "transmission")]
    transmission_coefficient: Option<Coefficient>,
}

impl GlensKeys {
    pub fn build(self) -> Result<Surface, String> {
        let axis = self.optical_axis.map_or(DVec3::Z, |a| a.0);
        let finite = (
            self.principal_point,
            self.focal_length_negative,
            self.focal_length_positive,
        );
        let focus = match (finite, (self.nodal_direction, self.focal_length_ratio)) {
            ((p, f_neg, f_pos), (None, None)) => Focus::Finite {
                principal_point: p.map_or(DVec3::new(0.0, 0.0, 5.0), |p| p.0),
                focal_length_negative: f_neg.map_or(-2.5, |f| f.0),
                focal_length_positive: f_pos.map_or(2.5, |f| f.0),
            },
            ((None, None, None), (Some(n), Some(ratio))) => {
                // Directions are unit vectors: a cosine below 1e-9 is perpendicular.
                if n.0.dot(axis).abs() < 1e-9 {
                    return Err(format!(
                        "glens: nodal_direction = {} must not lie in the glens's plane (perpendicular to optical_axis = {axis})",
                        n.0
                    ));
                }
                Focus::Homogeneous {
                    nodal_direction: n.0,
                    ratio: ratio.0,
                }
            }
            _ => return Err("glens: give principal_point, focal_length_negative and focal_length_positive (a glens with finite focal lengths, Dr TIM's where not given), or nodal_direction and focal_length_ratio (a homogeneous glens, both), not a mixture".into()),
        };
        Ok(Surface::Glens(Glens {
            optical_axis: axis,
            focus,
            transmission_coefficient: throughput(self.transmission_coefficient),
        }))
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
            optical_axis: a,
            focus: Focus::Finite {
                principal_point: p,
                focal_length_negative: -f,
                focal_length_positive: f,
            },
            transmission_coefficient: 1.0,
        };
        assert_eq!(glens.nodal_point(), Some(p));
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

#[cfg(test)]
mod imaging {
    use super::*;

    /// The homology with centre `c`, the plane through `p` normal to `n` as its axis, and
    /// characteristic ratio μ: X ↦ X + (μ − 1) (w·X / w·C) C, with C = (c, 1) and w the plane.
    fn homology(c: DVec3, p: DVec3, n: DVec3, mu: f64) -> DMat4 {
        let big_c = c.extend(1.0);
        let w = n.extend(-n.dot(p));
        let outer = DMat4::from_cols(big_c * w.x, big_c * w.y, big_c * w.z, big_c * w.w);
        DMat4::IDENTITY + outer * ((mu - 1.0) / w.dot(big_c))
    }

    /// Every ray from a point Q of negative space that crosses the glens leaves on the line
    /// through S and h(Q), going on into positive space.
    #[track_caller]
    fn images(glens: &Glens, h: DMat4, p: DVec3, n: DVec3) {
        let (u, v) = n.any_orthonormal_pair();
        for (i, q) in [
            p - 2.0 * n + 0.3 * u,
            p - 0.5 * n - 0.7 * v + 0.2 * u,
            p - 7.0 * n + 1.1 * v,
        ]
        .into_iter()
        .enumerate()
        {
            let image = h * q.extend(1.0);
            for s in [p, p + 0.4 * u - 0.9 * v, p - 1.3 * u + 0.2 * v] {
                let d = glens.direction((s - q).normalize(), s).normalize();
                assert!(d.dot(n) > 0.0, "case {i}: {d} turns back");
                // d ∥ image − s S (homogeneous: image.xyz − image.w s).
                let to_image = image.truncate() - image.w * s;
                let sine = d.cross(to_image.normalize()).length();
                assert!(
                    sine < 1e-12,
                    "case {i}, S = {s}: {d} is not along {to_image}"
                );
            }
        }
    }

    #[test]
    fn a_homology_about_the_plane_becomes_the_glens_of_its_centre() {
        let (p, n) = (
            DVec3::new(0.2, -0.1, 1.0),
            DVec3::new(0.3, 0.4, 1.0).normalize(),
        );
        for (c, mu) in [
            (DVec3::new(0.5, 0.3, -1.5), 6.0),
            (DVec3::new(-0.4, 1.0, 3.0), -0.4),
            // The centre in the plane: an ideal thin lens.
            (p + DVec3::new(0.5, 0.0, -0.15), 1.0),
        ] {
            let h = if mu == 1.0 {
                // An elation: X ↦ X + (w·X) C, C in the plane.
                let big_c = c.extend(1.0);
                let w = n.extend(-n.dot(p)) * 0.7;
                DMat4::IDENTITY
                    + DMat4::from_cols(big_c * w.x, big_c * w.y, big_c * w.z, big_c * w.w)
            } else {
                homology(c, p, n, mu)
            };
            let glens = Glens::imaging(p, n, h, 1.0).unwrap();
            let nodal = glens.nodal_point().expect("finite");
            assert!(
                (nodal - c).length() < 1e-12,
                "nodal point {nodal}, centre {c}"
            );
            images(&glens, h, p, n);
        }
    }

    #[test]
    fn an_affine_map_about_the_plane_becomes_a_homogeneous_glens() {
        let (p, n) = (DVec3::new(0.0, 1.0, 2.0), DVec3::new(0.0, 0.6, 0.8));
        // x ↦ x + (k − 1) (n·(x − p)) m / (n·m): axial coordinates scale by k along m.
        let (m, k) = (DVec3::new(0.2, 0.5, 1.0), -2.5);
        let shift = m * ((k - 1.0) / n.dot(m));
        let linear =
            glam::DMat3::IDENTITY + glam::DMat3::from_cols(shift * n.x, shift * n.y, shift * n.z);
        let h = DMat4::from_mat3_translation(linear, p - linear * p);
        let glens = Glens::imaging(p, n, h, 1.0).unwrap();
        assert!(glens.nodal_point().is_none());
        images(&glens, h, p, n);
        let identity = Glens::imaging(p, n, DMat4::IDENTITY * 3.0, 1.0).unwrap();
        let d = DVec3::new(0.1, 0.2, 0.9).normalize();
        assert!((identity.direction(d, p).normalize() - d).length() < 1e-15);
    }

    #[test]
    fn a_map_that_moves_the_plane_is_refused() {
        let p = DVec3::new(0.0, 0.0, 1.0);
        let shifted = DMat4::from_translation(DVec3::new(0.0, 0.0, 0.1));
        let error = Glens::imaging(p, DVec3::Z, shifted, 1.0).unwrap_err();
        assert!(error.contains("does not fix"), "{error}");
    }
}

#[cfg(test)]
mod conjugate_pairs {
    use super::*;

    /// Where the light leaving `q` is seen after the glens: the meeting point of two rays from
    /// q through the plane point `p` (the glens's plane), redirected by the glens's law.
    fn seen(glens: &Glens, q: DVec3, p: DVec3) -> DVec3 {
        let (u, v) = glens.optical_axis.any_orthonormal_pair();
        let (s1, s2) = (p + 0.3 * u - 0.2 * v, p - 0.5 * u + 0.4 * v);
        let (d1, d2) = (
            glens.direction((s1 - q).normalize(), s1),
            glens.direction((s2 - q).normalize(), s2),
        );
        // s1 + t d1 = s2 + t' d2, least squares.
        let w = s2 - s1;
        let (a, b, c) = (d1.dot(d1), d1.dot(d2), d2.dot(d2));
        let (d, e) = (d1.dot(w), d2.dot(w));
        let t = (d * c - b * e) / (a * c - b * b);
        s1 + t * d1
    }

    #[test]
    fn two_conjugate_pairs_give_back_the_glens_that_images_them() {
        let a = DVec3::new(0.2, -0.3, 1.0).normalize();
        let p = DVec3::new(0.1, 0.4, 2.0);
        let (u, v) = a.any_orthonormal_pair();
        for focus in [
            Focus::Finite {
                principal_point: p + 0.3 * u,
                focal_length_negative: -0.7,
                focal_length_positive: 1.9,
            },
            Focus::Homogeneous {
                nodal_direction: (a + 0.4 * v).normalize(),
                ratio: -2.5,
            },
        ] {
            let glens = Glens {
                optical_axis: a,
                focus: focus.clone(),
                transmission_coefficient: 0.9,
            };
            let (q, r) = (p - 3.0 * a + 0.2 * u, p - 1.5 * a - 0.6 * v);
            let (q_image, r_image) = (seen(&glens, q, p), seen(&glens, r, p));
            for (object, image) in [(q, q_image), (r, r_image)] {
                let from = glens.image(object, p + u, true).expect("finite image");
                assert!((from - image).length() < 1e-9, "{from} {image}");
                let back = glens.image(image, p - v, false).expect("finite image");
                assert!((back - object).length() < 1e-9, "{back} {object}");
            }
            let made =
                Glens::from_conjugate_pairs(p + v, a, (q, q_image), (r, r_image), 0.9).unwrap();
            match (made.focus, focus) {
                (
                    Focus::Finite {
                        principal_point: p1,
                        focal_length_negative: n1,
                        focal_length_positive: f1,
                    },
                    Focus::Finite {
                        principal_point: p2,
                        focal_length_negative: n2,
                        focal_length_positive: f2,
                    },
                ) => {
                    assert!(
                        (p1 - p2).length() < 1e-9
                            && (n1 - n2).abs() < 1e-9
                            && (f1 - f2).abs() < 1e-9
                    );
                }
                (
                    Focus::Homogeneous {
                        nodal_direction: d1,
                        ratio: r1,
                    },
                    Focus::Homogeneous {
                        nodal_direction: d2,
                        ratio: r2,
                    },
                ) => {
                    assert!(d1.cross(d2).length() < 1e-9 && (r1 - r2).abs() < 1e-9);
                }
                (made, given) => panic!("{made:?} from {given:?}"),
            }
        }
    }

    /// Pairs in the plane through N parallel to the glens, where Dr TIM's formula divides 0 by
    /// 0: a point there moves away from N by −f₋/f₊ (the glens equation's a′ − n over a − n as
    /// a → n).
    #[test]
    fn pairs_in_the_nodal_plane_give_the_focal_lengths_by_their_scale() {
        let (f_neg, f_pos) = (0.6, -1.4);
        let glens = Glens {
            optical_axis: DVec3::Z,
            focus: Focus::Finite {
                principal_point: DVec3::ZERO,
                focal_length_negative: f_neg,
                focal_length_positive: f_pos,
            },
            transmission_coefficient: 1.0,
        };
        let n = f_neg + f_pos;
        let (q, r) = (DVec3::new(0.3, 0.1, n), DVec3::new(-0.2, 0.5, n));
        let (q_image, r_image) = (seen(&glens, q, DVec3::ZERO), seen(&glens, r, DVec3::ZERO));
        let made = Glens::from_conjugate_pairs(
            DVec3::new(1.0, 2.0, 0.0),
            DVec3::Z,
            (q, q_image),
            (r, r_image),
            1.0,
        )
        .unwrap();
        let Focus::Finite {
            principal_point,
            focal_length_negative,
            focal_length_positive,
        } = made.focus
        else {
            panic!("finite")
        };
        assert!(principal_point.length() < 1e-9, "{principal_point}");
        assert!(
            (focal_length_negative - f_neg).abs() < 1e-9,
            "{focal_length_negative}"
        );
        assert!(
            (focal_length_positive - f_pos).abs() < 1e-9,
            "{focal_length_positive}"
        );
    }

    /// Lines Q₋Q₊ and R₋R₊ that meet at N = 0, but no glens about N images both pairs: the
    /// glens that images R sends Q₋ to (−2, 0, 2).
    #[test]
    fn pairs_no_one_glens_images_are_refused() {
        let error = Glens::from_conjugate_pairs(
            DVec3::ZERO,
            DVec3::Z,
            (DVec3::new(1.0, 0.0, -1.0), DVec3::new(-1.0, 0.0, 1.0)),
            (DVec3::new(0.0, 1.0, -1.0), DVec3::new(0.0, -2.0, 2.0)),
            1.0,
        )
        .unwrap_err();
        assert!(error.contains("do not fit one glens"), "{error}");
    }

    #[test]
    fn pairs_no_glens_images_are_refused() {
        // Lines Q₋Q₊ and R₋R₊ that miss each other.
        let error = Glens::from_conjugate_pairs(
            DVec3::ZERO,
            DVec3::Z,
            (DVec3::new(0.0, 0.0, -1.0), DVec3::new(0.1, 0.0, 1.0)),
            (DVec3::new(1.0, 0.0, -1.0), DVec3::new(1.0, 0.3, 1.0)),
            1.0,
        )
        .unwrap_err();
        assert!(error.contains("miss each other"), "{error}");
    }
}

#[cfg(test)]
mod homogeneous {
    use super::*;

    /// The homogeneous glens is the limit of glenses with focal lengths g ρ and g whose nodal
    /// point moves off to infinity along n̂ (N = P + g (ρ + 1) n̂/(n̂·â)) as g grows.
    #[test]
    fn it_is_the_limit_of_ever_longer_focal_lengths() {
        let (a, n, ratio) = (
            DVec3::new(0.0, 0.6, 0.8),
            DVec3::new(0.3, 0.2, 0.9).normalize(),
            -0.7,
        );
        let homogeneous = Glens {
            optical_axis: a,
            focus: Focus::Homogeneous {
                nodal_direction: n,
                ratio,
            },
            transmission_coefficient: 1.0,
        };
        let (d, s) = (DVec3::new(0.2, -0.1, 1.0), DVec3::new(0.4, 0.0, 0.0));
        let limit = homogeneous.direction(d, s).normalize();
        // Rays along the nodal direction pass undeviated.
        assert!((homogeneous.direction(n, s).normalize() - n).length() < 1e-15);
        let g = 1e7;
        let finite = Glens {
            optical_axis: a,
            focus: Focus::Finite {
                principal_point: g * (ratio + 1.0) * (n / n.dot(a) - a),
                focal_length_negative: g * ratio,
                focal_length_positive: g,
            },
            transmission_coefficient: 1.0,
        };
        let nodal = finite.nodal_point().unwrap();
        assert!((nodal.normalize() - n).length() < 1e-12, "{nodal}");
        let approx = finite.direction(d, s).normalize();
        assert!((approx - limit).length() < 1e-6, "{approx} {limit}");
    }
}
