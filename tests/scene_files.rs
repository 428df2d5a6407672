//! Integration tests of the scene-file placement features: transforms, groups, arrays,
//! includes, `--set` overrides and `timbre check`.
//!
//! Library tests parse TOML text with `timbre::scene::file::{parse, load, load_with}`; CLI tests
//! run the built binary in a temporary directory. Every scene is tiny (renders are 32×24 at
//! one sample per pixel), so the whole file runs in a second or two.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

use glam::{DMat3, DVec3};
use tempfile::TempDir;

use common::cli::{TIMBRE, decode_png, files_in, location, path_str, run, timbre, write};
use timbre::geometry::{
    AnalyticShape, Cylinder, ObjectArray, Parallelogram, Shape, Sphere, TriangleMesh,
};
use timbre::scene::file::{self, MAX_ARRAY_ELEMENTS, Override};
use timbre::scene::{SceneDescription, SceneObject};

// ---------------------------------------------------------------------------------------------
// Helpers
// ---------------------------------------------------------------------------------------------

/// A matt white surface, for objects whose surface does not matter.
const MATT: &str = r#"surface = { type = "matt", colour = [1, 1, 1] }"#;

/// Parses `text` (named "s.toml"), panicking with the error if it is rejected.
#[track_caller]
fn parse(text: &str) -> SceneDescription {
    file::parse(text, "s.toml").unwrap_or_else(|e| panic!("{e}\nin:\n{text}"))
}

/// The error message for `text` (named "s.toml"), panicking if it is accepted.
#[track_caller]
fn parse_error(text: &str) -> String {
    match file::parse(text, "s.toml") {
        Ok(_) => panic!("accepted:\n{text}"),
        Err(e) => e.to_string(),
    }
}

/// The 1-based number of the only line of `text` containing `needle`.
#[track_caller]
fn line_of(text: &str, needle: &str) -> usize {
    let lines: Vec<usize> = text
        .lines()
        .enumerate()
        .filter(|(_, l)| l.contains(needle))
        .map(|(i, _)| i + 1)
        .collect();
    assert_eq!(
        lines.len(),
        1,
        "{needle:?} is on lines {lines:?} of:\n{text}"
    );
    lines[0]
}

/// Asserts that `message` is `s.toml:LINE:COL: ...` with LINE the line of `needle` in `text`,
/// and that it contains every one of `parts`.
#[track_caller]
fn assert_error_at(text: &str, needle: &str, parts: &[&str]) {
    let message = parse_error(text);
    assert!(message.starts_with("s.toml:"), "{message}");
    assert_eq!(
        location(&message, "s.toml").0,
        line_of(text, needle),
        "wrong line: {message}"
    );
    for part in parts {
        assert!(message.contains(part), "lacks {part:?}: {message}");
    }
}

#[track_caller]
fn object<'a>(scene: &'a SceneDescription, name: &str) -> &'a SceneObject {
    let names: Vec<&str> = scene.objects.iter().map(|o| o.name.as_str()).collect();
    let mut found = scene.objects.iter().filter(|o| o.name == name);
    let o = found
        .next()
        .unwrap_or_else(|| panic!("no object {name:?} among {names:?}"));
    assert!(found.next().is_none(), "two objects {name:?} in {names:?}");
    o
}

fn index_of(scene: &SceneDescription, name: &str) -> usize {
    scene
        .objects
        .iter()
        .position(|o| o.name == name)
        .unwrap_or_else(|| panic!("no object {name:?}"))
}

#[track_caller]
fn sphere<'a>(scene: &'a SceneDescription, name: &str) -> &'a Sphere {
    match &object(scene, name).shape {
        Shape::Sphere(s) => s,
        other => panic!("{name} is not a sphere: {other:?}"),
    }
}

#[track_caller]
fn cylinder<'a>(scene: &'a SceneDescription, name: &str) -> &'a Cylinder {
    match &object(scene, name).shape {
        Shape::Cylinder(c) => c,
        other => panic!("{name} is not a cylinder: {other:?}"),
    }
}

#[track_caller]
fn parallelogram<'a>(scene: &'a SceneDescription, name: &str) -> &'a Parallelogram {
    match &object(scene, name).shape {
        Shape::Parallelogram(p) => p,
        other => panic!("{name} is not a parallelogram: {other:?}"),
    }
}

#[track_caller]
fn mesh<'a>(scene: &'a SceneDescription, name: &str) -> &'a TriangleMesh {
    match &object(scene, name).shape {
        Shape::TriangleMesh(m) => m,
        other => panic!("{name} is not a triangle mesh: {other:?}"),
    }
}

fn v(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

#[track_caller]
fn assert_close(actual: DVec3, expected: DVec3) {
    assert!(
        (actual - expected).length() < 1e-9,
        "expected {expected}, got {actual}"
    );
}

#[track_caller]
fn assert_all_close(actual: &[DVec3], expected: &[DVec3]) {
    assert_eq!(
        actual.len(),
        expected.len(),
        "expected {expected:?}, got {actual:?}"
    );
    for (a, e) in actual.iter().zip(expected) {
        assert!(
            (*a - *e).length() < 1e-9,
            "expected {expected:?}, got {actual:?}"
        );
    }
}

/// The outward normal of triangle `i` of `m`, from its winding: (v1 − v0) × (v2 − v0).
fn winding_normal(m: &TriangleMesh, i: usize) -> DVec3 {
    let [a, b, c] = m.triangles()[i].map(|k| m.vertices()[k as usize]);
    (b - a).cross(c - a).normalize()
}

/// The only array containing the object `name`.
#[track_caller]
fn array_of<'a>(scene: &'a SceneDescription, name: &str) -> &'a ObjectArray {
    let i = index_of(scene, name);
    let mut found = scene.arrays.iter().filter(|a| a.objects.contains(&i));
    let a = found
        .next()
        .unwrap_or_else(|| panic!("{name} is in no array: {:?}", scene.arrays));
    assert!(found.next().is_none(), "{name} is in two arrays");
    a
}

/// Every object appears exactly once, and every array's range is a valid, non-empty range
/// of objects; no object is in two arrays.
#[track_caller]
fn assert_arrays_well_formed(scene: &SceneDescription) {
    let mut owner = vec![None; scene.objects.len()];
    for (k, a) in scene.arrays.iter().enumerate() {
        assert!(
            a.objects.start < a.objects.end && a.objects.end <= scene.objects.len(),
            "bad range {:?} for {} objects",
            a.objects,
            scene.objects.len()
        );
        assert!(!a.offsets.is_empty(), "array {k} has no offsets");
        for i in a.objects.clone() {
            assert_eq!(owner[i], None, "object {i} is in arrays {owner:?} and {k}");
            owner[i] = Some(k);
        }
    }
}

// ---------------------------------------------------------------------------------------------
// 1. Transforms
// ---------------------------------------------------------------------------------------------

#[test]
fn an_objects_transform_scales_then_rotates_then_translates() {
    let scene = parse(&format!(
        r#"studio = "none"
[[object]]
name = "ball"
shape = {{ type = "sphere", centre = [1, 0, 0], radius = 0.5 }}
{MATT}
transform = {{ scale = 2, rotate = {{ axis = [0, 0, 1], angle_deg = 90 }}, translate = [0, 0, 5] }}

[[object]]
name = "tri"
shape = {{ type = "triangle_mesh", vertices = [[0, 0, 0], [1, 0, 0], [1, 1, 1]], triangles = [[0, 1, 2]] }}
{MATT}
transform = {{ scale = [1, 2, 3], rotate = {{ axis = [1, 0, 0], angle_deg = 90 }}, translate = [1, 1, 1] }}

[[object]]
name = "stick"
shape = {{ type = "cylinder", start = [0, 0, 0], end = [0, 0, 1], radius = 0.25 }}
{MATT}
transform = {{ scale = 4, rotate = {{ axis = [0, 1, 0], angle_deg = 90 }} }}

[[object]]
name = "tile"
shape = {{ type = "parallelogram", corner = [0, 0, 0], span_u = [1, 0, 0], span_v = [0, 1, 0] }}
{MATT}
transform = {{ scale = [2, 3, 1], translate = [0, 0, -1] }}

[[object]]
name = "moved only"
shape = {{ type = "sphere", centre = [1, 2, 3], radius = 1 }}
{MATT}
transform = {{ translate = [-1, -2, -3] }}
"#
    ));
    assert_eq!(scene.objects.len(), 5);
    assert!(scene.arrays.is_empty());

    // (1,0,0) ×2 → (2,0,0), 90° about z → (0,2,0), + (0,0,5) → (0,2,5).
    let ball = sphere(&scene, "ball");
    assert_close(ball.centre(), v(0.0, 2.0, 5.0));
    assert!((ball.radius() - 1.0).abs() < 1e-12, "{}", ball.radius());

    // (x,y,z) → (x,2y,3z) → 90° about x: (x, −3z, 2y) → + (1,1,1).
    let tri = mesh(&scene, "tri");
    assert_all_close(
        tri.vertices(),
        &[v(1.0, 1.0, 1.0), v(2.0, 1.0, 1.0), v(2.0, -2.0, 3.0)],
    );

    // A right-handed 90° turn about y takes +z to +x.
    let stick = cylinder(&scene, "stick");
    assert_close(stick.start(), DVec3::ZERO);
    assert_close(stick.end(), v(4.0, 0.0, 0.0));
    assert!((stick.radius() - 1.0).abs() < 1e-12);

    // Parallelograms take non-uniform scales.
    let tile = parallelogram(&scene, "tile");
    assert_close(tile.corner(), v(0.0, 0.0, -1.0));
    assert_close(tile.span_u(), v(2.0, 0.0, 0.0));
    assert_close(tile.span_v(), v(0.0, 3.0, 0.0));

    assert_close(sphere(&scene, "moved only").centre(), DVec3::ZERO);
}

