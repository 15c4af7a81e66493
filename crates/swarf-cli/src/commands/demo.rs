//! `swarf demo`: the built-in job — a 100 × 80 × 20 mm block, a roughing and a 3-D finishing
//! program written for it, and their tool library, all embedded in the binary — read, simulated
//! on a tri-dexel stock, and written out as a mesh and a summary; then the program is checked
//! against the design surface of its finishing operation (`swarf gouge`), which shows where
//! the naive finishing raster (ball tip put on the surface) gouges the slopes.

use swarf_io::OutputSet;

use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};
use clap::Args;
use serde::Serialize;
use swarf_job::JobSetup;
use swarf_path::canonical::CanonicalPrinter;
use swarf_path::load::{stream_program, ReadOptions};
use swarf_path::Machine;
use swarf_plan::gouge::{check_program, GougeOptions, GougeSummary, GougeSurface};
use swarf_stock::{simulate, MeshOptions, SimOptions, StockSpec};
use swarf_surface::build::{hermite_height_field, HeightGrid};
use swarf_surface::{CompoundSurface, Patch, PreparedSurface, Surface};
use swarf_tool::table::parse_toml_library;

use crate::commands::path::PathReport;
use crate::commands::simulate::{write_outputs, SimulateSummary, StockMeshOut};
use crate::commands::tools::defined_tools;
use crate::output::{output_set, print_json};

/// `swarf demo`.
#[derive(Debug, Args)]
pub(crate) struct DemoArgs {
    /// Where to write the machined part (stock.stl, stock.glb), moves.csv, summary.json, the
    /// program, its tool library and its canonical motion.
    #[arg(long, value_name = "DIR", default_value = "swarf-demo")]
    pub(crate) out: PathBuf,
    /// Largest total size of the files written, MB (estimated before anything is written).
    #[arg(long, value_name = "MB", default_value_t = crate::output::DEFAULT_MAX_OUTPUT_MB)]
    pub(crate) max_output_mb: u64,
    /// Ray spacing of the stock, mm.
    #[arg(
        allow_negative_numbers = true,
        long,
        value_name = "H",
        default_value_t = 0.25
    )]
    pub(crate) resolution: f64,
}

/// The demo program (LinuxCNC G-code with parameters, loops, conditionals and arcs).
const PROGRAM: &str = include_str!("../../demo/demo.ngc");
/// Its tool library (swarf TOML).
const TOOLS: &str = include_str!("../../demo/tools.toml");
/// The block the program was written for: top face at Z0, origin at its front-left corner.
const STOCK: &str = "box:0,0,-20,100,80,0";

#[derive(Serialize)]
struct DemoReport<'a> {
    stock: &'static str,
    program: &'a PathReport,
    simulation: &'a SimulateSummary,
    gouge: &'a GougeSummary,
    out_dir: String,
}

/// The design surface of Op 2, `z = −6 + 1.5·sin(9x°)·cos(9y°)` over the finished area
/// `[20, 80] × [20, 60]` mm, as one bicubic NURBS on a 2 mm grid
/// ([`hermite_height_field`]). Within 1e-4 mm of the formula (tested).
fn wavy_floor() -> CompoundSurface {
    let k = 9f64.to_radians();
    let jet = |x: f64, y: f64| {
        let (sx, cx, sy, cy) = ((k * x).sin(), (k * x).cos(), (k * y).sin(), (k * y).cos());
        [
            -6.0 + 1.5 * sx * cy,
            1.5 * k * cx * cy,
            -1.5 * k * sx * sy,
            -1.5 * k * k * cx * sy,
        ]
    };
    let grid = HeightGrid {
        origin: [20.0, 20.0],
        h: 2.0,
        cells: [30, 20],
    };
    let s = hermite_height_field(&grid, jet).expect("the demo floor is a valid NURBS");
    let mut patch = Patch::new(Surface::Nurbs(s));
    patch.name = Some("wavy_floor".into());
    CompoundSurface::new(vec![patch])
}

pub(crate) fn run(args: &DemoArgs) -> Result<()> {
    if !(args.resolution > 0.0 && args.resolution.is_finite()) {
        bail!(
            "--resolution must be a positive number of mm, got {}",
            args.resolution
        );
    }
    let table = parse_toml_library(TOOLS, "demo/tools.toml")?;
    let setup = JobSetup {
        machine: Machine::three_axis(),
        single: None,
        table: Some(table.clone()),
        read: ReadOptions::default(),
    };
    let job = setup.read_str(PROGRAM, "demo/demo.ngc")?;
    let path_report = PathReport::new(&job);
    let tools = defined_tools(&job)?;
    crate::commands::tools::check_resolution(tools, args.resolution)?;
    let program = &job.program;
    let mut stock = StockSpec::parse(STOCK)?.build(args.resolution, MeshOptions::default())?;
    let report = simulate(program, tools, &mut stock, &SimOptions::default())?;
    let mut summary = SimulateSummary::new(&report, program);

    let dir = &args.out;
    // Every file of the demo is written as one set: all of them, or none.
    let mut set = output_set(dir, args.max_output_mb)?;
    write_outputs(
        &mut set,
        program,
        &stock,
        &report,
        &mut summary,
        StockMeshOut::default(),
    )?;
    write_sources(&mut set, &job.setup.read)?;

    let t0 = std::time::Instant::now();
    let floor = wavy_floor();
    let json = swarf_surface::io::json::to_string(&floor).context("encoding the floor surface")?;
    set.write_bytes("floor.json", json.as_bytes())?;
    let surface = GougeSurface::new(&PreparedSurface::new(&floor));
    let opts = GougeOptions::DEFAULT;
    let gouge = check_program(&surface, program, tools, &opts)?;
    let gouge_summary = gouge.summary(
        &floor,
        &opts,
        program.moves.len(),
        t0.elapsed().as_secs_f64(),
    );
    crate::commands::gouge::write_outputs(
        &mut set,
        "gouge/",
        &floor,
        program,
        &gouge,
        &gouge_summary,
    )?;
    let demo = DemoReport {
        stock: STOCK,
        program: &path_report,
        simulation: &summary,
        gouge: &gouge_summary,
        out_dir: dir.display().to_string(),
    };
    let page = report_page(program, &table, &stock, &floor, &gouge, &demo)?;
    set.write_bytes("report.html", swarf_io::html::render(&page).as_bytes())?;
    set.commit()?;
    print_json(&demo)
}

