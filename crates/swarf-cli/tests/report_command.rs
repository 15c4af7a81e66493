//! `swarf verify --report`: one self-contained HTML page whose figures equal the JSON, which
//! escapes what comes from the inputs, and which a real headless browser (Debian's chromium)
//! loads without console errors, drawing a canvas that is not blank. Without chromium the
//! browser test says so and passes (`apt-get install chromium` to run it).
mod common;
use common::*;
use std::path::{Path, PathBuf};
use std::process::Command;

fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("swarf-report-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A 0.3 mm deep slot in a faced design top (as in `verify_command.rs`), its line carrying a
/// comment that would be a script if it were not escaped. Writes the report; returns it, the
/// summary (parsed, and as printed) and the folder.
fn report(name: &str) -> (String, serde_json::Value, String, PathBuf) {
    let dir = temp_dir(name);
    let mut s = String::from("G21 G90\nG0 Z20\nG0 X10 Y17\nG1 Z10 F500\n");
    let mut y = 17.0;
    let mut left = true;
    while y <= 65.0 {
        s += &format!("G1 X{} Y{y}\n", if left { 70 } else { 10 });
        y += 8.0;
        if y <= 65.0 {
            s += &format!("G1 Y{y}\n");
        }
        left = !left;
    }
    s += "G0 Z20\nG0 X30 Y40\nG1 Z9.7 F200 ; (<script>alert(1)</script>)\nG1 X50\nG0 Z20\nM30\n";
    let prog = dir.join("evil.ngc");
    std::fs::write(&prog, s).unwrap();
    let part = dir.join("part.stl");
    std::fs::write(
        &part,
        boxes_stl(&[[[20.0, 20.0, 0.0], [60.0, 60.0, 10.0]]], 0),
    )
    .unwrap();
    let html = dir.join("report.html");
    let o = swarf(&[
        "verify",
        "--stock",
        "box:20,20,0,60,60,12",
        "--program",
        prog.to_str().unwrap(),
        "--tool",
        "ball:d=10",
        "--design",
        part.to_str().unwrap(),
        "--out",
        dir.join("out").to_str().unwrap(),
        "--report",
        html.to_str().unwrap(),
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    (
        std::fs::read_to_string(&html).unwrap(),
        json(&o),
        stdout(&o),
        dir,
    )
}

/// The text of `<td data-key="KEY">…</td>`.
fn figure(html: &str, key: &str) -> String {
    let tag = format!("<td data-key=\"{key}\">");
    let start = html.find(&tag).unwrap_or_else(|| panic!("no figure {key}")) + tag.len();
    html[start..start + html[start..].find("</td>").unwrap()].to_string()
}

#[test]
fn figures_equal_the_json_and_inputs_are_escaped() {
    let (html, j, printed, _) = report("figures");
    for key in [
        "max_gouge_mm",
        "max_excess_mm",
        "gouge_regions",
        "excess_regions",
        "excess_volume_mm3",
        "tolerance_mm",
        "collisions",
    ] {
        // The number exactly as the JSON prints it (parsing it back may move the last bit).
        let tag = format!("\n  \"{key}\": ");
        let at = printed.find(&tag).unwrap() + tag.len();
        let text = printed[at..].split([',', '\n']).next().unwrap();
        assert_eq!(figure(&html, key), text, "{key}");
    }
    assert!(j["gouge_regions"].as_u64().unwrap() >= 1);
    // The comment shows as text; the page's only scripts are its own three.
    assert!(!html.contains("<script>alert"), "unescaped program comment");
    assert!(html.contains("(&lt;script&gt;alert(1)&lt;/script&gt;)"));
    assert_eq!(html.matches("<script").count(), 3);
    // Self-contained: no external resource.
    for needle in ["src=\"http", "href=\"http", "src=\"//", "@import", "<link"] {
        assert!(!html.contains(needle), "{needle}");
    }
}

fn chromium() -> Option<PathBuf> {
    ["chromium", "chromium-browser", "google-chrome"]
        .iter()
        .find_map(|name| {
            let out = Command::new("which").arg(name).output().ok()?;
            out.status
                .success()
                .then(|| PathBuf::from(String::from_utf8_lossy(&out.stdout).trim()))
        })
}

fn headless(browser: &Path, extra: &[&str], url: &str) -> std::process::Output {
    Command::new(browser)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-dev-shm-usage",
            "--use-angle=swiftshader",
            "--enable-unsafe-swiftshader",
            "--enable-logging=stderr",
            "--v=0",
            "--window-size=1400,1000",
            "--virtual-time-budget=8000",
        ])
        .args(extra)
        .arg(url)
        .output()
        .expect("chromium runs")
}

#[test]
fn the_page_loads_in_a_real_browser_and_draws() {
    let Some(browser) = chromium() else {
        eprintln!(
            "SKIPPED: no chromium on this machine (apt-get install chromium); the report was \
             not loaded in a browser"
        );
        return;
    };
    let (_, _, _, dir) = report("browser");
    let url = format!("file://{}", dir.join("report.html").display());
    // The DOM after the scripts ran: the viewer finished loading its data.
    let o = headless(&browser, &["--dump-dom"], &url);
    let dom = stdout(&o);
    let log = stderr(&o);
    assert!(
        dom.contains("data-viewer=\"ready\""),
        "viewer not ready; log:\n{log}"
    );
    for bad in ["Uncaught", "CONSOLE", ":ERROR:CONSOLE"] {
        let errors: Vec<&str> = log
            .lines()
            .filter(|l| l.contains(bad) && (l.contains("Uncaught") || l.contains("Error")))
            .collect();
        assert!(errors.is_empty(), "console errors:\n{}", errors.join("\n"));
    }
    // A screenshot: the canvas area (top of the left column) is not blank.
    let shot = dir.join("shot.png");
    let o = headless(
        &browser,
        &[&format!("--screenshot={}", shot.display())],
        &url,
    );
    assert!(shot.exists(), "no screenshot: {}", stderr(&o));
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&shot).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).unwrap();
    let ch = info.color_type.samples();
    let (w, h) = (info.width as usize, info.height as usize);
    let mut colours = std::collections::HashSet::new();
    let (mut coloured, mut total) = (0usize, 0usize);
    for y in 130.min(h)..600.min(h) {
        for x in 40.min(w)..800.min(w) {
            let p = &buf[(y * w + x) * ch..(y * w + x) * ch + 3];
            colours.insert([p[0], p[1], p[2]]);
            total += 1;
            let (mx, mn) = (p.iter().max().unwrap(), p.iter().min().unwrap());
            if mx - mn > 40 {
                coloured += 1; // saturated: the deviation colours, the toolpath, markers
            }
        }
    }
    assert!(
        colours.len() > 50 && coloured * 200 > total,
        "the 3-D view looks blank: {} colours, {coloured} of {total} pixels coloured",
        colours.len()
    );
}
