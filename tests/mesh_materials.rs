//! Materials from mesh files: an OBJ file's MTL colours become its parts' surfaces, one per
//! `usemtl`; a given surface overrides them; unsupported keys are warnings; a missing library
//! or material is an error located in the scene file and the OBJ file.

mod common;

use std::path::Path;

use glam::DVec3;
use tempfile::TempDir;
use timbre::io::to_rgb8;
use timbre::scene::{SceneDescription, file};
use timbre::surfaces::{Coloured, Surface};

use common::images::render_description;

/// A unit square at z = 0 in two triangles, the lower right one `red` and the upper left one
/// `blue`.
const SQUARE: &str = "mtllib two.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n\
                      usemtl red\nf 1 2 3\nusemtl blue\nf 1 3 4\n";
const TWO: &str = "newmtl red\nKd 1 0 0\nKs 0.25 0.5 0.75\nnewmtl blue\nKd 0 0 1\nd 0.25\n";

fn dir_with(files: &[(&str, &str)]) -> TempDir {
    let dir = TempDir::new().unwrap();
    for (name, text) in files {
        std::fs::write(dir.path().join(name), text).unwrap();
    }
    dir
}

fn parse_in(dir: &Path, text: &str) -> Result<SceneDescription, String> {
    let path = dir.join("scene.toml");
    file::parse(text, path.to_str().unwrap()).map_err(|e| e.to_string())
}

fn surface_of<'a>(d: &'a SceneDescription, name: &str) -> &'a Surface {
    let found = d.objects.iter().find(|o| o.name == name);
    &found
        .unwrap_or_else(|| panic!("no object '{name}'"))
        .surface
}

const SCENE: &str = "[[object]]\nname = \"sq\"\nshape = { type = \"mesh\", file = \"square.obj\" }\n\
                     transform = { translate = [-0.5, -0.5, 5] }\n";

#[test]
fn each_usemtl_part_shows_its_mtl_colours() {
    let dir = dir_with(&[("square.obj", SQUARE), ("two.mtl", TWO)]);
    let d = parse_in(dir.path(), SCENE).unwrap();
    assert_eq!(
        *surface_of(&d, "sq/red"),
        Surface::Coloured(Coloured {
            diffuse: DVec3::new(1.0, 0.0, 0.0),
            specular: DVec3::new(0.25, 0.5, 0.75),
        })
    );
    // d = 0.25: a quarter of the colour, three quarters of what lies behind.
    let Surface::Dissolved(blue) = surface_of(&d, "sq/blue") else {
        panic!("blue is not dissolved");
    };
    assert_eq!(blue.parts[0].weight, DVec3::splat(0.25));
    assert_eq!(blue.parts[1].weight, DVec3::splat(0.75));
    assert_eq!(
        blue.parts[0].surface,
        Surface::Coloured(Coloured::matt(DVec3::new(0.0, 0.0, 1.0)))
    );
}

#[test]
fn a_red_diffuse_material_reflects_no_green_or_blue() {
    let mtl = "newmtl red\nKd 1 0 0\n";
    let obj = "mtllib red.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nusemtl red\nf 1 2 3 4\n";
    let dir = dir_with(&[("square.obj", obj), ("red.mtl", mtl)]);
    let d = parse_in(
        dir.path(),
        &format!("[render]\nwidth = 40\nheight = 30\nspp = 1\n{SCENE}"),
    )
    .unwrap();
    let picture = to_rgb8(&render_description(&d));
    let centre = picture.get_pixel(20, 15);
    assert!(centre[0] > 50, "{centre:?}");
    assert_eq!((centre[1], centre[2]), (0, 0), "{centre:?}");
}

#[test]
fn a_given_surface_overrides_the_materials() {
    let dir = dir_with(&[("square.obj", SQUARE), ("two.mtl", TWO)]);
    let text = format!("{SCENE}surface = {{ type = \"mirror\" }}\n");
    let d = parse_in(dir.path(), &text).unwrap();
    let mesh: Vec<_> = d
        .objects
        .iter()
        .filter(|o| o.name.starts_with("sq"))
        .collect();
    // Without the materials the file is one part.
    assert_eq!(mesh.len(), 1);
    assert_eq!(mesh[0].surface.kind(), "mirror");
}

#[test]
fn every_copy_of_an_array_keeps_its_parts_materials() {
    let dir = dir_with(&[("square.obj", SQUARE), ("two.mtl", TWO)]);
    let text = format!("{SCENE}array = {{ vectors = [[2, 0, 0]], counts = [3] }}\n");
    let d = parse_in(dir.path(), &text).unwrap();
    assert_eq!(d.arrays.len(), 1);
    let array = &d.arrays[0];
    assert_eq!(array.offsets.len(), 3);
    let mut kinds: Vec<(&str, &str)> = d.objects[array.objects.clone()]
        .iter()
        .map(|o| (o.name.as_str(), o.surface.kind()))
        .collect();
    kinds.sort();
    assert_eq!(
        kinds,
        [("sq/blue", "mesh material"), ("sq/red", "coloured")]
    );
}

