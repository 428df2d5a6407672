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
use timbre::scene::file::Override;
use timbre::scene::{Animation, Stereo};

use super::args::RenderArgs;
use super::render::{load_settings, render};
use crate::{Failure, bad_input, internal};

/// `timbre render`: a movie's frames if the scene has an `[animation]` (or `--frames`), else
/// the one picture.
pub fn run_render(mut args: RenderArgs) -> Result<(), Failure> {
    let stopping = Stopping::new().map_err(internal)?;
    if args.scene.is_none() && (args.frames.is_some() || args.frame.is_some()) {
        return Err(bad_input(
            "--frames and --frame render a movie of a scene file: name one",
        ));
    }
    frame_options(&mut args);
    let loading = Instant::now();
    let (description, settings) = load_settings(&args)?;
    match description.animation.clone() {
        Some(animation) => run_movie(args, &animation, &stopping),
        None if args.encode.is_some() => Err(bad_input(
            "--encode makes a video of a movie's frames: give the scene an [animation] or \
             --frames N",
        )),
        None if args.output.to_string_lossy().contains('%') => Err(bad_input(format!(
            "{}: a % pattern names a movie's frames, and this scene has no [animation] (give \
             --frames N, or a plain name)",
            args.output.display()
        ))),
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
    if let Some((o, track)) = args
        .set
        .iter()
        .find_map(|o| animation.clash(o).map(|t| (o, t)))
    {
        return Err(bad_input(format!(
            "--set {o}: '{}' is animated by the scene's [animation] (change its keyframes, \
             or --set animation.track.N.keyframes)",
            track.key()
        )));
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
    // Before any frame is rendered the scene is read at the first and the last frame, at the
    // frames on either side of each keyframe, and where a track of whole numbers first takes
    // a value with a fraction: a value outside a range that the keyframes' values are inside,
    // and a number with a fraction for a whole-number setting, are refused at once.
    let mut checked = std::collections::BTreeSet::from([first, last]);
    for track in &animation.tracks {
        for frame in track.keyframe_frames() {
            for k in [frame.floor(), frame.ceil()] {
                if k >= first as f64 && k <= last as f64 {
                    checked.insert(k as u32);
                }
            }
        }
        checked.extend((first..=last).find(|&k| track.fraction_at(k)));
    }
    for k in checked {
        let mut frame = frame_args(k);
        frame.quiet = true;
        load_settings(&frame)?;
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
        // A stereo picture keeps no checkpoint: --resume only skips the frames written, and
        // --checkpoint-interval (which the Slurm recipe gives every frame) saves nothing.
        if description.stereo != Stereo::Mono {
            frame.resume = false;
            frame.checkpoint_interval = None;
        }
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
    directory: PathBuf,
    /// The file name with the frame number's place as `%d` or `%0Nd`.
    name: String,
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
        let (name, width) = match name.matches('%').count() {
            0 => {
                let stem = Path::new(name)
                    .file_stem()
                    .unwrap_or_default()
                    .to_string_lossy();
                let extension = Path::new(name)
                    .extension()
                    .map_or(String::new(), |e| format!(".{}", e.to_string_lossy()));
                (format!("{stem}-%04d{extension}"), 4)
            }
            1 => {
                let (_, after) = name.split_once('%').expect("one %");
                let digits: String = after.chars().take_while(char::is_ascii_digit).collect();
                let width = match digits.as_str() {
                    "" => 0,
                    d if d.len() == 2 && d.starts_with('0') && d != "00" => {
                        d[1..].parse().expect("a digit")
                    }
                    _ => return Err(bad()),
                };
                if !after[digits.len()..].starts_with('d') {
                    return Err(bad());
                }
                (name.to_string(), width)
            }
            _ => return Err(bad()),
        };
        Ok(FramePattern {
            directory: output.parent().unwrap_or(Path::new("")).to_path_buf(),
            name,
            width,
        })
    }

    /// The file of frame `k`.
    fn path(&self, k: u32) -> PathBuf {
        let (before, after) = self.name.split_once('%').expect("a pattern");
        let after = &after[after.find('d').expect("a pattern") + 1..];
        self.directory
            .join(format!("{before}{k:0width$}{after}", width = self.width))
    }

    /// The pattern as ffmpeg reads it: a `%` of the directory doubled.
    fn ffmpeg(&self) -> String {
        let directory = self.directory.to_string_lossy().replace('%', "%%");
        match directory.is_empty() {
            true => self.name.clone(),
            false => format!("{directory}/{}", self.name),
        }
    }
}

/// The videos `--encode` makes, by extension.
const VIDEO_FORMATS: [&str; 8] = ["mp4", "m4v", "mov", "mkv", "webm", "avi", "gif", "apng"];

/// The video `video` may be made of PNG frames by the ffmpeg installed: checked before any
/// frame is rendered.
fn check_encode(video: &Path, output: &Path) -> Result<PathBuf, Failure> {
    if OutputFormat::from_path(output).map_err(bad_input)? != OutputFormat::Png {
        return Err(bad_input(
            "--encode makes a video of PNG frames: give -o a .png pattern",
        ));
    }
    let known = video
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| VIDEO_FORMATS.contains(&e.to_ascii_lowercase().as_str()));
    if !known {
        return Err(bad_input(format!(
            "--encode {}: the video's extension chooses its format, one of .{}",
            video.display(),
            VIDEO_FORMATS.join(", .")
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
        .args(["-start_number", &first.to_string(), "-i", &pattern.ffmpeg()])
        .args(["-frames:v", &count.to_string()]);
    // H.264 and the like store colour at half resolution: even sizes, 4:2:0.
    if matches!(
        extension.to_ascii_lowercase().as_str(),
        "mp4" | "mov" | "mkv" | "m4v"
    ) {
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
