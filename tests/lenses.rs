//! The lenses of Dr TIM §3 (`timbre::surfaces::lenses`) against expectations derived here,
//! independently, from the paper and from the ray optics of the index profiles:
//!
//! * Table 1: the GGRIN lens (Eqs 11–15) with (r, r′, φ) = (∞, R, 180°), (∞, ∞, 0°) and
//!   (R, R, 180°) is the Luneburg, Eaton and Maxwell-fisheye lens (Eqs 5–10);
//! * what each lens is for: the Luneburg lens focuses a parallel bundle onto C + R d̂, the Eaton
//!   lens retro-reflects (d′ = −d, leaving from P mirrored in the line through C along d), the
//!   Maxwell-fisheye lens images every surface point onto its antipode, whatever the direction
//!   — for the closed forms and for the ray equation integrated through n(r), including a
//!   tabulated (spline) Luneburg profile and Eaton rays aimed within 1e-7 R of the singular
//!   centre (and just either side of the impact parameter below which the implementation stops
//!   integrating them);
//! * the GGRIN construction itself: angular momentum |(P′ − C) × d′| conserved, the ray staying
//!   in its plane of incidence, leaving outwards from the surface, its lines through A and A′
//!   (distances r and r′ from C) meeting at C at the angle φ; r = ∞ is the limit r → ∞;
//! * the invisible core (§3.2): rays whose line passes closer than R_t to C cross undeviated;
//! * the index step at the surface (§3.3): Snell's law in and out (written here from angles),
//!   around the law; the closed-form and integrated Luneburg lens agree with it; the Maxwell
//!   fisheye still images onto the antipode, while the Eaton lens no longer retro-reflects
//!   (it sends d to d − 2(d·t̂)t̂, t̂ the refracted direction); reflection on entry when
//!   n_surface < n_surrounding; rays leave at the angle they arrived at, even at grazing
//!   incidence, as total internal reflection on the way out is impossible for these
//!   spherically symmetric laws (rounding must not trap rays there);
//! * the time of the crossing (the `path` of integrated rays): the optical path lengths that
//!   perfect imaging makes equal (Luneburg R(π/2 − x̂·t̂) along its elliptical orbits, Maxwell
//!   fisheye πR, Eaton R(π − 2 x̂·d̂)), scaled by the index ratio.
//!
//! Rays are drawn from fixed seeds with the tests' SplitMix64 generator, on lenses of random
//! centre (within 10 of the origin) and radius (0.1 to 10).

mod common;

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use glam::DVec3;

use common::rng::Rng;
use timbre::geometry::Exit;
use timbre::geometry::Sphere;
use timbre::surfaces::lenses::Ggrin;
use timbre::surfaces::lenses::GradientIndex;
use timbre::surfaces::lenses::IndexProfile;
use timbre::surfaces::lenses::Lens;
use timbre::surfaces::lenses::LensLaw;
use timbre::surfaces::lenses::TableProfile;
use timbre::surfaces::lenses::eaton;
use timbre::surfaces::lenses::luneburg;
use timbre::surfaces::lenses::maxwell_fisheye;

const INF: f64 = f64::INFINITY;

/// Eqs 5–6, 7–8 or 9–10.
type ClosedForm = fn(&Sphere, DVec3, DVec3) -> Exit;

/// The largest error seen by a test, checked against its tolerance at the end (NaN counts as
/// infinitely wrong).
struct Worst {
    what: String,
    tolerance: f64,
    value: f64,
    case: String,
}

impl Worst {
    fn new(what: impl Into<String>, tolerance: f64) -> Worst {
        Worst {
            what: what.into(),
            tolerance,
            value: 0.0,
            case: String::new(),
        }
    }

    fn see(&mut self, error: f64, case: impl FnOnce() -> String) {
        let error = if error.is_nan() { INF } else { error };
        if error > self.value {
            self.value = error;
            self.case = case();
        }
    }

    fn check(&self) {
        assert!(
            self.value <= self.tolerance,
            "{}: worst error {:e} exceeds {:e}, at {}",
            self.what,
            self.value,
            self.tolerance,
            self.case
        );
    }
}

/// The worst errors of closed-form and integrated exits against the expected exit point (in
/// units of R) and direction.
struct Exits {
    closed: [Worst; 2],
    integrated: [Worst; 2],
}

impl Exits {
    /// Trackers named after what is compared: closed forms within 1e-12 R of the point and
    /// `closed_direction` of the direction, integrated rays within 1e-6 of both.
    fn new(point: &str, direction: &str, closed_direction: f64) -> Exits {
        Exits {
            closed: [
                Worst::new(format!("closed form: {point}"), 1e-12),
                Worst::new(format!("closed form: {direction}"), closed_direction),
            ],
            integrated: [
                Worst::new(format!("integrated: {point}"), 1e-6),
                Worst::new(format!("integrated: {direction}"), 1e-6),
            ],
        }
    }

