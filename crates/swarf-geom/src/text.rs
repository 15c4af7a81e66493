//! Positions in text, for the readers' error messages (file, line, column).

/// 1-based line and column (in characters) of byte offset `byte` in `text`; an offset past the
/// end or inside a multi-byte character counts from the character it falls in.
///
/// ```
/// use swarf_geom::text::line_col;
/// assert_eq!(line_col("ab\nçd", 5), (2, 2));
/// assert_eq!(line_col("ab\nçd", 4), (2, 1)); // inside `ç`
/// assert_eq!(line_col("ab", 99), (1, 3));
/// ```
pub fn line_col(text: &str, byte: usize) -> (usize, usize) {
    let mut b = byte.min(text.len());
    while !text.is_char_boundary(b) {
        b -= 1;
    }
    let before = &text[..b];
    let line = before.matches('\n').count() + 1;
    let col = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, col)
}
