//! Refraction at the interface between spaces with different optical metrics (§4, Eqs 16–38).
//!
//! A metric g makes the squared optical path length ds² = drᵀ g dr (Eq 17). With the interface
//! in the plane z = 0, Fermat's principle (Eqs 19–20) fixes the tangential part of h e for the
//! outgoing direction e from the incident direction d: (h e)ₓ = cₓ and (h e)ᵧ = c_y (Eqs 25–26),
//! where c = ±(g d)/√|dᵀ g d| (Eq 22; − for negative refraction). Normalising eᵀ h e = 1
//! (Eq 24) leaves the quadratic a e_z² + c = 0 (Eqs 29–31), with e_z of the sign of d_z
//! (Eq 32). No real root (−c/a < 0) means total internal reflection.
//!
//! When dᵀ g d < 0 (an indefinite metric), the solution with imaginary optical path lengths
//! (§4.2) normalises eᵀ h e = −1 (Eq 35), which changes c to Eq 36; it is used only if the
//! interface allows it, otherwise the ray is totally internally reflected.
//!
//! Choices the paper leaves open, made here:
//! - Total internal reflection obeys the same condition in the incident metric: the tangential
//!   part of g e stays that of g d and eᵀ g e = ±1, so e is the other root of Eq 29 with h = g.
//!   In an isotropic metric this is the mirror image; in an anisotropic one it is the direction
//!   Fermat's principle gives, which is not (Dr TIM's `MetricInterface` always mirrors).
//! - Total internal reflection loses no light unless a reflection coefficient says so, as in
//!   Dr TIM ("don't multiply by the transmission coefficient, as this is TIR").
//! - A null incident direction (dᵀ g d = 0) and a tangential metric with h₁₁h₂₂ − h₁₂² = 0 or
//!   a = 0 (det h = 0) give no unique direction; the ray is reflected (in a degenerate incident
//!   metric, mirrored). Scene files reject singular tensors, so this can only happen for a
//!   globally given indefinite metric at points where the surface's tangent plane is null.

use glam::{DMat3, DVec2, DVec3};
use serde::{Deserialize, Deserializer, de};

use super::{Basis, Outgoing, jacobian};
use crate::geometry::Interaction;
use crate::keys::{Coefficient, Matrix, coefficient, throughput};
use crate::surfaces::{Redirection, Surface, reflect};

/// Whether the optical path lengths on the two sides have the same sign (positive refraction)
/// or opposite signs (negative refraction, e.g. n = −1 against n = +1).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Refraction {
    #[default]
    Positive,
    Negative,
}

#[derive(Debug, Clone, PartialEq)]
pub struct MetricInterface {
    /// The metric tensor g on the inside (the side the outward normal points away from).
    pub inside: DMat3,
    /// The metric tensor h on the outside.
    pub outside: DMat3,
    /// The basis the tensors are given in (Eqs 37–38).
    pub basis: Basis,
    pub refraction: Refraction,
    /// Whether to use the imaginary-optical-path-length solution of §4.2.
    pub allow_imaginary: bool,
    /// Fraction of the light transmitted, in [0, 1].
    pub transmission_coefficient: f64,
    /// Fraction of the light totally internally reflected, in [0, 1].
    pub reflection_coefficient: f64,
}

/// Eqs 22–36: the direction e of the ray leaving the interface z = 0 into metric `h` when it
/// arrives in metric `g` with direction `d` (any length, d_z ≠ 0). e is normalised as Eq 24
/// (eᵀ h e = 1), or as Eq 35 (eᵀ h e = −1) for the imaginary solution. `None` means total
/// internal reflection.
pub fn metric_refracted_direction(
    d: DVec3,
    g: &DMat3,
    h: &DMat3,
    refraction: Refraction,
    allow_imaginary: bool,
) -> Option<DVec3> {
    let (c, q) = fermat_constants(d, g)?;
    if q < 0.0 && !allow_imaginary {
        return None;
    }
    let c = match refraction {
        Refraction::Positive => c,
        Refraction::Negative => -c,
    };
    solve(c, h, d.z.signum(), q.signum())
}

