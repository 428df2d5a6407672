//! The generalised focusing gradient-index (GGRIN) lens of Šarbort and Tyc (§3.1, Eqs 11–15).
//!
//! Before the lens, the ray's straight line passes through a point A at distance r from the
//! centre C; after it, through a point A′ at distance r′, such that the lines AC and CA′ meet at
//! the angle φ and the impact parameter (the angular momentum) is unchanged. Table 1: Luneburg
//! is (∞, R, 180°), Eaton (∞, ∞, 0°), Maxwell fisheye (R, R, 180°).
//!
//! r and r′ are given in units of the lens radius R and may be `f64::INFINITY`. Eq 13's
//! arctan(x, y) is the angle of the point (x, y), i.e. `y.atan2(x)`; with r = ∞, a_d = −∞ and
//! IEEE arithmetic gives that angle's exact limit, π, not an approximation by a large r.

use glam::DVec3;
use serde::Deserialize;

use super::{LensKeys, LensLaw};
use crate::geometry::{Exit, Sphere};
use crate::keys::{Finite, MAX_MAGNITUDE, number};
use crate::surfaces::Surface;

#[derive(Debug, Clone, PartialEq)]
pub struct Ggrin {
    /// Distance of A from the centre, in units of the lens radius (≥ 1, may be infinite).
    pub r: f64,
    /// Distance of A′ from the centre, in units of the lens radius (≥ 1, may be infinite).
    pub r_prime: f64,
    /// Angle φ between the lines AC and CA′, in radians.
    pub phi: f64,
}

impl Ggrin {
    /// The ray leaving the lens `lens` after entering at `p` with direction `d`.
    ///
    /// A ray aimed exactly at the centre has no plane of incidence (ê of Eq 11 is undefined);
    /// any plane containing it is taken, which matters only for φ ∉ {0°, 180°}.
    pub fn transmit(&self, lens: &Sphere, p: DVec3, d: DVec3) -> Exit {
        let radius = lens.radius();
        let d_hat = d.normalize();
        let pv = p - lens.centre();
        let p_d = d_hat.dot(pv);
        // Eq 11.
        let e_hat = (pv - d_hat * p_d)
            .try_normalize()
            .unwrap_or_else(|| d_hat.any_orthonormal_vector());
        let p_e = e_hat.dot(pv);
        // A on the incident line, a distance r from C, before P (a_d < 0).
        let (a_e, a_d) = (p_e, -leg(self.r * radius, p_e));
        // Eq 12: Q (where the undeviated ray would leave) and I (distance r′ from C on it).
        let (q_e, q_d) = (p_e, -p_d);
        let (i_e, i_d) = (p_e, leg(self.r_prime * radius, p_e));
        // Eq 13.
        let beta = a_e.atan2(a_d) - i_e.atan2(i_d) + self.phi;
        // Eq 14.
        let (sin, cos) = beta.sin_cos();
        let d_prime = d_hat * cos + e_hat * sin;
        let e_prime = -d_hat * sin + e_hat * cos;
        // Eq 15.
        let exit = lens.centre() + q_d * d_prime + q_e * e_prime;
        Exit::chord(p, exit, d_prime)
    }
}

/// The leg √(h² − x²) of a right triangle with hypotenuse h ≥ |x| (infinite for infinite h),
/// clamped at zero against rounding when h = |x|.
fn leg(h: f64, x: f64) -> f64 {
    ((h - x) * (h + x)).max(0.0).sqrt()
}

number!(
    /// A distance of a GGRIN lens's focal point from its centre, in units of the lens radius:
    /// at least 1, or `inf` (TOML's infinity).
    LensDistance,
    |x: f64| x >= 1.0 && (x <= MAX_MAGNITUDE || x == f64::INFINITY),
    "a distance in units of the lens radius, at least 1 (the surface) or inf"
);

/// `type = "ggrin-lens"`: r, r′ (in units of the lens radius) and φ in degrees; where not
/// given, those of Dr TIM's GUI's GGRIN lens (of radius 1): r = r′ = 1, φ = 0.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GgrinLensKeys {
    r: Option<LensDistance>,
    r_prime: Option<LensDistance>,
    phi_deg: Option<Finite>,
    #[serde(flatten)]
    lens: LensKeys,
}

impl GgrinLensKeys {
    pub fn build(self) -> Result<Surface, String> {
        Ok(self.lens.lens(LensLaw::Ggrin(Ggrin {
            r: self.r.map_or(1.0, |r| r.0),
            r_prime: self.r_prime.map_or(1.0, |r| r.0),
            phi: self.phi_deg.map_or(0.0, |phi| phi.0).to_radians(),
        })))
    }
}

