//! The move limit of the readers: how many motion statements a program may make before reading
//! stops with [`PathErrorKind::Limit`].
//!
//! A program that loops forever with moves in the loop, or a generated program far longer than
//! any machine runs, would otherwise grow the consumer's move list until memory runs out (a
//! [`Move`](crate::Move) takes about 300 bytes: ten million moves are 3 GB). The readers count
//! the motion events they hand to the sink ([`Canon::Traverse`], [`Canon::Feed`],
//! [`Canon::Arc`], [`Canon::ArcAxis`], [`Canon::Spline`]) and stop at the first one over the
//! limit, naming its file and line. Consumers that do not keep the moves (a streamed summary, the
//! canonical print) may lift the limit (`u64::MAX`).

use std::collections::HashSet;

use crate::{Canon, CanonSink, PathError, PathErrorKind, SourcePos, Warning};

/// Most distinct warnings a reader passes on (a warning repeated at the same place with the same
/// words is passed on once: a loop that warns at every iteration would otherwise fill memory);
/// the rest are counted and said in one last warning.
pub const MAX_WARNINGS: usize = 10_000;

/// Default of [`GcodeOptions::max_moves`](crate::gcode::GcodeOptions::max_moves) and
/// [`AptOptions::max_moves`](crate::apt::AptOptions::max_moves): four million motion
/// statements, about 1.3 GB of [`Move`](crate::Move)s — far more than a real program makes, far
/// less than a machine's memory.
pub const DEFAULT_MAX_MOVES: u64 = 4_000_000;

/// A sink in front of the reader's sink that counts motion events and drops every event from
/// the first one over the limit on (the reader then stops with [`move_limit_error`]), and
/// passes each distinct warning on once, at most [`MAX_WARNINGS`] of them.
pub(crate) struct MoveLimit<'s> {
    inner: &'s mut dyn CanonSink,
    moves: u64,
    max: u64,
    /// A motion event over the limit was met (and dropped).
    pub(crate) over: bool,
    /// The warnings passed on.
    warned: HashSet<Warning>,
    /// Distinct warnings beyond [`MAX_WARNINGS`], and the file of the last one.
    unreported: u64,
    last_file: String,
}

impl<'s> MoveLimit<'s> {
    pub(crate) fn new(inner: &'s mut dyn CanonSink, max: u64) -> Self {
        Self {
            inner,
            moves: 0,
            max,
            over: false,
            warned: HashSet::new(),
            unreported: 0,
            last_file: String::new(),
        }
    }

    /// Says how many warnings were not passed on, if any (at the end of reading).
    pub(crate) fn finish(&mut self) {
        if self.unreported > 0 {
            let message = format!(
                "{} more distinct warnings are not reported (the reader reports at most \
                 {MAX_WARNINGS})",
                self.unreported
            );
            self.inner.warn(Warning {
                file: std::mem::take(&mut self.last_file),
                line: 0,
                column: 0,
                message,
            });
            self.unreported = 0;
        }
    }

    /// The limit in force.
    pub(crate) fn max(&self) -> u64 {
        self.max
    }

    /// The motion events passed on so far.
    pub(crate) fn moves(&self) -> u64 {
        self.moves
    }
}

impl CanonSink for MoveLimit<'_> {
    #[inline]
    fn emit(&mut self, line: u32, event: &Canon<'_>) {
        if self.over {
            return;
        }
        if matches!(
            event,
            Canon::Traverse { .. }
                | Canon::Feed { .. }
                | Canon::Arc { .. }
                | Canon::ArcAxis { .. }
                | Canon::Spline { .. }
        ) {
            if self.moves >= self.max {
                self.over = true;
                return;
            }
            self.moves += 1;
        }
        self.inner.emit(line, event);
    }

    fn warn(&mut self, warning: Warning) {
        if self.over || self.warned.contains(&warning) {
            return;
        }
        if self.warned.len() >= MAX_WARNINGS {
            self.unreported += 1;
            self.last_file.clone_from(&warning.file);
            return;
        }
        self.warned.insert(warning.clone());
        self.inner.warn(warning);
    }

    fn position(&self) -> Option<crate::Axes> {
        self.inner.position()
    }
}

/// What the reader says when the move limit `max` is reached.
pub(crate) fn move_limit_message(max: u64) -> (String, String) {
    (
        format!(
            "more than {max} moves: the program may never end, or it is longer than the reader's \
             move limit, which bounds the memory the moves take (raise the limit for a program \
             this long)"
        ),
        move_limit_expected(max),
    )
}

/// The `expected` part of the move-limit error for limit `max`: "at most N moves".
pub fn move_limit_expected(max: u64) -> String {
    format!("at most {max} moves")
}

/// True when `e` is the readers' move-limit error for limit `max`.
pub fn is_move_limit(e: &PathError, max: u64) -> bool {
    e.kind == PathErrorKind::Limit && e.expected == move_limit_expected(max)
}

/// The move-limit error at `pos`, `found` being the statement's text.
pub(crate) fn move_limit_error(pos: SourcePos, found: &str, max: u64) -> PathError {
    let (message, expected) = move_limit_message(max);
    PathError::new(pos, PathErrorKind::Limit, message, found.trim(), expected)
}
