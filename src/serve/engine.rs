//! The engine thread: it owns the [`Preview`], takes the pages' changes and requests from the
//! shared inputs, renders, and broadcasts state and frames; beside it a thread that watches the
//! scene file.

use std::collections::VecDeque;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::time::{Duration, Instant, SystemTime};

use axum::body::Bytes;
use tokio::sync::{broadcast, watch};

use super::messages::{AnimationState, CameraState, Hit, SceneState, ToPage};
use super::parameters::{Parameter, Slider, parameters};
use super::preview::{LoadError, Preview};
use super::{ServeError, ServeOptions};
use crate::cameras::Projection;
use crate::io::{Provenance, encoded_rgb8, write_image};
use crate::production::{self, Job, Signals};
use crate::render::{Image, PixelBounds};
use crate::scene::file::{self, Confinement, MAX_FILE_BYTES, Override};
use crate::scene::settings::{PngTransfer, SETTINGS, Value};
use crate::scene::{RenderSettings, Scene, SceneDescription, Stereo};
use crate::stereo::render_stereo;

/// How often the scene file is checked for changes.
const WATCH_INTERVAL: Duration = Duration::from_millis(250);

/// How long after a change of the scene file its text is compared at every check, not only its
/// modification time and size: longer than any file system's time resolution.
const RACY_STAMP: Duration = Duration::from_secs(2);

/// Scene texts longer than this get no parameter list (it would be enormous).
const MAX_PARAMETER_TEXT: usize = 8 << 20;

/// Most checks of the scene one state's sliders are narrowed with ([`Slider::PROBES`] a
/// slider at most); the sliders left then keep their unnarrowed ranges, for this state.
const PROBE_BUDGET: usize = 400;

/// Largest scene text whose sliders are narrowed (each probe checks the whole text).
const MAX_PROBED_TEXT: usize = 256 << 10;

/// The sliders found for a scene text, by key and value (the bits of the f64).
#[derive(Default)]
struct Sliders {
    text: String,
    found: std::collections::HashMap<(String, u64), Slider>,
}

/// Most `--set`s a page may have at once.
pub const MAX_PAGE_OVERRIDES: usize = 1000;

/// Most requests waiting for the engine (a page that sends faster is told it is busy).
const MAX_REQUESTS: usize = 16;

/// JSON messages kept for pages that read slowly: beyond these a page gets the latest state
/// instead. (Frames are not kept: a page gets the newest one when it is ready for it.)
const BACKLOG: usize = 64;

/// Bytes before the pixels of a frame: five little-endian u32s (generation, samples done,
/// samples to do, width, height).
pub const FRAME_HEADER: usize = 20;

/// What a page gets from the engine: the latest state (and error) to start with, then every
/// JSON message, and the newest frame whenever it is ready for one.
pub struct Subscription {
    pub now: Vec<Arc<str>>,
    pub json: broadcast::Receiver<Arc<str>>,
    pub frames: watch::Receiver<Frames>,
}

/// The frames a page is sent: the newest, and the first of its scene (the coarse one, which a
/// page sees even when later ones came before it was ready: it shows that the accumulation
/// started again).
#[derive(Debug, Clone, Default)]
pub struct Frames {
    /// The generation of the scene shown.
    pub generation: u64,
    pub first: Option<Bytes>,
    pub newest: Option<Bytes>,
}

/// Something a page asked for that is not a change of the picture.
#[derive(Debug, Clone, PartialEq)]
pub enum Request {
    Inspect { x: u32, y: u32 },
    Trajectory { x: u32, y: u32 },
    Save { file: String },
    WriteScene,
}

impl Request {
    fn is_inspect(&self) -> bool {
        matches!(self, Request::Inspect { .. })
    }
}

/// What the pages change, and what the engine has yet to do.
struct Inputs {
    text: String,
    /// The command line's `--set`s, then the page's (one per key, in the order first set).
    base: Vec<Override>,
    page: Vec<Override>,
    /// Whether the text came from a page (not from the scene file on disk).
    from_page: bool,
    /// Exposure in stops (a display setting: it does not restart the accumulation): the
    /// scene's `exposure` setting when it loads, then the page's slider.
    exposure: f64,
    /// The scene's `png_transfer`, which frames are encoded by, as its PNG would be.
    transfer: PngTransfer,
    /// The frame of the scene's `[animation]` the page shows; `None`: the scene as written.
    frame: Option<u32>,
    /// Raised by every change of the picture, and of the display.
    generation: u64,
    display: u64,
    requests: VecDeque<Request>,
}

impl Inputs {
    fn overrides(&self) -> Vec<Override> {
        self.base.iter().chain(&self.page).cloned().collect()
    }
}

/// The last state and error (if the last load failed) sent, for pages that connect (or fall
/// behind) later.
#[derive(Default)]
struct Latest {
    state: Option<Arc<str>>,
    error: Option<Arc<str>>,
}

