//! Issue 41 item 2, Dr TIM's box cloaks of glenses, the cubic one (`EditableBoxCloak`,
//! `CubicBoxCloakMaker`) and the extended Rochester cloak (`EditableRochesterCloak`,
//! `RochesterCloakMaker`), checked against what a cloak must do, worked out from its
//! parameters alone:
//!
//! * seen from outside, space outside the cloak is as it is: a ray that enters and leaves the
//!   cloak goes on along the line it came on;
//! * the inner cube of side p L, and everything in it, is seen as a cube of side e L about the
//!   same centre c: a ray leaving a point P inside it leaves the cloak on a line through
//!   c + (e/p)(P − c);
//! * Dr TIM's defaults, part names and refusals, and its outer front glens, which images the
//!   inner cube's corners onto their images (Dr TIM's conjugate pairs) by the glens equation;
//! * the Rochester cloak likewise lets every ray through on its line (including those through
//!   its middle, where Dr TIM's own construction does not: see `docs/SCENE_FORMAT.md`), and
//!   shows its inner volume as its four lenses image it, by the thin-lens equation with Dr
//!   TIM's focal lengths.

mod common;

use glam::{DQuat, DVec3};
use timbre::surfaces::{Focus, Surface};
use timbre::trajectories::{self, End, Trajectory};

use common::cli::{location, path_str, timbre, write};
use common::rng::Rng;

fn trace(text: &str) -> Vec<Trajectory> {
    let description = common::images::parse(text);
    trajectories::trace(common::rays::device(), &description).expect("trace")
}

/// Distance of `p` from the line through `a` along `d`.
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

fn ray(start: DVec3, direction: DVec3) -> String {
    format!(
        "[[ray_trajectory]]\nstart = [{}, {}, {}]\ndirection = [{}, {}, {}]\nmax_interactions = 1000\n",
        start.x, start.y, start.z, direction.x, direction.y, direction.z
    )
}

/// A cloak checked: its `lenses` keys, the device's transform (TOML, or empty) as a rotation,
/// uniform scale and translation, and its centre, side length L, e and p in its own
/// coordinates.
struct Case {
    keys: &'static str,
    transform: &'static str,
    rotation: DQuat,
    scale: f64,
    shift: DVec3,
    centre: DVec3,
    side: f64,
    e: f64,
    p: f64,
}

fn cases() -> Vec<Case> {
    let plain = |keys, centre, side, e, p| Case {
        keys,
        transform: "",
        rotation: DQuat::IDENTITY,
        scale: 1.0,
        shift: DVec3::ZERO,
        centre,
        side,
        e,
        p,
    };
    vec![
        // Dr TIM's defaults, moved to the origin.
        plain("centre = [0, 0, 0]", DVec3::ZERO, 2.0, 0.4, 0.8),
        // Skew, the inner cube seen larger and flipped.
        plain(
            "centre = [0.2, -0.1, 0.3], front_direction = [1, 0, 1], right_direction = [0, 1, 0.2], \
             top_direction = [-1, 0, 1], side_length = 1.5, inner_volume_size_factor_em = -0.7, \
             inner_volume_size_factor_p = 0.5",
            DVec3::new(0.2, -0.1, 0.3),
            1.5,
            -0.7,
            0.5,
        ),
        // The inner cube seen larger than it is.
        plain(
            "centre = [0, 0, 0], inner_volume_size_factor_em = 0.9, inner_volume_size_factor_p = 0.3",
            DVec3::ZERO,
            2.0,
            0.9,
            0.3,
        ),
        // The octahedral cloak (Dr TIM's OctahedralBoxCloakMaker): the inner octahedron of
        // vertices p L/2 from the centre seen scaled by e/p; Dr TIM's defaults, and skew.
        plain(
            "cloak_type = \"octahedral\", centre = [0, 0, 0]",
            DVec3::ZERO,
            2.0,
            0.4,
            0.8,
        ),
        plain(
            "cloak_type = \"octahedral\", centre = [0.1, 0, 0.2], front_direction = [1, 1, 0], \
             right_direction = [0, 0, 1], top_direction = [1, -1, 0], side_length = 2.5, \
             inner_volume_size_factor_em = 0.25, inner_volume_size_factor_p = 0.6",
            DVec3::new(0.1, 0.0, 0.2),
            2.5,
            0.25,
            0.6,
        ),
        // The octahedral cloak rotated, scaled and moved.
        Case {
            keys: "cloak_type = \"octahedral\", centre = [0, 0, 0]",
            transform: "transform = { scale = 0.7, rotate = { axis = [1, 0, 1], angle_deg = 40 }, translate = [0, 1, 0] }\n",
            rotation: DQuat::from_axis_angle(
                DVec3::new(1.0, 0.0, 1.0).normalize(),
                40f64.to_radians(),
            ),
            scale: 0.7,
            shift: DVec3::new(0.0, 1.0, 0.0),
            centre: DVec3::ZERO,
            side: 2.0,
            e: 0.4,
            p: 0.8,
        },
        // Rotated by 30° about (1, 1, 0), scaled by 1.5 and moved.
        Case {
            keys: "centre = [0, 0, 0]",
            transform: "transform = { scale = 1.5, rotate = { axis = [1, 1, 0], angle_deg = 30 }, translate = [0.5, 0, -1] }\n",
            rotation: DQuat::from_axis_angle(
                DVec3::new(1.0, 1.0, 0.0).normalize(),
                30f64.to_radians(),
            ),
            scale: 1.5,
            shift: DVec3::new(0.5, 0.0, -1.0),
            centre: DVec3::ZERO,
            side: 2.0,
            e: 0.4,
            p: 0.8,
        },
    ]
}

impl Case {
    fn scene(&self, rays: &str) -> String {
        format!(
            "studio = \"none\"\n[[device]]\nname = \"cloak\"\n{}lenses = {{ type = \"box-cloak\", {} }}\n{rays}",
            self.transform, self.keys
        )
    }

