//! Ray trajectories: the time to follow the example scenes' rays (one BVH build included), and
//! the cost of drawing them, as renders of the examples with and without their trajectories.

mod common;

use common::bench_frame;
use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use timbre::embree::Device;
use timbre::scene::file;
use timbre::trajectories;

const SCENES: [&str; 3] = [
    "trajectories-glass-ball",
    "trajectories-metatoy-window",
    "trajectories-luneburg-focus",
];

fn scene(name: &str) -> timbre::scene::SceneDescription {
    let path = format!("{}/scenes/{name}.toml", env!("CARGO_MANIFEST_DIR"));
    file::load(path.as_ref()).expect("example scene")
}

fn follow(c: &mut Criterion) {
    let device = Device::new("").expect("Embree device");
    let mut group = c.benchmark_group("trajectory_trace");
    for name in SCENES {
        let d = scene(name);
        let rays: usize = d.trajectories.iter().map(|t| t.rays().len()).sum();
        group.throughput(Throughput::Elements(rays as u64));
        group.bench_function(name, |b| {
            b.iter(|| trajectories::trace(&device, &d).expect("traced"))
        });
    }
    group.finish();
}

fn draw(c: &mut Criterion) {
    let device = Device::new("").expect("Embree device");
    let mut group = c.benchmark_group("trajectory_render_640x480_1spp");
    group.sample_size(10);
    for name in SCENES {
        let mut d = scene(name);
        d.render.spp = 1;
        d.render.threads = Some(2);
        bench_frame(&mut group, &device, &format!("{name}_drawn"), &d);
        d.trajectories.clear();
        bench_frame(&mut group, &device, &format!("{name}_without"), &d);
    }
    group.finish();
}

criterion_group!(benches, follow, draw);
criterion_main!(benches);
