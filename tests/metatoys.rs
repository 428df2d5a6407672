//! METATOY surface laws (§4–6 of the TIM paper), checked from the physics rather than against
//! the implementation's own formulas.
//!
//! - Metric interfaces (§4, Eqs 16–38): against a vector Snell's law for isotropic metrics
//!   n²I, against an independent solution of the Fermat conditions (the outgoing e lies on the
//!   line h⁻¹ (cₓ, c_y, s), s chosen so that eᵀ h e = ±1) rather than Eqs 27–32, by numerically
//!   differentiating the optical path length A → P → B along the interface (Fermat's
//!   principle), by reciprocity (−e goes back to −d) and by the change of basis of Eq 37.
//! - Generalised confocal lenslet arrays (§5, Eq 39): against the two lenslets of a
//!   telescopelet traced lens by lens as ideal thin lenses (Fig. 16), in the order the ray
//!   meets them, rather than against Eq 39; the known special cases (η = −1 flips, η = 1 shifts
//!   slopes by δ), reciprocity and the change of basis.
//! - Ray rotation, flipping, phase holograms and teleporting (§6): the defining geometric
//!   facts (inverse rotation, kick = phase gradient, focusing by a quadratic phase, surface
//!   coordinates preserved by teleporting).
//!
//! Rays come from a small deterministic generator, many per test, so failures reproduce.

mod common;

use std::f64::consts::{FRAC_1_SQRT_2, PI, TAU};

use common::rng::Rng;
use glam::{DMat3, DQuat, DVec2, DVec3};
use timbre::geometry::{Parallelogram, Shape};
use timbre::math::Frame;
use timbre::surfaces::metatoys::{
    Basis, LinearPhase, MetricInterface, Phase, QuadraticPhase, Refraction, Teleportation,
    Teleporting, Telescopelets, flipped, hologram_direction, metric_reflected_direction,
    metric_refracted_direction, rotated, rotated_in_plane_of_incidence,
};

/// Rays per test (per case, where a test has several).
const RAYS: usize = 2000;

// ---------------------------------------------------------------------------------------------
// Random numbers, vectors and tensors.

/// The draws these tests need beyond the common generator's.
trait Draws {
    fn sign(&mut self) -> f64;
    fn cube(&mut self) -> DVec3;
    fn cone(&mut self, axis: DVec3, min: f64, max: f64) -> DVec3;
    fn incident(&mut self) -> DVec3;
    fn rotation(&mut self) -> DMat3;
    fn positive_definite(&mut self) -> DMat3;
    fn indefinite(&mut self) -> DMat3;
}

impl Draws for Rng {
    fn sign(&mut self) -> f64 {
        if self.f() < 0.5 { -1.0 } else { 1.0 }
    }

    /// A point in the cube [−1, 1]³.
    fn cube(&mut self) -> DVec3 {
        self.point(1.0)
    }

    /// A unit vector at an angle between `min` and `max` from the unit vector `axis`.
    fn cone(&mut self, axis: DVec3, min: f64, max: f64) -> DVec3 {
        let cos_t = self.range(max.cos(), min.cos());
        let sin_t = (1.0 - cos_t * cos_t).sqrt();
        let phi = self.range(0.0, TAU);
        let (p, q) = axis.any_orthonormal_pair();
        cos_t * axis + sin_t * (phi.cos() * p + phi.sin() * q)
    }

    /// A direction within 75° of +z or −z, of random length (the laws take any length).
    fn incident(&mut self) -> DVec3 {
        let side = self.sign();
        self.cone(side * DVec3::Z, 0.0, 75f64.to_radians()) * self.range(0.2, 3.0)
    }

    fn rotation(&mut self) -> DMat3 {
        DMat3::from_quat(DQuat::from_axis_angle(self.unit(), self.range(0.0, TAU)))
    }

    /// A random symmetric positive-definite metric.
    fn positive_definite(&mut self) -> DMat3 {
        let a = DMat3::from_cols(self.cube(), self.cube(), self.cube());
        a.transpose() * a + DMat3::from_diagonal(DVec3::splat(0.2))
    }

    /// A random symmetric metric with signature (−, +, +).
    fn indefinite(&mut self) -> DMat3 {
        let r = self.rotation();
        let l = DVec3::new(
            -self.range(0.5, 2.0),
            self.range(0.5, 2.0),
            self.range(0.5, 2.0),
        );
        r * DMat3::from_diagonal(l) * r.transpose()
    }
}

// ---------------------------------------------------------------------------------------------
// Reference computations.

fn isotropic(n: f64) -> DMat3 {
    DMat3::from_diagonal(DVec3::splat(n * n))
}

fn assert_close(got: DVec3, want: DVec3, tol: f64, what: &str) {
    assert!(
        (got - want).length() <= tol,
        "{what}: got {got}, want {want}, difference {:e}",
        (got - want).length()
    );
}

/// Vector Snell's law at a surface with unit normal `n`, from index `n1` into `n2`: the
/// tangential part of the unit direction scales by n1/n2, the normal part keeps its sign.
/// `None` beyond the critical angle.
fn snell(d: DVec3, n: DVec3, n1: f64, n2: f64) -> Option<DVec3> {
    let d = d.normalize();
    let cos_i = d.dot(n);
    let t = (d - cos_i * n) * (n1 / n2);
    let s = t.length_squared();
    (s <= 1.0).then(|| t + cos_i.signum() * (1.0 - s).sqrt() * n)
}

fn mirror(d: DVec3, n: DVec3) -> DVec3 {
    d - 2.0 * d.dot(n) * n
}

/// Eq 22: c = ±(g d)ₓ,ᵧ / √|dᵀ g d|, − for negative refraction.
fn fermat_constants(d: DVec3, g: &DMat3, refraction: Refraction) -> DVec2 {
    let gd = *g * d;
    let sign = match refraction {
        Refraction::Positive => 1.0,
        Refraction::Negative => -1.0,
    };
    sign * DVec2::new(gd.x, gd.y) / d.dot(gd).abs().sqrt()
}

