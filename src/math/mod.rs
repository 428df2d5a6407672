//! f64 geometry shared by the whole renderer: rays, surface frames, colours, quadratic roots,
//! Lorentz and Galilean transformations and reference frames, keyed random numbers, and the ODE integrator
//! of the gradient-index lenses. The bottom layer: it imports nothing else of timbre.

mod dop853;
mod galileo;
mod lorentz;
pub mod random;

pub use dop853::{Dop853, ErrorEstimate, Phase};
pub use galileo::{galilean_backwards_direction, galilean_event};
pub use lorentz::{LorentzTransform, ReferenceFrame};

use glam::DVec3;

/// Linear RGB radiance, unbounded (clamped only when written to PNG).
pub type Colour = glam::DVec3;

/// A light ray traced backwards from the camera. `time` is the time (c = 1) at which the ray
/// passes through `origin`; tracing backwards, the time decreases by the distance travelled.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ray {
    pub origin: DVec3,
    /// Unit vector.
    pub direction: DVec3,
    pub time: f64,
}

impl Ray {
    /// A ray with normalised direction.
    pub fn new(origin: DVec3, direction: DVec3, time: f64) -> Ray {
        Ray {
            origin,
            direction: direction.normalize(),
            time,
        }
    }

    /// The point at distance `t` along the ray.
    pub fn at(&self, t: f64) -> DVec3 {
        self.origin + t * self.direction
    }

    /// The ray continuing from the point at distance `t` in a new direction, `t` later back in
    /// time (the backwards-traced ray left that point earlier).
    pub fn continued(&self, t: f64, direction: DVec3) -> Ray {
        Ray::new(self.at(t), direction, self.time - t)
    }
}

/// A right-handed orthonormal surface frame (u, v, w) with w the outward normal.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    pub u: DVec3,
    pub v: DVec3,
    pub w: DVec3,
}

impl Frame {
    /// A frame with outward normal `w` (normalised here) and u, v chosen perpendicular to it.
    pub fn from_normal(w: DVec3) -> Frame {
        let w = w.normalize();
        let (u, v) = w.any_orthonormal_pair();
        Frame { u, v, w }
    }

    /// A frame with outward normal `w` and u along the part of `u_hint` perpendicular to w.
    pub fn from_normal_and_u(w: DVec3, u_hint: DVec3) -> Frame {
        let w = w.normalize();
        let u = u_hint.reject_from_normalized(w).try_normalize();
        match u {
            Some(u) => Frame {
                u,
                v: w.cross(u),
                w,
            },
            None => Frame::from_normal(w),
        }
    }
}

/// Both t with |offset + t direction| = radius, nearest first; `None` if the line passes farther
/// than `radius` from the origin (or `direction` is zero).
///
/// The quadratic is solved about the line's point closest to the origin: with t = mid + s it
/// reads a s² = r² − h², where h is that point's distance. This avoids subtracting the nearly
/// equal |offset|² and (offset·direction)²/a of the textbook formula, which loses most digits for
/// a small sphere or thin cylinder seen from far away.
pub fn circle_crossings(offset: DVec3, direction: DVec3, radius: f64) -> Option<(f64, f64)> {
    let a = direction.length_squared();
    if a == 0.0 || a.is_nan() {
        return None;
    }
    let mid = -offset.dot(direction) / a;
    let h2 = (offset + mid * direction).length_squared();
    let r2 = radius * radius;
    if h2 > r2 {
        return None;
    }
    let s = ((r2 - h2) / a).sqrt();
    Some((mid - s, mid + s))
}

/// Both roots of a s² + 2 b s + c (a ≠ 0), smaller first, given its discriminant
/// `disc` = b² − a c (clamped at 0), which the caller computes in a form that keeps its digits.
/// The root of larger magnitude comes from q = −(b + sign(b) √disc) as q / a and the other as
/// c / q, so neither subtracts nearly equal numbers.
pub fn quadratic_roots(a: f64, b: f64, c: f64, disc: f64) -> (f64, f64) {
    let q = -(b + disc.max(0.0).sqrt().copysign(b));
    if q == 0.0 {
        // b = 0 and disc = 0, so c = 0: a double root at 0.
        return (0.0, 0.0);
    }
    let (r0, r1) = (q / a, c / q);
    (r0.min(r1), r0.max(r1))
}

/// The helium–neon laser's wavelength, 632.8 nm, in metres: Dr TIM's wavelength for
/// diffraction (its GUI's `Pixellation` and lenslet arrays, its research programs' cameras),
/// timbre's default wherever something diffracts.
pub const HE_NE_WAVELENGTH: f64 = 632.8e-9;

