//! How to render a scene: image size, sampling and tracing limits (what `render` obeys), and
//! [`SETTINGS`], the one definition of the settings a scene file's `[render]` table, the command
//! line (`--max-trace-level`), the live preview's page (`render.max_trace_level`) and Python
//! (`max_trace_level=`) give.

use serde::Deserialize;
use serde::de::{self, DeserializeSeed, Deserializer, MapAccess, SeqAccess, Visitor};

/// How to render: image size, sampling and tracing limits.
#[derive(Debug, Clone, PartialEq)]
pub struct RenderSettings {
    pub width: u32,
    pub height: u32,
    /// Samples (primary rays) per pixel.
    pub spp: u32,
    pub seed: u64,
    /// Maximum number of surfaces a ray path may meet; a ray that runs out of levels is black.
    pub max_trace_level: u32,
    /// Scene-wide switch for hard shadows.
    pub shadows: bool,
    /// Also record depth, normal and object id of the surface seen through each pixel centre.
    pub aovs: bool,
    /// With `aovs`, also the albedo of each pixel (a mean of its first samples: the renderer's
    /// `ALBEDO_SAMPLES`).
    pub albedo: bool,
    /// Worker threads; `None` for as many as the machine has cores.
    pub threads: Option<usize>,
    /// Exposure compensation in stops: every output value is multiplied by 2^exposure (Dr TIM's
    /// exposure compensation), in every format.
    pub exposure: f64,
    /// How PNG files encode the linear values.
    pub png_transfer: PngTransfer,
}

/// How a PNG file's 8-bit values encode the linear values rendered.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum PngTransfer {
    /// The values themselves (clamped, ×255), as TIM writes them; the file says gamma 1.
    #[default]
    Linear,
    /// The sRGB transfer curve (IEC 61966-2-1); the file has an sRGB chunk.
    Srgb,
}

impl PngTransfer {
    /// The names `png_transfer` takes, in the order of the variants.
    pub const NAMES: &[&str] = &["linear", "srgb"];

    pub fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }

    /// The transfer called `name`, if it is one of [`Self::NAMES`].
    pub fn named(name: &str) -> Option<PngTransfer> {
        match name {
            "linear" => Some(PngTransfer::Linear),
            "srgb" => Some(PngTransfer::Srgb),
            _ => None,
        }
    }
}

/// Largest accepted maximum trace level. Tracing recurses once per level, so worker threads get
/// stacks sized for the level (see `render::render`).
pub const MAX_TRACE_LEVEL_LIMIT: u32 = 100_000;

/// Largest accepted image, in pixels (2³⁶, e.g. 262144 × 262144): single views are streamed to
/// their file in bounded memory, so the limit is one of sense (such a render takes days);
/// renders held in memory (stereo outputs) are limited by the memory there is.
pub const MAX_PIXELS: u64 = 1 << 36;

/// Largest accepted width or height (OpenEXR stores coordinates as 32-bit integers).
pub const MAX_SIDE: u32 = 1 << 24;

impl RenderSettings {
    /// Checks the limits a render must respect; the message says what is wrong.
    pub fn validate(&self) -> Result<(), String> {
        let pixels = self.width as u64 * self.height as u64;
        if self.width == 0 || self.height == 0 || self.spp == 0 || self.max_trace_level == 0 {
            return Err("width, height, spp and max_trace_level must be at least 1".into());
        }
        if self.width > MAX_SIDE || self.height > MAX_SIDE {
            return Err(format!(
                "an image of {}x{} pixels is wider or higher than the limit of {MAX_SIDE} pixels",
                self.width, self.height
            ));
        }
        if pixels > MAX_PIXELS {
            return Err(format!(
                "an image of {}x{} pixels is larger than the limit of {MAX_PIXELS} pixels",
                self.width, self.height
            ));
        }
        if self.max_trace_level > MAX_TRACE_LEVEL_LIMIT {
            return Err(format!(
                "max_trace_level {} is above the limit of {MAX_TRACE_LEVEL_LIMIT}",
                self.max_trace_level
            ));
        }
        Ok(())
    }
}

