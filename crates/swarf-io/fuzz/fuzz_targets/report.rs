//! Fuzz target `report`: any folder of a command's outputs — the bytes before the first NUL
//! as its `summary.json`, those after as its `defects.csv` — gives a page or an error naming
//! the file (`swarf report --from DIR`), never a panic or a hang, and a page that is made is
//! written. Run with `cargo +nightly fuzz run report` from `crates/swarf-io`.
#![no_main]

use libfuzzer_sys::fuzz_target;
use swarf_io::html::Report;

fuzz_target!(|data: &[u8]| {
    let dir = std::env::temp_dir().join(format!("swarf-fuzz-report-{}", std::process::id()));
    let _ = std::fs::create_dir_all(&dir);
    let (summary, csv) = match data.iter().position(|&b| b == 0) {
        Some(i) => (&data[..i], &data[i + 1..]),
        None => (data, &[][..]),
    };
    std::fs::write(dir.join("summary.json"), summary).expect("temporary folder");
    std::fs::write(dir.join("defects.csv"), csv).expect("temporary folder");
    if let Ok(page) = Report::from_dir(&dir) {
        page.write(&dir.join("report.html"))
            .expect("the page is written");
    }
});
