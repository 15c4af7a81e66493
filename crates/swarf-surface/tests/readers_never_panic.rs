//! Property tests: random bytes, and random corruptions of real files, never panic a reader;
//! they parse or return an error.

mod common;
use common::data;

use proptest::prelude::*;
use swarf_surface::io::{iges, json, step};

/// The third-party data file `rel`'s text, read once; `None` (the skip printed once) without it.
fn real(rel: &'static str) -> Option<&'static str> {
    static FILES: std::sync::Mutex<Vec<(&str, Option<&str>)>> = std::sync::Mutex::new(Vec::new());
    let mut files = FILES.lock().unwrap();
    if let Some((_, text)) = files.iter().find(|(r, _)| *r == rel) {
        return *text;
    }
    let text = data(rel).map(|p| &*std::fs::read_to_string(p).unwrap().leak());
    files.push((rel, text));
    text
}

/// `text` with `n` bytes overwritten at positions drawn from `picks`, kept valid UTF-8.
fn corrupt(text: &str, picks: &[(usize, u8)]) -> String {
    let mut b = text.as_bytes().to_vec();
    for &(at, byte) in picks {
        let i = at % b.len();
        b[i] = byte;
    }
    String::from_utf8_lossy(&b).into_owned()
}

fn all_readers(text: &str) {
    let _ = json::parse(text);
    let _ = step::parse(text);
    let _ = iges::parse_document(text);
}

proptest! {
    #![proptest_config(swarf_testdata::proptest_config(256))]

    #[test]
    fn random_bytes(bytes in proptest::collection::vec(any::<u8>(), 0..2000)) {
        all_readers(&String::from_utf8_lossy(&bytes));
    }

    #[test]
    fn random_printable_text(s in "[ -~\n]{0,1500}") {
        all_readers(&s);
    }

    #[test]
    fn corrupted_step(picks in proptest::collection::vec((any::<usize>(), prop_oneof![Just(b'('), Just(b')'), Just(b','), Just(b'#'), Just(b'\''), Just(b';'), Just(b'9'), Just(b'-'), Just(b'.'), any::<u8>()]), 1..6)) {
        let _ = step::parse(&corrupt(&swarf_testdata::fixtures::sphere_step(5.0), &picks));
        if let Some(text) = real("step/occt_bug28366_fuselage.stp") {
            let _ = step::parse(&corrupt(text, &picks));
        }
    }

    #[test]
    fn corrupted_iges(picks in proptest::collection::vec((any::<usize>(), prop_oneof![Just(b','), Just(b';'), Just(b'9'), Just(b'H'), Just(b' '), Just(b'-'), Just(b'D'), any::<u8>()]), 1..6)) {
        let Some(text) = real("iges/occt_bug29356.igs") else {
            return Ok(());
        };
        let _ = iges::parse_document(&corrupt(text, &picks));
    }

    #[test]
    fn corrupted_json(picks in proptest::collection::vec((any::<usize>(), prop_oneof![Just(b'['), Just(b']'), Just(b','), Just(b'0'), Just(b'-'), Just(b'"'), any::<u8>()]), 1..4)) {
        let text = r#"{"units": "mm", "patches": [{"name": "floor", "degree_u": 2, "degree_v": 1,
  "knots_u": [0, 0, 0, 1, 1, 1], "knots_v": [0, 0, 1, 1],
  "control_points": [[[0, 0, 0, 1], [0, 10, 0, 1]], [[5, 0, 3, 0.5], [5, 10, 3, 0.5]], [[10, 0, 0, 1], [10, 10, 0, 1]]]}]}"#;
        if let Ok(s) = json::parse(&corrupt(text, &picks)) {
            // Whatever parses evaluates to finite points.
            for cc in s.grid(5) {
                prop_assert!(s.local(&cc, &swarf_surface::Tolerances::DEFAULT).point().is_finite());
            }
        }
    }
}
