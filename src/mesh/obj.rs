//! Wavefront OBJ, read with `tobj` (one mesh per object or group and material; polygons
//! triangulated; materials from `mtllib` files when asked for; texture coordinates) and written with one `v` (and `vn`) line per
//! vertex.
//!
//! `tobj` reports what went wrong but not where, and takes some malformed lines without a word,
//! so the text is checked line by line first, to the rules below; what passes is what `tobj`
//! reads without error:
//! - `v`: x y z, optionally w (not 0) or r g b, all numbers; x y z (and x/w …) finite; every
//!   vertex with a colour or none;
//! - `vt`: u v, optionally w; `vn`: x y z (a NaN or infinite normal is allowed: the mesh is then
//!   shaded flat);
//! - `f`: at least three vertex references `v`, `v/vt`, `v//vn` or `v/vt/vn`, all of one form,
//!   each index (1-based, or negative counting back) within what the lines before define;
//! - the file is UTF-8.
//!
//! Errors say the line, and the column of the word at fault where there is one; text from the
//! file is quoted through [`shown`].

use std::borrow::Cow;
use std::io::Write;

use glam::{DVec2, DVec3};

use super::mtl::Material;
use super::{
    Loaded, Mesh, ParseProblem, Precision, check_finite, column, escaped, not_finite, shown,
};

/// Opens a file an OBJ file names (an MTL library), by its name relative to the OBJ file.
pub type Open<'a> = &'a mut dyn FnMut(&str) -> Result<Vec<u8>, String>;

/// The meshes of an OBJ file, each with the index of its material in the libraries its
/// `mtllib` lines name (read through `open` when given; ignored, as `tobj` alone would, when
/// not), the materials, and the libraries' warnings (each "LIBRARY:N:C: ...").
pub(super) fn read_with(bytes: &[u8], open: Option<Open>) -> Result<Loaded, ParseProblem> {
    let text = std::str::from_utf8(bytes).map_err(|e| not_utf8(bytes, &e))?;
    let checked = check(text)?;
    let options = tobj::LoadOptions {
        single_index: true,
        triangulate: true,
        ignore_points: true,
        ignore_lines: true,
    };
    let mut libraries = Vec::new();
    let mut materials = Vec::new();
    let mut warnings = Vec::new();
    if let Some(open) = open {
        for (i, line) in text.lines().enumerate() {
            let mut words = line.split_whitespace();
            match words.next() {
                Some("mtllib") => {
                    let name = line.split_once(' ').unwrap_or_default().1.trim();
                    let at = |m: String| ParseProblem::new(column(i + 1, line, name), m);
                    let bytes = open(name).map_err(|e| at(format!("mtllib: {e}")))?;
                    let (read, told) = super::mtl::read(&bytes).map_err(|e| {
                        at(format!(
                            "in '{}': {}: {}",
                            shown(name.as_bytes()),
                            e.location,
                            e.message
                        ))
                    })?;
                    let first = materials.len();
                    warnings.extend(told.into_iter().map(|w| format!("{name}:{w}")));
                    // A texture is named relative to its library, kept relative to the OBJ file.
                    let dir = std::path::Path::new(name)
                        .parent()
                        .unwrap_or(std::path::Path::new(""));
                    materials.extend(read.into_iter().map(|mut m| {
                        m.diffuse_map = m
                            .diffuse_map
                            .map(|t| dir.join(t).to_string_lossy().into_owned());
                        m
                    }));
                    libraries.push((name.to_string(), first..materials.len()));
                }
                Some("usemtl") if !libraries.is_empty() => {
                    let name = line.split_once(' ').unwrap_or_default().1.trim();
                    if !materials.iter().any(|m: &Material| m.name == name) {
                        return Err(ParseProblem::new(
                            column(i + 1, line, name),
                            format!(
                                "usemtl: no material '{}' in the libraries named before",
                                shown(name.as_bytes())
                            ),
                        ));
                    }
                }
                _ => {}
            }
        }
    }
    let (models, _materials) = tobj::load_obj_buf(&mut checked.as_bytes(), &options, |path| {
        let name = path.to_string_lossy();
        let Some((_, range)) = libraries.iter().find(|(n, _)| *n == name) else {
            return Err(tobj::LoadError::OpenFileFailed);
        };
        let map = materials[range.clone()]
            .iter()
            .enumerate()
            .map(|(k, m)| (m.name.clone(), k))
            .collect();
        let named = materials[range.clone()]
            .iter()
            .map(|m| tobj::Material {
                name: m.name.clone(),
                ..Default::default()
            })
            .collect();
        Ok((named, map))
    })
    .map_err(|e| ParseProblem::new("", format!("invalid OBJ file: {e}")))?;
    let mut indices = Vec::with_capacity(models.len());
    let mut uvs = Vec::with_capacity(models.len());
    let mut meshes = Vec::with_capacity(models.len());
    for model in models {
        let m = model.mesh;
        indices.push(m.material_id);
        uvs.push(
            (m.texcoords.len() * 3 == m.positions.len() * 2)
                .then(|| m.texcoords.chunks_exact(2).map(DVec2::from_slice).collect()),
        );
        let vertices = to_points(&m.positions);
        check_finite("vertex", &vertices, |_| String::new())?;
        let normals = (m.normals.len() == m.positions.len())
            .then(|| to_points(&m.normals))
            .filter(|n| n.iter().all(|n| n.is_finite()));
        meshes.push(Mesh {
            // tobj names the objects of a file that names none "unnamed_object".
            name: if model.name == "unnamed_object" {
                String::new()
            } else {
                printable_name(model.name)
            },
            vertices,
            triangles: m
                .indices
                .chunks_exact(3)
                .map(|t| [t[0], t[1], t[2]])
                .collect(),
            normals,
        });
    }
    Ok(Loaded {
        colours: vec![None; meshes.len()],
        meshes,
        uvs,
        material_of: indices,
        materials,
        warnings,
    })
}

