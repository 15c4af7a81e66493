//! LinuxCNC's own interpreter tests (`tests/interp/*` of LinuxCNC, copied into the shared data
//! set under `gcode/linuxcnc-interp/`), run through swarf's G-code reader and compared with the
//! `expected` output LinuxCNC's `rs274` produced.
//!
//! Each folder holds a program, its `expected` canonical output and the `test.sh` that shows how
//! `rs274` was run (`-t` tool table, `-i` INI with `SUBROUTINE_PATH`, `-v` parameter file, and
//! whether the output went through `awk '{$1=""; print}'`, which drops the first word of every
//! line). What is compared, in order:
//!
//! * the motion calls (`STRAIGHT_TRAVERSE`, `STRAIGHT_FEED`, `ARC_FEED`, `NURBS_FEED`, …): the
//!   same calls with the same numbers to 1e-4 (program units, as LinuxCNC prints them);
//! * the operator messages: `MESSAGE("…")` lines (`(debug,…)`/`(msg,…)` comments, parameters
//!   substituted) and the `(print,…)` lines LinuxCNC writes to its terminal, whitespace
//!   collapsed (as `awk` collapses it);
//! * for a folder whose program is meant to fail, the error: same file and line, and the
//!   records before it.
//!
//! The table of all folders is printed (`cargo test --test linuxcnc_interp_suite -- --nocapture`);
//! the test fails when a folder of [`PASSING`] fails, so the list only grows. Without the data
//! set (`SWARF_TEST_DATA`, default `../shared/data` beside the repository) the test says that it
//! skips.

use std::fmt::Write as _;
use std::path::Path;

use swarf_path::canon::{Canon, CanonSink};
use swarf_path::canonical::CanonicalPrinter;
use swarf_path::gcode::{read_gcode, GcodeOptions, LinuxCncIni};
use swarf_path::{MessageKind, Units, Warning};

/// Folders that reproduce LinuxCNC. Only ever add to this list.
const PASSING: &[&str] = &[
    "do-while-break",
    "flowsnake",
    "fractional-linenumbers",
    "g10-g10-l1-l10",
    "g10-g10-l2-while-active",
    "g10-g10-l20-while-active",
    "g10-g10-with-g92",
    "g52-g52-g92-interaction",
    "g52-g92-offset-persistence",
    "g6164",
    "g64-r-planner",
    "g81-g17-g98",
    "g81-g18-g99",
    "g81-g19-g98",
    "g81-g19-g99",
    "g84-g17-g98",
    "g84-g17-g99",
    "g84-g18-g98",
    "g84-g19-g99",
    "good",
    "inside-corners",
    "inverse-time-with-comp",
    "m98m99-01-basics",
    "m98m99-02-variables",
    "m98m99-07-nested-subs",
    "m98m99-10-M98-P001",
    "m98m99-13-named-program",
    "m98m99-14-o-expression-call",
    "machine-coord-params",
    "namedparam-bug424",
    "oword-unwind",
    "return-value",
    "rotation-abs-pts",
    "rotation-g28",
    "rotation-g53",
    "sequence-number",
    "sub-call-from-sub",
    "unit-conversion",
];

/// Folders of LinuxCNC 2.9's `tests/interp` that the shared data set does not hold (they are
/// checked where `SWARF_TEST_DATA` points at a fuller copy, flattened as the shared set is:
/// `g10/g10-l11` as `g10-g10-l11`). Only ever add to this list.
const PASSING_ELSEWHERE: &[&str] = &[
    "abort-hot-comment",
    "cam-nisley",
    "crazy-paths",
    "exists",
    "g10-g10-l11",
    "g33.1",
    "g81-g17-g99",
    "g81-g18-g98",
    "g84-g18-g99",
    "g84-g19-g98",
    "iniparam",
    "iniparam-failassign",
    "m98m99-03-error-M98-no-P-word",
    "m98m99-04-M98-but-no-sub",
    "m98m99-05-M98-loops",
    "m98m99-06-error-mixed-sub-styles",
    "m98m99-08-sub-follows-main",
    "m19",
    "magic_comments-param_format_printing",
    "oword-bug315",
    "oword-bug315-p2",
    "subs-follow-main",
];

