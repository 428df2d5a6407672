//! Relativistic cameras (§2): β = 0 is the camera at rest, camera-frame objects and the time
//! along rays, the three shutter models, finite apertures and focus surfaces, orthographic
//! projection.

mod common;

use glam::DVec3;
use timbre::cameras::{Camera, Focus, LensType, Shutter};
use timbre::io::to_rgb8;
use timbre::math::LorentzTransform;
use timbre::render::Image;

use common::images::{
    REFERENCE_FRACTION, REFERENCE_LEVELS, compare_with_reference, differing, parse,
    render_description, render_text, rgb8_differing_by_more_than, studio_reference,
};

const LATTICE: &str = "studio = \"lattice\"\n[render]\nwidth = 160\nheight = 120\n";

#[test]
fn beta_zero_renders_the_camera_at_rest() {
    // Every shutter model and opening time gives exactly the picture of the camera without a
    // velocity (the scene does not change with time); both are rendered here by the same build,
    // so they must agree to the bit.
    let at_rest = to_rgb8(&render_text(LATTICE));
    for shutter in ["entrance-pupil", "detector-plane", "focus-surface"] {
        let text = format!(
            "{LATTICE}[camera]\nbeta = [0, 0, 0]\nshutter = \"{shutter}\"\nshutter_time = -7.5\n"
        );
        let got = to_rgb8(&render_text(&text));
        assert!(got == at_rest, "{shutter}: differs from the camera at rest");
    }
    // The camera at rest is the non-relativistic studio reference (rendered before cameras
    // could move, possibly on another machine: compared within the stated tolerance).
    compare_with_reference(&at_rest, &studio_reference())
        .unwrap_or_else(|e| panic!("at rest: {e}"));
    // A moving camera sees something else, by far more than the tolerance allows.
    let moving = to_rgb8(&render_text(&format!(
        "{LATTICE}[camera]\nbeta = [0, 0, 0.5]\n"
    )));
    let changed = rgb8_differing_by_more_than(&moving, &at_rest, REFERENCE_LEVELS);
    assert!(
        changed > 4 * (160 * 120) / REFERENCE_FRACTION,
        "{changed} pixels changed"
    );
    assert!(compare_with_reference(&moving, &studio_reference()).is_err());
}

#[test]
fn a_camera_moving_forwards_sees_the_lattice_smaller() {
    let lattice_pixels = |beta: f64| {
        let mut d = parse(&format!("{LATTICE}[camera]\nbeta = [0, 0, {beta}]\n"));
        d.render.aovs = true;
        let image = render_description(&d);
        // Objects 0 and 1 are the sky and the floor; the rest are the lattice's cylinders.
        image
            .aovs
            .unwrap()
            .iter()
            .filter(|a| a.object >= 2.0)
            .count()
    };
    let (rest, half, fast) = (
        lattice_pixels(0.0),
        lattice_pixels(0.5),
        lattice_pixels(0.9),
    );
    assert!(
        rest > 2 * half && half > 2 * fast && fast > 0,
        "{rest} {half} {fast}"
    );
    // Moving backwards, the scene ahead looks larger.
    assert!(lattice_pixels(-0.5) > rest);
}

#[test]
fn the_shutter_time_is_where_the_camera_has_moved_to() {
    // Opening the shutter at t_s = 2 (camera frame) is the camera at rest-frame time γ t_s,
    // moved by γ β t_s: the same picture as a camera placed there opening at t = 0.
    let beta = DVec3::new(0.3, 0.0, 0.8);
    let gamma = LorentzTransform::new(beta).unwrap().gamma();
    let shift = 2.0 * gamma * beta;
    let later = render_text(&format!(
        "{LATTICE}[camera]\nposition = [0, 0, -20]\nbeta = [0.3, 0, 0.8]\nshutter_time = 2\n"
    ));
    let moved = render_text(&format!(
        "{LATTICE}[camera]\nposition = [{}, {}, {}]\nbeta = [0.3, 0, 0.8]\n",
        shift.x,
        shift.y,
        shift.z - 20.0
    ));
    let unmoved = render_text(&format!(
        "{LATTICE}[camera]\nposition = [0, 0, -20]\nbeta = [0.3, 0, 0.8]\n"
    ));
    assert!(
        differing(&later, &moved) <= 2,
        "{}",
        differing(&later, &moved)
    );
    assert!(differing(&later, &unmoved) > 500);
}

