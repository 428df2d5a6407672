//! Integration tests of the `timbre` command: each runs the built binary in a temporary
//! directory and checks its exit code, its messages and the files it writes. Images are small
//! (80×60 or less), so every run takes a few milliseconds.

mod common;

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::process::Command;

use exr::prelude::{AttributeValue, FlatSamples};
use tempfile::TempDir;

use common::cli::{Run, decode_png, files_in, location, path_str, timbre, write};

/// Runs `timbre` with the whitespace-separated arguments of `line` in `dir`.
fn timbre_line(dir: &Path, line: &str) -> Run {
    timbre(dir, &line.split_whitespace().collect::<Vec<_>>())
}

/// The parts of the summary line `WxH, S spp: N rays in T s (M Mrays/s) -> PATH`.
struct Summary {
    size: String,
    spp: u32,
    rays: u64,
    seconds: f64,
    mrays_per_second: f64,
    output: String,
}

/// The printed rate is the printed number of rays over the time, in millions a second: the
/// time is printed to 3 decimals and the rate to 2, so the rate must lie between
/// rays / (T + 0.0005) / 1e6 − 0.005 and rays / (T − 0.0005) / 1e6 + 0.005 (no upper bound when
/// T is printed as 0.000).
#[track_caller]
fn assert_rate_is_rays_over_seconds(s: &Summary, stdout: &str) {
    let rays = s.rays as f64;
    let lowest = rays / (s.seconds + 0.0005) / 1e6 - 0.005;
    let highest = if s.seconds > 0.0005 {
        rays / (s.seconds - 0.0005) / 1e6 + 0.005
    } else {
        f64::INFINITY
    };
    assert!(
        s.mrays_per_second >= lowest && s.mrays_per_second <= highest,
        "{} Mrays/s is not {} rays in {} s (between {lowest} and {highest}): {stdout}",
        s.mrays_per_second,
        s.rays,
        s.seconds
    );
}

#[track_caller]
fn summary(stdout: &str) -> Summary {
    let line = stdout
        .lines()
        .find(|l| l.contains(" rays in "))
        .unwrap_or_else(|| panic!("no summary: {stdout}"));
    let fail = || -> ! { panic!("malformed summary line: {line}") };
    let (size, rest) = line.split_once(", ").unwrap_or_else(|| fail());
    let (spp, rest) = rest.split_once(" spp: ").unwrap_or_else(|| fail());
    let (rays, rest) = rest.split_once(" rays in ").unwrap_or_else(|| fail());
    let (seconds, rest) = rest.split_once(" s (").unwrap_or_else(|| fail());
    let (rate, output) = rest.split_once(" Mrays/s) -> ").unwrap_or_else(|| fail());
    Summary {
        size: size.to_string(),
        spp: spp.parse().unwrap_or_else(|_| fail()),
        rays: rays.parse().unwrap_or_else(|_| fail()),
        seconds: seconds.parse().unwrap_or_else(|_| fail()),
        mrays_per_second: rate.parse().unwrap_or_else(|_| fail()),
        output: output.to_string(),
    }
}

/// A scene with nothing but a constant-colour sphere around the camera: every pixel of the
/// picture is (0.2, 0.4, 0.6), i.e. (51, 102, 153) in the PNG, whatever the sampling.
const UNIFORM_SCENE: &str = r#"
studio = "none"

[render]
width = 40
height = 30
spp = 2

[[object]]
name = "inside of a ball"
shape = { type = "sphere", centre = [0, 0, 0], radius = 10 }
surface = { type = "constant_colour", colour = [0.2, 0.4, 0.6] }
"#;

#[test]
fn object_names_in_any_script_go_into_the_exr_header() {
    let dir = TempDir::new().unwrap();
    let scene = write(
        &dir,
        "names.toml",
        "studio = \"none\"\n[[object]]\nname = \"球 ∅\"\n\
         shape = { type = \"sphere\", centre = [0, 0, 5], radius = 1 }\n\
         surface = { type = \"constant_colour\", colour = [1, 1, 1] }\n",
    );
    let args = [
        "render",
        path_str(&scene),
        "-q",
        "-o",
        "n.exr",
        "--aov",
        "object",
        "--width",
        "8",
        "--height",
        "6",
    ];
    timbre(dir.path(), &args).assert_success();
    let exr = Exr::read(&dir.path().join("n.exr"));
    match exr.attributes.get("timbre.objects") {
        Some(AttributeValue::TextVector(names)) => {
            assert_eq!(names.len(), 1);
            assert_eq!(std::str::from_utf8(names[0].bytes()).unwrap(), "球 ∅");
        }
        other => panic!("timbre.objects: {other:?}"),
    }
}

#[test]
fn the_default_render_is_tims_640_by_480_studio() {
    let dir = TempDir::new().unwrap();
    timbre_line(dir.path(), "render -q -o default.png").assert_success();
    let png = decode_png(&dir.path().join("default.png"));
    assert_eq!(png.dimensions(), (640, 480));
    assert_eq!(png.get_pixel(320, 0).0, [128, 128, 255], "sky at the top");
}

#[test]
fn render_without_a_scene_writes_the_studio_and_a_summary() {
    let dir = TempDir::new().unwrap();
    let run = timbre_line(dir.path(), "render -o studio.png --width 80 --height 60");
    run.assert_success();

    let png = decode_png(&dir.path().join("studio.png"));
    assert_eq!(png.dimensions(), (80, 60));
    // The top row looks into the sky, (0.5, 0.5, 1) → (128, 128, 255); the bottom row sees the
    // floor's grey and white tiles.
    assert_eq!(png.get_pixel(40, 0).0, [128, 128, 255]);
    let floor = png.get_pixel(40, 59).0;
    assert!(
        floor[0] == floor[1] && floor[1] == floor[2] && floor[0] > 100,
        "floor pixel {floor:?}"
    );

    let s = summary(&run.stdout);
    assert_eq!(
        (s.size.as_str(), s.spp, s.output.as_str()),
        ("80x60", 1, "studio.png")
    );
    assert!(
        s.rays >= 80 * 60,
        "at least one primary ray per pixel: {}",
        run.stdout
    );
    assert_rate_is_rays_over_seconds(&s, &run.stdout);
    assert!(
        run.stderr.is_empty(),
        "no progress bar without a terminal: {}",
        run.stderr
    );

    // --quiet prints nothing at all.
    let quiet = timbre_line(dir.path(), "render -q -o q.png --width 8 --height 6");
    quiet.assert_success();
    assert!(quiet.stdout.is_empty() && quiet.stderr.is_empty());
    assert_eq!(decode_png(&dir.path().join("q.png")).dimensions(), (8, 6));
}