    fn place(&self, x: DVec3) -> DVec3 {
        self.rotation * (self.scale * x) + self.shift
    }
}

#[test]
fn space_outside_the_box_cloak_is_seen_as_it_is() {
    let mut rng = Rng(42);
    for case in cases() {
        let mut rays = Vec::new();
        for _ in 0..40 {
            let start = case.place(case.centre + 3.0 * case.side * random_unit(&mut rng));
            let target = case.place(case.centre + 0.4 * case.side * random_unit(&mut rng));
            rays.push((start, target - start));
        }
        let text = case.scene(&rays.iter().map(|&(s, d)| ray(s, d)).collect::<String>());
        let mut crossed = 0;
        for (t, &(start, direction)) in trace(&text).iter().zip(&rays) {
            assert_eq!(t.end, End::Escaped, "{}: {:?}", case.keys, t.points);
            // Into the cloak, through at least one inner face and out.
            if t.points.len() < 4 {
                continue;
            }
            crossed += 1;
            let last = t.points.last().unwrap().position;
            assert!(
                (t.direction - direction.normalize()).length() < 1e-9,
                "{}: leaves along {}, came along {}",
                case.keys,
                t.direction,
                direction.normalize()
            );
            let off = line_distance(last, start, direction);
            assert!(off < 1e-9, "{}: {off} off its line", case.keys);
        }
        assert!(crossed >= 30, "{}: only {crossed} rays crossed", case.keys);
    }
}

/// The inner cube (or octahedron) is seen scaled by e/p about the centre.
#[test]
fn the_inner_cube_is_seen_scaled_by_e_over_p() {
    let mut rng = Rng(8);
    for case in cases() {
        let mut rays = Vec::new();
        for _ in 0..20 {
            // Inside the inner cube: within a third of its half side of the centre (the
            // octahedron's inscribed sphere, of radius p L/(2√3), holds these points too).
            let p = case.centre
                + case.p * case.side / 6.0 * rng.range(0.0, 1.0) * random_unit(&mut rng);
            rays.push((p, random_unit(&mut rng)));
        }
        let placed: Vec<_> = rays
            .iter()
            .map(|&(p, d)| (case.place(p), case.rotation * d))
            .collect();
        let text = case.scene(&placed.iter().map(|&(s, d)| ray(s, d)).collect::<String>());
        for (t, &(p, _)) in trace(&text).iter().zip(&rays) {
            assert_eq!(t.end, End::Escaped, "{}: {:?}", case.keys, t.points);
            let last = t.points.last().unwrap().position;
            let image = case.place(case.centre + case.e / case.p * (p - case.centre));
            let off = line_distance(image, last, t.direction);
            assert!(
                off < 1e-9,
                "{}: the ray from {p} leaves {off} off {image}",
                case.keys
            );
        }
    }
}

/// `EditableBoxCloak(parent, studio)`: centre (0, 0, 10), front (0, 0, −1), right (1, 0, 0),
/// top (0, 1, 0), side length 2, e = 0.4, p = 0.8, transmission coefficient 0.96, frames hidden,
/// radius 0.01 × 2, `RED_SHINY`; 6 outer, 6 inner and 12 diagonal glenses, 16 vertices and
/// 12 + 12 + 8 edges.
#[test]
fn a_box_cloak_named_by_its_type_alone_is_dr_tims_default_cloak() {
    let d = common::images::parse(
        "studio = \"none\"\n[[device]]\nname = \"d\"\nlenses = { type = \"box-cloak\" }\n",
    );
    assert_eq!(d.objects.len(), 24, "frames hidden");
    for o in &d.objects {
        let Surface::Glens(g) = &o.surface else {
            panic!("{} is no glens", o.name)
        };
        assert_eq!(g.transmission_coefficient, 0.96, "{}", o.name);
        assert!(!o.shadow_throwing, "{}", o.name);
    }
    // Dr TIM's outer front glens, in the plane z = 9 with its axis along front = −z, images
    // the inner cube's corner at z = 9.2 (axial coordinate a = −0.2) to the apparent one at
    // z = 9.6 (a′ = −0.6) on the line through the centre: with N at a = −1 = f₋ + f₊, the
    // glens equation f₊/a′ + f₋/a = 1 gives f₋ = 0.2, f₊ = −1.2.
    let front = d
        .objects
        .iter()
        .find(|o| o.name == "d/outer face in front direction")
        .expect("outer front glens");
    let Surface::Glens(g) = &front.surface else {
        unreachable!()
    };
    assert!((g.optical_axis - DVec3::NEG_Z).length() < 1e-12);
    let nodal = g.nodal_point().expect("finite");
    assert!(
        (nodal - DVec3::new(0.0, 0.0, 10.0)).length() < 1e-12,
        "{nodal}"
    );
    let Focus::Finite {
        focal_length_negative,
        focal_length_positive,
        ..
    } = g.focus
    else {
        unreachable!()
    };
    assert!((focal_length_negative - 0.2).abs() < 1e-12);
    assert!((focal_length_positive + 1.2).abs() < 1e-12);
    let names: Vec<&str> = d.objects.iter().map(|o| o.name.as_str()).collect();
    for name in [
        "d/inner face in back direction",
        "d/diagonal face between the top and front faces",
    ] {
        assert!(names.contains(&name), "{name} in {names:?}");
    }

    let framed = common::images::parse(
        "studio = \"none\"\n[[device]]\nname = \"d\"\nshow_edges = true\n\
         lenses = { type = \"box-cloak\", side_length = 3 }\n",
    );
    assert_eq!(framed.objects.len(), 24 + 16 + 32);
    let vertex = framed
        .objects
        .iter()
        .find(|o| o.name == "d/outer vertex top right front")
        .expect("outer vertex");
    let (lo, hi) = vertex.shape.bounds().unwrap();
    assert!(((lo + hi) / 2.0 - DVec3::new(1.5, 1.5, 8.5)).length() < 1e-12);
    assert!(((hi - lo).x - 0.06).abs() < 1e-12, "radius 0.01 × 3");
    let Surface::Coloured(c) = &vertex.surface else {
        panic!("frames are coloured")
    };
    assert_eq!(c.diffuse, timbre::math::Colour::new(1.0, 0.0, 0.0));
}