impl Default for RenderSettings {
    fn default() -> Self {
        RenderSettings {
            width: 640,
            height: 480,
            spp: 1,
            seed: 0,
            max_trace_level: 100,
            shadows: true,
            aovs: false,
            albedo: false,
            threads: None,
            exposure: 0.0,
            png_transfer: PngTransfer::Linear,
        }
    }
}

/// The value of a render setting.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Value {
    Whole(u64),
    Switch(bool),
    Number(f64),
    /// One of the names a [`Kind::Choice`] lists.
    Choice(&'static str),
}

/// The values a render setting takes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Kind {
    /// A whole number from `least` to `most`.
    Whole { least: u64, most: u64 },
    /// `true` or `false`.
    Switch,
    /// A number from `least` to `most`.
    Number { least: f64, most: f64 },
    /// One of these names.
    Choice(&'static [&'static str]),
}

/// One render setting: its key (`[render]`'s, the command line's with dashes for underscores,
/// the page's as `render.KEY`, Python's keyword), what it is, the values it takes, and how it
/// is read from and written into [`RenderSettings`].
#[derive(Debug)]
pub struct Setting {
    pub key: &'static str,
    /// What it is, as the command line's help says it.
    pub help: &'static str,
    pub kind: Kind,
    get: fn(&RenderSettings) -> Value,
    /// Sets a value of the setting's kind (checked by [`Setting::set`]).
    set: fn(&mut RenderSettings, Value),
}

/// Whole numbers from 1 that fit a u32 (sizes, samples, levels).
const COUNT: Kind = Kind::Whole {
    least: 1,
    most: u32::MAX as u64,
};

/// Every render setting of a scene. Adding one here gives it its `[render]` key, its command-line
/// option of `timbre render`, its parameter on the live preview's page, its entry in Python's
/// `Scene.settings` and its keyword of `Scene.render` (whose signature and stub list it, as a
/// test checks).
pub const SETTINGS: [Setting; 8] = [
    Setting {
        key: "width",
        help: "Image width in pixels",
        kind: COUNT,
        get: |s| Value::Whole(s.width.into()),
        set: |s, v| s.width = v.whole() as u32,
    },
    Setting {
        key: "height",
        help: "Image height in pixels",
        kind: COUNT,
        get: |s| Value::Whole(s.height.into()),
        set: |s, v| s.height = v.whole() as u32,
    },
    Setting {
        key: "spp",
        help: "Samples per pixel",
        kind: COUNT,
        get: |s| Value::Whole(s.spp.into()),
        set: |s, v| s.spp = v.whole() as u32,
    },
    Setting {
        key: "seed",
        help: "Seed of the random sample positions",
        kind: Kind::Whole {
            least: 0,
            most: u64::MAX,
        },
        get: |s| Value::Whole(s.seed),
        set: |s, v| s.seed = v.whole(),
    },
    Setting {
        key: "max_trace_level",
        help: "Maximum trace level: how many surfaces a ray path may meet",
        kind: COUNT,
        get: |s| Value::Whole(s.max_trace_level.into()),
        set: |s, v| s.max_trace_level = v.whole() as u32,
    },
    Setting {
        key: "shadows",
        help: "Whether objects throw shadows (hard shadows of the point lights)",
        kind: Kind::Switch,
        get: |s| Value::Switch(s.shadows),
        set: |s, v| s.shadows = v == Value::Switch(true),
    },
    Setting {
        key: "exposure",
        help: "Exposure compensation in stops: output values are multiplied by 2^EXPOSURE",
        kind: Kind::Number {
            least: -30.0,
            most: 30.0,
        },
        get: |s| Value::Number(s.exposure),
        set: |s, v| {
            if let Value::Number(x) = v {
                s.exposure = x;
            }
        },
    },
    Setting {
        key: "png_transfer",
        help: "How PNG values encode the linear values: linear (as TIM writes) or srgb",
        kind: Kind::Choice(PngTransfer::NAMES),
        get: |s| Value::Choice(s.png_transfer.name()),
        set: |s, v| {
            if let Value::Choice(name) = v {
                s.png_transfer = PngTransfer::named(name).unwrap_or_default();
            }
        },
    },
];

impl Value {
    /// A whole number's value (0 for another kind, which [`Setting::set`] never passes on).
    fn whole(self) -> u64 {
        match self {
            Value::Whole(n) => n,
            _ => 0,
        }
    }
}

