//! Hostile input (issue 18): files that are not regular files, files too large, text that is
//! not UTF-8, include "diamonds" and absurd options get one clear message and exit code 2,
//! promptly, never a hang or a runaway read.

mod common;

use std::path::Path;
use std::process::Command;

use serde::Deserialize;
use tempfile::TempDir;

use common::cli::{HANG, Run, path_str, write};

/// Runs `timbre` with `args` in `dir`, killed (and the test failed) after [`HANG`].
fn bounded(dir: &std::path::Path, args: &[&str]) -> Run {
    capped(dir, args, u64::MAX)
}

/// [`bounded`] with an address-space limit of `bytes`: needing more memory is a failure.
fn capped(dir: &std::path::Path, args: &[&str], bytes: u64) -> Run {
    let mut command = Command::new("timeout");
    command.arg(HANG.as_secs().to_string());
    if bytes < u64::MAX {
        command.args(["prlimit", &format!("--as={bytes}")]);
    }
    command.arg(common::cli::TIMBRE).args(args).current_dir(dir);
    let run = common::cli::run(command);
    assert_ne!(run.code, Some(124), "timbre {args:?} hung");
    run
}

/// Makes a FIFO (named pipe) at `path`.
fn mkfifo(path: &Path) {
    let made = Command::new("mkfifo").arg(path).status().unwrap();
    assert!(made.success(), "mkfifo {}", path.display());
}

const SPHERE: &str = "[[object]]\nshape = { type = \"sphere\", centre = [0, 0, 0], radius = 1 }\n\
                      surface = { type = \"matt\", colour = [1, 1, 1] }\n";

#[test]
fn only_regular_files_are_read() {
    let dir = TempDir::new().unwrap();
    let d = dir.path();
    mkfifo(&d.join("fifo.toml"));
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
    // Not after expanding a million spheres, which needs more than 200 MB.
    capped(dir.path(), &["check", "level0.toml"], 200_000_000)
        .assert_bad_input(&["includes files more than 10000 times"]);
}

#[test]
fn includes_nested_too_deeply_are_refused_not_a_stack_overflow() {
    // A chain of 2000 files, each including the next once.
    let dir = TempDir::new().unwrap();
    for level in 0..2000 {
        let include = format!("[[include]]\nfile = \"level{}.toml\"\n", level + 1);
        write(dir.path(), &format!("level{level}.toml"), include);
    }
    write(dir.path(), "level2000.toml", SPHERE);
    bounded(dir.path(), &["check", "level0.toml"])
        .assert_bad_input(&["level100.toml:2:8", "nested more than 100 levels deep"]);
    bounded(dir.path(), &["check", "level1900.toml"]).assert_success();
}

#[test]
fn usage_errors_are_escaped_and_cut_too() {
    let dir = TempDir::new().unwrap();
    let deep = format!("v={}{}", "[".repeat(5000), "]".repeat(5000));
    let bell = "a\u{7}b";
    for value in [deep.as_str(), bell] {
        let run = bounded(dir.path(), &["check", "x.toml", "--set", value]);
        assert_eq!(run.code, Some(2), "{}", run.stderr);
        assert!(run.stderr.contains("--set <KEY=VALUE>"), "{}", run.stderr);
        assert!(run.stderr.len() < 2000, "{} bytes", run.stderr.len());
        assert!(!run.stderr.contains('\u{7}'), "{}", run.stderr);
    }
}

#[test]
fn a_scene_too_large_for_the_memory_there_is_refused_not_aborted() {
    // Ten million array copies of one sphere: 150 bytes of text, about 5 GB of BVH.
    let dir = TempDir::new().unwrap();
    write(
        dir.path(),
        "copies.toml",
        format!("{SPHERE}array = {{ vectors = [[3, 0, 0], [0, 3, 0]], counts = [10000, 1000] }}\n"),
    );
    let run = capped(dir.path(), &["check", "copies.toml"], 2_000_000_000);
    run.assert_bad_input(&[
        "copies.toml",
        "GiB for the scene's BVH",
        "fewer array copies",
    ]);
}