/// Folders whose program ends in an error in LinuxCNC: the file and line of the error and a
/// word of its message.
const ERRORS: &[(&str, &str, u32, &str)] = &[
    ("oword-unwind", "fail.ngc", 4, "zero"),
    ("abort-hot-comment", "test.ngc", 5, "ini=3.140000"),
    ("iniparam", "test.ngc", 7, "not defined"),
    ("iniparam-failassign", "test.ngc", 1, "read-only"),
    ("m98m99-03-error-M98-no-P-word", "test.ngc", 4, "p word"),
    ("m98m99-04-M98-but-no-sub", "test.ngc", 4, "o1"),
    (
        "m98m99-06-error-mixed-sub-styles",
        "O...-called-with-O..._call.ngc",
        4,
        "o1",
    ),
];

/// Folders that cannot be reproduced by design, and why.
const OUT_OF_SCOPE: &[(&str, &str)] = &[(
    "value-returned",
    "calls O-word subroutines written in Python (subs.py, oword.py): swarf runs no embedded Python",
)];

const MOTION_CALLS: [&str; 6] = [
    "STRAIGHT_TRAVERSE(",
    "STRAIGHT_FEED(",
    "ARC_FEED(",
    "NURBS_FEED(",
    "SPLINE_FEED(",
    "RIGID_TAP(",
];

/// What one `rs274` run printed (or what swarf printed for it).
#[derive(Debug, Default, Clone, PartialEq)]
struct Output {
    /// Motion calls: name and numbers.
    motion: Vec<(String, Vec<f64>)>,
    /// Messages and printed lines, whitespace collapsed.
    messages: Vec<String>,
}

/// One `rs274` invocation of a `test.sh`.
#[derive(Debug, Default)]
struct Run {
    program: String,
    tool_table: Option<String>,
    ini: Option<String>,
    var_file: Option<String>,
    /// `awk '{$1=""; print}'` dropped the first word of each line.
    awk: bool,
    /// `awk '/MESSAGE/ …'` kept only the message lines.
    messages_only: bool,
}

fn collapse(s: &str) -> String {
    s.split_whitespace().collect::<Vec<_>>().join(" ")
}

fn parse_motion(line: &str) -> Option<(String, Vec<f64>)> {
    let call = MOTION_CALLS.iter().find(|c| line.contains(*c))?;
    let start = line.find(call)? + call.len();
    let end = line[start..].rfind(')')? + start;
    let nums = line[start..end]
        .split(|c: char| c == ',' || c.is_whitespace())
        .filter(|t| !t.is_empty())
        .filter_map(|t| t.parse::<f64>().ok())
        .collect();
    Some((call.trim_end_matches('(').to_string(), nums))
}

/// A canonical call line: `[line] N..... NAME(…)` or `N1234 NAME(…)`.
fn is_canonical_call(line: &str) -> bool {
    let words: Vec<&str> = line.split_whitespace().take(3).collect();
    words.windows(2).any(|w| {
        let n = w[0]
            .strip_prefix('N')
            .is_some_and(|r| !r.is_empty() && r.chars().all(|c| c.is_ascii_digit() || c == '.'));
        let call = w[1].split('(').next().unwrap_or("");
        // (Per-spindle calls have dots: `SPINDLE.0.WAIT_ORIENT_COMPLETE(2.0000)`.)
        n && w[1].contains('(')
            && call
                .chars()
                .all(|c| c.is_ascii_uppercase() || c.is_ascii_digit() || c == '_' || c == '.')
    })
}

