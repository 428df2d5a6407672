//! PLY (Stanford polygon file), ASCII and binary little/big endian: read by the parser here
//! straight into vertices and triangles (no allocation per face), and written by hand
//! (`double` vertices, `uint` indices).
//!
//! Read: element `vertex` with `x y z` (any numeric type) and optionally `nx ny nz` and
//! `red green blue` (colours: an integer type's values over its largest, or floats in [0, 1])
//! and `s t` (or `u v`, `texture_u texture_v`: texture coordinates);
//! element
//! `face` with a list `vertex_indices` (or `vertex_index`) of an integer type; other elements
//! and properties are read, checked and skipped. Only PLY 1.0.
//!
//! The header is taken at its word and the body must match it exactly: every value of its
//! declared type (in range, an integer where the type is one), every ASCII line with exactly the
//! values its element declares, nothing after the last element, no property or element declared
//! twice, list counts of integer types, coordinates that are numbers and finite. Errors say where
//! (ASCII: line and column; binary: the byte offset) and which element; the caller adds the
//! file's name. Text from the file in a message goes through [`shown`].

use std::collections::HashMap;
use std::io::Write;

use glam::{DVec2, DVec3};

use super::{Mesh, ParseProblem, not_finite, shown};

/// How a PLY file is written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlyEncoding {
    Ascii,
    BinaryLittleEndian,
    BinaryBigEndian,
}

/// The precision of a written mesh's coordinates: single (half the size, about 7 significant
/// digits) or double (exact).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Precision {
    F32,
    F64,
}

/// A PLY number type.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    /// The type named in a header (both the classic names and the sized ones).
    fn from_word(word: &[u8]) -> Option<Scalar> {
        Some(match word {
            b"char" | b"int8" => Scalar::I8,
            b"uchar" | b"uint8" => Scalar::U8,
            b"short" | b"int16" => Scalar::I16,
            b"ushort" | b"uint16" => Scalar::U16,
            b"int" | b"int32" => Scalar::I32,
            b"uint" | b"uint32" => Scalar::U32,
            b"float" | b"float32" => Scalar::F32,
            b"double" | b"float64" => Scalar::F64,
            _ => return None,
        })
    }

    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }

    fn is_integer(self) -> bool {
        !matches!(self, Scalar::F32 | Scalar::F64)
    }

    /// The values of an integer type.
    fn range(self) -> (i64, i64) {
        match self {
            Scalar::I8 => (i8::MIN.into(), i8::MAX.into()),
            Scalar::U8 => (0, u8::MAX.into()),
            Scalar::I16 => (i16::MIN.into(), i16::MAX.into()),
            Scalar::U16 => (0, u16::MAX.into()),
            Scalar::I32 => (i32::MIN.into(), i32::MAX.into()),
            Scalar::U32 => (0, u32::MAX.into()),
            Scalar::F32 | Scalar::F64 => (i64::MIN, i64::MAX),
        }
    }

    /// "a float", "a double" or "an int", for "too large for …".
    fn with_article(self) -> &'static str {
        match self {
            Scalar::F32 => "a float",
            Scalar::F64 => "a double",
            _ => "an integer",
        }
    }
}

/// The PLY type names, for messages.
const TYPE_NAMES: &str = "char, uchar, short, ushort, int, uint, float, double \
    (or int8, uint8, int16, uint16, int32, uint32, float32, float64)";

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    Scalar(Scalar),
    List { count: Scalar, item: Scalar },
}

/// A property as declared: its name, type (and the type's words as written) and line.
#[derive(Debug)]
struct Property<'a> {
    name: &'a [u8],
    kind: Kind,
    /// The type as written: `[type]`, or `[count type, item type]` for a list.
    words: [&'a [u8]; 2],
    line: usize,
}

impl Property<'_> {
    fn is_list(&self) -> bool {
        matches!(self.kind, Kind::List { .. })
    }
}

#[derive(Debug)]
struct Element<'a> {
    name: &'a [u8],
    count: u64,
    line: usize,
    properties: Vec<Property<'a>>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
enum Encoding {
    /// Until a format line says otherwise.
    #[default]
    Ascii,
    BinaryLittleEndian,
    BinaryBigEndian,
}

#[derive(Debug)]
struct Header<'a> {
    encoding: Encoding,
    elements: Vec<Element<'a>>,
    /// Where the body starts (just after the `end_header` line).
    body: usize,
    /// How many lines the header has.
    lines: usize,
}

/// Blanks between words: spaces, tabs, a carriage return before the newline.
fn is_blank(b: u8) -> bool {
    matches!(b, b' ' | b'\t' | b'\r' | b'\x0b' | b'\x0c')
}

fn words(line: &[u8]) -> Vec<&[u8]> {
    line.split(|&b| is_blank(b))
        .filter(|w| !w.is_empty())
        .collect()
}

fn trimmed(line: &[u8]) -> &[u8] {
    let start = line
        .iter()
        .position(|&b| !is_blank(b))
        .unwrap_or(line.len());
    let end = line
        .iter()
        .rposition(|&b| !is_blank(b))
        .map_or(start, |e| e + 1);
    &line[start..end]
}

