//! Integration tests of mesh files: OBJ and PLY (ASCII, binary little and big endian) written
//! and read back exactly, polygons triangulated, several objects per OBJ file, a corpus of
//! malformed files (`tests/data/meshes/`, plus binary ones made here) that must each give an
//! error naming the file and the place, zero-area triangles, and the `timbre` command's
//! `generate-mesh` and `check` on scenes that use mesh files. Everything is small: the whole
//! file runs in well under a second of work.

mod common;

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use glam::DVec3;
use tempfile::TempDir;

use common::cli::{timbre, write};
use timbre::geometry::TriangleMesh;
use timbre::mesh::{self, Mesh, MeshError, MeshFormat, PlyEncoding, generate};

/// Every PLY encoding, with a file-name-friendly label.
const ENCODINGS: [(PlyEncoding, &str); 3] = [
    (PlyEncoding::Ascii, "ascii"),
    (PlyEncoding::BinaryLittleEndian, "binary_le"),
    (PlyEncoding::BinaryBigEndian, "binary_be"),
];

// ---------------------------------------------------------------------------------------------
// Helpers
// ---------------------------------------------------------------------------------------------

/// The committed corpus of mesh files.
fn corpus(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/meshes")
        .join(name)
}

/// Loads a file that must load.
#[track_caller]
fn load_ok(path: &Path) -> Vec<Mesh> {
    mesh::load(path).unwrap_or_else(|e| panic!("{} should load: {e}", path.display()))
}

/// Loads a file that must fail and returns the error's text, after checking that it starts with
/// the file's path (as `load` was given it).
#[track_caller]
fn load_err(path: &Path) -> String {
    let error: MeshError = match mesh::load(path) {
        Ok(meshes) => panic!("{} should not load, got {meshes:?}", path.display()),
        Err(e) => e,
    };
    let text = error.to_string();
    assert!(
        text.starts_with(&path.display().to_string()),
        "the error does not start with the path {}: {text}",
        path.display()
    );
    text
}

/// Asserts that `text` contains every needle.
#[track_caller]
fn assert_contains(text: &str, needles: &[&str]) {
    for needle in needles {
        assert!(text.contains(needle), "{needle:?} not in {text:?}");
    }
}

/// The corners of triangle `t` of `m`.
fn corners(m: &Mesh, t: [u32; 3]) -> [DVec3; 3] {
    t.map(|i| m.vertices[i as usize])
}

/// The triangles of `m` as coordinate triples, in order.
fn triangle_coordinates(m: &Mesh) -> Vec<[DVec3; 3]> {
    m.triangles.iter().map(|&t| corners(m, t)).collect()
}

/// Twice the vector area of a triangle: its normal (counter-clockwise) times twice its area.
fn area_vector([a, b, c]: [DVec3; 3]) -> DVec3 {
    (b - a).cross(c - a)
}

/// Asserts that `loaded` is `original` with its vertices renumbered: a one-to-one map between
/// the two index sets under which positions, normals and every triangle (in order, corners in
/// order) agree exactly. This is what an OBJ round trip through `tobj` guarantees (it numbers
/// vertices in the order the faces first use them).
#[track_caller]
fn assert_same_up_to_renumbering(loaded: &Mesh, original: &Mesh) {
    assert_eq!(loaded.triangles.len(), original.triangles.len());
    assert_eq!(loaded.vertices.len(), original.vertices.len());
    let mut forward: HashMap<u32, u32> = HashMap::new();
    let mut backward: HashMap<u32, u32> = HashMap::new();
    for (k, (l, o)) in loaded.triangles.iter().zip(&original.triangles).enumerate() {
        for (&li, &oi) in l.iter().zip(o) {
            assert_eq!(
                *forward.entry(li).or_insert(oi),
                oi,
                "triangle {k}: loaded vertex {li} stands for two original vertices"
            );
            assert_eq!(
                *backward.entry(oi).or_insert(li),
                li,
                "triangle {k}: original vertex {oi} became two loaded vertices"
            );
            assert_eq!(
                loaded.vertices[li as usize], original.vertices[oi as usize],
                "triangle {k}: positions differ"
            );
        }
    }
    assert_eq!(triangle_coordinates(loaded), triangle_coordinates(original));
    match (&loaded.normals, &original.normals) {
        (None, None) => {}
        (Some(ln), Some(on)) => {
            for (&li, &oi) in &forward {
                assert_eq!(ln[li as usize], on[oi as usize], "normal of vertex {oi}");
            }
        }
        (l, o) => panic!(
            "normals: loaded has {}, original has {}",
            l.is_some(),
            o.is_some()
        ),
    }
}

/// A mesh with awkward coordinates (sub-normal, huge, tiny, negative zero, not representable
/// in decimal) that a careless writer would round.
fn awkward_mesh() -> Mesh {
    Mesh {
        name: "awkward".into(),
        vertices: vec![
            DVec3::new(0.1 + 0.2, -0.0, 1e-310),
            DVec3::new(1e300, -1.7976931348623157e308, 5e-324),
            DVec3::new(std::f64::consts::PI, -1.0 / 3.0, 1e8 / 7.0),
            DVec3::new(2.0f64.powi(-60), 1.0 + f64::EPSILON, -7.0e-7),
        ],
        triangles: vec![[0, 1, 2], [0, 2, 3]],
        normals: None,
    }
}

/// A square of two triangles with short coordinates and normals, for tests that read many
/// variants of its files.
fn small_mesh() -> Mesh {
    Mesh {
        name: "small".into(),
        vertices: vec![
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(0.0, 1.0, 0.5),
        ],
        triangles: vec![[0, 1, 2], [0, 2, 3]],
        normals: Some(vec![
            DVec3::Z,
            DVec3::Z,
            DVec3::Z,
            DVec3::new(0.0, -0.5, 1.0),
        ]),
    }
}

/// A scene with nothing but one mesh object named `m` from `file`. The `shape` value starts at
/// line 5, column 9 ([`SHAPE_AT`]).
fn mesh_scene(file: &str) -> String {
    format!(
        "studio = \"none\"\n\
         \n\
         [[object]]\n\
         name = \"m\"\n\
         shape = {{ type = \"mesh\", file = \"{file}\", smooth = true }}\n\
         surface = {{ type = \"matt\", colour = [1, 1, 1] }}\n"
    )
}

/// Where `mesh_scene` puts the shape, as `line:column`.
const SHAPE_AT: &str = "5:9";

/// The number after `label` on a line of `text` (e.g. "  triangles:    8192").
#[track_caller]
fn number_after(text: &str, label: &str) -> u64 {
    let line = text
        .lines()
        .find_map(|l| l.trim_start().strip_prefix(label))
        .unwrap_or_else(|| panic!("no {label:?} in {text:?}"));
    line.split_whitespace()
        .next()
        .and_then(|w| w.parse().ok())
        .unwrap_or_else(|| panic!("no number after {label:?} in {text:?}"))
}

// ---------------------------------------------------------------------------------------------
// 1. Round trips
// ---------------------------------------------------------------------------------------------

#[test]
fn a_generated_sphere_round_trips_exactly_through_every_ply_encoding() {
    let dir = TempDir::new().unwrap();
    let sphere = generate::displaced_sphere(2000, 0.1);
    assert!(sphere.triangles.len() >= 2000);
    assert!(sphere.normals.is_some());
    for (encoding, label) in ENCODINGS {
        let path = dir.path().join(format!("sphere_{label}.ply"));
        mesh::save(&path, &sphere, encoding).unwrap();
        let meshes = load_ok(&path);
        assert_eq!(meshes.len(), 1, "{label}: a PLY file holds one mesh");
        // PLY keeps vertex order and indices as written; only the name is not stored.
        let expected = Mesh {
            name: String::new(),
            ..sphere.clone()
        };
        assert_eq!(meshes[0], expected, "{label}");
    }
}

#[test]
fn ply_encodings_are_laid_out_as_declared() {
    let dir = TempDir::new().unwrap();
    let sphere = generate::displaced_sphere(100, 0.2);
    let mut bytes = Vec::new();
    for (encoding, label) in ENCODINGS {
        let path = dir.path().join(format!("s_{label}.ply"));
        mesh::save(&path, &sphere, encoding).unwrap();
        let data = std::fs::read(&path).unwrap();
        let header_format = format!(
            "format {} 1.0\n",
            match encoding {
                PlyEncoding::Ascii => "ascii",
                PlyEncoding::BinaryLittleEndian => "binary_little_endian",
                PlyEncoding::BinaryBigEndian => "binary_big_endian",
            }
        );
        assert!(
            data.starts_with(format!("ply\n{header_format}").as_bytes()),
            "{label}: header {:?}",
            String::from_utf8_lossy(&data[..40])
        );
        bytes.push(data);
    }
    assert_ne!(bytes[1], bytes[2], "little and big endian bodies differ");
    // Binary size: header + 6 doubles per vertex + (1 + 3·4) bytes per triangle.
    for data in &bytes[1..] {
        let end = b"end_header\n";
        let body = data.windows(end.len()).position(|w| w == end).unwrap() + end.len();
        assert_eq!(
            data.len() - body,
            sphere.vertices.len() * 6 * 8 + sphere.triangles.len() * 13
        );
    }
}

#[test]
fn a_generated_sphere_round_trips_through_obj_up_to_vertex_numbering() {
    let dir = TempDir::new().unwrap();
    let sphere = generate::displaced_sphere(2000, 0.1);
    let path = dir.path().join("sphere.obj");
    mesh::save(&path, &sphere, PlyEncoding::Ascii).unwrap();
    let meshes = load_ok(&path);
    assert_eq!(meshes.len(), 1);
    assert_eq!(meshes[0].name, sphere.name, "the object name is kept");
    assert_same_up_to_renumbering(&meshes[0], &sphere);
}