/// The root in [0, 1] of the cubic Hermite interpolant with values `g0` ≤ 0 ≤ `g1` and
/// derivatives `m0`, `m1` (with respect to the unit interval) at its ends, by Newton's method
/// kept inside the bracket by bisection.
pub fn hermite_root(g0: f64, m0: f64, g1: f64, m1: f64) -> f64 {
    let cubic = |t: f64| {
        let u = 1.0 - t;
        let value =
            u * u * ((1.0 + 2.0 * t) * g0 + t * m0) + t * t * ((3.0 - 2.0 * t) * g1 - u * m1);
        let slope = 6.0 * t * u * (g1 - g0) + u * (1.0 - 3.0 * t) * m0 + t * (3.0 * t - 2.0) * m1;
        (value, slope)
    };
    let (mut lo, mut hi) = (0.0, 1.0);
    let mut t = if g1 > g0 { g0 / (g0 - g1) } else { 0.5 };
    for _ in 0..50 {
        let (p, dp) = cubic(t);
        if p < 0.0 {
            lo = t;
        } else {
            hi = t;
        }
        let newton = t - p / dp;
        let next = if newton > lo && newton < hi {
            newton
        } else {
            0.5 * (lo + hi)
        };
        if (next - t).abs() <= 1e-3 * f64::EPSILON.sqrt() {
            return next;
        }
        t = next;
    }
    t
}

/// The smallest of the candidate distances inside the open interval (t_min, t_max).
#[inline]
pub fn nearest_in(
    candidates: impl IntoIterator<Item = f64>,
    t_min: f64,
    t_max: f64,
) -> Option<f64> {
    candidates
        .into_iter()
        .filter(|&t| t > t_min && t < t_max)
        .min_by(f64::total_cmp)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_hermite_root_of_a_cubic_is_its_root() {
        // g = t³ + t − 1/2 (g′ = 3t² + 1) is its own interpolant.
        let t = hermite_root(-0.5, 1.0, 1.5, 4.0);
        assert!((t * t * t + t - 0.5).abs() < 1e-15, "{t}");
    }

    #[test]
    fn circle_crossings_keep_precision_far_from_a_small_circle() {
        // A line 1e6 away from a circle of radius 1e-3, passing 0.6e-3 from its centre: the
        // crossings are 0.8e-3 either side of the closest point.
        let offset = DVec3::new(-1e6, 0.6e-3, 0.0);
        let (t0, t1) = circle_crossings(offset, DVec3::X, 1e-3).unwrap();
        assert!(
            (t0 - (1e6 - 0.8e-3)).abs() < 1e-9 && (t1 - (1e6 + 0.8e-3)).abs() < 1e-9,
            "{t0} {t1}"
        );
        assert_eq!(circle_crossings(offset, DVec3::X, 0.5e-3), None);
        assert_eq!(circle_crossings(offset, DVec3::ZERO, 1.0), None);
    }

    #[test]
    fn quadratic_roots_keep_the_small_root_s_digits() {
        // s² − 2·1e8 s + 1 = 0: roots 1e8 ± sqrt(1e16 − 1); the small one is 1/(2e8) to
        // rounding, which the textbook formula returns as 0 or with no correct digit.
        let (r0, r1) = quadratic_roots(1.0, -1e8, 1.0, 1e16 - 1.0);
        assert!(
            (r0 - 0.5e-8).abs() < 1e-22 && (r1 - 2e8).abs() < 1e-6,
            "{r0} {r1}"
        );
        // -(s − 1)(s − 3) = −s² + 4 s − 3: a = −1, b = 2, c = −3, disc = 4 − 3.
        assert_eq!(quadratic_roots(-1.0, 2.0, -3.0, 1.0), (1.0, 3.0));
        assert_eq!(quadratic_roots(2.0, 0.0, 0.0, 0.0), (0.0, 0.0));
    }

    #[test]
    fn a_continued_ray_is_earlier_by_the_distance_travelled() {
        // Traced backwards, light reached the far point 3 before it reached the origin (c = 1).
        let ray = Ray::new(DVec3::ZERO, DVec3::new(0.0, 0.0, 2.0), 7.0);
        let next = ray.continued(3.0, DVec3::X);
        assert_eq!(
            (next.origin, next.direction, next.time),
            (DVec3::new(0.0, 0.0, 3.0), DVec3::X, 4.0)
        );
    }

    #[test]
    fn frame_is_right_handed_and_orthonormal() {
        let f = Frame::from_normal_and_u(DVec3::new(0.0, 2.0, 0.0), DVec3::new(0.0, 0.3, 1.0));
        assert!((f.u.cross(f.v) - f.w).length() < 1e-15);
        assert!(f.u.dot(f.w).abs() < 1e-15 && (f.u.length() - 1.0).abs() < 1e-15);
        assert!((f.u - DVec3::Z).length() < 1e-15);
    }
}
