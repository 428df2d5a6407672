//! `[animation]`: a movie, a sequence of frames in each of which scene values take the
//! frame's value on their tracks (Dr TIM's `NonInteractiveTIMEngine` movie parameters
//! `numberOfFrames`, `firstFrame` and `lastFrame`; a Dr TIM program computes its values for
//! each `frame` in code, a scene file keyframes them).
//!
//! A track changes one value of the scene file, named by its `--set` key (`camera.position`,
//! `object.2.shape.radius`), through keyframes (frame, value). Between two keyframes a and b,
//! with u = (k − a)/(b − a) at frame k, numbers (and each number of an array of numbers) are
//! interpolated linearly, v = v_a + u (v_b − v_a), or smoothly, with u replaced by
//! 3u² − 2u³ (a cubic that eases out of a and into b, its slope 0 at both), or step (hold a's
//! value until b); between two whole numbers a whole result stays a whole number (so that a
//! whole-number setting such as `render.spp` can be animated through values that land on whole
//! numbers, or stepped). Other values (strings, booleans, tables) step. Before the first keyframe a track has
//! its first value, after the last its last. Frame k renders the file as though each track's
//! value at k were given with `--set`.

use serde::Deserialize;
use toml::Value;

use super::file::Override;

/// Dr TIM's `numberOfFrames` by default.
pub const DEFAULT_FRAMES: u32 = 10;
/// Frames a second of the encoded video, by default.
pub const DEFAULT_FPS: f64 = 25.0;
/// The most frames a movie may have.
pub const MAX_FRAMES: u32 = 1_000_000;

#[derive(Debug, Clone, PartialEq)]
pub struct Animation {
    /// Frames in the whole movie (Dr TIM's `numberOfFrames`).
    pub frames: u32,
    /// The frames this run renders, first to last inclusive (Dr TIM's `firstFrame`,
    /// `lastFrame`).
    pub first_frame: u32,
    pub last_frame: u32,
    /// Frames a second of the encoded video.
    pub fps: f64,
    pub tracks: Vec<Track>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Interpolation {
    Linear,
    Smooth,
    Step,
}

/// A track, as its keys make it: at least one keyframe, frames increasing, values of one kind.
#[derive(Debug, Clone, PartialEq)]
pub struct Track {
    /// The `--set` key.
    key: String,
    interpolation: Interpolation,
    /// (frame, value).
    keyframes: Vec<(f64, Value)>,
}

impl Animation {
    /// The track that a `--set` of `o` clashes with: one of an animated value, of a part of
    /// one or of a table holding one, which the track would overwrite, or which would
    /// overwrite the track.
    pub fn clash(&self, o: &Override) -> Option<&Track> {
        self.tracks.iter().find(|track| {
            let animated: Vec<&str> = track.key.split('.').collect();
            let n = o.key.len().min(animated.len());
            o.key[..n].iter().zip(&animated[..n]).all(|(a, b)| a == b)
        })
    }

    /// The `--set` overrides that make frame `k` of the scene file.
    pub fn overrides(&self, k: u32) -> Vec<Override> {
        self.tracks
            .iter()
            .map(|t| Override::new(&t.key, t.value(k as f64)))
            .collect()
    }
}

impl Track {
    /// The `--set` key of the value the track changes.
    pub fn key(&self) -> &str {
        &self.key
    }

    /// The frames of the keyframes.
    pub fn keyframe_frames(&self) -> impl Iterator<Item = f64> + '_ {
        self.keyframes.iter().map(|(frame, _)| *frame)
    }

    /// Whether the track, of whole numbers, takes a number with a fraction at frame `k`.
    pub fn fraction_at(&self, k: u32) -> bool {
        let whole = |v: &Value| match v {
            Value::Integer(_) => true,
            Value::Array(a) => a.iter().all(Value::is_integer),
            _ => false,
        };
        self.keyframes.iter().all(|(_, v)| whole(v)) && !whole(&self.value(k as f64))
    }

