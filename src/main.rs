//! The `timbre` command: parse, load, render, write.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use clap::{Parser, Subcommand, ValueEnum};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressFinish, ProgressStyle};
use serde::Serialize;

use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Duration;
use timbre::display::{self, Server, Viewer};
use timbre::embree::Device;

use timbre::io::{AovSelection, OutputFormat, Provenance, write_image};
use timbre::math::Colour;
use timbre::memory;
use timbre::mesh::{self, PlyEncoding, generate};
use timbre::prepare::{self, Needs, PrepareError, Ready};
use timbre::production::{self, Checkpointing, Done, Job, JobError, Signals};
use timbre::render::PixelBounds;
use timbre::render::RenderError;
use timbre::scene::file::{self, Override};
use timbre::scene::settings::{Kind, SETTINGS, SettingValues, Value};
use timbre::scene::studio::Studio;
use timbre::scene::{RenderSettings, SceneDescription, Stereo};
use timbre::stereo::{self, render_stereo};
use timbre::trajectories::{self, Trajectory};

/// `println!` of [`printable`] text that ignores a closed standard output
/// (`timbre check s.toml | head -1`) instead of panicking.
macro_rules! out {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stdout(), "{}", printable(&format!($($arg)*)));
    }};
}

/// `eprintln!` of [`printable`] text.
macro_rules! err {
    ($($arg:tt)*) => {{
        eprintln!("{}", printable(&format!($($arg)*)));
    }};
}

/// Longest run of characters without a space that is printed whole.
const LONGEST_WORD: usize = 200;

/// `text` made safe to print on a terminal as one line, whatever a file put in it: control
/// characters (line breaks too: a name cannot start a line that looks like timbre's own) and
/// invisible or reordering marks are escaped
/// ([`timbre::text::escape`]), so a name or token cannot drive the terminal; a run of more than
/// [`LONGEST_WORD`] characters without a space (a 10 MB key, a 309-digit number) is cut in the
/// middle, saying how much was left out.
fn printable(text: &str) -> String {
    let mut out = String::with_capacity(text.len().min(1 << 16));
    let mut word = String::new();
    let flush = |word: &mut String, out: &mut String| {
        let n = word.chars().count();
        if n > LONGEST_WORD {
            let head: String = word.chars().take(LONGEST_WORD - 40).collect();
            let tail: String = word.chars().skip(n - 20).collect();
            let left_out = n - LONGEST_WORD + 20;
            out.push_str(&format!("{head}…[{left_out} characters left out]…{tail}"));
        } else {
            out.push_str(word);
        }
        word.clear();
    };
    for c in text.chars() {
        match c {
            ' ' => {
                flush(&mut word, &mut out);
                out.push(c);
            }
            c => match timbre::text::escape(c) {
                Some(e) => word.push_str(&e),
                None => word.push(c),
            },
        }
    }
    flush(&mut word, &mut out);
    out
}

#[derive(Parser)]
#[command(
    name = "timbre",
    version,
    about = "A fast, scientifically exact ray tracer for ray-optics research"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Render a scene file (or, with none, TIM's standard studio) to PNG or OpenEXR.
    Render(RenderArgs),
    /// Check a scene file as a render would (load its meshes, trace its ray trajectories,
    /// build the BVH), without rendering it; print a summary.
    Check {
        /// The TOML scene file.
        scene: PathBuf,
        /// Override a scene-file value, e.g. --set camera.position=[0,0,-2] (repeatable).
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<Override>,
    },
    /// Trace a scene file's ray trajectories and print the points they pass through.
    Trace {
        /// The TOML scene file, with [[ray_trajectory]] tables.
        scene: PathBuf,
        /// Print JSON (for analysis outside timbre) instead of a table.
        #[arg(long)]
        json: bool,
        /// Override a scene-file value, e.g. --set camera.position=[0,0,-2] (repeatable).
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<Override>,
    },
    /// Write a test mesh (a bumpy sphere of at least N triangles) as PLY or OBJ.
    GenerateMesh {
        /// Output file; the extension (.ply or .obj) chooses the format.
        #[arg(short, long)]
        output: PathBuf,
        /// Least number of triangles (the mesh has the smallest grid with at least this many),
        /// at most 200 million.
        #[arg(long, default_value_t = 10_000, value_parser = clap::value_parser!(u64).range(1..=200_000_000))]
        triangles: u64,
        /// Height of the bumps relative to the radius (0: a plain faceted sphere).
        #[arg(long, default_value_t = 0.1)]
        displacement: f64,
        /// PLY encoding.
        #[arg(long, value_enum, default_value_t = Encoding::BinaryLittleEndian)]
        encoding: Encoding,
    },
    /// Merge parts of one render (written with --tile, --pixel-bounds, --samples) into the
    /// whole image, exactly as a single render would have made it.
    Merge {
        /// The merged image; the extension (.png or .exr) chooses the format.
        output: PathBuf,
        /// The parts (OpenEXR files), in any order.
        #[arg(required = true)]
        parts: Vec<PathBuf>,
        /// Print nothing but errors.
        #[arg(short, long)]
        quiet: bool,
    },
    /// Print the versions of timbre and Embree, the CPU's SIMD support and the thread count.
    Info,
    /// Serve a live, progressive preview of a scene file to a web browser: navigation,
    /// parameters, the scene text, inspection, saving (docs/PREVIEW.md).
    Serve(ServeArgs),
}

