//! The TOML scene-file format (documented key by key in `docs/SCENE_FORMAT.md`).
//!
//! Values are checked while they are read, so every error names the file, the line and column
//! of the offending value and what was expected. Objects may come from mesh files and other
//! scene files (`include`), and be grouped, transformed and repeated in arrays
//! (`placement.rs`); `--set key=value` overrides any value (`overrides.rs`).

mod camera;
mod confine;
mod overrides;
mod parts;
mod placement;
mod trajectories;

use std::ops::Range;
use std::path::{Path, PathBuf};

use serde::Deserialize;
use thiserror::Error;

use super::lights::{Lights, PointLight};
use super::settings::SettingValues;
use super::studio::{self, Studio};
use super::{AnimationKeys, SceneDescription, SceneObject};
use crate::geometry::{Shape, Transform};
use crate::keys::{Positive, Rgb, Vector};
use crate::surfaces::SkyKeys;
use crate::surfaces::Surface;
use crate::surfaces::SurfaceKeys;
use camera::CameraSection;

pub use confine::Confinement;
use confine::Within;
pub use overrides::Override;
use parts::Spanned;
pub use placement::MAX_ARRAY_ELEMENTS;
use placement::{
    DeviceSection, GroupSection, IncludeSection, Items, Link, MAX_OBJECTS, ObjectSection, Placer,
};
use trajectories::TrajectorySection;

/// A scene file that could not be read or understood.
#[derive(Debug, Error)]
pub enum SceneFileError {
    #[error("{path}: {source}")]
    Io {
        path: String,
        source: std::io::Error,
    },
    #[error("{path}:{line}:{column}: {message}")]
    Invalid {
        path: String,
        line: usize,
        column: usize,
        message: String,
    },
    /// An error in a file changed by `--set`, whose positions no longer match the file.
    #[error("{path} (with {overrides}): {message}")]
    Overridden {
        path: String,
        overrides: String,
        message: String,
    },
}

impl SceneFileError {
    /// The same place in the file with another message.
    fn with_message(self, message: String) -> SceneFileError {
        match self {
            SceneFileError::Io { .. } => self,
            SceneFileError::Invalid {
                path, line, column, ..
            } => SceneFileError::Invalid {
                path,
                line,
                column,
                message,
            },
            SceneFileError::Overridden {
                path, overrides, ..
            } => SceneFileError::Overridden {
                path,
                overrides,
                message,
            },
        }
    }
}

/// A TOML or serde message in the scene file's own words: Rust type names become what the
/// file should have there ("struct CameraSection" is a table, "nonzero u32" a whole number
/// from 1 to 4294967295).
fn plain(message: &str) -> String {
    // The punctuation after the last word of a phrase, kept when the phrase is replaced.
    let punctuation = |word: &str| word[word.trim_end_matches([',', '.']).len()..].to_string();
    let section = |word: &&str| {
        let word = word.trim_end_matches([',', '.']);
        word.ends_with("Section") || word.ends_with("Keys")
    };
    let mut words: Vec<String> = Vec::new();
    let mut tokens = message.split(' ').peekable();
    while let Some(token) = tokens.next() {
        let (replacement, skipped) = match token {
            // "struct RenderSection with 6 elements": a table (its fields are not an array).
            "struct" if tokens.peek().is_some_and(section) => {
                let with = tokens.clone().nth(1) == Some("with");
                ("a table", if with { 4 } else { 1 })
            }
            "internally" if tokens.peek() == Some(&"tagged") => ("a table with a `type` key", 3),
            "enum" if tokens.peek().is_some_and(section) => ("one of the names listed", 1),
            _ => {
                words.push(token.to_string());
                continue;
            }
        };
        let last = tokens.nth(skipped - 1).unwrap_or_default();
        words.push(format!("{replacement}{}", punctuation(last)));
    }
    let text = words.join(" ");
    let words = [
        ("a nonzero u32", "a whole number from 1 to 4294967295"),
        (
            "a nonzero u64",
            "a whole number from 1 to 18446744073709551615",
        ),
        ("u32", "a whole number from 0 to 4294967295"),
        ("u64", "a whole number from 0 to 18446744073709551615"),
        ("usize", "a whole number"),
        ("i64", "a whole number"),
        ("f64", "a number"),
        ("a sequence", "an array"),
        ("floating point", "number"),
        (
            "cannot recurse further; max recursion depth met",
            "arrays or tables nested too deeply",
        ),
        ("recursion limit", "arrays or tables nested too deeply"),
        (" as i128", ""),
        ("expected variant identifier", "expected a name in quotes"),
        ("wanted string or table", "expected a name in quotes"),
    ];
    // Only outside `quoted` words: those are the file's own.
    let text = text
        .split('`')
        .enumerate()
        .map(|(k, part)| match k % 2 {
            0 => words
                .iter()
                .fold(part.to_string(), |t, (rust, w)| t.replace(rust, w)),
            _ => part.to_string(),
        })
        .collect::<Vec<_>>()
        .join("`");
    expected_first(&text)
}

