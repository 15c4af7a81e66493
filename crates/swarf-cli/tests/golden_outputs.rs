//! Golden outputs of every subcommand: the demo job, a few cutters, the shared programs and the
//! shared surfaces, run through the built `swarf` and compared with what was recorded under
//! `tests/golden/` (one JSON manifest per case), so a restructure that changes no behaviour can
//! prove it.
//!
//! What is compared, per case: the arguments, the exit status, stdout, stderr and every file the
//! command writes.
//! * JSON is compared value by value, timing keys ([`TIMING_KEYS`]) dropped.
//! * Text (CSV, canonical motion, messages) line by line: the text between numbers exactly, every
//!   number within [`REL_TOL`] relative (a parallel sum may move in its last bits).
//! * Text longer than [`INLINE_LIMIT`] is kept as a digest: its SHA-256 (equal bytes pass at
//!   once), its line count, the SHA-256 of its text with the numbers taken out, the sum of the
//!   k-th number of every line for each k (within [`REL_TOL`] of the sum of magnitudes), and
//!   [`SAMPLES`] lines spread over it, compared as above.
//! * Binary files (STL, glb, PNG) by the SHA-256 of their bytes: they are deterministic, over
//!   runs and over thread counts (checked when this test was written).
//!
//! Paths are written as `$OUT` (the run's temporary folder) and `$DATA` (the shared data), so
//! the goldens hold on any checkout.
//!
//! Re-record after an intended change, and review the diff of `tests/golden/`:
//! `SWARF_RECORD_GOLDEN=1 cargo test -p swarf-cli --release --test golden_outputs`.
//!
//! The shared data is read from `SWARF_TEST_DATA` (default `../shared/data`, relative to the
//! repository root; see `swarf-testdata`); where it is absent the cases that need it are skipped
//! with a printed reason.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;

use serde_json::{json, Map, Value};

/// Relative tolerance on every number.
const REL_TOL: f64 = 1e-9;
/// Absolute floor of the tolerance, for numbers that should be zero.
const ABS_TOL: f64 = 1e-12;
/// Text up to this many bytes is kept whole in the manifest; longer text as a digest.
const INLINE_LIMIT: usize = 40 * 1024;
/// Lines kept from a digested text.
const SAMPLES: usize = 40;
/// Numbers per line whose sums a digest keeps.
const SUM_COLUMNS: usize = 32;
/// JSON keys whose values are timings, not results.
const TIMING_KEYS: &[&str] = &["elapsed_s"];
/// Files compared by the hash of their bytes.
const BINARY_EXTENSIONS: &[&str] = &["stl", "glb", "png", "ply"];

fn golden_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden")
}

/// One group of cases: a temporary folder, the data folder, and what went wrong so far.
struct Golden {
    out: PathBuf,
    data: Option<PathBuf>,
    record: bool,
    failures: Vec<String>,
}

impl Golden {
    fn new(group: &str, data: Option<PathBuf>) -> Self {
        let out = swarf_testdata::scratch_dir(&format!("golden-{group}"));
        let _ = std::fs::remove_dir_all(&out);
        std::fs::create_dir_all(&out).unwrap();
        let out = out.canonicalize().unwrap();
        Self {
            out,
            data,
            record: std::env::var_os("SWARF_RECORD_GOLDEN").is_some(),
            failures: Vec::new(),
        }
    }

    /// `$OUT` and `$DATA` in an argument replaced by the real folders.
    fn expand(&self, arg: &str) -> String {
        let mut s = arg.replace("$OUT", &self.out.display().to_string());
        if let Some(d) = &self.data {
            s = s.replace("$DATA", &d.display().to_string());
        }
        s
    }

    /// The real folders in an output replaced by `$OUT` and `$DATA`.
    fn normalise(&self, text: &str) -> String {
        let mut s = text.replace(&self.out.display().to_string(), "$OUT");
        if let Some(d) = &self.data {
            s = s.replace(&d.display().to_string(), "$DATA");
        }
        s
    }

