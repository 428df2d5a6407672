//! Bilinear surface (Dr TIM's `BilinearSurface`): the patch
//! p(α, β) = (1 − α)(1 − β) P₀₀ + α (1 − β) P₁₀ + α β P₁₁ + (1 − α) β P₀₁, α, β ∈ [0, 1],
//! whose four sides are straight: a hyperbolic paraboloid, or flat if its corners are coplanar.
//!
//! Written p = P₀₀ + α e + β f + α β g (e = P₁₀ − P₀₀, f = P₀₁ − P₀₀,
//! g = P₁₁ − P₁₀ − P₀₁ + P₀₀), a point of the line o + t d is on it where its components
//! across d, along two unit vectors a₁, a₂ perpendicular to d, vanish:
//! Aₖ + α Bₖ + β Cₖ + α β Dₖ = 0 (k = 1, 2; Aₖ = (P₀₀ − o)·aₖ, Bₖ = e·aₖ, Cₖ = f·aₖ,
//! Dₖ = g·aₖ). Eliminating β leaves a quadratic in α,
//! (B₁D₂ − B₂D₁) α² + (A₁D₂ − A₂D₁ + B₁C₂ − B₂C₁) α + (A₁C₂ − A₂C₁) = 0, solved without
//! cancellation (a flat patch makes it linear); β follows from whichever equation divides by
//! more, and t from the point found.

use glam::{DVec2, DVec3};
use serde::Deserialize;

use super::{AnalyticShape, GeometryError, Shape};
use crate::keys::{Array, Vector};
use crate::math::{Frame, nearest_in};

#[derive(Debug, Clone, PartialEq)]
pub struct BilinearSurface {
    /// P₀₀, P₁₀, P₁₁, P₀₁.
    corners: [DVec3; 4],
    /// e, f and g (see the module's notes).
    e: DVec3,
    f: DVec3,
    g: DVec3,
    /// A direction along which every normal of the patch has a positive component.
    mean_normal: DVec3,
}

impl BilinearSurface {
    /// The patch with corners P₀₀, P₁₀, P₁₁, P₀₁ (in order round it); its normal must not
    /// vanish or turn over anywhere on it.
    pub fn new(corners: [DVec3; 4]) -> Result<BilinearSurface, GeometryError> {
        for c in corners {
            super::check_point("bilinear surface corner", c)?;
        }
        let [p00, p10, p11, p01] = corners;
        let (e, f) = (p10 - p00, p01 - p00);
        let g = p11 - p10 - p01 + p00;
        // The normal ∂p/∂α × ∂p/∂β = (e + β g) × (f + α g) is affine in (α, β), so it is
        // nowhere zero or turned over if some direction has a positive component along its
        // values at all four corners.
        let normals = [
            e.cross(f),
            e.cross(f + g),
            (e + g).cross(f + g),
            (e + g).cross(f),
        ];
        let size = [e, f, p11 - p10, p11 - p01]
            .iter()
            .fold(0.0, |a: f64, s| a.max(s.length()));
        let mean_normal = std::iter::once(normals.iter().sum::<DVec3>())
            .chain(normals)
            .filter_map(DVec3::try_normalize)
            .find(|m| normals.iter().all(|n| m.dot(*n) > 1e-12 * size * size))
            .ok_or_else(|| {
                GeometryError::Degenerate(
                    "the bilinear surface is degenerate: its normal vanishes or turns over \
                     somewhere on it (repeated corners, three corners in a line, or a fold)"
                        .into(),
                )
            })?;
        Ok(BilinearSurface {
            corners,
            e,
            f,
            g,
            mean_normal,
        })
    }

    /// P₀₀, P₁₀, P₁₁, P₀₁.
    pub fn corners(&self) -> [DVec3; 4] {
        self.corners
    }

    /// p(α, β).
    pub fn point(&self, alpha: f64, beta: f64) -> DVec3 {
        self.corners[0] + alpha * self.e + beta * self.f + alpha * beta * self.g
    }

    /// The (α, β) (either may be outside [0, 1]) where the line `origin + t direction` meets
    /// the surface the patch lies on: none, one or two.
    fn crossings(&self, origin: DVec3, direction: DVec3) -> impl Iterator<Item = DVec2> {
        let across = direction
            .try_normalize()
            .map(|d| {
                let frame = Frame::from_normal(d);
                [frame.u, frame.v]
            })
            .unwrap_or([DVec3::NAN; 2]);
        let r = self.corners[0] - origin;
        let [a, b, c, d] = [r, self.e, self.f, self.g].map(|v| across.map(|x| v.dot(x)));
        let quadratic = b[0] * d[1] - b[1] * d[0];
        let linear = a[0] * d[1] - a[1] * d[0] + b[0] * c[1] - b[1] * c[0];
        let constant = a[0] * c[1] - a[1] * c[0];
        roots(quadratic, linear, constant)
            .into_iter()
            .flatten()
            .filter_map(move |alpha| {
                let k = usize::from((c[1] + alpha * d[1]).abs() > (c[0] + alpha * d[0]).abs());
                let beta = -(a[k] + alpha * b[k]) / (c[k] + alpha * d[k]);
                beta.is_finite().then_some(DVec2::new(alpha, beta))
            })
    }

