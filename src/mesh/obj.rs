//! Wavefront OBJ, read with `tobj` (one mesh per object or group; polygons triangulated;
//! materials and texture coordinates ignored) and written with one `v` (and `vn`) line per
//! vertex.
//!
//! `tobj` reports what went wrong but not where, so the text is checked line by line first.

use std::borrow::Cow;
use std::io::Write;

use glam::DVec3;

use super::{Mesh, ParseProblem, check_finite};

pub(super) fn read(bytes: &[u8]) -> Result<Vec<Mesh>, ParseProblem> {
    let text = std::str::from_utf8(bytes)
        .map_err(|_| ParseProblem::new("", "not a text file (invalid UTF-8)"))?;
    let faces_only = check(text)?;
    let options = tobj::LoadOptions {
        single_index: true,
        triangulate: true,
        ignore_points: true,
        ignore_lines: true,
    };
    let (models, _materials) = tobj::load_obj_buf(&mut faces_only.as_bytes(), &options, |_| {
        Err(tobj::LoadError::OpenFileFailed)
    })
    .map_err(|e| ParseProblem::new("", format!("invalid OBJ file: {e}")))?;

    let mut meshes = Vec::with_capacity(models.len());
    for model in models {
        let m = model.mesh;
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
                model.name
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
    Ok(meshes)
}

fn to_points(xyz: &[f64]) -> Vec<DVec3> {
    xyz.chunks_exact(3).map(DVec3::from_slice).collect()
}

/// Checks every vertex, normal and face line (`tobj` reports errors without a line number),
/// and returns the text with point (`p`) and polyline (`l`) lines blanked: `tobj` would read
/// those of three or more points as polygons.
fn check(text: &str) -> Result<Cow<'_, str>, ParseProblem> {
    let mut counts = [0i64; 3]; // v, vt, vn read so far
    let mut blanked = false;
    for (i, line) in text.lines().enumerate() {
        let at = |message: String| ParseProblem::new(format!("line {}", i + 1), message);
        let mut words = line.split_whitespace();
        let keyword = words.next().unwrap_or("");
        let words: Vec<&str> = words.collect();
        let numbers = || -> Result<Vec<f64>, ParseProblem> {
            words
                .iter()
                .map(|w| {
                    w.parse::<f64>()
                        .map_err(|_| at(format!("'{w}' is not a number")))
                })
                .collect()
        };
        match keyword {
            "v" => {
                let x = numbers()?;
                let p = match x.len() {
                    3 | 6 => DVec3::new(x[0], x[1], x[2]),
                    4 | 7 if x[3] == 0.0 => return Err(at("a vertex with w = 0".into())),
                    4 | 7 => DVec3::new(x[0], x[1], x[2]) / x[3],
                    n => {
                        return Err(at(format!(
                            "a vertex needs x y z, optionally w and r g b; got {n} numbers"
                        )));
                    }
                };
                if !p.is_finite() {
                    return Err(at("a vertex coordinate is not finite".into()));
                }
                counts[0] += 1;
            }
            "vt" => {
                numbers()?;
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
                for word in &words {
                    check_reference(word, &counts).map_err(at)?;
                }
            }
            "l" | "p" => blanked = true,
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
            _ => line,
        })
        .collect();
    Ok(Cow::Owned(kept.join("\n")))
}

/// Checks a face's vertex reference `v`, `v/vt`, `v//vn` or `v/vt/vn` against the vertices,
/// texture coordinates and normals read so far (negative indices count back from the last).
fn check_reference(word: &str, counts: &[i64; 3]) -> Result<(), String> {
    const WHAT: [&str; 3] = ["vertex", "texture coordinate", "normal"];
    let parts: Vec<&str> = word.split('/').collect();
    if parts.len() > 3 || parts[0].is_empty() {
        return Err(format!("'{word}' is not a vertex reference"));
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
            Err(_) => return Err(format!("'{word}' is not a vertex reference")),
        }
    }
    Ok(())
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