/// The render settings as options, one for each of `timbre::scene::settings::SETTINGS`
/// (`--width`, `--max-trace-level`, ...), in place of the scene file's values; shared by
/// `render` and `serve`.
#[derive(Debug, Clone, Default)]
struct SettingArgs(SettingValues);

impl clap::Args for SettingArgs {
    fn augment_args(command: clap::Command) -> clap::Command {
        SETTINGS.iter().fold(command, |command, setting| {
            let arg = clap::Arg::new(setting.key)
                .long(setting.key.replace('_', "-"))
                .value_name(setting.key.to_uppercase())
                .help(format!("{} (overrides the scene file)", setting.help));
            command.arg(match setting.kind {
                Kind::Whole { least, most } => {
                    arg.value_parser(clap::value_parser!(u64).range(least..=most))
                }
                Kind::Switch => arg.value_parser(clap::value_parser!(bool)),
            })
        })
    }

    fn augment_args_for_update(command: clap::Command) -> clap::Command {
        Self::augment_args(command)
    }
}

impl clap::FromArgMatches for SettingArgs {
    fn from_arg_matches(matches: &clap::ArgMatches) -> Result<Self, clap::Error> {
        let mut args = SettingArgs::default();
        args.update_from_arg_matches(matches)?;
        Ok(args)
    }

    fn update_from_arg_matches(&mut self, matches: &clap::ArgMatches) -> Result<(), clap::Error> {
        for setting in &SETTINGS {
            let value = match setting.kind {
                Kind::Whole { .. } => matches
                    .get_one::<u64>(setting.key)
                    .map(|n| Value::Whole(*n)),
                Kind::Switch => matches
                    .get_one::<bool>(setting.key)
                    .map(|b| Value::Switch(*b)),
            };
            if let Some(value) = value {
                // Parsed in range, so the setting takes it.
                self.0
                    .push(setting, value)
                    .map_err(|e| clap::Error::raw(clap::error::ErrorKind::ValueValidation, e))?;
            }
        }
        Ok(())
    }
}

#[derive(Parser)]
struct ServeArgs {
    /// The TOML scene file (watched: saving it in an editor updates the page).
    scene: PathBuf,
    /// Port to listen on (0: any free port; the address is printed).
    #[arg(long, default_value_t = 7700)]
    port: u16,
    /// Address to listen on. Any but a loopback address (127.0.0.1, ::1) makes the page
    /// require a random access token, printed at start.
    #[arg(long, default_value = "127.0.0.1")]
    bind: std::net::IpAddr,
    /// The render settings (`--spp`: the samples per pixel the preview accumulates, by
    /// default the scene's, at least 64; the picture converges to `timbre render --spp N`'s).
    #[command(flatten)]
    settings: SettingArgs,
    /// Worker threads (default: all cores), at most 1024.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1024))]
    threads: Option<u32>,
    /// Override a scene-file value, e.g. --set camera.position=[0,0,-2] (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<Override>,
}

#[derive(Parser)]
struct RenderArgs {
    /// The TOML scene file; without it, TIM's standard studio with the cylinder lattice.
    scene: Option<PathBuf>,
    /// Output image; the extension (.png or .exr) chooses the format.
    #[arg(short, long, default_value = "out.png")]
    output: PathBuf,
    #[command(flatten)]
    settings: SettingArgs,
    /// Worker threads (default: all cores), at most 1024.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1024))]
    threads: Option<u32>,
    /// Extra EXR channels: depth (depth.Z), normal (normal.X/Y/Z), object (object.id).
    #[arg(long, value_delimiter = ',')]
    aov: Vec<Aov>,
    /// Override a scene-file value, e.g. --set camera.position=[0,0,-2] (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<Override>,
    /// Print nothing but errors (and progress lines, if --progress json asks for them).
    #[arg(short, long)]
    quiet: bool,
    /// How to show progress: a bar with elapsed and remaining time on a terminal, or one JSON
    /// line per update (at most one a second) on standard error, for schedulers and logs.
    #[arg(long, value_enum, default_value_t = ProgressMode::Bar)]
    progress: ProgressMode,
    /// Render horizontal strip K of N (0-based, K < N) as a part for `timbre merge`.
    #[arg(long, value_name = "K/N", conflicts_with = "pixel_bounds")]
    tile: Option<TileArg>,
    /// Render only the pixels x0..x1, y0..y1 (half-open) as a part for `timbre merge`.
    #[arg(long, value_name = "x0,x1,y0,y1")]
    pixel_bounds: Option<BoundsArg>,
    /// Render samples A to B-1 of each pixel's sample sequence (of --spp) as a part for
    /// `timbre merge`.
    #[arg(long, value_name = "A..B")]
    samples: Option<SamplesArg>,
    /// Save a checkpoint (OUTPUT.checkpoint/) every SECONDS, and on SIGINT, SIGTERM (then stop)
    /// and SIGUSR1 (then go on).
    #[arg(long, value_name = "SECONDS")]
    checkpoint_interval: Option<f64>,
    /// Continue from the checkpoint of the same output, if there is one (checkpoints are saved
    /// as with --checkpoint-interval).
    #[arg(long)]
    resume: bool,
    /// Show the image in the tev viewer listening at HOST:PORT (tev's own is 127.0.0.1:14158)
    /// while it renders (a stereo output once it is combined, after the render), reconnecting
    /// if tev restarts; a tev that cannot be reached is a warning.
    #[arg(long, value_name = "HOST:PORT")]
    display_server: Option<Server>,
}

