//! What the server sends a page: one typed message each, as JSON text with its `type` (frames go
//! as binary messages, `engine::encode`). What a page sends is `protocol::ClientMessage`.

use serde::Serialize;

use super::parameters::Parameter;
use super::preview::Inspection;

/// A message to the page.
#[derive(Debug, Serialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum ToPage<'a> {
    /// A scene loaded (generation `generation` of the inputs).
    Scene(SceneState<'a>),
    /// A scene that did not load (with its place in `text`, and the text itself, when the
    /// load failed), or a render pass that failed (a message alone).
    Error {
        #[serde(skip_serializing_if = "Option::is_none")]
        generation: Option<u64>,
        message: String,
        #[serde(skip_serializing_if = "Option::is_none")]
        line: Option<usize>,
        #[serde(skip_serializing_if = "Option::is_none")]
        column: Option<usize>,
        /// `None` for a text too long to send back (see `shown_text`), or a failed pass.
        #[serde(skip_serializing_if = "Option::is_none")]
        text: Option<&'a str>,
    },
    /// What became of a request (saved, written, refused): `error` when it went wrong.
    Notice { message: String, error: bool },
    /// What the ray through pixel (`x`, `y`) meets first, if anything.
    Inspection {
        x: u32,
        y: u32,
        hit: Option<Hit<'a>>,
    },
    /// How much of a render to a file is done.
    Saving { fraction: f64 },
    /// A public server has as many visitors as it takes: this page is not served (the
    /// connection closes after this message).
    Busy { message: String },
}

impl ToPage<'_> {
    /// The message as the JSON text the page is sent.
    pub fn text(&self) -> String {
        serde_json::to_string(self).expect("messages are plain data")
    }

    /// A notice of `result`: its message, or its error.
    pub fn notice(result: Result<String, String>) -> ToPage<'static> {
        match result {
            Ok(message) => ToPage::Notice {
                message,
                error: false,
            },
            Err(message) => ToPage::Notice {
                message,
                error: true,
            },
        }
    }
}

/// A loaded scene as the page shows it: its text (`None` when too long to send back), the
/// page's and command line's `--set`s, the parameters offered as sliders, the camera (for
/// navigation, and as TOML to copy) and the render settings.
#[derive(Debug, Serialize)]
pub struct SceneState<'a> {
    pub generation: u64,
    pub path: String,
    pub text: Option<&'a str>,
    pub overrides: Vec<String>,
    pub parameters: Vec<Parameter>,
    pub more_parameters: bool,
    pub camera: CameraState,
    pub camera_toml: String,
    pub stereo: &'static str,
    pub width: u32,
    pub height: u32,
    pub spp: u32,
    /// The scene's exposure setting, in stops: where the page's slider starts.
    pub exposure: f64,
    pub warnings: Vec<String>,
    /// A public server's page: nothing is saved or written (the page hides those controls).
    pub public: bool,
    /// The scene's `[animation]`, if it has one: the page's frame slider.
    pub animation: Option<AnimationState>,
}

/// A scene's movie as the page's frame slider shows it.
#[derive(Debug, Serialize)]
pub struct AnimationState {
    /// Frames in the movie, 0 to `frames` − 1.
    pub frames: u32,
    /// The frame shown; `None`: the scene as written.
    pub frame: Option<u32>,
}

/// The camera as the page moves it.
#[derive(Debug, Serialize)]
pub struct CameraState {
    pub position: [f64; 3],
    pub view_direction: [f64; 3],
    pub up: [f64; 3],
    pub horizontal_view_angle_deg: Option<f64>,
    pub view_width: Option<f64>,
}

/// What a pixel's ray meets: [`Inspection`] with its vectors as arrays.
#[derive(Debug, Serialize)]
pub struct Hit<'a> {
    object: &'a str,
    id: usize,
    surface: &'static str,
    distance: f64,
    point: [f64; 3],
    normal: [f64; 3],
    element: u32,
    part: u32,
    frame: &'static str,
}

impl<'a> From<&'a Inspection> for Hit<'a> {
    fn from(i: &'a Inspection) -> Hit<'a> {
        Hit {
            object: &i.object,
            id: i.id,
            surface: i.surface,
            distance: i.distance,
            point: i.point.to_array(),
            normal: i.normal.to_array(),
            element: i.element,
            part: i.part,
            frame: i.frame,
        }
    }
}