#[test]
fn a_groups_transform_applies_after_its_members() {
    let scene = parse(&format!(
        r#"studio = "none"
# Member: translate by x; group: turn 90° about z. Group after member puts the ball on +y;
# the other order would leave it on +x.
[[group]]
name = "turned"
transform = {{ rotate = {{ axis = [0, 0, 1], angle_deg = 90 }} }}
[[group.object]]
name = "ball"
shape = {{ type = "sphere", centre = [0, 0, 0], radius = 1 }}
{MATT}
transform = {{ translate = [1, 0, 0] }}

# Member: turn 90° about z; group: translate by x. Group after member puts the ball at (1,1,0)
# (the member's turn moves (0,1,0) to (-1,0,0) first); the other order would give (-1,1,0).
[[group]]
name = "shifted"
transform = {{ translate = [2, 0, 0] }}
[[group.object]]
name = "ball"
shape = {{ type = "sphere", centre = [0, 1, 0], radius = 1 }}
{MATT}
transform = {{ rotate = {{ axis = [0, 0, 1], angle_deg = 90 }} }}

# Group scale after member translation: the offset is scaled too.
[[group]]
name = "grown"
transform = {{ scale = 3 }}
[[group.object]]
name = "ball"
shape = {{ type = "sphere", centre = [0, 0, 0], radius = 0.5 }}
{MATT}
transform = {{ translate = [0, 0, 1] }}

# Nested groups: innermost first.
[[group]]
name = "outer"
transform = {{ translate = [0, 0, 10] }}
[[group.group]]
name = "inner"
transform = {{ rotate = {{ axis = [0, 0, 1], angle_deg = 90 }} }}
[[group.group.object]]
name = "ball"
shape = {{ type = "sphere", centre = [0, 0, 0], radius = 1 }}
{MATT}
transform = {{ translate = [1, 0, 0] }}
[[group.group.object]]
shape = {{ type = "sphere", centre = [2, 0, 0], radius = 1 }}
{MATT}
"#
    ));
    assert_eq!(scene.objects.len(), 5);
    assert_close(sphere(&scene, "turned/ball").centre(), v(0.0, 1.0, 0.0));
    assert_close(sphere(&scene, "shifted/ball").centre(), v(1.0, 0.0, 0.0));
    let grown = sphere(&scene, "grown/ball");
    assert_close(grown.centre(), v(0.0, 0.0, 3.0));
    assert!((grown.radius() - 1.5).abs() < 1e-12);
    assert_close(
        sphere(&scene, "outer/inner/ball").centre(),
        v(0.0, 1.0, 10.0),
    );
    // The fifth object is unnamed: "object N" inside the groups' names.
    let unnamed = scene
        .objects
        .iter()
        .find(|o| o.name.starts_with("outer/inner/object "))
        .unwrap_or_else(|| panic!("no unnamed object in {:?}", scene.objects));
    let Shape::Sphere(s) = &unnamed.shape else {
        panic!("{unnamed:?}")
    };
    assert_close(s.centre(), v(0.0, 2.0, 10.0));
}

#[test]
fn a_reflection_keeps_the_outward_normal_of_parallelograms_and_meshes() {
    // A unit tile and a triangle in the plane z = 0, both facing +z, placed by reflections.
    let tile = r#"shape = { type = "parallelogram", corner = [0, 0, 0], span_u = [1, 0, 0], span_v = [0, 1, 0] }"#;
    let tri = r#"shape = { type = "triangle_mesh", vertices = [[0, 0, 0], [1, 0, 0], [0, 1, 0]], triangles = [[0, 1, 2]] }"#;
    let mut text = String::from("studio = \"none\"\n");
    let cases = [
        ("z mirror", "scale = [1, 1, -1]"),
        ("x mirror", "scale = [-1, 1, 1]"),
        ("inversion", "scale = -1"),
        (
            "turned x mirror",
            "scale = [-1, 2, 1], rotate = { axis = [1, 1, 0], angle_deg = 30 }",
        ),
        ("no mirror", "scale = [1, 2, 3]"),
    ];
    for (name, transform) in cases {
        for (kind, shape) in [("tile", tile), ("tri", tri)] {
            text += &format!(
                "[[object]]\nname = \"{name} {kind}\"\n{shape}\n{MATT}\ntransform = {{ {transform} }}\n"
            );
        }
    }
    // A reflection in a group, and two reflections (member and group) that cancel.
    for (name, group, member) in [
        (
            "group mirror",
            "scale = [1, 1, -1]",
            "translate = [0, 0, 1]",
        ),
        ("double mirror", "scale = [1, 1, -1]", "scale = [1, 1, -1]"),
    ] {
        text += &format!("[[group]]\nname = \"{name}\"\ntransform = {{ {group} }}\n");
        for (kind, shape) in [("tile", tile), ("tri", tri)] {
            text += &format!(
                "[[group.object]]\nname = \"{kind}\"\n{shape}\n{MATT}\ntransform = {{ {member} }}\n"
            );
        }
    }
    let scene = parse(&text);

    // The image of the outward side is on the side of M⁻ᵀ n.
    let turn = DMat3::from_axis_angle(v(1.0, 1.0, 0.0).normalize(), 30f64.to_radians());
    let expected = [
        ("z mirror", DVec3::NEG_Z),
        ("x mirror", DVec3::Z),
        ("inversion", DVec3::NEG_Z),
        (
            "turned x mirror",
            (turn * DMat3::from_diagonal(v(-1.0, 2.0, 1.0)))
                .inverse()
                .transpose()
                .mul_vec3(DVec3::Z)
                .normalize(),
        ),
        ("no mirror", DVec3::Z),
        ("group mirror/", DVec3::NEG_Z),
        ("double mirror/", DVec3::Z),
    ];
    for (prefix, normal) in expected {
        let sep = if prefix.ends_with('/') { "" } else { " " };
        let p = parallelogram(&scene, &format!("{prefix}{sep}tile"));
        assert!(
            (p.frame(p.corner(), 0).w - normal).length() < 1e-9,
            "{prefix} tile faces {}, not {normal}",
            p.frame(p.corner(), 0).w
        );
        let m = mesh(&scene, &format!("{prefix}{sep}tri"));
        assert!(
            (winding_normal(m, 0) - normal).length() < 1e-9,
            "{prefix} triangle faces {}, not {normal}",
            winding_normal(m, 0)
        );
    }

    // The mirrored tile covers the mirror image of the tile: the unit square at z = 0 under
    // the x mirror is [-1, 0] × [0, 1].
    let mirrored = parallelogram(&scene, "x mirror tile");
    let (lo, hi) = mirrored.bounds().unwrap();
    assert_close(lo, v(-1.0, 0.0, 0.0));
    assert_close(hi, v(0.0, 1.0, 0.0));
    let (lo, hi) = parallelogram(&scene, "group mirror/tile").bounds().unwrap();
    assert_close(lo, v(0.0, 0.0, -1.0));
    assert_close(hi, v(1.0, 1.0, -1.0));
}

// ---------------------------------------------------------------------------------------------
// 2. Arrays
// ---------------------------------------------------------------------------------------------

fn array_scene(array: &str) -> String {
    format!(
        r#"studio = "none"
[[object]]
name = "ball"
shape = {{ type = "sphere", centre = [0, 0, 0], radius = 0.1 }}
{MATT}
array = {array}
"#
    )
}

#[track_caller]
fn offsets_of(array: &str) -> Vec<DVec3> {
    let scene = parse(&array_scene(array));
    assert_eq!(scene.objects.len(), 1, "an arrayed object appears once");
    assert_eq!(scene.arrays.len(), 1);
    assert_eq!(scene.arrays[0].objects, 0..1);
    scene.arrays[0].offsets.clone()
}

#[test]
fn arrays_place_copies_on_1d_2d_and_3d_grids() {
    assert_all_close(
        &offsets_of("{ vectors = [[2, 0, 0]], counts = [3] }"),
        &[v(0.0, 0.0, 0.0), v(2.0, 0.0, 0.0), v(4.0, 0.0, 0.0)],
    );
    assert_all_close(
        &offsets_of("{ vectors = [[1, 1, 0]], counts = [1] }"),
        &[DVec3::ZERO],
    );

    // The first vector runs fastest.
    assert_all_close(
        &offsets_of("{ vectors = [[1, 0, 0], [0, 2, 0]], counts = [2, 3] }"),
        &[
            v(0.0, 0.0, 0.0),
            v(1.0, 0.0, 0.0),
            v(0.0, 2.0, 0.0),
            v(1.0, 2.0, 0.0),
            v(0.0, 4.0, 0.0),
            v(1.0, 4.0, 0.0),
        ],
    );

    let three = offsets_of("{ vectors = [[1, 0, 0], [0, 1, 0], [0, 0, 1]], counts = [2, 3, 4] }");
    assert_eq!(three.len(), 24);
    for k in 0..4 {
        for j in 0..3 {
            for i in 0..2 {
                assert_close(three[i + 2 * j + 6 * k], v(i as f64, j as f64, k as f64));
            }
        }
    }

    // Vectors need not be orthogonal or axis-aligned.
    let skew = offsets_of("{ vectors = [[1, 1, 0], [0, 1, 1]], counts = [2, 2], centred = false }");
    assert_all_close(
        &skew,
        &[
            v(0.0, 0.0, 0.0),
            v(1.0, 1.0, 0.0),
            v(0.0, 1.0, 1.0),
            v(1.0, 2.0, 1.0),
        ],
    );
}

