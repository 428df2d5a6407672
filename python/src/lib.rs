//! `timbre._timbre`: the native half of timbre's Python package (python/timbre/ is the other).
//!
//! A [`NativeScene`] is a scene file's text (or its path) with `--set` overrides, parsed by the
//! same code as the command line's; its BVH is built once and kept until an override changes
//! it. Renders run with the GIL released on timbre's own threads while the calling thread
//! reports progress and checks for Ctrl-C; the pixels are the f32 values the command line writes
//! to an OpenEXR file.

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::mpsc::{self, RecvTimeoutError};
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::Duration;

use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray3, PyUntypedArrayMethods};
use pyo3::IntoPyObjectExt;
use pyo3::PyTypeInfo;
use pyo3::create_exception;
use pyo3::exceptions::{
    PyFileNotFoundError, PyKeyError, PyMemoryError, PyOSError, PyRuntimeError, PyValueError,
};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict, PyList};

use timbre::embree::Device;
use timbre::math::Colour;
use timbre::memory;
use timbre::prepare::{self, Needs, PrepareError};
use timbre::render::{AovSample, Image, PixelBounds, RenderError, render_part};
use timbre::scene::file::{self, Override, SceneFileError};
use timbre::scene::settings::{Kind, PngTransfer, SETTINGS, Setting, SettingValues, Value};
use timbre::scene::{RenderSettings, Scene, SceneDescription, Stereo};
use timbre::stereo::{self, render_stereo_until};
use timbre::trajectories::{self, Trajectory, TrajectoryError};

create_exception!(
    timbre,
    SceneError,
    PyValueError,
    "A scene that timbre cannot use: `path`, `line` and `column` (from 1) say where, when known."
);

/// How often a waiting thread reports progress and looks for Ctrl-C.
const POLL: Duration = Duration::from_millis(50);

/// Most worker threads a render may ask for (as `timbre render --threads`).
const MAX_THREADS: u32 = 1024;

/// The AOVs a render can add, and their channels.
const AOVS: [(&str, usize); 4] = [("depth", 1), ("normal", 3), ("object", 1), ("albedo", 3)];

/// A scene's text, read once, and the name that stands for it in messages and locates the
/// relative paths in it: a file's path, or `<text>` (the working directory).
struct Source {
    text: String,
    name: String,
}

impl Source {
    fn parse(&self, overrides: &[Override]) -> Result<SceneDescription, SceneFileError> {
        file::parse_with(&self.text, &self.name, overrides)
    }
}

/// A scene with its BVH.
struct Built {
    scene: Scene,
    /// Kept for the scene's lifetime (Embree's scenes belong to it).
    _device: Device,
}

/// One version of a scene: what a render or a question works on throughout.
#[derive(Clone)]
struct State {
    source: Arc<Source>,
    overrides: Vec<Override>,
    description: Arc<SceneDescription>,
    /// Built on the first render that needs it; kept while the objects stay the same.
    built: Option<Arc<Built>>,
}

/// A scene file's text with `--set` overrides, parsed, and its BVH once built.
///
/// The lock is only ever held for moments, never while calling Python or waiting for it.
#[pyclass(module = "timbre._timbre", frozen)]
struct NativeScene {
    state: Mutex<State>,
}

/// An exception of type `E` whose message is made safe to print as the CLI's messages are
/// (`timbre::text::printable`): an uncaught traceback cannot drive the terminal.
fn error<E: PyTypeInfo>(message: impl std::fmt::Display) -> PyErr {
    PyErr::new::<E, _>(timbre::text::printable(&message.to_string()))
}

/// `SceneError` with its message and place.
fn located(
    py: Python<'_>,
    message: String,
    path: String,
    line: Option<usize>,
    column: Option<usize>,
) -> PyErr {
    let err = error::<SceneError>(message);
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
            error::<PyFileNotFoundError>(message)
        }
        SceneFileError::Io { .. } => error::<PyOSError>(message),
        SceneFileError::Invalid {
            path, line, column, ..
        } => located(py, message, path, Some(line), Some(column)),
        SceneFileError::Overridden { path, .. } => located(py, message, path, None, None),
    }
}