#[test]
fn bad_box_cloaks_are_refused_where_they_are_given() {
    let dir = tempfile::tempdir().unwrap();
    for (keys, needles) in [
        (
            "inner_volume_size_factor_p = 1",
            &["inner_volume_size_factor_p = 1", "between 0.001 and 0.999"][..],
        ),
        (
            "inner_volume_size_factor_p = -0.5",
            &["inner_volume_size_factor_p", "between 0.001 and 0.999"][..],
        ),
        (
            "inner_volume_size_factor_em = 1",
            &["inner_volume_size_factor_em = 1", "outer cube's faces"][..],
        ),
        (
            "inner_volume_size_factor_em = 0",
            &["inner_volume_size_factor_em = 0", "point"][..],
        ),
        (
            "right_direction = [0, 0, 2]",
            &["right_direction must not be along front_direction"][..],
        ),
        (
            "top_direction = [0, 0, 1]",
            &["top_direction must not be perpendicular"][..],
        ),
        (
            "cloak_type = \"prismatic\", inner_volume_size_factor_em = 2.00001",
            &["inner_volume_size_factor_em = 2.00001", "within 1e-4 of 2"][..],
        ),
        (
            "cloak_type = \"octahedral\", inner_volume_size_factor_em = 2",
            &["inner_volume_size_factor_em = 2", "flattens"][..],
        ),
        (
            "side_length = 0.001",
            &["side_length = 0.001 is too small", "from the origin"][..],
        ),
        ("cloak_type = \"round\"", &["round", "cubic"][..]),
        ("side_length = 0", &["positive number"][..]),
        ("inner_volume_size_factor_em = nan", &["finite number"][..]),
        ("show_frames = true", &["show_frames"][..]),
    ] {
        let text = format!(
            "studio = \"none\"\n\n[[device]]\nname = \"c\"\nlenses = {{ type = \"box-cloak\", {keys} }}\n"
        );
        let path = write(dir.path(), "bad.toml", text);
        let run = timbre(dir.path(), &["check", path_str(&path)]);
        run.assert_bad_input(needles);
        assert_eq!(location(&run.stderr, &path).0, 5, "{}", run.stderr);
    }
}

/// A Rochester cloak checked: its `lenses` table, transform, and in its own coordinates its
/// centre, unit front direction, half side h and e, p.
struct Rochester {
    lenses: &'static str,
    transform: &'static str,
    rotation: DQuat,
    scale: f64,
    shift: DVec3,
    centre: DVec3,
    front: DVec3,
    h: f64,
    e: f64,
    p: f64,
}

fn rochester_cases() -> Vec<Rochester> {
    vec![
        // Dr TIM's defaults (M = −2), moved to the origin.
        Rochester {
            lenses: "type = \"rochester-cloak\", centre = [0, 0, 0]",
            transform: "",
            rotation: DQuat::IDENTITY,
            scale: 1.0,
            shift: DVec3::ZERO,
            centre: DVec3::ZERO,
            front: DVec3::NEG_Z,
            h: 1.0,
            e: -1.6,
            p: 0.8,
        },
        // A box cloak of Rochester type, skew, M = −3.
        Rochester {
            lenses: "type = \"box-cloak\", cloak_type = \"rochester\", centre = [0.1, 0.2, -0.1], \
                     front_direction = [1, 0, 1], right_direction = [1, 0, -1], \
                     top_direction = [0, 1, 0], side_length = 1.5, \
                     inner_volume_size_factor_em = -1.5, inner_volume_size_factor_p = 0.5",
            transform: "",
            rotation: DQuat::IDENTITY,
            scale: 1.0,
            shift: DVec3::ZERO,
            centre: DVec3::new(0.1, 0.2, -0.1),
            front: DVec3::new(1.0, 0.0, 1.0).normalize(),
            h: 0.75,
            e: -1.5,
            p: 0.5,
        },
        // Rotated, scaled and moved.
        Rochester {
            lenses: "type = \"rochester-cloak\", centre = [0, 0, 0], inner_volume_size_factor_em = -1.2, inner_volume_size_factor_p = 0.6",
            transform: "transform = { scale = 0.5, rotate = { axis = [0, 1, 1], angle_deg = 50 }, translate = [1, 0, 2] }\n",
            rotation: DQuat::from_axis_angle(
                DVec3::new(0.0, 1.0, 1.0).normalize(),
                50f64.to_radians(),
            ),
            scale: 0.5,
            shift: DVec3::new(1.0, 0.0, 2.0),
            centre: DVec3::ZERO,
            front: DVec3::NEG_Z,
            h: 1.0,
            e: -1.2,
            p: 0.6,
        },
    ]
}

impl Rochester {
    fn scene(&self, rays: &str) -> String {
        format!(
            "studio = \"none\"\n[[device]]\nname = \"cloak\"\n{}lenses = {{ {} }}\n{rays}",
            self.transform, self.lenses
        )
    }

    fn place(&self, x: DVec3) -> DVec3 {
        self.rotation * (self.scale * x) + self.shift
    }

    /// Where a point x of the inner volume is seen from the front: imaged by the inner lens
    /// (focal length f₂, a distance d = h − f₁ − f₂ in front of the centre) and then the outer
    /// one (f₁, on the front face), each by the thin-lens equation 1/a′ − 1/a = 1/f with
    /// transverse magnification a′/a, Dr TIM's f₁ = L (M + 1)/(2 (M − 1)) and
    /// f₂ = −L (M + 1)/(2 M (M − 1)), M = e/p.
    fn seen(&self, x: DVec3) -> DVec3 {
        let (l, m) = (2.0 * self.h, self.e / self.p);
        let (f1, f2) = (
            l * (m + 1.0) / (2.0 * (m - 1.0)),
            -l * (m + 1.0) / (2.0 * m * (m - 1.0)),
        );
        let lens = |x: DVec3, at: f64, f: f64| {
            let z = (x - self.centre).dot(self.front);
            let across = (x - self.centre) - z * self.front;
            let a = z - at;
            let a_image = 1.0 / (1.0 / f + 1.0 / a);
            self.centre + (at + a_image) * self.front + across * (a_image / a)
        };
        lens(lens(x, self.h - f1 - f2, f2), self.h, f1)
    }
}

