//! Relativistic photography beyond the paper's three shutters (issue 40): the Galilean
//! transformation, Dr TIM's arbitrary-plane and fixed-point-surface shutters and the
//! detector plane's lens types, and the Doppler shift and headlight effect.

mod common;

use glam::DVec3;
use timbre::cameras::{Camera, Focus, LensType, Shutter, Transformation};
use timbre::io::to_rgb8;
use timbre::math::LorentzTransform;
use timbre::scene::file;

use common::images::{parse, render_text};

const NO_SURFACE: &dyn Fn(DVec3, DVec3) -> Option<f64> = &|_, _| None;

/// A finite-aperture camera at (0.2, −0.1, −1) looking along +z, focused 15 ahead, the
/// detector 2 behind, moving at β.
fn camera(shutter: Shutter, beta: DVec3) -> Camera {
    Camera::pinhole(
        DVec3::new(0.2, -0.1, -1.0),
        DVec3::Z,
        DVec3::Y,
        40f64.to_radians(),
    )
    .unwrap()
    .with_aperture(0.3, Focus::Plane { distance: 15.0 })
    .with_shutter(shutter, 0.5, 2.0)
    .with_velocity(LorentzTransform::new(beta).unwrap())
}

const SAMPLES: [((f64, f64), [f64; 2]); 4] = [
    ((0.0, 0.0), [0.3, 0.1]),
    ((31.5, 23.5), [0.0, 0.0]),
    ((50.2, 7.7), [0.99, 0.75]),
    ((12.0, 40.0), [0.5, 0.5]),
];

/// Classical aberration by adding velocities: a pinhole camera moving at β along its view
/// direction z sees light from a point at the scene-frame angle θ to z with velocity
/// −(sin θ, 0, cos θ) − (0, 0, β) in its own frame, i.e. at tan θ_c = sin θ / (cos θ + β).
#[test]
fn a_galilean_camera_sees_by_adding_velocities() {
    let beta = 0.7;
    let camera = Camera::pinhole(DVec3::ZERO, DVec3::Z, DVec3::Y, 90f64.to_radians())
        .unwrap()
        .with_velocity(LorentzTransform::new(DVec3::new(0.0, 0.0, beta)).unwrap())
        .with_transformation(Transformation::Galileo);
    let (w, h) = (101, 11);
    for x in [50.0, 60.0, 75.5, 99.0] {
        let ray = camera.ray(w, h, (x, 5.0), [0.0, 0.0], NO_SURFACE);
        let theta_c = ray.direction.x.atan2(ray.direction.z);
        let scene = camera.to_scene_frame(&ray);
        let theta = scene.direction.x.atan2(scene.direction.z);
        assert!(
            (theta_c.tan() - theta.sin() / (theta.cos() + beta)).abs() < 1e-12,
            "x = {x}: θ_c = {theta_c}, θ = {theta}"
        );
        assert!(theta >= theta_c, "the scene looks drawn towards the motion");
        // Time is absolute: the ray leaves the pinhole at t_s = 0, where the camera is at 0.
        assert_eq!((scene.origin, scene.time), (DVec3::ZERO, 0.0));
    }
    // The same camera by the Lorentz transformation sees otherwise (cos θ′ formula, Eq 4).
    let lorentz = camera.clone().with_transformation(Transformation::Lorentz);
    let ray = lorentz.ray(w, h, (75.5, 5.0), [0.0, 0.0], NO_SURFACE);
    let (g, l) = (
        camera.to_scene_frame(&ray).direction,
        lorentz.to_scene_frame(&ray).direction,
    );
    assert!((g - l).length() > 0.05);
}

#[test]
fn a_galilean_camera_starts_its_rays_where_it_has_moved_to() {
    // Entrance-pupil shutter at t_s = 0.5: the pupil point E is at E + β t_s at t_s.
    let beta = DVec3::new(0.1, 0.0, 0.6);
    let c = camera(Shutter::EntrancePupil, beta).with_transformation(Transformation::Galileo);
    for (pixel, pupil) in SAMPLES {
        let ray = c.ray(64, 48, pixel, pupil, NO_SURFACE);
        let scene = c.to_scene_frame(&ray);
        assert!((scene.origin - (ray.origin + 0.5 * beta)).length() < 1e-15);
        assert_eq!(scene.time, 0.5);
    }
}

/// The point where the backwards-traced camera-frame ray from E meets the plane through
/// `point` with normal `n`, found by solving (E + s d − point)·n = 0, and its distance s.
fn meets_plane(origin: DVec3, d: DVec3, point: DVec3, n: DVec3) -> f64 {
    (point - origin).dot(n) / d.dot(n)
}