    /// Runs `swarf ARGS`, collects its outputs and the files under `$OUT/files` (if given), and
    /// records or compares them as case `name`.
    fn case(&mut self, name: &str, args: &[&str], files: Option<&str>) {
        let real: Vec<String> = args.iter().map(|a| self.expand(a)).collect();
        let o = Command::new(env!("CARGO_BIN_EXE_swarf"))
            .args(&real)
            .output()
            .expect("swarf runs");
        let mut files_map = Map::new();
        if let Some(dir) = files {
            let root = PathBuf::from(self.expand(dir));
            for path in files_under(&root) {
                let rel = path
                    .strip_prefix(&root)
                    .unwrap()
                    .to_string_lossy()
                    .replace('\\', "/");
                let bytes = std::fs::read(&path).unwrap();
                files_map.insert(rel.clone(), self.entry(&rel, &bytes));
            }
        }
        let got = json!({
            "args": args,
            "status": o.status.code(),
            "stdout": self.entry("stdout", &o.stdout),
            "stderr": self.entry("stderr", &o.stderr),
            "files": files_map,
        });
        let path = golden_dir().join(format!("{name}.json"));
        if self.record {
            std::fs::create_dir_all(golden_dir()).unwrap();
            let text = serde_json::to_string_pretty(&got).unwrap() + "\n";
            std::fs::write(&path, text).unwrap();
            println!("recorded {}", path.display());
            return;
        }
        let want: Value = match std::fs::read_to_string(&path) {
            Ok(t) => serde_json::from_str(&t).unwrap(),
            Err(e) => {
                self.failures.push(format!(
                    "{name}: no golden {} ({e}); record with SWARF_RECORD_GOLDEN=1",
                    path.display()
                ));
                return;
            }
        };
        let mut diffs = Vec::new();
        compare_case(&want, &got, &mut diffs);
        for d in diffs.into_iter().take(20) {
            self.failures.push(format!("{name}: {d}"));
        }
    }

    /// How an output is kept: JSON value, text lines, a digest of long text, or a hash.
    fn entry(&self, name: &str, bytes: &[u8]) -> Value {
        let ext = name.rsplit('.').next().unwrap_or("");
        if ext == "html" {
            // A report embeds the run's timings and its meshes compressed: its contents are
            // checked by the report tests (figures equal the JSON), here only that it is there.
            return json!({ "html": true });
        }
        if BINARY_EXTENSIONS.contains(&ext) {
            return json!({"sha256": sha256_hex(bytes), "bytes": bytes.len()});
        }
        let text = self.normalise(&String::from_utf8_lossy(bytes));
        let trimmed = text.trim_start();
        if ext == "json" || trimmed.starts_with('{') || trimmed.starts_with('[') {
            if let Ok(mut v) = serde_json::from_str::<Value>(&text) {
                drop_timing(&mut v);
                let pretty = serde_json::to_string_pretty(&v).unwrap();
                return if pretty.len() <= INLINE_LIMIT {
                    json!({ "json": v })
                } else {
                    json!({ "digest": digest(&pretty) })
                };
            }
        }
        if text.len() <= INLINE_LIMIT {
            json!({ "text": text.lines().collect::<Vec<_>>() })
        } else {
            json!({ "digest": digest(&text) })
        }
    }

    fn finish(self) {
        let _ = std::fs::remove_dir_all(&self.out);
        assert!(
            self.failures.is_empty(),
            "outputs differ from the goldens (re-record with SWARF_RECORD_GOLDEN=1 only if the \
             change is intended):\n{}",
            self.failures.join("\n")
        );
    }
}

/// Every file under `root`, sorted.
fn files_under(root: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![root.to_path_buf()];
    while let Some(dir) = stack.pop() {
        let Ok(rd) = std::fs::read_dir(&dir) else {
            continue;
        };
        for e in rd {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else {
                out.push(p);
            }
        }
    }
    out.sort();
    out
}

fn drop_timing(v: &mut Value) {
    match v {
        Value::Object(m) => {
            for k in TIMING_KEYS {
                m.remove(*k);
            }
            m.values_mut().for_each(drop_timing);
        }
        Value::Array(a) => a.iter_mut().for_each(drop_timing),
        _ => {}
    }
}