#[test]
fn space_outside_the_rochester_cloak_is_seen_as_it_is() {
    let mut rng = Rng(43);
    for case in rochester_cases() {
        let mut rays = Vec::new();
        for _ in 0..60 {
            let start = case.place(case.centre + 6.0 * case.h * random_unit(&mut rng));
            let target = case.place(case.centre + 0.8 * case.h * random_unit(&mut rng));
            rays.push((start, target - start));
        }
        let text = case.scene(&rays.iter().map(|&(s, d)| ray(s, d)).collect::<String>());
        let description = common::images::parse(&text);
        let traced = trajectories::trace(common::rays::device(), &description).expect("trace");
        let mut middle = 0;
        for (t, &(start, direction)) in traced.iter().zip(&rays) {
            assert_eq!(t.end, End::Escaped, "{}: {:?}", case.lenses, t.points);
            assert!(
                t.points.len() >= 3,
                "{}: a ray missed the cloak",
                case.lenses
            );
            if t.points.iter().any(|p| {
                p.object.is_some_and(|o| {
                    let name = &description.objects[o].name;
                    name.ends_with("inner glens") || name.contains("centre diagonal")
                })
            }) {
                middle += 1;
            }
            let last = t.points.last().unwrap().position;
            assert!(
                (t.direction - direction.normalize()).length() < 1e-9,
                "{}: leaves along {}, came along {}",
                case.lenses,
                t.direction,
                direction.normalize()
            );
            let off = line_distance(last, start, direction);
            assert!(off < 1e-9, "{}: {off} off its line", case.lenses);
        }
        assert!(
            middle >= 20,
            "{}: only {middle} rays crossed the middle",
            case.lenses
        );
    }
}

#[test]
fn the_rochester_cloaks_inner_volume_is_seen_through_its_four_lenses() {
    let mut rng = Rng(9);
    for case in rochester_cases() {
        let mut rays = Vec::new();
        for _ in 0..20 {
            // Inside the inner volume: within a third of its half size across (p h) and along
            // (h − f₁ − f₂ = −L/(2M), at least p h / 3 for these cases) of its centre.
            let x =
                case.centre + case.p * case.h / 3.0 * rng.range(0.0, 1.0) * random_unit(&mut rng);
            rays.push((x, random_unit(&mut rng)));
        }
        let placed: Vec<_> = rays
            .iter()
            .map(|&(x, d)| (case.place(x), case.rotation * d))
            .collect();
        let text = case.scene(&placed.iter().map(|&(s, d)| ray(s, d)).collect::<String>());
        let mut escaped = 0;
        for (t, &(x, _)) in trace(&text).iter().zip(&rays) {
            // The inner volume is seen larger than the cloak (|e| > 1 here, as in Dr TIM's
            // default), so the regions' images overlap and a ray from inside may circle in the
            // cloak for ever; those that leave must leave on a line through x's image.
            if t.end == End::MaxInteractions {
                continue;
            }
            assert_eq!(t.end, End::Escaped, "{}", case.lenses);
            escaped += 1;
            let last = t.points.last().unwrap().position;
            let image = case.place(case.seen(x));
            let off = line_distance(image, last, t.direction);
            assert!(
                off < 1e-9 * (1.0 + (image - last).length()),
                "{}: the ray from {x} leaves {off} off {image}",
                case.lenses
            );
        }
        assert!(escaped >= 10, "{}: only {escaped} rays left", case.lenses);
    }
}

/// `EditableRochesterCloak(parent, studio)`: the box cloak's defaults but e = −1.6, so M = −2,
/// f₁ = 1/3 (the outer lenses on the faces z = 9 and 11) and f₂ = 1/6 (the inner lenses at
/// z = 9.5 and 10.5); 4 lenses and 40 glenses, all of transmission coefficient 0.96 and throwing
/// no shadow; frames hidden, radius 0.01 × 2, red: 64 when shown.
#[test]
fn a_rochester_cloak_named_by_its_type_alone_is_dr_tims_default_cloak() {
    let d = common::images::parse(
        "studio = \"none\"\n[[device]]\nname = \"d\"\nlenses = { type = \"rochester-cloak\" }\n",
    );
    assert_eq!(d.objects.len(), 44, "frames hidden");
    for o in &d.objects {
        let Surface::Glens(g) = &o.surface else {
            panic!("{} is no glens", o.name)
        };
        assert_eq!(g.transmission_coefficient, 0.96, "{}", o.name);
        assert!(!o.shadow_throwing, "{}", o.name);
    }
    for (name, principal_point, f) in [
        ("d/front outer lens", DVec3::new(0.0, 0.0, 9.0), 1.0 / 3.0),
        ("d/front inner lens", DVec3::new(0.0, 0.0, 9.5), 1.0 / 6.0),
        ("d/back outer lens", DVec3::new(0.0, 0.0, 11.0), 1.0 / 3.0),
        ("d/back inner lens", DVec3::new(0.0, 0.0, 10.5), 1.0 / 6.0),
    ] {
        let lens = d.objects.iter().find(|o| o.name == name).expect(name);
        let Surface::Glens(g) = &lens.surface else {
            unreachable!()
        };
        let Focus::Finite {
            principal_point: p,
            focal_length_negative,
            focal_length_positive,
        } = g.focus
        else {
            panic!("{name}: finite")
        };
        assert!((p - principal_point).length() < 1e-12, "{name}: {p}");
        assert!(
            (focal_length_positive - f).abs() < 1e-12,
            "{name}: f₊ {focal_length_positive}"
        );
        assert!(
            (focal_length_negative + f).abs() < 1e-12,
            "{name}: f₋ {focal_length_negative}"
        );
    }
    let names: Vec<&str> = d.objects.iter().map(|o| o.name.as_str()).collect();
    for name in [
        "d/front top glens",
        "d/back left diagonal glens",
        "d/front top right diagonal glens",
        "d/back bottom centre diagonal glens",
        "d/top inner glens",
        "d/top right centre diagonal glens",
    ] {
        assert!(names.contains(&name), "{name} in {names:?}");
    }
    let framed = common::images::parse(
        "studio = \"none\"\n[[device]]\nname = \"d\"\nshow_edges = true\n\
         lenses = { type = \"rochester-cloak\", show_placeholder_surfaces = true }\n",
    );
    assert_eq!(framed.objects.len(), 44 + 64);
    let placeholders = framed
        .objects
        .iter()
        .filter(
            |o| matches!(&o.surface, Surface::Transparent(t) if t.transmission_coefficient == 0.96),
        )
        .count();
    assert_eq!(placeholders, 44);
    let belly = framed
        .objects
        .iter()
        .find(|o| o.name == "d/belly vertex top right")
        .expect("belly vertex");
    let (lo, hi) = belly.shape.bounds().unwrap();
    assert!(((lo + hi) / 2.0 - DVec3::new(1.5, 1.5, 10.0)).length() < 1e-12);
    assert!(((hi - lo).x - 0.04).abs() < 1e-12, "radius 0.01 × 2");
}