/// The records of an `expected` file.
fn parse_expected(text: &str) -> Output {
    let mut out = Output::default();
    for line in text.lines() {
        if let Some(m) = parse_motion(line) {
            out.motion.push(m);
        } else if let Some(i) = line.find("MESSAGE(\"") {
            let body = &line[i + 9..];
            let body = body.strip_suffix("\")").unwrap_or(body);
            out.messages.push(collapse(body));
        } else if !is_canonical_call(line) && !line.trim().is_empty() && line != "executing" {
            // (`executing` is rs274's banner on stderr, in the output of `2>&1` runs.)
            // A line rs274 printed to the terminal: `(print,…)`.
            out.messages.push(collapse(line));
        }
    }
    out
}

fn parse_runs(script: &str) -> Vec<Run> {
    let mut runs = Vec::new();
    let mut joined = String::new();
    for line in script.lines() {
        let l = line.trim_end();
        if let Some(s) = l.strip_suffix('\\') {
            joined.push_str(s);
            joined.push(' ');
            continue;
        }
        joined.push_str(l);
        let full = std::mem::take(&mut joined);
        let t = full.trim_start();
        if t.starts_with('#') {
            continue;
        }
        let Some(at) = t.find("rs274") else { continue };
        let mut run = Run {
            awk: t.contains("{$1=\"\"; print}"),
            messages_only: t.contains("awk '/MESSAGE/"),
            ..Run::default()
        };
        let cmd = t[at..].split('|').next().unwrap_or("");
        let mut words = cmd.split_whitespace().skip(1);
        while let Some(w) = words.next() {
            match w {
                "-t" => run.tool_table = words.next().map(str::to_string),
                "-i" => run.ini = words.next().map(str::to_string),
                "-v" => run.var_file = words.next().map(str::to_string),
                "-n" => {
                    words.next();
                }
                "-g" | "2>&1" => {}
                w if w.ends_with(".ngc") => run.program = w.to_string(),
                _ => {}
            }
        }
        runs.push(run);
    }
    runs
}

/// Collects swarf's records: motion through the canonical printer (so the printed numbers are
/// what is compared), messages as events.
struct Collect {
    printer: CanonicalPrinter<Vec<u8>>,
    messages: Vec<String>,
    awk: bool,
    messages_only: bool,
}

impl CanonSink for Collect {
    fn emit(&mut self, line: u32, event: &Canon<'_>) {
        if let Some((print, text)) = message_of(event) {
            if print && self.messages_only {
                return;
            }
            let mut t = collapse(&text);
            if self.awk && print {
                // A line printed to the terminal has no line-number field: its own first
                // word went with awk's `$1 = ""`.
                t = t
                    .split_once(' ')
                    .map_or(String::new(), |(_, r)| r.to_string());
            }
            self.messages.push(t);
        }
        self.printer.emit(line, event);
    }
    fn warn(&mut self, _: Warning) {}
}

/// The text an event shows the operator, as LinuxCNC's output has it.
fn message_of(event: &Canon<'_>) -> Option<(bool, String)> {
    match event {
        Canon::Message { kind, text } => Some((*kind == MessageKind::Print, text.to_string())),
        _ => None,
    }
}