#[test]
fn unsupported_mtl_keys_are_warnings_naming_them() {
    let mtl = format!("{TWO}Ka 0.1 0.1 0.1\nillum 2\n");
    let dir = dir_with(&[("square.obj", SQUARE), ("two.mtl", &mtl)]);
    let warnings = parse_in(dir.path(), SCENE).unwrap().warnings();
    for (key, line) in [("Ka", 7), ("illum", 8)] {
        let expected = format!("object 'sq': two.mtl:{line}:1: '{key}' is not supported");
        assert!(
            warnings.iter().any(|w| w.starts_with(&expected)),
            "{expected} not in {warnings:?}"
        );
    }
}

#[test]
fn a_missing_library_or_material_is_a_located_error() {
    let obj = SQUARE.replace("two.mtl", "none.mtl");
    let dir = dir_with(&[("square.obj", &obj)]);
    let e = parse_in(dir.path(), SCENE).unwrap_err();
    assert!(e.contains("scene.toml:3:9: object 'sq': "), "{e}");
    assert!(e.contains("square.obj:1:8: mtllib: "), "{e}");
    assert!(e.contains("none.mtl"), "{e}");

    let obj = SQUARE.replace("usemtl blue", "usemtl green");
    let dir = dir_with(&[("square.obj", &obj), ("two.mtl", TWO)]);
    let e = parse_in(dir.path(), SCENE).unwrap_err();
    assert!(
        e.contains("square.obj:8:8: usemtl: no material 'green'"),
        "{e}"
    );

    let dir = dir_with(&[
        ("square.obj", SQUARE),
        ("two.mtl", "newmtl red\nKd 2 0 0\n"),
    ]);
    let e = parse_in(dir.path(), SCENE).unwrap_err();
    assert!(
        e.contains("in 'two.mtl': 2:4: Kd: 2 must be in [0, 1]"),
        "{e}"
    );
}

#[test]
fn a_mesh_without_materials_still_needs_a_surface() {
    let dir = dir_with(&[("square.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")]);
    let e = parse_in(dir.path(), SCENE).unwrap_err();
    assert!(
        e.contains(":3:9: object 'sq': missing field `surface`"),
        "{e}"
    );
}

/// A 2 × 2 texture: red, green on the top row; blue, white on the bottom one.
fn write_quadrants(path: &Path) {
    let mut picture = image::RgbImage::new(2, 2);
    picture.put_pixel(0, 0, image::Rgb([255, 0, 0]));
    picture.put_pixel(1, 0, image::Rgb([0, 255, 0]));
    picture.put_pixel(0, 1, image::Rgb([0, 0, 255]));
    picture.put_pixel(1, 1, image::Rgb([255, 255, 255]));
    picture.save(path).unwrap();
}

#[test]
fn a_textured_material_shows_the_texel_at_the_interpolated_texture_coordinates() {
    // The square's texture coordinates run over the texture once; u right, v up.
    let obj = "mtllib t.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n\
               usemtl t\nf 1/1 2/2 3/3 4/4\n";
    let dir = dir_with(&[
        ("square.obj", obj),
        ("t.mtl", "newmtl t\nKd 1 1 1\nmap_Kd q.png\n"),
    ]);
    write_quadrants(&dir.path().join("q.png"));
    let d = parse_in(
        dir.path(),
        &format!("[render]\nwidth = 40\nheight = 40\nspp = 1\n{SCENE}"),
    )
    .unwrap();
    let picture = to_rgb8(&render_description(&d));
    // The camera looks along +z with x to the left on the picture (the square spans x in
    // [-0.5, 0.5] at z = 5): find the square's pixels and check each quadrant's hue.
    let hue = |x: u32, y: u32| {
        let p = picture.get_pixel(x, y);
        (p[0] > 20, p[1] > 20, p[2] > 20)
    };
    let (cx, cy) = (20, 20);
    let off = 2;
    let quadrants = [
        hue(cx - off, cy - off),
        hue(cx + off, cy - off),
        hue(cx - off, cy + off),
        hue(cx + off, cy + off),
    ];
    // Top row of the picture is the top of the texture (v up = y up); the four colours each
    // appear once.
    let mut seen = quadrants.to_vec();
    seen.sort();
    assert_eq!(
        seen,
        [
            (false, false, true),
            (false, true, false),
            (true, false, false),
            (true, true, true)
        ],
        "{quadrants:?}"
    );
    assert!(
        [(true, false, false), (false, true, false)].contains(&quadrants[0]),
        "the top of the picture shows the top row of the texture: {quadrants:?}"
    );
}

#[test]
fn a_missing_texture_is_an_error_naming_it() {
    let obj = "mtllib t.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nusemtl t\nf 1/1 2/2 3/3\n";
    let dir = dir_with(&[
        ("square.obj", obj),
        ("t.mtl", "newmtl t\nmap_Kd gone.png\n"),
    ]);
    let e = parse_in(dir.path(), SCENE).unwrap_err();
    assert!(
        e.contains(":3:9: object 'sq': material 't': map_Kd 'gone.png': "),
        "{e}"
    );
}

