//! Dr TIM's `LensSurface` (sceneObjects/LensSurface.java): the surface of glass of refractive
//! index n > 1 (outside 1) that refracts every ray travelling inside the glass along the
//! optical axis so that outside it passes through one point, the *focal point* F (and so,
//! reversed, refracts every ray from F into a ray along the axis inside). It images F
//! stigmatically to infinity inside the glass: a Cartesian oval whose second point is at
//! infinity. Two of them back to back image one point onto another exactly (Dr TIM's
//! `FresnelLens`, made of rings of such surfaces: `devices::FresnelLens`).
//!
//! **The surface.** With ŵ the optical axis pointing outwards (from the glass), w = (p − F)·ŵ
//! and the vertex V = F − f ŵ on the axis (f ≠ 0 the focal length, Dr TIM's parametrisation),
//! Fermat's principle (the optical path from a plane across the axis inside the glass, along
//! the axis to p and on to F, is the same for every surface point p) reads
//!
//! ```text
//! sign(f) |p − F| + n w + (n − 1) f = 0,                                              (1)
//! ```
//!
//! one sheet of a two-sheeted hyperboloid of revolution about the axis, of eccentricity n:
//! w(ρ) = −f (n + √(1 + (n + 1) ρ² / ((n − 1) f²))) / (n + 1), ρ the distance from the axis
//! (Dr TIM's `calculateW`). For f > 0 the glass lies behind a sheet that bulges towards F,
//! which is a real focus outside (a converging surface); for f < 0 the sheet is hollow, F lies
//! behind it in the glass, and rays leave as if from F (a diverging surface).
//!
//! **The solid.** Both are one convex solid, taken as it is or inside out: with g = |f| and
//! â = sign(f) ŵ,
//!
//! ```text
//! G(p) = |p − F| + n (p − F)·â + (n − 1) g ≤ 0                                        (2)
//! ```
//!
//! is convex (a norm plus a linear function) and bounded by the sheet (1); its outward normal
//! is ∇G = (p − F)/|p − F| + n â (Dr TIM's normal). For f > 0 the glass is this solid
//! ([`LensSurface`]); for f < 0 it is the solid's outside, an `inverse` of it
//! ([`lens_surface`]), whose normal −∇G again points out of the glass.
//!
//! **Intersection, exactly in f64.** Along a line q + s d (q relative to F and re-origined at
//! the line's point nearest F, so that q·d ≈ 0; z along â), the solid (2) is where
//! L(s) = −(n z + (n − 1) g) ≥ 0 and h(s) = |q + s d|² − L(s)² ≤ 0. h is the quadratic
//! a s² + 2 b s + c with a = |d|² − n² d_z², b = q·d − L₀L₁, c = (|q| − L₀)(|q| + L₀)
//! (L = L₀ + L₁ s), whose discriminant is computed as
//! (q·d)² − 2 (q·d) L₀L₁ + |d|² L₀² − |q|² a, without the cancelling L₀²L₁². On the plane
//! L = 0, h = |p − F|² > 0 (F is not on it), so each stretch of h ≤ 0 lies wholly on one side
//! of it: the one with L ≥ 0 is inside this sheet, the other inside the other sheet.

use glam::{DVec2, DVec3};
use serde::Deserialize;

use super::axial::{Axis, Line};
use super::{AnalyticShape, ConvexSolid, Csg, CsgOperation, GeometryError, Shape, Span};
use crate::keys::{MAX_MAGNITUDE, NonZero, Vector, number};
use crate::math::{Frame, quadratic_roots};

number!(
    /// A refractive index greater than 1 (of at most 10¹⁵).
    RefractiveIndex,
    |x: f64| x > 1.0 && x <= MAX_MAGNITUDE,
    "a refractive index greater than 1"
);

/// The convex solid (2) of a lens surface: for a surface of positive focal length the glass,
/// for one of negative focal length the outside of the glass ([`lens_surface`]).
#[derive(Debug, Clone, PartialEq)]
pub struct LensSurface {
    /// Origin F (the focal point), w = â: from the solid towards F's side.
    axis: Axis,
    /// g = |f|, the distance from F to the vertex.
    g: f64,
    /// The refractive index n > 1.
    n: f64,
}