struct Shared {
    scene: PathBuf,
    inputs: Mutex<Inputs>,
    wake: Condvar,
    /// Set when the picture changed: the pass in progress stops.
    stop: Arc<AtomicBool>,
    out: broadcast::Sender<Arc<str>>,
    frames: watch::Sender<Frames>,
    latest: Mutex<Latest>,
    /// Set while a render is being saved; its stop signal, which cancels it.
    saving: Arc<AtomicBool>,
    cancel_save: Arc<AtomicBool>,
    /// The file names the user gave, on the command line and in the scene file as the watcher
    /// last read it: the page may keep them ([`confinement`]).
    given: Vec<String>,
    on_disk: Mutex<Vec<String>>,
    /// The text the page last wrote into the scene file (the watcher need not reload it).
    written: Mutex<Option<String>>,
    /// A public server's visitor's engine: no file is read for its page but the scene's own,
    /// none written.
    public: bool,
    /// Set when the engine is closed (its visitor left): its threads end.
    closed: AtomicBool,
}

/// The handle the server's connections use.
#[derive(Clone)]
pub struct Engine {
    shared: Arc<Shared>,
}

/// Reads the scene file as text (regular files only, within the scene-file size limit).
pub fn read_scene(path: &Path) -> Result<String, String> {
    let bytes = crate::files::read_regular(path, MAX_FILE_BYTES)
        .map_err(|e| format!("{}: {e}", path.display()))?;
    String::from_utf8(bytes).map_err(|_| format!("{}: is not UTF-8 text", path.display()))
}

fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|e| e.into_inner())
}

impl Engine {
    /// Starts the engine and the file watcher on threads of their own; `held` is kept until
    /// the engine's thread ends (a public server's visitor's place).
    pub fn start(
        options: &ServeOptions,
        text: String,
        held: impl Send + 'static,
    ) -> Result<Engine, ServeError> {
        let preview = Preview::new(options.scene.clone(), options.preview.clone())
            .map_err(ServeError::Internal)?;
        let (out, _) = broadcast::channel(BACKLOG);
        let (frames, _) = watch::channel(Frames::default());

        let shared = Arc::new(Shared {
            scene: options.scene.clone(),
            inputs: Mutex::new(Inputs {
                text: text.clone(),
                base: options.overrides.clone(),
                page: Vec::new(),
                from_page: false,
                exposure: 0.0,
                transfer: PngTransfer::Linear,
                frame: None,
                generation: 1,
                display: 0,
                requests: VecDeque::new(),
            }),
            wake: Condvar::new(),
            stop: Arc::new(AtomicBool::new(false)),
            out,
            frames,
            latest: Mutex::new(Latest::default()),
            saving: Arc::new(AtomicBool::new(false)),
            cancel_save: Arc::new(AtomicBool::new(false)),
            given: override_names(&options.overrides),
            on_disk: Mutex::new(text_names(&text).unwrap_or_default()),
            written: Mutex::new(None),
            public: options.public.is_some(),
            closed: AtomicBool::new(false),
        });
        let engine = shared.clone();
        std::thread::Builder::new()
            .name("timbre-preview".into())
            .spawn(move || {
                run(engine, preview);
                drop(held);
            })
            .map_err(|e| ServeError::Internal(e.to_string()))?;
        let engine = Engine { shared };
        let watched = engine.shared.clone();
        std::thread::Builder::new()
            .name("timbre-watch".into())
            .spawn(move || watch(&watched, text))
            .map_err(|e| {
                engine.close();
                ServeError::Internal(e.to_string())
            })?;
        Ok(engine)
    }

    /// Ends the engine's threads (a public server's visitor has left): the pass in progress
    /// stops, and so does the watcher at its next look.
    pub fn close(&self) {
        self.shared.closed.store(true, Ordering::Relaxed);
        self.shared.stop.store(true, Ordering::Relaxed);
        let _inputs = lock(&self.shared.inputs);
        self.shared.wake.notify_all();
    }

    /// The last state (and error), the messages from now on, and the frames.
    pub fn subscribe(&self) -> Subscription {
        let latest = lock(&self.shared.latest);
        Subscription {
            now: [latest.state.clone(), latest.error.clone()]
                .into_iter()
                .flatten()
                .collect(),
            json: self.shared.out.subscribe(),
            frames: self.shared.frames.subscribe(),
        }
    }

    /// Changes the inputs with `change`, which says whether it changed anything; `picture`:
    /// whether that changes the picture (the pass in progress stops) or only the display.
    fn change(&self, picture: bool, change: impl FnOnce(&mut Inputs) -> bool) {
        let mut inputs = lock(&self.shared.inputs);
        if !change(&mut inputs) {
            return;
        }
        if picture {
            inputs.generation += 1;
            self.shared.stop.store(true, Ordering::Relaxed);
        } else {
            inputs.display += 1;
        }
        self.shared.wake.notify_all();
    }