    fn check(self) {
        check_all(self.closed);
        check_all(self.integrated);
    }
}

/// Records how far `exit` leaves from `point` (relative to the lens radius) and in what
/// direction from `direction`.
fn see_exit(
    worst: &mut [Worst; 2],
    exit: &Exit,
    lens: &Sphere,
    point: DVec3,
    direction: DVec3,
    case: impl Fn() -> String,
) {
    worst[0].see(exit.point.distance(point) / lens.radius(), &case);
    worst[1].see(exit.direction.distance(direction), case);
}

/// Checks every tracker.
fn check_all<const N: usize>(worsts: [Worst; N]) {
    for w in worsts {
        w.check();
    }
}

fn random_lens(rng: &mut Rng) -> Sphere {
    let centre = rng.point(10.0);
    let radius = rng.range(0.1f64.ln(), 10f64.ln()).exp();
    Sphere::new(centre, radius).unwrap()
}

/// A random unit vector perpendicular to the unit vector `u`.
fn perpendicular(rng: &mut Rng, u: DVec3) -> DVec3 {
    let (a, b) = u.any_orthonormal_pair();
    let turn = rng.range(0.0, TAU);
    a * turn.cos() + b * turn.sin()
}

/// A random point on the surface and a unit direction arriving there from outside, the cosine
/// of its angle of incidence uniform in [1e-3, 1] (from near-grazing to radial).
fn random_entry(rng: &mut Rng, lens: &Sphere) -> (DVec3, DVec3) {
    let u = rng.unit();
    let p = lens.centre() + lens.radius() * u;
    let cos = rng.range(1e-3, 1.0);
    let sin = (1.0 - cos * cos).sqrt();
    let d = -cos * u + sin * perpendicular(rng, u);
    (p, d.normalize())
}

/// Where the ray with unit direction `d` and impact parameter `b` (units of R), its plane of
/// incidence containing the unit vector `e` ⊥ `d`, meets the lens.
fn entry_point(lens: &Sphere, d: DVec3, e: DVec3, b: f64) -> DVec3 {
    lens.centre() + lens.radius() * (b * e - (1.0 - b * b).sqrt() * d)
}

/// Where the straight line of that ray leaves the lens.
fn straight_exit(lens: &Sphere, d: DVec3, e: DVec3, b: f64) -> DVec3 {
    lens.centre() + lens.radius() * (b * e + (1.0 - b * b).sqrt() * d)
}

/// Entry points of a parallel bundle along the unit `d`, spread uniformly over the lens's disc
/// as seen along `d` (up to impact parameter 0.999 R), starting with the axial ray.
fn bundle(rng: &mut Rng, lens: &Sphere, d: DVec3, count: usize) -> Vec<DVec3> {
    (0..count)
        .map(|k| {
            let b = if k == 0 { 0.0 } else { 0.999 * rng.f().sqrt() };
            let e = perpendicular(rng, d);
            entry_point(lens, d, e, b)
        })
        .collect()
}

/// Unit outward normal of the lens at `x`.
fn normal(lens: &Sphere, x: DVec3) -> DVec3 {
    ((x - lens.centre()) / lens.radius()).normalize()
}

/// Snell's law written with angles: the ray with unit direction `d` crossing a surface whose
/// unit normal `across` points in the direction of travel, from index n₁ into n₂
/// (`n1_over_n2` = n₁/n₂): sin θ₂ = (n₁/n₂) sin θ₁ in the plane of `d` and the normal. `None`
/// for total internal reflection.
fn snell(d: DVec3, across: DVec3, n1_over_n2: f64) -> Option<DVec3> {
    let cos1 = d.dot(across);
    let tangent = d - cos1 * across;
    let sin1 = tangent.length();
    let sin2 = n1_over_n2 * sin1;
    if sin2 > 1.0 {
        return None;
    }
    let cos2 = (1.0 - sin2 * sin2).sqrt();
    let along = if sin1 > 0.0 {
        tangent / sin1
    } else {
        DVec3::ZERO
    };
    Some(cos2 * across + sin2 * along)
}

/// Sine of the angle between the unit vector `d` and the line of the unit normal `n`.
fn sin_to_normal(d: DVec3, n: DVec3) -> f64 {
    (d - d.dot(n) * n).length()
}

fn integrated(profile: IndexProfile) -> GradientIndex {
    GradientIndex { profile }
}

fn lens_with_ratio(law: LensLaw, index_ratio: f64) -> Lens {
    Lens {
        index_ratio,
        ..Lens::new(law)
    }
}

/// Signed angle of `v` in the plane of incidence, with axes d̂ and ê (Eq 11).
fn angle_in_plane(v: DVec3, d: DVec3, e: DVec3) -> f64 {
    v.dot(e).atan2(v.dot(d))
}