/// `n` instances of an element, in words: "3 vertices", "1 face", "2 'edge' elements".
fn count_of(n: u64, element: &[u8]) -> String {
    let plural = n != 1;
    match (element, plural) {
        (b"vertex", false) => format!("{n} vertex"),
        (b"vertex", true) => format!("{n} vertices"),
        (b"face", false) => format!("{n} face"),
        (b"face", true) => format!("{n} faces"),
        (name, false) => format!("{n} '{}' element", shown(name)),
        (name, true) => format!("{n} '{}' elements", shown(name)),
    }
}

/// "1 value", "2 values".
fn values_count(n: u64) -> String {
    if n == 1 {
        "1 value".into()
    } else {
        format!("{n} values")
    }
}

/// Reads the header: every line up to `end_header`, checked for syntax and repetition.
fn parse_header(bytes: &[u8]) -> Result<Header<'_>, ParseProblem> {
    if bytes.is_empty() {
        return Err(ParseProblem::new("", "not a PLY file: the file is empty"));
    }
    let mut pos = 0;
    let mut line_no = 0;
    let mut header = HeaderLines::default();
    loop {
        if pos >= bytes.len() {
            return Err(ParseProblem::new(
                (line_no + 1).to_string(),
                "the file ends in the header: there is no 'end_header' line",
            ));
        }
        let end = bytes[pos..]
            .iter()
            .position(|&b| b == b'\n')
            .map_or(bytes.len(), |k| pos + k);
        let line = &bytes[pos..end];
        let next = (end + 1).min(bytes.len());
        line_no += 1;
        let at = |message: String| ParseProblem::new(line_no.to_string(), message);
        if line_no == 1 {
            if trimmed(line) != b"ply" {
                return Err(at(format!(
                    "not a PLY file: the first line is '{}', not 'ply'",
                    shown(trimmed(line))
                )));
            }
            pos = next;
            continue;
        }
        let w = words(line);
        match w.first().copied() {
            None | Some(b"comment" | b"obj_info") => {}
            Some(b"format") => header.format(&w, line, line_no, &at)?,
            Some(b"element") => header.element(&w, line, line_no, &at)?,
            Some(b"property") => header.property(&w, line, line_no, &at)?,
            Some(b"end_header") => {
                if w.len() > 1 {
                    return Err(at(format!(
                        "'{}' has words after 'end_header'",
                        shown(trimmed(line))
                    )));
                }
                if header.format.is_none() {
                    return Err(at("the header has no 'format' line".into()));
                }
                return Ok(Header {
                    encoding: header.encoding,
                    elements: header.elements,
                    body: next,
                    lines: line_no,
                });
            }
            Some(keyword) => {
                return Err(at(format!(
                    "'{}' is not a PLY header keyword (format, comment, obj_info, element, \
                     property, end_header)",
                    shown(keyword)
                )));
            }
        }
        pos = next;
    }
}

/// The header lines read so far: the format (and its line), the elements with their
/// properties, and the lines each element and each property of the last element are declared
/// on (to report one declared twice).
#[derive(Default)]
struct HeaderLines<'a> {
    format: Option<usize>,
    encoding: Encoding,
    elements: Vec<Element<'a>>,
    element_lines: HashMap<&'a [u8], usize>,
    property_lines: HashMap<&'a [u8], usize>,
}

/// Makes the error of a header line.
type At<'f> = &'f dyn Fn(String) -> ParseProblem;

impl<'a> HeaderLines<'a> {
    /// A `format ENCODING 1.0` line (its words `w`).
    fn format(
        &mut self,
        w: &[&[u8]],
        line: &[u8],
        line_no: usize,
        at: At,
    ) -> Result<(), ParseProblem> {
        if let Some(first) = self.format {
            return Err(at(format!(
                "the format is declared twice (first on line {first})"
            )));
        }
        if !self.elements.is_empty() {
            return Err(at("the format must come before the elements".into()));
        }
        let &[_, name, version] = w else {
            return Err(at(format!(
                "'{}' is not a format line such as 'format ascii 1.0'",
                shown(trimmed(line))
            )));
        };
        let declared = format!("{} {}", shown(name), shown(version));
        self.encoding = match name {
            b"ascii" => Encoding::Ascii,
            b"binary_little_endian" => Encoding::BinaryLittleEndian,
            b"binary_big_endian" => Encoding::BinaryBigEndian,
            _ => {
                return Err(at(format!(
                    "format '{declared}' is not supported: the encoding must be \
                     ascii, binary_little_endian or binary_big_endian"
                )));
            }
        };
        if version != b"1.0" {
            return Err(at(format!(
                "format '{declared}' is not supported: PLY 1.0 only"
            )));
        }
        self.format = Some(line_no);
        Ok(())
    }

