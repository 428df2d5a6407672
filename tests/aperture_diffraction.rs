//! The finite-aperture camera's diffraction (Dr TIM's `CircularApertureDiffraction`): what
//! renders show against the Airy pattern's known facts, at rest, moving and in stereo, and the
//! keys' errors, located.
//!
//! The scenes are in metres: an aperture of radius r = 0.1 mm, HeNe light (λ = 632.8 nm), so
//! the first dark ring is at sin θ₁ = j₁,₁ λ / (2π r) = 1.22 λ / (2r) ≈ 3.86 mrad.

mod common;

use std::f64::consts::{PI, TAU};

use common::cli::{assert_refused_at_line, path_str, timbre, write};
use common::images::{parse, render_description, render_text};
use tempfile::TempDir;
use timbre::cameras::aperture_diffraction::{bessel_j0_j1, encircled_energy};
use timbre::embree::Device;
use timbre::render::Image;
use timbre::scene::Scene;
use timbre::stereo::render_stereo;

/// The aperture radius of the scenes.
const R: f64 = 1e-4;
const LAMBDA: f64 = 632.8e-9;
/// The first two zeros of J₁, the Airy pattern's dark rings (Abramowitz & Stegun, Table 9.5),
/// and the shares of its power inside them, 1 − J₀(j)²: the famous 83.8 % and 91.0 %.
const DARK_RINGS: [(f64, f64); 2] = [(3.831_705_970_2, 0.8378), (7.015_586_669_8, 0.9099)];

/// The angle of the Airy pattern's x = 2π r sin θ / λ.
fn angle(x: f64, lambda: f64) -> f64 {
    (x * lambda / (TAU * R)).asin()
}

/// A one-pixel picture (a pixel far smaller than the blur) through the aperture, focused 1 m
/// ahead, of `objects`, with `camera` keys added; `spp` samples.
fn one_pixel(camera: &str, objects: &str, spp: u32) -> String {
    format!(
        "studio = \"none\"\n[render]\nwidth = 1\nheight = 1\nspp = {spp}\n\
         [camera]\ntype = \"finite-aperture\"\nhorizontal_view_angle_deg = 1e-4\n\
         aperture_radius = {R}\nfocus_distance = 1\n{camera}\n{objects}"
    )
}

/// A white disc 1 m ahead, centred on the view direction, of angular radius `rho`.
fn disc(rho: f64) -> String {
    format!(
        "[[object]]\nshape = {{ type = \"disc\", centre = [0, 0, 1], normal = [0, 0, -1], radius = {} }}\n\
         surface = {{ type = \"constant-colour\", colour = [1, 1, 1] }}\n",
        rho.tan()
    )
}

/// The one pixel's brightness.
fn brightness(image: &Image) -> f64 {
    image.pixel(0, 0).x
}

/// 4 standard deviations of a share `p` counted in `n` samples.
fn four_sigma(p: f64, n: u32) -> f64 {
    4.0 * (p * (1.0 - p) / n as f64).sqrt()
}

/// By reciprocity a pixel sees the point-spread function: the one pixel centred on a disc of
/// angular radius θ sees the share of the Airy pattern's power inside θ. At the dark rings that
/// is 83.8 % and 91.0 %; without diffraction, all of it; with λ → 0, all but nothing.
#[test]
fn a_pixel_sees_the_encircled_energy_of_the_airy_pattern() {
    let spp = 20_000;
    for (ring, share) in DARK_RINGS {
        let objects = disc(angle(ring, LAMBDA));
        // Dr TIM's HeNe wavelength is the default.
        let seen = brightness(&render_text(&one_pixel(
            "diffractive_aperture = true",
            &objects,
            spp,
        )));
        assert!(
            (seen - share).abs() < four_sigma(share, spp),
            "inside x = {ring}: {seen}, not {share}"
        );
        let text = one_pixel("diffractive_aperture = false", &objects, spp);
        assert_eq!(brightness(&render_text(&text)), 1.0);
        let text = one_pixel("diffractive_aperture = true\nlambda = 1e-15", &objects, spp);
        assert_eq!(brightness(&render_text(&text)), 1.0);
    }
}

/// A diffracted ray that would be evanescent is lost: black. Inside a white sphere every other
/// ray sees white, so a pixel sees the share of draws with x below 2π r / λ: at λ = 2π r / j₁,₁
/// (a pupil smaller than the wavelength), 83.8 %.
#[test]
fn evanescent_rays_are_black() {
    let spp = 20_000;
    let (ring, share) = DARK_RINGS[0];
    let lambda = TAU * R / ring;
    let sphere = "[[object]]\nshape = { type = \"sphere\", centre = [0, 0, 0], radius = 10 }\n\
                  surface = { type = \"constant-colour\", colour = [1, 1, 1] }\n";
    let seen = brightness(&render_text(&one_pixel(
        &format!("diffractive_aperture = true\nlambda = {lambda}"),
        sphere,
        spp,
    )));
    assert!((seen - share).abs() < four_sigma(share, spp), "{seen}");
}

