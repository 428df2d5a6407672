//! Production renders through the `timbre` command: parts of one render (tiles, pixel bounds,
//! sample ranges) merged with `timbre merge`, and renders stopped by a signal and resumed from
//! their checkpoint, all equal to the single uninterrupted render byte for byte; work of
//! another render is refused with a message naming the difference, and nothing on disk is lost.

mod common;

use std::io::{BufRead, BufReader};
use std::path::Path;
use std::process::{Command, Stdio};

use nix::sys::signal::{Signal, kill};
use nix::unistd::Pid;
use tempfile::TempDir;

use common::cli::{Run, files_in, path_str, timbre, write};

/// A small scene with several samples per pixel (jittered) and every AOV.
const SCENE: &str = "studio = \"lattice\"\n[render]\nwidth = 96\nheight = 72\nspp = 4\nseed = 11\n";
const AOVS: &str = "--aov=depth,normal,object,albedo";

fn bytes(path: &Path) -> Vec<u8> {
    std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

#[track_caller]
fn assert_same_file(a: &Path, b: &Path) {
    let (x, y) = (bytes(a), bytes(b));
    assert!(
        x == y,
        "{} and {} differ ({} and {} bytes)",
        a.display(),
        b.display(),
        x.len(),
        y.len()
    );
}

/// Runs `timbre render SCENE` with `args` in `dir`.
fn render(dir: &Path, scene: &Path, args: &[&str]) -> Run {
    let mut all = vec!["render", "--quiet", path_str(scene)];
    all.extend_from_slice(args);
    timbre(dir, &all)
}

fn merge(dir: &Path, output: &str, parts: &[&str]) -> Run {
    let mut all = vec!["merge", "--quiet", output];
    all.extend_from_slice(parts);
    timbre(dir, &all)
}

/// The data window (x0, y0, width, height) and the display window size of an EXR file.
fn windows(path: &Path) -> ((i32, i32, usize, usize), (usize, usize)) {
    let meta = exr::meta::MetaData::read_from_file(path, true).unwrap();
    let h = &meta.headers[0];
    let p = h.own_attributes.layer_position;
    let d = h.shared_attributes.display_window.size;
    ((p.0, p.1, h.layer_size.0, h.layer_size.1), (d.0, d.1))
}

#[test]
fn merged_tiles_and_pixel_bounds_equal_the_single_render_byte_for_byte() {
    let dir = TempDir::new().unwrap();
    let d = dir.path();
    let scene = write(d, "s.toml", SCENE);
    render(d, &scene, &["-o", "single.exr", AOVS]).assert_success();
    render(d, &scene, &["-o", "single.png"]).assert_success();

    for k in 0..3 {
        let tile = format!("{k}/3");
        render(
            d,
            &scene,
            &["-o", &format!("tile{k}.exr"), "--tile", &tile, AOVS],
        )
        .assert_success();
    }
    // Strip 1 of 3 of 72 rows: rows 24 to 47, within the whole 96 × 72 image.
    assert_eq!(windows(&d.join("tile1.exr")), ((0, 24, 96, 24), (96, 72)));
    // In any order.
    merge(d, "tiles.exr", &["tile2.exr", "tile0.exr", "tile1.exr"]).assert_success();
    assert_same_file(&d.join("tiles.exr"), &d.join("single.exr"));
    // One tile of one (a job array of one task) is a part too.
    render(d, &scene, &["-o", "all.exr", "--tile", "0/1", AOVS]).assert_success();
    merge(d, "one.exr", &["all.exr"]).assert_success();
    assert_same_file(&d.join("one.exr"), &d.join("single.exr"));

    // A mosaic of uneven rectangles, not aligned to anything.
    let bounds = ["0,37,0,29", "37,96,0,29", "0,61,29,72", "61,96,29,72"];
    let mut parts = Vec::new();
    for (i, b) in bounds.iter().enumerate() {
        let name = format!("piece{i}.exr");
        render(d, &scene, &["-o", &name, "--pixel-bounds", b, AOVS]).assert_success();
        parts.push(name);
    }
    assert_eq!(windows(&d.join("piece3.exr")), ((61, 29, 35, 43), (96, 72)));
    let parts: Vec<&str> = parts.iter().map(String::as_str).collect();
    merge(d, "mosaic.exr", &parts).assert_success();
    assert_same_file(&d.join("mosaic.exr"), &d.join("single.exr"));
    // Merged straight to PNG, as the single render writes it.
    merge(d, "mosaic.png", &parts).assert_success();
    assert_same_file(&d.join("mosaic.png"), &d.join("single.png"));
}

#[test]
fn merged_sample_ranges_equal_the_single_render_byte_for_byte() {
    let dir = TempDir::new().unwrap();
    let d = dir.path();
    let scene = write(d, "s.toml", SCENE.replace("spp = 4", "spp = 7"));
    render(d, &scene, &["-o", "single.exr", AOVS]).assert_success();
    for (name, samples) in [("a.exr", "0..2"), ("b.exr", "2..3"), ("c.exr", "3..7")] {
        render(d, &scene, &["-o", name, "--samples", samples, AOVS]).assert_success();
    }
    merge(d, "samples.exr", &["c.exr", "a.exr", "b.exr"]).assert_success();
    assert_same_file(&d.join("samples.exr"), &d.join("single.exr"));
    // Sample ranges of tiles and whole tiles mixed.
    for (name, args) in [
        ("top-a.exr", ["--tile", "0/2", "--samples", "0..5"]),
        ("top-b.exr", ["--tile", "0/2", "--samples", "5..7"]),
        ("bottom.exr", ["--tile", "1/2", "--samples", "0..7"]),
    ] {
        let mut all = vec!["-o", name, AOVS];
        all.extend_from_slice(&args);
        render(d, &scene, &all).assert_success();
    }
    merge(d, "mixed.exr", &["bottom.exr", "top-b.exr", "top-a.exr"]).assert_success();
    assert_same_file(&d.join("mixed.exr"), &d.join("single.exr"));
    // A sample range is a part of the same sequence, not a new one: its mean differs from the
    // whole render's.
    assert_ne!(bytes(&d.join("c.exr")), bytes(&d.join("single.exr")));
}

/// Starts `timbre render SCENE ARGS --progress json` in `dir`, waits until it reports some but
/// not all pixels done, and sends it `signal`; returns what it did.
fn interrupt(dir: &Path, scene: &Path, args: &[&str], signal: Signal) -> Run {
    let mut child = Command::new(common::cli::TIMBRE)
        .args(["render", path_str(scene), "--progress", "json"])
        .args(args)
        .current_dir(dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stderr = BufReader::new(child.stderr.take().unwrap());
    let mut seen = String::new();
    let mut line = String::new();
    let mut sent = false;
    while stderr.read_line(&mut line).unwrap() > 0 {
        seen.push_str(&line);
        let value: serde_json::Value = serde_json::from_str(line.trim()).unwrap_or_default();
        let fraction = value["fraction"].as_f64().unwrap_or(0.0);
        if !sent && fraction > 0.0 && fraction < 0.9 {
            let pid = Pid::from_raw(child.id().try_into().unwrap());
            kill(pid, signal).unwrap();
            sent = true;
        }
        line.clear();
    }
    let out = child.wait_with_output().unwrap();
    assert!(
        sent,
        "the render finished before it could be interrupted:\n{seen}"
    );
    Run {
        code: out.status.code(),
        stdout: String::from_utf8(out.stdout).unwrap(),
        stderr: seen,
    }
}

#[test]
fn a_render_stopped_by_a_signal_and_resumed_equals_the_uninterrupted_render() {
    let dir = TempDir::new().unwrap();
    let d = dir.path();
    // Long enough (a few seconds) to be stopped part of the way.
    let scene = write(
        d,
        "s.toml",
        "studio = \"lattice\"\n[render]\nwidth = 320\nheight = 240\nspp = 384\n",
    );
    let checkpoint = d.join("out.exr.checkpoint");
    let run = interrupt(
        d,
        &scene,
        &["-o", "out.exr", "--checkpoint-interval", "0.2", AOVS],
        Signal::SIGINT,
    );
    assert_eq!(run.code, Some(130), "{}", run.stderr);
    assert!(run.stderr.contains("--resume"), "{}", run.stderr);
    assert!(
        !d.join("out.exr").exists(),
        "no output from a stopped render"
    );
    let saved = files_in(&checkpoint);
    assert!(
        !saved.is_empty() && saved.iter().all(|f| f.starts_with("rows-")),
        "{saved:?}"
    );
    // Without --resume a checkpoint is not silently overwritten.
    render(
        d,
        &scene,
        &["-o", "out.exr", "--checkpoint-interval", "5", AOVS],
    )
    .assert_bad_input(&["out.exr.checkpoint", "--resume"]);
    let resumed = timbre(
        d,
        &[
            "render",
            path_str(&scene),
            "-o",
            "out.exr",
            "--resume",
            AOVS,
        ],
    );
    resumed.assert_success();
    assert!(
        resumed.stderr.contains("from the checkpoint"),
        "{}",
        resumed.stderr
    );
    assert!(
        !checkpoint.exists(),
        "the checkpoint is removed once the image is written"
    );
    render(d, &scene, &["-o", "whole.exr", AOVS]).assert_success();
    assert_same_file(&d.join("out.exr"), &d.join("whole.exr"));

    // SIGTERM (what Kubernetes and Slurm send) stops with a checkpoint too; resumed with more
    // samples per pixel, the render goes on with the same sample sequence.
    let run = interrupt(
        d,
        &scene,
        &["-o", "more.exr", "--spp", "256", "--resume"],
        Signal::SIGTERM,
    );
    assert_eq!(run.code, Some(143), "{}", run.stderr);
    render(d, &scene, &["-o", "more.exr", "--spp", "320", "--resume"]).assert_success();
    render(d, &scene, &["-o", "fresh.exr", "--spp", "320"]).assert_success();
    assert_same_file(&d.join("more.exr"), &d.join("fresh.exr"));
}

#[test]
fn a_checkpoint_is_continued_exactly_and_one_of_another_render_is_refused() {
    let dir = TempDir::new().unwrap();
    let d = dir.path();
    let scene = write(d, "s.toml", SCENE);
    render(d, &scene, &["-o", "single.exr", AOVS]).assert_success();
    // A checkpoint holds groups of 32 whole rows: a part of rows 0 to 31 is one.
    render(
        d,
        &scene,
        &["-o", "group.exr", "--pixel-bounds", "0,96,0,32", AOVS],
    )
    .assert_success();
    let checkpoint = d.join("out.exr.checkpoint");
    let kept = checkpoint.join("rows-0.exr");
    std::fs::create_dir(&checkpoint).unwrap();
    std::fs::copy(d.join("group.exr"), &kept).unwrap();
    let old = write(d, "out.exr", "the previous picture");

    let refused = |args: &[&str], needles: &[&str]| {
        let mut all = vec!["-o", "out.exr", "--resume"];
        all.extend_from_slice(args);
        render(d, &scene, &all).assert_bad_input(needles);
        assert_eq!(bytes(&old), b"the previous picture", "the output is kept");
        assert!(kept.exists(), "the checkpoint is kept");
    };
    refused(
        &[AOVS, "--seed", "12"],
        &["rows-0.exr", "seed is 11, not 12"],
    );
    refused(
        &[AOVS, "--width", "100", "--height", "72"],
        &["image is 96x72, not 100x72"],
    );
    refused(
        &[AOVS, "--set", "camera.position=[0, 1, -2]"],
        &["another scene"],
    );
    refused(
        &["--aov", "depth"],
        &["AOVs are depth,normal,object,albedo, not depth"],
    );
    refused(
        &[AOVS, "--spp", "3"],
        &["holds samples 0..4, more than this render's 0..3"],
    );
    refused(
        &[AOVS, "--spp", "1"],
        &["sample(s) per pixel", "pixel centre"],
    );
    refused(&[AOVS, "--samples", "1..4"], &["holds samples from 0"]);
    // Another version of timbre (the same number of characters, so the file stays valid).
    let mut other = bytes(&kept);
    let at = other
        .windows(5)
        .position(|w| w == env!("CARGO_PKG_VERSION").as_bytes());
    if env!("CARGO_PKG_VERSION").len() == 5
        && let Some(at) = at
    {
        other[at..at + 5].copy_from_slice(b"9.9.9");
        std::fs::write(&kept, &other).unwrap();
        refused(&[AOVS], &["written by timbre 9.9.9"]);
        std::fs::copy(d.join("group.exr"), &kept).unwrap();
    }
    // Truncated, and corrupted.
    let good = bytes(&kept);
    std::fs::write(&kept, &good[..good.len() * 2 / 3]).unwrap();
    refused(&[AOVS], &["rows-0.exr", "truncated"]);
    let mut bad = good.clone();
    let n = bad.len();
    for b in &mut bad[n - 2000..n - 1000] {
        *b ^= 0x5a;
    }
    std::fs::write(&kept, &bad).unwrap();
    refused(&[AOVS], &["rows-0.exr", "corrupted"]);
    std::fs::write(&kept, &good).unwrap();

    // The right checkpoint is continued: the rest is rendered, the kept rows are taken as they
    // are, and the image is the single render's.
    let run = render(d, &scene, &["-o", "out.exr", "--resume", AOVS]);
    run.assert_success();
    assert_same_file(&d.join("out.exr"), &d.join("single.exr"));
    assert!(!checkpoint.exists());
    // --resume with no checkpoint starts afresh (a requeued job's first run).
    std::fs::remove_file(d.join("out.exr")).unwrap();
    render(d, &scene, &["-o", "out.exr", "--resume", AOVS]).assert_success();
    assert_same_file(&d.join("out.exr"), &d.join("single.exr"));
}

#[test]
fn parts_that_do_not_make_up_one_image_are_refused_and_nothing_is_lost() {
    let dir = TempDir::new().unwrap();
    let d = dir.path();
    let scene = write(d, "s.toml", SCENE);
    for k in 0..3 {
        let tile = format!("{k}/3");
        render(d, &scene, &["-o", &format!("t{k}.exr"), "--tile", &tile]).assert_success();
    }
    render(d, &scene, &["-o", "s.exr", "--samples", "0..2"]).assert_success();
    render(
        d,
        &scene,
        &["-o", "seed.exr", "--tile", "1/3", "--seed", "3"],
    )
    .assert_success();
    render(d, &scene, &["-o", "whole.exr"]).assert_success();
    let old = write(d, "out.exr", "the previous picture");
    let refused = |parts: &[&str], needles: &[&str]| {
        merge(d, "out.exr", parts).assert_bad_input(needles);
        assert_eq!(bytes(&old), b"the previous picture");
    };
    refused(
        &["t0.exr", "t2.exr"],
        &["a gap", "samples 0..4 of pixels 0,96,24,48"],
    );
    refused(
        &["t0.exr", "t1.exr", "t1.exr", "t2.exr"],
        &["overlap", "t1.exr"],
    );
    refused(
        &["t0.exr", "t1.exr", "t2.exr", "s.exr"],
        &["overlap", "s.exr"],
    );
    refused(
        &["t0.exr", "seed.exr", "t2.exr"],
        &["seed.exr", "seed is 3, not 11"],
    );
    refused(&["t0.exr", "whole.exr"], &["whole.exr", "no exact sums"]);
    refused(
        &["t0.exr", "t1.exr", "missing.exr"],
        &["missing.exr", "cannot open"],
    );
    let good = bytes(&d.join("t1.exr"));
    write(d, "cut.exr", &good[..good.len() / 2]);
    refused(&["t0.exr", "cut.exr", "t2.exr"], &["cut.exr", "truncated"]);
    write(d, "junk.exr", "not an image at all");
    refused(
        &["t0.exr", "junk.exr"],
        &["junk.exr", "not a readable OpenEXR file"],
    );

    // Bad part requests: one message each, exit 2, nothing written.
    let args_refused = |args: &[&str], needles: &[&str]| {
        let mut all = vec!["-o", "part.exr"];
        all.extend_from_slice(args);
        let run = render(d, &scene, &all);
        assert_eq!(run.code, Some(2), "{}", run.stderr);
        for n in needles {
            assert!(run.stderr.contains(n), "{n:?}: {}", run.stderr);
        }
        assert!(!d.join("part.exr").exists());
    };
    args_refused(&["--tile", "3/3"], &["tile 3 of 3 does not exist"]);
    args_refused(&["--tile", "0/0"], &["tile 0 of 0"]);
    args_refused(&["--tile", "1/100"], &["72 rows high", "100 strips"]);
    args_refused(&["--tile", "a/b"], &["K/N"]);
    args_refused(
        &["--pixel-bounds", "0,97,0,10"],
        &["not within the 96x72 image"],
    );
    args_refused(&["--pixel-bounds", "5,5,0,10"], &["hold no pixels"]);
    args_refused(&["--samples", "2..9"], &["beyond the 4 samples per pixel"]);
    args_refused(&["--samples", "3..3"], &["are none"]);
    args_refused(
        &["--checkpoint-interval", "0"],
        &["from 0.001 to 1000000000 seconds, got 0"],
    );
    render(d, &scene, &["--tile", "0/2", "-o", "part.png"])
        .assert_bad_input(&["needs an OpenEXR output"]);
    let stereo = write(
        d,
        "stereo.toml",
        format!("{SCENE}[camera]\nstereo = \"anaglyph\"\n"),
    );
    render(d, &stereo, &["-o", "part.exr", "--tile", "0/2"])
        .assert_bad_input(&["single views only"]);
    merge(d, "nowhere/out.exr", &["t0.exr"]).assert_bad_input(&["nowhere/out.exr"]);
}