    /// The page's `--set`s: each replaces an earlier one of the same key; refused (all of
    /// them) if the page would have more than [`MAX_PAGE_OVERRIDES`].
    pub fn set(&self, overrides: Vec<Override>) -> Result<(), String> {
        let mut result = Ok(());
        self.change(true, |i| {
            let mut page = i.page.clone();
            for o in overrides {
                match page.iter_mut().find(|p| p.key == o.key) {
                    Some(p) => *p = o,
                    None => page.push(o),
                }
            }
            if page.len() > MAX_PAGE_OVERRIDES {
                result = Err(format!(
                    "at most {MAX_PAGE_OVERRIDES} --set values at once: reset some first"
                ));
                return false;
            }
            let changed = page != i.page;
            i.page = page;
            changed
        });
        result
    }

    /// Drops the page's `--set`s of these keys (all of them, if `keys` is empty).
    pub fn unset(&self, keys: &[String]) {
        let keys: std::collections::HashSet<&str> = keys.iter().map(String::as_str).collect();
        self.change(true, |i| {
            let before = i.page.len();
            i.page
                .retain(|o| !keys.is_empty() && !keys.contains(o.key.join(".").as_str()));
            i.page.len() != before
        });
    }

    /// Shows frame `frame` of the scene's `[animation]`, or with `None` the scene as written.
    pub fn frame(&self, frame: Option<u32>) {
        self.change(true, |i| {
            let changed = i.frame != frame;
            i.frame = frame;
            changed
        });
    }

    /// New scene text (from the page's editor).
    pub fn text(&self, text: String) {
        self.change(true, |i| {
            let changed = i.text != text;
            i.text = text;
            i.from_page = true;
            changed
        });
    }

    pub fn exposure(&self, stops: f64) {
        self.change(false, |i| {
            let changed = i.exposure != stops;
            i.exposure = stops;
            changed
        });
    }

    /// Queues a request; a newer inspection replaces one still waiting. Refused while
    /// [`MAX_REQUESTS`] wait.
    pub fn request(&self, request: Request) -> Result<(), String> {
        if self.shared.public && matches!(request, Request::Save { .. } | Request::WriteScene) {
            return Err("a public server writes no files: save a picture from the browser".into());
        }
        let mut inputs = lock(&self.shared.inputs);
        if request.is_inspect() {
            inputs.requests.retain(|r| !r.is_inspect());
        }
        if inputs.requests.len() >= MAX_REQUESTS {
            return Err("busy: too many requests at once".into());
        }
        inputs.requests.push_back(request);
        self.shared.wake.notify_all();
        Ok(())
    }

    /// Stops the render being saved, if there is one, and drops saves still waiting.
    pub fn cancel_save(&self) {
        let mut inputs = lock(&self.shared.inputs);
        inputs
            .requests
            .retain(|r| !matches!(r, Request::Save { .. }));
        self.shared.cancel_save.store(true, Ordering::Relaxed);
    }
}

/// Sends a JSON message to every page.
fn send(shared: &Shared, message: ToPage) {
    let _ = shared.out.send(message.text().into());
}

/// Which files of a scene are confined when it is loaded ([`confinement`]).
#[derive(Debug, Clone, Copy, PartialEq)]
enum Check {
    /// The scene file and the command line: none.
    Nothing,
    /// The scene file, with `--set`s from the page: the files they name, and all those reach.
    Overrides,
    /// Text from the page: every file it names, and all those reach.
    All,
}

/// What the engine does next.
enum Work {
    Load {
        text: String,
        overrides: Vec<Override>,
        generation: u64,
        /// What the page wrote of it (and may name only the scene's own files in).
        check: Check,
        /// The command line's `--set`s (the first of `overrides`), which are trusted.
        base: usize,
        frame: Option<u32>,
    },
    Show,
    Pass,
    Request(Request),
}

