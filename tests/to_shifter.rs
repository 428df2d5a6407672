//! Issue 41 item 3, the transformation-optics shifter (Dr TIM's `SurfaceOfTOShifter`), checked
//! against what transformation optics says of it, worked out from its parameters alone: the
//! shell between radii r₁ < R about c shows a point x of it at V(x) = x + f(|x − c|) δ (f = 0
//! on the outer sphere, 1 on the inner; inside, the shift δ), and light in it follows the curves
//! V maps onto straight lines. So:
//!
//! * space round the device is seen as it is: light crossing the device (its core empty) goes
//!   on along the line it came on;
//! * the core, and everything in it, is seen shifted by δ: light from a point P in it leaves the
//!   device on a line through P + δ;
//! * every point of the curved path inside the shell is mapped by V onto that line, and the
//!   path runs on without jumps from where the light enters to where it leaves;
//! * also where the map folds (|δ| beyond the shell's thickness, Dr TIM's abyss regime);
//! * the device's defaults (those of Dr TIM's `SphericalShiftyCloakVisualiser`) and refusals.

mod common;

use glam::{DQuat, DVec3};
use timbre::trajectories::{self, Arrival, End, Trajectory};

use common::cli::{location, path_str, timbre, write};
use common::rng::Rng;

fn trace(text: &str) -> Vec<Trajectory> {
    let description = common::images::parse(text);
    trajectories::trace(common::rays::device(), &description).expect("trace")
}

fn line_distance(p: DVec3, a: DVec3, d: DVec3) -> f64 {
    (p - a).reject_from_normalized(d.normalize()).length()
}

fn random_unit(rng: &mut Rng) -> DVec3 {
    DVec3::new(
        rng.range(-1.0, 1.0),
        rng.range(-1.0, 1.0),
        rng.range(-1.0, 1.0),
    )
    .normalize()
}

/// A shifter checked: its keys, transform (TOML) as rotation, uniform scale and translation,
/// and in its own coordinates centre, radii, δ and whether the shift is quadratic.
struct Case {
    keys: &'static str,
    transform: &'static str,
    rotation: DQuat,
    scale: f64,
    shift: DVec3,
    centre: DVec3,
    radius: f64,
    inner: f64,
    delta: DVec3,
    quadratic: bool,
}

impl Case {
    fn place(&self, x: DVec3) -> DVec3 {
        self.rotation * (self.scale * x) + self.shift
    }

    /// V(x) for a point of the placed shell, in placed coordinates.
    fn seen(&self, x: DVec3) -> DVec3 {
        let centre = self.place(self.centre);
        let (big_r, r1) = (self.scale * self.radius, self.scale * self.inner);
        let r = (x - centre).length();
        let f = if self.quadratic {
            (big_r * big_r - r * r) / (big_r * big_r - r1 * r1)
        } else {
            (big_r - r) / (big_r - r1)
        };
        x + f * (self.rotation * (self.scale * self.delta))
    }

    fn scene(&self, rays: &[(DVec3, DVec3)]) -> String {
        let mut text = format!(
            "studio = \"none\"\n[[device]]\nname = \"s\"\n{}lenses = {{ type = \"to-shifter\", {} }}\n",
            self.transform, self.keys
        );
        for (s, d) in rays {
            text += &format!(
                "[[ray_trajectory]]\nstart = [{}, {}, {}]\ndirection = [{}, {}, {}]\nmax_interactions = 100\n",
                s.x, s.y, s.z, d.x, d.y, d.z
            );
        }
        text
    }
}

fn plain(
    keys: &'static str,
    centre: DVec3,
    radius: f64,
    inner: f64,
    delta: DVec3,
    quadratic: bool,
) -> Case {
    Case {
        keys,
        transform: "",
        rotation: DQuat::IDENTITY,
        scale: 1.0,
        shift: DVec3::ZERO,
        centre,
        radius,
        inner,
        delta,
        quadratic,
    }
}

