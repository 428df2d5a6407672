//! `--set key=value`: change any value of a scene file from the command line.
//!
//! The key is a dotted path into the file's TOML tree (`camera.position`, `render.width`);
//! entries of arrays of tables are selected by index (`object.0.shape.radius`). The value is
//! TOML (`[0, 0, -2]`, `2.5`, `true`, `"lattice"`); a bare word is taken as a string
//! (`studio=lattice`). Missing tables are created; a missing array entry is an error.

use std::fmt;
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

impl fmt::Display for Override {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.text)
    }
}

/// The scene-file text with the overrides applied (reformatted by toml).
pub(super) fn apply(text: &str, overrides: &[Override]) -> Result<String, String> {
    let mut root = text.parse::<Table>().map_err(|e| e.to_string())?;
    for o in overrides {
        set(&mut root, o).map_err(|e| format!("{o}: {e}"))?;
    }
    toml::to_string(&root).map_err(|e| e.to_string())
}

fn set(root: &mut Table, o: &Override) -> Result<(), String> {
    let (last, path) = o.key.split_last().expect("keys are not empty");
    let mut here = Value::Table(std::mem::take(root));
    let result = descend(&mut here, path).map(|slot| match slot {
        Value::Table(t) => {
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

/// The value at `path` below `here`, creating missing tables.
fn descend<'a>(here: &'a mut Value, path: &[String]) -> Result<&'a mut Value, String> {
    let Some((first, rest)) = path.split_first() else {
        return Ok(here);
    };
    let next = match here {
        Value::Table(t) => t
            .entry(first.clone())
            .or_insert_with(|| Value::Table(Table::new())),
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
    descend(next, rest)
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
        let e = apply_one(text, "render.width.x=1").unwrap_err();
        assert!(
            e.contains("'x' cannot be set inside a value of type integer"),
            "{e}"
        );
    }
}
