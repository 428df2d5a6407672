//! `timbre render`: a scene (or TIM's studio) rendered to PNG or OpenEXR, as a whole or a part
//! of a production render, shown in tev meanwhile, with progress and a summary.

use std::io::IsTerminal;
use std::time::Instant;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use timbre::display::{self, Viewer};
use timbre::io::{AovSelection, OutputFormat, Provenance, write_image};
use timbre::math::Colour;
use timbre::memory;
use timbre::prepare::{self, Needs, Ready};
use timbre::production::{self, Checkpoints, Done, Job, Part, Stopping};
use timbre::render::{PixelBounds, RenderError};
use timbre::scene::{RenderSettings, SceneDescription, Stereo};
use timbre::stereo::{self, render_stereo};

use super::args::{Aov, BoundsArg, ProgressMode, RenderArgs, SamplesArg, TileArg};
use super::denoise;
use super::progress::{JsonProgress, spinner};
use crate::{Failure, bad_input, internal, job_failure, load, unprepared};

/// Bytes a stereo render needs at its peak, roughly: the views in memory
/// ([`stereo::memory_needed`]) and the output file's encoding (PNG: 3 bytes a pixel and a
/// compressed copy; EXR: 4 bytes a channel, twice).
fn memory_needed(settings: &RenderSettings, stereo: &Stereo, format: OutputFormat) -> u64 {
    let pixels = settings.width as u64 * settings.height as u64;
    let views = stereo.views() as u64;
    let output = match format {
        OutputFormat::Png => 3 * 2 * (1 + (views > 1) as u64),
        OutputFormat::Exr => 4 * (3 + 5 * settings.aovs as u64 + 3 * settings.albedo as u64) * 2,
    };
    stereo::memory_needed(settings.aovs, stereo, pixels) + pixels * output
}

/// Renders the scene loaded from `args`' scene (since `loading`) with its `settings`.
pub fn render(
    args: RenderArgs,
    description: SceneDescription,
    settings: RenderSettings,
    loading: Instant,
    stopping: &Stopping,
) -> Result<(), Failure> {
    let load_seconds = loading.elapsed().as_secs_f64();
    let stereo = &description.stereo;
    let format = OutputFormat::from_path(&args.output).map_err(bad_input)?;
    let mut job = job(&args, &settings, description.hash())?;
    check_output(&args, &settings, stereo, format, &job)?;
    // A single view stops cleanly on SIGINT and SIGTERM (keeping a checkpoint, if asked for),
    // also while its BVH is built; stereo outputs are not stopped early.
    if *stereo == Stereo::Mono {
        stopping.handle().map_err(internal)?;
    }
    let building = Instant::now();
    let waiting = spinner(args.quiet, "building the BVH");
    let needs = needs(&args, &settings, stereo, format, &job);
    let Ready {
        scene,
        device: _device,
    } = prepare::prepare(&description, &settings, &needs)
        .map_err(|e| unprepared(args.scene.as_deref(), e))?;
    waiting.finish_and_clear();
    let build_seconds = building.elapsed().as_secs_f64();
    job.provenance.object_names = scene.object_names.clone();

    let pixels = match stereo {
        Stereo::Mono => job.provenance.bounds.pixels(),
        _ => settings.width as u64 * settings.height as u64 * stereo.views() as u64,
    };
    let shown = Shown::new(&args, pixels, &job, &settings)?;
    let start = Instant::now();
    let camera = &description.camera;
    // Measured before waiting for tev at the end.
    let (rays, seconds) = if *stereo == Stereo::Mono {
        let signals = &stopping.signals;
        let mut viewer = shown.viewer(&args, &settings, job.provenance.bounds);
        let mut show = |y0, colours: &[Colour]| {
            if let Some(viewer) = &mut viewer {
                viewer.show(y0, colours);
            }
        };
        let report = |n| shown.report(n);
        let done = production::run(&scene, camera, &settings, &job, signals, &report, &mut show)
            .map_err(job_failure)?;
        shown.bar.finish_and_clear();
        let rays = written(&args, done, stopping)?;
        let seconds = start.elapsed().as_secs_f64();
        if let Some(viewer) = viewer {
            viewer.finish();
        }
        (rays, seconds)
    } else {
        let report = |n| shown.report(n);
        let image =
            render_stereo(&scene, camera, &settings, stereo, &report).map_err(|e| match e {
                RenderError::Memory { .. } => bad_input(e),
                e => internal(e),
            })?;
        shown.bar.finish_and_clear();
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
            let (width, height, warn) = (image.width, image.height, shown.warn(&args));
            Viewer::show_image(server, &shown.name, width, height, &image.pixels, warn);
        }
        (image.rays, seconds)
    };
    // Beside the output, which stays as it is (check_output allows it for single views only).
    let denoised = args.denoise.then(|| denoise::denoised_path(&args.output));
    if let Some(denoised) = &denoised {
        let waiting = spinner(args.quiet, "denoising");
        denoise::denoise_file(&args.output, denoised)?;
        waiting.finish_and_clear();
    }
    if !args.quiet {
        let (pixels_part, samples_part) = job.part_names(&settings);
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
        if let Some(denoised) = denoised {
            out!(
                "denoised with Intel Open Image Denoise -> {}",
                denoised.display()
            );
        }
    }
    Ok(())
}