/// `a` reduced to (−π, π].
fn wrap(a: f64) -> f64 {
    let w = a.rem_euclid(TAU);
    if w > PI { w - TAU } else { w }
}

// ---------------------------------------------------------------------------------------------
// 1. Table 1.

#[test]
fn table_1_ggrin_parameters_give_luneburg_eaton_and_maxwell_fisheye() {
    let cases: [(&str, Ggrin, ClosedForm); 3] = [
        (
            "Luneburg (inf, R, 180 deg)",
            Ggrin {
                r: INF,
                r_prime: 1.0,
                phi: PI,
            },
            luneburg,
        ),
        (
            "Eaton (inf, inf, 0 deg)",
            Ggrin {
                r: INF,
                r_prime: INF,
                phi: 0.0,
            },
            eaton,
        ),
        (
            "Maxwell fisheye (R, R, 180 deg)",
            Ggrin {
                r: 1.0,
                r_prime: 1.0,
                phi: PI,
            },
            maxwell_fisheye,
        ),
    ];
    let mut rng = Rng(1);
    for (name, ggrin, closed) in cases {
        let mut point = Worst::new("exit point / R", 1e-9);
        let mut direction = Worst::new("exit direction", 1e-9);
        for _ in 0..3000 {
            let lens = random_lens(&mut rng);
            let (p, d) = random_entry(&mut rng, &lens);
            // The paper normalises d (d̂ = d/|d|); the length of d must not matter.
            let d = d * rng.range(0.5, 2.0);
            let g = ggrin.transmit(&lens, p, d);
            let c = closed(&lens, p, d);
            let case = || format!("{name}: lens {lens:?}, p {p}, d {d}: {g:?} vs {c:?}");
            point.see(g.point.distance(c.point) / lens.radius(), case);
            direction.see(g.direction.distance(c.direction), case);
        }
        point.check();
        direction.check();
    }
}

// ---------------------------------------------------------------------------------------------
// 2.–4. What the three lenses do.

#[test]
fn luneburg_focuses_a_parallel_bundle_onto_the_far_surface() {
    let mut rng = Rng(2);
    let law = integrated(IndexProfile::Luneburg);
    let mut errors = Exits::new("distance from C + R d / R", "direction vs C - P", 1e-12);
    for _ in 0..4 {
        let lens = random_lens(&mut rng);
        let d = rng.unit();
        let focus = lens.centre() + lens.radius() * d;
        for p in bundle(&mut rng, &lens, d, 60) {
            // Leaving the focus, each ray heads back along the line it came in on the far side
            // of the centre (Fig. 7(a)).
            let towards = (lens.centre() - p).normalize();
            let case = || format!("lens {lens:?}, p {p}, d {d}");
            let c = luneburg(&lens, p, d);
            see_exit(&mut errors.closed, &c, &lens, focus, towards, case);
            let i = law.transmit(&lens, p, d).expect("the ray leaves");
            see_exit(&mut errors.integrated, &i, &lens, focus, towards, case);
        }
    }
    errors.check();
}

#[test]
fn eaton_lens_retro_reflects() {
    let mut rng = Rng(3);
    let law = integrated(IndexProfile::Eaton);
    let mut errors = Exits::new("exit point vs mirrored entry / R", "direction vs -d", 1e-15);
    for k in 0..400 {
        let lens = random_lens(&mut rng);
        let (p, d) = random_entry(&mut rng, &lens);
        // P mirrored in the line through C along d: the trajectory is symmetric about its
        // closest approach to the centre.
        let x = p - lens.centre();
        let mirrored = lens.centre() + 2.0 * x.dot(d) * d - x;
        let case = || format!("lens {lens:?}, p {p}, d {d}");
        let c = eaton(&lens, p, d);
        see_exit(&mut errors.closed, &c, &lens, mirrored, -d, case);
        if k % 2 == 0 {
            let i = law.transmit(&lens, p, d).expect("the ray leaves");
            see_exit(&mut errors.integrated, &i, &lens, mirrored, -d, case);
        }
    }
    errors.check();
}

#[test]
fn maxwell_fisheye_lens_images_every_surface_point_onto_its_antipode() {
    let mut rng = Rng(4);
    let law = integrated(IndexProfile::MaxwellFisheye);
    let mut errors = Exits::new("distance from antipode / R", "direction vs Eq 10", 1e-12);
    for _ in 0..6 {
        let lens = random_lens(&mut rng);
        let u = rng.unit();
        let p = lens.centre() + lens.radius() * u;
        let antipode = lens.centre() - lens.radius() * u;
        // Rays from one point in all inward directions, from radial to near-grazing.
        for _ in 0..50 {
            let cos = rng.range(1e-3, 1.0);
            let d = (-cos * u + (1.0 - cos * cos).sqrt() * perpendicular(&mut rng, u)).normalize();
            // The ray leaves as it came in, mirrored in the plane through C perpendicular to
            // the diameter through P: the component along the diameter kept, the rest reversed.
            let expected = (2.0 * d.dot(-u) * (-u) - d).normalize();
            let case = || format!("lens {lens:?}, p {p}, d {d}");
            let c = maxwell_fisheye(&lens, p, d);
            see_exit(&mut errors.closed, &c, &lens, antipode, expected, case);
            let i = law.transmit(&lens, p, d).expect("the ray leaves");
            see_exit(&mut errors.integrated, &i, &lens, antipode, expected, case);
        }
    }
    errors.check();
}

