//! One self-contained HTML report: a page that opens offline with no other file and no network,
//! with the inputs, a 3-D view, plots, the figures of a summary and a list of defects linked to
//! the program's lines.
//!
//! The 3-D view is swarf's own small WebGL2 viewer ([`VIEWER_JS`], written for swarf, no
//! third-party code): coloured triangle meshes, polylines (feed and rapid motion), markers;
//! rotate (left drag), pan (right drag or shift-drag), zoom (wheel), a section plane along X, Y
//! or Z, and clicking a marker (or a row of the defect list) shows its program line. Meshes and
//! lines are embedded **quantised** (positions as `u16` over the scene's box, colours as `u8`)
//! and **compressed** (zlib, inflated by the browser's `DecompressionStream`), base64-encoded.
//!
//! Every string that comes from an input (file names, program text, tool descriptions, labels)
//! is escaped ([`escape`]); the embedded JSON is written so that no `<`, `>` or `&` appears in it
//! raw ([`script_json`]), so nothing from an input can close a tag or start a script.

use std::fmt::Write as _;
use std::io::Write as _;

use swarf_geom::math::Vec3;

use crate::mesh::TriMesh;

mod page;
pub use page::{figure_text, source_line, MAX_IMAGES, MAX_ROWS};

/// The viewer's script, embedded in every report.
pub const VIEWER_JS: &str = include_str!("viewer.js");

/// A report.
#[derive(Clone, Debug, Default)]
pub struct Report {
    /// Page title.
    pub title: String,
    /// The inputs: label, value.
    pub inputs: Vec<(String, String)>,
    /// The tools, with their profiles.
    pub tools: Vec<ToolEntry>,
    /// Summary figures: label, value (as displayed; the same numbers are in `summary`).
    pub figures: Vec<(String, String)>,
    /// The command's JSON summary, embedded whole (the page's figures are read from it).
    pub summary: serde_json::Value,
    /// The summary's JSON text as the command wrote it, without white space between tokens
    /// ([`Report::with_summary_json`]): embedded instead of `summary` when set, so that its
    /// numbers and key order are the file's.
    pub summary_text: Option<String>,
    /// The 3-D scene.
    pub scene: Scene,
    /// Plots (SVG documents or PNG images).
    pub plots: Vec<Plot>,
    /// The defects (or any rows) linked to program lines.
    pub defects: Vec<DefectRow>,
    /// The program lines the defects refer to (and a few around them).
    pub source: Vec<SourceLine>,
}

/// A tool and its profile.
#[derive(Clone, Debug, Default)]
pub struct ToolEntry {
    /// Tool number.
    pub number: u32,
    /// Description (the spec or the library's text).
    pub description: String,
    /// Half-profile `(radius, height)` from the tip up, mm.
    pub profile: Vec<(f64, f64)>,
}

/// What the 3-D view shows.
#[derive(Clone, Debug, Default)]
pub struct Scene {
    /// Meshes with per-vertex colours (grey when they have none).
    pub meshes: Vec<(String, TriMesh)>,
    /// Polylines: points and whether they are rapid motion.
    pub paths: Vec<(Vec<Vec3>, bool)>,
    /// Markers.
    pub markers: Vec<Marker>,
}

/// A marker in the 3-D view, tied to a row of the defect list.
#[derive(Clone, Debug, Default)]
pub struct Marker {
    /// Where.
    pub position: Vec3,
    /// RGB colour, components in `[0, 1]`.
    pub color: [f32; 3],
    /// Index into [`Report::defects`].
    pub row: usize,
}

/// A plot.
#[derive(Clone, Debug)]
pub enum Plot {
    /// An SVG document (built by swarf; embedded inline).
    Svg {
        /// Caption.
        title: String,
        /// The SVG text.
        svg: String,
    },
    /// A PNG image (embedded as a data URL).
    Png {
        /// Caption.
        title: String,
        /// The PNG bytes.
        bytes: Vec<u8>,
    },
}

/// A row of the defect list.
#[derive(Clone, Debug, Default)]
pub struct DefectRow {
    /// Cells as displayed.
    pub cells: Vec<String>,
    /// The program line it names: file, line.
    pub line: Option<(String, u32)>,
}

/// A program line.
#[derive(Clone, Debug, Default)]
pub struct SourceLine {
    /// File.
    pub file: String,
    /// 1-based line.
    pub line: u32,
    /// Its text.
    pub text: String,
}

/// `s` with `& < > " '` replaced by entities: safe in element content and quoted attributes.
pub fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c => out.push(c),
        }
    }
    out
}

