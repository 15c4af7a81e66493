//! The sink the program-reader fuzz targets share: every position the reader emits must be a
//! number (infinite values can only come from overflowing arithmetic on huge inputs, which is
//! allowed; NaN would mean an unchecked domain error), and the events go on to the move
//! builder (arcs, splines, frames, tilted planes, tool vectors).

use swarf_path::{Canon, CanonSink, MoveBuilder, Warning};

pub struct Check(pub MoveBuilder);

impl CanonSink for Check {
    fn emit(&mut self, line: u32, event: &Canon<'_>) {
        if let Canon::Traverse { end } | Canon::Feed { end } | Canon::Arc { end, .. } = event {
            assert!(
                !end.to_array().iter().any(|v| v.is_nan()),
                "NaN position {event:?}"
            );
        }
        self.0.emit(line, event);
    }
    fn warn(&mut self, _warning: Warning) {}
}