    /// An `element NAME COUNT` line (its words `w`).
    fn element(
        &mut self,
        w: &[&'a [u8]],
        line: &[u8],
        line_no: usize,
        at: At,
    ) -> Result<(), ParseProblem> {
        let &[_, name, count] = w else {
            return Err(at(format!(
                "'{}' is not an element line such as 'element vertex 8'",
                shown(trimmed(line))
            )));
        };
        if self.format.is_none() {
            return Err(at(format!(
                "element '{}' comes before the 'format' line",
                shown(name)
            )));
        }
        if let Some(first) = self.element_lines.insert(name, line_no) {
            return Err(at(format!(
                "element '{}' is declared twice (first on line {first})",
                shown(name)
            )));
        }
        let count = std::str::from_utf8(count)
            .ok()
            .filter(|c| c.bytes().all(|b| b.is_ascii_digit()))
            .ok_or_else(|| {
                at(format!(
                    "element '{}' has count '{}': a count must be a whole number",
                    shown(name),
                    shown(count)
                ))
            })?
            .parse::<u64>()
            .map_err(|_| {
                at(format!(
                    "element '{}' has count '{}', more than any file can hold",
                    shown(name),
                    shown(count)
                ))
            })?;
        self.property_lines.clear();
        self.elements.push(Element {
            name,
            count,
            line: line_no,
            properties: Vec::new(),
        });
        Ok(())
    }

    /// A `property TYPE NAME` or `property list COUNT ITEM NAME` line (its words `w`).
    fn property(
        &mut self,
        w: &[&'a [u8]],
        line: &[u8],
        line_no: usize,
        at: At,
    ) -> Result<(), ParseProblem> {
        let (kind, words, name) = match *w {
            [_, b"list", count, item, name] => {
                let (c, i) = (scalar(count, &at)?, scalar(item, &at)?);
                (Kind::List { count: c, item: i }, [count, item], name)
            }
            [_, t, name] if t != b"list" => (Kind::Scalar(scalar(t, &at)?), [t, t], name),
            _ => {
                return Err(at(format!(
                    "'{}' is not a property line such as 'property float x' or \
                     'property list uchar int vertex_indices'",
                    shown(trimmed(line))
                )));
            }
        };
        let Some(element) = self.elements.last_mut() else {
            return Err(at(format!(
                "property '{}' comes before any element",
                shown(name)
            )));
        };
        if let Some(first) = self.property_lines.insert(name, line_no) {
            return Err(at(format!(
                "property '{}' of element '{}' is declared twice (first on line {first})",
                shown(name),
                shown(element.name)
            )));
        }
        if let Kind::List { count, .. } = kind
            && !count.is_integer()
        {
            return Err(at(format!(
                "the count of list property '{}' of element '{}' has type '{}': a list \
                 count must be of an integer type",
                shown(name),
                shown(element.name),
                shown(words[0])
            )));
        }
        element.properties.push(Property {
            name,
            kind,
            words,
            line: line_no,
        });
        Ok(())
    }
}

/// A type named in a property line.
fn scalar(word: &[u8], at: &impl Fn(String) -> ParseProblem) -> Result<Scalar, ParseProblem> {
    Scalar::from_word(word)
        .ok_or_else(|| at(format!("'{}' is not a PLY type: {TYPE_NAMES}", shown(word))))
}

/// What timbre does with a property.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Role {
    /// Read, checked and dropped.
    Skip,
    /// Coordinate k of a vertex: x, y, z, nx, ny, nz, red, green, blue, s, t.
    Coordinate(usize),
    /// The face's vertex indices.
    Indices,
}

const COORDINATES: [&[u8]; 11] = [
    b"x", b"y", b"z", b"nx", b"ny", b"nz", b"red", b"green", b"blue", b"s", b"t",
];

/// Other names of texture coordinates s and t.
fn texture_alias(name: &[u8]) -> Option<usize> {
    match name {
        b"u" | b"texture_u" => Some(9),
        b"v" | b"texture_v" => Some(10),
        _ => None,
    }
}

/// What the header means for timbre: which element is which, and each property's role.
struct Plan {
    vertex: usize,
    face: usize,
    vertex_count: u64,
    normals: bool,
    colours: bool,
    uvs: bool,
    roles: Vec<Vec<Role>>,
}

fn plan(header: &Header) -> Result<Plan, ParseProblem> {
    let find = |name: &[u8]| header.elements.iter().position(|e| e.name == name);
    let line = |n: usize| n.to_string();
    let mut roles: Vec<Vec<Role>> = header
        .elements
        .iter()
        .map(|e| vec![Role::Skip; e.properties.len()])
        .collect();

    let vertex = find(b"vertex".as_slice())
        .ok_or_else(|| ParseProblem::new("header", "there is no 'vertex' element"))?;
    let v = &header.elements[vertex];
    let mut present = [false; 11];
    for (k, p) in v.properties.iter().enumerate() {
        let Some(c) = COORDINATES
            .iter()
            .position(|&c| c == p.name)
            .or_else(|| texture_alias(p.name))
        else {
            continue;
        };
        if p.is_list() {
            let what = match c {
                0..3 => "a coordinate",
                3..6 => "a normal's component",
                6..9 => "a colour's component",
                _ => "a texture coordinate",
            };
            return Err(ParseProblem::new(
                line(p.line),
                format!(
                    "property '{}' of element 'vertex' is a list; {what} must be a number",
                    shown(p.name)
                ),
            ));
        }
        present[c] = true;
        roles[vertex][k] = Role::Coordinate(c);
    }
    if let Some(c) = (0..3).find(|&c| !present[c]) {
        return Err(ParseProblem::new(
            line(v.line),
            format!(
                "the 'vertex' element has no property '{}'",
                shown(COORDINATES[c])
            ),
        ));
    }
    let normals = present[3..6].iter().all(|&p| p);
    let colours = present[6..9].iter().all(|&p| p);
    let uvs = present[9..].iter().all(|&p| p);
    // Part of a normal, colour or texture coordinate pair is none: those properties are skipped.
    let kept = |c: usize| match c {
        0..3 => true,
        3..6 => normals,
        6..9 => colours,
        _ => uvs,
    };
    for r in &mut roles[vertex] {
        if matches!(r, Role::Coordinate(c) if !kept(*c)) {
            *r = Role::Skip;
        }
    }
    // Indices are u32.
    if v.count > u64::from(u32::MAX) + 1 {
        return Err(ParseProblem::new(
            line(v.line),
            format!(
                "the header declares {}: timbre reads at most 4294967296",
                count_of(v.count, b"vertex")
            ),
        ));
    }

    let face = find(b"face".as_slice())
        .ok_or_else(|| ParseProblem::new("header", "there is no 'face' element"))?;
    let f = &header.elements[face];
    let mut indices: Option<&Property> = None;
    for (k, p) in f.properties.iter().enumerate() {
        if p.name != b"vertex_indices" && p.name != b"vertex_index" {
            continue;
        }
        let at = |message: String| ParseProblem::new(line(p.line), message);
        if let Some(first) = indices {
            return Err(at(format!(
                "the 'face' element has both '{}' (line {}) and '{}': which are the faces?",
                shown(first.name),
                first.line,
                shown(p.name)
            )));
        }
        match p.kind {
            Kind::Scalar(_) => {
                return Err(at(format!(
                    "property '{}' of element 'face' is not a list; it must be a list of \
                     vertex indices ('property list uchar int {}')",
                    shown(p.name),
                    shown(p.name)
                )));
            }
            Kind::List { item, .. } if !item.is_integer() => {
                return Err(at(format!(
                    "property '{}' of element 'face' is a list of '{}'; vertex indices must \
                     be of an integer type",
                    shown(p.name),
                    shown(p.words[1])
                )));
            }
            Kind::List { .. } => {}
        }
        indices = Some(p);
        roles[face][k] = Role::Indices;
    }
    if indices.is_none() {
        return Err(ParseProblem::new(
            line(f.line),
            "the 'face' element has no list property 'vertex_indices'",
        ));
    }
    Ok(Plan {
        vertex,
        face,
        vertex_count: v.count,
        normals,
        colours,
        uvs,
        roles,
    })
}

/// What a PLY file holds.
pub(super) struct Read {
    pub mesh: Mesh,
    pub colours: Option<Vec<DVec3>>,
    pub uvs: Option<Vec<DVec2>>,
}

/// The mesh of a PLY file, its vertex colours (linear RGB in [0, 1]) and texture
/// coordinates, if it has them.
pub(super) fn read(bytes: &[u8]) -> Result<Read, ParseProblem> {
    let header = parse_header(bytes)?;
    let plan = plan(&header)?;
    let body = header.body;
    match header.encoding {
        Encoding::Ascii => read_body(
            Ascii {
                bytes,
                next: body,
                line_no: header.lines,
                line_start: body,
                line_end: body,
                cursor: body,
                token: (body, body),
                values: 0,
            },
            &header,
            &plan,
        ),
        Encoding::BinaryLittleEndian => read_body(
            Binary::<false> {
                bytes,
                pos: body,
                last: body,
            },
            &header,
            &plan,
        ),
        Encoding::BinaryBigEndian => read_body(
            Binary::<true> {
                bytes,
                pos: body,
                last: body,
            },
            &header,
            &plan,
        ),
    }
}

/// Why a value could not be read.
enum Fault {
    /// ASCII: the line has no more values; binary: the file has no more bytes.
    Missing,
    /// ASCII: the word is not a number.
    NotNumber,
    /// ASCII: the word is not an integer, and the type is one.
    NotInteger,
    /// ASCII: the integer is outside the type's range.
    OutOfRange,
}

/// The body of a PLY file, value by value.
trait Source {
    const BINARY: bool;
    /// Starts the next element instance (ASCII: the next line that is not blank); false at the
    /// end of the file.
    fn begin(&mut self) -> bool;
    /// A value of type `t`, as a number.
    fn float(&mut self, t: Scalar) -> Result<f64, Fault>;
    /// A value of integer type `t`.
    fn int(&mut self, t: Scalar) -> Result<i64, Fault>;
    /// Skips (and in ASCII checks) `n` values of type `t`.
    fn skip(&mut self, t: Scalar, n: u64) -> Result<(), Fault>;
    /// Ends an instance: ASCII: `Err(values on the line)` if the line has more values.
    fn end(&mut self) -> Result<(), u64>;
    /// Where the value just read is.
    fn here(&self) -> String;
    /// Where a value was looked for and not found (ASCII: the line).
    fn line(&self) -> String;
    /// ASCII: the word just read.
    fn token(&self) -> Option<&[u8]>;
    /// ASCII: how many values the current line had up to where reading stopped.
    fn values(&self) -> u64;
    /// Where the file ends (for "the file ends after …").
    fn at_end(&self) -> String;
    /// Bytes left.
    fn remaining(&self) -> usize;
    /// Where data after the last element starts, if there is any.
    fn trailing(&mut self) -> Option<String>;
}

struct Ascii<'a> {
    bytes: &'a [u8],
    /// Where the next line starts.
    next: usize,
    /// The current line's number (1-based, counting from the file's first line).
    line_no: usize,
    line_start: usize,
    line_end: usize,
    cursor: usize,
    token: (usize, usize),
    values: u64,
}