#[test]
fn meshes_without_normals_round_trip_without_normals() {
    let dir = TempDir::new().unwrap();
    let mut sphere = generate::displaced_sphere(300, 0.3);
    sphere.normals = None;
    for (encoding, label) in ENCODINGS {
        let path = dir.path().join(format!("plain_{label}.ply"));
        mesh::save(&path, &sphere, encoding).unwrap();
        let loaded = load_ok(&path).remove(0);
        assert_eq!(loaded.normals, None, "{label}");
        assert_eq!(loaded.vertices, sphere.vertices, "{label}");
        assert_eq!(loaded.triangles, sphere.triangles, "{label}");
    }
    let path = dir.path().join("plain.obj");
    mesh::save(&path, &sphere, PlyEncoding::Ascii).unwrap();
    let loaded = load_ok(&path).remove(0);
    assert_eq!(loaded.normals, None);
    assert_same_up_to_renumbering(&loaded, &sphere);
}

#[test]
fn awkward_coordinates_round_trip_bit_for_bit() {
    let dir = TempDir::new().unwrap();
    let original = awkward_mesh();
    let bits = |m: &Mesh| -> Vec<[u64; 3]> {
        triangle_coordinates(m)
            .iter()
            .flatten()
            .map(|v| v.to_array().map(f64::to_bits))
            .collect()
    };
    for (encoding, label) in ENCODINGS {
        let path = dir.path().join(format!("awkward_{label}.ply"));
        mesh::save(&path, &original, encoding).unwrap();
        let loaded = load_ok(&path).remove(0);
        assert_eq!(bits(&loaded), bits(&original), "{label}");
    }
    let path = dir.path().join("awkward.obj");
    mesh::save(&path, &original, PlyEncoding::Ascii).unwrap();
    let loaded = load_ok(&path).remove(0);
    assert_eq!(bits(&loaded), bits(&original), "obj");
}

#[test]
fn save_chooses_the_format_by_extension_in_any_case_and_rejects_others() {
    let dir = TempDir::new().unwrap();
    let sphere = generate::displaced_sphere(8, 0.0);
    assert_eq!(
        MeshFormat::from_path(Path::new("a/B.PLY")),
        Some(MeshFormat::Ply)
    );
    assert_eq!(
        MeshFormat::from_path(Path::new("x.Obj")),
        Some(MeshFormat::Obj)
    );
    assert_eq!(MeshFormat::from_path(Path::new("x.stl")), None);
    assert_eq!(MeshFormat::from_path(Path::new("ply")), None);

    let upper = dir.path().join("UPPER.PLY");
    mesh::save(&upper, &sphere, PlyEncoding::BinaryBigEndian).unwrap();
    assert_eq!(load_ok(&upper)[0].triangles, sphere.triangles);

    let stl = dir.path().join("sphere.stl");
    let error = mesh::save(&stl, &sphere, PlyEncoding::Ascii).unwrap_err();
    assert_contains(&error.to_string(), &["sphere.stl", "unknown mesh format"]);

    let nowhere = dir.path().join("no/such/dir/sphere.ply");
    let error = mesh::save(&nowhere, &sphere, PlyEncoding::Ascii).unwrap_err();
    assert!(matches!(error, MeshError::Io { .. }), "{error:?}");
    assert!(
        error
            .to_string()
            .starts_with(&nowhere.display().to_string()),
        "{error}"
    );
}

// ---------------------------------------------------------------------------------------------
// 2. Polygons, property types, extra elements
// ---------------------------------------------------------------------------------------------

/// Asserts that `m` is `n` triangles covering a convex planar polygon of `area` facing `facing`:
/// the triangles' areas add up to the polygon's, all face the same way, and every corner is a
/// polygon vertex.
#[track_caller]
fn assert_covers_polygon(m: &Mesh, polygon: &[DVec3], n: usize, area: f64, facing: DVec3) {
    assert_eq!(m.triangles.len(), n, "{m:?}");
    let mut total = 0.0;
    let mut signed = DVec3::ZERO;
    for &t in &m.triangles {
        let c = corners(m, t);
        for p in c {
            assert!(polygon.contains(&p), "{p} is not a polygon vertex");
        }
        let a = area_vector(c);
        assert!(a.dot(facing) > 0.0, "triangle {c:?} is wound the wrong way");
        total += a.length() / 2.0;
        signed += a / 2.0;
    }
    assert!(
        (total - area).abs() < 1e-12,
        "area {total}, expected {area}"
    );
    // The same total with signs: no triangle overlaps another with opposite orientation.
    assert!((signed.dot(facing) - area).abs() < 1e-12);
}

#[test]
fn obj_quads_and_pentagons_are_split_into_fans() {
    let dir = TempDir::new().unwrap();
    let path = write(
        &dir,
        "polygons.obj",
        "# a 2×1 rectangle and a convex pentagon of area 7, both facing +z\n\
         o quad\n\
         v 0 0 0\nv 2 0 0\nv 2 1 0\nv 0 1 0\n\
         f 1 2 3 4\n\
         o pentagon\n\
         v 0 0 5\nv 2 0 5\nv 3 1 5\nv 1 3 5\nv -1 1 5\n\
         f 5 6 7 8 9\n",
    );
    let meshes = load_ok(&path);
    assert_eq!(meshes.len(), 2);
    let quad = [(0., 0.), (2., 0.), (2., 1.), (0., 1.)].map(|(x, y)| DVec3::new(x, y, 0.0));
    let pentagon =
        [(0., 0.), (2., 0.), (3., 1.), (1., 3.), (-1., 1.)].map(|(x, y)| DVec3::new(x, y, 5.0));
    assert_eq!(meshes[0].name, "quad");
    assert_covers_polygon(&meshes[0], &quad, 2, 2.0, DVec3::Z);
    assert_eq!(meshes[1].name, "pentagon");
    assert_covers_polygon(&meshes[1], &pentagon, 3, 7.0, DVec3::Z);
}

#[test]
fn a_ply_quad_is_split_into_two_triangles() {
    let dir = TempDir::new().unwrap();
    // A unit square in the x = 1 plane, counter-clockwise seen from +x.
    let path = write(
        &dir,
        "quad.ply",
        "ply\nformat ascii 1.0\n\
         element vertex 4\nproperty float x\nproperty float y\nproperty float z\n\
         element face 1\nproperty list uchar int vertex_indices\nend_header\n\
         1 0 0\n1 1 0\n1 1 1\n1 0 1\n\
         4 0 1 2 3\n",
    );
    let m = load_ok(&path).remove(0);
    let square = [(0., 0.), (1., 0.), (1., 1.), (0., 1.)].map(|(y, z)| DVec3::new(1.0, y, z));
    assert_covers_polygon(&m, &square, 2, 1.0, DVec3::X);
    // A fan from the first vertex.
    assert_eq!(m.triangles, vec![[0, 1, 2], [0, 2, 3]]);
}

#[test]
fn ply_with_mixed_types_extra_properties_and_elements_loads() {
    let dir = TempDir::new().unwrap();
    // float/int/uchar coordinates, a colour, normals as floats, `vertex_index` (the other
    // common name) as a list of uint counted by a uchar, a per-face property after the list,
    // and an `edge` element between the vertices and the faces.
    let path = write(
        &dir,
        "types.ply",
        "ply\nformat ascii 1.0\ncomment mixed types\nobj_info made by hand\n\
         element vertex 4\n\
         property float x\nproperty int y\nproperty uchar z\n\
         property uchar red\nproperty uchar green\nproperty uchar blue\n\
         property float nx\nproperty float ny\nproperty float nz\n\
         element edge 2\nproperty int vertex1\nproperty int vertex2\n\
         element face 2\nproperty list uchar uint vertex_index\nproperty short flags\n\
         end_header\n\
         0.5 0 3 255 0 0 0 0 1\n\
         1.5 0 3 0 255 0 0 0 1\n\
         1.5 2 3 0 0 255 0 0 1\n\
         0.5 2 3 9 9 9 0 0 1\n\
         0 1\n\
         2 3\n\
         3 0 1 2 -7\n\
         3 0 2 3 12\n",
    );
    let m = load_ok(&path).remove(0);
    assert_eq!(
        m.vertices,
        vec![
            DVec3::new(0.5, 0.0, 3.0),
            DVec3::new(1.5, 0.0, 3.0),
            DVec3::new(1.5, 2.0, 3.0),
            DVec3::new(0.5, 2.0, 3.0),
        ]
    );
    assert_eq!(m.triangles, vec![[0, 1, 2], [0, 2, 3]]);
    assert_eq!(m.normals, Some(vec![DVec3::Z; 4]));
}

/// A PLY header + body in binary with small integer types: `short`/`ushort`/`char`
/// coordinates, a `double` weight, and `ushort` indices counted by a `uchar`.
fn small_types_ply(big_endian: bool) -> Vec<u8> {
    let format = if big_endian {
        "binary_big_endian"
    } else {
        "binary_little_endian"
    };
    let mut out = format!(
        "ply\nformat {format} 1.0\n\
         element vertex 3\nproperty short x\nproperty ushort y\nproperty char z\n\
         property double weight\n\
         element face 1\nproperty list uchar ushort vertex_indices\nend_header\n"
    )
    .into_bytes();
    let be = |b: &[u8]| -> Vec<u8> {
        let mut b = b.to_vec();
        if big_endian {
            b.reverse();
        }
        b
    };
    for (x, y, z) in [(-3i16, 0u16, -1i8), (5, 0, -1), (0, 60000, 2)] {
        out.extend(be(&x.to_le_bytes()));
        out.extend(be(&y.to_le_bytes()));
        out.extend(z.to_le_bytes());
        out.extend(be(&0.25f64.to_le_bytes()));
    }
    out.push(3);
    for i in [0u16, 1, 2] {
        out.extend(be(&i.to_le_bytes()));
    }
    out
}

#[test]
fn binary_ply_with_small_integer_types_loads_in_both_byte_orders() {
    let dir = TempDir::new().unwrap();
    for big_endian in [false, true] {
        let path = write(
            &dir,
            &format!("small_{big_endian}.ply"),
            small_types_ply(big_endian),
        );
        let m = load_ok(&path).remove(0);
        assert_eq!(
            m.vertices,
            vec![
                DVec3::new(-3.0, 0.0, -1.0),
                DVec3::new(5.0, 0.0, -1.0),
                DVec3::new(0.0, 60000.0, 2.0),
            ],
            "big endian: {big_endian}"
        );
        assert_eq!(m.triangles, vec![[0, 1, 2]]);
        assert_eq!(m.normals, None);
    }
}