impl Setting {
    /// The setting called `key`.
    pub fn named(key: &str) -> Option<&'static Setting> {
        SETTINGS.iter().find(|s| s.key == key)
    }

    /// The setting's value in `settings`.
    pub fn get(&self, settings: &RenderSettings) -> Value {
        (self.get)(settings)
    }

    /// Sets the setting in `settings` to `value`, or says what it takes instead.
    pub fn set(&self, settings: &mut RenderSettings, value: Value) -> Result<(), String> {
        let fits = match (self.kind, value) {
            (Kind::Whole { least, most }, Value::Whole(n)) => (least..=most).contains(&n),
            (Kind::Switch, Value::Switch(_)) => true,
            (Kind::Number { least, most }, Value::Number(x)) => (least..=most).contains(&x),
            (Kind::Choice(names), Value::Choice(name)) => names.contains(&name),
            _ => false,
        };
        if !fits {
            return Err(format!("expected {}, got {value}", self.kind.expected()));
        }
        (self.set)(settings, value);
        Ok(())
    }
}

impl Kind {
    /// What a value of this kind is, for messages: "a whole number from 1 to 4294967295".
    pub fn expected(self) -> String {
        match self {
            Kind::Whole { least, most } => format!("a whole number from {least} to {most}"),
            Kind::Switch => "true or false".into(),
            Kind::Number { least, most } => format!("a number from {least} to {most}"),
            Kind::Choice(names) => format!("one of {}", names.join(", ")),
        }
    }

    /// A value written as on the command line (`640`, `true`), or what the kind takes instead.
    pub fn parse(self, text: &str) -> Result<Value, String> {
        match self {
            Kind::Whole { least, most } => whole_number(text, least, most).map(Value::Whole),
            Kind::Switch => text
                .parse::<bool>()
                .map(Value::Switch)
                .map_err(|_| format!("expected {}, got '{text}'", self.expected())),
            Kind::Number { least, most } => text
                .parse::<f64>()
                .ok()
                .filter(|x| (least..=most).contains(x))
                .map(Value::Number)
                .ok_or_else(|| format!("expected {}, got '{text}'", self.expected())),
            Kind::Choice(_) => self
                .choice(text)
                .ok_or_else(|| format!("expected {}, got '{text}'", self.expected())),
        }
    }

    /// The name of a [`Kind::Choice`] that `text` is.
    fn choice(self, text: &str) -> Option<Value> {
        match self {
            Kind::Choice(names) => names
                .iter()
                .find(|&&n| n == text)
                .map(|&n| Value::Choice(n)),
            _ => None,
        }
    }
}

/// A whole number from `least` to `most` written as on the command line, or the message that
/// says so.
pub fn whole_number(text: &str, least: u64, most: u64) -> Result<u64, String> {
    text.parse::<u64>()
        .ok()
        .filter(|n| (least..=most).contains(n))
        .ok_or_else(|| {
            format!(
                "expected {}, got '{text}'",
                Kind::Whole { least, most }.expected()
            )
        })
}

impl std::fmt::Display for Value {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Value::Whole(n) => write!(f, "{n}"),
            Value::Switch(b) => write!(f, "{b}"),
            Value::Number(x) => write!(f, "{x}"),
            Value::Choice(name) => write!(f, "'{name}'"),
        }
    }
}