/// The direction of a ray arriving with direction `d` in metric `g` at the interface z = 0 and
/// totally internally reflected, normalised like the incident ray (eᵀ g e = ±1); the mirror
/// image for isotropic metrics.
pub fn metric_reflected_direction(d: DVec3, g: &DMat3) -> DVec3 {
    fermat_constants(d, g)
        .and_then(|(c, q)| solve(c, g, -d.z.signum(), q.signum()))
        .unwrap_or_else(|| reflect(d, DVec3::Z))
}

/// Eq 22 with the '+' sign: (cₓ, c_y) = (g d)ₓ,ᵧ / √|dᵀ g d|, and dᵀ g d itself; `None` for a
/// null direction.
fn fermat_constants(d: DVec3, g: &DMat3) -> Option<(DVec2, f64)> {
    let gd = *g * d;
    let q = d.dot(gd);
    (q != 0.0 && q.is_finite()).then(|| (DVec2::new(gd.x, gd.y) / q.abs().sqrt(), q))
}

/// Eqs 27–32 (with Eq 36 for `norm` = −1): the e with (h e)ₓ,ᵧ = c, eᵀ h e = `norm` and e_z of
/// the sign of `side`; `None` if there is no real (or no unique) solution.
fn solve(c: DVec2, h: &DMat3, side: f64, norm: f64) -> Option<DVec3> {
    let [h11, h12, h13] = h.x_axis.to_array();
    let [_, h22, h23] = h.y_axis.to_array();
    let h33 = h.z_axis.z;
    let det2 = h11 * h22 - h12 * h12;
    // Eq 30.
    let a = h13 * h13 * h22 - 2.0 * h12 * h13 * h23 + h12 * h12 * h33 + h11 * h23 * h23
        - h11 * h22 * h33;
    // Eq 31 (norm = 1) or Eq 36 (norm = −1).
    let c0 = -c.y * c.y * h11 + 2.0 * c.x * c.y * h12 - c.x * c.x * h22 + norm * det2;
    if det2 == 0.0 || a == 0.0 {
        return None;
    }
    let ez2 = -c0 / a;
    if ez2 < 0.0 || ez2.is_nan() {
        return None;
    }
    // Eq 32, on the far side.
    let ez = side * ez2.sqrt();
    // Eqs 27–28.
    let ex = (c.x * h22 - c.y * h12 - ez * h13 * h22 + ez * h12 * h23) / det2;
    let ey = (c.y * h11 - c.x * h12 - ez * h23 * h11 + ez * h12 * h13) / det2;
    Some(DVec3::new(ex, ey, ez))
}

impl MetricInterface {
    /// The unit direction a ray arriving with direction `d` leaves in, at a point with surface
    /// frame given by the Jacobian `lambda` (Eq 38); either side may be the incident one.
    pub fn outgoing(&self, d: DVec3, lambda: &DMat3) -> Outgoing {
        let (g, h) = match self.basis {
            // Eq 37.
            Basis::Global => (
                lambda.transpose() * self.inside * *lambda,
                lambda.transpose() * self.outside * *lambda,
            ),
            Basis::Local => (self.inside, self.outside),
        };
        let d = lambda.transpose() * d;
        // A ray arriving from outside (against w) travels from h into g.
        let (from, to) = if d.z < 0.0 { (&h, &g) } else { (&g, &h) };
        let global = |e: DVec3| (*lambda * e).normalize();
        match metric_refracted_direction(d, from, to, self.refraction, self.allow_imaginary) {
            Some(e) => Outgoing::Transmitted(global(e)),
            None => Outgoing::Reflected(global(metric_reflected_direction(d, from))),
        }
    }

    pub fn redirect(&self, at: &Interaction) -> Redirection<'static> {
        self.outgoing(at.ray.direction, &jacobian(&at.frame()))
            .leaves(self.transmission_coefficient, self.reflection_coefficient)
    }
}

/// A metric tensor (Eq 18): a symmetric, non-singular 3×3 matrix, given row by row.
#[derive(Debug, Clone, Copy)]
struct MetricTensor(DMat3);

