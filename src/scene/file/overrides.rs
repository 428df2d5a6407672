//! `--set key=value`: change any value of a scene file from the command line.
//!
//! The key is a dotted path into the file's TOML tree (`camera.position`, `render.width`);
//! entries of arrays of tables are selected by index (`object.0.shape.radius`). The value is
//! TOML (`[0, 0, -2]`, `2.5`, `true`, `"lattice"`); a bare word is taken as a string
//! (`studio=lattice`). Missing tables are created; a missing array entry is an error.

use std::collections::HashMap;
use std::fmt;
use std::ops::Range;
use std::str::FromStr;

use toml::{Table, Value};

/// One `key=value` override.
#[derive(Debug, Clone, PartialEq)]
pub struct Override {
    pub key: Vec<String>,
    pub value: Value,
    text: String,
}

impl FromStr for Override {
    type Err = String;

    fn from_str(s: &str) -> Result<Override, String> {
        let (key, value) = s
            .split_once('=')
            .ok_or_else(|| format!("'{s}' is not of the form key=value"))?;
        let key: Vec<String> = key
            .trim()
            .split('.')
            .map(|k| k.trim().to_string())
            .collect();
        if key.iter().any(String::is_empty) {
            return Err(format!("'{s}': the key has an empty part"));
        }
        let value = value.trim();
        let parsed = format!("v = {value}")
            .parse::<Table>()
            .map(|mut t| t.remove("v"));
        let value = match parsed {
            Ok(Some(v)) => v,
            // A bare word is a string; anything that looks like TOML must be TOML.
            _ if value.starts_with(['[', '{', '"', '\'']) || value.is_empty() => {
                return Err(format!("'{s}': the value is not valid TOML"));
            }
            _ => Value::String(value.to_string()),
        };
        Ok(Override {
            key,
            value,
            text: s.to_string(),
        })
    }
}

impl Override {
    /// The override setting the dotted `key` (a valid key, as `--set` reads it) to `value`.
    pub fn new(key: &str, value: toml::Value) -> Override {
        Override {
            key: key.split('.').map(str::to_string).collect(),
            text: format!("{key}={value}"),
            value,
        }
    }
}

impl fmt::Display for Override {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.text)
    }
}

/// The scene-file text with the overrides applied. A large file is changed in the parts it is
/// parsed in (`parts.rs`), so that memory stays in proportion to a part: each part an override
/// reaches is reformatted by toml, the others are kept as they are.
pub(super) fn apply(text: &str, overrides: &[Override]) -> Result<String, String> {
    let parts = super::parts::outline(text, usize::MAX).parts;
    let parse = |part: &Range<usize>| {
        text[part.clone()]
            .parse::<Table>()
            .map_err(|e| e.to_string())
    };
    // The top-level keys of each part, with the lengths of those that are arrays.
    let mut keys = Vec::new();
    for part in &parts {
        let table = parse(part)?;
        let lengths: HashMap<String, Option<usize>> = table
            .into_iter()
            .map(|(k, v)| (k, v.as_array().map(Vec::len)))
            .collect();
        keys.push(lengths);
    }
    let mut located = vec![Vec::new(); parts.len()];
    for o in overrides {
        let (part, o) = locate(&keys, o).map_err(|e| format!("{o}: {e}"))?;
        located[part].push(o);
    }
    // After the first part only headers may stand at the top: a plain value would belong to
    // the table before it.
    let plain = |v: &Value| match v {
        Value::Table(_) => false,
        Value::Array(a) => a.is_empty() || !a.iter().all(Value::is_table),
        _ => true,
    };
    let mut changed = String::with_capacity(text.len());
    for (k, (part, overrides)) in parts.iter().zip(located).enumerate() {
        if overrides.is_empty() {
            changed += &text[part.clone()];
            continue;
        }
        let mut table = parse(part)?;
        for o in &overrides {
            set(&mut table, o).map_err(|e| format!("{o}: {e}"))?;
            if k > 0 && table.values().any(plain) {
                return Err(format!(
                    "{o}: in a file this large (parsed in parts), '{}' can be set only to a \
                     table or to tables",
                    o.key[0]
                ));
            }
        }
        changed += &toml::to_string(&table).map_err(|e| e.to_string())?;
    }
    Ok(changed)
}

/// The part whose table `o` changes, given each part's top-level `keys`, and `o` with an index
/// into an array of tables counted within that part.
fn locate(
    keys: &[HashMap<String, Option<usize>>],
    o: &Override,
) -> Result<(usize, Override), String> {
    let first = &o.key[0];
    let holding: Vec<(usize, Option<usize>)> = keys
        .iter()
        .enumerate()
        .filter_map(|(p, k)| k.get(first).map(|&len| (p, len)))
        .collect();
    let Some(&(part, _)) = holding.first() else {
        return Ok((0, o.clone()));
    };
    let Some(entry) = o.key.get(1).and_then(|k| k.parse::<usize>().ok()) else {
        if o.key.len() == 1 && holding.len() > 1 {
            return Err(format!(
                "'{first}' is too long to be replaced whole; set its entries one by one"
            ));
        }
        return Ok((part, o.clone()));
    };
    let mut before = 0;
    for &(part, len) in &holding {
        let len = len.unwrap_or(0);
        if entry < before + len || holding.len() == 1 {
            let mut o = o.clone();
            o.key[1] = (entry - before).to_string();
            return Ok((part, o));
        }
        before += len;
    }
    Err(format!("index {entry} is beyond the {before} entries"))
}

