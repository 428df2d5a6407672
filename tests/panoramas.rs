//! Issue 41 item 4, the equirectangular (360°) camera, Dr TIM's `SurroundAnaglyphCamera` with
//! its `StandardPanorama3DGeometry`, checked against facts worked out here:
//!
//! * a small ball in the direction of longitude λ (from the view direction towards the right)
//!   and latitude β appears at column W (λ + π) / 2π − ½ and row H (π/2 − β) / π − ½;
//! * omnidirectional stereo: eyes a distance s apart on a circle, each looking along the
//!   tangent, see a ball at distance D straight ahead at λ = ±asin(s / 2D) (the left eye to the
//!   right); focused at distance R (Dr TIM's `GeneralisedStandardPanorama3DGeometry`) both
//!   see a ball at distance R straight ahead;
//! * a camera moving at β along its view sees a distant ball to its right where aberration
//!   puts it: cos α′ = (cos α + β) / (1 + β cos α) from the direction of motion;
//! * keys an equirectangular camera cannot have are refused where they are written.

mod common;

use std::f64::consts::PI;

use glam::DVec3;
use tempfile::TempDir;

use common::cli::{assert_refused_at_line, decode_png, path_str, timbre, write};

const WIDTH: u32 = 720;
const HEIGHT: u32 = 360;

/// The unit direction of longitude `lambda` and latitude `beta` (radians) for a camera looking
/// along `view` with `up` (perpendicular to it), its right up × view.
fn direction(view: DVec3, up: DVec3, lambda: f64, beta: f64) -> DVec3 {
    let right = up.cross(view);
    beta.cos() * (lambda.cos() * view + lambda.sin() * right) + beta.sin() * up
}

/// The continuous pixel position (0 the centre of the top-left pixel) of longitude and latitude.
fn pixel(lambda: f64, beta: f64, width: u32, height: u32) -> (f64, f64) {
    (
        width as f64 * (lambda + PI) / (2.0 * PI) - 0.5,
        height as f64 * (0.5 * PI - beta) / PI - 0.5,
    )
}

/// A ball of constant colour, lit by nothing, on black.
fn ball(centre: DVec3, radius: f64, colour: [u8; 3]) -> String {
    format!(
        "[[object]]\nshape = {{ type = \"sphere\", centre = [{}, {}, {}], radius = {radius} }}\n\
         surface = {{ type = \"constant-colour\", colour = [{}, {}, {}] }}\n",
        centre.x, centre.y, centre.z, colour[0], colour[1], colour[2]
    )
}

/// Renders `text` (a scene with its camera) into a PNG.
fn render(dir: &TempDir, text: &str, args: &[&str]) -> image::RgbImage {
    let scene = write(dir, "scene.toml", text);
    let mut all = vec!["render", "-q", path_str(&scene), "-o", "out.png"];
    all.extend_from_slice(args);
    timbre(dir.path(), &all).assert_success();
    decode_png(&dir.path().join("out.png"))
}

/// The centroid of the pixels of rows `rows` whose colour is `colour` (each channel on or off).
fn centroid(image: &image::RgbImage, rows: std::ops::Range<u32>, colour: [u8; 3]) -> (f64, f64) {
    let (mut sx, mut sy, mut n) = (0.0, 0.0, 0.0);
    for y in rows.clone() {
        for x in 0..image.width() {
            let p = image.get_pixel(x, y).0;
            if (0..3).all(|c| (p[c] > 128) == (colour[c] > 0)) && p != [0, 0, 0] {
                sx += x as f64;
                sy += (y - rows.start) as f64;
                n += 1.0;
            }
        }
    }
    assert!(n > 10.0, "only {n} pixels of {colour:?}");
    (sx / n, sy / n)
}

fn header(camera: &str) -> String {
    format!(
        "studio = \"none\"\n[render]\nwidth = {WIDTH}\nheight = {HEIGHT}\n\
         [camera]\ntype = \"equirectangular\"\n{camera}\n"
    )
}

#[test]
fn each_direction_appears_at_its_longitude_and_latitude() {
    let dir = TempDir::new().unwrap();
    // A camera away from the origin, looking along a slanted direction.
    let position = DVec3::new(1.0, 2.0, 3.0);
    let view = DVec3::new(1.0, 0.0, 1.0).normalize();
    let up = DVec3::Y;
    let balls: [(f64, f64, [u8; 3]); 4] = [
        (0.0, 0.0, [255, 0, 0]),
        (90.0, 0.0, [0, 255, 0]),
        (-135.0, 30.0, [0, 0, 255]),
        (60.0, -45.0, [255, 255, 0]),
    ];
    let mut text = header("position = [1, 2, 3]\nview_direction = [1, 0, 1]\nup = [0, 1, 0]");
    for &(lambda, beta, colour) in &balls {
        let d = direction(view, up, lambda.to_radians(), beta.to_radians());
        text += &ball(position + 50.0 * d, 2.0, colour);
    }
    let image = render(&dir, &text, &[]);
    for (lambda, beta, colour) in balls {
        let (x, y) = centroid(&image, 0..HEIGHT, colour);
        let (ex, ey) = pixel(lambda.to_radians(), beta.to_radians(), WIDTH, HEIGHT);
        assert!(
            (x - ex).abs() < 0.35 && (y - ey).abs() < 0.35,
            "ball at ({lambda}°, {beta}°): seen at ({x}, {y}), expected ({ex}, {ey})"
        );
    }
    // `timbre check` names the camera.
    let scene = write(&dir, "scene.toml", &text);
    let run = timbre(dir.path(), &["check", path_str(&scene)]);
    assert!(
        run.stdout
            .contains("camera:       equirectangular, 360° × 180°"),
        "{}",
        run.stdout
    );
}

