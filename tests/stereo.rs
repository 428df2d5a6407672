//! Stereo outputs: anaglyph channels, which eye is which and where the eyes converge, HDMI 1.4a
//! frame-packing layouts, autostereograms of rendered scenes, and the scene-file keys.

mod common;

use common::cli::{assert_refused_at_line, decode_png, path_str, timbre, write};
use glam::DVec3;
use tempfile::TempDir;
use timbre::embree::Device;
use timbre::math::Colour;
use timbre::render::{Image, render};
use timbre::scene::Packing;
use timbre::scene::Stereo;
use timbre::scene::{Scene, SceneDescription, file};
use timbre::stereo::{Autostereogram, anaglyph, autostereogram, pack, render_stereo};

fn image(width: u32, height: u32, f: impl Fn(u32, u32) -> Colour) -> Image {
    Image {
        width,
        height,
        pixels: (0..height)
            .flat_map(|y| (0..width).map(move |x| (x, y)))
            .map(|(x, y)| f(x, y))
            .collect(),
        aovs: None,
        rays: 0,
    }
}

#[test]
fn anaglyph_channels_come_from_the_right_eyes() {
    let left = image(2, 1, |x, _| {
        [Colour::new(1.0, 0.0, 0.0), Colour::new(0.2, 0.4, 0.6)][x as usize]
    });
    let right = image(2, 1, |x, _| {
        [Colour::new(0.0, 0.0, 1.0), Colour::new(0.0, 1.0, 0.0)][x as usize]
    });
    let red_blue = anaglyph(&left, &right, false);
    // Luminance 0.2126 R + 0.7152 G + 0.0722 B: left eye in red, right eye in blue.
    assert_eq!(red_blue.pixels[0], Colour::new(0.2126, 0.0, 0.0722));
    let l1 = 0.2126 * 0.2 + 0.7152 * 0.4 + 0.0722 * 0.6;
    assert!((red_blue.pixels[1] - Colour::new(l1, 0.0, 0.7152)).length() < 1e-15);
    // Colour anaglyph: red from the left eye, green and blue from the right.
    let colour = anaglyph(&left, &right, true);
    assert_eq!(
        colour.pixels,
        vec![Colour::new(1.0, 0.0, 1.0), Colour::new(0.2, 1.0, 0.0)]
    );
}

#[test]
fn frame_packing_puts_the_left_view_left_or_on_top() {
    let left = image(4, 2, |x, y| Colour::new(1.0, x as f64, y as f64));
    let right = image(4, 2, |x, y| Colour::new(2.0, x as f64, y as f64));
    let sbs = pack(&left, &right, Packing::SideBySide, false);
    assert_eq!((sbs.width, sbs.height), (8, 2));
    assert_eq!(sbs.pixel(3, 1), Colour::new(1.0, 3.0, 1.0));
    assert_eq!(sbs.pixel(4, 0), Colour::new(2.0, 0.0, 0.0));
    let tb = pack(&left, &right, Packing::TopBottom, false);
    assert_eq!((tb.width, tb.height), (4, 4));
    assert_eq!(tb.pixel(2, 1), Colour::new(1.0, 2.0, 1.0));
    assert_eq!(tb.pixel(2, 2), Colour::new(2.0, 2.0, 0.0));
    // Half resolution: the frame keeps its size, each view squeezed by averaging pairs.
    let half = pack(&left, &right, Packing::SideBySide, true);
    assert_eq!((half.width, half.height), (4, 2));
    assert_eq!(half.pixel(1, 1), Colour::new(1.0, 2.5, 1.0));
    assert_eq!(half.pixel(2, 0), Colour::new(2.0, 0.5, 0.0));
    let half = pack(&left, &right, Packing::TopBottom, true);
    assert_eq!((half.width, half.height), (4, 2));
    assert_eq!(half.pixel(3, 0), Colour::new(1.0, 3.0, 0.5));
    assert_eq!(half.pixel(3, 1), Colour::new(2.0, 3.0, 0.5));
}

