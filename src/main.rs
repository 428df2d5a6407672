//! The `timbre` command: parse, load, render, write.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use clap::{Parser, Subcommand, ValueEnum};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use timbre::embree::Device;
use timbre::io::{AovSelection, OutputFormat, Provenance, write_image};
use timbre::render::render;
use timbre::scene::studio::Studio;
use timbre::scene::{Scene, SceneDescription, file};

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
    /// Check a scene file without rendering it.
    Check {
        /// The TOML scene file.
        scene: PathBuf,
    },
    /// Print the versions of timbre and Embree, the CPU's SIMD support and the thread count.
    Info,
}

#[derive(Parser)]
struct RenderArgs {
    /// The TOML scene file; without it, TIM's standard studio with the cylinder lattice.
    scene: Option<PathBuf>,
    /// Output image; the extension (.png or .exr) chooses the format.
    #[arg(short, long, default_value = "out.png")]
    output: PathBuf,
    /// Image width in pixels (overrides the scene file).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    width: Option<u32>,
    /// Image height in pixels (overrides the scene file).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    height: Option<u32>,
    /// Samples per pixel (overrides the scene file).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    spp: Option<u32>,
    /// Worker threads (default: all cores).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    threads: Option<u32>,
    /// Seed of the random sample positions (overrides the scene file).
    #[arg(long)]
    seed: Option<u64>,
    /// Maximum trace level: how many surfaces a ray path may meet (overrides the scene file).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    max_trace_level: Option<u32>,
    /// Extra EXR channels: depth (depth.Z), normal (normal.X/Y/Z), object (object.id).
    #[arg(long, value_delimiter = ',')]
    aov: Vec<Aov>,
    /// Print nothing but errors.
    #[arg(short, long)]
    quiet: bool,
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

fn load(scene: Option<&Path>) -> Result<SceneDescription, Failure> {
    match scene {
        Some(path) => file::load(path).map_err(bad_input),
        None => Ok(Studio::Lattice.description()),
    }
}

fn run_render(args: RenderArgs) -> Result<(), Failure> {
    let mut description = load(args.scene.as_deref())?;
    let s = &mut description.render;
    s.width = args.width.unwrap_or(s.width);
    s.height = args.height.unwrap_or(s.height);
    s.spp = args.spp.unwrap_or(s.spp);
    s.seed = args.seed.unwrap_or(s.seed);
    s.max_trace_level = args.max_trace_level.unwrap_or(s.max_trace_level);
    s.aovs = !args.aov.is_empty();
    s.threads = args.threads.map(|t| t as usize);
    s.validate().map_err(bad_input)?;
    let settings = s.clone();

    let format = OutputFormat::from_path(&args.output).map_err(bad_input)?;
    if settings.aovs && format != OutputFormat::Exr {
        return Err(bad_input("--aov needs an OpenEXR output (-o NAME.exr)"));
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

    let device = match settings.threads {
        Some(t) => Device::new(&format!("threads={t}")),
        None => Device::new(""),
    }
    .map_err(internal)?;
    let scene = Scene::build(&device, &description).map_err(internal)?;

    let pixels = settings.width as u64 * settings.height as u64;
    let bar = if args.quiet || !std::io::stderr().is_terminal() {
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
    let image =
        render(&scene, &description.camera, &settings, &|n| bar.inc(n)).map_err(internal)?;
    let seconds = start.elapsed().as_secs_f64();
    bar.finish_and_clear();

    let aovs = AovSelection {
        depth: args.aov.contains(&Aov::Depth),
        normal: args.aov.contains(&Aov::Normal),
        object: args.aov.contains(&Aov::Object),
    };
    let provenance = Provenance {
        spp: settings.spp,
        seed: settings.seed,
        aovs,
        object_names: scene.objects.iter().map(|o| o.name.clone()).collect(),
    };
    write_image(&args.output, &image, &provenance).map_err(bad_input)?;
    if !args.quiet {
        println!(
            "{}x{}, {} spp: {} rays in {:.3} s ({:.2} Mrays/s) -> {}",
            settings.width,
            settings.height,
            settings.spp,
            image.rays,
            seconds,
            image.rays as f64 / seconds / 1e6,
            args.output.display()
        );
    }
    Ok(())
}

fn run_check(scene: &Path) -> Result<(), Failure> {
    let description = load(Some(scene))?;
    println!(
        "{}: {} objects, {} point lights, {}x{} at {} spp: OK",
        scene.display(),
        description.objects.len(),
        description.lights.points.len(),
        description.render.width,
        description.render.height,
        description.render.spp
    );
    Ok(())
}

fn run_info() -> Result<(), Failure> {
    let device = Device::new("").map_err(internal)?;
    println!("timbre {}", env!("CARGO_PKG_VERSION"));
    println!("Embree {}", device.version());
    println!("CPU SIMD: {}", simd_features().join(" "));
    println!(
        "native Embree packet widths: {:?}",
        device.native_packet_widths()
    );
    println!("threads: {}", rayon::current_num_threads());
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
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Render(args) => run_render(args),
        Command::Check { scene } => run_check(&scene),
        Command::Info => run_info(),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(f) => {
            eprintln!("timbre: error: {}", f.message);
            ExitCode::from(f.code)
        }
    }
}
