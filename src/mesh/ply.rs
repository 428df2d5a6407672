//! PLY (Stanford polygon file), ASCII and binary little/big endian, read with `ply-rs-bw`
//! straight into typed vertices and faces, and written by hand (`float`/`double` vertices,
//! `uint` indices).
//!
//! Read: element `vertex` with `x y z` (any numeric type) and optionally `nx ny nz`; element
//! `face` with a list `vertex_indices` (or `vertex_index`); other elements and properties are
//! skipped.

use std::io::Write;

use glam::DVec3;
use ply_rs_bw::parser::{Parser, Reader};
use ply_rs_bw::ply::{ElementDef, Encoding, Header, PropertyAccess, PropertyAccessResult};

use super::{Mesh, ParseProblem, check_finite, fan};

/// How a PLY file is written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlyEncoding {
    Ascii,
    BinaryLittleEndian,
    BinaryBigEndian,
}

#[derive(Debug, Default)]
struct Vertex {
    position: [f64; 3],
    normal: [f64; 3],
}

impl Vertex {
    fn set(&mut self, name: &str, value: f64) -> PropertyAccessResult {
        let slot = match name {
            "x" => &mut self.position[0],
            "y" => &mut self.position[1],
            "z" => &mut self.position[2],
            "nx" => &mut self.normal[0],
            "ny" => &mut self.normal[1],
            "nz" => &mut self.normal[2],
            _ => return PropertyAccessResult::Ignored,
        };
        *slot = value;
        PropertyAccessResult::Set
    }
}

impl PropertyAccess for Vertex {
    fn new() -> Self {
        Vertex::default()
    }
    fn set_char(&mut self, name: &str, value: i8) -> PropertyAccessResult {
        self.set(name, value.into())
    }
    fn set_uchar(&mut self, name: &str, value: u8) -> PropertyAccessResult {
        self.set(name, value.into())
    }
    fn set_short(&mut self, name: &str, value: i16) -> PropertyAccessResult {
        self.set(name, value.into())
    }
    fn set_ushort(&mut self, name: &str, value: u16) -> PropertyAccessResult {
        self.set(name, value.into())
    }
    fn set_int(&mut self, name: &str, value: i32) -> PropertyAccessResult {
        self.set(name, value.into())
    }
    fn set_uint(&mut self, name: &str, value: u32) -> PropertyAccessResult {
        self.set(name, value.into())
    }
    fn set_float(&mut self, name: &str, value: f32) -> PropertyAccessResult {
        self.set(name, value.into())
    }
    fn set_double(&mut self, name: &str, value: f64) -> PropertyAccessResult {
        self.set(name, value)
    }
}

/// A polygon's vertex indices (as i64, so that negative values can be reported).
#[derive(Debug, Default)]
struct Face {
    indices: Vec<i64>,
}

fn is_index_list(name: &str) -> bool {
    name == "vertex_indices" || name == "vertex_index"
}

impl Face {
    fn set<T: Into<i64>>(&mut self, name: &str, values: Vec<T>) -> PropertyAccessResult {
        if !is_index_list(name) {
            return PropertyAccessResult::Ignored;
        }
        self.indices = values.into_iter().map(Into::into).collect();
        PropertyAccessResult::Set
    }
}

impl PropertyAccess for Face {
    fn new() -> Self {
        Face::default()
    }
    fn set_list_char(&mut self, name: &str, value: Vec<i8>) -> PropertyAccessResult {
        self.set(name, value)
    }
    fn set_list_uchar(&mut self, name: &str, value: Vec<u8>) -> PropertyAccessResult {
        self.set(name, value)
    }
    fn set_list_short(&mut self, name: &str, value: Vec<i16>) -> PropertyAccessResult {
        self.set(name, value)
    }
    fn set_list_ushort(&mut self, name: &str, value: Vec<u16>) -> PropertyAccessResult {
        self.set(name, value)
    }
    fn set_list_int(&mut self, name: &str, value: Vec<i32>) -> PropertyAccessResult {
        self.set(name, value)
    }
    fn set_list_uint(&mut self, name: &str, value: Vec<u32>) -> PropertyAccessResult {
        self.set(name, value)
    }
}

/// An element timbre does not use: every property is skipped.
struct Skipped;

impl PropertyAccess for Skipped {
    fn new() -> Self {
        Skipped
    }
}