#[test]
fn centred_arrays_are_centred_on_the_object() {
    assert_all_close(
        &offsets_of("{ vectors = [[2, 0, 0]], counts = [3], centred = true }"),
        &[v(-2.0, 0.0, 0.0), v(0.0, 0.0, 0.0), v(2.0, 0.0, 0.0)],
    );
    assert_all_close(
        &offsets_of("{ vectors = [[1, 0, 0], [0, 1, 0]], counts = [2, 2], centred = true }"),
        &[
            v(-0.5, -0.5, 0.0),
            v(0.5, -0.5, 0.0),
            v(-0.5, 0.5, 0.0),
            v(0.5, 0.5, 0.0),
        ],
    );
    let cube = offsets_of(
        "{ vectors = [[1, 0, 0], [0, 2, 0], [0, 0, 3]], counts = [4, 3, 2], centred = true }",
    );
    assert_eq!(cube.len(), 24);
    let mean = cube.iter().sum::<DVec3>() / cube.len() as f64;
    assert_close(mean, DVec3::ZERO);
    assert_close(cube[0], v(-1.5, -2.0, -1.5));
    assert_close(cube[23], v(1.5, 2.0, 1.5));
}

#[test]
fn array_vectors_are_in_the_enclosing_frame() {
    let scene = parse(&format!(
        r#"studio = "none"
# The object's own transform turns and moves it, but not its array.
[[object]]
name = "turned"
shape = {{ type = "cylinder", start = [0, 0, 0], end = [1, 0, 0], radius = 0.1 }}
{MATT}
transform = {{ rotate = {{ axis = [0, 0, 1], angle_deg = 90 }}, translate = [0, 0, 7] }}
array = {{ vectors = [[1, 0, 0]], counts = [3] }}

# An array inside a turned and moved group: the group turns the vectors (and does not move them).
[[group]]
name = "g"
transform = {{ rotate = {{ axis = [0, 0, 1], angle_deg = 90 }}, translate = [5, 5, 5] }}
array = {{ vectors = [[0, 0, 2]], counts = [2] }}
[[group.object]]
name = "ball"
shape = {{ type = "sphere", centre = [0, 0, 0], radius = 0.1 }}
{MATT}
array = {{ vectors = [[1, 0, 0]], counts = [3] }}
"#
    ));
    assert_arrays_well_formed(&scene);
    let c = cylinder(&scene, "turned");
    assert_close(c.start(), v(0.0, 0.0, 7.0));
    assert_close(c.end(), v(0.0, 1.0, 7.0));
    assert_all_close(
        &array_of(&scene, "turned").offsets,
        &[v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(2.0, 0.0, 0.0)],
    );

    assert_close(sphere(&scene, "g/ball").centre(), v(5.0, 5.0, 5.0));
    // The member's array along the group's x is along world y; the group's own array is in
    // the world frame (the group's turn about z leaves z alone anyway).
    assert_all_close(
        &array_of(&scene, "g/ball").offsets,
        &[
            v(0.0, 0.0, 0.0),
            v(0.0, 1.0, 0.0),
            v(0.0, 2.0, 0.0),
            v(0.0, 0.0, 2.0),
            v(0.0, 1.0, 2.0),
            v(0.0, 2.0, 2.0),
        ],
    );
}

#[test]
fn a_groups_array_is_not_turned_by_the_groups_own_transform() {
    let scene = parse(&format!(
        r#"studio = "none"
[[group]]
name = "outer"
transform = {{ rotate = {{ axis = [0, 0, 1], angle_deg = 90 }} }}
[[group.group]]
name = "inner"
transform = {{ rotate = {{ axis = [1, 0, 0], angle_deg = 90 }} }}
array = {{ vectors = [[1, 0, 0]], counts = [2] }}
[[group.group.object]]
name = "ball"
shape = {{ type = "sphere", centre = [0, 0, 0], radius = 0.1 }}
{MATT}
"#
    ));
    // The inner group's array is in the outer group's frame: the outer turn takes x to y;
    // the inner group's own turn about x does not apply to it.
    assert_all_close(
        &array_of(&scene, "outer/inner/ball").offsets,
        &[v(0.0, 0.0, 0.0), v(0.0, 1.0, 0.0)],
    );
}

#[test]
fn arrays_of_groups_containing_arrays_flatten_into_sums() {
    let scene = parse(&format!(
        r#"studio = "none"
[[object]]
name = "single"
shape = {{ type = "sphere", centre = [0, 0, -5], radius = 0.1 }}
{MATT}

[[group]]
name = "rows"
array = {{ vectors = [[0, 10, 0]], counts = [3] }}
[[group.object]]
name = "row"
shape = {{ type = "sphere", centre = [0, 0, 0], radius = 0.1 }}
{MATT}
array = {{ vectors = [[1, 0, 0]], counts = [4] }}
[[group.object]]
name = "marker"
shape = {{ type = "sphere", centre = [0, 0, 1], radius = 0.1 }}
{MATT}

[[group]]
name = "stack"
array = {{ vectors = [[0, 0, 100]], counts = [2] }}
[[group.group]]
name = "sheet"
array = {{ vectors = [[0, 1, 0], [0, 0, 1]], counts = [2, 3] }}
[[group.group.object]]
name = "grain"
shape = {{ type = "sphere", centre = [0, 0, 0], radius = 0.1 }}
{MATT}
array = {{ vectors = [[0.5, 0, 0]], counts = [5] }}
"#
    ));
    assert_arrays_well_formed(&scene);
    assert_eq!(scene.objects.len(), 4, "each object appears once");
    assert_eq!(scene.arrays.len(), 3);
    assert!(
        scene
            .arrays
            .iter()
            .all(|a| !a.objects.contains(&index_of(&scene, "single"))),
        "an object in no array stays out of arrays"
    );

    // rows × row: 3 × 4 sums, inner (row) fastest.
    let row = &array_of(&scene, "rows/row").offsets;
    assert_eq!(row.len(), 12);
    for j in 0..3 {
        for i in 0..4 {
            assert!(
                row.contains(&v(i as f64, 10.0 * j as f64, 0.0)),
                "missing ({i}, {}, 0) in {row:?}",
                10 * j
            );
        }
    }
    assert_close(row[6], v(2.0, 10.0, 0.0));

    // The marker, in no array of its own, is repeated by the group's array alone.
    assert_all_close(
        &array_of(&scene, "rows/marker").offsets,
        &[v(0.0, 0.0, 0.0), v(0.0, 10.0, 0.0), v(0.0, 20.0, 0.0)],
    );
    assert_ne!(
        array_of(&scene, "rows/marker").objects,
        array_of(&scene, "rows/row").objects
    );

    // Three levels: 2 × (2 × 3) × 5 copies, one flat array of all the sums.
    let grain = &array_of(&scene, "stack/sheet/grain").offsets;
    assert_eq!(grain.len(), 2 * 2 * 3 * 5);
    let mut expected = Vec::new();
    for s in 0..2 {
        for k in 0..3 {
            for j in 0..2 {
                for i in 0..5 {
                    expected.push(v(0.5 * i as f64, j as f64, k as f64 + 100.0 * s as f64));
                }
            }
        }
    }
    let mut sorted = grain.clone();
    let key = |a: &DVec3| (a.z, a.y, a.x);
    sorted.sort_by(|a, b| key(a).partial_cmp(&key(b)).unwrap());
    assert_all_close(&sorted, &expected);
    assert!(grain.contains(&v(2.0, 1.0, 102.0)));

    let summary = scene.summary();
    assert_eq!(summary.objects, 4);
    assert_eq!(summary.instances, 12 + 3 + 60);
}

#[test]
fn arrays_after_the_studio_index_the_right_objects() {
    let scene = file::parse(
        &format!(
            r#"studio = "lattice"
[[object]]
name = "lenslet"
shape = {{ type = "sphere", centre = [0, 0, 4], radius = 0.02 }}
{MATT}
array = {{ vectors = [[0.04, 0, 0], [0, 0.04, 0]], counts = [3, 2], centred = true }}
"#
        ),
        "s.toml",
    )
    .unwrap();
    assert_arrays_well_formed(&scene);
    assert_eq!(scene.arrays.len(), 1);
    let a = &scene.arrays[0];
    assert_eq!(a.objects.len(), 1);
    assert_eq!(scene.objects[a.objects.start].name, "lenslet");
    assert_eq!(a.offsets.len(), 6);
}