impl Ascii<'_> {
    fn next_line(&mut self) -> bool {
        if self.next >= self.bytes.len() {
            return false;
        }
        let start = self.next;
        let end = self.bytes[start..]
            .iter()
            .position(|&b| b == b'\n')
            .map_or(self.bytes.len(), |k| start + k);
        self.line_no += 1;
        self.line_start = start;
        self.line_end = end;
        self.cursor = start;
        self.token = (start, start);
        self.next = end + 1;
        self.values = 0;
        true
    }

    fn next_token(&mut self) -> Option<&[u8]> {
        let line = &self.bytes[..self.line_end];
        let mut i = self.cursor;
        while i < line.len() && is_blank(line[i]) {
            i += 1;
        }
        if i == line.len() {
            self.cursor = i;
            return None;
        }
        let start = i;
        while i < line.len() && !is_blank(line[i]) {
            i += 1;
        }
        self.cursor = i;
        self.token = (start, i);
        self.values += 1;
        Some(&line[start..i])
    }

    /// The next word as an integer of type `t`.
    fn integer(&mut self, t: Scalar) -> Result<i64, Fault> {
        let word = self.next_token().ok_or(Fault::Missing)?;
        let text = std::str::from_utf8(word).map_err(|_| Fault::NotInteger)?;
        let value = match text.parse::<i64>() {
            Ok(v) => v,
            Err(_) => {
                let digits = text.strip_prefix(['-', '+']).unwrap_or(text);
                return Err(
                    if !digits.is_empty() && digits.bytes().all(|b| b.is_ascii_digit()) {
                        Fault::OutOfRange
                    } else if text.parse::<f64>().is_ok() {
                        Fault::NotInteger
                    } else {
                        Fault::NotNumber
                    },
                );
            }
        };
        let (low, high) = t.range();
        if value < low || value > high {
            return Err(Fault::OutOfRange);
        }
        Ok(value)
    }
}