// ---------------------------------------------------------------------------------------------
// 5.–6. The GGRIN construction.

fn random_ggrin(rng: &mut Rng) -> Ggrin {
    let distance = |rng: &mut Rng| {
        if rng.f() < 0.25 {
            INF
        } else if rng.f() < 0.1 {
            1.0
        } else {
            rng.range(1.0, 10.0)
        }
    };
    Ggrin {
        r: distance(rng),
        r_prime: distance(rng),
        phi: rng.range(-TAU, TAU),
    }
}

#[test]
fn ggrin_conserves_angular_momentum_and_turns_the_ray_by_phi_in_its_plane() {
    let mut rng = Rng(5);
    let mut momentum = Worst::new("| |(P'-C) x d'| - |(P-C) x d| | / R", 1e-12);
    let mut plane = Worst::new("out of the plane of incidence / R", 1e-12);
    let mut surface = Worst::new("| |P'-C| - R | / R", 1e-12);
    let mut inwards = Worst::new("-(P'-C).d' / R (exit ray heading inwards)", 1e-12);
    let mut angle = Worst::new("angle ACA' - phi (rad)", 1e-9);
    for _ in 0..5000 {
        let lens = random_lens(&mut rng);
        let g = random_ggrin(&mut rng);
        let (p, d) = random_entry(&mut rng, &lens);
        let (c, radius) = (lens.centre(), lens.radius());
        let out = g.transmit(&lens, p, d);
        let case = || format!("{g:?}, lens {lens:?}, p {p}, d {d}: {out:?}");
        let x = p - c;
        let x_out = out.point - c;
        let l_in = x.cross(d);
        momentum.see(
            (x_out.cross(out.direction).length() - l_in.length()).abs() / radius,
            case,
        );
        let m = l_in.normalize();
        plane.see(
            (x_out.dot(m) / radius)
                .abs()
                .max(out.direction.dot(m).abs()),
            case,
        );
        surface.see((x_out.length() - radius).abs() / radius, case);
        inwards.see(-x_out.dot(out.direction) / radius, case);
        assert!((out.direction.length() - 1.0).abs() < 1e-14, "{}", case());

        // The plane's axes as in Eq 11: d̂ and ê, with P on ê's positive side.
        let e = (x - x.dot(d) * d).normalize();
        // A: on the incident line before P at distance r from C (at infinity: back along d).
        let angle_a = if g.r.is_infinite() {
            PI
        } else {
            let s = x.dot(d) + ((g.r * radius).powi(2) - l_in.length_squared()).sqrt();
            angle_in_plane(x - s * d, d, e)
        };
        // A': on the outgoing line, past its closest approach, at distance r' from C.
        let angle_a_prime = if g.r_prime.is_infinite() {
            angle_in_plane(out.direction, d, e)
        } else {
            let along = x_out.dot(out.direction);
            let b2 = x_out.length_squared() - along * along;
            let s = -along + ((g.r_prime * radius).powi(2) - b2).max(0.0).sqrt();
            angle_in_plane(x_out + s * out.direction, d, e)
        };
        angle.see(wrap(angle_a_prime - angle_a - g.phi).abs(), case);
    }
    check_all([momentum, plane, surface, inwards, angle]);
}

#[test]
fn ggrin_with_infinite_distances_is_the_limit_of_large_ones() {
    let mut rng = Rng(6);
    let mut point = Worst::new("exit point, inf vs 1e9 / R", 1e-8);
    let mut direction = Worst::new("exit direction, inf vs 1e9", 1e-8);
    for k in 0..3000 {
        let lens = random_lens(&mut rng);
        let (p, d) = random_entry(&mut rng, &lens);
        let phi = rng.range(-PI, PI);
        let other = rng.range(1.0, 10.0);
        // r, r′ or both infinite.
        let (r, r_prime) = [(INF, other), (other, INF), (INF, INF)][k % 3];
        let large = |v: f64| if v.is_infinite() { 1e9 } else { v };
        let exact = Ggrin { r, r_prime, phi }.transmit(&lens, p, d);
        let near = Ggrin {
            r: large(r),
            r_prime: large(r_prime),
            phi,
        }
        .transmit(&lens, p, d);
        let case =
            || format!("r {r}, r' {r_prime}, phi {phi}, p {p}, d {d}: {exact:?} vs {near:?}");
        assert!(
            exact.point.is_finite() && exact.direction.is_finite(),
            "{}",
            case()
        );
        point.see(exact.point.distance(near.point) / lens.radius(), case);
        direction.see(exact.direction.distance(near.direction), case);
    }
    point.check();
    direction.check();
}