/// An object or group name with control and invisible characters escaped (it ends up in
/// messages).
fn printable_name(name: String) -> String {
    if name.chars().any(|c| crate::text::escape(c).is_some()) {
        escaped(name.as_bytes(), usize::MAX)
    } else {
        name
    }
}

/// Where the first byte that is not UTF-8 is.
fn not_utf8(bytes: &[u8], e: &std::str::Utf8Error) -> ParseProblem {
    let good = &bytes[..e.valid_up_to()];
    let line_start = good.iter().rposition(|&b| b == b'\n').map_or(0, |k| k + 1);
    let line = good.iter().filter(|&&b| b == b'\n').count() + 1;
    let column = String::from_utf8_lossy(&good[line_start..]).chars().count() + 1;
    let bad_len = e.error_len().unwrap_or(bytes.len() - good.len());
    let bad = &bytes[good.len()..good.len() + bad_len];
    ParseProblem::new(
        format!("{line}:{column}"),
        format!("not a text file (invalid UTF-8: {})", shown(bad)),
    )
}

/// "1 number", "2 numbers".
fn numbers_count(n: usize) -> String {
    if n == 1 {
        "1 number".into()
    } else {
        format!("{n} numbers")
    }
}

fn to_points(xyz: &[f64]) -> Vec<DVec3> {
    xyz.chunks_exact(3).map(DVec3::from_slice).collect()
}

/// Checks every vertex, normal and face line (see the module's rules), and returns the text
/// with the lines `tobj` must not see blanked: points (`p`) and polylines (`l`), which it would
/// read as polygons when they have three or more points, and `usemtl` lines it would reject
/// (materials are ignored anyway).
fn check(text: &str) -> Result<Cow<'_, str>, ParseProblem> {
    let mut counts = [0i64; 3]; // v, vt, vn read so far
    let mut blanked = false;
    // Whether the first vertex has a colour, and its line.
    let mut coloured: Option<(bool, usize)> = None;
    for (i, line) in text.lines().enumerate() {
        let line_no = i + 1;
        let at = |message: String| ParseProblem::new(line_no.to_string(), message);
        let at_word =
            |word: &str, message: String| ParseProblem::new(column(line_no, line, word), message);
        let mut words = line.split_whitespace();
        let keyword = words.next().unwrap_or("");
        let words: Vec<&str> = words.collect();
        let numbers = || -> Result<Vec<f64>, ParseProblem> {
            words
                .iter()
                .map(|w| {
                    w.parse::<f64>().map_err(|_| {
                        at_word(w, format!("'{}' is not a number", shown(w.as_bytes())))
                    })
                })
                .collect()
        };
        match keyword {
            "v" => {
                let x = numbers()?;
                let n = counts[0] + 1;
                if !matches!(x.len(), 3 | 4 | 6) {
                    return Err(at(format!(
                        "a vertex needs x y z, optionally w or r g b; got {}",
                        numbers_count(x.len())
                    )));
                }
                for (k, name) in ["x", "y", "z", "w"].iter().enumerate().take(x.len()) {
                    if !x[k].is_finite() {
                        return Err(at_word(
                            words[k],
                            format!(
                                "vertex {n}: {name} is {}",
                                not_finite(x[k], Some(words[k].as_bytes()), "a double")
                            ),
                        ));
                    }
                }
                if x.len() == 4 {
                    if x[3] == 0.0 {
                        return Err(at_word(
                            words[3],
                            format!("vertex {n}: w is 0 (x, y and z are divided by w)"),
                        ));
                    }
                    for (k, name) in ["x", "y", "z"].iter().enumerate() {
                        if !(x[k] / x[3]).is_finite() {
                            return Err(at(format!(
                                "vertex {n}: {name} / w is too large (infinite)"
                            )));
                        }
                    }
                }
                // tobj keeps colours in a list of their own, which must cover every vertex.
                let colour = x.len() == 6;
                match coloured {
                    None => coloured = Some((colour, line_no)),
                    Some((first, first_line)) if first != colour => {
                        let (this, that) = if colour { ("a", "none") } else { ("no", "one") };
                        return Err(at(format!(
                            "vertex {n} has {this} colour (r g b) but the first vertex (line \
                             {first_line}) has {that}: give every vertex a colour or none"
                        )));
                    }
                    Some(_) => {}
                }
                counts[0] += 1;
            }
            "vt" => {
                let x = numbers()?;
                if !matches!(x.len(), 2 | 3) {
                    return Err(at(format!(
                        "a texture coordinate needs u v, optionally w; got {}",
                        numbers_count(x.len())
                    )));
                }
                counts[1] += 1;
            }
            "vn" => {
                if numbers()?.len() != 3 {
                    return Err(at("a normal needs three numbers x y z".into()));
                }
                counts[2] += 1;
            }
            "f" => {
                if words.len() < 3 {
                    return Err(at(format!(
                        "a face needs at least 3 vertices, got {}",
                        words.len()
                    )));
                }
                let mut first_form = None;
                for word in &words {
                    let form = check_reference(word, &counts).map_err(|m| at_word(word, m))?;
                    match first_form {
                        None => first_form = Some((form, word)),
                        Some((f, first)) if f != form => {
                            return Err(at_word(
                                word,
                                format!(
                                    "the face mixes '{}' and '{}': all its vertices must have \
                                     the same form (v, v/vt, v//vn or v/vt/vn)",
                                    shown(first.as_bytes()),
                                    shown(word.as_bytes())
                                ),
                            ));
                        }
                        Some(_) => {}
                    }
                }
            }
            "l" | "p" => blanked = true,
            // What tobj takes for the material's name (and rejects when empty).
            "usemtl" if line.split_once(' ').unwrap_or_default().1.trim().is_empty() => {
                blanked = true;
            }
            _ => {}
        }
    }
    if !blanked {
        return Ok(Cow::Borrowed(text));
    }
    let kept: Vec<&str> = text
        .lines()
        .map(|line| match line.split_whitespace().next() {
            Some("l" | "p") => "",
            Some("usemtl") if line.split_once(' ').unwrap_or_default().1.trim().is_empty() => "",
            _ => line,
        })
        .collect();
    Ok(Cow::Owned(kept.join("\n")))
}