/// Keys that say the same thing two ways: setting one removes the other from its table.
const EITHER_OR: &[[&str; 2]] = &[["view_direction", "look_at"]];

fn set(root: &mut Table, o: &Override) -> Result<(), String> {
    let (last, path) = o.key.split_last().expect("keys are not empty");
    let mut here = Value::Table(std::mem::take(root));
    let result = descend(&mut here, path, last).map(|slot| match slot {
        Value::Table(t) => {
            for pair in EITHER_OR
                .iter()
                .filter(|pair| pair.contains(&last.as_str()))
            {
                pair.iter().filter(|&&k| k != last).for_each(|k| {
                    t.remove(*k);
                });
            }
            t.insert(last.clone(), o.value.clone());
            Ok(())
        }
        Value::Array(a) => {
            let i = index(last, a.len())?;
            a[i] = o.value.clone();
            Ok(())
        }
        other => Err(format!(
            "'{last}' cannot be set inside a value of type {}",
            other.type_str()
        )),
    });
    if let Value::Table(t) = here {
        *root = t;
    }
    result.and_then(|r| r)
}

/// The value at `path` below `here`, creating missing tables; `last` is the key set there.
fn descend<'a>(here: &'a mut Value, path: &[String], last: &str) -> Result<&'a mut Value, String> {
    let Some((first, rest)) = path.split_first() else {
        return Ok(here);
    };
    let next = match here {
        Value::Table(t) => {
            // An index selects an entry of an array that is there, never of a new table.
            let after = rest.first().map_or(last, String::as_str);
            if !t.contains_key(first) && after.bytes().all(|b| b.is_ascii_digit()) {
                return Err(format!(
                    "there are no '{first}' entries for '{after}' to select"
                ));
            }
            t.entry(first.clone())
                .or_insert_with(|| Value::Table(Table::new()))
        }
        Value::Array(a) => {
            let i = index(first, a.len())?;
            &mut a[i]
        }
        other => {
            return Err(format!(
                "'{first}' cannot be set inside a value of type {}",
                other.type_str()
            ));
        }
    };
    descend(next, rest, last)
}

fn index(key: &str, len: usize) -> Result<usize, String> {
    match key.parse::<usize>() {
        Ok(i) if i < len => Ok(i),
        Ok(i) => Err(format!("index {i} is beyond the {len} entries")),
        Err(_) => Err(format!(
            "'{key}' selects an array entry, so it must be an index"
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn apply_one(text: &str, o: &str) -> Result<Table, String> {
        apply(text, &[o.parse().unwrap()]).map(|t| t.parse::<Table>().unwrap())
    }

    #[test]
    fn values_are_toml_or_bare_strings() {
        let o: Override = "camera.position=[0, 0, -2]".parse().unwrap();
        assert_eq!(o.key, ["camera", "position"]);
        assert_eq!(o.value, Value::Array(vec![0.into(), 0.into(), (-2).into()]));
        let o: Override = "studio=lattice".parse().unwrap();
        assert_eq!(o.value, Value::String("lattice".into()));
        assert!("nokey".parse::<Override>().is_err());
        assert!("a..b=1".parse::<Override>().is_err());
    }

    #[test]
    fn overrides_replace_create_and_index() {
        let text = "[render]\nwidth = 10\n[[object]]\nname = \"a\"\n[[object]]\nname = \"b\"\n";
        let t = apply_one(text, "render.width=99").unwrap();
        assert_eq!(t["render"]["width"].as_integer(), Some(99));
        let t = apply_one(text, "camera.up=[0,1,0]").unwrap();
        assert!(t["camera"]["up"].is_array());
        let t = apply_one(text, "object.1.name=c").unwrap();
        assert_eq!(t["object"][1]["name"].as_str(), Some("c"));
        let e = apply_one(text, "object.2.name=c").unwrap_err();
        assert!(e.contains("index 2 is beyond the 2 entries"), "{e}");
        let e = apply_one(text, "group.0.name=c").unwrap_err();
        assert!(
            e.contains("there are no 'group' entries for '0' to select"),
            "{e}"
        );
        let e = apply_one(text, "render.width.x=1").unwrap_err();
        assert!(
            e.contains("'x' cannot be set inside a value of type integer"),
            "{e}"
        );
    }

    #[test]
    fn a_look_at_point_replaces_the_view_direction_and_back() {
        let text = "[camera]\nview_direction = [0, 0, 1]\n";
        let t = apply_one(text, "camera.look_at=[1,2,3]").unwrap();
        assert!(t["camera"].get("view_direction").is_none());
        assert!(t["camera"]["look_at"].is_array());
        let text = "[camera]\nlook_at = [0, 0, 1]\n";
        let t = apply_one(text, "camera.view_direction=[1,2,3]").unwrap();
        assert!(t["camera"].get("look_at").is_none());
    }
}
