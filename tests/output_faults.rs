//! Output faults of the operating system's making: a file-size limit (`ulimit -f`), which the
//! kernel enforces with SIGXFSZ, and a render killed outright (`kill -9`), which cannot remove
//! its temporary file. A limit is an error of one line (exit code 2) that names the file, with
//! the old file intact and no temporary file left; a killed run's temporary file is removed by
//! the next run that writes the same file, and nothing else is touched.

mod common;

use std::path::Path;
use std::process::Command;
use std::time::{Duration, Instant};

use common::cli::{HANG, Run, TIMBRE, files_in, path_str, run, timbre};
use nix::sys::signal::{Signal, kill};
use nix::unistd::Pid;
use tempfile::TempDir;
use timbre::files::temporary_prefix;

/// Runs `timbre ARGS` in `dir` under a file-size limit of 50 blocks (25 600 bytes with a
/// POSIX shell's 512-byte blocks, 51 200 with bash's), set by the shell as a user would.
fn limited(dir: &Path, args: &[&str]) -> Run {
    let mut command = Command::new("sh");
    command
        .args(["-c", "ulimit -f 50 && exec \"$0\" \"$@\"", TIMBRE])
        .args(args)
        .current_dir(dir);
    run(command)
}

/// Asserts that `run` failed with one line naming `file` and the file-size limit.
#[track_caller]
fn assert_size_limit(run: &Run, file: &str) {
    run.assert_bad_input(&[file, "file too large", "file-size limit"]);
    assert_eq!(run.stderr.lines().count(), 1, "one line: {}", run.stderr);
}

/// A temporary file's name as process `pid` would make it for `target`.
fn temporary_name(target: &Path, pid: u32, random: &str) -> String {
    let mut name = temporary_prefix(target, pid);
    name.push(format!("{random}.tmp"));
    name.into_string().unwrap()
}

#[test]
fn a_file_size_limit_is_an_error_and_keeps_the_old_file() {
    let dir = TempDir::new().unwrap();
    let d = dir.path();
    for name in ["out.png", "out.exr", "mesh.ply"] {
        std::fs::write(d.join(name), format!("the old {name}")).unwrap();
    }
    let size = ["--width", "400", "--height", "300"];
    for name in ["out.png", "out.exr"] {
        let run = limited(d, &[&["render", "-o", name][..], &size].concat());
        assert_size_limit(&run, name);
        assert!(run.stderr.contains("unchanged"), "{}", run.stderr);
    }
    // The parts of a merge are written without a limit, the merge with one.
    let parts = TempDir::new().unwrap();
    for k in 0..2 {
        let (name, tile) = (format!("part{k}.exr"), format!("{k}/2"));
        let args = [&["render", "-q", "-o", &name, "--tile", &tile][..], &size].concat();
        timbre(parts.path(), &args).assert_success();
    }
    let (part0, part1) = (
        parts.path().join("part0.exr"),
        parts.path().join("part1.exr"),
    );
    let merge = ["merge", "out.exr", path_str(&part0), path_str(&part1)];
    assert_size_limit(&limited(d, &merge), "out.exr");
    let mesh = ["generate-mesh", "-o", "mesh.ply", "--triangles", "100000"];
    assert_size_limit(&limited(d, &mesh), "mesh.ply");
    // Standard output redirected to a file is held to the limit too.
    let info = Command::new("sh")
        .args(["-c", "ulimit -f 0 && exec \"$0\" info > info.txt", TIMBRE])
        .current_dir(d)
        .output()
        .unwrap();
    let stderr = String::from_utf8(info.stderr).unwrap();
    assert_eq!(info.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.starts_with("timbre: error: cannot write to standard output: file too large"),
        "{stderr}"
    );
    std::fs::remove_file(d.join("info.txt")).unwrap();
    for name in ["out.png", "out.exr", "mesh.ply"] {
        let now = std::fs::read_to_string(d.join(name)).unwrap();
        assert_eq!(now, format!("the old {name}"), "{name} is intact");
    }
    assert_eq!(
        files_in(d),
        ["mesh.ply", "out.exr", "out.png"],
        "no temporary file"
    );
}