    /// The track's value at frame `k`.
    pub fn value(&self, k: f64) -> Value {
        let keys = &self.keyframes;
        let after = keys.partition_point(|(frame, _)| *frame <= k);
        if after == 0 {
            return keys[0].1.clone();
        }
        let (a, va) = &keys[after - 1];
        let Some((b, vb)) = keys.get(after) else {
            return va.clone();
        };
        let u = (k - a) / (b - a);
        let u = match self.interpolation {
            Interpolation::Linear => u,
            Interpolation::Smooth => u * u * (3.0 - 2.0 * u),
            Interpolation::Step => return va.clone(),
        };
        between(va, vb, u)
    }
}

/// The value a fraction `u` of the way from `a` to `b` (numbers or arrays of numbers, checked
/// when the track was read); a whole number between whole numbers stays one.
fn between(a: &Value, b: &Value, u: f64) -> Value {
    match (a, b) {
        (Value::Integer(x), Value::Integer(y)) => {
            let v = *x as f64 + u * (*y as f64 - *x as f64);
            if v == v.round() && v.abs() < 9e15 {
                Value::Integer(v as i64)
            } else {
                Value::Float(v)
            }
        }
        (Value::Array(x), Value::Array(y)) => {
            Value::Array(x.iter().zip(y).map(|(x, y)| between(x, y, u)).collect())
        }
        _ => {
            let (x, y) = (number(a), number(b));
            Value::Float(x + u * (y - x))
        }
    }
}

fn number(v: &Value) -> f64 {
    match v {
        Value::Integer(i) => *i as f64,
        Value::Float(f) => *f,
        _ => f64::NAN,
    }
}

/// What a track's values are, for interpolation.
#[derive(PartialEq)]
enum Kind {
    Number,
    Numbers(usize),
    Other(&'static str),
}

fn kind(v: &Value) -> Kind {
    match v {
        Value::Integer(_) | Value::Float(_) => Kind::Number,
        Value::Array(a) if a.iter().all(|x| x.is_integer() || x.is_float()) => {
            Kind::Numbers(a.len())
        }
        other => Kind::Other(other.type_str()),
    }
}

/// `[animation]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AnimationKeys {
    frames: Option<u32>,
    first_frame: Option<u32>,
    last_frame: Option<u32>,
    fps: Option<f64>,
    #[serde(default)]
    track: Vec<TrackKeys>,
}

/// `[[animation.track]]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct TrackKeys {
    key: String,
    interpolation: Option<Interpolation>,
    keyframes: Vec<KeyframeKeys>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct KeyframeKeys {
    frame: f64,
    value: Value,
}

impl AnimationKeys {
    pub fn build(self) -> Result<Animation, String> {
        let frames = self.frames.unwrap_or(DEFAULT_FRAMES);
        if !(1..=MAX_FRAMES).contains(&frames) {
            return Err(format!(
                "frames must be from 1 to {MAX_FRAMES} (it is {frames})"
            ));
        }
        let first_frame = self.first_frame.unwrap_or(0);
        let last_frame = self.last_frame.unwrap_or(frames - 1);
        if first_frame > last_frame || last_frame >= frames {
            return Err(format!(
                "the frames rendered, first_frame = {first_frame} to last_frame = {last_frame}, \
                 must lie in order within the movie's {frames} frames (0 to {})",
                frames - 1
            ));
        }
        let fps = self.fps.unwrap_or(DEFAULT_FPS);
        if !(fps > 0.0 && fps <= 1000.0) {
            return Err(format!(
                "fps must be above 0 and at most 1000 (it is {fps})"
            ));
        }
        let mut tracks: Vec<Track> = Vec::with_capacity(self.track.len());
        for t in self.track {
            let track = t.build()?;
            if tracks.iter().any(|other| other.key == track.key) {
                return Err(format!("two tracks animate '{}'", track.key));
            }
            tracks.push(track);
        }
        Ok(Animation {
            frames,
            first_frame,
            last_frame,
            fps,
            tracks,
        })
    }
}

