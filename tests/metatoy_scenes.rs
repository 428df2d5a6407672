//! The METATOY surfaces (§4–6) in scene files and rendered pictures: every surface type and its
//! errors, the built-in "metatoy-window" studio, and picture-level facts: the n = 10 metric
//! window's total-internal-reflection circle, laws that undo each other, equivalent laws that
//! must look the same, and no NaN pixels in any example. (The laws themselves are checked ray by
//! ray in tests/metatoys.rs.)

mod common;

use std::path::Path;

use glam::{DMat3, DVec2, DVec3};
use timbre::geometry::{AnalyticShape, Interaction, Shape};
use timbre::math::Ray;
use timbre::render::Image;
use timbre::scene::{SceneDescription, file};
use timbre::surfaces::metatoys::{
    AzimuthalPixelatedFresnelWedgePhase, AzimuthalRadial, Basis, Conjugation, CylindricalPhase,
    LensPhase, Phase, PointToPointImagingHologram, PolynomialPhase, Refraction, RotationAxis,
    RotationallySymmetricPhase, Sectors, Teleportation, Transmission,
};
use timbre::surfaces::{ConfocalLensletArrays, Field, PhaseConjugating, Redirection, Surface};

use common::images::{differing, differing_by_more_than, parse, render_description, render_text};

/// The METATOY-window studio at a small size, with `window` as the pane's surface.
fn window_scene(window: &str, extra: &str) -> String {
    format!(
        "studio = \"metatoy-window\"\n[render]\nwidth = 160\nheight = 120\n[window]\nsurface = {window}\n{extra}"
    )
}

fn object<'a>(d: &'a SceneDescription, name: &str) -> &'a timbre::scene::SceneObject {
    d.objects
        .iter()
        .find(|o| o.name == name)
        .unwrap_or_else(|| panic!("no object '{name}'"))
}

fn error(text: &str) -> String {
    file::parse(text, "s.toml").unwrap_err().to_string()
}

fn assert_finite(image: &Image, what: &str) {
    let bad = image.pixels.iter().filter(|c| !c.is_finite()).count();
    assert_eq!(bad, 0, "{what}: {bad} pixels are not finite");
}

#[test]
fn the_metatoy_window_studio_is_tims_scene() {
    let d = parse("studio = \"metatoy-window\"\n");
    let pane = object(&d, "window");
    let Shape::Parallelogram(p) = &pane.shape else {
        panic!("{:?}", pane.shape)
    };
    assert_eq!(
        (p.corner(), p.span_u(), p.span_v()),
        (
            DVec3::new(-1.5, -0.98, 10.0),
            DVec3::X * 3.0,
            DVec3::Y * 2.0
        )
    );
    assert_eq!(p.frame(p.corner(), 0).w, DVec3::Z, "outward normal +z");
    assert!(!pane.shadow_throwing);
    let Surface::RayRotating(r) = &pane.surface else {
        panic!("{:?}", pane.surface)
    };
    // Dr TIM's RayRotating(60°) turns rays by −60° about their crossing direction.
    assert!((r.angle + 60f64.to_radians()).abs() < 1e-15);
    assert_eq!(
        (r.axis, r.transmission_coefficient, r.reflection_coefficient),
        (RotationAxis::Normal, 0.96, 1.0)
    );

    let frame: Vec<_> = d
        .objects
        .iter()
        .filter(|o| o.name.starts_with("window frame"))
        .collect();
    assert_eq!(frame.len(), 8);
    for o in &frame {
        assert!(o.shadow_throwing, "{}", o.name);
        let Surface::Coloured(c) = &o.surface else {
            panic!("{:?}", o.surface)
        };
        assert_eq!((c.diffuse, c.specular), (DVec3::splat(0.5), DVec3::ONE));
        match &o.shape {
            Shape::Cylinder(c) => assert_eq!(c.radius(), 0.025),
            Shape::Sphere(s) => {
                assert_eq!(s.radius(), 0.025);
                let c = s.centre();
                assert!(c.x.abs() == 1.5 && (c.y == -0.98 || c.y == 1.02) && c.z == 10.0);
            }
            other => panic!("{other:?}"),
        }
    }

    // The lattice: 16 red cylinders along z from 11 to 38, blue along x and green along y
    // from −0.98 to 0.98, on the grid {−0.98, −0.32667, 0.32667, 0.98}.
    let grid = [-0.98, -0.98 / 3.0, 0.98 / 3.0, 0.98];
    let cylinders: Vec<_> = d
        .objects
        .iter()
        .filter_map(|o| match (&o.shape, &o.surface) {
            (Shape::Cylinder(c), Surface::Coloured(s)) if c.radius() == 0.02 => {
                Some((c.start(), c.end(), s.diffuse))
            }
            _ => None,
        })
        .collect();
    assert_eq!(cylinders.len(), 48);
    for (start, end, colour) in cylinders {
        let along = (end - start).normalize();
        let expected = if colour.x > 0.0 {
            DVec3::Z
        } else if colour.y > 0.0 {
            DVec3::Y
        } else {
            DVec3::X
        };
        assert_eq!(along, expected, "{start} {end}");
        let on_grid = |x: f64| grid.iter().any(|g| (g - x).abs() < 1e-12);
        for p in [start, end] {
            assert!(on_grid(p.x) && on_grid(p.y) && [11.0, 20.0, 29.0, 38.0].contains(&p.z));
        }
    }
}