#[test]
fn bad_rochester_cloaks_are_refused_where_they_are_given() {
    let dir = tempfile::tempdir().unwrap();
    for (lenses, needles) in [
        (
            "type = \"rochester-cloak\", inner_volume_size_factor_em = -0.8",
            &[
                "inner_volume_size_factor_em = -0.8",
                "less than -inner_volume_size_factor_p",
            ][..],
        ),
        (
            "type = \"box-cloak\", cloak_type = \"rochester\"",
            &["inner_volume_size_factor_em = 0.4", "magnified and flipped"][..],
        ),
        (
            "type = \"rochester-cloak\", inner_volume_size_factor_p = 1.2",
            &[
                "inner_volume_size_factor_p = 1.2",
                "between 0.001 and 0.999",
            ][..],
        ),
        (
            "type = \"rochester-cloak\", inner_volume_size_factor_em = -0.805",
            &["-1.00625 is too close to -1"][..],
        ),
        (
            "type = \"rochester-cloak\", inner_volume_size_factor_em = -900",
            &["-1125 is below -1000"][..],
        ),
        (
            "type = \"rochester-cloak\", cloak_type = \"cubic\"",
            &["rochester-cloak has no cloak_type"][..],
        ),
    ] {
        let text =
            format!("studio = \"none\"\n\n[[device]]\nname = \"c\"\nlenses = {{ {lenses} }}\n");
        let path = write(dir.path(), "bad.toml", text);
        let run = timbre(dir.path(), &["check", path_str(&path)]);
        run.assert_bad_input(needles);
        assert_eq!(location(&run.stderr, &path).0, 5, "{}", run.stderr);
    }
}

/// Dr TIM's `OctahedralBoxCloakMaker` gives its gCLAs η from closed forms in e and p (its
/// exterior faces η₁ = (p − 1)/(e − 1), interior pyramid faces η₂ = p (e − 1)(p − 2)/(e (p − 1)
/// (e − 2)), star prongs η* = p (e − 2)(p − 3)/(e (p − 2)(e − 3)), octahedron faces
/// η₀ = p (e − 3)/(e (p − 3))); timbre's region maps must give the same η, or 1/η where its
/// arrays face the other way.
#[test]
fn the_octahedral_cloaks_gclas_have_dr_tims_etas() {
    for (e, p) in [(0.4, 0.8), (-0.3, 0.6), (1.5, 0.3)] {
        let d = common::images::parse(&format!(
            "studio = \"none\"\n[[device]]\nname = \"d\"\nlenses = {{ type = \"box-cloak\", \
             cloak_type = \"octahedral\", inner_volume_size_factor_em = {e}, \
             inner_volume_size_factor_p = {p} }}\n"
        ));
        assert_eq!(d.objects.len(), 6 + 24 + 24 + 8, "frames hidden");
        for (prefix, eta, count) in [
            ("d/exterior face", (p - 1.0) / (e - 1.0), 6),
            (
                "d/interface between",
                p * (e - 1.0) * (p - 2.0) / (e * (p - 1.0) * (e - 2.0)),
                24,
            ),
            (
                "d/star prong",
                p * (e - 2.0) * (p - 3.0) / (e * (p - 2.0) * (e - 3.0)),
                24,
            ),
            ("d/octahedron face", p * (e - 3.0) / (e * (p - 3.0)), 8),
        ] {
            let faces: Vec<_> = d
                .objects
                .iter()
                .filter(|o| o.name.starts_with(prefix))
                .collect();
            assert_eq!(faces.len(), count, "{prefix}");
            for o in faces {
                let Surface::ConfocalLensletArrays(a) = &o.surface else {
                    panic!("{} is no gCLAs", o.name)
                };
                assert_eq!(a.eta.x, a.eta.y, "{}", o.name);
                let (x, want) = (a.eta.x, eta);
                assert!(
                    (x - want).abs() < 1e-9 * want.abs() || (x * want - 1.0).abs() < 1e-9,
                    "e = {e}, p = {p}, {}: η = {x}, Dr TIM's {want}",
                    o.name
                );
                assert_eq!(
                    a.transmission,
                    timbre::surfaces::metatoys::Transmission::Constant(0.96)
                );
            }
        }
    }
}

/// A prismatic cloak checked (`box-cloak` of `cloak_type = "prismatic"`, or `gclas-cloak`):
/// its `lenses` table and, in its own terms, centre, front and top directions, side length,
/// and e and p (a and a′).
struct Prismatic {
    lenses: &'static str,
    centre: DVec3,
    front: DVec3,
    top: DVec3,
    side: f64,
    e: f64,
    p: f64,
}