impl Source for Ascii<'_> {
    const BINARY: bool = false;

    fn begin(&mut self) -> bool {
        while self.next_line() {
            if self.bytes[self.line_start..self.line_end]
                .iter()
                .any(|&b| !is_blank(b))
            {
                return true;
            }
        }
        false
    }

    fn float(&mut self, t: Scalar) -> Result<f64, Fault> {
        if t.is_integer() {
            return self.integer(t).map(|v| v as f64);
        }
        let word = self.next_token().ok_or(Fault::Missing)?;
        let text = std::str::from_utf8(word).map_err(|_| Fault::NotNumber)?;
        let value = match t {
            Scalar::F32 => text.parse::<f32>().map(f64::from),
            _ => text.parse::<f64>(),
        };
        value.map_err(|_| Fault::NotNumber)
    }

    fn int(&mut self, t: Scalar) -> Result<i64, Fault> {
        self.integer(t)
    }

    fn skip(&mut self, t: Scalar, n: u64) -> Result<(), Fault> {
        for _ in 0..n {
            self.float(t)?;
        }
        Ok(())
    }

    fn end(&mut self) -> Result<(), u64> {
        if self.next_token().is_none() {
            return Ok(());
        }
        let token = self.token;
        while self.next_token().is_some() {}
        let values = self.values;
        self.token = token;
        Err(values)
    }

    fn here(&self) -> String {
        let column = self.token.0 - self.line_start + 1;
        format!("{}:{column}", self.line_no)
    }

    fn line(&self) -> String {
        self.line_no.to_string()
    }

    fn token(&self) -> Option<&[u8]> {
        Some(&self.bytes[self.token.0..self.token.1])
    }

    fn values(&self) -> u64 {
        self.values
    }

    fn at_end(&self) -> String {
        (self.line_no + 1).to_string()
    }

    fn remaining(&self) -> usize {
        self.bytes.len().saturating_sub(self.next)
    }

    fn trailing(&mut self) -> Option<String> {
        while self.next_line() {
            if let Some(k) = self.bytes[self.line_start..self.line_end]
                .iter()
                .position(|&b| !is_blank(b))
            {
                return Some(format!("{}:{}", self.line_no, k + 1));
            }
        }
        None
    }
}