#[test]
fn omnidirectional_stereo_eyes_see_a_near_ball_at_the_tangent_angle() {
    let dir = TempDir::new().unwrap();
    let (separation, distance) = (1.0, 5.0);
    // One ball ahead, one to the right: eyes that did not turn with the azimuth would see the
    // second without parallax (both eyes on the line to it).
    let near = ball(DVec3::new(0.0, 0.0, distance), 0.2, [255, 0, 0])
        + &ball(DVec3::new(distance, 0.0, 0.0), 0.2, [0, 255, 0]);
    // Dr TIM's interpupillary distance 1 by default; the eyes look along parallel rays.
    let image = render(
        &dir,
        &format!(
            "{}{near}",
            header("position = [0, 0, 0]\nstereo = \"top-bottom\"")
        ),
        &[],
    );
    assert_eq!(image.dimensions(), (WIDTH, 2 * HEIGHT));
    let lambda = (0.5 * separation / distance).asin();
    for (colour, towards) in [([255, 0, 0], 0.0), ([0, 255, 0], 0.5 * PI)] {
        let (left, _) = centroid(&image, 0..HEIGHT, colour);
        let (right, _) = centroid(&image, HEIGHT..2 * HEIGHT, colour);
        let (expected_left, _) = pixel(towards + lambda, 0.0, WIDTH, HEIGHT);
        let (expected_right, _) = pixel(towards - lambda, 0.0, WIDTH, HEIGHT);
        assert!(
            (left - expected_left).abs() < 0.35 && (right - expected_right).abs() < 0.35,
            "{colour:?}: left eye at {left} (expected {expected_left}), right eye at {right} (expected {expected_right})"
        );
    }
    // Focused at R = D, both eyes see the ball straight ahead (no disparity).
    let image = render(
        &dir,
        &format!(
            "{}{near}",
            header("position = [0, 0, 0]\nstereo = \"top-bottom\"\nfocus_distance = 5")
        ),
        &[],
    );
    for (colour, towards) in [([255, 0, 0], 0.0), ([0, 255, 0], 0.5 * PI)] {
        let (centre, _) = pixel(towards, 0.0, WIDTH, HEIGHT);
        for rows in [0..HEIGHT, HEIGHT..2 * HEIGHT] {
            let (x, _) = centroid(&image, rows, colour);
            assert!((x - centre).abs() < 0.35, "{colour:?}: {x} != {centre}");
        }
    }
}

#[test]
fn a_moving_panorama_shows_the_aberrated_sky() {
    let dir = TempDir::new().unwrap();
    let beta = 0.6;
    // A ball far off to the right (α = 90° from the motion along the view direction).
    let text = format!(
        "{}{}",
        header(&format!("position = [0, 0, 0]\nbeta = [0, 0, {beta}]")),
        ball(DVec3::new(100.0, 0.0, 0.0), 4.0, [0, 255, 0])
    );
    let image = render(&dir, &text, &[]);
    let alpha = f64::acos((0.0 + beta) / (1.0 + beta * 0.0));
    let (x, y) = centroid(&image, 0..HEIGHT, [0, 255, 0]);
    let (ex, ey) = pixel(alpha, 0.0, WIDTH, HEIGHT);
    assert!(
        (x - ex).abs() < 0.5 && (y - ey).abs() < 0.5,
        "seen at ({x}, {y}), expected ({ex}, {ey}) at α′ = {}°",
        alpha.to_degrees()
    );
}

#[test]
fn what_an_equirectangular_camera_cannot_have_is_refused() {
    let dir = TempDir::new().unwrap();
    for (key, line, needles) in [
        (
            "horizontal_view_angle_deg = 90",
            3,
            &["no horizontal_view_angle_deg"][..],
        ),
        ("view_width = 2", 3, &["no view_width"]),
        ("aperture_radius = 0.1", 3, &["finite-aperture"]),
        ("shutter = \"detector-plane\"", 3, &["no detector plane"]),
        ("detector_distance = 2", 3, &["no detector_distance"]),
        (
            "stereo = \"autostereogram\"",
            3,
            &["not of an equirectangular camera's"],
        ),
    ] {
        let text = format!("[camera]\ntype = \"equirectangular\"\n{key}\n");
        assert_refused_at_line(dir.path(), &text, needles, line);
    }
}