#[test]
fn bad_arrays_are_rejected_at_their_line() {
    let cases: [(&str, &[&str]); 8] = [
        (
            "{ vectors = [[1, 0, 0]], counts = [0] }",
            &["from 1 to 10000000, got 0"],
        ),
        (
            "{ vectors = [[1, 0, 0]], counts = [-3] }",
            &["from 1 to 10000000, got -3"],
        ),
        (
            "{ vectors = [[1, 0, 0], [0, 1, 0]], counts = [2] }",
            &["one count per vector", "2 vectors, 1 counts"],
        ),
        (
            "{ vectors = [[1, 0, 0]], counts = [2, 2] }",
            &["1 vectors, 2 counts"],
        ),
        (
            "{ vectors = [[1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 1]], counts = [1, 1, 1, 1] }",
            &["1, 2 or 3 vectors, got 4"],
        ),
        (
            "{ vectors = [], counts = [] }",
            &["1, 2 or 3 vectors, got 0"],
        ),
        (
            "{ vectors = [[1, 0, 0], [0, 0, 0]], counts = [2, 2] }",
            &["array vector 2 is zero"],
        ),
        (
            "{ vectors = [[1, 0, 0]], counts = [2], spacing = 3 }",
            &["unknown field `spacing`"],
        ),
    ];
    for (array, parts) in cases {
        let text = array_scene(array);
        assert_error_at(&text, "array =", parts);
    }
}

#[test]
fn arrays_of_more_than_the_maximum_number_of_copies_are_rejected() {
    let max = MAX_ARRAY_ELEMENTS;
    assert_eq!(max, 10_000_000);

    // One count too many.
    let text = array_scene(&format!(
        "{{ vectors = [[1, 0, 0]], counts = [{}] }}",
        max + 1
    ));
    assert_error_at(&text, "array =", &[&format!("got {}", max + 1)]);

    // A product of allowed counts too many.
    let text = array_scene("{ vectors = [[1, 0, 0], [0, 1, 0]], counts = [10001, 1000] }");
    assert_error_at(&text, "array =", &["10001000 copies", "at most 10000000"]);
    let text =
        array_scene("{ vectors = [[1, 0, 0], [0, 1, 0], [0, 0, 1]], counts = [1000, 1000, 1000] }");
    assert_error_at(&text, "array =", &["1000000000 copies"]);

    // An array of arrays too many (the outer array's line).
    let text = format!(
        r#"studio = "none"
[[group]]
name = "g"
array = {{ vectors = [[0, 1, 0]], counts = [1001] }}
[[group.object]]
name = "ball"
shape = {{ type = "sphere", centre = [0, 0, 0], radius = 0.1 }}
{MATT}
array = {{ vectors = [[1, 0, 0]], counts = [10000] }}
"#
    );
    assert_error_at(
        &text,
        "counts = [1001]",
        &["10010000 copies", "at most 10000000"],
    );
}

/// Counts whose product is 2⁶⁴ (each allowed on its own) must be refused like any other
/// product beyond the maximum, not wrap around to 0. Run in a child process with limited
/// memory, so that a wrap-around (which goes on to enumerate 2⁶⁴ offsets) fails fast instead of
/// exhausting the machine's memory.
#[test]
fn array_counts_whose_product_overflows_are_rejected() {
    let dir = TempDir::new().unwrap();
    let scene = write(
        dir.path(),
        "huge.toml",
        array_scene(
            "{ vectors = [[1, 0, 0], [0, 1, 0], [0, 0, 1]], counts = [1048576, 4194304, 4194304] }",
        ),
    );
    let limited = |scene: &Path| {
        let mut command = Command::new("sh");
        command
            .arg("-c")
            .arg("ulimit -v 1000000 && exec \"$0\" check \"$1\"")
            .arg(TIMBRE)
            .arg(scene)
            .env("RUST_BACKTRACE", "0")
            .current_dir(dir.path());
        run(command)
    };
    // The memory limit leaves `timbre check` room for an ordinary scene.
    let small = write(
        dir.path(),
        "small.toml",
        array_scene("{ vectors = [[1, 0, 0]], counts = [1000] }"),
    );
    limited(&small).assert_success();

    let run = limited(&scene);
    run.assert_bad_input(&["copies", "at most 10000000"]);
    assert_eq!(
        location(&run.stderr, path_str(&scene)).0,
        6,
        "{}",
        run.stderr
    );
}

// ---------------------------------------------------------------------------------------------
// 3. Includes
// ---------------------------------------------------------------------------------------------

/// main.toml includes parts/sub.toml (turned and moved, in an array) which includes
/// deeper/leaf.toml, which loads the OBJ file next to it.
fn include_tree(root: &Path) -> PathBuf {
    let main = write(
        root,
        "scenes/main.toml",
        format!(
            r#"studio = "none"
[[light]]
type = "ambient"
colour = [0.25, 0.25, 0.25]

[[object]]
name = "base"
shape = {{ type = "sphere", centre = [0, 0, 0], radius = 1 }}
{MATT}

[[include]]
file = "parts/sub.toml"
name = "sub"
transform = {{ translate = [0, 0, 10] }}
array = {{ vectors = [[5, 0, 0]], counts = [2] }}
"#
        ),
    );
    write(
        root,
        "scenes/parts/sub.toml",
        format!(
            r#"# Only the objects, groups and includes of an included file are used.
studio = "lattice"
[render]
width = 12
[camera]
type = "pinhole"
position = [0, 0, -9]
view_direction = [0, 0, 1]
up = [0, 1, 0]
horizontal_view_angle_deg = 30
[[light]]
type = "point"
position = [0, 9, 0]
colour = [1, 1, 1]

[[object]]
name = "ball"
shape = {{ type = "sphere", centre = [1, 0, 0], radius = 1 }}
{MATT}

[[include]]
file = "deeper/leaf.toml"
name = "leaf"
transform = {{ rotate = {{ axis = [0, 0, 1], angle_deg = 90 }} }}
"#
        ),
    );
    write(
        root,
        "scenes/parts/deeper/leaf.toml",
        format!(
            r#"[[object]]
name = "stick"
shape = {{ type = "cylinder", start = [1, 0, 0], end = [2, 0, 0], radius = 0.1 }}
{MATT}

[[object]]
name = "pair"
shape = {{ type = "mesh", file = "pair.obj" }}
{MATT}
"#
        ),
    );
    write(
        root,
        "scenes/parts/deeper/pair.obj",
        "o left\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\no right\nv 3 0 0\nv 4 0 0\nv 3 1 0\nf 4 5 6\n",
    );
    main
}

#[test]
fn includes_are_placed_by_their_transform_and_array() {
    let dir = TempDir::new().unwrap();
    let main = include_tree(dir.path());
    let scene = file::load(&main).unwrap_or_else(|e| panic!("{e}"));
    assert_arrays_well_formed(&scene);

    let mut names: Vec<&str> = scene.objects.iter().map(|o| o.name.as_str()).collect();
    names.sort();
    assert_eq!(
        names,
        [
            "base",
            "sub/ball",
            "sub/leaf/pair/left",
            "sub/leaf/pair/right",
            "sub/leaf/stick"
        ],
        "the included file's studio adds nothing"
    );
    // The including file's lights, camera and render settings; none of the included file's.
    assert!(scene.lights.points.is_empty(), "{:?}", scene.lights);
    assert_close(scene.lights.ambient, DVec3::splat(0.25));
    assert_ne!(scene.render.width, 12);
    assert_eq!(
        scene.camera,
        file::parse("studio = \"none\"\n", "x.toml").unwrap().camera
    );

    assert_close(sphere(&scene, "base").centre(), DVec3::ZERO);
    assert_close(sphere(&scene, "sub/ball").centre(), v(1.0, 0.0, 10.0));
    let stick = cylinder(&scene, "sub/leaf/stick");
    assert_close(stick.start(), v(0.0, 1.0, 10.0));
    assert_close(stick.end(), v(0.0, 2.0, 10.0));
    assert_all_close(
        mesh(&scene, "sub/leaf/pair/right").vertices(),
        &[v(0.0, 3.0, 10.0), v(0.0, 4.0, 10.0), v(-1.0, 3.0, 10.0)],
    );

    // Every included object is in the include's array; the base object is in none.
    assert_eq!(scene.arrays.len(), 1);
    let a = &scene.arrays[0];
    assert_eq!(a.objects.len(), 4);
    assert!(!a.objects.contains(&index_of(&scene, "base")));
    assert_all_close(&a.offsets, &[DVec3::ZERO, v(5.0, 0.0, 0.0)]);

    // `parse` with the file's path resolves includes the same way.
    let text = std::fs::read_to_string(&main).unwrap();
    assert_eq!(file::parse(&text, path_str(&main)).unwrap(), scene);
}

#[test]
fn include_paths_are_relative_to_the_including_file_not_the_working_directory() {
    let dir = TempDir::new().unwrap();
    include_tree(dir.path());
    // A decoy next to the working directory that must not be picked up.
    write(
        dir.path(),
        "parts/sub.toml",
        "this is = not a scene file [\n",
    );

    // Relative scene path, run from the temporary directory.
    let run = timbre(dir.path(), &["check", "scenes/main.toml"]);
    run.assert_success();
    assert!(
        run.stdout.starts_with("scenes/main.toml: OK\n"),
        "{}",
        run.stdout
    );
    assert_eq!(run.count("objects"), 5);
    assert_eq!(run.count("triangles"), 2 * 2);
    // Instances count the copies of each array (not of each member).
    assert_eq!(run.field("instances"), "2 (in 1 arrays)");
    // base: [-1,-1,-1]..[1,1,1]; copies of sub reach x = 5 + 1 + 1 (ball), y = 4 (the turned
    // right triangle) and z = 11.
    let (lo, hi) = run.bounding_box();
    assert_close(lo, v(-1.0, -1.0, -1.0));
    assert_close(hi, v(7.0, 4.0, 11.0));

    // And from the scene's own directory, and from elsewhere with an absolute path.
    timbre(&dir.path().join("scenes"), &["check", "main.toml"]).assert_success();
    let absolute = dir.path().join("scenes/main.toml");
    timbre(&std::env::temp_dir(), &["check", path_str(&absolute)]).assert_success();
}