/// `--tile K/N`.
#[derive(Clone, Copy)]
struct TileArg {
    k: u32,
    n: u32,
}

impl std::str::FromStr for TileArg {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        let (k, n) = s
            .split_once('/')
            .and_then(|(k, n)| Some((k.trim().parse().ok()?, n.trim().parse().ok()?)))
            .ok_or_else(|| format!("expected K/N, e.g. 0/4, got '{s}'"))?;
        if n == 0 || k >= n {
            return Err(format!(
                "tile {k} of {n} does not exist: tiles are numbered 0 to N-1"
            ));
        }
        Ok(TileArg { k, n })
    }
}

/// `--pixel-bounds x0,x1,y0,y1`.
#[derive(Clone, Copy)]
struct BoundsArg(PixelBounds);

impl std::str::FromStr for BoundsArg {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        let v: Vec<u32> = s
            .split(',')
            .map(|x| x.trim().parse())
            .collect::<Result<_, _>>()
            .map_err(|_| format!("expected four whole numbers x0,x1,y0,y1, got '{s}'"))?;
        let [x0, x1, y0, y1] = v[..] else {
            return Err(format!(
                "expected four whole numbers x0,x1,y0,y1, got '{s}'"
            ));
        };
        if x0 >= x1 || y0 >= y1 {
            return Err(format!(
                "the bounds {s} hold no pixels: x0 < x1 and y0 < y1 are needed"
            ));
        }
        Ok(BoundsArg(PixelBounds { x0, x1, y0, y1 }))
    }
}

/// `--samples A..B`.
#[derive(Clone)]
struct SamplesArg(std::ops::Range<u32>);

impl std::str::FromStr for SamplesArg {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        let (a, b) = s
            .split_once("..")
            .and_then(|(a, b)| Some((a.trim().parse().ok()?, b.trim().parse().ok()?)))
            .ok_or_else(|| format!("expected A..B, e.g. 0..64, got '{s}'"))?;
        if a >= b {
            return Err(format!("the samples {a}..{b} are none: A < B is needed"));
        }
        Ok(SamplesArg(a..b))
    }
}

#[derive(Clone, Copy, PartialEq, ValueEnum)]
enum ProgressMode {
    Bar,
    Json,
}

/// One `--progress json` line: pixels done of all (of every view), the fraction done, the
/// seconds since rendering started and the estimated seconds left (none before any pixel).
#[derive(Serialize)]
struct ProgressLine {
    done_pixels: u64,
    total_pixels: u64,
    fraction: f64,
    elapsed_s: f64,
    eta_s: Option<f64>,
}

/// Progress as JSON lines: at the start, at most one a second, and at the end.
struct JsonProgress {
    total: u64,
    start: Instant,
    /// Pixels done, and when the last line was printed.
    state: std::sync::Mutex<(u64, Instant)>,
}

impl JsonProgress {
    fn new(total: u64) -> JsonProgress {
        let start = Instant::now();
        let progress = JsonProgress {
            total,
            start,
            state: std::sync::Mutex::new((0, start)),
        };
        progress.print(0);
        progress
    }

    fn add(&self, pixels: u64) {
        let mut state = self.state.lock().unwrap_or_else(|e| e.into_inner());
        state.0 += pixels;
        if state.0 >= self.total || state.1.elapsed().as_secs_f64() >= 1.0 {
            self.print(state.0);
            state.1 = Instant::now();
        }
    }

    fn print(&self, done: u64) {
        use std::io::Write as _;
        let elapsed = self.start.elapsed().as_secs_f64();
        let line = ProgressLine {
            done_pixels: done,
            total_pixels: self.total,
            fraction: done as f64 / self.total.max(1) as f64,
            elapsed_s: elapsed,
            eta_s: (done > 0).then(|| elapsed * (self.total - done) as f64 / done as f64),
        };
        if let Ok(text) = serde_json::to_string(&line) {
            let _ = writeln!(std::io::stderr(), "{text}");
        }
    }
}