/// A line cut into its text with every number replaced by `#`, and the numbers.
fn split_numbers(line: &str) -> (String, Vec<f64>) {
    let b = line.as_bytes();
    let (mut skeleton, mut numbers) = (String::new(), Vec::new());
    let mut i = 0;
    while i < b.len() {
        let word_before = i > 0 && (b[i - 1].is_ascii_alphanumeric() || b"_.".contains(&b[i - 1]));
        let starts = b[i].is_ascii_digit()
            || (b[i] == b'.' && b.get(i + 1).is_some_and(u8::is_ascii_digit))
            || (b[i] == b'-'
                && (b.get(i + 1).is_some_and(u8::is_ascii_digit)
                    || (b.get(i + 1) == Some(&b'.')
                        && b.get(i + 2).is_some_and(u8::is_ascii_digit))));
        if !starts || word_before {
            // Copy a whole word, so the digits in `G17` or `patch_0` stay text; else one char.
            let word = |c: u8| c.is_ascii_alphanumeric() || c == b'_';
            let mut j = i + line[i..].chars().next().map_or(1, char::len_utf8);
            if word(b[i]) {
                while j < b.len() && word(b[j]) {
                    j += 1;
                }
            }
            skeleton.push_str(&line[i..j]);
            i = j;
            continue;
        }
        let mut j = i + 1;
        while j < b.len() && (b[j].is_ascii_digit() || b[j] == b'.') {
            j += 1;
        }
        if j < b.len() && (b[j] == b'e' || b[j] == b'E') {
            let mut k = j + 1;
            if k < b.len() && (b[k] == b'-' || b[k] == b'+') {
                k += 1;
            }
            if k < b.len() && b[k].is_ascii_digit() {
                while k < b.len() && b[k].is_ascii_digit() {
                    k += 1;
                }
                j = k;
            }
        }
        match line[i..j].parse::<f64>() {
            Ok(x) => {
                skeleton.push('#');
                numbers.push(x);
            }
            Err(_) => skeleton.push_str(&line[i..j]),
        }
        i = j;
    }
    (skeleton, numbers)
}

fn close(a: f64, b: f64, scale: f64) -> bool {
    a == b || (a - b).abs() <= REL_TOL * scale.max(a.abs()).max(b.abs()) + ABS_TOL
}

fn compare_lines(where_: &str, want: &str, got: &str, diffs: &mut Vec<String>) {
    let (sw, nw) = split_numbers(want);
    let (sg, ng) = split_numbers(got);
    if sw != sg || nw.len() != ng.len() || nw.iter().zip(&ng).any(|(a, b)| !close(*a, *b, 0.0)) {
        diffs.push(format!("{where_}:\n  want {want}\n  got  {got}"));
    }
}

fn digest(text: &str) -> Value {
    let lines: Vec<&str> = text.lines().collect();
    let mut skeleton = String::new();
    let mut sums: Vec<[f64; 2]> = Vec::new();
    for l in &lines {
        let (s, nums) = split_numbers(l);
        skeleton.push_str(&s);
        skeleton.push('\n');
        for (k, x) in nums.iter().take(SUM_COLUMNS).enumerate() {
            if sums.len() <= k {
                sums.push([0.0; 2]);
            }
            if x.is_finite() {
                sums[k][0] += x;
                sums[k][1] += x.abs();
            }
        }
    }
    let mut samples = Map::new();
    for i in 0..SAMPLES {
        let k = i * lines.len() / SAMPLES;
        samples.insert(k.to_string(), json!(lines[k]));
    }
    if let Some(last) = lines.last() {
        samples.insert((lines.len() - 1).to_string(), json!(last));
    }
    json!({
        "sha256": sha256_hex(text.as_bytes()),
        "lines": lines.len(),
        "skeleton_sha256": sha256_hex(skeleton.as_bytes()),
        "sums": sums,
        "samples": samples,
    })
}