impl<'de> Deserialize<'de> for MetricTensor {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let m = Matrix::deserialize(d)?.0;
        // Row i, column j.
        let g = |i: usize, j: usize| m.col(j)[i];
        for (i, j) in [(0, 1), (0, 2), (1, 2)] {
            if g(i, j) != g(j, i) {
                return Err(de::Error::custom(format!(
                    "a metric tensor must be symmetric, but g{}{} = {} and g{}{} = {}",
                    i + 1,
                    j + 1,
                    g(i, j),
                    j + 1,
                    i + 1,
                    g(j, i)
                )));
            }
        }
        // Scaled to a largest element of 1 so that the test neither underflows nor overflows.
        let scale = m.to_cols_array().iter().fold(0.0f64, |s, x| s.max(x.abs()));
        if scale == 0.0 || (m * (1.0 / scale)).determinant().abs() <= 1e-12 {
            return Err(de::Error::custom(
                "the metric tensor is singular or ill-conditioned (determinant 0 relative to its largest element), so refraction into it is undefined (Eq 30: a = 0)",
            ));
        }
        Ok(MetricTensor(m))
    }
}

/// `type = "metric-interface"`: the metrics `inside` and `outside` (Euclidean when not given);
/// in the local basis their tangential parts must be invertible.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MetricInterfaceKeys {
    inside: Option<MetricTensor>,
    outside: Option<MetricTensor>,
    basis: Option<Basis>,
    refraction: Option<Refraction>,
    allow_imaginary: Option<bool>,
    #[serde(alias = "transmission")]
    transmission_coefficient: Option<Coefficient>,
    #[serde(alias = "reflection")]
    reflection_coefficient: Option<Coefficient>,
}

impl MetricInterfaceKeys {
    pub fn build(self) -> Result<Surface, String> {
        let euclidean = DMat3::IDENTITY;
        let g = self.inside.map_or(euclidean, |m| m.0);
        let h = self.outside.map_or(euclidean, |m| m.0);
        let basis = self.basis.unwrap_or_default();
        if basis == Basis::Local {
            check_tangential("inside", &g)?;
            check_tangential("outside", &h)?;
        }
        Ok(Surface::MetricInterface(MetricInterface {
            inside: g,
            outside: h,
            basis,
            refraction: self.refraction.unwrap_or_default(),
            allow_imaginary: self.allow_imaginary.unwrap_or(false),
            transmission_coefficient: throughput(self.transmission_coefficient),
            reflection_coefficient: coefficient(self.reflection_coefficient),
        }))
    }
}