// ---------------------------------------------------------------------------------------------
// 3. Several objects in one OBJ file
// ---------------------------------------------------------------------------------------------

#[test]
fn obj_objects_and_groups_become_separate_named_meshes() {
    let dir = TempDir::new().unwrap();
    let path = write(
        &dir,
        "two.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n\
         o a\nf 1 2 3\n\
         o b\nf 1 2 4\nf 2 3 4\n",
    );
    let meshes = load_ok(&path);
    let names: Vec<&str> = meshes.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(names, ["a", "b"]);
    assert_eq!(meshes[0].triangles.len(), 1);
    assert_eq!(meshes[1].triangles.len(), 2);
    // Each mesh holds just the vertices it uses (vertices are shared across the file).
    assert_eq!(meshes[0].vertices.len(), 3);
    assert_eq!(meshes[1].vertices.len(), 4);
    assert_eq!(
        triangle_coordinates(&meshes[1])[1],
        [DVec3::X, DVec3::Y, DVec3::Z]
    );

    let groups = write(
        &dir,
        "groups.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\n\
         g left\nf 1 2 3\n\
         g right\nf 3 2 1\n",
    );
    let names: Vec<String> = load_ok(&groups).into_iter().map(|m| m.name).collect();
    assert_eq!(names, ["left", "right"]);
}