/// A binary body; `BIG`: big endian.
struct Binary<'a, const BIG: bool> {
    bytes: &'a [u8],
    pos: usize,
    /// Where the value just read starts.
    last: usize,
}

impl<const BIG: bool> Binary<'_, BIG> {
    fn take<const N: usize>(&mut self) -> Result<[u8; N], Fault> {
        let bytes = self
            .bytes
            .get(self.pos..self.pos + N)
            .and_then(|b| <[u8; N]>::try_from(b).ok())
            .ok_or(Fault::Missing)?;
        self.last = self.pos;
        self.pos += N;
        Ok(bytes)
    }
}

macro_rules! number {
    ($self:ident, $t:ty) => {{
        let b = $self.take::<{ size_of::<$t>() }>()?;
        if BIG {
            <$t>::from_be_bytes(b)
        } else {
            <$t>::from_le_bytes(b)
        }
    }};
}

impl<const BIG: bool> Source for Binary<'_, BIG> {
    const BINARY: bool = true;

    fn begin(&mut self) -> bool {
        self.pos < self.bytes.len()
    }

    fn float(&mut self, t: Scalar) -> Result<f64, Fault> {
        Ok(match t {
            Scalar::I8 => number!(self, i8).into(),
            Scalar::U8 => number!(self, u8).into(),
            Scalar::I16 => number!(self, i16).into(),
            Scalar::U16 => number!(self, u16).into(),
            Scalar::I32 => number!(self, i32).into(),
            Scalar::U32 => number!(self, u32).into(),
            Scalar::F32 => number!(self, f32).into(),
            Scalar::F64 => number!(self, f64),
        })
    }

    fn int(&mut self, t: Scalar) -> Result<i64, Fault> {
        Ok(match t {
            Scalar::I8 => number!(self, i8).into(),
            Scalar::U8 => number!(self, u8).into(),
            Scalar::I16 => number!(self, i16).into(),
            Scalar::U16 => number!(self, u16).into(),
            Scalar::I32 => number!(self, i32).into(),
            Scalar::U32 => number!(self, u32).into(),
            // The header allows only integer types for list counts and indices.
            Scalar::F32 | Scalar::F64 => return Err(Fault::NotInteger),
        })
    }

    fn skip(&mut self, t: Scalar, n: u64) -> Result<(), Fault> {
        let end = usize::try_from(n)
            .ok()
            .and_then(|n| n.checked_mul(t.size()))
            .and_then(|len| self.pos.checked_add(len))
            .filter(|&end| end <= self.bytes.len())
            .ok_or(Fault::Missing)?;
        self.last = self.pos;
        self.pos = end;
        Ok(())
    }

    fn end(&mut self) -> Result<(), u64> {
        Ok(())
    }

    fn here(&self) -> String {
        format!("byte {}", self.last)
    }

    fn line(&self) -> String {
        self.at_end()
    }

    fn token(&self) -> Option<&[u8]> {
        None
    }

    fn values(&self) -> u64 {
        0
    }

    fn at_end(&self) -> String {
        format!("byte {}", self.bytes.len())
    }

    fn remaining(&self) -> usize {
        self.bytes.len() - self.pos
    }

    fn trailing(&mut self) -> Option<String> {
        (self.pos < self.bytes.len()).then(|| format!("byte {}", self.pos))
    }
}

/// The least number of bytes an instance of `element` takes: to believe a count only as far as
/// the data goes.
fn least_bytes<S: Source>(element: &Element) -> usize {
    if !S::BINARY {
        // A digit and a blank or newline per value.
        return 2 * element.properties.len();
    }
    element
        .properties
        .iter()
        .map(|p| match p.kind {
            Kind::Scalar(t) | Kind::List { count: t, .. } => t.size(),
        })
        .sum()
}

/// One instance being read, for messages.
struct Instance<'h> {
    element: &'h Element<'h>,
    index: u64,
    /// Values the header declares for it so far (one per property, plus the list counts read).
    declared: u64,
}

