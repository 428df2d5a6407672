//! `timbre._timbre`: the native half of timbre's Python package (python/timbre/ is the other).
//!
//! A [`NativeScene`] is a scene file's text (or its path) with `--set` overrides, parsed by the
//! same code as the command line's; its BVH is built once and kept until an override changes
//! it. Renders run with the GIL released on timbre's own threads while the calling thread
//! reports progress and checks for Ctrl-C; the pixels are the f32 values the command line writes
//! to an OpenEXR file.

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::Duration;

use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray3, PyUntypedArrayMethods};
use pyo3::IntoPyObjectExt;
use pyo3::create_exception;
use pyo3::exceptions::{
    PyFileNotFoundError, PyKeyError, PyMemoryError, PyOSError, PyRuntimeError, PyValueError,
};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict, PyList};

use timbre::embree::Device;
use timbre::math::Colour;
use timbre::render::{Image, PixelBounds, RenderError, render_part};
use timbre::scene::file::{self, Override, SceneFileError};
use timbre::scene::{RenderSettings, Scene, SceneDescription, Stereo};
use timbre::stereo::{self, render_stereo_until};
use timbre::trajectories::{self, TrajectoryError};

create_exception!(
    timbre,
    SceneError,
    PyValueError,
    "A scene that timbre cannot use: `path`, `line` and `column` (from 1) say where, when known."
);

/// How often a waiting render reports progress and looks for Ctrl-C.
const POLL: Duration = Duration::from_millis(50);

/// Most worker threads a render may ask for (as `timbre render --threads`).
const MAX_THREADS: u32 = 1024;

/// Where a scene's text comes from.
#[derive(Clone)]
enum Source {
    File(PathBuf),
    /// Text, with the name that stands for it in messages (relative paths in it are relative to
    /// the working directory).
    Text {
        text: String,
        name: String,
    },
}

impl Source {
    fn parse(&self, overrides: &[Override]) -> Result<SceneDescription, SceneFileError> {
        match self {
            Source::File(path) => file::load_with(path, overrides),
            Source::Text { text, name } => file::parse_with(text, name, overrides),
        }
    }

    fn name(&self) -> String {
        match self {
            Source::File(path) => path.display().to_string(),
            Source::Text { name, .. } => name.clone(),
        }
    }
}

/// A scene with its BVH.
struct Built {
    scene: Scene,
    /// Kept for the scene's lifetime (Embree's scenes belong to it).
    _device: Device,
}

struct State {
    source: Source,
    overrides: Vec<Override>,
    description: SceneDescription,
    /// Built on the first render after a change.
    built: Option<Arc<Built>>,
}

/// A scene file's text with `--set` overrides, parsed, and its BVH once built.
#[pyclass(module = "timbre._timbre", frozen)]
struct NativeScene {
    state: Mutex<State>,
}

/// `SceneError` with its message and place.
fn located(
    py: Python<'_>,
    message: String,
    path: String,
    line: Option<usize>,
    column: Option<usize>,
) -> PyErr {
    let err = SceneError::new_err(message);
    let value = err.value(py);
    let set = || -> PyResult<()> {
        value.setattr("path", path)?;
        value.setattr("line", line)?;
        value.setattr("column", column)
    };
    match set() {
        Ok(()) => err,
        Err(e) => e,
    }
}

/// `SceneError` for a scene file's error, with its place; the file's absence as
/// `FileNotFoundError`, other failures to read it as `OSError`.
fn scene_error(py: Python<'_>, e: SceneFileError) -> PyErr {
    let message = e.to_string();
    match e {
        SceneFileError::Io { source, .. } if source.kind() == std::io::ErrorKind::NotFound => {
            PyFileNotFoundError::new_err(message)
        }
        SceneFileError::Io { .. } => PyOSError::new_err(message),
        SceneFileError::Invalid {
            path, line, column, ..
        } => located(py, message, path, Some(line), Some(column)),
        SceneFileError::Overridden { path, .. } => located(py, message, path, None, None),
    }
}