/// The engine's loop: requests first, then a changed scene, a changed display, and passes
/// until the samples are all there; then it sleeps until something changes.
fn run(shared: Arc<Shared>, mut preview: Preview) {
    let shared = &shared;
    let (mut generation, mut display) = (0, 0);
    // The generation of the scene loaded last, which frames are labelled with (a failed load
    // leaves the earlier scene, and its label), and the one whose passes failed: no more
    // passes until another scene is loaded.
    let (mut shown, mut failed) = (0, 0);
    // The text of the scene that loaded last, how it was checked and the changes it had: while
    // the text has an error, moves and settings go on with that text and the new changes.
    let mut good: Option<(String, Check, Vec<Override>)> = None;
    let mut sliders = Sliders::default();
    loop {
        let work = {
            let mut inputs = lock(&shared.inputs);
            loop {
                if shared.closed.load(Ordering::Relaxed) {
                    return;
                }
                // Changes first: a request answers for the scene as the page has it now.
                if inputs.generation != generation {
                    generation = inputs.generation;
                    shared.stop.store(false, Ordering::Relaxed);
                    break Work::Load {
                        text: inputs.text.clone(),
                        overrides: inputs.overrides(),
                        generation,
                        check: match (inputs.from_page, inputs.page.is_empty()) {
                            (true, _) => Check::All,
                            (false, false) => Check::Overrides,
                            (false, true) => Check::Nothing,
                        },
                        base: inputs.base.len(),
                        frame: inputs.frame,
                    };
                }
                if let Some(r) = inputs.requests.pop_front() {
                    break Work::Request(r);
                }
                if inputs.display != display {
                    display = inputs.display;
                    break Work::Show;
                }
                if preview.accumulating() && failed != shown {
                    break Work::Pass;
                }
                inputs = shared.wake.wait(inputs).unwrap_or_else(|e| e.into_inner());
            }
        };
        let show = |image: &Image, shown: u64, (done, target): (u32, u32)| {
            let (exposure, transfer) = {
                let inputs = lock(&shared.inputs);
                (inputs.exposure, inputs.transfer)
            };
            let frame = encode(image, exposure, transfer, shown, done, target);
            shared.frames.send_modify(|f| {
                if f.generation != shown {
                    f.generation = shown;
                    f.first = Some(frame.clone());
                }
                f.newest = Some(frame);
            });
        };
        match work {
            Work::Load {
                text,
                overrides,
                generation,
                check,
                base,
                frame,
            } => {
                preview.frame = frame;
                let changes = &overrides[base.min(overrides.len())..];
                let load = |preview: &mut Preview, text: &str, check| {
                    preview.load(
                        text,
                        &overrides,
                        confinement(shared, check, changes).as_ref(),
                    )
                };
                // The new text, or else the last good text with the new changes (the error
                // is still the new text's).
                let (loaded, error) = match load(&mut preview, &text, check) {
                    Ok(()) => (Some((text.clone(), check)), None),
                    Err(e) => {
                        let message: Arc<str> = error(shared, &e, &text, generation).text().into();
                        // Only for new changes: without them the last good scene is loaded.
                        let fallback = good
                            .as_ref()
                            .filter(|(g, _, o)| *g != text && *o != overrides)
                            .map(|(g, c, _)| (g.clone(), *c))
                            .filter(|(g, c)| load(&mut preview, g, *c).is_ok());
                        (fallback, Some(message))
                    }
                };
                if let Some((text, check)) = loaded {
                    if let Some(s) = preview.settings() {
                        let mut inputs = lock(&shared.inputs);
                        (inputs.exposure, inputs.transfer) = (s.exposure, s.png_transfer);
                        // A frame of a movie the scene no longer has is not kept for a later
                        // one, nor one past the end of a shorter movie.
                        let frames = preview
                            .description()
                            .and_then(|d| d.animation.as_ref())
                            .map(|a| a.frames);
                        inputs.frame = inputs.frame.zip(frames).map(|(k, n)| k.min(n - 1));
                    }
                    let mut state = state(shared, &preview, &text, &overrides, generation);
                    let valid = |key: &str, x: f64, integer: bool| {
                        // A closed engine's state is not shown: its probes end at once.
                        if shared.closed.load(Ordering::Relaxed) {
                            return true;
                        }
                        let value = if integer {
                            format!("{}", x as i64)
                        } else {
                            format!("{x:?}")
                        };
                        let Ok(probe) = format!("{key}={value}").parse::<Override>() else {
                            return false;
                        };
                        let mut changes = changes.to_vec();
                        changes.push(probe.clone());
                        let mut all = overrides.clone();
                        all.push(probe);
                        let confined = confinement(shared, check, &changes);
                        preview.describe(&text, &all, confined.as_ref()).is_ok()
                    };
                    probe_sliders(&mut sliders, &text, &mut state.parameters, &valid);
                    let state: Arc<str> = ToPage::Scene(state).text().into();
                    {
                        let mut latest = lock(&shared.latest);
                        latest.state = Some(state.clone());
                        latest.error = None;
                    }
                    let _ = shared.out.send(state);
                    good = Some((text, check, overrides.clone()));
                    shown = generation;
                    match preview.coarse() {
                        Ok(Some(image)) => show(&image, shown, preview.progress()),
                        Ok(None) => {}
                        Err(e) => send(shared, pass_failed(for_page(shared, &e))),
                    }
                }
                if let Some(message) = error {
                    lock(&shared.latest).error = Some(message.clone());
                    let _ = shared.out.send(message);
                }
            }
            Work::Show => {
                if let Some(image) = preview.picture() {
                    show(&image, shown, preview.progress());
                }
            }
            Work::Pass => {
                if let Err(e) = preview.pass(&shared.stop, &mut |image, progress| {
                    show(&image, shown, progress)
                }) {
                    failed = shown;
                    send(shared, pass_failed(for_page(shared, &e)));
                }
            }
            Work::Request(r) => answer(shared, &preview, r),
        }
    }
}