#[test]
fn the_same_file_may_be_included_twice() {
    let dir = TempDir::new().unwrap();
    write(
        dir.path(),
        "brick.toml",
        format!(
            "[[object]]\nname = \"b\"\nshape = {{ type = \"sphere\", centre = [0, 0, 0], radius = 1 }}\n{MATT}\n"
        ),
    );
    let main = write(
        dir.path(),
        "main.toml",
        r#"studio = "none"
[[include]]
file = "brick.toml"
name = "left"
transform = { translate = [-2, 0, 0] }
[[include]]
file = "brick.toml"
name = "right"
transform = { translate = [2, 0, 0] }
[[group]]
name = "g"
[[group.include]]
file = "brick.toml"
"#,
    );
    let scene = file::load(&main).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene.objects.len(), 3);
    assert_close(sphere(&scene, "left/b").centre(), v(-2.0, 0.0, 0.0));
    assert_close(sphere(&scene, "right/b").centre(), v(2.0, 0.0, 0.0));
    // An unnamed include adds no name part.
    assert_close(sphere(&scene, "g/b").centre(), DVec3::ZERO);
}

#[test]
fn include_cycles_are_errors() {
    let dir = TempDir::new().unwrap();
    let a = write(
        dir.path(),
        "a.toml",
        "studio = \"none\"\n[[include]]\nfile = \"sub/b.toml\"\n",
    );
    let b_text = format!(
        "[[object]]\nname = \"x\"\nshape = {{ type = \"sphere\", centre = [0, 0, 0], radius = 1 }}\n{MATT}\n[[include]]\nfile = \"../a.toml\"\n"
    );
    let b = write(dir.path(), "sub/b.toml", &b_text);
    let e = file::load(&a).unwrap_err().to_string();
    assert!(e.contains("include cycle"), "{e}");
    assert!(e.contains("a.toml") && e.contains("b.toml"), "{e}");
    // Located at the include that closes the cycle.
    assert_eq!(
        location(&e, path_str(&b)).0,
        line_of(&b_text, "../a.toml"),
        "{e}"
    );

    // A file including itself, through a group.
    let own = write(
        dir.path(),
        "own.toml",
        "studio = \"none\"\n[[group]]\nname = \"g\"\n[[group.include]]\nfile = \"own.toml\"\n",
    );
    let e = file::load(&own).unwrap_err().to_string();
    assert!(e.contains("include cycle"), "{e}");
    assert_eq!(location(&e, path_str(&own)).0, 5, "{e}");

    // The command line reports it as bad input.
    timbre(dir.path(), &["check", "a.toml"]).assert_bad_input(&["include cycle"]);
}

#[test]
fn a_missing_include_is_named_at_the_including_line() {
    let dir = TempDir::new().unwrap();
    let source =
        "studio = \"none\"\n\n[[include]]\nname = \"x\"\nfile = \"nowhere/missing.toml\"\n";
    let main = write(dir.path(), "main.toml", source);
    let e = file::load(&main).unwrap_err().to_string();
    assert!(e.starts_with(&format!("{}:", main.display())), "{e}");
    assert_eq!(location(&e, path_str(&main)).0, 5, "{e}");
    assert!(e.contains("missing.toml"), "{e}");

    let run = timbre(dir.path(), &["check", "main.toml"]);
    run.assert_bad_input(&["main.toml:5:", "missing.toml"]);
}

#[test]
fn errors_in_included_files_name_the_included_file_and_line() {
    let dir = TempDir::new().unwrap();
    let main = write(
        dir.path(),
        "main.toml",
        "studio = \"none\"\n[[include]]\nfile = \"parts/bad.toml\"\n",
    );
    let bad = dir.path().join("parts/bad.toml");

    // A value error, found while the included file is read.
    let bad_text = format!(
        "[[object]]\nname = \"b\"\nshape = {{ type = \"sphere\", centre = [0, 0, 0], radius = -1 }}\n{MATT}\n"
    );
    write(dir.path(), "parts/bad.toml", &bad_text);
    let e = file::load(&main).unwrap_err().to_string();
    assert_eq!(location(&e, path_str(&bad)).0, 3, "{e}");
    assert!(e.contains("got -1"), "{e}");

    // A TOML syntax error.
    write(
        dir.path(),
        "parts/bad.toml",
        "[[object]]\nname = \"b\"\nshape = {\n",
    );
    let e = file::load(&main).unwrap_err().to_string();
    assert_eq!(location(&e, path_str(&bad)).0, 3, "{e}");

    // A placement error, found while the included file's objects are placed.
    let bad_text = format!(
        "[[object]]\nname = \"b\"\nshape = {{ type = \"sphere\", centre = [0, 0, 0], radius = 1 }}\n{MATT}\n\narray = {{ vectors = [[0, 0, 0]], counts = [2] }}\n"
    );
    write(dir.path(), "parts/bad.toml", &bad_text);
    let e = file::load(&main).unwrap_err().to_string();
    assert_eq!(location(&e, path_str(&bad)).0, 6, "{e}");
    assert!(e.contains("array vector 1 is zero"), "{e}");

    // A singular transform in a file included by an included file.
    write(
        dir.path(),
        "parts/bad.toml",
        "[[include]]\nfile = \"deeper/worse.toml\"\n",
    );
    let worse_text = format!(
        "[[object]]\nname = \"b\"\nshape = {{ type = \"sphere\", centre = [0, 0, 0], radius = 1 }}\n{MATT}\ntransform = {{ scale = [1, 0, 1] }}\n"
    );
    let worse = write(dir.path(), "parts/deeper/worse.toml", &worse_text);
    let e = file::load(&main).unwrap_err().to_string();
    assert_eq!(location(&e, path_str(&worse)).0, 5, "{e}");
    assert!(e.contains("singular"), "{e}");

    let run = timbre(dir.path(), &["check", "main.toml"]);
    run.assert_bad_input(&["worse.toml:5:", "singular"]);
}

// ---------------------------------------------------------------------------------------------
// 4. Transforms that cannot be applied
// ---------------------------------------------------------------------------------------------

#[test]
fn a_singular_transform_is_an_error_at_its_line() {
    let text = format!(
        r#"studio = "none"
[[object]]
name = "tile"
shape = {{ type = "parallelogram", corner = [0, 0, 0], span_u = [1, 0, 0], span_v = [0, 1, 0] }}
{MATT}
transform = {{ scale = [1, 0, 1] }}
"#
    );
    assert_error_at(&text, "transform =", &["singular", "'tile'"]);

    let flat = format!(
        r#"studio = "none"
[[group]]
name = "flat"

transform = {{ scale = 0 }}
[[group.object]]
shape = {{ type = "sphere", centre = [0, 0, 0], radius = 1 }}
{MATT}
"#
    );
    assert_error_at(&flat, "transform =", &["singular"]);

    let dir = TempDir::new().unwrap();
    let scene = write(dir.path(), "s.toml", &flat);
    timbre(dir.path(), &["check", path_str(&scene)]).assert_bad_input(&["s.toml:5:", "singular"]);
}

