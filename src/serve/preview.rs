//! The progressive preview behind `timbre serve`: a scene loaded from text with `--set`
//! overrides, a coarse picture first, then one sample per pixel per pass, accumulated exactly.
//!
//! Pass k renders sample k of a `spp`-sample render ([`Samples`] with the range k..k+1), and
//! the passes' exact sums are added ([`Sum`]), so after `spp` passes the picture is bit for bit
//! the one `timbre render --spp N` makes of the same scene. Nothing here knows about the
//! network; `serve` drives it from one thread.

use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};

use glam::DVec3;

use crate::cameras::Camera;
use crate::embree::Device;
use crate::math::{Colour, Ray, ReferenceFrame};
use crate::memory;
use crate::prepare::{self, Needs, PrepareError};
use crate::render::{self, Image, PixelBounds, Rows, Samples, Sum, Tracer};
use crate::scene::file::{self, Confinement, Override, SceneFileError};
use crate::scene::settings::SettingValues;
use crate::scene::{Packing, RenderSettings, Scene, SceneDescription, Stereo};
use crate::stereo::{self, anaglyph, pack, render_stereo};

/// Pixels of the coarse picture shown first after a change, about.
pub const COARSE_PIXELS: u64 = 20_000;

/// Most pixels of a view the preview holds (its exact sums take 48 bytes a pixel): 4096 × 4096.
pub const MAX_PREVIEW_PIXELS: u64 = 1 << 24;

/// How often a pass shows the rows it has finished so far.
pub const FRAME_INTERVAL: Duration = Duration::from_millis(100);

/// A scene that could not be previewed: where (for errors in the text) and what.
#[derive(Debug, Clone, PartialEq)]
pub struct LoadError {
    pub message: String,
    /// Line and column (from 1) in the text, when the error has them.
    pub line: Option<usize>,
    pub column: Option<usize>,
}

impl LoadError {
    fn plain(message: impl ToString) -> LoadError {
        LoadError {
            message: message.to_string(),
            line: None,
            column: None,
        }
    }

    /// `e`, located in the text when it is an error of the scene file `path` itself (not of a
    /// file it includes).
    fn of(e: SceneFileError, path: &str) -> LoadError {
        match e {
            SceneFileError::Invalid {
                line,
                column,
                path: ref at,
                ..
            } if at == path => LoadError {
                message: e.to_string(),
                line: Some(line),
                column: Some(column),
            },
            e => LoadError::plain(e),
        }
    }
}

/// The command line's choices that the scene text does not override.
#[derive(Debug, Clone, Default)]
pub struct PreviewOptions {
    /// Render settings in place of the scene's; `spp` is the samples per pixel the preview
    /// accumulates, by default the scene's, at least [`DEFAULT_SPP`].
    pub settings: SettingValues,
    pub threads: Option<u32>,
    /// A public server's visitor's preview: at most [`PUBLIC_MAX_PIXELS`] pixels and a scene
    /// of at most [`PUBLIC_MAX_SCENE_BYTES`].
    pub public: bool,
}

/// Most pixels of a public server's previews (1024×1024), each visitor's own.
pub const PUBLIC_MAX_PIXELS: u64 = 1 << 20;

/// Most memory the scene of a public server's visitor's preview may take (its BVH and
/// objects, as `timbre check` estimates them): 256 MiB.
pub const PUBLIC_MAX_SCENE_BYTES: u64 = 256 << 20;

/// Samples per pixel the preview accumulates when neither `--spp` nor the scene asks for more.
pub const DEFAULT_SPP: u32 = 64;

/// One view being accumulated: its camera, the exact sums and how many samples each row has.
struct View {
    camera: Camera,
    sums: Vec<Sum>,
    rows: Vec<u32>,
}