/// A message about the scene `source` (not at a place in its text) as `SceneError`.
fn about_scene(py: Python<'_>, source: &Source, message: impl std::fmt::Display) -> PyErr {
    let path = source.name();
    located(py, format!("{path}: {message}"), path, None, None)
}

fn parse_overrides(set: Vec<String>) -> PyResult<Vec<Override>> {
    set.iter()
        .map(|s| s.parse::<Override>().map_err(PyValueError::new_err))
        .collect()
}

fn render_error(e: RenderError) -> PyErr {
    match e {
        RenderError::Memory { .. } => PyMemoryError::new_err(e.to_string()),
        e => PyRuntimeError::new_err(e.to_string()),
    }
}

impl NativeScene {
    fn state(&self) -> MutexGuard<'_, State> {
        // A panic while holding the lock leaves a consistent state (every change is made whole).
        self.state.lock().unwrap_or_else(|p| p.into_inner())
    }

    fn open(py: Python<'_>, source: Source, set: Vec<String>) -> PyResult<NativeScene> {
        let overrides = parse_overrides(set)?;
        let description = py
            .detach(|| source.parse(&overrides))
            .map_err(|e| scene_error(py, e))?;
        Ok(NativeScene {
            state: Mutex::new(State {
                source,
                overrides,
                description,
                built: None,
            }),
        })
    }

    /// The scene with its BVH, built now if it is not yet.
    fn built(&self, py: Python<'_>) -> PyResult<(Arc<Built>, SceneDescription)> {
        let (source, description, built) = {
            let state = self.state();
            (
                state.source.clone(),
                state.description.clone(),
                state.built.clone(),
            )
        };
        if let Some(built) = built {
            return Ok((built, description));
        }
        let made = py.detach(|| -> Result<Built, Result<TrajectoryError, String>> {
            let device = Device::new("").map_err(|e| Err(e.to_string()))?;
            let drawn = trajectories::draw(&device, &description).map_err(Ok)?;
            let scene = Scene::build(&device, &drawn).map_err(|e| Err(e.to_string()))?;
            Ok(Built {
                scene,
                _device: device,
            })
        });
        let built = Arc::new(match made {
            Ok(b) => b,
            Err(Ok(TrajectoryError::Embree(e))) => {
                return Err(PyRuntimeError::new_err(e.to_string()));
            }
            Err(Ok(e)) => return Err(about_scene(py, &source, e)),
            Err(Err(e)) => return Err(PyRuntimeError::new_err(e)),
        });
        let mut state = self.state();
        // Kept unless the scene changed meanwhile.
        if state.description == description {
            state.built = Some(built.clone());
        }
        Ok((built, description))
    }
}

/// Runs `work` on its own thread with the GIL released, while this thread passes the pixels
/// finished to `progress` (with the GIL) and looks for Ctrl-C and other signals, about every
/// 50 ms. A signal's exception (KeyboardInterrupt) or the callback's stops the work and is
/// raised once the work has stopped.
fn interruptible<T: Send>(
    py: Python<'_>,
    progress: Option<&Bound<'_, PyAny>>,
    work: impl FnOnce(&AtomicBool, &(dyn Fn(u64) + Sync)) -> T + Send,
) -> PyResult<T> {
    let stop = AtomicBool::new(false);
    let done = AtomicU64::new(0);
    let add = |n: u64| {
        done.fetch_add(n, Ordering::Relaxed);
    };
    std::thread::scope(|s| {
        let worker = std::thread::Builder::new()
            .name("timbre-render".into())
            .spawn_scoped(s, || work(&stop, &add))
            .map_err(|e| {
                PyRuntimeError::new_err(format!("could not start a render thread: {e}"))
            })?;
        let mut reported = 0;
        let mut failure = None;
        loop {
            let finished = worker.is_finished();
            if failure.is_none() {
                let now = done.load(Ordering::Relaxed);
                let told = match progress {
                    Some(callback) if now > reported => callback.call1((now - reported,)).map(drop),
                    _ => Ok(()),
                };
                reported = now;
                if let Err(e) = told.and_then(|()| py.check_signals()) {
                    stop.store(true, Ordering::Relaxed);
                    failure = Some(e);
                }
            }
            if finished {
                break;
            }
            py.detach(|| std::thread::park_timeout(POLL));
        }
        let result = worker
            .join()
            .map_err(|_| PyRuntimeError::new_err("the render thread panicked"))?;
        match failure {
            Some(e) => Err(e),
            None => Ok(result),
        }
    })
}