/// A message about the scene `source` (not at a place in its text) as `SceneError`.
fn about_scene(py: Python<'_>, source: &Source, message: impl std::fmt::Display) -> PyErr {
    let path = source.name.clone();
    located(py, format!("{path}: {message}"), path, None, None)
}

/// A trajectory error: Embree's own is timbre's failure, too many points the scene's.
fn trajectory_error(py: Python<'_>, source: &Source, e: TrajectoryError) -> PyErr {
    match e {
        TrajectoryError::Embree(e) => error::<PyRuntimeError>(e.to_string()),
        e => about_scene(py, source, e),
    }
}

/// A scene that could not be made ready, as Python reports it: settings out of range are a
/// ValueError, what needs more memory than can be had a MemoryError, what is wrong in the scene
/// file is about the scene, Embree's failures are a RuntimeError.
fn unprepared(py: Python<'_>, source: &Source, e: PrepareError) -> PyErr {
    match e {
        PrepareError::Settings(m) => error::<PyValueError>(m),
        PrepareError::Stereo(m) => about_scene(py, source, m),
        e @ PrepareError::Memory { .. } => error::<PyMemoryError>(e.to_string()),
        PrepareError::Trajectories(e) => trajectory_error(py, source, e),
        e @ (PrepareError::Embree(_) | PrepareError::Build(_)) => {
            error::<PyRuntimeError>(e.to_string())
        }
    }
}

/// Runs `work` on a thread of its own with the GIL released, and looks for Ctrl-C (and other
/// signals) every 50 ms meanwhile: a signal's exception is raised at once, and the work, which
/// cannot be stopped (loading, building a BVH, tracing trajectories), finishes unseen.
fn detached<T: Send + 'static>(
    py: Python<'_>,
    work: impl FnOnce() -> T + Send + 'static,
) -> PyResult<T> {
    let (send, receive) = mpsc::channel();
    std::thread::Builder::new()
        .name("timbre".into())
        .spawn(move || {
            // Nobody may be waiting any more.
            let _ = send.send(work());
        })
        .map_err(|e| error::<PyRuntimeError>(format!("could not start a thread: {e}")))?;
    let mut receive = Some(receive);
    loop {
        // The receiver goes with the GIL-free closure and comes back (it is not `Sync`).
        let (got, back) = py.detach(move || {
            let r = receive.take().expect("the receiver");
            (r.recv_timeout(POLL), r)
        });
        receive = Some(back);
        match got {
            Ok(done) => return Ok(done),
            Err(RecvTimeoutError::Timeout) => py.check_signals()?,
            Err(RecvTimeoutError::Disconnected) => {
                return Err(error::<PyRuntimeError>("timbre's worker thread panicked"));
            }
        }
    }
}

/// A buffer for `n` values, or `MemoryError` (instead of aborting the process).
fn buffer<T>(n: usize) -> PyResult<Vec<T>> {
    let mut v = Vec::new();
    v.try_reserve_exact(n).map_err(|_| {
        error::<PyMemoryError>(format!(
            "not enough memory for {} MiB of results",
            (n * size_of::<T>()) >> 20
        ))
    })?;
    Ok(v)
}

/// The most render threads a render of this process has had (0 before the first): their stacks
/// and allocator arenas, and Embree's own memory, are mapped already and stay so.
static THREADS_SEEN: AtomicU64 = AtomicU64::new(0);

/// What a render with `threads` threads will map besides its buffers that this process has not
/// mapped yet ([`memory::reserve`] less what earlier renders mapped).
fn memory_reserve(threads: u64) -> u64 {
    match THREADS_SEEN.load(Ordering::Relaxed) {
        0 => memory::reserve(threads),
        seen => memory::reserve(threads).saturating_sub(memory::reserve(seen)),
    }
}