/// serde's "invalid type: string "a", expected a number" as the project says it: "expected a
/// number, got the text "a"" (also for "invalid value" and "invalid length"), with what was
/// given in the file's words (an array, a table, 1.5) and control characters in the text
/// escaped as everywhere else (`\x1b`, not Rust's `\u{1b}`).
fn expected_first(text: &str) -> String {
    // The earliest: the phrase begins serde's message, and text the file gave may follow.
    let serde_phrase = ["invalid type: ", "invalid value: ", "invalid length "]
        .iter()
        .filter_map(|p| text.find(p).map(|at| (at, p.len())))
        .min();
    let Some((at, len)) = serde_phrase else {
        return text.to_string();
    };
    let rest = &text[at + len..];
    let Some(split) = rest.rfind(", expected ") else {
        return text.to_string();
    };
    let given = &rest[..split];
    let expected = &rest[split + ", expected ".len()..];
    // An array given where a table belongs is not a question of its length.
    if len == "invalid length ".len() && expected.starts_with("a table") {
        return format!("{}expected a table, not an array", &text[..at]);
    }
    let unquote = |s: &str| s.trim_matches('`').to_string();
    let given = match given.split_once(' ') {
        _ if given == "sequence" => "an array".to_string(),
        _ if given == "map" => "a table".to_string(),
        _ if given == "unit value" => "nothing".to_string(),
        Some(("string", quoted)) => format!("the text {}", control_escapes(quoted)),
        Some(("integer" | "number" | "boolean" | "character", value)) => unquote(value),
        _ if given.bytes().all(|b| b.is_ascii_digit()) => {
            format!("{given} value{}", if given == "1" { "" } else { "s" })
        }
        _ => given.to_string(),
    };
    format!("{}expected {expected}, got {given}", &text[..at])
}

/// Rust's `\u{1b}` escapes of control characters as `\x1b` ([`crate::text::escape`]).
fn control_escapes(debug: &str) -> String {
    let mut out = String::new();
    let mut rest = debug;
    while let Some(at) = rest.find("\\u{") {
        out.push_str(&rest[..at]);
        let after = &rest[at + 3..];
        let code = after
            .split_once('}')
            .and_then(|(hex, tail)| Some((u32::from_str_radix(hex, 16).ok()?, tail)))
            .and_then(|(n, tail)| Some((char::from_u32(n)?, tail)));
        match code.and_then(|(c, tail)| Some((crate::text::escape(c)?, tail))) {
            Some((escaped, tail)) => {
                out.push_str(&escaped);
                rest = tail;
            }
            None => {
                out.push_str(&rest[at..at + 3]);
                rest = after;
            }
        }
    }
    out.push_str(rest);
    out
}

