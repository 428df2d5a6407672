//! Issue 41 item 2, Dr TIM's pinch-transformation window (`EditableGCLAsPinchTransformationWindow`),
//! checked against what the device must do, worked out from its parameters alone:
//!
//! * seen through the window, space is as seen through an open one: light that crosses the
//!   window goes on along the line it came on;
//! * the light is funnelled through the opening: inside the window it crosses the middle
//!   plane no lower than (1 − s) h above the bottom (s the central strain factor, h the
//!   height), above the wedge light does not reach;
//! * Dr TIM's defaults, names and refusals.

mod common;

use glam::DVec3;
use timbre::surfaces::Surface;
use timbre::trajectories::{self, End, Trajectory};

use common::cli::{location, path_str, timbre, write};
use common::rng::Rng;

fn trace(text: &str) -> Vec<Trajectory> {
    let description = common::images::parse(text);
    trajectories::trace(common::rays::device(), &description).expect("trace")
}

fn line_distance(p: DVec3, a: DVec3, d: DVec3) -> f64 {
    (p - a).reject_from_normalized(d.normalize()).length()
}

/// A window checked: its keys and, in its terms, centre, unit x̂ and ŷ (perpendicular here),
/// width, height, thickness and central strain factor.
struct Case {
    keys: &'static str,
    centre: DVec3,
    x: DVec3,
    y: DVec3,
    size: DVec3,
    strain: f64,
}

fn cases() -> Vec<Case> {
    vec![
        Case {
            keys: "",
            centre: DVec3::new(0.0, 0.0, 5.0),
            x: DVec3::X,
            y: DVec3::Y,
            size: DVec3::new(1.0, 1.0, 0.5),
            strain: 0.5,
        },
        Case {
            keys: "centre = [0.3, 0.2, -1], right_direction = [1, 0, 1], up_direction = [0, 2, 0], \
                   width = 2, height = 1.5, thickness = 0.8, central_strain_factor = 0.2, \
                   gclas_transmission_coefficient_method = \"constant\", \
                   gclas_transmission_coefficient = 0.9",
            centre: DVec3::new(0.3, 0.2, -1.0),
            x: DVec3::new(1.0, 0.0, 1.0).normalize(),
            y: DVec3::Y,
            size: DVec3::new(2.0, 1.5, 0.8),
            strain: 0.2,
        },
    ]
}

#[test]
fn light_crossing_the_window_goes_on_along_its_line_through_the_opening() {
    let mut rng = Rng(23);
    for case in cases() {
        let z = case.x.cross(case.y);
        let (w, h, t) = (case.size.x, case.size.y, case.size.z);
        let mut rays = Vec::new();
        for _ in 0..40 {
            // From in front, through the window, nearly along ẑ.
            let target =
                case.centre + rng.range(-0.4, 0.4) * w * case.x + rng.range(-0.4, 0.4) * h * case.y;
            let direction = z + rng.range(-0.2, 0.2) * case.x + rng.range(-0.2, 0.2) * case.y;
            rays.push((target - 3.0 * t * direction, direction));
        }
        let text = format!(
            "studio = \"none\"\n[[device]]\nname = \"w\"\nlenses = {{ type = \
             \"gclas-pinch-transformation-window\", show_wall = false, {} }}\n{}",
            case.keys,
            rays.iter()
                .map(|(s, d)| format!(
                    "[[ray_trajectory]]\nstart = [{}, {}, {}]\ndirection = [{}, {}, {}]\n",
                    s.x, s.y, s.z, d.x, d.y, d.z
                ))
                .collect::<String>()
        );
        let bottom = case.centre - 0.5 * h * case.y;
        for (t, &(start, direction)) in trace(&text).iter().zip(&rays) {
            let label = format!("{}: ray from {start}", case.keys);
            assert_eq!(t.end, End::Escaped, "{label}: {:?}", t.points);
            let names: Vec<_> = t.points.iter().filter_map(|p| p.object).collect();
            assert_eq!(names.len(), 4, "{label}: crosses the four windows");
            let last = t.points.last().unwrap().position;
            assert!(
                (t.direction - direction.normalize()).length() < 1e-9,
                "{label}"
            );
            let off = line_distance(last, start, direction);
            assert!(off < 1e-9, "{label}: {off} off its line");
            // Between the inner diagonal windows (points 2 and 3), where it crosses the
            // middle plane.
            let (a, b) = (t.points[2].position, t.points[3].position);
            let (za, zb) = ((a - case.centre).dot(z), (b - case.centre).dot(z));
            let middle = a + (b - a) * (za / (za - zb));
            let raised = (middle - bottom).dot(case.y);
            assert!(
                raised >= (1.0 - case.strain) * h - 1e-9,
                "{label}: crosses the middle plane {raised} above the bottom"
            );
        }
    }
}

