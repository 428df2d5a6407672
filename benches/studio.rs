//! TIM's standard studio at 1920×1080, 1 spp, on 1 and 2 threads. Criterion reports the time
//! per frame and, as throughput, rays per second (primary + shadow rays of one frame).
//!
//! Run with `cargo bench --bench studio`; see docs/PERFORMANCE.md for figures and anchors.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use timbre::embree::Device;
use timbre::render::{RenderSettings, render};
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

criterion_group!(benches, studio_1080p);
criterion_main!(benches);
