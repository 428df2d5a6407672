//! `timbre render`, which renders a still picture (`render.rs`) or a movie: the frames of a
//! scene's `[animation]` (or `--frames N`), each
//! rendered as `timbre render --set KEY=VALUE ...` would render it with its tracks' values at
//! that frame, written to the output pattern's file for the frame; `--frame K` renders one
//! (a job of a job array), `--resume` skips those already written, and `--encode` makes a
//! video of them with the system's ffmpeg.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

use timbre::io::OutputFormat;
use timbre::production::Stopping;
use timbre::scene::Animation;
use timbre::scene::file::Override;

use super::args::RenderArgs;
use super::render::{load_settings, render};
use crate::{Failure, bad_input, internal};

/// `timbre render`: a movie's frames if the scene has an `[animation]` (or `--frames`), else
/// the one picture.
pub fn run_render(mut args: RenderArgs) -> Result<(), Failure> {
    let stopping = Stopping::new().map_err(internal)?;
    frame_options(&mut args);
    let loading = Instant::now();
    let (description, settings) = load_settings(&args)?;
    match description.animation.clone() {
        Some(animation) => run_movie(args, &animation, &stopping),
        None if args.encode.is_some() => Err(bad_input(
            "--encode makes a video of a movie's frames: give the scene an [animation] or \
             --frames N",
        )),
        None => render(args, description, settings, loading, &stopping),
    }
}

/// `--frames N` and `--frame K` are the `[animation]`'s `frames`, and `first_frame` and
/// `last_frame`: they are given to the scene file as `--set` overrides.
fn frame_options(args: &mut RenderArgs) {
    let set = |key: &str, n: u32| Override::new(key, toml::Value::Integer(n.into()));
    if let Some(n) = args.frames {
        args.set.push(set("animation.frames", n));
    }
    if let Some(k) = args.frame {
        args.set.push(set("animation.first_frame", k));
        args.set.push(set("animation.last_frame", k));
    }
}

/// Renders frames `first_frame` to `last_frame` of `animation`, then encodes them if asked.
fn run_movie(args: RenderArgs, animation: &Animation, stopping: &Stopping) -> Result<(), Failure> {
    for track in &animation.tracks {
        if let Some(o) = args.set.iter().find(|o| o.key.join(".") == track.key) {
            return Err(bad_input(format!(
                "--set {o}: '{}' is animated by the scene's [animation] (change its keyframes, \
                 or --set animation.track.N.keyframes)",
                track.key
            )));
        }
    }
    let pattern = FramePattern::new(&args.output)?;
    let video = args
        .encode
        .as_ref()
        .map(|video| check_encode(video, &args.output))
        .transpose()?;
    let (first, last) = (animation.first_frame, animation.last_frame);
    let count = last - first + 1;
    let frame_args = |k: u32| {
        let mut frame = args.clone();
        frame.set.extend(animation.overrides(k));
        frame
    };
    // The scene is read at the first and the last frame and at each keyframe between before
    // any frame is rendered: a value no frame may take is refused at once (between two
    // keyframes a value goes from one to the other).
    let mut checked = std::collections::BTreeSet::from([first, last]);
    for track in &animation.tracks {
        checked.extend(
            track
                .keyframes
                .iter()
                .map(|(frame, _)| frame.round())
                .filter(|&k| k >= first as f64 && k <= last as f64)
                .map(|k| k as u32),
        );
    }
    for k in checked {
        let frame = frame_args(k);
        crate::load(frame.scene.as_deref(), &frame.set)?;
    }
    for k in first..=last {
        let output = pattern.path(k);
        if !args.quiet {
            err!(
                "timbre: frame {k} ({} of {count}) -> {}",
                k - first + 1,
                output.display()
            );
        }
        if args.resume && output.exists() {
            if !args.quiet {
                err!("timbre: frame {k} is written already (--resume): skipped");
            }
            continue;
        }
        let mut frame = frame_args(k);
        frame.output = output;
        frame.encode = None;
        let loading = Instant::now();
        let (description, settings) = load_settings(&frame)?;
        render(frame, description, settings, loading, stopping)?;
    }
    if let Some(video) = video {
        encode(&pattern, first, count, animation.fps, &video, args.quiet)?;
    }
    Ok(())
}

/// The frames' file names: the output's name with `%d` or `%0Nd` (N from 1 to 9) in it, or
/// with `-%04d` before its extension (Dr TIM numbers its frames 0000, 0001, ...).
struct FramePattern {
    /// The output path with the frame number's place as `%0Nd`, as ffmpeg reads it.
    text: String,
    /// The digits the number is padded to (0: not padded).
    width: usize,
}