/// The render settings given by key: each one of `SETTINGS`, a whole number or a bool as the
/// setting takes.
fn setting_values(given: &[(String, Bound<'_, PyAny>)]) -> PyResult<SettingValues> {
    let mut values = SettingValues::default();
    for (key, value) in given {
        let setting = Setting::named(key)
            .ok_or_else(|| error::<PyValueError>(format!("no render setting is called '{key}'")))?;
        let value = match setting.kind {
            Kind::Whole { .. } => Value::Whole(value.extract()?),
            Kind::Switch => Value::Switch(value.extract()?),
            Kind::Number { .. } => Value::Number(value.extract()?),
            Kind::Choice(names) => {
                let name: String = value.extract()?;
                match names.iter().find(|&&n| n == name) {
                    Some(&n) => Value::Choice(n),
                    None => {
                        return Err(error::<PyValueError>(format!(
                            "{key}: expected {}, got '{name}'",
                            setting.kind.expected()
                        )));
                    }
                }
            }
        };
        values
            .push(setting, value)
            .map_err(|e| error::<PyValueError>(format!("{key}: {e}")))?;
    }
    Ok(values)
}

/// A render setting's key, kind and range (or names), for Python.
type SettingKind = (&'static str, &'static str, Py<PyAny>, Py<PyAny>);

/// The render settings' keys and kinds, for the Python side: (key, "whole", least, most),
/// (key, "switch", False, True), (key, "number", least, most) or (key, "choice", [names], None).
#[pyfunction]
fn render_settings(py: Python<'_>) -> PyResult<Vec<SettingKind>> {
    let any = |v: Bound<'_, PyAny>| v.unbind();
    SETTINGS
        .iter()
        .map(|s| {
            Ok(match s.kind {
                Kind::Whole { least, most } => (
                    s.key,
                    "whole",
                    any(least.into_pyobject(py)?.into_any()),
                    any(most.into_pyobject(py)?.into_any()),
                ),
                Kind::Switch => (
                    s.key,
                    "switch",
                    any(false.into_pyobject(py)?.to_owned().into_any()),
                    any(true.into_pyobject(py)?.to_owned().into_any()),
                ),
                Kind::Number { least, most } => (
                    s.key,
                    "number",
                    any(least.into_pyobject(py)?.into_any()),
                    any(most.into_pyobject(py)?.into_any()),
                ),
                Kind::Choice(names) => (
                    s.key,
                    "choice",
                    any(names.into_pyobject(py)?.into_any()),
                    py.None(),
                ),
            })
        })
        .collect()
}

fn parse_overrides(set: Vec<String>) -> PyResult<Vec<Override>> {
    set.iter()
        .map(|s| s.parse::<Override>().map_err(PyValueError::new_err))
        .collect()
}

fn render_error(e: RenderError) -> PyErr {
    match e {
        RenderError::Memory { .. } => error::<PyMemoryError>(e.to_string()),
        e => error::<PyRuntimeError>(e.to_string()),
    }
}

impl NativeScene {
    /// The scene as it is now.
    fn state(&self) -> MutexGuard<'_, State> {
        // Every change is made whole, so a panic elsewhere leaves a consistent state.
        self.state.lock().unwrap_or_else(|p| p.into_inner())
    }

    fn snapshot(&self) -> State {
        self.state().clone()
    }

    /// Reads (`path`) or takes (`text`) a scene and parses it with `set`.
    fn open(
        py: Python<'_>,
        path: Option<PathBuf>,
        text: String,
        name: String,
        set: Vec<String>,
    ) -> PyResult<NativeScene> {
        let overrides = parse_overrides(set)?;
        let parsing = overrides.clone();
        let opened = detached(py, move || {
            let text = match path {
                Some(path) => file::read_file(&path)?,
                None => text,
            };
            let source = Source { text, name };
            let description = source.parse(&parsing)?;
            Ok((source, description))
        })?;
        let (source, description) = opened.map_err(|e| scene_error(py, e))?;
        Ok(NativeScene {
            state: Mutex::new(State {
                source: Arc::new(source),
                overrides,
                description: Arc::new(description),
                built: None,
            }),
        })
    }

    /// The BVH of `state`: its own, or built now (with `threads` threads, if given), and kept
    /// if the scene still has the same objects.
    fn built(&self, py: Python<'_>, state: &State, threads: Option<u32>) -> PyResult<Arc<Built>> {
        if let Some(built) = &state.built {
            return Ok(built.clone());
        }
        let description = state.description.clone();
        let made = detached(py, move || -> Result<Built, PrepareError> {
            let device = prepare::device(threads.map(|t| t as usize))?;
            let scene = prepare::build(&device, &description)?;
            Ok(Built {
                scene,
                _device: device,
            })
        })?;
        let built = Arc::new(made.map_err(|e| unprepared(py, &state.source, e))?);
        let mut now = self.state();
        if now.built.is_none() && now.description.same_objects(&state.description) {
            now.built = Some(built.clone());
        }
        Ok(built)
    }
}

/// Runs `work` on its own thread with the GIL released, while this thread passes the pixels
/// finished to `progress` (with the GIL) and looks for Ctrl-C and other signals, about every
/// 50 ms, and at the end. A signal's exception (KeyboardInterrupt) or the callback's stops the
/// work and is raised once the work has stopped.
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
    let finished = AtomicBool::new(false);
    let waiting = std::thread::current();
    std::thread::scope(|s| {
        let worker = std::thread::Builder::new()
            .name("timbre-render".into())
            .spawn_scoped(s, || {
                let result = work(&stop, &add);
                finished.store(true, Ordering::Release);
                waiting.unpark();
                result
            })
            .map_err(|e| {
                error::<PyRuntimeError>(format!("could not start a render thread: {e}"))
            })?;
        let mut reported = 0;
        let mut failure = None;
        loop {
            // The flag is set before the wake-up; `is_finished` also covers a panic.
            let finished = finished.load(Ordering::Acquire) || worker.is_finished();
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
            .map_err(|_| error::<PyRuntimeError>("the render thread panicked"))?;
        match failure {
            Some(e) => Err(e),
            None => Ok(result),
        }
    })
}

/// An image's colours as a float32 array of shape (height, width, 3): each channel as the
/// command line writes it to OpenEXR (the f64 mean rounded to f32).
fn rgb<'py>(py: Python<'py>, image: &Image) -> PyResult<Bound<'py, PyAny>> {
    let mut values = buffer(3 * image.pixels.len())?;
    values.extend(
        image
            .pixels
            .iter()
            .flat_map(|c: &Colour| c.to_array().map(|v| v as f32)),
    );
    let shape = [image.height as usize, image.width as usize, 3];
    Ok(PyArray1::from_vec(py, values).reshape(shape)?.into_any())
}

