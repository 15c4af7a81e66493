//! The readers' move limit (a program that loops forever with moves, or one far longer than
//! memory allows, stops with a `Limit` error at the line of the first move over the limit) and
//! the streamed summary (memory independent of the program's length, same numbers as the
//! summary of the program read whole).

use proptest::prelude::*;
use swarf_path::apt::{read_apt, AptOptions};
use swarf_path::gcode::{read_gcode, GcodeOptions};
use swarf_path::limit::{is_move_limit, DEFAULT_MAX_MOVES};
use swarf_path::load::{read_program_str, stream_program, ReadOptions};
use swarf_path::summary::{summarize, SummaryOptions, SummarySink};
use swarf_path::{Canon, CanonSink, Machine, PathErrorKind, Warning};

/// Counts motion events, keeps the warnings.
#[derive(Default)]
struct Count {
    moves: u64,
    warnings: Vec<Warning>,
}

impl CanonSink for Count {
    fn emit(&mut self, _line: u32, event: &Canon<'_>) {
        if matches!(
            event,
            Canon::Traverse { .. } | Canon::Feed { .. } | Canon::Arc { .. } | Canon::Spline { .. }
        ) {
            self.moves += 1;
        }
    }
    fn warn(&mut self, w: Warning) {
        self.warnings.push(w);
    }
}

const ENDLESS: &str = "G21 G90\nG0 X0 Y0 Z5\nG1 Z-1 F600\no100 while [1]\nG1 X10\nG1 X0\n\
                       o100 endwhile\nM30\n";

#[test]
fn endless_loop_with_moves_stops_at_the_move_limit_naming_its_line() {
    let options = GcodeOptions::default().with_max_moves(1000);
    let mut count = Count::default();
    let e = read_gcode(ENDLESS, "endless.ngc", &options, &mut count).unwrap_err();
    assert_eq!(e.kind, PathErrorKind::Limit, "{e}");
    assert!(is_move_limit(&e, 1000), "{e}");
    // Moves 1 and 2 before the loop, then X10/X0 pairs: move 1001 is a `G1 X10` on line 5.
    assert_eq!((e.pos.file.as_str(), e.pos.line), ("endless.ngc", 5), "{e}");
    assert_eq!(e.found, "G1 X10");
    assert!(e.to_string().contains("more than 1000 moves"), "{e}");
    assert_eq!(count.moves, 1000, "nothing past the limit reaches the sink");
}

#[test]
fn the_default_move_limit_stops_an_endless_loop_before_the_iteration_limit() {
    let options = GcodeOptions::default();
    assert_eq!(options.max_moves, DEFAULT_MAX_MOVES);
    assert!(DEFAULT_MAX_MOVES < options.max_loop_iterations);
    let mut count = Count::default();
    let e = read_gcode(ENDLESS, "endless.ngc", &options, &mut count).unwrap_err();
    assert!(is_move_limit(&e, DEFAULT_MAX_MOVES), "{e}");
    assert_eq!(count.moves, DEFAULT_MAX_MOVES);
}

#[test]
fn a_lifted_limit_leaves_the_iteration_limit_to_end_the_loop() {
    let options = GcodeOptions::default()
        .with_max_moves(u64::MAX)
        .with_max_loop_iterations(5000);
    let e = read_gcode(ENDLESS, "endless.ngc", &options, &mut Count::default()).unwrap_err();
    assert_eq!(e.kind, PathErrorKind::Limit);
    assert!(e.message.contains("loop iterations"), "{e}");
}

#[test]
fn a_program_within_the_limit_reads_whole() {
    let text = "G0 X0 Y0 Z5\nG1 Z-1 F100\nG1 X10\nG2 X20 I5\nM30\n";
    let options = GcodeOptions::default().with_max_moves(4);
    let mut count = Count::default();
    read_gcode(text, "a.ngc", &options, &mut count).unwrap();
    assert_eq!(count.moves, 4);
    let options = GcodeOptions::default().with_max_moves(3);
    let e = read_gcode(text, "a.ngc", &options, &mut Count::default()).unwrap_err();
    assert_eq!(e.pos.line, 4, "{e}");
}

#[test]
fn apt_stops_at_the_record_over_the_limit() {
    let text = "PARTNO T\nFEDRAT/100\nGOTO/0,0,5\nGOTO/1,0,5\nGOTO/2,0,5\nGOTO/3,0,5\nFINI\n";
    // The first point is where the tool starts, not a move: four GOTOs make three moves.
    let options = AptOptions::default().with_max_moves(2);
    let e = read_apt(text, "a.apt", &options, &mut Count::default()).unwrap_err();
    assert!(is_move_limit(&e, 2), "{e}");
    assert_eq!((e.pos.line, e.pos.column), (6, 1), "{e}");
    assert_eq!(e.found, "GOTO/3,0,5");
    read_apt(
        text,
        "a.apt",
        &AptOptions::default().with_max_moves(3),
        &mut Count::default(),
    )
    .unwrap();
}

