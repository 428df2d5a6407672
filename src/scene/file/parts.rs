//! Large scene files are parsed in parts. The toml crate keeps a whole document's tokens and
//! tree in memory at once (about 40 bytes for each byte of text), so a file of a million objects
//! would need gigabytes; it is cut instead before `[[name]]` headers into parts of about
//! [`PART_BYTES`], each parsed on its own, and the parts' tables are joined in order.
//!
//! A cut never changes what the file means: it is made only before a header that starts a new
//! element of an array of tables, and a later header that reaches back into a table opened in an
//! earlier part (`[render]` twice, `[object.transform]` after a cut) joins the parts between
//! them again, so that TOML itself judges such files. A file whose outline is anything but plain
//! (quoted keys in headers, an unterminated string or bracket) is parsed whole.
//!
//! The outline also counts `[[object]]` headers, so that a file with too many objects is refused
//! before anything is parsed.

use std::cell::Cell;
use std::collections::HashMap;
use std::ops::Range;

use serde::de::DeserializeOwned;
use serde::{Deserialize, Deserializer};

/// The size of text from which a file is parsed in parts, and about the size of each part.
pub(super) const PART_BYTES: usize = 1 << 20;

/// Largest part that is parsed (the toml crate needs up to 75 bytes for each byte of a dense
/// array): a longer stretch without a header to cut at, or a file whose outline is unclear, is
/// refused.
pub(super) const MAX_PART_BYTES: usize = 16 << 20;

thread_local! {
    /// Where in its file the part being parsed starts.
    static PART_START: Cell<usize> = const { Cell::new(0) };
}

/// Deserialises `text[range]`, so that every [`Spanned`] it makes and the span of its error are
/// offsets in the whole `text` (an error without a span is put at the part's start).
pub(super) fn in_part<T: DeserializeOwned>(
    text: &str,
    range: Range<usize>,
) -> Result<T, (Range<usize>, toml::de::Error)> {
    let start = range.start;
    let before = PART_START.replace(start);
    let result = toml::from_str(&text[range]);
    PART_START.set(before);
    result.map_err(|e| {
        let at = e
            .span()
            .map_or(start..start, |s| s.start + start..s.end + start);
        (at, e)
    })
}

/// A value and its byte range in the scene file (not only in the part that held it).
#[derive(Debug)]
pub(super) struct Spanned<T>(toml::Spanned<T>);

impl<T> Spanned<T> {
    pub(super) fn span(&self) -> Range<usize> {
        self.0.span()
    }

    pub(super) fn get_ref(&self) -> &T {
        self.0.get_ref()
    }

    pub(super) fn into_inner(self) -> T {
        self.0.into_inner()
    }
}

impl<'de, T: Deserialize<'de>> Deserialize<'de> for Spanned<T> {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let value = toml::Spanned::<T>::deserialize(d)?;
        let start = PART_START.get();
        let span = value.span();
        Ok(Spanned(toml::Spanned::new(
            span.start + start..span.end + start,
            value.into_inner(),
        )))
    }
}

/// How a file is cut, and where its first `[[object]]` header past `max_objects` is.
#[derive(Debug, PartialEq)]
pub(super) struct Outline {
    pub parts: Vec<Range<usize>>,
    pub excess_object: Option<usize>,
}

/// The outline of `text`; one part where the text is short or its outline unclear.
pub(super) fn outline(text: &str, max_objects: usize) -> Outline {
    cut(text, PART_BYTES, max_objects)
}