/// A loaded scene and its accumulated samples.
struct Loaded {
    /// As parsed (before trajectories are drawn), to tell whether a change needs a new BVH.
    parsed: SceneDescription,
    scene: Arc<Scene>,
    settings: RenderSettings,
    views: Vec<View>,
    /// Passes completed.
    samples: u32,
    /// What is shown where a view has no sample yet: the coarse picture of each view, at full
    /// size (an autostereogram, which has no views: the coarse picture, then the finished one).
    shown: Vec<Image>,
}

/// What is seen through a pixel centre.
#[derive(Debug, Clone, PartialEq)]
pub struct Inspection {
    pub object: String,
    /// The object's index in the scene's object order (the `object.id` AOV).
    pub id: usize,
    pub surface: &'static str,
    /// Distance along the ray.
    pub distance: f64,
    pub point: DVec3,
    pub normal: DVec3,
    /// Which copy in an array (0 outside arrays), and which part of the shape.
    pub element: u32,
    pub part: u32,
    /// `"scene"` or `"camera"`: the frame the object is at rest in.
    pub frame: &'static str,
}

/// The preview's state: the Embree device, the scene file's path (which locates its includes
/// and meshes), and the loaded scene.
pub struct Preview {
    device: Device,
    path: PathBuf,
    options: PreviewOptions,
    loaded: Option<Loaded>,
    /// The frame of the scene's `[animation]` shown (the last frame where the movie is
    /// shorter); `None`, or a scene without one: the scene as written.
    pub frame: Option<u32>,
}

impl Preview {
    pub fn new(path: PathBuf, options: PreviewOptions) -> Result<Preview, String> {
        let threads = options.threads.map(|t| t as usize);
        let device = prepare::device(threads).map_err(|e| e.to_string())?;
        Ok(Preview {
            device,
            path,
            options,
            loaded: None,
            frame: None,
        })
    }

    /// The scene as `timbre render` would read `text` (the scene file's contents) with
    /// `overrides` (reading only the files `confinement` allows, if given), at the frame shown
    /// (as `timbre render --frame K` renders it), and the settings the preview renders it with.
    /// A failure leaves the loaded scene as it was.
    pub fn describe(
        &self,
        text: &str,
        overrides: &[Override],
        confinement: Option<&Confinement>,
    ) -> Result<(SceneDescription, RenderSettings), LoadError> {
        let path = self.path.display().to_string();
        let parse = |overrides: &[Override]| {
            match confinement {
                Some(c) => file::parse_confined(text, &path, overrides, c),
                None => file::parse_with(text, &path, overrides),
            }
            .map_err(|e| LoadError::of(e, &path))
        };
        let mut description = parse(overrides)?;
        if let (Some(k), Some(animation)) =
            (shown(self.frame, &description), &description.animation)
        {
            // As `timbre render --frame K` does, a --set of an animated value is refused.
            if let Some((o, track)) = overrides
                .iter()
                .find_map(|o| animation.clash(o).map(|t| (o, t)))
            {
                return Err(LoadError::plain(format!(
                    "--set {o}: '{}' is animated by the scene's [animation], whose frame {k} is \
                     shown (change its keyframes, or show the scene as written)",
                    track.key()
                )));
            }
            let at_frame = animation.overrides(k);
            description = parse(&[overrides, &at_frame].concat()).map_err(|e| LoadError {
                message: format!("frame {k} of the [animation]: {}", e.message),
                ..e
            })?;
        }
        let mut s = description.render.clone();
        let o = &self.options;
        if !o.settings.gives("spp") {
            s.spp = s.spp.max(DEFAULT_SPP);
        }
        o.settings.apply_over(&mut s);
        s.threads = o.threads.map(|t| t as usize);
        s.aovs = false;
        prepare::check_settings(&s, &description.stereo).map_err(LoadError::plain)?;
        if s.width as u64 * s.height as u64 > MAX_PREVIEW_PIXELS {
            return Err(LoadError::plain(format!(
                "a preview of {}x{} pixels is larger than the limit of {MAX_PREVIEW_PIXELS} pixels (4096x4096): choose a smaller --width and --height for the preview; `timbre render` renders any size",
                s.width, s.height
            )));
        }
        if o.public && matches!(description.stereo, Stereo::Autostereogram { .. }) {
            return Err(LoadError::plain(
                "a public server previews no autostereograms (they render on every core)",
            ));
        }
        if o.public && s.width as u64 * s.height as u64 > PUBLIC_MAX_PIXELS {
            return Err(LoadError::plain(format!(
                "a preview of {}x{} pixels is larger than a public server's limit of {PUBLIC_MAX_PIXELS} pixels (1024x1024) a visitor",
                s.width, s.height
            )));
        }
        Ok((description, s))
    }

