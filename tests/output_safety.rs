//! Crash-safe output, tested with real faults: a full device, a full file system, a read-only
//! file system and a process killed while it writes. In every case the run reports the error
//! (never exit 0) and the file that was there before survives byte for byte.
//!
//! The file-system cases mount a small tmpfs, which needs root; where mounting is not allowed
//! they say so on stderr and check nothing else.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

use common::cli::{HANG, TIMBRE, files_in, path_str, timbre};
use tempfile::TempDir;

/// A small studio picture, rendered once as the "previous good file".
fn old_picture(dir: &Path, name: &str) -> (PathBuf, Vec<u8>) {
    let path = dir.join(name);
    timbre(
        dir,
        &[
            "render",
            "-o",
            path_str(&path),
            "--width",
            "32",
            "--height",
            "24",
            "--quiet",
        ],
    )
    .assert_success();
    let bytes = std::fs::read(&path).unwrap();
    (path, bytes)
}

/// A tmpfs of `size` mounted on a new directory, unmounted when dropped.
struct Tmpfs {
    dir: TempDir,
}

impl Tmpfs {
    fn mount(size: &str) -> Option<Tmpfs> {
        let dir = TempDir::new().unwrap();
        let status = Command::new("mount")
            .args(["-t", "tmpfs", "-o", &format!("size={size}"), "tmpfs"])
            .arg(dir.path())
            .status();
        if status.is_ok_and(|s| s.success()) {
            Some(Tmpfs { dir })
        } else {
            eprintln!("skipped: cannot mount a tmpfs here (needs root)");
            None
        }
    }

    fn path(&self) -> &Path {
        self.dir.path()
    }

    fn remount_read_only(&self) {
        let status = Command::new("mount")
            .args(["-o", "remount,ro"])
            .arg(self.path())
            .status()
            .unwrap();
        assert!(status.success(), "remount read-only");
    }
}

impl Drop for Tmpfs {
    fn drop(&mut self) {
        let _ = Command::new("umount").arg(self.dir.path()).status();
    }
}

#[test]
fn a_full_device_is_an_error_not_a_silent_success() {
    let dir = TempDir::new().unwrap();
    for name in ["full.png", "full.exr"] {
        std::os::unix::fs::symlink("/dev/full", dir.path().join(name)).unwrap();
        timbre(
            dir.path(),
            &["render", "-o", name, "--width", "32", "--height", "24"],
        )
        .assert_bad_input(&[name, "No space left on device"]);
    }
    std::os::unix::fs::symlink("/dev/full", dir.path().join("full.ply")).unwrap();
    let run = timbre(
        dir.path(),
        &["generate-mesh", "-o", "full.ply", "--triangles", "1000"],
    );
    assert_ne!(run.code, Some(0), "{}", run.stderr);
    assert!(
        run.stderr.contains("No space left on device"),
        "{}",
        run.stderr
    );
    assert!(Path::new("/dev/full").exists(), "the device is still there");
}

#[test]
fn a_full_file_system_keeps_the_old_picture() {
    let Some(fs) = Tmpfs::mount("96k") else {
        return;
    };
    let (png, old_png) = old_picture(fs.path(), "studio.png");
    let (exr, old_exr) = old_picture(fs.path(), "studio.exr");
    // Each of these needs more room than is left (the PNG about 150 kB).
    for (path, old) in [(&png, &old_png), (&exr, &old_exr)] {
        timbre(
            fs.path(),
            &[
                "render",
                "-o",
                path_str(path),
                "--width",
                "2560",
                "--height",
                "1920",
            ],
        )
        .assert_bad_input(&["No space left on device", "unchanged"]);
        assert_eq!(&std::fs::read(path).unwrap(), old, "{}", path.display());
    }
    // Merged parts and checkpoints are written the same way: a merge that does not fit, and a
    // render whose checkpoint does not fit, leave everything as it was.
    let parts = tempfile::TempDir::new().unwrap();
    for tile in ["0/2", "1/2"] {
        let name = format!("part{}.exr", &tile[..1]);
        let args = [
            "render", "-q", "-o", &name, "--width", "2560", "--height", "1920",
        ];
        timbre(parts.path(), &[&args[..], &["--tile", tile]].concat()).assert_success();
    }
    for path in [&png, &exr] {
        let part = |k: u32| parts.path().join(format!("part{k}.exr"));
        timbre(
            fs.path(),
            &[
                "merge",
                path_str(path),
                path_str(&part(0)),
                path_str(&part(1)),
            ],
        )
        .assert_bad_input(&["No space left on device", "unchanged"]);
    }
    timbre(
        fs.path(),
        &[
            "render",
            "-o",
            path_str(&exr),
            "--width",
            "2560",
            "--height",
            "1920",
            "--checkpoint-interval",
            "0.001",
        ],
    )
    .assert_bad_input(&["No space left on device"]);
    assert_eq!(std::fs::read(&png).unwrap(), old_png);
    assert_eq!(std::fs::read(&exr).unwrap(), old_exr);
    assert_eq!(
        files_in(fs.path()),
        ["studio.exr", "studio.exr.checkpoint", "studio.png"],
        "no temporary file"
    );
}

#[test]
fn a_read_only_directory_is_refused_before_rendering() {
    let Some(fs) = Tmpfs::mount("1m") else {
        return;
    };
    let (png, old) = old_picture(fs.path(), "studio.png");
    fs.remount_read_only();
    let run = timbre(
        fs.path(),
        &[
            "render",
            "-o",
            path_str(&png),
            "--width",
            "64",
            "--height",
            "48",
        ],
    );
    run.assert_bad_input(&["studio.png", "cannot write the output there", "Read-only"]);
    assert!(
        !run.stdout.contains("rays in"),
        "nothing was rendered: {}",
        run.stdout
    );
    assert_eq!(std::fs::read(&png).unwrap(), old);
}

#[test]
fn a_process_killed_while_writing_leaves_the_old_picture() {
    let dir = TempDir::new().unwrap();
    let (exr, old) = old_picture(dir.path(), "big.exr");
    // A large picture with AOVs takes long enough to write that the kill lands during it.
    let mut child = Command::new(TIMBRE)
        .args([
            "render", "-o", "big.exr", "--width", "3000", "--height", "2000",
        ])
        .args(["--aov", "depth,normal,object", "--quiet"])
        .current_dir(dir.path())
        .spawn()
        .unwrap();
    let start = Instant::now();
    let mut writing = false;
    while start.elapsed() < HANG {
        let temporary = files_in(dir.path())
            .iter()
            .any(|n| n.starts_with(".big.exr.timbre-") && n.ends_with(".tmp"));
        if temporary {
            writing = true;
            child.kill().unwrap();
            break;
        }
        if child.try_wait().unwrap().is_some() {
            break;
        }
        std::thread::sleep(Duration::from_micros(200));
    }
    child.wait().unwrap();
    let now = std::fs::read(&exr).unwrap();
    if writing {
        assert_eq!(now, old, "killed while writing: the old picture is intact");
    } else {
        // The write was too quick to catch: the new picture must then be complete.
        eprintln!("the write finished before it could be killed");
        assert!(now.len() > old.len() && now.starts_with(&[0x76, 0x2f, 0x31, 0x01]));
    }
}
