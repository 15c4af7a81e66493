//! Building a [`Report`] from what a command produced: its JSON summary (the figures are read
//! from it, so the numbers on the page are the JSON's own text), labelled inputs, PNG plots
//! already written to disk, defect rows linked to program lines, and writing the page
//! atomically. [`Report::from_dir`] assembles a page from a command's output folder alone
//! (`swarf report --from DIR`).

use std::path::{Path, PathBuf};

use super::{DefectRow, Marker, Plot, Report, SourceLine};
use crate::error::IoError;
use crate::TriMesh;
use swarf_geom::math::Vec3;
use swarf_path::load::{decode_text, program_lines, ProgramFormat};

/// Most rows (and markers) a page lists from a CSV table.
pub const MAX_ROWS: usize = 2000;

/// Most PNG images a page embeds (a folder with more lists the first ones, sorted by path).
pub const MAX_IMAGES: usize = 64;

/// A summary value as the page shows it: a string as it is, anything else as its JSON text
/// (`serde_json` writes a number the same way in the page and in the printed JSON).
pub fn figure_text(v: &serde_json::Value) -> String {
    match v {
        serde_json::Value::String(s) => s.clone(),
        other => other.to_string(),
    }
}

/// A value small enough to be a figure: a number, string, boolean or null, or an array of up
/// to four of these.
fn is_figure(v: &serde_json::Value) -> bool {
    match v {
        serde_json::Value::Object(_) => false,
        serde_json::Value::Array(a) => {
            a.len() <= 4
                && a.iter().all(|x| {
                    !matches!(
                        x,
                        serde_json::Value::Array(_) | serde_json::Value::Object(_)
                    )
                })
        }
        _ => true,
    }
}

impl Report {
    /// An empty report titled `title`.
    pub fn new(title: &str) -> Self {
        Self {
            title: title.to_string(),
            ..Self::default()
        }
    }

    /// Embeds `summary` and shows its figures: the keys `first` (those present) in that order,
    /// then every other top-level figure (number, string, boolean, null, short array) in the
    /// summary's order. Nested objects and long arrays stay in the embedded JSON only.
    pub fn with_summary(mut self, summary: serde_json::Value, first: &[&str]) -> Self {
        let mut figures: Vec<(String, String)> = Vec::new();
        if let Some(obj) = summary.as_object() {
            for k in first {
                if let Some(v) = obj.get(*k).filter(|v| is_figure(v)) {
                    figures.push((k.to_string(), figure_text(v)));
                }
            }
            for (k, v) in obj {
                if is_figure(v) && !first.contains(&k.as_str()) {
                    figures.push((k.clone(), figure_text(v)));
                }
            }
        }
        self.figures = figures;
        self.summary = summary;
        self.summary_text = None;
        self
    }

    /// Embeds the JSON summary `text` (an object, as the command wrote it) and shows its
    /// figures: the keys `first` (those present) in that order, then every other top-level
    /// figure in the text's order, each exactly as the text writes it (a number's digits as
    /// they are — read into an `f64` and written again, some come out otherwise —, an array
    /// without its white space, a string unquoted). The embedded copy is the text itself
    /// without white space between its tokens, so its numbers and key order are the file's
    /// too.
    ///
    /// # Errors
    /// `text` is not a JSON object.
    pub fn with_summary_json(mut self, text: &str, first: &[&str]) -> Result<Self, String> {
        let summary: serde_json::Value = serde_json::from_str(text).map_err(|e| e.to_string())?;
        let entries = raw_entries(text).ok_or("not a JSON object")?;
        let shown = |(k, raw, v): &(String, &str, serde_json::Value)| {
            is_figure(v).then(|| {
                let text = match v {
                    serde_json::Value::String(s) => s.clone(),
                    _ => compact_json(raw),
                };
                (k.clone(), text)
            })
        };
        let mut figures: Vec<(String, String)> = Vec::new();
        for k in first {
            if let Some(f) = entries.iter().find(|e| e.0 == *k).and_then(shown) {
                figures.push(f);
            }
        }
        for e in &entries {
            if !first.contains(&e.0.as_str()) {
                figures.extend(shown(e));
            }
        }
        self.figures = figures;
        self.summary = summary;
        self.summary_text = Some(compact_json(text));
        Ok(self)
    }

    /// Adds an input row.
    pub fn with_input(mut self, label: &str, value: impl Into<String>) -> Self {
        self.inputs.push((label.to_string(), value.into()));
        self
    }