/// The confinement of a scene's files (`check`: what the page wrote of it; `page`: the page's
/// `--set`s): every file that the page names reaches must be in the scene file's directory.
/// The names the user gave in the text itself (on the command line, or in the scene file as
/// the watcher last read it) are read with all they include; so, for the scene file with
/// `--set`s from the page, is every name but those the `--set`s give.
fn confinement<'a>(shared: &'a Shared, check: Check, page: &[Override]) -> Option<Confinement<'a>> {
    let page = match check {
        Check::Nothing => return None,
        Check::Overrides => Some(override_names(page)),
        Check::All => None,
    };
    let own = lock(&shared.on_disk).clone();
    Some(Confinement {
        trusted: Box::new(move |name: &str| {
            let among = |names: &[String]| names.iter().any(|n| n == name);
            among(&shared.given) || among(&own) || page.as_ref().is_some_and(|p| !among(p))
        }),
        only_trusted: shared.public,
    })
}

/// Whether text from the page may be written into the scene file (which is read unchecked
/// when it changes): when it names no files but the user's own, or loads with its files
/// confined.
fn writable(shared: &Shared, text: &str, confinement: &Confinement) -> Result<(), String> {
    if text_names(text).is_some_and(|names| names.iter().all(|n| (confinement.trusted)(n))) {
        return Ok(());
    }
    let path = shared.scene.display().to_string();
    file::parse_confined(text, &path, &[], confinement)
        .map(drop)
        .map_err(|e| {
            format!("not written (text that names files is written only if it loads): {e}")
        })
}

/// The file names in scene text; `None` if it is too large to read whole here, or not TOML.
fn text_names(text: &str) -> Option<Vec<String>> {
    let table = (text.len() <= MAX_PARAMETER_TEXT)
        .then(|| text.parse::<toml::Table>().ok())
        .flatten()?;
    let mut names = Vec::new();
    file_names(&toml::Value::Table(table), &mut names);
    Some(names)
}

/// The file names `--set`s give: a value set for a `file` key, and any `file` key inside a
/// value.
fn override_names(overrides: &[Override]) -> Vec<String> {
    let mut names = Vec::new();
    for o in overrides {
        match &o.value {
            toml::Value::String(name) if o.key.last().is_some_and(|k| k == "file") => {
                names.push(name.clone())
            }
            value => file_names(value, &mut names),
        }
    }
    names
}

/// The directory of the scene file (`.` for a bare file name).
fn scene_dir(scene: &Path) -> &Path {
    match scene.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir,
        _ => Path::new("."),
    }
}

/// The strings under `file` keys anywhere in `value`.
fn file_names(value: &toml::Value, names: &mut Vec<String>) {
    match value {
        toml::Value::Table(t) => {
            for (k, v) in t {
                match v {
                    toml::Value::String(s) if k == "file" => names.push(s.clone()),
                    v => file_names(v, names),
                }
            }
        }
        toml::Value::Array(items) => items.iter().for_each(|v| file_names(v, names)),
        _ => {}
    }
}

/// Scene text for the page: none when it is longer than a page may send back (such a scene is
/// edited in an editor).
fn shown_text(text: &str) -> Option<&str> {
    (text.len() <= super::MAX_MESSAGE_BYTES / 2).then_some(text)
}

/// A failed load: the message, its line and column in `text` if it has them, and the text
/// itself (the page shows it with the error, and keeps the last good picture).
fn error<'a>(shared: &Shared, e: &LoadError, text: &'a str, generation: u64) -> ToPage<'a> {
    ToPage::Error {
        generation: Some(generation),
        message: for_page(shared, &e.message),
        line: e.line,
        column: e.column,
        text: shown_text(text),
    }
}

/// A message as a page is shown it: on a public server, without where the scene file is
/// (the path of its directory is left out, as in the state's `path`).
fn for_page(shared: &Shared, message: &str) -> String {
    let dir = shared.scene.parent().filter(|d| !d.as_os_str().is_empty());
    match dir {
        Some(dir) if shared.public => {
            let mut prefixes = vec![format!("{}/", dir.display())];
            if let Ok(full) = dir.canonicalize() {
                prefixes.push(format!("{}/", full.display()));
            }
            prefixes
                .iter()
                .fold(message.to_string(), |m, p| m.replace(p.as_str(), ""))
        }
        _ => message.to_string(),
    }
}

/// A render pass that failed.
fn pass_failed(message: String) -> ToPage<'static> {
    ToPage::Error {
        generation: None,
        message,
        line: None,
        column: None,
        text: None,
    }
}

/// A frame: [`FRAME_HEADER`], then the picture as 8-bit RGBA, each channel as a PNG output
/// by `transfer` has it after multiplying by 2^`exposure`.
fn encode(
    image: &Image,
    exposure: f64,
    transfer: PngTransfer,
    generation: u64,
    done: u32,
    target: u32,
) -> Bytes {
    let scaled;
    let image = if exposure == 0.0 {
        image
    } else {
        let gain = exposure.exp2();
        scaled = Image {
            pixels: image.pixels.iter().map(|&c| c * gain).collect(),
            aovs: None,
            ..*image
        };
        &scaled
    };
    let rgb = encoded_rgb8(image, transfer);
    let mut bytes = Vec::with_capacity(FRAME_HEADER + 4 * rgb.len() / 3);
    for v in [generation as u32, done, target, image.width, image.height] {
        bytes.extend_from_slice(&v.to_le_bytes());
    }
    for p in rgb.chunks_exact(3) {
        bytes.extend_from_slice(&[p[0], p[1], p[2], 255]);
    }
    Bytes::from(bytes)
}