impl Instance<'_> {
    fn name(&self) -> String {
        format!("{} {}", shown(self.element.name), self.index)
    }

    /// "has 4 values, the header declares 3" (with lists: "the header and its list count
    /// declare").
    fn has_values(&self, values: u64, at_least: bool) -> String {
        let lists = self
            .element
            .properties
            .iter()
            .filter(|p| p.is_list())
            .count();
        let who = match lists {
            0 => "the header declares",
            1 => "the header and its list count declare",
            _ => "the header and its list counts declare",
        };
        format!(
            "{} has {}, {who} {}{}",
            self.name(),
            values_count(values),
            if at_least { "at least " } else { "" },
            self.declared
        )
    }

    /// A value that could not be read as property `p` (of type word `word`, `t`).
    fn fault<S: Source>(
        &self,
        src: &S,
        fault: Fault,
        p: usize,
        word: &[u8],
        t: Scalar,
    ) -> ParseProblem {
        let property = &self.element.properties[p];
        let token = || shown(src.token().unwrap_or_default());
        let message = match fault {
            Fault::Missing if S::BINARY => {
                return ParseProblem::new(
                    src.at_end(),
                    format!(
                        "the file ends inside {} (the header declares {})",
                        self.name(),
                        count_of(self.element.count, self.element.name)
                    ),
                );
            }
            Fault::Missing => {
                let more = self.element.properties[p + 1..].iter().any(|q| q.is_list());
                return ParseProblem::new(src.line(), self.has_values(src.values(), more));
            }
            Fault::NotNumber => format!(
                "{}: '{}' is not a number (property '{}' is {})",
                self.name(),
                token(),
                shown(property.name),
                shown(word)
            ),
            Fault::NotInteger => format!(
                "{}: '{}' is not an integer (property '{}' is {})",
                self.name(),
                token(),
                shown(property.name),
                shown(word)
            ),
            Fault::OutOfRange => {
                let (low, high) = t.range();
                format!(
                    "{}: {} is out of range for property '{}' ({}: {low} to {high})",
                    self.name(),
                    token(),
                    shown(property.name),
                    shown(word)
                )
            }
        };
        ParseProblem::new(src.here(), message)
    }

    fn at<S: Source>(&self, src: &S, message: impl std::fmt::Display) -> ParseProblem {
        ParseProblem::new(src.here(), format!("{}: {message}", self.name()))
    }
}

fn read_body<S: Source>(mut src: S, header: &Header, plan: &Plan) -> Result<Read, ParseProblem> {
    let mut vertices: Vec<DVec3> = Vec::new();
    let mut uvs: Vec<DVec2> = Vec::new();
    let mut normals: Vec<DVec3> = Vec::new();
    let mut colours: Vec<DVec3> = Vec::new();
    let mut triangles: Vec<[u32; 3]> = Vec::new();
    let vertex_count = plan.vertex_count;

    for (e, element) in header.elements.iter().enumerate() {
        if element.properties.is_empty() {
            // Nothing to read (not even a line in ASCII, where blank lines are skipped).
            continue;
        }
        let roles = &plan.roles[e];
        let room = (src.remaining() / least_bytes::<S>(element).max(1)) as u64;
        let capacity = element.count.min(room) as usize;
        if e == plan.vertex {
            vertices.reserve_exact(capacity);
            if plan.normals {
                normals.reserve_exact(capacity);
            }
            if plan.colours {
                colours.reserve_exact(capacity);
            }
            if plan.uvs {
                uvs.reserve_exact(capacity);
            }
        } else if e == plan.face {
            triangles.reserve(capacity);
        }
        for index in 0..element.count {
            if !src.begin() {
                return Err(ParseProblem::new(
                    src.at_end(),
                    format!(
                        "the file ends after {index} of the {} the header declares",
                        count_of(element.count, element.name)
                    ),
                ));
            }
            let mut instance = Instance {
                element,
                index,
                declared: element.properties.len() as u64,
            };
            let mut values = [0.0f64; 11];
            let mut short_face = None;
            for (p, (property, &role)) in element.properties.iter().zip(roles).enumerate() {
                match (property.kind, role) {
                    (Kind::Scalar(t), Role::Coordinate(c)) => {
                        let v = src
                            .float(t)
                            .map_err(|f| instance.fault(&src, f, p, property.words[0], t))?;
                        // A NaN or infinite normal is allowed: the mesh is then shaded flat.
                        if !v.is_finite() && c < 3 {
                            return Err(instance.at(
                                &src,
                                format_args!(
                                    "{} is {}",
                                    shown(property.name),
                                    not_finite(v, src.token(), t.with_article())
                                ),
                            ));
                        }
                        // A colour: an integer type's values over its largest.
                        let v = if (6..9).contains(&c) && t.is_integer() {
                            v / t.range().1 as f64
                        } else {
                            v
                        };
                        if (6..9).contains(&c) && !(0.0..=1.0).contains(&v) {
                            return Err(instance.at(
                                &src,
                                format_args!(
                                    "{} is {v}: a colour's component must be in [0, 1] (an \
                                     integer type's 0 to its largest)",
                                    shown(property.name)
                                ),
                            ));
                        }
                        values[c] = v;
                    }
                    (Kind::Scalar(t), _) => src
                        .skip(t, 1)
                        .map_err(|f| instance.fault(&src, f, p, property.words[0], t))?,
                    (Kind::List { .. }, role) => {
                        let faces = (role == Role::Indices).then_some(&mut triangles);
                        let read =
                            read_list(&mut src, &mut instance, p, property, vertex_count, faces);
                        short_face = short_face.or(read?);
                    }
                }
            }
            if let Err(values) = src.end() {
                return Err(ParseProblem::new(
                    src.here(),
                    instance.has_values(values, false),
                ));
            }
            if let Some(problem) = short_face {
                return Err(problem);
            }
            if e == plan.vertex {
                vertices.push(DVec3::new(values[0], values[1], values[2]));
                if plan.normals {
                    normals.push(DVec3::new(values[3], values[4], values[5]));
                }
                if plan.colours {
                    colours.push(DVec3::new(values[6], values[7], values[8]));
                }
                if plan.uvs {
                    uvs.push(DVec2::new(values[9], values[10]));
                }
            }
        }
    }
    if let Some(at) = src.trailing() {
        let counts: Vec<String> = header
            .elements
            .iter()
            .map(|e| count_of(e.count, e.name))
            .collect();
        let counts = match counts.split_last() {
            Some((last, rest)) if !rest.is_empty() => format!("{} and {last}", rest.join(", ")),
            _ => counts.join(""),
        };
        return Err(ParseProblem::new(
            at,
            format!("the body has data after the {counts} the header declares"),
        ));
    }
    let normals = (plan.normals && normals.iter().all(|n| n.is_finite())).then_some(normals);
    let mesh = Mesh {
        name: String::new(),
        vertices,
        triangles,
        normals,
    };
    Ok(Read {
        mesh,
        colours: plan.colours.then_some(colours),
        uvs: plan.uvs.then_some(uvs),
    })
}