/// An independent solution of Eqs 24–26 (or 35): (h e)ₓ,ᵧ = c means h e = (cₓ, c_y, s) for
/// some s, i.e. e = h⁻¹ (cₓ, c_y, s), and then eᵀ h e = (c, s)ᵀ h⁻¹ (c, s) = `norm` is a
/// quadratic in s. Its two roots give e_z of opposite signs; the one on the `side` of the
/// interface is returned, `None` if there is no real root (or the discriminant is too close to
/// zero to tell).
fn fermat_solution(c: DVec2, h: &DMat3, norm: f64, side: f64) -> Option<Option<DVec3>> {
    let k = h.inverse();
    let base = k * DVec3::new(c.x, c.y, 0.0);
    let col = k * DVec3::Z;
    // (base + s col)ᵀ h (base + s col) = base·(c,0) + 2 s base_z + s² col_z (k symmetric).
    let qa = col.z;
    let qb = base.z;
    let qc = base.x * c.x + base.y * c.y - norm;
    let disc = qb * qb - qa * qc;
    if disc.abs() < 1e-9 * (qb * qb + (qa * qc).abs()) {
        return None;
    }
    if disc < 0.0 {
        return Some(None);
    }
    // e_z = qa s + qb = ±√disc.
    let s = (side * disc.sqrt() - qb) / qa;
    Some(Some(base + s * col))
}

/// Optical path length from `a` via `p` to `b`, in metric `g` before and `h` after; `sign` is
/// +1 for positive refraction (s₁ and s₂ of the same sign) and −1 for negative refraction.
fn optical_path(a: DVec3, p: DVec3, b: DVec3, g: &DMat3, h: &DMat3, sign: f64) -> f64 {
    let (ap, pb) = (p - a, b - p);
    ap.dot(*g * ap).sqrt() + sign * pb.dot(*h * pb).sqrt()
}

/// Numerical derivatives of the optical path length as P moves from `p0` along the tangents
/// `t1` and `t2` of the interface (central differences).
fn path_gradient(
    a: DVec3,
    b: DVec3,
    p0: DVec3,
    (t1, t2): (DVec3, DVec3),
    g: &DMat3,
    h: &DMat3,
    sign: f64,
) -> DVec2 {
    let step = 1e-5;
    let derivative = |t: DVec3| {
        (optical_path(a, p0 + step * t, b, g, h, sign)
            - optical_path(a, p0 - step * t, b, g, h, sign))
            / (2.0 * step)
    };
    DVec2::new(derivative(t1), derivative(t2))
}

fn frame_matrix(f: &Frame) -> DMat3 {
    DMat3::from_cols(f.u, f.v, f.w)
}

fn components(d: DVec3, f: &Frame) -> DVec3 {
    DVec3::new(d.dot(f.u), d.dot(f.v), d.dot(f.w))
}

/// A random tilted surface frame.
fn tilted_frame(rng: &mut Rng) -> Frame {
    let w = rng.cone(DVec3::Z, 20f64.to_radians(), 70f64.to_radians());
    Frame::from_normal_and_u(w, rng.unit())
}

/// The telescopelets' basis of §5.2: â = a normalised, û = u projected perpendicular to â and
/// normalised, v̂ = â × û.
fn gcla_basis(a: DVec3, u: DVec3) -> (DVec3, DVec3, DVec3) {
    let a_hat = a.normalize();
    let u_hat = (u - u.dot(a_hat) * a_hat).normalize();
    (a_hat, u_hat, a_hat.cross(u_hat))
}

/// One lenslet of a telescopelet, as crossed cylindrical thin lenses: focal lengths along û and
/// v̂, and where its optical axis crosses the transverse (û, v̂) plane.
#[derive(Debug, Clone, Copy)]
struct Lenslet {
    focal_length: DVec2,
    axis: DVec2,
}

/// Traces a ray lens by lens (Fig. 16) through `lenslets` spaced `separation` apart along the
/// direction of travel t̂. The ray has transverse slopes `slopes` (û and v̂ components per unit
/// of t̂) and meets the first lens at transverse position `at`. An ideal thin lens of focal
/// length f sends the ray to where the parallel ray through its centre meets its focal plane,
/// f × slope off the axis, so at height h off the axis the slope becomes slope − h/f (in û and
/// v̂ separately, the lenses being cylindrical); between lenses the ray moves on by
/// separation × slope. Returns the slopes after the last lens.
fn trace_lenslets(
    mut slopes: DVec2,
    mut at: DVec2,
    lenslets: &[Lenslet],
    separation: f64,
) -> DVec2 {
    for (k, lens) in lenslets.iter().enumerate() {
        if k > 0 {
            at += separation * slopes;
        }
        slopes -= (at - lens.axis) / lens.focal_length;
    }
    slopes
}

/// The direction in which a gCLA telescopelet sends a ray of direction `d` that meets it at
/// transverse position `at`, worked out from its lenses rather than from Eq 39: lenslet 1 of
/// focal lengths f₁ on the axis, lenslet 2 of focal lengths f₂ = −η f₁ with its axis offset by
/// δ f₁ (the definitions of η and δ in §5.1), confocal so f₁ + f₂ = L for both u and v (here
/// L = 1; η ≠ 1). â points from lenslet array 1 to array 2, so a ray crossing the sheet (normal
/// `n`) towards the side â points to meets lenslet 1 first and travels along â, otherwise it
/// meets lenslet 2 first and travels along −â. `None` if the ray cannot travel from the first
/// lens to the second (d against the direction of travel) or its exit direction does not leave
/// through the far side of the sheet.
fn telescopelet_exit(
    d: DVec3,
    (a_hat, u_hat, v_hat): (DVec3, DVec3, DVec3),
    eta: DVec2,
    delta: DVec2,
    n: DVec3,
    at: DVec2,
) -> Option<DVec3> {
    let separation = 1.0;
    let f1 = DVec2::splat(separation) / (DVec2::ONE - eta);
    let lenslet_1 = Lenslet {
        focal_length: f1,
        axis: DVec2::ZERO,
    };
    let lenslet_2 = Lenslet {
        focal_length: -eta * f1,
        axis: delta * f1,
    };
    let (travel, lenslets) = if a_hat.dot(n) * d.dot(n) > 0.0 {
        (a_hat, [lenslet_1, lenslet_2])
    } else {
        (-a_hat, [lenslet_2, lenslet_1])
    };
    if d.dot(travel) <= 0.0 {
        return None;
    }
    let slopes = DVec2::new(d.dot(u_hat), d.dot(v_hat)) / d.dot(travel);
    let out = trace_lenslets(slopes, at, &lenslets, separation);
    let exit = out.x * u_hat + out.y * v_hat + travel;
    (exit.dot(n) * d.dot(n) > 0.0).then_some(exit)
}