impl FramePattern {
    fn new(output: &Path) -> Result<FramePattern, Failure> {
        let name = output
            .file_name()
            .and_then(|n| n.to_str())
            .ok_or_else(|| bad_input(format!("{}: not a file name", output.display())))?;
        let bad = || {
            bad_input(format!(
                "{}: a movie's output names each frame with one %d or %0Nd (N from 1 to 9) and \
                 no other %",
                output.display()
            ))
        };
        let named = |name: String| output.with_file_name(name).to_string_lossy().into_owned();
        let (text, width) = match name.matches('%').count() {
            0 => {
                let stem = Path::new(name)
                    .file_stem()
                    .unwrap_or_default()
                    .to_string_lossy();
                let extension = Path::new(name)
                    .extension()
                    .map_or(String::new(), |e| format!(".{}", e.to_string_lossy()));
                (named(format!("{stem}-%04d{extension}")), 4)
            }
            1 => {
                let (_, after) = name.split_once('%').expect("one %");
                let digits: String = after.chars().take_while(char::is_ascii_digit).collect();
                let rest = &after[digits.len()..];
                let width = match digits.as_str() {
                    "" => 0,
                    d if d.len() == 2 && d.starts_with('0') && d != "00" => {
                        d[1..].parse().expect("a digit")
                    }
                    _ => return Err(bad()),
                };
                if !rest.starts_with('d') {
                    return Err(bad());
                }
                (named(name.to_string()), width)
            }
            _ => return Err(bad()),
        };
        Ok(FramePattern { text, width })
    }

    /// The file of frame `k`.
    fn path(&self, k: u32) -> PathBuf {
        let (before, after) = self.text.rsplit_once('%').expect("a pattern");
        let after = &after[after.find('d').expect("a pattern") + 1..];
        PathBuf::from(format!("{before}{k:0width$}{after}", width = self.width))
    }
}

/// The video `video` may be made of PNG frames by the ffmpeg installed: checked before any
/// frame is rendered.
fn check_encode(video: &Path, output: &Path) -> Result<PathBuf, Failure> {
    if OutputFormat::from_path(output).map_err(bad_input)? != OutputFormat::Png {
        return Err(bad_input(
            "--encode makes a video of PNG frames: give -o a .png pattern",
        ));
    }
    if video.extension().is_none() {
        return Err(bad_input(format!(
            "--encode {}: the video's extension (.mp4, .webm, .gif, ...) chooses its format",
            video.display()
        )));
    }
    let found = Command::new("ffmpeg")
        .arg("-version")
        .output()
        .is_ok_and(|o| o.status.success());
    if !found {
        return Err(bad_input(
            "--encode needs ffmpeg, which is not installed (Debian: apt-get install ffmpeg)",
        ));
    }
    Ok(video.to_path_buf())
}

/// Encodes `count` frames from `first` at `fps` into `video` with ffmpeg, through a temporary
/// file beside it that is renamed when it is complete.
fn encode(
    pattern: &FramePattern,
    first: u32,
    count: u32,
    fps: f64,
    video: &Path,
    quiet: bool,
) -> Result<(), Failure> {
    let name = video.file_name().unwrap_or_default().to_string_lossy();
    let extension = video.extension().unwrap_or_default().to_string_lossy();
    let partial = video.with_file_name(format!(".{name}.partial.{extension}"));
    let mut command = Command::new("ffmpeg");
    command
        .args(["-y", "-loglevel", "error", "-framerate"])
        .arg(fps.to_string())
        .args(["-start_number", &first.to_string(), "-i", &pattern.text])
        .args(["-frames:v", &count.to_string()]);
    // H.264 and the like store colour at half resolution: even sizes, 4:2:0.
    if matches!(extension.as_ref(), "mp4" | "mov" | "mkv" | "m4v") {
        command.args([
            "-vf",
            "pad=ceil(iw/2)*2:ceil(ih/2)*2",
            "-pix_fmt",
            "yuv420p",
        ]);
    }
    let out = command.arg(&partial).output().map_err(internal)?;
    if !out.status.success() {
        let _ = std::fs::remove_file(&partial);
        return Err(internal(format!(
            "ffmpeg could not encode {}: {}",
            video.display(),
            String::from_utf8_lossy(&out.stderr).trim()
        )));
    }
    std::fs::rename(&partial, video).map_err(|e| internal(format!("{}: {e}", video.display())))?;
    if !quiet {
        out!(
            "{count} frames at {fps} frames a second -> {}",
            video.display()
        );
    }
    Ok(())
}
