//! The `timbre` command's arguments (clap): the commands, their options, and the render
//! settings as options, derived from `timbre::scene::settings::SETTINGS`.

use std::path::PathBuf;

use clap::{Parser, Subcommand, ValueEnum};
use timbre::display::Server;
use timbre::render::PixelBounds;
use timbre::scene::RenderSettings;
use timbre::scene::file::Override;
use timbre::scene::settings::{SETTINGS, SettingValues, Value, whole_number};

#[derive(Parser)]
#[command(
    name = "timbre",
    version,
    about = "A fast, scientifically exact ray tracer for ray-optics research"
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Subcommand)]
pub enum Command {
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
        #[arg(long, default_value_t = 10_000, value_parser = whole::<u64>(1, 200_000_000))]
        triangles: u64,
        /// Height of the bumps relative to the radius (0: a plain faceted sphere).
        #[arg(long, default_value_t = 0.1, value_parser = number)]
        displacement: f64,
        /// PLY encoding.
        #[arg(long, value_enum, default_value_t = Encoding::BinaryLittleEndian)]
        encoding: Encoding,
        /// Precision of the coordinates: f32 (half the size of f64) or f64 (exact).
        #[arg(long, value_enum, default_value_t = PrecisionArg::F32)]
        precision: PrecisionArg,
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
    /// Picture tools: information, conversion with exposure, comparison with a metric.
    Image {
        #[command(subcommand)]
        command: super::image::ImageCommand,
    },
    /// Serve a live, progressive preview of a scene file to a web browser: navigation,
    /// parameters, the scene text, inspection, saving (docs/PREVIEW.md).
    Serve(ServeArgs),
}

/// The render settings as options, one for each of `timbre::scene::settings::SETTINGS`
/// (`--width`, `--max-trace-level`, ...), in place of the scene file's values; shared by
/// `render` and `serve`.
#[derive(Debug, Clone, Default)]
pub struct SettingArgs(pub SettingValues);

