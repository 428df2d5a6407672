//! Meshes in rendered pictures: a cube mesh renders like the same cube made of parallelograms,
//! with any surface law (the frame at a mesh hit comes from the triangle), placed by a transform
//! computed independently here.

use std::f64::consts::PI;

mod common;

use glam::DVec3;
use timbre::embree::Device;
use timbre::render::Image;

use common::images::render_text_in;

/// The cube [0,1]³ as an OBJ file with quad faces, wound counter-clockwise from outside.
const CUBE_OBJ: &str = "\
v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1
f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 4 8 7 3\nf 1 5 8 4\nf 2 3 7 6\n";

/// The cube's faces as (corner, span u, span v) with span_u × span_v pointing outwards.
fn cube_faces() -> [(DVec3, DVec3, DVec3); 6] {
    let (o, x, y, z) = (DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z);
    [
        (o, y, x), // z = 0, normal -z
        (z, x, y), // z = 1, normal +z
        (o, x, z), // y = 0, normal -y
        (y, z, x), // y = 1, normal +y
        (o, z, y), // x = 0, normal -x
        (x, y, z), // x = 1, normal +x
    ]
}

const SCALE: f64 = 0.6;
const ANGLE_DEG: f64 = 35.0;
const TRANSLATE: DVec3 = DVec3::new(-0.3, -0.4, 4.0);

/// Scale by SCALE, rotate by ANGLE_DEG about the axis (1,1,0)/√2 (Rodrigues' formula), then
/// translate: the placement the scene file asks for, computed without timbre's code.
fn place(p: DVec3) -> DVec3 {
    let k = DVec3::new(1.0, 1.0, 0.0).normalize();
    let a = ANGLE_DEG * PI / 180.0;
    let v = SCALE * p;
    v * a.cos() + k.cross(v) * a.sin() + k * k.dot(v) * (1.0 - a.cos()) + TRANSLATE
}

fn vec(v: DVec3) -> String {
    format!("[{:?}, {:?}, {:?}]", v.x, v.y, v.z)
}

fn scenes(surface: &str) -> (String, String) {
    let header = "studio = \"lattice\"\n[render]\nwidth = 96\nheight = 72\n";
    let mesh = format!(
        "{header}[[object]]\nname = \"cube\"\nshadow_throwing = false\n\
         shape = {{ type = \"mesh\", file = \"cube.obj\" }}\nsurface = {surface}\n\
         transform = {{ scale = {SCALE:?}, rotate = {{ axis = [1, 1, 0], angle_deg = {:?} }}, translate = {} }}\n",
        ANGLE_DEG,
        vec(TRANSLATE)
    );
    let mut faces = header.to_string();
    for (i, (c, u, v)) in cube_faces().into_iter().enumerate() {
        let corner = place(c);
        let (su, sv) = (place(c + u) - corner, place(c + v) - corner);
        faces += &format!(
            "[[object]]\nname = \"face {i}\"\nshadow_throwing = false\n\
             shape = {{ type = \"parallelogram\", corner = {}, span_u = {}, span_v = {} }}\n\
             surface = {surface}\n",
            vec(corner),
            vec(su),
            vec(sv)
        );
    }
    (mesh, faces)
}

/// Fraction of pixels whose colours differ by more than `tolerance` in any channel.
fn differing(a: &Image, b: &Image, tolerance: f64) -> f64 {
    let n = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .filter(|(p, q)| (**p - **q).abs().max_element() > tolerance)
        .count();
    n as f64 / a.pixels.len() as f64
}

#[test]
fn a_cube_mesh_renders_like_six_parallelograms() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("cube.obj"), CUBE_OBJ).unwrap();
    for surface in [
        "{ type = \"shiny\", colour = [0.8, 0.4, 0.2] }",
        "{ type = \"refractive\", index_ratio = 1.5, transmission = 0.9 }",
        "{ type = \"mirror\", reflection = 0.8 }",
    ] {
        let (mesh, faces) = scenes(surface);
        let (a, b) = (
            render_text_in(&mesh, dir.path()),
            render_text_in(&faces, dir.path()),
        );
        // The cube covers a good part of the picture, so the comparison means something.
        let empty = render_text_in(
            "studio = \"lattice\"\n[render]\nwidth = 96\nheight = 72\n",
            dir.path(),
        );
        let covered = differing(&b, &empty, 1e-9);
        assert!(covered > 0.05, "{surface}: the cube covers only {covered}");
        // Identical surfaces; only pixels whose rays graze an edge may differ (Embree decides
        // triangle hits in f32).
        let off = differing(&a, &b, 1e-6);
        assert!(
            off < 0.003,
            "{surface}: {:.2}% of the pixels differ",
            100.0 * off
        );
    }
}

/// Smooth normals bend the shading, but a surface law must still see a ray arrive from the side
/// the triangle faces, and a reflection about w must not pass through the triangle — also at
/// silhouettes, where the interpolated normal and the triangle's normal disagree most.
#[test]
fn smooth_mesh_frames_agree_with_the_triangle_about_sides() {
    use timbre::geometry::{SceneGeometry, Shape, TriangleMesh};
    use timbre::mesh::generate;

    let m = generate::displaced_sphere(200, 0.0);
    let mesh = TriangleMesh::with_normals(m.vertices, m.triangles, m.normals).unwrap();
    let device = Device::new("").unwrap();
    let scene = SceneGeometry::build(
        &device,
        vec![(Shape::TriangleMesh(mesh.clone()), true)],
        vec![],
    )
    .unwrap();
    let origin = DVec3::new(0.0, 0.0, -4.0);
    let (mut hits, mut bent) = (0, 0);
    for i in 0..200 {
        for j in 0..200 {
            let target = DVec3::new(-1.1 + 0.011 * i as f64, -1.1 + 0.011 * j as f64, 0.0);
            let d = (target - origin).normalize();
            let Some(hit) = scene.nearest(origin, d, 0.0, f64::INFINITY) else {
                continue;
            };
            hits += 1;
            let p = origin + hit.t * d;
            let g = mesh.face_normal(hit.prim);
            let w = scene.shapes()[hit.object].frame_along(p, hit.prim, d).w;
            let r = d - 2.0 * d.dot(w) * w;
            assert!(
                d.dot(g) < 0.0 && d.dot(w) < 0.0,
                "ray from outside seen from inside"
            );
            assert!(r.dot(g) > 0.0, "reflection through the triangle at {p}");
            if (w - g.normalize()).length() > 1e-6 {
                bent += 1;
            }
        }
    }
    // Most hits keep their smooth normal.
    assert!(
        hits > 20_000 && bent > hits * 9 / 10,
        "{bent} of {hits} smooth"
    );
}
