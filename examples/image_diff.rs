//! Compares two 8-bit RGB PNGs of the same size, as `scripts/bench-anchors.sh` compares timbre's
//! pictures of the anchor scenes with bare Embree's: prints how many pixels differ by more than
//! a tolerance (in 8-bit levels, default 2) in any channel, and the largest difference.
//! Exits 1 if the sizes differ or more than `--max-differing` pixels (default: any) differ.
//!
//! `cargo run --release --example image_diff -- A.png B.png [TOLERANCE] [--max-differing N]`

use std::process::ExitCode;

fn main() -> Result<ExitCode, Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (mut paths, mut tolerance, mut max_differing) = (Vec::new(), 2u8, 0usize);
    let mut it = args.iter();
    while let Some(a) = it.next() {
        if a == "--max-differing" {
            max_differing = it.next().ok_or("--max-differing needs a number")?.parse()?;
        } else if paths.len() < 2 {
            paths.push(a.clone());
        } else {
            tolerance = a.parse()?;
        }
    }
    let [a, b] = paths.as_slice() else {
        return Err("usage: image_diff A.png B.png [TOLERANCE] [--max-differing N]".into());
    };
    let (a, b) = (image::open(a)?.to_rgb8(), image::open(b)?.to_rgb8());
    if a.dimensions() != b.dimensions() {
        println!(
            "sizes differ: {:?} and {:?}",
            a.dimensions(),
            b.dimensions()
        );
        return Ok(ExitCode::FAILURE);
    }
    let (mut differing, mut largest) = (0usize, 0u8);
    for (p, q) in a.pixels().zip(b.pixels()) {
        let d = (0..3).map(|c| p[c].abs_diff(q[c])).max().unwrap_or(0);
        largest = largest.max(d);
        differing += usize::from(d > tolerance);
    }
    let total = a.width() as usize * a.height() as usize;
    println!(
        "{differing} of {total} pixels differ by more than {tolerance}/255 ({:.4} %); largest difference {largest}/255",
        100.0 * differing as f64 / total as f64
    );
    Ok(if differing > max_differing {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    })
}
