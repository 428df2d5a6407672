//! §3's lenses: one ray through each lens by its closed-form map and by integrating the ray
//! equation through its index profile, and the Fig. 6 scene (three lenses in front of the
//! lattice, 640×480, 1 spp, 2 threads) rendered both ways.
//!
//! Run with `cargo bench --bench lenses`; see docs/PERFORMANCE.md for figures.

mod common;

use std::hint::black_box;

use common::bench_frame;
use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use glam::DVec3;
use timbre::embree::Device;
use timbre::geometry::Sphere;
use timbre::scene::file;
use timbre::surfaces::lenses::{GradientIndex, IndexProfile, LensLaw};

/// 64 rays along +z entering the unit lens at the origin, impact parameters across (0, 1).
fn rays() -> Vec<(DVec3, DVec3)> {
    (0..64)
        .map(|k| {
            let b = (k as f64 + 0.5) / 64.0;
            (DVec3::new(b, 0.0, -(1.0 - b * b).sqrt()), DVec3::Z)
        })
        .collect()
}

fn one_ray(c: &mut Criterion) {
    let lens = Sphere::new(DVec3::ZERO, 1.0).expect("unit sphere");
    let rays = rays();
    let mut group = c.benchmark_group("lens_ray");
    group.throughput(Throughput::Elements(rays.len() as u64));
    for (name, mapping, profile) in [
        ("luneburg", LensLaw::Luneburg, IndexProfile::Luneburg),
        ("eaton", LensLaw::Eaton, IndexProfile::Eaton),
        (
            "maxwell_fisheye",
            LensLaw::MaxwellFisheye,
            IndexProfile::MaxwellFisheye,
        ),
    ] {
        let integration = LensLaw::GradientIndex(GradientIndex { profile });
        for (method, law) in [("mapping", &mapping), ("integration", &integration)] {
            group.bench_function(format!("{name}_{method}"), |b| {
                b.iter(|| {
                    for &(p, d) in &rays {
                        black_box(law.transmit(&lens, black_box(p), d));
                    }
                })
            });
        }
    }
    group.finish();
}

fn fig6(c: &mut Criterion) {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenes/fig6-perfect-imaging-lenses.toml"
    );
    let device = Device::new("").expect("Embree device");
    let mut group = c.benchmark_group("fig6_640x480_1spp");
    group.sample_size(10);
    for method in ["mapping", "integration"] {
        let overrides: Vec<file::Override> = (0..3)
            .map(|i| {
                format!("object.{i}.surface.method={method}")
                    .parse()
                    .expect("override")
            })
            .collect();
        let mut d = file::load_with(path.as_ref(), &overrides).expect("Fig. 6 scene");
        d.render.spp = 1;
        d.render.threads = Some(2);
        bench_frame(&mut group, &device, &format!("{method}_2_threads"), &d);
    }
    group.finish();
}

criterion_group!(benches, one_ray, fig6);
criterion_main!(benches);
