//! §3's lenses in scene files and in rendered pictures: the lens surface types and their
//! errors, the closed-form maps against gradient-index integration at image level, Table 1's
//! GGRIN parameters against the named lenses, the invisible core, lenses in arrays, and the
//! warning for a camera inside a lens. (The laws themselves are checked in tests/lenses.rs.)

mod common;

use timbre::render::Image;
use timbre::scene::{SceneDescription, file};
use timbre::surfaces::Surface;
use timbre::surfaces::lenses::{IndexProfile, LensLaw};

use common::images::{differing, parse, render_text};

const LATTICE: &str = "studio = \"lattice\"\n[render]\nwidth = 128\nheight = 96\n";

/// The lattice with one lens object of `surface` on the sphere of radius 1 at (0, 0, 8).
fn lens_scene(surface: &str) -> String {
    format!(
        "{LATTICE}[[object]]\nname = \"lens\"\nshadow_throwing = false\nshape = {{ type = \"sphere\", centre = [0, 0, 8], radius = 1 }}\nsurface = {surface}\n"
    )
}

fn lens_of(d: &SceneDescription) -> &timbre::surfaces::Lens {
    match &d.objects.iter().find(|o| o.name == "lens").unwrap().surface {
        Surface::Lens(l) => l,
        other => panic!("not a lens: {other:?}"),
    }
}

