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

use crate::{Canon, CanonSink, PathError, PathErrorKind, SourcePos, Warning};

/// Default of [`GcodeOptions::max_moves`](crate::gcode::GcodeOptions::max_moves) and
/// [`AptOptions::max_moves`](crate::apt::AptOptions::max_moves): four million motion
/// statements, about 1.3 GB of [`Move`](crate::Move)s — far more than a real program makes, far
/// less than a machine's memory.
pub const DEFAULT_MAX_MOVES: u64 = 4_000_000;

/// A sink in front of the reader's sink that counts motion events and drops every event from
/// the first one over the limit on (the reader then stops with [`move_limit_error`]).
pub(crate) struct MoveLimit<'s> {
    inner: &'s mut dyn CanonSink,
    moves: u64,
    max: u64,
    /// A motion event over the limit was met (and dropped).
    pub(crate) over: bool,
}

impl<'s> MoveLimit<'s> {
    pub(crate) fn new(inner: &'s mut dyn CanonSink, max: u64) -> Self {
        Self {
            inner,
            moves: 0,
            max,
            over: false,
        }
    }

    /// The limit in force.
    pub(crate) fn max(&self) -> u64 {
        self.max
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
        if !self.over {
            self.inner.warn(warning);
        }
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