#[test]
fn scene_file_renders_and_the_command_line_overrides_it() {
    let dir = TempDir::new().unwrap();
    let scene = write(&dir, "ball.toml", UNIFORM_SCENE);

    // The file's own settings: 40×30 at 2 spp, every pixel the sphere's colour.
    let run = timbre(dir.path(), &["render", path_str(&scene), "-o", "file.png"]);
    run.assert_success();
    let png = decode_png(&dir.path().join("file.png"));
    assert_eq!(png.dimensions(), (40, 30));
    assert!(
        png.pixels().all(|p| p.0 == [51, 102, 153]),
        "the scene file's sphere fills the picture"
    );
    let s = summary(&run.stdout);
    assert_eq!((s.size.as_str(), s.spp), ("40x30", 2));
    // A constant-colour surface and no light: every sample is one primary ray and nothing more.
    assert_eq!(s.rays, 40 * 30 * 2, "{}", run.stdout);
    assert_rate_is_rays_over_seconds(&s, &run.stdout);

    // --width and --height override the file; its spp stays.
    let run = timbre(
        dir.path(),
        &[
            "render",
            path_str(&scene),
            "-o",
            "wh.png",
            "--width",
            "80",
            "--height",
            "60",
        ],
    );
    run.assert_success();
    assert_eq!(
        decode_png(&dir.path().join("wh.png")).dimensions(),
        (80, 60)
    );
    let s = summary(&run.stdout);
    assert_eq!((s.size.as_str(), s.spp), ("80x60", 2));
    assert_eq!(s.rays, 80 * 60 * 2, "{}", run.stdout);

    // --width alone keeps the file's aspect ratio (40:30): 100 wide is 75 high.
    let run = timbre(
        dir.path(),
        &["render", path_str(&scene), "-o", "w.png", "--width", "100"],
    );
    run.assert_success();
    assert_eq!(
        decode_png(&dir.path().join("w.png")).dimensions(),
        (100, 75)
    );

    // --spp overrides the file too; --height alone keeps the aspect: 10 high is
    // round(40 × 10/30) = 13 wide.
    let run = timbre(
        dir.path(),
        &[
            "render",
            path_str(&scene),
            "-o",
            "spp.png",
            "--spp",
            "3",
            "--height",
            "10",
        ],
    );
    run.assert_success();
    assert_eq!(
        decode_png(&dir.path().join("spp.png")).dimensions(),
        (13, 10)
    );
    let s = summary(&run.stdout);
    assert_eq!((s.size.as_str(), s.spp), ("13x10", 3));
    assert_eq!(s.rays, 13 * 10 * 3, "{}", run.stdout);

    // A matt inside of the ball lit by a point light at its centre: every sample is a primary
    // ray and one shadow ray towards the light (nothing is in the way, and the matt surface
    // sends no further rays).
    let lit = UNIFORM_SCENE.replace("constant_colour", "matt").replace(
        "[[object]]",
        "[[light]]\ntype = \"point\"\nposition = [0, 0, 0]\ncolour = [1, 1, 1]\n\n[[object]]",
    );
    let scene = write(&dir, "lit.toml", &lit);
    let run = timbre(dir.path(), &["render", path_str(&scene), "-o", "lit.png"]);
    run.assert_success();
    let s = summary(&run.stdout);
    assert_eq!(s.rays, 2 * 40 * 30 * 2, "{}", run.stdout);
    assert_rate_is_rays_over_seconds(&s, &run.stdout);
}

#[test]
fn a_missing_scene_file_is_named() {
    let dir = TempDir::new().unwrap();
    let missing = dir.path().join("no-such-scene.toml");
    timbre(dir.path(), &["render", path_str(&missing), "-o", "x.png"])
        .assert_bad_input(&[path_str(&missing)]);
    timbre(dir.path(), &["check", path_str(&missing)]).assert_bad_input(&[path_str(&missing)]);
    assert_eq!(files_in(&dir).len(), 0, "nothing is written");
}

#[test]
fn malformed_toml_is_located() {
    let dir = TempDir::new().unwrap();
    let scene = write(
        &dir,
        "broken.toml",
        r#"studio = "empty"

[render]
width = = 3
height = 10
"#,
    );
    let run = timbre(dir.path(), &["render", path_str(&scene), "-o", "x.png"]);
    run.assert_bad_input(&[]);
    assert_eq!(location(&run.stderr, &scene).0, 4, "{}", run.stderr);
    assert_eq!(files_in(&dir).len(), 1, "no image is written");
}

#[test]
fn an_unknown_key_is_named_and_located() {
    let dir = TempDir::new().unwrap();
    let scene = write(
        &dir,
        "typo.toml",
        r#"studio = "empty"

[render]
width = 10
hieght = 10
"#,
    );
    let run = timbre(dir.path(), &["render", path_str(&scene), "-o", "x.png"]);
    run.assert_bad_input(&["unknown field `hieght`", "expected one of", "`height`"]);
    assert_eq!(location(&run.stderr, &scene), (5, 1), "{}", run.stderr);

    let scene = write(
        &dir,
        "top.toml",
        "studio = \"empty\"\nstudoi = \"lattice\"\n",
    );
    let run = timbre(dir.path(), &["check", path_str(&scene)]);
    run.assert_bad_input(&["unknown field `studoi`"]);
    assert_eq!(location(&run.stderr, &scene), (2, 1), "{}", run.stderr);
}

#[test]
fn a_negative_radius_is_rejected_with_its_line() {
    let dir = TempDir::new().unwrap();
    let scene = write(
        &dir,
        "negative.toml",
        r#"studio = "empty"

[[object]]
name = "ball"
shape = { type = "sphere", centre = [0, 0, 5], radius = -0.5 }
surface = { type = "matt", colour = [1, 1, 1] }
"#,
    );
    let run = timbre(dir.path(), &["render", path_str(&scene), "-o", "x.png"]);
    run.assert_bad_input(&["expected a positive number of at most 1e15, got -0.5"]);
    assert_eq!(location(&run.stderr, &scene).0, 5, "{}", run.stderr);
    assert_eq!(files_in(&dir).len(), 1, "no image is written");
}