/// The TOML parser's `message` at `span` of `text` in the scene file's words, where the parser's
/// own words mislead: a missing value is not an unquoted string, and a duplicate key is named.
fn parser_message(text: &str, span: &Range<usize>, message: &str) -> String {
    let at = text.get(span.clone()).unwrap_or_default();
    let after = text.get(span.start..).unwrap_or_default();
    let next = after.trim_start_matches([' ', '\t']).chars().next();
    if message.starts_with("string values must be quoted")
        && matches!(next, None | Some('\n' | '\r' | '#'))
    {
        return "expected a value after `=`".into();
    }
    if message == "duplicate key" && !at.is_empty() {
        return duplicate(at);
    }
    plain(message)
}

/// The error for `key` given twice.
fn duplicate(key: &str) -> String {
    format!("duplicate key `{key}`: each key and table may be given only once")
}

/// `message` with every number of more than 20 characters written in scientific notation
/// (`1e308`, not 309 digits).
fn short_numbers(message: &str) -> String {
    let shorten = |word: &str| {
        let start = word
            .find(|c: char| c.is_ascii_digit() || c == '-')
            .unwrap_or(word.len());
        let end = word
            .rfind(|c: char| c.is_ascii_digit() || c == '.')
            .map_or(start, |i| i + 1)
            .max(start);
        let number = &word[start..end];
        match number.parse::<f64>() {
            Ok(v) if number.len() > 20 => format!("{}{v:e}{}", &word[..start], &word[end..]),
            _ => word.to_string(),
        }
    };
    message
        .split(' ')
        .map(shorten)
        .collect::<Vec<_>>()
        .join(" ")
}

/// How messages name an object: `object 'NAME'`, and one named "" so that it can be told.
fn object_label(name: &str) -> String {
    if name.is_empty() {
        "an object with an empty name (name = \"\")".into()
    } else {
        format!("object '{name}'")
    }
}

/// 1-based line and column of byte `offset` in `text` (a byte-order mark takes no column).
pub fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let before = text.get(..offset.min(text.len())).unwrap_or(text);
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let line = before.matches('\n').count() + 1;
    let line_text = before[line_start..].trim_start_matches('\u{feff}');
    (line, line_text.chars().count() + 1)
}

/// The text of a scene file, for error messages, and its directory, for relative paths.
struct Source {
    path: String,
    text: String,
    dir: PathBuf,
    /// The `--set` overrides applied to `text` (spans then refer to a rewritten file).
    overrides: Vec<Override>,
}

impl Source {
    fn new(text: String, path: &str) -> Source {
        Source {
            dir: Path::new(path)
                .parent()
                .map_or_else(PathBuf::new, Path::to_path_buf),
            path: path.to_string(),
            text,
            overrides: Vec::new(),
        }
    }

    fn dir(&self) -> &Path {
        &self.dir
    }

    /// An error at `span` (the start of the file when `None`).
    fn error(&self, span: Option<Range<usize>>, message: String) -> SceneFileError {
        if !self.overrides.is_empty() {
            let list: Vec<String> = self
                .overrides
                .iter()
                .map(|o| format!("--set {o}"))
                .collect();
            return SceneFileError::Overridden {
                path: self.path.clone(),
                overrides: list.join(" "),
                message: short_numbers(&message),
            };
        }
        let (line, column) = line_column(&self.text, span.map_or(0, |s| s.start));
        SceneFileError::Invalid {
            path: self.path.clone(),
            line,
            column,
            message: short_numbers(&message),
        }
    }