impl RenderArgs {
    /// The command line's values in place of the scene file's.
    fn apply_to(&self, s: &mut RenderSettings) {
        self.settings.0.apply(s);
        s.aovs = !self.aov.is_empty();
        s.threads = self.threads.map(|t| t as usize);
    }
}

#[derive(Clone, Copy, PartialEq, ValueEnum)]
enum Encoding {
    Ascii,
    BinaryLittleEndian,
    BinaryBigEndian,
}

#[derive(Clone, Copy, PartialEq, ValueEnum)]
enum Aov {
    Depth,
    Normal,
    Object,
}

/// A failure, with the exit code it maps to: 2 for bad input, 1 for everything else.
struct Failure {
    code: u8,
    message: String,
}

fn bad_input(message: impl ToString) -> Failure {
    Failure {
        code: 2,
        message: message.to_string(),
    }
}

fn internal(message: impl ToString) -> Failure {
    Failure {
        code: 1,
        message: message.to_string(),
    }
}

fn load(scene: Option<&Path>, set: &[Override]) -> Result<SceneDescription, Failure> {
    match scene {
        Some(path) => file::load_with(path, set).map_err(bad_input),
        None if set.is_empty() => Ok(Studio::Lattice.description()),
        None => Err(bad_input("--set needs a scene file")),
    }
}

/// `message` about the scene file, if there is one.
fn in_file(scene: Option<&Path>, message: String) -> String {
    match scene {
        Some(path) => format!("{}: {message}", path.display()),
        None => message,
    }
}

/// A spinner saying what is going on (loading meshes, building the BVH can take seconds), on a
/// terminal only.
fn spinner(quiet: bool, message: &'static str) -> ProgressBar {
    if quiet || !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    // Cleared also when dropped early, by an error.
    let spinner = ProgressBar::new_spinner().with_finish(ProgressFinish::AndClear);
    spinner.set_message(message);
    spinner.enable_steady_tick(std::time::Duration::from_millis(100));
    spinner
}

/// Bytes a stereo render needs at its peak, roughly: the views in memory
/// ([`stereo::memory_needed`]) and the output file's encoding (PNG: 3 bytes a pixel and a
/// compressed copy; EXR: 4 bytes a channel, twice).
fn memory_needed(settings: &RenderSettings, stereo: &Stereo, format: OutputFormat) -> u64 {
    let pixels = settings.width as u64 * settings.height as u64;
    let views = stereo.views() as u64;
    let output = match format {
        OutputFormat::Png => 3 * 2 * (1 + (views > 1) as u64),
        OutputFormat::Exr => 4 * (3 + 5 * settings.aovs as u64) * 2,
    };
    stereo::memory_needed(settings.aovs, stereo, pixels) + pixels * output
}

/// A scene that could not be made ready, as the command reports it: what the scene file or the
/// options ask for that cannot be done is bad input (with the file's name where it is about
/// the file), Embree's failures are internal.
fn unprepared(scene: Option<&Path>, e: PrepareError) -> Failure {
    match e {
        PrepareError::Stereo(_) | PrepareError::Trajectories(_) if e.is_bad_input() => {
            bad_input(in_file(scene, e.to_string()))
        }
        e if e.is_bad_input() => bad_input(e),
        e => internal(e),
    }
}