    /// Loads the scene `text` with `overrides` (its files confined by `confinement`, if given)
    /// and starts accumulating afresh. The BVH is kept when only the camera, the output or the
    /// render settings changed. A preview that would need more memory than can be had is
    /// refused before anything is built.
    pub fn load(
        &mut self,
        text: &str,
        overrides: &[Override],
        confinement: Option<&Confinement>,
    ) -> Result<(), LoadError> {
        let (parsed, settings) = self.describe(text, overrides, confinement)?;
        let n = settings.width as usize * settings.height as usize;
        let keep = matches!(&self.loaded, Some(old) if old.parsed.same_objects(&parsed));
        // Each view's sums, and the picture made of them.
        let views = parsed.stereo.views() as u64;
        let image = n as u64 * views * std::mem::size_of::<Sum>() as u64
            + stereo::memory_needed(false, &parsed.stereo, n as u64);
        let threads = settings.threads.unwrap_or_else(prepare::default_threads) as u64;
        let needs = Needs {
            what: format!("a {}x{} preview", settings.width, settings.height),
            image,
            // The render threads of an earlier preview are mapped already, and stay.
            reserve: match self.loaded {
                Some(_) => 0,
                None => memory::reserve(threads),
            },
        };
        let scene_bytes = if keep { 0 } else { parsed.build_memory() };
        if self.options.public && parsed.build_memory() > PUBLIC_MAX_SCENE_BYTES {
            return Err(LoadError::plain(format!(
                "the scene needs {} MiB, more than a public server's {} MiB a visitor",
                parsed.build_memory() >> 20,
                PUBLIC_MAX_SCENE_BYTES >> 20
            )));
        }
        prepare::check_memory(&needs, scene_bytes).map_err(LoadError::plain)?;
        let built = if keep {
            None
        } else {
            let scene = prepare::build(&self.device, &parsed).map_err(|e| match e {
                PrepareError::Trajectories(e) => LoadError::plain(format!("ray trajectories: {e}")),
                e => LoadError::plain(e),
            })?;
            Some(scene)
        };
        let camera = &parsed.camera;
        let cameras = match &parsed.stereo {
            Stereo::Mono => vec![camera.clone()],
            Stereo::Anaglyph { eye_separation, .. }
            | Stereo::FramePacking { eye_separation, .. } => vec![
                camera.eye(-0.5 * *eye_separation),
                camera.eye(0.5 * *eye_separation),
            ],
            // Made whole in one pass.
            Stereo::Autostereogram { .. } => Vec::new(),
        };
        let mut views = Vec::new();
        for camera in cameras {
            let mut sums = Vec::new();
            sums.try_reserve_exact(n).map_err(|_| {
                LoadError::plain(format!(
                    "not enough memory for a preview of {}x{} pixels",
                    settings.width, settings.height
                ))
            })?;
            sums.resize(n, Sum::default());
            views.push(View {
                camera,
                sums,
                rows: vec![0; settings.height as usize],
            });
        }
        let scene = match built {
            Some(scene) => Arc::new(scene),
            None => self.loaded.take().expect("a loaded scene to keep").scene,
        };
        self.loaded = Some(Loaded {
            parsed,
            scene,
            settings,
            views,
            samples: 0,
            shown: Vec::new(),
        });
        Ok(())
    }