/// Black room, three small white balls: one on the axis 10 ahead (where the eyes converge), one
/// 40 ahead and one 5 ahead, at different heights.
fn balls(stereo: &str) -> SceneDescription {
    let text = format!(
        "studio = \"none\"\n[render]\nwidth = 200\nheight = 150\n\
         [camera]\nhorizontal_view_angle_deg = 30\nfocus_distance = 10\neye_separation = [0.4, 0, 0]\nstereo = \"{stereo}\"\n\
         [[light]]\ntype = \"ambient\"\ncolour = [1, 1, 1]\n\
         [[object]]\nshape = {{ type = \"sphere\", centre = [0, 0, 10], radius = 0.15 }}\nsurface = {{ type = \"matt\", colour = [1, 1, 1] }}\n\
         [[object]]\nshape = {{ type = \"sphere\", centre = [0, 2, 40], radius = 0.6 }}\nsurface = {{ type = \"matt\", colour = [1, 1, 1] }}\n\
         [[object]]\nshape = {{ type = \"sphere\", centre = [0, -0.7, 5], radius = 0.08 }}\nsurface = {{ type = \"matt\", colour = [1, 1, 1] }}\n"
    );
    file::parse(&text, "balls.toml").unwrap_or_else(|e| panic!("{e}"))
}

/// Mean x of the lit pixels of `image` in rows `rows`, within columns `columns`.
fn centroid_x(image: &Image, columns: std::ops::Range<u32>, rows: std::ops::Range<u32>) -> f64 {
    let (mut sum, mut n) = (0.0, 0.0);
    for y in rows {
        for x in columns.clone() {
            if image.pixel(x, y).x > 0.5 {
                sum += x as f64;
                n += 1.0;
            }
        }
    }
    assert!(n > 0.0, "nothing lit");
    sum / n
}

#[test]
fn the_eyes_converge_on_the_focus_plane() {
    let d = balls("side-by-side");
    let device = Device::new("").unwrap();
    let scene = Scene::build(&device, &d).unwrap();
    let packed = render_stereo(&scene, &d.camera, &d.render, &d.stereo, &|_| {}).unwrap();
    assert_eq!((packed.width, packed.height), (400, 150));
    // Rows of each ball: the far one is high, the near one low, the converged one central.
    let (far, mid, near) = (0..60, 65..85, 95..150);
    let x = |half: u32, rows: std::ops::Range<u32>| {
        centroid_x(&packed, half * 200..half * 200 + 200, rows) - (half * 200) as f64
    };
    let centre = 99.5;
    // On the focus plane: no parallax, both in the middle.
    assert!((x(0, mid.clone()) - centre).abs() < 0.5 && (x(1, mid) - centre).abs() < 0.5);
    // Behind it: the left eye (left half) sees the ball to the left, the right eye to the right.
    assert!(x(0, far.clone()) < centre - 3.0 && x(1, far.clone()) > centre + 3.0);
    assert!(
        (x(0, far.clone()) + x(1, far) - 2.0 * centre).abs() < 0.5,
        "symmetric"
    );
    // In front of it: crossed disparity.
    assert!(x(0, near.clone()) > centre + 3.0 && x(1, near) < centre - 3.0);

    // The left half is the view of the camera with its pupil moved by −s/2.
    let left = render(
        &scene,
        &d.camera.eye(DVec3::new(-0.2, 0.0, 0.0)),
        &d.render,
        &|_| {},
    )
    .unwrap();
    for y in 0..150 {
        for x in 0..200 {
            assert_eq!(packed.pixel(x, y), left.pixel(x, y));
        }
    }
}

/// The viewing geometry of Thimbleby, Inglis & Witten (IEEE Computer, 1994), written out here
/// from the paper: the eyes are `e` pixels apart at distance D from the screen, the far plane
/// is D behind the screen and depth z ∈ [0, 1] puts a point μzD in front of it, straight behind
/// its pixel. Measured from the eyes in units of D, the screen is at 1, the far plane at 2, the
/// near plane at 2 − μ and a point of depth z at 2 − μz.
struct Viewing {
    e: f64,
    mu: f64,
}

impl Viewing {
    /// Distance from the eyes (in D) of a point of depth z.
    fn distance(&self, z: f64) -> f64 {
        2.0 - self.mu * z
    }

    /// Where the lines of sight from a point of depth z to the eyes (±e/2 to the side of it)
    /// cross the screen: by similar triangles, e/2 × (1 − 1/distance) to either side, so
    /// s(z) = (1 − μz)e/(2 − μz) apart.
    fn separation(&self, z: f64) -> f64 {
        self.e * (1.0 - 1.0 / self.distance(z))
    }

    /// The two pixels of a row that show the point at pixel x and depth z (the paper's
    /// placement: s rounded, the left one ⌊s/2⌋ left of x), if both are in a row `width` long.
    fn pair(&self, x: usize, z: f64, width: usize) -> Option<(usize, usize)> {
        let s = self.separation(z).round() as usize;
        let left = x.checked_sub(s / 2)?;
        (left + s < width).then_some((left, left + s))
    }