/// Values of some of [`SETTINGS`], in the order they are given: a `[render]` table's (read with
/// each value checked, an error at the key or value otherwise) or the command line's options.
#[derive(Debug, Clone, Default)]
pub struct SettingValues(Vec<(&'static Setting, Value)>);

impl SettingValues {
    /// Adds `value` of `setting`, or says what the setting takes instead.
    pub fn push(&mut self, setting: &'static Setting, value: Value) -> Result<(), String> {
        setting.set(&mut RenderSettings::default(), value)?;
        self.0.push((setting, value));
        Ok(())
    }

    /// `settings` with these values in place.
    pub fn apply(&self, settings: &mut RenderSettings) {
        for (setting, value) in &self.0 {
            setting.set(settings, *value).expect("checked when given");
        }
    }

    /// These values over a scene's `settings`, as the command line, the live preview and
    /// Python give them: a width or a height given alone scales the other, rounded (at least
    /// 1), so that the picture keeps the scene's aspect ratio.
    pub fn apply_over(&self, settings: &mut RenderSettings) {
        let (width, height) = (settings.width, settings.height);
        self.apply(settings);
        let scaled = |n: u32, new: u32, old: u32| {
            (n as f64 * new as f64 / old as f64)
                .round()
                .clamp(1.0, u32::MAX as f64) as u32
        };
        match (self.gives("width"), self.gives("height")) {
            (true, false) => settings.height = scaled(height, settings.width, width),
            (false, true) => settings.width = scaled(width, settings.height, height),
            _ => {}
        }
    }

    /// Whether `key` is given.
    pub fn gives(&self, key: &str) -> bool {
        self.0.iter().any(|(s, _)| s.key == key)
    }
}

impl<'de> Deserialize<'de> for SettingValues {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Table;
        impl<'de> Visitor<'de> for Table {
            type Value = SettingValues;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str("a table of render settings")
            }
            fn visit_seq<A: SeqAccess<'de>>(self, _: A) -> Result<SettingValues, A::Error> {
                Err(de::Error::custom("expected a table, not an array"))
            }
            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<SettingValues, A::Error> {
                let mut table = SettingValues::default();
                while let Some(setting) = map.next_key_seed(Key)? {
                    let value = map.next_value_seed(setting)?;
                    table.0.push((setting, value));
                }
                Ok(table)
            }
        }
        d.deserialize_map(Table)
    }
}

/// A `[render]` key, read as the setting it names (an error at the key otherwise).
struct Key;

impl<'de> DeserializeSeed<'de> for Key {
    type Value = &'static Setting;

    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<&'static Setting, D::Error> {
        const KEYS: [&str; SETTINGS.len()] = {
            let mut keys = [""; SETTINGS.len()];
            let mut i = 0;
            while i < SETTINGS.len() {
                keys[i] = SETTINGS[i].key;
                i += 1;
            }
            keys
        };
        let key = String::deserialize(d)?;
        Setting::named(&key).ok_or_else(|| de::Error::unknown_field(&key, &KEYS))
    }
}

/// A setting's value read where it is written, so that an error has the value's place.
impl<'de> DeserializeSeed<'de> for &'static Setting {
    type Value = Value;

    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<Value, D::Error> {
        d.deserialize_any(self)
    }
}

impl<'de> Visitor<'de> for &'static Setting {
    type Value = Value;

    fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.kind.expected())
    }

    fn visit_i64<E: de::Error>(self, n: i64) -> Result<Value, E> {
        if let Kind::Number { .. } = self.kind {
            return self.checked(Value::Number(n as f64));
        }
        match u64::try_from(n) {
            Ok(n) => self.visit_u64(n),
            Err(_) => Err(E::custom(format!(
                "expected {}, got {n}",
                self.kind.expected()
            ))),
        }
    }

    fn visit_u64<E: de::Error>(self, n: u64) -> Result<Value, E> {
        match self.kind {
            // `exposure = 1` is a number too.
            Kind::Number { .. } => self.checked(Value::Number(n as f64)),
            _ => self.checked(Value::Whole(n)),
        }
    }

    fn visit_bool<E: de::Error>(self, b: bool) -> Result<Value, E> {
        self.checked(Value::Switch(b))
    }

    fn visit_f64<E: de::Error>(self, x: f64) -> Result<Value, E> {
        self.checked(Value::Number(x))
    }

    fn visit_str<E: de::Error>(self, text: &str) -> Result<Value, E> {
        match (self.kind, self.kind.choice(text)) {
            (_, Some(value)) => self.checked(value),
            (Kind::Choice(_), None) => Err(E::invalid_value(de::Unexpected::Str(text), &self)),
            _ => Err(E::invalid_type(de::Unexpected::Str(text), &self)),
        }
    }
}

impl Setting {
    /// `value`, if it is one this setting takes.
    fn checked<E: de::Error>(&self, value: Value) -> Result<Value, E> {
        self.set(&mut RenderSettings::default(), value)
            .map(|()| value)
            .map_err(E::custom)
    }
}