    /// The scene loaded last, as parsed.
    pub fn description(&self) -> Option<&SceneDescription> {
        self.loaded.as_ref().map(|l| &l.parsed)
    }

    /// The frame of the loaded scene's `[animation]` shown, if one is, and the `--set`s that
    /// make it.
    pub fn shown_frame(&self) -> Option<(u32, Vec<Override>)> {
        let description = self.description()?;
        let k = shown(self.frame, description)?;
        Some((k, frame_overrides(self.frame, description)))
    }

    /// The scene loaded last, built (shared, so that a render to a file can go on beside the
    /// preview).
    pub fn scene(&self) -> Option<Arc<Scene>> {
        self.loaded.as_ref().map(|l| l.scene.clone())
    }

    /// The settings the preview renders with (`spp`: the samples it accumulates).
    pub fn settings(&self) -> Option<&RenderSettings> {
        self.loaded.as_ref().map(|l| &l.settings)
    }

    /// Passes completed, and how many there will be.
    pub fn progress(&self) -> (u32, u32) {
        self.loaded.as_ref().map_or((0, 0), |l| {
            let target = if l.views.is_empty() {
                1
            } else {
                l.settings.spp
            };
            (l.samples, target)
        })
    }

    /// Whether more passes are to come.
    pub fn accumulating(&self) -> bool {
        let (done, target) = self.progress();
        done < target
    }

    /// Renders the coarse picture (about [`COARSE_PIXELS`] pixels a view, each standing for a
    /// square of the image) and returns the picture with it.
    pub fn coarse(&mut self) -> Result<Option<Image>, String> {
        let Some(l) = self.loaded.as_mut() else {
            return Ok(None);
        };
        let s = &l.settings;
        let pixels = s.width as u64 * s.height as u64;
        let f = ((pixels as f64 / COARSE_PIXELS as f64).sqrt().ceil() as u32).max(2);
        let small = RenderSettings {
            width: s.width.div_ceil(f),
            height: s.height.div_ceil(f),
            spp: 1,
            ..s.clone()
        };
        if small.width < 2 || small.height < 2 {
            return Ok(None);
        }
        let coarse = |image: Image| enlarge(&image, f, s.width, s.height);
        l.shown = if l.views.is_empty() {
            let image = render_stereo(
                &l.scene,
                &l.parsed.camera,
                &small,
                &l.parsed.stereo,
                &|_| {},
            )
            .map_err(|e| e.to_string())?;
            vec![coarse(image)]
        } else {
            l.views
                .iter()
                .map(|v| render::render(&l.scene, &v.camera, &small, &|_| {}).map(coarse))
                .collect::<Result<_, _>>()
                .map_err(|e| e.to_string())?
        };
        Ok(Some(picture(l, &l.views)))
    }