/// Shifters whose map V does not fold (|δ| well below the shell's thickness).
fn unfolded() -> Vec<Case> {
    vec![
        plain(
            "delta = [0, 0.2, 0]",
            DVec3::ZERO,
            1.0,
            0.5,
            DVec3::new(0.0, 0.2, 0.0),
            true,
        ),
        plain(
            "shift_function_type = \"linear\", centre = [0.3, -0.2, 1], radius = 2, \
             inner_radius = 0.7, delta = [0.3, -0.4, 0.2]",
            DVec3::new(0.3, -0.2, 1.0),
            2.0,
            0.7,
            DVec3::new(0.3, -0.4, 0.2),
            false,
        ),
        Case {
            transform: "transform = { scale = 1.5, rotate = { axis = [1, 1, 0], angle_deg = 35 }, translate = [0.5, 0, -1] }\n",
            rotation: DQuat::from_axis_angle(
                DVec3::new(1.0, 1.0, 0.0).normalize(),
                35f64.to_radians(),
            ),
            scale: 1.5,
            shift: DVec3::new(0.5, 0.0, -1.0),
            ..plain(
                "delta = [0.1, 0.05, -0.15]",
                DVec3::ZERO,
                1.0,
                0.5,
                DVec3::new(0.1, 0.05, -0.15),
                true,
            )
        },
    ]
}

/// Dr TIM's default (quadratic, δ = (0, 1, 0), twice the thickness) and a folded linear one.
fn folded() -> Vec<Case> {
    vec![
        plain("", DVec3::ZERO, 1.0, 0.5, DVec3::Y, true),
        plain(
            "shift_function_type = \"linear\", delta = [0.8, 0, 0.3]",
            DVec3::ZERO,
            1.0,
            0.5,
            DVec3::new(0.8, 0.0, 0.3),
            false,
        ),
    ]
}

/// The curved points of `t` map onto straight lines of electromagnetic space: each run of them
/// (one passage through the shell) onto the line the light arrived on, seen from outside from
/// where it entered, and they follow one another without jumps.
fn check_curved_path(case: &Case, t: &Trajectory, label: &str) {
    let step = 0.1 * case.scale * case.radius;
    let points = &t.points;
    let mut line: Option<(DVec3, DVec3)> = None;
    for i in 2..points.len() {
        if points[i].arrival != Arrival::Curved {
            line = None;
            continue;
        }
        let (a, b) = (points[i - 1].position, points[i].position);
        let (base, direction) = *line.get_or_insert_with(|| {
            let arrived = (a - points[i - 2].position).normalize();
            (case.seen(a), arrived)
        });
        let off = line_distance(case.seen(b), base, direction);
        assert!(off < 1e-9, "{label}: {b} is seen {off} off its line");
        assert!(
            (b - a).length() < step,
            "{label}: the path jumps from {a} to {b}"
        );
    }
}

#[test]
fn space_round_the_shifter_is_seen_as_it_is() {
    let mut rng = Rng(3);
    for case in unfolded().into_iter().chain(folded()) {
        let mut rays = Vec::new();
        for _ in 0..40 {
            let start = case.place(case.centre + 3.0 * case.radius * random_unit(&mut rng));
            let target = case.place(case.centre + 0.9 * case.radius * random_unit(&mut rng));
            rays.push((start, target - start));
        }
        let mut crossed = 0;
        for (k, (t, &(start, direction))) in trace(&case.scene(&rays)).iter().zip(&rays).enumerate()
        {
            let label = format!("{} ray {k}", case.keys);
            if t.end != End::Escaped {
                // Light can circle through the core of a folded shifter for ever.
                assert!(
                    case.delta.length() > 0.5 * (case.radius - case.inner),
                    "{label}: {:?}",
                    t.end
                );
                continue;
            }
            crossed += 1;
            let last = t.points.last().unwrap().position;
            assert!(
                (t.direction - direction.normalize()).length() < 1e-9,
                "{label}: leaves along {}, came along {}",
                t.direction,
                direction.normalize()
            );
            let off = line_distance(last, start, direction);
            assert!(off < 1e-9, "{label}: {off} off its line");
            check_curved_path(&case, t, &label);
        }
        assert!(crossed >= 30, "{}: only {crossed} rays crossed", case.keys);
    }
}

