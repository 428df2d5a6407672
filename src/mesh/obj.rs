//! Wavefront OBJ, read with `tobj` (one mesh per object or group; polygons triangulated;
//! materials and texture coordinates ignored) and written with one `v` (and `vn`) line per
//! vertex.
//!
//! `tobj` reports what went wrong but not where, so when it fails (or a coordinate is not
//! finite) the text is scanned again for the first offending line.

use std::io::Write;

use glam::DVec3;

use super::{Mesh, ParseProblem, check_finite};

pub(super) fn read(bytes: &[u8]) -> Result<Vec<Mesh>, ParseProblem> {
    let options = tobj::LoadOptions {
        single_index: true,
        triangulate: true,
        ignore_points: true,
        ignore_lines: true,
    };
    let (models, _materials) = tobj::load_obj_buf(&mut &bytes[..], &options, |_| {
        Err(tobj::LoadError::OpenFileFailed)
    })
    .map_err(|e| locate(bytes, e))?;

    let mut meshes = Vec::with_capacity(models.len());
    for model in models {
        let m = model.mesh;
        let vertices = to_points(&m.positions);
        if check_finite("vertex", &vertices, |_| String::new()).is_err() {
            return Err(non_finite(bytes));
        }
        let normals = (m.normals.len() == m.positions.len())
            .then(|| to_points(&m.normals))
            .filter(|n| n.iter().all(|n| n.is_finite()));
        meshes.push(Mesh {
            name: model.name,
            vertices,
            triangles: m
                .indices
                .chunks_exact(3)
                .map(|t| [t[0], t[1], t[2]])
                .collect(),
            normals,
        });
    }
    Ok(meshes)
}

fn to_points(xyz: &[f64]) -> Vec<DVec3> {
    xyz.chunks_exact(3).map(DVec3::from_slice).collect()
}

/// The numbered lines of the file (1-based) that start with `keyword`, and the rest of each.
fn lines_with<'a>(text: &'a str, keyword: &'a str) -> impl Iterator<Item = (usize, &'a str)> {
    text.lines().enumerate().filter_map(move |(i, line)| {
        let mut words = line.trim_start().splitn(2, char::is_whitespace);
        (words.next() == Some(keyword)).then(|| (i + 1, words.next().unwrap_or("")))
    })
}

fn parses_as_numbers(rest: &str, n: usize) -> bool {
    let words: Vec<&str> = rest.split_whitespace().collect();
    words.len() >= n && words[..n].iter().all(|w| w.parse::<f64>().is_ok())
}

/// Turns a `tobj` error into a message with the line it comes from, where that can be found.
fn locate(bytes: &[u8], error: tobj::LoadError) -> ParseProblem {
    let Ok(text) = std::str::from_utf8(bytes) else {
        return ParseProblem::new("", "not a text file (invalid UTF-8)");
    };
    let vertex_count = lines_with(text, "v").count();
    let found = match error {
        tobj::LoadError::PositionParseError => lines_with(text, "v")
            .find(|(_, rest)| !parses_as_numbers(rest, 3))
            .map(|(line, _)| (line, "a vertex needs three numbers x y z".to_string())),
        tobj::LoadError::NormalParseError => lines_with(text, "vn")
            .find(|(_, rest)| !parses_as_numbers(rest, 3))
            .map(|(line, _)| (line, "a normal needs three numbers x y z".to_string())),
        tobj::LoadError::FaceVertexOutOfBounds | tobj::LoadError::FaceParseError => {
            lines_with(text, "f").find_map(|(line, rest)| {
                bad_face(rest, vertex_count).map(|message| (line, message))
            })
        }
        _ => None,
    };
    match found {
        Some((line, message)) => ParseProblem::new(format!("line {line}"), message),
        None => ParseProblem::new("", format!("invalid OBJ file: {error}")),
    }
}

/// What is wrong with a face line's vertex references, if anything.
fn bad_face(rest: &str, vertex_count: usize) -> Option<String> {
    let n = vertex_count as i64;
    for word in rest.split_whitespace() {
        let index = word.split('/').next().unwrap_or("");
        match index.parse::<i64>() {
            Ok(i) if (1..=n).contains(&i) || (-n..=-1).contains(&i) => {}
            Ok(i) => {
                return Some(format!(
                    "face refers to vertex {i}, but the file has {vertex_count} vertices"
                ));
            }
            Err(_) => return Some(format!("'{word}' is not a vertex reference")),
        }
    }
    None
}

/// The error for a vertex with a non-finite coordinate, at its line.
fn non_finite(bytes: &[u8]) -> ParseProblem {
    let text = String::from_utf8_lossy(bytes);
    let line = lines_with(&text, "v")
        .find(|(_, rest)| {
            rest.split_whitespace()
                .take(3)
                .any(|w| w.parse::<f64>().is_ok_and(|x| !x.is_finite()))
        })
        .map_or(String::new(), |(line, _)| format!("line {line}"));
    ParseProblem::new(line, "a vertex coordinate is not finite")
}

pub(super) fn write(out: &mut impl Write, mesh: &Mesh) -> std::io::Result<()> {
    writeln!(out, "# written by timbre {}", env!("CARGO_PKG_VERSION"))?;
    if !mesh.name.is_empty() {
        writeln!(out, "o {}", mesh.name)?;
    }
    // Rust prints f64 with the fewest digits that read back exactly.
    for v in &mesh.vertices {
        writeln!(out, "v {} {} {}", v.x, v.y, v.z)?;
    }
    if let Some(normals) = &mesh.normals {
        for n in normals {
            writeln!(out, "vn {} {} {}", n.x, n.y, n.z)?;
        }
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