/// An image's colours as a float32 array of shape (height, width, 3): each channel as the
/// command line writes it to OpenEXR (the f64 mean rounded to f32).
fn rgb<'py>(py: Python<'py>, image: &Image) -> PyResult<Bound<'py, PyAny>> {
    let values: Vec<f32> = image
        .pixels
        .iter()
        .flat_map(|c: &Colour| c.to_array().map(|v| v as f32))
        .collect();
    let shape = [image.height as usize, image.width as usize, 3];
    Ok(PyArray1::from_vec(py, values).reshape(shape)?.into_any())
}

/// The AOVs of `image` as arrays: `depth` (h, w), `normal` (h, w, 3), `object` (h, w).
fn aov_arrays<'py>(py: Python<'py>, image: &Image, out: &Bound<'py, PyDict>) -> PyResult<()> {
    let Some(aovs) = &image.aovs else {
        return Ok(());
    };
    let (h, w) = (image.height as usize, image.width as usize);
    let depth: Vec<f32> = aovs.iter().map(|a| a.depth).collect();
    let normal: Vec<f32> = aovs.iter().flat_map(|a| a.normal.to_array()).collect();
    let object: Vec<f32> = aovs.iter().map(|a| a.object).collect();
    out.set_item("depth", PyArray1::from_vec(py, depth).reshape([h, w])?)?;
    out.set_item("normal", PyArray1::from_vec(py, normal).reshape([h, w, 3])?)?;
    out.set_item("object", PyArray1::from_vec(py, object).reshape([h, w])?)?;
    Ok(())
}