/// Sends a notice (a message, or an error) to every page.
fn notice(shared: &Shared, result: Result<String, String>) {
    let shown = |m: String| for_page(shared, &m);
    send(shared, ToPage::notice(result.map(shown).map_err(shown)))
}

/// Answers a page's request (to every page: they show the same scene).
fn answer(shared: &Arc<Shared>, preview: &Preview, request: Request) {
    match request {
        Request::Inspect { x, y } => {
            let found = preview.inspect(x, y);
            let hit = found.as_ref().map(Hit::from);
            send(shared, ToPage::Inspection { x, y, hit });
        }
        Request::Trajectory { x, y } => {
            let Some(ray) = preview.pixel_ray(x, y) else {
                return notice(
                    shared,
                    Err(format!("pixel {x},{y}: no ray trajectory starts there")),
                );
            };
            let table = format!(
                "\n[[ray_trajectory]]\nname = \"pixel {x},{y}\"\nstart = {:?}\ndirection = {:?}\n",
                ray.origin.to_array(),
                ray.direction.to_array()
            );
            let mut inputs = lock(&shared.inputs);
            if inputs.text.len() + table.len() > super::MAX_MESSAGE_BYTES {
                drop(inputs);
                return notice(
                    shared,
                    Err("the scene text is at its size limit: no more trajectories".into()),
                );
            }
            inputs.text.push_str(&table);
            inputs.generation += 1;
            shared.stop.store(true, Ordering::Relaxed);
        }
        Request::Save { file } => save(shared, preview, &file),
        Request::WriteScene => {
            let (text, from_page) = {
                let inputs = lock(&shared.inputs);
                (inputs.text.clone(), inputs.from_page)
            };
            // The file is read unchecked when it changes: what the page wrote is checked now.
            let check = if from_page {
                Check::All
            } else {
                Check::Nothing
            };
            if let Some(confinement) = confinement(shared, check, &[])
                && let Err(e) = writable(shared, &text, &confinement)
            {
                return notice(shared, Err(e));
            }
            *lock(&shared.written) = Some(text.clone());
            let written =
                crate::files::write_atomically(&shared.scene, |w| w.write_all(text.as_bytes()));
            notice(
                shared,
                written
                    .map(|()| format!("wrote {}", shared.scene.display()))
                    .map_err(|e| format!("{}: {e}", shared.scene.display())),
            );
        }
    }
}

/// Whether `name` may be saved beside the scene file: a plain file name (no directories, not
/// hidden) ending in .png or .exr.
pub fn saveable(name: &str) -> Result<(), String> {
    let plain = !name.is_empty()
        && name.len() <= 255
        && !name.starts_with('.')
        && !name.contains(['/', '\\', '\0']);
    if !plain {
        return Err(format!(
            "'{name}' is not a plain file name: renders are saved beside the scene file"
        ));
    }
    if !(name.ends_with(".png") || name.ends_with(".exr")) {
        return Err(format!("'{name}': the name must end in .png or .exr"));
    }
    Ok(())
}

/// Starts rendering the loaded scene at the preview's settings (its samples per pixel) through
/// the normal render path into `name` beside the scene file, on a thread of its own (the
/// preview goes on; `cancel_save` stops a single view): the picture the preview converges to.
fn save(shared: &Arc<Shared>, preview: &Preview, name: &str) {
    let path = scene_dir(&shared.scene).join(name);
    if let Err(e) = saveable(name).and_then(|()| plain_target(&path)) {
        return notice(shared, Err(e));
    }
    if lock(&shared.latest).error.is_some() {
        return notice(
            shared,
            Err("the scene does not load (see its error): fix it before saving".into()),
        );
    }
    let (Some(description), Some(settings), Some(scene)) =
        (preview.description(), preview.settings(), preview.scene())
    else {
        return notice(shared, Err("no scene is loaded".into()));
    };
    if shared.saving.swap(true, Ordering::Relaxed) {
        return notice(
            shared,
            Err("a render is being saved: wait for it, or cancel it".into()),
        );
    }
    shared.cancel_save.store(false, Ordering::Relaxed);
    let (description, settings) = (description.clone(), settings.clone());
    /// Marks the save done however it ends (a panic too).
    struct Saving(Arc<Shared>);
    impl Drop for Saving {
        fn drop(&mut self) {
            self.0.saving.store(false, Ordering::Relaxed);
        }
    }
    let saving = Saving(shared.clone());
    let spawned = std::thread::Builder::new()
        .name("timbre-save".into())
        .spawn(move || {
            let shared = &saving.0;
            let result = render_to(shared, &scene, &description, &settings, &path);
            notice(shared, result);
        });
    if let Err(e) = spawned {
        notice(shared, Err(e.to_string()));
    }
}