    /// Adds the figures of a JSON object as inputs labelled `prefix key` (a program's summary,
    /// a tool's description…); nested objects and long arrays are left out.
    pub fn with_json_inputs(mut self, prefix: &str, v: &serde_json::Value) -> Self {
        if let Some(obj) = v.as_object() {
            for (k, x) in obj {
                let empty = matches!(x, serde_json::Value::Array(a) if a.is_empty());
                if is_figure(x) && !x.is_null() && !empty {
                    self.inputs.push((format!("{prefix} {k}"), figure_text(x)));
                }
            }
        }
        self
    }

    /// Adds a mesh to the 3-D view.
    pub fn with_mesh(mut self, name: &str, mesh: TriMesh) -> Self {
        self.scene.meshes.push((name.to_string(), mesh));
        self
    }

    /// Adds a PNG plot.
    pub fn with_png(mut self, title: &str, bytes: Vec<u8>) -> Self {
        self.plots.push(Plot::Png {
            title: title.to_string(),
            bytes,
        });
        self
    }

    /// Adds every PNG under `dir` (recursively, sorted by path, at most [`MAX_IMAGES`]), each
    /// captioned with its path relative to `dir`. A missing folder adds nothing.
    pub fn with_pngs_in(mut self, dir: &Path) -> Result<Self, IoError> {
        let mut files = Vec::new();
        collect_files(dir, "png", &mut files)?;
        files.sort();
        for f in files.into_iter().take(MAX_IMAGES) {
            let bytes = std::fs::read(&f).map_err(|e| IoError::io(&f, e))?;
            let title = f.strip_prefix(dir).unwrap_or(&f).display().to_string();
            self = self.with_png(&title, bytes);
        }
        Ok(self)
    }

    /// Adds a table of rows linked to program lines: `header`, then each row's cells, its
    /// line, and a marker (position, colour) in the 3-D view. At most [`MAX_ROWS`] rows are
    /// kept; the caller says where the rest are.
    pub fn with_rows(mut self, header: &[&str], rows: impl IntoIterator<Item = Row>) -> Self {
        self.defects = vec![DefectRow {
            cells: header.iter().map(|s| s.to_string()).collect(),
            line: None,
        }];
        self.scene.markers.clear();
        for (row, marker) in rows.into_iter().take(MAX_ROWS) {
            if let Some((position, color)) = marker.filter(|(p, _)| p.is_finite()) {
                self.scene.markers.push(Marker {
                    position,
                    color,
                    row: self.defects.len() - 1,
                });
            }
            self.defects.push(row);
        }
        self
    }

    /// Fills the program lines the rows name from the files' text `sources` (file name, text),
    /// in order of first mention, at most [`MAX_ROWS`]; a file not given shows empty lines.
    /// Lines are counted as the program readers count them ([`source_line`]).
    pub fn with_sources(mut self, sources: &[(String, String)]) -> Self {
        let mut wanted: Vec<(String, u32)> = Vec::new();
        for (f, l) in self.defects.iter().filter_map(|d| d.line.as_ref()) {
            if wanted.len() < MAX_ROWS && !wanted.iter().any(|(g, m)| g == f && m == l) {
                wanted.push((f.clone(), *l));
            }
        }
        self.source = wanted
            .into_iter()
            .map(|(file, line)| {
                let text = source_line(sources, &file, line).to_string();
                SourceLine { file, line, text }
            })
            .collect();
        self
    }

    /// The page, written atomically to `path`.
    pub fn write(&self, path: &Path) -> Result<(), IoError> {
        let html = super::render(self);
        crate::write_atomic(path, |w| std::io::Write::write_all(w, html.as_bytes()))
    }