/// A TOML value as Python's numbers, bools, strings, lists and dicts (a date as its text).
fn to_python(py: Python<'_>, value: toml::Value) -> PyResult<Bound<'_, PyAny>> {
    match value {
        toml::Value::String(s) => s.into_bound_py_any(py),
        toml::Value::Integer(i) => i.into_bound_py_any(py),
        toml::Value::Float(f) => f.into_bound_py_any(py),
        toml::Value::Boolean(b) => b.into_bound_py_any(py),
        toml::Value::Datetime(d) => d.to_string().into_bound_py_any(py),
        toml::Value::Array(a) => {
            let list = PyList::empty(py);
            for v in a {
                list.append(to_python(py, v)?)?;
            }
            Ok(list.into_any())
        }
        toml::Value::Table(t) => {
            let dict = PyDict::new(py);
            for (k, v) in t {
                dict.set_item(k, to_python(py, v)?)?;
            }
            Ok(dict.into_any())
        }
    }
}

#[pymethods]
impl NativeScene {
    /// The scene file at `path`, with `set` (`KEY=VALUE` strings) applied as `--set`.
    #[staticmethod]
    fn from_file(py: Python<'_>, path: PathBuf, set: Vec<String>) -> PyResult<NativeScene> {
        NativeScene::open(py, Source::File(path), set)
    }

    /// Scene-file text (`name` stands for it in messages), with `set` applied as `--set`.
    #[staticmethod]
    fn from_text(
        py: Python<'_>,
        text: String,
        name: String,
        set: Vec<String>,
    ) -> PyResult<NativeScene> {
        NativeScene::open(py, Source::Text { text, name }, set)
    }

    /// The same scene, overrides and built BVH (shared), to be changed on its own.
    fn copy(&self) -> NativeScene {
        let state = self.state();
        NativeScene {
            state: Mutex::new(State {
                source: state.source.clone(),
                overrides: state.overrides.clone(),
                description: state.description.clone(),
                built: state.built.clone(),
            }),
        }
    }

    /// Replaces the overrides (`KEY=VALUE` strings, applied in order) if the scene with them
    /// is valid; the scene is left as it was otherwise.
    fn set_overrides(&self, py: Python<'_>, set: Vec<String>) -> PyResult<()> {
        let overrides = parse_overrides(set)?;
        let source = self.state().source.clone();
        let description = py
            .detach(|| source.parse(&overrides))
            .map_err(|e| scene_error(py, e))?;
        let mut state = self.state();
        if state.description != description {
            state.built = None;
        }
        state.description = description;
        state.overrides = overrides;
        Ok(())
    }

    /// The name of the scene in messages: the file's path, or the name given to its text.
    fn name(&self) -> String {
        self.state().source.name()
    }

    /// The scene text with the overrides applied (TOML), for a scene given as text or a file.
    fn text(&self) -> PyResult<String> {
        let state = self.state();
        let text = match &state.source {
            Source::File(path) => std::fs::read_to_string(path)
                .map_err(|e| PyOSError::new_err(format!("{}: {e}", path.display())))?,
            Source::Text { text, .. } => text.clone(),
        };
        file::with_overrides(&text, &state.overrides).map_err(PyValueError::new_err)
    }

    /// The value at `key` (a dotted path, as `--set` takes) in the scene text with the
    /// overrides applied; `KeyError` where the text has none.
    fn get<'py>(&self, py: Python<'py>, key: &str) -> PyResult<Bound<'py, PyAny>> {
        let table: toml::Table = self
            .text()?
            .parse()
            .map_err(|e: toml::de::Error| PyValueError::new_err(e.to_string()))?;
        let mut value = toml::Value::Table(table);
        for part in key.split('.').map(str::trim) {
            let inner = match value {
                toml::Value::Table(mut t) => t.remove(part),
                toml::Value::Array(mut a) => match part.parse::<usize>() {
                    Ok(i) if i < a.len() => Some(a.swap_remove(i)),
                    _ => None,
                },
                _ => None,
            };
            value = inner.ok_or_else(|| PyKeyError::new_err(key.to_string()))?;
        }
        to_python(py, value)
    }

    /// The render settings of the scene (width, height, spp, seed, max_trace_level, shadows),
    /// its stereo output (`camera.stereo`) and the number of views that renders.
    fn settings<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let state = self.state();
        let s = &state.description.render;
        let d = PyDict::new(py);
        d.set_item("width", s.width)?;
        d.set_item("height", s.height)?;
        d.set_item("spp", s.spp)?;
        d.set_item("seed", s.seed)?;
        d.set_item("max_trace_level", s.max_trace_level)?;
        d.set_item("shadows", s.shadows)?;
        d.set_item("stereo", state.description.stereo.name())?;
        d.set_item("views", state.description.stereo.views())?;
        Ok(d)
    }

    /// The objects' names, in the scene's order (the `object` AOV's ids).
    fn object_names(&self) -> Vec<String> {
        let state = self.state();
        state
            .description
            .objects
            .iter()
            .map(|o| o.name.clone())
            .collect()
    }

    /// What is questionable about the scene (as `timbre render` warns).
    fn warnings(&self) -> Vec<String> {
        self.state().description.warnings()
    }

    /// The scene's hash: what parts of a render record to be merged (`timbre.scene` in EXR).
    fn hash(&self) -> String {
        self.state().description.hash()
    }

    /// Renders the scene (arguments in place of the scene's `[render]` values, as `timbre
    /// render`'s options) and returns a dict: `rgb` (float32, (h, w, 3)), the AOVs asked for,
    /// and `rays`.
    #[pyo3(signature = (*, width=None, height=None, spp=None, seed=None, threads=None,
        max_trace_level=None, aovs=false, pixel_bounds=None, progress=None))]
    #[allow(clippy::too_many_arguments)]
    fn render<'py>(
        &self,
        py: Python<'py>,
        width: Option<u32>,
        height: Option<u32>,
        spp: Option<u32>,
        seed: Option<u64>,
        threads: Option<u32>,
        max_trace_level: Option<u32>,
        aovs: bool,
        pixel_bounds: Option<(u32, u32, u32, u32)>,
        progress: Option<Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let (source, description) = {
            let state = self.state();
            (state.source.clone(), state.description.clone())
        };
        let mut settings: RenderSettings = description.render.clone();
        settings.width = width.unwrap_or(settings.width);
        settings.height = height.unwrap_or(settings.height);
        settings.spp = spp.unwrap_or(settings.spp);
        settings.seed = seed.unwrap_or(settings.seed);
        settings.max_trace_level = max_trace_level.unwrap_or(settings.max_trace_level);
        settings.aovs = aovs;
        if let Some(t) = threads {
            if !(1..=MAX_THREADS).contains(&t) {
                return Err(PyValueError::new_err(format!(
                    "threads must be from 1 to {MAX_THREADS}, got {t}"
                )));
            }
            settings.threads = Some(t as usize);
        }
        settings.validate().map_err(PyValueError::new_err)?;
        let stereo = &description.stereo;
        stereo::validate(stereo, settings.width, settings.height)
            .map_err(|m| about_scene(py, &source, m))?;
        let full = PixelBounds::full(settings.width, settings.height);
        let bounds = match pixel_bounds {
            None => full,
            Some((x0, x1, y0, y1)) => {
                let b = PixelBounds { x0, x1, y0, y1 };
                if b.is_empty() || !full.contains(&b) {
                    return Err(PyValueError::new_err(format!(
                        "pixel_bounds ({x0}, {x1}, {y0}, {y1}) are not pixels of the {}x{} image: x0 < x1 <= width and y0 < y1 <= height are needed",
                        settings.width, settings.height
                    )));
                }
                b
            }
        };
        if *stereo != Stereo::Mono && (aovs || bounds != full) {
            return Err(PyValueError::new_err(
                "aovs and pixel_bounds work with single views only (camera.stereo = \"none\")",
            ));
        }
        let (built, description) = self.built(py)?;
        let camera = &description.camera;
        let rendered = interruptible(py, progress.as_ref(), |stop, progress| {
            let scene = &built.scene;
            match stereo {
                Stereo::Mono => render_part(scene, camera, &settings, bounds, stop, progress),
                _ => render_stereo_until(scene, camera, &settings, stereo, stop, progress),
            }
        })?;
        // Stopped only by an exception, which `interruptible` raises.
        let image = rendered
            .map_err(render_error)?
            .ok_or_else(|| PyRuntimeError::new_err("the render stopped"))?;
        let out = PyDict::new(py);
        out.set_item("rgb", rgb(py, &image)?)?;
        aov_arrays(py, &image, &out)?;
        out.set_item("rays", image.rays)?;
        Ok(out)
    }

    /// The ray trajectories of the scene, traced: one dict per ray with `trajectory` (its
    /// name), `ray` (its index), `points` (float64, (n, 3)), `arrivals`, `objects` (a name or
    /// None per point), `end` and `direction`.
    fn trajectories<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let (source, description) = {
            let state = self.state();
            (state.source.clone(), state.description.clone())
        };
        let traced = py.detach(|| -> Result<_, Result<TrajectoryError, String>> {
            let device = Device::new("").map_err(|e| Err(e.to_string()))?;
            trajectories::trace(&device, &description).map_err(Ok)
        });
        let traced = match traced {
            Ok(t) => t,
            Err(Ok(TrajectoryError::Embree(e))) => {
                return Err(PyRuntimeError::new_err(e.to_string()));
            }
            Err(Ok(e)) => return Err(about_scene(py, &source, e)),
            Err(Err(e)) => return Err(PyRuntimeError::new_err(e)),
        };
        let list = PyList::empty(py);
        for t in &traced {
            let d = PyDict::new(py);
            d.set_item("trajectory", &description.trajectories[t.source].name)?;
            d.set_item("ray", t.ray)?;
            let xyz: Vec<f64> = t
                .points
                .iter()
                .flat_map(|p| p.position.to_array())
                .collect();
            let points = PyArray1::from_vec(py, xyz).reshape([t.points.len(), 3])?;
            d.set_item("points", points)?;
            let arrivals: Vec<&str> = t.points.iter().map(|p| p.arrival.name()).collect();
            d.set_item("arrivals", arrivals)?;
            let objects: Vec<Option<&str>> = t
                .points
                .iter()
                .map(|p| p.object.map(|i| description.objects[i].name.as_str()))
                .collect();
            d.set_item("objects", objects)?;
            d.set_item("end", t.end.name())?;
            d.set_item(
                "direction",
                PyArray1::from_vec(py, t.direction.to_array().to_vec()),
            )?;
            list.append(d)?;
        }
        Ok(list)
    }
}