/// What `rs274` was given: the INI's `SUBROUTINE_PATH` (relative to the test folder, where
/// `rs274` ran) and the tool table's diameters, offsets and pockets (`T1 P1 D0.25 Z1 …`, in
/// the table's units: the standalone interpreter's are inches).
fn options_for(dir: &Path, run: &Run) -> GcodeOptions {
    // The standalone `rs274` keeps its offset parameters in inches.
    let mut o = GcodeOptions::default()
        .with_subroutine_dir(dir)
        .with_parameter_units(Units::Inch);
    let mut keep_g92 = true;
    if let Some(ini) = &run.ini {
        // The INI as swarf reads a machine's (`--ini`): subroutine path, `#<_ini[…]>` values,
        // DISABLE_FANUC_STYLE_SUB, tool-change settings.
        let ini = LinuxCncIni::read(&dir.join(ini)).expect("the test's INI");
        keep_g92 = ini
            .get("RS274NGC", "DISABLE_G92_PERSISTENCE")
            .map(str::trim)
            != Some("1");
        o = o.with_linuxcnc_ini(ini).expect("the test's INI settings");
        // The standalone rs274 keeps its parameters in inches whatever the INI says.
        o = o.with_parameter_units(Units::Inch);
    }
    if let Some(var) = &run.var_file {
        // `-v file.var`: parameter number and value per line (the test copies the template).
        let name = if dir.join(var).exists() {
            var.clone()
        } else {
            format!("{var}.template")
        };
        let text = std::fs::read_to_string(dir.join(name)).unwrap_or_default();
        for line in text.lines() {
            let mut w = line.split_whitespace();
            if let (Some(n), Some(v)) = (w.next(), w.next()) {
                if let (Ok(n), Ok(v)) = (n.parse::<usize>(), v.parse::<f64>()) {
                    if keep_g92 || !(5210..=5219).contains(&n) {
                        o = o.with_parameter(n, v);
                    }
                }
            }
        }
    }
    if let Some(tbl) = &run.tool_table {
        let text = std::fs::read_to_string(dir.join(tbl)).unwrap_or_default();
        for line in text.lines() {
            let words = line.split(';').next().unwrap_or("");
            let mut tool = None;
            let mut dia = None;
            let mut pocket = None;
            let mut offsets = None;
            for w in words.split_whitespace() {
                let (k, v) = w.split_at(1);
                match k {
                    "T" | "t" => tool = v.parse::<u32>().ok(),
                    "D" | "d" => dia = v.parse::<f64>().ok(),
                    "P" | "p" => pocket = v.parse::<u32>().ok(),
                    _ => {
                        let i = "XYZABC".find(&*k.to_ascii_uppercase());
                        if let (Some(i), Ok(v)) = (i, v.parse::<f64>()) {
                            let e = offsets.get_or_insert([0.0; 6]);
                            e[i] = if i < 3 { v * 25.4 } else { v };
                        }
                    }
                }
            }
            if let (Some(t), Some(d)) = (tool, dia) {
                o = o.with_tool_diameter(t, d * 25.4);
            }
            if let (Some(t), Some(e)) = (tool, offsets) {
                o = o.with_tool_offsets(t, e);
            }
            if let (Some(t), Some(p)) = (tool, pocket) {
                o = o.with_tool_pocket(t, p);
            }
        }
    }
    o
}

enum Verdict {
    Pass(String),
    Fail(String),
}

fn first_motion_difference(got: &Output, want: &Output) -> Option<String> {
    for (i, (g, w)) in got.motion.iter().zip(&want.motion).enumerate() {
        let same = g.0 == w.0
            && g.1.len() == w.1.len()
            && g.1
                .iter()
                .zip(&w.1)
                .all(|(a, b)| (a - b).abs() <= 1e-4 + 1e-12);
        if !same {
            return Some(format!("motion call {}: got {g:?}, want {w:?}", i + 1));
        }
    }
    if got.motion.len() != want.motion.len() {
        return Some(format!(
            "{} motion calls, want {}",
            got.motion.len(),
            want.motion.len()
        ));
    }
    None
}

/// Text split into runs of number characters and runs of other characters.
fn runs_of(s: &str) -> Vec<(bool, &str)> {
    let is_num = |c: char| c.is_ascii_digit() || c == '.' || c == '-';
    let mut out = Vec::new();
    let mut start = 0;
    let mut kind = None;
    for (i, c) in s.char_indices() {
        let k = is_num(c);
        if kind.is_some_and(|p| p != k) {
            out.push((kind.unwrap(), &s[start..i]));
            start = i;
        }
        kind = Some(k);
    }
    if let Some(k) = kind {
        out.push((k, &s[start..]));
    }
    out
}