/// The scene the arguments name (with a spinner while it loads, and its warnings), and the
/// settings the render obeys: the scene's, with the command line's in place, checked.
pub fn load_settings(args: &RenderArgs) -> Result<(SceneDescription, RenderSettings), Failure> {
    let waiting = spinner(args.quiet, "loading the scene");
    let mut description = load(args.scene.as_deref(), &args.set)?;
    waiting.finish_and_clear();
    if !args.quiet {
        for w in description.warnings() {
            err!("timbre: warning: {w}");
        }
    }
    args.apply_to(&mut description.render);
    let settings = description.render.clone();
    prepare::check_settings(&settings, &description.stereo)
        .map_err(|e| unprepared(args.scene.as_deref(), e))?;
    if !args.quiet && description.camera.aperture_radius() > 0.0 && settings.spp == 1 {
        err!(
            "timbre: warning: a finite-aperture camera with 1 sample per pixel sees through one random pupil point per pixel (noisy); set --spp or [render] spp"
        );
    }
    Ok((description, settings))
}

/// Refuses, before anything is built, an output that cannot be: AOVs or production options
/// with a stereo output or in PNG, an output directory that is missing or not writable.
fn check_output(
    args: &RenderArgs,
    settings: &RenderSettings,
    stereo: &Stereo,
    format: OutputFormat,
    job: &Job,
) -> Result<(), Failure> {
    if args.denoise {
        if let Some(why) = denoise::unavailable() {
            return Err(bad_input(format!("--denoise: {why}")));
        }
        if *stereo != Stereo::Mono || format != OutputFormat::Exr || job.provenance.sums {
            return Err(bad_input(
                "--denoise needs a whole single view in OpenEXR (-o NAME.exr, camera.stereo = \"none\", no --tile, --pixel-bounds or --samples: denoise a merged render with `timbre image denoise`)",
            ));
        }
    }
    if settings.aovs && *stereo != Stereo::Mono {
        return Err(bad_input(
            "--aov works with single views only (camera.stereo = \"none\")",
        ));
    }
    if settings.aovs && format != OutputFormat::Exr {
        return Err(bad_input("--aov needs an OpenEXR output (-o NAME.exr)"));
    }
    let production = job.provenance.sums || job.checkpointing.is_some() || args.crop.is_some();
    if production && *stereo != Stereo::Mono {
        return Err(bad_input(
            "--tile, --pixel-bounds, --crop, --samples, --checkpoint-interval and --resume work with single views only (camera.stereo = \"none\")",
        ));
    }
    if job.provenance.sums && format != OutputFormat::Exr {
        return Err(bad_input(
            "--tile, --pixel-bounds and --samples write a part for `timbre merge`: it needs an OpenEXR output (-o NAME.exr)",
        ));
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
    })
}