/// An ellipse in space: its centre and two perpendicular semi-axis vectors.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ellipse {
    pub centre: DVec3,
    pub semi_axes: [DVec3; 2],
}

/// Where a plane cuts a lens surface's sheet: the ellipse, and the range of the axial
/// coordinate z (along â, from F) on it, smallest first.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlaneSection {
    pub ellipse: Ellipse,
    pub z_range: (f64, f64),
}

/// The lens surface (1) of Dr TIM's `LensSurface`: focal point `focal_point`, optical axis
/// `outwards` (from the glass, any length), focal length `focal_length` ≠ 0 and refractive
/// index `n` > 1, as a shape whose inside is the glass: the convex solid (2) for f > 0, its
/// inverse (named `lens-surface`) for f < 0.
pub fn lens_surface(
    focal_point: DVec3,
    outwards: DVec3,
    focal_length: f64,
    n: f64,
) -> Result<Shape, GeometryError> {
    let outwards = super::check_direction("lens surface optical_axis_outwards", outwards)?;
    if !(focal_length.is_finite() && focal_length != 0.0) {
        return Err(GeometryError::Degenerate(format!(
            "a lens surface's focal_length must be finite and non-zero, got {focal_length}"
        )));
    }
    let solid = LensSurface::new(
        focal_point,
        focal_length.signum() * outwards,
        focal_length.abs(),
        n,
    )?;
    if focal_length > 0.0 {
        Ok(Shape::LensSurface(solid))
    } else {
        let inverse = Csg::new(CsgOperation::Inverse, vec![Shape::LensSurface(solid)])?;
        Ok(Shape::Csg(inverse.called("lens-surface")))
    }
}

impl LensSurface {
    /// The convex solid (2) with focus `focal_point`, axis `towards_focus` (â, from the solid
    /// towards F, any length), vertex distance `g` > 0 and refractive index `n` > 1.
    pub fn new(
        focal_point: DVec3,
        towards_focus: DVec3,
        g: f64,
        n: f64,
    ) -> Result<LensSurface, GeometryError> {
        super::check_point("lens surface focal_point", focal_point)?;
        let axis = super::check_direction("lens surface axis", towards_focus)?;
        super::check_positive("lens surface |focal_length|", g)?;
        if !(n > 1.0 && n.is_finite()) {
            return Err(GeometryError::OutOfRange {
                what: "lens surface refractive_index",
                range: "greater than 1".into(),
                value: n,
            });
        }
        Ok(LensSurface {
            axis: Axis::new(focal_point, axis, None),
            g,
            n,
        })
    }

    pub fn focal_point(&self) -> DVec3 {
        self.axis.origin
    }

    /// â: the unit axis from the solid towards the focal point.
    pub fn axis(&self) -> DVec3 {
        self.axis.frame.w
    }

    /// The vertex F − g â.
    pub fn vertex(&self) -> DVec3 {
        self.axis.world(DVec3::new(0.0, 0.0, -self.g))
    }

    /// L(z) = −(n z + (n − 1) g): the distance |p − F| of the sheet's points at axial
    /// coordinate z (where it is ≥ 0).
    fn distance_at(&self, z: f64) -> f64 {
        -(self.n * z + (self.n - 1.0) * self.g)
    }

    /// The distance from the axis of the sheet's points at axial coordinate z ≤ −g.
    pub fn radius_at(&self, z: f64) -> f64 {
        let l = self.distance_at(z);
        ((l - z) * (l + z)).max(0.0).sqrt()
    }

    /// The axial coordinate of the sheet at distance ρ from the axis (Dr TIM's `calculateW`).
    fn height_at(&self, rho2: f64) -> f64 {
        let (n, g) = (self.n, self.g);
        -g * (n + (1.0 + (n + 1.0) / (n - 1.0) * rho2 / (g * g)).sqrt()) / (n + 1.0)
    }