    /// Deserialises the text into `File`, a large text in parts (`parts.rs`).
    fn file(&self) -> Result<File, SceneFileError> {
        let outline = parts::outline(&self.text, MAX_OBJECTS);
        if let Some(at) = outline.excess_object {
            return Err(self.error(Some(at..at), placement::too_many_objects()));
        }
        let mut file = File::default();
        for part in outline.parts {
            if part.len() > parts::MAX_PART_BYTES {
                return Err(self.error(
                    Some(part.start..part.start),
                    format!(
                        "{} MB from here on could not be cut into parts of at most {} MiB: \
                         timbre parses large files in parts cut before plain `[[name]]` \
                         headers (no quoted keys), so write long lists as `[[object]]` \
                         entries and large meshes as mesh files",
                        part.len() / 1_000_000,
                        parts::MAX_PART_BYTES >> 20
                    ),
                ));
            }
            let start = part.start;
            let more: File = parts::in_part(&self.text, part).map_err(|(span, e)| {
                let message = parser_message(&self.text, &span, e.message().trim());
                self.error(Some(span), message)
            })?;
            file.append(more)
                .map_err(|key| self.error(Some(start..start), duplicate(key)))?;
        }
        Ok(file)
    }
}

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct File {
    studio: Option<StudioName>,
    render: Option<Spanned<SettingValues>>,
    camera: Option<Spanned<CameraSection>>,
    #[serde(default)]
    light: Vec<LightSection>,
    #[serde(default)]
    object: Vec<ObjectSection>,
    #[serde(default)]
    device: Vec<Spanned<DeviceSection>>,
    #[serde(default)]
    group: Vec<GroupSection>,
    #[serde(default)]
    include: Vec<IncludeSection>,
    window: Option<Spanned<WindowSection>>,
    sky: Option<Spanned<SkyKeys>>,
    #[serde(default)]
    ray_trajectory: Vec<Spanned<TrajectorySection>>,
    animation: Option<Spanned<AnimationKeys>>,
}

/// The METATOY window's pane (studio "metatoy-window").
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct WindowSection {
    surface: Spanned<SurfaceKeys>,
}

impl File {
    /// Adds the tables of the next part of the file. Only the first part has top-level keys,
    /// and a table opened in two parts is parsed in one (`parts.rs`), so a key given in both
    /// (the name is returned) is a duplicate the cut did not foresee, never a replacement.
    fn append(&mut self, next: File) -> Result<(), &'static str> {
        fn one<T>(a: &mut Option<T>, b: Option<T>, name: &'static str) -> Result<(), &'static str> {
            match (a.is_some(), b) {
                (true, Some(_)) => Err(name),
                (_, b) => {
                    *a = a.take().or(b);
                    Ok(())
                }
            }
        }
        one(&mut self.studio, next.studio, "studio")?;
        one(&mut self.render, next.render, "render")?;
        one(&mut self.camera, next.camera, "camera")?;
        one(&mut self.window, next.window, "window")?;
        one(&mut self.sky, next.sky, "sky")?;
        one(&mut self.animation, next.animation, "animation")?;
        self.light.extend(next.light);
        self.object.extend(next.object);
        self.device.extend(next.device);
        self.group.extend(next.group);
        self.include.extend(next.include);
        self.ray_trajectory.extend(next.ray_trajectory);
        Ok(())
    }

    fn items(self) -> Items {
        Items {
            object: self.object,
            device: self.device,
            group: self.group,
            include: self.include,
        }
    }
}

#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(rename_all = "kebab-case")]
enum StudioName {
    /// Sky, floor, lights and camera of TIM's standard studio.
    Empty,
    /// The empty studio plus TIM's cylinder lattice.
    Lattice,
    /// TIM's "METATOY science" scene: a lattice behind a framed METATOY window.
    #[serde(alias = "metatoy_window")]
    MetatoyWindow,
    /// Nothing at all: no sky, no floor, no lights.
    None,
}

#[derive(Debug, Deserialize)]
#[serde(tag = "type", rename_all = "kebab-case", deny_unknown_fields)]
enum LightSection {
    Ambient {
        colour: Rgb,
    },
    Point {
        position: Vector,
        colour: Rgb,
        phong_exponent: Option<Positive>,
    },
}

fn yes() -> bool {
    true
}