#[test]
fn round_shapes_scaled_non_uniformly_become_exact_transformed_shapes() {
    for shape in [
        r#"{ type = "sphere", centre = [0, 0, 0], radius = 1 }"#,
        r#"{ type = "disc", centre = [0, 0, 0], normal = [0, 0, 1], radius = 1 }"#,
        r#"{ type = "cylinder", start = [0, 0, 0], end = [0, 0, 1], radius = 1 }"#,
    ] {
        for text in [
            format!(
                "studio = \"none\"\n[[object]]\nname = \"round\"\nshape = {shape}\n{MATT}\ntransform = {{ scale = [3, 2, 1] }}\n"
            ),
            // Through a group's scale.
            format!(
                "studio = \"none\"\n[[group]]\nname = \"squash\"\ntransform = {{ scale = [3, 2, 1] }}\n[[group.object]]\nname = \"round\"\nshape = {shape}\n{MATT}\n"
            ),
        ] {
            let scene = parse(&text);
            let s = &scene.objects[0].shape;
            assert!(matches!(s, Shape::Transformed(_)), "{s:?}");
            // The sphere becomes the ellipsoid x²/9 + y²/4 + z² = 1, the disc the ellipse
            // x²/9 + y²/4 ≤ 1 at z = 0, the cylinder the elliptic one over that ellipse.
            let hit = |o: DVec3, d: DVec3| s.intersect(o, d, 0.0, f64::INFINITY).map(|h| h.0);
            let down = v(0.0, 0.0, -1.0);
            if shape.contains("sphere") {
                let t = hit(v(10.0, 0.0, 0.2), v(-1.0, 0.0, 0.0)).unwrap();
                assert!((10.0 - t - 3.0 * 0.96f64.sqrt()).abs() < 1e-12, "t {t}");
            } else {
                let t = hit(v(2.9, 0.0, 5.0), down).unwrap();
                let top = if shape.contains("disc") { 0.0 } else { 1.0 };
                assert!((5.0 - t - top).abs() < 1e-12, "{shape}: t {t}");
                assert_eq!(hit(v(3.01, 0.0, 5.0), down), None, "{shape}");
                assert_eq!(hit(v(0.0, 2.01, 5.0), down), None, "{shape}");
            }
        }

        // Uniform scales, also negative ones, are fine.
        let text = format!(
            "studio = \"none\"\n[[object]]\nname = \"round\"\nshape = {shape}\n{MATT}\ntransform = {{ scale = [-2, -2, -2], rotate = {{ axis = [1, 2, 3], angle_deg = 33 }} }}\n"
        );
        parse(&text);
    }

    // Meshes take any non-singular scale.
    let scene = parse(&format!(
        "studio = \"none\"\n[[object]]\nname = \"m\"\nshape = {{ type = \"triangle_mesh\", vertices = [[0, 0, 0], [1, 0, 0], [0, 1, 0]], triangles = [[0, 1, 2]] }}\n{MATT}\ntransform = {{ scale = [1, 2, 3] }}\n"
    ));
    assert_all_close(
        mesh(&scene, "m").vertices(),
        &[DVec3::ZERO, v(1.0, 0.0, 0.0), v(0.0, 2.0, 0.0)],
    );
}

#[test]
fn bad_transform_values_are_located() {
    let base = |transform: &str| {
        format!(
            "studio = \"none\"\n[[object]]\nshape = {{ type = \"sphere\", centre = [0, 0, 0], radius = 1 }}\n{MATT}\ntransform = {transform}\n"
        )
    };
    assert_error_at(
        &base("{ rotate = { axis = [0, 0, 0], angle_deg = 30 } }"),
        "transform =",
        &["axis"],
    );
    assert_error_at(
        &base("{ scale = \"big\" }"),
        "transform =",
        &["scale factor"],
    );
    assert_error_at(
        &base("{ shear = 1 }"),
        "transform =",
        &["unknown field `shear`"],
    );
    // A zero angle needs no axis direction.
    parse(&base("{ rotate = { axis = [0, 0, 0], angle_deg = 0 } }"));
}

// ---------------------------------------------------------------------------------------------
// 5. --set
// ---------------------------------------------------------------------------------------------

const RENDER_SCENE: &str = r#"studio = "empty"

[render]
width = 32
height = 24
spp = 1

[camera]
type = "pinhole"
position = [0, 1.0001, 0]
view_direction = [0, 0, 1]
up = [0, 1, 0]
horizontal_view_angle_deg = 60

[[object]]
name = "ball"
shape = { type = "sphere", centre = [0, 1, 5], radius = 1 }
surface = { type = "matt", colour = [1, 0.2, 0.2] }
"#;

/// A camera at (0.5, 2, −1) told to look at the ball's centre (0, 1, 5) sees what one told to
/// look along (0, 1, 5) − (0.5, 2, −1) = (−0.5, −1, 6) sees, pixel for pixel, from the file
/// and from `--set` (which replaces the file's view_direction); both together, or a look-at
/// point at the camera, is a located error.
#[test]
fn look_at_is_the_view_direction_towards_a_point() {
    let dir = TempDir::new().unwrap();
    write(dir.path(), "scene.toml", RENDER_SCENE);
    let render = |out: &str, sets: &[&str]| {
        let mut args = vec!["render", "scene.toml", "-o", out, "--quiet"];
        for s in sets {
            args.extend(["--set", s]);
        }
        timbre(dir.path(), &args).assert_success();
        decode_png(&dir.path().join(out))
    };
    let at = "camera.position=[0.5, 2, -1]";
    let along = render("along.png", &[at, "camera.view_direction=[-0.5, -1, 6]"]);
    let looking = render("at.png", &[at, "camera.look_at=[0, 1, 5]"]);
    assert_eq!(along, looking);
    assert_ne!(
        along,
        render("plain.png", &[at]),
        "the view direction matters"
    );
    let text = RENDER_SCENE.replace("view_direction = [0, 0, 1]", "look_at = [0, 1.0001, 5]");
    let d = file::parse(&text, "scene.toml").unwrap();
    assert!((d.camera.view_direction() - DVec3::Z).length() < 1e-12);
    let both = RENDER_SCENE.replace("up = [0, 1, 0]", "look_at = [0, 1, 5]");
    let e = file::parse(&both, "scene.toml").unwrap_err().to_string();
    assert!(
        e.contains("scene.toml:12:11:") && e.contains("view_direction or look_at, not both"),
        "{e}"
    );
    let here = RENDER_SCENE.replace("view_direction = [0, 0, 1]", "look_at = [0, 1.0001, 0]");
    let e = file::parse(&here, "scene.toml").unwrap_err().to_string();
    assert!(e.contains("look_at point is its position"), "{e}");
}

#[test]
fn set_changes_the_camera_and_the_picture_size() {
    let dir = TempDir::new().unwrap();
    let scene = write(dir.path(), "scene.toml", RENDER_SCENE);
    let render = |out: &str, sets: &[&str]| {
        let mut args = vec!["render", "scene.toml", "-o", out, "--quiet"];
        for s in sets {
            args.extend(["--set", s]);
        }
        timbre(dir.path(), &args).assert_success();
        decode_png(&dir.path().join(out))
    };
    let plain = render("plain.png", &[]);
    assert_eq!(plain.dimensions(), (32, 24));
    let again = render("again.png", &[]);
    assert_eq!(plain, again, "renders are deterministic");

    let moved = render("moved.png", &["camera.position=[0.5, 2, -1]"]);
    assert_eq!(moved.dimensions(), (32, 24));
    assert_ne!(plain, moved, "moving the camera changes the picture");

    let wide = render("wide.png", &["render.width=40"]);
    assert_eq!(wide.dimensions(), (40, 24));

    // Several overrides; a later one wins; the file itself is unchanged.
    let both = render(
        "both.png",
        &["render.width=8", "render.height=6", "render.width=10"],
    );
    assert_eq!(both.dimensions(), (10, 6));
    assert_eq!(std::fs::read_to_string(&scene).unwrap(), RENDER_SCENE);

    // --width beats --set render.width, and alone keeps the picture's aspect: the file with
    // --set render.width=40 is 40x24, so 16 wide is round(24 * 16/40) = 10 high.
    timbre(
        dir.path(),
        &[
            "render",
            "scene.toml",
            "-o",
            "cli.png",
            "--quiet",
            "--width",
            "16",
            "--set",
            "render.width=40",
        ],
    )
    .assert_success();
    assert_eq!(
        decode_png(&dir.path().join("cli.png")).dimensions(),
        (16, 10)
    );
}

const CHECK_SCENE: &str = r#"studio = "none"
[[object]]
name = "ball"
shape = { type = "sphere", centre = [0, 0, 0], radius = 1 }
surface = { type = "matt", colour = [1, 1, 1] }

[[group]]
name = "g"
[[group.object]]
name = "inner"
shape = { type = "sphere", centre = [0, 0, 0], radius = 0.25 }
surface = { type = "matt", colour = [1, 1, 1] }
"#;

#[test]
fn set_changes_what_check_reports() {
    let dir = TempDir::new().unwrap();
    write(dir.path(), "scene.toml", CHECK_SCENE);
    let run = timbre(dir.path(), &["check", "scene.toml"]);
    run.assert_success();
    assert_eq!(run.bounding_box(), (DVec3::splat(-1.0), DVec3::splat(1.0)));

    let run = timbre(
        dir.path(),
        &["check", "scene.toml", "--set", "object.0.shape.radius=0.5"],
    );
    run.assert_success();
    assert_eq!(run.bounding_box(), (DVec3::splat(-0.5), DVec3::splat(0.5)));

    // Into nested arrays of tables, and creating a table the file lacks.
    let run = timbre(
        dir.path(),
        &[
            "check",
            "scene.toml",
            "--set",
            "object.0.shape.radius=0.1",
            "--set",
            "group.0.object.0.shape.centre=[3, 0, 0]",
            "--set",
            "group.0.transform={ translate = [0, 2, 0] }",
            "--set",
            "group.0.array={ vectors = [[0, 0, 1]], counts = [4] }",
        ],
    );
    run.assert_success();
    assert_eq!(run.field("instances"), "4 (in 1 arrays)");
    let (lo, hi) = run.bounding_box();
    assert_close(lo, v(-0.1, -0.1, -0.25));
    assert_close(hi, v(3.25, 2.25, 3.25));
}