#[test]
fn the_shutter_model_matters_only_for_a_moving_camera() {
    let image = |beta: &str, shutter: &str| {
        render_text(&format!(
            "{LATTICE}spp = 4\n[camera]\ntype = \"finite-aperture\"\naperture_radius = 0.05\nfocus_distance = 15\nbeta = {beta}\nshutter = \"{shutter}\"\n"
        ))
    };
    let rest = image("[0, 0, 0]", "entrance-pupil");
    for shutter in ["detector-plane", "focus-surface"] {
        assert_eq!(
            differing(&rest, &image("[0, 0, 0]", shutter)),
            0,
            "{shutter}"
        );
    }
    // Moving, the focus-surface shutter starts rays 15 earlier than the entrance pupil's
    // (about γβ·15 ≈ 10 tiles back along z), the detector-plane shutter about 1 later.
    let pupil = image("[0, 0, 0.6]", "entrance-pupil");
    let focus = image("[0, 0, 0.6]", "focus-surface");
    let detector = image("[0, 0, 0.6]", "detector-plane");
    let n = (160 * 120) as usize;
    assert!(differing(&pupil, &focus) > n / 10);
    assert!(differing(&pupil, &detector) > n / 50);
}

/// A finite-aperture camera at (0.2, −0.1, −1) looking along +z, focused 15 ahead, moving.
fn finite_aperture(shutter: Shutter) -> Camera {
    Camera::pinhole(
        DVec3::new(0.2, -0.1, -1.0),
        DVec3::Z,
        DVec3::Y,
        40f64.to_radians(),
    )
    .unwrap()
    .with_aperture(0.3, Focus::Plane { distance: 15.0 })
    .with_shutter(shutter, 0.5, 2.0)
    .with_velocity(LorentzTransform::new(DVec3::new(0.0, 0.0, 0.9)).unwrap())
}

#[test]
fn ray_start_times_follow_the_three_shutter_models() {
    let no_surface = |_: DVec3, _: DVec3| None;
    let (w, h) = (64, 48);
    for (x, y) in [(0.0, 0.0), (31.5, 23.5), (50.2, 7.7)] {
        let camera = finite_aperture(Shutter::EntrancePupil);
        let (centre, chief) = camera.chief_ray(w, h, x, y);
        let chief = chief.normalize();
        // The pixel's image on the focus plane z = −1 + 15, and the pixel 2 behind the pupil.
        let image_point = centre + 15.0 / chief.z * chief;
        let pixel = centre - 2.0 / chief.z * chief;
        for pupil in [[0.0, 0.0], [0.3, 0.1], [0.99, 0.75]] {
            let times: Vec<f64> = [
                Shutter::EntrancePupil,
                Shutter::FocusSurface,
                Shutter::DetectorPlane(LensType::IdealLens),
            ]
            .into_iter()
            .map(|s| {
                let ray = finite_aperture(s).ray(w, h, (x, y), pupil, &no_surface);
                let e = ray.origin;
                // E lies on the pupil disk, and the ray heads for the pixel's image.
                assert!((e.z - centre.z).abs() < 1e-12);
                assert!((e - centre).length() <= 0.3 + 1e-12);
                let to_image = image_point - e;
                assert!(to_image.normalize().dot(ray.direction) > 1.0 - 1e-12);
                ray.time
            })
            .collect();
            let e = finite_aperture(Shutter::EntrancePupil)
                .ray(w, h, (x, y), pupil, &no_surface)
                .origin;
            let ie = (image_point - e).length();
            let ip = (image_point - pixel).length();
            assert_eq!(times[0], 0.5, "entrance pupil: t_s");
            assert!(
                (times[1] - (0.5 - ie)).abs() < 1e-12,
                "focus surface: t_s − |I − E|"
            );
            assert!(
                (times[2] - (0.5 + ip - ie)).abs() < 1e-12,
                "detector: t_s + |I − P| − |I − E|"
            );
        }
    }
}