/// Largest scene file (each of a scene and its includes) that is read, in bytes (256 MiB: a
/// million spheres take about 130 MB).
pub const MAX_FILE_BYTES: u64 = 256 << 20;

/// Reads and checks a scene file, with `overrides` applied: the file's own errors are
/// reported at their line and column first.
fn read(path: &Path, overrides: &[Override]) -> Result<(Source, File), SceneFileError> {
    read_text(read_file(path)?, &path.display().to_string(), overrides)
}

/// A scene file's text, as [`load`] reads it: a regular file of at most [`MAX_FILE_BYTES`],
/// UTF-8 (what [`parse_with`] then takes, with the path).
pub fn read_file(path: &Path) -> Result<String, SceneFileError> {
    let shown = path.display().to_string();
    let bytes =
        crate::files::read_regular(path, MAX_FILE_BYTES).map_err(|source| SceneFileError::Io {
            path: shown.clone(),
            source,
        })?;
    let text = String::from_utf8(bytes).map_err(|e| {
        let valid = e.utf8_error().valid_up_to();
        let before = String::from_utf8_lossy(&e.as_bytes()[..valid]);
        let (line, column) = line_column(&before, valid);
        SceneFileError::Invalid {
            path: shown.clone(),
            line,
            column,
            message: format!("the file is not UTF-8 text (invalid bytes at byte offset {valid})"),
        }
    })?;
    Ok(text)
}

fn read_text(
    text: String,
    path: &str,
    overrides: &[Override],
) -> Result<(Source, File), SceneFileError> {
    let mut source = Source::new(text, path);
    let file = source.file()?;
    if overrides.is_empty() {
        return Ok((source, file));
    }
    source.overrides = overrides.to_vec();
    source.text = overrides::apply(&source.text, overrides).map_err(|m| source.error(None, m))?;
    let file = source.file()?;
    Ok((source, file))
}

/// Reads a scene file.
pub fn load(path: &Path) -> Result<SceneDescription, SceneFileError> {
    load_with(path, &[])
}

/// Reads a scene file with `--set` overrides applied.
pub fn load_with(path: &Path, overrides: &[Override]) -> Result<SceneDescription, SceneFileError> {
    let (source, file) = read(path, overrides)?;
    describe(&source, file, path, None)
}

/// Parses scene-file text; `path` names it in error messages and locates relative paths.
pub fn parse(text: &str, path: &str) -> Result<SceneDescription, SceneFileError> {
    parse_with(text, path, &[])
}

/// Scene-file text with `--set` overrides applied, as TOML (the overrides' own errors as
/// messages).
pub fn with_overrides(text: &str, overrides: &[Override]) -> Result<String, String> {
    overrides::apply(text, overrides)
}

/// Parses scene-file text with `--set` overrides applied (the text's own errors first, at
/// their line and column), as [`load_with`] reads a file.
pub fn parse_with(
    text: &str,
    path: &str,
    overrides: &[Override],
) -> Result<SceneDescription, SceneFileError> {
    let (source, file) = read_text(text.to_string(), path, overrides)?;
    describe(&source, file, Path::new(path), None)
}

/// Parses scene-file text as [`parse_with`] does, reading only files in the scene file's
/// directory (`path`'s, symbolic links followed), however deep the includes that name them,
/// except the files named in `text` itself that `confinement` trusts. Each file is checked
/// before it is touched, so nothing of a refused one is read or shown.
pub fn parse_confined(
    text: &str,
    path: &str,
    overrides: &[Override],
    confinement: &Confinement,
) -> Result<SceneDescription, SceneFileError> {
    let (source, file) = read_text(text.to_string(), path, overrides)?;
    let path = Path::new(path);
    describe(&source, file, path, Some(&Within::new(path, confinement)))
}