/// JSON text safe inside a `<script type="application/json">` element: `<`, `>` and `&` as
/// `\u003c`, `\u003e`, `\u0026` (JSON parsers read them back unchanged), and the line
/// separators U+2028/U+2029 escaped.
pub fn script_json(v: &serde_json::Value) -> String {
    script_json_text(&v.to_string())
}

/// [`script_json`] of JSON text as it is.
fn script_json_text(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '<' => out.push_str("\\u003c"),
            '>' => out.push_str("\\u003e"),
            '&' => out.push_str("\\u0026"),
            '\u{2028}' => out.push_str("\\u2028"),
            '\u{2029}' => out.push_str("\\u2029"),
            c => out.push(c),
        }
    }
    out
}

/// Standard base64 with padding.
pub fn base64(bytes: &[u8]) -> String {
    const A: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for c in bytes.chunks(3) {
        let n = (u32::from(c[0]) << 16)
            | (u32::from(*c.get(1).unwrap_or(&0)) << 8)
            | u32::from(*c.get(2).unwrap_or(&0));
        for k in 0..4 {
            if k <= c.len() {
                out.push(A[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

fn zlib(bytes: &[u8]) -> Vec<u8> {
    let mut e = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::default());
    // Writing to a Vec cannot fail.
    let _ = e.write_all(bytes);
    e.finish().unwrap_or_default()
}

/// The scene as compact binary streams (quantised, compressed, base64) and its box.
fn scene_json(scene: &Scene) -> serde_json::Value {
    let mut pts = scene
        .meshes
        .iter()
        .flat_map(|(_, m)| m.vertices.iter().copied())
        .chain(scene.paths.iter().flat_map(|(p, _)| p.iter().copied()))
        .chain(scene.markers.iter().map(|m| m.position))
        .filter(|p| p.is_finite());
    let first = pts.next().unwrap_or(Vec3::ZERO);
    let (lo, hi) = pts.fold((first, first), |(a, b), p| (a.min(p), b.max(p)));
    let span = (hi - lo).max(Vec3::splat(1e-9));
    let quant = |p: Vec3| -> [u16; 3] {
        let t = ((p - lo) / span).clamp(Vec3::ZERO, Vec3::ONE) * 65535.0;
        [t.x.round() as u16, t.y.round() as u16, t.z.round() as u16]
    };
    let pack_positions = |ps: &mut dyn Iterator<Item = Vec3>| -> String {
        let mut b = Vec::new();
        for p in ps {
            for c in quant(p) {
                b.extend_from_slice(&c.to_le_bytes());
            }
        }
        base64(&zlib(&b))
    };
    let meshes: Vec<serde_json::Value> = scene
        .meshes
        .iter()
        .map(|(name, m)| {
            let mut colors = Vec::with_capacity(m.vertices.len() * 3);
            for k in 0..m.vertices.len() {
                let c = m
                    .colors
                    .as_ref()
                    .and_then(|c| c.get(k))
                    .copied()
                    .unwrap_or([0.7, 0.7, 0.72, 1.0]);
                colors.extend(
                    c[..3]
                        .iter()
                        .map(|x| (x.clamp(0.0, 1.0) * 255.0).round() as u8),
                );
            }
            let mut idx = Vec::with_capacity(m.triangles.len() * 12);
            for t in &m.triangles {
                for i in t {
                    idx.extend_from_slice(&i.to_le_bytes());
                }
            }
            serde_json::json!({
                "name": name,
                "vertices": m.vertices.len(),
                "triangles": m.triangles.len(),
                "positions": pack_positions(&mut m.vertices.iter().copied()),
                "colors": base64(&zlib(&colors)),
                "indices": base64(&zlib(&idx)),
            })
        })
        .collect();
    // Paths as line segments, feed and rapid apart.
    let segments = |rapid: bool| -> (usize, String) {
        let mut n = 0;
        let mut it = scene
            .paths
            .iter()
            .filter(|(_, r)| *r == rapid)
            .flat_map(|(p, _)| p.windows(2).map(|w| [w[0], w[1]]))
            .flatten()
            .inspect(|_| n += 1);
        let s = pack_positions(&mut it);
        (n / 2, s)
    };
    let (nf, feed) = segments(false);
    let (nr, rapid) = segments(true);
    let markers: Vec<serde_json::Value> = scene
        .markers
        .iter()
        .map(|m| {
            serde_json::json!({
                "p": [m.position.x, m.position.y, m.position.z],
                "c": m.color,
                "row": m.row,
            })
        })
        .collect();
    serde_json::json!({
        "min": [lo.x, lo.y, lo.z],
        "max": [hi.x, hi.y, hi.z],
        "meshes": meshes,
        "feed": { "segments": nf, "positions": feed },
        "rapid": { "segments": nr, "positions": rapid },
        "markers": markers,
    })
}

/// A tool's profile as a small SVG (the half-profile mirrored about the axis).
fn tool_svg(t: &ToolEntry) -> String {
    let rmax = t.profile.iter().map(|p| p.0).fold(1e-9, f64::max);
    let hmax = t.profile.iter().map(|p| p.1).fold(1e-9, f64::max);
    let s = 110.0 / (2.0 * rmax).max(hmax);
    let (w, h) = (2.0 * rmax * s + 10.0, hmax * s + 10.0);
    let mut right = String::new();
    let mut left = String::new();
    for &(r, z) in &t.profile {
        let _ = write!(right, "{:.2},{:.2} ", w / 2.0 + r * s, h - 5.0 - z * s);
    }
    for &(r, z) in t.profile.iter().rev() {
        let _ = write!(left, "{:.2},{:.2} ", w / 2.0 - r * s, h - 5.0 - z * s);
    }
    format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w:.0}\" height=\"{h:.0}\" \
         viewBox=\"0 0 {w:.1} {h:.1}\"><polygon points=\"{right}{left}\" fill=\"#cdd3dc\" \
         stroke=\"#334\" stroke-width=\"1\"/></svg>"
    )
}

const STYLE: &str = "body{font:14px system-ui,sans-serif;margin:0;color:#222;background:#f6f7f9}\
header{background:#223;color:#fff;padding:10px 16px}h1{font-size:18px;margin:0}\
main{display:grid;grid-template-columns:minmax(0,3fr) minmax(0,2fr);gap:12px;padding:12px}\
section{background:#fff;border:1px solid #ddd;border-radius:6px;padding:10px;overflow:auto}\
h2{font-size:15px;margin:0 0 8px}table{border-collapse:collapse;width:100%}\
td,th{border-bottom:1px solid #eee;padding:3px 6px;text-align:left;font-variant-numeric:tabular-nums}\
tr.row{cursor:pointer}tr.row:hover{background:#eef}tr.sel{background:#dde6ff}\
#view{width:100%;height:520px;display:block;background:#fff;border:1px solid #ccc;touch-action:none}\
#line{font-family:monospace;white-space:pre-wrap;background:#f3f3f3;padding:6px;min-height:1.4em}\
.tools{display:flex;gap:12px;flex-wrap:wrap}.tools figure{margin:0;text-align:center}\
.controls{display:flex;gap:8px;align-items:center;margin:6px 0}pre.src{margin:0}\
section img{max-width:100%;height:auto}";

/// The report as one HTML document.
pub fn render(r: &Report) -> String {
    let mut h = String::new();
    let _ = write!(
        h,
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>{}</title>\
         <style>{STYLE}</style></head><body><header><h1>{}</h1></header><main><div>",
        escape(&r.title),
        escape(&r.title)
    );
    // 3-D view and the selected line.
    h.push_str(
        "<section><h2>3-D view</h2><div class=\"controls\"><label>section \
         <select id=\"axis\"><option value=\"-1\">none</option><option value=\"0\">X</option>\
         <option value=\"1\">Y</option><option value=\"2\" selected>Z</option></select></label>\
         <input id=\"cut\" type=\"range\" min=\"0\" max=\"1000\" value=\"1000\"> \
         <label><input id=\"showpath\" type=\"checkbox\" checked> toolpath</label> \
         <button id=\"reset\">reset view</button></div><canvas id=\"view\"></canvas>\
         <p>Left drag: rotate · right or shift drag: pan · wheel: zoom · click a marker or a \
         row: its program line.</p><div id=\"line\"></div></section>",
    );
    // Plots.
    for p in &r.plots {
        match p {
            Plot::Svg { title, svg } => {
                let _ = write!(h, "<section><h2>{}</h2>{svg}</section>", escape(title));
            }
            Plot::Png { title, bytes } => {
                let _ = write!(
                    h,
                    "<section><h2>{}</h2><img alt=\"{}\" src=\"data:image/png;base64,{}\">\
                     </section>",
                    escape(title),
                    escape(title),
                    base64(bytes)
                );
            }
        }
    }
    h.push_str("</div><div>");
    // Figures.
    h.push_str("<section><h2>Summary</h2><table id=\"figures\">");
    for (k, v) in &r.figures {
        let _ = write!(
            h,
            "<tr><th>{}</th><td data-key=\"{}\">{}</td></tr>",
            escape(k),
            escape(k),
            escape(v)
        );
    }
    h.push_str("</table></section>");
    // Defects (a page without rows has no such section).
    let hidden = if r.defects.is_empty() { " hidden" } else { "" };
    let _ = write!(h, "<section{hidden}><h2>Defects</h2><table id=\"defects\">");
    for (i, row) in r.defects.iter().enumerate() {
        let tag = if i == 0 { "th" } else { "td" };
        let attrs = if i == 0 {
            String::new()
        } else {
            format!(" class=\"row\" data-row=\"{}\"", i - 1)
        };
        let _ = write!(h, "<tr{attrs}>");
        for c in &row.cells {
            let _ = write!(h, "<{tag}>{}</{tag}>", escape(c));
        }
        h.push_str("</tr>");
    }
    h.push_str("</table></section>");
    // Inputs and tools.
    h.push_str("<section><h2>Inputs</h2><table>");
    for (k, v) in &r.inputs {
        let _ = write!(h, "<tr><th>{}</th><td>{}</td></tr>", escape(k), escape(v));
    }
    h.push_str("</table><div class=\"tools\">");
    for t in &r.tools {
        let _ = write!(
            h,
            "<figure>{}<figcaption>T{} {}</figcaption></figure>",
            tool_svg(t),
            t.number,
            escape(&t.description)
        );
    }
    h.push_str("</div></section>");
    // Program lines.
    let hidden = if r.source.is_empty() { " hidden" } else { "" };
    let _ = write!(
        h,
        "<section{hidden}><h2>Program lines</h2><pre class=\"src\" id=\"source\">"
    );
    for s in &r.source {
        let _ = writeln!(
            h,
            "<span data-file=\"{}\" data-line=\"{}\">{}:{}: {}</span>",
            escape(&s.file),
            s.line,
            escape(&s.file),
            s.line,
            escape(&s.text)
        );
    }
    h.push_str("</pre></section></div></main>");
    // Data and the viewer.
    let rows: Vec<serde_json::Value> = r
        .defects
        .iter()
        .skip(1)
        .map(|d| match &d.line {
            Some((f, l)) => serde_json::json!({"file": f, "line": l}),
            None => serde_json::Value::Null,
        })
        .collect();
    let source: Vec<serde_json::Value> = r
        .source
        .iter()
        .map(|s| serde_json::json!({"file": s.file, "line": s.line, "text": s.text}))
        .collect();
    let data = serde_json::json!({
        "scene": scene_json(&r.scene),
        "rows": rows,
        "source": source,
    });
    let _ = writeln!(
        h,
        "<script type=\"application/json\" id=\"summary\">{}</script>\
         <script type=\"application/json\" id=\"data\">{}</script><script>{}</script>\
         </body></html>",
        r.summary_text
            .as_deref()
            .map_or_else(|| script_json(&r.summary), script_json_text),
        script_json(&data),
        VIEWER_JS
    );
    h
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_matches_rfc4648() {
        for (i, o) in [
            ("", ""),
            ("f", "Zg=="),
            ("fo", "Zm8="),
            ("foo", "Zm9v"),
            ("foob", "Zm9vYg=="),
            ("fooba", "Zm9vYmE="),
            ("foobar", "Zm9vYmFy"),
        ] {
            assert_eq!(base64(i.as_bytes()), o);
        }
    }

    #[test]
    fn input_strings_cannot_open_tags() {
        let evil = "(<script>alert(1)</script>) & \"x\" 'y'";
        let r = Report {
            title: evil.into(),
            inputs: vec![("program".into(), evil.into())],
            tools: vec![ToolEntry {
                number: 1,
                description: evil.into(),
                profile: vec![(0.0, 0.0), (3.0, 3.0), (3.0, 10.0)],
            }],
            figures: vec![(evil.into(), evil.into())],
            summary: serde_json::json!({ "note": evil }),
            defects: vec![
                DefectRow {
                    cells: vec!["region".into()],
                    line: None,
                },
                DefectRow {
                    cells: vec![evil.into()],
                    line: Some((evil.into(), 3)),
                },
            ],
            source: vec![SourceLine {
                file: evil.into(),
                line: 3,
                text: evil.into(),
            }],
            ..Default::default()
        };
        let html = render(&r);
        assert!(!html.contains("<script>alert"), "raw script tag");
        assert!(!html.contains("</script>)"));
        assert!(html.contains("&lt;script&gt;alert(1)&lt;/script&gt;"));
        // The only script elements are the report's own three.
        assert_eq!(html.matches("<script").count(), 3);
        assert_eq!(html.matches("</script>").count(), 3);
        // The embedded JSON reads back to the input.
        let start = html.find("id=\"summary\">").unwrap() + "id=\"summary\">".len();
        let end = start + html[start..].find("</script>").unwrap();
        let v: serde_json::Value = serde_json::from_str(&html[start..end]).unwrap();
        assert_eq!(v["note"], evil);
    }
}