/// The (u, v, w) components of h whose tangential part h₁₁h₂₂ − h₁₂² must not vanish.
fn check_tangential(name: &str, h: &DMat3) -> Result<(), String> {
    let det2 = h.x_axis.x * h.y_axis.y - h.y_axis.x * h.y_axis.x;
    let scale = h.x_axis.x.abs().max(h.y_axis.y.abs()).max(h.y_axis.x.abs());
    if det2.abs() <= 1e-12 * scale * scale {
        return Err(format!(
            "metric-interface: in the local basis, the {name} tensor's tangential part has g11 g22 - g12^2 = 0, so Eqs 27-28 have no unique solution"
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Plane, Shape, Sphere};
    use crate::surfaces::tests::{leaves, meet};

    fn isotropic(n: f64) -> DMat3 {
        DMat3::from_diagonal(DVec3::splat(n * n))
    }

    #[test]
    fn isotropic_metrics_refract_by_snells_law_with_eq_24_normalisation() {
        // From n = 1 (z < 0) into n = 1.5 at 30°: sin θ₂ = 1/3, and |e| = 1/n₂ by Eq 24.
        let d = DVec3::new(0.5, 0.0, 3f64.sqrt() / 2.0);
        let e = metric_refracted_direction(
            d,
            &isotropic(1.0),
            &isotropic(1.5),
            Refraction::Positive,
            false,
        )
        .unwrap();
        assert!((e.dot(isotropic(1.5) * e) - 1.0).abs() < 1e-15);
        let e = e.normalize();
        assert!(
            (e.x - 1.0 / 3.0).abs() < 1e-15 && e.z > 0.0 && e.y == 0.0,
            "{e}"
        );
    }

    #[test]
    fn reflection_in_an_isotropic_metric_is_the_mirror_image() {
        let d = DVec3::new(0.3, -0.4, 0.8);
        let r = metric_reflected_direction(d, &isotropic(2.0));
        let mirror = DVec3::new(d.x, d.y, -d.z);
        assert!((r.normalize() - mirror.normalize()).length() < 1e-15, "{r}");
    }

    #[test]
    fn reflection_in_an_anisotropic_metric_keeps_the_tangential_constants() {
        let g = DMat3::from_cols(
            DVec3::new(1.0, 0.2, 0.3),
            DVec3::new(0.2, 1.2, -0.5),
            DVec3::new(0.3, -0.5, 2.0),
        );
        let d = DVec3::new(0.3, -0.4, 0.8);
        let r = metric_reflected_direction(d, &g);
        let (c, q) = fermat_constants(d, &g).unwrap();
        let gr = g * r;
        assert!((DVec2::new(gr.x, gr.y) - c).length() < 1e-14);
        assert!((r.dot(gr) - q.signum()).abs() < 1e-14 && r.z < 0.0);
    }

    #[test]
    fn a_tangential_null_plane_reflects_instead_of_giving_nan() {
        // An indefinite metric (det h = −1) whose tangential part h₁₁h₂₂ − h₁₂² vanishes.
        let h = DMat3::from_cols(
            DVec3::new(0.0, 0.0, 1.0),
            DVec3::Y,
            DVec3::new(1.0, 0.0, 1.0),
        );
        let d = DVec3::new(0.1, 0.2, 1.0);
        assert_eq!(
            metric_refracted_direction(d, &isotropic(1.0), &h, Refraction::Positive, true),
            None
        );
        let interface = MetricInterface {
            inside: isotropic(1.0),
            outside: h,
            basis: Basis::Local,
            refraction: Refraction::Positive,
            allow_imaginary: true,
            transmission_coefficient: 1.0,
            reflection_coefficient: 1.0,
        };
        let Outgoing::Reflected(out) = interface.outgoing(d.normalize(), &DMat3::IDENTITY) else {
            panic!("transmitted")
        };
        assert!(out.is_finite() && out.z < 0.0, "{out}");
    }

    /// The metric interface with the isotropic metrics inside = n² I and outside = I in the
    /// global basis, refracting at `at`.
    fn snell_interface(n: f64) -> MetricInterface {
        MetricInterface {
            inside: isotropic(n),
            outside: isotropic(1.0),
            basis: Basis::Global,
            refraction: Refraction::Positive,
            allow_imaginary: false,
            transmission_coefficient: 0.9,
            reflection_coefficient: 0.6,
        }
    }

    /// Checks `out` against Snell's law n₁ sin θ₁ = n₂ sin θ₂ at a surface with unit normal
    /// `n` (sines as |d × n|): on the far side, in the plane of incidence, running along the
    /// surface the way d does (with `n2` negative, negative refraction: the other way).
    fn assert_snell(d: DVec3, n: DVec3, n1: f64, n2: f64, out: DVec3) {
        assert!((out.length() - 1.0).abs() < 1e-14, "{out}");
        let (sin1, sin2) = (d.cross(n).length(), out.cross(n).length());
        assert!((n1 * sin1 - n2.abs() * sin2).abs() < 1e-13, "{sin1} {sin2}");
        assert!(out.dot(n) * d.dot(n) > 0.0, "crosses");
        assert!(
            out.dot(d.cross(n)).abs() < 1e-14,
            "in the plane of incidence"
        );
        assert!(out.cross(n).dot(d.cross(n)) * n2.signum() > 0.0 || sin1 == 0.0);
    }

    /// A metric g = n² I makes ds² = n² |dr|², the optical path of a medium of index n, so the
    /// interface between inside = n² I and outside = I refracts exactly as Snell's law with
    /// index n inside: on the plane z = 0 (outward normal +z), entering and leaving, and
    /// totally internally reflected (mirror image, with the reflection coefficient) beyond
    /// the critical angle arcsin(1/n); transmitted rays carry the transmission coefficient.
    #[test]
    fn isotropic_metrics_refract_as_snells_law_on_a_plane() {
        let plane = Shape::Plane(Plane::new(DVec3::ZERO, DVec3::Z, DVec3::X).unwrap());
        let glass = snell_interface(1.5);
        let across = DVec3::new(-0.6, 0.8, 0.0);
        let ray = |deg: f64, z: f64| {
            let t: f64 = deg.to_radians();
            t.sin() * across + z * t.cos() * DVec3::Z
        };
        for deg in [5.0, 30.0, 60.0, 85.0] {
            let d = ray(deg, -1.0);
            let (out, factor) = leaves(glass.redirect(&meet(&plane, -2.0 * d, d)));
            assert_eq!(factor, 0.9);
            assert_snell(d, DVec3::Z, 1.0, 1.5, out);
        }
        for deg in [5.0, 30.0, 41.0] {
            let d = ray(deg, 1.0);
            let (out, factor) = leaves(glass.redirect(&meet(&plane, -2.0 * d, d)));
            assert_eq!(factor, 0.9);
            assert_snell(d, DVec3::Z, 1.5, 1.0, out);
        }
        for deg in [42.5, 60.0] {
            let d = ray(deg, 1.0);
            let (out, factor) = leaves(glass.redirect(&meet(&plane, -2.0 * d, d)));
            assert_eq!(factor, 0.6);
            assert!((out - DVec3::new(d.x, d.y, -d.z)).length() < 1e-14, "{out}");
        }
    }

    /// Identical metrics on both sides (Euclidean, or the same anisotropic one) are no
    /// interface: the direction is unchanged. Negative refraction between n = 1 and n = −1
    /// (Veselago's lens: the same metric, opposite signs of the optical path) keeps the
    /// normal component and reverses the tangential one, Snell's law with n₂ = −n₁.
    #[test]
    fn identical_metrics_leave_the_direction_unchanged() {
        let plane = Shape::Plane(
            Plane::new(
                DVec3::new(0.0, 1.0, 0.0),
                DVec3::new(0.0, 0.6, 0.8),
                DVec3::X,
            )
            .unwrap(),
        );
        let sheared = DMat3::from_cols(
            DVec3::new(1.0, 0.2, 0.3),
            DVec3::new(0.2, 1.2, -0.5),
            DVec3::new(0.3, -0.5, 2.0),
        );
        for (g, basis) in [
            (DMat3::IDENTITY, Basis::Global),
            (sheared, Basis::Global),
            (sheared, Basis::Local),
        ] {
            let same = MetricInterface {
                inside: g,
                outside: g,
                basis,
                ..snell_interface(1.0)
            };
            for d in [DVec3::new(0.3, -0.5, -0.7), DVec3::new(-0.2, 0.4, 0.9)] {
                let d = d.normalize();
                let at = meet(&plane, DVec3::new(0.1, 1.0, 0.0) - 3.0 * d, d);
                let (out, factor) = leaves(same.redirect(&at));
                assert!((out - d).length() < 1e-14, "{g} {d}: {out}");
                assert_eq!(factor, 0.9);
            }
        }
        let veselago = MetricInterface {
            refraction: Refraction::Negative,
            ..snell_interface(1.0)
        };
        let n = DVec3::new(0.0, 0.6, 0.8);
        let d = DVec3::new(0.3, -0.5, -0.7).normalize();
        let at = meet(&plane, DVec3::new(0.1, 1.0, 0.0) - 3.0 * d, d);
        let (out, _) = leaves(veselago.redirect(&at));
        assert_snell(d, n, 1.0, -1.0, out);
        assert!((out - (2.0 * d.dot(n) * n - d)).length() < 1e-14, "{out}");
    }

    /// On a sphere, an isotropic metric refracts by Snell's law about the sphere's own
    /// outward normal (P − C)/R at each hit: a metric sphere of n = 1.33.
    #[test]
    fn an_isotropic_metric_sphere_refracts_about_its_normal() {
        let (centre, radius) = (DVec3::new(2.0, 0.0, -1.0), 1.0);
        let sphere = Shape::Sphere(Sphere::new(centre, radius).unwrap());
        let drop = snell_interface(1.33);
        let d = DVec3::new(0.0, 0.28, 0.96);
        let (e1, e2) = d.any_orthonormal_pair();
        for k in 0..8 {
            let (b, turn) = ((k as f64 + 0.5) / 8.0, 1.9 * k as f64);
            let origin = centre - 3.0 * d + b * (turn.cos() * e1 + turn.sin() * e2);
            let at = meet(&sphere, origin, d);
            let n = (at.point() - centre) / radius;
            assert_snell(d, n, 1.0, 1.33, leaves(drop.redirect(&at)).0);
        }
    }
}