    /// A page from a command's output folder: `summary.json` (required: its figures, embedded
    /// whole), every PNG under the folder, the meshes `*.stl` in it (the machined stock of
    /// `swarf simulate --out`), and the rows of `defects.csv` (`swarf verify`) or
    /// `violations.csv` (`swarf gouge`), linked to their `file` and `line` columns and marked at
    /// their `x,y,z` columns when it has them. The program lines' text is read from the files
    /// the rows name when they can be read, decoded as the program readers decode them
    /// ([`source_text`]).
    pub fn from_dir(dir: &Path) -> Result<Self, IoError> {
        let summary_path = dir.join("summary.json");
        let text =
            std::fs::read_to_string(&summary_path).map_err(|e| IoError::io(&summary_path, e))?;
        let name = dir
            .file_name()
            .map_or_else(|| dir.display().to_string(), |n| n.to_string_lossy().into());
        // The figures as the file writes them, in its order.
        let mut r = Report::new(&format!("swarf report: {name}"))
            .with_summary_json(&text, &[])
            .map_err(|e| {
                IoError::malformed(&summary_path, e, "a command's JSON summary (an object)")
            })?
            .with_input("folder", dir.display().to_string())
            .with_pngs_in(dir)?;
        let mut stls = Vec::new();
        let entries = std::fs::read_dir(dir).map_err(|e| IoError::io(dir, e))?;
        for e in entries {
            let p = e.map_err(|e| IoError::io(dir, e))?.path();
            if p.is_file() && has_ext(&p, "stl") {
                stls.push(p);
            }
        }
        stls.sort();
        for p in stls {
            let mesh = crate::read_stl(&p)?;
            let name = p
                .file_name()
                .map_or(String::new(), |n| n.to_string_lossy().into());
            r = r.with_mesh(&name, mesh);
        }
        for table in ["defects.csv", "violations.csv"] {
            let p = dir.join(table);
            if p.is_file() {
                let text = std::fs::read_to_string(&p).map_err(|e| IoError::io(&p, e))?;
                let n = text.lines().count().saturating_sub(1);
                r = r.with_input("rows", format!("{n} in {table}"));
                r = csv_rows(r, &text);
                break;
            }
        }
        let mut files: Vec<String> = r
            .defects
            .iter()
            .filter_map(|d| d.line.as_ref().map(|(f, _)| f.clone()))
            .collect();
        files.sort();
        files.dedup();
        let sources: Vec<(String, String)> = files
            .into_iter()
            .filter(|f| is_source_file(Path::new(f)))
            .filter_map(|f| source_text(Path::new(&f)).map(|t| (f, t)))
            .collect();
        Ok(r.with_sources(&sources))
    }
}

/// The top-level entries of the JSON object `text` in its order: key, the value's text as
/// written, the value read; `None` when `text` is not one JSON object.
fn raw_entries(text: &str) -> Option<Vec<(String, &str, serde_json::Value)>> {
    let b = text.as_bytes();
    let ws = |mut i: usize| {
        while i < b.len() && b[i].is_ascii_whitespace() {
            i += 1;
        }
        i
    };
    // One JSON value at `i`: it and where it ends (the reader stops after it).
    let value_at = |i: usize| -> Option<(serde_json::Value, usize)> {
        let mut values =
            serde_json::Deserializer::from_str(&text[i..]).into_iter::<serde_json::Value>();
        let v = values.next()?.ok()?;
        Some((v, i + values.byte_offset()))
    };
    let mut i = ws(0);
    if b.get(i) != Some(&b'{') {
        return None;
    }
    i = ws(i + 1);
    let mut out = Vec::new();
    if b.get(i) == Some(&b'}') {
        return (ws(i + 1) == b.len()).then_some(out);
    }
    loop {
        let (serde_json::Value::String(key), end) = value_at(i)? else {
            return None;
        };
        i = ws(end);
        if b.get(i) != Some(&b':') {
            return None;
        }
        i = ws(i + 1);
        let (value, end) = value_at(i)?;
        out.push((key, &text[i..end], value));
        i = ws(end);
        match b.get(i) {
            Some(b',') => i = ws(i + 1),
            Some(b'}') => break,
            _ => return None,
        }
    }
    (ws(i + 1) == b.len()).then_some(out)
}

/// JSON `text` without the white space between its tokens (strings kept as written).
fn compact_json(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let (mut in_string, mut escaped) = (false, false);
    for c in text.chars() {
        if in_string {
            out.push(c);
            if escaped {
                escaped = false;
            } else if c == '\\' {
                escaped = true;
            } else if c == '"' {
                in_string = false;
            }
        } else if !c.is_ascii_whitespace() {
            in_string = c == '"';
            out.push(c);
        }
    }
    out
}

/// Line `line` (1-based) of `file`'s text in `sources` (file name, text), counted as the
/// program readers count lines ([`program_lines`]: a G-code line also ends at a lone `\r`, the
/// line end of old Mac editors); empty when the file is not given or has no such line.
pub fn source_line<'a>(sources: &'a [(String, String)], file: &str, line: u32) -> &'a str {
    sources
        .iter()
        .find(|(f, _)| f == file)
        .and_then(|(f, t)| {
            let format = ProgramFormat::detect(Path::new(f), t);
            program_lines(t, format).nth((line as usize).checked_sub(1)?)
        })
        .unwrap_or("")
}