    /// Whether the line of sight from the point at pixel x of `row` (its depth) to the eye on
    /// side `side` (−1 left, +1 right) passes in front of every other pixel's surface: at t
    /// pixels to that side the line is at distance (1 − 2t/e) × distance(z) from the eyes, and
    /// the surface there, at distance(row[x ± t]), blocks it if it is no farther. Past the near
    /// plane nothing can block; beyond the row's ends there is nothing.
    fn seen_by(&self, row: &[f64], x: usize, side: isize) -> bool {
        let from = self.distance(row[x]);
        (1..)
            .map(|t: usize| (t, from * (1.0 - 2.0 * t as f64 / self.e)))
            .take_while(|&(_, line)| line >= self.distance(1.0))
            .all(|(t, line)| {
                let column = x as isize + side * t as isize;
                usize::try_from(column)
                    .ok()
                    .and_then(|c| row.get(c))
                    .is_none_or(|&z| self.distance(z) > line)
            })
    }

    fn seen_by_both_eyes(&self, row: &[f64], x: usize) -> bool {
        self.seen_by(row, x, -1) && self.seen_by(row, x, 1)
    }
}

/// Pixels of `row` seen by both eyes whose two image pixels are in the row: every such pair of
/// `image` (the row's colours) must share its colour. Returns their number; panics at the
/// first pair that differs.
fn check_pairs(viewing: &Viewing, row: &[f64], image: &[Colour], what: &str) -> usize {
    let mut pairs = 0;
    for x in 0..row.len() {
        let Some((left, right)) = viewing.pair(x, row[x], row.len()) else {
            continue;
        };
        if viewing.seen_by_both_eyes(row, x) {
            assert_eq!(image[left], image[right], "{what}: x = {x}, z = {}", row[x]);
            pairs += 1;
        }
    }
    pairs
}

#[test]
fn an_autostereogram_shows_each_point_seen_by_both_eyes_in_one_colour() {
    // Depth maps with steps, slopes and waves, decoded by the viewing geometry worked out here
    // (not by the library's own separation or visibility).
    let (width, height) = (400usize, 40usize);
    let a = Autostereogram {
        eye_separation: 90,
        depth_of_field: 1.0 / 3.0,
        seed: 9,
        colour: true,
    };
    let viewing = Viewing {
        e: 90.0,
        mu: 1.0 / 3.0,
    };
    // s(0) = E/2, s(1) = (2/3)·90/(5/3) = 36.
    assert_eq!(viewing.separation(0.0), 45.0);
    assert!((viewing.separation(1.0) - 36.0).abs() < 1e-12);
    let map = |f: &dyn Fn(usize, usize) -> f64| -> Vec<f64> {
        (0..width * height)
            .map(|i| f(i % width, i / width))
            .collect()
    };
    let maps: [(&str, Vec<f64>); 4] = [
        (
            "steps",
            map(&|x, y| match (x, y) {
                (170..240, 10..30) => 1.0,
                (100..300, _) => 0.6,
                _ => 0.0,
            }),
        ),
        ("ramp up", map(&|x, _| x as f64 / 399.0)),
        ("ramp down", map(&|x, _| 1.0 - x as f64 / 399.0)),
        (
            "wave",
            map(&|x, y| 0.5 + 0.5 * (x as f64 / 15.0 + y as f64).sin()),
        ),
    ];
    for (what, depth) in maps {
        let image = a.render(&depth, width as u32, height as u32);
        let pairs: usize = depth
            .chunks(width)
            .zip(image.chunks(width))
            .map(|(row, colours)| check_pairs(&viewing, row, colours, what))
            .sum();
        assert!(pairs > 300 * height, "{what}: only {pairs} pairs");
    }
}

