//! f64 geometry shared by the whole renderer: rays, surface frames, quadratic roots.

use glam::DVec3;

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

/// Real roots `t0 <= t1` of `a t² + 2 b t + c = 0` with a > 0, computed without the
/// cancellation of the textbook formula. `None` when the discriminant is negative.
pub fn half_b_quadratic(a: f64, half_b: f64, c: f64) -> Option<(f64, f64)> {
    let disc = half_b * half_b - a * c;
    if disc < 0.0 || a <= 0.0 {
        return None;
    }
    let q = -(half_b + half_b.signum() * disc.sqrt());
    if q == 0.0 {
        // b = 0 and c = 0: double root at 0.
        return Some((0.0, 0.0));
    }
    let (r0, r1) = (q / a, c / q);
    Some(if r0 <= r1 { (r0, r1) } else { (r1, r0) })
}

/// The smallest of the candidate distances inside the open interval (t_min, t_max).
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
    fn quadratic_roots_are_accurate_when_b_dominates() {
        // (t - 1e-9)(t - 1e9) = t² - (1e9 + 1e-9) t + 1
        let (t0, t1) = half_b_quadratic(1.0, -(1e9 + 1e-9) / 2.0, 1.0).unwrap();
        assert!((t0 - 1e-9).abs() < 1e-24, "{t0}");
        assert!((t1 - 1e9).abs() < 1e-6, "{t1}");
    }

    #[test]
    fn quadratic_without_real_roots() {
        assert_eq!(half_b_quadratic(1.0, 0.0, 1.0), None);
    }

    #[test]
    fn frame_is_right_handed_and_orthonormal() {
        let f = Frame::from_normal_and_u(DVec3::new(0.0, 2.0, 0.0), DVec3::new(0.0, 0.3, 1.0));
        assert!((f.u.cross(f.v) - f.w).length() < 1e-15);
        assert!(f.u.dot(f.w).abs() < 1e-15 && (f.u.length() - 1.0).abs() < 1e-15);
        assert!((f.u - DVec3::Z).length() < 1e-15);
    }
}