/// The scene a checked file describes; `within`: the confinement of the files it reaches.
fn describe(
    source: &Source,
    file: File,
    path: &Path,
    within: Option<&Within>,
) -> Result<SceneDescription, SceneFileError> {
    let invalid = |span: Option<Range<usize>>, message: String| source.error(span, message);
    let studio = match file.studio.unwrap_or(StudioName::Empty) {
        StudioName::Empty => Some(Studio::Empty),
        StudioName::Lattice => Some(Studio::Lattice),
        StudioName::MetatoyWindow => Some(Studio::MetatoyWindow),
        StudioName::None => None,
    };
    let mut scene = match studio {
        Some(s) => s.description(),
        None => SceneDescription {
            objects: Vec::new(),
            arrays: Vec::new(),
            lights: Lights::none(),
            camera: studio::camera(),
            focus_surface: Vec::new(),
            stereo: Default::default(),
            file_warnings: Vec::new(),
            render: Default::default(),
            trajectories: Vec::new(),
            animation: None,
        },
    };

    if let Some(r) = file.render {
        let span = r.span();
        let s = &mut scene.render;
        r.into_inner().apply(s);
        s.validate().map_err(|m| invalid(Some(span), m))?;
    }

    if let Some(camera) = file.camera {
        let span = camera.span();
        // The stereo output is checked against the image size by the caller, after any
        // command-line size.
        let setup = camera.into_inner().build(source, Some(span))?;
        scene.camera = setup.camera;
        scene.focus_surface = setup.focus_surface;
        scene.stereo = setup.stereo;
    }

    // Lights given in the file replace the studio's lights.
    if !file.light.is_empty() {
        scene.lights = lights(file.light);
    }

    if let Some(animation) = file.animation {
        let span = animation.span();
        let animation = animation
            .into_inner()
            .build()
            .map_err(|m| invalid(Some(span), format!("animation: {m}")))?;
        scene.animation = Some(animation);
    }

    for (k, t) in file.ray_trajectory.into_iter().enumerate() {
        let span = t.span();
        let trajectory = t.into_inner().build(source, span, k + 1)?;
        scene.trajectories.push(trajectory);
    }

    let mut placer = Placer::new(path, source.text.len(), within);
    let mut links = Vec::new();
    if let Some(window) = file.window {
        links.extend(set_window(source, &mut placer, &mut scene, studio, window)?);
    }
    if let Some(sky) = file.sky {
        set_sky(source, &mut placer, &mut scene, sky)?;
    }

    let studio_objects = scene.objects.len();
    let items = Items {
        object: file.object,
        device: file.device,
        group: file.group,
        include: file.include,
    };
    let placed = placer.items(
        source,
        items,
        &Transform::IDENTITY,
        placement::Inherited::TOP,
        "",
    )?;
    scene.objects.extend(placed.objects);
    scene.file_warnings.append(&mut placer.warnings);
    scene.arrays.extend(placed.arrays.into_iter().map(|mut a| {
        a.objects = a.objects.start + studio_objects..a.objects.end + studio_objects;
        a
    }));
    let mut linked = vec![false; scene.objects.len()];
    for link in links.into_iter().chain(placer.links) {
        link_teleporter(&mut scene, &mut linked, &link.origin, &link.destination).map_err(|m| {
            link.at
                .with_message(format!("{}: {m}", object_label(&link.origin)))
        })?;
    }
    Ok(scene)
}

/// The lights of the `[[light]]` tables: ambient colours add up.
fn lights(sections: Vec<LightSection>) -> Lights {
    let mut lights = Lights::none();
    for light in sections {
        match light {
            LightSection::Ambient { colour } => lights.ambient += colour.0,
            LightSection::Point {
                position,
                colour,
                phong_exponent,
            } => lights.points.push(PointLight {
                position: position.0,
                colour: colour.0,
                phong_exponent: phong_exponent.map_or(40.0, |k| k.0),
            }),
        }
    }
    lights
}