fn run_render(args: RenderArgs) -> Result<(), Failure> {
    let stopping = Stopping::new().map_err(internal)?;
    let loading = Instant::now();
    let waiting = spinner(args.quiet, "loading the scene");
    let mut description = load(args.scene.as_deref(), &args.set)?;
    waiting.finish_and_clear();
    let load_seconds = loading.elapsed().as_secs_f64();
    if !args.quiet {
        for w in description.warnings() {
            err!("timbre: warning: {w}");
        }
    }
    args.apply_to(&mut description.render);
    let settings = description.render.clone();
    let stereo = &description.stereo;
    let scene_file = args.scene.as_deref();
    prepare::check_settings(&settings, stereo).map_err(|e| unprepared(scene_file, e))?;
    if !args.quiet && description.camera.aperture_radius() > 0.0 && settings.spp == 1 {
        err!(
            "timbre: warning: a finite-aperture camera with 1 sample per pixel sees through one random pupil point per pixel (noisy); set --spp or [render] spp"
        );
    }
    if settings.aovs && *stereo != Stereo::Mono {
        return Err(bad_input(
            "--aov works with single views only (camera.stereo = \"none\")",
        ));
    }

    let format = OutputFormat::from_path(&args.output).map_err(bad_input)?;
    if settings.aovs && format != OutputFormat::Exr {
        return Err(bad_input("--aov needs an OpenEXR output (-o NAME.exr)"));
    }
    let mut job = job(&args, &settings, description.hash(), Vec::new())?;
    let production = job.provenance.sums || job.checkpointing.is_some();
    if production && *stereo != Stereo::Mono {
        return Err(bad_input(
            "--tile, --pixel-bounds, --samples, --checkpoint-interval and --resume work with single views only (camera.stereo = \"none\")",
        ));
    }
    if job.provenance.sums && format != OutputFormat::Exr {
        return Err(bad_input(
            "--tile, --pixel-bounds and --samples write a part for `timbre merge`: it needs an OpenEXR output (-o NAME.exr)",
        ));
    }
    // A single view stops cleanly on SIGINT and SIGTERM (keeping a checkpoint, if asked for),
    // also while its BVH is built; stereo outputs are not stopped early.
    if *stereo == Stereo::Mono {
        stopping.handle().map_err(internal)?;
    }

    if let Some(dir) = args.output.parent().filter(|d| !d.as_os_str().is_empty())
        && !dir.is_dir()
    {
        return Err(bad_input(format!(
            "{}: the output directory {} does not exist",
            args.output.display(),
            dir.display()
        )));
    }
    // Found out now, not after a long render.
    timbre::files::check_writable(&args.output).map_err(|e| {
        bad_input(format!(
            "{}: cannot write the output there: {e}",
            args.output.display()
        ))
    })?;

    let threads = settings
        .threads
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    // A single view shown in tev keeps a copy of it to send again; a stereo output is sent from
    // its combined image.
    let shown = args.display_server.is_some();
    let image = match stereo {
        Stereo::Mono => {
            let bounds = job.provenance.bounds;
            production::memory_needed(bounds.width(), threads, job.checkpointing.is_some())
                + shown as u64 * display::memory_needed(bounds.pixels())
        }
        _ => memory_needed(&settings, stereo, format),
    };
    let what = format!(
        "a {}x{} render{}{}",
        settings.width,
        settings.height,
        match stereo.views() {
            1 => String::new(),
            n => format!(" of {n} views"),
        },
        if shown { " shown in tev" } else { "" }
    );
    let needs = Needs::render(what, image, threads);
    let building = Instant::now();
    let waiting = spinner(args.quiet, "building the BVH");
    let Ready {
        scene,
        device: _device,
    } = prepare::prepare(&description, &settings, &needs).map_err(|e| unprepared(scene_file, e))?;
    waiting.finish_and_clear();
    let build_seconds = building.elapsed().as_secs_f64();
    job.provenance.object_names = scene.object_names.clone();

    let pixels = match stereo {
        Stereo::Mono => job.provenance.bounds.pixels(),
        _ => settings.width as u64 * settings.height as u64 * stereo.views() as u64,
    };
    let json = (args.progress == ProgressMode::Json).then(|| JsonProgress::new(pixels));
    let bar = if args.quiet || json.is_some() || !std::io::stderr().is_terminal() {
        ProgressBar::hidden()
    } else {
        let bar = ProgressBar::with_draw_target(Some(pixels), ProgressDrawTarget::stderr());
        bar.set_style(
            ProgressStyle::with_template("{bar:40} {percent:>3}% {elapsed} (eta {eta})")
                .map_err(internal)?,
        );
        bar
    };
    let start = Instant::now();
    let camera = &description.camera;
    let report = |n| match &json {
        Some(json) => json.add(n),
        None => bar.inc(n),
    };
    // The image in tev is named as the output file, and as the part rendered if it is one (tev
    // replaces an image of the same name).
    let (pixels_part, samples_part) = part_of(&job, &settings);
    let name = args.output.file_name().unwrap_or(args.output.as_os_str());
    let name = format!("{}{pixels_part}{samples_part}", name.to_string_lossy());
    let warn = || -> Box<dyn FnMut(&str)> {
        let (bar, quiet) = (bar.clone(), args.quiet);
        Box::new(move |message| {
            if !quiet {
                bar.suspend(|| err!("timbre: warning: {message}"));
            }
        })
    };
    // Measured before waiting for tev at the end.
    let (rays, seconds) = if *stereo == Stereo::Mono {
        let mut viewer = args.display_server.clone().and_then(|server| {
            let (width, height) = (settings.width, settings.height);
            Viewer::new(server, &name, width, height, job.provenance.bounds, warn())
        });
        let mut show = |y0, colours: &[Colour]| {
            if let Some(viewer) = &mut viewer {
                viewer.show(y0, colours);
            }
        };
        let signals = &stopping.signals;
        let done = production::run(&scene, camera, &settings, &job, signals, &report, &mut show)
            .map_err(job_failure)?;
        bar.finish_and_clear();
        match done {
            Done::Written {
                rays,
                resumed_groups,
            } => {
                let seconds = start.elapsed().as_secs_f64();
                if let Some(viewer) = viewer {
                    viewer.finish();
                }
                if resumed_groups > 0 && !args.quiet {
                    err!(
                        "timbre: resumed {resumed_groups} group(s) of {} rows from the checkpoint",
                        production::checkpoint::GROUP
                    );
                }
                (rays, seconds)
            }
            Done::Stopped { checkpoint } => {
                let saved = match checkpoint {
                    Some(dir) => format!(
                        "; the work done is saved in {}: run the same command with --resume to continue",
                        dir.display()
                    ),
                    None => String::new(),
                };
                // 128 + the signal's number, as shells report a process it ended.
                return Err(Failure {
                    code: 128 + stopping.which.load(Ordering::Relaxed).min(127) as u8,
                    message: format!(
                        "interrupted; {} was not written{saved}",
                        args.output.display()
                    ),
                });
            }
        }
    } else {
        let image =
            render_stereo(&scene, camera, &settings, stereo, &report).map_err(|e| match e {
                RenderError::Memory { .. } => bad_input(e),
                e => internal(e),
            })?;
        bar.finish_and_clear();
        // A packed frame is larger than a view.
        let provenance = Provenance {
            width: image.width,
            height: image.height,
            bounds: PixelBounds::full(image.width, image.height),
            ..job.provenance.clone()
        };
        write_image(&args.output, &image, &provenance).map_err(bad_input)?;
        let seconds = start.elapsed().as_secs_f64();
        if let Some(server) = args.display_server.clone() {
            let (width, height) = (image.width, image.height);
            Viewer::show_image(server, &name, width, height, &image.pixels, warn());
        }
        (image.rays, seconds)
    };
    if !args.quiet {
        out!(
            "{}x{}{pixels_part}, {} spp{samples_part}: {} rays in {:.3} s ({:.2} Mrays/s) -> {}",
            settings.width,
            settings.height,
            settings.spp,
            rays,
            seconds,
            rays as f64 / seconds / 1e6,
            args.output.display()
        );
        let summary = description.summary();
        out!(
            "scene: {} objects, {} triangles, {} instances; loaded in {:.3} s, BVH built in {:.3} s; peak memory {}",
            summary.objects,
            summary.triangles,
            summary.instances,
            load_seconds,
            build_seconds,
            memory::peak().unwrap_or_else(|| "unknown".into())
        );
    }
    Ok(())
}

