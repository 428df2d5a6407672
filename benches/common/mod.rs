//! Shared by the benchmarks: timing whole frames.

use criterion::measurement::WallTime;
use criterion::{BenchmarkGroup, Throughput};
use timbre::embree::Device;
use timbre::render::render;
use timbre::scene::{Scene, SceneDescription};
use timbre::trajectories;

/// Benchmarks rendering `d` with its own settings as `name` in `group`, with the frame's rays
/// (counted by one render first) as the throughput.
pub fn bench_frame(
    group: &mut BenchmarkGroup<WallTime>,
    device: &Device,
    name: &str,
    d: &SceneDescription,
) {
    let drawn = trajectories::draw(device, d).expect("trajectories");
    let scene = Scene::build(device, &drawn).expect("scene");
    let rays = render(&scene, &d.camera, &d.render, &|_| {})
        .expect("render")
        .rays;
    group.throughput(Throughput::Elements(rays));
    group.bench_function(name, |b| {
        b.iter(|| render(&scene, &d.camera, &d.render, &|_| {}))
    });
}