/// Whether a render may be written at `path`: never through a link, nor over anything but a
/// file.
fn plain_target(path: &Path) -> Result<(), String> {
    match std::fs::symlink_metadata(path) {
        Ok(m) if !m.file_type().is_file() => Err(format!(
            "{}: is not a plain file; renders are saved as new files or over files",
            path.display()
        )),
        _ => Ok(()),
    }
}

/// Renders `description` with `settings` to `path` as `timbre render` would, telling the pages
/// how far it has got; stopped by `cancel_save` (single views).
fn render_to(
    shared: &Shared,
    scene: &Scene,
    description: &SceneDescription,
    settings: &RenderSettings,
    path: &Path,
) -> Result<String, String> {
    let start = Instant::now();
    let total = settings.width as u64 * settings.height as u64 * description.stereo.views() as u64;
    let done = std::sync::atomic::AtomicU64::new(0);
    let last = Mutex::new(Instant::now());
    let progress = |n: u64| {
        let d = done.fetch_add(n, Ordering::Relaxed) + n;
        let mut last = lock(&last);
        if last.elapsed() >= Duration::from_millis(250) {
            *last = Instant::now();
            let fraction = d as f64 / total.max(1) as f64;
            send(shared, ToPage::Saving { fraction });
        }
    };
    let mut provenance = Provenance {
        object_names: scene.object_names.clone(),
        // What the page shows: its slider's exposure.
        exposure: lock(&shared.inputs).exposure,
        ..Provenance::whole(settings, description.hash())
    };
    match &description.stereo {
        Stereo::Mono => {
            let job = Job {
                output: path.to_path_buf(),
                provenance,
                checkpointing: None,
            };
            let signals = Signals {
                stop: shared.cancel_save.clone(),
                checkpoint: Arc::new(AtomicBool::new(false)),
            };
            let done = production::run(
                scene,
                &description.camera,
                settings,
                &job,
                &signals,
                &progress,
                &mut |_, _| {},
            )
            .map_err(|e| e.to_string())?;
            if let production::Done::Stopped { .. } = done {
                return Err(format!("cancelled; {} was not written", path.display()));
            }
        }
        stereo => {
            let image = render_stereo(scene, &description.camera, settings, stereo, &progress)
                .map_err(|e| e.to_string())?;
            provenance.width = image.width;
            provenance.height = image.height;
            provenance.bounds = PixelBounds::full(image.width, image.height);
            // Again: the views took a while.
            plain_target(path)?;
            write_image(path, &image, &provenance).map_err(|e| e.to_string())?;
        }
    }
    Ok(format!(
        "saved {} ({}x{}, {} spp) in {:.1} s",
        path.display(),
        settings.width,
        settings.height,
        settings.spp,
        start.elapsed().as_secs_f64()
    ))
}

/// Watches the scene file: when its text changes (an editor saved it), the pages' scene text
/// is replaced and the scene reloaded.
fn watch(shared: &Shared, mut known: String) {
    let stamp = |path: &Path| -> Option<(SystemTime, u64)> {
        let m = std::fs::metadata(path).ok()?;
        Some((m.modified().ok()?, m.len()))
    };
    // None: the file is read at once, since it may have changed after `known` was read and
    // before this thread started.
    let mut last = None;
    loop {
        std::thread::sleep(WATCH_INTERVAL);
        if shared.closed.load(Ordering::Relaxed) {
            return;
        }
        let now = stamp(&shared.scene);
        // A file written twice within the clock's resolution keeps its stamp (the same size,
        // too, for an edited number): while the stamp is that recent its text is compared
        // ("racy" stamps, as git calls them).
        let racy = now
            .is_some_and(|(modified, _)| modified.elapsed().map_or(true, |age| age < RACY_STAMP));
        if now == last && !racy {
            continue;
        }
        last = now;
        let Ok(text) = read_scene(&shared.scene) else {
            continue;
        };
        if text == known {
            continue;
        }
        known = text.clone();
        *lock(&shared.on_disk) = text_names(&text).unwrap_or_default();
        // What the page wrote is what it has (or had, if it has gone on since).
        if lock(&shared.written).take_if(|w| *w == text).is_some() {
            continue;
        }
        let mut inputs = lock(&shared.inputs);
        if inputs.text != text {
            inputs.text = text;
            inputs.from_page = false;
            inputs.generation += 1;
            shared.stop.store(true, Ordering::Relaxed);
            shared.wake.notify_all();
        }
    }
}

/// Gives each number of `parameters` its slider, narrowed to its key's valid domain as `valid`
/// (key, value, whole) says, within [`PROBE_BUDGET`] checks; remembered for the same `text`.
/// The sliders of a text that names files (meshes, pictures, includes: each check would read
/// them) or is larger than [`MAX_PROBED_TEXT`] are not narrowed.
fn probe_sliders(
    sliders: &mut Sliders,
    text: &str,
    parameters: &mut [Parameter],
    valid: &dyn Fn(&str, f64, bool) -> bool,
) {
    if sliders.text != text {
        sliders.text = text.to_string();
        sliders.found.clear();
    }
    let probed = text.len() <= MAX_PROBED_TEXT && text_names(text).is_some_and(|n| n.is_empty());
    let mut left = if probed { PROBE_BUDGET } else { 0 };
    for p in parameters {
        let Some(v) = p.number() else { continue };
        let known = (p.key.clone(), v.to_bits());
        p.slider = Some(match sliders.found.get(&known) {
            Some(s) => *s,
            None if left >= Slider::PROBES => {
                let mut checks = 0;
                let s = Slider::around(v, p.integer, &mut |x| {
                    checks += 1;
                    valid(&p.key, x, p.integer)
                });
                left -= checks;
                sliders.found.insert(known, s);
                s
            }
            None => Slider::around(v, p.integer, &mut |_| true),
        });
    }
}