/// The production job the arguments ask for: the part of the image and of the samples, the
/// output's provenance and checkpointing.
fn job(
    args: &RenderArgs,
    s: &RenderSettings,
    hash: String,
    object_names: Vec<String>,
) -> Result<Job, Failure> {
    let full = PixelBounds::full(s.width, s.height);
    let bounds = match (args.tile, args.pixel_bounds) {
        (Some(TileArg { k, n }), _) => {
            if n > s.height {
                return Err(bad_input(format!(
                    "--tile {k}/{n}: an image {} rows high cannot be cut into {n} strips",
                    s.height
                )));
            }
            let rows = production::tile_rows(k, n, s.height);
            PixelBounds {
                y0: rows.start,
                y1: rows.end,
                ..full
            }
        }
        (None, Some(BoundsArg(b))) => {
            if !full.contains(&b) {
                return Err(bad_input(format!(
                    "--pixel-bounds {b} is not within the {}x{} image",
                    s.width, s.height
                )));
            }
            b
        }
        (None, None) => full,
    };
    let samples = match &args.samples {
        Some(SamplesArg(r)) if r.end > s.spp => {
            return Err(bad_input(format!(
                "--samples {}..{} goes beyond the {} samples per pixel of the render (--spp)",
                r.start, r.end, s.spp
            )));
        }
        Some(SamplesArg(r)) => r.clone(),
        None => 0..s.spp,
    };
    let checkpointing = match (args.checkpoint_interval, args.resume) {
        // A millisecond to about 32 years: what a Duration holds, and more than a render takes.
        (Some(i), _) if !(1e-3..=1e9).contains(&i) => {
            let shown = if i.abs() < 1e15 {
                i.to_string()
            } else {
                format!("{i:e}")
            };
            return Err(bad_input(format!(
                "--checkpoint-interval must be from 0.001 to 1000000000 seconds, got {shown}"
            )));
        }
        (None, false) => None,
        (interval, resume) => Some(Checkpointing {
            interval: interval.map(Duration::from_secs_f64),
            resume,
        }),
    };
    let aovs = AovSelection {
        depth: args.aov.contains(&Aov::Depth),
        normal: args.aov.contains(&Aov::Normal),
        object: args.aov.contains(&Aov::Object),
    };
    Ok(Job {
        output: args.output.clone(),
        provenance: Provenance {
            width: s.width,
            height: s.height,
            // Asked for a part, a part it is (to be merged), even if it is all of the image.
            sums: args.tile.is_some() || args.pixel_bounds.is_some() || args.samples.is_some(),
            bounds,
            spp: s.spp,
            samples,
            seed: s.seed,
            scene: hash,
            aovs,
            object_names,
        },
        checkpointing,
    })
}

/// What part of the whole render `job` is: " (pixels x0,x1,y0,y1)" and " (samples A..B)", each
/// empty where the part is the whole.
fn part_of(job: &Job, settings: &RenderSettings) -> (String, String) {
    let p = &job.provenance;
    let pixels = match p.bounds == PixelBounds::full(settings.width, settings.height) {
        true => String::new(),
        false => format!(" (pixels {})", p.bounds),
    };
    let samples = match p.count() == settings.spp {
        true => String::new(),
        false => format!(" (samples {}..{})", p.samples.start, p.samples.end),
    };
    (pixels, samples)
}