#[test]
fn a_long_stretch_that_cannot_be_parsed_in_parts_is_refused_before_parsing() {
    // 20 MB of one array: the toml crate would need about 1.5 GB for it.
    let dir = TempDir::new().unwrap();
    let text = format!(
        "studio = \"empty\"\n\n[render]\nx = [{}1]\n",
        "1,".repeat(10_000_000)
    );
    write(dir.path(), "dense.toml", text);
    bounded(dir.path(), &["check", "dense.toml"]).assert_bad_input(&[
        "dense.toml:1:1",
        "20 MB from here on could not be cut into parts of at most 16 MiB",
    ]);
}

#[test]
fn a_scene_reading_more_than_a_gibibyte_through_includes_is_refused() {
    // A 9 MB file included 130 times, refused from its size before it is read: its text (zero
    // bytes, not TOML) would be an error of its own if it were read first.
    let dir = TempDir::new().unwrap();
    let big = std::fs::File::create(dir.path().join("big.toml")).unwrap();
    big.set_len(9_000_000).unwrap();
    let include = "[[include]]\nfile = \"big.toml\"\n";
    write(dir.path(), "top.toml", include.repeat(130));
    bounded(dir.path(), &["check", "top.toml"]).assert_bad_input(&[
        "top.toml:240:8",
        "the scene's files come to more than 1024 MiB in all",
    ]);
    // The same behind a file that includes them, inside a group.
    write(
        dir.path(),
        "outer.toml",
        "[[group]]\n[[group.include]]\nfile = \"top.toml\"\n",
    );
    bounded(dir.path(), &["check", "outer.toml"]).assert_bad_input(&[
        "top.toml:240:8",
        "the scene's files come to more than 1024 MiB in all",
    ]);
}

#[test]
fn merge_reads_only_regular_files() {
    let dir = TempDir::new().unwrap();
    let d = dir.path();
    bounded(
        d,
        &[
            "render", "--width", "8", "--height", "4", "--tile", "0/2", "-o", "a.exr",
        ],
    )
    .assert_success();
    mkfifo(&d.join("b.exr"));
    bounded(d, &["merge", "out.exr", "a.exr", "b.exr"]).assert_bad_input(&["b.exr", "FIFO"]);
    bounded(d, &["merge", "out.exr", "a.exr", "/dev/zero"])
        .assert_bad_input(&["/dev/zero", "a device"]);
    assert!(!d.join("out.exr").exists());
}

#[test]
fn checkpoint_intervals_out_of_range_are_refused() {
    let dir = TempDir::new().unwrap();
    for (interval, shown) in [
        ("1e308", "1e308"),
        ("nan", "NaN"),
        ("0", "0"),
        ("inf", "inf"),
    ] {
        let args = ["render", "--checkpoint-interval", interval, "-o", "x.exr"];
        bounded(dir.path(), &args)
            .assert_bad_input(&[&format!("from 0.001 to 1000000000 seconds, got {shown}")]);
    }
}

#[test]
fn absurd_thread_counts_are_refused_by_the_command_line() {
    let dir = TempDir::new().unwrap();
    let run = bounded(
        dir.path(),
        &["render", "--threads", "100000", "-o", "x.png"],
    );
    assert_eq!(run.code, Some(2), "{}", run.stderr);
    assert!(
        run.stderr
            .contains("expected a whole number from 1 to 1024, got '100000'"),
        "{}",
        run.stderr
    );
    assert!(!dir.path().join("x.png").exists());
}