/// Checks a face's vertex reference `v`, `v/vt`, `v//vn` or `v/vt/vn` against the vertices,
/// texture coordinates and normals read so far (negative indices count back from the last), and
/// returns its form: whether it has a texture coordinate and a normal.
fn check_reference(word: &str, counts: &[i64; 3]) -> Result<(bool, bool), String> {
    const WHAT: [&str; 3] = ["vertex", "texture coordinate", "normal"];
    let not_a_reference = || format!("'{}' is not a vertex reference", shown(word.as_bytes()));
    let parts: Vec<&str> = word.split('/').collect();
    if parts.len() > 3 || parts[0].is_empty() {
        return Err(not_a_reference());
    }
    for (k, part) in parts.iter().enumerate().filter(|(_, p)| !p.is_empty()) {
        let n = counts[k];
        match part.parse::<i64>() {
            Ok(i) if (1..=n).contains(&i) || (-n..=-1).contains(&i) => {}
            Ok(0) => {
                return Err(format!(
                    "face refers to {} 0, but indices count from 1",
                    WHAT[k]
                ));
            }
            Ok(i) => {
                return Err(format!(
                    "face refers to {} {i}, but {n} are defined before this line",
                    WHAT[k]
                ));
            }
            Err(_) => {
                // An integer too large for 64 bits is still an index out of range.
                let digits = part.strip_prefix(['-', '+']).unwrap_or(part);
                if digits.bytes().all(|b| b.is_ascii_digit()) && !digits.is_empty() {
                    return Err(format!(
                        "face refers to {} {}, but {n} are defined before this line",
                        WHAT[k],
                        shown(part.as_bytes())
                    ));
                }
                return Err(not_a_reference());
            }
        }
    }
    let has = |k: usize| parts.get(k).is_some_and(|p| !p.is_empty());
    Ok((has(1), has(2)))
}

pub(super) fn write(
    out: &mut impl Write,
    mesh: &Mesh,
    precision: Precision,
) -> std::io::Result<()> {
    writeln!(out, "# written by timbre {}", env!("CARGO_PKG_VERSION"))?;
    if !mesh.name.is_empty() {
        writeln!(out, "o {}", mesh.name)?;
    }
    // Rust prints f64 (and f32) with the fewest digits that read back exactly (as f32).
    let line = |out: &mut dyn Write, key: &str, v: &DVec3| match precision {
        Precision::F32 => writeln!(out, "{key} {} {} {}", v.x as f32, v.y as f32, v.z as f32),
        Precision::F64 => writeln!(out, "{key} {} {} {}", v.x, v.y, v.z),
    };
    for v in &mesh.vertices {
        line(out, "v", v)?;
    }
    for n in mesh.normals.iter().flatten() {
        line(out, "vn", n)?;
    }
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|i| i + 1);
        if mesh.normals.is_some() {
            writeln!(out, "f {a}//{a} {b}//{b} {c}//{c}")?;
        } else {
            writeln!(out, "f {a} {b} {c}")?;
        }
    }
    Ok(())
}
