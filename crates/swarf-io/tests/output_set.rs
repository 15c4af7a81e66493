//! Output sets: sizes refused before anything is written, all files or none, no temporaries
//! left behind, earlier files kept when a new set fails.

use std::io::Write;
use swarf_io::{IoError, OutputSet};

fn temp_dir(name: &str) -> std::path::PathBuf {
    // Fresh and absent: the tests make it as a set's first write does.
    let d = swarf_testdata::fresh_scratch_dir(&format!("io-set-{name}"));
    let _ = std::fs::remove_dir_all(&d);
    d
}

fn names(dir: &std::path::Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .map(|r| {
            r.map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                .collect()
        })
        .unwrap_or_default();
    v.sort();
    v
}

#[test]
fn a_set_over_the_limit_writes_nothing_and_names_every_size() {
    let d = temp_dir("limit");
    let set = OutputSet::new(&d, 1000).unwrap();
    let e = set
        .check_sizes(&[("a.stl", 900), ("b.glb", 200)])
        .unwrap_err();
    assert!(matches!(e, IoError::TooLarge { .. }));
    let m = e.to_string();
    for part in [
        "1.1 kB",
        "a.stl 900 B",
        "b.glb 200 B",
        "limit of 1.0 kB",
        "nothing was written",
    ] {
        assert!(m.contains(part), "{part:?} in {m}");
    }
    drop(set);
    assert!(!d.exists(), "not even the folder is made");
    set_ok(&d, 1100);
}

fn set_ok(d: &std::path::Path, limit: u64) {
    let set = OutputSet::new(d, limit).unwrap();
    set.check_sizes(&[("a.stl", 900), ("b.glb", 200)]).unwrap();
}