fn compare_case(want: &Value, got: &Value, diffs: &mut Vec<String>) {
    for key in ["args", "status"] {
        if want[key] != got[key] {
            diffs.push(format!("{key}: want {} got {}", want[key], got[key]));
        }
    }
    compare_entry("stdout", &want["stdout"], &got["stdout"], diffs);
    compare_entry("stderr", &want["stderr"], &got["stderr"], diffs);
    let (wf, gf) = (
        want["files"].as_object().unwrap(),
        got["files"].as_object().unwrap(),
    );
    for k in wf.keys().filter(|k| !gf.contains_key(*k)) {
        diffs.push(format!("file {k} not written"));
    }
    for k in gf.keys().filter(|k| !wf.contains_key(*k)) {
        diffs.push(format!("file {k} written but not in the golden"));
    }
    for (k, w) in wf {
        if let Some(g) = gf.get(k) {
            compare_entry(k, w, g, diffs);
        }
    }
}

fn compare_entry(what: &str, want: &Value, got: &Value, diffs: &mut Vec<String>) {
    if let (Some(w), Some(g)) = (want.get("json"), got.get("json")) {
        compare_json(what, w, g, diffs);
    } else if let (Some(w), Some(g)) = (want.get("text"), got.get("text")) {
        let (w, g) = (w.as_array().unwrap(), got_lines(g));
        if w.len() != g.len() {
            diffs.push(format!("{what}: {} lines, want {}", g.len(), w.len()));
        }
        for (i, (a, b)) in w.iter().zip(&g).enumerate() {
            compare_lines(
                &format!("{what} line {}", i + 1),
                a.as_str().unwrap(),
                b,
                diffs,
            );
        }
    } else if let (Some(w), Some(g)) = (want.get("digest"), got.get("digest")) {
        compare_digest(what, w, g, diffs);
    } else if want.get("sha256").is_some() {
        if want != got {
            diffs.push(format!("{what}: bytes differ (want {want}, got {got})"));
        }
    } else if want.get("html").is_some() && got.get("html").is_some() {
        // Present in both: a report's contents are the report tests' to check.
    } else {
        diffs.push(format!(
            "{what}: kept as {want} in the golden but now {got}"
        ));
    }
}

fn got_lines(v: &Value) -> Vec<&str> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|l| l.as_str().unwrap())
        .collect()
}

fn compare_digest(what: &str, w: &Value, g: &Value, diffs: &mut Vec<String>) {
    if w["sha256"] == g["sha256"] {
        return;
    }
    for key in ["lines", "skeleton_sha256"] {
        if w[key] != g[key] {
            diffs.push(format!("{what}: {key} want {} got {}", w[key], g[key]));
            return;
        }
    }
    let (ws, gs) = (w["sums"].as_array().unwrap(), g["sums"].as_array().unwrap());
    for (k, (a, b)) in ws.iter().zip(gs).enumerate() {
        let (a0, b0, scale) = (
            a[0].as_f64().unwrap(),
            b[0].as_f64().unwrap(),
            a[1].as_f64().unwrap(),
        );
        if !close(a0, b0, scale) {
            diffs.push(format!(
                "{what}: sum of number {k} of each line: want {a0} got {b0}"
            ));
        }
    }
    for (i, line) in w["samples"].as_object().unwrap() {
        let got_line = g["samples"][i].as_str().unwrap_or("<none>");
        compare_lines(
            &format!("{what} line {i}"),
            line.as_str().unwrap(),
            got_line,
            diffs,
        );
    }
}

fn compare_json(path: &str, w: &Value, g: &Value, diffs: &mut Vec<String>) {
    match (w, g) {
        (Value::Number(a), Value::Number(b)) => {
            let (a, b) = (a.as_f64().unwrap(), b.as_f64().unwrap());
            if !close(a, b, 0.0) {
                diffs.push(format!("{path}: want {a} got {b}"));
            }
        }
        (Value::String(a), Value::String(b)) => compare_lines(path, a, b, diffs),
        (Value::Array(a), Value::Array(b)) => {
            if a.len() != b.len() {
                diffs.push(format!("{path}: {} items, want {}", b.len(), a.len()));
            }
            for (i, (x, y)) in a.iter().zip(b).enumerate() {
                compare_json(&format!("{path}[{i}]"), x, y, diffs);
            }
        }
        (Value::Object(a), Value::Object(b)) => {
            let keys = |m: &Map<String, Value>| m.keys().cloned().collect::<Vec<_>>();
            if keys(a) != keys(b) {
                diffs.push(format!("{path}: keys {:?}, want {:?}", keys(b), keys(a)));
            }
            for (k, x) in a {
                if let Some(y) = b.get(k) {
                    compare_json(&format!("{path}.{k}"), x, y, diffs);
                }
            }
        }
        _ if w == g => {}
        _ => diffs.push(format!("{path}: want {w} got {g}")),
    }
}