/// The AOV `name` of `image` as a float32 array: `depth` and `object` (h, w), `normal` and
/// `albedo` (h, w, 3).
fn aov_array<'py>(py: Python<'py>, image: &Image, name: &str) -> PyResult<Bound<'py, PyAny>> {
    let aovs: &[AovSample] = image.aovs.as_deref().unwrap_or_default();
    let (h, w) = (image.height as usize, image.width as usize);
    let channels = AOVS.iter().find(|(a, _)| *a == name).map_or(1, |(_, n)| *n);
    let mut values = buffer(channels * aovs.len())?;
    for a in aovs {
        match name {
            "depth" => values.push(a.depth),
            "normal" => values.extend(a.normal.to_array()),
            "albedo" => values.extend(a.albedo.to_array()),
            _ => values.push(a.object),
        }
    }
    let array = PyArray1::from_vec(py, values);
    Ok(match channels {
        1 => array.reshape([h, w])?.into_any(),
        _ => array.reshape([h, w, 3])?.into_any(),
    })
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
    /// The scene file at `path` (read now, once; named by its absolute path), with `set`
    /// (`KEY=VALUE` strings) applied as `--set`.
    #[staticmethod]
    fn from_file(py: Python<'_>, path: PathBuf, set: Vec<String>) -> PyResult<NativeScene> {
        // Absolute, so that the paths in it stay found after the working directory changes.
        let path = std::path::absolute(&path)
            .map_err(|e| error::<PyOSError>(format!("{}: {e}", path.display())))?;
        let name = path.display().to_string();
        NativeScene::open(py, Some(path), String::new(), name, set)
    }

    /// Scene-file text (`name` stands for it in messages), with `set` applied as `--set`.
    #[staticmethod]
    fn from_text(
        py: Python<'_>,
        text: String,
        name: String,
        set: Vec<String>,
    ) -> PyResult<NativeScene> {
        NativeScene::open(py, None, text, name, set)
    }

    /// The same scene, overrides and built BVH (shared), to be changed on its own.
    fn copy(&self) -> NativeScene {
        NativeScene {
            state: Mutex::new(self.snapshot()),
        }
    }

    /// Changes the overrides as one change: removes those of the keys `unset` (`KeyError` for
    /// one that has none) and of the keys of `set` (`KEY=VALUE` strings), then appends `set`,
    /// in order. A scene the result makes invalid raises, and the scene stays as it was.
    fn update(&self, py: Python<'_>, set: Vec<String>, unset: Vec<String>) -> PyResult<()> {
        let sets = parse_overrides(set)?;
        let unset: Vec<Vec<String>> = unset
            .iter()
            .map(|k| k.split('.').map(|p| p.trim().to_string()).collect())
            .collect();
        loop {
            let old = self.snapshot();
            if let Some(k) = unset
                .iter()
                .find(|k| !old.overrides.iter().any(|o| o.key == **k))
            {
                return Err(error::<PyKeyError>(k.join(".")));
            }
            let mut overrides: Vec<Override> = old
                .overrides
                .iter()
                .filter(|o| !unset.contains(&o.key) && !sets.iter().any(|s| s.key == o.key))
                .cloned()
                .collect();
            overrides.extend(sets.iter().cloned());
            let (source, parsing) = (old.source.clone(), overrides.clone());
            let parsed = detached(py, move || source.parse(&parsing))?;
            let description = parsed.map_err(|e| scene_error(py, e))?;
            let mut state = self.state();
            // Changed by another thread meanwhile: again, from its version.
            if !Arc::ptr_eq(&state.description, &old.description) {
                continue;
            }
            let built = state
                .built
                .take()
                .filter(|_| state.description.same_objects(&description));
            *state = State {
                source: old.source,
                overrides,
                description: Arc::new(description),
                built,
            };
            return Ok(());
        }
    }

    /// The overrides in force, in order, as (key, TOML value) pairs.
    fn overrides(&self) -> Vec<(String, String)> {
        self.state()
            .overrides
            .iter()
            .map(|o| {
                let text = o.to_string();
                let value = text.split_once('=').map_or("", |(_, v)| v);
                (o.key.join("."), value.trim().to_string())
            })
            .collect()
    }

    /// The name of the scene in messages: the file's path, or the name given to its text.
    fn name(&self) -> String {
        self.state().source.name.clone()
    }

    /// The scene text (as read when loaded) with the overrides applied.
    fn text(&self) -> PyResult<String> {
        let state = self.snapshot();
        file::with_overrides(&state.source.text, &state.overrides).map_err(PyValueError::new_err)
    }

    /// The value at `key` (a dotted path, as `--set` takes) in the scene text with the
    /// overrides applied; `KeyError` where the text has none.
    fn get<'py>(&self, py: Python<'py>, key: &str) -> PyResult<Bound<'py, PyAny>> {
        let table: toml::Table = self
            .text()?
            .parse()
            .map_err(|e: toml::de::Error| error::<PyValueError>(e.to_string()))?;
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
            value = inner.ok_or_else(|| error::<PyKeyError>(key.to_string()))?;
        }
        to_python(py, value)
    }

    /// The render settings of the scene (each of `SETTINGS`), its stereo output
    /// (`camera.stereo`) and the number of views that renders.
    fn settings<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let description = self.snapshot().description;
        let d = PyDict::new(py);
        for setting in &SETTINGS {
            match setting.get(&description.render) {
                Value::Whole(n) => d.set_item(setting.key, n)?,
                Value::Switch(b) => d.set_item(setting.key, b)?,
                Value::Number(x) => d.set_item(setting.key, x)?,
                Value::Choice(name) => d.set_item(setting.key, name)?,
            }
        }
        d.set_item("stereo", description.stereo.name())?;
        d.set_item("views", description.stereo.views())?;
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

    /// Renders the scene (`settings`, render settings by key, in place of the scene's
    /// `[render]` values, as `timbre render`'s options) and returns a dict: `rgb` (float32,
    /// (h, w, 3)), the AOVs named in `aovs`, and `rays`.
    #[pyo3(signature = (*, settings=Vec::new(), threads=None, aovs=Vec::new(), pixel_bounds=None,
        progress=None))]
    fn render<'py>(
        &self,
        py: Python<'py>,
        settings: Vec<(String, Bound<'py, PyAny>)>,
        threads: Option<u32>,
        aovs: Vec<String>,
        pixel_bounds: Option<(u32, u32, u32, u32)>,
        progress: Option<Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        // One version of the scene throughout, whatever other threads change meanwhile.
        let state = self.snapshot();
        let description = &state.description;
        let given = setting_values(&settings)?;
        let mut settings: RenderSettings = description.render.clone();
        given.apply_over(&mut settings);
        let mut channels = 0;
        for name in &aovs {
            let Some((_, n)) = AOVS.iter().find(|(a, _)| a == name) else {
                return Err(error::<PyValueError>(format!(
                    "unknown AOV '{name}': the AOVs are depth, normal, object and albedo"
                )));
            };
            channels += *n as u64;
        }
        settings.aovs = !aovs.is_empty();
        settings.albedo = aovs.iter().any(|a| a == "albedo");
        if let Some(t) = threads {
            if !(1..=MAX_THREADS).contains(&t) {
                return Err(error::<PyValueError>(format!(
                    "threads must be from 1 to {MAX_THREADS}, got {t}"
                )));
            }
            settings.threads = Some(t as usize);
        }
        let stereo = &description.stereo;
        prepare::check_settings(&settings, stereo).map_err(|e| unprepared(py, &state.source, e))?;
        let full = PixelBounds::full(settings.width, settings.height);
        let bounds = match pixel_bounds {
            None => full,
            Some((x0, x1, y0, y1)) => {
                let b = PixelBounds { x0, x1, y0, y1 };
                if b.is_empty() || !full.contains(&b) {
                    return Err(error::<PyValueError>(format!(
                        "pixel_bounds ({x0}, {x1}, {y0}, {y1}) are not pixels of the {}x{} image: x0 < x1 <= width and y0 < y1 <= height are needed",
                        settings.width, settings.height
                    )));
                }
                b
            }
        };
        if *stereo != Stereo::Mono && (settings.aovs || bounds != full) {
            return Err(error::<PyValueError>(
                "aovs and pixel_bounds work with single views only (camera.stereo = \"none\")",
            ));
        }
        // Refused before it starts if it could not finish (as `timbre render` does), rather
        // than the process killed midway: the views in memory, and the float32 arrays handed
        // to Python (12 bytes a pixel of the output, 4 a channel of the AOVs asked for).
        let workers = settings
            .threads
            .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
            as u64;
        let pixels = bounds.pixels();
        let views = stereo.views() as u64;
        let image = stereo::memory_needed(settings.aovs, stereo, pixels)
            + pixels * (12 * views + 4 * channels);
        let scene = match state.built {
            Some(_) => 0,
            None => description.build_memory(),
        };
        let needs = Needs {
            what: format!("a {}x{} render", bounds.width(), bounds.height()),
            image,
            reserve: memory_reserve(workers),
        };
        prepare::check_memory(&needs, scene).map_err(|e| unprepared(py, &state.source, e))?;
        let built = self.built(py, &state, threads)?;
        THREADS_SEEN.fetch_max(workers, Ordering::Relaxed);
        let camera = &description.camera;
        let rendered = interruptible(py, progress.as_ref(), |stop, progress| {
            let scene = &built.scene;
            match stereo {
                Stereo::Mono => render_part(scene, camera, &settings, bounds, stop, progress),
                _ => render_stereo_until(scene, camera, &settings, stereo, stop, progress),
            }
        })?;
        // Stopped only by an exception, which `interruptible` raises.
        let mut image = rendered
            .map_err(render_error)?
            .ok_or_else(|| error::<PyRuntimeError>("the render stopped"))?;
        // The exposure scales the values, as in every file `timbre render` writes.
        if settings.exposure != 0.0 {
            let gain = settings.exposure.exp2();
            image.pixels.iter_mut().for_each(|p| *p *= gain);
        }
        let out = PyDict::new(py);
        out.set_item("rgb", rgb(py, &image)?)?;
        out.set_item("png_transfer", settings.png_transfer.name())?;
        for name in &aovs {
            out.set_item(name, aov_array(py, &image, name)?)?;
        }
        out.set_item("rays", image.rays)?;
        Ok(out)
    }

    /// The ray trajectories of the scene, traced, as JSON: the rays of `timbre trace --json`
    /// (`trajectories::TracedRay`, the one format of both).
    fn trajectories(&self, py: Python<'_>) -> PyResult<String> {
        let state = self.snapshot();
        let description = state.description.clone();
        let needs = Needs {
            what: "tracing the scene's ray trajectories".into(),
            image: 0,
            reserve: memory_reserve(prepare::default_threads() as u64),
        };
        let traced = detached(py, move || -> Result<Vec<Trajectory>, PrepareError> {
            prepare::check_memory(&needs, description.build_memory())?;
            let device = prepare::device(None)?;
            Ok(trajectories::trace(&device, &description)?)
        })?
        .map_err(|e| unprepared(py, &state.source, e))?;
        let rays = trajectories::traced_rays(&state.description, &traced);
        serde_json::to_string(&rays).map_err(|e| error::<PyRuntimeError>(e.to_string()))
    }
}