impl TrackKeys {
    fn build(self) -> Result<Track, String> {
        let key = &self.key;
        // The key as `--set` reads it.
        let parsed = format!("{key}=0")
            .parse::<Override>()
            .map_err(|e| format!("track '{key}': {e}"))?;
        if parsed.key[0] == "animation" {
            return Err(format!(
                "track '{key}': the animation cannot animate itself"
            ));
        }
        let at = |m: String| format!("track '{key}': {m}");
        if self.keyframes.is_empty() {
            return Err(at("no keyframes".into()));
        }
        for pair in self.keyframes.windows(2) {
            if pair[1].frame <= pair[0].frame {
                return Err(at(format!(
                    "keyframes must be in order of their frames ({} comes after {})",
                    pair[1].frame, pair[0].frame
                )));
            }
        }
        if let Some(k) = self.keyframes.iter().find(|k| !k.frame.is_finite()) {
            return Err(at(format!(
                "a keyframe's frame must be a number (it is {})",
                k.frame
            )));
        }
        let first = kind(&self.keyframes[0].value);
        if let Some(k) = self.keyframes.iter().find(|k| kind(&k.value) != first) {
            return Err(at(format!(
                "the keyframes' values must be of one kind: numbers, or arrays of as many \
                 numbers, or one type (the value at frame {} is not like the first)",
                k.frame
            )));
        }
        let interpolation = match (self.interpolation, first) {
            (None, Kind::Other(_)) => Interpolation::Step,
            (Some(i), Kind::Other(kind)) if i != Interpolation::Step => {
                return Err(at(format!(
                    "values of type {kind} cannot be interpolated; they step (interpolation = \
                     \"step\")"
                )));
            }
            (i, _) => i.unwrap_or(Interpolation::Linear),
        };
        Ok(Track {
            key: parsed.key.join("."),
            interpolation,
            keyframes: self
                .keyframes
                .into_iter()
                .map(|k| (k.frame, k.value))
                .collect(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn track(interpolation: Interpolation, keys: &[(f64, Value)]) -> Track {
        Track {
            key: "x".into(),
            interpolation,
            keyframes: keys.to_vec(),
        }
    }

    #[test]
    fn linear_smooth_and_step_between_keyframes() {
        let keys = [(0.0, Value::Float(1.0)), (4.0, Value::Float(3.0))];
        let at = |i, k| track(i, &keys).value(k).as_float().unwrap();
        // Linear: a quarter of the way at frame 1.
        assert_eq!(at(Interpolation::Linear, 1.0), 1.5);
        // Smooth: 3u² − 2u³ of the way, u = 1/4: 5/32.
        assert_eq!(at(Interpolation::Smooth, 1.0), 1.0 + 2.0 * 5.0 / 32.0);
        assert_eq!(at(Interpolation::Smooth, 2.0), 2.0);
        assert_eq!(at(Interpolation::Step, 3.0), 1.0);
        // Held before the first keyframe and after the last.
        assert_eq!(at(Interpolation::Linear, -1.0), 1.0);
        assert_eq!(at(Interpolation::Linear, 9.0), 3.0);
        assert_eq!(at(Interpolation::Linear, 4.0), 3.0);
    }

    #[test]
    fn arrays_component_by_component_and_whole_numbers_kept_whole() {
        let v = |x: &[f64]| Value::Array(x.iter().map(|&x| Value::Float(x)).collect());
        let t = track(
            Interpolation::Linear,
            &[(0.0, v(&[0.0, 0.0, -2.0])), (10.0, v(&[1.0, -1.0, -2.0]))],
        );
        assert_eq!(t.value(3.0), v(&[0.3, -0.3, -2.0]));
        let whole = track(
            Interpolation::Linear,
            &[(0.0, Value::Integer(100)), (3.0, Value::Integer(200))],
        );
        // v_a + u (v_b − v_a) at u = 1/3 is no whole number; at u = 1 it is.
        assert_eq!(whole.value(1.0), Value::Float(100.0 + (1.0 / 3.0) * 100.0));
        assert_eq!(whole.value(3.0), Value::Integer(200));
        let halves = track(
            Interpolation::Linear,
            &[(0.0, Value::Integer(1)), (2.0, Value::Integer(3))],
        );
        assert_eq!(halves.value(1.0), Value::Integer(2));
    }
}
