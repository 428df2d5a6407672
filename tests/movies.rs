//! Issue 41 item 6, movies: `timbre render` of a scene's `[animation]` (and `--frames`,
//! `--frame`, `--resume`, output patterns), checked against facts worked out here:
//!
//! * frame k is, pixel for pixel, the picture `timbre render --set KEY=VALUE` makes of the
//!   scene without its animation, with each track's value at k interpolated here (linear:
//!   v_a + u (v_b − v_a); smooth: u → 3u² − 2u³; strings stepped), and a whole-number
//!   setting takes the whole value between whole keyframes;
//! * the frames are named by the output's pattern (%0Nd, %d, or -0000 before the extension);
//! * `--frame K` renders frame K alone, `--resume` leaves frames already written as they are,
//!   and `timbre check` names the frames;
//! * `--encode` makes a video of the frames with ffmpeg (ffprobe counts its frames, its size
//!   and rate), from the first frame asked for;
//! * bad animations and options are refused where they are written, with exit code 2.

mod common;

use std::path::Path;

use tempfile::TempDir;

use common::cli::{files_in, path_str, timbre, write};

/// A small scene: TIM's lattice, 48 × 36 pixels.
const SCENE: &str = "studio = \"lattice\"\n[render]\nwidth = 48\nheight = 36\n";

/// Four frames moving the camera (linearly), widening its view (smoothly) and stepping its
/// studio from the lattice to the empty one at frame 2.
const ANIMATION: &str = r#"
[animation]
frames = 4
[[animation.track]]
key = "camera.position"
keyframes = [{ frame = 0, value = [0, 0, 0] }, { frame = 3, value = [0.3, 0.15, 0] }]
[[animation.track]]
key = "camera.horizontal_view_angle_deg"
interpolation = "smooth"
keyframes = [{ frame = 0, value = 20.0 }, { frame = 3, value = 47.5 }]
[[animation.track]]
key = "studio"
keyframes = [{ frame = 0, value = "lattice" }, { frame = 2, value = "empty" }]
"#;

fn pixels(path: &Path) -> Vec<u8> {
    image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgb8()
        .into_raw()
}

#[test]
fn frame_k_is_the_scene_with_its_tracks_values_at_k() {
    let dir = TempDir::new().unwrap();
    let movie = write(&dir, "movie.toml", format!("{SCENE}{ANIMATION}"));
    let still = write(&dir, "still.toml", SCENE);
    timbre(
        dir.path(),
        &["render", path_str(&movie), "-o", "frame.png", "-q"],
    )
    .assert_success();
    assert_eq!(
        files_in(dir.path())
            .into_iter()
            .filter(|f| f.ends_with(".png"))
            .collect::<Vec<_>>(),
        [
            "frame-0000.png",
            "frame-0001.png",
            "frame-0002.png",
            "frame-0003.png"
        ]
    );
    // The values at each frame, worked out here: the position a third of the way per frame;
    // the angle 20 + 27.5 (3u² − 2u³), u = k/3; the studio "empty" from frame 2.
    let smooth = |u: f64| 3.0 * u * u - 2.0 * u * u * u;
    for k in 0..4 {
        let u = k as f64 / 3.0;
        let set = [
            format!("camera.position=[{:?}, {:?}, 0.0]", 0.3 * u, 0.15 * u),
            format!(
                "camera.horizontal_view_angle_deg={:?}",
                20.0 + 27.5 * smooth(u)
            ),
            format!("studio={}", if k < 2 { "lattice" } else { "empty" }),
        ];
        let mut args = vec!["render", path_str(&still), "-o", "still.png", "-q"];
        for s in &set {
            args.extend(["--set", s]);
        }
        timbre(dir.path(), &args).assert_success();
        assert!(
            pixels(&dir.path().join(format!("frame-{k:04}.png")))
                == pixels(&dir.path().join("still.png")),
            "frame {k} differs from the scene with {set:?}"
        );
    }
    // The frames do differ (the animation did something).
    assert_ne!(
        pixels(&dir.path().join("frame-0000.png")),
        pixels(&dir.path().join("frame-0003.png"))
    );
}