// ---------------------------------------------------------------------------------------------
// 7. The invisible core (§3.2).

#[test]
fn rays_through_the_invisible_core_cross_undeviated_and_the_others_follow_the_law() {
    let laws = [
        LensLaw::Luneburg,
        LensLaw::Eaton,
        LensLaw::MaxwellFisheye,
        LensLaw::Ggrin(Ggrin {
            r: INF,
            r_prime: INF,
            phi: FRAC_PI_2,
        }),
        LensLaw::GradientIndex(integrated(IndexProfile::Luneburg)),
    ];
    let mut rng = Rng(7);
    for law in laws {
        let lens_law = Lens {
            invisible_radius: 0.4,
            ..Lens::new(law.clone())
        };
        let mut core_point = Worst::new("core: exit vs straight line / R", 1e-12);
        let mut core_direction = Worst::new("core: direction vs d", 1e-15);
        let (mut inside, mut outside) = (0, 0);
        for k in 0..200 {
            let lens = random_lens(&mut rng);
            let d = rng.unit();
            let e = perpendicular(&mut rng, d);
            let b = if k % 2 == 0 {
                rng.range(0.0, 0.4 - 1e-6)
            } else {
                rng.range(0.4 + 1e-6, 0.999)
            };
            let p = entry_point(&lens, d, e, b);
            let case = || format!("{} b {b}, lens {lens:?}, p {p}, d {d}", law.name());
            let exit = lens_law
                .emerge(&lens, p, d)
                .unwrap_or_else(|| panic!("no emergence: {}", case()));
            if b < 0.4 {
                inside += 1;
                core_point.see(
                    exit.point.distance(straight_exit(&lens, d, e, b)) / lens.radius(),
                    case,
                );
                core_direction.see(exit.direction.distance(d), case);
            } else {
                outside += 1;
                let plain = law.transmit(&lens, p, d).unwrap();
                assert_eq!(exit, plain, "{}", case());
            }
        }
        assert!(inside > 50 && outside > 50);
        core_point.check();
        core_direction.check();
    }
}

// ---------------------------------------------------------------------------------------------
// 8. The index step at the surface (§3.3).

#[test]
fn matched_index_leaves_the_law_exactly_as_it_is() {
    let laws = [
        LensLaw::Luneburg,
        LensLaw::Eaton,
        LensLaw::MaxwellFisheye,
        LensLaw::Ggrin(Ggrin {
            r: 3.0,
            r_prime: INF,
            phi: 2.0,
        }),
        LensLaw::GradientIndex(integrated(IndexProfile::Eaton)),
        LensLaw::GradientIndex(integrated(IndexProfile::MaxwellFisheye)),
    ];
    let mut rng = Rng(8);
    for law in laws {
        let lens_law = lens_with_ratio(law.clone(), 1.0);
        for _ in 0..50 {
            let lens = random_lens(&mut rng);
            let (p, d) = random_entry(&mut rng, &lens);
            let e = lens_law.emerge(&lens, p, d).unwrap();
            assert_eq!(e, law.transmit(&lens, p, d).unwrap(), "{}", law.name());
        }
    }
}

/// The Luneburg lens behind an index step `k`, worked out here: Snell in, Eqs 5–6 on the
/// refracted ray, Snell out (or total internal reflection, `None`). Returns the exit point, the
/// emerging direction and the direction inside.
fn luneburg_behind_step(
    lens: &Sphere,
    p: DVec3,
    d: DVec3,
    k: f64,
) -> Option<(DVec3, DVec3, DVec3)> {
    let inside = snell(d, -normal(lens, p), 1.0 / k)?;
    let exit = lens.centre() + lens.radius() * inside; // Eq 5
    let across = (lens.centre() - p).normalize(); // Eq 6
    let out = snell(across, normal(lens, exit), k)?;
    Some((exit, out, inside))
}

