//! The values of a scene file that the page offers as sliders and fields: every number, vector
//! of numbers, matrix and switch, named by the key `--set` takes for it.

use serde::Serialize;
use toml::{Table, Value};

/// Most parameters listed for one scene (a file of a million spheres has millions of numbers).
pub const MAX_PARAMETERS: usize = 2000;

/// One value of the scene file: its `--set` key and its value (a number, a boolean, or an array
/// of numbers, nested for matrices).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Parameter {
    pub key: String,
    pub value: serde_json::Value,
    /// Whether the value is a whole number (or an array of them), which `--set` keeps whole.
    pub integer: bool,
    /// The slider of a number ([`Slider::around`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub slider: Option<Slider>,
}

impl Parameter {
    /// The number this parameter is, if it is one (not a switch or an array).
    pub fn number(&self) -> Option<f64> {
        self.value.as_number().and_then(|n| n.as_f64())
    }
}

/// A slider's range and step for one number.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Slider {
    pub min: f64,
    pub max: f64,
    pub step: f64,
}

impl Slider {
    /// Most checks [`Slider::around`] makes: two ends, each checked, then v's grid point, then
    /// at most 64 halvings.
    pub const PROBES: usize = 2 * (2 + 64);

    /// The slider of the number `v` (`integer`: a whole number, which `--set` keeps whole): a
    /// span of twice its magnitude (1 for 0) either side, a round step (1 for whole numbers,
    /// else the power of ten about a hundredth of the span, so that round values such as 1 are
    /// on it), ends on the step's grid; each end then narrowed to the key's valid domain, as
    /// `valid` says (the scene checked with that value, as a `--set` of it would be): where an
    /// end is not valid, the valid end nearest it is found by bisection on the grid, between it
    /// and `v` (the valid values round `v` being an interval, as every key's are).
    pub fn around(v: f64, integer: bool, valid: &mut dyn FnMut(f64) -> bool) -> Slider {
        let span = if v == 0.0 { 1.0 } else { 2.0 * v.abs() };
        let digits = if integer {
            0
        } else {
            (2 - span.log10().floor() as i32).max(0)
        };
        // Grid point k, k / 10^digits: the decimal it stands for, as near as f64 has it.
        let scale = 10f64.powi(digits);
        let at = |k: f64| k / scale;
        // The grid point nearest the end `end` (an index) that is valid, searched towards `v`
        // (`up`: from below), or `v` itself if none is.
        let mut narrow = |end: f64, up: bool| -> f64 {
            if end.is_finite() && valid(at(end)) {
                return at(end);
            }
            let beside_v = if up {
                (v * scale).ceil()
            } else {
                (v * scale).floor()
            };
            let (mut bad, mut good) = (end, beside_v);
            if !end.is_finite() || !valid(at(good)) {
                return v;
            }
            for _ in 0..64 {
                let mid = ((bad + good) / 2.0).floor();
                // Adjacent grid points (or as near as f64 tells them apart).
                if (good - bad).abs() <= 1.0 || mid == bad || mid == good {
                    break;
                }
                if valid(at(mid)) {
                    good = mid;
                } else {
                    bad = mid;
                }
            }
            at(good)
        };
        let min = narrow(((v - span) * scale).floor(), true);
        let max = narrow(((v + span) * scale).ceil(), false);
        Slider {
            min,
            max,
            step: at(1.0),
        }
    }
}

/// The parameters of a scene file's TOML `table`, in the file's order of keys, at most
/// [`MAX_PARAMETERS`]; and whether some were left out.
pub fn parameters(table: &Table) -> (Vec<Parameter>, bool) {
    let mut found = Vec::new();
    let complete = walk(&mut found, "", table);
    (found, !complete)
}

/// Adds the parameters under `table` (whose key is `prefix`); false once the list is full.
fn walk(found: &mut Vec<Parameter>, prefix: &str, table: &Table) -> bool {
    for (name, value) in table {
        // `--set` splits keys at dots and trims them: such keys cannot be addressed.
        if name.is_empty() || name.contains('.') || name.trim() != name {
            continue;
        }
        let key = if prefix.is_empty() {
            name.clone()
        } else {
            format!("{prefix}.{name}")
        };
        if !visit(found, key, value) {
            return false;
        }
    }
    true
}

fn visit(found: &mut Vec<Parameter>, key: String, value: &Value) -> bool {
    match value {
        Value::Table(t) => walk(found, &key, t),
        Value::Array(items) if !items.is_empty() && items.iter().all(Value::is_table) => {
            items.iter().enumerate().all(|(i, item)| {
                let Value::Table(t) = item else { return true };
                walk(found, &format!("{key}.{i}"), t)
            })
        }
        _ => {
            let Some((value, integer)) = leaf(value) else {
                return true;
            };
            if found.len() == MAX_PARAMETERS {
                return false;
            }
            found.push(Parameter {
                key,
                value,
                integer,
                slider: None,
            });
            true
        }
    }
}

