//! What the fuzz targets run and check, one function a target; `tests/fuzz_corpus.rs` runs the
//! same functions on the committed corpus in the normal test command. Each panics (an assertion)
//! where timbre misbehaves: a panic of its own, an error message that does not start with its
//! file, or one that shows a Rust type name or a parser's `Debug` output.

use std::path::{Path, PathBuf};

use timbre::prepare::{self, Needs};
use timbre::scene::RenderSettings;
use timbre::scene::file::{self, Override};

/// Scene files with includes and meshes, checked as `timbre check` checks them: the input is up
/// to four files separated by 0xFF bytes (never part of UTF-8 text), written as `scene.toml`,
/// `inc.toml`, `m.obj` and `m.ply`, so that the scene can include the second and use the meshes.
pub fn scene(data: &[u8]) {
    const NAMES: [&str; 4] = ["scene.toml", "inc.toml", "m.obj", "m.ply"];
    let mut files = data.split(|&b| b == 0xFF);
    for name in NAMES {
        put(name, files.next().unwrap_or_default());
    }
    let path = scratch().join(NAMES[0]);
    let description = match file::load(&path) {
        Ok(d) => d,
        Err(e) => return assert_plain(&e.to_string(), &path, data),
    };
    // Every check `timbre check` makes after loading, as it makes them; it refuses what would
    // not fit in memory, here (the fuzzer's limit is 2 GiB) a BVH of more than 1 GiB.
    if description.build_memory() > 1 << 30 {
        return;
    }
    let settings = RenderSettings {
        threads: Some(1),
        ..description.render.clone()
    };
    let _ = prepare::prepare(&description, &settings, &Needs::scene("fuzzing".into()));
}

/// A mesh file named `name` (its extension says how it is read), read as a `type = "mesh"`
/// shape reads it.
pub fn mesh(data: &[u8], name: &str) {
    let path = put(name, data);
    if let Err(e) = timbre::mesh::load(&path) {
        assert_plain(&e.to_string(), &path, data);
    }
}

/// `--set key=value` overrides, one a line, applied to a scene that uses most of the format.
pub fn set(data: &[u8]) {
    const INCLUDED: &str = "[[object]]\nname = \"ball\"\n\
        shape = { type = \"sphere\", centre = [0, 0, 0], radius = 0.5 }\n\
        surface = { type = \"mirror\" }\n";
    // Written every time: the scene target writes its own inc.toml in the same directory.
    put("inc.toml", INCLUDED.as_bytes());
    let path = put("base.toml", include_bytes!("../set-base.toml"));
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let overrides: Result<Vec<Override>, String> = text.lines().map(str::parse).collect();
    let Ok(overrides) = overrides else {
        return;
    };
    if let Err(e) = file::load_with(&path, &overrides) {
        assert_plain(&e.to_string(), &path, data);
    }
}

/// A directory for this thread's input files (tests replay several targets at once), removed
/// when the thread ends.
pub fn scratch() -> PathBuf {
    thread_local! {
        static DIR: tempfile::TempDir = tempfile::tempdir().expect("a scratch directory");
    }
    DIR.with(|d| d.path().to_path_buf())
}

/// Writes `bytes` to `name` in the scratch directory.
pub fn put(name: &str, bytes: &[u8]) -> PathBuf {
    let path = scratch().join(name);
    std::fs::write(&path, bytes).expect("a scratch file");
    path
}

/// Asserts what every error message must be: it names `path` first, and no Rust type name or
/// `Debug` output of a parser reaches the user (unless the input itself has those words, which
/// a message may quote).
pub fn assert_plain(message: &str, path: &Path, input: &[u8]) {
    let shown = path.display().to_string();
    assert!(
        message.starts_with(&shown),
        "an error that does not start with its file: {message}"
    );
    for leak in [
        "Section",
        "ParseError",
        "LineCol",
        "Some(",
        "Ascii",
        "BinaryLittleEndian",
        "Utf8Error",
        "invalid type",
        "invalid length",
        "invalid value",
        "i64",
        "\\u{1b}",
    ] {
        // Quoted from the input, perhaps with its runs of white space made one space (as a
        // header's words are quoted).
        let words = String::from_utf8_lossy(input)
            .split_whitespace()
            .collect::<Vec<_>>()
            .join(" ");
        let quoted =
            input.windows(leak.len()).any(|w| w == leak.as_bytes()) || words.contains(leak);
        assert!(
            !message.contains(leak) || quoted,
            "{leak} in an error: {message}"
        );
    }
}