/// A float32 (h, w, 3) array of linear colours as the image the command line writes to PNG
/// (each channel clamped to [0, 1], times 255, rounded; no gamma).
fn rgb8_image(rgb: &PyReadonlyArray3<'_, f32>) -> PyResult<image::RgbImage> {
    let shape = rgb.shape();
    let (height, width) = (shape[0], shape[1]);
    if shape[2] != 3 || u32::try_from(width).is_err() || u32::try_from(height).is_err() {
        return Err(PyValueError::new_err(format!(
            "an array of shape {shape:?} is not an image's colours: (height, width, 3) is needed"
        )));
    }
    let pixels = rgb
        .as_array()
        .rows()
        .into_iter()
        .map(|c| Colour::new(c[0] as f64, c[1] as f64, c[2] as f64))
        .collect();
    let image = Image {
        width: width as u32,
        height: height as u32,
        pixels,
        aovs: None,
        rays: 0,
    };
    Ok(timbre::io::to_rgb8(&image))
}

/// The 8-bit (h, w, 3) uint8 array of a float32 (h, w, 3) image, as the command line's PNG.
#[pyfunction]
fn rgb8<'py>(py: Python<'py>, rgb: PyReadonlyArray3<'py, f32>) -> PyResult<Bound<'py, PyAny>> {
    let image = rgb8_image(&rgb)?;
    let shape = [image.height() as usize, image.width() as usize, 3];
    Ok(PyArray1::from_vec(py, image.into_raw())
        .reshape(shape)?
        .into_any())
}

/// A float32 (h, w, 3) image as the PNG file the command line writes.
#[pyfunction]
fn png_bytes<'py>(
    py: Python<'py>,
    rgb: PyReadonlyArray3<'py, f32>,
) -> PyResult<Bound<'py, PyBytes>> {
    let image = rgb8_image(&rgb)?;
    let mut bytes = Vec::new();
    let mut encoder = png::Encoder::new(&mut bytes, image.width(), image.height());
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    encoder
        .write_header()
        .and_then(|mut w| w.write_image_data(&image))
        .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    Ok(PyBytes::new(py, &bytes))
}

/// The version of the Embree library timbre runs on.
#[pyfunction]
fn embree_version() -> PyResult<String> {
    let device = Device::new("").map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    Ok(device.version())
}

#[pymodule]
fn _timbre(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<NativeScene>()?;
    m.add("SceneError", m.py().get_type::<SceneError>())?;
    m.add_function(wrap_pyfunction!(png_bytes, m)?)?;
    m.add_function(wrap_pyfunction!(rgb8, m)?)?;
    m.add_function(wrap_pyfunction!(embree_version, m)?)?;
    Ok(())
}