fn prismatic_cases() -> Vec<Prismatic> {
    vec![
        // Dr TIM's box-cloak defaults, moved to the origin.
        Prismatic {
            lenses: "type = \"box-cloak\", cloak_type = \"prismatic\", centre = [0, 0, 0]",
            centre: DVec3::ZERO,
            front: DVec3::NEG_Z,
            top: DVec3::Y,
            side: 2.0,
            e: 0.4,
            p: 0.8,
        },
        // Skew, the central prism seen larger.
        Prismatic {
            lenses: "type = \"box-cloak\", cloak_type = \"prismatic\", centre = [0.3, 0, -0.2], \
                     front_direction = [1, 0, 1], right_direction = [0, 1, 0], \
                     top_direction = [-1, 0, 1], side_length = 1.5, \
                     inner_volume_size_factor_em = 0.9, inner_volume_size_factor_p = 0.5",
            centre: DVec3::new(0.3, 0.0, -0.2),
            front: DVec3::new(1.0, 0.0, 1.0).normalize(),
            top: DVec3::new(-1.0, 0.0, 1.0).normalize(),
            side: 1.5,
            e: 0.9,
            p: 0.5,
        },
        // Dr TIM's gCLAs cloak, prismatic, moved to the origin: a = 0.07, a′ = 0.7, side 1.
        Prismatic {
            lenses: "type = \"gclas-cloak\", cloak_type = \"prismatic\", centre = [0, 0, 0]",
            centre: DVec3::ZERO,
            front: DVec3::NEG_Z,
            top: DVec3::Y,
            side: 1.0,
            e: 0.07,
            p: 0.7,
        },
    ]
}

impl Prismatic {
    fn scene(&self, rays: &str) -> String {
        format!(
            "studio = \"none\"\n[[device]]\nname = \"cloak\"\nshow_edges = false\nlenses = {{ {} }}\n{rays}",
            self.lenses
        )
    }

    /// A random point at a height within ±`height` × the half side and a distance `r` × the
    /// half side from the axis, and its height.
    fn point(&self, rng: &mut Rng, r: f64, height: f64) -> DVec3 {
        let h = self.side / 2.0;
        let across = random_unit(rng)
            .reject_from_normalized(self.top)
            .normalize();
        self.centre + r * h * across + rng.range(-height, height) * h * self.top
    }
}

/// A prismatic cloak has no top or bottom faces (Dr TIM's neither): it is a slice of an
/// infinitely long cloak, and shows space as it is to light that crosses only its sides.
#[test]
fn space_outside_the_prismatic_cloak_is_seen_as_it_is() {
    let mut rng = Rng(5);
    for case in prismatic_cases() {
        let mut rays = Vec::new();
        for _ in 0..40 {
            // Straight lines that stay within 0.6 of the half side of the middle height
            // while in the cloak.
            let start = case.point(&mut rng, 6.0, 0.3);
            let r = rng.range(0.0, 0.8);
            let target = case.point(&mut rng, r, 0.3);
            rays.push((start, target - start));
        }
        let text = case.scene(&rays.iter().map(|&(s, d)| ray(s, d)).collect::<String>());
        let mut crossed = 0;
        for (t, &(start, direction)) in trace(&text).iter().zip(&rays) {
            assert_eq!(t.end, End::Escaped, "{}: {:?}", case.lenses, t.points);
            if t.points.len() < 4 {
                continue;
            }
            crossed += 1;
            let last = t.points.last().unwrap().position;
            assert!(
                (t.direction - direction.normalize()).length() < 1e-9,
                "{}: leaves along {}, came along {}",
                case.lenses,
                t.direction,
                direction.normalize()
            );
            let off = line_distance(last, start, direction);
            assert!(off < 1e-9, "{}: {off} off its line", case.lenses);
        }
        assert!(
            crossed >= 30,
            "{}: only {crossed} rays crossed",
            case.lenses
        );
    }
}

/// The central prism is seen scaled by e/p across the top direction, its height unchanged.
#[test]
fn the_central_prism_is_seen_scaled_by_e_over_p_across() {
    let mut rng = Rng(13);
    for case in prismatic_cases() {
        let mut rays = Vec::new();
        for _ in 0..20 {
            // Within the central prism's inscribed cylinder, of radius p h/√2.
            let r = rng.range(0.0, 0.7) * case.p;
            let p = case.point(&mut rng, r, 0.3);
            // Mostly across: within the cloak it climbs at most 0.3 of the half side.
            let across = random_unit(&mut rng).reject_from_normalized(case.top);
            let d = across.normalize() + rng.range(-0.1, 0.1) * case.top;
            rays.push((p, d));
        }
        let text = case.scene(&rays.iter().map(|&(s, d)| ray(s, d)).collect::<String>());
        for (t, &(p, _)) in trace(&text).iter().zip(&rays) {
            assert_eq!(t.end, End::Escaped, "{}: {:?}", case.lenses, t.points);
            let last = t.points.last().unwrap().position;
            let x = p - case.centre;
            let along = x.dot(case.top) * case.top;
            let image = case.centre + case.e / case.p * (x - along) + along;
            let off = line_distance(image, last, t.direction);
            assert!(
                off < 1e-9,
                "{}: the ray from {p} leaves {off} off {image}",
                case.lenses
            );
        }
        // The front exterior face is where Dr TIM puts it.
        let d = common::images::parse(&case.scene(""));
        let face = d
            .objects
            .iter()
            .find(|o| o.name == "cloak/exterior face front")
            .expect("front face");
        let (lo, hi) = face.shape.bounds().unwrap();
        let middle = (lo + hi) / 2.0;
        assert!(
            (middle - (case.centre + case.side / 2.0 * case.front)).length() < 1e-9,
            "{}: {middle}",
            case.lenses
        );
    }
}

