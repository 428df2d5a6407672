//! A collineation surface (Dr TIM's `CollineationSurface`, Precenieks and Courtial): a sheet
//! that changes a ray's direction and position so that lines of sight are imaged by a
//! collineation, the projective map
//!
//! x′ = (a₁ x + b₁ y + c₁ z + d₁) / (a x + b y + c z + d), and likewise y′ (row 2) and z′ (row 3),
//!
//! i.e. the 4 × 4 homogeneous matrix C with rows (a₁ b₁ c₁ d₁), (a₂ …), (a₃ …), (a b c d). As in
//! Dr TIM, the line of the ray as traced, through the hit point P and P + d, is mapped to the
//! line through C(P) and C(P + d); the ray leaves from where that line meets the sheet (nearest
//! C(P), looking along it first), in its direction or the reverse, whichever leaves on the side
//! the ray travels to, carrying the transmission coefficient. Where the line misses the sheet,
//! or C takes P to infinity, no light passes.
//!
//! An ideal thin lens of focal length f in the plane z = 0 is the collineation
//! C(x, y, z) = f (x, y, z) / (z + f) for rays traced along +z (the camera on the −z side). Light
//! crossing the other way is imaged by C⁻¹: a collineation surface describes a device for rays
//! that cross it one way, as in Dr TIM.

use glam::{DMat4, DVec3, DVec4};
use serde::Deserialize;

use crate::geometry::{Exit, Interaction, Transform};
use crate::keys::{Array, Coefficient, Finite, throughput};
use crate::math::Colour;
use crate::surfaces::{Redirection, Surface};

#[derive(Debug, Clone, PartialEq)]
pub struct CollineationSurface {
    /// C, acting on homogeneous points (x, y, z, 1).
    pub collineation: DMat4,
    /// Fraction of the light transmitted, in [0, 1].
    pub transmission_coefficient: f64,
}

impl CollineationSurface {
    /// C(p), at infinity (not finite) where the denominator vanishes.
    pub fn image(&self, p: DVec3) -> DVec3 {
        let h = self.collineation * p.extend(1.0);
        h.truncate() / h.w
    }

    pub fn redirect(&self, at: &Interaction) -> Redirection<'static> {
        let (p, d) = (at.local_point(), at.ray.direction);
        let start = self.image(p);
        let along = (self.image(p + d) - start).normalize();
        if !start.is_finite() || !along.is_finite() {
            return Redirection::Lost;
        }
        // From just behind C(P) forwards (so a sheet through C(P) itself is found), then
        // backwards.
        let margin = 1e-9 * (1.0 + start.abs().max_element());
        let meet = |e: DVec3| {
            let origin = start - margin * e;
            let (t, prim) = at.shape.intersect(origin, e, 0.0, f64::INFINITY)?;
            Some((origin + t * e, prim))
        };
        let Some((exit, prim)) = meet(along).or_else(|| meet(-along)) else {
            return Redirection::Lost;
        };
        // Leave on the side the ray travels to.
        let n_in = at.normal();
        let n_out = at.shape.normal_along(exit, prim, along);
        let same = (d.dot(n_in) > 0.0) == (along.dot(n_out) > 0.0);
        let direction = if same { along } else { -along };
        Redirection::Jumps {
            exit: Exit::chord(at.point(), exit + at.offset, direction),
            factor: Colour::splat(self.transmission_coefficient),
        }
    }

    /// The surface of an object placed by `t` (any affine map A): the collineation
    /// A C A⁻¹, which maps placed lines as C maps the unplaced ones.
    pub fn transformed(&self, t: &Transform) -> CollineationSurface {
        let a = DMat4::from_cols(
            t.vector(DVec3::X).extend(0.0),
            t.vector(DVec3::Y).extend(0.0),
            t.vector(DVec3::Z).extend(0.0),
            t.point(DVec3::ZERO).extend(1.0),
        );
        CollineationSurface {
            collineation: a * self.collineation * a.inverse(),
            ..*self
        }
    }
}

/// `type = "collineation-surface"`: `collineation`, the rows [a₁, b₁, c₁, d₁], [a₂, b₂, c₂, d₂],
/// [a₃, b₃, c₃, d₃], [a, b, c, d] (required, a non-singular matrix; Dr TIM's GUI has none), and
/// `transmission_coefficient` (0.96).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CollineationSurfaceKeys {
    collineation: Array<Array<Finite, 4>, 4>,
    #[serde(alias = "transmission")]
    transmission_coefficient: Option<Coefficient>,
}

impl CollineationSurfaceKeys {
    pub fn build(self) -> Result<Surface, String> {
        let rows = self
            .collineation
            .0
            .map(|row| DVec4::from(row.0.map(|x| x.0)));
        let collineation = DMat4::from_cols(rows[0], rows[1], rows[2], rows[3]).transpose();
        let scale = collineation
            .to_cols_array()
            .iter()
            .fold(0f64, |m, x| m.max(x.abs()));
        if scale == 0.0 || (collineation * (1.0 / scale)).determinant().abs() < 1e-12 {
            return Err(
                "collineation-surface: `collineation` must be a non-singular matrix (a \
                 collineation maps space one to one)"
                    .into(),
            );
        }
        Ok(Surface::CollineationSurface(CollineationSurface {
            collineation,
            transmission_coefficient: throughput(self.transmission_coefficient),
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The lens collineation fixes the lens plane and images (0, 0, −2f) to (0, 0, 2f) and the
    /// front focal plane to infinity.
    #[test]
    fn the_lens_collineation_images_as_a_thin_lens() {
        let f = 2.0;
        let c = CollineationSurface {
            collineation: DMat4::from_cols(
                DVec4::new(f, 0.0, 0.0, 0.0),
                DVec4::new(0.0, f, 0.0, 0.0),
                DVec4::new(0.0, 0.0, f, 1.0),
                DVec4::new(0.0, 0.0, 0.0, f),
            ),
            transmission_coefficient: 1.0,
        };
        assert_eq!(
            c.image(DVec3::new(0.3, -0.4, 0.0)),
            DVec3::new(0.3, -0.4, 0.0)
        );
        assert_eq!(
            c.image(DVec3::new(0.0, 0.0, -4.0)),
            DVec3::new(0.0, 0.0, 4.0)
        );
        assert!(!c.image(DVec3::new(1.0, 0.0, -2.0)).is_finite());
    }
}