/// A moving camera diffracts in its own frame, at the pupil, before the Lorentz
/// transformation: moving at β = 0.5 towards a disc whose scene-frame angular radius ρ_s is
/// seen at θ with tan(θ/2) = √((1 − β)/(1 + β)) tan(ρ_s/2) (relativistic aberration), the pixel
/// sees the power inside θ. Had the diffraction happened in the scene frame, it would see the
/// power inside ρ_s instead.
#[test]
fn a_moving_camera_diffracts_in_its_own_frame() {
    let spp = 20_000;
    let beta: f64 = 0.5;
    let (ring, share) = DARK_RINGS[0];
    let theta = angle(ring, LAMBDA);
    let rho = 2.0 * ((theta / 2.0).tan() * ((1.0 + beta) / (1.0 - beta)).sqrt()).atan();
    let in_scene_frame = encircled_energy(TAU * R * rho.sin() / LAMBDA);
    assert!(in_scene_frame - share > 0.05, "{in_scene_frame}");
    let camera = format!("diffractive_aperture = true\nbeta = [0, 0, {beta}]");
    let seen = brightness(&render_text(&one_pixel(&camera, &disc(rho), spp)));
    assert!((seen - share).abs() < four_sigma(share, spp), "{seen}");
}

/// Each eye of a stereo pair diffracts: both converge on the disc and see 83.8 % of the power.
#[test]
fn each_eye_of_a_stereo_pair_diffracts() {
    let spp = 20_000;
    let (ring, share) = DARK_RINGS[0];
    let camera =
        "diffractive_aperture = true\nstereo = \"side-by-side\"\neye_separation = [2e-3, 0, 0]";
    let d = parse(&one_pixel(camera, &disc(angle(ring, LAMBDA)), spp));
    let device = Device::new("").unwrap();
    let scene = Scene::build(&device, &d).unwrap();
    let image = render_stereo(&scene, &d.camera, &d.render, &d.stereo, &|_| {}).unwrap();
    assert_eq!((image.width, image.height), (2, 1));
    for eye in 0..2 {
        let seen = image.pixel(eye, 0).x;
        assert!(
            (seen - share).abs() < four_sigma(share, spp),
            "eye {eye}: {seen}"
        );
    }
}

/// The brightness a pixel sees across the straight edge of a bright half-plane, the edge at
/// the pattern's x = `a` from the pixel's ray (dark side a > 0): the share of the Airy pattern
/// with x cos φ > a, ∫ p(x) acos(a/x)/π dx, p(x) = 2 J₁(x)²/x the radial density (each ring's
/// azimuths uniform), by the trapezoid rule up to x = 400 and the tail beyond, where p averages
/// 2/(πx²) and the half-plane takes half: 1/(400π). (J₁ is tested against tables in the
/// library.)
struct EdgeSpread {
    step: f64,
    density: Vec<f64>,
}

impl EdgeSpread {
    fn new() -> EdgeSpread {
        let step = 0.005;
        let density = (0..=80_000)
            .map(|i| {
                let x = i as f64 * step;
                let (_, j1) = bessel_j0_j1(x);
                if x > 0.0 { 2.0 * j1 * j1 / x } else { 0.0 }
            })
            .collect();
        EdgeSpread { step, density }
    }

    fn share(&self, a: f64) -> f64 {
        let last = self.density.len() - 1;
        let body: f64 = self
            .density
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let x = i as f64 * self.step;
                let weight = if i == 0 || i == last { 0.5 } else { 1.0 };
                let inside = if x == 0.0 {
                    if a < 0.0 { 1.0 } else { 0.0 }
                } else {
                    (a / x).clamp(-1.0, 1.0).acos() / PI
                };
                weight * p * inside
            })
            .sum();
        body * self.step + 1.0 / (PI * last as f64 * self.step)
    }
}