fn random_gcla(rng: &mut Rng, n: DVec3) -> (DVec3, DVec3, DVec2, DVec2) {
    let a = rng.sign() * rng.cone(n, 0.0, 50f64.to_radians()) * rng.range(0.5, 2.0);
    let u = rng.cube();
    let eta = DVec2::new(
        rng.sign() * rng.range(0.3, 3.0),
        rng.sign() * rng.range(0.3, 3.0),
    );
    let delta = DVec2::new(rng.range(-0.5, 0.5), rng.range(-0.5, 0.5));
    (a, u, eta, delta)
}

/// The angle from `a` to `b` about `axis`, wrapped into (−π, π].
fn angle_about(a: DVec3, b: DVec3, axis: DVec3) -> f64 {
    let (p, q) = (a.reject_from_normalized(axis).normalize(), axis);
    let r = q.cross(p);
    let angle = b.dot(r).atan2(b.dot(p));
    wrap(angle)
}

fn wrap(angle: f64) -> f64 {
    let a = angle.rem_euclid(TAU);
    if a > PI { a - TAU } else { a }
}

// ---------------------------------------------------------------------------------------------
// Metric interfaces (§4).

#[test]
fn isotropic_metrics_refract_by_snells_law_with_total_internal_reflection() {
    // Between n₁²I and n₂²I the metric law is Snell's law, and TIR sets in exactly at the
    // critical angle arcsin(n₂/n₁).
    let mut rng = Rng(1);
    let mut refracted = 0;
    for _ in 0..RAYS {
        let (n1, n2) = (rng.range(0.5, 3.0), rng.range(0.5, 3.0));
        let d = rng.incident();
        let got = metric_refracted_direction(
            d,
            &isotropic(n1),
            &isotropic(n2),
            Refraction::Positive,
            false,
        );
        match (got, snell(d, DVec3::Z, n1, n2)) {
            (Some(e), Some(want)) => {
                assert_close(e.normalize(), want, 1e-12, &format!("n {n1} → {n2}, d {d}"));
                refracted += 1;
            }
            (None, None) => {}
            (got, want) => panic!("n {n1} → {n2}, d {d}: got {got:?}, Snell {want:?}"),
        }
    }
    assert!(refracted > RAYS / 2, "only {refracted} rays refracted");

    for _ in 0..200 {
        let n2 = rng.range(0.5, 2.0);
        let n1 = n2 * rng.range(1.1, 3.0);
        let critical = (n2 / n1).asin();
        let phi = rng.range(0.0, TAU);
        let side = rng.sign();
        let at = |theta: f64| {
            let d = DVec3::new(
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                side * theta.cos(),
            );
            metric_refracted_direction(
                d,
                &isotropic(n1),
                &isotropic(n2),
                Refraction::Positive,
                false,
            )
        };
        for eps in [1e-9, 1e-6, 1e-3] {
            let below = at(critical - eps)
                .unwrap_or_else(|| panic!("n {n1} → {n2}: TIR {eps} rad below the critical angle"));
            assert!(below.z * side > 0.0, "{below}");
            // Nearly grazing: e makes ≈ 90° with the normal.
            assert!(below.normalize().z.abs() < 1e-3f64.max(3.0 * (2.0 * eps).sqrt()));
            assert_eq!(
                at(critical + eps),
                None,
                "n {n1} → {n2}: refracted {eps} rad above"
            );
        }
    }
}

#[test]
fn minus_one_against_plus_one_reverses_the_tangential_direction() {
    // Fig. 14b, the Veselago lens: n = −1 against n = +1 is negative refraction between two
    // identity metrics, e ∝ (−dₓ, −d_y, d_z).
    let mut rng = Rng(2);
    for _ in 0..RAYS {
        let d = rng.incident();
        let e = metric_refracted_direction(
            d,
            &DMat3::IDENTITY,
            &DMat3::IDENTITY,
            Refraction::Negative,
            false,
        )
        .unwrap_or_else(|| panic!("no refraction for {d}"));
        assert_close(
            e.normalize(),
            DVec3::new(-d.x, -d.y, d.z).normalize(),
            1e-12,
            "",
        );
        // Eq 24 in the identity metric: e is a unit vector.
        assert!((e.length() - 1.0).abs() < 1e-12, "{e}");
    }
}

#[test]
fn refraction_at_a_metric_interface_is_reciprocal() {
    // Light retraces its path: if d in g refracts into e in h, then −e in h refracts into −d
    // in g, for positive and negative refraction.
    let mut rng = Rng(3);
    for refraction in [Refraction::Positive, Refraction::Negative] {
        let mut passed = 0;
        for _ in 0..RAYS {
            let (g, h) = (rng.positive_definite(), rng.positive_definite());
            let d = rng.incident();
            let Some(e) = metric_refracted_direction(d, &g, &h, refraction, false) else {
                continue;
            };
            let back = metric_refracted_direction(-e, &h, &g, refraction, false)
                .unwrap_or_else(|| panic!("{refraction:?}: −e = {} is reflected", -e));
            assert_close(
                back.normalize(),
                -d.normalize(),
                1e-9,
                &format!("{refraction:?}, g {g}, h {h}, d {d}"),
            );
            passed += 1;
        }
        assert!(
            passed > RAYS / 2,
            "{refraction:?}: only {passed} rays refracted"
        );
    }
}