    /// The (α, β) of point `p` of the patch: where the line through p along the mean normal,
    /// which meets the patch once, meets it.
    fn parameters(&self, p: DVec3) -> DVec2 {
        self.crossings(p, self.mean_normal)
            .map(|ab| ab.clamp(DVec2::ZERO, DVec2::ONE))
            .min_by(|x, y| {
                let miss = |ab: &DVec2| self.point(ab.x, ab.y).distance_squared(p);
                miss(x).total_cmp(&miss(y))
            })
            .unwrap_or(DVec2::ZERO)
    }
}

/// The finite real roots of q x² + l x + c = 0, computed without cancellation (a vanishing q
/// leaves the linear equation's root).
fn roots(q: f64, l: f64, c: f64) -> [Option<f64>; 2] {
    let discriminant = l * l - 4.0 * q * c;
    if discriminant.is_nan() || discriminant < 0.0 {
        return [None; 2];
    }
    let h = -0.5 * (l + discriminant.sqrt().copysign(l));
    [c / h, h / q].map(|x| x.is_finite().then_some(x))
}

impl AnalyticShape for BilinearSurface {
    fn intersect(
        &self,
        origin: DVec3,
        direction: DVec3,
        t_min: f64,
        t_max: f64,
    ) -> Option<(f64, u32)> {
        let unit = 0.0..=1.0;
        let ts = self
            .crossings(origin, direction)
            .filter(|ab| unit.contains(&ab.x) && unit.contains(&ab.y))
            .map(|ab| {
                (self.point(ab.x, ab.y) - origin).dot(direction) / direction.length_squared()
            });
        nearest_in(ts, t_min, t_max).map(|t| (t, 0))
    }

    /// w along ∂p/∂α × ∂p/∂β, u along ∂p/∂α.
    fn frame(&self, p: DVec3, _part: u32) -> Frame {
        let ab = self.parameters(p);
        let (along_alpha, along_beta) = (self.e + ab.y * self.g, self.f + ab.x * self.g);
        Frame::from_normal_and_u(along_alpha.cross(along_beta), along_alpha)
    }

    /// (α |P₁₀ − P₀₀|, β |P₀₁ − P₀₀|).
    fn coordinates(&self, p: DVec3, _part: u32) -> DVec2 {
        self.parameters(p) * DVec2::new(self.e.length(), self.f.length())
    }

    /// The point with coordinates `c` (inverse of [`Self::coordinates`]); `None` outside.
    fn point_at(&self, c: DVec2) -> Option<DVec3> {
        let ab = c / DVec2::new(self.e.length(), self.f.length());
        let unit = 0.0..=1.0;
        (unit.contains(&ab.x) && unit.contains(&ab.y)).then(|| self.point(ab.x, ab.y))
    }

    /// (∂p/∂(α |e|), ∂p/∂(β |f|)) = ((e + β g)/|e|, (f + α g)/|f|).
    fn coordinate_axes(&self, p: DVec3, _part: u32) -> Option<[DVec3; 2]> {
        let ab = self.parameters(p);
        Some([
            (self.e + ab.y * self.g) / self.e.length(),
            (self.f + ab.x * self.g) / self.f.length(),
        ])
    }

    fn is_charted(&self) -> bool {
        true
    }

    /// The box around the corners (the patch is inside their convex hull).
    fn bounds(&self) -> Option<(DVec3, DVec3)> {
        Some(super::point_bounds(&self.corners))
    }
}

/// `type = "bilinear-surface"`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BilinearSurfaceKeys {
    corners: Array<Vector, 4>,
}

impl BilinearSurfaceKeys {
    pub fn build(self) -> Result<Shape, GeometryError> {
        Ok(Shape::BilinearSurface(BilinearSurface::new(
            self.corners.0.map(|c| c.0),
        )?))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn roots_are_found_without_cancellation_and_a_vanishing_square_leaves_a_line() {
        let sorted = |r: [Option<f64>; 2]| {
            let mut v: Vec<f64> = r.into_iter().flatten().collect();
            v.sort_by(f64::total_cmp);
            v
        };
        assert_eq!(sorted(roots(1.0, -3.0, 2.0)), [1.0, 2.0]);
        assert_eq!(sorted(roots(0.0, 2.0, -4.0)), [2.0]);
        assert!(sorted(roots(1.0, 0.0, 1.0)).is_empty());
        // x² − 10⁸ x + 1: the small root 10⁻⁸ (to 1e-16 relative), which the textbook
        // formula loses to cancellation.
        let small = sorted(roots(1.0, -1e8, 1.0))[0];
        assert!((small - 1e-8).abs() < 1e-23, "{small}");
    }

    #[test]
    fn a_flat_patch_is_hit_by_the_linear_equation() {
        // A trapezoid in z = 0 (corners counter-clockwise seen from +z: normal +z).
        let corners = [
            DVec3::ZERO,
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(1.5, 1.0, 0.0),
            DVec3::new(0.5, 1.0, 0.0),
        ];
        let patch = BilinearSurface::new(corners).unwrap();
        let (t, part) = patch
            .intersect(DVec3::new(1.0, 0.5, 3.0), DVec3::NEG_Z, 0.0, 10.0)
            .unwrap();
        assert_eq!(t, 3.0);
        assert_eq!(patch.frame(DVec3::new(1.0, 0.5, 0.0), part).w, DVec3::Z);
        // Outside the trapezoid, though inside its bounding box: a miss.
        assert_eq!(
            patch.intersect(DVec3::new(0.1, 0.9, 3.0), DVec3::NEG_Z, 0.0, 10.0),
            None
        );
    }
}
