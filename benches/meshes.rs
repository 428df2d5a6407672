//! Meshes and arrays: loading a 1,000,000-triangle binary PLY, building its BVH, rendering it
//! in front of the studio at 1920×1080 (rays per second as throughput), and building the BVH of
//! a 1000 × 1000 array of spheres (one million Embree instances).
//!
//! Run with `cargo bench --bench meshes`; see docs/PERFORMANCE.md for figures.

use std::path::Path;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use glam::DVec3;
use timbre::embree::Device;
use timbre::geometry::{ObjectArray, SceneGeometry, Shape, Sphere};
use timbre::mesh::{self, PlyEncoding, generate};
use timbre::render::render;
use timbre::scene::RenderSettings;
use timbre::scene::Scene;
use timbre::scene::file::parse;

const SCENE: &str = r#"
studio = "lattice"
[render]
width = 1920
height = 1080
[[object]]
name = "sphere"
shape = { type = "mesh", file = "sphere.ply" }
surface = { type = "shiny", colour = [0.9, 0.3, 0.2] }
transform = { scale = 0.6, translate = [0, 0, 5] }
"#;

fn mesh_1m(c: &mut Criterion) {
    let dir = tempfile::tempdir().expect("temporary directory");
    let ply = dir.path().join("sphere.ply");
    mesh::save(
        &ply,
        &generate::displaced_sphere(1_000_000, 0.1),
        PlyEncoding::BinaryLittleEndian,
    )
    .expect("write the mesh");
    let scene_path = dir.path().join("scene.toml");
    let load = || parse(SCENE, scene_path.to_str().expect("UTF-8 path")).expect("scene");
    let device = Device::new("").expect("Embree device");

    let mut group = c.benchmark_group("mesh_1m_triangles");
    group.sample_size(10);
    group.bench_function("load_binary_ply", |b| {
        b.iter(|| mesh::load(Path::new(&ply)))
    });
    let d = load();
    group.bench_function("load_scene_and_build_bvh", |b| {
        b.iter(|| Scene::build(&device, &load()).expect("BVH"))
    });
    let scene = Scene::build(&device, &d).expect("BVH");
    let rays = render(&scene, &d.camera, &d.render, &|_| {})
        .expect("render")
        .rays;
    group.throughput(Throughput::Elements(rays));
    let settings = RenderSettings {
        threads: Some(2),
        ..d.render.clone()
    };
    group.bench_function("render_1920x1080_2_threads", |b| {
        b.iter(|| render(&scene, &d.camera, &settings, &|_| {}))
    });
    group.finish();
}

fn array_1m(c: &mut Criterion) {
    let device = Device::new("").expect("Embree device");
    let sphere = Shape::Sphere(Sphere::new(DVec3::ZERO, 0.02).expect("sphere"));
    let offsets: Vec<DVec3> = (0..1_000_000)
        .map(|k| DVec3::new((k % 1000) as f64 * 0.05, (k / 1000) as f64 * 0.05, 5.0))
        .collect();
    let mut group = c.benchmark_group("array_1000x1000_spheres");
    group.sample_size(10);
    group.bench_function("build_bvh", |b| {
        b.iter(|| {
            SceneGeometry::build(
                &device,
                vec![(sphere.clone(), true)],
                vec![ObjectArray {
                    objects: 0..1,
                    offsets: offsets.clone(),
                }],
            )
            .expect("BVH")
        })
    });
    group.finish();
}

criterion_group!(benches, mesh_1m, array_1m);
criterion_main!(benches);
