//! Wavefront MTL material libraries, read line by line with located errors: `newmtl`, `Kd`,
//! `Ks` (r g b, each in [0, 1], or one number for all three), `d` (in [0, 1]), `map_Kd` (a file
//! name). `Ns` and `Ni` are not used, and every other key is ignored: each such key is named in
//! one warning, with where it first appears and how often.

use glam::DVec3;

use super::{ParseProblem, column, shown};

/// One material of an MTL file, in plain numbers (the defaults are the MTL format's: black
/// specular, opaque).
#[derive(Debug, Clone, PartialEq)]
pub struct Material {
    pub name: String,
    /// `Kd`, diffuse colour (default 0.8 grey, as Blender and tobj's users assume).
    pub diffuse: DVec3,
    /// `Ks`, specular colour.
    pub specular: DVec3,
    /// `d`, the opaque fraction (1 − transparency).
    pub dissolve: f64,
    /// `map_Kd`, the diffuse texture's file name (as loaded from an OBJ file: relative to it).
    pub diffuse_map: Option<String>,
}

impl Material {
    fn new(name: &str) -> Material {
        Material {
            name: name.to_string(),
            diffuse: DVec3::splat(0.8),
            specular: DVec3::ZERO,
            dissolve: 1.0,
            diffuse_map: None,
        }
    }
}