/// [`outline`] with parts of about `part_bytes`.
fn cut(text: &str, part_bytes: usize, max_objects: usize) -> Outline {
    let whole = |excess_object| Outline {
        parts: std::iter::once(0..text.len()).collect(),
        excess_object,
    };
    if text.len() < part_bytes {
        return whole(None);
    }
    let Some(lines) = scan(text.as_bytes()) else {
        return whole(None);
    };
    let mut starts = vec![0];
    // Where each top-level key was last opened or reached, and whether it is an array of tables.
    let mut opened: HashMap<&str, (usize, bool)> = HashMap::new();
    let mut objects = 0;
    let mut excess_object = None;
    for line in lines {
        let (at, key, array) = match line {
            Line::Key { at, first } => {
                opened.insert(first, (at, false));
                continue;
            }
            Line::Header { at, key, array } => (at, key, array),
        };
        let mut names = key.split('.');
        let first = names.next().unwrap_or_default();
        let new_element = array && !key.contains('.');
        if array && names.next_back().unwrap_or(first) == "object" {
            objects += 1;
            if objects > max_objects && excess_object.is_none() {
                excess_object = Some(at);
            }
        }
        let previous = opened.get(first).copied();
        match previous {
            // A new element of an array of tables: the place to cut.
            Some((_, true)) | None if new_element => {
                let part_start = starts[starts.len() - 1];
                if at - part_start >= part_bytes {
                    starts.push(at);
                }
            }
            // Reaching back into a table opened in an earlier part: join the parts between.
            Some((was, _)) => {
                let part = starts.partition_point(|&s| s <= was);
                starts.truncate(part);
            }
            None => {}
        }
        // `[[a.b]]` makes `a` a table, unless it is an array of tables already.
        let is_array = match previous {
            Some((_, was_array)) if key.contains('.') => was_array,
            _ => new_element,
        };
        opened.insert(first, (at, is_array));
    }
    let mut ends: Vec<usize> = starts.iter().skip(1).copied().collect();
    ends.push(text.len());
    Outline {
        parts: starts.into_iter().zip(ends).map(|(s, e)| s..e).collect(),
        excess_object,
    }
}

/// A line of a TOML file's outline: a table header or a key at the start of a line.
#[derive(Debug, PartialEq)]
enum Line<'a> {
    /// `[key]` or `[[key]]` (with `array`) at byte `at`; `key` is bare keys joined by dots.
    Header {
        at: usize,
        key: &'a str,
        array: bool,
    },
    /// A key-value pair at byte `at`, whose key starts with `first`.
    Key { at: usize, first: &'a str },
}

/// The outline of a TOML text (the keys before the first header, then the headers), or `None`
/// where it is not plain: quoted keys, spaces inside a header's key, or an unterminated string
/// or bracket.
fn scan(text: &[u8]) -> Option<Vec<Line<'_>>> {
    let bare = |c: u8| c.is_ascii_alphanumeric() || c == b'_' || c == b'-';
    let bare_run = |from: usize| from + text[from..].iter().take_while(|&&c| bare(c)).count();
    // Text is UTF-8 and every delimiter is ASCII, so these byte ranges are `str` boundaries.
    let as_str = |r: Range<usize>| std::str::from_utf8(&text[r]).ok();
    let mut lines = Vec::new();
    let mut keys = Vec::new();
    let mut depth = 0usize;
    // A byte-order mark before the first line is not part of it.
    let mut i = if text.starts_with("\u{feff}".as_bytes()) {
        3
    } else {
        0
    };
    let mut line_start = true;
    while i < text.len() {
        if line_start {
            line_start = false;
            i += text[i..]
                .iter()
                .take_while(|&&c| c == b' ' || c == b'\t')
                .count();
            if depth == 0 && i < text.len() && text[i] == b'[' {
                let array = text.get(i + 1) == Some(&b'[');
                let from = i + 1 + usize::from(array);
                let mut end = from;
                loop {
                    let run = bare_run(end);
                    if run == end {
                        return None;
                    }
                    end = run;
                    if text.get(end) != Some(&b'.') {
                        break;
                    }
                    end += 1;
                }
                let close: &[u8] = if array { b"]]" } else { b"]" };
                if !text[end..].starts_with(close) {
                    return None;
                }
                lines.push(Line::Header {
                    at: i,
                    key: as_str(from..end)?,
                    array,
                });
                i = end + close.len();
                continue;
            }
            if depth == 0 && i < text.len() && matches!(text[i], b'"' | b'\'') {
                return None;
            }
            // Keys before the first header are the top level's own.
            if depth == 0 && lines.is_empty() && i < text.len() && bare(text[i]) {
                keys.push(Line::Key {
                    at: i,
                    first: as_str(i..bare_run(i))?,
                });
            }
            continue;
        }
        match text[i] {
            b'\n' => line_start = true,
            b'#' => {
                i += text[i..].iter().take_while(|&&c| c != b'\n').count();
                continue;
            }
            quote @ (b'"' | b'\'') => {
                i = string_end(text, i, quote)?;
                continue;
            }
            b'[' | b'{' => depth += 1,
            b']' | b'}' => depth = depth.checked_sub(1)?,
            _ => {}
        }
        i += 1;
    }
    keys.extend(lines);
    (depth == 0).then_some(keys)
}

