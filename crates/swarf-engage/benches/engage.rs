//! Engagement benchmark (work in progress).
fn main() {}
