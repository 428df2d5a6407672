//! The `timbre` command: parse, load, render, write.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::Parser;
use serde::Serialize;

use timbre::embree::Device;

use timbre::io::OutputFormat;
use timbre::mesh::{self, PlyEncoding, Precision, generate};
use timbre::prepare::{self, Needs, PrepareError};
use timbre::production::{self, JobError};
use timbre::render::RenderError;
use timbre::scene::file::{self, Override};
use timbre::scene::studio::Studio;
use timbre::scene::{RenderSettings, SceneDescription};
use timbre::trajectories::{self, TracedRay};

/// `println!` of [`printable`](timbre::text::printable) text. A closed standard output
/// (`timbre check s.toml | head -1`) is ignored, not a panic; any other failure to write it (a
/// full disk, the file-size limit) ends the command with an error ([`stdout_failed`]), not a
/// silent loss.
macro_rules! out {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let line = timbre::text::printable(&format!($($arg)*));
        if let Err(e) = writeln!(std::io::stdout(), "{line}") {
            $crate::stdout_failed(e);
        }
    }};
}

/// `eprintln!` of [`printable`](timbre::text::printable) text; a standard error that cannot be
/// written is no panic.
macro_rules! err {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stderr(), "{}", timbre::text::printable(&format!($($arg)*)));
    }};
}

// After the macros, which its modules use.
mod cli;

use cli::args::{Cli, Command, Encoding, PrecisionArg, ServeArgs};
use cli::movie::run_render;
use cli::progress::spinner;

/// A failure to write standard output: a closed pipe is ignored (the reader has all it wanted;
/// the command goes on and writes its files), anything else (a full disk, the file-size limit)
/// ends the command with one line and exit code 2. Nothing is printed to standard output while
/// a file is being written, so no temporary file is left by the exit.
fn stdout_failed(e: std::io::Error) {
    if e.kind() == std::io::ErrorKind::BrokenPipe {
        return;
    }
    let e = timbre::files::explained(e);
    err!("timbre: error: cannot write to standard output: {e}");
    std::process::exit(2);
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

/// A production job's failure, with its exit code: 2 for bad input (files that cannot be
/// used or written), 1 for everything else.
fn job_failure(e: JobError) -> Failure {
    match e {
        JobError::Render(RenderError::Threads(_)) => internal(e),
        e => bad_input(e),
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

/// `timbre trace --json`: the traced rays of a scene file.
#[derive(Serialize)]
struct TraceDocument<'a> {
    rays: Vec<TracedRay<'a>>,
    scene: String,
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
    let rays = trajectories::traced_rays(&description, &traced);
    if json {
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
        if let Err(e) = writeln!(std::io::stdout(), "{text}") {
            stdout_failed(e);
        }
        return Ok(());
    }
    for r in &rays {
        let [x, y, z] = r.direction;
        let n = r.points.len();
        out!(
            "{} ray {}: {n} points, {}; direction [{x}, {y}, {z}]",
            r.trajectory,
            r.ray,
            r.end
        );
        for p in &r.points {
            let [x, y, z] = p.position;
            let object = p.object.unwrap_or("");
            out!("  {:<10} [{x}, {y}, {z}] {object}", p.arrival);
        }
    }
    Ok(())
}

fn run_generate_mesh(
    output: &Path,
    triangles: u64,
    displacement: f64,
    encoding: Encoding,
    precision: PrecisionArg,
) -> Result<(), Failure> {
    if !displacement.is_finite() || displacement.abs() >= 1.0 {
        return Err(bad_input(format!(
            "--displacement must be between -1 and 1, got {displacement}"
        )));
    }
    // Refused before anything is allocated if the mesh could not be held (as a render is).
    let (made, _) = generate::displaced_sphere_size(triangles as usize);
    let needs = Needs {
        what: format!("a mesh of {made} triangles"),
        image: generate::displaced_sphere_memory(triangles as usize),
        reserve: timbre::memory::PLAIN_RESERVE,
    };
    prepare::check_work_memory(&needs, "ask for fewer triangles")
        .map_err(|e| unprepared(None, e))?;
    let mesh = generate::displaced_sphere(triangles as usize, displacement);
    let encoding = match encoding {
        Encoding::Ascii => PlyEncoding::Ascii,
        Encoding::BinaryLittleEndian => PlyEncoding::BinaryLittleEndian,
        Encoding::BinaryBigEndian => PlyEncoding::BinaryBigEndian,
    };
    let precision = match precision {
        PrecisionArg::F32 => Precision::F32,
        PrecisionArg::F64 => Precision::F64,
    };
    mesh::save_as(output, &mesh, encoding, precision).map_err(bad_input)?;
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
            public: false,
        },
        public: args.public.then_some(timbre::serve::Public {
            visitors: args.visitors as usize,
        }),
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
    // A file-size limit (`ulimit -f`) then fails a write with EFBIG, which is reported like
    // every write error, instead of killing the process with SIGXFSZ without a word. A
    // handler rather than SIG_IGN: nothing unsafe, and not passed on to programs run from here.
    let size_limit = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
    if let Err(e) = signal_hook::flag::register(signal_hook::consts::SIGXFSZ, size_limit) {
        err!("timbre: error: cannot handle SIGXFSZ: {e}");
        return ExitCode::from(1);
    }
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
            precision,
        } => run_generate_mesh(&output, triangles, displacement, encoding, precision),
        Command::Merge {
            output,
            parts,
            quiet,
        } => run_merge(&output, &parts, quiet),
        Command::Info => run_info(),
        Command::Image { command } => cli::image::run_image(command),
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