    /// The span (in s) of `line` inside the solid (2); its finite ends are on the sheet.
    fn inside(&self, line: &Line) -> Option<Span> {
        let (q, d, n) = (line.q, line.d, self.n);
        let l0 = self.distance_at(q.z);
        let l1 = -n * d.z;
        let (qd, qq, dd) = (q.dot(d), q.length_squared(), d.length_squared());
        let a = dd - l1 * l1;
        let b = qd - l0 * l1;
        let c = (qq.sqrt() - l0) * (qq.sqrt() + l0);
        let ahead = |s: f64| Span {
            enter: (s, 0),
            exit: (f64::INFINITY, Span::NO_PART),
        };
        let behind = |s: f64| Span {
            enter: (f64::NEG_INFINITY, Span::NO_PART),
            exit: (s, 0),
        };
        if a == 0.0 {
            // Along an asymptote's direction: h = 2 b s + c, ≤ 0 on one half-line, whose far
            // end tells the side of L = 0 (L₁ ≠ 0 here, as |L₁| = |d|).
            let s = -c / (2.0 * b);
            return match (s.is_finite(), b > 0.0, l1 > 0.0) {
                (true, true, false) => Some(behind(s)),
                (true, false, true) => Some(ahead(s)),
                _ => None,
            };
        }
        let disc = qd * qd - 2.0 * qd * l0 * l1 + dd * l0 * l0 - qq * a;
        if a > 0.0 && disc < 0.0 {
            return None;
        }
        let (s0, s1) = quadratic_roots(a, b, c, disc);
        if a > 0.0 {
            // h ≤ 0 between the roots: inside this sheet if L ≥ 0 there.
            (s0 < s1 && l0 + 0.5 * (s0 + s1) * l1 >= 0.0).then_some(Span {
                enter: (s0, 0),
                exit: (s1, 0),
            })
        } else if l1 < 0.0 {
            // h ≤ 0 beyond the roots, and L ≥ 0 towards s → −∞.
            Some(behind(s0))
        } else {
            Some(ahead(s1))
        }
    }

    /// Where the plane through `point` with normal `normal` cuts the sheet: an ellipse (with
    /// the range of z on it), or `None` if the plane misses the sheet (or only touches it).
    /// The plane must cross the axis at an angle θ to its normal with sin θ < 1/n, the
    /// condition for an ellipse (the sheet's asymptotic cone has half angle
    /// arctan √(n² − 1)).
    ///
    /// With P where the plane meets the axis (z_P its axial coordinate), ê₁ along the part of
    /// â in the plane (â·ê₁ = α = sin θ), ê₂ = N × ê₁ and L_P = L(z_P), the points
    /// P + a ê₁ + b ê₂ of the sheet satisfy λ (a − a_c)² + b² = R², with λ = 1 − n² α²,
    /// a_c = −α (z_P + n L_P)/λ and R² = λ a_c² − (z_P² − L_P²), on this sheet where L ≥ 0.
    pub fn plane_section(
        &self,
        point: DVec3,
        normal: DVec3,
    ) -> Result<Option<PlaneSection>, GeometryError> {
        let normal = super::check_direction("plane normal", normal)?;
        let (a_hat, f, n) = (self.axis(), self.focal_point(), self.n);
        let across = a_hat.dot(normal);
        let alpha = a_hat.reject_from_normalized(normal).length();
        let lambda = 1.0 - n * n * alpha * alpha;
        if across == 0.0 || lambda <= 0.0 {
            return Err(GeometryError::Degenerate(format!(
                "the plane is tilted too far from the optical axis: the angle θ between its \
                 normal and the axis must have sin θ < 1/n = {}, got sin θ = {alpha}",
                1.0 / n
            )));
        }
        let z_p = normal.dot(point - f) / across;
        let e1 = a_hat
            .reject_from_normalized(normal)
            .try_normalize()
            .unwrap_or_else(|| normal.any_orthonormal_vector());
        let e2 = normal.cross(e1);
        let l_p = self.distance_at(z_p);
        let a_c = -alpha * (z_p + n * l_p) / lambda;
        let r2 = lambda * a_c * a_c - (z_p - l_p) * (z_p + l_p);
        if r2 <= 0.0 {
            return Ok(None);
        }
        let (r, half_width) = (r2.sqrt(), (r2 / lambda).sqrt());
        let z = |a: f64| z_p + alpha * a;
        if self.distance_at(z(a_c + half_width)) < 0.0 {
            return Ok(None); // the other sheet
        }
        Ok(Some(PlaneSection {
            ellipse: Ellipse {
                centre: f + z_p * a_hat + a_c * e1,
                semi_axes: [half_width * e1, r * e2],
            },
            z_range: (z(a_c - half_width), z(a_c + half_width)),
        }))
    }