#[test]
fn a_texture_without_texture_coordinates_is_refused() {
    let obj = "mtllib t.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl t\nf 1 2 3\n";
    let dir = dir_with(&[("square.obj", obj), ("t.mtl", "newmtl t\nmap_Kd q.png\n")]);
    write_quadrants(&dir.path().join("q.png"));
    let e = parse_in(dir.path(), SCENE).unwrap_err();
    assert!(e.contains("needs texture coordinates (OBJ vt)"), "{e}");
}

/// A PLY square (z = 0, x and y in [0, 1]) with the given vertex colours (`uchar` r g b).
fn coloured_ply(colours: [[u8; 3]; 4]) -> String {
    let corners = ["0 0 0", "1 0 0", "1 1 0", "0 1 0"];
    let mut text = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n\
                    property float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n\
                    element face 1\nproperty list uchar int vertex_indices\nend_header\n"
        .to_string();
    for (p, [r, g, b]) in corners.iter().zip(colours) {
        text += &format!("{p} {r} {g} {b}\n");
    }
    text + "4 0 1 2 3\n"
}

const PLY_SCENE: &str = "[render]\nwidth = 40\nheight = 30\nspp = 1\n[[object]]\nname = \"sq\"\n\
                         shape = { type = \"mesh\", file = \"square.ply\" }\n\
                         transform = { translate = [-0.5, -0.5, 5] }\n";

#[test]
fn ply_vertex_colours_are_the_surface_when_none_is_given() {
    let ply = coloured_ply([[255, 0, 0]; 4]);
    let dir = dir_with(&[("square.ply", &ply)]);
    let d = parse_in(dir.path(), PLY_SCENE).unwrap();
    assert_eq!(surface_of(&d, "sq").kind(), "vertex colours");
    let Some(timbre::geometry::Shape::TriangleMesh(m)) =
        d.objects.iter().find(|o| o.name == "sq").map(|o| &o.shape)
    else {
        panic!("not a mesh");
    };
    // 255 of uchar is 1.
    assert_eq!(m.colours().unwrap()[0], DVec3::new(1.0, 0.0, 0.0));
    let picture = to_rgb8(&render_description(&d));
    let centre = picture.get_pixel(20, 15);
    assert!(centre[0] > 50, "{centre:?}");
    assert_eq!((centre[1], centre[2]), (0, 0), "{centre:?}");
}

#[test]
fn ply_vertex_colours_are_interpolated_to_their_mean_at_the_centroid() {
    // Triangle 0 of the fan is vertices 0, 1, 2; its centroid (2/3, 1/3, 0) sees the mean.
    let ply = coloured_ply([[255, 0, 0], [0, 255, 0], [0, 0, 255], [0, 0, 0]]);
    let dir = dir_with(&[("square.ply", &ply)]);
    let d = parse_in(dir.path(), PLY_SCENE).unwrap();
    let o = d.objects.iter().find(|o| o.name == "sq").unwrap();
    let timbre::geometry::Shape::TriangleMesh(m) = &o.shape else {
        panic!("not a mesh");
    };
    let [a, b, c] = m.triangles()[0].map(|i| m.vertices()[i as usize]);
    let c = m.colour_at((a + b + c) / 3.0, 0).unwrap();
    assert!((c - DVec3::splat(1.0 / 3.0)).length() < 1e-12, "{c}");
}

#[test]
fn a_ply_colour_out_of_range_is_a_located_error() {
    let ply = coloured_ply([[255, 0, 0]; 4]).replace("property uchar red", "property float red");
    let ply = ply.replacen("0 0 0 255 0 0", "0 0 0 1.5 0 0", 1);
    let dir = dir_with(&[("square.ply", &ply)]);
    let e = parse_in(dir.path(), PLY_SCENE).unwrap_err();
    assert!(e.contains("square.ply:13:"), "{e}");
    assert!(
        e.contains("red is 1.5: a colour's component must be in [0, 1]"),
        "{e}"
    );
}

#[test]
fn ply_texture_coordinates_are_the_meshs_surface_coordinates() {
    let ply = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
               property float z\nproperty float s\nproperty float t\nelement face 1\n\
               property list uchar int vertex_indices\nend_header\n\
               0 0 0 0 0\n1 0 0 0.5 0\n0 1 0 0 0.25\n3 0 1 2\n";
    let dir = dir_with(&[("square.ply", ply)]);
    let d = parse_in(
        dir.path(),
        &format!("{PLY_SCENE}surface = {{ type = \"mirror\" }}\n"),
    )
    .unwrap();
    let o = d.objects.iter().find(|o| o.name == "sq").unwrap();
    // The centroid's coordinates are the mean of the corners' (0, 0), (0.5, 0), (0, 0.25).
    let [a, b, c] = match &o.shape {
        timbre::geometry::Shape::TriangleMesh(m) => {
            m.triangles()[0].map(|i| m.vertices()[i as usize])
        }
        _ => panic!("not a mesh"),
    };
    let at = o.shape.coordinates((a + b + c) / 3.0, 0);
    assert!(
        (at - glam::DVec2::new(0.5, 0.25) / 3.0).length() < 1e-12,
        "{at}"
    );
}
