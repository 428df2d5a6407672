//! §4–6's METATOY laws: the cost of one direction change for each law, and the METATOY window
//! studio (640×480, 1 spp, 2 threads) rendered with a clear pane and with each law in the pane.
//!
//! Run with `cargo bench --bench metatoys`; see docs/PERFORMANCE.md for figures.

mod common;

use std::hint::black_box;

use common::bench_frame;
use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use glam::{DMat3, DVec2, DVec3};
use timbre::embree::Device;
use timbre::scene::file;
use timbre::surfaces::metatoys::{
    Refraction, Telescopelets, hologram_direction, metric_refracted_direction, rotated,
};

/// 64 unit directions within 30° of +z.
fn directions() -> Vec<DVec3> {
    (0..64)
        .map(|k| {
            let (a, b) = (k as f64 * 2.4, 0.5 * (k as f64 + 0.5) / 64.0);
            DVec3::new(b * a.cos(), b * a.sin(), 1.0).normalize()
        })
        .collect()
}

fn one_ray(c: &mut Criterion) {
    let rays = directions();
    let g = DMat3::from_cols(
        DVec3::new(1.0, 0.2, 0.0),
        DVec3::new(0.2, 1.2, -0.5),
        DVec3::new(0.0, -0.5, 0.5),
    );
    let telescopes =
        Telescopelets::new(DVec3::Z, DVec3::X, DVec2::new(-0.5, -1.0), DVec2::ZERO).expect("gCLA");
    let mut group = c.benchmark_group("metatoy_ray");
    group.throughput(Throughput::Elements(rays.len() as u64));
    group.bench_function("metric_interface", |b| {
        b.iter(|| {
            for &d in &rays {
                black_box(metric_refracted_direction(
                    black_box(d),
                    &DMat3::IDENTITY,
                    &g,
                    Refraction::Positive,
                    false,
                ));
            }
        })
    });
    group.bench_function("gcla", |b| {
        b.iter(|| {
            for &d in &rays {
                black_box(telescopes.refract(black_box(d), DVec3::Z));
            }
        })
    });
    group.bench_function("ray_rotating", |b| {
        b.iter(|| {
            for &d in &rays {
                black_box(rotated(black_box(d), DVec3::Z, 1.0, DVec3::Z));
            }
        })
    });
    group.bench_function("phase_hologram", |b| {
        b.iter(|| {
            for &d in &rays {
                black_box(hologram_direction(black_box(d), DVec2::new(0.1, -0.05)));
            }
        })
    });
    group.finish();
}

fn window(c: &mut Criterion) {
    let device = Device::new("").expect("Embree device");
    let mut group = c.benchmark_group("metatoy_window_640x480_1spp");
    group.sample_size(10);
    for (name, surface) in [
        ("transparent", r#"{ type = "transparent" }"#),
        ("ray_rotating", r#"{ type = "ray-rotating" }"#),
        (
            "metric_interface",
            r#"{ type = "metric-interface", inside = [[1, 0.2, 0], [0.2, 1.2, -0.5], [0, -0.5, 0.5]] }"#,
        ),
        (
            "gcla",
            r#"{ type = "gcla", a = [0, 0, 1], u = [1, 0, 0], eta_u = -0.5, eta_v = -1 }"#,
        ),
    ] {
        let text = format!("studio = \"metatoy-window\"\n[window]\nsurface = {surface}\n");
        let mut d = file::parse(&text, "bench.toml").expect("window scene");
        d.render.threads = Some(2);
        bench_frame(&mut group, &device, &format!("{name}_2_threads"), &d);
    }
    group.finish();
}

criterion_group!(benches, one_ray, window);
criterion_main!(benches);