#[test]
fn lens_surfaces_are_read_with_their_parameters_and_defaults() {
    // Dr TIM's `EditableLuneburgLens` as its GUI makes it: no transparent tunnel, index ratio
    // 1, transmission coefficient `DEFAULT_TRANSMISSION_COEFFICIENT`, 0.96.
    let d = parse(&lens_scene(r#"{ type = "luneburg-lens" }"#));
    let l = lens_of(&d);
    assert_eq!(l.law, LensLaw::Luneburg);
    assert_eq!(
        (
            l.invisible_radius,
            l.index_ratio,
            l.transmission_coefficient
        ),
        (0.0, 1.0, 0.96)
    );
    // Dr TIM's GUI's GGRIN lens (radius 1): r = r′ = 1 (in lens radii), φ = 0.
    let d = parse(&lens_scene(r#"{ type = "ggrin-lens" }"#));
    let LensLaw::Ggrin(g) = &lens_of(&d).law else {
        panic!()
    };
    assert_eq!((g.r, g.r_prime, g.phi), (1.0, 1.0, 0.0));

    let d = parse(&lens_scene(
        r#"{ type = "ggrin-lens", r = inf, r_prime = 2.5, phi_deg = 90, invisible_radius = 0.3, index_ratio = 1.5, transmission = 0.9 }"#,
    ));
    let l = lens_of(&d);
    let LensLaw::Ggrin(g) = &l.law else {
        panic!("{:?}", l.law)
    };
    assert_eq!((g.r, g.r_prime), (f64::INFINITY, 2.5));
    assert!((g.phi - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
    assert_eq!(
        (
            l.invisible_radius,
            l.index_ratio,
            l.transmission_coefficient
        ),
        (0.3, 1.5, 0.9)
    );

    for (name, profile) in [
        ("luneburg", IndexProfile::Luneburg),
        ("eaton", IndexProfile::Eaton),
        ("maxwell_fisheye", IndexProfile::MaxwellFisheye),
    ] {
        let d = parse(&lens_scene(&format!(
            r#"{{ type = "{name}_lens", method = "integration" }}"#
        )));
        let LensLaw::GradientIndex(g) = &lens_of(&d).law else {
            panic!("{name}: not integrated")
        };
        assert_eq!(g.profile, profile);
    }

    let d = parse(&lens_scene(
        r#"{ type = "gradient-index-lens", rho = [0, 0.5, 1], n = [1.4, 1.2, 1.1], index_ratio = 2 }"#,
    ));
    let l = lens_of(&d);
    let LensLaw::GradientIndex(g) = &l.law else {
        panic!("{:?}", l.law)
    };
    assert!((g.profile.n(0.5) - 1.2).abs() < 1e-15);
    assert!(
        (l.surface_index() - 2.2).abs() < 1e-15,
        "the profile is scaled by the index ratio"
    );
}

#[test]
fn bad_lens_parameters_are_errors_at_their_line() {
    let cases = [
        (
            r#"{ type = "ggrin-lens", r = 0.5, r_prime = 1, phi_deg = 0 }"#,
            "at least 1",
        ),
        (
            r#"{ type = "ggrin-lens", r = nan, r_prime = 1, phi_deg = 0 }"#,
            "at least 1",
        ),
        (
            r#"{ type = "ggrin-lens", r = 1, r_prime = 1, phi_deg = inf }"#,
            "finite",
        ),
        (
            r#"{ type = "eaton-lens", invisible_radius = 1 }"#,
            "less than 1",
        ),
        (r#"{ type = "eaton-lens", index_ratio = 0 }"#, "positive"),
        (r#"{ type = "eaton-lens", method = "exact" }"#, "mapping"),
        (
            r#"{ type = "ggrin-lens", r = 1, r_prime = 1, phi_deg = 0, method = "integration" }"#,
            "unknown field",
        ),
        (
            r#"{ type = "gradient-index-lens", rho = [0, 0.7, 0.5, 1], n = [1, 1, 1, 1] }"#,
            "increase strictly",
        ),
        (
            r#"{ type = "gradient-index-lens", rho = [0, 1], n = [1] }"#,
            "rho has 2 values but n has 1",
        ),
        (
            r#"{ type = "gradient-index-lens", rho = [0, 0.5], n = [1, 1] }"#,
            "from 0 (the centre) to 1",
        ),
        (
            r#"{ type = "gradient-index-lens", rho = [0, 1], n = [-1, 1] }"#,
            "not a positive number",
        ),
    ];
    for (surface, reason) in cases {
        let text = lens_scene(surface);
        let line = text.lines().position(|l| l.starts_with("surface")).unwrap() + 1;
        let e = file::parse(&text, "s.toml")
            .map(|_| ())
            .unwrap_err()
            .to_string();
        assert!(e.starts_with(&format!("s.toml:{line}:")), "{surface}: {e}");
        assert!(e.contains(reason), "{surface}: {e}");
    }
    // A lens needs a sphere: its centre and radius.
    let text = format!(
        "{LATTICE}[[object]]\nshape = {{ type = \"cylinder\", start = [0, 0, 5], end = [0, 0, 6], radius = 1 }}\nsurface = {{ type = \"luneburg-lens\" }}\n"
    );
    let e = file::parse(&text, "s.toml")
        .map(|_| ())
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("s.toml:7:") && e.contains("needs a sphere"),
        "{e}"
    );
}

#[test]
fn closed_form_lenses_and_their_integrated_profiles_render_the_same_picture() {
    // The three lenses of Fig. 6, each as the paper's map and as its index profile traced by
    // the ray equation: the pictures agree to the 8-bit pixel but for a few rim pixels.
    let scene = |method: &str| {
        let mut text = LATTICE.to_string();
        for (name, centre) in [
            ("luneburg", "[-0.5, -0.3, 6]"),
            ("eaton", "[0, 0.4, 6]"),
            ("maxwell-fisheye", "[0.5, -0.3, 6]"),
        ] {
            text += &format!(
                "[[object]]\nshadow_throwing = false\nshape = {{ type = \"sphere\", centre = {centre}, radius = 0.3 }}\nsurface = {{ type = \"{name}-lens\", method = \"{method}\" }}\n"
            );
        }
        render_text(&text)
    };
    let (mapped, integrated) = (scene("mapping"), scene("integration"));
    let lens_pixels = differing(&mapped, &render_text(LATTICE));
    assert!(lens_pixels > 1500, "the lenses change {lens_pixels} pixels");
    let n = differing(&mapped, &integrated);
    assert!(n <= 10, "{n} of {lens_pixels} lens pixels differ");
}

#[test]
fn ggrin_lenses_with_table_1_parameters_render_as_the_named_lenses() {
    for (named, ggrin) in [
        ("luneburg-lens", "r = inf, r_prime = 1, phi_deg = 180"),
        ("eaton-lens", "r = inf, r_prime = inf, phi_deg = 0"),
        ("maxwell-fisheye-lens", "r = 1, r_prime = 1, phi_deg = 180"),
    ] {
        let a = render_text(&lens_scene(&format!(r#"{{ type = "{named}" }}"#)));
        let b = render_text(&lens_scene(&format!(
            r#"{{ type = "ggrin-lens", {ggrin} }}"#
        )));
        let n = differing(&a, &b);
        assert!(n <= 3, "{named}: {n} pixels differ");
    }
}

#[test]
fn through_the_invisible_core_the_scene_looks_as_if_the_lens_were_not_there() {
    // Camera at the origin, lens of radius 1 at distance 8 with R_t = 0.4: a pixel whose ray
    // passes within 0.4 of the centre sees what it would see without the lens.
    let with = render_text(&lens_scene(
        r#"{ type = "ggrin-lens", r = inf, r_prime = inf, phi_deg = 90, invisible_radius = 0.4, transmission = 1 }"#,
    ));
    let without = render_text(LATTICE);
    let (w, h) = (with.width, with.height);
    // TIM's pinhole: pixel pitch 2 tan(10°)/(w − 1) at distance 1.
    let pitch = 2.0 * 10f64.to_radians().tan() / (w - 1) as f64;
    let (mut core, mut ring) = ((0, 0), (0, 0));
    for y in 0..h {
        for x in 0..w {
            let dx = (x as f64 - (w - 1) as f64 / 2.0) * pitch;
            let dy = (y as f64 - (h - 1) as f64 / 2.0) * pitch;
            // Distance of the pixel's ray from the lens centre (0, 0, 8).
            let b = 8.0 * (dx * dx + dy * dy).sqrt() / (1.0 + dx * dx + dy * dy).sqrt();
            // Equal but for rounding: the ray continues from where it leaves the lens.
            let same = (with.pixel(x, y) - without.pixel(x, y)).abs().max_element() < 1e-9;
            if b < 0.39 {
                core = (core.0 + 1, core.1 + same as usize);
            } else if b > 0.41 && b < 0.99 {
                ring = (ring.0 + 1, ring.1 + same as usize);
            }
        }
    }
    assert!(
        core.0 > 100 && core.1 == core.0,
        "core: {core:?} (pixels, unchanged)"
    );
    assert!(
        ring.1 * 10 < ring.0,
        "the lens outside the core turns rays: {ring:?} (pixels, unchanged)"
    );
}

#[test]
fn a_lens_in_an_array_maps_about_its_own_copy() {
    // One copy of the arrayed lens is where the single lens is; the other is out of view.
    let single = render_text(&format!(
        "{LATTICE}[[object]]\nshadow_throwing = false\nshape = {{ type = \"sphere\", centre = [0.4, 0, 7], radius = 0.6 }}\nsurface = {{ type = \"luneburg-lens\" }}\n"
    ));
    let arrayed = render_text(&format!(
        "{LATTICE}[[object]]\nshadow_throwing = false\nshape = {{ type = \"sphere\", centre = [-5.6, 0, 7], radius = 0.6 }}\nsurface = {{ type = \"luneburg-lens\" }}\narray = {{ vectors = [[6, 0, 0]], counts = [2] }}\n"
    ));
    assert_eq!(differing(&single, &arrayed), 0);
}

#[test]
fn a_camera_inside_a_lens_is_warned_about() {
    let text = format!(
        "{LATTICE}[[object]]\nname = \"big lens\"\nshape = {{ type = \"sphere\", centre = [0, 0, 0.5], radius = 1 }}\nsurface = {{ type = \"luneburg-lens\" }}\n"
    );
    let warnings = parse(&text).warnings();
    assert!(
        warnings
            .iter()
            .any(|w| w.contains("inside lens 'big lens'")),
        "{warnings:?}"
    );
    assert!(
        parse(&lens_scene(r#"{ type = "luneburg-lens" }"#))
            .warnings()
            .is_empty()
    );
}

#[test]
fn a_lens_moving_with_the_camera_charges_its_crossing_time() {
    // A multi-focal lens in the camera frame whose invisible core fills all but a thin rim:
    // rays cross it straight and leave 2·√(R² − b²) further on, as much earlier (TIM's vacuum
    // length), so their events lie on the scene-frame rays they would have followed without
    // the lens and the picture is unchanged. Charging no time would move each by γβ × chord.
    // (The camera moves horizontally: moving up or down, the lens's exit events would lie
    // below the floor in the scene frame, as if the lens cut through it, and the floor would
    // be skipped, rightly.)
    let lens = "[[object]]\nframe = \"camera\"\nshadow_throwing = false\n\
        shape = { type = \"sphere\", centre = [0, 0, 4], radius = 0.95 }\n\
        surface = { type = \"ggrin-lens\", r = inf, r_prime = inf, phi_deg = 90, invisible_radius = 0.999, transmission = 1 }\n";
    let camera = "[camera]\nbeta = [0.3, 0, 0.9]\n";
    let without = render_text(&format!("{LATTICE}{camera}"));
    let with = render_text(&format!("{LATTICE}{camera}{lens}"));
    let n = differing(&with, &without);
    assert!(n <= 40, "{n} pixels differ");
}

#[test]
fn a_lens_as_a_chequerboard_tile_also_needs_a_sphere() {
    let tiles = r#"{ type = "chequerboard", surfaces = [{ type = "matt", colour = [1, 1, 1] }, { type = "eaton-lens" }] }"#;
    let on = |shape: &str| format!("{LATTICE}[[object]]\nshape = {shape}\nsurface = {tiles}\n");
    let e = file::parse(
        &on(r#"{ type = "plane", point = [0, 0, 9], normal = [0, 0, -1] }"#),
        "s.toml",
    )
    .map(|_| ())
    .unwrap_err()
    .to_string();
    assert!(
        e.starts_with("s.toml:7:") && e.contains("needs a sphere"),
        "{e}"
    );
    parse(&on(
        r#"{ type = "sphere", centre = [0, 0, 8], radius = 1 }"#,
    ));
}

#[test]
fn behind_an_index_step_the_core_is_no_longer_an_empty_tunnel() {
    // Fig. 12: with n_surface / n_surrounding = 1.5 rays are refracted at the surface, so even
    // those crossing the invisible core are deviated, like rays through a glass ball.
    let surface = |ratio: f64| {
        format!(
            r#"{{ type = "ggrin-lens", r = inf, r_prime = inf, phi_deg = 90, invisible_radius = 0.4, index_ratio = {ratio}, transmission = 1 }}"#
        )
    };
    let without = render_text(LATTICE);
    let (w, h) = (without.width, without.height);
    let centre = |image: &Image| {
        // The 9 × 9 pixels about the view's centre, all well inside the core.
        (h / 2 - 4..h / 2 + 5)
            .flat_map(|y| (w / 2 - 4..w / 2 + 5).map(move |x| (x, y)))
            .filter(|&(x, y)| {
                (image.pixel(x, y) - without.pixel(x, y))
                    .abs()
                    .max_element()
                    > 1e-9
            })
            .count()
    };
    assert_eq!(centre(&render_text(&lens_scene(&surface(1.0)))), 0);
    let changed = centre(&render_text(&lens_scene(&surface(1.5))));
    assert!(changed > 40, "{changed} of 81 central pixels changed");
}