#[test]
fn the_light_crosses_an_arbitrary_shutter_plane_at_the_opening_time() {
    // A tilted plane ahead of the camera and one behind it (inside the camera body).
    for (point, normal) in [
        (DVec3::new(0.0, 0.0, 3.0), DVec3::new(0.2, -0.3, 1.0)),
        (DVec3::new(0.0, 0.0, -1.5), DVec3::new(0.0, 0.1, 1.0)),
    ] {
        let n = normal.normalize();
        let c = camera(Shutter::ArbitraryPlane { point, normal: n }, DVec3::Z * 0.8);
        for (pixel, pupil) in SAMPLES {
            let ray = c.ray(64, 48, pixel, pupil, NO_SURFACE);
            let s = meets_plane(ray.origin, ray.direction, point, n);
            // Traced backwards, the ray's time falls by the distance: at the plane it is t_s.
            assert!(
                (ray.time - s - 0.5).abs() < 1e-12,
                "{pixel:?}: {}",
                ray.time - s
            );
        }
    }
}

/// An arbitrary shutter plane through the entrance pupil, perpendicular to the view, is the
/// entrance-pupil shutter: every ray leaves the pupil at the opening time, t_s = 0.5.
#[test]
fn an_arbitrary_shutter_plane_in_the_pupil_is_the_entrance_pupil_shutter() {
    let pupil = camera(Shutter::EntrancePupil, DVec3::Z * 0.8);
    let plane = camera(
        Shutter::ArbitraryPlane {
            point: DVec3::new(0.2, -0.1, -1.0),
            normal: DVec3::Z,
        },
        DVec3::Z * 0.8,
    );
    for (pixel, sample) in SAMPLES {
        let (a, b) = (
            pupil.ray(64, 48, pixel, sample, NO_SURFACE),
            plane.ray(64, 48, pixel, sample, NO_SURFACE),
        );
        assert_eq!(a.time, 0.5);
        assert!((b.time - 0.5).abs() < 1e-15, "{pixel:?}: {}", b.time);
        assert_eq!((a.origin, a.direction), (b.origin, b.direction));
    }
}

#[test]
fn the_detector_planes_lens_hologram_times_rays_from_the_pixel() {
    let c = camera(
        Shutter::DetectorPlane(LensType::LensHologram),
        DVec3::Z * 0.8,
    );
    for (pixel, pupil) in SAMPLES {
        let (centre, chief) = c.chief_ray(64, 48, pixel.0, pixel.1);
        let chief = chief.normalize();
        // The pixel, 2 behind the pupil on the chief ray.
        let p = centre - 2.0 / chief.z * chief;
        let ray = c.ray(64, 48, pixel, pupil, NO_SURFACE);
        assert!((ray.time - (0.5 + (ray.origin - p).length())).abs() < 1e-12);
    }
}

/// The fixed-point-surface shutter keeps the focus plane in place: the scene-frame ray of
/// every sample passes through the pixel's image I, found in the camera frame.
#[test]
fn the_fixed_point_surface_shutter_leaves_the_focus_plane_in_place() {
    let c = camera(Shutter::FixedPointSurface, DVec3::new(0.3, 0.2, 0.85));
    for (pixel, pupil) in SAMPLES {
        let (centre, chief) = c.chief_ray(64, 48, pixel.0, pixel.1);
        let image = centre + 15.0 / chief.normalize().z * chief.normalize();
        let scene = c.to_scene_frame(&c.ray(64, 48, pixel, pupil, NO_SURFACE));
        let off_line = (image - scene.origin).reject_from_normalized(scene.direction);
        assert!(off_line.length() < 1e-9, "{pixel:?}: {off_line}");
    }
    // Another shutter does not.
    let c = camera(Shutter::FocusSurface, DVec3::new(0.3, 0.2, 0.85));
    let (centre, chief) = c.chief_ray(64, 48, 10.0, 10.0);
    let image = centre + 15.0 / chief.normalize().z * chief.normalize();
    let scene = c.to_scene_frame(&c.ray(64, 48, (10.0, 10.0), [0.2, 0.2], NO_SURFACE));
    assert!(
        (image - scene.origin)
            .reject_from_normalized(scene.direction)
            .length()
            > 1.0
    );
}

/// D = γ(1 + β cos θ′) in terms of the scene-frame angle θ′ between β and the backwards ray
/// equals 1/(γ(1 − β cos θ)) in terms of the camera-frame angle θ: the photon's frequency
/// seen by the camera, from the two frames' sides.
#[test]
fn the_doppler_factor_agrees_in_both_frames() {
    let beta = 0.6;
    let gamma = 1.25;
    let c = Camera::pinhole(DVec3::ZERO, DVec3::Z, DVec3::Y, 120f64.to_radians())
        .unwrap()
        .with_velocity(LorentzTransform::new(DVec3::new(0.0, 0.0, beta)).unwrap())
        .with_doppler(true);
    for x in [0.0, 20.0, 50.0, 77.7, 100.0] {
        let ray = c.ray(101, 3, (x, 1.0), [0.0, 0.0], NO_SURFACE);
        let scene = c.to_scene_frame(&ray);
        let from_scene = gamma * (1.0 + beta * scene.direction.z);
        let from_camera = 1.0 / (gamma * (1.0 - beta * ray.direction.z));
        let d = c.doppler_factor(scene.direction);
        assert!(
            (d - from_scene).abs() < 1e-14 && (d - from_camera).abs() < 1e-12,
            "{x}"
        );
    }
    // Straight ahead: √((1 + β)/(1 − β)) = 2, a blue shift.
    assert!((c.doppler_factor(DVec3::Z) - 2.0).abs() < 1e-15);
}

