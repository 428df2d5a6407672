//! Issue 41 item 4, Dr TIM's lenticular-array camera (`LenticularArrayCamera`): each pixel
//! column of a lenslet records the orthographic view along its own tilt, worked out here from
//! the print's geometry alone, and the camera's keys are checked where they are given.

mod common;

use common::cli::{location, path_str, timbre, write};

/// A picture 40 columns wide spanning 1 (pitch p = 1/39), 4 columns a lenslet of focal length
/// p: column k of a lenslet sits (k − 1.5) p from its axis and looks along the direction
/// tilted right by atan(k − 1.5). Through the plane z = 1, red left of x = 0 and blue right of
/// it, the column at X (|X| ≤ ½) sees x = X + (k − 1.5): red for k = 0, 1 (x ≤ −½), blue for
/// k = 2, 3 (x ≥ ½), whatever X, where a plain orthographic camera sees red on the left half
/// and blue on the right.
#[test]
fn each_column_of_a_lenslet_looks_along_its_tilt() {
    let pitch = 1.0 / 39.0;
    let scene = |lenticular: &str| {
        format!(
            "studio = \"none\"\n[render]\nwidth = 40\nheight = 3\nspp = 1\n\
             [camera]\ntype = \"orthographic\"\nposition = [0, 0, 0]\nview_direction = [0, 0, 1]\n\
             view_width = 1\n{lenticular}\n\
             [[object]]\nshape = {{ type = \"parallelogram\", corner = [-20, -20, 1], span_u = [20, 0, 0], span_v = [0, 40, 0] }}\n\
             surface = {{ type = \"constant-colour\", colour = [1, 0, 0] }}\n\
             [[object]]\nshape = {{ type = \"parallelogram\", corner = [0, -20, 1], span_u = [20, 0, 0], span_v = [0, 40, 0] }}\n\
             surface = {{ type = \"constant-colour\", colour = [0, 0, 1] }}\n"
        )
    };
    let red = |image: &timbre::render::Image, column: usize| {
        let c = image.pixels[image.width as usize + column];
        assert!(
            (c.x == 1.0 && c.z == 0.0) || (c.x == 0.0 && c.z == 1.0),
            "column {column}: {c:?}"
        );
        c.x == 1.0
    };
    let lenticular = common::images::render_text(&scene(&format!(
        "lenticular_array = {{ pixels_per_cylindrical_lens = 4, cylindrical_lenslet_focal_length = {pitch} }}"
    )));
    for column in 0..40 {
        assert_eq!(red(&lenticular, column), column % 4 < 2, "column {column}");
    }
    let plain = common::images::render_text(&scene(""));
    for column in 0..40 {
        assert_eq!(red(&plain, column), column < 20, "column {column}");
    }
}

#[test]
fn bad_lenticular_array_cameras_are_refused_where_they_are_given() {
    let dir = tempfile::tempdir().unwrap();
    for (camera, needles) in [
        (
            "type = \"pinhole\"\nlenticular_array = {}",
            &[
                "lenticular_array is for orthographic cameras",
                "LenticularArrayCamera",
            ][..],
        ),
        (
            "type = \"orthographic\"\nview_width = 1\nlenticular_array = { pixels_per_cylindrical_lens = 0 }",
            &["pixels_per_cylindrical_lens = 0", "from 1"][..],
        ),
        (
            "type = \"orthographic\"\nview_width = 1\nlenticular_array = { cylindrical_lenslet_focal_length = -1 }",
            &["positive number"][..],
        ),
        (
            "type = \"orthographic\"\nview_width = 1\nlenticular_array = { pitch = 1 }",
            &["pitch"][..],
        ),
        (
            "type = \"equirectangular\"\nlenticular_array = {}",
            &["no lenticular_array"][..],
        ),
    ] {
        let text = format!("studio = \"none\"\n\n[camera]\n{camera}\n");
        let path = write(dir.path(), "bad.toml", text);
        let run = timbre(dir.path(), &["check", path_str(&path)]);
        run.assert_bad_input(needles);
        assert!(location(&run.stderr, &path).0 >= 4, "{}", run.stderr);
    }
}