#[test]
fn points_beside_a_near_plateau_hidden_from_one_eye_get_free_dots() {
    // A plateau on the near plane (z = 1) over columns 150..250, the far plane (z = 0) around
    // it, E = 90, μ = 1/3. From a far point the line of sight to an eye is at distance
    // 2 (1 − 2t/90) t pixels to the side, in front of the plateau (at 2 − 1/3) only while
    // t ≥ 7.5: the 7 far pixels on either side of the plateau (143..=149 and 250..=256) are
    // hidden from one eye, every other point is seen by both.
    let width = 400;
    let mut row = vec![0.0; width];
    row[150..250].fill(1.0);
    let viewing = Viewing {
        e: 90.0,
        mu: 1.0 / 3.0,
    };
    let hidden: Vec<usize> = (0..width)
        .filter(|&x| !viewing.seen_by_both_eyes(&row, x))
        .collect();
    let by_hand: Vec<usize> = (143..=149).chain(250..=256).collect();
    assert_eq!(hidden, by_hand);
    let a = Autostereogram {
        eye_separation: 90,
        depth_of_field: 1.0 / 3.0,
        seed: 5,
        colour: true,
    };
    let image = a.render(&row, width as u32, 1);
    assert!(check_pairs(&viewing, &row, &image, "plateau") > 300);
    // The pairs of the hidden points are not tied together: random dots differ.
    for x in by_hand {
        let (left, right) = viewing.pair(x, 0.0, width).unwrap();
        assert_ne!(image[left], image[right], "x = {x}");
    }
    // The plateau repeats at its own separation (36), not at the far plane's (45): pixel x
    // matches x − 36 where the point between them, x − 18, is on the plateau.
    let at = |s: usize| (170..260).filter(|&x| image[x - s] == image[x]).count();
    assert_eq!(at(36), 90);
    assert!(at(45) < 5, "{}", at(45));
}

#[test]
fn an_autostereogram_repeats_with_the_separation_of_each_depth() {
    // A wall 20 ahead (the far plane) with a ball in front, its front 9 ahead (the near plane).
    let text = "studio = \"none\"\n[render]\nwidth = 300\nheight = 100\nseed = 3\n\
        [camera]\nhorizontal_view_angle_deg = 40\nstereo = \"autostereogram\"\n\
        [camera.autostereogram]\neye_separation_px = 80\ndepth_of_field = 0.5\nnear = 9\nfar = 20\n\
        [[light]]\ntype = \"ambient\"\ncolour = [1, 1, 1]\n\
        [[object]]\nshape = { type = \"plane\", point = [0, 0, 20], normal = [0, 0, -1] }\nsurface = { type = \"matt\", colour = [1, 1, 1] }\n\
        [[object]]\nshape = { type = \"sphere\", centre = [0, 0, 10], radius = 1 }\nsurface = { type = \"matt\", colour = [1, 1, 1] }\n";
    let d = file::parse(text, "a.toml").unwrap();
    let options = autostereogram(&d.stereo, 300, 3).unwrap();
    assert_eq!((options.eye_separation, options.depth_of_field), (80, 0.5));
    let viewing = Viewing { e: 80.0, mu: 0.5 };
    let device = Device::new("").unwrap();
    let scene = Scene::build(&device, &d).unwrap();
    let image = render_stereo(&scene, &d.camera, &d.render, &d.stereo, &|_| {}).unwrap();
    assert_eq!((image.width, image.height), (300, 100));
    let matches = |y: u32, xs: std::ops::Range<u32>, s: u32| {
        xs.filter(|&x| image.pixel(x, y) == image.pixel(x - s, y))
            .count()
    };
    // Far wall: z = 0, s = E/2 = 40. Ball front: z = 1, s = (1 − μ)E/(2 − μ) = 26.7, rounded
    // 27. The ball spans rows 9 to 91 and columns 109 to 191 (5.7° of the ±20° across).
    // Check the top row (wall only) and the middle row's centre (ball).
    let far_s = viewing.separation(0.0).round() as u32;
    assert_eq!(far_s, 40);
    assert_eq!(
        matches(2, 40..300, far_s),
        260,
        "the wall's row repeats every 40 pixels"
    );
    assert!(matches(2, 40..300, 27) < 30);
    let near_s = viewing.separation(1.0).round() as u32;
    assert_eq!(near_s, 27);
    assert!(
        matches(50, 140..160, near_s) >= 18,
        "{}",
        matches(50, 140..160, near_s)
    );
    // Colours are random dots, not the scene's shading.
    let distinct: std::collections::HashSet<[u64; 3]> = image
        .pixels
        .iter()
        .map(|c| c.to_array().map(f64::to_bits))
        .collect();
    assert!(distinct.len() > 100);
}

