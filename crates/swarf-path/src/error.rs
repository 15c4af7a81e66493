//! Source positions, errors and warnings of the program readers.

use std::fmt;

/// A place in a source file: the file name, 1-based line and 1-based column (in characters).
#[derive(Clone, Debug, PartialEq, Eq, Default)]
pub struct SourcePos {
    /// File name as the user gave it (or `<input>` for text not read from a file).
    pub file: String,
    /// 1-based line number (0 when the whole file is meant: it could not be read).
    pub line: u32,
    /// 1-based column number (0 when the whole line is meant).
    pub column: u32,
}

impl fmt::Display for SourcePos {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        // Line 0: the file as a whole (it could not be read).
        match (self.line, self.column) {
            (0, _) => write!(f, "{}", self.file),
            (line, 0) => write!(f, "{}:{line}", self.file),
            (line, column) => write!(f, "{}:{line}:{column}", self.file),
        }
    }
}

/// What went wrong, so callers can react to classes of errors without parsing messages.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PathErrorKind {
    /// The text could not be read as the language (bad word, bad number, unbalanced brackets…).
    Syntax,
    /// A well-formed statement that is wrong in context (missing axis word, arc radius mismatch…).
    Semantic,
    /// A feature swarf recognises but deliberately does not simulate (cutter compensation,
    /// another controller's dialect).
    Unsupported,
    /// A hard limit was reached (loop iterations, call depth, repeat count): the program would
    /// not end, or not in reasonable time.
    Limit,
    /// The file could not be read.
    Io,
}

/// A reader error: where, what was found, what was expected.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub struct PathError {
    /// Where the error is.
    pub pos: SourcePos,
    /// Its class.
    pub kind: PathErrorKind,
    /// What is wrong, in a machinist's words.
    pub message: String,
    /// The text found at the position (may be empty at end of line).
    pub found: String,
    /// What would have been accepted there (may be empty when nothing sensible can be said).
    pub expected: String,
}

impl PathError {
    /// Builds an error.
    pub fn new(
        pos: SourcePos,
        kind: PathErrorKind,
        message: impl Into<String>,
        found: impl Into<String>,
        expected: impl Into<String>,
    ) -> Self {
        Self {
            pos,
            kind,
            message: message.into(),
            found: found.into(),
            expected: expected.into(),
        }
    }
}

/// The found text as a terminal shows it: control characters (a NUL in a binary file, an escape
/// code) written as escapes, so that the message neither loses them nor drives the terminal;
/// beyond [`FOUND_SHOWN`] characters (a word of 5000 digits, a line of a binary file) the rest
/// is counted, not shown.
struct Visible<'a>(&'a str);

/// Most characters of the found text a message shows.
const FOUND_SHOWN: usize = 120;

impl fmt::Display for Visible<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let total = self.0.chars().count();
        if total > FOUND_SHOWN {
            let head: String = self.0.chars().take(FOUND_SHOWN).collect();
            Visible(&head).fmt(f)?;
            return write!(f, "… ({} more characters)", total - FOUND_SHOWN);
        }
        for c in self.0.chars() {
            if c.is_control() && c != '\t' {
                write!(f, "{}", c.escape_unicode())?;
            } else {
                write!(f, "{c}")?;
            }
        }
        Ok(())
    }
}

impl fmt::Display for PathError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.pos, self.message)?;
        let found = Visible(&self.found);
        match (self.found.is_empty(), self.expected.is_empty()) {
            (false, false) => write!(f, " (found `{found}`, expected {})", self.expected),
            (false, true) => write!(f, " (found `{found}`)"),
            (true, false) => write!(f, " (found end of line, expected {})", self.expected),
            (true, true) => Ok(()),
        }
    }
}

/// Something harmless the reader did not act on (an unsupported word, a coolant code…),
/// reported rather than silently dropped.
#[derive(Clone, Debug, PartialEq, Eq, Hash, serde::Serialize)]
pub struct Warning {
    /// Where it is.
    pub file: String,
    /// 1-based line.
    pub line: u32,
    /// 1-based column (0 for the whole line).
    pub column: u32,
    /// What was ignored and why.
    pub message: String,
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let at = SourcePos {
            file: self.file.clone(),
            line: self.line,
            column: self.column,
        };
        write!(f, "{at}: warning: {}", self.message)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn control_characters_found_are_written_as_escapes() {
        let pos = SourcePos {
            file: "garbage.ngc".into(),
            line: 1,
            column: 1,
        };
        let e = PathError::new(
            pos,
            PathErrorKind::Syntax,
            "unexpected character",
            "\u{0}",
            "a G-code word",
        );
        assert_eq!(
            e.to_string(),
            "garbage.ngc:1:1: unexpected character (found `\\u{0}`, expected a G-code word)"
        );
        let e = PathError {
            found: "X°\u{1b}[2J".into(),
            expected: String::new(),
            ..e
        };
        assert!(e.to_string().ends_with("(found `X°\\u{1b}[2J`)"), "{e}");
    }

    #[test]
    fn a_position_names_what_it_has() {
        let at = |line, column| {
            SourcePos {
                file: "a.ngc".into(),
                line,
                column,
            }
            .to_string()
        };
        assert_eq!(at(0, 0), "a.ngc");
        assert_eq!(at(3, 0), "a.ngc:3");
        assert_eq!(at(3, 7), "a.ngc:3:7");
        let w = |line, column| {
            Warning {
                file: "a.ngc".into(),
                line,
                column,
                message: "m".into(),
            }
            .to_string()
        };
        assert_eq!(w(0, 0), "a.ngc: warning: m");
        assert_eq!(w(4, 0), "a.ngc:4: warning: m");
        assert_eq!(w(4, 2), "a.ngc:4:2: warning: m");
    }
}