/// Gives the pane of the METATOY window studio the `[window]` table's surface; a teleporting
/// pane's link to its destination is returned, to be made once every object is placed.
fn set_window(
    source: &Source,
    placer: &mut Placer,
    scene: &mut SceneDescription,
    studio: Option<Studio>,
    window: Spanned<WindowSection>,
) -> Result<Option<Link>, SceneFileError> {
    let span = window.span();
    let pane = scene
        .objects
        .iter_mut()
        .find(|o| o.name == studio::WINDOW && studio == Some(Studio::MetatoyWindow))
        .ok_or_else(|| {
            source.error(
                Some(span),
                "[window] sets the pane of studio = \"metatoy-window\", which this scene does not use".into(),
            )
        })?;
    let surface_span = window.into_inner().surface;
    let (span, mut section) = (surface_span.span(), surface_span.into_inner());
    let at = |m: String| source.error(Some(span.clone()), format!("window: {m}"));
    placer.open_pictures(source, &mut section).map_err(at)?;
    let link = section.destination().map(|destination| Link {
        origin: studio::WINDOW.to_string(),
        destination: destination.to_string(),
        at: at(String::new()),
    });
    pane.surface = section.build().map_err(at)?;
    pane.surface.check_shape(&pane.shape).map_err(at)?;
    Ok(link)
}

/// Gives the studio's sky the `[sky]` table's picture, or adds a sky with it to a scene
/// without a studio.
fn set_sky(
    source: &Source,
    placer: &mut Placer,
    scene: &mut SceneDescription,
    sky: Spanned<SkyKeys>,
) -> Result<(), SceneFileError> {
    let span = sky.span();
    let at = |m: String| source.error(Some(span.clone()), format!("sky: {m}"));
    let mut keys = sky.into_inner();
    keys.image.picture = Some(placer.picture(source, &keys.image.name).map_err(at)?);
    let surface = keys.build().map_err(at)?;
    match scene.objects.iter_mut().find(|o| o.name == "sky") {
        Some(studio_sky) => studio_sky.surface = surface,
        None => scene.objects.push(SceneObject {
            surface,
            ..studio::sky()
        }),
    }
    Ok(())
}