/// A number, a boolean, or a non-empty array of numbers (nested to any depth), as JSON; and
/// whether the numbers are all whole. Non-finite numbers are left out: JSON has
/// none.
fn leaf(value: &Value) -> Option<(serde_json::Value, bool)> {
    match value {
        Value::Integer(i) => Some(((*i).into(), true)),
        Value::Float(f) => Some((serde_json::Number::from_f64(*f)?.into(), false)),
        Value::Boolean(b) => Some(((*b).into(), false)),
        Value::Array(items) if !items.is_empty() => {
            let leaves: Vec<_> = items
                .iter()
                .filter(|v| !v.is_bool())
                .map(leaf)
                .collect::<Option<_>>()?;
            let integer = leaves.iter().all(|(_, i)| *i);
            (leaves.len() == items.len())
                .then(|| (leaves.into_iter().map(|(v, _)| v).collect(), integer))
        }
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The slider of `v` for a key whose valid values are those `valid` accepts.
    fn slider(v: f64, integer: bool, valid: impl Fn(f64) -> bool) -> (f64, f64, f64) {
        let mut probes = 0;
        let s = Slider::around(v, integer, &mut |x| {
            probes += 1;
            valid(x)
        });
        // A bisection at the step's resolution, not a scan of the grid.
        assert!(probes <= 24, "{probes} probes");
        (s.min, s.max, s.step)
    }

    #[test]
    fn sliders_keep_to_each_keys_valid_domain_on_a_round_grid() {
        // An index ratio (> 0) of 1: the slider starts one step above 0, and 1 is on its grid.
        assert_eq!(slider(1.0, false, |x| x > 0.0), (0.01, 3.0, 0.01));
        // A coefficient of Dr TIM's default 0.96, from 0 to 1.
        assert_eq!(
            slider(0.96, false, |x| (0.0..=1.0).contains(&x)),
            (0.0, 1.0, 0.01)
        );
        // A view angle of 20° (0 < angle < 180); and of 170°, near the top.
        assert_eq!(
            slider(20.0, false, |x| x > 0.0 && x < 180.0),
            (0.1, 60.0, 0.1)
        );
        assert_eq!(
            slider(170.0, false, |x| x > 0.0 && x < 180.0),
            (1.0, 179.0, 1.0)
        );
        // Samples per pixel, whole and at least 1.
        assert_eq!(slider(4.0, true, |x| x >= 1.0), (1.0, 12.0, 1.0));
        // A camera's speed |β| < 1 given by one component of 0.9.
        assert_eq!(
            slider(0.9, false, |x: f64| x.abs() < 1.0),
            (-0.9, 0.99, 0.01)
        );
        // No bounds: twice the magnitude either side.
        assert_eq!(slider(-3.0, false, |_| true), (-9.0, 3.0, 0.01));
        assert_eq!(slider(0.0, false, |_| true), (-1.0, 1.0, 0.01));
        // A value valid on its own only: the slider is that value.
        assert_eq!(slider(0.123, false, |x| x == 0.123), (0.123, 0.123, 0.001));
    }

    fn listed(text: &str) -> Vec<(String, String, bool)> {
        let (found, _) = parameters(&text.parse().unwrap());
        found
            .into_iter()
            .map(|p| (p.key, p.value.to_string(), p.integer))
            .collect()
    }

    #[test]
    fn numbers_vectors_matrices_and_switches_are_listed_by_their_set_keys() {
        let text = r#"
studio = "lattice"
[render]
width = 64
shadows = false
[camera]
position = [0, 0.5, -2]
beta = [0.1, 0, 0]
[[object]]
name = "a"
shape = { type = "sphere", centre = [0, 0, 5], radius = 1 }
surface = { type = "metric-interface", metric = [[1, 0], [0, 2]] }
[[object]]
shape = { type = "sphere", centre = [1, 2.5, 3], radius = 0.5 }
"#;
        let got = listed(text);
        let want = [
            ("render.width", "64", true),
            ("render.shadows", "false", false),
            ("camera.position", "[0,0.5,-2]", false),
            ("camera.beta", "[0.1,0,0]", false),
            ("object.0.shape.centre", "[0,0,5]", true),
            ("object.0.shape.radius", "1", true),
            ("object.0.surface.metric", "[[1,0],[0,2]]", true),
            ("object.1.shape.centre", "[1,2.5,3]", false),
            ("object.1.shape.radius", "0.5", false),
        ];
        let want: Vec<_> = want
            .iter()
            .map(|(k, v, i)| (k.to_string(), v.to_string(), *i))
            .collect();
        let mut got_sorted = got.clone();
        got_sorted.sort();
        let mut want_sorted = want.clone();
        want_sorted.sort();
        assert_eq!(got_sorted, want_sorted);
    }

    #[test]
    fn strings_mixed_arrays_dotted_keys_and_infinities_are_not_parameters() {
        let got = listed("a = \"x\"\nb = [1, \"x\"]\n\"c.d\" = 1\ne = inf\nf = []\ng = [true]\n");
        assert!(got.is_empty(), "{got:?}");
    }

    #[test]
    fn the_list_stops_at_its_limit_and_says_so() {
        let text: String = (0..MAX_PARAMETERS + 5)
            .map(|i| format!("k{i} = {i}\n"))
            .collect();
        let (found, more) = parameters(&text.parse().unwrap());
        assert_eq!(found.len(), MAX_PARAMETERS);
        assert!(more);
        let (found, more) = parameters(&"a = 1".parse().unwrap());
        assert_eq!(found.len(), 1);
        assert!(!more);
    }
}
