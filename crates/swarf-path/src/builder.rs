//! Turns canonical events into the move stream.
