//! Helpers shared by the CLI tests: run the built `swarf` binary and read shared data.
#![allow(dead_code)]

use std::process::{Command, Output};

/// Runs `swarf` with the arguments and returns its output.
pub(crate) fn swarf(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_swarf"))
        .args(args)
        .output()
        .expect("swarf runs")
}

/// Path of a file in the third-party test data (`SWARF_TEST_DATA`), or `None` after the
/// printed line that says why the calling test skips.
pub(crate) fn shared(rel: &str) -> Option<String> {
    swarf_testdata::path(rel).map(|p| p.display().to_string())
}

/// A folder of its own for the calling test under the system's temporary folder, empty.
pub(crate) fn temp_dir(name: &str) -> std::path::PathBuf {
    swarf_testdata::fresh_scratch_dir(&format!("cli-{name}"))
}

/// Writes `dir/sphere.step`, [`swarf_testdata::fixtures::sphere_step`] of radius `r` mm;
/// returns its path.
pub(crate) fn sphere_step(dir: &std::path::Path, r: f64) -> String {
    let path = dir.join("sphere.step");
    std::fs::write(&path, swarf_testdata::fixtures::sphere_step(r)).unwrap();
    path.display().to_string()
}

/// Stdout as text.
pub(crate) fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// Stderr as text.
pub(crate) fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Parses stdout as JSON, failing the test with stderr when it is not.
pub(crate) fn json(o: &Output) -> serde_json::Value {
    serde_json::from_slice(&o.stdout)
        .unwrap_or_else(|e| panic!("stdout is not JSON ({e}); stderr: {}", stderr(o)))
}

/// Runs `swarf` with `args`, `--out out --json` and `extra` (`--merge-planar`, `--simplify MM`):
/// its JSON summary and the mesh `out/stl` read back, which must be closed.
pub(crate) fn run_mesh(
    args: &[&str],
    out: &std::path::Path,
    extra: &[&str],
    stl: &str,
) -> (serde_json::Value, swarf_io::TriMesh) {
    let mut all = args.to_vec();
    all.extend(["--out", out.to_str().unwrap(), "--json"]);
    all.extend_from_slice(extra);
    let o = swarf(&all);
    assert!(o.status.success(), "{}", stderr(&o));
    let mesh = swarf_io::read_stl(&out.join(stl)).unwrap();
    assert!(mesh.is_closed());
    (json(&o), mesh)
}

/// Closed boxes `[lo, hi]` as ASCII STL, counter-clockwise seen from outside; `drop` triangles
/// left out at the end (an open mesh when > 0).
pub(crate) fn boxes_stl(boxes: &[[[f64; 3]; 2]], drop: usize) -> String {
    let mut tris: Vec<[[f64; 3]; 3]> = Vec::new();
    for [lo, hi] in boxes {
        let m = swarf_io::TriMesh::cuboid((*lo).into(), (*hi).into());
        tris.extend(
            m.triangles
                .iter()
                .map(|t| t.map(|i| m.vertices[i as usize].to_array())),
        );
    }
    let mut s = String::from("solid boxes\n");
    for t in &tris[..tris.len() - drop] {
        s.push_str("  facet normal 0 0 0\n    outer loop\n");
        for p in t {
            s.push_str(&format!("      vertex {} {} {}\n", p[0], p[1], p[2]));
        }
        s.push_str("    endloop\n  endfacet\n");
    }
    s.push_str("endsolid boxes\n");
    s
}

/// Runs `swarf` with the arguments and its stdout closed before it writes anything (a reader
/// that went away, as `| head` does): its exit status and stderr.
pub(crate) fn swarf_into_closed_pipe(args: &[&str]) -> (std::process::ExitStatus, String) {
    use std::io::Read;
    let mut child = Command::new(env!("CARGO_BIN_EXE_swarf"))
        .args(args)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("swarf runs");
    drop(child.stdout.take());
    let mut err = String::new();
    child
        .stderr
        .take()
        .expect("stderr piped")
        .read_to_string(&mut err)
        .expect("stderr read");
    (child.wait().expect("swarf ends"), err)
}
