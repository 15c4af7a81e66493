//! The verification as one self-contained HTML page (`swarf_io::html`): inputs with the tools'
//! profiles, the machined part coloured by deviation with the toolpath and the defects as
//! markers in the 3-D view, the deviation histogram, the summary's figures and the defect list
//! linked to the program's lines.

use std::fmt::Write as _;

use swarf_io::html::{DefectRow, Marker, Plot, Report, Scene, SourceLine, ToolEntry};
use swarf_io::TriMesh;
use swarf_path::Program;
use swarf_tool::Cutter;

use crate::deviation::Legend;
use crate::verify::{DefectKind, Verification};

/// Most defect rows (and markers) a report lists; the rest are in `defects.csv`.
pub const MAX_REPORT_ROWS: usize = 2000;

/// What the report shows besides the verification.
#[derive(Clone, Debug)]
pub struct ReportInputs<'a> {
    /// The program.
    pub program: &'a Program,
    /// The program's files' text, by the names in `program.files` (lines are looked up here).
    pub sources: &'a [(String, String)],
    /// Labelled inputs (program, stock, design, machine…), shown as given.
    pub inputs: Vec<(String, String)>,
    /// The tools: number, description, cutter.
    pub tools: Vec<(u32, String, &'a Cutter)>,
    /// The command's JSON summary as `summary.json` holds it (the figures are read from it:
    /// every top-level number, string, boolean and short array, the contract's keys first,
    /// then the rest in the text's order, each as the text writes it).
    pub summary: &'a str,
    /// The machined part coloured by deviation ([`crate::deviation_mesh`]) and its legend.
    pub part: (&'a TriMesh, &'a Legend),
}

/// The deviation histogram (and the colour scale) as an SVG.
fn histogram_svg(v: &Verification, legend: &Legend) -> String {
    let h = &v.histogram;
    let (w, ht, pad) = (560.0, 220.0, 40.0);
    let max = h.counts.iter().copied().max().unwrap_or(1).max(1) as f64;
    let n = h.counts.len().max(1) as f64;
    let bw = (w - 2.0 * pad) / n;
    let mut s = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{ht}\" \
         viewBox=\"0 0 {w} {ht}\" font-size=\"11\">"
    );
    for (i, &c) in h.counts.iter().enumerate() {
        let mid = 0.5 * (h.edges_mm[i] + h.edges_mm[i + 1]);
        // log scale: one end in a million still shows.
        let t = if c == 0 {
            0.0
        } else {
            (1.0 + (c as f64).ln()) / (1.0 + max.ln())
        };
        let bh = t * (ht - 2.0 * pad);
        let colour = swarf_io::color::rgb8(
            swarf_io::ColorMap::Diverging.rgba(0.5 - mid / (2.0 * legend.max_mm.max(1e-12))),
        );
        let _ = write!(
            s,
            "<rect x=\"{:.1}\" y=\"{:.1}\" width=\"{:.1}\" height=\"{:.1}\" \
             fill=\"rgb({},{},{})\" stroke=\"#555\" stroke-width=\"0.3\"><title>{:.4} mm: {} \
             ends</title></rect>",
            pad + i as f64 * bw,
            ht - pad - bh,
            bw,
            bh,
            colour[0],
            colour[1],
            colour[2],
            mid,
            c
        );
    }
    let first = h.edges_mm.first().copied().unwrap_or(0.0);
    let last = h.edges_mm.last().copied().unwrap_or(0.0);
    let _ = write!(
        s,
        "<line x1=\"{pad}\" y1=\"{y}\" x2=\"{x2}\" y2=\"{y}\" stroke=\"#333\"/>\
         <text x=\"{pad}\" y=\"{ty}\">{first:.4}</text>\
         <text x=\"{xm}\" y=\"{ty}\" text-anchor=\"middle\">0 mm (gouge ← → excess)</text>\
         <text x=\"{x2}\" y=\"{ty}\" text-anchor=\"end\">{last:.4}</text>\
         <text x=\"{pad}\" y=\"14\">ray ends per signed deviation (log scale); colours as in the \
         3-D view, ±{:.4} mm</text></svg>",
        legend.max_mm,
        y = ht - pad,
        x2 = w - pad,
        ty = ht - pad + 16.0,
        xm = w / 2.0,
    );
    s
}

/// The summary's keys shown first: the contract of `summary.json` (the rest follow in its
/// order).
const FIRST_FIGURES: &[&str] = &[
    "max_gouge_mm",
    "max_excess_mm",
    "gouge_regions",
    "excess_regions",
    "excess_volume_mm3",
    "tolerance_mm",
    "collisions",
    "elapsed_s",
];