#[test]
fn frames_are_named_by_the_pattern_and_rendered_one_by_one() {
    let dir = TempDir::new().unwrap();
    let movie = write(&dir, "movie.toml", format!("{SCENE}{ANIMATION}"));
    let m = path_str(&movie);
    std::fs::create_dir(dir.path().join("frames")).unwrap();
    // --frames sets the count (the tracks keep their keyframes); %02d numbers the frames.
    timbre(
        dir.path(),
        &["render", m, "-o", "frames/f%02d.png", "--frames", "6", "-q"],
    )
    .assert_success();
    let expected: Vec<String> = (0..6).map(|k| format!("f{k:02}.png")).collect();
    assert_eq!(files_in(dir.path().join("frames")), expected);
    // `timbre check` names the frames a run renders (what cluster/slurm/submit-movie.sh reads):
    // the file's 4 frames at the default 25 fps, or those --set asks for.
    let run = timbre(dir.path(), &["check", m]);
    run.assert_success();
    assert!(
        run.stdout
            .contains("movie:        frames 0 to 3 of 4, 3 track(s), 25 fps"),
        "{}",
        run.stdout
    );
    let run = timbre(
        dir.path(),
        &[
            "check",
            m,
            "--set",
            "animation.frames=9",
            "--set",
            "animation.first_frame=5",
        ],
    );
    assert!(run.stdout.contains("frames 5 to 8 of 9"), "{}", run.stdout);
    // --frame K renders only frame K, %d unpadded.
    timbre(
        dir.path(),
        &["render", m, "-o", "one-%d.png", "--frame", "2", "-q"],
    )
    .assert_success();
    assert!(dir.path().join("one-2.png").exists());
    assert!(!dir.path().join("one-0.png").exists() && !dir.path().join("one-3.png").exists());
    assert_eq!(
        pixels(&dir.path().join("one-2.png")),
        pixels(&dir.path().join("frames/f02.png"))
    );
    // --resume leaves the frames already written alone and renders the others.
    std::fs::write(dir.path().join("frames/f03.png"), b"not a picture").unwrap();
    std::fs::remove_file(dir.path().join("frames/f04.png")).unwrap();
    let run = timbre(
        dir.path(),
        &[
            "render",
            m,
            "-o",
            "frames/f%02d.png",
            "--frames",
            "6",
            "--resume",
        ],
    );
    run.assert_success();
    assert!(
        run.stderr.contains("frame 3 is written already"),
        "{}",
        run.stderr
    );
    assert_eq!(
        std::fs::read(dir.path().join("frames/f03.png")).unwrap(),
        b"not a picture"
    );
    assert!(dir.path().join("frames/f04.png").exists());
    // A stereo movie's frames keep no checkpoint: with --resume and --checkpoint-interval (as
    // each task of cluster/slurm/render-frames.sbatch has them) they are rendered all the same.
    let run = timbre(
        dir.path(),
        &[
            "render",
            m,
            "-o",
            "anaglyph-%d.png",
            "--frame",
            "1",
            "--resume",
            "--checkpoint-interval",
            "300",
            "--set",
            "camera.stereo=\"anaglyph\"",
            "-q",
        ],
    );
    run.assert_success();
    assert!(dir.path().join("anaglyph-1.png").exists());
    // Without an [animation], --frames N renders N frames of the scene as it is.
    let still = write(&dir, "still.toml", SCENE);
    let s = path_str(&still);
    timbre(
        dir.path(),
        &["render", s, "-o", "s.png", "--frames", "2", "-q"],
    )
    .assert_success();
    timbre(dir.path(), &["render", s, "-o", "plain.png", "-q"]).assert_success();
    for k in 0..2 {
        assert_eq!(
            pixels(&dir.path().join(format!("s-000{k}.png"))),
            pixels(&dir.path().join("plain.png"))
        );
    }
}