/// SHA-256 (FIPS 180-4) of `data`, as lowercase hex; the test needs no crate for it.
fn sha256_hex(data: &[u8]) -> String {
    const K: [u32; 64] = [
        0x428a2f98, 0x71374491, 0xb5c0fbcf, 0xe9b5dba5, 0x3956c25b, 0x59f111f1, 0x923f82a4,
        0xab1c5ed5, 0xd807aa98, 0x12835b01, 0x243185be, 0x550c7dc3, 0x72be5d74, 0x80deb1fe,
        0x9bdc06a7, 0xc19bf174, 0xe49b69c1, 0xefbe4786, 0x0fc19dc6, 0x240ca1cc, 0x2de92c6f,
        0x4a7484aa, 0x5cb0a9dc, 0x76f988da, 0x983e5152, 0xa831c66d, 0xb00327c8, 0xbf597fc7,
        0xc6e00bf3, 0xd5a79147, 0x06ca6351, 0x14292967, 0x27b70a85, 0x2e1b2138, 0x4d2c6dfc,
        0x53380d13, 0x650a7354, 0x766a0abb, 0x81c2c92e, 0x92722c85, 0xa2bfe8a1, 0xa81a664b,
        0xc24b8b70, 0xc76c51a3, 0xd192e819, 0xd6990624, 0xf40e3585, 0x106aa070, 0x19a4c116,
        0x1e376c08, 0x2748774c, 0x34b0bcb5, 0x391c0cb3, 0x4ed8aa4a, 0x5b9cca4f, 0x682e6ff3,
        0x748f82ee, 0x78a5636f, 0x84c87814, 0x8cc70208, 0x90befffa, 0xa4506ceb, 0xbef9a3f7,
        0xc67178f2,
    ];
    let mut h: [u32; 8] = [
        0x6a09e667, 0xbb67ae85, 0x3c6ef372, 0xa54ff53a, 0x510e527f, 0x9b05688c, 0x1f83d9ab,
        0x5be0cd19,
    ];
    let mut msg = data.to_vec();
    msg.push(0x80);
    while msg.len() % 64 != 56 {
        msg.push(0);
    }
    msg.extend_from_slice(&(data.len() as u64 * 8).to_be_bytes());
    for block in msg.chunks_exact(64) {
        let mut w = [0u32; 64];
        for (i, c) in block.chunks_exact(4).enumerate() {
            w[i] = u32::from_be_bytes([c[0], c[1], c[2], c[3]]);
        }
        for i in 16..64 {
            let s0 = w[i - 15].rotate_right(7) ^ w[i - 15].rotate_right(18) ^ (w[i - 15] >> 3);
            let s1 = w[i - 2].rotate_right(17) ^ w[i - 2].rotate_right(19) ^ (w[i - 2] >> 10);
            w[i] = w[i - 16]
                .wrapping_add(s0)
                .wrapping_add(w[i - 7])
                .wrapping_add(s1);
        }
        let mut s = h;
        for i in 0..64 {
            let s1 = s[4].rotate_right(6) ^ s[4].rotate_right(11) ^ s[4].rotate_right(25);
            let ch = (s[4] & s[5]) ^ (!s[4] & s[6]);
            let t1 = s[7]
                .wrapping_add(s1)
                .wrapping_add(ch)
                .wrapping_add(K[i])
                .wrapping_add(w[i]);
            let s0 = s[0].rotate_right(2) ^ s[0].rotate_right(13) ^ s[0].rotate_right(22);
            let maj = (s[0] & s[1]) ^ (s[0] & s[2]) ^ (s[1] & s[2]);
            let t2 = s0.wrapping_add(maj);
            s = [
                t1.wrapping_add(t2),
                s[0],
                s[1],
                s[2],
                s[3].wrapping_add(t1),
                s[4],
                s[5],
                s[6],
            ];
        }
        for (a, b) in h.iter_mut().zip(s) {
            *a = a.wrapping_add(b);
        }
    }
    h.iter().fold(String::new(), |mut out, x| {
        let _ = write!(out, "{x:08x}");
        out
    })
}