#[test]
fn the_command_line_writes_packed_frames() {
    let dir = TempDir::new().unwrap();
    let scene = write(
        &dir,
        "s.toml",
        "studio = \"lattice\"\n[render]\nwidth = 40\nheight = 30\n",
    );
    let render = |mode: &str, out: &str| {
        timbre(
            dir.path(),
            &[
                "render",
                "-q",
                path_str(&scene),
                "-o",
                out,
                "--set",
                &format!("camera.stereo={mode}"),
            ],
        )
    };
    for (mode, size) in [
        ("side-by-side", (80, 30)),
        ("top-bottom", (40, 60)),
        ("side-by-side-half", (40, 30)),
        ("top-bottom-half", (40, 30)),
        ("anaglyph", (40, 30)),
        ("colour-anaglyph", (40, 30)),
        ("autostereogram", (40, 30)),
    ] {
        render(mode, "x.png").assert_success();
        assert_eq!(
            decode_png(&dir.path().join("x.png")).dimensions(),
            size,
            "{mode}"
        );
    }
    // A red-blue anaglyph has no green.
    render("anaglyph", "a.png").assert_success();
    assert!(
        decode_png(&dir.path().join("a.png"))
            .pixels()
            .all(|p| p[1] == 0)
    );
    render("stereo", "x.png").assert_bad_input(&["unknown variant `stereo`"]);
    timbre(
        dir.path(),
        &[
            "render",
            "-q",
            path_str(&scene),
            "-o",
            "x.png",
            "--width",
            "41",
            "--set",
            "camera.stereo=side-by-side-half",
        ],
    )
    .assert_bad_input(&["even width, got 41"]);
    timbre(
        dir.path(),
        &[
            "render",
            "-q",
            path_str(&scene),
            "-o",
            "x.exr",
            "--aov",
            "depth",
            "--set",
            "camera.stereo=anaglyph",
        ],
    )
    .assert_bad_input(&["--aov works with single views only"]);
}

#[test]
fn bad_camera_keys_are_reported_where_they_are() {
    let dir = TempDir::new().unwrap();
    let check = |text: &str, needles: &[&str], line: usize| {
        assert_refused_at_line(dir.path(), text, needles, line)
    };
    check(
        "[camera]\nbeta = [0, 0.6, 0.8]\n",
        &["beta must have a magnitude below 1"],
        2,
    );
    check("[camera]\nbeta = [0, nan, 0]\n", &["finite"], 2);
    check(
        "[camera]\nshutter = \"curtain\"\n",
        &["unknown variant `curtain`", "entrance-pupil"],
        2,
    );
    check(
        "[camera]\ntype = \"finite-aperture\"\n",
        &["needs aperture_radius > 0"],
        1,
    );
    check(
        "[camera]\n\naperture_radius = 0.1\ntype = \"pinhole\"\n",
        &["only a finite-aperture camera"],
        3,
    );
    check(
        "[camera]\ntype = \"orthographic\"\n",
        &["needs view_width"],
        1,
    );
    check(
        "[camera]\ntype = \"orthographic\"\nview_width = 2\nhorizontal_view_angle_deg = 30\n",
        &["not a view angle"],
        4,
    );
    check(
        "[camera]\nfocus_distance = 3\nfocus_surface = []\n",
        &["not both"],
        3,
    );
    check("[camera]\nfocus_surface = []\n", &["at least one shape"], 2);
    check(
        "[camera]\nstereo = \"anaglyph\"\neye_separation = [0, 0, 0]\n",
        &["eye_separation must not be zero"],
        3,
    );
    check(
        "[camera]\n[camera.autostereogram]\nnear = 2\n",
        &["needs stereo = \"autostereogram\""],
        2,
    );
    check(
        "[camera]\nstereo = \"autostereogram\"\n[camera.autostereogram]\nnear = 5\nfar = 2\n",
        &["near (5) must be less than far (2)"],
        3,
    );
    check(
        "[camera]\nstereo = \"autostereogram\"\n[camera.autostereogram]\ndepth_of_field = 1\n",
        &["depth_of_field must be between 0 and 1"],
        3,
    );
    check(
        "[camera]\nstereo = \"anaglyph\"\neye_separation = [0.4, 0, 0.1]\n",
        &["eye_separation must be perpendicular to the view direction"],
        3,
    );
    check(
        "[[object]]\nframe = \"train\"\nshape = { type = \"sphere\", centre = [0, 0, 5], radius = 1 }\nsurface = { type = \"mirror\" }\n",
        &["unknown variant `train`"],
        2,
    );
}