/// A row of pixels across the edge of a bright half-plane 1 m ahead, four pixels to the first
/// dark ring's angle: without diffraction the edge is a sharp step between two pixels; with it
/// the light spreads over pixels as the Airy pattern's edge spread says (each pixel's samples
/// spread uniformly across it); with λ → 0 the row is the sharp one.
#[test]
fn an_edge_blurs_by_the_airy_pattern() {
    let width = 33;
    let pitch = angle(DARK_RINGS[0].0, LAMBDA) / 4.0;
    // The pixel centres span 2 tan(angle/2) (TIM's convention).
    let view_angle = 2.0 * (0.5 * (width - 1) as f64 * pitch).atan();
    let edge = 0.5 * pitch;
    let spp = 4096;
    let text = |camera: &str| {
        format!(
            "studio = \"none\"\n[render]\nwidth = {width}\nheight = 1\nspp = {spp}\n\
             [camera]\ntype = \"finite-aperture\"\nhorizontal_view_angle_deg = {}\n\
             aperture_radius = {R}\nfocus_distance = 1\n{camera}\n\
             [[object]]\nshape = {{ type = \"parallelogram\", corner = [{edge}, -1, 1], span_u = [1, 0, 0], span_v = [0, 2, 0] }}\n\
             surface = {{ type = \"constant-colour\", colour = [1, 1, 1] }}\n",
            view_angle.to_degrees()
        )
    };
    let row = |image: &Image| -> Vec<f64> { (0..width).map(|x| image.pixel(x, 0).x).collect() };
    let sharp = row(&render_text(&text("")));
    let centre = (width / 2) as usize;
    for (k, v) in sharp.iter().enumerate() {
        assert_eq!(*v, if k > centre { 1.0 } else { 0.0 }, "pixel {k}");
    }
    let tiny = row(&render_text(&text(
        "diffractive_aperture = true\nlambda = 1e-15",
    )));
    assert_eq!(tiny, sharp);
    let blurred = row(&render_text(&text("diffractive_aperture = true")));
    let spread = EdgeSpread::new();
    for (k, &seen) in blurred.iter().enumerate().take(centre + 7).skip(centre - 6) {
        // The pixel's samples, uniform across it: the edge at x = a from each.
        let subpixels = 16;
        let expected = (0..subpixels)
            .map(|i| {
                let s = (i as f64 + 0.5) / subpixels as f64 - 0.5;
                let t = (k as f64 - centre as f64 + s) * pitch;
                spread.share(TAU * R * (edge - t) / LAMBDA)
            })
            .sum::<f64>()
            / subpixels as f64;
        assert!(
            (seen - expected).abs() < four_sigma(expected, spp) + 2e-3,
            "pixel {k}: {seen}, not {expected}"
        );
    }
    // Light reaches past the first dark ring's angle into the dark side.
    assert!(blurred[centre - 4] > 0.01, "{blurred:?}");
}

/// The keys' errors, each at its line: diffraction only with a finite aperture, a wavelength
/// only with diffraction, and a positive one.
#[test]
fn bad_diffraction_keys_are_reported_where_they_are() {
    let dir = TempDir::new().unwrap();
    let check = |text: &str, needles: &[&str], line: usize| {
        assert_refused_at_line(dir.path(), text, needles, line)
    };
    let finite = "[camera]\ntype = \"finite-aperture\"\naperture_radius = 1e-4\n";
    check(
        "[camera]\ndiffractive_aperture = true\n",
        &["diffractive_aperture is for the finite-aperture camera"],
        2,
    );
    check(
        "[camera]\ntype = \"orthographic\"\nview_width = 2\n\ndiffractive_aperture = true\n",
        &["diffractive_aperture is for the finite-aperture camera"],
        5,
    );
    check(
        &format!("{finite}lambda = 5e-7\n"),
        &["lambda", "needs diffractive_aperture = true"],
        4,
    );
    check(
        &format!("{finite}diffractive_aperture = true\nlambda = 0\n"),
        &["got 0"],
        5,
    );
    check(
        &format!("{finite}diffractive_aperture = \"yes\"\n"),
        &["expected a boolean"],
        4,
    );
    // Also from the command line.
    let path = write(&dir, "pinhole.toml", "studio = \"empty\"\n");
    timbre(
        dir.path(),
        &[
            "check",
            path_str(&path),
            "--set",
            "camera.diffractive_aperture=true",
        ],
    )
    .assert_bad_input(&["diffractive_aperture is for the finite-aperture camera"]);
    // Off, on any camera, is what every camera does: accepted; switched off explicitly, a
    // wavelength is kept for switching it on again.
    let path = write(&dir, "off.toml", "[camera]\ndiffractive_aperture = false\n");
    timbre(dir.path(), &["check", path_str(&path)]).assert_success();
    let path = write(
        &dir,
        "off-lambda.toml",
        format!("{finite}lambda = 5e-7\ndiffractive_aperture = false\n"),
    );
    timbre(dir.path(), &["check", path_str(&path)]).assert_success();
}

/// `timbre check` says that the aperture diffracts, and with which wavelength.
#[test]
fn the_camera_description_names_the_diffraction() {
    let d = parse("[camera]\naperture_radius = 1e-4\ndiffractive_aperture = true\n");
    assert_eq!(d.camera.diffraction(), Some(632.8e-9));
    let words = d.camera.describe(0).to_string();
    assert!(words.contains("diffracting (lambda = 6.328e-7)"), "{words}");
    let d = parse("[camera]\naperture_radius = 1e-4\n");
    assert_eq!(d.camera.diffraction(), None);
    // The same picture as without the keys when diffraction is off.
    let with = "[camera]\naperture_radius = 0.05\ndiffractive_aperture = false\n[render]\nwidth = 16\nheight = 12\nspp = 2\n";
    let without = "[camera]\naperture_radius = 0.05\n[render]\nwidth = 16\nheight = 12\nspp = 2\n";
    assert_eq!(
        render_description(&parse(with)).pixels,
        render_description(&parse(without)).pixels
    );
}
