//! O-word subroutines in files of their own (`o<name> call` of `name.ngc` in the program's
//! folder or on the subroutine path, LinuxCNC's `SUBROUTINE_PATH`), computed calls
//! (`o[expression] call`) and returned values (LinuxCNC G-code manual, "O Codes": "Calling
//! Files", "Computed Subroutine Calls", "Return Values").

use std::path::PathBuf;

use swarf_path::canon::Recorder;
use swarf_path::gcode::{read_gcode, GcodeOptions};
use swarf_path::load::{read_program_str, ReadOptions};
use swarf_path::Machine;

/// A fresh folder with `lib/square.ngc`.
fn folder(tag: &str) -> PathBuf {
    let dir = swarf_testdata::scratch_dir(&format!("subfiles-{tag}"));
    std::fs::create_dir_all(dir.join("lib")).unwrap();
    std::fs::write(
        dir.join("lib/square.ngc"),
        "(library)\no<square> sub\n(debug,line #<_line> side #1)\nG1 X#1 F100\nY#1\no<square> endsub [#1 * 2]\nM2\n",
    )
    .unwrap();
    dir
}

#[test]
fn a_call_reads_the_subroutine_file_from_the_path() {
    let dir = folder("path");
    let main = dir.join("main.ngc").display().to_string();
    let src = "G21\no<square> call [5]\n(debug,got #<_value> #<_value_returned>)\nG0 X0\nM2\n";
    let options = GcodeOptions::default().with_subroutine_dir(dir.join("lib"));
    let mut rec = Recorder::default();
    read_gcode(src, &main, &options, &mut rec).unwrap();
    // `_line` counts lines of the subroutine's own file.
    assert_eq!(
        rec.messages(),
        vec!["line 3.000000 side 5.000000", "got 10.000000 1.000000"]
    );
    // The moves name the file and line they come from.
    let read = ReadOptions {
        gcode: options,
        ..ReadOptions::default()
    };
    let p = read_program_str(src, &main, Machine::three_axis(), &read).unwrap();
    assert_eq!(p.moves.len(), 3);
    assert_eq!((p.moves[0].file, p.moves[0].line), (1, 4));
    assert_eq!((p.moves[1].file, p.moves[1].line), (1, 5));
    assert!(p.files[1].ends_with("square.ngc"), "{:?}", p.files);
    assert_eq!((p.moves[2].file, p.moves[2].line), (0, 4));
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn without_the_path_the_subroutine_is_not_found() {
    let dir = folder("nopath");
    let main = dir.join("main.ngc").display().to_string();
    let mut rec = Recorder::default();
    let e = read_gcode(
        "o<square> call [5]\nM2\n",
        &main,
        &GcodeOptions::default(),
        &mut rec,
    )
    .unwrap_err();
    assert_eq!((e.pos.line, e.pos.column), (1, 1));
    assert!(e.message.contains("not defined"), "{e}");
    // A file in the program's own folder is found without a path.
    std::fs::copy(dir.join("lib/square.ngc"), dir.join("square.ngc")).unwrap();
    read_gcode(
        "o<square> call [5]\nM2\n",
        &main,
        &GcodeOptions::default(),
        &mut Recorder::default(),
    )
    .unwrap();
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn computed_calls_and_m98_expressions() {
    let src = "#2 = 10\no[#2 * 10] call [7]\nM98 P[5 * 20 + 100]\nM2\no100 sub\n(print,sub #1)\no100 endsub\nO200\n(print,fanuc)\nM99\n";
    let mut rec = Recorder::default();
    read_gcode(src, "c.ngc", &GcodeOptions::default(), &mut rec).unwrap();
    assert_eq!(rec.messages(), vec!["sub 7.000000", "fanuc"]);
}
