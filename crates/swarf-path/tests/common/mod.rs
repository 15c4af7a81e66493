//! Helpers shared by the reader tests.
#![allow(dead_code)]

use swarf_path::apt::{read_apt, AptOptions};
use swarf_path::canon::Recorder;
use swarf_path::{Canon, PathError};

/// The events of an APT program that reads.
pub(crate) fn apt_events(text: &str) -> Vec<Canon<'static>> {
    let mut rec = Recorder::default();
    read_apt(text, "t.apt", &AptOptions::default(), &mut rec).unwrap();
    rec.events.into_iter().map(|(_, e)| e).collect()
}

/// The error of an APT program that does not.
pub(crate) fn apt_err(text: &str) -> PathError {
    let mut rec = Recorder::default();
    read_apt(text, "t.apt", &AptOptions::default(), &mut rec).unwrap_err()
}