#[test]
fn the_core_is_seen_shifted_by_delta() {
    let mut rng = Rng(11);
    for case in unfolded().into_iter().chain(folded()) {
        let mut rays = Vec::new();
        for _ in 0..30 {
            let p = case.centre + 0.9 * case.inner * rng.range(0.0, 1.0) * random_unit(&mut rng);
            rays.push((p, random_unit(&mut rng)));
        }
        let placed: Vec<_> = rays
            .iter()
            .map(|&(p, d)| (case.place(p), case.rotation * d))
            .collect();
        let mut escaped = 0;
        for (k, (t, &(p, _))) in trace(&case.scene(&placed)).iter().zip(&rays).enumerate() {
            let label = format!("{} ray {k}", case.keys);
            if t.end != End::Escaped {
                assert!(
                    case.delta.length() > 0.5 * (case.radius - case.inner),
                    "{label}: {:?}",
                    t.end
                );
                continue;
            }
            escaped += 1;
            let last = t.points.last().unwrap().position;
            let image = case.place(p + case.delta);
            let off = line_distance(image, last, t.direction);
            assert!(
                off < 1e-9,
                "{label}: the ray from {p} leaves {off} off {image}"
            );
            check_curved_path(&case, t, &label);
        }
        assert!(escaped >= 10, "{}: only {escaped} rays escaped", case.keys);
    }
}

/// Named by its type alone: the outer device of Dr TIM's `SphericalShiftyCloakVisualiser`,
/// spheres of radii 1 and 0.5 about the origin; a ray along the y axis from below passes the
/// core shifted by δ = (0, 1, 0) and leaves on its line.
#[test]
fn a_to_shifter_named_by_its_type_alone_is_dr_tims_program_default() {
    let d = common::images::parse(
        "studio = \"none\"\n[[device]]\nname = \"s\"\nlenses = { type = \"to-shifter\" }\n",
    );
    let names: Vec<&str> = d.objects.iter().map(|o| o.name.as_str()).collect();
    assert_eq!(names, ["s/outer sphere", "s/inner sphere"]);
    for (o, radius) in d.objects.iter().zip([1.0, 0.5]) {
        let (lo, hi) = o.shape.bounds().unwrap();
        assert!(((lo + hi) / 2.0).length() < 1e-12 && ((hi - lo).x - 2.0 * radius).abs() < 1e-12);
        let timbre::surfaces::Surface::ToShifter(s) = &o.surface else {
            panic!("{} is no shifter", o.name)
        };
        assert_eq!(s.delta, DVec3::Y);
        assert_eq!(s.shift_function, timbre::surfaces::ShiftFunction::Quadratic);
        assert_eq!(s.transmission_coefficient, 0.96);
        assert!(!o.shadow_throwing);
    }
    // A ray along x at height 0.6: seen from outside, the core is the sphere of radius 0.5
    // about (0, 1, 0), which the line y = 0.6 crosses where (x, 0.6 − 1) is 0.5 from it: the
    // light crosses the core on the line y = −0.4, from x = −0.3 to 0.3.
    let t = &trace(
        "studio = \"none\"\n[[device]]\nlenses = { type = \"to-shifter\" }\n\
         [[ray_trajectory]]\nstart = [-5, 0.6, 0]\ndirection = [1, 0, 0]\n",
    )[0];
    let core: Vec<DVec3> = t
        .points
        .iter()
        .map(|p| p.position)
        .filter(|p| p.length() < 0.5 + 1e-9)
        .collect();
    assert!(
        core.iter()
            .any(|p| (*p - DVec3::new(-0.3, -0.4, 0.0)).length() < 1e-9),
        "{core:?}"
    );
    assert!(
        core.iter()
            .any(|p| (*p - DVec3::new(0.3, -0.4, 0.0)).length() < 1e-9),
        "{core:?}"
    );
}