/// The PNG transfer called `name` (`png_transfer`'s values).
fn transfer(name: &str) -> PyResult<PngTransfer> {
    PngTransfer::named(name).ok_or_else(|| {
        error::<PyValueError>(format!(
            "png_transfer: expected one of {}, got '{name}'",
            PngTransfer::NAMES.join(", ")
        ))
    })
}

/// A float32 (h, w, 3) array of linear colours as the image the command line writes to PNG
/// (each channel clamped to [0, 1], encoded by `transfer`, times 255, rounded).
fn rgb8_image(rgb: &PyReadonlyArray3<'_, f32>, transfer: PngTransfer) -> PyResult<image::RgbImage> {
    let shape = rgb.shape();
    let (height, width) = (shape[0], shape[1]);
    if shape[2] != 3 || u32::try_from(width).is_err() || u32::try_from(height).is_err() {
        return Err(error::<PyValueError>(format!(
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
    Ok(timbre::io::encoded_rgb8(&image, transfer))
}

/// The 8-bit (h, w, 3) uint8 array of a float32 (h, w, 3) image, as the command line's PNG.
#[pyfunction]
#[pyo3(signature = (rgb, png_transfer="linear"))]
fn rgb8<'py>(
    py: Python<'py>,
    rgb: PyReadonlyArray3<'py, f32>,
    png_transfer: &str,
) -> PyResult<Bound<'py, PyAny>> {
    let image = rgb8_image(&rgb, transfer(png_transfer)?)?;
    let shape = [image.height() as usize, image.width() as usize, 3];
    Ok(PyArray1::from_vec(py, image.into_raw())
        .reshape(shape)?
        .into_any())
}

/// A float32 (h, w, 3) image as the PNG file the command line writes.
#[pyfunction]
#[pyo3(signature = (rgb, png_transfer="linear"))]
fn png_bytes<'py>(
    py: Python<'py>,
    rgb: PyReadonlyArray3<'py, f32>,
    png_transfer: &str,
) -> PyResult<Bound<'py, PyBytes>> {
    let transfer = transfer(png_transfer)?;
    let image = rgb8_image(&rgb, transfer)?;
    let mut bytes = Vec::new();
    timbre::io::png_encoder(&mut bytes, image.width(), image.height(), transfer)
        .write_header()
        .and_then(|mut w| w.write_image_data(&image))
        .map_err(|e| error::<PyRuntimeError>(e.to_string()))?;
    Ok(PyBytes::new(py, &bytes))
}

/// The version of the Embree library timbre runs on.
#[pyfunction]
fn embree_version() -> PyResult<String> {
    let device = Device::new("").map_err(|e| error::<PyRuntimeError>(e.to_string()))?;
    Ok(device.version())
}

#[pymodule]
fn _timbre(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<NativeScene>()?;
    m.add("SceneError", m.py().get_type::<SceneError>())?;
    m.add_function(wrap_pyfunction!(png_bytes, m)?)?;
    m.add_function(wrap_pyfunction!(rgb8, m)?)?;
    m.add_function(wrap_pyfunction!(embree_version, m)?)?;
    m.add_function(wrap_pyfunction!(render_settings, m)?)?;
    Ok(())
}