#[test]
fn refracted_direction_satisfies_eqs_24_to_26_and_35() {
    // The outgoing e has (h e)ₓ,ᵧ = c (Eqs 25–26, c from Eq 22), eᵀ h e = 1 (Eq 24) and leaves
    // on the far side; it equals the independent solution of these conditions, and is `None`
    // exactly when they have none. For dᵀ g d < 0 the imaginary solution has eᵀ h e = −1
    // (Eq 35), and without allow_imaginary the ray is totally internally reflected.
    let mut rng = Rng(4);
    let check = |d: DVec3, g: &DMat3, h: &DMat3, refraction, norm: f64| -> bool {
        let got = metric_refracted_direction(d, g, h, refraction, true);
        let c = fermat_constants(d, g, refraction);
        let side = d.z.signum();
        let Some(want) = fermat_solution(c, h, norm, side) else {
            return false; // Too close to the TIR threshold to judge.
        };
        match (got, want) {
            (Some(e), Some(want)) => {
                let he = *h * e;
                let what = format!("{refraction:?}, g {g}, h {h}, d {d}, e {e}");
                assert!(
                    (e.dot(he) - norm).abs() < 1e-10,
                    "eᵀ h e = {}: {what}",
                    e.dot(he)
                );
                assert!((DVec2::new(he.x, he.y) - c).length() < 1e-10 * (1.0 + c.length()));
                assert!(e.z * side > 0.0, "{what}");
                assert_close(e, want, 1e-9 * want.length(), &what);
                true
            }
            (None, None) => false,
            (got, want) => panic!("g {g}, h {h}, d {d}: got {got:?}, want {want:?}"),
        }
    };
    for refraction in [Refraction::Positive, Refraction::Negative] {
        let mut refracted = 0;
        for _ in 0..RAYS {
            let (g, h) = (rng.positive_definite(), rng.positive_definite());
            refracted += check(rng.incident(), &g, &h, refraction, 1.0) as usize;
        }
        assert!(
            refracted > RAYS / 2,
            "{refraction:?}: {refracted} refracted"
        );
    }
    // Indefinite metrics: directions with dᵀ g d < 0 use Eq 35.
    let (mut imaginary, mut real) = (0, 0);
    for _ in 0..RAYS {
        let (g, h) = (rng.indefinite(), rng.indefinite());
        let d = rng.incident();
        let q = d.dot(g * d);
        if q < 0.0 {
            assert_eq!(
                metric_refracted_direction(d, &g, &h, Refraction::Positive, false),
                None,
                "dᵀ g d = {q} without allow_imaginary"
            );
            imaginary += check(d, &g, &h, Refraction::Positive, -1.0) as usize;
        } else {
            real += check(d, &g, &h, Refraction::Positive, 1.0) as usize;
        }
    }
    assert!(
        imaginary > RAYS / 20 && real > RAYS / 20,
        "{imaginary} imaginary, {real} real"
    );
}

#[test]
fn refracted_direction_makes_the_optical_path_stationary() {
    // Fermat's principle (Eqs 19–20): with A = −d and B = e, the optical path A → P → B via
    // P = (x, y, 0) is stationary at P = 0 (s₁ − s₂ for negative refraction). So is the
    // totally internally reflected path, A → P → B in g throughout. A direction turned by
    // 10⁻³ rad is visibly not stationary, so the check can fail.
    let mut rng = Rng(5);
    let tangents = (DVec3::X, DVec3::Y);
    let mut reflected = 0;
    for refraction in [Refraction::Positive, Refraction::Negative] {
        let sign = if refraction == Refraction::Positive {
            1.0
        } else {
            -1.0
        };
        for _ in 0..RAYS {
            let (g, h) = (rng.positive_definite(), rng.positive_definite());
            let d = rng.incident();
            let a = -d.normalize();
            let Some(e) = metric_refracted_direction(d, &g, &h, refraction, false) else {
                if refraction == Refraction::Positive {
                    let r = metric_reflected_direction(d, &g).normalize();
                    assert!(r.z * d.z < 0.0, "reflected {r} for {d}");
                    let grad = path_gradient(a, r, DVec3::ZERO, tangents, &g, &g, 1.0);
                    assert!(grad.length() < 1e-7, "TIR g {g}, d {d}: gradient {grad}");
                    reflected += 1;
                }
                continue;
            };
            let b = e.normalize();
            let grad = path_gradient(a, b, DVec3::ZERO, tangents, &g, &h, sign);
            assert!(
                grad.length() < 1e-7,
                "{refraction:?} g {g}, h {h}, d {d}: gradient {grad}"
            );
            let turned = DQuat::from_axis_angle(b.any_orthonormal_vector(), 1e-3) * b;
            let grad = path_gradient(a, turned, DVec3::ZERO, tangents, &g, &h, sign);
            assert!(grad.length() > 1e-5, "insensitive: {grad}");
        }
    }
    assert!(reflected > 10, "only {reflected} rays reflected");
}