#[test]
fn bad_to_shifters_are_refused_where_they_are_given() {
    let dir = tempfile::tempdir().unwrap();
    for (keys, needles) in [
        (
            "lenses = { type = \"to-shifter\", inner_radius = 1 }",
            &["inner_radius = 1", "radius"][..],
        ),
        (
            "lenses = { type = \"to-shifter\", radius = 0.4 }",
            &["inner_radius = 0.5", "radius = 0.4"][..],
        ),
        (
            "lenses = { type = \"to-shifter\", shift_function_type = \"cubic\" }",
            &["cubic", "linear", "quadratic"][..],
        ),
        (
            "lenses = { type = \"to-shifter\", delta = [0, inf, 0] }",
            &["finite"][..],
        ),
        (
            "lenses = { type = \"to-shifter\", delta = [0, 1e7, 0] }",
            &["more than 1e6 times radius"][..],
        ),
        (
            "show_edges = true\nlenses = { type = \"to-shifter\" }",
            &["no edges"][..],
        ),
        (
            "transform = { scale = [1, 2, 1] }\nlenses = { type = \"to-shifter\" }",
            &["not stretched"][..],
        ),
    ] {
        let text = format!("studio = \"none\"\n\n[[device]]\nname = \"c\"\n{keys}\n");
        let path = write(dir.path(), "bad.toml", text);
        let run = timbre(dir.path(), &["check", path_str(&path)]);
        run.assert_bad_input(needles);
        assert!(location(&run.stderr, &path).0 >= 3, "{}", run.stderr);
    }
}

/// Light that grazes the core seen from outside (its line nearly tangent to the inner sphere's
/// image), and light along δ through the centre (where the conic is a pair of lines), still
/// goes on along its line, and its path has no undefined points.
#[test]
fn grazing_light_and_light_along_delta_go_on_along_their_lines() {
    let mut rays = Vec::new();
    // The core, of radius 0.5, is seen about (0, 0.3, 0): the line y = 0.8 touches it.
    for h in [1e-12, 1e-10, 1e-8, 1e-6, 1e-4, 1e-2] {
        rays.push((
            "delta = [0, 0.3, 0]",
            DVec3::new(-5.0, 0.8 - h, 0.0),
            DVec3::X,
        ));
    }
    for keys in [
        "shift_function_type = \"linear\", delta = [0, 0, 0.2]",
        "shift_function_type = \"linear\", delta = [0, 0, 0]",
        "delta = [0, 0, -0.2]",
    ] {
        rays.push((keys, DVec3::new(0.0, 0.0, -5.0), DVec3::Z));
        rays.push((keys, DVec3::new(1e-9, 0.0, -5.0), DVec3::Z));
    }
    for (keys, start, direction) in rays {
        let text = format!(
            "studio = \"none\"\n[[device]]\nlenses = {{ type = \"to-shifter\", {keys} }}\n\
             [[ray_trajectory]]\nstart = [{}, {}, {}]\ndirection = [{}, {}, {}]\n",
            start.x, start.y, start.z, direction.x, direction.y, direction.z
        );
        let t = &trace(&text)[0];
        let label = format!("{keys}, from {start}");
        assert_eq!(t.end, End::Escaped, "{label}");
        assert!(
            t.points.iter().all(|p| p.position.is_finite()),
            "{label}: {:?}",
            t.points
        );
        let last = t.points.last().unwrap().position;
        assert!((t.direction - direction).length() < 1e-9, "{label}");
        assert!(line_distance(last, start, direction) < 1e-9, "{label}");
    }
}
