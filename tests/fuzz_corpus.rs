//! The fuzzers' corpus (`tests/data/fuzz/TARGET/`, the inputs that reached new code while
//! fuzzing, minimised by `scripts/fuzz.sh --minimize`) run through the fuzz targets' own checks
//! (`fuzz/src/lib.rs`): no panic, and every error names its file first, in plain words.

#[path = "../fuzz/src/lib.rs"]
mod checks;

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::Path;

/// Runs `check` on every input of `target`'s corpus; fails naming each input that panicked.
fn replay(target: &str, check: impl Fn(&[u8])) {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/fuzz")
        .join(target);
    let mut inputs: Vec<_> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .collect();
    inputs.sort();
    assert!(inputs.len() >= 20, "{target}: {} inputs", inputs.len());
    let failed: Vec<String> = inputs
        .iter()
        .filter(|input| {
            let data = std::fs::read(input).unwrap();
            catch_unwind(AssertUnwindSafe(|| check(&data))).is_err()
        })
        .map(|input| input.display().to_string())
        .collect();
    assert!(failed.is_empty(), "{target}: failed on {failed:#?}");
}

#[test]
fn scene_files_with_includes_and_meshes() {
    replay("scene", checks::scene);
}

#[test]
fn obj_files() {
    replay("obj", |data| checks::mesh(data, "m.obj"));
}

#[test]
fn ply_files() {
    replay("ply", |data| checks::mesh(data, "m.ply"));
}

#[test]
fn set_values() {
    replay("set", checks::set);
}