#[test]
fn a_render_removes_the_temporary_files_of_killed_runs_of_its_output_only() {
    let dir = TempDir::new().unwrap();
    let d = dir.path();
    let out = d.join("out.exr");
    // A process id that no process has (beyond Linux's largest pid_max, 2²²), and a process
    // that is certainly alive: this test.
    let (dead, alive) = ((1 << 22) + 1, std::process::id());
    let stale = temporary_name(&out, dead, "AAAAAA");
    let mut kept = vec![
        temporary_name(&out, alive, "BBBBBB"),
        temporary_name(&d.join("other.exr"), dead, "CCCCCC"),
        // From another machine, boot or container: its process id means nothing here.
        format!(".out.exr.timbre-{dead}-00000000-DDDDDD.tmp"),
        "notes.txt".to_string(),
    ];
    for name in kept.iter().chain([&stale]) {
        std::fs::write(d.join(name), b"x").unwrap();
    }
    let render = [
        "render", "-q", "-o", "out.exr", "--width", "32", "--height", "24",
    ];
    timbre(d, &render).assert_success();
    kept.push("out.exr".to_string());
    kept.sort();
    assert_eq!(files_in(d), kept);
}

#[test]
fn a_run_killed_outright_leaves_a_temporary_file_that_the_next_run_removes() {
    let dir = TempDir::new().unwrap();
    let d = dir.path();
    let is_temporary = |n: &String| n.starts_with(".big.exr.timbre-") && n.ends_with(".tmp");
    // Large enough to take seconds: the image streams into the temporary file meanwhile.
    let mut child = Command::new(TIMBRE)
        .args(["render", "-q", "-o", "big.exr", "--width", "3000"])
        .args(["--height", "2000", "--spp", "16"])
        .current_dir(d)
        .spawn()
        .unwrap();
    let start = Instant::now();
    // The render's own temporary file once the image streams into it: not the empty one that
    // checking the output is writable makes and removes at once.
    let streaming =
        |n: &String| is_temporary(n) && std::fs::metadata(d.join(n)).is_ok_and(|m| m.len() > 0);
    let temporary = loop {
        if let Some(name) = files_in(d).into_iter().find(streaming) {
            break name;
        }
        let exited = child.try_wait().unwrap();
        assert!(exited.is_none(), "the render ended before it was killed");
        assert!(start.elapsed() < HANG, "no temporary file");
        std::thread::sleep(Duration::from_millis(1));
    };
    let pid = child.id();
    assert!(temporary.starts_with(&format!(".big.exr.timbre-{pid}-")));
    kill(Pid::from_raw(pid as i32), Signal::SIGKILL).unwrap();
    child.wait().unwrap();
    assert_eq!(files_in(d), [temporary], "left by the killed run");
    let render = [
        "render", "-q", "-o", "big.exr", "--width", "32", "--height", "24",
    ];
    timbre(d, &render).assert_success();
    assert_eq!(files_in(d), ["big.exr"]);
}

#[test]
fn a_resumed_render_removes_the_stale_temporary_files_of_its_checkpoint() {
    let dir = TempDir::new().unwrap();
    let d = dir.path();
    let size = ["--width", "96", "--height", "72", "--seed", "1"];
    // A checkpoint of one group (rows 0 to 31), as a render stopped after it would leave.
    let group = [&["render", "-q", "-o", "group.exr"][..], &size].concat();
    timbre(d, &[&group[..], &["--pixel-bounds", "0,96,0,32"]].concat()).assert_success();
    let checkpoint = d.join("out.exr.checkpoint");
    std::fs::create_dir(&checkpoint).unwrap();
    std::fs::rename(d.join("group.exr"), checkpoint.join("rows-0.exr")).unwrap();
    // The save of the next group killed outright, and one of a live process.
    let (dead, alive) = ((1 << 22) + 1, std::process::id());
    let stale = temporary_name(&checkpoint.join("rows-32.exr"), dead, "AAAAAA");
    let live = temporary_name(&checkpoint.join("rows-64.exr"), alive, "BBBBBB");
    for name in [&stale, &live] {
        std::fs::write(checkpoint.join(name), b"x").unwrap();
    }
    // A resume that is refused (another seed) has still swept the checkpoint.
    let resume = ["render", "-q", "-o", "out.exr", "--resume"];
    let other_seed = ["--width", "96", "--height", "72", "--seed", "2"];
    timbre(d, &[&resume[..], &other_seed].concat()).assert_bad_input(&["rows-0.exr", "seed"]);
    let mut kept = vec![live, "rows-0.exr".to_string()];
    kept.sort();
    assert_eq!(files_in(&checkpoint), kept);
}