#[test]
fn stereo_outputs_are_checked_against_the_final_image_size() {
    let dir = TempDir::new().unwrap();
    let odd = write(
        &dir,
        "odd.toml",
        "studio = \"lattice\"\n[render]\nwidth = 41\nheight = 30\n[camera]\nstereo = \"side-by-side-half\"\n",
    );
    let path = path_str(&odd);
    timbre(dir.path(), &["check", path]).assert_bad_input(&[path, "even width, got 41"]);
    timbre(dir.path(), &["render", "-q", path, "-o", "x.png"])
        .assert_bad_input(&["even width, got 41"]);
    // The command line may fix what the file gets wrong (both sides: a width alone would keep
    // the file's aspect ratio).
    timbre(
        dir.path(),
        &[
            "render", "-q", path, "-o", "x.png", "--width", "40", "--height", "30",
        ],
    )
    .assert_success();
    assert_eq!(decode_png(&dir.path().join("x.png")).dimensions(), (40, 30));

    let auto = write(
        &dir,
        "auto.toml",
        "[render]\nwidth = 100\n[camera]\nstereo = \"autostereogram\"\n[camera.autostereogram]\neye_separation_px = 250\n",
    );
    timbre(dir.path(), &["check", path_str(&auto)])
        .assert_bad_input(&["eye_separation_px", "too wide for an image 100 pixels wide"]);
    let auto = write(
        &dir,
        "narrow.toml",
        "[camera]\nstereo = \"autostereogram\"\n",
    );
    timbre(
        dir.path(),
        &[
            "render",
            "-q",
            path_str(&auto),
            "-o",
            "x.png",
            "--width",
            "5",
        ],
    )
    .assert_bad_input(&["at least 6 pixels wide, got 5"]);
}

#[test]
fn an_autostereogram_of_a_ball_in_empty_space_is_not_flat() {
    // Most rays hit nothing: the default depth range comes from the ball alone, so the ball
    // stands out (its pixels repeat closer than the far separation).
    let d = file::parse(
        "studio = \"none\"\n[render]\nwidth = 400\nheight = 100\n\
         [camera]\nstereo = \"autostereogram\"\n[camera.autostereogram]\neye_separation_px = 90\n\
         [[light]]\ntype = \"ambient\"\ncolour = [1, 1, 1]\n\
         [[object]]\nshape = { type = \"sphere\", centre = [0, 0, 10], radius = 0.5 }\nsurface = { type = \"matt\", colour = [1, 1, 1] }\n",
        "ball.toml",
    )
    .unwrap();
    let device = Device::new("").unwrap();
    let scene = Scene::build(&device, &d).unwrap();
    let image = render_stereo(&scene, &d.camera, &d.render, &d.stereo, &|_| {}).unwrap();
    let far = |x: u32| image.pixel(x, 50) == image.pixel(x - 45, 50);
    // The ball covers about a quarter of the picture, columns 143 to 257 of the middle row.
    let repeating_far = (190..210).filter(|&x| far(x)).count();
    assert!(
        repeating_far < 5,
        "{repeating_far} ball pixels repeat at the far separation"
    );
    assert!((50..90).all(far), "the empty background is the far plane");
}

#[test]
fn objects_and_groups_can_move_with_the_camera() {
    let d = file::parse(
        "studio = \"empty\"\n\
         [[object]]\nname = \"a\"\nframe = \"camera\"\nshape = { type = \"sphere\", centre = [0, 0, 5], radius = 1 }\nsurface = { type = \"mirror\" }\n\
         [[group]]\nname = \"g\"\nframe = \"camera\"\n\
         [[group.object]]\nname = \"b\"\nshape = { type = \"sphere\", centre = [0, 0, 5], radius = 1 }\nsurface = { type = \"mirror\" }\n\
         [[group.object]]\nname = \"c\"\nframe = \"scene\"\nshape = { type = \"sphere\", centre = [0, 0, 5], radius = 1 }\nsurface = { type = \"mirror\" }\n",
        "f.toml",
    )
    .unwrap();
    use timbre::math::ReferenceFrame::{Camera, Scene as SceneFrame};
    let frames: Vec<_> = d
        .objects
        .iter()
        .map(|o| (o.name.as_str(), o.frame))
        .collect();
    assert_eq!(
        frames,
        [
            ("sky", SceneFrame),
            ("floor", SceneFrame),
            ("a", Camera),
            ("g/b", Camera),
            ("g/c", SceneFrame)
        ]
    );
    assert_eq!(d.stereo, Stereo::Mono);
}