#[test]
fn nan_parameters_are_rejected() {
    let dir = TempDir::new().unwrap();
    let radius = write(
        &dir,
        "nan-radius.toml",
        r#"[[object]]
shape = { type = "sphere", centre = [0, 0, 5], radius = nan }
surface = { type = "mirror" }
"#,
    );
    let run = timbre(dir.path(), &["render", path_str(&radius), "-o", "x.png"]);
    run.assert_bad_input(&["expected a positive number of at most 1e15, got NaN"]);
    assert_eq!(location(&run.stderr, &radius).0, 2, "{}", run.stderr);

    let centre = write(
        &dir,
        "nan-centre.toml",
        r#"
[[object]]
shape = { type = "sphere", centre = [0, nan, 5], radius = 1 }
surface = { type = "mirror" }
"#,
    );
    let run = timbre(dir.path(), &["render", path_str(&centre), "-o", "x.png"]);
    run.assert_bad_input(&["expected a finite number of magnitude at most 1e15, got NaN"]);
    assert_eq!(location(&run.stderr, &centre).0, 3, "{}", run.stderr);

    let colour = write(
        &dir,
        "nan-light.toml",
        "[[light]]\ntype = \"ambient\"\ncolour = [0.2, -nan, 0.2]\n",
    );
    timbre(dir.path(), &["check", path_str(&colour)]).assert_bad_input(&["finite", "NaN"]);
    assert_eq!(files_in(&dir).len(), 3, "no image is written");
}

#[test]
fn unsupported_outputs_are_rejected() {
    let dir = TempDir::new().unwrap();
    timbre_line(dir.path(), "render -o picture.jpg --width 8 --height 6").assert_bad_input(&[
        "picture.jpg",
        "unsupported output format",
        ".png or .exr",
    ]);
    timbre_line(dir.path(), "render -o no-extension --width 8 --height 6")
        .assert_bad_input(&["no-extension", "unsupported output format"]);
    timbre_line(
        dir.path(),
        "render -o aov.png --aov depth --width 8 --height 6",
    )
    .assert_bad_input(&["--aov", "OpenEXR", ".exr"]);
    assert_eq!(files_in(&dir).len(), 0, "nothing is written");
}