#[test]
fn global_and_local_tensors_agree_on_a_tilted_interface() {
    // Eq 37: tensors g, h in the global basis act like Λᵀ g Λ, Λᵀ h Λ in the local one. A ray
    // from inside (along w) goes from `inside` into `outside`, one from outside (against w)
    // from `outside` into `inside`: Snell's law for isotropic tensors, mirror reflection at
    // TIR, and a stationary optical path along the tilted plane for anisotropic ones.
    let mut rng = Rng(6);
    for _ in 0..RAYS {
        let frame = tilted_frame(&mut rng);
        let lambda = frame_matrix(&frame);
        let (g, h) = (rng.positive_definite(), rng.positive_definite());
        let interface = |inside, outside, basis| MetricInterface {
            inside,
            outside,
            basis,
            refraction: Refraction::Positive,
            allow_imaginary: false,
            transmission_coefficient: 1.0,
            reflection_coefficient: 1.0,
        };
        let global = interface(g, h, Basis::Global);
        let local = interface(
            lambda.transpose() * g * lambda,
            lambda.transpose() * h * lambda,
            Basis::Local,
        );
        let d = rng.sign() * rng.cone(frame.w, 0.0, 75f64.to_radians());
        let e = global.outgoing(d, &lambda).direction();
        assert_close(
            e,
            local.outgoing(d, &lambda).direction(),
            1e-12,
            &format!("d {d}"),
        );
        assert!((e.length() - 1.0).abs() < 1e-12);

        // Fermat along the tilted plane, in global coordinates.
        let from = if d.dot(frame.w) > 0.0 { g } else { h };
        let to = if e.dot(frame.w) * d.dot(frame.w) > 0.0 {
            if d.dot(frame.w) > 0.0 { h } else { g }
        } else {
            from // Totally internally reflected.
        };
        let grad = path_gradient(-d, e, DVec3::ZERO, (frame.u, frame.v), &from, &to, 1.0);
        assert!(
            grad.length() < 1e-7,
            "g {g}, h {h}, d {d}, e {e}: gradient {grad}"
        );
    }

    let (n_in, n_out) = (1.2, 1.7);
    let (mut inward_tir, mut inward) = (0, 0);
    for _ in 0..RAYS {
        let frame = tilted_frame(&mut rng);
        let lambda = frame_matrix(&frame);
        let interface = MetricInterface {
            inside: isotropic(n_in),
            outside: isotropic(n_out),
            basis: Basis::Global,
            refraction: Refraction::Positive,
            allow_imaginary: false,
            transmission_coefficient: 1.0,
            reflection_coefficient: 1.0,
        };
        let d = rng.sign() * rng.cone(frame.w, 0.0, 85f64.to_radians());
        let (n1, n2) = if d.dot(frame.w) > 0.0 {
            (n_in, n_out)
        } else {
            (n_out, n_in)
        };
        let want = snell(d, frame.w, n1, n2);
        if d.dot(frame.w) < 0.0 {
            inward += 1;
            inward_tir += want.is_none() as usize;
        }
        let want = want.unwrap_or_else(|| mirror(d, frame.w));
        assert_close(
            interface.outgoing(d, &lambda).direction(),
            want,
            1e-12,
            &format!("d {d}, w {}", frame.w),
        );
    }
    assert!(
        inward_tir > 10 && inward > inward_tir + 10,
        "{inward_tir} of {inward} TIR"
    );
}

// ---------------------------------------------------------------------------------------------
// Generalised confocal lenslet arrays (§5).

#[test]
fn gcla_with_eta_minus_one_along_the_normal_flips_both_tangential_components() {
    // η_u = η_v = −1, δ = 0 and â along the normal: d′ ∝ (−d_u, −d_v, d_w) from either side,
    // which is flipping about u and then about v.
    let mut rng = Rng(7);
    for _ in 0..RAYS {
        let frame = tilted_frame(&mut rng);
        let n = frame.w;
        let t = Telescopelets::new(
            n * rng.range(0.5, 2.0),
            rng.cube(),
            DVec2::NEG_ONE,
            DVec2::ZERO,
        )
        .unwrap();
        let d = rng.sign() * rng.cone(n, 0.0, 80f64.to_radians());
        let out = t
            .refract(d, n)
            .unwrap_or_else(|| panic!("d {d} did not pass"));
        let l = components(
            d,
            &Frame {
                u: t.u_hat,
                v: t.v_hat,
                w: t.a_hat,
            },
        );
        let want = (-l.x * t.u_hat - l.y * t.v_hat + l.z * t.a_hat).normalize();
        assert_close(out.normalize(), want, 1e-12, &format!("d {d}"));
        let twice = flipped(flipped(d, t.u_hat), t.v_hat);
        assert_close(out.normalize(), twice.normalize(), 1e-12, "flipped twice");
    }
}

#[test]
fn gcla_with_eta_one_shifts_the_slopes_by_delta() {
    // With η = 1 (f₂ = −f₁: lenses of opposite power, their axes δ f₁ apart) the slopes
    // (d′·û)/(d′·â) are the incident slopes minus δ, wherever the ray enters.
    let mut rng = Rng(8);
    let mut shifted = 0;
    for _ in 0..RAYS {
        let n = rng.unit();
        let a = rng.cone(n, 0.0, 40f64.to_radians());
        let delta = DVec2::new(rng.range(-0.3, 0.3), rng.range(-0.3, 0.3));
        let u = rng.cube();
        let t = Telescopelets::new(a, u, DVec2::ONE, delta).unwrap();
        let d = rng.cone(a, 0.0, 40f64.to_radians());
        let Some(out) = t.refract(d, n) else {
            continue;
        };
        let (a_hat, u_hat, v_hat) = gcla_basis(a, u);
        let slopes = |x: DVec3| DVec2::new(x.dot(u_hat), x.dot(v_hat)) / x.dot(a_hat);
        let diff = slopes(out) - (slopes(d) - delta);
        assert!(
            diff.length() < 1e-12,
            "d {d}, δ {delta}: slopes off by {diff}"
        );
        shifted += 1;
    }
    assert!(shifted > RAYS / 2, "only {shifted} passed");
}

