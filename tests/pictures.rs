//! Picture surfaces and the image sky in whole renders: the texel a pixel sees, worked out by
//! hand from the pinhole camera's geometry and the mapping; the sky's texel in the direction
//! of a pixel; a picture file named several times read once; pictures confined as other files.

mod common;

use std::path::Path;

use glam::DVec3;
use tempfile::TempDir;
use timbre::scene::file::{self, Confinement};

use common::cli::write;
use common::images::{parse_as, render_text_in};

/// Writes an 8-bit RGB PNG of `width` × `height` texels, `texel(column, row from the top)`.
fn png(dir: &Path, name: &str, width: u32, height: u32, texel: impl Fn(u32, u32) -> [u8; 3]) {
    let pixels: Vec<u8> = (0..height)
        .flat_map(|r| (0..width).flat_map(move |c| (0..3).map(move |k| (c, r, k))))
        .map(|(c, r, k)| texel(c, r)[k])
        .collect();
    image::save_buffer(
        dir.join(name),
        &pixels,
        width,
        height,
        image::ExtendedColorType::Rgb8,
    )
    .unwrap();
}

/// An 8-bit texel as timbre reads it: value / 255, in single precision.
fn linear(t: [u8; 3]) -> DVec3 {
    DVec3::from_array(t.map(|v| (v as f32 / 255.0) as f64))
}

fn near(a: DVec3, b: DVec3) -> bool {
    (a - b).abs().max_element() < 1e-6
}

/// Texel (column c, row r) of the test pictures: a different colour for each.
fn numbered(c: u32, r: u32) -> [u8; 3] {
    [(10 + 25 * c) as u8, (20 + 100 * r) as u8, 128]
}

/// A pinhole camera at the origin looking along +z, 11 × 7 pixels, horizontal view angle
/// 2 atan(0.25): the outermost columns' centres are at ±0.25 of the distance ahead, so
/// pixel (i, j) looks at (0.05 (i − 5), 0.05 (3 − j), 1) and meets the plane z = 10 at
/// x = (i − 5)/2, y = (3 − j)/2. The plane's normal −z with u_direction +x gives u = x and
/// v = (n̂ × û)·p = −y. The 4 × 2 picture fills the rectangle from (u, v) = (−2.25, −1.25) of
/// size (4, 2), not tiled: column ⌊x + 2.25⌋, row from the top ⌊−y + 1.25⌋, for x in
/// [−2.25, 1.75) and y in (−0.75, 1.25]; elsewhere the surface is transparent and, without
/// studio, the pixel black. No pixel is within 0.25 of a texel's edge.
#[test]
fn each_pixel_shows_the_texel_its_ray_meets() {
    let dir = TempDir::new().unwrap();
    png(dir.path(), "p.png", 4, 2, numbered);
    let text = format!(
        r#"studio = "none"
[render]
width = 11
height = 7
[camera]
horizontal_view_angle_deg = {}
[[object]]
shape = {{ type = "plane", point = [0, 0, 10], normal = [0, 0, -1], u_direction = [1, 0, 0] }}
surface = {{ type = "picture", file = "p.png", corner = [-2.25, -1.25], size = [4, 2], tiled = false, lighting = "light-independent" }}
"#,
        2.0 * 0.25f64.atan().to_degrees()
    );
    let image = render_text_in(&text, dir.path());
    let mut seen = 0;
    for j in 0..7 {
        for i in 0..11 {
            let (x, y) = ((i as f64 - 5.0) / 2.0, (3.0 - j as f64) / 2.0);
            let expected = if (-2.25..1.75).contains(&x) && y > -0.75 && y <= 1.25 {
                seen += 1;
                linear(numbered(
                    (x + 2.25).floor() as u32,
                    (1.25 - y).floor() as u32,
                ))
            } else {
                DVec3::ZERO
            };
            let got = image.pixel(i, j);
            assert!(
                near(got, expected),
                "pixel ({i}, {j}): {got} not {expected}"
            );
        }
    }
    // 8 columns by 4 rows of pixels on the picture, 2 × 2 on each texel.
    assert_eq!(seen, 32);
}

/// The scene of `[sky]` with the 9 × 3 numbered picture and a 3 × 3 camera looking along
/// `view` with `up`: the centre pixel looks exactly along `view`.
fn sky_centre(dir: &Path, view: [f64; 3], up: [f64; 3], extra: &str) -> DVec3 {
    let text = format!(
        "studio = \"none\"\n[sky]\nimage = \"sky.png\"\n{extra}\n[render]\nwidth = 3\nheight = 3\n\
         [camera]\nview_direction = {view:?}\nup = {up:?}\n"
    );
    render_text_in(&text, dir).pixel(1, 1)
}