    /// Dr TIM's `calculateFocalLengthOfSurfaceThroughPoint`: the focal length f of the lens
    /// surface (1) with focal point `focal_point`, unit optical axis `outwards` and index `n`
    /// that passes through `point`, or `None` if no such surface does (when |p − F| > n |w|).
    pub fn focal_length_through(
        point: DVec3,
        focal_point: DVec3,
        outwards: DVec3,
        n: f64,
    ) -> Option<f64> {
        let r = point - focal_point;
        let w = r.dot(outwards);
        // (1) has sign(f) = −sign(w) on its sheet (the vertex is at w = −f), so it reads
        // |p − F| − n |w| + (n − 1) |f| = 0: |f| = (n |w| − |p − F|)/(n − 1), which must be
        // positive.
        let g = (n * w.abs() - r.length()) / (n - 1.0);
        (g > 0.0).then_some(-w.signum() * g)
    }
}

impl AnalyticShape for LensSurface {
    fn intersect(
        &self,
        origin: DVec3,
        direction: DVec3,
        t_min: f64,
        t_max: f64,
    ) -> Option<(f64, u32)> {
        self.chord(origin, direction)?.nearest(t_min, t_max)
    }

    /// w = ∇G/|∇G| = ((p − F)/|p − F| + n â)/|…| (never along the axis's û, as its part
    /// along â is at least n − 1), u along the part of û across it, v = w × u.
    fn frame(&self, p: DVec3, _part: u32) -> Frame {
        let to_p = (p - self.focal_point()).normalize_or_zero();
        Frame::from_normal_and_u(to_p + self.n * self.axis(), self.axis.frame.u)
    }

    /// (x, y): the point's Cartesian coordinates across the axis, along û and v̂ (the disc
    /// axes for a normal along â) from the axis.
    fn coordinates(&self, p: DVec3, _part: u32) -> DVec2 {
        self.axis.local(p).truncate()
    }

    /// The sheet's point with coordinates `c`.
    fn point_at(&self, c: DVec2) -> Option<DVec3> {
        Some(
            self.axis
                .world(c.extend(self.height_at(c.length_squared()))),
        )
    }

    /// Unbounded.
    fn bounds(&self) -> Option<(DVec3, DVec3)> {
        None
    }

    fn solid(&self) -> Option<&dyn ConvexSolid> {
        Some(self)
    }
}

impl ConvexSolid for LensSurface {
    fn chord(&self, origin: DVec3, direction: DVec3) -> Option<Span> {
        let line = self.axis.line(origin, direction);
        line.cut(self.inside(&line)?, None, None)
    }

    fn contains(&self, p: DVec3) -> bool {
        let r = p - self.focal_point();
        r.length() - self.distance_at(r.dot(self.axis())) <= 0.0
    }
}

/// `type = "lens-surface"`: Dr TIM's `LensSurface` (no default: it has no editable form).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LensSurfaceKeys {
    focal_point: Vector,
    focal_length: NonZero,
    refractive_index: RefractiveIndex,
    optical_axis_outwards: Vector,
}

