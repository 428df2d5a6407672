//! Triangle meshes from files: Wavefront OBJ and PLY (ASCII, binary little and big endian),
//! read and written, and a generator of test meshes.
//!
//! A file is read into [`Mesh`]es (an OBJ file may hold several objects or groups, each one
//! mesh). Polygons are triangulated as fans. Every index and coordinate is checked, and so is
//! every PLY value against its header's declaration; errors name the file, the place (line and
//! column in text, byte offset in binary PLY) and what is at fault, in words. Text quoted from a
//! file is shortened and has its control characters escaped.

pub mod generate;
mod mtl;
mod obj;
mod ply;

use std::path::Path;

use glam::DVec3;
use thiserror::Error;

pub use mtl::Material;
pub use obj::Open;
pub use ply::{PlyEncoding, Precision};

/// A triangle mesh as read from (or written to) a file: shared vertices, index triples
/// (counter-clockwise seen from outside) and optional per-vertex normals.
#[derive(Debug, Clone, PartialEq)]
pub struct Mesh {
    /// The object or group name in the file ("" when the file names none).
    pub name: String,
    pub vertices: Vec<DVec3>,
    pub triangles: Vec<[u32; 3]>,
    /// One normal per vertex, when the file has them.
    pub normals: Option<Vec<DVec3>>,
}

/// A mesh file that could not be read.
#[derive(Debug, Error)]
pub enum MeshError {
    #[error("{path}: {source}")]
    Io {
        path: String,
        source: std::io::Error,
    },
    /// `location` is where in the file, in the scene file's style: "N:C" (line and column) or
    /// "N" (a line) in OBJ, ASCII PLY and PLY headers, "byte N" in binary PLY, "header", or
    /// empty.
    #[error("{path}:{location}{}{message}", if location.is_empty() { " " } else { ": " })]
    Invalid {
        path: String,
        location: String,
        message: String,
    },
}

/// Mesh file formats.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MeshFormat {
    Obj,
    Ply,
}

impl MeshFormat {
    /// The format named by a file's extension (`.obj`, `.ply`, any case).
    pub fn from_path(path: &Path) -> Option<MeshFormat> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "obj" => Some(MeshFormat::Obj),
            "ply" => Some(MeshFormat::Ply),
            _ => None,
        }
    }
}

/// Largest mesh file that is read, in bytes (4 GiB: 200 million triangles in binary PLY).
pub const MAX_FILE_BYTES: u64 = 4 << 30;

/// Reads the meshes in an OBJ or PLY file (a PLY file holds one); an OBJ file's materials are
/// not read.
pub fn load(path: &Path) -> Result<Vec<Mesh>, MeshError> {
    Ok(load_with(path, None)?.meshes)
}

/// A mesh file's meshes with their materials.
#[derive(Debug)]
pub struct Loaded {
    pub meshes: Vec<Mesh>,
    /// Each mesh's texture coordinates (OBJ `vt`, PLY `s t`), one per vertex, if it has them.
    pub uvs: Vec<Option<Vec<glam::DVec2>>>,
    /// Each mesh's vertex colours (PLY `red green blue`), one per vertex, if it has them.
    pub colours: Vec<Option<Vec<DVec3>>>,
    /// The index in `materials` of each mesh's material (OBJ `usemtl`), if any.
    pub material_of: Vec<Option<usize>>,
    pub materials: Vec<Material>,
    /// Unsupported MTL keys, each "LIBRARY:N:C: 'KEY' is not supported and is ignored".
    pub warnings: Vec<String>,
}

/// Reads the meshes in an OBJ or PLY file; with `open`, also the materials of the MTL files
/// an OBJ file names (`open` is given their names relative to the OBJ file).
pub fn load_with(path: &Path, open: Option<Open>) -> Result<Loaded, MeshError> {
    let shown = path.display().to_string();
    let format = MeshFormat::from_path(path).ok_or_else(|| MeshError::Invalid {
        path: shown.clone(),
        location: String::new(),
        message: "unknown mesh format: the file name must end in .obj or .ply".into(),
    })?;
    let bytes =
        crate::files::read_regular(path, MAX_FILE_BYTES).map_err(|source| MeshError::Io {
            path: shown.clone(),
            source,
        })?;
    let loaded = match format {
        MeshFormat::Obj => obj::read_with(&bytes, open),
        MeshFormat::Ply => ply::read(&bytes).map(|r| Loaded {
            meshes: vec![r.mesh],
            uvs: vec![r.uvs],
            colours: vec![r.colours],
            material_of: vec![None],
            materials: Vec::new(),
            warnings: Vec::new(),
        }),
    }
    .map_err(|e| e.in_file(&shown))?;
    if loaded.meshes.iter().all(|m| m.triangles.is_empty()) {
        return Err(MeshError::Invalid {
            path: shown,
            location: String::new(),
            message: "the mesh has no faces".into(),
        });
    }
    Ok(loaded)
}

/// Writes a mesh as OBJ or PLY (chosen by the extension; PLY in the given encoding), exactly
/// (coordinates in double precision).
pub fn save(path: &Path, mesh: &Mesh, encoding: PlyEncoding) -> Result<(), MeshError> {
    save_as(path, mesh, encoding, Precision::F64)
}

