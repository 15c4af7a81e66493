//! Where the reading is and what the control stack holds: the reading cursor, the O-word
//! keywords, open loops and subroutine frames. The interpreter ([`super::interp`]) keeps them;
//! the O-word control flow ([`super::control`]) moves them.

use super::params::N_ARGS;

/// A place in the text between lines: `pos` is the start of the next line to read, `line` the
/// number of the line before it (so the next line read is `line + 1`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Cursor {
    pub(crate) pos: usize,
    pub(crate) line: u32,
    /// Index of the file (0: the program; then subroutine files as they are loaded).
    pub(crate) file: u32,
}

impl Cursor {
    /// The lines of `text` (the cursor's file) from here on: each line's text with the cursor
    /// before it and the one after it (the forward scans of O-words, line numbers and Macro B
    /// share this walk).
    pub(crate) fn lines(self, text: &str) -> impl Iterator<Item = (&str, Cursor, Cursor)> {
        let mut at = self;
        std::iter::from_fn(move || {
            if at.pos >= text.len() {
                return None;
            }
            let (raw, next) = super::lexer::split_line(text, at.pos);
            let before = at;
            at = Cursor {
                pos: next,
                line: at.line + 1,
                file: at.file,
            };
            Some((raw, before, at))
        })
    }
}

/// A remembered forward scan: the O name looked for and what was found.
pub(crate) type ScanHit = (Vec<u8>, Option<(Kw, Cursor, Cursor)>);

/// The keyword after an O name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Kw {
    Sub,
    Endsub,
    Call,
    Do,
    While,
    Endwhile,
    If,
    Elseif,
    Else,
    Endif,
    Break,
    Continue,
    Repeat,
    Endrepeat,
    Return,
    /// A bare `O1234`: a Fanuc program number or subprogram label.
    Label,
}

/// Loop kinds on the control stack.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum LoopKind {
    While,
    Do,
    Repeat,
}

impl LoopKind {
    /// The keyword that closes the loop.
    pub(crate) fn end(self) -> Kw {
        match self {
            LoopKind::While => Kw::Endwhile,
            LoopKind::Do => Kw::While,
            LoopKind::Repeat => Kw::Endrepeat,
        }
    }
}

/// An open loop.
#[derive(Clone, Debug)]
pub(crate) struct Ctl {
    pub(crate) kind: LoopKind,
    pub(crate) name: Vec<u8>,
    /// Before the head line (a `while` re-evaluates its condition there).
    pub(crate) head: Cursor,
    /// After the head line (where `do` and `repeat` bodies start).
    pub(crate) body: Cursor,
    /// Repeats left (`repeat`).
    pub(crate) remaining: u64,
}

/// A subroutine call in progress.
#[derive(Clone, Debug)]
pub(crate) struct Frame {
    /// Where the caller continues.
    pub(crate) ret: Cursor,
    /// The caller's `#1`–`#30` (O-word calls only).
    pub(crate) saved: [f64; N_ARGS],
    /// Height of the loop stack at the call.
    pub(crate) ctl_len: usize,
    /// For `M98`: the subprogram's start and the calls left.
    pub(crate) fanuc: Option<(Cursor, u64)>,
}