/// Gives the teleporting surfaces of object `origin` (and, for a mesh file, its parts) the
/// shape of the object named `destination`, which must be a single analytic shape at rest in
/// the same frame. `linked` marks the objects linked so far: an object two links name is an
/// error, since teleporting objects are told apart by their names.
fn link_teleporter(
    scene: &mut SceneDescription,
    linked: &mut [bool],
    origin: &str,
    destination: &str,
) -> Result<(), String> {
    let named: Vec<usize> = (0..scene.objects.len())
        .filter(|&i| scene.objects[i].name == destination)
        .collect();
    let &[target] = named.as_slice() else {
        return Err(if named.is_empty() {
            format!(
                "teleporting: no object is named '{destination}' (the destination is named in full, with its group names, as `timbre check` lists it)"
            )
        } else {
            format!(
                "teleporting: {} objects are named '{destination}'; give the destination a unique name",
                named.len()
            )
        });
    };
    if scene.arrays.iter().any(|a| a.objects.contains(&target)) {
        return Err(format!(
            "teleporting: the destination '{destination}' is repeated in an array; it must be a single object"
        ));
    }
    let target = &scene.objects[target];
    if matches!(target.shape, Shape::TriangleMesh(_)) {
        return Err(format!(
            "teleporting: the destination '{destination}' is a mesh, which has no surface coordinates to arrive at; use an analytic shape"
        ));
    }
    let (shape, frame) = (target.shape.clone(), target.frame);
    let part = format!("{origin}/");
    for (o, done) in scene.objects.iter_mut().zip(linked) {
        let mesh_part = o.name.starts_with(&part) && matches!(o.shape, Shape::TriangleMesh(_));
        if (o.name == origin || mesh_part)
            && let Surface::Teleporting(t) = &mut o.surface
        {
            if *done {
                return Err(format!(
                    "teleporting: another teleporting object is also named '{}'; teleporting objects need unique names",
                    o.name
                ));
            }
            if o.frame != frame {
                return Err(format!(
                    "teleporting: the destination '{destination}' is at rest in another frame"
                ));
            }
            t.destination = Some(shape.clone());
            *done = true;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Colour;
    use crate::surfaces::Refractive;
    use crate::surfaces::Surface;

    fn error(text: &str) -> String {
        parse(text, "s.toml").unwrap_err().to_string()
    }

    #[test]
    fn the_issue_example_parses() {
        let s = parse(
            r#"
studio = "lattice"
[render]
width = 64
height = 48
[camera]
type = "pinhole"
position = [0,0,0]
view_direction = [0,0,1]
up = [0,1,0]
horizontal_view_angle_deg = 20
[[light]]
type = "point"
position = [100,300,-500]
colour = [1,1,1]
[[object]]
name = "ball"
shadow_throwing = true
shape = { type = "sphere", centre = [0,0,5], radius = 0.5 }
surface = { type = "refractive", index_ratio = 1.5, transmission = 0.96 }
"#,
            "s.toml",
        )
        .unwrap();
        assert_eq!(s.objects.len(), 2 + 48 + 1);
        assert_eq!((s.render.width, s.render.height), (64, 48));
        assert_eq!(s.lights.points.len(), 1);
        assert_eq!(
            s.lights.ambient,
            Colour::ZERO,
            "file lights replace the studio's"
        );
        assert_eq!(
            s.objects.last().unwrap().surface,
            Surface::Refractive(Refractive {
                index_ratio: 1.5,
                transmission_coefficient: 0.96
            })
        );
    }

    #[test]
    fn errors_name_line_column_and_reason() {
        let e = error(
            "studio = \"empty\"\n[[object]]\nshape = { type = \"sphere\", centre = [0,0,5], radius = -0.5 }\nsurface = { type = \"matt\", colour = [1,1,1] }\n",
        );
        assert!(e.starts_with("s.toml:3:"), "{e}");
        assert!(
            e.contains("expected a positive number of at most 1e15, got -0.5"),
            "{e}"
        );

        let e = error("[render]\nwidht = 3\n");
        assert!(
            e.starts_with("s.toml:2:1:") && e.contains("unknown field `widht`"),
            "{e}"
        );

        let e = error("[render]\nwidth = \n");
        assert!(e.starts_with("s.toml:2:"), "{e}");

        let e = error(
            "[[object]]\nshape = { type = \"cylinder\", start = [0,0,1], end = [0,0,1], radius = 1 }\nsurface = { type = \"mirror\" }\n",
        );
        assert!(
            e.starts_with("s.toml:2:9:") && e.contains("start and end coincide"),
            "{e}"
        );

        let e = error(
            "[camera]\ntype = \"pinhole\"\nposition = [0,0,0]\nview_direction = [0,1,0]\nup = [0,2,0]\nhorizontal_view_angle_deg = 20\n",
        );
        assert!(e.contains("not parallel"), "{e}");

        let e = error(
            "[[object]]\nshape = { type = \"sphere\", centre = [0,nan,5], radius = 1 }\nsurface = { type = \"mirror\" }\n",
        );
        assert!(e.contains("finite"), "{e}");
    }

    #[test]
    fn a_plane_u_direction_along_the_normal_is_rejected() {
        let e = error(
            "[[object]]\nshape = { type = \"plane\", point = [0,0,5], normal = [0,0,1], u_direction = [0,0,2] }\nsurface = { type = \"mirror\" }\n",
        );
        assert!(
            e.starts_with("s.toml:2:9:") && e.contains("parallel to the normal"),
            "{e}"
        );
    }

    #[test]
    fn line_and_column_are_one_based() {
        assert_eq!(line_column("ab\ncd", 0), (1, 1));
        assert_eq!(line_column("ab\ncd", 4), (2, 2));
    }
}