#[test]
fn luneburg_behind_an_index_step_refracts_in_maps_and_refracts_out() {
    let k = 1.5;
    let closed = lens_with_ratio(LensLaw::Luneburg, k);
    let profile = lens_with_ratio(
        LensLaw::GradientIndex(integrated(IndexProfile::Luneburg)),
        k,
    );
    let mut rng = Rng(9);
    let mut own_point = Worst::new("closed vs own Snell + Eqs 5-6: exit point / R", 1e-12);
    let mut own_direction = Worst::new("closed vs own Snell + Eqs 5-6: direction", 1e-10);
    let mut snell_in = Worst::new("sin th1 - 1.5 sin th2 at entry", 1e-12);
    let mut snell_out = Worst::new("sin of emerging angle - sin th1", 1e-10);
    let mut profile_point = Worst::new("integrated vs closed: exit point / R", 1e-6);
    let mut profile_direction = Worst::new("integrated vs closed: direction", 1e-6);
    let mut profile_path = Worst::new("integrated path vs k R (pi/2 - x.t) / R", 1e-7);
    for i in 0..600 {
        let lens = random_lens(&mut rng);
        let (p, d) = random_entry(&mut rng, &lens);
        let case = || format!("lens {lens:?}, p {p}, d {d}");
        let (exit, out, inside) =
            luneburg_behind_step(&lens, p, d, k).expect("n_surface > n_outside: no TIR");
        let e = closed.emerge(&lens, p, d).unwrap();
        own_point.see(e.point.distance(exit) / lens.radius(), case);
        own_direction.see(e.direction.distance(out), case);
        // The exit point C + R t̂ shows the direction t̂ inside; Snell's law at P.
        let n_in = normal(&lens, p);
        let t = normal(&lens, e.point);
        let sin1 = sin_to_normal(d, n_in);
        snell_in.see((sin1 - k * sin_to_normal(t, n_in)).abs(), case);
        // By symmetry, the ray emerges at the angle at which it arrived.
        snell_out.see((sin_to_normal(e.direction, t) - sin1).abs(), case);
        assert!(e.direction.dot(t) > 0.0, "emerging outwards: {}", case());
        if i % 3 == 0 {
            let g = profile.emerge(&lens, p, d).unwrap();
            profile_point.see(g.point.distance(e.point) / lens.radius(), case);
            profile_direction.see(g.direction.distance(e.direction), case);
            // In n = k √(2 − ρ²) the ray (units of R) is x(τ) = x̂ cos τ + t̂ sin τ for
            // τ ∈ [0, π/2] (dτ = ds/n after scaling by k); ∫n ds = k ∫(2 − |x|²) dτ
            // = k R (π/2 − x̂·t̂).
            let expected = k * lens.radius() * (FRAC_PI_2 - n_in.dot(inside));
            profile_path.see((g.path - expected).abs() / lens.radius(), case);
        }
    }
    check_all([
        own_point,
        own_direction,
        snell_in,
        snell_out,
        profile_point,
        profile_direction,
        profile_path,
    ]);
}

#[test]
fn eaton_and_maxwell_fisheye_behind_an_index_step() {
    let mut rng = Rng(10);
    let cases = [
        (LensLaw::Eaton, "Eaton"),
        (
            LensLaw::GradientIndex(integrated(IndexProfile::Eaton)),
            "Eaton integrated",
        ),
        (LensLaw::MaxwellFisheye, "Maxwell"),
        (
            LensLaw::GradientIndex(integrated(IndexProfile::MaxwellFisheye)),
            "Maxwell integrated",
        ),
    ];
    for (law, name) in cases {
        let tolerance = if name.ends_with("integrated") {
            1e-6
        } else {
            1e-12
        };
        let mut point = Worst::new("exit point / R", tolerance);
        let mut direction = Worst::new("direction", tolerance);
        for _ in 0..100 {
            let lens = random_lens(&mut rng);
            let (p, d) = random_entry(&mut rng, &lens);
            let k = rng.range(1.1, 3.0);
            let e = lens_with_ratio(law.clone(), k).emerge(&lens, p, d).unwrap();
            let case = || format!("{name}, k {k}, lens {lens:?}, p {p}, d {d}");
            let x = p - lens.centre();
            if name.starts_with("Eaton") {
                // Inside, the refracted ray t is retro-reflected, leaving from P′, P mirrored in
                // the line M along t. Mirrored in M, the ray arriving at P along d becomes one
                // arriving at P′ along M(d) and refracted into M(t) = t; reversed, the ray
                // leaving P′ along −t emerges along −M(d) = d − 2(d·t)t, which is −d only for
                // d ∥ t: behind an index step the Eaton lens no longer retro-reflects.
                let t = snell(d, -normal(&lens, p), 1.0 / k).unwrap();
                let mirrored = lens.centre() + 2.0 * x.dot(t) * t - x;
                point.see(e.point.distance(mirrored) / lens.radius(), case);
                direction.see(e.direction.distance(d - 2.0 * d.dot(t) * t), case);
            } else {
                // Antipode, whatever the direction; inside, the tangential part is reversed (Eq 10),
                // so refracted out the emerging ray is d with its tangential part reversed.
                let u = x.normalize();
                point.see(e.point.distance(lens.centre() - x) / lens.radius(), case);
                let expected = 2.0 * d.dot(u) * u - d;
                direction.see(e.direction.distance(expected), case);
            }
        }
        point.check();
        direction.check();
    }
}