#[test]
fn set_errors_are_bad_input_that_mention_set() {
    let dir = TempDir::new().unwrap();
    write(dir.path(), "scene.toml", CHECK_SCENE);
    write(dir.path(), "render.toml", RENDER_SCENE);

    for command in ["check", "render"] {
        let scene = if command == "check" {
            "scene.toml"
        } else {
            "render.toml"
        };
        let with = |sets: &[&str]| {
            let mut args = vec![command, scene, "-o", "x.png"];
            if command == "check" {
                args.truncate(2);
            }
            for s in sets {
                args.extend(["--set", s]);
            }
            timbre(dir.path(), &args)
        };
        with(&["render.width=-3"]).assert_bad_input(&["--set render.width=-3"]);
        with(&["render.width=0"]).assert_bad_input(&["--set render.width=0"]);
        with(&["object.0.shape.radius=-1"]).assert_bad_input(&["--set", "got -1"]);
        with(&["object.9.name=x"]).assert_bad_input(&["--set object.9.name=x", "beyond"]);
        with(&["object.0.name.x=1"]).assert_bad_input(&["--set", "cannot be set"]);
        with(&["object.first.name=x"]).assert_bad_input(&["--set", "index"]);

        // Without "=": a usage error from the argument parser, also exit code 2.
        let run = with(&["render.width"]);
        assert_eq!(run.code, Some(2), "{}", run.stderr);
        assert!(run.stderr.contains("key=value"), "{}", run.stderr);
    }
    assert_eq!(
        files_in(dir.path()),
        ["render.toml", "scene.toml"],
        "no picture written"
    );

    // --set without a scene file.
    timbre(
        dir.path(),
        &["render", "-o", "x.png", "--set", "render.width=3"],
    )
    .assert_bad_input(&["--set needs a scene file"]);
}

#[test]
fn overrides_through_the_library() {
    let dir = TempDir::new().unwrap();
    let path = write(dir.path(), "scene.toml", CHECK_SCENE);
    let set = |s: &[&str]| -> Vec<Override> { s.iter().map(|o| o.parse().unwrap()).collect() };

    let scene = file::load_with(&path, &set(&["object.0.shape.radius=0.5"])).unwrap();
    assert!((sphere(&scene, "ball").radius() - 0.5).abs() < 1e-12);
    assert_eq!(
        file::load_with(&path, &[]).unwrap(),
        file::load(&path).unwrap()
    );

    let scene = file::load_with(&path, &set(&["studio=lattice", "render.seed=7"])).unwrap();
    assert_eq!(scene.objects.len(), 50 + 2, "a bare word is a string");
    assert_eq!(scene.render.seed, 7);

    let e = file::load_with(&path, &set(&["render.width=-3"]))
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with(&format!(
            "{} (with --set render.width=-3): ",
            path.display()
        )),
        "{e}"
    );

    let e = file::load_with(&path, &set(&["object.9.name=x"]))
        .unwrap_err()
        .to_string();
    assert!(e.contains("index 9 is beyond the 1 entries"), "{e}");

    let o: Override = "camera.position=[0, 0, -2]".parse().unwrap();
    assert_eq!(o.key, ["camera", "position"]);
    assert_eq!(o.to_string(), "camera.position=[0, 0, -2]");
    assert!("no equals sign".parse::<Override>().is_err());
    assert!("a..b=1".parse::<Override>().is_err());
}

// ---------------------------------------------------------------------------------------------
// 6. check
// ---------------------------------------------------------------------------------------------

#[test]
fn check_summarises_objects_triangles_instances_and_bounds_and_renders_nothing() {
    let dir = TempDir::new().unwrap();
    write(
        dir.path(),
        "scene.toml",
        format!(
            r#"studio = "none"

[[object]]
name = "ball"
shape = {{ type = "sphere", centre = [0, 0, 5], radius = 1 }}
{MATT}

# A unit square of two triangles in the plane z = 0, repeated 3 × 2 times.
[[object]]
name = "square"
shape = {{ type = "triangle_mesh", vertices = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], triangles = [[0, 1, 2], [0, 2, 3]] }}
{MATT}
array = {{ vectors = [[2, 0, 0], [0, 2, 0]], counts = [3, 2] }}

[[object]]
name = "floor"
shape = {{ type = "plane", point = [0, -1, 0], normal = [0, 1, 0] }}
{MATT}
"#
        ),
    );
    let before = files_in(dir.path());
    let run = timbre(dir.path(), &["check", "scene.toml"]);
    run.assert_success();
    assert!(run.stderr.is_empty(), "{}", run.stderr);
    assert_eq!(run.stdout.lines().next(), Some("scene.toml: OK"));
    assert_eq!(run.count("objects"), 3);
    assert_eq!(run.count("triangles"), 2 * 6);
    assert_eq!(run.field("instances"), "6 (in 1 arrays)");
    let (lo, hi) = run.bounding_box();
    assert_close(lo, v(-1.0, -1.0, 0.0));
    assert_close(hi, v(5.0, 3.0, 6.0));
    assert!(
        run.field("bounding box").ends_with("(and 1 unbounded)"),
        "{}",
        run.stdout
    );
    assert_eq!(files_in(dir.path()), before, "check writes nothing");
    assert!(!dir.path().join("out.png").exists());

    // The library's summary agrees.
    let scene = file::load(&dir.path().join("scene.toml")).unwrap();
    let s = scene.summary();
    assert_eq!(
        (s.objects, s.triangles, s.instances, s.unbounded),
        (3, 12, 6, 1)
    );
    assert!(scene.warnings().is_empty());
}

#[test]
fn check_counts_generated_meshes_in_nested_arrays() {
    let dir = TempDir::new().unwrap();
    let generated = timbre(
        dir.path(),
        &["generate-mesh", "-o", "bump.ply", "--triangles", "200"],
    );
    generated.assert_success();
    let triangles: u64 = generated
        .stdout
        .split_whitespace()
        .next()
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("{}", generated.stdout));
    assert!(triangles >= 200);
    write(
        dir.path(),
        "scene.toml",
        format!(
            r#"studio = "none"
[[group]]
name = "crate"
array = {{ vectors = [[0, 0, 3]], counts = [2] }}
[[group.object]]
name = "bumps"
shape = {{ type = "mesh", file = "bump.ply" }}
{MATT}
array = {{ vectors = [[3, 0, 0], [0, 3, 0]], counts = [2, 2], centred = true }}
[[group.object]]
name = "lid"
shape = {{ type = "parallelogram", corner = [0, 0, 0], span_u = [1, 0, 0], span_v = [0, 1, 0] }}
{MATT}
"#
        ),
    );
    let run = timbre(dir.path(), &["check", "scene.toml"]);
    run.assert_success();
    assert_eq!(run.count("objects"), 2);
    assert_eq!(run.count("triangles"), triangles * 8);
    assert_eq!(run.field("instances"), "10 (in 2 arrays)");
    assert_eq!(files_in(dir.path()), ["bump.ply", "scene.toml"]);
}

#[test]
fn check_rejects_bad_files_with_exit_code_2() {
    let dir = TempDir::new().unwrap();
    let source = array_scene("{ vectors = [[1, 0, 0]], counts = [0] }");
    write(dir.path(), "bad.toml", &source);
    let run = timbre(dir.path(), &["check", "bad.toml"]);
    run.assert_bad_input(&["bad.toml:6:", "got 0"]);
    assert!(run.stdout.is_empty(), "{}", run.stdout);

    timbre(dir.path(), &["check", "absent.toml"]).assert_bad_input(&["absent.toml"]);
}

// ---------------------------------------------------------------------------------------------
// Extras
// ---------------------------------------------------------------------------------------------

#[test]
fn unnamed_objects_are_numbered_by_their_entry() {
    let scene = parse(&format!(
        r#"studio = "lattice"
[[object]]
shape = {{ type = "sphere", centre = [0, 0, 5], radius = 1 }}
{MATT}
[[object]]
name = "x"
shape = {{ type = "sphere", centre = [0, 0, 5], radius = 1 }}
{MATT}
[[object]]
shape = {{ type = "sphere", centre = [0, 0, 5], radius = 1 }}
{MATT}
"#
    ));
    let names: Vec<&str> = scene.objects[50..]
        .iter()
        .map(|o| o.name.as_str())
        .collect();
    assert_eq!(names, ["object 1", "x", "object 3"]);
}

#[test]
fn an_includes_transform_turns_the_included_arrays_but_not_its_own() {
    let dir = TempDir::new().unwrap();
    write(
        dir.path(),
        "row.toml",
        format!(
            r#"[[object]]
name = "bead"
shape = {{ type = "sphere", centre = [0, 0, 0], radius = 0.1 }}
{MATT}
array = {{ vectors = [[0, 1, 0]], counts = [2] }}
"#
        ),
    );
    let main = write(
        dir.path(),
        "main.toml",
        r#"studio = "none"
[[include]]
file = "row.toml"
name = "rows"
transform = { rotate = { axis = [0, 0, 1], angle_deg = 90 }, translate = [0, 0, 1] }
array = { vectors = [[0, 0, 5]], counts = [3] }
"#,
    );
    let scene = file::load(&main).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene.objects.len(), 1);
    assert_eq!(scene.arrays.len(), 1);
    assert_close(sphere(&scene, "rows/bead").centre(), v(0.0, 0.0, 1.0));
    // The bead's y vector turned 90° about z is -x; the include's own array stays along z.
    let offsets = &array_of(&scene, "rows/bead").offsets;
    assert_eq!(offsets.len(), 6);
    for k in 0..3 {
        for j in 0..2 {
            let expected = v(-(j as f64), 0.0, 5.0 * k as f64);
            assert!(
                offsets.iter().any(|o| (*o - expected).length() < 1e-9),
                "missing {expected} in {offsets:?}"
            );
        }
    }
}