/// A production job's failure, with its exit code: 2 for bad input (files that cannot be
/// used or written), 1 for everything else.
fn job_failure(e: JobError) -> Failure {
    match e {
        JobError::Render(RenderError::Threads(_)) => internal(e),
        e => bad_input(e),
    }
}

/// Signals a render obeys. SIGUSR1 (a scheduler's warning that time runs out) asks for a
/// checkpoint: handled from the start, so that it does not end the process while the scene
/// loads. SIGINT and SIGTERM stop a production job ([`Signals::stop`]; a second one ends the
/// process at once), handled by [`Stopping::handle`] once the render is known to be one; the
/// number of the stopping signal is kept for the exit code.
struct Stopping {
    signals: Signals,
    which: Arc<AtomicUsize>,
}

impl Stopping {
    fn new() -> std::io::Result<Stopping> {
        let signals = Signals::default();
        signal_hook::flag::register(signal_hook::consts::SIGUSR1, signals.checkpoint.clone())?;
        Ok(Stopping {
            signals,
            which: Arc::new(AtomicUsize::new(0)),
        })
    }

    fn handle(&self) -> std::io::Result<()> {
        use signal_hook::consts::{SIGINT, SIGTERM};
        use signal_hook::flag;
        let stop = &self.signals.stop;
        for signal in [SIGINT, SIGTERM] {
            flag::register_conditional_shutdown(signal, 128 + signal, stop.clone())?;
            flag::register(signal, stop.clone())?;
            flag::register_usize(signal, self.which.clone(), signal as usize)?;
        }
        Ok(())
    }
}

/// `timbre merge`.
fn run_merge(output: &Path, parts: &[PathBuf], quiet: bool) -> Result<(), Failure> {
    OutputFormat::from_path(output).map_err(bad_input)?;
    timbre::files::check_writable(output).map_err(|e| {
        bad_input(format!(
            "{}: cannot write the output there: {e}",
            output.display()
        ))
    })?;
    let parts: Vec<&Path> = parts.iter().map(PathBuf::as_path).collect();
    let merged = production::merge(output, &parts).map_err(job_failure)?;
    if !quiet {
        out!(
            "{}x{}, {} spp: {} parts merged -> {}",
            merged.width,
            merged.height,
            merged.spp,
            merged.parts,
            output.display()
        );
    }
    Ok(())
}

fn run_check(scene: &Path, set: &[Override]) -> Result<(), Failure> {
    let waiting = spinner(false, "loading the scene");
    let description = load(Some(scene), set)?;
    waiting.finish_and_clear();
    for w in description.warnings() {
        err!("timbre: warning: {w}");
    }
    // Every check a render makes before it starts: the render settings, the stereo output,
    // the memory, the ray trajectories (traced and drawn) and the BVH.
    let waiting = spinner(false, "building the BVH");
    let needs = Needs::scene(format!("checking {}", scene.display()));
    let settings = RenderSettings {
        threads: None,
        ..description.render.clone()
    };
    prepare::prepare(&description, &settings, &needs).map_err(|e| unprepared(Some(scene), e))?;
    waiting.finish_and_clear();
    out!("{}: OK", scene.display());
    for line in description.report().to_string().lines() {
        out!("{line}");
    }
    Ok(())
}

/// `timbre trace --json`: the traced rays of a scene file. Fields are in alphabetical order,
/// as JSON tools print them.
#[derive(Serialize)]
struct TraceDocument<'a> {
    rays: Vec<TracedRay<'a>>,
    scene: String,
}

#[derive(Serialize)]
struct TracedRay<'a> {
    direction: [f64; 3],
    end: &'static str,
    points: Vec<TracedPoint<'a>>,
    ray: usize,
    trajectory: &'a str,
}

#[derive(Serialize)]
struct TracedPoint<'a> {
    arrival: &'static str,
    object: Option<&'a str>,
    position: [f64; 3],
}