#[test]
fn surface_index_below_the_surroundings_reflects_steep_rays_off_on_entry() {
    let k = 0.8; // critical angle of incidence: asin 0.8 ≈ 53°
    let laws = [
        LensLaw::Luneburg,
        LensLaw::GradientIndex(integrated(IndexProfile::Luneburg)),
    ];
    let mut rng = Rng(11);
    for law in laws {
        let lens_law = lens_with_ratio(law, k);
        for i in 0..200 {
            let lens = random_lens(&mut rng);
            let u = rng.unit();
            let p = lens.centre() + lens.radius() * u;
            let sin = if i % 2 == 0 {
                rng.range(0.8 + 1e-9, 1.0)
            } else {
                rng.range(0.0, 0.8 - 1e-9)
            };
            let d = (-(1.0 - sin * sin).sqrt() * u + sin * perpendicular(&mut rng, u)).normalize();
            let e = lens_law.emerge(&lens, p, d).unwrap();
            let case = format!("sin th1 {sin}, lens {lens:?}, p {p}, d {d}: {e:?}");
            if sin > k {
                assert_eq!((e.point, e.path), (p, 0.0), "{case}");
                let reflected = d - 2.0 * d.dot(u) * u;
                assert!(e.direction.distance(reflected) < 1e-14, "{case}");
            } else {
                // Luneburg behind the step: exit at C + R t̂ where sin θ₁ = 0.8 sin θ₂.
                let t = normal(&lens, e.point);
                assert!((sin - k * sin_to_normal(t, u)).abs() < 1e-6, "{case}");
            }
        }
    }
}

/// Rays arriving at angles of incidence with the cosines `cosines`, behind index steps of 1.5
/// to 3.7, must leave at the angle at which they arrived.
///
/// Every law here conserves the angular momentum about C and the surface index is the same at
/// entry and exit, so the ray meets the surface from inside at the angle at which it was
/// refracted in, below the critical angle: total internal reflection on the way out is
/// impossible. Near grazing incidence, however, that angle is within rounding of the critical
/// angle, where rounding must not reflect or trap the ray.
fn assert_leave_as_they_arrived_near_grazing(cosines: &[f64], seed: u64) {
    let laws = [
        LensLaw::Luneburg,
        LensLaw::Eaton,
        LensLaw::MaxwellFisheye,
        LensLaw::Ggrin(Ggrin {
            r: 2.0,
            r_prime: 5.0,
            phi: 1.0,
        }),
        LensLaw::GradientIndex(integrated(IndexProfile::Luneburg)),
    ];
    let mut rng = Rng(seed);
    for law in laws {
        for i in 0..300 {
            let lens = random_lens(&mut rng);
            let k = [1.5, 2.0, 3.7][i % 3];
            let u = rng.unit();
            let p = lens.centre() + lens.radius() * u;
            let cos = cosines[i % cosines.len()];
            let d = (-cos * u + (1.0 - cos * cos).sqrt() * perpendicular(&mut rng, u)).normalize();
            let e = lens_with_ratio(law.clone(), k).emerge(&lens, p, d);
            let case = || {
                format!(
                    "{} k {k}, cos th1 {cos}, lens {lens:?}, p {p}, d {d}: {e:?}",
                    law.name()
                )
            };
            let e = e.unwrap_or_else(|| panic!("trapped: {}", case()));
            let n = normal(&lens, e.point);
            let sin_in = (1.0 - cos * cos).sqrt();
            // Outwards, or along the surface to rounding (of P − C, relative to R).
            let rounding = 1e-15 * (1.0 + lens.centre().length() / lens.radius());
            assert!(
                e.direction.dot(n) >= -rounding
                    && (sin_to_normal(e.direction, n) - sin_in).abs() < 1e-12,
                "{}",
                case()
            );
        }
    }
}

#[test]
fn near_grazing_rays_leave_as_they_arrived_behind_a_higher_surface_index() {
    assert_leave_as_they_arrived_near_grazing(&[1e-6, 1e-5, 1e-4, 1e-3], 12);
}

/// Within about 1e-7 rad of grazing incidence (cos θ₁ ≲ 1e-7), rounding in the closed forms and
/// the integration puts the ray inside just beyond the critical angle at the exit.
#[test]
fn grazing_rays_leave_as_they_arrived_behind_a_higher_surface_index() {
    assert_leave_as_they_arrived_near_grazing(&[1e-12, 1e-10, 1e-8, 1e-7], 16);
}

// ---------------------------------------------------------------------------------------------
// 9.–10. Integration: a tabulated profile, and the Eaton lens's singular centre.