#[test]
fn an_override_is_the_same_as_editing_the_file() {
    let dir = TempDir::new().unwrap();
    let path = write(dir.path(), "scene.toml", RENDER_SCENE);
    let cases = [
        (
            "camera.position.2=-3",
            "position = [0, 1.0001, 0]",
            "position = [0, 1.0001, -3]",
        ),
        (
            "camera.position=[1, 2, -3]",
            "position = [0, 1.0001, 0]",
            "position = [1, 2, -3]",
        ),
        (
            "object.0.shape.radius=0.5",
            "centre = [0, 1, 5], radius = 1",
            "centre = [0, 1, 5], radius = 0.5",
        ),
        (
            "object.0.surface={ type = \"mirror\" }",
            "surface = { type = \"matt\", colour = [1, 0.2, 0.2] }",
            "surface = { type = \"mirror\" }",
        ),
        (
            "object.0.array={ vectors = [[1, 0, 0]], counts = [3] }",
            "[[object]]",
            "[[object]]\narray = { vectors = [[1, 0, 0]], counts = [3] }",
        ),
        ("render.spp=3", "spp = 1", "spp = 3"),
        (
            "studio=lattice",
            "studio = \"empty\"",
            "studio = \"lattice\"",
        ),
    ];
    for (set, from, to) in cases {
        let overridden = file::load_with(&path, &[set.parse().unwrap()])
            .unwrap_or_else(|e| panic!("--set {set}: {e}"));
        assert!(RENDER_SCENE.contains(from));
        let edited = file::parse(&RENDER_SCENE.replacen(from, to, 1), path_str(&path))
            .unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(overridden, edited, "--set {set}");
        assert_ne!(overridden, file::load(&path).unwrap(), "--set {set}");
    }
}

#[test]
fn set_camera_values_work_on_a_file_without_a_camera() {
    // The documented example: the other camera keys keep the standard camera's values.
    let dir = tempfile::TempDir::new().unwrap();
    let scene = write(
        &dir,
        "s.toml",
        "studio = \"lattice\"\n[render]\nwidth = 32\nheight = 24\n",
    );
    let path = scene.to_str().unwrap();
    timbre(
        dir.path(),
        &["check", path, "--set", "camera.position=[0,0,-2]"],
    )
    .assert_success();
    let standard = timbre(dir.path(), &["render", path, "-o", "a.png", "-q"]);
    standard.assert_success();
    let moved = timbre(
        dir.path(),
        &[
            "render",
            path,
            "-o",
            "b.png",
            "-q",
            "--set",
            "camera.position=[0,0,-2]",
        ],
    );
    moved.assert_success();
    let same = timbre(
        dir.path(),
        &[
            "render",
            path,
            "-o",
            "c.png",
            "-q",
            "--set",
            "camera.up=[0,1,0]",
        ],
    );
    same.assert_success();
    let read = |name: &str| std::fs::read(dir.path().join(name)).unwrap();
    assert_ne!(
        read("a.png"),
        read("b.png"),
        "moving the camera changes the picture"
    );
    assert_eq!(
        read("a.png"),
        read("c.png"),
        "the standard camera's own values change nothing"
    );
    // A value that looks like TOML but is not is an error (clap's, exit 2), not a string.
    let bad = timbre(
        dir.path(),
        &["check", path, "--set", "camera.position=[0,0,-2"],
    );
    assert_eq!(bad.code, Some(2), "{}", bad.stderr);
    assert!(bad.stderr.contains("not valid TOML"), "{}", bad.stderr);
}

#[test]
fn array_copies_are_limited_for_the_whole_scene() {
    // Two arrays of 6 000 000 copies each: each within the per-array limit, together not.
    let object = |name: &str| {
        format!(
            "[[object]]\nname = \"{name}\"\nshape = {{ type = \"sphere\", centre = [0, 0, 0], radius = 0.1 }}\n{MATT}\narray = {{ vectors = [[1, 0, 0], [0, 1, 0]], counts = [3000, 2000] }}\n"
        )
    };
    let e = parse_error(&format!(
        "studio = \"none\"\n{}{}",
        object("a"),
        object("b")
    ));
    assert!(e.contains("12000000 copies in all"), "{e}");
}

/// A scene of `n` spheres named `s0`, `s1`, … at x = 0, 1, …, with `head` before them and
/// `tail` after: past a mebibyte, timbre parses such a file in parts.
fn many_spheres(head: &str, n: usize, tail: &str) -> String {
    let mut text = format!("studio = \"none\"\n{head}");
    for i in 0..n {
        text += &format!(
            "[[object]]\nname = \"s{i}\"\nshape = {{ type = \"sphere\", centre = [{i}, 0, 0], radius = 0.25 }}\n{MATT}\n"
        );
    }
    text + tail
}

#[test]
fn large_files_mean_the_same_when_parsed_in_parts() {
    // Past the spheres, a mebibyte of lights, then a table of the last sphere: it reaches back
    // over the lights, which TOML allows.
    let lights = "[[light]]\ntype = \"ambient\"\ncolour = [1e-6, 0, 0]\n".repeat(25_000);
    let text = many_spheres(
        "[render]\nwidth = 7\n",
        25_000,
        &format!("{lights}[object.transform]\ntranslate = [0, 0, 3]\n"),
    );
    assert!(text.len() > 3 << 20);
    let scene = parse(&text);
    assert_eq!(scene.objects.len(), 25_000);
    assert_eq!(scene.render.width, 7);
    assert_close(scene.lights.ambient, v(0.025, 0.0, 0.0));
    assert_close(sphere(&scene, "s0").centre(), v(0.0, 0.0, 0.0));
    assert_close(sphere(&scene, "s12345").centre(), v(12345.0, 0.0, 0.0));
    assert_close(sphere(&scene, "s24999").centre(), v(24999.0, 0.0, 3.0));
}

#[test]
fn errors_deep_in_large_files_are_located_in_the_whole_file() {
    let bad = many_spheres("", 20_000, "").replace(
        "name = \"s15000\"\nshape = { type = \"sphere\", centre = [15000, 0, 0], radius = 0.25 }",
        "name = \"s15000\"\nshape = { type = \"sphere\", centre = [15000, 0, 0], radius = -2 }",
    );
    assert_error_at(&bad, "radius = -2", &["expected a positive number"]);
    // A table given twice, far apart, is TOML's error, at the second.
    let twice = many_spheres("[render]\nwidth = 7\n", 20_000, "[render]\nheight = 5\n");
    let message = parse_error(&twice);
    assert_eq!(
        location(&message, "s.toml").0,
        twice.lines().count() - 1,
        "{message}"
    );
    assert!(message.contains("duplicate"), "{message}");
    // The same with the first table on the first line, after a byte-order mark.
    let spheres = many_spheres("", 20_000, "[render]\nheight = 5\n");
    let marked = format!(
        "\u{feff}[render]\nwidth = 7\n{}",
        spheres.trim_start_matches("studio = \"none\"\n")
    );
    let message = parse_error(&marked);
    assert!(message.contains("duplicate key `render`"), "{message}");
    assert_eq!(
        location(&message, "s.toml").0,
        marked.lines().count() - 1,
        "{message}"
    );
}

#[test]
fn overrides_reach_every_part_of_a_large_file() {
    let dir = TempDir::new().unwrap();
    let path = write(
        dir.path(),
        "many.toml",
        many_spheres("[render]\nwidth = 7\n", 25_000, ""),
    );
    let set = |s: &[&str]| -> Vec<Override> { s.iter().map(|o| o.parse().unwrap()).collect() };
    let scene = file::load_with(
        &path,
        &set(&[
            "object.0.shape.radius=0.5",
            "object.20000.shape.centre=[0, 1, 2]",
            "object.24999.name=last",
            "render.width=9",
            "camera.horizontal_view_angle_deg=30",
        ]),
    )
    .unwrap();
    assert_eq!(scene.objects.len(), 25_000);
    assert_eq!(scene.render.width, 9);
    assert!((sphere(&scene, "s0").radius() - 0.5).abs() < 1e-12);
    assert_close(sphere(&scene, "s20000").centre(), v(0.0, 1.0, 2.0));
    assert_close(sphere(&scene, "s19999").centre(), v(19999.0, 0.0, 0.0));
    assert_close(sphere(&scene, "last").centre(), v(24999.0, 0.0, 0.0));
    assert_eq!(
        scene.camera,
        file::parse("[camera]\nhorizontal_view_angle_deg = 30\n", "c.toml")
            .unwrap()
            .camera
    );
    let e = file::load_with(&path, &set(&["object.25000.name=x"]))
        .unwrap_err()
        .to_string();
    assert!(e.contains("index 25000 is beyond the 25000 entries"), "{e}");
    // A plain value in a later part would belong to the table before it: refused.
    let lights = "[[light]]\ntype = \"ambient\"\ncolour = [0, 0, 0]\n".repeat(30_000);
    let path = write(dir.path(), "late.toml", many_spheres(&lights, 3, ""));
    let e = file::load_with(&path, &set(&["object=[]"]))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("'object' can be set only to a table or to tables"),
        "{e}"
    );
    let scene = file::load_with(&path, &set(&["object.2.name=last"])).unwrap();
    assert_close(sphere(&scene, "last").centre(), v(2.0, 0.0, 0.0));
}