#[test]
fn an_obj_file_that_names_no_object_gives_a_mesh_with_an_empty_name() {
    // `Mesh::name` is documented as "" when the file names none; it must not be a placeholder
    // made up by the OBJ reader (tobj says "unnamed_object").
    let dir = TempDir::new().unwrap();
    let path = write(
        &dir,
        "anonymous.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    );
    let meshes = load_ok(&path);
    assert_eq!(meshes.len(), 1);
    assert_eq!(meshes[0].name, "", "{meshes:?}");

    // Saving an unnamed mesh and reading it back keeps it unnamed.
    let mut m = awkward_mesh();
    m.name = String::new();
    let path = dir.path().join("unnamed.obj");
    mesh::save(&path, &m, PlyEncoding::Ascii).unwrap();
    assert_eq!(load_ok(&path)[0].name, "");
}

#[test]
fn obj_face_with_two_vertices_is_an_error() {
    // Like a PLY face with two vertices (see `ply_face_with_two_vertices_names_the_face`),
    // an OBJ `f` with two vertices is malformed and must not vanish silently.
    let dir = TempDir::new().unwrap();
    let path = write(
        &dir,
        "two.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2\n",
    );
    // `load_err` panics with the meshes if the file loads.
    assert_contains(&load_err(&path), &["two.obj:5: "]);
}

#[test]
fn obj_polylines_are_not_faces() {
    // `l` lines are polylines (ignored by timbre); a polyline through three or four points
    // is not a triangle or a quad.
    let dir = TempDir::new().unwrap();
    let path = write(
        &dir,
        "lines.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n\
         f 1 2 3\n\
         l 1 2\n\
         l 1 2 4\n\
         l 1 2 4 3\n",
    );
    let meshes = load_ok(&path);
    let triangles: usize = meshes.iter().map(|m| m.triangles.len()).sum();
    assert_eq!(triangles, 1, "{meshes:?}");
}

// ---------------------------------------------------------------------------------------------
// 4. Malformed files: every one is an error naming the file and the place, never a panic
// ---------------------------------------------------------------------------------------------

#[test]
fn a_missing_file_is_an_io_error_naming_it() {
    for name in ["does_not_exist.obj", "does_not_exist.ply"] {
        let path = corpus(name);
        let error = mesh::load(&path).unwrap_err();
        assert!(matches!(error, MeshError::Io { .. }), "{error:?}");
        let text = load_err(&path);
        assert_contains(&text, &[name, "No such file"]);
    }
}

#[test]
fn a_directory_is_an_io_error() {
    let dir = TempDir::new().unwrap();
    let path = dir.path().join("folder.ply");
    std::fs::create_dir(&path).unwrap();
    assert!(matches!(mesh::load(&path), Err(MeshError::Io { .. })));
    load_err(&path);
}

#[test]
fn an_unknown_extension_is_rejected_before_reading() {
    for name in ["triangle.stl", "missing.stl", "no_extension"] {
        let path = corpus(name);
        let text = load_err(&path);
        assert_eq!(
            text,
            format!(
                "{}: unknown mesh format: the file name must end in .obj or .ply",
                path.display()
            )
        );
    }
}

#[test]
fn obj_face_index_out_of_range_names_the_line() {
    let path = corpus("face_out_of_range.obj");
    let text = load_err(&path);
    assert_eq!(
        text,
        format!(
            "{}:6:7: face refers to vertex 4, but 3 are defined before this line",
            path.display()
        )
    );
}

#[test]
fn obj_face_index_out_of_range_names_the_line_with_crlf_and_negative_indices() {
    let dir = TempDir::new().unwrap();
    let crlf = write(
        &dir,
        "crlf.obj",
        "v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\n\r\nf 1 2 3\r\nf 1 2 9\r\n",
    );
    assert_contains(&load_err(&crlf), &["crlf.obj:6:7: ", "refers to vertex 9"]);
    // Relative indices: -1 is the last vertex so far, -4 is before the first of three.
    let negative = write(
        &dir,
        "negative.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nf -1 -2 -4\n",
    );
    assert_contains(
        &load_err(&negative),
        &["negative.obj:5:9: ", "refers to vertex -4"],
    );
    // Texture-coordinate-and-normal syntax still finds the vertex index.
    let slashes = write(
        &dir,
        "slashes.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\nf 1//1 5//1 3//1\n",
    );
    assert_contains(
        &load_err(&slashes),
        &["slashes.obj:6:8: ", "refers to vertex 5"],
    );
}

#[test]
fn obj_errors_name_the_line_for_every_kind_of_bad_vertex_or_reference() {
    // The module promises the offending line wherever the format allows (and the column of the
    // word at fault where there is one); it always does in OBJ. Collect every case before
    // failing, so one run shows them all.
    let dir = TempDir::new().unwrap();
    let cases = [
        ("w_zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0 0\nf 1 2 3\n", 3),
        (
            "five_numbers.obj",
            "v 0 0 0\nv 1 0 0 0.5 0.5\nv 0 1 0\nf 1 2 3\n",
            2,
        ),
        (
            "normal_index.obj",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\nf 1//9 2//1 3//1\n",
            6,
        ),
        (
            "texture_index.obj",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/1\nf 1/1 2/7 3/1\n",
            6,
        ),
        // -4 is before the first of the three vertices read so far (a fourth comes later).
        (
            "relative.obj",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\nv 5 5 5\n",
            4,
        ),
    ];
    let mut wrong = Vec::new();
    for (name, text, line) in cases {
        let path = write(&dir, name, text);
        let message = load_err(&path);
        if !message.contains(&format!("{name}:{line}: "))
            && !message.contains(&format!("{name}:{line}:"))
        {
            wrong.push(format!("expected line {line}: {message}"));
        }
    }
    assert!(
        wrong.is_empty(),
        "errors without their line:\n{}",
        wrong.join("\n")
    );
}

#[test]
fn obj_zero_index_names_the_line() {
    let path = corpus("zero_index.obj");
    let text = load_err(&path);
    assert_eq!(
        text,
        format!(
            "{}:5:3: face refers to vertex 0, but indices count from 1",
            path.display()
        )
    );
}

#[test]
fn obj_vertex_with_two_coordinates_names_the_line() {
    let path = corpus("short_vertex.obj");
    let text = load_err(&path);
    assert_eq!(
        text,
        format!(
            "{}:3: a vertex needs x y z, optionally w or r g b; got 2 numbers",
            path.display()
        )
    );
}

#[test]
fn obj_vertex_with_a_word_names_the_line() {
    let dir = TempDir::new().unwrap();
    let path = write(&dir, "word.obj", "v 0 0 0\nv 1 zero 0\nv 0 1 0\nf 1 2 3\n");
    assert_contains(
        &load_err(&path),
        &["word.obj:2:5: ", "'zero' is not a number"],
    );
    let normal = write(
        &dir,
        "normal.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 1\nf 1 2 3\n",
    );
    assert_contains(
        &load_err(&normal),
        &["normal.obj:4: ", "a normal needs three numbers"],
    );
    let face = write(
        &dir,
        "face.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 two 3\n",
    );
    assert_contains(
        &load_err(&face),
        &["face.obj:5:5: ", "'two' is not a vertex reference"],
    );
}

#[test]
fn obj_non_finite_vertex_names_the_line() {
    let path = corpus("nan_vertex.obj");
    let text = load_err(&path);
    assert_eq!(text, format!("{}:5:3: vertex 3: x is NaN", path.display()));
    let dir = TempDir::new().unwrap();
    for (name, word, why) in [
        ("inf.obj", "inf", "infinite"),
        (
            "huge.obj",
            "1e999",
            "infinite ('1e999' is too large for a double)",
        ),
        ("neg.obj", "-inf", "infinite"),
        ("nan.obj", "NaN", "NaN"),
    ] {
        let path = write(
            &dir,
            name,
            format!("v 0 0 0\nv 1 0 0\nv 0 {word} 0\nf 1 2 3\n"),
        );
        assert_contains(
            &load_err(&path),
            &[&format!("{name}:3:5: vertex 3: y is {why}")],
        );
    }
}

#[test]
fn obj_without_faces_is_an_error() {
    let path = corpus("no_faces.obj");
    assert_eq!(
        load_err(&path),
        format!("{}: the mesh has no faces", path.display())
    );
    let dir = TempDir::new().unwrap();
    let empty = write(&dir, "empty.obj", "");
    assert_contains(&load_err(&empty), &["empty.obj: ", "no faces"]);
    let comments = write(&dir, "comments.obj", "# nothing\n\n# at all\n");
    assert_contains(&load_err(&comments), &["comments.obj: ", "no faces"]);
}

#[test]
fn obj_that_is_not_utf8_is_an_error() {
    let dir = TempDir::new().unwrap();
    let mut bytes = b"v 0 0 0\nv 1 0 0\nv 0 1 0\n# caf".to_vec();
    bytes.extend([0xE9, 0xFF, 0xFE, b'\n']);
    bytes.extend(b"f 1 2 3\n");
    let path = write(&dir, "latin1.obj", bytes);
    // The first byte that is not UTF-8, where it is, escaped.
    assert_eq!(
        load_err(&path),
        format!(
            "{}:4:6: not a text file (invalid UTF-8: \\xe9)",
            path.display()
        )
    );
    // Random binary data named .obj.
    let noise: Vec<u8> = (0..4096u32)
        .map(|i| (i.wrapping_mul(2_654_435_761) >> 13) as u8)
        .collect();
    let path = write(&dir, "noise.obj", noise);
    load_err(&path);
}

#[test]
fn ply_without_a_vertex_element_is_an_error() {
    let path = corpus("no_vertex_element.ply");
    assert_eq!(
        load_err(&path),
        format!("{}:header: there is no 'vertex' element", path.display())
    );
}

#[test]
fn ply_without_an_x_property_is_an_error() {
    let path = corpus("no_x_property.ply");
    assert_eq!(
        load_err(&path),
        format!(
            "{}:4: the 'vertex' element has no property 'x'",
            path.display()
        )
    );
}

#[test]
fn ply_without_a_face_element_is_an_error() {
    let path = corpus("no_face_element.ply");
    assert_eq!(
        load_err(&path),
        format!("{}:header: there is no 'face' element", path.display())
    );
    // A face element without an index list.
    let dir = TempDir::new().unwrap();
    let path = write(
        &dir,
        "no_list.ply",
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
         property float z\nelement face 1\nproperty int material\nend_header\n\
         0 0 0\n1 0 0\n0 1 0\n7\n",
    );
    assert_contains(
        &load_err(&path),
        &[
            "no_list.ply:7: ",
            "the 'face' element has no list property 'vertex_indices'",
        ],
    );
}

#[test]
fn ply_face_index_out_of_range_names_the_face() {
    let path = corpus("face_out_of_range.ply");
    assert_eq!(
        load_err(&path),
        format!(
            "{}:14:7: face 1: vertex index 3 is out of range (the file has 3 vertices)",
            path.display()
        )
    );
}

#[test]
fn ply_negative_index_names_the_face() {
    let path = corpus("negative_index.ply");
    assert_eq!(
        load_err(&path),
        format!(
            "{}:15:5: face 2: vertex index -1 is out of range (the file has 3 vertices)",
            path.display()
        )
    );
}

#[test]
fn ply_face_with_two_vertices_names_the_face() {
    let path = corpus("two_vertex_face.ply");
    assert_eq!(
        load_err(&path),
        format!(
            "{}:14:1: face 1: a face needs at least 3 vertices, got 2",
            path.display()
        )
    );
}

/// Where the body of a PLY file starts.
fn body_start(bytes: &[u8]) -> usize {
    let end = b"end_header\n";
    bytes.windows(end.len()).position(|w| w == end).unwrap() + end.len()
}

#[test]
fn ply_non_finite_vertex_names_the_vertex() {
    let path = corpus("non_finite_vertex.ply");
    assert_eq!(
        load_err(&path),
        format!(
            "{}:13:3: vertex 2: y is infinite ('1e999' is too large for a double)",
            path.display()
        )
    );
    // A NaN in a binary file: the byte where the value starts (three doubles per vertex).
    let dir = TempDir::new().unwrap();
    let mut m = awkward_mesh();
    m.vertices[3].y = f64::NAN;
    for (encoding, label) in &ENCODINGS[1..] {
        let path = dir.path().join(format!("nan_{label}.ply"));
        mesh::save(&path, &m, *encoding).unwrap();
        let at = body_start(&std::fs::read(&path).unwrap()) + 3 * 24 + 8;
        assert_contains(
            &load_err(&path),
            &[&format!("nan_{label}.ply:byte {at}: vertex 3: y is NaN")],
        );
    }
}

#[test]
fn truncated_binary_ply_is_an_error() {
    let dir = TempDir::new().unwrap();
    let sphere = generate::displaced_sphere(200, 0.1);
    let (v, f) = (sphere.vertices.len(), sphere.triangles.len());
    for (encoding, label) in &ENCODINGS[1..] {
        let whole = dir.path().join(format!("whole_{label}.ply"));
        mesh::save(&whole, &sphere, *encoding).unwrap();
        let bytes = std::fs::read(&whole).unwrap();
        // Cut in half (in the vertices), one byte short (in the last face), and just after
        // the header. The error is at the end of the file.
        let body = body_start(&bytes);
        let half = bytes.len() / 2;
        let in_vertex = (half - body) / 48;
        for (cut, keep, expected) in [
            (
                "half",
                half,
                format!(
                    "the file ends inside vertex {in_vertex} (the header declares {v} vertices)"
                ),
            ),
            (
                "one_short",
                bytes.len() - 1,
                format!(
                    "the file ends inside face {} (the header declares {f} faces)",
                    f - 1
                ),
            ),
            (
                "header_only",
                body,
                format!("the file ends after 0 of the {v} vertices the header declares"),
            ),
        ] {
            let path = write(&dir, &format!("{cut}_{label}.ply"), &bytes[..keep]);
            assert_eq!(
                load_err(&path),
                format!("{}:byte {keep}: {expected}", path.display())
            );
        }
    }
}

#[test]
fn truncated_ascii_ply_names_the_missing_line() {
    let path = corpus("truncated_ascii.ply");
    // 9 header lines, 4 vertices, 1 of 2 faces: line 15 is missing.
    assert_eq!(
        load_err(&path),
        format!(
            "{}:15: the file ends after 1 of the 2 faces the header declares",
            path.display()
        )
    );
    // Cut in the middle of a vertex line.
    let dir = TempDir::new().unwrap();
    let bytes = std::fs::read(&path).unwrap();
    let keep = bytes.windows(5).position(|w| w == b"1 0 0").unwrap() + 3;
    let cut = write(&dir, "cut.ply", &bytes[..keep]);
    assert_contains(
        &load_err(&cut),
        &["cut.ply:11: vertex 1 has 2 values, the header declares 3"],
    );
}

#[test]
fn ply_garbage_in_the_body_names_the_line() {
    let dir = TempDir::new().unwrap();
    let path = write(
        &dir,
        "garbage.ply",
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
         property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n\
         0 0 0\n1 zero 0\n0 1 0\n3 0 1 2\n",
    );
    assert_contains(
        &load_err(&path),
        &["garbage.ply:11:3: vertex 1: 'zero' is not a number (property 'y' is float)"],
    );
}

#[test]
fn ply_garbage_header_is_an_error_at_line_1() {
    let path = corpus("not_a_ply.ply");
    assert_eq!(
        load_err(&path),
        format!(
            "{}:1: not a PLY file: the first line is 'not a ply file', not 'ply'",
            path.display()
        )
    );
    // An OBJ file named .ply, and a header that never ends.
    let dir = TempDir::new().unwrap();
    let obj = write(&dir, "obj.ply", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    assert_contains(
        &load_err(&obj),
        &["obj.ply:1: not a PLY file: the first line is 'v 0 0 0', not 'ply'"],
    );
    let endless = write(
        &dir,
        "endless.ply",
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n",
    );
    assert_contains(
        &load_err(&endless),
        &["endless.ply:5: the file ends in the header: there is no 'end_header' line"],
    );
    let bad_property = write(
        &dir,
        "bad_property.ply",
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty quaternion x\nend_header\n",
    );
    assert_contains(
        &load_err(&bad_property),
        &["bad_property.ply:4: 'quaternion' is not a PLY type: char, uchar, "],
    );
}

#[test]
fn an_empty_ply_file_is_an_error() {
    let path = corpus("empty.ply");
    assert_eq!(std::fs::metadata(&path).unwrap().len(), 0);
    assert_eq!(
        load_err(&path),
        format!("{}: not a PLY file: the file is empty", path.display())
    );
}

#[test]
fn ply_with_huge_counts_in_a_tiny_file_is_an_error_not_an_abort() {
    // The counts are believed only as far as the data goes: no giant allocation.
    let dir = TempDir::new().unwrap();
    for (label, format) in [
        ("ascii", "ascii"),
        ("le", "binary_little_endian"),
        ("be", "binary_big_endian"),
    ] {
        let path = write(
            &dir,
            &format!("huge_{label}.ply"),
            format!(
                "ply\nformat {format} 1.0\nelement vertex 18446744073709551615\n\
                 property float x\nproperty float y\nproperty float z\n\
                 element face 4000000000\nproperty list uint int vertex_indices\nend_header\n"
            ),
        );
        load_err(&path);
    }
    // A face list claiming four billion indices.
    let mut bytes = b"ply\nformat binary_little_endian 1.0\nelement vertex 3\n\
        property float x\nproperty float y\nproperty float z\n\
        element face 1\nproperty list uint int vertex_indices\nend_header\n"
        .to_vec();
    for v in [[0f32, 0., 0.], [1., 0., 0.], [0., 1., 0.]] {
        for x in v {
            bytes.extend(x.to_le_bytes());
        }
    }
    bytes.extend(u32::MAX.to_le_bytes());
    bytes.extend([0u8; 12]);
    let path = write(&dir, "long_list.ply", bytes);
    load_err(&path);
}

#[test]
fn every_prefix_of_a_small_ply_file_is_an_error_or_a_mesh_never_a_panic() {
    let dir = TempDir::new().unwrap();
    let m = small_mesh();
    for (encoding, label) in ENCODINGS {
        let whole = dir.path().join(format!("whole_{label}.ply"));
        mesh::save(&whole, &m, encoding).unwrap();
        let bytes = std::fs::read(&whole).unwrap();
        let path = dir.path().join(format!("prefix_{label}.ply"));
        for keep in 0..bytes.len() {
            std::fs::write(&path, &bytes[..keep]).unwrap();
            // An ASCII file cut just before its final newline is still complete.
            if let Ok(meshes) = mesh::load(&path) {
                assert_eq!(
                    encoding,
                    PlyEncoding::Ascii,
                    "{label} prefix of {keep} bytes"
                );
                assert_eq!(meshes[0].triangles, m.triangles);
            }
        }
    }
}

#[test]
fn every_prefix_of_a_small_obj_file_is_an_error_or_a_mesh_never_a_panic() {
    let dir = TempDir::new().unwrap();
    let m = small_mesh();
    let whole = dir.path().join("whole.obj");
    mesh::save(&whole, &m, PlyEncoding::Ascii).unwrap();
    let bytes = std::fs::read(&whole).unwrap();
    let path = dir.path().join("prefix.obj");
    for keep in 0..bytes.len() {
        std::fs::write(&path, &bytes[..keep]).unwrap();
        if let Err(e) = mesh::load(&path) {
            assert!(e.to_string().starts_with(&path.display().to_string()));
        }
    }
}

// ---------------------------------------------------------------------------------------------
// 4b. Header and body that disagree (issue 18): each is an error naming the line (and column)
//     or byte, and the declaration at fault, in plain words
// ---------------------------------------------------------------------------------------------

/// Asserts that every case (file name, contents, message after "PATH:") fails with exactly that
/// message; collects every mismatch before failing.
#[track_caller]
fn assert_messages(dir: &TempDir, cases: &[(&str, Vec<u8>, &str)]) {
    let mut wrong = Vec::new();
    for (name, contents, expected) in cases {
        let path = write(dir, name, contents);
        let expected = format!("{}:{expected}", path.display());
        match mesh::load(&path) {
            Ok(meshes) => wrong.push(format!("{name} loaded: {meshes:?}")),
            Err(e) if e.to_string() != expected => wrong.push(format!(
                "{name}:\n  expected {expected:?}\n  got      {:?}",
                e.to_string()
            )),
            Err(_) => {}
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

/// The start of an ASCII PLY file with `vertex` (x y z float) and `face` elements, with
/// `extra` header lines before `end_header`: 9 lines, plus those of `extra`.
fn ascii_header(vertices: usize, faces: usize, extra: &str) -> String {
    format!(
        "ply\nformat ascii 1.0\nelement vertex {vertices}\nproperty float x\nproperty float y\n\
         property float z\nelement face {faces}\nproperty list uchar int vertex_indices\n\
         {extra}end_header\n"
    )
}

#[test]
fn ply_corpus_of_header_and_body_mismatches_gives_exact_messages() {
    let cases = [
        (
            "x_is_a_list.ply",
            "5: property 'x' of element 'vertex' is a list; a coordinate must be a number",
        ),
        (
            "property_twice.ply",
            "7: property 'y' of element 'vertex' is declared twice (first on line 6)",
        ),
        (
            "element_twice.ply",
            "8: element 'vertex' is declared twice (first on line 4)",
        ),
        (
            "float_list_count.ply",
            "9: the count of list property 'vertex_indices' of element 'face' has type \
             'float': a list count must be of an integer type",
        ),
        (
            "ascii_2_0.ply",
            "2: format 'ascii 2.0' is not supported: PLY 1.0 only",
        ),
        (
            "extra_vertex_value.ply",
            "12:7: vertex 1 has 4 values, the header declares 3",
        ),
        (
            "extra_face_value.ply",
            "14:9: face 0 has 5 values, the header and its list count declare 4",
        ),
        (
            "more_faces_than_declared.ply",
            "15:1: the body has data after the 3 vertices and 1 face the header \
             declares",
        ),
        // The fourth vertex line is read as face 0: a list of 1, and one value too many.
        (
            "more_vertices_than_declared.ply",
            "14:5: face 0 has 3 values, the header and its list count declare 2",
        ),
        (
            "float_index_list.ply",
            "9: property 'vertex_indices' of element 'face' is a list of 'float'; vertex \
             indices must be of an integer type",
        ),
        ("nan_coordinate.ply", "11:1: vertex 0: x is NaN"),
        ("inf_coordinate.ply", "13:5: vertex 2: z is infinite"),
    ];
    let mut wrong = Vec::new();
    for (name, expected) in cases {
        let path = corpus(name);
        let text = load_err(&path);
        let expected = format!("{}:{expected}", path.display());
        if text != expected {
            wrong.push(format!(
                "{name}:\n  expected {expected:?}\n  got      {text:?}"
            ));
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

#[test]
fn ply_header_mistakes_name_the_line() {
    let dir = TempDir::new().unwrap();
    let body = "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    let vertex = "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n";
    let face = "element face 1\nproperty list uchar int vertex_indices\n";
    let file = |header: &str| format!("ply\n{header}end_header\n{body}").into_bytes();
    let cases: Vec<(&str, Vec<u8>, &str)> = vec![
        (
            "encoding.ply",
            file(&format!("format binary 1.0\n{vertex}{face}")),
            "2: format 'binary 1.0' is not supported: the encoding must be ascii, \
             binary_little_endian or binary_big_endian",
        ),
        (
            "binary_2.ply",
            file(&format!("format binary_big_endian 1.1\n{vertex}{face}")),
            "2: format 'binary_big_endian 1.1' is not supported: PLY 1.0 only",
        ),
        (
            "short_format.ply",
            file(&format!("format ascii\n{vertex}{face}")),
            "2: 'format ascii' is not a format line such as 'format ascii 1.0'",
        ),
        (
            "format_twice.ply",
            file(&format!(
                "format ascii 1.0\nformat ascii 1.0\n{vertex}{face}"
            )),
            "3: the format is declared twice (first on line 2)",
        ),
        (
            "no_format.ply",
            file(&format!("{vertex}{face}")),
            "2: element 'vertex' comes before the 'format' line",
        ),
        (
            "property_first.ply",
            file(&format!(
                "format ascii 1.0\nproperty float w\n{vertex}{face}"
            )),
            "3: property 'w' comes before any element",
        ),
        (
            "keyword.ply",
            file(&format!("format ascii 1.0\n{vertex}elemnt face 1\n")),
            "7: 'elemnt' is not a PLY header keyword (format, comment, obj_info, element, \
             property, end_header)",
        ),
        (
            "negative_count.ply",
            file("format ascii 1.0\nelement vertex -3\n"),
            "3: element 'vertex' has count '-3': a count must be a whole number",
        ),
        (
            "fractional_count.ply",
            file(&format!("format ascii 1.0\n{vertex}element face 1.5\n")),
            "7: element 'face' has count '1.5': a count must be a whole number",
        ),
        (
            "endless_count.ply",
            file(&format!(
                "format ascii 1.0\n{vertex}element face 123456789012345678901234567890\n"
            )),
            "7: element 'face' has count '123456789012345678901234567890', more than any \
             file can hold",
        ),
        (
            "too_many_vertices.ply",
            file(&format!(
                "format ascii 1.0\nelement vertex 4294967297\nproperty float x\n\
                 property float y\nproperty float z\n{face}"
            )),
            "3: the header declares 4294967297 vertices: timbre reads at most 4294967296",
        ),
        (
            "short_property.ply",
            file(&format!(
                "format ascii 1.0\n{vertex}element face 1\nproperty list uchar int\n"
            )),
            "8: 'property list uchar int' is not a property line such as 'property float \
             x' or 'property list uchar int vertex_indices'",
        ),
        (
            "end_header_and_more.ply",
            format!("ply\nformat ascii 1.0\n{vertex}{face}end_header now\n{body}").into_bytes(),
            "9: 'end_header now' has words after 'end_header'",
        ),
        (
            "scalar_indices.ply",
            file(&format!(
                "format ascii 1.0\n{vertex}element face 1\nproperty int vertex_indices\n"
            )),
            "8: property 'vertex_indices' of element 'face' is not a list; it must be a \
             list of vertex indices ('property list uchar int vertex_indices')",
        ),
        (
            "two_index_lists.ply",
            file(&format!(
                "format ascii 1.0\n{vertex}{face}property list uchar int vertex_index\n"
            )),
            "9: the 'face' element has both 'vertex_indices' (line 8) and 'vertex_index': \
             which are the faces?",
        ),
        (
            "normal_list.ply",
            file(&format!(
                "format ascii 1.0\n{vertex}property list uchar float nx\nproperty float ny\n\
                 property float nz\n{face}"
            )),
            "7: property 'nx' of element 'vertex' is a list; a normal's component must be a \
             number",
        ),
    ];
    assert_messages(&dir, &cases);
}

#[test]
fn ply_body_values_that_do_not_fit_their_declaration_name_line_and_column() {
    let dir = TempDir::new().unwrap();
    let header = ascii_header(3, 1, "");
    // 9 header lines: the vertices are on lines 10 to 12, the face on line 13.
    let file = |vertices: &str, face: &str| format!("{header}{vertices}{face}").into_bytes();
    let good = "0 0 0\n1 0 0\n0 1 0\n";
    let signed = "ply\nformat ascii 1.0\nelement vertex 3\nproperty int x\nproperty float y\n\
                  property float z\nelement face 1\nproperty list char int vertex_indices\n\
                  end_header\n";
    let long_digits = "9".repeat(400);
    let cases: Vec<(&str, Vec<u8>, &str)> = vec![
        (
            "short_line.ply",
            file("0 0 0\n1 0\n0 1 0\n", "3 0 1 2\n"),
            "11: vertex 1 has 2 values, the header declares 3",
        ),
        (
            "short_face.ply",
            file(good, "3 0 1\n"),
            "13: face 0 has 3 values, the header and its list count declare 4",
        ),
        (
            "float_index.ply",
            file(good, "3 0 1.0 2\n"),
            "13:5: face 0: '1.0' is not an integer (property 'vertex_indices' is \
             int)",
        ),
        (
            "big_count.ply",
            file(good, "300 0 1 2\n"),
            "13:1: face 0: 300 is out of range for property 'vertex_indices' \
             (uchar: 0 to 255)",
        ),
        (
            "negative_count.ply",
            format!("{signed}0 0 0\n1 0 0\n0 1 0\n-1 0 1 2\n").into_bytes(),
            "13:1: face 0: list 'vertex_indices' has a negative count (-1)",
        ),
        (
            "fractional_int.ply",
            format!("{signed}0 0 0\n1.5 0 0\n0 1 0\n3 0 1 2\n").into_bytes(),
            "11:1: vertex 1: '1.5' is not an integer (property 'x' is int)",
        ),
        // No 400-digit number in a message: cut at 40 characters.
        (
            "long_int.ply",
            format!("{signed}0 0 0\n{long_digits} 0 0\n0 1 0\n3 0 1 2\n").into_bytes(),
            "11:1: vertex 1: 9999999999999999999999999999999999999999… is out of \
             range for property 'x' (int: -2147483648 to 2147483647)",
        ),
        (
            "float_overflow.ply",
            file("0 0 0\n1 1e39 0\n0 1 0\n", "3 0 1 2\n"),
            "11:3: vertex 1: y is infinite ('1e39' is too large for a float)",
        ),
        (
            "long_double.ply",
            format!(
                "{}0 0 0\n1{} 0 0\n0 1 0\n3 0 1 2\n",
                header.replace("float x", "double x"),
                "0".repeat(309)
            )
            .into_bytes(),
            "11:1: vertex 1: x is infinite ('1000000000000000000000000000000000000000…' \
             is too large for a double)",
        ),
        (
            "word.ply",
            file("0 0 0\n1 one 0\n0 1 0\n", "3 0 1 2\n"),
            "11:3: vertex 1: 'one' is not a number (property 'y' is float)",
        ),
        (
            "index.ply",
            file(good, "3 0 1 3\n"),
            "13:7: face 0: vertex index 3 is out of range (the file has 3 vertices)",
        ),
        (
            "missing_vertex_line.ply",
            file("0 0 0\n1 0 0\n", ""),
            "12: the file ends after 2 of the 3 vertices the header declares",
        ),
        (
            "no_faces_line.ply",
            file(good, ""),
            "13: the file ends after 0 of the 1 face the header declares",
        ),
        (
            "trailing_words.ply",
            file(good, "3 0 1 2\n\n  # written by hand\n"),
            "15:3: the body has data after the 3 vertices and 1 face the header \
             declares",
        ),
    ];
    assert_messages(&dir, &cases);
}

#[test]
fn ply_other_elements_are_checked_as_strictly_as_vertices_and_faces() {
    let dir = TempDir::new().unwrap();
    let header = ascii_header(
        3,
        1,
        "element edge 2\nproperty int vertex1\nproperty uchar vertex2\n\
         element material 1\nproperty list uchar float weights\n",
    );
    let ok = "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    let good = write(
        &dir,
        "good.ply",
        format!("{header}{ok}0 1\n1 2\n2 0.5 1.5\n"),
    );
    assert_eq!(load_ok(&good)[0].triangles, vec![[0, 1, 2]]);
    let cases: Vec<(&str, Vec<u8>, &str)> = vec![
        (
            "edge_range.ply",
            format!("{header}{ok}0 1\n1 256\n2 0.5 1.5\n").into_bytes(),
            "20:3: edge 1: 256 is out of range for property 'vertex2' (uchar: 0 to \
             255)",
        ),
        (
            "edge_extra.ply",
            format!("{header}{ok}0 1 2\n1 2\n2 0.5 1.5\n").into_bytes(),
            "19:5: edge 0 has 3 values, the header declares 2",
        ),
        (
            "weights_short.ply",
            format!("{header}{ok}0 1\n1 2\n3 0.5 1.5\n").into_bytes(),
            "21: material 0 has 3 values, the header and its list count declare 4",
        ),
        (
            "after_material.ply",
            format!("{header}{ok}0 1\n1 2\n2 0.5 1.5\n0 0\n").into_bytes(),
            "22:1: the body has data after the 3 vertices, 1 face, 2 'edge' \
             elements and 1 'material' element the header declares",
        ),
    ];
    assert_messages(&dir, &cases);
}

/// `mesh` saved in `encoding`, as bytes.
fn saved_bytes(dir: &TempDir, m: &Mesh, encoding: PlyEncoding) -> Vec<u8> {
    let path = dir.path().join("saved.ply");
    mesh::save(&path, m, encoding).unwrap();
    std::fs::read(path).unwrap()
}

/// `bytes` with `from` replaced by `to` once, in the header.
fn with_header_change(bytes: &[u8], from: &str, to: &str) -> Vec<u8> {
    let body = body_start(bytes);
    let header = std::str::from_utf8(&bytes[..body]).unwrap();
    assert!(header.contains(from), "{from:?} not in {header:?}");
    let mut out = header.replacen(from, to, 1).into_bytes();
    out.extend(&bytes[body..]);
    out
}

#[test]
fn binary_ply_mismatches_name_the_element_and_the_byte() {
    let dir = TempDir::new().unwrap();
    let m = Mesh {
        normals: None,
        ..small_mesh()
    };
    // 4 vertices of 3 doubles (24 bytes), then 2 faces of 1 + 3·4 bytes.
    for (encoding, label) in &ENCODINGS[1..] {
        let bytes = saved_bytes(&dir, &m, *encoding);
        let body = body_start(&bytes);
        let face = |i: usize| body + 4 * 24 + i * 13;

        // One face fewer declared than the body holds.
        let fewer = with_header_change(&bytes, "element face 2", "element face 1");
        let path = write(&dir, &format!("fewer_{label}.ply"), &fewer);
        assert_eq!(
            load_err(&path),
            format!(
                "{}:byte {}: the body has data after the 4 vertices and 1 face the header \
                 declares",
                path.display(),
                face(1)
            )
        );
        // Two bytes of junk after the last face.
        let mut junk = bytes.clone();
        junk.extend(b"\n\n");
        let path = write(&dir, &format!("junk_{label}.ply"), &junk);
        assert_contains(
            &load_err(&path),
            &[&format!(
                "junk_{label}.ply:byte {}: the body has data after the 4 vertices and 2 faces",
                bytes.len()
            )],
        );

        // An index out of range: the third index of face 1 (byte 1 + 2·4 into the face).
        let mut bad = bytes.clone();
        let at = face(1) + 1 + 2 * 4;
        let seven = if *encoding == PlyEncoding::BinaryBigEndian {
            7u32.to_be_bytes()
        } else {
            7u32.to_le_bytes()
        };
        bad[at..at + 4].copy_from_slice(&seven);
        let path = write(&dir, &format!("index_{label}.ply"), &bad);
        assert_eq!(
            load_err(&path),
            format!(
                "{}:byte {at}: face 1: vertex index 7 is out of range (the file has 4 vertices)",
                path.display()
            )
        );

        // A face of two vertices: the error is at its count.
        let mut two = bytes.clone();
        two[face(0)] = 2;
        let path = write(&dir, &format!("two_{label}.ply"), &two);
        assert_contains(
            &load_err(&path),
            &[&format!(
                "two_{label}.ply:byte {}: face 0: a face needs at least 3 vertices, got 2",
                face(0)
            )],
        );

        // Infinity in vertex 2's z.
        let mut inf = bytes.clone();
        let at = body + 2 * 24 + 16;
        let value = if *encoding == PlyEncoding::BinaryBigEndian {
            f64::NEG_INFINITY.to_be_bytes()
        } else {
            f64::NEG_INFINITY.to_le_bytes()
        };
        inf[at..at + 8].copy_from_slice(&value);
        let path = write(&dir, &format!("inf_{label}.ply"), &inf);
        assert_eq!(
            load_err(&path),
            format!("{}:byte {at}: vertex 2: z is infinite", path.display())
        );
    }
}

#[test]
fn ply_messages_are_plain_words_without_rust_debug_output() {
    // ply-rs-bw's errors came through as `ParseError { location: LineCol { … } }` or
    // `Format((Ascii, Some(Version …)))`; none of that may reach a user.
    let dir = TempDir::new().unwrap();
    let mut paths: Vec<PathBuf> = std::fs::read_dir(corpus(""))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "ply"))
        .collect();
    for (name, text) in [
        ("version.ply", "ply\nformat ascii 1.5\n"),
        (
            "type.ply",
            "ply\nformat ascii 1.0\nelement vertex 1\nproperty real x\n",
        ),
        (
            "body.ply",
            "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n#\n",
        ),
        ("header.ply", "ply\nformat ascii 1.0\nelement vertex\n"),
    ] {
        paths.push(write(&dir, name, text));
    }
    assert!(paths.len() > 20);
    for path in paths {
        let Err(e) = mesh::load(&path) else {
            continue;
        };
        let text = e.to_string();
        for rust in [
            "ParseError",
            "LineCol",
            "Some(",
            "None",
            "Ascii",
            "Version",
            "Format(",
            "Error",
            "{",
            "::",
            "expected one of",
        ] {
            assert!(!text.contains(rust), "{rust:?} in {text:?}");
        }
    }
}

#[test]
fn text_from_a_file_is_shortened_and_escaped_in_messages() {
    let dir = TempDir::new().unwrap();
    let long = "v".repeat(5000);
    let cases: Vec<(&str, Vec<u8>, &str)> = vec![
        // Escape sequences that would clear the screen or set the window title.
        (
            "escape_header.ply",
            b"ply\nformat ascii 1.0\n\x1b]0;owned\x07\nend_header\n".to_vec(),
            "3: '\\x1b]0;owned\\x07' is not a PLY header keyword (format, comment, \
             obj_info, element, property, end_header)",
        ),
        (
            "escape_body.ply",
            format!(
                "{}0 0 0\n1 \x1b[2J 0\n0 1 0\n3 0 1 2\n",
                ascii_header(3, 1, "")
            )
            .into_bytes(),
            "11:3: vertex 1: '\\x1b[2J' is not a number (property 'y' is float)",
        ),
        // Bytes that are not UTF-8, and a right-to-left override.
        (
            "latin1.ply",
            b"ply\nformat ascii 1.0\nelement caf\xe9 1\nproperty float x\nend_header\n".to_vec(),
            "header: there is no 'vertex' element",
        ),
        (
            "bidi.ply",
            "ply\nformat ascii\u{202e}1.0 \n".as_bytes().to_vec(),
            "2: 'format ascii\\u{202e}1.0' is not a format line such as 'format ascii 1.0'",
        ),
        (
            "long_first_line.ply",
            long.clone().into_bytes(),
            "1: not a PLY file: the first line is 'vvvvvvvvvvvvvvvvvvvvvvvvvvvvvvvvvvvvvvvv…', \
             not 'ply'",
        ),
        (
            "long_obj.obj",
            format!("v 0 0 0\nv 1 0 {long}\n").into_bytes(),
            "2:7: 'vvvvvvvvvvvvvvvvvvvvvvvvvvvvvvvvvvvvvvvv…' is not a number",
        ),
        (
            "escape.obj",
            b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 \x1b[31m3\x00\n".to_vec(),
            "4:7: '\\x1b[31m3\\x00' is not a vertex reference",
        ),
    ];
    assert_messages(&dir, &cases);
    for (name, ..) in &cases {
        let text = load_err(&dir.path().join(name));
        assert!(
            !text.chars().any(|c| c.is_control() || c == '\u{202e}'),
            "{text:?}"
        );
        assert!(text.chars().count() < 250, "{text:?}");
    }
}

#[test]
fn ascii_ply_with_crlf_blank_lines_and_tabs_loads_like_the_plain_file() {
    let dir = TempDir::new().unwrap();
    let plain = format!(
        "{}0.1 0 0\n1 0 0\n0 1 0\n1 1 0\n3 0 1 2\n3 1 3 2\n",
        ascii_header(4, 2, "")
    );
    let expected = load_ok(&write(&dir, "plain.ply", &plain));
    // float properties are read as f32 (and widened), as the header says.
    assert_eq!(expected[0].vertices[0].x, f64::from(0.1f32));
    let crlf = plain.replace('\n', "\r\n");
    let spaced = plain
        .replace("0 1 0\n", "\t0   1\t0 \n\n")
        .replace("3 1 3 2\n", "\n3 1 3 2\n\n\n");
    for (name, text) in [("crlf.ply", crlf), ("spaced.ply", spaced)] {
        assert_eq!(load_ok(&write(&dir, name, text)), expected, "{name}");
    }
}

#[test]
fn obj_lines_tobj_would_reject_without_a_line_are_errors_with_one() {
    // Before, each of these came back from tobj as "invalid OBJ file: … parse error" with no
    // line, or (mixed forms) lost the normals silently.
    let dir = TempDir::new().unwrap();
    let tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    let long_index = "1".repeat(400);
    let cases: Vec<(&str, Vec<u8>, &str)> = vec![
        (
            "seven.obj",
            b"v 0 0 0\nv 1 0 0 1 0.5 0.5 0.5\nv 0 1 0\nf 1 2 3\n".to_vec(),
            "2: a vertex needs x y z, optionally w or r g b; got 7 numbers",
        ),
        (
            "colours.obj",
            b"v 0 0 0 1 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n".to_vec(),
            "2: vertex 2 has no colour (r g b) but the first vertex (line 1) has one: give \
             every vertex a colour or none",
        ),
        (
            "colours_late.obj",
            format!("{tri}v 1 1 0 0 0 1\nf 1 2 3\n").into_bytes(),
            "4: vertex 4 has a colour (r g b) but the first vertex (line 1) has none: give \
             every vertex a colour or none",
        ),
        (
            "vt.obj",
            format!("{tri}vt 0.5\nf 1/1 2/1 3/1\n").into_bytes(),
            "4: a texture coordinate needs u v, optionally w; got 1 number",
        ),
        (
            "forms.obj",
            format!("{tri}vn 0 0 1\nf 1//1 2//1 3\n").into_bytes(),
            "5:13: the face mixes '1//1' and '3': all its vertices must have the \
             same form (v, v/vt, v//vn or v/vt/vn)",
        ),
        (
            "w_nan.obj",
            format!("{tri}v 1 1 1 nan\nf 1 2 3\n").into_bytes(),
            "4:9: vertex 4: w is NaN",
        ),
        // An infinite w would put the vertex at the origin.
        (
            "w_inf.obj",
            format!("{tri}v 1 1 1 inf\nf 1 2 3\n").into_bytes(),
            "4:9: vertex 4: w is infinite",
        ),
        (
            "w_zero.obj",
            format!("{tri}v 1 1 1 0.0\nf 1 2 3\n").into_bytes(),
            "4:9: vertex 4: w is 0 (x, y and z are divided by w)",
        ),
        (
            "w_tiny.obj",
            format!("{tri}v 1 1e300 1 1e-300\nf 1 2 3\n").into_bytes(),
            "4: vertex 4: y / w is too large (infinite)",
        ),
        (
            "absurd.obj",
            format!("{tri}f 1 2 {long_index}\n").into_bytes(),
            "4:7: face refers to vertex 1111111111111111111111111111111111111111…, \
             but 3 are defined before this line",
        ),
        (
            "absurd_negative.obj",
            format!("{tri}f 1 2 -{long_index}\n").into_bytes(),
            "4:7: face refers to vertex -111111111111111111111111111111111111111…, \
             but 3 are defined before this line",
        ),
        (
            "utf8_late.obj",
            b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\no caf\xc3\xa9 \xff\n".to_vec(),
            "5:8: not a text file (invalid UTF-8: \\xff)",
        ),
    ];
    assert_messages(&dir, &cases);
    for (name, ..) in &cases {
        assert!(!load_err(&dir.path().join(name)).contains("invalid OBJ file"));
    }
}

#[test]
fn obj_harmless_oddities_still_load() {
    let dir = TempDir::new().unwrap();
    // tobj rejects a `usemtl` without a name after a space; materials are ignored anyway.
    let path = write(
        &dir,
        "usemtl.obj",
        "mtllib none.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl\nf 1 2 3\nusemtl\tred\nf 3 2 1\n",
    );
    let meshes = load_ok(&path);
    assert_eq!(meshes.iter().map(|m| m.triangles.len()).sum::<usize>(), 2);
    // Colours on every vertex, texture coordinates with w, faces of each form.
    let path = write(
        &dir,
        "forms.obj",
        "v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 1\nvt 0 0 0\nvt 1 0\nvn 0 0 1\n\
         f 1 2 3\nf 1/1 2/2 3/1\nf 1//1 2//1 3//1\nf 1/1/1 2/2/1 3/1/1\n",
    );
    let m = load_ok(&path);
    assert_eq!(m[0].triangles.len(), 4);
    // An object name with a control character is escaped: it ends up in messages.
    let path = write(
        &dir,
        "name.obj",
        "o red\x1b[31m\\x\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\no plain\\name\nf 3 2 1\n",
    );
    let names: Vec<String> = load_ok(&path).into_iter().map(|m| m.name).collect();
    assert_eq!(names, ["red\\x1b[31m\\\\x", "plain\\name"]);
}

// ---------------------------------------------------------------------------------------------
// 5. Zero-area triangles
// ---------------------------------------------------------------------------------------------

#[test]
fn zero_area_triangles_are_loaded_then_left_out_and_counted() {
    let path = corpus("degenerate.obj");
    let meshes = load_ok(&path);
    assert_eq!(meshes.len(), 1);
    let m = meshes.into_iter().next().unwrap();
    assert_eq!(m.triangles.len(), 5, "loading keeps every face");
    let zero = m
        .triangles
        .iter()
        .filter(|&&t| area_vector(corners(&m, t)) == DVec3::ZERO)
        .count();
    assert_eq!(zero, 3);

    let kept = triangle_coordinates(&m)[..2].to_vec();
    let t = TriangleMesh::with_normals(m.vertices.clone(), m.triangles.clone(), m.normals.clone())
        .unwrap();
    assert_eq!(t.triangles().len(), 2);
    assert_eq!(t.removed_degenerate(), 3);
    let left: Vec<[DVec3; 3]> = t
        .triangles()
        .iter()
        .map(|tri| tri.map(|i| t.vertices()[i as usize]))
        .collect();
    assert_eq!(left, kept, "the two good triangles are the ones kept");
}

#[test]
fn a_mesh_of_only_zero_area_triangles_is_rejected() {
    let path = corpus("all_degenerate.ply");
    let m = load_ok(&path).remove(0);
    assert_eq!(m.triangles.len(), 2);
    let error = TriangleMesh::with_normals(m.vertices, m.triangles, m.normals).unwrap_err();
    assert_contains(&error.to_string(), &["zero area"]);
}

#[test]
fn check_warns_about_zero_area_triangles() {
    let dir = TempDir::new().unwrap();
    std::fs::copy(corpus("degenerate.obj"), dir.path().join("degenerate.obj")).unwrap();
    write(&dir, "scene.toml", mesh_scene("degenerate.obj"));
    let run = timbre(dir.path(), &["check", "scene.toml"]);
    run.assert_success();
    assert_eq!(
        run.stderr.trim_end(),
        "timbre: warning: object 'm': 3 zero-area triangles ignored"
    );
    assert_eq!(number_after(&run.stdout, "triangles:"), 2);
    assert_eq!(number_after(&run.stdout, "objects:"), 1);
}

#[test]
fn check_rejects_a_mesh_of_only_zero_area_triangles() {
    let dir = TempDir::new().unwrap();
    std::fs::copy(
        corpus("all_degenerate.ply"),
        dir.path().join("all_degenerate.ply"),
    )
    .unwrap();
    write(&dir, "scene.toml", mesh_scene("all_degenerate.ply"));
    timbre(dir.path(), &["check", "scene.toml"]).assert_bad_input(&[
        &format!("scene.toml:{SHAPE_AT}: object 'm': "),
        "all_degenerate.ply",
        "zero area",
    ]);
}

// ---------------------------------------------------------------------------------------------
// 6. The command end to end
// ---------------------------------------------------------------------------------------------

#[test]
fn a_generated_mesh_checks_with_the_triangle_count_generate_mesh_printed() {
    let dir = TempDir::new().unwrap();
    for (file, encoding) in [
        ("x.ply", None),
        ("a.ply", Some("ascii")),
        ("b.ply", Some("binary-big-endian")),
        ("x.obj", None),
    ] {
        let mut args = vec!["generate-mesh", "-o", file, "--triangles", "5000"];
        if let Some(e) = encoding {
            args.extend(["--encoding", e]);
        }
        let run = timbre(dir.path(), &args);
        run.assert_success();
        // "8192 triangles, 4098 vertices -> x.ply"
        let line = run.stdout.trim_end();
        assert!(line.ends_with(&format!(" -> {file}")), "{line}");
        let made: u64 = line.split_whitespace().next().unwrap().parse().unwrap();
        assert!(made >= 5000, "{line}");
        assert!(line.contains(&format!("{made} triangles, ")), "{line}");

        let loaded = load_ok(&dir.path().join(file));
        assert_eq!(loaded[0].triangles.len() as u64, made, "{file}");

        let scene = format!("{file}.toml");
        write(&dir, &scene, mesh_scene(file));
        let run = timbre(dir.path(), &["check", &scene]);
        run.assert_success();
        assert_eq!(run.stderr, "", "{file}: no warnings");
        assert!(
            run.stdout.starts_with(&format!("{scene}: OK\n")),
            "{}",
            run.stdout
        );
        assert_eq!(number_after(&run.stdout, "triangles:"), made, "{file}");
        assert_eq!(number_after(&run.stdout, "objects:"), 1);
        // The bumpy unit sphere (bumps of 0.1) fits in [-1.1, 1.1]³.
        let bounds = run
            .stdout
            .lines()
            .find(|l| l.contains("bounding box:"))
            .unwrap();
        let numbers: Vec<f64> = bounds
            .split(|c: char| !(c.is_ascii_digit() || c == '.' || c == '-' || c == 'e'))
            .filter_map(|w| w.parse().ok())
            .collect();
        assert_eq!(numbers.len(), 6, "{bounds}");
        assert!(
            numbers.iter().all(|x| x.abs() <= 1.1 && x.abs() > 0.8),
            "{bounds}"
        );
    }
}

#[test]
fn generate_mesh_rejects_bad_arguments() {
    let dir = TempDir::new().unwrap();
    timbre(
        dir.path(),
        &["generate-mesh", "-o", "x.stl", "--triangles", "8"],
    )
    .assert_bad_input(&["x.stl", "unknown mesh format"]);
    timbre(
        dir.path(),
        &["generate-mesh", "-o", "x.ply", "--displacement", "1.5"],
    )
    .assert_bad_input(&["--displacement"]);
    timbre(
        dir.path(),
        &["generate-mesh", "-o", "no/dir/x.ply", "--triangles", "8"],
    )
    .assert_bad_input(&["no/dir/x.ply"]);
}

#[test]
fn check_names_the_scene_position_and_a_missing_mesh() {
    let dir = TempDir::new().unwrap();
    write(&dir, "scene.toml", mesh_scene("missing.ply"));
    let run = timbre(dir.path(), &["check", "scene.toml"]);
    run.assert_bad_input(&[&format!(
        "scene.toml:{SHAPE_AT}: object 'm': missing.ply: No such file"
    )]);
    assert_eq!(run.stdout, "");
}

#[test]
fn check_names_the_scene_the_mesh_and_the_line_of_a_malformed_obj() {
    let dir = TempDir::new().unwrap();
    std::fs::copy(corpus("face_out_of_range.obj"), dir.path().join("bad.obj")).unwrap();
    write(&dir, "scene.toml", mesh_scene("bad.obj"));
    let run = timbre(dir.path(), &["check", "scene.toml"]);
    run.assert_bad_input(&[]);
    assert_eq!(
        run.stderr.trim_end(),
        format!(
            "timbre: error: scene.toml:{SHAPE_AT}: object 'm': bad.obj:6:7: \
             face refers to vertex 4, but 3 are defined before this line"
        )
    );
}

#[test]
fn check_resolves_mesh_paths_relative_to_the_scene_file() {
    let dir = TempDir::new().unwrap();
    std::fs::create_dir_all(dir.path().join("scenes/meshes")).unwrap();
    std::fs::copy(
        corpus("face_out_of_range.ply"),
        dir.path().join("scenes/meshes/bad.ply"),
    )
    .unwrap();
    write(&dir, "scenes/scene.toml", mesh_scene("meshes/bad.ply"));
    timbre(dir.path(), &["check", "scenes/scene.toml"]).assert_bad_input(&[&format!(
        "scenes/scene.toml:{SHAPE_AT}: object 'm': scenes/meshes/bad.ply:14:7: \
         face 1: vertex index 3 is out of range"
    )]);

    // The same file, fixed, checks from anywhere.
    let m = generate::displaced_sphere(8, 0.0);
    mesh::save(
        &dir.path().join("scenes/meshes/bad.ply"),
        &m,
        PlyEncoding::BinaryLittleEndian,
    )
    .unwrap();
    let run = timbre(&dir.path().join("scenes"), &["check", "scene.toml"]);
    run.assert_success();
    assert_eq!(number_after(&run.stdout, "triangles:"), 8);
}

#[test]
fn check_reports_each_part_of_a_multi_object_obj() {
    let dir = TempDir::new().unwrap();
    write(
        &dir,
        "parts.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\n\
         o good\nf 1 2 3\n\
         o flat\nf 1 2 3\nf 1 2 4\n",
    );
    write(&dir, "scene.toml", mesh_scene("parts.obj"));
    let run = timbre(dir.path(), &["check", "scene.toml"]);
    run.assert_success();
    assert_eq!(number_after(&run.stdout, "objects:"), 2);
    assert_eq!(number_after(&run.stdout, "triangles:"), 2);
    assert_eq!(
        run.stderr.trim_end(),
        "timbre: warning: object 'm/flat': 1 zero-area triangles ignored"
    );
}

#[test]
fn check_numbers_the_unnamed_parts_of_a_multi_object_obj() {
    // Faces before the first `o` form a part the file does not name: the scene calls it
    // "part 1" (src/scene/file/shapes.rs), which needs `Mesh::name` to be "" for it.
    let dir = TempDir::new().unwrap();
    write(
        &dir,
        "parts.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\n\
         f 1 2 3\nf 1 2 4\n\
         o b\nf 3 2 1\n",
    );
    write(&dir, "scene.toml", mesh_scene("parts.obj"));
    let run = timbre(dir.path(), &["check", "scene.toml"]);
    run.assert_success();
    assert_eq!(number_after(&run.stdout, "objects:"), 2);
    assert_eq!(
        run.stderr.trim_end(),
        "timbre: warning: object 'm/part 1': 1 zero-area triangles ignored"
    );
}

#[test]
fn ply_with_no_faces_is_an_error() {
    let dir = TempDir::new().unwrap();
    let path = write(
        &dir,
        "zero_faces.ply",
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
         property float z\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n\
         0 0 0\n1 0 0\n0 1 0\n",
    );
    assert_eq!(
        load_err(&path),
        format!("{}: the mesh has no faces", path.display())
    );
}

/// `generate-mesh` writes single precision unless asked for double: the PLY declares `float`
/// coordinates (and normals), its vertex data takes half the bytes (the file is shorter by
/// 4 bytes a coordinate: 6 a vertex with its normal), and every coordinate read back is the
/// double-precision one rounded to the nearest f32; in every encoding and in OBJ alike.
#[test]
fn generated_meshes_are_single_precision_unless_asked() {
    let dir = TempDir::new().unwrap();
    let generate = |file: &str, extra: &[&str]| {
        let args = [&["generate-mesh", "-o", file, "--triangles", "2000"], extra].concat();
        timbre(dir.path(), &args).assert_success();
        dir.path().join(file)
    };
    for encoding in ["binary-little-endian", "binary-big-endian", "ascii"] {
        let single = generate("s.ply", &["--encoding", encoding]);
        let double = generate("d.ply", &["--encoding", encoding, "--precision", "f64"]);
        let text = |p: &Path| String::from_utf8_lossy(&std::fs::read(p).unwrap()).into_owned();
        assert!(text(&single).contains("property float x\n"), "{encoding}");
        assert!(text(&double).contains("property double x\n"), "{encoding}");
        let (s, d) = (load_ok(&single).remove(0), load_ok(&double).remove(0));
        if encoding != "ascii" {
            let size = |p: &Path| std::fs::metadata(p).unwrap().len();
            let header = |p: &Path| text(p).find("end_header\n").unwrap() as u64;
            let coordinates = d.vertices.len() as u64 * (3 + 3 * d.normals.is_some() as u64);
            assert_eq!(
                size(&double) - header(&double) - (size(&single) - header(&single)),
                4 * coordinates,
                "{encoding}"
            );
        }
        let rounded =
            |v: DVec3| DVec3::new(v.x as f32 as f64, v.y as f32 as f64, v.z as f32 as f64);
        assert_eq!(s.triangles, d.triangles);
        for (a, b) in s.vertices.iter().zip(&d.vertices) {
            assert_eq!(*a, rounded(*b), "{encoding}");
        }
    }
    let (single, double) = (
        generate("s.obj", &[]),
        generate("d.obj", &["--precision", "f64"]),
    );
    let (s, d) = (load_ok(&single).remove(0), load_ok(&double).remove(0));
    assert_eq!(s.vertices.len(), d.vertices.len());
    let rounded = |v: DVec3| DVec3::new(v.x as f32 as f64, v.y as f32 as f64, v.z as f32 as f64);
    let sorted = |m: &Mesh| {
        let mut v: Vec<[f64; 3]> = m.vertices.iter().map(|v| rounded(*v).to_array()).collect();
        v.sort_by(|a, b| a.partial_cmp(b).unwrap());
        v
    };
    assert_eq!(sorted(&s), sorted(&d));
}