#[test]
fn tabulated_luneburg_profile_focuses_a_parallel_bundle() {
    let points = 100;
    let rho: Vec<f64> = (0..points)
        .map(|i| i as f64 / (points - 1) as f64)
        .collect();
    let n: Vec<f64> = rho.iter().map(|r| (2.0 - r * r).sqrt()).collect();
    let law = integrated(IndexProfile::Table(TableProfile::new(rho, n).unwrap()));
    let mut rng = Rng(13);
    let mut point = Worst::new("distance from C + R d / R", 1e-5);
    let mut direction = Worst::new("direction vs C - P", 1e-5);
    for _ in 0..3 {
        let lens = random_lens(&mut rng);
        let d = rng.unit();
        let focus = lens.centre() + lens.radius() * d;
        for p in bundle(&mut rng, &lens, d, 30) {
            let case = || format!("lens {lens:?}, p {p}, d {d}");
            let exit = law.transmit(&lens, p, d).expect("the ray leaves");
            point.see(exit.point.distance(focus) / lens.radius(), case);
            direction.see(
                exit.direction.distance((lens.centre() - p).normalize()),
                case,
            );
        }
    }
    point.check();
    direction.check();
}

#[test]
fn eaton_profile_retro_reflects_rays_aimed_at_its_singular_centre() {
    let law = integrated(IndexProfile::Eaton);
    let mut rng = Rng(14);
    let mut point = Worst::new("exit point vs mirrored entry / R", 1e-6);
    let mut direction = Worst::new("direction vs -d", 1e-6);
    for &b in &[
        0.0, 1e-300, 1e-12, 1e-9, 1e-7, 5e-6, 9.9e-6, 1.01e-5, 2e-5, 1e-4, 1e-3,
    ] {
        for _ in 0..5 {
            let lens = random_lens(&mut rng);
            let d = rng.unit();
            let e = perpendicular(&mut rng, d);
            let p = entry_point(&lens, d, e, b);
            let x = p - lens.centre();
            let mirrored = lens.centre() + 2.0 * x.dot(d) * d - x;
            let exit = law.transmit(&lens, p, d).expect("the ray leaves");
            let case = || format!("b {b}, lens {lens:?}, p {p}, d {d}: {exit:?}");
            assert!(
                exit.point.is_finite() && exit.direction.is_finite() && exit.path.is_finite(),
                "{}",
                case()
            );
            point.see(exit.point.distance(mirrored) / lens.radius(), case);
            direction.see(exit.direction.distance(-d), case);
        }
    }
    point.check();
    direction.check();
}

// ---------------------------------------------------------------------------------------------
// The time of the crossing of integrated profiles.

/// Perfect imaging makes the optical path lengths between object and image equal:
/// * Luneburg: x(τ) = x̂ cos τ + d̂ sin τ, so ∫n ds = ∫(2 − |x|²) dτ = R(π/2 − x̂·d̂) for any
///   inward d (plus R(1 + x̂·d̂) from a wavefront through C − R d̂: R(1 + π/2) for the bundle);
/// * Maxwell fisheye: πR from P to its antipode, the diameter's ∫₋₁¹ 2/(1 + x²) dx;
/// * Eaton: the incoming and retro-reflected plane waves, R(π + 2) along the diameter, so
///   R(π − 2 x̂·d̂) inside.
#[test]
fn integrated_paths_are_the_equal_optical_paths_of_perfect_imaging() {
    let mut rng = Rng(15);
    let profiles = [
        IndexProfile::Luneburg,
        IndexProfile::MaxwellFisheye,
        IndexProfile::Eaton,
    ];
    for profile in profiles {
        let name = profile.name();
        let law = integrated(profile);
        let mut path = Worst::new("optical path / R", 1e-7);
        let mut scaled = Worst::new("path behind an index step: k x path / R", 1e-7);
        for i in 0..150 {
            let lens = random_lens(&mut rng);
            let (p, d) = random_entry(&mut rng, &lens);
            let x = normal(&lens, p);
            let expected = lens.radius()
                * match name {
                    "luneburg" => FRAC_PI_2 - x.dot(d),
                    "maxwell-fisheye" => PI,
                    _ => PI - 2.0 * x.dot(d),
                };
            let exit = law.transmit(&lens, p, d).unwrap();
            let case = || format!("{name}, lens {lens:?}, p {p}, d {d}: {exit:?}");
            path.see((exit.path - expected).abs() / lens.radius(), case);
            if i % 5 == 0 {
                // Scaling n by k keeps the rays and multiplies the optical path by k.
                let k = 1.7;
                let t = snell(d, -x, 1.0 / k).unwrap();
                let inside = lens.radius()
                    * match name {
                        "luneburg" => FRAC_PI_2 - x.dot(t),
                        "maxwell-fisheye" => PI,
                        _ => PI - 2.0 * x.dot(t),
                    };
                let e = lens_with_ratio(LensLaw::GradientIndex(law.clone()), k)
                    .emerge(&lens, p, d)
                    .unwrap();
                scaled.see((e.path - k * inside).abs() / lens.radius(), case);
            }
        }
        path.check();
        scaled.check();
    }
}