#[test]
fn gcla_bends_rays_like_confocal_lenslets_traced_lens_by_lens() {
    // The basis is that of §5.2, and d′ is the direction the two lenslets of a telescopelet give
    // the ray, traced through them in the order the ray meets them; that direction does not
    // depend on where the ray enters (the telescope property, checked on the oracle too).
    let mut rng = Rng(12);
    let mut passed = 0;
    for _ in 0..RAYS {
        let n = rng.unit();
        let (a, u, eta, delta) = random_gcla(&mut rng, n);
        let t = Telescopelets::new(a, u, eta, delta).unwrap();
        let basis = gcla_basis(a, u);
        let (a_hat, u_hat, v_hat) = basis;
        assert_close(t.a_hat, a_hat, 1e-15, "â");
        assert_close(t.u_hat, u_hat, 1e-14, "û");
        assert_close(t.v_hat, v_hat, 1e-14, "v̂");
        let d = rng.sign() * rng.cone(n, 0.0, 75f64.to_radians());
        let entry = |rng: &mut Rng| DVec2::new(rng.range(-0.5, 0.5), rng.range(-0.5, 0.5));
        let want = telescopelet_exit(d, basis, eta, delta, n, entry(&mut rng));
        let elsewhere = telescopelet_exit(d, basis, eta, delta, n, entry(&mut rng));
        let what = || format!("a {a}, u {u}, η {eta}, δ {delta}, d {d}");
        match (t.refract(d, n), want, elsewhere) {
            (Some(out), Some(want), Some(elsewhere)) => {
                let want = want.normalize();
                assert_close(elsewhere.normalize(), want, 1e-9, &what());
                assert_close(out.normalize(), want, 1e-9, &what());
                passed += 1;
            }
            (None, None, None) => {}
            other => panic!("{}: {other:?}", what()),
        }
    }
    assert!(passed > RAYS / 4, "only {passed} passed");
}

#[test]
fn gcla_is_reciprocal_by_the_reverse_order_rule() {
    // A ray sent back along −d′ meets the arrays in the opposite order and leaves along −d.
    let mut rng = Rng(9);
    let mut passed = 0;
    for _ in 0..RAYS {
        let n = rng.unit();
        let (a, u, eta, delta) = random_gcla(&mut rng, n);
        let t = Telescopelets::new(a, u, eta, delta).unwrap();
        let d = rng.sign() * rng.cone(n, 0.0, 75f64.to_radians());
        let Some(out) = t.refract(d, n) else {
            continue;
        };
        let back = t
            .refract(-out, n)
            .unwrap_or_else(|| panic!("a {a}, η {eta}, δ {delta}: −d′ for d {d} is stopped"));
        assert_close(
            back.normalize(),
            -d.normalize(),
            1e-10,
            &format!("a {a}, d {d}"),
        );
        passed += 1;
    }
    assert!(passed > RAYS / 4, "only {passed} passed");
}

