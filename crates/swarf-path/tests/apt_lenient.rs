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