/// Reads list property `p` of `instance` (a property of kind `Kind::List`): into `faces` as a
/// fan of triangles when it is a face's vertex indices (each checked against `vertex_count`),
/// or checked and skipped. A face of fewer than 3 vertices is returned, to be reported once the
/// instance is read whole.
fn read_list<S: Source>(
    src: &mut S,
    instance: &mut Instance,
    p: usize,
    property: &Property,
    vertex_count: u64,
    faces: Option<&mut Vec<[u32; 3]>>,
) -> Result<Option<ParseProblem>, ParseProblem> {
    let Kind::List { count, item } = property.kind else {
        unreachable!("a list property");
    };
    let n = src
        .int(count)
        .map_err(|f| instance.fault(src, f, p, property.words[0], count))?;
    let Ok(n) = u64::try_from(n) else {
        return Err(instance.at(
            src,
            format_args!("list '{}' has a negative count ({n})", shown(property.name)),
        ));
    };
    instance.declared += n;
    let word = property.words[1];
    let triangles = match faces {
        Some(triangles) if n >= 3 => triangles,
        faces => {
            let short = faces.is_some().then(|| {
                instance.at(
                    src,
                    format_args!("a face needs at least 3 vertices, got {n}"),
                )
            });
            src.skip(item, n)
                .map_err(|f| instance.fault(src, f, p, word, item))?;
            return Ok(short);
        }
    };
    let mut vertex = || -> Result<u32, ParseProblem> {
        let k = src
            .int(item)
            .map_err(|f| instance.fault(src, f, p, word, item))?;
        if k < 0 || k as u64 >= vertex_count {
            return Err(instance.at(
                src,
                format_args!(
                    "vertex index {k} is out of range (the file has {vertex_count} vertices)"
                ),
            ));
        }
        Ok(k as u32)
    };
    let first = vertex()?;
    let mut previous = vertex()?;
    for _ in 2..n {
        let next = vertex()?;
        triangles.push([first, previous, next]);
        previous = next;
    }
    Ok(None)
}

pub(super) fn write(
    out: &mut impl Write,
    mesh: &Mesh,
    encoding: PlyEncoding,
    precision: Precision,
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
    let scalar = match precision {
        Precision::F32 => "float",
        Precision::F64 => "double",
    };
    for p in ["x", "y", "z"] {
        writeln!(out, "property {scalar} {p}")?;
    }
    if mesh.normals.is_some() {
        for p in ["nx", "ny", "nz"] {
            writeln!(out, "property {scalar} {p}")?;
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
        for (k, x) in values.into_iter().enumerate() {
            match (encoding, precision) {
                (PlyEncoding::Ascii, _) => {
                    let space = if k == 0 { "" } else { " " };
                    match precision {
                        Precision::F32 => write!(out, "{space}{}", x as f32)?,
                        Precision::F64 => write!(out, "{space}{x}")?,
                    }
                }
                (PlyEncoding::BinaryLittleEndian, Precision::F32) => {
                    out.write_all(&(x as f32).to_le_bytes())?
                }
                (PlyEncoding::BinaryLittleEndian, Precision::F64) => {
                    out.write_all(&x.to_le_bytes())?
                }
                (PlyEncoding::BinaryBigEndian, Precision::F32) => {
                    out.write_all(&(x as f32).to_be_bytes())?
                }
                (PlyEncoding::BinaryBigEndian, Precision::F64) => {
                    out.write_all(&x.to_be_bytes())?
                }
            }
        }
        if encoding == PlyEncoding::Ascii {
            writeln!(out)?;
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
