//! Running the built `timbre` command in a temporary directory, and reading what it printed and
//! wrote (`tests/cli.rs`, `tests/mesh_io.rs`, `tests/scene_files.rs`).

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

use glam::DVec3;

pub const TIMBRE: &str = env!("CARGO_BIN_EXE_timbre");

/// The bound on every wait of the tests (a command, a connection, a message): reached only by a
/// hang, far above any honest run on a 2-core machine kept busy by other work. Speed is measured
/// by the benchmarks, never by a test.
pub const HANG: Duration = Duration::from_secs(300);

/// What a run of `timbre` did.
pub struct Run {
    pub code: Option<i32>,
    pub stdout: String,
    pub stderr: String,
}

impl Run {
    #[track_caller]
    pub fn assert_success(&self) -> &Self {
        assert_eq!(
            self.code,
            Some(0),
            "timbre failed:\nstdout: {}\nstderr: {}",
            self.stdout,
            self.stderr
        );
        self
    }

    /// Asserts exit code 2 (bad input) and a "timbre: error:" message containing every needle.
    #[track_caller]
    pub fn assert_bad_input(&self, needles: &[&str]) -> &Self {
        assert_eq!(
            self.code,
            Some(2),
            "expected exit 2:\nstdout: {}\nstderr: {}",
            self.stdout,
            self.stderr
        );
        assert!(
            self.stderr.starts_with("timbre: error: "),
            "no error message: {}",
            self.stderr
        );
        for needle in needles {
            assert!(
                self.stderr.contains(needle),
                "error message lacks {needle:?}: {}",
                self.stderr
            );
        }
        self
    }

    /// The value after `  NAME:` in the output of `timbre check`.
    #[track_caller]
    pub fn field(&self, name: &str) -> &str {
        let prefix = format!("  {name}:");
        self.stdout
            .lines()
            .find_map(|l| l.strip_prefix(&prefix))
            .map(str::trim)
            .unwrap_or_else(|| panic!("no {prefix:?} line in:\n{}", self.stdout))
    }

    /// The number after `  NAME:` in the output of `timbre check`.
    #[track_caller]
    pub fn count(&self, name: &str) -> u64 {
        let value = self.field(name);
        value
            .split_whitespace()
            .next()
            .and_then(|n| n.parse().ok())
            .unwrap_or_else(|| panic!("{name}: no number in {value:?}"))
    }

    /// The bounding box `[x, y, z] to [x, y, z]` printed by `timbre check`.
    #[track_caller]
    pub fn bounding_box(&self) -> (DVec3, DVec3) {
        let value = self.field("bounding box");
        let parse = |s: &str| -> DVec3 {
            let inner = s
                .trim()
                .strip_prefix('[')
                .and_then(|s| s.split(']').next())
                .unwrap_or_else(|| panic!("no [x, y, z] in {value:?}"));
            let xyz: Vec<f64> = inner
                .split(',')
                .map(|n| n.trim().parse().expect("a number"))
                .collect();
            DVec3::from_slice(&xyz)
        };
        let (lo, hi) = value
            .split_once(" to ")
            .unwrap_or_else(|| panic!("no 'A to B' in {value:?}"));
        (parse(lo), parse(hi))
    }
}

/// Runs `command` (which runs `timbre`) and collects what it did.
pub fn run(mut command: Command) -> Run {
    let out = command.output().expect("run timbre");
    Run {
        code: out.status.code(),
        stdout: String::from_utf8(out.stdout).expect("UTF-8 stdout"),
        stderr: String::from_utf8(out.stderr).expect("UTF-8 stderr"),
    }
}

/// Runs `timbre` with `args` in `dir`.
pub fn timbre(dir: &Path, args: &[&str]) -> Run {
    let mut command = Command::new(TIMBRE);
    command.args(args).current_dir(dir);
    run(command)
}

/// Writes `contents` to `dir/name`, creating directories on the way.
pub fn write(dir: impl AsRef<Path>, name: &str, contents: impl AsRef<[u8]>) -> PathBuf {
    let path = dir.as_ref().join(name);
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    std::fs::write(&path, contents).expect("write test file");
    path
}

pub fn path_str(path: &Path) -> &str {
    path.to_str().expect("UTF-8 path")
}

/// The names of the files in `dir`, sorted.
pub fn files_in(dir: impl AsRef<Path>) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

pub fn decode_png(path: &Path) -> image::RgbImage {
    image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgb8()
}

/// `timbre check` refuses the scene `text` (written to `dir` as `bad.toml`): exit code 2, a
/// message with every one of `needles`, located at line `line` of the file.
#[track_caller]
pub fn assert_refused_at_line(dir: &Path, text: &str, needles: &[&str], line: usize) {
    let path = write(dir, "bad.toml", text);
    let run = timbre(dir, &["check", path_str(&path)]);
    run.assert_bad_input(needles);
    assert_eq!(location(&run.stderr, &path).0, line, "{}", run.stderr);
}

/// The (line, column) of an error message `PATH:LINE:COLUMN: ...` about `path`.
#[track_caller]
pub fn location(message: &str, path: impl AsRef<Path>) -> (usize, usize) {
    let prefix = format!("{}:", path.as_ref().display());
    let start = message
        .find(&prefix)
        .unwrap_or_else(|| panic!("message does not name {prefix}: {message}"));
    let mut parts = message[start + prefix.len()..].splitn(3, ':');
    let mut number = || -> usize {
        let part = parts.next().unwrap_or_default();
        part.parse()
            .unwrap_or_else(|_| panic!("no {prefix}line:column in {message:?}"))
    };
    let (line, column) = (number(), number());
    assert!(column >= 1, "columns are 1-based: {message}");
    (line, column)
}

/// The port a `timbre serve` child (started with `--port 0` and its standard output piped)
/// listens on, read from the address it prints first, and that line; panics after [`HANG`].
pub fn served_port(child: &mut std::process::Child) -> (u16, String) {
    use std::io::{BufRead, BufReader};
    let stdout = child.stdout.take().expect("standard output piped");
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let mut line = String::new();
        let _ = BufReader::new(stdout).read_line(&mut line);
        let _ = tx.send(line);
    });
    let line = rx
        .recv_timeout(HANG)
        .expect("the server prints its address");
    let port = line
        .split("http://")
        .nth(1)
        .and_then(|rest| rest.split('/').next())
        .and_then(|host| host.rsplit(':').next())
        .and_then(|p| p.parse().ok())
        .unwrap_or_else(|| panic!("no address in {line:?}"));
    (port, line)
}