/// Messages agree when their words agree and their numbers agree to 1e-5 (LinuxCNC prints
/// `%f`; its tests' `sed` turns `-0.0000…` into `0.0000…`).
fn same_message(got: &str, want: &str) -> bool {
    let (g, w) = (runs_of(got), runs_of(want));
    g.len() == w.len()
        && g.iter().zip(&w).all(|(a, b)| match (a, b) {
            ((true, x), (true, y)) => match (x.parse::<f64>(), y.parse::<f64>()) {
                (Ok(x), Ok(y)) => (x - y).abs() <= 1e-5,
                _ => x == y,
            },
            (x, y) => x == y,
        })
}

fn first_message_difference(got: &[String], want: &[String]) -> Option<String> {
    for (i, (g, w)) in got.iter().zip(want).enumerate() {
        if !same_message(g, w) {
            return Some(format!("message {}: got {g:?}, want {w:?}", i + 1));
        }
    }
    (got.len() != want.len()).then(|| format!("{} messages, want {}", got.len(), want.len()))
}

/// Runs one program; `Err` holds swarf's error.
fn run_swarf(dir: &Path, run: &Run) -> (Output, Result<(), swarf_path::PathError>) {
    let path = dir.join(&run.program);
    let text = std::fs::read_to_string(&path).unwrap_or_default();
    let mut sink = Collect {
        printer: CanonicalPrinter::new(Vec::new()),
        messages: Vec::new(),
        awk: run.awk,
        messages_only: run.messages_only,
    };
    let options = options_for(dir, run);
    let res = read_gcode(&text, &run.program, &options, &mut sink);
    let printed = String::from_utf8(sink.printer.finish().unwrap()).unwrap();
    let mut out = parse_expected(&printed);
    out.messages = sink.messages;
    if run.messages_only {
        out.motion.clear();
    }
    (out, res)
}

fn check_folder(dir: &Path, name: &str) -> Verdict {
    if let Some((_, why)) = OUT_OF_SCOPE.iter().find(|(n, _)| *n == name) {
        return Verdict::Fail(format!("out of scope: {why}"));
    }
    // The `good` folder runs every program against its own `.expected` (its `test` script).
    let mut cases: Vec<(Run, String)> = Vec::new();
    if dir.join("test.sh").exists() {
        let script = std::fs::read_to_string(dir.join("test.sh")).unwrap();
        let runs = parse_runs(&script);
        if runs.is_empty() {
            return Verdict::Fail("no rs274 run in test.sh".into());
        }
        let expected = std::fs::read_to_string(dir.join("expected")).unwrap_or_default();
        let n = runs.len();
        for (i, run) in runs.into_iter().enumerate() {
            // Several runs write one after the other into the same file: split it at each
            // run's first line (`USE_LENGTH_UNITS` opens every run).
            let part = split_runs(&expected, n, i);
            cases.push((run, part));
        }
    } else {
        let mut programs: Vec<_> = std::fs::read_dir(dir)
            .unwrap()
            .filter_map(|e| e.ok().map(|e| e.file_name().to_string_lossy().into_owned()))
            .filter(|n| n.ends_with(".ngc"))
            .collect();
        programs.sort();
        for p in programs {
            let expected =
                std::fs::read_to_string(dir.join(format!("{p}.expected"))).unwrap_or_default();
            cases.push((
                Run {
                    program: p,
                    ..Run::default()
                },
                expected,
            ));
        }
    }
    let error = ERRORS.iter().find(|(n, ..)| *n == name);
    let mut calls = 0;
    let mut messages = 0;
    for (run, expected) in &cases {
        let want = parse_expected(expected);
        let (got, res) = run_swarf(dir, run);
        if std::env::var("SWARF_SUITE_SHOW").is_ok_and(|s| s == name) {
            // Both sides, call by call, for the folder being worked on.
            let n = got.motion.len().max(want.motion.len());
            for i in 0..n {
                println!(
                    "{i:4} got {:?}\n     want {:?}",
                    got.motion.get(i),
                    want.motion.get(i)
                );
            }
            println!("{res:?}");
        }
        match (res, error) {
            (Ok(()), None) => {}
            (Err(e), None) => return Verdict::Fail(format!("{}: {e}", run.program)),
            (Ok(()), Some(_)) => return Verdict::Fail("no error, LinuxCNC raises one".into()),
            (Err(e), Some((_, file, line, word))) => {
                let at = e.pos.file.ends_with(file) && e.pos.line == *line;
                if !at || !e.message.to_lowercase().contains(word) {
                    return Verdict::Fail(format!("other error: {e}"));
                }
                // LinuxCNC (`-n 0`) goes on after the error; the records before it must agree.
                let prefix = Output {
                    motion: want.motion[..got.motion.len().min(want.motion.len())].to_vec(),
                    messages: want.messages[..got.messages.len().min(want.messages.len())].to_vec(),
                };
                if let Some(d) = first_motion_difference(&got, &prefix) {
                    return Verdict::Fail(d);
                }
                if let Some(d) = first_message_difference(&got.messages, &prefix.messages) {
                    return Verdict::Fail(d);
                }
                return Verdict::Pass(format!("same error: {e}"));
            }
        }
        if let Some(d) = first_motion_difference(&got, &want) {
            return Verdict::Fail(format!("{}: {d}", run.program));
        }
        if let Some(d) = first_message_difference(&got.messages, &want.messages) {
            return Verdict::Fail(format!("{}: {d}", run.program));
        }
        calls += want.motion.len();
        messages += want.messages.len();
    }
    Verdict::Pass(format!(
        "{} run(s), {calls} motion calls, {messages} messages",
        cases.len()
    ))
}