/// A program file's text as the program readers decode it
/// ([`decode_text`](swarf_path::load::decode_text): UTF-16 with a byte-order mark, else UTF-8
/// with other bytes replaced), for [`Report::with_sources`]; `None` when it cannot be read.
fn source_text(path: &Path) -> Option<String> {
    std::fs::read(path).ok().map(decode_text)
}

/// Largest program file a report reads to show the lines its rows name, bytes.
const MAX_SOURCE_BYTES: u64 = 256 << 20;

/// Whether a report reads `p` to show the program lines its rows name: a regular file of a
/// program's size. A row may name anything (`/dev/zero` was read until memory ran out).
fn is_source_file(p: &Path) -> bool {
    std::fs::metadata(p).is_ok_and(|m| m.is_file() && m.len() <= MAX_SOURCE_BYTES)
}

fn has_ext(p: &Path, ext: &str) -> bool {
    p.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case(ext))
}

fn collect_files(dir: &Path, ext: &str, out: &mut Vec<PathBuf>) -> Result<(), IoError> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Ok(());
    };
    for e in entries {
        let p = e.map_err(|e| IoError::io(dir, e))?.path();
        if p.is_dir() {
            collect_files(&p, ext, out)?;
        } else if has_ext(&p, ext) {
            out.push(p);
        }
    }
    Ok(())
}

/// One CSV record's fields (RFC 4180 quoting, as swarf writes it).
fn csv_fields(line: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut cur = String::new();
    let mut quoted = false;
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '"' if quoted && chars.peek() == Some(&'"') => {
                cur.push('"');
                chars.next();
            }
            '"' => quoted = !quoted,
            ',' if !quoted => out.push(std::mem::take(&mut cur)),
            c => cur.push(c),
        }
    }
    out.push(cur);
    out
}

/// A row and its marker (position, colour).
type Row = (DefectRow, Option<(Vec3, [f32; 3])>);