#[test]
fn metatoy_surfaces_are_read_with_their_parameters_and_defaults() {
    let pane = |surface: &str| parse(&window_scene(surface, "")).objects.clone();
    let surface_of = |surface: &str| {
        let objects = pane(surface);
        objects
            .into_iter()
            .find(|o| o.name == "window")
            .unwrap()
            .surface
    };

    let Surface::MetricInterface(m) =
        surface_of(r#"{ type = "metric-interface", inside = [[4, 0, 0], [0, 4, 0], [0, 0, 4]] }"#)
    else {
        panic!()
    };
    assert_eq!(m.inside, DMat3::from_diagonal(DVec3::splat(4.0)));
    assert_eq!(m.outside, DMat3::IDENTITY, "Euclidean by default");
    assert_eq!(
        (m.basis, m.refraction, m.allow_imaginary),
        (Basis::Global, Refraction::Positive, false)
    );
    let Surface::MetricInterface(m) = surface_of(
        r#"{ type = "metric-interface", outside = [[1, 0.2, 0], [0.2, 1.2, -0.5], [0, -0.5, 0.5]], basis = "local", refraction = "negative", allow_imaginary = true, transmission = 0.5 }"#,
    ) else {
        panic!()
    };
    assert_eq!(m.outside.y_axis, DVec3::new(0.2, 1.2, -0.5));
    assert_eq!(
        (
            m.basis,
            m.refraction,
            m.allow_imaginary,
            m.transmission_coefficient
        ),
        (Basis::Local, Refraction::Negative, true, 0.5)
    );

    let Surface::ConfocalLensletArrays(g) = surface_of(
        r#"{ type = "gcla", a = [0, 0, 2], u = [1, 0, 0], eta_u = -0.5, eta_v = -1, delta_u = 0.1 }"#,
    ) else {
        panic!()
    };
    assert_eq!(
        (g.eta, g.delta),
        (DVec2::new(-0.5, -1.0), DVec2::new(0.1, 0.0))
    );

    let Surface::RayRotating(r) = surface_of(r#"{ type = "ray-rotating" }"#) else {
        panic!()
    };
    assert!(
        (r.angle + 60f64.to_radians()).abs() < 1e-15,
        "TIM's default"
    );
    let Surface::RayRotating(r) = surface_of(
        r#"{ type = "ray-rotating", angle_deg = 30, axis = [1, 0, 1], basis = "local" }"#,
    ) else {
        panic!()
    };
    assert_eq!(
        r.axis,
        RotationAxis::Direction(DVec3::new(1.0, 0.0, 1.0).normalize(), Basis::Local)
    );

    // Total internal reflection loses no light unless a reflection coefficient is given.
    let reflections = |extra: &str| {
        [
            r#"type = "metric-interface""#,
            r#"type = "gcla", a = [0, 0, 1], u = [1, 0, 0], eta_u = -1, eta_v = -1"#,
            r#"type = "ray-rotating""#,
            r#"type = "phase-hologram", phase = { type = "linear", gradient = [0.1, 0] }"#,
        ]
        .map(|keys| {
            match surface_of(&format!("{{ {keys}, transmission = 0.9{extra} }}")) {
                Surface::MetricInterface(s) => {
                    (s.transmission_coefficient, s.reflection_coefficient)
                }
                Surface::ConfocalLensletArrays(ConfocalLensletArrays {
                    transmission: Transmission::Constant(t),
                    reflection_coefficient,
                    ..
                }) => (t, reflection_coefficient),
                Surface::RayRotating(s) => (s.transmission_coefficient, s.reflection_coefficient),
                Surface::PhaseHologram(s) => (s.transmission_coefficient, s.reflection_coefficient),
                other => panic!("{other:?}"),
            }
        })
    };
    assert_eq!(reflections(""), [(0.9, 1.0); 4]);
    assert_eq!(
        reflections(", reflection_coefficient = 0.3"),
        [(0.9, 0.3); 4]
    );
    assert_eq!(reflections(", reflection = 0.3"), [(0.9, 0.3); 4]);

    let Surface::PhaseHologram(h) = surface_of(
        r#"{ type = "phase-hologram", phase = { type = "cylindrical", focal_length = -2, centre = [1, 1], axis_angle_deg = 90 } }"#,
    ) else {
        panic!()
    };
    let Phase::Cylindrical(CylindricalPhase {
        focal_length,
        centre,
        axis_angle,
    }) = h.phase
    else {
        panic!("{:?}", h.phase)
    };
    assert_eq!((focal_length, centre), (-2.0, DVec2::ONE));
    assert!((axis_angle - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
    let Surface::PhaseHologram(h) = surface_of(
        r#"{ type = "phase-hologram", phase = { type = "lens", focal_length = 3, centre = [1, 0] } }"#,
    ) else {
        panic!()
    };
    assert_eq!(
        h.phase,
        Phase::Lens(LensPhase {
            focal_length: 3.0,
            centre: DVec2::X
        })
    );

    for (surface, conjugation, coefficient) in [
        (
            r#"{ type = "phase-conjugating", reflection = 0.5 }"#,
            Conjugation::Reflective,
            0.5,
        ),
        (
            r#"{ type = "phase-conjugating", mode = "reflective", reflection_coefficient = 0.4 }"#,
            Conjugation::Reflective,
            0.4,
        ),
        (
            r#"{ type = "phase-conjugating", mode = "transmissive", transmission = 0.3 }"#,
            Conjugation::Transmissive,
            0.3,
        ),
        // Dr TIM's GUI's "Transmission/reflection coefficient", DEFAULT_TRANSMISSION_COEFFICIENT.
        (
            r#"{ type = "phase-conjugating", mode = "transmissive" }"#,
            Conjugation::Transmissive,
            0.96,
        ),
    ] {
        assert_eq!(
            surface_of(surface),
            Surface::PhaseConjugating(PhaseConjugating {
                conjugation,
                coefficient
            }),
            "{surface}"
        );
    }
    let Surface::LorentzWindow(l) =
        surface_of(r#"{ type = "lorentz-window", beta = [0, 0, 0.6] }"#)
    else {
        panic!()
    };
    assert!((l.boost.gamma() - 1.25).abs() < 1e-15);

    // A teleporter gets its destination's shape, wherever that object is defined.
    let d = parse(&window_scene(
        r#"{ type = "teleporting", destination = "exit", positional_error = 0.01, angular_error_deg = 1 }"#,
        "[[object]]\nname = \"exit\"\nshape = { type = \"disc\", centre = [0, 0, 20], normal = [0, 0, 1], radius = 1 }\nsurface = { type = \"transparent\" }\n",
    ));
    let Surface::Teleporting(t) = &object(&d, "window").surface else {
        panic!()
    };
    assert_eq!(t.destination.as_ref(), Some(&object(&d, "exit").shape));
    assert_eq!(t.positional_error, 0.01);
    assert!((t.angular_error - 1f64.to_radians()).abs() < 1e-15);
    assert_eq!(t.teleportation, Teleportation::Perfect);
    let d = parse(&window_scene(
        r#"{ type = "teleporting", destination = "exit", teleportation = "holographic", reflection = 0.5 }"#,
        "[[object]]\nname = \"exit\"\nshape = { type = \"disc\", centre = [0, 0, 20], normal = [0, 0, 1], radius = 1 }\nsurface = { type = \"transparent\" }\n",
    ));
    let Surface::Teleporting(t) = &object(&d, "window").surface else {
        panic!()
    };
    assert_eq!(
        (t.teleportation, t.reflection_coefficient),
        (Teleportation::Holographic, 0.5)
    );
}

#[test]
fn bad_metatoy_surfaces_are_errors_at_their_line() {
    let on_line_6 = |surface: &str, message: &str| {
        let e = error(&window_scene(surface, ""));
        assert!(e.starts_with("s.toml:6:"), "{surface}: {e}");
        assert!(
            e.contains(message),
            "{surface}: expected '{message}' in: {e}"
        );
    };
    for (surface, message) in [
        (
            r#"{ type = "metric-interface", inside = [[1, 0.2, 0], [0.3, 1, 0], [0, 0, 1]] }"#,
            "must be symmetric, but g12 = 0.2 and g21 = 0.3",
        ),
        (
            r#"{ type = "metric-interface", inside = [[1, 1, 0], [1, 1, 0], [0, 0, 1]] }"#,
            "singular",
        ),
        (
            r#"{ type = "metric-interface", inside = [[1, 0, 0], [0, nan, 0], [0, 0, 1]] }"#,
            "finite",
        ),
        (
            r#"{ type = "metric-interface", inside = [[0, 0, 1], [0, 1, 0], [1, 0, 1]], basis = "local" }"#,
            "g11 g22 - g12^2 = 0",
        ),
        (
            r#"{ type = "metric-interface", refraction = "sideways" }"#,
            "unknown variant `sideways`",
        ),
        (
            r#"{ type = "gcla", a = [0, 0, 1], u = [0, 0, 3], eta_u = 1, eta_v = 1 }"#,
            "must not be parallel",
        ),
        (
            r#"{ type = "gcla", a = [0, 0, 1], u = [1, 0, 0], eta_u = 0, eta_v = 1 }"#,
            "non-zero",
        ),
        (
            r#"{ type = "gcla", a = [0, 0, 1], u = [1, 0, 0], v = [1, 0, 1] }"#,
            "must not lie in the plane of a",
        ),
        (
            r#"{ type = "gcla", a = [0, 0, 1], u = [1, 0, 0], sigma1_u = 0.5 }"#,
            "only used with transmission_coefficient_method = \"geometric\"",
        ),
        (
            r#"{ type = "gcla", a = [0, 0, 1], u = [1, 0, 0], transmission_coefficient_method = "geometric-best", transmission = 0.5 }"#,
            "only used with transmission_coefficient_method = \"constant\"",
        ),
        (
            r#"{ type = "gcla", a = [0, 0, 1], u = [1, 0, 0], transmission_coefficient_method = "geometric", sigma2_v = 0 }"#,
            "expected a positive number",
        ),
        (
            r#"{ type = "gcla", a = [0, 0, 1], u = [1, 0, 0], transmission_coefficient_method = "sometimes" }"#,
            "unknown variant `sometimes`",
        ),
        (
            r#"{ type = "pixellation", pixel_side_length_u = -1 }"#,
            "expected a positive number",
        ),
        (
            r#"{ type = "layer-stack", layers = [{ type = "pixellation" }, { type = "matt", colour = [1, 1, 1] }] }"#,
            "without a ray offset",
        ),
        (
            r#"{ type = "layer-stack", layers = [{ type = "idealised-dove-prism-array" }, { type = "matt", colour = [1, 1, 1] }] }"#,
            "a idealised-dove-prism-array surface cannot be a layer",
        ),
        (
            r#"{ type = "idealised-dove-prism-array", period = 0 }"#,
            "expected a positive number",
        ),
        (
            r#"{ type = "complex-metarefraction", function = { type = "multiplication", inwards_factor = [0, 0] } }"#,
            "`inwards_factor` must not be 0",
        ),
        (
            r#"{ type = "complex-metarefraction", function = { type = "julia-set", constant = [0, 0], iterations = 100000 } }"#,
            "is more than 1000",
        ),
        (
            r#"{ type = "complex-metarefraction", function = { type = "tan" } }"#,
            "unknown variant `tan`",
        ),
        (
            r#"{ type = "complex-metarefraction", function = { type = "exp", factor = 2 } }"#,
            "unknown field `factor`",
        ),
        (
            r#"{ type = "ideal-thin-space-plate", centre = [0, 0, 0], distance_vector = [0, 0, 0] }"#,
            "`distance_vector` must not be zero",
        ),
        (
            r#"{ type = "ideal-thin-space-plate", distance_vector = [0, 0, 1] }"#,
            "missing field `centre`",
        ),
        (
            r#"{ type = "layer-stack", layers = [{ type = "ideal-thin-space-plate", centre = [0, 0, 0], distance_vector = [0, 0, 1] }, { type = "matt", colour = [1, 1, 1] }] }"#,
            "a ideal-thin-space-plate surface cannot be a layer",
        ),
        (
            r#"{ type = "space-shifting", image_space_offset = [0, 0] }"#,
            "expected an array of 3 values",
        ),
        (
            r#"{ type = "space-shifting", offset = [0, 0, 1] }"#,
            "unknown field `offset`",
        ),
        (
            r#"{ type = "space-shifting", transmission_coefficient = 1.5 }"#,
            "expected a coefficient between 0 and 1, got 1.5",
        ),
        (
            r#"{ type = "layer-stack", layers = [{ type = "space-shifting" }, { type = "matt", colour = [1, 1, 1] }] }"#,
            "a space-shifting surface cannot be a layer",
        ),
        (
            r#"{ type = "collineation-surface", collineation = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 2, 0]] }"#,
            "must be a non-singular matrix",
        ),
        (
            r#"{ type = "collineation-surface", collineation = [[1, 0, 0], [0, 1, 0], [0, 0, 1]] }"#,
            "expected an array of 4 values, got 3",
        ),
        (
            r#"{ type = "derivative-control", jacobian = [[1, 2], [2, 4]] }"#,
            "must be an invertible 2 × 2 matrix",
        ),
        (
            r#"{ type = "derivative-control", jacobian = [[1, 0], [0, 1]], view_rotation = { eye_position = [0, 0, -5], point_on_plane = [0, 0, 10], plane_normal = [0, 0, 1], rotation_angle_deg = 20 } }"#,
            "give it alone",
        ),
        (
            r#"{ type = "derivative-control", view_rotation = { eye_position = [0, 0, -5], point_on_plane = [0, 0, 10], plane_normal = [0, 0, 1] } }"#,
            "missing field `rotation_angle_deg`",
        ),
        (
            r#"{ type = "derivative-control", pixel_period_u = 0.1 }"#,
            "need pixellated = true",
        ),
        (
            r#"{ type = "derivative-control", inside_direction = [0, 0, 0] }"#,
            "expected a direction, got the zero vector",
        ),
        (
            r#"{ type = "refractive-complex", index_ratio = [0, 0] }"#,
            "`index_ratio` must not be 0",
        ),
        (
            r#"{ type = "complex-metarefraction" }"#,
            "missing field `function`",
        ),
        (
            r#"{ type = "light-ray-field", field = { type = "collimated" } }"#,
            "missing field `direction`",
        ),
        (
            r#"{ type = "light-ray-field", angular_fuzziness_deg = 0 }"#,
            "expected a positive number",
        ),
        (
            r#"{ type = "layer-stack", layers = [{ type = "light-ray-field" }, { type = "matt", colour = [1, 1, 1] }] }"#,
            "a light-ray-field surface cannot be a layer",
        ),
        (
            r#"{ type = "idealised-dove-prism-array", inversion_direction = [0, 0, 0] }"#,
            "expected a direction, got the zero vector",
        ),
        (
            r#"{ type = "ray-rotating", axis = [0, 0, 0] }"#,
            "expected a direction, got the zero vector",
        ),
        (
            r#"{ type = "ray-rotating", basis = "local" }"#,
            "none is given",
        ),
        (
            r#"{ type = "lorentz-window", beta = [0, 0, 1] }"#,
            "magnitude below 1",
        ),
        (
            r#"{ type = "phase-hologram", phase = { type = "quadratic", focal_length = 0 } }"#,
            "non-zero",
        ),
        (
            r#"{ type = "teleporting", destination = "nowhere" }"#,
            "no object is named 'nowhere'",
        ),
        (
            r#"{ type = "teleporting", destination = "red cylinder 0,0", angular_error_deg = 200 }"#,
            "more than 180",
        ),
        (
            r#"{ type = "teleporting", destination = "red cylinder 0,0", teleportation = "holographic", positional_error = 0.1 }"#,
            "apply to perfect teleportation only",
        ),
        (
            r#"{ type = "teleporting", destination = "red cylinder 0,0", reflection = 0.5 }"#,
            "applies to teleportation = \"holographic\" only",
        ),
        (
            r#"{ type = "teleporting", destination = "red cylinder 0,0", teleportation = "quantum" }"#,
            "unknown variant `quantum`",
        ),
        (
            r#"{ type = "phase-conjugating", transmission = 0.5 }"#,
            "a reflective one has a reflection_coefficient, not a transmission_coefficient",
        ),
        (
            r#"{ type = "phase-conjugating", mode = "transmissive", reflection_coefficient = 0.5 }"#,
            "has a transmission_coefficient, not a reflection_coefficient",
        ),
        (
            r#"{ type = "phase-conjugating", mode = "sideways" }"#,
            "unknown variant `sideways`",
        ),
        (
            r#"{ type = "phase-hologram", phase = { type = "lens", focal_length = 0 } }"#,
            "non-zero",
        ),
        (
            r#"{ type = "ray-rotating", reflection_coefficient = 1.5 }"#,
            "between 0 and 1",
        ),
    ] {
        on_line_6(surface, message);
    }

    let two = "[[object]]\nname = \"exit\"\nshape = { type = \"sphere\", centre = [0, 0, 20], radius = 1 }\nsurface = { type = \"transparent\" }\n";
    let e = error(&window_scene(
        r#"{ type = "teleporting", destination = "exit" }"#,
        &format!("{two}{two}"),
    ));
    assert!(
        e.starts_with("s.toml:6:") && e.contains("2 objects are named 'exit'"),
        "{e}"
    );
    // Two teleporting objects of one name cannot be told apart.
    let teleporter = |to: &str| {
        format!(
            "[[object]]\nname = \"tp\"\nshape = {{ type = \"disc\", centre = [0, 0, 5], normal = [0, 0, 1], radius = 1 }}\nsurface = {{ type = \"teleporting\", destination = \"{to}\" }}\n"
        )
    };
    let e = error(&format!(
        "{}{}{two}",
        teleporter("exit"),
        teleporter("exit")
    ));
    assert!(
        e.contains("another teleporting object is also named 'tp'"),
        "{e}"
    );
    let arrayed = format!("{two}array = {{ vectors = [[3, 0, 0]], counts = [2] }}\n");
    let e = error(&window_scene(
        r#"{ type = "teleporting", destination = "exit" }"#,
        &arrayed,
    ));
    assert!(e.contains("repeated in an array"), "{e}");

    let e = error(
        "studio = \"lattice\"\n[[object]]\nshape = { type = \"cylinder\", start = [0, 0, 5], end = [0, 0, 6], radius = 1 }\nsurface = { type = \"phase-hologram\", phase = { type = \"linear\", gradient = [0.1, 0] } }\n",
    );
    assert!(
        e.starts_with("s.toml:4:")
            && e.contains("needs surface coordinates on every part")
            && e.contains("open = true"),
        "{e}"
    );
    let e = error(
        "studio = \"lattice\"\n[[object]]\nshape = { type = \"sphere\", centre = [0, 0, 5], radius = 1 }\nsurface = { type = \"derivative-control\", pixellated = true }\n",
    );
    assert!(
        e.starts_with("s.toml:4:") && e.contains("needs a flat shape"),
        "{e}"
    );
    let e = error("studio = \"lattice\"\n[window]\nsurface = { type = \"mirror\" }\n");
    assert!(
        e.starts_with("s.toml:2:") && e.contains("metatoy-window"),
        "{e}"
    );
    let e = error(
        "studio = \"lattice\"\n[[object]]\nshape = { type = \"sphere\", centre = [0, 0, 5], radius = 1 }\nsurface = { type = \"chequerboard\", surfaces = [{ type = \"teleporting\", destination = \"x\" }, { type = \"mirror\" }] }\n",
    );
    assert!(e.contains("cannot be a chequerboard tile"), "{e}");
}

/// Fig. 14(a): behind the n = 10 metric window, rays from the camera transmit only within
/// asin(1/10) = 5.74° of the window normal; outside that circle they are totally internally
/// reflected. A magenta wall behind the camera and a green one behind the window tell the two
/// apart: window pixels must be magenta exactly outside the circle (up to a pixel's width at the
/// boundary) and green inside it. With transmission 0.5, the green is halved but the magenta
/// seen by total internal reflection keeps its full brightness (as in Dr TIM), unless a
/// reflection coefficient is given.
#[test]
fn the_n10_metric_window_shows_the_tir_circle() {
    for (coefficients, reflected) in [
        ("transmission = 0.5", 1.0),
        ("transmission = 0.5, reflection = 0.25", 0.25),
    ] {
        tir_circle(coefficients, reflected);
    }
}

fn tir_circle(coefficients: &str, reflected: f64) {
    let plane = |name: &str, z: f64, normal: f64, colour: &str| {
        format!(
            "[[object]]\nname = \"{name}\"\nshape = {{ type = \"plane\", point = [0, 0, {z}], normal = [0, 0, {normal}], u_direction = [1, 0, 0] }}\nsurface = {{ type = \"constant_colour\", colour = {colour} }}\n"
        )
    };
    let text = format!(
        "studio = \"none\"\n[render]\nwidth = 400\nheight = 300\n[[object]]\nname = \"n = 10 window\"\nshape = {{ type = \"parallelogram\", corner = [-1.5, -0.98, 10], span_u = [3, 0, 0], span_v = [0, 2, 0] }}\nsurface = {{ type = \"metric-interface\", inside = [[100, 0, 0], [0, 100, 0], [0, 0, 100]], {coefficients} }}\n{}{}",
        plane("wall behind the camera", -5.0, 1.0, "[1, 0, 1]"),
        plane("wall behind the window", 30.0, -1.0, "[0, 1, 0]"),
    );
    let d = parse(&text);
    let image = render_description(&d);
    let critical = (0.1f64).asin();
    let pixel = 20f64.to_radians() / 400.0;
    let (mut inside, mut outside, mut wrong) = (0, 0, Vec::new());
    for y in 0..300 {
        for x in 0..400 {
            let (_, dir) = d.camera.chief_ray(400, 300, x as f64, y as f64);
            let dir = dir.normalize();
            // Only pixels that see the pane well inside its frame.
            let at = dir * (10.0 / dir.z);
            if !(at.x.abs() < 1.4 && at.y > -0.9 && at.y < 0.94) {
                continue;
            }
            let angle = dir.z.acos();
            let c = image.pixel(x, y);
            let red = c == reflected * DVec3::new(1.0, 0.0, 1.0);
            assert!(red || c == 0.5 * DVec3::Y, "({x}, {y}) sees {c}");
            if (angle - critical).abs() < 1.5 * pixel {
                continue;
            }
            if angle > critical {
                outside += 1;
            } else {
                inside += 1;
            }
            if red != (angle > critical) {
                wrong.push((x, y, angle.to_degrees(), c));
            }
        }
    }
    assert!(inside > 10_000 && outside > 10_000, "{inside} {outside}");
    assert!(
        wrong.is_empty(),
        "{} pixels on the wrong side of the 5.74° circle, e.g. {:?}",
        wrong.len(),
        &wrong[..wrong.len().min(5)]
    );
}

/// Two windows that undo each other look like one clear window: rotation by 60° then by −60°
/// (a second pane 1e-4 behind the first, so the ray's offset between them is invisible), and a
/// teleporter whose destination is the window itself.
#[test]
fn laws_that_undo_each_other_leave_the_view_unchanged() {
    let second = |surface: &str| {
        format!(
            "[[object]]\nname = \"second pane\"\nshadow_throwing = false\nshape = {{ type = \"parallelogram\", corner = [-1.5, -0.98, 10.0001], span_u = [3, 0, 0], span_v = [0, 2, 0] }}\nsurface = {surface}\n"
        )
    };
    let clear = render_text(&window_scene(
        r#"{ type = "transparent" }"#,
        &second(r#"{ type = "transparent" }"#),
    ));
    let rotated = render_text(&window_scene(
        r#"{ type = "ray-rotating", angle_deg = 60 }"#,
        &second(r#"{ type = "ray-rotating", angle_deg = -60 }"#),
    ));
    // The ray crosses the 1e-4 gap rotated, which moves a few silhouette pixels.
    let moved = differing_by_more_than(&clear, &rotated, 2);
    assert!(moved <= 10, "{moved}");
    let once = render_text(&window_scene(
        r#"{ type = "ray-rotating", angle_deg = 60 }"#,
        &second(r#"{ type = "transparent" }"#),
    ));
    assert!(differing(&clear, &once) > 2000, "the rotation shows");

    let teleported = render_text(&window_scene(
        r#"{ type = "teleporting", destination = "window" }"#,
        "",
    ));
    let plain = render_text(&window_scene(r#"{ type = "transparent" }"#, ""));
    assert!(
        differing(&plain, &teleported) <= 2,
        "{}",
        differing(&plain, &teleported)
    );
}

/// Different laws with the same effect render the same: gCLAs with η = −1, the Veselago
/// metric interface, transmissive phase conjugation and a half turn all reverse the tangential
/// direction; a Lorentz window at rest and a metric interface between equal metrics change
/// nothing.
#[test]
fn equivalent_laws_render_the_same() {
    let gcla = render_text(&window_scene(
        r#"{ type = "gcla", a = [0, 0, 1], u = [1, 0, 0], eta_u = -1, eta_v = -1 }"#,
        "",
    ));
    let veselago = render_text(&window_scene(
        r#"{ type = "metric-interface", refraction = "negative" }"#,
        "",
    ));
    let plain = render_text(&window_scene(r#"{ type = "transparent" }"#, ""));
    assert!(differing(&gcla, &veselago) <= 2);
    assert!(differing(&gcla, &plain) > 2000, "the flip shows");
    // Transmissive phase conjugation, d′ = d∥ − d⊥, reverses the tangential direction too: a
    // half turn about the normal.
    let conjugating = render_text(&window_scene(
        r#"{ type = "phase-conjugating", mode = "transmissive" }"#,
        "",
    ));
    let half_turn = render_text(&window_scene(
        r#"{ type = "ray-rotating", angle_deg = 180 }"#,
        "",
    ));
    assert!(differing(&conjugating, &gcla) <= 2);
    assert!(differing(&conjugating, &half_turn) <= 2);
    for same in [
        r#"{ type = "lorentz-window", beta = [0, 0, 0] }"#,
        r#"{ type = "metric-interface", inside = [[2, 0.3, 0], [0.3, 1, 0], [0, 0, 3]], outside = [[2, 0.3, 0], [0.3, 1, 0], [0, 0, 3]] }"#,
        r#"{ type = "phase-hologram", phase = { type = "linear", gradient = [0, 0] }, transmission = 0.96 }"#,
    ] {
        let image = render_text(&window_scene(same, ""));
        assert!(differing(&image, &plain) <= 2, "{same}");
    }
}

#[test]
fn metatoy_example_scenes_render_without_nan() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    for name in [
        "metatoy-window",
        "fig14a-metric-interface-n10",
        "fig14b-veselago-lens",
        "fig14c-sheared-space",
        "fig15a-metric-bubble",
        "fig15b-minkowski-bubble",
        "gcla-window-eta-minus-1",
        "gcla-window-eta-u-minus-half",
        "phase-hologram-window",
        "ray-flipping-window",
        "lorentz-window",
        "teleporting-window",
    ] {
        let mut d = file::load(&dir.join(format!("{name}.toml"))).unwrap();
        d.render.width = 160;
        d.render.height = 120;
        d.render.spp = 1;
        assert_finite(&render_description(&d), name);
    }
}

/// §4.2: with the same indefinite metric diag(1, 1, −1) on both sides of the window, every ray
/// from the camera (close to the z axis) has dᵀ g d < 0. Allowing the imaginary-optical-path
/// solution passes it straight through (Eq 34 with h = g gives e ∝ d), so the window is clear;
/// refusing it reflects every ray.
#[test]
fn the_imaginary_solution_is_used_only_when_allowed() {
    let minkowski = |allow: bool| {
        render_text(&window_scene(
            &format!(
                "{{ type = \"metric-interface\", inside = [[1, 0, 0], [0, 1, 0], [0, 0, -1]], outside = [[1, 0, 0], [0, 1, 0], [0, 0, -1]], allow_imaginary = {allow} }}"
            ),
            "",
        ))
    };
    let plain = render_text(&window_scene(r#"{ type = "transparent" }"#, ""));
    // Total internal reflection is lossless.
    let mirror = render_text(&window_scene(r#"{ type = "mirror", reflection = 1 }"#, ""));
    let (allowed, refused) = (minkowski(true), minkowski(false));
    assert_finite(&allowed, "allowed");
    assert_finite(&refused, "refused");
    assert!(
        differing(&allowed, &plain) <= 2,
        "{}",
        differing(&allowed, &plain)
    );
    assert!(
        differing(&refused, &mirror) <= 2,
        "{}",
        differing(&refused, &mirror)
    );
    assert!(differing(&allowed, &refused) > 5000);
}

/// A phase-conjugating mirror sends every ray back the way it came, through the camera's
/// pinhole to the opposite side behind it; a plain mirror keeps the ray on its side. With a
/// magenta wall behind the camera on the left (x < 0) and a green one on the right, the right
/// half of a phase-conjugating pane shows magenta and of a mirror pane green.
#[test]
fn a_phase_conjugating_pane_returns_rays_through_the_camera() {
    let view = |surface: &str| {
        let wall = |x0: f64, colour: &str| {
            format!(
                "[[object]]\nshape = {{ type = \"parallelogram\", corner = [{x0}, -100, -5], span_u = [100, 0, 0], span_v = [0, 200, 0] }}\nsurface = {{ type = \"constant_colour\", colour = {colour} }}\n"
            )
        };
        let text = format!(
            "studio = \"none\"\n[render]\nwidth = 80\nheight = 60\n[[object]]\nname = \"pane\"\nshape = {{ type = \"parallelogram\", corner = [-1.5, -0.98, 10], span_u = [3, 0, 0], span_v = [0, 2, 0] }}\nsurface = {surface}\n{}{}",
            wall(-100.0, "[1, 0, 1]"),
            wall(0.0, "[0, 1, 0]"),
        );
        render_text(&text)
    };
    let magenta = DVec3::new(1.0, 0.0, 1.0);
    for (surface, right, left) in [
        (
            r#"{ type = "phase-conjugating", reflection = 1 }"#,
            magenta,
            DVec3::Y,
        ),
        (r#"{ type = "mirror", reflection = 1 }"#, DVec3::Y, magenta),
    ] {
        let image = view(surface);
        // Columns well inside the pane on either side of the centre, the middle row.
        for x in [12, 20, 35] {
            assert_eq!(image.pixel(x, 30), left, "{surface} at column {x}");
            assert_eq!(
                image.pixel(79 - x, 30),
                right,
                "{surface} at column {}",
                79 - x
            );
        }
    }
}

/// A point-to-point imaging hologram moves with its object: a disc at the origin (normal −z)
/// imaging O = (0.2, 0.1, 3) into I = (−0.3, 0, −4), placed by a non-uniform scale [1, 2, 1],
/// a rotation by 30° about y and a translation, images the placed O into the placed I (both
/// worked out here by the maps written out: a straight line stays straight under any affine
/// map, so the imaging does too): every ray from the placed O through the placed disc leaves
/// towards the placed I.
#[test]
fn a_point_to_point_hologram_moves_with_its_object() {
    let d = parse(
        "studio = \"none\"\n[[object]]\nname = \"h\"\nshape = { type = \"disc\", centre = [0, 0, 0], normal = [0, 0, -1], radius = 1 }\nsurface = { type = \"point-to-point-imaging-hologram\", object_position = [0.2, 0.1, 3], image_position = [-0.3, 0, -4] }\ntransform = { scale = [1, 2, 1], rotate = { axis = [0, 1, 0], angle_deg = 30 }, translate = [1, -1, 10] }\n",
    );
    let h = object(&d, "h");
    let (sin, cos) = 30f64.to_radians().sin_cos();
    let place = |p: DVec3| {
        let (x, y, z) = (p.x, 2.0 * p.y, p.z);
        DVec3::new(cos * x + sin * z + 1.0, y - 1.0, -sin * x + cos * z + 10.0)
    };
    let (object_point, image_point) = (
        place(DVec3::new(0.2, 0.1, 3.0)),
        place(DVec3::new(-0.3, 0.0, -4.0)),
    );
    for k in 0..30 {
        let angle = 0.9 * k as f64;
        let q = (0.03 * k as f64) * DVec3::new(angle.cos(), angle.sin(), 0.0);
        let ray = Ray::new(object_point, place(q) - object_point, 0.0);
        let (t, prim) = h
            .shape
            .intersect(ray.origin, ray.direction, 0.0, f64::INFINITY)
            .unwrap();
        let at = Interaction::on(&h.shape, ray, t, prim);
        assert!(at.point().distance(place(q)) < 1e-12);
        let Redirection::Leaves { direction, factor } = h.surface.redirect(&at, &mut |_| {}) else {
            panic!("not transmitted at {q}")
        };
        assert_eq!(factor, glam::DVec3::splat(0.96));
        let along = (image_point - at.point()).dot(direction);
        let miss = (image_point - at.point() - along * direction).length();
        assert!(
            miss < 1e-12 && along > 0.0,
            "at {q}: misses by {miss}, {along}"
        );
    }
}

/// The new holograms' keys and Dr TIM's defaults: a rotationally symmetric phase without keys
/// is Dr TIM's panel's (no gradients, simulated honestly in 8 segments, the first along u);
/// a polynomial's rows are uⁱ's; a lens hologram images P − 2f â into P + 2f â; both
/// imaging holograms transmit Dr TIM's 0.96 and reflect all.
#[test]
fn the_hologram_phases_and_imaging_holograms_are_read_with_dr_tims_defaults() {
    let surface = |s: &str| {
        let text = format!(
            "[[object]]\nname = \"h\"\nshape = {{ type = \"disc\", centre = [0, 0, 5], normal = [0, 0, -1], radius = 1 }}\nsurface = {s}\n"
        );
        object(&parse(&text), "h").surface.clone()
    };
    let phase = |p: &str| match surface(&format!("{{ type = \"phase-hologram\", phase = {p} }}")) {
        Surface::PhaseHologram(h) => h.phase,
        other => panic!("{other:?}"),
    };
    let none = AzimuthalRadial {
        azimuthal_coefficient: 0.0,
        azimuthal_exponent: 0.0,
        radial_coefficient: 0.0,
        radial_exponent: 0.0,
    };
    assert_eq!(
        phase(r#"{ type = "rotationally-symmetric" }"#),
        Phase::RotationallySymmetric(RotationallySymmetricPhase {
            centre: DVec2::ZERO,
            gradients: none,
            sectors: Some(Sectors {
                count: 8,
                direction: 0.0
            }),
        })
    );
    assert_eq!(
        phase(
            r#"{ type = "rotationally-symmetric", centre = [1, 2], azimuthal_coefficient = 0.5, azimuthal_exponent = 2, radial_coefficient = -0.25, radial_exponent = 1, simulate_honestly = false }"#
        ),
        Phase::RotationallySymmetric(RotationallySymmetricPhase {
            centre: DVec2::new(1.0, 2.0),
            gradients: AzimuthalRadial {
                azimuthal_coefficient: 0.5,
                azimuthal_exponent: 2.0,
                radial_coefficient: -0.25,
                radial_exponent: 1.0,
            },
            sectors: None,
        })
    );
    assert_eq!(
        phase(r#"{ type = "azimuthal-pixelated-fresnel-wedge", pixel_size = [0.1, 0.2] }"#),
        Phase::AzimuthalPixelatedFresnelWedge(AzimuthalPixelatedFresnelWedgePhase {
            centre: DVec2::ZERO,
            gradients: none,
            pixel_size: DVec2::new(0.1, 0.2),
        })
    );
    assert_eq!(
        phase(r#"{ type = "polynomial", coefficients = [[1, 2], [3]], centre = [0.5, 0] }"#),
        Phase::Polynomial(PolynomialPhase {
            coefficients: vec![vec![1.0, 2.0], vec![3.0]],
            centre: DVec2::new(0.5, 0.0),
        })
    );
    assert_eq!(
        surface(
            r#"{ type = "lens-hologram", principal_point = [1, 2, 3], optical_axis = [0, 0, 2], focal_length = 1.5 }"#
        ),
        Surface::PointToPointImagingHologram(PointToPointImagingHologram {
            object_position: DVec3::new(1.0, 2.0, 0.0),
            image_position: DVec3::new(1.0, 2.0, 6.0),
            transmission_coefficient: 0.96,
            reflection_coefficient: 1.0,
        })
    );
    assert_eq!(
        surface(
            r#"{ type = "point-to-point-imaging-hologram", object_position = [0, 0, 9], image_position = [0, 0, 1], transmission = 0.5, reflection = 0.25 }"#
        ),
        Surface::PointToPointImagingHologram(PointToPointImagingHologram {
            object_position: DVec3::new(0.0, 0.0, 9.0),
            image_position: DVec3::new(0.0, 0.0, 1.0),
            transmission_coefficient: 0.5,
            reflection_coefficient: 0.25,
        })
    );
}

/// An idealised Dove-prism array's positions are the object's own: a rotation by 90° about z
/// and a shift by (1, 0, 0) take prism 0's centre (0.05, 0, 0) to (1, 0.05, 0) and the
/// inversion direction x to y, keeping the period; a uniform scaling by 2 doubles the period.
/// A non-uniform scaling would not keep the prisms' mirrors mirrors.
#[test]
fn dove_prism_arrays_move_with_their_objects() {
    let text = |transform: &str| {
        format!(
            "studio = \"none\"\n[[object]]\nname = \"d\"\nshape = {{ type = \"disc\", centre = [0, 0, 0], normal = [0, 0, 1], radius = 1 }}\nsurface = {{ type = \"idealised-dove-prism-array\", centre = [0.05, 0, 0], period = 0.2 }}\ntransform = {transform}\n"
        )
    };
    let parsed = file::parse(
        &text("{ rotate = { axis = [0, 0, 1], angle_deg = 90 }, translate = [1, 0, 0] }"),
        "s.toml",
    )
    .unwrap();
    let Surface::IdealisedDovePrismArray(a) = &object(&parsed, "d").surface else {
        panic!()
    };
    assert!((a.centre - DVec3::new(1.0, 0.05, 0.0)).length() < 1e-15);
    assert!((a.inversion_direction - DVec3::Y).length() < 1e-15);
    assert!((a.period - 0.2).abs() < 1e-15);
    let parsed = file::parse(&text("{ scale = [2, 2, 2] }"), "s.toml").unwrap();
    let Surface::IdealisedDovePrismArray(a) = &object(&parsed, "d").surface else {
        panic!()
    };
    assert!((a.period - 0.4).abs() < 1e-15 && (a.centre.x - 0.1).abs() < 1e-15);
    let e = error(&text("{ scale = [1, 2, 1] }"));
    assert!(e.contains("cannot be scaled non-uniformly"), "{e}");
}

/// An ideal thin space plate adds |D| of free space to every ray crossing it, whichever way:
/// through a plate 2 in front of the camera with |D| = 3, a self-luminous chequerboard 5 away
/// looks exactly as one 8 away seen without the plate (each line of sight shifts sideways by
/// 3 tan θ at the plate, as 3 more of travel would move it), from either side of the plate.
#[test]
fn a_space_plate_looks_like_the_space_it_adds() {
    let scene = |camera_z: f64, view: f64, pattern_z: f64, plate: bool| {
        let plate = if plate {
            format!(
                "[[object]]\nname = \"plate\"\nshadow_throwing = false\nshape = {{ type = \"parallelogram\", corner = [-20, -20, {z}], span_u = [40, 0, 0], span_v = [0, 40, 0] }}\nsurface = {{ type = \"ideal-thin-space-plate\", centre = [0, 0, {z}], distance_vector = [0, 0, 3], transmission_coefficient = 1 }}\n",
                z = camera_z + 2.0 * view
            )
        } else {
            String::new()
        };
        format!(
            "studio = \"none\"\n[render]\nwidth = 96\nheight = 72\n[camera]\nposition = [0.3, 0.2, {camera_z}]\nview_direction = [0.1, 0.05, {view}]\nhorizontal_view_angle_deg = 60\n{plate}[[object]]\nname = \"pattern\"\nshape = {{ type = \"plane\", point = [0, 0, {pattern_z}], normal = [0, 0, 1], u_direction = [1, 0, 0] }}\nsurface = {{ type = \"chequerboard\", tile_width = 0.4, surfaces = [{{ type = \"constant-colour\", colour = [1, 0.5, 0] }}, {{ type = \"constant-colour\", colour = [0, 0.2, 1] }}] }}\n"
        )
    };
    for (camera_z, view) in [(0.0, 1.0), (10.0, -1.0)] {
        let with_plate = render_text(&scene(camera_z, view, camera_z + 5.0 * view, true));
        let farther = render_text(&scene(camera_z, view, camera_z + 8.0 * view, false));
        let nearer = render_text(&scene(camera_z, view, camera_z + 5.0 * view, false));
        // Rounding can flip a pixel centre lying on a tile edge.
        assert!(
            differing(&with_plate, &farther) <= 3,
            "{}",
            differing(&with_plate, &farther)
        );
        assert!(differing(&with_plate, &nearer) > 1000);
    }
}

/// A space-shifting plane (Dr TIM's `EditableSpaceShiftingPlane`) shows the space behind it
/// shifted by its image-space offset O: through a sheet 2 in front of the camera, a
/// self-luminous chequerboard 5 away looks exactly as the same chequerboard moved by O seen
/// without the sheet. From the other side (crossing against the sheet's normal) light is
/// shifted by −O, as reversibility demands: a sheet that moves the space behind it away from a
/// camera on one side moves it away from a camera on the other side too.
#[test]
fn a_space_shifting_plane_shows_the_space_behind_it_shifted() {
    let offset = DVec3::new(0.3, -0.2, 1.5);
    let scene = |camera_z: f64, view: f64, pattern: DVec3, sheet: bool| {
        let sheet = if sheet {
            format!(
                "[[object]]\nname = \"sheet\"\nshadow_throwing = false\nshape = {{ type = \"parallelogram\", corner = [-20, -20, {z}], span_u = [40, 0, 0], span_v = [0, 40, 0] }}\nsurface = {{ type = \"space-shifting\", image_space_offset = [{}, {}, {}] }}\n",
                offset.x,
                offset.y,
                offset.z,
                z = camera_z + 2.0 * view
            )
        } else {
            String::new()
        };
        format!(
            "studio = \"none\"\n[render]\nwidth = 96\nheight = 72\n[camera]\nposition = [0.3, 0.2, {camera_z}]\nview_direction = [0.1, 0.05, {view}]\nhorizontal_view_angle_deg = 60\n{sheet}[[object]]\nname = \"pattern\"\nshape = {{ type = \"plane\", point = [{}, {}, {}], normal = [0, 0, 1], u_direction = [1, 0, 0] }}\nsurface = {{ type = \"chequerboard\", tile_width = 0.4, surfaces = [{{ type = \"constant-colour\", colour = [1, 0.5, 0] }}, {{ type = \"constant-colour\", colour = [0, 0.2, 1] }}] }}\n",
            pattern.x, pattern.y, pattern.z
        )
    };
    // The sheet's normal is +z: the camera at z = 0 looks along it, the one at z = 10 against.
    for (camera_z, view, seen_shift) in [(0.0, 1.0, offset), (10.0, -1.0, -offset)] {
        let pattern = DVec3::new(0.0, 0.0, camera_z + 5.0 * view);
        let through_sheet = render_text(&scene(camera_z, view, pattern, true));
        let moved = render_text(&scene(camera_z, view, pattern + seen_shift, false));
        let unmoved = render_text(&scene(camera_z, view, pattern, false));
        // Rounding can flip a pixel centre lying on a tile edge.
        let off = differing(&through_sheet, &moved);
        assert!(off <= 3, "{off} pixels differ");
        assert!(differing(&through_sheet, &unmoved) > 1000);
    }
}

/// A collineation surface moves with its object: the thin-lens collineation of the plane z = 0
/// placed 10 along z is T C T⁻¹, worked out by hand for f = 5 as x′ = 5x/(z − 5),
/// z′ = (15z − 100)/(z − 5) (scenes/collineation-surface.toml's matrix).
#[test]
fn collineation_surfaces_move_with_their_objects() {
    let text = "studio = \"none\"\n[[object]]\nname = \"c\"\nshape = { type = \"plane\", point = [0, 0, 0], normal = [0, 0, 1], u_direction = [1, 0, 0] }\nsurface = { type = \"collineation-surface\", collineation = [[5, 0, 0, 0], [0, 5, 0, 0], [0, 0, 5, 0], [0, 0, 1, 5]] }\ntransform = { translate = [0, 0, 10] }\n";
    let parsed = file::parse(text, "s.toml").unwrap();
    let Surface::CollineationSurface(c) = &object(&parsed, "c").surface else {
        panic!()
    };
    for p in [
        DVec3::new(1.0, 2.0, 3.0),
        DVec3::new(-0.5, 0.2, 12.0),
        DVec3::new(0.3, 0.0, 10.0),
    ] {
        let by_hand = DVec3::new(5.0 * p.x, 5.0 * p.y, 15.0 * p.z - 100.0) / (p.z - 5.0);
        assert!(
            (c.image(p) - by_hand).length() < 1e-12,
            "{p}: {}",
            c.image(p)
        );
    }
}

/// A light-ray field's vortex moves with its object: its m/k is a length (the tilt is
/// (m/k)/r), so a uniform scaling by 2 doubles it, and a mirror turns its sense.
#[test]
fn optical_vortices_scale_and_mirror_with_their_objects() {
    let text = |transform: &str| {
        format!(
            "studio = \"none\"\n[[object]]\nname = \"v\"\nshape = {{ type = \"plane\", point = [0, 0, 0], normal = [0, 0, 1], u_direction = [1, 0, 0] }}\nsurface = {{ type = \"light-ray-field\", field = {{ type = \"optical-vortex\", point = [1, 0, 0], direction = [0, 0, 1], m_over_k = 0.3 }} }}\ntransform = {transform}\n"
        )
    };
    let vortex = |transform: &str| {
        let parsed = file::parse(&text(transform), "s.toml").unwrap();
        let Surface::LightRayField(f) = &object(&parsed, "v").surface else {
            panic!()
        };
        f.field
    };
    assert_eq!(
        vortex("{ scale = [2, 2, 2] }"),
        Field::OpticalVortex {
            point: DVec3::new(2.0, 0.0, 0.0),
            direction: DVec3::Z,
            m_over_k: 0.6
        }
    );
    let Field::OpticalVortex { m_over_k, .. } = vortex("{ scale = [-1, 1, 1] }") else {
        panic!()
    };
    assert_eq!(m_over_k, -0.3);
    let e = error(&text("{ scale = [1, 2, 1] }"));
    assert!(e.contains("cannot be scaled non-uniformly"), "{e}");
}