/// The `i`-th of `n` runs' output in one expected file.
fn split_runs(expected: &str, n: usize, i: usize) -> String {
    if n == 1 {
        return expected.to_string();
    }
    let mut parts: Vec<String> = Vec::new();
    for line in expected.lines() {
        let opens =
            line.contains("USE_LENGTH_UNITS(") && line.split_whitespace().next() == Some("1");
        if opens || parts.is_empty() {
            parts.push(String::new());
        }
        let last = parts.last_mut().unwrap();
        last.push_str(line);
        last.push('\n');
    }
    parts.get(i).cloned().unwrap_or_default()
}

#[test]
fn linuxcnc_interpreter_tests() {
    let Some(root) = swarf_testdata::path("gcode/linuxcnc-interp") else {
        return;
    };
    let mut names: Vec<String> = std::fs::read_dir(&root)
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.path().is_dir())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    let mut table = String::new();
    let mut passed = Vec::new();
    for name in &names {
        let verdict = check_folder(&root.join(name), name);
        let (mark, why) = match &verdict {
            Verdict::Pass(w) => ("pass", w),
            Verdict::Fail(w) => ("FAIL", w),
        };
        let why: String = why.chars().take(160).collect();
        writeln!(table, "{name:<32} {mark}  {why}").unwrap();
        if matches!(verdict, Verdict::Pass(_)) {
            passed.push(name.clone());
        }
    }
    println!("{table}");
    println!(
        "LinuxCNC interpreter tests: {}/{} folders pass",
        passed.len(),
        names.len()
    );
    let present = |n: &&&str| names.iter().any(|m| m == **n);
    let regressions: Vec<_> = PASSING
        .iter()
        .chain(PASSING_ELSEWHERE.iter().filter(present))
        .filter(|n| !passed.iter().any(|p| p == *n))
        .collect();
    assert!(
        regressions.is_empty(),
        "folders that passed before fail now: {regressions:?}"
    );
    let new: Vec<_> = passed
        .iter()
        .filter(|p| !PASSING.contains(&p.as_str()) && !PASSING_ELSEWHERE.contains(&p.as_str()))
        .collect();
    if !new.is_empty() {
        println!("passing but not yet in PASSING: {new:?}");
    }
}
