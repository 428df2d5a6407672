//! TIM's standard studio at 1920×1080, 1 spp, on 1 and 2 threads, with the camera at rest and
//! moving at 0.99c (Fig. 2b: every primary ray Lorentz-transformed), and a finite-aperture camera
//! at 0.99c (Fig. 3, 8 spp). Criterion reports the time per frame and, as throughput, rays per
//! second (primary + shadow rays of one frame).
//!
//! Run with `cargo bench --bench studio`; see docs/PERFORMANCE.md for figures and anchors.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use glam::DVec3;
use timbre::cameras::{Camera, Focus};
use timbre::embree::Device;
use timbre::math::LorentzTransform;
use timbre::render::render;
use timbre::scene::RenderSettings;
use timbre::scene::Scene;
use timbre::scene::studio::Studio;

fn studio_1080p(c: &mut Criterion) {
    let d = Studio::Lattice.description();
    let device = Device::new("").expect("Embree device");
    let scene = Scene::build(&device, &d).expect("studio scene");
    let settings = RenderSettings {
        width: 1920,
        height: 1080,
        ..RenderSettings::default()
    };
    let rays = render(&scene, &d.camera, &settings, &|_| {})
        .expect("render")
        .rays;

    let mut group = c.benchmark_group("studio_1920x1080_1spp");
    group.sample_size(10).throughput(Throughput::Elements(rays));
    for threads in [1, 2] {
        let settings = RenderSettings {
            threads: Some(threads),
            ..settings.clone()
        };
        group.bench_function(format!("{threads}_threads"), |b| {
            b.iter(|| render(&scene, &d.camera, &settings, &|_| {}))
        });
    }
    group.finish();
}

/// The studio through a camera moving at 0.99c along +z: a pinhole (1 spp, rays still in
/// packets) and a finite aperture focused at 15 (8 spp).
fn studio_relativistic(c: &mut Criterion) {
    let d = Studio::Lattice.description();
    let device = Device::new("").expect("Embree device");
    let scene = Scene::build(&device, &d).expect("studio scene");
    let boost = LorentzTransform::new(DVec3::new(0.0, 0.0, 0.99)).expect("speed below c");
    let pinhole = d.camera.clone().with_velocity(boost);
    let aperture = Camera::clone(&pinhole).with_aperture(0.02, Focus::Plane { distance: 15.0 });
    let mut group = c.benchmark_group("studio_1920x1080_0.99c");
    group.sample_size(10);
    for (name, camera, spp) in [
        ("pinhole_1spp", &pinhole, 1),
        ("aperture_8spp", &aperture, 8),
    ] {
        let settings = RenderSettings {
            width: 1920,
            height: 1080,
            spp,
            threads: Some(2),
            ..RenderSettings::default()
        };
        let rays = render(&scene, camera, &settings, &|_| {})
            .expect("render")
            .rays;
        group.throughput(Throughput::Elements(rays));
        group.bench_function(format!("{name}_2_threads"), |b| {
            b.iter(|| render(&scene, camera, &settings, &|_| {}))
        });
    }
    group.finish();
}

criterion_group!(benches, studio_1080p, studio_relativistic);
criterion_main!(benches);