/// `EditableGCLAsCloak(parent, studio)`: an octahedral cloak about (0, 0, 10), side 1,
/// a = 0.07, a′ = 0.7, transmission 0.96, frames shown (radius 0.01 × the side,
/// `GREY50_SHINY`); its prismatic type's gCLAs have the η of Dr TIM's formulas (from its
/// Mathematica notebook: (a′ − 1)/(a − 1) outside, a′(a − 1)(a′ − 2)/(a(a′ − 1)(a − 2)) within,
/// (a − 2) a′/(a (a′ − 2)) innermost; up to the sheet's orientation).
#[test]
fn a_gclas_cloak_named_by_its_type_alone_is_dr_tims_default_cloak() {
    let d = common::images::parse(
        "studio = \"none\"\n[[device]]\nname = \"d\"\nlenses = { type = \"gclas-cloak\" }\n",
    );
    let faces: Vec<_> = d
        .objects
        .iter()
        .filter(|o| matches!(o.surface, Surface::ConfocalLensletArrays(_)))
        .collect();
    assert_eq!(faces.len(), 6 + 24 + 24 + 8, "the octahedral cloak's gCLAs");
    // Frames: 8 + 6 vertices, 12 + 12 + 24 edges.
    assert_eq!(d.objects.len(), faces.len() + 14 + 48);
    let front = d
        .objects
        .iter()
        .find(|o| o.name == "d/exterior face front")
        .expect("front face");
    let (lo, hi) = front.shape.bounds().unwrap();
    assert!(((lo + hi) / 2.0 - DVec3::new(0.0, 0.0, 9.5)).length() < 1e-12);
    assert!(((hi - lo).x - 1.0).abs() < 1e-12, "side 1");
    let Surface::ConfocalLensletArrays(a) = &front.surface else {
        unreachable!()
    };
    let want = (0.7 - 1.0) / (0.07 - 1.0);
    assert!((a.eta.x - want).abs() < 1e-9 || (a.eta.x * want - 1.0).abs() < 1e-9);
    let vertex = d
        .objects
        .iter()
        .find(|o| o.name == "d/cube vertex top right front")
        .expect("frames shown");
    let (lo, hi) = vertex.shape.bounds().unwrap();
    assert!(((lo + hi) / 2.0 - DVec3::new(0.5, 0.5, 9.5)).length() < 1e-12);
    assert!(((hi - lo).x - 0.02).abs() < 1e-12, "radius 0.01 × 1");
    let Surface::Coloured(c) = &vertex.surface else {
        panic!("frames are coloured")
    };
    assert_eq!(c.diffuse, timbre::math::Colour::new(0.5, 0.5, 0.5));

    for (e, p) in [(0.07, 0.7), (-0.3, 0.6), (1.5, 0.3)] {
        let d = common::images::parse(&format!(
            "studio = \"none\"\n[[device]]\nname = \"d\"\nshow_edges = true\nlenses = {{ type = \
             \"gclas-cloak\", cloak_type = \"prismatic\", a = {e}, a_prime = {p}, \
             gclas_transmission_coefficient = 0.9 }}\n"
        ));
        // 16 gCLAs; frames: 8 + 8 vertices, 12 + 12 + 16 edges.
        assert_eq!(d.objects.len(), 16 + 16 + 40);
        for (prefix, eta, count) in [
            ("d/exterior face", (p - 1.0) / (e - 1.0), 4),
            (
                "d/interface between",
                p * (e - 1.0) * (p - 2.0) / (e * (p - 1.0) * (e - 2.0)),
                8,
            ),
            ("d/innermost interface", (e - 2.0) * p / (e * (p - 2.0)), 4),
        ] {
            let faces: Vec<_> = d
                .objects
                .iter()
                .filter(|o| o.name.starts_with(prefix))
                .collect();
            assert_eq!(faces.len(), count, "{prefix}");
            for o in faces {
                let Surface::ConfocalLensletArrays(a) = &o.surface else {
                    panic!("{} is no gCLAs", o.name)
                };
                assert_eq!(a.eta.x, a.eta.y, "{}", o.name);
                let (x, want) = (a.eta.x, eta);
                assert!(
                    (x - want).abs() < 1e-9 * want.abs() || (x * want - 1.0).abs() < 1e-9,
                    "a = {e}, a′ = {p}, {}: η = {x}, Dr TIM's {want}",
                    o.name
                );
                assert_eq!(
                    a.transmission,
                    timbre::surfaces::metatoys::Transmission::Constant(0.9)
                );
            }
        }
    }
}

#[test]
fn bad_gclas_cloaks_are_refused_where_they_are_given() {
    let dir = tempfile::tempdir().unwrap();
    for (keys, needles) in [
        (
            "a_prime = 1",
            &["a_prime = 1", "between 0.001 and 0.999"][..],
        ),
        ("a = 3", &["a = 3", "flattens"][..]),
        (
            "cloak_type = \"prismatic\", a = 2",
            &["a = 2", "flattens"][..],
        ),
        (
            "cloak_type = \"cubic\"",
            &["cubic", "octahedral", "prismatic"][..],
        ),
        (
            "inner_volume_size_factor_em = 0.3",
            &["inner_volume_size_factor_em"][..],
        ),
        (
            "gclas_transmission_coefficient = 2",
            &["between 0 and 1"][..],
        ),
    ] {
        let text = format!(
            "studio = \"none\"\n\n[[device]]\nname = \"c\"\nlenses = {{ type = \"gclas-cloak\", {keys} }}\n"
        );
        let path = write(dir.path(), "bad.toml", text);
        let run = timbre(dir.path(), &["check", path_str(&path)]);
        run.assert_bad_input(needles);
        assert_eq!(location(&run.stderr, &path).0, 5, "{}", run.stderr);
    }
}