/// The rows of a swarf CSV table (one record per line), linked and marked by their columns.
fn csv_rows(r: Report, text: &str) -> Report {
    let mut lines = text.lines();
    let header = lines.next().map(csv_fields).unwrap_or_default();
    let col = |name: &str| header.iter().position(|h| h == name);
    let (file, line) = (col("file"), col("line"));
    let xyz = [col("x"), col("y"), col("z")];
    let kind = col("kind");
    let rows: Vec<Row> = lines
        .map(|l| {
            let cells = csv_fields(l);
            let get = |c: Option<usize>| c.and_then(|i| cells.get(i)).map(String::as_str);
            let link = match (get(file), get(line).and_then(|l| l.parse::<u32>().ok())) {
                (Some(f), Some(l)) if l > 0 => Some((f.to_string(), l)),
                _ => None,
            };
            let p = xyz.map(|c| get(c).and_then(|v| v.parse::<f64>().ok()));
            let colour = match get(kind) {
                Some("excess") => [0.05, 0.2, 0.85],
                _ => [0.85, 0.05, 0.05],
            };
            let marker = match p {
                [Some(x), Some(y), Some(z)] => Some((Vec3::new(x, y, z), colour)),
                _ => None,
            };
            (DefectRow { cells, line: link }, marker)
        })
        .collect();
    let header: Vec<&str> = header.iter().map(String::as_str).collect();
    r.with_rows(&header, rows)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn figures_are_the_json_text_and_first_keys_lead() {
        let s = serde_json::json!({"b": 0.1 + 0.2, "a": "x<y", "nested": {"c": 1}, "v": [1, 2, 3]});
        let r = Report::new("t").with_summary(s, &["v", "missing"]);
        let keys: Vec<&str> = r.figures.iter().map(|(k, _)| k.as_str()).collect();
        assert_eq!(keys[0], "v");
        assert!(!keys.contains(&"nested") && !keys.contains(&"missing"));
        let b = r.figures.iter().find(|(k, _)| k == "b").unwrap();
        assert_eq!(b.1, "0.30000000000000004");
        assert_eq!(
            r.figures.iter().find(|(k, _)| k == "v").unwrap().1,
            "[1,2,3]"
        );
        let html = super::super::render(&r);
        assert!(html.contains("<td data-key=\"a\">x&lt;y</td>"));
    }

    #[test]
    fn a_summary_file_shows_its_own_numbers_in_its_own_order() {
        // Numbers that reading into an f64 and writing again changed (…369, …672e-7), keys
        // out of alphabetical order, an array over several lines, a string with an escape.
        let text = "{\n  \"z_first\": 119.99998092651367,\n  \"a\": 1.4901158351676719e-7,\n  \
                    \"m\": [\n    0.5,\n    2\n  ],\n  \"s\": \"x \\\"y\\\"\",\n  \"b\": true,\n  \
                    \"nested\": {\"c\": 1},\n  \"n\": null\n}\n";
        let dir = swarf_testdata::scratch_dir("report-order");
        std::fs::write(dir.join("summary.json"), text).unwrap();
        let r = Report::from_dir(&dir).unwrap();
        let figures: Vec<(&str, &str)> = r
            .figures
            .iter()
            .map(|(k, v)| (k.as_str(), v.as_str()))
            .collect();
        assert_eq!(
            figures,
            [
                ("z_first", "119.99998092651367"),
                ("a", "1.4901158351676719e-7"),
                ("m", "[0.5,2]"),
                ("s", "x \"y\""),
                ("b", "true"),
                ("n", "null"),
            ]
        );
        // The embedded summary: the file's text without its white space.
        let html = super::super::render(&r);
        assert!(
            html.contains(
                "{\"z_first\":119.99998092651367,\"a\":1.4901158351676719e-7,\"m\":[0.5,2],\
                 \"s\":\"x \\\"y\\\"\",\"b\":true,\"nested\":{\"c\":1},\"n\":null}"
            ),
            "{html}"
        );
        // The keys named first lead, the rest follow in the text's order.
        let r = Report::new("t")
            .with_summary_json(text, &["b", "missing"])
            .unwrap();
        let keys: Vec<&str> = r.figures.iter().map(|(k, _)| k.as_str()).collect();
        assert_eq!(keys, ["b", "z_first", "a", "m", "s", "n"]);
        // Not an object: an error, naming the file.
        std::fs::write(dir.join("summary.json"), "[1, 2]").unwrap();
        let e = Report::from_dir(&dir).unwrap_err().to_string();
        assert!(e.contains("summary.json"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn rows_naming_devices_or_folders_are_not_read() {
        // A row's file may be anything: /dev/zero was read until memory ran out.
        let dir = swarf_testdata::scratch_dir("report-dev");
        let program = dir.join("p.ngc");
        std::fs::write(&program, "G0 X0\nG1 X1\n").unwrap();
        std::fs::write(dir.join("summary.json"), "{\"locations\": 1}").unwrap();
        let csv = format!(
            "file,line\n/dev/zero,1\n{},2\n{},1\n",
            program.display(),
            dir.display()
        );
        std::fs::write(dir.join("defects.csv"), csv).unwrap();
        assert!(is_source_file(&program));
        for other in [Path::new("/dev/zero"), &dir] {
            assert!(!is_source_file(other), "{}", other.display());
        }
        let r = Report::from_dir(&dir).unwrap();
        let text: Vec<(&str, &str)> = r
            .source
            .iter()
            .map(|s| (s.file.as_str(), s.text.as_str()))
            .collect();
        let p = program.display().to_string();
        let d = dir.display().to_string();
        assert_eq!(
            text,
            [("/dev/zero", ""), (p.as_str(), "G1 X1"), (d.as_str(), "")]
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn csv_rows_link_lines_and_markers() {
        assert_eq!(csv_fields("1,\"a,\"\"b\"\"\",3"), ["1", "a,\"b\"", "3"]);
        let r = csv_rows(
            Report::new("t"),
            "region,kind,x,y,z,file,line\n1,gouge,1,2,3,p.ngc,7\n2,excess,,,,,\n",
        );
        assert_eq!(r.defects.len(), 3);
        assert_eq!(r.defects[1].line, Some(("p.ngc".into(), 7)));
        assert_eq!(r.defects[2].line, None);
        assert_eq!(r.scene.markers.len(), 1);
        assert_eq!(r.scene.markers[0].row, 0);
        let r = r.with_sources(&[("p.ngc".into(), "a\nb\nc\nd\ne\nf\nG1 X1 (<b>)\n".into())]);
        assert_eq!(r.source.len(), 1);
        assert_eq!(r.source[0].text, "G1 X1 (<b>)");
    }
}
