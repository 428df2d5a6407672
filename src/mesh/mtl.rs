//! Wavefront MTL material libraries, read line by line with located errors: `newmtl`, `Kd`,
//! `Ks` (r g b, each in [0, 1]), `d` (in [0, 1]), `map_Kd` (a file name); `Ns` (≥ 0) and `Ni`
//! (> 0) are checked and kept but not used, with a warning; every other key is named in a warning and
//! ignored.

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
    /// `Ns`, Phong exponent (read; timbre's exponent is the light's).
    pub shininess: Option<f64>,
    /// `d`, the opaque fraction (1 − transparency).
    pub dissolve: f64,
    /// `Ni`, refractive index (read; not used).
    pub index: Option<f64>,
    /// `map_Kd`, the diffuse texture's file name (as loaded from an OBJ file: relative to it).
    pub diffuse_map: Option<String>,
}

impl Material {
    fn new(name: &str) -> Material {
        Material {
            name: name.to_string(),
            diffuse: DVec3::splat(0.8),
            specular: DVec3::ZERO,
            shininess: None,
            dissolve: 1.0,
            index: None,
            diffuse_map: None,
        }
    }
}

/// The materials of an MTL file's text, and a warning for each key that is not read, each
/// starting "N:C: " (line and column).
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
    let mut warnings = Vec::new();
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
        let known = matches!(key, "Kd" | "Ks" | "Ns" | "d" | "Ni" | "map_Kd");
        if !known {
            warnings.push(format!(
                "{}: '{}' is not supported and is ignored",
                column(line_no, line, key),
                shown(key.as_bytes())
            ));
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
        let count = if matches!(key, "Kd" | "Ks") { 3 } else { 1 };
        if numbers.len() != count {
            let what = if count == 3 { "r g b" } else { "one number" };
            return Err(at(
                key,
                format!("{key} needs {what}, got {} numbers", numbers.len()),
            ));
        }
        let (low, high, range) = match key {
            "Kd" | "Ks" | "d" => (0.0, 1.0, "in [0, 1]"),
            "Ns" => (0.0, f64::INFINITY, "at least 0"),
            _ => (f64::MIN_POSITIVE, f64::INFINITY, "positive"),
        };
        if let Some((k, x)) = numbers
            .iter()
            .enumerate()
            .find(|(_, x)| !(low..=high).contains(*x))
        {
            return Err(at(words[k], format!("{key}: {x} must be {range}")));
        }
        match key {
            "Kd" => material.diffuse = DVec3::from_slice(&numbers),
            "Ks" => material.specular = DVec3::from_slice(&numbers),
            "Ns" => material.shininess = Some(numbers[0]),
            "d" => material.dissolve = numbers[0],
            _ => material.index = Some(numbers[0]),
        }
        let unused = match key {
            "Ns" => "the Phong exponent is each light's (phong_exponent)",
            "Ni" => "a partly transparent material passes light straight on",
            _ => "",
        };
        if !unused.is_empty() {
            warnings.push(format!(
                "{}: '{key}' is read but not used: {unused}",
                column(line_no, line, key)
            ));
        }
    }
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
                "6:1: 'Ns' is read but not used: the Phong exponent is each light's \
                 (phong_exponent)",
                "7:1: 'Ni' is read but not used: a partly transparent material passes light \
                 straight on",
            ]
        );
        assert_eq!(m.len(), 2);
        assert_eq!(m[0].name, "red");
        assert_eq!(m[0].diffuse, DVec3::new(1.0, 0.0, 0.0));
        assert_eq!(m[0].specular, DVec3::new(0.25, 0.5, 0.75));
        assert_eq!(m[0].dissolve, 0.4);
        assert_eq!(m[0].shininess, Some(20.0));
        assert_eq!(m[0].index, Some(1.5));
        assert_eq!(m[0].diffuse_map.as_deref(), Some("tex.png"));
        assert_eq!(m[1], Material::new("plain"));
    }

    #[test]
    fn unsupported_keys_are_warnings_that_name_them() {
        let (_, warnings) = read(b"newmtl a\n  Ka 1 1 1\nillum 2\n").unwrap();
        assert_eq!(
            warnings,
            [
                "2:3: 'Ka' is not supported and is ignored",
                "3:1: 'illum' is not supported and is ignored"
            ]
        );
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
        assert_eq!(err("newmtl a\nNi 0\n"), "2:4: Ni: 0 must be positive");
    }
}
