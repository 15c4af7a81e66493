//! Line normalisation: what LinuxCNC does before parsing a block — comments out, spaces out,
//! letters to lower case — into buffers reused from line to line, so the common path allocates
//! nothing.
//!
//! The normalised code keeps, for each of its bytes, the byte offset it came from in the raw
//! line, so errors can point at the column the user wrote.

use super::{Fault, Res, Span};

/// One line, normalised. The vectors are cleared and refilled for every line; their capacity
/// stays, so reading allocates only when a line is longer than any before it.
#[derive(Default, Debug)]
pub(crate) struct LineBuf {
    /// Code without comments and whitespace, ASCII lower case.
    pub(crate) code: Vec<u8>,
    /// For each byte of `code`, its byte offset in the raw line.
    pub(crate) offs: Vec<u32>,
    /// Parenthesised comments: byte ranges of their text (without the parentheses) in the raw
    /// line.
    pub(crate) comments: Vec<(u32, u32)>,
    /// The line starts with `/` (block delete).
    pub(crate) deleted: bool,
}

impl LineBuf {
    /// The raw byte range `[start, end)` covered by code indices `[a, b)`.
    pub(crate) fn raw_range(&self, a: usize, b: usize, raw_len: usize) -> (usize, usize) {
        if self.offs.is_empty() {
            return (raw_len, raw_len);
        }
        let a = a.min(self.offs.len());
        let start = if a < self.offs.len() {
            self.offs[a] as usize
        } else {
            raw_len
        };
        let end = if b > a {
            self.offs[(b - 1).min(self.offs.len() - 1)] as usize + 1
        } else {
            start
        };
        (start, end.max(start))
    }
}

/// Splits `text` at `pos` into the line there (without its `\n`, `\r\n` or lone `\r`, the line
/// end of old Mac editors) and the position of the next line.
pub(crate) fn split_line(text: &str, pos: usize) -> (&str, usize) {
    let rest = &text.as_bytes()[pos..];
    let (len, next) = match memchr_nl(rest) {
        Some(i) => (i, pos + i + 1),
        None => (rest.len(), text.len()),
    };
    let mut line = &text[pos..pos + len];
    if let Some(stripped) = line.strip_suffix('\r') {
        line = stripped;
    }
    (line, next)
}

/// The lines of `text` as [`split_line`] splits them.
pub(crate) fn lines(text: &str) -> impl Iterator<Item = &str> {
    let mut pos = 0;
    std::iter::from_fn(move || {
        (pos < text.len()).then(|| {
            let (line, next) = split_line(text, pos);
            pos = next;
            line
        })
    })
}

/// Where the first line of `b` ends: its `\n` (the `\n` of a `\r\n`), or a `\r` not followed
/// by `\n`.
pub(crate) fn memchr_nl(b: &[u8]) -> Option<usize> {
    b.iter()
        .enumerate()
        .position(|(i, &c)| c == b'\n' || (c == b'\r' && b.get(i + 1) != Some(&b'\n')))
}

