//! Properties of the feed rewrite on arbitrary text: it never panics, a factor of 1 everywhere
//! changes nothing, and whatever it writes differs from the input only in feed numbers (G-code:
//! the text with every F word's number removed is unchanged, up to added ` F` words).

use std::collections::BTreeMap;

use proptest::prelude::*;
use swarf_path::load::ProgramFormat;
use swarf_path::rewrite::rewrite_feeds;

fn line() -> impl Strategy<Value = String> {
    prop_oneof![
        Just("G1 X1 F100".to_string()),
        Just("G1 X2".to_string()),
        Just("G0 Z5".to_string()),
        Just("F250".to_string()),
        Just("G1 Y3 F[#1*2]".to_string()),
        Just("(F comment) G1 X4".to_string()),
        Just("G1 X5 ; F9".to_string()),
        Just("FEDRAT/ 300,MMPM".to_string()),
        Just("GOTO/1,2,3".to_string()),
        "[ -~]{0,20}",
    ]
}

fn drop_feed_numbers(t: &str) -> String {
    let mut out = String::new();
    let mut chars = t.chars().peekable();
    while let Some(c) = chars.next() {
        out.push(c);
        if matches!(c, 'F' | 'f' | '/' | ',') {
            while chars
                .peek()
                .is_some_and(|&d| d.is_ascii_digit() || matches!(d, '.' | '+' | '-'))
            {
                chars.next();
            }
        }
    }
    // An F word (kept, replaced or added before a comment) reads the same.
    out.replace(" F", "")
}

proptest! {
    #![proptest_config(swarf_testdata::proptest_config(256))]
    #[test]
    fn rewrite_is_safe_and_changes_only_feeds(
        lines in proptest::collection::vec(line(), 0..12),
        picks in proptest::collection::vec((0u32..14, 0.1f64..4.0), 0..8),
        apt in any::<bool>(),
    ) {
        let text = lines.join("\n") + "\n";
        let format = if apt { ProgramFormat::Apt } else { ProgramFormat::Gcode };
        let ones: BTreeMap<u32, f64> = picks.iter().map(|&(l, _)| (l, 1.0)).collect();
        if let Ok(r) = rewrite_feeds(&text, "p", format, &ones, &BTreeMap::new()) {
            // Factor 1: lines whose feed is in effect keep it; only restoring words may appear.
            prop_assert_eq!(drop_feed_numbers(&r.text), drop_feed_numbers(&text));
        }
        let factors: BTreeMap<u32, f64> = picks.iter().copied().collect();
        if let Ok(r) = rewrite_feeds(&text, "p", format, &factors, &BTreeMap::new()) {
            if !apt {
                prop_assert_eq!(drop_feed_numbers(&r.text), drop_feed_numbers(&text));
                prop_assert_eq!(r.text.lines().count(), text.lines().count());
            } else {
                // APT: only FEDRAT records are added.
                let extra: Vec<&str> = r.text.lines().filter(|l| !text.lines().any(|t| t == *l)).collect();
                prop_assert!(extra.iter().all(|l| l.to_ascii_uppercase().contains("FEDRAT")), "{:?}", extra);
            }
        }
    }
}

/// Lines end where the G-code reader ends them: at `\n`, `\r\n` or a lone `\r` (old Mac
/// editors), so line N of the rewrite is the reader's line N, and each keeps its own line end.
/// Before, a file with lone `\r` ends was one line to the rewrite.
#[test]
fn lone_carriage_returns_end_lines_and_each_keeps_its_end() {
    use swarf_path::load::{program_lines, program_lines_with_ends};
    use swarf_path::rewrite::{gcode_line_modes, SplitPiece};
    let text = "G21 G90\rG1 X10 F100\rG1 X20\r\nG1 X30\n";
    assert_eq!(
        program_lines_with_ends(text, ProgramFormat::Gcode).collect::<Vec<_>>(),
        ["G21 G90\r", "G1 X10 F100\r", "G1 X20\r\n", "G1 X30\n"]
    );
    assert_eq!(
        program_lines(text, ProgramFormat::Gcode).collect::<Vec<_>>(),
        ["G21 G90", "G1 X10 F100", "G1 X20", "G1 X30"]
    );
    // APT is read by lines ending at `\n`, and counted so.
    assert_eq!(program_lines("A\rB\r\nC", ProgramFormat::Apt).count(), 2);
    let factors: BTreeMap<u32, f64> = [(2, 0.5), (3, 1.0), (4, 1.0)].into();
    let r = rewrite_feeds(text, "p", ProgramFormat::Gcode, &factors, &BTreeMap::new()).unwrap();
    assert_eq!(r.text, "G21 G90\rG1 X10 F50\rG1 X20 F100\r\nG1 X30\n");
    // A split line's pieces end as the line does.
    let splits: BTreeMap<u32, Vec<SplitPiece>> = [(
        3,
        vec![SplitPiece {
            delta: [5.0, 0.0, 0.0],
            factor: 0.5,
        }],
    )]
    .into();
    let text = "G21 G90\rG1 X10 F100\rG1 X20\r";
    let factors: BTreeMap<u32, f64> = [(2, 1.0), (3, 1.0)].into();
    let r = rewrite_feeds(text, "p", ProgramFormat::Gcode, &factors, &splits).unwrap();
    assert_eq!(
        r.text,
        "G21 G90\rG1 X10 F100\rG91 G1 X5 Y0 Z0 F50\rG90\rG1 X20 F100\r"
    );
    // The modes are per line too: G91 on line 2 is not in effect on line 1.
    let modes = gcode_line_modes("G90\rG91 G1 X1\rG20\r", false);
    assert_eq!(modes.len(), 3);
    assert!(modes[0].absolute && !modes[1].absolute && modes[2].inch && !modes[1].inch);
    // A tilted working plane transforms the frame: its moves' pieces would be written in the
    // wrong coordinates.
    let modes = gcode_line_modes(
        "G1 X1
G68.2 X0 Y0 Z0 I0 J30 K0
G1 X2
",
        false,
    );
    assert!(!modes[0].transformed && modes[1].transformed && modes[2].transformed);
}