fn run_trace(scene: &Path, json: bool, set: &[Override]) -> Result<(), Failure> {
    let description = load(Some(scene), set)?;
    for w in description.warnings() {
        err!("timbre: warning: {w}");
    }
    if description.trajectories.is_empty() {
        return Err(bad_input(format!(
            "{}: no [[ray_trajectory]] to trace",
            scene.display()
        )));
    }
    let needs = Needs::scene(format!("tracing {}", scene.display()));
    let unprepared = |e| unprepared(Some(scene), e);
    prepare::check_memory(&needs, description.build_memory()).map_err(unprepared)?;
    let device = prepare::device(None).map_err(unprepared)?;
    let traced = trajectories::trace(&device, &description)
        .map_err(|e| unprepared(PrepareError::from(e)))?;
    let names = |t: &Trajectory| &description.trajectories[t.source].name;
    let object = |o: Option<usize>| o.map(|i| description.objects[i].name.as_str());
    if json {
        let rays = traced
            .iter()
            .map(|t| TracedRay {
                direction: t.direction.to_array(),
                end: t.end.name(),
                points: t
                    .points
                    .iter()
                    .map(|p| TracedPoint {
                        arrival: p.arrival.name(),
                        object: object(p.object),
                        position: p.position.to_array(),
                    })
                    .collect(),
                ray: t.ray,
                trajectory: names(t),
            })
            .collect();
        let document = TraceDocument {
            rays,
            scene: scene.display().to_string(),
        };
        // serde_json escapes control characters; invisible marks get JSON escapes too, and
        // nothing is cut (the output must stay JSON).
        let text: String = serde_json::to_string_pretty(&document)
            .map_err(internal)?
            .chars()
            .map(|c| {
                if timbre::text::is_invisible(c) {
                    format!("\\u{:04x}", c as u32)
                } else {
                    c.to_string()
                }
            })
            .collect();
        use std::io::Write as _;
        let _ = writeln!(std::io::stdout(), "{text}");
        return Ok(());
    }
    for t in &traced {
        out!(
            "{} ray {}: {} points, {}; direction [{}, {}, {}]",
            names(t),
            t.ray,
            t.points.len(),
            t.end.name(),
            t.direction.x,
            t.direction.y,
            t.direction.z
        );
        for p in &t.points {
            out!(
                "  {:<10} [{}, {}, {}] {}",
                p.arrival.name(),
                p.position.x,
                p.position.y,
                p.position.z,
                object(p.object).unwrap_or("")
            );
        }
    }
    Ok(())
}

fn run_generate_mesh(
    output: &Path,
    triangles: u64,
    displacement: f64,
    encoding: Encoding,
) -> Result<(), Failure> {
    if !displacement.is_finite() || displacement.abs() >= 1.0 {
        return Err(bad_input(format!(
            "--displacement must be between -1 and 1, got {displacement}"
        )));
    }
    let mesh = generate::displaced_sphere(triangles as usize, displacement);
    let encoding = match encoding {
        Encoding::Ascii => PlyEncoding::Ascii,
        Encoding::BinaryLittleEndian => PlyEncoding::BinaryLittleEndian,
        Encoding::BinaryBigEndian => PlyEncoding::BinaryBigEndian,
    };
    mesh::save(output, &mesh, encoding).map_err(bad_input)?;
    out!(
        "{} triangles, {} vertices -> {}",
        mesh.triangles.len(),
        mesh.vertices.len(),
        output.display()
    );
    Ok(())
}

fn run_serve(args: ServeArgs) -> Result<(), Failure> {
    let options = timbre::serve::ServeOptions {
        scene: args.scene,
        bind: args.bind,
        port: args.port,
        overrides: args.set,
        preview: timbre::serve::PreviewOptions {
            settings: args.settings.0,
            threads: args.threads,
        },
    };
    timbre::serve::serve(options).map_err(|e| match e {
        timbre::serve::ServeError::Internal(_) => internal(e),
        e => bad_input(e),
    })
}

fn run_info() -> Result<(), Failure> {
    let device = Device::new("").map_err(internal)?;
    out!("timbre {}", env!("CARGO_PKG_VERSION"));
    out!("Embree {}", device.version());
    out!("CPU SIMD: {}", simd_features().join(" "));
    out!(
        "native Embree packet widths: {:?}",
        device.native_packet_widths()
    );
    out!("threads: {}", rayon::current_num_threads());
    Ok(())
}

/// The SIMD instruction sets that matter to Embree's kernels, as the CPU reports them.
#[cfg(target_arch = "x86_64")]
fn simd_features() -> Vec<&'static str> {
    [
        ("sse4.2", std::arch::is_x86_feature_detected!("sse4.2")),
        ("avx", std::arch::is_x86_feature_detected!("avx")),
        ("avx2", std::arch::is_x86_feature_detected!("avx2")),
        ("avx512f", std::arch::is_x86_feature_detected!("avx512f")),
    ]
    .into_iter()
    .filter_map(|(name, on)| on.then_some(name))
    .collect()
}

#[cfg(not(target_arch = "x86_64"))]
fn simd_features() -> Vec<&'static str> {
    vec!["(not detected on this architecture)"]
}

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        // A usage error quotes the argument: printed like every message, escaped and cut.
        Err(e) if e.use_stderr() => {
            for line in e.render().to_string().lines() {
                err!("{line}");
            }
            std::process::exit(e.exit_code());
        }
        Err(e) => e.exit(),
    };
    let result = match cli.command {
        Command::Render(args) => run_render(args),
        Command::Check { scene, set } => run_check(&scene, &set),
        Command::Trace { scene, json, set } => run_trace(&scene, json, &set),
        Command::GenerateMesh {
            output,
            triangles,
            displacement,
            encoding,
        } => run_generate_mesh(&output, triangles, displacement, encoding),
        Command::Merge {
            output,
            parts,
            quiet,
        } => run_merge(&output, &parts, quiet),
        Command::Info => run_info(),
        Command::Serve(args) => run_serve(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(f) => {
            err!("timbre: error: {}", f.message);
            ExitCode::from(f.code)
        }
    }
}