/// Normalises `raw` into `lb`.
///
/// # Errors
/// An unclosed or nested comment, or a character that cannot start or continue a word.
pub(crate) fn normalize(raw: &str, lb: &mut LineBuf) -> Res<()> {
    lb.code.clear();
    lb.offs.clear();
    lb.comments.clear();
    lb.deleted = false;
    let b = raw.as_bytes();
    let mut i = 0;
    // Block delete: a `/` before any code.
    while i < b.len() && (b[i] == b' ' || b[i] == b'\t') {
        i += 1;
    }
    if i < b.len() && b[i] == b'/' {
        lb.deleted = true;
        i += 1;
    }
    // Fanuc and many posts also write the slash after the sequence number: `N20 /G0 X5`.
    let slash_after_n = {
        let mut j = i;
        if matches!(b.get(j), Some(b'n' | b'N')) {
            j += 1;
            while matches!(b.get(j), Some(b'0'..=b'9' | b'.')) {
                j += 1;
            }
            while matches!(b.get(j), Some(b' ' | b'\t')) {
                j += 1;
            }
        }
        (j > i && b.get(j) == Some(&b'/')).then_some(j)
    };
    while i < b.len() {
        if Some(i) == slash_after_n {
            lb.deleted = true;
            i += 1;
            continue;
        }
        let c = b[i];
        match c {
            b'(' => {
                let mut j = i + 1;
                loop {
                    match b.get(j) {
                        None => {
                            return Err(Fault::syntax(
                                Span::Raw(i, b.len()),
                                "comment is not closed",
                                "`)` before the end of the line",
                            ))
                        }
                        Some(b')') => break,
                        Some(b'(') => {
                            return Err(Fault::syntax(
                                Span::Raw(j, j + 1),
                                "nested comment",
                                "`)` closing the comment opened before",
                            ))
                        }
                        _ => j += 1,
                    }
                }
                lb.comments.push((i as u32 + 1, j as u32));
                i = j + 1;
            }
            b';' => break,
            // (0x1a: the Ctrl-Z DOS tools and DNC senders put at the end of a file.)
            b' ' | b'\t' | b'\r' | 0x1a => i += 1,
            0x21..=0x7e => {
                lb.code.push(c.to_ascii_lowercase());
                lb.offs.push(i as u32);
                i += 1;
            }
            _ => {
                let mut j = i + 1;
                while j < b.len() && !raw.is_char_boundary(j) {
                    j += 1;
                }
                return Err(Fault::syntax(
                    Span::Raw(i, j),
                    "unexpected character",
                    "a G-code word",
                ));
            }
        }
    }
    Ok(())
}

/// The 1-based column (in characters) of byte offset `byte` in `raw`.
pub(crate) fn column_of(raw: &str, byte: usize) -> u32 {
    let byte = byte.min(raw.len());
    let mut b = byte;
    while b > 0 && !raw.is_char_boundary(b) {
        b -= 1;
    }
    raw[..b].chars().count() as u32 + 1
}

/// Index of the first code byte after an optional `N123` line number.
pub(crate) fn skip_line_number(code: &[u8]) -> usize {
    if code.first() != Some(&b'n') {
        return 0;
    }
    let mut i = 1;
    while matches!(code.get(i), Some(b'0'..=b'9' | b'.')) {
        i += 1;
    }
    i
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strips_spaces_comments_and_case() {
        let mut lb = LineBuf::default();
        normalize("  G 1 x1 . 5 (Hello) Y2 ; tail", &mut lb).unwrap();
        assert_eq!(lb.code, b"g1x1.5y2");
        assert_eq!(lb.comments, vec![(14, 19)]);
        assert_eq!(lb.offs[0], 2);
        assert!(!lb.deleted);
    }

    #[test]
    fn block_delete_and_errors() {
        let mut lb = LineBuf::default();
        normalize(" /G1 X1", &mut lb).unwrap();
        assert!(lb.deleted);
        let e = normalize("G1 (open", &mut lb).unwrap_err();
        assert_eq!(e.span, Span::Raw(3, 8));
        let e = normalize("G1 (a (b))", &mut lb).unwrap_err();
        assert_eq!(e.span, Span::Raw(6, 7));
        let e = normalize("G1 X°", &mut lb).unwrap_err();
        assert_eq!(e.span, Span::Raw(4, 6));
        assert_eq!(column_of("G1 X°1", 6), 6);
    }

    #[test]
    fn splits_lines() {
        let t = "a\r\nb\nc";
        assert_eq!(split_line(t, 0), ("a", 3));
        assert_eq!(split_line(t, 3), ("b", 5));
        assert_eq!(split_line(t, 5), ("c", 6));
        let t = "a\rb\r\r\nc";
        assert_eq!(split_line(t, 0), ("a", 2));
        assert_eq!(split_line(t, 2), ("b", 4));
        assert_eq!(split_line(t, 4), ("", 6));
        assert_eq!(split_line(t, 6), ("c", 7));
    }
}