#[test]
fn whole_number_settings_take_whole_values_between_whole_keyframes() {
    // render.spp from 1 to 3 over frames 0 to 2: 2 at frame 1, a whole number, as the setting
    // needs.
    let dir = TempDir::new().unwrap();
    let animation = "[animation]\nframes = 3\n[[animation.track]]\nkey = \"render.spp\"\n\
                     keyframes = [{ frame = 0, value = 1 }, { frame = 2, value = 3 }]\n";
    let movie = write(&dir, "movie.toml", format!("{SCENE}{animation}"));
    let still = write(&dir, "still.toml", SCENE);
    timbre(
        dir.path(),
        &["render", path_str(&movie), "-o", "f.png", "-q"],
    )
    .assert_success();
    timbre(
        dir.path(),
        &[
            "render",
            path_str(&still),
            "-o",
            "two.png",
            "--set",
            "render.spp=2",
            "-q",
        ],
    )
    .assert_success();
    assert_eq!(
        pixels(&dir.path().join("f-0001.png")),
        pixels(&dir.path().join("two.png"))
    );
    assert_ne!(
        pixels(&dir.path().join("f-0000.png")),
        pixels(&dir.path().join("two.png"))
    );
}

#[test]
fn bad_animations_are_refused_where_they_are_written() {
    let dir = TempDir::new().unwrap();
    let track =
        |keys: &str| format!("{SCENE}[animation]\nframes = 4\n[[animation.track]]\n{keys}\n");
    let cases = [
        (
            format!("{SCENE}[animation]\nframes = 0\n"),
            vec![":5:1:", "frames must be from 1"],
        ),
        (
            format!("{SCENE}[animation]\nframes = 4\nfirst_frame = 3\nlast_frame = 1\n"),
            vec![":5:1:", "first_frame = 3 to last_frame = 1"],
        ),
        (
            format!("{SCENE}[animation]\nframes = 4\nlast_frame = 4\n"),
            vec![":5:1:", "within the movie's 4 frames"],
        ),
        (
            track(
                "key = \"camera.position\"\nkeyframes = [{ frame = 2, value = [0, 0, 0] }, { frame = 1, value = [1, 0, 0] }]",
            ),
            vec!["track 'camera.position'", "in order of their frames"],
        ),
        (
            track(
                "key = \"camera.position\"\nkeyframes = [{ frame = 0, value = [0, 0, 0] }, { frame = 1, value = [1, 0] }]",
            ),
            vec!["track 'camera.position'", "of one kind"],
        ),
        (
            track(
                "key = \"studio\"\ninterpolation = \"smooth\"\nkeyframes = [{ frame = 0, value = \"empty\" }]",
            ),
            vec!["values of type string cannot be interpolated"],
        ),
        (
            track("key = \"animation.frames\"\nkeyframes = [{ frame = 0, value = 2 }]"),
            vec!["cannot animate itself"],
        ),
        (
            track("key = \"camera.position\"\nkeyframes = []"),
            vec!["no keyframes"],
        ),
        (
            track(
                "key = \"camera.position\"\ninterpolation = \"cubic\"\nkeyframes = [{ frame = 0, value = 1 }]",
            ),
            vec!["unknown variant `cubic`"],
        ),
        (
            // A key the scene file cannot take: refused before any frame is written.
            track("key = \"camera.nonsense\"\nkeyframes = [{ frame = 0, value = 1 }]"),
            vec!["nonsense"],
        ),
        (
            // A value only the last keyframe takes, beyond the view angle's range: refused
            // before frames 0 to 2 are rendered.
            track(
                "key = \"camera.horizontal_view_angle_deg\"\n\
                 keyframes = [{ frame = 0, value = 20 }, { frame = 3, value = 200 }]",
            ),
            vec!["200"],
        ),
        (
            // A whole-number setting given 1.5 at frame 1 (from 1 to 2 over two frames):
            // refused before frame 0 is rendered.
            track(
                "key = \"render.spp\"\n\
                 keyframes = [{ frame = 0, value = 1 }, { frame = 2, value = 2 }]",
            ),
            vec!["1.5"],
        ),
    ];
    for (text, needles) in cases {
        let path = write(&dir, "bad.toml", &text);
        timbre(dir.path(), &["render", path_str(&path), "-o", "bad.png"])
            .assert_bad_input(&needles);
        assert!(
            !files_in(dir.path()).iter().any(|f| f.ends_with(".png")),
            "{text}: a frame was written"
        );
    }
    // Options that cannot be: a --set of an animated key, a pattern with another %, --encode
    // without a movie or of OpenEXR frames.
    let movie = write(&dir, "movie.toml", format!("{SCENE}{ANIMATION}"));
    let still = write(&dir, "still.toml", SCENE);
    let (m, s) = (path_str(&movie), path_str(&still));
    for (args, needles) in [
        (
            vec!["render", m, "--set", "camera.position=[1,0,0]"],
            vec!["'camera.position' is animated"],
        ),
        (vec!["render", m, "-o", "f%s.png"], vec!["one %d or %0Nd"]),
        (
            vec!["render", m, "-o", "f%d-%d.png"],
            vec!["one %d or %0Nd"],
        ),
        (
            vec!["render", s, "--encode", "m.mp4"],
            vec!["--encode makes a video of a movie"],
        ),
        (
            vec!["render", m, "-o", "f.exr", "--encode", "m.mp4"],
            vec!["PNG frames"],
        ),
        (vec!["render", m, "--encode", "m.xyz"], vec!["one of .mp4"]),
        (
            // A table holding an animated value.
            vec![
                "render",
                m,
                "--set",
                "camera={ horizontal_view_angle_deg = 30 }",
            ],
            vec!["'camera.position' is animated"],
        ),
        (vec!["render", s, "-o", "f%04d.png"], vec!["no [animation]"]),
        (vec!["render", "--frames", "2"], vec!["name one"]),
        (
            vec!["render", m, "--frame", "4"],
            vec!["within the movie's 4 frames"],
        ),
    ] {
        timbre(dir.path(), &args).assert_bad_input(&needles);
    }
}