pub(super) fn read(bytes: &[u8]) -> Result<Mesh, ParseProblem> {
    let mut reader = Reader::new(bytes);
    let header = Parser::<Skipped>::new()
        .read_header(&mut reader)
        .map_err(|e| problem(e, true))?;
    let ascii = header.encoding == Encoding::Ascii;
    let element = |name: &str| header.elements.get(name);
    let vertex_def = element("vertex")
        .ok_or_else(|| ParseProblem::new("header", "there is no 'vertex' element"))?;
    for p in ["x", "y", "z"] {
        if !vertex_def.properties.contains_key(p) {
            return Err(ParseProblem::new(
                "header",
                format!("the 'vertex' element has no property '{p}'"),
            ));
        }
    }
    let face_def =
        element("face").ok_or_else(|| ParseProblem::new("header", "there is no 'face' element"))?;
    if !face_def.properties.keys().any(|k| is_index_list(k)) {
        return Err(ParseProblem::new(
            "header",
            "the 'face' element has no list property 'vertex_indices'",
        ));
    }
    let has_normals = ["nx", "ny", "nz"]
        .iter()
        .all(|p| vertex_def.properties.contains_key(*p));

    let mut vertices = Vec::new();
    let mut faces = Vec::new();
    for def in header.elements.values() {
        match def.name.as_str() {
            "vertex" => vertices = payload::<Vertex>(&mut reader, def, &header, ascii)?,
            "face" => faces = payload::<Face>(&mut reader, def, &header, ascii)?,
            _ => {
                payload::<Skipped>(&mut reader, def, &header, ascii)?;
            }
        }
    }

    let positions: Vec<DVec3> = vertices.iter().map(|v| DVec3::from(v.position)).collect();
    check_finite("vertex", &positions, |i| format!("element 'vertex' {i}"))?;
    let n = positions.len() as i64;
    let mut triangles = Vec::with_capacity(faces.len());
    let mut polygon = Vec::new();
    for (i, face) in faces.iter().enumerate() {
        if face.indices.len() < 3 {
            return Err(ParseProblem::new(
                format!("element 'face' {i}"),
                format!(
                    "a face needs at least 3 vertices, got {}",
                    face.indices.len()
                ),
            ));
        }
        if let Some(bad) = face.indices.iter().find(|&&k| k < 0 || k >= n) {
            return Err(ParseProblem::new(
                format!("element 'face' {i}"),
                format!("vertex index {bad} is out of range (the file has {n} vertices)"),
            ));
        }
        polygon.clear();
        polygon.extend(face.indices.iter().map(|&k| k as u32));
        fan(&polygon, &mut triangles);
    }
    let normals = has_normals
        .then(|| {
            vertices
                .iter()
                .map(|v| DVec3::from(v.normal))
                .collect::<Vec<_>>()
        })
        .filter(|n| n.iter().all(|n| n.is_finite()));
    Ok(Mesh {
        name: String::new(),
        vertices: positions,
        triangles,
        normals,
    })
}

/// Reads all instances of one element.
fn payload<E: PropertyAccess>(
    reader: &mut Reader<&[u8]>,
    def: &ElementDef,
    header: &Header,
    ascii: bool,
) -> Result<Vec<E>, ParseProblem> {
    Parser::<E>::new()
        .read_payload_for_element(reader, def, header)
        .map_err(|e| problem(e, ascii))
}

/// A `ply-rs-bw` error; its line number means something only in ASCII files and the header.
fn problem(e: ply_rs_bw::parser::ParseError, lines_mean_something: bool) -> ParseProblem {
    let location = match e.line() {
        Some(line) if lines_mean_something => format!("line {line}"),
        _ => String::new(),
    };
    let text = e.to_string();
    let message = text
        .strip_prefix(&format!("Line {}: ", e.line().unwrap_or(0)))
        .unwrap_or(&text);
    // ply-rs-bw's messages run over several tab-indented lines.
    let message: Vec<&str> = message
        .split(['\n', '\t'])
        .filter(|m| !m.trim().is_empty())
        .collect();
    ParseProblem::new(
        location,
        format!("invalid PLY file: {}", message.join(" ").trim()),
    )
}

pub(super) fn write(
    out: &mut impl Write,
    mesh: &Mesh,
    encoding: PlyEncoding,
) -> std::io::Result<()> {
    let format = match encoding {
        PlyEncoding::Ascii => "ascii",
        PlyEncoding::BinaryLittleEndian => "binary_little_endian",
        PlyEncoding::BinaryBigEndian => "binary_big_endian",
    };
    writeln!(out, "ply\nformat {format} 1.0")?;
    writeln!(
        out,
        "comment written by timbre {}",
        env!("CARGO_PKG_VERSION")
    )?;
    writeln!(out, "element vertex {}", mesh.vertices.len())?;
    for p in ["x", "y", "z"] {
        writeln!(out, "property double {p}")?;
    }
    if mesh.normals.is_some() {
        for p in ["nx", "ny", "nz"] {
            writeln!(out, "property double {p}")?;
        }
    }
    writeln!(out, "element face {}", mesh.triangles.len())?;
    writeln!(out, "property list uchar uint vertex_indices\nend_header")?;

    let normals = mesh.normals.as_deref();
    for (i, v) in mesh.vertices.iter().enumerate() {
        let mut values = v.to_array().to_vec();
        if let Some(n) = normals {
            values.extend(n[i].to_array());
        }
        match encoding {
            PlyEncoding::Ascii => {
                let words: Vec<String> = values.iter().map(f64::to_string).collect();
                writeln!(out, "{}", words.join(" "))?;
            }
            PlyEncoding::BinaryLittleEndian => {
                for x in values {
                    out.write_all(&x.to_le_bytes())?;
                }
            }
            PlyEncoding::BinaryBigEndian => {
                for x in values {
                    out.write_all(&x.to_be_bytes())?;
                }
            }
        }
    }
    for t in &mesh.triangles {
        match encoding {
            PlyEncoding::Ascii => writeln!(out, "3 {} {} {}", t[0], t[1], t[2])?,
            PlyEncoding::BinaryLittleEndian => {
                out.write_all(&[3])?;
                for i in t {
                    out.write_all(&i.to_le_bytes())?;
                }
            }
            PlyEncoding::BinaryBigEndian => {
                out.write_all(&[3])?;
                for i in t {
                    out.write_all(&i.to_be_bytes())?;
                }
            }
        }
    }
    Ok(())
}
