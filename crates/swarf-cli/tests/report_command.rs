//! `swarf verify --report`: one self-contained HTML page whose figures equal the JSON, which
//! escapes what comes from the inputs, and which a real headless browser (Debian's chromium)
//! loads without console errors, drawing a canvas that is not blank. Without chromium the
//! browser test says so and passes (`apt-get install chromium` to run it).
mod common;
use common::*;
use std::path::{Path, PathBuf};
use std::process::Command;

fn report_dir(name: &str) -> PathBuf {
    let d = swarf_testdata::scratch_dir(&format!("report-{name}"));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A 0.3 mm deep slot in a faced design top (as in `verify_command.rs`), its line carrying a
/// comment that would be a script if it were not escaped. Writes the report; returns it, the
/// summary (parsed, and as printed) and the folder.
fn report(name: &str) -> (String, serde_json::Value, String, PathBuf) {
    let dir = report_dir(name);
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
    let (html, j, printed, dir) = report("figures");
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
    // Every top-level figure, not a list of twelve (the design's reach beyond the stock, the
    // ray ends and the reader's caveats among them), in the JSON's order.
    assert!(figures_equal(&html, &printed) >= 22);
    for key in [
        "design_beyond_stock_box",
        "design_outside_stock_mm3",
        "ends_unmatched",
        "gouge_ends",
        "excess_ends",
        "skipped_faces",
        "untrimmed_faces",
        "unapplied_placements",
    ] {
        figure(&html, key);
    }
    assert_eq!(figure_keys(&html), top_level_keys(&printed, &html));
    // `swarf report --from` the output folder: the same figures, as summary.json writes them,
    // in its order (it showed them alphabetically, some numbers read and written otherwise).
    let out = dir.join("out");
    let o = swarf(&["report", "--from", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let from = std::fs::read_to_string(out.join("report.html")).unwrap();
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert_eq!(
        figures_equal(&from, &summary),
        figures_equal(&html, &printed)
    );
    assert_eq!(figure_keys(&from), figure_keys(&html));
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

/// What a headless browser made of a page: the viewer loaded without console errors (asserted
/// here); the screenshot's canvas area (top of the left column): distinct colours, saturated
/// pixels, pixels that are not white, pixels. `None` (after a printed line) without chromium.
fn browser_check(page: &Path) -> Option<(usize, usize, usize, usize)> {
    let Some(browser) = chromium() else {
        eprintln!(
            "SKIPPED: no chromium on this machine (apt-get install chromium); the report was \
             not loaded in a browser"
        );
        return None;
    };
    let url = format!("file://{}", page.display());
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
    // A screenshot of the canvas area.
    let shot = page.with_extension("png");
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
    let (mut coloured, mut drawn, mut total) = (0usize, 0usize, 0usize);
    for y in 130.min(h)..600.min(h) {
        for x in 40.min(w)..800.min(w) {
            let p = &buf[(y * w + x) * ch..(y * w + x) * ch + 3];
            colours.insert([p[0], p[1], p[2]]);
            total += 1;
            let (mx, mn) = (p.iter().max().unwrap(), p.iter().min().unwrap());
            if mx - mn > 40 {
                coloured += 1; // saturated: the deviation colours, the toolpath, markers
            }
            if *mn < 235 {
                drawn += 1;
            }
        }
    }
    Some((colours.len(), coloured, drawn, total))
}

#[test]
fn the_page_loads_in_a_real_browser_and_draws() {
    let (_, _, _, dir) = report("browser");
    let Some((colours, coloured, _, total)) = browser_check(&dir.join("report.html")) else {
        return;
    };
    assert!(
        colours > 50 && coloured * 200 > total,
        "the 3-D view looks blank: {colours} colours, {coloured} of {total} pixels coloured"
    );
}

// ---- `--report` on the other commands, and `swarf report --from DIR` ----

/// A file name that would be markup if it were not escaped (no `/`: it is one path component).
const EVIL_NAME: &str = "<img src=x onerror=alert(1)>";
/// A program comment that would be a script if it were not escaped.
const EVIL_COMMENT: &str = "; (<script>alert(1)</script>)";

/// `s` as the page escapes element content.
fn escaped(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
        .replace('\'', "&#39;")
}

/// Every top-level figure of a JSON summary (as printed, pretty) is on the page with the
/// JSON's own text (strings escaped), and the page has no other figure; returns their number.
fn figures_equal(html: &str, printed: &str) -> usize {
    let v: serde_json::Value = serde_json::from_str(printed).unwrap();
    let mut n = 0;
    for (key, x) in v.as_object().unwrap() {
        let expect = match x {
            serde_json::Value::Object(_) => continue,
            serde_json::Value::Array(a)
                if a.len() > 4 || a.iter().any(|y| y.is_array() || y.is_object()) =>
            {
                continue
            }
            serde_json::Value::Array(_) => x.to_string(),
            serde_json::Value::String(s) => escaped(s),
            _ => {
                let tag = format!("\n  \"{key}\": ");
                let at = printed.find(&tag).unwrap() + tag.len();
                printed[at..].split([',', '\n']).next().unwrap().to_string()
            }
        };
        assert_eq!(figure(html, key), expect, "{key}");
        n += 1;
    }
    assert_eq!(
        html.matches("<td data-key=").count(),
        n,
        "figures not in the JSON"
    );
    n
}

/// The keys of the page's figures, in its order.
fn figure_keys(html: &str) -> Vec<String> {
    html.split("<td data-key=\"")
        .skip(1)
        .map(|s| s[..s.find('"').unwrap()].to_string())
        .collect()
}

/// The top-level keys of a pretty-printed JSON object that the page shows, in the text's
/// order.
fn top_level_keys(printed: &str, html: &str) -> Vec<String> {
    printed
        .lines()
        .filter_map(|l| l.strip_prefix("  \""))
        .filter_map(|l| l.split_once("\": ").map(|(k, _)| k.to_string()))
        .filter(|k| html.contains(&format!("<td data-key=\"{k}\">")))
        .collect()
}

/// Offline, self-contained, and nothing from the inputs became markup.
fn safe(html: &str) {
    assert_eq!(
        html.matches("<script").count(),
        3,
        "scripts besides the page's own"
    );
    for needle in [
        "src=\"http",
        "href=\"http",
        "src=\"//",
        "@import",
        "<link",
        "<img src=x",
    ] {
        assert!(!html.contains(needle), "{needle}");
    }
    assert!(
        html.contains(&escaped(EVIL_NAME)),
        "the file name is not shown escaped"
    );
}

/// Embedded PNG images.
fn images(html: &str) -> usize {
    html.matches("src=\"data:image/png;base64,").count()
}

/// PNG files under `dir`.
fn pngs(dir: &Path) -> usize {
    std::fs::read_dir(dir)
        .map(|rd| {
            rd.filter_map(|e| e.ok())
                .filter(|e| e.path().extension().is_some_and(|x| x == "png"))
                .count()
        })
        .unwrap_or(0)
}

/// Rows of the page's defect list.
fn rows(html: &str) -> usize {
    html.matches("<tr class=\"row\"").count()
}

const MATERIAL: &str = "name = \"Al (test)\"\nktc = 796\nkrc = 168.8\nkac = 222\nkte = 27.7\nkre = 30.8\nkae = 1.8\nsource = \"test <values>\"\n";

/// A slot through a 40 × 20 × 10 box; the first rapid (line 3) enters the stock.
fn slot(dir: &Path) -> String {
    let p = dir.join(format!("slot{EVIL_NAME}.ngc"));
    std::fs::write(
        &p,
        format!("G21 G90 G94\nS1000 M3\nG0 X-10 Y10 Z-4 {EVIL_COMMENT}\nG1 X50 F400\nG0 Z10\n"),
    )
    .unwrap();
    p.to_str().unwrap().to_string()
}

/// Runs `swarf ARGS --report DIR/NAME.html --json`; returns the page and the printed JSON.
fn page(dir: &Path, name: &str, args: &[&str]) -> (String, String) {
    let html = dir.join(format!("{name}.html"));
    let mut all = args.to_vec();
    all.extend(["--report", html.to_str().unwrap(), "--json"]);
    let o = swarf(&all);
    assert!(o.status.success(), "{}", stderr(&o));
    (std::fs::read_to_string(&html).unwrap(), stdout(&o))
}

#[test]
fn simulate_report_and_report_from_its_folder() {
    let dir = temp_dir("simulate");
    let prog = slot(&dir);
    let out = dir.join("out");
    let (html, printed) = page(
        &dir,
        "simulate",
        &[
            "simulate",
            "--stock",
            "box:0,0,-10,40,20,0",
            "--program",
            &prog,
            "--tool",
            "flat:d=10",
            "--out",
            out.to_str().unwrap(),
        ],
    );
    assert!(figures_equal(&html, &printed) >= 9);
    safe(&html);
    // The rapid collision, linked to its line, whose comment shows as text.
    let j: serde_json::Value = serde_json::from_str(&printed).unwrap();
    assert_eq!(j["rapid_collisions"], 1);
    assert_eq!(rows(&html), 1);
    assert!(html.contains(&escaped(EVIL_COMMENT)));
    assert!(!html.contains("<script>alert"));
    assert!(html.contains("\"name\":\"machined stock\""));
    assert!(
        html.contains("<figcaption>T0 flat:d=10,"),
        "the tool is not drawn"
    );

    // `swarf report --from DIR`: the same figures from summary.json, the machined stock.
    let o = swarf(&["report", "--from", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let from = std::fs::read_to_string(out.join("report.html")).unwrap();
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert!(figures_equal(&from, &summary) >= 9);
    assert!(from.contains("\"name\":\"stock.stl\""));
    assert_eq!(from.matches("<script").count(), 3);
    // A folder without summary.json is refused with a message naming it.
    let o = swarf(&["report", "--from", dir.to_str().unwrap()]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("summary.json"), "{}", stderr(&o));
}

#[test]
fn engage_and_forces_reports_embed_their_plots() {
    let dir = temp_dir("engage");
    let prog = slot(&dir);
    let run = [
        "--stock",
        "box:0,0,-10,40,20,0",
        "--program",
        &prog,
        "--tool",
        "flat:d=10,flutes=4,helix=30",
        "--resolution",
        "0.25",
    ];
    let out = dir.join("engage");
    let mut args = vec!["engage"];
    args.extend(run);
    args.extend(["--out", out.to_str().unwrap()]);
    let (html, printed) = page(&dir, "engage", &args);
    assert!(figures_equal(&html, &printed) >= 7);
    safe(&html);
    let maps = pngs(&out.join("maps"));
    assert!(maps >= 3, "{maps}"); // largest, area, mrr
    assert_eq!(images(&html), maps);
    assert!(html.contains("<h2>area.png</h2>") && html.contains("<h2>largest.png</h2>"));

    let material = dir.join("al.toml");
    std::fs::write(&material, MATERIAL).unwrap();
    let out = dir.join("forces");
    let mut args = vec!["forces"];
    args.extend(run);
    args.extend([
        "--coefficients",
        material.to_str().unwrap(),
        "--curves-at",
        "25",
        "--out",
        out.to_str().unwrap(),
    ]);
    let (html, printed) = page(&dir, "forces", &args);
    assert!(figures_equal(&html, &printed) >= 6);
    safe(&html);
    assert!(html.contains("test &lt;values&gt;"));
    assert_eq!(images(&html), 4); // peak force, torque, power, the curves at 25
    assert!(html.contains("<h2>curves_location_25.png</h2>"));
}

/// The gouge scene of `gouge_command.rs` (a floor, a plunge 0.5 mm into it at line 6).
fn gouge_page(dir: &Path) -> (String, String, PathBuf) {
    let floor = dir.join(format!("floor{EVIL_NAME}.json"));
    std::fs::write(
        &floor,
        r#"{"units": "mm", "patches": [{"name": "floor", "degree_u": 1,
  "degree_v": 1, "knots_u": [0, 0, 1, 1], "knots_v": [0, 0, 1, 1],
  "control_points": [[[-40, -40, 0, 1], [-40, 40, 0, 1]], [[40, -40, 0, 1], [40, 40, 0, 1]]]}]}"#,
    )
    .unwrap();
    let prog = dir.join(format!("job{EVIL_NAME}.ngc"));
    std::fs::write(
        &prog,
        format!("G0 X-15 Y0 Z5\nG1 Z0 F300\nG1 X6\nG0 Z5\nG0 X-30 Y-30\nG1 Z-0.5 {EVIL_COMMENT}\nG0 Z5\n"),
    )
    .unwrap();
    let out = dir.join("out");
    let (html, printed) = page(
        dir,
        "gouge",
        &[
            "gouge",
            "--surface",
            floor.to_str().unwrap(),
            "--program",
            prog.to_str().unwrap(),
            "--tool",
            "flat:d=10",
            "--out",
            out.to_str().unwrap(),
        ],
    );
    (html, printed, out)
}

#[test]
fn gouge_report_links_violations_to_lines() {
    let dir = temp_dir("gouge");
    let (html, printed, out) = gouge_page(&dir);
    assert!(figures_equal(&html, &printed) >= 8);
    safe(&html);
    let j: serde_json::Value = serde_json::from_str(&printed).unwrap();
    let n = j["violations"].as_u64().unwrap() as usize;
    assert!(n >= 1 && j["gouging_moves"].as_u64().unwrap() >= 1);
    assert_eq!(rows(&html), n);
    // The plunge's line and its comment, as text.
    assert!(html.contains(&format!("{}.ngc:6</td>", escaped(EVIL_NAME))));
    assert!(html.contains(&escaped(EVIL_COMMENT)));
    assert!(!html.contains("<script>alert"));
    assert!(html.contains("\"name\":\"part surface\""));
    // `swarf report --from` the same folder lists violations.csv's rows.
    let page = dir.join("from.html");
    let o = swarf(&[
        "report",
        "--from",
        out.to_str().unwrap(),
        "--out",
        page.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let from = std::fs::read_to_string(&page).unwrap();
    let csv = std::fs::read_to_string(out.join("violations.csv")).unwrap();
    assert_eq!(rows(&from), csv.lines().count() - 1);
    assert!(
        from.contains(&escaped(EVIL_COMMENT)),
        "the violation's line is not shown"
    );
    assert_eq!(from.matches("<script").count(), 3);
}

/// The page shows the program lines its rows name as the reader numbers and decodes them: a
/// program with lone `\r` line ends (old Mac editors), and one saved as UTF-16 with a
/// byte-order mark (Windows "Unicode" text). Before, the first was one line on the page and
/// the second was not read, so the plunge's line 6 showed empty.
#[test]
fn report_lines_of_lone_cr_and_utf16_programs() {
    let dir = temp_dir("report-line-ends");
    let floor = dir.join("floor.json");
    std::fs::write(
        &floor,
        r#"{"units": "mm", "patches": [{"name": "floor", "degree_u": 1,
  "degree_v": 1, "knots_u": [0, 0, 1, 1], "knots_v": [0, 0, 1, 1],
  "control_points": [[[-40, -40, 0, 1], [-40, 40, 0, 1]], [[40, -40, 0, 1], [40, 40, 0, 1]]]}]}"#,
    )
    .unwrap();
    let text =
        "G0 X-15 Y0 Z5\nG1 Z0 F300\nG1 X6\nG0 Z5\nG0 X-30 Y-30\nG1 Z-0.5 (the plunge)\nG0 Z5\n";
    let utf16: Vec<u8> = [0xFF, 0xFE]
        .into_iter()
        .chain(
            text.replace('\n', "\r\n")
                .encode_utf16()
                .flat_map(u16::to_le_bytes),
        )
        .collect();
    for (name, bytes) in [
        ("cr.ngc", text.replace('\n', "\r").into_bytes()),
        ("utf16.ngc", utf16),
    ] {
        let prog = dir.join(name);
        std::fs::write(&prog, bytes).unwrap();
        let out = dir.join(format!("out-{name}"));
        let (html, _) = page(
            &dir,
            name,
            &[
                "gouge",
                "--surface",
                floor.to_str().unwrap(),
                "--program",
                prog.to_str().unwrap(),
                "--tool",
                "flat:d=10",
                "--out",
                out.to_str().unwrap(),
            ],
        );
        let shown = format!("{}:6: G1 Z-0.5 (the plunge)</span>", prog.display());
        assert!(html.contains(&shown), "{name}: line 6 not shown");
        let from = dir.join(format!("from-{name}.html"));
        let o = swarf(&[
            "report",
            "--from",
            out.to_str().unwrap(),
            "--out",
            from.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        let from = std::fs::read_to_string(&from).unwrap();
        assert!(
            from.contains(&shown),
            "{name}: line 6 not shown by report --from"
        );
    }
}

#[test]
fn toolsize_report_shows_the_part_and_its_maps() {
    let dir = temp_dir("toolsize");
    let sphere = sphere_step(&dir, 5.0);
    let evil = dir.join(format!("sphere{EVIL_NAME}.step"));
    std::fs::rename(&sphere, &evil).unwrap();
    let out = dir.join("out");
    let (html, printed) = page(
        &dir,
        "toolsize",
        &[
            "toolsize",
            "--surface",
            evil.to_str().unwrap(),
            "--cutter",
            "ball",
            "--flip",
            "--grid",
            "5",
            "--out",
            out.to_str().unwrap(),
        ],
    );
    assert!(figures_equal(&html, &printed) >= 5);
    safe(&html);
    let maps = pngs(&out.join("maps"));
    assert!(maps >= 1);
    assert_eq!(images(&html), maps);
    assert!(html.contains("\"name\":\"part coloured by allowable radius\""));
}

#[test]
fn simulate_and_gouge_pages_load_in_a_real_browser_and_draw() {
    let dir = temp_dir("browser-pages");
    let prog = slot(&dir);
    let _ = page(
        &dir,
        "simulate",
        &[
            "simulate",
            "--stock",
            "box:0,0,-10,40,20,0",
            "--program",
            &prog,
            "--tool",
            "flat:d=10",
        ],
    );
    let _ = gouge_page(&dir);
    for name in ["simulate", "gouge"] {
        let Some((colours, _, drawn, total)) = browser_check(&dir.join(format!("{name}.html")))
        else {
            return;
        };
        assert!(
            colours > 20 && drawn * 50 > total,
            "{name}: the 3-D view looks blank: {colours} colours, {drawn} of {total} pixels drawn"
        );
    }
}

/// `swarf report --from D --out D/summary.json` would write the page over a result the report
/// reads: refused, the summary kept; an .html name beside it is written.
#[test]
fn the_page_never_replaces_a_result() {
    let (_, _, _, dir) = report("no-overwrite");
    let out = dir.join("out");
    let summary = out.join("summary.json");
    let before = std::fs::read_to_string(&summary).unwrap();
    let o = swarf(&[
        "report",
        "--from",
        out.to_str().unwrap(),
        "--out",
        summary.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("would replace one of the results"),
        "{}",
        stderr(&o)
    );
    assert_eq!(std::fs::read_to_string(&summary).unwrap(), before);
    let page = out.join("again.html");
    let o = swarf(&[
        "report",
        "--from",
        out.to_str().unwrap(),
        "--out",
        page.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(page.is_file());
}

/// `--report` names an HTML page: given the run's own program or one of its results it is
/// refused before any work, and the file is left as it was (it was replaced by the page, exit
/// 0).
#[test]
fn a_report_never_replaces_an_input_or_a_result() {
    let dir = report_dir("not-html");
    let prog = dir.join("job.ngc");
    let text = "G21 G90\nG0 X-10 Y10 Z-3\nG1 X50 F600\nG0 Z5\n";
    std::fs::write(&prog, text).unwrap();
    let out = dir.join("out");
    for target in [prog.clone(), out.join("summary.json")] {
        let o = swarf(&[
            "engage",
            "--stock",
            "box:0,0,-10,40,20,0",
            "--program",
            prog.to_str().unwrap(),
            "--tool",
            "flat:d=10",
            "--out",
            out.to_str().unwrap(),
            "--report",
            target.to_str().unwrap(),
        ]);
        assert!(!o.status.success(), "{}", target.display());
        assert!(stderr(&o).contains(".html"), "{}", stderr(&o));
        assert!(!out.exists(), "{}: the run went on", target.display());
    }
    assert_eq!(std::fs::read_to_string(&prog).unwrap(), text);
}

/// A report page that cannot be written (here a name longer than a file system takes) stops
/// the run before its work, with the page named: the outputs are not written first and the
/// error left for the end.
#[test]
fn an_unwritable_report_stops_the_run_before_its_work() {
    let dir = report_dir("unwritable");
    let prog = dir.join("job.ngc");
    std::fs::write(&prog, "G21 G90\nG0 X-10 Y10 Z-3\nG1 X50 F600\nG0 Z5\n").unwrap();
    let out = dir.join("out");
    let page = dir.join(format!("{}.html", "p".repeat(300)));
    let o = swarf(&[
        "simulate",
        "--stock",
        "box:0,0,-10,40,20,0",
        "--program",
        prog.to_str().unwrap(),
        "--tool",
        "flat:d=10",
        "--out",
        out.to_str().unwrap(),
        "--report",
        page.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("--report"), "{}", stderr(&o));
    assert!(!out.exists(), "the run went on");
    // No temporary left beside it.
    let left: Vec<_> = std::fs::read_dir(&dir).unwrap().flatten().collect();
    assert_eq!(left.len(), 1, "{left:?}");
}