/// The materials of an MTL file's text, and a warning for each key that is not used, starting
/// "N:C: " (the line and column where it first appears).
pub(super) fn read(bytes: &[u8]) -> Result<(Vec<Material>, Vec<String>), ParseProblem> {
    let text = std::str::from_utf8(bytes).map_err(|e| {
        let line = bytes[..e.valid_up_to()]
            .iter()
            .filter(|&&b| b == b'\n')
            .count()
            + 1;
        ParseProblem::new(line.to_string(), "not a text file (invalid UTF-8)")
    })?;
    let mut materials: Vec<Material> = Vec::new();
    // Keys not used: the key, where it first appears, how many lines have it.
    let mut ignored: Vec<(String, String, usize)> = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line_no = i + 1;
        let at =
            |word: &str, message: String| ParseProblem::new(column(line_no, line, word), message);
        let mut words = line.split_whitespace();
        let Some(key) = words.next() else { continue };
        if key.starts_with('#') {
            continue;
        }
        let words: Vec<&str> = words.collect();
        let rest = line.trim_start()[key.len()..].trim();
        if key == "newmtl" {
            if rest.is_empty() {
                return Err(at(key, "newmtl needs a material name".into()));
            }
            if materials.iter().any(|m| m.name == rest) {
                return Err(at(
                    key,
                    format!("material '{}' is defined twice", shown(rest.as_bytes())),
                ));
            }
            materials.push(Material::new(rest));
            continue;
        }
        if !matches!(key, "Kd" | "Ks" | "d" | "map_Kd") {
            match ignored.iter_mut().find(|(k, _, _)| k == key) {
                Some((_, _, n)) => *n += 1,
                None => ignored.push((key.to_string(), column(line_no, line, key), 1)),
            }
            continue;
        }
        let Some(material) = materials.last_mut() else {
            return Err(at(key, format!("'{key}' before the first newmtl")));
        };
        if key == "map_Kd" {
            if words.len() != 1 {
                return Err(at(
                    key,
                    "map_Kd needs one file name (texture options are not supported)".into(),
                ));
            }
            material.diffuse_map = Some(words[0].to_string());
            continue;
        }
        let numbers = words
            .iter()
            .map(|w| {
                w.parse::<f64>()
                    .ok()
                    .filter(|x| x.is_finite())
                    .ok_or_else(|| {
                        at(
                            w,
                            format!("'{}' is not a finite number", shown(w.as_bytes())),
                        )
                    })
            })
            .collect::<Result<Vec<f64>, _>>()?;
        let colour = matches!(key, "Kd" | "Ks");
        let counts: &[usize] = if colour { &[1, 3] } else { &[1] };
        if !counts.contains(&numbers.len()) {
            let what = if colour {
                "r g b (or one number)"
            } else {
                "one number"
            };
            return Err(at(
                key,
                format!("{key} needs {what}, got {} numbers", numbers.len()),
            ));
        }
        if let Some((k, x)) = numbers
            .iter()
            .enumerate()
            .find(|(_, x)| !(0.0..=1.0).contains(*x))
        {
            return Err(at(words[k], format!("{key}: {x} must be in [0, 1]")));
        }
        let value = match numbers[..] {
            [r, g, b] => DVec3::new(r, g, b),
            _ => DVec3::splat(numbers[0]),
        };
        match key {
            "Kd" => material.diffuse = value,
            "Ks" => material.specular = value,
            _ => material.dissolve = numbers[0],
        }
    }
    let warnings = ignored
        .into_iter()
        .map(|(key, first, n)| {
            let why = match key.as_str() {
                "Ns" => "not used: the Phong exponent is each light's (phong_exponent)",
                "Ni" => "not used: a partly transparent material passes light straight on",
                _ => "not supported and is ignored",
            };
            let lines = if n > 1 {
                format!(" ({n} lines)")
            } else {
                String::new()
            };
            format!("{first}: '{}' is {why}{lines}", shown(key.as_bytes()))
        })
        .collect();
    Ok((materials, warnings))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn colours_and_opacity_are_read_with_defaults_for_the_rest() {
        let text = "# a test\nnewmtl red\nKd 1 0 0\nKs 0.25 0.5 0.75\nd 0.4\nNs 20\nNi 1.5\n\
                    map_Kd tex.png\nnewmtl plain\n";
        let (m, warnings) = read(text.as_bytes()).unwrap();
        assert_eq!(
            warnings,
            [
                "6:1: 'Ns' is not used: the Phong exponent is each light's (phong_exponent)",
                "7:1: 'Ni' is not used: a partly transparent material passes light straight on",
            ]
        );
        assert_eq!(m.len(), 2);
        assert_eq!(m[0].name, "red");
        assert_eq!(m[0].diffuse, DVec3::new(1.0, 0.0, 0.0));
        assert_eq!(m[0].specular, DVec3::new(0.25, 0.5, 0.75));
        assert_eq!(m[0].dissolve, 0.4);
        assert_eq!(m[0].diffuse_map.as_deref(), Some("tex.png"));
        assert_eq!(m[1], Material::new("plain"));
    }

    #[test]
    fn unsupported_keys_are_warnings_that_name_them_once() {
        let (_, warnings) =
            read(b"newmtl a\n  Ka 1 1 1\nillum 2\nNi 0\nnewmtl b\nKa 0 0 0\n").unwrap();
        assert_eq!(
            warnings,
            [
                "2:3: 'Ka' is not supported and is ignored (2 lines)",
                "3:1: 'illum' is not supported and is ignored",
                "4:1: 'Ni' is not used: a partly transparent material passes light straight on",
            ]
        );
    }

    /// The MTL format's one-number colour means grey: `Kd 0.5` is (0.5, 0.5, 0.5).
    #[test]
    fn one_number_is_a_grey() {
        let (m, _) = read(b"newmtl a\nKd 0.5\nKs 0.25\n").unwrap();
        assert_eq!(m[0].diffuse, DVec3::splat(0.5));
        assert_eq!(m[0].specular, DVec3::splat(0.25));
    }

    #[test]
    fn bad_values_are_located_errors() {
        let err = |text: &str| {
            let e = read(text.as_bytes()).unwrap_err();
            format!("{}: {}", e.location, e.message)
        };
        assert_eq!(
            err("newmtl a\nKd 1 x 0\n"),
            "2:6: 'x' is not a finite number"
        );
        assert_eq!(err("newmtl a\nKd 1 2 0\n"), "2:6: Kd: 2 must be in [0, 1]");
        assert_eq!(
            err("newmtl a\nd 1 1\n"),
            "2:1: d needs one number, got 2 numbers"
        );
        assert_eq!(err("Kd 1 1 1\n"), "1:1: 'Kd' before the first newmtl");
        assert_eq!(
            err("newmtl a\nnewmtl a\n"),
            "2:1: material 'a' is defined twice"
        );
        assert_eq!(
            err("newmtl a\nKs 1 1\n"),
            "2:1: Ks needs r g b (or one number), got 2 numbers"
        );
    }
}