const WALL: &str = r#"studio = "none"
[render]
width = 9
height = 9
spp = 1
[[object]]
name = "white wall"
shape = { type = "plane", point = [0, 0, 10], normal = [0, 0, -1] }
surface = { type = "constant-colour", colour = [0.1, 0.1, 0.1] }
"#;

/// A camera moving at β = 0.6 towards a wall that glows white sees it Doppler-shifted by
/// D = 2 straight ahead: still white (a flat spectrum), D³ = 8 times as bright.
#[test]
fn a_camera_moving_towards_a_white_wall_sees_it_brighter_by_d_cubed() {
    let at_rest = render_text(WALL);
    let moving = render_text(&format!(
        "{WALL}[camera]\nhorizontal_view_angle_deg = 10\nbeta = [0, 0, 0.6]\ndoppler = true\n"
    ));
    let centre = (4 * 9 + 4) as usize;
    let (a, b) = (at_rest.pixels[centre], moving.pixels[centre]);
    assert!((b - 8.0 * a).length() < 1e-6, "{a} → {b}");
    // Without the option the wall looks as bright as at rest.
    let plain = render_text(&format!("{WALL}[camera]\nbeta = [0, 0, 0.6]\n"));
    assert!((plain.pixels[centre] - a).length() < 1e-12);
}

#[test]
fn doppler_at_rest_changes_nothing_to_the_bit() {
    let lattice = "studio = \"lattice\"\n[render]\nwidth = 80\nheight = 60\n";
    let plain = to_rgb8(&render_text(lattice));
    let doppler = to_rgb8(&render_text(&format!(
        "{lattice}[camera]\nbeta = [0, 0, 0]\ndoppler = true\n"
    )));
    assert!(plain == doppler);
}

#[test]
fn the_scene_file_reads_the_options() {
    let d = parse(
        "[camera]\nbeta = [0, 0, 0.5]\ntransformation = \"galileo\"\nshutter = \"arbitrary-plane\"\nshutter_plane_point = [0, 0, 2]\nshutter_plane_normal = [0, 0, 4]\n",
    );
    assert_eq!(d.camera.transformation(), Transformation::Galileo);
    assert_eq!(
        d.camera.shutter().0,
        Shutter::ArbitraryPlane {
            point: DVec3::new(0.0, 0.0, 2.0),
            normal: DVec3::Z
        }
    );
    // Dr TIM's GUI's defaults: the plane through (0, 0, 0) with normal (0, 0, 1); an ideal
    // lens; the Lorentz transformation; no Doppler shift.
    let d = parse("[camera]\nbeta = [0, 0, 0.5]\nshutter = \"arbitrary-plane\"\n");
    assert_eq!(
        d.camera.shutter().0,
        Shutter::ArbitraryPlane {
            point: DVec3::ZERO,
            normal: DVec3::Z
        }
    );
    let d = parse("[camera]\nbeta = [0, 0, 0.5]\nshutter = \"detector-plane\"\n");
    assert_eq!(
        d.camera.shutter().0,
        Shutter::DetectorPlane(LensType::IdealLens)
    );
    assert_eq!(d.camera.transformation(), Transformation::Lorentz);
    assert!(!d.camera.doppler());
    let d = parse(
        "[camera]\nbeta = [0, 0, 0.5]\nshutter = \"detector-plane\"\nlens_type = \"lens-hologram\"\n",
    );
    assert_eq!(
        d.camera.shutter().0,
        Shutter::DetectorPlane(LensType::LensHologram)
    );
}

#[test]
fn options_that_would_do_nothing_are_refused() {
    for (text, message) in [
        (
            "doppler = true\ntransformation = \"galileo\"",
            "needs the Lorentz transformation",
        ),
        (
            "lens_type = \"lens-hologram\"",
            "lens_type is for the detector-plane shutter",
        ),
        (
            "shutter = \"focus-surface\"\nshutter_plane_point = [0, 0, 1]",
            "shutter_plane_point is for the arbitrary-plane shutter",
        ),
        (
            "shutter_plane_normal = [0, 0, 1]",
            "shutter_plane_normal is for the arbitrary-plane shutter",
        ),
        (
            "shutter = \"fixed-point-surface\"\nshutter_time = 1",
            "has no shutter_time",
        ),
        (
            "shutter = \"fixed-point-surface\"\ntransformation = \"galileo\"",
            "needs the Lorentz transformation",
        ),
        (
            "shutter = \"fixed-point-surface\"\nfocus_surface = [{ type = \"sphere\", centre = [0, 0, 0], radius = 5 }]",
            "needs a focus plane",
        ),
        (
            "shutter_plane_normal = [0, 0, 0]\nshutter = \"arbitrary-plane\"",
            "zero",
        ),
        ("transformation = \"newton\"", "unknown variant"),
    ] {
        let text = format!("[camera]\nbeta = [0, 0, 0.5]\n{text}\n");
        let e = file::parse(&text, "test.toml")
            .err()
            .unwrap_or_else(|| panic!("{text}"));
        assert!(e.to_string().contains(message), "{text}: {e}");
    }
}