/// The demo's summary with its sections' figures lifted to the top (`simulation.removed_volume_mm3`,
/// `gouge.max_gouge_mm`, …): the figures a page shows are top-level values.
fn flat_figures(v: &serde_json::Value) -> serde_json::Value {
    let mut out = serde_json::Map::new();
    if let Some(obj) = v.as_object() {
        for (k, x) in obj {
            match x.as_object() {
                Some(inner) if k != "program" => {
                    for (k2, y) in inner {
                        out.insert(format!("{k}.{k2}"), y.clone());
                    }
                }
                _ => {
                    out.insert(k.clone(), x.clone());
                }
            }
        }
    }
    serde_json::Value::Object(out)
}

/// The demo's HTML report: the program and its tools, the machined stock, the floor surface
/// and the toolpath in 3-D, the finishing raster's gouges linked to their lines, the figures.
fn report_page(
    program: &swarf_path::Program,
    table: &swarf_tool::ToolTable,
    stock: &swarf_stock::TriDexel,
    floor: &CompoundSurface,
    gouge: &swarf_plan::gouge::GougeReport,
    demo: &DemoReport<'_>,
) -> Result<swarf_io::html::Report> {
    use crate::commands::report as page;
    let tools: Vec<(u32, String, &swarf_tool::Cutter)> = table
        .tools
        .iter()
        .map(|(n, t)| (*n, t.description.clone(), &t.cutter))
        .collect();
    let (mesh, _) = stock.to_mesh(&swarf_io::ContourOptions::default());
    let part = swarf_surface::tessellate(floor, 61, &swarf_surface::Tolerances::DEFAULT);
    let rows = gouge.violations.iter().map(|v| {
        let row = swarf_io::html::DefectRow {
            cells: vec![
                v.move_index.to_string(),
                format!("demo/demo.ngc:{}", v.line),
                v.kind.as_str().to_string(),
                format!("{:.4}", v.depth),
            ],
            line: Some(("demo/demo.ngc".to_string(), v.line)),
        };
        (row, Some((v.point, [0.85, 0.05, 0.05])))
    });
    Ok(
        page::program_page("swarf demo", Path::new("demo/demo.ngc"), program, &tools)?
            .with_input("stock", STOCK)
            .with_mesh("machined stock", mesh)
            .with_mesh("design floor", part.mesh)
            .with_rows(&["move", "line", "kind", "depth mm"], rows)
            .with_sources(&[("demo/demo.ngc".to_string(), PROGRAM.to_string())])
            .with_summary(flat_figures(&serde_json::to_value(demo)?), &[]),
    )
}

/// The program, its tool library and its LinuxCNC canonical motion, beside the results.
fn write_sources(set: &mut OutputSet, options: &ReadOptions) -> Result<()> {
    set.write_bytes("demo.ngc", PROGRAM.as_bytes())?;
    set.write_bytes("tools.toml", TOOLS.as_bytes())?;
    let mut printer = CanonicalPrinter::new(Vec::new());
    stream_program(PROGRAM, "demo/demo.ngc", options, &mut printer)?;
    let canonical = printer.finish().context("printing the canonical motion")?;
    set.write_bytes("canonical.txt", &canonical)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use swarf_surface::ParametricSurface;

    #[test]
    fn the_demo_floor_follows_its_formula_within_1e_4_mm() {
        let floor = wavy_floor();
        let Surface::Nurbs(s) = &floor.patches[0].surface else {
            panic!("not a NURBS");
        };
        let k = 9f64.to_radians();
        let mut worst: f64 = 0.0;
        for i in 0..=240 {
            for j in 0..=160 {
                let (u, v) = (30.0 * i as f64 / 240.0, 20.0 * j as f64 / 160.0);
                let p = s.point(u, v);
                let z = -6.0 + 1.5 * (k * p.x).sin() * (k * p.y).cos();
                worst = worst.max((p.z - z).abs());
            }
        }
        assert!(worst < 1e-4, "{worst}");
        assert!(worst > 0.0);
    }
}