#[test]
fn gcla_in_the_local_basis_agrees_with_the_global_basis() {
    // a and u given as components along the frame's u, v, w are the vectors Λ a, Λ u globally,
    // and the law is covariant: refracting in the tilted frame is refracting the local
    // components at a sheet with normal z and rotating the result back.
    let mut rng = Rng(10);
    for _ in 0..RAYS {
        let frame = tilted_frame(&mut rng);
        let lambda = frame_matrix(&frame);
        let (a_local, u_local, eta, delta) = random_gcla(&mut rng, DVec3::Z);
        let a = a_local.x * frame.u + a_local.y * frame.v + a_local.z * frame.w;
        let u = u_local.x * frame.u + u_local.y * frame.v + u_local.z * frame.w;
        assert_close(Basis::Local.to_global(a_local, &frame), a, 1e-14, "a");
        assert_close(Basis::Local.to_global(u_local, &frame), u, 1e-14, "u");
        assert_eq!(Basis::Global.to_global(a, &frame), a);

        let from_local = Telescopelets::new(
            Basis::Local.to_global(a_local, &frame),
            Basis::Local.to_global(u_local, &frame),
            eta,
            delta,
        )
        .unwrap();
        let from_global = Telescopelets::new(a, u, eta, delta).unwrap();
        let untilted = Telescopelets::new(a_local, u_local, eta, delta).unwrap();
        let d = rng.sign() * rng.cone(frame.w, 0.0, 75f64.to_radians());
        let got = from_local.refract(d, frame.w);
        let global = from_global.refract(d, frame.w);
        let rotated_back = untilted
            .refract(lambda.transpose() * d, DVec3::Z)
            .map(|x| lambda * x);
        match (got, global, rotated_back) {
            (Some(x), Some(y), Some(z)) => {
                assert_close(x, y, 1e-12 * y.length(), "local vs global");
                assert_close(x, z, 1e-10 * z.length(), "tilted vs untilted");
            }
            (None, None, None) => {}
            other => panic!("d {d}: {other:?}"),
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Ray rotation and flipping, phase holograms, teleporting (§6).

#[test]
fn ray_rotation_is_undone_by_the_opposite_angle_and_turns_about_the_normal() {
    // Rotation by α then by −α (same axis, same crossing direction) is the identity; sending
    // the result back (−d′) gives −d. About the normal, d·n is kept and the tangential part
    // turns by α about the crossing direction sign(d·n) n.
    let mut rng = Rng(11);
    let mut passed = 0;
    for _ in 0..RAYS {
        let n = rng.unit();
        let axis = rng.unit();
        let alpha = rng.range(-PI, PI);
        let d = rng.sign() * rng.cone(n, 0.0, 80f64.to_radians());
        let Some(out) = rotated(d, axis, alpha, n) else {
            continue;
        };
        let back = rotated(out, axis, -alpha, n).expect("the inverse rotation crosses");
        assert_close(back, d, 1e-12, &format!("axis {axis}, α {alpha}, d {d}"));
        let reverse = rotated(-out, axis, alpha, n).expect("the reversed ray crosses");
        assert_close(reverse, -d, 1e-12, "reciprocity");
        passed += 1;
    }
    assert!(passed > RAYS / 4, "only {passed} passed");

    for _ in 0..RAYS {
        let n = rng.unit();
        let alpha = rng.range(-PI, PI);
        let d = rng.sign() * rng.cone(n, 5f64.to_radians(), 85f64.to_radians());
        let out = rotated(d, n, alpha, n).expect("rotation about the normal always crosses");
        assert!(
            (out.dot(n) - d.dot(n)).abs() < 1e-12,
            "d·n changed: {d} → {out}"
        );
        assert!((out.length() - d.length()).abs() < 1e-12);
        let crossing = d.dot(n).signum() * n;
        let turned = angle_about(d, out, crossing);
        assert!(
            wrap(turned - alpha).abs() < 1e-9,
            "turned {turned}, α {alpha}"
        );
    }
}

#[test]
fn rotation_in_the_plane_of_incidence_adds_the_angle_to_the_angle_of_incidence() {
    // Dr TIM's RayRotatingInPlaneOfIncidence: the direction stays in the plane of d and n, on
    // the same side of the normal, at the angle of incidence plus θ from the normal it
    // crosses along (for α + θ from 0 to 180°).
    let mut rng = Rng(17);
    for _ in 0..RAYS {
        let n = rng.unit();
        let d = rng.sign() * rng.cone(n, 1f64.to_radians(), 89f64.to_radians());
        let crossing = d.dot(n).signum() * n;
        let alpha = d.angle_between(crossing);
        let theta = rng.range(-alpha + 1e-3, PI - alpha - 1e-3);
        let out = rotated_in_plane_of_incidence(d, n, theta).expect("not normal incidence");
        let what = format!("d {d}, n {n}, θ {theta}");
        assert!((out.length() - 1.0).abs() < 1e-12, "{what}");
        assert!(
            out.dot(d.cross(n).normalize()).abs() < 1e-12,
            "in the plane: {what}"
        );
        assert!(
            (out.angle_between(crossing) - (alpha + theta)).abs() < 1e-9,
            "{what}"
        );
        let side = |v: DVec3| v - v.dot(n) * n;
        assert!(
            side(out).dot(side(d)) >= -1e-12,
            "the same side of the normal: {what}"
        );
    }
}

#[test]
fn linear_phase_hologram_gives_a_constant_tangential_kick() {
    // φ = g·(u, v): every ray, anywhere on the hologram, gains exactly g in its tangential
    // direction components (unless the wave becomes evanescent), keeps its side and unit
    // length; −d′ comes back as −d.
    let mut rng = Rng(12);
    let gradient = DVec2::new(0.21, -0.13);
    let phase = Phase::Linear(LinearPhase { gradient });
    let mut passed = 0;
    for _ in 0..RAYS {
        let r = DVec2::new(rng.range(-5.0, 5.0), rng.range(-5.0, 5.0));
        let d = rng.sign() * rng.cone(DVec3::Z, 0.0, 70f64.to_radians());
        let Some(out) = hologram_direction(d, phase.gradient(r)) else {
            assert!(
                (DVec2::new(d.x, d.y) + gradient).length() >= 1.0,
                "d {d} refused"
            );
            continue;
        };
        let kick = DVec2::new(out.x - d.x, out.y - d.y);
        assert!(
            (kick - gradient).length() < 1e-14,
            "r {r}, d {d}: kick {kick}"
        );
        assert!(
            (out.length() - 1.0).abs() < 1e-14 && out.z * d.z > 0.0,
            "{out}"
        );
        let back = hologram_direction(-out, phase.gradient(r)).unwrap();
        assert_close(back, -d, 1e-12, "reciprocity");
        passed += 1;
    }
    assert!(passed > RAYS * 3 / 4, "only {passed} passed");
}

#[test]
fn quadratic_phase_hologram_focuses_a_parallel_bundle() {
    // φ = −|r − c|²/(2f) is a thin lens: a bundle along the normal, within radius ρ ≪ f of the
    // centre, passes the point at distance f on the axis through c within the paraxial
    // aberration (≈ ρ³/(2f²)), and misses the points at 0.5 f and 1.5 f by about ρ/2.
    let mut rng = Rng(13);
    for f in [0.5, 2.0, 10.0] {
        let centre = DVec2::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0));
        let phase = Phase::Quadratic(QuadraticPhase {
            focal_length: f,
            centre,
        });
        let rho = 0.02 * f;
        let spread = |z: f64| {
            let focus = DVec3::new(centre.x, centre.y, z);
            let mut rng = Rng(14);
            (0..RAYS)
                .map(|_| {
                    let offset = rho * rng.f().sqrt();
                    let phi = rng.range(0.0, TAU);
                    let r = centre + offset * DVec2::new(phi.cos(), phi.sin());
                    let e = hologram_direction(DVec3::Z, phase.gradient(r)).unwrap();
                    let p = DVec3::new(r.x, r.y, 0.0);
                    (focus - p).cross(e).length() / e.length()
                })
                .fold(0.0, f64::max)
        };
        let at_focus = spread(f);
        assert!(
            at_focus <= rho.powi(3) / (f * f),
            "f {f}: spread {at_focus:e} at the focus"
        );
        for z in [0.5 * f, 1.5 * f] {
            let off = spread(z);
            assert!(
                off > 0.4 * rho && off > 100.0 * at_focus,
                "f {f}: spread {off:e} at {z}"
            );
        }
    }
}

fn parallelogram(corner: DVec3, span_u: DVec3, span_v: DVec3) -> Shape {
    Shape::Parallelogram(Parallelogram::new(corner, span_u, span_v).unwrap())
}

#[test]
fn teleporting_keeps_surface_coordinates_and_local_direction_components() {
    // A perfect teleporter from a 2 × 1 rectangle to a smaller, skewed, rotated and moved
    // parallelogram: the ray leaves from the point with the same coordinates (α|span_u|,
    // β|span_v|), with the direction's (u, v, w) components unchanged, i.e. rotated with the
    // surface; beyond the destination's edge nothing leaves.
    let mut rng = Rng(15);
    let origin = parallelogram(DVec3::new(-1.0, -0.5, 0.0), 2.0 * DVec3::X, DVec3::Y);
    let rotation = DMat3::from_quat(DQuat::from_axis_angle(
        DVec3::new(1.0, 2.0, 3.0).normalize(),
        2.0,
    ));
    let corner = DVec3::new(5.0, -3.0, 7.0);
    let (span_u, span_v) = (
        rotation * DVec3::new(1.5, 0.0, 0.0),
        rotation * DVec3::new(0.4, 0.8, 0.0),
    );
    let teleporter = Teleporting {
        destination: Some(parallelogram(corner, span_u, span_v)),
        teleportation: Teleportation::Perfect,
        positional_error: 0.0,
        angular_error: 0.0,
        transmission_coefficient: 1.0,
        reflection_coefficient: 1.0,
    };
    let (mut inside, mut outside) = (0, 0);
    for _ in 0..RAYS {
        let c = DVec2::new(rng.range(0.0, 2.0), rng.range(0.0, 1.0));
        let p = origin.point_at(c).unwrap();
        let frame = origin.frame(p, 0);
        let d = rng.unit();
        let got = teleporter.teleport(c, d, &frame, |_| 0.5);
        if c.x > span_u.length() || c.y > span_v.length() {
            assert_eq!(got, None, "c {c} is beyond the destination");
            outside += 1;
            continue;
        }
        let (point, direction) = got.unwrap_or_else(|| panic!("c {c} not teleported"));
        let want = corner + c.x * span_u.normalize() + c.y * span_v.normalize();
        assert_close(point, want, 1e-12, &format!("c {c}"));
        let coordinates = teleporter
            .destination
            .as_ref()
            .unwrap()
            .coordinates(point, 0);
        assert!(
            (coordinates - c).length() < 1e-12,
            "c {c} arrives at {coordinates}"
        );
        let exit = teleporter.destination.as_ref().unwrap().frame(point, 0);
        assert_close(
            components(direction, &exit),
            components(d, &frame),
            1e-12,
            "components",
        );
        assert_close(direction, rotation * d, 1e-12, "rotated with the surface");
        inside += 1;
    }
    assert!(
        inside > RAYS / 4 && outside > RAYS / 4,
        "{inside} inside, {outside} outside"
    );
}

#[test]
fn imperfect_teleporting_spreads_exit_points_within_the_positional_error() {
    // With positional error σ the exit point is within σ of the perfect one (on a rectangular
    // destination, coordinates are distances), spread over the disc: not all the same, about
    // half within σ/√2 (uniform over the disc), centred on the perfect point.
    let mut rng = Rng(16);
    let origin = parallelogram(DVec3::ZERO, 2.0 * DVec3::X, DVec3::Y);
    let rotation = rng.rotation();
    let sigma = 0.05;
    let destination = parallelogram(
        DVec3::new(-4.0, 2.0, 1.0),
        rotation * DVec3::new(1.5, 0.0, 0.0),
        rotation * DVec3::new(0.0, 1.0, 0.0),
    );
    let perfect = Teleporting {
        destination: Some(destination.clone()),
        teleportation: Teleportation::Perfect,
        positional_error: 0.0,
        angular_error: 0.0,
        transmission_coefficient: 1.0,
        reflection_coefficient: 1.0,
    };
    let noisy = Teleporting {
        positional_error: sigma,
        ..perfect.clone()
    };
    for _ in 0..5 {
        let c = DVec2::new(rng.range(sigma, 1.5 - sigma), rng.range(sigma, 1.0 - sigma));
        let frame = origin.frame(origin.point_at(c).unwrap(), 0);
        let d = rng.unit();
        let (centre, _) = perfect.teleport(c, d, &frame, |_| 0.5).unwrap();
        let offsets: Vec<DVec3> = (0..RAYS)
            .map(|_| {
                let noise = [rng.f(), rng.f(), rng.f(), rng.f()];
                let (p, direction) = noisy.teleport(c, d, &frame, |i| noise[i as usize]).unwrap();
                assert_close(direction, rotation * d, 1e-12, "direction");
                p - centre
            })
            .collect();
        let largest = offsets.iter().map(|o| o.length()).fold(0.0, f64::max);
        assert!(largest <= sigma * (1.0 + 1e-9), "offset {largest} > σ");
        assert!(largest > 0.9 * sigma, "largest offset only {largest}");
        let near = offsets
            .iter()
            .filter(|o| o.length() < sigma * FRAC_1_SQRT_2)
            .count();
        let fraction = near as f64 / RAYS as f64;
        assert!((0.4..0.6).contains(&fraction), "{fraction} within σ/√2");
        let mean = offsets.iter().sum::<DVec3>() / RAYS as f64;
        assert!(mean.length() < 0.1 * sigma, "mean offset {mean}");
        let normal = rotation * DVec3::Z;
        assert!(
            offsets.iter().all(|o| o.dot(normal).abs() < 1e-12),
            "off the destination"
        );
    }
}

/// The Lorentz and Galileo windows in the local basis: β = (0, 0, b) along the window's outward
/// normal w is the global β = b w, here on the METATOY window, whose normal is +z (seen from
/// the inside), so the pictures agree.
#[test]
fn transform_windows_read_beta_in_the_local_basis() {
    use common::images::render_text;
    for kind in ["lorentz-window", "galileo-window"] {
        let scene = |keys: &str| {
            render_text(&format!(
                "studio = \"metatoy-window\"\n[render]\nwidth = 48\nheight = 36\n[window]\nsurface = {{ type = \"{kind}\", {keys} }}\n"
            ))
        };
        let global = scene("beta = [0, 0, 0.6]");
        let local = scene("beta = [0, 0, 0.6], basis = \"local\"");
        let sideways = scene("beta = [0.6, 0, 0]");
        let diff = |a: &timbre::render::Image, b: &timbre::render::Image| {
            a.pixels
                .iter()
                .zip(&b.pixels)
                .map(|(p, q)| (*p - *q).abs().max_element())
                .fold(0.0, f64::max)
        };
        assert!(diff(&global, &local) < 1e-9, "{kind}");
        assert!(diff(&global, &sideways) > 0.1, "{kind}: β matters");
    }
}