#[test]
fn a_failing_file_leaves_the_previous_set_untouched() {
    let d = temp_dir("fail");
    let mut set = OutputSet::new(&d, u64::MAX).unwrap();
    set.write_bytes("a.txt", b"old a").unwrap();
    set.write_bytes("sub/b.txt", b"old b").unwrap();
    set.commit().unwrap();
    assert_eq!(names(&d), ["a.txt", "sub"]);

    // The second file fails while being written: nothing changes.
    let mut set = OutputSet::new(&d, u64::MAX).unwrap();
    set.write_bytes("a.txt", b"new a").unwrap();
    let e = set
        .write("sub/b.txt", |w| {
            w.write_all(b"half")?;
            Err(std::io::Error::other("disk full"))
        })
        .unwrap_err();
    assert!(e.to_string().contains("disk full"), "{e}");
    drop(set);
    assert_eq!(std::fs::read_to_string(d.join("a.txt")).unwrap(), "old a");
    assert_eq!(
        std::fs::read_to_string(d.join("sub/b.txt")).unwrap(),
        "old b"
    );
    assert_eq!(names(&d), ["a.txt", "sub"], "no temporary left");
    assert_eq!(names(&d.join("sub")), ["b.txt"]);

    // A folder in the way of the last file: the set fails before any rename.
    std::fs::create_dir_all(d.join("c.txt")).unwrap();
    let mut set = OutputSet::new(&d, u64::MAX).unwrap();
    set.write_bytes("a.txt", b"new a").unwrap();
    assert!(set.write_bytes("c.txt", b"c").is_err());
    drop(set);
    assert_eq!(std::fs::read_to_string(d.join("a.txt")).unwrap(), "old a");
    assert_eq!(names(&d), ["a.txt", "c.txt", "sub"]);

    // A set that succeeds replaces every file.
    let mut set = OutputSet::new(&d, u64::MAX).unwrap();
    set.write_bytes("a.txt", b"new a").unwrap();
    set.write_bytes("sub/b.txt", b"new b").unwrap();
    assert_eq!(std::fs::read_to_string(d.join("a.txt")).unwrap(), "old a");
    set.commit().unwrap();
    assert_eq!(std::fs::read_to_string(d.join("a.txt")).unwrap(), "new a");
    assert_eq!(
        std::fs::read_to_string(d.join("sub/b.txt")).unwrap(),
        "new b"
    );
    assert_eq!(
        names(&d),
        ["a.txt", "c.txt", "sub"],
        "no temporary or backup left"
    );
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn files_written_side_by_side_appear_together_or_not_at_all() {
    let d = temp_dir("side");
    let mut set = OutputSet::new(&d, u64::MAX).unwrap();
    let big = vec![7u8; 3 << 20];
    set.write_all(vec![
        ("a.bin", Box::new(|w| w.write_all(&big))),
        ("b.txt", Box::new(|w| w.write_all(b"b"))),
    ])
    .unwrap();
    assert!(
        !d.join("a.bin").exists() && !d.join("b.txt").exists(),
        "nothing appears before the commit"
    );
    set.commit().unwrap();
    assert_eq!(names(&d), ["a.bin", "b.txt"]);
    assert_eq!(std::fs::read(d.join("a.bin")).unwrap(), big);
    // One of them fails: its error (the first in order), and the old files stay as they were.
    let mut set = OutputSet::new(&d, u64::MAX).unwrap();
    let e = set
        .write_all(vec![
            ("a.bin", Box::new(|w| w.write_all(b"new a"))),
            (
                "b.txt",
                Box::new(|_| Err(std::io::Error::other("disk on fire"))),
            ),
        ])
        .unwrap_err();
    assert!(
        e.to_string().contains("b.txt") && e.to_string().contains("disk on fire"),
        "{e}"
    );
    drop(set);
    assert_eq!(names(&d), ["a.bin", "b.txt"]);
    assert_eq!(std::fs::read(d.join("a.bin")).unwrap(), big);
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn owned_files_are_this_runs_only() {
    let d = temp_dir("owned");
    let write = |files: &[&str]| {
        let mut set = OutputSet::new(&d, 1 << 20).unwrap();
        set.owns_files("maps", &["location_", "largest"]);
        for f in files {
            set.write(f, |w| w.write_all(b"x")).unwrap();
        }
        set.commit().unwrap();
    };
    write(&["summary.json", "maps/location_5.png", "maps/location_9.png"]);
    // The user's own files beside them, and a hidden one.
    std::fs::write(d.join("notes.txt"), "mine").unwrap();
    std::fs::write(d.join("maps/mine.png"), "mine").unwrap();
    std::fs::write(d.join("maps/location_notes.txt"), "mine").unwrap();
    std::fs::write(d.join("maps/.hidden"), "kept").unwrap();
    write(&["summary.json", "maps/location_9.png"]);
    assert_eq!(
        names(&d.join("maps")),
        [
            ".hidden",
            "location_9.png",
            "location_notes.txt",
            "mine.png"
        ]
    );
    assert_eq!(names(&d), ["maps", "notes.txt", "summary.json"]);
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn a_set_asked_to_stop_starts_no_file_and_leaves_nothing() {
    static STOP: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);
    let d = temp_dir("stop");
    std::fs::create_dir_all(&d).unwrap();
    std::fs::write(d.join("a.txt"), "old\n").unwrap();
    let mut set = OutputSet::new(&d, 1 << 20).unwrap();
    set.stop_when(&STOP);
    set.write("a.txt", |w| w.write_all(b"new\n")).unwrap();
    // Ctrl-C between two files: the next one is not started, the set's temporary goes, the
    // earlier output stays as it was.
    STOP.store(true, std::sync::atomic::Ordering::SeqCst);
    let e = set.write("b.txt", |w| w.write_all(b"b\n")).unwrap_err();
    assert!(matches!(e, IoError::Stopped { .. }), "{e}");
    assert!(e.to_string().contains("nothing was written"), "{e}");
    drop(set);
    assert_eq!(names(&d), ["a.txt"]);
    assert_eq!(std::fs::read_to_string(d.join("a.txt")).unwrap(), "old\n");
    // Asked to stop after its files were written: the commit renames none of them.
    let mut set = OutputSet::new(&d, 1 << 20).unwrap();
    set.write("c.txt", |w| w.write_all(b"c\n")).unwrap();
    set.stop_when(&STOP);
    assert!(matches!(set.commit(), Err(IoError::Stopped { .. })));
    assert_eq!(names(&d), ["a.txt"]);
    std::fs::remove_dir_all(&d).unwrap();
}

/// A file where a subfolder of the set must go is named as such (it was "File exists (os
/// error 17)"), and the set writes nothing.
#[test]
fn a_file_in_the_way_of_a_subfolder_is_named() {
    let d = temp_dir("file-in-the-way");
    std::fs::create_dir_all(&d).unwrap();
    std::fs::write(d.join("maps"), b"not a folder").unwrap();
    let mut set = OutputSet::new(&d, 1_000_000).unwrap();
    let e = set
        .write_bytes("maps/a.png", b"png")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("maps") && e.contains("a file has the name of the output's folder"),
        "{e}"
    );
    drop(set);
    assert_eq!(names(&d), ["maps"]);
    assert_eq!(std::fs::read(d.join("maps")).unwrap(), b"not a folder");
}