#[test]
fn control_characters_from_a_file_never_reach_the_terminal_and_long_tokens_are_cut() {
    let dir = TempDir::new().unwrap();
    // An object name with an OSC title sequence, BEL, a clear-screen sequence, NUL and a
    // right-to-left override, on a degenerate shape so that the name is quoted in the error.
    write(
        dir.path(),
        "evil.toml",
        "studio = \"empty\"\n[[object]]\n\
         name = \"evil\\u001b]0;pwned\\u0007\\u001b[2J\\u0000\\u202e\"\n\
         shape = { type = \"parallelogram\", corner = [0, 0, 0], span_u = [0, 0, 0], span_v = [0, 0, 0] }\n\
         surface = { type = \"matt\", colour = [1, 1, 1] }\n",
    );
    let run = bounded(dir.path(), &["check", "evil.toml"]);
    run.assert_bad_input(&["evil.toml:4:", r"evil\x1b]0;pwned\x07\x1b[2J\x00\u{202e}"]);
    let raw = |c: char| run.stderr.contains(c) || run.stdout.contains(c);
    for c in ['\x1b', '\x07', '\0', '\u{202e}'] {
        assert!(!raw(c), "{c:?} printed raw: {:?}", run.stderr);
    }
    // A 100 000-character key is not echoed whole.
    write(
        dir.path(),
        "long.toml",
        format!("{} = 1\n", "k".repeat(100_000)),
    );
    let run = bounded(dir.path(), &["check", "long.toml"]);
    run.assert_bad_input(&["long.toml:1:1", "unknown field", "characters left out"]);
    assert!(run.stderr.len() < 2000, "{} bytes", run.stderr.len());
}

#[test]
fn check_refuses_what_render_would_refuse() {
    let dir = TempDir::new().unwrap();
    // Between two facing mirrors, 10 000 rays of up to 100 interactions each would have a
    // million points: more than a scene's trajectories may have.
    let mirrors = "studio = \"empty\"\n\
        [[object]]\nshape = { type = \"disc\", centre = [0, 0, 0], normal = [0, 0, 1], radius = 10 }\n\
        surface = { type = \"mirror\" }\n\
        [[object]]\nshape = { type = \"disc\", centre = [0, 0, 1], normal = [0, 0, -1], radius = 10 }\n\
        surface = { type = \"mirror\" }\n\
        [[ray_trajectory]]\nstart = [0, 0, 0.5]\ndirection = [0, 0, 1]\n\
        cone_half_angle_deg = 1\nrays = 10000\nmax_interactions = 100\n";
    write(dir.path(), "mirrors.toml", mirrors);
    bounded(dir.path(), &["check", "mirrors.toml"]).assert_bad_input(&["mirrors.toml", "points"]);
    // Render settings beyond their limits.
    write(
        dir.path(),
        "huge.toml",
        "studio = \"empty\"\n[render]\nwidth = 16777217\nheight = 1\n",
    );
    bounded(dir.path(), &["check", "huge.toml"]).assert_bad_input(&["limit of 16777216"]);
}

/// The cases of `tests/data/malformed/expected.toml`.
#[derive(Deserialize)]
struct Corpus {
    case: Vec<Case>,
}

/// A malformed scene file, the exit code of `timbre check` on it and fragments of its message.
#[derive(Deserialize)]
struct Case {
    file: String,
    code: i32,
    message: Vec<String>,
}

#[test]
fn every_file_of_the_malformed_corpus_gets_its_one_line_message() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/malformed");
    let expected = std::fs::read_to_string(dir.join("expected.toml")).unwrap();
    let corpus: Corpus = toml::from_str(&expected).unwrap();
    let mut files: Vec<String> = common::cli::files_in(&dir);
    files.retain(|f| f != "expected.toml");
    let mut listed: Vec<String> = corpus.case.iter().map(|c| c.file.clone()).collect();
    listed.sort();
    assert_eq!(files, listed, "every file of the corpus has one case");
    for case in &corpus.case {
        let run = bounded(&dir, &["check", &case.file]);
        let what = format!("{}: {}", case.file, run.stderr);
        assert_eq!(run.code, Some(case.code), "{what}");
        assert!(run.stdout.is_empty(), "{what}");
        // One line, after the file name and where in it.
        let head = format!("timbre: error: {}{}", case.file, case.message[0]);
        assert!(run.stderr.starts_with(&head), "{what}");
        assert_eq!(run.stderr.find('\n'), Some(run.stderr.len() - 1), "{what}");
        assert!(
            !run.stderr.trim_end().chars().any(char::is_control),
            "a control character: {what}"
        );
        for fragment in &case.message {
            assert!(run.stderr.contains(fragment), "lacks {fragment:?}: {what}");
        }
        // No Rust type names or `Debug` output.
        for rust in [
            "Section",
            "u32",
            "i64",
            "i128",
            "f64",
            "struct",
            "enum",
            "Some(",
            "{ ",
            "invalid type",
            "invalid length",
            "sequence",
            "\\u{1b}",
        ] {
            assert!(!run.stderr.contains(rust), "{rust}: {what}");
        }
    }
}

