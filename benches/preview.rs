//! `timbre serve`'s targets (issue 22): after a camera change on TIM's studio at 640×480, the
//! first coarse frame within 100 ms and a full 1-spp frame within 250 ms. Each iteration moves
//! the camera (a `--set` of `camera.position`, as the page's navigation sends it), reloads the
//! scene (the BVH is kept: only the camera changed) and renders the coarse frame, then, in the
//! second benchmark, also the first full pass (one sample per pixel).
//!
//! Run with `cargo bench --bench preview`; see docs/PERFORMANCE.md for figures.

use std::path::PathBuf;
use std::sync::atomic::AtomicBool;

use criterion::{Criterion, criterion_group, criterion_main};
use timbre::scene::file::Override;
use timbre::serve::{Preview, PreviewOptions};

const STUDIO: &str = "studio = \"lattice\"\n[render]\nwidth = 640\nheight = 480\n";

fn camera_change(c: &mut Criterion) {
    let mut preview = Preview::new(PathBuf::from("studio.toml"), PreviewOptions::default())
        .expect("Embree device");
    let mut step = 0u32;
    let mut moved = move || {
        step += 1;
        let x = 0.01 * (step % 50) as f64;
        let set: Override = format!("camera.position=[{x}, 0, 0]").parse().unwrap();
        vec![set]
    };
    preview.load(STUDIO, &moved(), None).expect("the studio");
    let never = AtomicBool::new(false);
    let mut group = c.benchmark_group("preview_studio_640x480");
    group.sample_size(20);
    group.bench_function("camera_change_to_coarse_frame", |b| {
        b.iter(|| {
            preview.load(STUDIO, &moved(), None).unwrap();
            preview.coarse().unwrap().expect("a coarse frame")
        })
    });
    group.bench_function("camera_change_to_full_1spp_frame", |b| {
        b.iter(|| {
            preview.load(STUDIO, &moved(), None).unwrap();
            preview.coarse().unwrap();
            let mut frames = 0;
            assert!(preview.pass(&never, &mut |_, _| frames += 1).unwrap());
            frames
        })
    });
    group.finish();
}

criterion_group!(benches, camera_change);
criterion_main!(benches);