/// `EditableGCLAsTardisWindow(parent, studio)`: the octahedral gCLAs cloak's side behind its
/// front face, Dr TIM's 17 windows (the exterior face, 4 pyramid interfaces, 8 star prongs, 4
/// octahedron faces: those through the front vertex) and its frames on the front side (4 cube
/// vertices and edges, 5 octahedron vertices, 8 octahedron edges, 12 star edges), each face the
/// same as the cloak's; the minimum window's 4 faces.
#[test]
fn a_gclas_tardis_window_is_the_front_of_dr_tims_cloak() {
    let cloak = common::images::parse(
        "studio = \"none\"\n[[device]]\nname = \"d\"\nlenses = { type = \"gclas-cloak\" }\n",
    );
    let window = common::images::parse(
        "studio = \"none\"\n[[device]]\nname = \"d\"\nlenses = { type = \"gclas-tardis-window\" }\n",
    );
    let faces: Vec<_> = window
        .objects
        .iter()
        .filter(|o| matches!(o.surface, Surface::ConfocalLensletArrays(_)))
        .collect();
    assert_eq!(faces.len(), 17);
    assert_eq!(window.objects.len(), 17 + 4 + 4 + 5 + 8 + 12);
    for o in &window.objects {
        let same = cloak
            .objects
            .iter()
            .find(|c| c.name == o.name)
            .unwrap_or_else(|| panic!("{} is no part of the cloak", o.name));
        assert_eq!(same.surface, o.surface, "{}", o.name);
        assert_eq!(same.shape.bounds(), o.shape.bounds(), "{}", o.name);
        // Nothing behind the middle plane z = 10 (front is −z).
        let (lo, _) = o.shape.bounds().unwrap();
        assert!(lo.z < 10.0 + 1e-9, "{}", o.name);
    }
    for name in [
        "d/exterior face front",
        "d/interface between the front pyramid and the front left edge",
        "d/star prong between the bottom left front corner and the front left edge",
        "d/octahedron face bottom left front",
        "d/star edge from the top right front corner to the right vertex",
        "d/octahedron edge right top",
    ] {
        assert!(window.objects.iter().any(|o| o.name == name), "{name}");
    }
    let minimum = common::images::parse(
        "studio = \"none\"\n[[device]]\nname = \"d\"\nshow_edges = false\nlenses = { type = \
         \"gclas-tardis-window\", tardis_window_type = \"cloak-side-minimum\" }\n",
    );
    let mut names: Vec<&str> = minimum.objects.iter().map(|o| o.name.as_str()).collect();
    names.sort();
    assert_eq!(
        names,
        [
            "d/exterior face front",
            "d/interface between the front pyramid and the front top edge",
            "d/octahedron face top right front",
            "d/star prong between the top right front corner and the front top edge",
        ]
    );
}

/// Through the Tardis window the space behind it is seen scaled by a/a′ about the cloak's
/// centre: light from in front that crosses the window into the central octahedron runs
/// there along the line that, scaled by a/a′ about the centre, is the line it came on; beyond
/// the window (which has no back) it goes on along that line.
#[test]
fn through_a_tardis_window_space_is_seen_scaled_by_a_over_a_prime() {
    let (centre, side, a, a_prime) = (DVec3::new(0.0, 0.0, 8.0), 2.0, 0.3, 0.6);
    let mut rng = Rng(17);
    let mut rays = Vec::new();
    for _ in 0..30 {
        let start = DVec3::new(rng.range(-0.3, 0.3), rng.range(-0.3, 0.3), 0.0);
        let target = centre + DVec3::new(rng.range(-0.1, 0.1), rng.range(-0.1, 0.1), 0.0);
        rays.push((start, target - start));
    }
    let text = format!(
        "studio = \"none\"\n[[device]]\nname = \"w\"\nshow_edges = false\nlenses = {{ type = \
         \"gclas-tardis-window\", centre = [{}, {}, {}], side_length = {side}, a = {a}, \
         a_prime = {a_prime} }}\n{}",
        centre.x,
        centre.y,
        centre.z,
        rays.iter().map(|&(s, d)| ray(s, d)).collect::<String>()
    );
    let on_octahedron =
        |x: DVec3| ((x - centre).abs().element_sum() - a_prime * side / 2.0).abs() < 1e-9;
    let mut checked = 0;
    for (t, &(start, direction)) in trace(&text).iter().zip(&rays) {
        assert_eq!(t.end, End::Escaped, "{:?}", t.points);
        // From the last interface on: into the octahedron, and straight on out of it.
        let p = t.points[t.points.len() - 2].position;
        if !on_octahedron(p) {
            continue;
        }
        checked += 1;
        for x in [p, p + 0.01 * t.direction, p + 10.0 * t.direction] {
            let seen = centre + a / a_prime * (x - centre);
            let off = line_distance(seen, start, direction);
            assert!(off < 1e-9, "{x} is seen at {seen}, {off} off the line");
        }
    }
    assert!(checked >= 20, "only {checked} rays reached the octahedron");
}

#[test]
fn bad_gclas_tardis_windows_are_refused_where_they_are_given() {
    let dir = tempfile::tempdir().unwrap();
    for (lenses, needles) in [
        (
            "type = \"gclas-tardis-window\", cloak_type = \"octahedral\"",
            &["no cloak_type", "tardis_window_type"][..],
        ),
        (
            "type = \"gclas-tardis-window\", tardis_window_type = \"door\"",
            &["door", "cloak-side", "cloak-side-minimum"][..],
        ),
        (
            "type = \"gclas-tardis-window\", a = 2",
            &["a = 2", "flattens"][..],
        ),
        (
            "type = \"gclas-cloak\", tardis_window_type = \"cloak-side\"",
            &["tardis_window_type belongs to a gclas-tardis-window"][..],
        ),
    ] {
        let text =
            format!("studio = \"none\"\n\n[[device]]\nname = \"c\"\nlenses = {{ {lenses} }}\n");
        let path = write(dir.path(), "bad.toml", text);
        let run = timbre(dir.path(), &["check", path_str(&path)]);
        run.assert_bad_input(needles);
        assert_eq!(location(&run.stderr, &path).0, 5, "{}", run.stderr);
    }
}