/// Issue 36: a vector, matrix or array value has exactly the length it means, on the command
/// line (`--set`) as in files; what was given is said in the file's words, its control
/// characters escaped as everywhere else.
#[test]
fn set_values_have_exactly_their_length_and_are_described_in_the_files_words() {
    let dir = TempDir::new().unwrap();
    write(
        dir.path(),
        "s.toml",
        format!("studio = \"empty\"\n{SPHERE}"),
    );
    let render = |set: &str| {
        bounded(
            dir.path(),
            &["render", "s.toml", "-o", "x.png", "--set", set],
        )
    };
    for (set, message) in [
        (
            "camera.position=[0, 0, -5, 9]",
            "expected an array of 3 values, got 4 values",
        ),
        (
            "object.0.transform.translate=[1, 2, 3, 4]",
            "expected an array of 3 values, got 4 values",
        ),
        (
            "object.0.transform.matrix=[[1, 0, 0, 5], [0, 1, 0, 0], [0, 0, 1, 0]]",
            "expected an array of 3 values, got 4 values",
        ),
        (
            "camera.view_direction=[0, 1]",
            "expected an array of 3 values, got 2 values",
        ),
        (
            r#"camera.position="\u001b[2J""#,
            r#"expected an array of 3 values, got the text "\x1b[2J""#,
        ),
        ("render.shadows=[1]", "expected true or false, got an array"),
    ] {
        let run = render(set);
        run.assert_bad_input(&["s.toml (with --set", message]);
        assert!(!run.stderr.contains('\x1b') && !run.stderr.contains("\\u{1b}"));
    }
    assert!(!dir.path().join("x.png").exists());
}

/// Issue 36: the command line's numbers are refused in the words of the scene file's keys,
/// not Rust's ("invalid digit found in string").
#[test]
fn option_values_are_refused_in_the_words_of_the_scene_file() {
    let dir = TempDir::new().unwrap();
    for (option, value, message) in [
        (
            "--width",
            "1.5",
            "expected a whole number from 1 to 4294967295, got '1.5'",
        ),
        (
            "--seed",
            "-1",
            "expected a whole number from 0 to 18446744073709551615, got '-1'",
        ),
        (
            "--spp",
            "0",
            "expected a whole number from 1 to 4294967295, got '0'",
        ),
        ("--shadows", "maybe", "expected true or false, got 'maybe'"),
        (
            "--threads",
            "x",
            "expected a whole number from 1 to 1024, got 'x'",
        ),
        (
            "--checkpoint-interval",
            "soon",
            "expected a number, got 'soon'",
        ),
    ] {
        let run = bounded(
            dir.path(),
            &["render", "-o", "x.png", &format!("{option}={value}")],
        );
        assert_eq!(run.code, Some(2), "{option}: {}", run.stderr);
        assert!(run.stderr.contains(message), "{option}: {}", run.stderr);
        assert!(!run.stderr.contains("invalid digit"), "{}", run.stderr);
    }
    let run = bounded(
        dir.path(),
        &["generate-mesh", "-o", "m.ply", "--triangles", "2e8"],
    );
    assert_eq!(run.code, Some(2), "{}", run.stderr);
    assert!(
        run.stderr
            .contains("expected a whole number from 1 to 200000000, got '2e8'"),
        "{}",
        run.stderr
    );
}
