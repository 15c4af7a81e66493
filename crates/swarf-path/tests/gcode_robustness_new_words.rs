//! Random programs made of the words issue 12 added (cutter compensation, Fanuc blocks, G68/G51
//! frames, G10 R, G52, tapping and boring cycles, splines, computed and file calls) in random
//! order with random numbers: the reader ends with events or an error — never a panic, a hang
//! or a NaN — in both dialects, and the move builder takes whatever it emits. (The cargo-fuzz
//! target `gcode` explores the same words from arbitrary bytes.)

use proptest::prelude::*;
use swarf_path::gcode::{read_gcode, GcodeDialect, GcodeOptions};
use swarf_path::{Machine, MoveBuilder};

const WORDS: &[&str] = &[
    "G41 D#",
    "G42 D#",
    "G41.1 D#",
    "G42.1 D#",
    "G40",
    "G17",
    "G18",
    "G19",
    "G90",
    "G91",
    "G20",
    "G21",
    "G0 X# Y#",
    "G1 X# Y# Z# F#",
    "G2 X# Y# I# J#",
    "G3 X# Y# R#",
    "X# Y#",
    "G5 X# Y# I# J# P# Q#",
    "G5 X# Y# P# Q#",
    "G5.1 X# Y# I# J#",
    "G5.2 X# Y# P# L#",
    "X# Y# P#",
    "G5.3",
    "G68 X# Y# R#",
    "G69",
    "G51 X# Y# P#",
    "G51 I# J# K#",
    "G50",
    "G10 L2 P1 X# Y# R#",
    "G10 L20 P2 X#",
    "G55",
    "G54",
    "G52 X# Y#",
    "G92 X#",
    "G92.1",
    "G53 G0 X#",
    "G28",
    "G91 G28 Z0",
    "G28.1",
    "G81 X# Y# Z# R#",
    "G84 X# Y# Z# R# P#",
    "G74 X# Z# R#",
    "G86 X# Z# R#",
    "G87 X# Y# Z# R# I# J# K#",
    "G88 X# Z# R# P#",
    "G80",
    "G80 G0 X#",
    "G80 G1 Z#",
    "M98 P#",
    "M98 P30010",
    "M99",
    "O10",
    "O#",
    "o[#] call [#]",
    "o<nofile> call",
    "N# /G0 X#",
    "/N# G1 X#",
    "T# M6",
    "M3 S#",
    "(debug,#5420 #<_value>)",
    "G43 Z# H#",
    "@# ^#",
    "G81 @# ^# Z# R#",
];

fn program() -> impl Strategy<Value = String> {
    prop::collection::vec(
        (0..WORDS.len(), prop::collection::vec(-50.0f64..50.0, 8)),
        1..40,
    )
    .prop_map(|lines| {
        let mut out = String::from("F100\n");
        for (w, nums) in lines {
            let mut it = nums.into_iter();
            let line: String = WORDS[w]
                .split('#')
                .enumerate()
                .map(|(i, part)| {
                    if i == 0 {
                        part.to_string()
                    } else {
                        format!("{:.3}{part}", it.next().unwrap_or(1.0))
                    }
                })
                .collect();
            out.push_str(&line);
            out.push('\n');
        }
        out.push_str("M2\n");
        out
    })
}

proptest! {
    #![proptest_config(swarf_testdata::proptest_config(512))]

    #[test]
    fn new_words_never_panic(src in program(), fanuc in any::<bool>(), tools in any::<bool>()) {
        let mut opts = GcodeOptions::default()
            .with_max_loop_iterations(20_000)
            .with_max_repeat(1_000)
            .with_dialect(if fanuc { GcodeDialect::Fanuc } else { GcodeDialect::LinuxCnc });
        if tools {
            for t in 0..60 {
                opts = opts.with_tool_diameter(t, f64::from(t) * 0.5);
            }
        }
        let mut b = MoveBuilder::new(Machine::three_axis(), "r.ngc");
        let _ = read_gcode(&src, "r.ngc", &opts, &mut b);
        for m in &b.finish().moves {
            prop_assert!(!m.end.tip.is_nan(), "NaN in {src}");
        }
    }
}