/// Equirectangular, +y up, the centre along +z, unmirrored from inside (x is to the right of
/// a camera looking along +z with +y up, so the picture's right half lies towards +x): +z is
/// u = 1/2, column 4.5 → 4 of 9, the middle row; +x is u = 3/4, column 6.75 → 6; −x is u = 1/4,
/// column 2.25 → 2; straight up is the top row. Rotated by 90° about +y the centre is along
/// +x; an intensity of 0.5 halves the texel.
#[test]
fn the_sky_shows_the_texel_in_the_direction_of_the_pixel() {
    let dir = TempDir::new().unwrap();
    png(dir.path(), "sky.png", 9, 3, numbered);
    let centre = |view, up, extra| sky_centre(dir.path(), view, up, extra);
    let y = [0.0, 1.0, 0.0];
    assert!(near(centre([0.0, 0.0, 1.0], y, ""), linear(numbered(4, 1))));
    assert!(near(centre([1.0, 0.0, 0.0], y, ""), linear(numbered(6, 1))));
    assert!(near(
        centre([-1.0, 0.0, 0.0], y, ""),
        linear(numbered(2, 1))
    ));
    let up = centre([0.0, 1.0, 0.0], [0.0, 0.0, 1.0], "");
    assert!((up.y - 20.0 / 255.0).abs() < 1e-6, "top row: {up}");
    assert!(near(
        centre([1.0, 0.0, 0.0], y, "rotation = 90\nintensity = 0.5"),
        0.5 * linear(numbered(4, 1))
    ));
}

/// With a studio the image replaces its constant sky (index 0, still named "sky"); without
/// one it adds the sky; the file named by two objects and the sky is read once.
#[test]
fn a_picture_named_three_times_is_read_once() {
    let dir = TempDir::new().unwrap();
    png(dir.path(), "p.png", 9, 3, numbered);
    let path = dir.path().join("scene.toml");
    let text = r#"[sky]
image = "p.png"
[[object]]
shape = { type = "sphere" }
surface = { type = "picture", file = "p.png" }
[[object]]
shape = { type = "plane" }
surface = { type = "chequerboard", surfaces = [{ type = "picture", file = "./p.png" }, { type = "matt", colour = [1, 1, 1] }] }
"#;
    let d = parse_as(text, path.to_str().unwrap());
    assert_eq!(d.objects[0].name, "sky");
    assert_eq!(d.pictures().len(), 1);
    assert_eq!(d.picture_bytes(), 9 * 3 * 12);
    let each: Vec<_> = d.objects.iter().map(|o| o.surface.pictures()).collect();
    assert_eq!(each[0], each[2]);
    assert_eq!(each[2], each[3]);
    let none = parse_as(
        "studio = \"none\"\n[sky]\nimage = \"p.png\"\n",
        path.to_str().unwrap(),
    );
    assert_eq!(none.objects.len(), 1);
    assert_eq!(none.objects[0].surface.kind(), "image-sky");
}

/// Pictures inside other surfaces count too, each file once: a mask (either-or), a holey
/// surface's mask inside a two-sided surface, a picture inside stripes and a semi-transparent
/// surface; two files of 9 × 3 and 2 × 2 texels hold 12 bytes a texel.
#[test]
fn pictures_inside_other_surfaces_are_counted_once() {
    let dir = TempDir::new().unwrap();
    png(dir.path(), "p.png", 9, 3, numbered);
    png(dir.path(), "q.png", 2, 2, numbered);
    let path = dir.path().join("scene.toml");
    let text = r#"studio = "none"
[[object]]
shape = { type = "parallelogram" }
surface = { type = "either-or", file = "p.png" }
[[object]]
shape = { type = "parallelogram" }
surface = { type = "two-sided", outside = { type = "holey", file = "q.png", surface = { type = "mirror" } } }
[[object]]
shape = { type = "parallelogram" }
surface = { type = "striped", surfaces = [{ type = "picture", file = "p.png" }, { type = "semi-transparent", surface = { type = "picture", file = "q.png" } }] }
"#;
    let d = parse_as(text, path.to_str().unwrap());
    assert_eq!(d.pictures().len(), 2);
    assert_eq!(d.picture_bytes(), (9 * 3 + 2 * 2) * 12);
    let each: Vec<usize> = d
        .objects
        .iter()
        .map(|o| o.surface.pictures().len())
        .collect();
    assert_eq!(each, [1, 1, 2]);
}

/// Read as `timbre serve` reads its page's text, a picture surface or a sky outside the scene
/// file's directory is refused before it is read, as meshes and includes are; one inside is
/// read.
#[test]
fn pictures_are_confined_to_the_scene_directory() {
    let outer = TempDir::new().unwrap();
    png(outer.path(), "outside.png", 1, 1, numbered);
    let inner = outer.path().join("scenes");
    std::fs::create_dir(&inner).unwrap();
    png(&inner, "in.png", 1, 1, numbered);
    let path = inner.join("scene.toml");
    let confined = Confinement {
        trusted: Box::new(|_| false),
        only_trusted: false,
    };
    let parse = |text: &str| file::parse_confined(text, path.to_str().unwrap(), &[], &confined);
    let object = |name: &str| {
        format!(
            "[[object]]\nshape = {{ type = \"sphere\" }}\nsurface = {{ type = \"picture\", file = \"{name}\" }}\n"
        )
    };
    for text in [
        object("../outside.png"),
        "[sky]\nimage = \"../outside.png\"\n".to_string(),
    ] {
        let e = parse(&text).unwrap_err().to_string();
        assert!(
            e.contains("'../outside.png': only files in the scene file's directory"),
            "{e}"
        );
    }
    assert!(parse(&object("in.png")).is_ok());
    assert!(parse("[sky]\nimage = \"in.png\"\n").is_ok());
    // Included scene files are confined too.
    write(&inner, "part.toml", object("../outside.png"));
    let e = parse("[[include]]\nfile = \"part.toml\"\n")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("only files in the scene file's directory"),
        "{e}"
    );
}
