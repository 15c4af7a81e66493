//! The feed rewrite of `swarf schedule` on arbitrary text: never panics, and with every factor 1
//! and no splits it returns the text unchanged or an error.
#![no_main]

use std::collections::BTreeMap;

use libfuzzer_sys::fuzz_target;
use swarf_path::load::ProgramFormat;
use swarf_path::rewrite::{rewrite_feeds, SplitPiece};

fuzz_target!(|data: &[u8]| {
    let Some((&head, rest)) = data.split_first() else {
        return;
    };
    let text = String::from_utf8_lossy(rest);
    let format = match head % 4 {
        0 => ProgramFormat::Gcode,
        3 => ProgramFormat::Sinumerik,
        1 => ProgramFormat::Apt,
        _ => ProgramFormat::Heidenhain,
    };
    let lines = text.lines().count() as u32 + 1;
    let every: BTreeMap<u32, f64> = (1..=lines).map(|l| (l, 1.0)).collect();
    if let Ok(r) = rewrite_feeds(&text, "fuzz", format, &every, &BTreeMap::new()) {
        // Lines whose feed is already in effect keep their bytes; only restoring words appear.
        assert!(r.text.len() >= text.len());
    }
    let factors: BTreeMap<u32, f64> = (1..=lines)
        .map(|l| (l, 0.5 + f64::from(head) / 64.0))
        .collect();
    let splits: BTreeMap<u32, Vec<SplitPiece>> = [(
        u32::from(head % 8) + 1,
        vec![SplitPiece {
            delta: [1.0, -0.0, f64::from(head)],
            factor: 0.5,
        }],
    )]
    .into_iter()
    .collect();
    let _ = rewrite_feeds(&text, "fuzz", format, &factors, &splits);
});