#[test]
fn check_accepts_good_files_and_locates_errors_in_bad_ones() {
    let dir = TempDir::new().unwrap();
    let good = write(&dir, "good.toml", UNIFORM_SCENE);
    let run = timbre(dir.path(), &["check", path_str(&good)]);
    run.assert_success();
    let expected = format!(
        "{}: OK\n  objects:      1\n  triangles:    0\n  instances:    0 (in 0 arrays)\n  \
         bounding box: [-10, -10, -10] to [10, 10, 10]\n  shapes:       1 sphere\n  \
         point lights: 0\n  camera:       pinhole, 20°\n  render:       40x30 at 2 spp",
        good.display()
    );
    assert_eq!(run.stdout.trim_end(), expected);
    assert_eq!(files_in(&dir).len(), 1, "check writes nothing");

    let lattice = write(&dir, "lattice.toml", "studio = \"lattice\"\n");
    let run = timbre(dir.path(), &["check", path_str(&lattice)]);
    run.assert_success();
    for line in [
        "objects:      50",
        "point lights: 1",
        "render:       640x480 at 1 spp",
    ] {
        assert!(run.stdout.contains(line), "{}", run.stdout);
    }

    // The camera line says how the camera moves and focuses.
    let moving = write(
        &dir,
        "moving.toml",
        "[camera]\naperture_radius = 0.1\nfocus_distance = 15\nbeta = [0, 0.6, 0]\nshutter = \"focus-surface\"\nstereo = \"anaglyph\"\n",
    );
    let run = timbre(dir.path(), &["check", path_str(&moving)]);
    run.assert_success();
    assert!(
        run.stdout.contains(
            "camera:       finite aperture (radius 0.1), 20°; focused at 15; moving at beta = (0, 0.6, 0) (gamma = 1.2500), focus-surface shutter at t = 0; stereo anaglyph"
        ),
        "{}",
        run.stdout
    );

    // Focused on a surface of two shapes, moving with one object.
    let surface = write(
        &dir,
        "surface.toml",
        "[camera]
beta = [0, 0, 0.8]
focus_surface = [{ type = \"sphere\", centre = [0, 0, 0], radius = 50 }, { type = \"plane\", point = [0, 0, 60], normal = [0, 0, -1] }]
\
         [[object]]\nframe = \"camera\"\nshape = { type = \"sphere\", centre = [0, 0, 5], radius = 1 }\nsurface = { type = \"mirror\" }\n",
    );
    let run = timbre(dir.path(), &["check", path_str(&surface)]);
    run.assert_success();
    assert!(
        run.stdout.contains(
            "camera:       pinhole, 20°; focused on 2 shapes; moving at beta = (0, 0, 0.8) (gamma = 1.6667), entrance-pupil shutter at t = 0; 1 objects moving with it\n"
        ),
        "{}",
        run.stdout
    );

    let bad = write(
        &dir,
        "bad.toml",
        r#"studio = "empty"
[[object]]
shape = { type = "sphere", centre = [0, 0, 5], radius = 1 }
surface = { type = "mirror", reflection = 1.5 }
"#,
    );
    let run = timbre(dir.path(), &["check", path_str(&bad)]);
    run.assert_bad_input(&["expected a coefficient between 0 and 1, got 1.5"]);
    assert_eq!(location(&run.stderr, &bad).0, 4, "{}", run.stderr);
    assert!(run.stdout.is_empty());
}

#[test]
fn info_prints_the_versions() {
    let dir = TempDir::new().unwrap();
    let run = timbre_line(dir.path(), "info");
    run.assert_success();
    let lines: Vec<&str> = run.stdout.lines().collect();
    assert!(
        lines.contains(&concat!("timbre ", env!("CARGO_PKG_VERSION"))),
        "{}",
        run.stdout
    );
    let embree = lines
        .iter()
        .find_map(|l| l.strip_prefix("Embree "))
        .unwrap_or_else(|| panic!("no Embree: {}", run.stdout));
    let parts: Vec<&str> = embree.split('.').collect();
    assert!(
        parts.len() == 3
            && parts.iter().all(|p| p.parse::<u32>().is_ok())
            && ["3", "4"].contains(&parts[0]),
        "Embree version should be 3.x.y or 4.x.y: {embree}"
    );
    assert!(
        lines.iter().any(|l| l.starts_with("threads: ")),
        "{}",
        run.stdout
    );
}

/// Renders the default studio at 80×60 with `--spp 4` (jittered samples) and `threads` threads
/// to `name`, and returns the file's bytes.
fn render_jittered(dir: &Path, name: &str, threads: u32, extra: &str) -> Vec<u8> {
    let line =
        format!("render -q -o {name} --width 80 --height 60 --spp 4 --threads {threads} {extra}");
    timbre_line(dir, &line).assert_success();
    std::fs::read(dir.join(name)).unwrap()
}

#[test]
fn the_thread_count_does_not_change_the_png() {
    let dir = TempDir::new().unwrap();
    let one = render_jittered(dir.path(), "one.png", 1, "");
    let two = render_jittered(dir.path(), "two.png", 2, "");
    assert!(one == two, "PNGs rendered with 1 and 2 threads differ");
    // The samples really are jittered: another seed gives another picture.
    let reseeded = render_jittered(dir.path(), "seed.png", 2, "--seed 7");
    assert!(one != reseeded, "--seed should move the jittered samples");
}

#[test]
fn the_thread_count_does_not_change_the_exr() {
    let dir = TempDir::new().unwrap();
    let aov = "--aov depth,normal,object";
    let one = render_jittered(dir.path(), "one.exr", 1, aov);
    // Several runs, so that a file layout that varies by chance is caught reliably.
    for (k, threads) in [2, 2, 1].into_iter().enumerate() {
        let other = render_jittered(dir.path(), &format!("other{k}.exr"), threads, aov);
        assert!(
            one == other,
            "EXR files rendered with 1 and {threads} threads differ (run {k}); the pixels do not, so \
             the chunk order or the order of the header attributes varies between runs"
        );
    }
}

/// The one layer of an EXR file: its size, channels and header attributes.
struct Exr {
    size: (usize, usize),
    channels: HashMap<String, Vec<f32>>,
    attributes: HashMap<String, AttributeValue>,
}

impl Exr {
    fn read(path: &Path) -> Exr {
        let image = exr::prelude::read_all_flat_layers_from_file(path)
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        assert_eq!(image.layer_data.len(), 1, "one layer");
        let layer = &image.layer_data[0];
        let channels = layer
            .channel_data
            .list
            .iter()
            .map(|channel| match &channel.sample_data {
                FlatSamples::F32(values) => (channel.name.to_string(), values.clone()),
                _ => panic!("channel {} is not f32", channel.name),
            })
            .collect();
        let attributes = layer
            .attributes
            .other
            .iter()
            .map(|(k, v)| (k.to_string(), v.clone()))
            .collect();
        Exr {
            size: (layer.size.width(), layer.size.height()),
            channels,
            attributes,
        }
    }

    /// The channel names, sorted.
    fn names(&self) -> Vec<&str> {
        let mut names: Vec<&str> = self.channels.keys().map(String::as_str).collect();
        names.sort();
        names
    }

    fn at(&self, channel: &str, x: usize, y: usize) -> f32 {
        self.channels[channel][y * self.size.0 + x]
    }

    fn text(&self, key: &str) -> Option<String> {
        match self.attributes.get(key) {
            Some(AttributeValue::Text(t)) => Some(t.to_string()),
            _ => None,
        }
    }

    fn int(&self, key: &str) -> Option<i32> {
        match self.attributes.get(key) {
            Some(AttributeValue::I32(i)) => Some(*i),
            _ => None,
        }
    }
}

/// Distance from the studio camera (at the origin, looking along +z, 20° across the centres of
/// the outermost columns, square pixels) to the floor y = −1.0001 through pixel (x, y).
fn floor_depth(width: usize, height: usize, x: usize, y: usize) -> f64 {
    let pitch = 2.0 * 10f64.to_radians().tan() / (width - 1) as f64;
    let dx = (x as f64 - 0.5 * (width - 1) as f64) * pitch;
    let dy = (0.5 * (height - 1) as f64 - y as f64) * pitch;
    assert!(dy < 0.0, "pixel row {y} looks downwards");
    let length = (dx * dx + dy * dy + 1.0).sqrt();
    1.0001 / -dy * length
}

const ALL_CHANNELS: [&str; 8] = [
    "B",
    "G",
    "R",
    "depth.Z",
    "normal.X",
    "normal.Y",
    "normal.Z",
    "object.id",
];
const AOV_CHANNELS: [&str; 5] = ["depth.Z", "normal.X", "normal.Y", "normal.Z", "object.id"];

/// Dr TIM-style coloured surfaces behind a transparent pane and in a mirror, for the albedo
/// AOV: a wall at z = 6 of diffuse colour (0.2, 0.5, 0.8) fills the view; a pane of
/// transmission 0.5 covers the lower left quadrant (z = 2), a mirror of reflection 0.9 the upper
/// right one (z = 3), which shows a wall of diffuse colour (0.9, 0.1, 0.1) behind the camera.
const ALBEDO_SCENE: &str = r#"
studio = "none"
[camera]
horizontal_view_angle_deg = 60
[[object]]
name = "wall"
shape = { type = "parallelogram", corner = [-10, -10, 6], span_u = [20, 0, 0], span_v = [0, 20, 0] }
surface = { type = "coloured", diffuse = [0.2, 0.5, 0.8], specular = [1, 1, 1] }
[[object]]
name = "back wall"
shape = { type = "parallelogram", corner = [-50, -50, -6], span_u = [100, 0, 0], span_v = [0, 100, 0] }
surface = { type = "coloured", diffuse = [0.9, 0.1, 0.1] }
[[object]]
name = "pane"
shape = { type = "parallelogram", corner = [-5, -5, 2], span_u = [5, 0, 0], span_v = [0, 5, 0] }
surface = { type = "transparent", transmission = 0.5 }
[[object]]
name = "mirror"
shape = { type = "parallelogram", corner = [0, 0, 3], span_u = [5, 0, 0], span_v = [0, 5, 0] }
surface = { type = "mirror", reflection = 0.9 }
"#;

#[test]
fn the_albedo_is_the_diffuse_colour_seen_through_every_law_times_its_factors() {
    let dir = TempDir::new().unwrap();
    write(dir.path(), "albedo.toml", ALBEDO_SCENE);
    timbre_line(
        dir.path(),
        "render albedo.toml -o a.exr --aov albedo --spp 4 --width 40 --height 30",
    )
    .assert_success();
    let exr = Exr::read(&dir.path().join("a.exr"));
    assert_eq!(
        exr.names(),
        ["B", "G", "R", "albedo.B", "albedo.G", "albedo.R"]
    );
    let albedo = |x, y| ["albedo.R", "albedo.G", "albedo.B"].map(|c| exr.at(c, x, y));
    let (wall, back) = ([0.2, 0.5, 0.8], [0.9, 0.1, 0.1]);
    // Pixel (x, y) of the quadrants: the wall, unlit (the picture itself is lit: shiny and
    // shaded); through the pane, times its transmission; in the mirror, times its reflection.
    for (x, y, want) in [
        (5, 5, wall),
        (35, 25, wall),
        (5, 25, wall.map(|c| 0.5 * c)),
        (35, 5, back.map(|c| 0.9 * c)),
    ] {
        let got = albedo(x, y);
        assert!(
            got.iter()
                .zip(want)
                .all(|(g, w)| (*g as f64 - w).abs() < 1e-6),
            "albedo at ({x}, {y}): {got:?}, expected {want:?}"
        );
        let colour = ["R", "G", "B"].map(|c| exr.at(c, x, y));
        assert_ne!(
            colour, got,
            "the colour at ({x}, {y}) is lit, not the albedo"
        );
    }
}

#[test]
fn exr_has_colour_and_aov_channels_and_provenance() {
    let dir = TempDir::new().unwrap();
    timbre_line(
        dir.path(),
        "render -o aov.exr --aov depth,normal,object --seed 42 --width 80 --height 60",
    )
    .assert_success();
    let path = dir.path().join("aov.exr");
    let exr = Exr::read(&path);
    assert_eq!(exr.size, (80, 60));
    assert_eq!(exr.names(), ALL_CHANNELS);
    assert!(exr.channels.values().all(|c| c.len() == 80 * 60));
    for c in ["R", "G", "B"] {
        assert!(
            exr.channels[c].iter().all(|v| v.is_finite() && *v >= 0.0),
            "{c} is finite and non-negative"
        );
    }

    // The top row sees the sky: exactly its constant colour, 10⁵ away (the camera is at the
    // sky sphere's centre), object 0, normal pointing outwards (away from the camera).
    for x in [0, 40, 79] {
        assert_eq!(
            [exr.at("R", x, 0), exr.at("G", x, 0), exr.at("B", x, 0)],
            [0.5, 0.5, 1.0],
            "sky at ({x}, 0)"
        );
        let depth = exr.at("depth.Z", x, 0);
        assert!((depth / 1e5 - 1.0).abs() < 1e-6, "sky depth {depth}");
        assert_eq!(exr.at("object.id", x, 0), 0.0, "the sky is object 0");
        assert!(
            exr.at("normal.Z", x, 0) > 0.9,
            "the sky's normal points away from the camera"
        );
    }

    // The bottom rows see the floor (object 1, normal +y) at the distance the camera geometry
    // predicts, lit to a grey above the ambient level 0.2 × 0.8.
    for (x, y) in [(0, 59), (40, 59), (79, 59), (20, 55)] {
        let expected = floor_depth(80, 60, x, y);
        let depth = exr.at("depth.Z", x, y) as f64;
        assert!(
            (depth / expected - 1.0).abs() < 1e-6,
            "floor depth at ({x}, {y}): {depth}, expected {expected}"
        );
        assert_eq!(exr.at("object.id", x, y), 1.0, "the floor is object 1");
        let normal = [
            exr.at("normal.X", x, y),
            exr.at("normal.Y", x, y),
            exr.at("normal.Z", x, y),
        ];
        assert_eq!(normal, [0.0, 1.0, 0.0], "floor normal at ({x}, {y})");
        let r = exr.at("R", x, y);
        assert!(
            r == exr.at("G", x, y) && r == exr.at("B", x, y) && r > 0.16,
            "floor colour {r}"
        );
    }

    // Some pixel sees a lattice cylinder (object ids 2 to 49).
    assert!(
        exr.channels["object.id"]
            .iter()
            .any(|id| (2.0..=49.0).contains(id))
    );

    assert_eq!(exr.int("timbre.spp"), Some(1), "{:?}", exr.attributes);
    // object.id indexes the object names in the header: the studio's sky, floor, then lattice.
    match exr.attributes.get("timbre.objects") {
        Some(AttributeValue::TextVector(names)) => {
            let names: Vec<String> = names.iter().map(|n| n.to_string()).collect();
            assert_eq!(names.len(), 50);
            assert_eq!((names[0].as_str(), names[1].as_str()), ("sky", "floor"));
            assert!(
                names[2..].iter().all(|n| n.contains("cylinder")),
                "{names:?}"
            );
        }
        other => panic!("timbre.objects: {other:?}"),
    }
    assert_eq!(
        exr.text("timbre.seed").as_deref(),
        Some("42"),
        "{:?}",
        exr.attributes
    );
    assert_eq!(
        exr.text("timbre.version").as_deref(),
        Some(env!("CARGO_PKG_VERSION")),
        "{:?}",
        exr.attributes
    );

    // The AOVs describe the pixel centres, so jittered sampling does not change them.
    timbre_line(
        dir.path(),
        "render -q -o aov4.exr --aov depth,normal,object --spp 4 --width 80 --height 60",
    )
    .assert_success();
    let jittered = Exr::read(&dir.path().join("aov4.exr"));
    for name in AOV_CHANNELS {
        assert!(
            jittered.channels[name] == exr.channels[name],
            "{name} differs between 1 and 4 spp"
        );
    }
    assert_eq!(jittered.int("timbre.spp"), Some(4));
    assert_eq!(jittered.text("timbre.seed").as_deref(), Some("0"));
    assert_eq!(jittered.text("timbre.samples").as_deref(), Some("0..4"));
    // The scene's hash: the same scene, the same hash (seed and spp aside); another, another.
    let scene = jittered.text("timbre.scene").expect("timbre.scene");
    assert!(
        scene.len() == 16 && scene.chars().all(|c| c.is_ascii_hexdigit()),
        "{scene}"
    );
    assert_eq!(exr.text("timbre.scene"), Some(scene.clone()));
    // A scene file of the same studio is the same scene; moving its camera makes another.
    let file = write(dir.path(), "studio.toml", "studio = \"lattice\"\n");
    let hash_of = |name: &str, set: &str| {
        let mut args = vec!["render", "-q", path_str(&file), "-o", name, "--width", "8"];
        args.extend(["--height", "6", "--set", set]);
        timbre(dir.path(), &args).assert_success();
        Exr::read(&dir.path().join(name)).text("timbre.scene")
    };
    assert_eq!(hash_of("same.exr", "render.seed=5"), Some(scene.clone()));
    assert_ne!(
        hash_of("moved.exr", "camera.position=[0,1,-1]"),
        Some(scene)
    );

    // A selection of AOVs writes only those channels.
    timbre_line(
        dir.path(),
        "render -q -o depth.exr --aov depth --width 8 --height 6",
    )
    .assert_success();
    assert_eq!(
        Exr::read(&dir.path().join("depth.exr")).names(),
        ["B", "G", "R", "depth.Z"]
    );

    // OpenEXR's own reader accepts the file.
    // scripts/setup.sh installs it (Debian package openexr).
    match Command::new("exrheader").arg(&path).output() {
        Err(e) => panic!("could not run exrheader (Debian package openexr): {e}"),
        Ok(out) => {
            let listing = String::from_utf8_lossy(&out.stdout);
            let errors = String::from_utf8_lossy(&out.stderr);
            assert!(out.status.success(), "exrheader failed:\n{listing}{errors}");
            for channel in ALL_CHANNELS {
                let listed = listing.lines().any(|l| {
                    l.trim_start().starts_with(&format!("{channel}, "))
                        && l.contains("32-bit floating-point")
                });
                assert!(
                    listed,
                    "exrheader does not list the f32 channel {channel}:\n{listing}"
                );
            }
            for line in [
                "dataWindow (type box2i): (0 0) - (79 59)",
                "timbre.spp (type int): 1",
                "timbre.seed (type string): \"42\"",
                concat!(
                    "timbre.version (type string): \"",
                    env!("CARGO_PKG_VERSION"),
                    "\""
                ),
            ] {
                assert!(
                    listing.contains(line),
                    "exrheader does not show {line:?}:\n{listing}"
                );
            }
        }
    }
}

/// The example scenes: scenes/*.toml and the research programs' figures, scenes/research/*.toml.
fn scene_files() -> Vec<PathBuf> {
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let mut files: Vec<PathBuf> = [scenes.clone(), scenes.join("research")]
        .iter()
        .flat_map(|dir| {
            std::fs::read_dir(dir)
                .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
                .map(|entry| entry.unwrap().path())
        })
        .filter(|path| path.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    files
}

#[test]
fn every_example_scene_checks_and_renders() {
    let files = scene_files();
    for name in [
        "studio.toml",
        "glass-ball.toml",
        "mirror.toml",
        "shapes.toml",
        "mesh.toml",
        "lenslet-array.toml",
        "sphere-array.toml",
        "fig2a-at-rest.toml",
        "fig2b-forwards-0.99c.toml",
        "fig2c-oblique-0.99c.toml",
        "fig3-finite-aperture-0.99c.toml",
        "fig4-relativistic-anaglyph.toml",
        "3d-tv-side-by-side.toml",
        "autostereogram.toml",
        "fig6-perfect-imaging-lenses.toml",
        "fig9-ggrin-lens.toml",
        "fig11a-multifocal-lens.toml",
        "fig11b-multifocal-lens.toml",
        "fig12-index-ratio.toml",
        "gradient-index-table.toml",
        "metatoy-window.toml",
        "fig14a-metric-interface-n10.toml",
        "fig14b-veselago-lens.toml",
        "fig14c-sheared-space.toml",
        "fig15a-metric-bubble.toml",
        "fig15b-minkowski-bubble.toml",
        "gcla-window-eta-minus-1.toml",
        "gcla-window-eta-u-minus-half.toml",
        "phase-hologram-window.toml",
        "ray-flipping-window.toml",
        "lorentz-window.toml",
        "teleporting-window.toml",
        "trajectories-glass-ball.toml",
        "trajectories-metatoy-window.toml",
        "trajectories-luneburg-focus.toml",
        "trajectories-hyperboloid.toml",
        "research/HolographicLensStarConicSectionTrajectoryPlotter.toml",
        "research/FourPiLensInsideView.toml",
        "research/SurroundAnaglyphCameraDemo.toml",
        "research/NegativeSpaceWedgeStarTrajectoryPlotter.toml",
        "research/CubeInRayRotationSheetStar.toml",
        "research/SpaceAroundBlackHoleVisualiser.toml",
        "research/NetOfHypercubeVisualiser.toml",
        "research/NetOfSymmetric4SimplexVisualiser.toml",
        "research/ShiftyGCLAsCubicCloakVisualiser.toml",
        "research/ShiftyGCLAsTetrahedralCloakVisualiser.toml",
        "research/NonAffineCubicCloakImageMaker.toml",
        "research/ExtendedRochesterCloakTrajectoryMovieMaker2.toml",
        "research/SphericalShiftyCloakVisualiser.toml",
        "research/IdealLensWormholeExplorer.toml",
        "research/PolyhedralShiftyCloakVisualiser.toml",
        "research/PixellationEffectsExplorer_1_0.toml",
        "gclas-cloak.toml",
        "gclas-tardis-window.toml",
        "gclas-pinch-transformation-window.toml",
        "gradient-index-volume.toml",
    ] {
        assert!(
            files.iter().any(|f| f.ends_with(name)),
            "scenes/{name} is missing"
        );
    }
    let dir = TempDir::new().unwrap();
    for file in &files {
        let run = timbre(dir.path(), &["check", path_str(file)]);
        run.assert_success();
        assert!(
            run.stdout.lines().next().unwrap().ends_with(": OK"),
            "{}",
            run.stdout
        );
        let mut args = vec![
            "render",
            "-q",
            path_str(file),
            "-o",
            "x.png",
            "--width",
            "32",
            "--height",
            "24",
            "--spp",
            "1",
        ];
        // A movie's first frame, named as Dr TIM numbers frames.
        let movie = run.stdout.contains("\n  movie:");
        if movie {
            args.extend(["--frame", "0"]);
        }
        timbre(dir.path(), &args).assert_success();
        let picture = if movie { "x-0000.png" } else { "x.png" };
        assert_eq!(
            decode_png(&dir.path().join(picture)).dimensions(),
            (32, 24),
            "{}",
            file.display()
        );
        if std::fs::read_to_string(file)
            .unwrap()
            .contains("[[ray_trajectory]]")
        {
            let run = timbre(dir.path(), &["trace", "--json", path_str(file)]);
            run.assert_success();
            let json: serde_json::Value = serde_json::from_str(&run.stdout).unwrap();
            assert!(!json["rays"].as_array().unwrap().is_empty());
        }
    }
}

#[test]
fn the_spelled_out_studio_is_the_built_in_one() {
    let dir = TempDir::new().unwrap();
    let studio = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/studio.toml");
    timbre(
        dir.path(),
        &[
            "render",
            "-q",
            path_str(&studio),
            "-o",
            "file.png",
            "--width",
            "80",
            "--height",
            "60",
        ],
    )
    .assert_success();
    timbre_line(
        dir.path(),
        "render -q -o builtin.png --width 80 --height 60",
    )
    .assert_success();
    let file = std::fs::read(dir.path().join("file.png")).unwrap();
    let builtin = std::fs::read(dir.path().join("builtin.png")).unwrap();
    assert!(
        file == builtin,
        "scenes/studio.toml renders differently from the built-in studio"
    );
}

#[test]
fn the_scene_format_example_checks() {
    let doc =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/SCENE_FORMAT.md"))
            .unwrap();
    let start = doc
        .find("```toml\n")
        .expect("a TOML example in docs/SCENE_FORMAT.md")
        + "```toml\n".len();
    let end = start + doc[start..].find("```").expect("the example ends");
    let dir = TempDir::new().unwrap();
    let scene = write(&dir, "example.toml", &doc[start..end]);
    let run = timbre(dir.path(), &["check", path_str(&scene)]);
    run.assert_success();
    for line in [
        "objects:      51",
        "point lights: 1",
        "render:       640x480 at 4 spp",
    ] {
        assert!(run.stdout.contains(line), "{}", run.stdout);
    }
}

#[test]
fn a_closed_standard_output_is_not_a_crash() {
    // `timbre check scene.toml | head -0`: the reader is gone before timbre prints.
    let dir = TempDir::new().unwrap();
    let scene = write(&dir, "s.toml", "studio = \"lattice\"\n");
    let mut child = Command::new(common::cli::TIMBRE)
        .args(["check", path_str(&scene)])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        out.status.success() && !stderr.contains("panicked"),
        "{stderr}"
    );
}

#[test]
fn progress_json_prints_lines_that_count_up_to_every_pixel_of_every_view() {
    let dir = TempDir::new().unwrap();
    let scene = write(&dir, "stereo.toml", "[camera]\nstereo = \"anaglyph\"\n");
    let run = timbre(
        dir.path(),
        &[
            "render",
            path_str(&scene),
            "-o",
            "a.png",
            "--width",
            "64",
            "--height",
            "48",
            "--progress",
            "json",
            "--quiet",
        ],
    );
    run.assert_success();
    assert!(run.stdout.is_empty(), "quiet: {}", run.stdout);
    let lines: Vec<serde_json::Value> = run
        .stderr
        .lines()
        .map(|l| serde_json::from_str(l).unwrap_or_else(|e| panic!("{e}: {l}")))
        .collect();
    assert!(lines.len() >= 2, "{}", run.stderr);
    let field = |line: &serde_json::Value, key: &str| line[key].as_f64();
    let total = 2.0 * 64.0 * 48.0; // two eyes
    for line in &lines {
        assert_eq!(field(line, "total_pixels"), Some(total), "{line}");
    }
    let (first, last) = (&lines[0], &lines[lines.len() - 1]);
    assert_eq!(field(first, "done_pixels"), Some(0.0));
    assert!(
        first["eta_s"].is_null(),
        "no estimate before any pixel: {first}"
    );
    assert_eq!(field(last, "done_pixels"), Some(total));
    assert_eq!(field(last, "fraction"), Some(1.0));
    assert_eq!(field(last, "eta_s"), Some(0.0));
    for pair in lines.windows(2) {
        for key in ["done_pixels", "elapsed_s"] {
            assert!(
                field(&pair[0], key) <= field(&pair[1], key),
                "{key}: {pair:?}"
            );
        }
    }
}

#[test]
fn a_large_render_streams_in_bounded_memory_and_what_cannot_fit_is_refused_up_front() {
    let dir = TempDir::new().unwrap();
    let capped = |args: &[&str]| {
        let mut command = Command::new("prlimit");
        command
            .arg("--as=1000000000")
            .arg(common::cli::TIMBRE)
            .arg("render")
            .args(args)
            .current_dir(dir.path());
        common::cli::run(command)
    };
    if Command::new("prlimit").arg("--version").output().is_err() {
        eprintln!("skipped: no prlimit");
        return;
    }
    // Under a 1 GB address-space cap, an 8192² single view (1.5 GiB for its f64 pixels alone,
    // had it been held in memory) is streamed to its file row by row.
    let run = capped(&["-o", "big.png", "--width", "8192", "--height", "8192"]);
    run.assert_success();
    let peak: f64 = run
        .stdout
        .split("peak memory ")
        .nth(1)
        .and_then(|m| m.split_whitespace().next())
        .and_then(|m| m.parse().ok())
        .expect("the peak memory line");
    assert!(peak < 256.0, "peak resident memory {peak} MiB");
    let image = decode_png(&dir.path().join("big.png"));
    assert_eq!(image.dimensions(), (8192, 8192));
    // The last row was rendered too: the floor's chequerboard has two colours there.
    let last: std::collections::HashSet<_> =
        (0..8192).map(|x| image.get_pixel(x, 8191).0).collect();
    assert!(last.len() >= 2, "{last:?}");
    // Two views held in memory to be combined (an anaglyph) would not fit: refused with exit 2
    // before rendering.
    let scene = write(
        dir.path(),
        "anaglyph.toml",
        "studio = \"lattice\"\n[camera]\nstereo = \"anaglyph\"\n",
    );
    let run = capped(&[
        path_str(&scene),
        "-o",
        "anaglyph.png",
        "--width",
        "8192",
        "--height",
        "8192",
    ]);
    run.assert_bad_input(&[
        "8192x8192",
        "of 2 views",
        "needs about",
        "GiB",
        "render a smaller image",
    ]);
    assert!(!run.stdout.contains("rays in"), "nothing was rendered");
    assert_eq!(files_in(&dir), ["anaglyph.toml", "big.png"]);
}

#[test]
fn each_render_setting_is_an_option_meaning_the_render_key() {
    // The render settings are defined once (SETTINGS): `--KEY V` (dashes for underscores) means
    // what `[render] KEY = V` means, for every one of them, and changes the picture.
    use timbre::scene::settings::SETTINGS;
    let values = [
        ("width", "60"),
        ("height", "40"),
        ("spp", "3"),
        ("seed", "5"),
        ("max_trace_level", "1"),
        ("shadows", "false"),
        ("exposure", "1"),
        ("png_transfer", "\"srgb\""),
    ];
    let keys: Vec<&str> = SETTINGS.iter().map(|s| s.key).collect();
    assert_eq!(
        keys,
        values.map(|(k, _)| k),
        "a new setting needs a value here"
    );
    let dir = TempDir::new().unwrap();
    let d = dir.path();
    // Two samples a pixel, so that the seed (of the samples after the first) shows, and a
    // mirror, so that the trace level does (it sees the lattice at the second level).
    let studio = "studio = \"lattice\"\n[[object]]\n\
                  shape = { type = \"sphere\", centre = [1.2, 0.8, 7], radius = 0.5 }\n\
                  surface = { type = \"mirror\" }\n\
                  [render]\nwidth = 64\nheight = 48\nspp = 2\n";
    write(d, "plain.toml", studio);
    // The pixels (the files name their scene files, which differ).
    let pixels = |name: &str| decode_png(&d.join(name)).into_raw();
    let render = |args: &[&str]| {
        timbre(d, &[&["render", "-q"], args].concat()).assert_success();
    };
    render(&["plain.toml", "-o", "plain.png"]);
    for (key, value) in values {
        // The plain scene with the key set in the file.
        let in_file = match studio.find(&format!("{key} = ")) {
            Some(at) => {
                let end = at + studio[at..].find('\n').unwrap();
                format!("{}{key} = {value}{}", &studio[..at], &studio[end..])
            }
            None => format!("{studio}{key} = {value}\n"),
        };
        // A width or height alone on the command line keeps the scene's 64:48 aspect ratio.
        let in_file = match key {
            "width" => in_file.replace("height = 48", "height = 45"),
            "height" => in_file.replace("width = 64", "width = 53"),
            _ => in_file,
        };
        write(d, "keyed.toml", &in_file);
        render(&["keyed.toml", "-o", "file.png"]);
        let option = format!("--{}", key.replace('_', "-"));
        // A string in the file is bare on the command line.
        render(&[
            "plain.toml",
            "-o",
            "option.png",
            &option,
            value.trim_matches('"'),
        ]);
        let option = pixels("option.png");
        assert!(
            pixels("file.png") == option,
            "--{key} is not [render] {key}"
        );
        assert!(
            option != pixels("plain.png"),
            "--{key} {value} changes nothing"
        );
    }
}

/// `--crop x0,x1,y0,y1` writes those pixels of the picture as a picture of their own: the PNG
/// is the same window of the whole PNG, and the OpenEXR the same window of the whole OpenEXR,
/// with its display window at the origin (a plain picture, not a part placed in a larger one);
/// a crop outside the image, or with a part's options, is refused.
#[test]
fn a_crop_is_that_window_of_the_whole_picture() {
    let dir = TempDir::new().unwrap();
    let d = dir.path();
    let render = |args: &[&str]| {
        timbre(
            d,
            &[&["render", "-q", "--width", "48", "--height", "36"], args].concat(),
        )
    };
    render(&["-o", "whole.png"]).assert_success();
    render(&["-o", "crop.png", "--crop", "10,30,5,25"]).assert_success();
    let whole = decode_png(&d.join("whole.png"));
    let crop = decode_png(&d.join("crop.png"));
    assert_eq!(crop.dimensions(), (20, 20));
    for (x, y, p) in crop.enumerate_pixels() {
        assert_eq!(*p, *whole.get_pixel(x + 10, y + 5), "({x}, {y})");
    }
    render(&["-o", "whole.exr"]).assert_success();
    render(&["-o", "crop.exr", "--crop", "10,30,5,25"]).assert_success();
    let (whole, crop) = (
        Exr::read(&d.join("whole.exr")),
        Exr::read(&d.join("crop.exr")),
    );
    assert_eq!(crop.size, (20, 20));
    for (x, y) in (0..20).flat_map(|y| (0..20).map(move |x| (x, y))) {
        for c in ["R", "G", "B"] {
            assert_eq!(crop.at(c, x, y), whole.at(c, x + 10, y + 5));
        }
    }
    let meta = exr::meta::MetaData::read_from_file(d.join("crop.exr"), false).unwrap();
    let header = &meta.headers[0];
    assert_eq!(header.own_attributes.layer_position, exr::math::Vec2(0, 0));
    assert_eq!(
        header.shared_attributes.display_window.size,
        exr::math::Vec2(20, 20)
    );
    let run = render(&["-o", "out.png", "--crop", "40,50,0,10"]);
    assert_eq!(run.code, Some(2));
    assert!(
        run.stderr
            .contains("--crop 40,50,0,10 is not within the 48x36 image"),
        "{}",
        run.stderr
    );
    let run = render(&["-o", "out.exr", "--crop", "0,8,0,8", "--samples", "0..1"]);
    assert_eq!(run.code, Some(2), "{}", run.stderr);
}

/// `timbre image`: `convert --exposure 1` doubles every value (2^1), the picture otherwise as
/// it was; `diff` measures the difference and exits 1 only past a threshold given (0 for equal
/// pictures, whose PSNR is infinite), 2 for pictures of different sizes; `info` tells the size
/// and what the render recorded.
#[test]
fn image_tools_convert_compare_and_describe() {
    let dir = TempDir::new().unwrap();
    let d = dir.path();
    let run = |args: &[&str]| timbre(d, args);
    run(&[
        "render", "-q", "--width", "32", "--height", "24", "--seed", "9", "-o", "a.exr",
    ])
    .assert_success();
    run(&["image", "convert", "a.exr", "b.exr", "--exposure", "1"]).assert_success();
    let (a, b) = (Exr::read(&d.join("a.exr")), Exr::read(&d.join("b.exr")));
    assert_eq!(b.size, (32, 24));
    for c in ["R", "G", "B"] {
        for (x, y) in [(0, 0), (16, 12), (31, 23)] {
            assert_eq!(b.at(c, x, y), 2.0 * a.at(c, x, y));
        }
    }
    let same = run(&["image", "diff", "a.exr", "a.exr", "--max-error", "0"]);
    same.assert_success();
    assert!(same.stdout.starts_with("PSNR inf dB"), "{}", same.stdout);
    // b − a = a: the largest error is the largest value of a.
    let largest = ["R", "G", "B"]
        .iter()
        .flat_map(|c| a.channels[*c].iter())
        .fold(0f32, |m, &v| m.max(v)) as f64;
    let within = format!("{}", largest * 1.001);
    let beyond = format!("{}", largest * 0.999);
    run(&["image", "diff", "a.exr", "b.exr", "--max-error", &within]).assert_success();
    let over = run(&["image", "diff", "a.exr", "b.exr", "--max-error", &beyond]);
    assert_eq!(over.code, Some(1), "{}", over.stderr);
    let many = run(&["image", "diff", "a.exr", "b.exr", "--max-differing", "10"]);
    assert_eq!(many.code, Some(1), "{}", many.stderr);
    run(&[
        "render",
        "-q",
        "--width",
        "16",
        "--height",
        "12",
        "-o",
        "small.exr",
    ])
    .assert_success();
    let sizes = run(&["image", "diff", "a.exr", "small.exr"]);
    assert_eq!(sizes.code, Some(2), "{}", sizes.stderr);
    assert!(
        sizes.stderr.contains("is 32x24 but small.exr is 16x12"),
        "{}",
        sizes.stderr
    );
    let info = run(&["image", "info", "a.exr"]);
    info.assert_success();
    assert!(
        info.stdout.starts_with("a.exr: 32x24 exr"),
        "{}",
        info.stdout
    );
    assert!(info.stdout.contains("timbre.seed: 9"), "{}", info.stdout);
}