#[test]
fn the_hash_is_sha256() {
    assert_eq!(
        sha256_hex(b"abc"),
        "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
    );
    assert_eq!(
        sha256_hex(&[b'a'; 1000]),
        "41edece42d63e8d9bf515a9ba6932e1c20cbc9f5a5d134645adb5db1b9737ea3"
    );
}

#[test]
fn numbers_are_found_in_text_and_compared_within_tolerance() {
    let (s, n) = split_numbers("G17 patch_0,-1.5e-3,2,inf STRAIGHT_FEED(1.0000, -.5)");
    assert_eq!(s, "G17 patch_0,#,#,inf STRAIGHT_FEED(#, #)");
    assert_eq!(n, vec![-1.5e-3, 2.0, 1.0, -0.5]);
    let mut diffs = Vec::new();
    compare_lines("l", "x,1.0000000000001", "x,1.0000000000002", &mut diffs);
    assert!(diffs.is_empty());
    compare_lines("l", "x,1.0", "x,1.00001", &mut diffs);
    assert_eq!(diffs.len(), 1);
}

/// The demo job and every command on its files: demo, path, simulate, envelope, toolsize,
/// gouge.
#[test]
fn demo_job() {
    let mut g = Golden::new("demo", None);
    g.case("demo", &["demo", "--out", "$OUT/demo"], Some("$OUT/demo"));
    // The files below are the demo's own: its program, library and floor surface.
    for (name, flag) in [
        ("path_demo_json", "--json"),
        ("path_demo_canonical", "--canonical"),
    ] {
        g.case(
            name,
            &[
                "path",
                "$OUT/demo/demo.ngc",
                "--tools",
                "$OUT/demo/tools.toml",
                flag,
            ],
            None,
        );
    }
    let job = [
        "--program",
        "$OUT/demo/demo.ngc",
        "--tools",
        "$OUT/demo/tools.toml",
    ];
    let mut simulate = vec!["simulate", "--json", "--stock", "box:0,0,-20,100,80,0"];
    simulate.extend(job);
    simulate.extend(["--out", "$OUT/simulate"]);
    g.case("simulate_demo", &simulate, Some("$OUT/simulate"));
    let mut envelope = vec!["envelope", "--json", "--moves", "100..110"];
    envelope.extend(job);
    envelope.extend(["--out", "$OUT/envelope"]);
    g.case(
        "envelope_demo_moves_100_110",
        &envelope,
        Some("$OUT/envelope"),
    );
    let mut gouge = vec!["gouge", "--json", "--surface", "$OUT/demo/floor.json"];
    gouge.extend(job);
    gouge.extend(["--out", "$OUT/gouge"]);
    g.case("gouge_demo", &gouge, Some("$OUT/gouge"));
    let floor = ["toolsize", "--json", "--surface", "$OUT/demo/floor.json"];
    for (name, extra) in [
        (
            "toolsize_floor_ball_standard",
            &["--cutter", "ball", "--grid", "9", "--standard", "6,10,20"][..],
        ),
        (
            "toolsize_floor_flat_axis4",
            &["--cutter", "flat", "--grid", "5", "--axis4", "Y"][..],
        ),
        (
            "toolsize_floor_ball_five_axis",
            &["--cutter", "ball", "--grid", "4", "--five-axis", "20,20"][..],
        ),
    ] {
        let dir = format!("$OUT/{name}");
        let mut args = floor.to_vec();
        args.extend(extra);
        args.extend(["--out", &dir]);
        g.case(name, &args, Some(&dir));
    }
    g.finish();
}