impl clap::Args for SettingArgs {
    fn augment_args(command: clap::Command) -> clap::Command {
        SETTINGS.iter().fold(command, |command, setting| {
            let arg = clap::Arg::new(setting.key)
                .long(setting.key.replace('_', "-"))
                .value_name(setting.key.to_uppercase())
                .help(format!("{} (overrides the scene file)", setting.help));
            let kind = setting.kind;
            command.arg(arg.value_parser(move |text: &str| kind.parse(text)))
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
            if let Some(&value) = matches.get_one::<Value>(setting.key) {
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
pub struct ServeArgs {
    /// The TOML scene file (watched: saving it in an editor updates the page).
    pub scene: PathBuf,
    /// Port to listen on (0: any free port; the address is printed).
    #[arg(long, default_value_t = 7700)]
    pub port: u16,
    /// Address to listen on. Any but a loopback address (127.0.0.1, ::1) makes the page
    /// require a random access token, printed at start.
    #[arg(long, default_value = "127.0.0.1")]
    pub bind: std::net::IpAddr,
    /// The render settings (`--spp`: the samples per pixel the preview accumulates, by
    /// default the scene's, at least 64; the picture converges to `timbre render --spp N`'s).
    #[command(flatten)]
    pub settings: SettingArgs,
    /// Worker threads (default: all cores), at most 1024.
    #[arg(long, value_parser = whole::<u32>(1, 1024))]
    pub threads: Option<u32>,
    /// Override a scene-file value, e.g. --set camera.position=[0,0,-2] (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<Override>,
    /// Serve anonymous visitors (with --bind 0.0.0.0, the world): each has a view and changes
    /// of their own on the scene, no file is read or written for a page, and each preview
    /// renders on --threads threads (default 1); the page may be embedded in an <iframe>.
    #[arg(long)]
    pub public: bool,
    /// With --public: most visitors at once (more are told the server is busy).
    #[arg(long, value_parser = whole::<u32>(1, timbre::serve::MAX_VISITORS as u64), default_value_t = 8, requires = "public")]
    pub visitors: u32,
}

#[derive(Parser, Clone)]
pub struct RenderArgs {
    /// The TOML scene file; without it, TIM's standard studio with the cylinder lattice.
    pub scene: Option<PathBuf>,
    /// Output image; the extension (.png or .exr) chooses the format. For a movie, the frames'
    /// names: a pattern with %d or %0Nd for the frame number (frames/f%04d.png), or the name
    /// with -0000, -0001, ... before its extension.
    #[arg(short, long, default_value = "out.png")]
    pub output: PathBuf,
    /// Render a movie of N frames, 0 to N-1 (the scene's [animation] frames; with no
    /// [animation], N frames of the scene as it is).
    #[arg(long, value_name = "N", value_parser = whole::<u32>(1, timbre::scene::MAX_FRAMES as u64))]
    pub frames: Option<u32>,
    /// Render only frame K of the movie (its first_frame and last_frame): one job of a job
    /// array.
    #[arg(long, value_name = "K", value_parser = whole::<u32>(0, timbre::scene::MAX_FRAMES as u64 - 1))]
    pub frame: Option<u32>,
    /// Encode the movie's frames (PNG) into a video (.mp4, .webm, .gif, ...) with ffmpeg, at
    /// the [animation]'s fps, once they are rendered.
    #[arg(long, value_name = "VIDEO")]
    pub encode: Option<PathBuf>,
    #[command(flatten)]
    pub settings: SettingArgs,
    /// Worker threads (default: all cores), at most 1024.
    #[arg(long, value_parser = whole::<u32>(1, 1024))]
    pub threads: Option<u32>,
    /// Extra EXR channels: depth (depth.Z), normal (normal.X/Y/Z), object (object.id), albedo
    /// (albedo.R/G/B: a denoiser's guide).
    #[arg(long, value_delimiter = ',')]
    pub aov: Vec<Aov>,
    /// Also write the picture denoised by Intel Open Image Denoise, as NAME.denoised.exr beside
    /// the OpenEXR output (which keeps the albedo and normal it is guided by); needs a build
    /// with the `denoise` feature.
    #[arg(long)]
    pub denoise: bool,
    /// Override a scene-file value, e.g. --set camera.position=[0,0,-2] (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<Override>,
    /// Print nothing but errors (and progress lines, if --progress json asks for them).
    #[arg(short, long)]
    pub quiet: bool,
    /// How to show progress: a bar with elapsed and remaining time on a terminal, or one JSON
    /// line per update (at most one a second) on standard error, for schedulers and logs.
    #[arg(long, value_enum, default_value_t = ProgressMode::Bar)]
    pub progress: ProgressMode,
    /// Render horizontal strip K of N (0-based, K < N) as a part for `timbre merge`.
    #[arg(long, value_name = "K/N", conflicts_with = "pixel_bounds")]
    pub tile: Option<TileArg>,
    /// Render only the pixels x0..x1, y0..y1 (half-open) as a part for `timbre merge`.
    #[arg(long, value_name = "x0,x1,y0,y1")]
    pub pixel_bounds: Option<BoundsArg>,
    /// Render only the pixels x0..x1, y0..y1 (half-open) of the picture, written as a picture
    /// of their own (PNG or OpenEXR), not a part.
    #[arg(long, value_name = "x0,x1,y0,y1", conflicts_with_all = ["pixel_bounds", "tile", "samples"])]
    pub crop: Option<BoundsArg>,
    /// Render samples A to B-1 of each pixel's sample sequence (of --spp) as a part for
    /// `timbre merge`.
    #[arg(long, value_name = "A..B")]
    pub samples: Option<SamplesArg>,
    /// Save a checkpoint (OUTPUT.checkpoint/) every SECONDS, and on SIGINT, SIGTERM (then stop)
    /// and SIGUSR1 (then go on).
    #[arg(long, value_name = "SECONDS", value_parser = number)]
    pub checkpoint_interval: Option<f64>,
    /// Continue from the checkpoint of the same output, if there is one (checkpoints are saved
    /// as with --checkpoint-interval); for a movie, also skip the frames already written.
    #[arg(long)]
    pub resume: bool,
    /// Show the image in the tev viewer listening at HOST:PORT (tev's own is 127.0.0.1:14158)
    /// while it renders (a stereo output once it is combined, after the render), reconnecting
    /// if tev restarts; a tev that cannot be reached is a warning.
    #[arg(long, value_name = "HOST:PORT")]
    pub display_server: Option<Server>,
}

/// A parser of whole numbers from `least` to `most` (within `T`), in the render settings'
/// words.
fn whole<T: TryFrom<u64>>(least: u64, most: u64) -> impl Fn(&str) -> Result<T, String> + Clone {
    move |text| {
        let n = whole_number(text, least, most)?;
        T::try_from(n).map_err(|_| format!("{n} is too large here"))
    }
}

/// A number (its range is the option's to check).
fn number(text: &str) -> Result<f64, String> {
    text.parse::<f64>()
        .map_err(|_| format!("expected a number, got '{text}'"))
}

/// `--tile K/N`.
#[derive(Clone, Copy)]
pub struct TileArg {
    pub k: u32,
    pub n: u32,
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
pub struct BoundsArg(pub PixelBounds);

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
pub struct SamplesArg(pub std::ops::Range<u32>);

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
pub enum ProgressMode {
    Bar,
    Json,
}

impl RenderArgs {
    /// The command line's values in place of the scene file's.
    pub fn apply_to(&self, s: &mut RenderSettings) {
        self.settings.0.apply_over(s);
        s.aovs = !self.aov.is_empty() || self.denoise;
        s.albedo = self.aov.contains(&Aov::Albedo) || self.denoise;
        s.threads = self.threads.map(|t| t as usize);
    }
}

#[derive(Clone, Copy, PartialEq, ValueEnum)]
pub enum PrecisionArg {
    F32,
    F64,
}

#[derive(Clone, Copy, PartialEq, ValueEnum)]
pub enum Encoding {
    Ascii,
    BinaryLittleEndian,
    BinaryBigEndian,
}

#[derive(Clone, Copy, PartialEq, ValueEnum)]
pub enum Aov {
    Depth,
    Normal,
    Object,
    Albedo,
}