/// The memory the render needs besides its scene, for [`prepare::prepare`].
fn needs(
    args: &RenderArgs,
    settings: &RenderSettings,
    stereo: &Stereo,
    format: OutputFormat,
    job: &Job,
) -> Needs {
    let threads = settings.threads.unwrap_or_else(prepare::default_threads);
    // A single view shown in tev keeps a copy of it to send again; a stereo output is sent from
    // its combined image.
    let shown = args.display_server.is_some();
    let image = match stereo {
        Stereo::Mono => {
            let bounds = job.provenance.bounds;
            production::memory_needed(bounds.width(), threads, job.checkpointing.is_some())
                + shown as u64 * display::memory_needed(bounds.pixels())
        }
        _ => memory_needed(settings, stereo, format),
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
    Needs::render(what, image, threads)
}

/// How the render is shown while it runs: a progress bar on a terminal or `--progress json`
/// lines, and the name of the image in tev.
struct Shown {
    bar: ProgressBar,
    json: Option<JsonProgress>,
    /// The output file's, and the part rendered if it is one (tev replaces an image of the
    /// same name).
    name: String,
}

impl Shown {
    fn new(
        args: &RenderArgs,
        pixels: u64,
        job: &Job,
        settings: &RenderSettings,
    ) -> Result<Shown, Failure> {
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
        let (pixels_part, samples_part) = job.part_names(settings);
        let name = args.output.file_name().unwrap_or(args.output.as_os_str());
        let name = format!("{}{pixels_part}{samples_part}", name.to_string_lossy());
        Ok(Shown { bar, json, name })
    }

    /// `n` more pixels done.
    fn report(&self, n: u64) {
        match &self.json {
            Some(json) => json.add(n),
            None => self.bar.inc(n),
        }
    }

    /// Prints a warning (about tev) above the bar, unless quiet.
    fn warn(&self, args: &RenderArgs) -> Box<dyn FnMut(&str)> {
        let (bar, quiet) = (self.bar.clone(), args.quiet);
        Box::new(move |message| {
            if !quiet {
                bar.suspend(|| err!("timbre: warning: {message}"));
            }
        })
    }

    /// The single view shown in tev as it is rendered, if the arguments ask for it.
    fn viewer(
        &self,
        args: &RenderArgs,
        settings: &RenderSettings,
        bounds: PixelBounds,
    ) -> Option<Viewer> {
        let server = args.display_server.clone()?;
        let (width, height) = (settings.width, settings.height);
        Viewer::new(server, &self.name, width, height, bounds, self.warn(args))
    }
}

/// The rays of a production job that wrote its output, or the failure of one a signal stopped
/// (with where its work is saved).
fn written(args: &RenderArgs, done: Done, stopping: &Stopping) -> Result<u64, Failure> {
    match done {
        Done::Written {
            rays,
            resumed_groups,
        } => {
            if resumed_groups > 0 && !args.quiet {
                err!(
                    "timbre: resumed {resumed_groups} group(s) of {} rows from the checkpoint",
                    production::checkpoint::GROUP
                );
            }
            Ok(rays)
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
            Err(Failure {
                code: stopping.exit_code(),
                message: format!(
                    "interrupted; {} was not written{saved}",
                    args.output.display()
                ),
            })
        }
    }
}

/// The production job the arguments ask for: the part of the image and of the samples, the
/// output's provenance and checkpointing.
fn job(args: &RenderArgs, s: &RenderSettings, hash: String) -> Result<Job, Failure> {
    let part = Part {
        tile: args.tile.map(|TileArg { k, n }| (k, n)),
        pixels: args.pixel_bounds.map(|BoundsArg(b)| b),
        crop: args.crop.map(|BoundsArg(b)| b),
        samples: args.samples.clone().map(|SamplesArg(r)| r),
    };
    let checkpoints = Checkpoints {
        interval: args.checkpoint_interval,
        resume: args.resume,
    };
    let aovs = AovSelection {
        depth: args.aov.contains(&Aov::Depth),
        normal: args.aov.contains(&Aov::Normal) || args.denoise,
        object: args.aov.contains(&Aov::Object),
        albedo: args.aov.contains(&Aov::Albedo) || args.denoise,
    };
    Job::plan(args.output.clone(), s, &part, checkpoints, hash, aovs).map_err(bad_input)
}
