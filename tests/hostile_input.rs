//! Hostile input (issue 18): files that are not regular files, files too large, text that is
//! not UTF-8, include "diamonds" and absurd options get one clear message and exit code 2,
//! promptly, never a hang or a runaway read.

mod common;

use std::process::Command;
use std::time::{Duration, Instant};

use tempfile::TempDir;

use common::cli::{Run, path_str, write};

/// Runs `timbre` with `args` in `dir`, killed (and the test failed) after 20 s: a hang.
fn bounded(dir: &std::path::Path, args: &[&str]) -> Run {
    let start = Instant::now();
    let mut command = Command::new("timeout");
    command
        .arg("20")
        .arg(common::cli::TIMBRE)
        .args(args)
        .current_dir(dir);
    let run = common::cli::run(command);
    assert_ne!(run.code, Some(124), "timbre {args:?} hung");
    assert!(start.elapsed() < Duration::from_secs(20));
    run
}

const SPHERE: &str = "[[object]]\nshape = { type = \"sphere\", centre = [0, 0, 0], radius = 1 }\n\
                      surface = { type = \"matt\", colour = [1, 1, 1] }\n";

#[test]
fn only_regular_files_are_read() {
    let dir = TempDir::new().unwrap();
    let d = dir.path();
    let fifo = d.join("fifo.toml");
    assert!(
        Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .unwrap()
            .success()
    );
    bounded(d, &["check", "fifo.toml"]).assert_bad_input(&[
        "fifo.toml",
        "FIFO",
        "not a regular file",
    ]);
    bounded(d, &["render", "/dev/zero"]).assert_bad_input(&["/dev/zero", "a device"]);
    bounded(d, &["check", path_str(d)]).assert_bad_input(&["a directory"]);
    // Included and mesh files alike, also behind a symbolic link.
    write(
        d,
        "inc.toml",
        "studio = \"empty\"\n[[include]]\nfile = \"fifo.toml\"\n",
    );
    bounded(d, &["check", "inc.toml"]).assert_bad_input(&["inc.toml:3:8", "FIFO"]);
    std::os::unix::fs::symlink("/dev/urandom", d.join("random.ply")).unwrap();
    write(
        d,
        "mesh.toml",
        "studio = \"empty\"\n[[object]]\nshape = { type = \"mesh\", file = \"random.ply\" }\n\
         surface = { type = \"matt\", colour = [1, 1, 1] }\n",
    );
    bounded(d, &["check", "mesh.toml"]).assert_bad_input(&["random.ply", "a device"]);
}

#[test]
fn text_that_is_not_utf8_is_located() {
    let dir = TempDir::new().unwrap();
    write(
        dir.path(),
        "latin1.toml",
        b"studio = \"empty\"\n# caf\xe9\n",
    );
    bounded(dir.path(), &["check", "latin1.toml"]).assert_bad_input(&[
        "latin1.toml:2:6",
        "not UTF-8",
        "at byte offset 22",
    ]);
}

#[test]
fn an_include_diamond_is_refused_at_once() {
    // Each file includes the next twice: 2^20 copies of the sphere at the bottom.
    let dir = TempDir::new().unwrap();
    for level in 0..20 {
        let next = format!("level{}.toml", level + 1);
        let include = format!("[[include]]\nfile = \"{next}\"\n");
        write(dir.path(), &format!("level{level}.toml"), include.repeat(2));
    }
    write(dir.path(), "level20.toml", SPHERE);
    let start = Instant::now();
    bounded(dir.path(), &["check", "level0.toml"])
        .assert_bad_input(&["includes files more than 10000 times"]);
    // Not after expanding a million spheres (the machine is shared: a generous bound).
    assert!(
        start.elapsed() < Duration::from_secs(5),
        "{:?}",
        start.elapsed()
    );
}

#[test]
fn absurd_thread_counts_are_refused_by_the_command_line() {
    let dir = TempDir::new().unwrap();
    let run = bounded(
        dir.path(),
        &["render", "--threads", "100000", "-o", "x.png"],
    );
    assert_eq!(run.code, Some(2), "{}", run.stderr);
    assert!(run.stderr.contains("1..=1024"), "{}", run.stderr);
    assert!(!dir.path().join("x.png").exists());
}