/// The streamed summary of `text` equals the summary of the program read whole.
fn streamed_equals_whole(text: &str, file: &str, machine: &str) {
    let machine = Machine::from_name(machine).unwrap();
    let options = ReadOptions::default();
    let whole = read_program_str(text, file, machine.clone(), &options).unwrap();
    let mut sink = SummarySink::new(machine, file, &SummaryOptions::default());
    stream_program(text, file, &options, &mut sink).unwrap();
    let streamed = sink.finish();
    assert_eq!(streamed.summary, summarize(&whole), "{text}");
    assert!(streamed.program.moves.is_empty(), "no move is kept");
    assert_eq!(streamed.program.tools, whole.tools);
    assert_eq!(
        streamed.tool_zero_moved,
        whole.moves.iter().any(|m| m.tool == 0)
    );
}

#[test]
fn streamed_summary_equals_the_whole_programs() {
    streamed_equals_whole(
        "G21 G90\nT1 M6\nS1000 M3\nG0 X0 Y0 Z5\nG1 Z-1 F100\nG2 X10 Y0 I5 J0\nG3 X0 I-5 Z-2\n\
         G1 X5\nG81 X1 Y1 Z-3 R1 F50\nX2\nG80\nG5 I1 J1 P2 Q-1 X4 Y4\nG95 G1 X9 F0.1\nM30\n",
        "a.ngc",
        "3axis",
    );
    streamed_equals_whole(
        "G21 G90\nG0 X0 Y0 Z5 A0\nG1 Z-1 F100\nG1 X10 A30\nG1 X0 A-45\nM30\n",
        "r.ngc",
        "4axis-a",
    );
    streamed_equals_whole(
        "PARTNO T\nCUTTER/6\nLOADTL/2\nFEDRAT/100\nGOTO/0,0,5,0,0,1\nGOTO/10,0,5,0,0.6,0.8\n\
         GOTO/10,10,0,0,0,1\nFINI\n",
        "c.apt",
        "3axis",
    );
}

proptest! {
    #![proptest_config(swarf_testdata::proptest_config(64))]
    #[test]
    fn streamed_summary_equals_the_whole_programs_on_random_programs(
        steps in prop::collection::vec((0u8..4, -50i32..50, -50i32..50, -20i32..5, -90i32..90), 1..40),
    ) {
        let mut text = String::from("G21 G90 G0 X0 Y0 Z5\nF300\n");
        for (kind, x, y, z, a) in steps {
            let (x, y) = (f64::from(x) * 0.5, f64::from(y) * 0.5);
            text.push_str(&match kind {
                0 => format!("G0 X{x} Y{y} Z{z}\n"),
                1 => format!("G1 X{x} Y{y} Z{z} A{a}\n"),
                2 => format!("G2 X{x} Y{y} R{}\n", 60.0 + x.abs()),
                _ => format!("G3 X{x} Y{y} Z{z} R{}\n", 60.0 + y.abs()),
            });
        }
        text.push_str("M30\n");
        streamed_equals_whole(&text, "p.ngc", "4axis-a");
    }
}

#[test]
fn a_loop_that_warns_at_every_iteration_warns_once() {
    // Before: one warning per iteration, kept by every sink: 10 million of them filled 1.6 GB.
    let text = "G21 G90\no100 while [1]\nM8\nG1 X1 F100\nG1 X0\no100 endwhile\nM30\n";
    let options = GcodeOptions::default()
        .with_max_moves(u64::MAX)
        .with_max_loop_iterations(10_000);
    let mut count = Count::default();
    let e = read_gcode(text, "w.ngc", &options, &mut count).unwrap_err();
    assert!(e.message.contains("loop iterations"), "{e}");
    assert_eq!(count.moves, 20_002);
    let m8: Vec<_> = count.warnings.iter().filter(|w| w.line == 3).collect();
    assert_eq!(m8.len(), 1, "{:?}", count.warnings);
}

#[test]
fn distinct_warnings_beyond_the_cap_are_counted_in_one_last_warning() {
    let n = swarf_path::limit::MAX_WARNINGS + 5;
    // (An unused Q is a warning; an unused R is an error under LinuxCNC's rules.)
    let text = format!("G21 G90\n{}M30\n", "S100 Q1\n".repeat(n));
    let mut count = Count::default();
    read_gcode(&text, "w.ngc", &GcodeOptions::default(), &mut count).unwrap();
    assert_eq!(count.warnings.len(), swarf_path::limit::MAX_WARNINGS + 1);
    let last = count.warnings.last().unwrap();
    assert!(
        last.message
            .starts_with("5 more distinct warnings are not reported"),
        "{last}"
    );
    assert_eq!(count.warnings[0].line, 2);
}