#[test]
fn a_focus_surface_plane_focuses_like_the_focus_distance() {
    let camera = "[camera]\ntype = \"finite-aperture\"\naperture_radius = 0.2\n";
    let by_distance = render_text(&format!("{LATTICE}spp = 8\n{camera}focus_distance = 20\n"));
    let by_surface = render_text(&format!(
        "{LATTICE}spp = 8\n{camera}focus_surface = [{{ type = \"plane\", point = [0, 0, 20], normal = [0, 0, -1] }}]\n"
    ));
    assert!(
        differing(&by_distance, &by_surface) <= 10,
        "{}",
        differing(&by_distance, &by_surface)
    );
    let elsewhere = render_text(&format!("{LATTICE}spp = 8\n{camera}focus_distance = 10\n"));
    assert!(differing(&by_distance, &elsewhere) > 1000);
}

/// Width in pixels over which row `y` changes from the background to a thin vertical bar, as
/// the number of pixels strictly between 5% and 95% of the full contrast.
fn edge_width(image: &Image, y: u32) -> usize {
    let row: Vec<f64> = (0..image.width).map(|x| image.pixel(x, y).x).collect();
    let (lo, hi) = row
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(l, h), &v| (l.min(v), h.max(v)));
    row.iter()
        .filter(|&&v| v > lo + 0.05 * (hi - lo) && v < lo + 0.95 * (hi - lo))
        .count()
}

#[test]
fn a_finite_aperture_blurs_what_is_not_in_focus() {
    // A white bar on black, 12 ahead; the camera focuses at 12 or at 6.
    let scene = |focus: f64| {
        render_text(&format!(
            "studio = \"none\"\n[render]\nwidth = 80\nheight = 20\nspp = 64\n\
             [camera]\ntype = \"finite-aperture\"\naperture_radius = 0.2\nfocus_distance = {focus}\n\
             [[light]]\ntype = \"ambient\"\ncolour = [1, 1, 1]\n\
             [[object]]\nshape = {{ type = \"parallelogram\", corner = [-0.3, -5, 12], span_u = [0.6, 0, 0], span_v = [0, 10, 0] }}\n\
             surface = {{ type = \"constant_colour\", colour = [1, 1, 1] }}\n"
        ))
    };
    let sharp = edge_width(&scene(12.0), 10);
    let blurred = edge_width(&scene(6.0), 10);
    assert!(sharp <= 4, "in focus: {sharp} pixels of edge");
    assert!(
        blurred >= 4 * sharp.max(2),
        "out of focus: {blurred} (in focus {sharp})"
    );
}

#[test]
fn objects_moving_with_the_camera_look_the_same_at_any_speed() {
    // A matt ball 3 ahead in the camera frame, with the lattice behind.
    let with = |beta: &str| {
        let mut d = parse(&format!(
            "{LATTICE}[camera]\nbeta = {beta}\n[[object]]\nname = \"ball\"\nframe = \"camera\"\n\
             shape = {{ type = \"sphere\", centre = [0.1, 0, 3], radius = 0.1 }}\n\
             surface = {{ type = \"shiny\", colour = [1, 0.5, 0] }}\n"
        ));
        d.render.aovs = true;
        render_description(&d)
    };
    let (rest, fast) = (with("[0, 0, 0]"), with("[0, 0, 0.95]"));
    let (ra, fa) = (rest.aovs.as_ref().unwrap(), fast.aovs.as_ref().unwrap());
    let mut ball_pixels = 0;
    for k in 0..rest.pixels.len() {
        // The ball is object 50, after the sky, the floor and 48 cylinders.
        let is_ball = ra[k].object == 50.0;
        assert_eq!(is_ball, fa[k].object == 50.0, "pixel {k}");
        if is_ball {
            ball_pixels += 1;
            assert_eq!(rest.pixels[k], fast.pixels[k], "pixel {k}");
        }
    }
    assert!(ball_pixels > 50, "{ball_pixels}");
    // ... while the scene behind it changes.
    assert!(differing(&rest, &fast) > 1000);
}