/// [`save`] with the coordinates in the given precision.
pub fn save_as(
    path: &Path,
    mesh: &Mesh,
    encoding: PlyEncoding,
    precision: Precision,
) -> Result<(), MeshError> {
    let shown = path.display().to_string();
    let io = |source| MeshError::Io {
        path: shown.clone(),
        source,
    };
    let Some(format) = MeshFormat::from_path(path) else {
        return Err(MeshError::Invalid {
            path: shown,
            location: String::new(),
            message: "unknown mesh format: the file name must end in .obj or .ply".into(),
        });
    };
    crate::files::write_atomically(path, |mut out| match format {
        MeshFormat::Obj => obj::write(&mut out, mesh, precision),
        MeshFormat::Ply => ply::write(&mut out, mesh, encoding, precision),
    })
    .map_err(io)
}

/// A problem found while parsing, before the file name is attached.
#[derive(Debug)]
struct ParseProblem {
    location: String,
    message: String,
}

impl ParseProblem {
    fn new(location: impl Into<String>, message: impl Into<String>) -> ParseProblem {
        ParseProblem {
            location: location.into(),
            message: message.into(),
        }
    }

    fn in_file(self, path: &str) -> MeshError {
        MeshError::Invalid {
            path: path.to_string(),
            location: self.location,
            message: self.message,
        }
    }
}

/// Checks that every coordinate is finite; `locate(i)` names vertex i in the file. (The readers
/// check every coordinate where they read it; this is a last guard after `tobj`.)
fn check_finite(
    what: &str,
    points: &[DVec3],
    locate: impl Fn(usize) -> String,
) -> Result<(), ParseProblem> {
    match points.iter().position(|p| !p.is_finite()) {
        Some(i) => Err(ParseProblem::new(
            locate(i),
            format!("{what} {i} is not finite"),
        )),
        None => Ok(()),
    }
}

/// The longest text from a file that a message shows; longer is cut, with "…".
const SHOWN_CHARS: usize = 40;

/// Where `word` (a slice of `line`) starts, as "N:C" (line and column).
pub(super) fn column(line_no: usize, line: &str, word: &str) -> String {
    let offset = (word.as_ptr() as usize).saturating_sub(line.as_ptr() as usize);
    let column = line.get(..offset).map_or(0, |s| s.chars().count()) + 1;
    format!("{line_no}:{column}")
}

/// Text from a file as a message may show it: at most [`SHOWN_CHARS`] characters (then "…"),
/// with [`escaped`] characters, so that a file cannot flood or drive the terminal.
fn shown(bytes: &[u8]) -> String {
    escaped(bytes, SHOWN_CHARS)
}

/// `bytes` as text with control and invisible formatting characters escaped (`\x1b`,
/// `\u{202e}`), bytes that are not UTF-8 written as `\xNN` and a backslash doubled; cut after
/// `limit` characters (then "…").
fn escaped(bytes: &[u8], limit: usize) -> String {
    let mut out = String::new();
    let mut chars = 0;
    for chunk in bytes.utf8_chunks() {
        for c in chunk.valid().chars() {
            if chars == limit {
                out.push('…');
                return out;
            }
            chars += 1;
            match (c, crate::text::escape(c)) {
                ('\\', _) => out.push_str("\\\\"),
                (_, Some(e)) => out.push_str(&e),
                (c, None) => out.push(c),
            }
        }
        for &b in chunk.invalid() {
            if chars == limit {
                out.push('…');
                return out;
            }
            chars += 1;
            out.push_str(&format!("\\x{b:02x}"));
        }
    }
    out
}

/// Why a coordinate read as `value` is not finite: "NaN", "infinite", or, when its text in the
/// file (`token`) is a finite number too large for the type, "infinite ('1e999' is too large for
/// a double)".
fn not_finite(value: f64, token: Option<&[u8]>, type_name: &str) -> String {
    if value.is_nan() {
        return "NaN".into();
    }
    let spelled_infinite = token.is_some_and(|t| {
        let t = t.to_ascii_lowercase();
        let t = t.strip_prefix(b"-").or(t.strip_prefix(b"+")).unwrap_or(&t);
        t.starts_with(b"inf")
    });
    match token {
        Some(t) if !spelled_infinite => {
            format!("infinite ('{}' is too large for {type_name})", shown(t))
        }
        _ => "infinite".into(),
    }
}

impl Mesh {
    /// Per-vertex normals: the area-weighted average of the normals of the triangles around
    /// each vertex (a vertex in no triangle, or whose triangles cancel, gets +z).
    pub fn vertex_normals(&self) -> Vec<DVec3> {
        let mut sums = vec![DVec3::ZERO; self.vertices.len()];
        for t in &self.triangles {
            let [a, b, c] = t.map(|i| self.vertices[i as usize]);
            let n = (b - a).cross(c - a);
            for &i in t {
                sums[i as usize] += n;
            }
        }
        sums.into_iter()
            .map(|n| n.try_normalize().unwrap_or(DVec3::Z))
            .collect()
    }
}
