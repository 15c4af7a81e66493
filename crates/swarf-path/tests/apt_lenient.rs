//! APT CL records as real post-processors write them: trailing commas, spaces before `/`,
//! records split with `$`, numbers like `1.` and `.5`; anything unknown a warning with its line.

use swarf_path::apt::{read_apt, AptOptions};
use swarf_path::canon::Recorder;
use swarf_path::Canon;

fn read(src: &str) -> Recorder {
    let mut rec = Recorder::default();
    read_apt(src, "lenient.apt", &AptOptions::default(), &mut rec)
        .unwrap_or_else(|e| panic!("{e}"));
    rec
}

fn ends(rec: &Recorder) -> Vec<[f64; 3]> {
    rec.events
        .iter()
        .filter_map(|(_, e)| match e {
            Canon::Feed { end } | Canon::Traverse { end } => Some([end.x, end.y, end.z]),
            _ => None,
        })
        .collect()
}

#[test]
fn sloppy_records_read_as_the_clean_ones() {
    let clean =
        read("UNITS/MM\nFEDRAT/100\nGOTO/0,0,10\nGOTO/1,0.5,-2\nGOTO/3,4,5\nGOTO/0,0,10\nFINI\n");
    let sloppy = read(
        "UNITS / MM\nFEDRAT /100.,\nGOTO  /  0, 0 ,10.,\nGOTO/1.,.5,$\n  -2.\nGOTO/ 3 , 4 ,$\n 5 ,\nGOTO /0,0,10\nFINI\n",
    );
    assert_eq!(ends(&clean), ends(&sloppy));
    // The first point is where the tool starts; three moves follow.
    assert_eq!(
        ends(&sloppy),
        vec![[1.0, 0.5, -2.0], [3.0, 4.0, 5.0], [0.0, 0.0, 10.0]]
    );
}

#[test]
fn unknown_records_are_warnings_with_their_line() {
    let rec = read("GOTO/0,0,0\nGOTO/0,1,0\nFLOOB/1,2\nGOTO/1,0,0\nFINI\n");
    assert_eq!(
        ends(&rec).len(),
        2,
        "the first point is where the tool starts"
    );
    let w = rec
        .warnings
        .iter()
        .find(|w| w.message.contains("FLOOB"))
        .expect("a warning for FLOOB");
    assert_eq!(w.line, 3);
}

#[test]
fn creo_comments_continued_over_lines_and_spaced_slashes() {
    // Creo writes its CSYS as a comment continued with `$` over lines of numbers, and spaces
    // the slashes; its files (`.ncl`) are recognised as APT by extension and by content.
    let creo = "$$* Pro/CLfile  Version Wildfire 5.0 - M060\n$$-> MFGNO / TEST\nPARTNO / TEST\n\
                MACHIN / UNCX01, 1\nUNITS / MM\nLOADTL / 1\n$$-> CUTTER / 6.000000\n\
                $$-> CSYS / 1.0000000000, 0.0000000000, 0.0000000000, 0.0000000000, $\n\
                \x20           0.0000000000, 1.0000000000, 0.0000000000, 0.0000000000, $\n\
                \x20           0.0000000000, 0.0000000000, 1.0000000000, 0.0000000000\n\
                SPINDL / RPM, 1000.000000, CLW\nRAPID\nGOTO / 10.0, 10.0, 50.0\nRAPID\n\
                GOTO / 10.0, 10.0, 5.0\nFEDRAT / 300.000000, MMPM\nGOTO / 10.0, 10.0, -1.0\n\
                SPINDL / OFF\nFINI\n";
    let rec = read(creo);
    assert_eq!(ends(&rec), vec![[10.0, 10.0, 5.0], [10.0, 10.0, -1.0]]);
    assert!(rec.warnings.is_empty(), "{:?}", rec.warnings);
    use std::path::Path;
    use swarf_path::load::ProgramFormat;
    assert_eq!(
        ProgramFormat::detect(Path::new("part.ncl"), creo),
        ProgramFormat::Apt
    );
    let spaced = "$$ header\nMACHIN / UNCX01, 1\nGOTO / 1, 2, 3\n";
    assert_eq!(
        ProgramFormat::detect(Path::new("part.txt"), spaced),
        ProgramFormat::Apt
    );
    // A whole-line comment ending in `$` does not swallow a record after it.
    let rec = read("$$ a comment $\nGOTO/0,0,0\nGOTO/1,0,0\n");
    assert_eq!(ends(&rec), vec![[1.0, 0.0, 0.0]]);
}
