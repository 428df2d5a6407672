//! Text from files made safe to show on a terminal: characters that could drive it or hide
//! what follows are written as escapes instead.

/// Characters that print as nothing or reorder what follows: zero-width spaces and joiners,
/// direction marks and overrides, line and paragraph separators, the byte order mark.
pub fn is_invisible(c: char) -> bool {
    matches!(
        c,
        '\u{200b}'..='\u{200f}' | '\u{2028}'..='\u{202e}' | '\u{2060}'..='\u{206f}' | '\u{feff}'
    )
}

/// How `c` is shown if it must not reach a terminal as it is: a control character as `\x1b`, an
/// invisible one as `\u{202e}`; `None` for every other character.
pub fn escape(c: char) -> Option<String> {
    if c.is_control() {
        // Control characters (Unicode's Cc) are all below U+0100.
        Some(format!("\\x{:02x}", c as u32))
    } else if is_invisible(c) {
        Some(format!("\\u{{{:x}}}", c as u32))
    } else {
        None
    }
}

/// Longest run of characters without a space that is printed whole.
pub const LONGEST_WORD: usize = 200;

/// `text` made safe to print on a terminal as one line, whatever a file put in it: control
/// characters (line breaks too: a name cannot start a line that looks like timbre's own) and
/// invisible or reordering marks are escaped
/// ([`escape`]), so a name or token cannot drive the terminal; a run of more than
/// [`LONGEST_WORD`] characters without a space (a 10 MB key, a 309-digit number) is cut in the
/// middle, saying how much was left out.
pub fn printable(text: &str) -> String {
    let mut out = String::with_capacity(text.len().min(1 << 16));
    let mut word = String::new();
    let flush = |word: &mut String, out: &mut String| {
        let n = word.chars().count();
        if n > LONGEST_WORD {
            let head: String = word.chars().take(LONGEST_WORD - 40).collect();
            let tail: String = word.chars().skip(n - 20).collect();
            let left_out = n - LONGEST_WORD + 20;
            out.push_str(&format!("{head}…[{left_out} characters left out]…{tail}"));
        } else {
            out.push_str(word);
        }
        word.clear();
    };
    for c in text.chars() {
        match c {
            ' ' => {
                flush(&mut word, &mut out);
                out.push(c);
            }
            c => match escape(c) {
                Some(e) => word.push_str(&e),
                None => word.push(c),
            },
        }
    }
    flush(&mut word, &mut out);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn controls_and_invisible_marks_are_escaped_and_nothing_else() {
        assert_eq!(escape('\x1b').as_deref(), Some("\\x1b"));
        assert_eq!(escape('\u{9b}').as_deref(), Some("\\x9b"));
        assert_eq!(escape('\u{202e}').as_deref(), Some("\\u{202e}"));
        assert_eq!(escape('\u{feff}').as_deref(), Some("\\u{feff}"));
        for c in ['a', 'é', '∅', '球', ' ', '\\'] {
            assert_eq!(escape(c), None, "{c}");
        }
    }
}