#[test]
fn tool_specs() {
    let mut g = Golden::new("tool", None);
    for (name, spec) in [
        ("flat", "flat:d=12"),
        ("ball", "ball:d=10"),
        ("bull", "bull:d=16,r=2,flutes=4,helix=35"),
        (
            "taper_ball",
            "taper-ball:d=6,taper=3,flute-length=20,shank=8,length=60",
        ),
        ("chamfer", "chamfer:d=10,angle=90"),
        ("drill", "drill:d=8,angle=118"),
        ("apt", "apt:10,2,3,0,5,10,40"),
    ] {
        g.case(&format!("tool_{name}"), &["tool", spec, "--json"], None);
    }
    g.case("tool_bull_text", &["tool", "bull:d=16,r=2"], None);
    g.case("tool_bad_spec", &["tool", "bull:d=16,r=9"], None);
    g.finish();
}

/// The group's cases, or `None` after the printed skip line when a file of `needs` is absent
/// from the third-party data.
fn with_shared_data<const N: usize>(group: &str, needs: [&str; N]) -> Option<Golden> {
    swarf_testdata::paths(needs)?;
    Some(Golden::new(group, Some(swarf_testdata::data_root())))
}

#[test]
fn shared_programs() {
    let programs = [
        (
            "camotics_heart",
            "gcode/camotics_heart.ngc",
            &["--tools", "$DATA/gcode/camotics_heart.camotics"][..],
        ),
        (
            "camotics_heart_cutout",
            "gcode/camotics_heart_cutout.ngc",
            &[][..],
        ),
        ("camotics_wave", "gcode/camotics_wave.gcode", &[][..]),
        (
            "linuxcnc_boat",
            "gcode/linuxcnc_boat-xyzac.ngc",
            &["--machine", "table-ac-tcp"][..],
        ),
        (
            "linuxcnc_g81",
            "gcode/linuxcnc_interp_g17-g99-g81.ngc",
            &[][..],
        ),
        ("linuxcnc_spiral", "gcode/linuxcnc_spiral.ngc", &[][..]),
        ("nx_haas", "gcode/nx_haas_vf3_testpart.ptp", &[][..]),
        ("nx_kontur", "apt/nx_1_KONTUR_NAR_40_N2.cls", &[][..]),
        (
            "swcam_paralelipipedo",
            "apt/swcam_Paralelipipedo.apt",
            &[][..],
        ),
    ];
    let needs = programs.map(|(_, file, _)| file);
    let Some(mut g) = with_shared_data("programs", needs) else {
        return;
    };
    for (name, file, setup) in programs {
        let file = format!("$DATA/{file}");
        for flag in ["--json", "--canonical"] {
            let mut args = vec!["path", &file, flag];
            args.extend(setup);
            let case = format!("path_{name}_{}", flag.trim_start_matches('-'));
            g.case(&case, &args, None);
        }
    }
    g.finish();
}

#[test]
fn shared_surfaces() {
    let surfaces = [
        (
            "toolsize_sphere_ball_inside",
            "step/llnl_revolved_sphere.step",
            &["--cutter", "ball", "--flip", "--grid", "9"][..],
        ),
        (
            "toolsize_sphere_bull_outside",
            "step/llnl_revolved_sphere.step",
            &["--cutter", "bull:r=1", "--grid", "5"][..],
        ),
        (
            "toolsize_fuselage_ball",
            "step/occt_bug28366_fuselage.stp",
            &["--cutter", "ball", "--grid", "5"][..],
        ),
        (
            "toolsize_iges_trimmed_flat",
            "iges/occt_bug29356.igs",
            &["--cutter", "flat", "--grid", "9"][..],
        ),
    ];
    let Some(mut g) = with_shared_data("surfaces", surfaces.map(|(_, file, _)| file)) else {
        return;
    };
    for (name, file, extra) in surfaces {
        let (file, dir) = (format!("$DATA/{file}"), format!("$OUT/{name}"));
        let mut args = vec!["toolsize", "--json", "--surface", &file];
        args.extend(extra);
        args.extend(["--out", &dir]);
        g.case(name, &args, Some(&dir));
    }
    g.finish();
}