/// The byte after the string that starts with `quote` at `start` (basic strings `"` have
/// backslash escapes, literal strings `'` none; three quotes start a multi-line string).
fn string_end(text: &[u8], start: usize, quote: u8) -> Option<usize> {
    let escapes = quote == b'"';
    let multi = text[start..].starts_with(&[quote; 3]);
    let mut i = start + if multi { 3 } else { 1 };
    while i < text.len() {
        match text[i] {
            b'\\' if escapes => i += 1,
            b'\n' if !multi => return None,
            c if c == quote && !multi => return Some(i + 1),
            c if c == quote && text[i..].starts_with(&[quote; 3]) => {
                // Up to two quotes may stand just before the closing three.
                let run = text[i..].iter().take_while(|&&c| c == quote).count();
                return (run <= 5).then_some(i + run);
            }
            _ => {}
        }
        i += 1;
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    fn headers(text: &str) -> Vec<(String, bool)> {
        scan(text.as_bytes())
            .unwrap()
            .into_iter()
            .filter_map(|l| match l {
                Line::Header { key, array, .. } => Some((key.to_string(), array)),
                Line::Key { .. } => None,
            })
            .collect()
    }

    #[test]
    fn headers_are_found_outside_strings_arrays_and_comments() {
        let text = "a = \"\"\"\n[[not]]\n\"\"\"\nb = '''\n[x]'''\nc = [\n[1],\n]\n# [y]\n\
                    d = \"[z]\\\"\" # ]\n  [[object]]\n[group.transform]\n";
        assert_eq!(
            headers(text),
            [("object".into(), true), ("group.transform".into(), false)]
        );
    }

    #[test]
    fn unclear_outlines_are_not_scanned() {
        for text in [
            "a = \"open\n",
            "a = [1\n",
            "[\"quoted\"]\n",
            "a = ]\n",
            "[a . b]\n",
        ] {
            assert_eq!(scan(text.as_bytes()), None, "{text:?}");
        }
    }

    /// `n` objects of about 100 bytes, after `head`, then `tail`.
    fn objects(head: &str, n: usize, tail: &str) -> String {
        let object = "[[object]]\nshape = { type = \"sphere\", centre = [0, 0, 5], radius = 1 }\n\
                      surface = { type = \"mirror\" }\n";
        format!("{head}{}{tail}", object.repeat(n))
    }

    #[test]
    fn large_files_are_cut_before_array_elements_into_parts_of_about_a_mebibyte() {
        let text = objects("studio = \"empty\"\n[render]\nwidth = 10\n", 30_000, "");
        let outline = outline(&text, usize::MAX);
        assert!(outline.parts.len() >= 2, "{}", outline.parts.len());
        assert_eq!(outline.parts[0].start, 0);
        assert_eq!(outline.parts.last().unwrap().end, text.len());
        for pair in outline.parts.windows(2) {
            assert_eq!(pair[0].end, pair[1].start);
            assert!(text[pair[1].clone()].starts_with("[[object]]\n"));
            assert!(pair[0].len() >= PART_BYTES && pair[0].len() < PART_BYTES + 200);
        }
    }

    #[test]
    fn a_header_reaching_back_joins_the_parts() {
        // `[render]` twice (TOML refuses it), and a subtable of the last object after a
        // mebibyte of lights: each must be parsed in one part with the header it reaches back to.
        let lights = "[[light]]\ntype = \"ambient\"\ncolour = [0, 0, 0]\n".repeat(30_000);
        for (tail, reached, parts) in [
            ("[render]\nwidth = 5\n".to_string(), "[render]", 1),
            (format!("{lights}[object.transform]\n"), "[[object]]", 2),
        ] {
            let text = objects("[render]\nwidth = 10\n", 30_000, &tail);
            let outline = outline(&text, usize::MAX);
            assert!(outline.parts.len() >= parts, "{reached}");
            let reaching = text.len() - tail.len() + tail.rfind('[').unwrap();
            let reached = text[..reaching].rfind(reached).unwrap();
            let part = |at: usize| outline.parts.iter().position(|p| p.contains(&at));
            assert_eq!(part(reaching), part(reached), "{tail:.20}");
        }
    }

    /// Pieces of TOML that a cut could get wrong: arrays of tables and their subtables,
    /// headers inside strings, arrays and comments, tables given twice or reached back into.
    const PIECES: [&str; 14] = [
        "\u{feff}[render]\nwidth = 4\n",
        "[[group.object]]\nname = \"n\"\n",
        "[[light]]\r\nname = 'crlf'\r\n[light.x]\r\ny = 1\r\n",
        "[[object]]\nname = \"a\"\n",
        "[[group]]\nname = \"g\"\n[[group.object]]\nname = \"m\"\n",
        "[render]\nwidth = 3\n",
        "[object.transform]\nscale = 2\n",
        "[[light]]\nx = \"\"\"\n[[object]]\n\"\"\"\n",
        "[[light]]\ny = [\n[1],\n]\n",
        "# [[object]]\n",
        "[camera]\nz = '[[x]]'\n",
        "[[include]]\nfile = 'f'\n",
        "[[object]]\n[object.shape]\nr = 1\n",
        "[object]\nname = \"b\"\n",
    ];

    /// The parts' tables joined as `File::append` joins them (arrays of tables extended), or
    /// `None` where a part is not TOML or two parts have the same key otherwise.
    fn joined(text: &str, parts: &[Range<usize>]) -> Option<toml::Table> {
        let mut all = toml::Table::new();
        for part in parts {
            for (key, value) in text[part.clone()].parse::<toml::Table>().ok()? {
                match (all.get_mut(&key), value) {
                    (Some(toml::Value::Array(a)), toml::Value::Array(more)) => a.extend(more),
                    (Some(_), _) => return None,
                    (None, value) => {
                        all.insert(key, value);
                    }
                }
            }
        }
        Some(all)
    }

    proptest::proptest! {
        #[test]
        fn parsing_the_parts_and_joining_them_is_parsing_the_whole(
            top in proptest::bool::ANY,
            pieces in proptest::collection::vec(0..PIECES.len(), 1..24),
            part_bytes in 1usize..120,
        ) {
            let mut text = if top { "studio = \"none\"\n".to_string() } else { String::new() };
            for p in pieces {
                text += PIECES[p];
            }
            let outline = cut(&text, part_bytes, usize::MAX);
            let whole = text.parse::<toml::Table>().ok();
            proptest::prop_assert_eq!(joined(&text, &outline.parts), whole, "{}", text);
        }
    }

    #[test]
    fn the_first_object_past_the_limit_is_located_without_parsing() {
        let text = objects("", 20_000, "");
        let outline = outline(&text, 10_000);
        let at = outline.excess_object.unwrap();
        assert_eq!(text[..at].matches("[[object]]").count(), 10_000);
        assert!(text[at..].starts_with("[[object]]"));
    }
}