    /// Renders the next pass (sample k of every pixel), adding it to the sums; `frame` is shown
    /// the picture so far, with the passes done and to do, about every [`FRAME_INTERVAL`] and
    /// at the end. Returns whether the pass completed: it stops early (its finished rows
    /// kept) when `stop` is set.
    pub fn pass(
        &mut self,
        stop: &AtomicBool,
        frame: &mut dyn FnMut(Image, (u32, u32)),
    ) -> Result<bool, String> {
        let Some(l) = self.loaded.as_mut() else {
            return Ok(true);
        };
        let s = l.settings.clone();
        if l.views.is_empty() {
            let image = render_stereo(&l.scene, &l.parsed.camera, &s, &l.parsed.stereo, &|_| {})
                .map_err(|e| e.to_string())?;
            l.shown = vec![image.clone()];
            l.samples = 1;
            frame(image, (1, 1));
            return Ok(true);
        }
        let k = l.samples;
        let first = |_| k;
        let samples = Samples {
            spp: s.spp,
            start: k,
            end: k + 1,
            first: &first,
            sums: true,
        };
        let bounds = PixelBounds::full(s.width, s.height);
        let mut last = Instant::now();
        // Taken out while they are added to, so that the scene can be read meanwhile.
        let mut views = std::mem::take(&mut l.views);
        let l = &*l;
        let mut complete = true;
        for v in 0..views.len() {
            let camera = views[v].camera.clone();
            let mut sink = |rows: Rows| -> Result<(), std::convert::Infallible> {
                let view = &mut views[v];
                let w = s.width as usize;
                for y in rows.bounds.y0..rows.bounds.y1 {
                    // A row that has sample k already (from a pass that was stopped, whose
                    // scene stayed because the change did not load) keeps it once.
                    if view.rows[y as usize] != k {
                        continue;
                    }
                    view.rows[y as usize] += 1;
                    let r = (y - rows.bounds.y0) as usize * w;
                    let to = &mut view.sums[y as usize * w..(y as usize + 1) * w];
                    for (sum, add) in to.iter_mut().zip(&rows.sums[r..r + w]) {
                        sum.add(add);
                    }
                }
                if views.len() == 1 && last.elapsed() >= FRAME_INTERVAL {
                    frame(picture(l, &views), (k, s.spp));
                    last = Instant::now();
                }
                Ok(())
            };
            let outcome =
                render::render_rows(&l.scene, &camera, &s, bounds, &samples, stop, &mut sink);
            match outcome {
                Ok(Ok(o)) if o.complete => {}
                Ok(Ok(_)) => {
                    complete = false;
                    break;
                }
                Err(e) => {
                    self.loaded.as_mut().expect("loaded").views = views;
                    return Err(e.to_string());
                }
            }
        }
        let l = self.loaded.as_mut().expect("loaded");
        l.views = views;
        if complete {
            l.samples += 1;
            frame(picture(l, &l.views), (l.samples, s.spp));
        }
        Ok(complete)
    }

    /// The picture so far: the accumulated samples' means, the coarse picture where there are
    /// none yet.
    pub fn picture(&self) -> Option<Image> {
        self.loaded.as_ref().map(|l| picture(l, &l.views))
    }

    /// The camera and the pixel of its view that pixel (x, y) of the picture shows: in a packed
    /// frame, the eye's; otherwise the central camera's.
    fn unpack(&self, x: u32, y: u32) -> Option<(&Loaded, &Camera, u32, u32)> {
        let l = self.loaded.as_ref()?;
        let (w, h) = (l.settings.width, l.settings.height);
        let (view, x, y) = match l.parsed.stereo {
            Stereo::FramePacking { packing, half, .. } => match (packing, half) {
                (Packing::SideBySide, false) => (x / w, x % w, y),
                (Packing::SideBySide, true) => (x / (w / 2), x % (w / 2) * 2, y),
                (Packing::TopBottom, false) => (y / h, x, y % h),
                (Packing::TopBottom, true) => (y / (h / 2), x, y % (h / 2) * 2),
            },
            _ => (0, x, y),
        };
        if view > 1 || x >= w || y >= h {
            return None;
        }
        let camera = match &l.parsed.stereo {
            Stereo::FramePacking { .. } => &l.views.get(view as usize)?.camera,
            _ => &l.parsed.camera,
        };
        Some((l, camera, x, y))
    }

    /// What the centre ray of pixel (x, y) of the picture meets first.
    pub fn inspect(&self, x: u32, y: u32) -> Option<Inspection> {
        let (l, camera, x, y) = self.unpack(x, y)?;
        let s = &l.settings;
        let ray = render::centre_ray(&l.scene, camera, s.width, s.height, x, y);
        let tracer = Tracer::new(&l.scene, camera, s.shadows);
        let found = tracer.first(&ray, 0.0, ReferenceFrame::Camera)?;
        let (id, normal) = tracer.identify(&found);
        let object = l.scene.object_names.get(id).cloned().unwrap_or_default();
        // Drawn trajectories are not in the parsed description.
        let surface = l
            .parsed
            .objects
            .get(id)
            .map_or("constant-colour", |o| o.surface.kind());
        Some(Inspection {
            object,
            id,
            surface,
            distance: found.hit.t,
            point: found.ray.at(found.hit.t),
            normal,
            element: found.hit.element,
            part: found.hit.prim,
            frame: match found.frame {
                ReferenceFrame::Scene => "scene",
                ReferenceFrame::Camera => "camera",
            },
        })
    }