/// `EditableGCLAsPinchTransformationWindow(parent, studio)`: centre (0, 0, 5), width and
/// height 1, thickness 0.5, central strain factor 0.5, gCLAs of geometric-best transmission,
/// shadow-throwing; the wall (1 wider and higher on each side, 0.2 thicker, grey 80% matt) and
/// its wedge shown; the frames hidden (radius 0.01, white).
#[test]
fn a_pinch_window_named_by_its_type_alone_is_dr_tims_default() {
    let d = common::images::parse(
        "studio = \"none\"\n[[device]]\nname = \"d\"\n\
         lenses = { type = \"gclas-pinch-transformation-window\" }\n",
    );
    let names: Vec<&str> = d.objects.iter().map(|o| o.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "d/front window",
            "d/inner front diagonal window",
            "d/inner back diagonal window",
            "d/back window",
            "d/wall left side",
            "d/wall right side",
            "d/wall bottom side",
            "d/wall top side",
            "d/front of wedge",
            "d/back of wedge",
        ]
    );
    for o in &d.objects {
        assert!(o.shadow_throwing, "{}", o.name);
    }
    let bounds = |name: &str| {
        d.objects
            .iter()
            .find(|o| o.name == name)
            .unwrap()
            .shape
            .bounds()
            .unwrap()
    };
    // The front window: x, y in [−0.5, 0.5] at z = 4.75.
    let (lo, hi) = bounds("d/front window");
    assert!((lo - DVec3::new(-0.5, -0.5, 4.75)).length() < 1e-12);
    assert!((hi - DVec3::new(0.5, 0.5, 4.75)).length() < 1e-12);
    // The inner diagonal windows meet at the inner vertices, 0.5 above the bottom.
    let (lo, _) = bounds("d/inner front diagonal window");
    assert!((lo - DVec3::new(-0.5, 0.0, 4.75)).length() < 1e-12, "{lo}");
    // The wall's left side: x from −1.5 to −0.5, y from −1.5 to 1.5, 0.7 thick.
    let (lo, hi) = bounds("d/wall left side");
    assert!((lo - DVec3::new(-1.5, -1.5, 4.65)).length() < 1e-12, "{lo}");
    assert!((hi - DVec3::new(-0.5, 1.5, 5.35)).length() < 1e-12, "{hi}");
    let Surface::ConfocalLensletArrays(a) = &d.objects[0].surface else {
        panic!("the front window is gCLAs")
    };
    assert_eq!(
        a.transmission,
        timbre::surfaces::metatoys::Transmission::GeometricBest
    );

    // The wall always throws shadows (Dr TIM's shadowThrowing is the gCLAs'), the windows
    // only if the window does.
    let unshadowed = common::images::parse(
        "studio = \"none\"\n[[device]]\nname = \"d\"\nshadow_throwing = false\n\
         lenses = { type = \"gclas-pinch-transformation-window\" }\n",
    );
    for o in &unshadowed.objects {
        assert_eq!(o.shadow_throwing, !o.name.contains("window"), "{}", o.name);
    }

    let framed = common::images::parse(
        "studio = \"none\"\n[[device]]\nname = \"d\"\nshow_edges = true\n\
         lenses = { type = \"gclas-pinch-transformation-window\", show_wall = false }\n",
    );
    assert_eq!(framed.objects.len(), 4 + 10 + 19);
    let vertex = framed
        .objects
        .iter()
        .find(|o| o.name == "d/left inner vertex")
        .expect("frames");
    let (lo, hi) = vertex.shape.bounds().unwrap();
    assert!(((lo + hi) / 2.0 - DVec3::new(-0.5, 0.0, 5.0)).length() < 1e-12);
    assert!(((hi - lo).x - 0.02).abs() < 1e-12);
    let Surface::Coloured(c) = &vertex.surface else {
        panic!("frames are coloured")
    };
    assert_eq!(c.diffuse, timbre::math::Colour::splat(1.0));
}

#[test]
fn bad_pinch_windows_are_refused_where_they_are_given() {
    let dir = tempfile::tempdir().unwrap();
    for (keys, needles) in [
        (
            "central_strain_factor = 1",
            &["central_strain_factor = 1", "between 0.001 and 0.999"][..],
        ),
        (
            "up_direction = [2, 0, 0]",
            &["up_direction must not be along right_direction"][..],
        ),
        (
            "gclas_transmission_coefficient = 0.9",
            &[
                "gclas_transmission_coefficient is only used with",
                "constant",
            ][..],
        ),
        (
            "show_wall = false, additional_wall_width = 2",
            &["additional_wall", "show_wall = false"][..],
        ),
        (
            "gclas_transmission_coefficient_method = \"worst\"",
            &["geometric-best"][..],
        ),
        ("thickness = 0", &["positive number"][..]),
    ] {
        let text = format!(
            "studio = \"none\"\n\n[[device]]\nname = \"c\"\nlenses = {{ type = \
             \"gclas-pinch-transformation-window\", {keys} }}\n"
        );
        let path = write(dir.path(), "bad.toml", text);
        let run = timbre(dir.path(), &["check", path_str(&path)]);
        run.assert_bad_input(needles);
        assert_eq!(location(&run.stderr, &path).0, 5, "{}", run.stderr);
    }
}