#[test]
fn a_clear_window_moving_with_the_camera_changes_nothing() {
    // A window of transmission 1 in the camera frame, 2 ahead: rays pass it and are transformed
    // into the scene frame where they leave it, 2 further and 2 earlier. That event lies on the
    // same scene-frame ray as the pupil's, so the picture is unchanged; without the time
    // bookkeeping it would be shifted by γβ·2 ≈ 6.
    let window = "[[object]]\nframe = \"camera\"\nshadow_throwing = false\n\
        shape = { type = \"parallelogram\", corner = [-5, -5, 2], span_u = [10, 0, 0], span_v = [0, 10, 0] }\n\
        surface = { type = \"transparent\", transmission = 1 }\n";
    let camera = "[camera]\nbeta = [0.2, 0.1, 0.9]\n";
    let without = render_text(&format!("{LATTICE}{camera}"));
    let with = render_text(&format!("{LATTICE}{camera}{window}"));
    assert!(
        differing(&with, &without) <= 3,
        "{}",
        differing(&with, &without)
    );
}

#[test]
fn an_orthographic_camera_sees_sizes_independent_of_distance() {
    let ball_pixels = |z: f64| {
        let mut d = parse(&format!(
            "studio = \"none\"\n[render]\nwidth = 100\nheight = 100\n\
             [camera]\ntype = \"orthographic\"\nview_width = 4\n\
             [[light]]\ntype = \"ambient\"\ncolour = [1, 1, 1]\n\
             [[object]]\nshape = {{ type = \"sphere\", centre = [0.5, 0, {z}], radius = 1 }}\n\
             surface = {{ type = \"matt\", colour = [1, 1, 1] }}\n"
        ));
        d.render.aovs = true;
        let image = render_description(&d);
        image
            .aovs
            .unwrap()
            .iter()
            .filter(|a| a.object == 0.0)
            .count()
    };
    let (near, far) = (ball_pixels(5.0), ball_pixels(500.0));
    // πr² in pixels: the pitch is 4/99 per pixel.
    let expected = std::f64::consts::PI / (4.0f64 / 99.0).powi(2);
    assert_eq!(near, far);
    assert!(
        (near as f64 - expected).abs() < 0.02 * expected,
        "{near} {expected}"
    );
}

#[test]
fn an_orthographic_camera_moving_along_its_rays_sees_what_it_sees_at_rest() {
    // Eq 4 leaves directions along β unchanged and Eq 1 leaves the pupil plane (perpendicular
    // to β, at t = 0) in place, so parallel rays along β are the same rays in both frames; a
    // pinhole camera's oblique rays are aberrated.
    let orthographic = |beta: &str| {
        render_text(&format!(
            "{LATTICE}[camera]\ntype = \"orthographic\"\nposition = [0, 0.2, 0]\nview_width = 3\nbeta = {beta}\n"
        ))
    };
    let rest = orthographic("[0, 0, 0]");
    assert_eq!(differing(&rest, &orthographic("[0, 0, 0.9]")), 0);
    // Moving sideways tilts every ray the same way: a different picture.
    assert!(differing(&rest, &orthographic("[0.5, 0, 0]")) > 1000);
}