#[cfg(test)]
mod tests {
    use std::f64::consts::PI;

    use super::*;
    use crate::geometry::Shape;
    use crate::surfaces::Lens;
    use crate::surfaces::tests::{crosses, line_miss, meet};

    /// The GGRIN lens of Šarbort and Tyc images the point A, a distance r R from the centre,
    /// perfectly onto A′, a distance r′ R from it, the lines AC and CA′ meeting at the angle
    /// φ: every ray from A leaves the lens on a line through A′. With φ = 180° (A′ on the far
    /// side, on the line from A through C) that holds for rays in every plane through A and C.
    /// Here A is 3R from the centre and A′ 2R on the other side (a real image: the rays leave
    /// towards it); then, for A at infinity (r = ∞), a parallel bundle along d is focused onto
    /// C + r′ R d̂, and with r′ = 1 (Table 1's Luneburg lens) onto the far surface itself.
    #[test]
    fn rays_from_a_point_are_imaged_onto_its_image_point() {
        let (centre, radius) = (DVec3::new(1.0, 0.0, -2.0), 0.8);
        let shape = Shape::Sphere(Sphere::new(centre, radius).unwrap());
        let axis = DVec3::new(0.0, 0.6, 0.8); // from A towards C
        let (e1, e2) = axis.any_orthonormal_pair();
        let ggrin = |r: f64, r_prime: f64| {
            Lens::new(LensLaw::Ggrin(Ggrin {
                r,
                r_prime,
                phi: PI,
            }))
        };
        // A ray of the bundle: the k-th across the aperture of the lens, seen from `from` (a
        // point, or far away along −axis).
        let aim = |k: usize| {
            let (b, turn) = (0.95 * radius * (k as f64 + 0.5) / 10.0, 2.4 * k as f64);
            centre + b * (turn.cos() * e1 + turn.sin() * e2)
        };
        let a = centre - 3.0 * radius * axis;
        let image = centre + 2.0 * radius * axis;
        let lens = ggrin(3.0, 2.0);
        for k in 0..10 {
            let at = meet(&shape, a, aim(k) - a);
            let (exit, _) = crosses(lens.redirect(&at, &mut |_| {}));
            let (miss, along) = line_miss(exit.point, exit.direction, image);
            assert!(miss < 1e-12 && along > 0.0, "k = {k}: {miss:e} {along}");
        }
        for (r_prime, focus) in [
            (2.5, centre + 2.5 * radius * axis),
            (1.0, centre + radius * axis),
        ] {
            let lens = ggrin(f64::INFINITY, r_prime);
            for k in 0..10 {
                let at = meet(&shape, aim(k) - 5.0 * axis, axis);
                let (exit, _) = crosses(lens.redirect(&at, &mut |_| {}));
                if r_prime == 1.0 {
                    assert!(
                        (exit.point - focus).length() < 1e-12,
                        "k = {k}: {}",
                        exit.point
                    );
                } else {
                    let (miss, along) = line_miss(exit.point, exit.direction, focus);
                    assert!(miss < 1e-12 && along > 0.0, "k = {k}: {miss:e} {along}");
                }
            }
        }
    }

    /// With φ = 0 and r = r′, A′ is A itself: the lens sends every ray from A back through
    /// A (Table 1's Eaton lens is the case r = r′ = ∞, a retro-reflector).
    #[test]
    fn with_phi_zero_and_equal_distances_rays_return_to_their_source() {
        let (centre, radius) = (DVec3::ZERO, 1.0);
        let shape = Shape::Sphere(Sphere::new(centre, radius).unwrap());
        let lens = Lens::new(LensLaw::Ggrin(Ggrin {
            r: 2.5,
            r_prime: 2.5,
            phi: 0.0,
        }));
        let a = DVec3::new(0.0, 0.0, -2.5);
        for k in 0..10 {
            let (b, turn) = (0.9 * (k as f64 + 0.5) / 10.0, 2.4 * k as f64);
            let target = DVec3::new(b * turn.cos(), b * turn.sin(), 0.0);
            let at = meet(&shape, a, target - a);
            let (exit, _) = crosses(lens.redirect(&at, &mut |_| {}));
            let (miss, along) = line_miss(exit.point, exit.direction, a);
            assert!(miss < 1e-12 && along > 0.0, "k = {k}: {miss:e} {along}");
        }
    }
}