/// ffprobe's width, height, frame rate and frame count of the video at `path`.
fn probe(path: &Path) -> String {
    let out = std::process::Command::new("ffprobe")
        .args([
            "-v",
            "error",
            "-count_frames",
            "-select_streams",
            "v:0",
            "-show_entries",
        ])
        .args([
            "stream=width,height,r_frame_rate,nb_read_frames",
            "-of",
            "csv=p=0",
        ])
        .arg(path)
        .output()
        .expect("ffprobe, installed with ffmpeg by scripts/test.sh (apt-get install ffmpeg)");
    String::from_utf8(out.stdout).unwrap().trim().to_string()
}

#[test]
fn the_frames_are_encoded_into_a_video_with_ffmpeg() {
    let dir = TempDir::new().unwrap();
    // 47 × 35 pixels (odd: H.264 needs even sizes, so the video is padded to 48 × 36), 12
    // frames a second.
    let scene = SCENE.replace("48", "47").replace("36", "35");
    let animation = ANIMATION.replace("frames = 4\n", "frames = 4\nfps = 12\n");
    let movie = write(&dir, "movie.toml", format!("{scene}{animation}"));
    let m = path_str(&movie);
    let run = timbre(
        dir.path(),
        &["render", m, "-o", "f.png", "--encode", "movie.mp4"],
    );
    run.assert_success();
    assert!(
        run.stdout
            .contains("4 frames at 12 frames a second -> movie.mp4"),
        "{}",
        run.stdout
    );
    assert_eq!(probe(&dir.path().join("movie.mp4")), "48,36,12/1,4");
    // With --resume frames 1 to 3 are there already: only the video is made, here an animated
    // GIF at their own size, from frame 1 (frame 0, removed, is not needed).
    std::fs::remove_file(dir.path().join("f-0000.png")).unwrap();
    let run = timbre(
        dir.path(),
        &[
            "render",
            m,
            "-o",
            "f.png",
            "--resume",
            "--set",
            "animation.first_frame=1",
            "--encode",
            "movie.gif",
        ],
    );
    run.assert_success();
    assert_eq!(
        run.stderr.matches("is written already").count(),
        3,
        "{}",
        run.stderr
    );
    // (A GIF's frame delays are whole hundredths of a second, so its rate is not 12.)
    let gif = probe(&dir.path().join("movie.gif"));
    let fields: Vec<&str> = gif.split(',').collect();
    assert_eq!(
        [fields[0], fields[1], fields[3]],
        ["47", "35", "3"],
        "{gif}"
    );
    // No partial video is left behind.
    assert!(
        files_in(dir.path()).iter().all(|f| !f.contains("partial")),
        "{:?}",
        files_in(dir.path())
    );
}