/// The JSON state of a loaded scene: its text, the page's and the command line's `--set`s,
/// the parameters, the camera (for navigation and as TOML to copy) and the render settings.
fn state<'a>(
    shared: &Shared,
    preview: &Preview,
    text: &'a str,
    overrides: &[Override],
    generation: u64,
) -> SceneState<'a> {
    let description = preview.description().expect("loaded");
    let settings = preview.settings().expect("loaded");
    // The values shown are the frame's where the page shows one of the scene's movie.
    let frame = preview.shown_frame();
    let shown: Vec<Override> = match &frame {
        Some((_, at_frame)) => [overrides, at_frame].concat(),
        None => overrides.to_vec(),
    };
    // A large scene is read in parts by the loader; here it would take tens of times its size.
    let applied = (text.len() <= MAX_PARAMETER_TEXT)
        .then(|| file::with_overrides(text, &shown).ok())
        .flatten()
        .and_then(|t| t.parse::<toml::Table>().ok());
    let camera = &description.camera;
    let (_, up) = camera.right_up();
    let (angle, view_width) = match camera.projection() {
        Projection::Perspective {
            horizontal_view_angle,
        } => (Some(horizontal_view_angle.to_degrees()), None),
        Projection::Orthographic { view_width, .. } => (None, Some(view_width)),
        Projection::Equirectangular => (None, None),
    };
    let mut table = applied
        .as_ref()
        .and_then(|t| t.get("camera"))
        .and_then(|c| c.as_table())
        .cloned()
        .unwrap_or_default();
    let vector = |v: glam::DVec3| toml::Value::Array(v.to_array().map(toml::Value::Float).into());
    for (key, value) in [
        ("position", Some(vector(camera.position()))),
        ("view_direction", Some(vector(camera.view_direction()))),
        ("up", Some(vector(up))),
        ("horizontal_view_angle_deg", angle.map(toml::Value::Float)),
    ] {
        if let Some(value) = value {
            table.entry(key).or_insert(value);
        }
    }
    let mut wrapped = toml::Table::new();
    wrapped.insert("camera".into(), toml::Value::Table(table.clone()));
    // The values the scene takes by default are parameters too: the camera's velocity, the
    // render settings.
    let (parameters, more) = match applied {
        Some(mut listed) if text.len() <= MAX_PARAMETER_TEXT => {
            table.entry("beta").or_insert(vector(camera.boost().beta()));
            listed.insert("camera".into(), toml::Value::Table(table));
            let r = &description.render;
            let render = listed
                .entry("render")
                .or_insert_with(|| toml::Value::Table(toml::Table::new()));
            if let Some(render) = render.as_table_mut() {
                for setting in &SETTINGS {
                    let value = match setting.get(r) {
                        Value::Whole(n) => toml::Value::Integer(n.min(i64::MAX as u64) as i64),
                        Value::Switch(b) => toml::Value::Boolean(b),
                        Value::Number(x) => toml::Value::Float(x),
                        Value::Choice(name) => toml::Value::String(name.into()),
                    };
                    render.entry(setting.key).or_insert(value);
                }
            }
            parameters(&listed)
        }
        _ => (Vec::new(), text.len() > MAX_PARAMETER_TEXT),
    };
    SceneState {
        generation,
        // A public server's visitors see the file's name, not where it is.
        path: match shared.public {
            true => shared
                .scene
                .file_name()
                .unwrap_or_default()
                .display()
                .to_string(),
            false => shared.scene.display().to_string(),
        },
        text: shown_text(text),
        overrides: overrides.iter().map(|o| o.to_string()).collect(),
        parameters,
        more_parameters: more,
        camera: CameraState {
            position: camera.position().to_array(),
            view_direction: camera.view_direction().to_array(),
            up: up.to_array(),
            horizontal_view_angle_deg: angle,
            view_width,
        },
        camera_toml: toml::to_string(&wrapped).unwrap_or_default(),
        stereo: description.stereo.name(),
        width: settings.width,
        height: settings.height,
        spp: settings.spp,
        exposure: settings.exposure,
        warnings: description
            .warnings()
            .iter()
            .map(|w| for_page(shared, w))
            .collect(),
        public: shared.public,
        animation: description.animation.as_ref().map(|a| AnimationState {
            frames: a.frames,
            frame: frame.map(|(k, _)| k),
        }),
    }
}