impl LensSurfaceKeys {
    pub fn build(self) -> Result<Shape, GeometryError> {
        lens_surface(
            self.focal_point.0,
            self.optical_axis_outwards.0,
            self.focal_length.0,
            self.refractive_index.0,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn surface(f: f64) -> Shape {
        lens_surface(DVec3::new(0.0, 0.0, 1.0), DVec3::NEG_Z, f, 1.5).unwrap()
    }

    #[test]
    fn the_vertex_lies_f_from_the_focal_point_against_the_outward_axis() {
        // F = (0, 0, 1), ŵ = −z: the vertex is at F − f ŵ = (0, 0, 1 + f).
        for f in [0.5, 2.0, -0.5, -2.0] {
            let s = surface(f);
            let (t, _) = s
                .intersect(DVec3::new(0.0, 0.0, -10.0), DVec3::Z, 0.0, 100.0)
                .unwrap();
            assert!((t - (11.0 + f)).abs() < 1e-12, "f = {f}: t = {t}");
            // The glass is behind the vertex (away from the outside, +z).
            let behind = DVec3::new(0.0, 0.0, 1.0 + f + 1e-3);
            assert!(s.contains(behind) && !s.contains(behind - 2e-3 * DVec3::Z));
            // The outward normal there points out of the glass, along ŵ.
            let w = s.normal(DVec3::new(0.0, 0.0, 1.0 + f), 0);
            assert!((w - DVec3::NEG_Z).length() < 1e-12, "f = {f}: {w}");
        }
    }

    #[test]
    fn dr_tims_calculate_w_is_the_sheet() {
        // Points of Dr TIM's w(ρ) satisfy (1), and point_at gives them back.
        let s = LensSurface::new(DVec3::ZERO, DVec3::Z, 1.0, 1.5).unwrap();
        for rho in [0.0, 0.3, 1.0, 5.0, 100.0] {
            let p = s.point_at(DVec2::new(rho, 0.0)).unwrap();
            let g = p.length() + 1.5 * p.z + 0.5;
            assert!(g.abs() < 1e-12 * (1.0 + rho), "ρ = {rho}: G = {g}");
            assert!((s.radius_at(p.z) - rho).abs() < 1e-9 * (1.0 + rho));
        }
    }

    #[test]
    fn a_plane_across_the_axis_cuts_a_circle() {
        // The plane z = −1.5 (axial coordinate) cuts the sheet f = 1, n = 1.5 where
        // |p| = 1.5 · 1.5 − 0.5 = 1.75, so ρ² = 1.75² − 1.5².
        let s = LensSurface::new(DVec3::ZERO, DVec3::Z, 1.0, 1.5).unwrap();
        let c = s
            .plane_section(DVec3::new(0.3, 0.2, -1.5), DVec3::NEG_Z)
            .unwrap()
            .unwrap();
        let rho = (1.75f64 * 1.75 - 1.5 * 1.5).sqrt();
        assert!((c.ellipse.centre - DVec3::new(0.0, 0.0, -1.5)).length() < 1e-12);
        for axis in c.ellipse.semi_axes {
            assert!((axis.length() - rho).abs() < 1e-12 && axis.z.abs() < 1e-15);
        }
        // Beyond the vertex, and through the other sheet, nothing.
        assert_eq!(
            s.plane_section(DVec3::new(0.0, 0.0, -0.9), DVec3::Z),
            Ok(None)
        );
        assert_eq!(
            s.plane_section(DVec3::new(0.0, 0.0, 3.0), DVec3::Z),
            Ok(None)
        );
        // Too steep for an ellipse: sin θ = 0.8 > 1/1.5.
        assert!(
            s.plane_section(DVec3::ZERO, DVec3::new(0.8, 0.0, 0.6))
                .is_err()
        );
    }

    #[test]
    fn dr_tims_focal_length_through_a_point() {
        // The surface through its own point has its focal length.
        for f in [0.7, -0.7] {
            let outwards = DVec3::NEG_Z;
            let shape = surface(f);
            let p = match &shape {
                Shape::LensSurface(s) => s.point_at(DVec2::new(0.4, 0.1)).unwrap(),
                Shape::Csg(c) => c.leaves()[0].point_at(DVec2::new(0.4, 0.1)).unwrap(),
                other => panic!("{other:?}"),
            };
            let got = LensSurface::focal_length_through(p, DVec3::Z, outwards, 1.5).unwrap();
            assert!((got - f).abs() < 1e-12, "f = {f}: {got}");
        }
        // No surface of index 1.5 about the axis passes through a point far to the side.
        assert_eq!(
            LensSurface::focal_length_through(
                DVec3::new(5.0, 0.0, 0.0),
                DVec3::Z,
                DVec3::NEG_Z,
                1.5
            ),
            None
        );
    }
}