/// What the page says when the design reaches beyond the stock's box (also a figure,
/// `design_beyond_stock_box`): part of the design is not compared.
pub fn beyond_stock_note(v: &Verification) -> Option<String> {
    v.design_beyond_stock_box.then(|| {
        let outside = v.design_outside_stock_mm3.map_or(String::new(), |o| {
            format!("; {o:.1} mm³ of it lies above or below the stock")
        });
        format!(
            "the design reaches beyond the stock's box{outside}: what lies outside is not \
             compared (a design in another frame than the program's, or fixtures exported with \
             the part)"
        )
    })
}

/// The report page.
pub fn html_report(v: &Verification, inputs: &ReportInputs<'_>) -> String {
    let program = inputs.program;
    // A summary that is not a JSON object (not the command's) shows no figures.
    let summary = swarf_io::html::Report::default()
        .with_summary_json(inputs.summary, FIRST_FIGURES)
        .unwrap_or_default();
    let mut defects = vec![DefectRow {
        cells: [
            "region",
            "kind",
            "depth mm",
            "area mm²",
            "volume mm³",
            "x",
            "y",
            "z",
            "line",
        ]
        .map(String::from)
        .to_vec(),
        line: None,
    }];
    let mut markers = Vec::new();
    let mut wanted: Vec<(String, u32)> = Vec::new();
    for r in v.regions.iter().take(MAX_REPORT_ROWS) {
        let m = r.deepest_move.and_then(|i| program.moves.get(i));
        let line = m.map(|m| {
            let file = program
                .files
                .get(usize::from(m.file))
                .cloned()
                .unwrap_or_default();
            (file, m.line)
        });
        // The deepest end's line first, then every other line that cut the region.
        for l in line
            .iter()
            .cloned()
            .chain(r.moves.iter().map(|m| (m.file.clone(), m.line)))
        {
            if wanted.len() < MAX_REPORT_ROWS && !wanted.contains(&l) {
                wanted.push(l);
            }
        }
        markers.push(Marker {
            position: r.deepest,
            color: match r.kind {
                DefectKind::Gouge => [0.85, 0.05, 0.05],
                DefectKind::Excess => [0.05, 0.2, 0.85],
            },
            row: defects.len() - 1,
        });
        defects.push(DefectRow {
            cells: vec![
                r.id.to_string(),
                r.kind.name().to_string(),
                format!("{:.4}", r.depth_mm),
                format!("{:.3}", r.area_mm2),
                format!("{:.4}", r.volume_mm3),
                format!("{:.3}", r.deepest.x),
                format!("{:.3}", r.deepest.y),
                format!("{:.3}", r.deepest.z),
                line.as_ref()
                    .map_or(String::new(), |(f, l)| format!("{f}:{l}")),
            ],
            line,
        });
    }
    let source = wanted
        .iter()
        .map(|(file, line)| SourceLine {
            file: file.clone(),
            line: *line,
            text: swarf_io::html::source_line(inputs.sources, file, *line).to_string(),
        })
        .collect();
    let (part, legend) = inputs.part;
    let mut all_inputs = inputs.inputs.clone();
    if let Some(note) = beyond_stock_note(v) {
        all_inputs.push(("warning".into(), note));
    }
    all_inputs.push(("moves".into(), program.moves.len().to_string()));
    if v.regions.len() > MAX_REPORT_ROWS {
        all_inputs.push((
            "note".into(),
            format!(
                "{} regions; the first {MAX_REPORT_ROWS} are listed, all are in defects.csv",
                v.regions.len()
            ),
        ));
    }
    let report = Report {
        title: "swarf verify".into(),
        inputs: all_inputs,
        tools: inputs
            .tools
            .iter()
            .map(|(n, d, c)| ToolEntry {
                number: *n,
                description: d.clone(),
                profile: c.half_profile(120),
            })
            .collect(),
        figures: summary.figures,
        summary: summary.summary,
        summary_text: summary.summary_text,
        scene: Scene {
            meshes: vec![("machined part".into(), part.clone())],
            paths: program.tip_polylines(8),
            markers,
        },
        plots: vec![Plot::Svg {
            title: "Deviation of the machined surface".into(),
            svg: histogram_svg(v, legend),
        }],
        defects,
        source,
    };
    swarf_io::html::render(&report)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{deviation_mesh, verify, MeshDesign, VerifyOptions};
    use swarf_geom::math::Vec3;
    use swarf_path::load::{read_program_str, ReadOptions};
    use swarf_stock::TriDexel;

    /// The texts of the page's figures, in the page's order.
    fn figures(html: &str) -> Vec<(String, String)> {
        html.split("<td data-key=\"")
            .skip(1)
            .map(|s| {
                let (key, rest) = s.split_once("\">").unwrap();
                (
                    key.to_string(),
                    rest[..rest.find("</td>").unwrap()].to_string(),
                )
            })
            .collect()
    }

    #[test]
    fn every_figure_of_the_summary_is_on_the_page_and_a_design_off_the_stock_is_said() {
        // A design 100 mm away from the stock: nothing is compared with it.
        let design = MeshDesign::new(&crate::box_mesh(
            Vec3::new(100.0, 100.0, -10.0),
            Vec3::new(120.0, 120.0, -1.0),
        ))
        .unwrap();
        let stock = TriDexel::from_box(Vec3::new(0.0, 0.0, -10.0), Vec3::new(20.0, 20.0, 0.0), 1.0)
            .unwrap();
        let v = verify(&stock, &design, None, &VerifyOptions::default()).unwrap();
        assert!(v.design_beyond_stock_box);
        let program = read_program_str(
            "G0 X0 Y0 Z5\n",
            "p.ngc",
            swarf_path::Machine::three_axis(),
            &ReadOptions::default(),
        )
        .unwrap();
        let (mesh, legend) = deviation_mesh(&stock, &design, 1.0);
        // summary.json as `swarf verify` writes it (pretty, its own order), cut short.
        let summary = "{\n  \"max_gouge_mm\": 0.0,\n  \"max_excess_mm\": 119.99998092651367,\n  \
            \"gouge_regions\": 0,\n  \"excess_regions\": 1,\n  \"excess_volume_mm3\": 4000.0,\n  \
            \"tolerance_mm\": 0.01,\n  \"collisions\": 0,\n  \"elapsed_s\": 0.5,\n  \
            \"excess_tolerance_mm\": 0.01,\n  \"gouge_volume_mm3\": 0.0,\n  \
            \"volume_method\": \"z-rays\",\n  \"design_outside_stock_mm3\": 0.0,\n  \
            \"design_beyond_stock_box\": true,\n  \"ends_checked\": 2400,\n  \
            \"ends_unmatched\": 0,\n  \"gouge_ends\": 0,\n  \"excess_ends\": 2400,\n  \
            \"resolution_mm\": [\n    1.0,\n    1.0,\n    1.0\n  ],\n  \
            \"design\": \"closed mesh, 12 triangles, 3600.000 mm³\",\n  \
            \"regions\": [],\n  \"skipped_faces\": 0,\n  \"untrimmed_faces\": 0,\n  \
            \"unapplied_placements\": 0,\n  \"notes\": []\n}\n";
        let inputs = ReportInputs {
            program: &program,
            sources: &[],
            inputs: Vec::new(),
            tools: Vec::new(),
            summary,
            part: (&mesh, &legend),
        };
        let html = html_report(&v, &inputs);
        let got = figures(&html);
        let want: Vec<(String, String)> = [
            ("max_gouge_mm", "0.0"),
            ("max_excess_mm", "119.99998092651367"),
            ("gouge_regions", "0"),
            ("excess_regions", "1"),
            ("excess_volume_mm3", "4000.0"),
            ("tolerance_mm", "0.01"),
            ("collisions", "0"),
            ("elapsed_s", "0.5"),
            ("excess_tolerance_mm", "0.01"),
            ("gouge_volume_mm3", "0.0"),
            ("volume_method", "z-rays"),
            ("design_outside_stock_mm3", "0.0"),
            ("design_beyond_stock_box", "true"),
            ("ends_checked", "2400"),
            ("ends_unmatched", "0"),
            ("gouge_ends", "0"),
            ("excess_ends", "2400"),
            ("resolution_mm", "[1.0,1.0,1.0]"),
            ("design", "closed mesh, 12 triangles, 3600.000 mm³"),
            ("regions", "[]"),
            ("skipped_faces", "0"),
            ("untrimmed_faces", "0"),
            ("unapplied_placements", "0"),
            ("notes", "[]"),
        ]
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .to_vec();
        assert_eq!(got, want);
        // The design off the stock is said among the inputs, not only as a figure.
        assert!(
            html.contains("<th>warning</th><td>the design reaches beyond the stock&#39;s box"),
            "{}",
            &html[..html.len().min(4000)]
        );
    }
}