    /// The ray through the centre of pixel (x, y) of the picture in the scene frame, for a
    /// ray trajectory: started ahead of the camera (a tile ahead, or halfway to the first
    /// surface if that is nearer) so that its drawn cylinder does not cover the view. None
    /// outside the picture, or where the ray is not finite.
    pub fn pixel_ray(&self, x: u32, y: u32) -> Option<Ray> {
        let (l, camera, x, y) = self.unpack(x, y)?;
        let s = &l.settings;
        let ray = camera.to_scene_frame(&render::centre_ray(
            &l.scene, camera, s.width, s.height, x, y,
        ));
        let tracer = Tracer::new(&l.scene, camera, s.shadows);
        let ahead = tracer
            .first(&ray, 0.0, ReferenceFrame::Scene)
            .map_or(1.0, |f| (0.5 * f.hit.t).min(1.0));
        let start = ray.at(ahead);
        (start.is_finite() && ray.direction.is_finite())
            .then(|| Ray::new(start, ray.direction, ray.time))
    }
}

/// `image` enlarged `f` times (each pixel a square), cut to `width` × `height`.
fn enlarge(image: &Image, f: u32, width: u32, height: u32) -> Image {
    let pixels = (0..height)
        .flat_map(|y| (0..width).map(move |x| (x, y)))
        .map(|(x, y)| image.pixel((x / f).min(image.width - 1), (y / f).min(image.height - 1)))
        .collect();
    Image {
        width,
        height,
        pixels,
        aovs: None,
        rays: image.rays,
    }
}

/// The accumulated means of every view (the coarse picture where a row has no sample yet),
/// combined as the scene's stereo output asks.
fn picture(l: &Loaded, views: &[View]) -> Image {
    let s = &l.settings;
    let view = |k: usize, v: &View| {
        let w = s.width as usize;
        let pixels = (0..s.height as usize)
            .flat_map(|y| {
                let n = v.rows[y];
                v.sums[y * w..(y + 1) * w]
                    .iter()
                    .enumerate()
                    .map(move |(x, sum)| match (n, l.shown.get(k)) {
                        (0, Some(shown)) => shown.pixel(x as u32, y as u32),
                        (0, None) => Colour::ZERO,
                        (n, _) => sum.mean(n),
                    })
            })
            .collect();
        Image {
            width: s.width,
            height: s.height,
            pixels,
            aovs: None,
            rays: 0,
        }
    };
    match (&l.parsed.stereo, views) {
        (_, []) => l.shown.first().cloned().unwrap_or_else(|| Image {
            width: s.width,
            height: s.height,
            pixels: vec![Colour::ZERO; s.width as usize * s.height as usize],
            aovs: None,
            rays: 0,
        }),
        (Stereo::Anaglyph { colour, .. }, [left, right]) => {
            anaglyph(&view(0, left), &view(1, right), *colour)
        }
        (Stereo::FramePacking { packing, half, .. }, [left, right]) => {
            pack(&view(0, left), &view(1, right), *packing, *half)
        }
        (_, views) => view(0, &views[0]),
    }
}

/// The frame of `description`'s `[animation]` that `frame` shows: at most its last.
fn shown(frame: Option<u32>, description: &SceneDescription) -> Option<u32> {
    let animation = description.animation.as_ref()?;
    Some(frame?.min(animation.frames - 1))
}

/// The `--set`s that make the frame `frame` shows of `description` (none for the scene as
/// written).
fn frame_overrides(frame: Option<u32>, description: &SceneDescription) -> Vec<Override> {
    match (shown(frame, description), &description.animation) {
        (Some(k), Some(animation)) => animation.overrides(k),
        _ => Vec::new(),
    }
}
