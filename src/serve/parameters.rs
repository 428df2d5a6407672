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
