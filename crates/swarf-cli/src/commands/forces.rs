//! `swarf forces`: cutting forces, torque and power at every cutter location of a program.

use crate::output::say;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{bail, Context, Result};
use clap::Args;
use rayon::prelude::*;
use serde::Serialize;
use swarf_engage::Engagement;
use swarf_force::{ForceCurves, ForceModel, LocationForces, Material};
use swarf_tool::ToolSource;

use crate::commands::engage::{walk, Prepared, RunArgs, Walked};
use crate::commands::plots::{self, Series, PALETTE};
use crate::output::{csv_field, output_set, print_json, DEFAULT_MAX_OUTPUT_MB};

/// The work material: a built-in name or a coefficient file.
#[derive(Debug, Args)]
pub(crate) struct MaterialArgs {
    /// A built-in material (see --list-materials).
    #[arg(long, value_name = "NAME", conflicts_with = "coefficients")]
    material: Option<String>,
    /// A material file: TOML with name, ktc, krc, kac (N/mm²), kte, kre, kae (N/mm), source.
    #[arg(long, value_name = "FILE")]
    coefficients: Option<PathBuf>,
    /// Spindle-angle samples per revolution.
    #[arg(long, value_name = "N", default_value_t = swarf_force::DEFAULT_SAMPLES_PER_REV)]
    pub(crate) samples_per_rev: usize,
    /// Flute count of the library tools that state none (a LinuxCNC .tbl cannot hold one);
    /// a count the spec or library gives wins.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=1000))]
    pub(crate) flutes: Option<u32>,
}

impl MaterialArgs {
    /// The coefficient file, if one is given.
    pub(crate) fn file(&self) -> Option<&Path> {
        self.coefficients.as_deref()
    }

    pub(crate) fn load(&self) -> Result<Material> {
        match (&self.material, &self.coefficients) {
            (Some(name), None) => Ok(swarf_force::builtin_material(name)?),
            (None, Some(file)) => {
                let text = std::fs::read_to_string(file)
                    .with_context(|| format!("reading {}", file.display()))?;
                Ok(swarf_force::parse_material(
                    &text,
                    &file.display().to_string(),
                )?)
            }
            _ => bail!(
                "give the work material: --material NAME (built in: {}) or --coefficients FILE",
                swarf_force::builtin_materials()
                    .iter()
                    .map(|m| m.name.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        }
    }
}

/// The force model of a prepared run (`run_args` its options, `args` the material's).
pub(crate) fn model(
    run: &Prepared,
    run_args: &RunArgs,
    args: &MaterialArgs,
    material: Material,
) -> Result<ForceModel> {
    let mut used: Vec<u32> = run.program.tools.clone();
    used.extend(run.program.moves.iter().map(|m| m.tool));
    used.sort_unstable();
    used.dedup();
    let model = ForceModel::with_default_flutes(
        material,
        &run.tools,
        &used,
        &run.opts,
        args.samples_per_rev,
        args.flutes,
    );
    match model {
        Err(swarf_force::ForceError::NoFlutes { tool, number }) => {
            // Say where the tool came from, and how to give its flutes there.
            let source = number
                .and_then(|n| run.tools.resolved().get(&n))
                .map(|r| r.source);
            let how = match (source, run_args.tools_file()) {
                (Some(ToolSource::Table), Some(file)) => {
                    let name = file.display();
                    let tbl = file
                        .extension()
                        .is_some_and(|e| e.eq_ignore_ascii_case("tbl"));
                    if tbl {
                        format!(
                            "the LinuxCNC tool table {name} cannot hold a flute count: give --flutes N for the library tools that state none"
                        )
                    } else {
                        format!(
                            "add `flutes = N` to its entry in the tool library {name}, or give --flutes N for the library tools that state none"
                        )
                    }
                }
                (Some(ToolSource::Program), _) => {
                    "its CUTTER/ record in the program holds none: give --flutes N".to_string()
                }
                _ => "add flutes=N to its --tool spec".to_string(),
            };
            bail!("{tool} has no flute count, which the force model needs: {how}")
        }
        m => Ok(m?),
    }
}

/// Hands the engagements to `each_batch` in batches, so that their forces can be computed in
/// parallel while the engagement walks on.
pub(crate) fn walk_batches(
    run: &mut Prepared,
    file: &Path,
    mut each_batch: impl FnMut(&[Engagement]) -> Result<()>,
) -> Result<Walked> {
    const BATCH: usize = 256;
    let mut batch = Vec::with_capacity(BATCH);
    let walked = walk(run, file, |e| {
        batch.push(e);
        if batch.len() == BATCH {
            each_batch(&batch)?;
            batch.clear();
        }
        Ok(())
    })?;
    each_batch(&batch)?;
    Ok(walked)
}

#[derive(Debug, Args)]
pub(crate) struct ForcesArgs {
    #[command(flatten)]
    run: RunArgs,
    #[command(flatten)]
    material: MaterialArgs,
    /// List the built-in materials and their sources, and stop.
    #[arg(long, exclusive = true)]
    list_materials: bool,
    /// Also write the force-versus-angle curves of these locations (comma-separated indices).
    #[arg(long, value_name = "N,...", value_delimiter = ',')]
    curves_at: Vec<usize>,
    /// Write forces.csv, curves.csv, plots/ and summary.json here (required).
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
    /// Also write one self-contained HTML report here (inputs, tools, the machined stock and
    /// the toolpath in 3-D, the force, torque and power curves, the summary's figures).
    #[arg(long, value_name = "FILE.html")]
    report: Option<PathBuf>,
    /// Print the JSON summary.
    #[arg(long)]
    json: bool,
}

/// The JSON summary (`summary.json`); the first six keys are a contract.
#[derive(Serialize)]
struct ForcesSummary {
    locations: usize,
    max_force_n: f64,
    max_torque_nm: f64,
    max_power_w: f64,
    /// Mean spindle power over the engaged locations, W.
    mean_power_w: f64,
    elapsed_s: f64,
    engaged_locations: usize,
    /// Location of the largest peak resultant force.
    max_force_location: Option<usize>,
    /// Engaged locations with the spindle stopped (no chip: edge forces only).
    engaged_without_spindle: usize,
    material: String,
    material_source: String,
    samples_per_rev: usize,
    engage_elapsed_s: f64,
    /// Rapids and holders in the material, as `simulate` reports them.
    #[serde(flatten)]
    collisions: crate::commands::engage::Collisions,
}

/// One row of forces.csv.
/// What stops the spindle, for the warnings of `forces` and `schedule`.
pub(crate) const SPINDLE_STOPPED: &str = "no S word, S0, M5, or an M6 that stops it";

struct Row {
    location: usize,
    move_index: usize,
    file: String,
    line: u32,
    tip: [f64; 3],
    engaged: bool,
    spindle: bool,
    f: LocationForces,
}

pub(crate) fn run(args: &ForcesArgs) -> Result<()> {
    crate::commands::report::prepare(args.report.as_deref())?;
    if args.list_materials {
        return list_materials(args.json);
    }
    let t0 = Instant::now();
    let run_args = &args.run;
    let Some(out) = &args.out else {
        bail!("--out DIR is required (where forces.csv, curves.csv, plots/ and summary.json go)");
    };
    let material = args.material.load()?;
    let mut run = run_args.prepare()?;
    let model = model(&run, run_args, &args.material, material)?;
    let mut rows: Vec<Row> = Vec::new();
    let mut curves: Vec<(usize, ForceCurves)> = Vec::new();
    let t_engage = Instant::now();
    let mut force_s = 0.0;
    let walked = walk_batches(&mut run, run_args.program()?, |batch| {
        let t = Instant::now();
        let done: Vec<(Row, Option<ForceCurves>)> = batch
            .par_iter()
            .map(|e| {
                let ev = model.evaluate(e);
                let (f, c) = model.forces(&ev, None);
                let row = Row {
                    location: e.location,
                    move_index: e.move_index,
                    file: e.file.clone(),
                    line: e.line,
                    tip: [e.tip.x, e.tip.y, e.tip.z],
                    engaged: ev.unit.engaged,
                    spindle: e.spindle_rpm > 0.0,
                    f,
                };
                (row, args.curves_at.contains(&e.location).then_some(c))
            })
            .collect();
        for (row, c) in done {
            if let Some(c) = c {
                curves.push((row.location, c));
            }
            rows.push(row);
        }
        force_s += t.elapsed().as_secs_f64();
        Ok(())
    })?;
    for &n in &args.curves_at {
        if n >= rows.len() {
            bail!(
                "--curves-at {n}: the program has {} cutter locations",
                rows.len()
            );
        }
    }
    walked.collisions.warn(
        " — no forces at a rapid: it has no cutter locations",
        " — the force model counts the cutting part only",
    );
    let engaged: Vec<&Row> = rows.iter().filter(|r| r.engaged).collect();
    let without_spindle = engaged.iter().filter(|r| !r.spindle).count();
    if let Some(first) = engaged.iter().find(|r| !r.spindle) {
        eprintln!(
            "swarf: warning: {without_spindle} engaged cutter locations with the spindle stopped ({SPINDLE_STOPPED}), the first at {}:{}: no chip, edge forces only",
            first.file, first.line
        );
    }
    let max_by = |f: fn(&LocationForces) -> f64| rows.iter().map(|r| f(&r.f)).fold(0.0, f64::max);
    let largest = rows
        .iter()
        .filter(|r| r.engaged)
        .max_by(|a, b| a.f.peak_resultant_n.total_cmp(&b.f.peak_resultant_n));
    let summary = ForcesSummary {
        locations: rows.len(),
        max_force_n: max_by(|f| f.peak_resultant_n),
        max_torque_nm: max_by(|f| f.torque_peak_nm),
        max_power_w: max_by(|f| f.power_peak_w),
        mean_power_w: if engaged.is_empty() {
            0.0
        } else {
            engaged.iter().map(|r| r.f.power_mean_w).sum::<f64>() / engaged.len() as f64
        },
        elapsed_s: t0.elapsed().as_secs_f64(),
        engaged_locations: engaged.len(),
        max_force_location: largest.map(|r| r.location),
        engaged_without_spindle: without_spindle,
        material: model.material().name.clone(),
        material_source: model.material().source.clone(),
        samples_per_rev: model.samples_per_rev(),
        engage_elapsed_s: (t_engage.elapsed().as_secs_f64() - force_s).max(0.0),
        collisions: walked.collisions,
    };
    write_outputs(out, &rows, &curves, &summary)?;
    if let Some(path) = &args.report {
        let page = run_args
            .report_page("swarf forces", &run)?
            .with_input("material", summary.material.clone())
            .with_pngs_in(&out.join("plots"))?
            .with_summary(
                serde_json::to_value(&summary)?,
                &[
                    "locations",
                    "max_force_n",
                    "max_torque_nm",
                    "max_power_w",
                    "mean_power_w",
                    "elapsed_s",
                ],
            );
        crate::commands::report::write(&page, path)?;
    }
    if args.json {
        print_json(&summary)
    } else {
        say!(
            "{} cutter locations, {} engaged; peak force {:.1} N, torque {:.3} N·m, power {:.0} W (mean {:.0} W); material {}; {:.2} s",
            summary.locations,
            summary.engaged_locations,
            summary.max_force_n,
            summary.max_torque_nm,
            summary.max_power_w,
            summary.mean_power_w,
            summary.material,
            summary.elapsed_s
        );
        Ok(())
    }
}

fn list_materials(json: bool) -> Result<()> {
    let all = swarf_force::builtin_materials();
    if json {
        return print_json(&all);
    }
    for m in all {
        let kind = if m.is_fixed() {
            "fixed coefficients"
        } else {
            "predicted from the tool's rake and helix (oblique transformation)"
        };
        say!("{}: {kind}\n  source: {}", m.name, m.source);
    }
    Ok(())
}

fn forces_csv(rows: &[Row]) -> String {
    let mut s = String::from(
        "location,move,file,line,x,y,z,feed_per_tooth_mm,fx_mean_n,fy_mean_n,fz_mean_n,fx_peak_n,fy_peak_n,fz_peak_n,f_peak_n,wx_mean_n,wy_mean_n,wz_mean_n,torque_mean_nm,torque_peak_nm,power_mean_w,power_peak_w\n",
    );
    for r in rows {
        let f = &r.f;
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
            r.location,
            r.move_index,
            csv_field(&r.file),
            r.line,
            r.tip[0],
            r.tip[1],
            r.tip[2],
            f.feed_per_tooth_mm,
            f.mean_n[0],
            f.mean_n[1],
            f.mean_n[2],
            f.peak_n[0],
            f.peak_n[1],
            f.peak_n[2],
            f.peak_resultant_n,
            f.mean_world_n[0],
            f.mean_world_n[1],
            f.mean_world_n[2],
            f.torque_mean_nm,
            f.torque_peak_nm,
            f.power_mean_w,
            f.power_peak_w
        );
    }
    s
}

fn write_outputs(
    dir: &Path,
    rows: &[Row],
    curves: &[(usize, ForceCurves)],
    summary: &ForcesSummary,
) -> Result<()> {
    // Every output as one set: all of the files, or none.
    let mut set = output_set(dir, DEFAULT_MAX_OUTPUT_MB)?;
    set.owns_files("plots", &["curves_location_"]);
    set.write_bytes("forces.csv", forces_csv(rows).as_bytes())?;
    let mut csv = String::from("location,angle_deg,fx_n,fy_n,fz_n,torque_nm\n");
    for (loc, c) in curves {
        let full: Vec<[f64; 4]> = (0..c.samples)
            .map(|j| std::array::from_fn(|o| c.at(o, j)))
            .collect();
        for (j, v) in full.iter().enumerate() {
            let angle = 360.0 * j as f64 / c.samples as f64;
            let _ = writeln!(csv, "{loc},{angle},{},{},{},{}", v[0], v[1], v[2], v[3]);
        }
        let col = |o: usize| full.iter().map(|v| v[o]).collect::<Vec<f64>>();
        let (fx, fy, fz) = (col(0), col(1), col(2));
        let series = [
            Series {
                name: "Fx (x_L)",
                values: &fx,
                colour: PALETTE[0],
            },
            Series {
                name: "Fy (y_L)",
                values: &fy,
                colour: PALETTE[1],
            },
            Series {
                name: "Fz (z_L)",
                values: &fz,
                colour: PALETTE[2],
            },
        ];
        plots::lines(
            &series,
            (0.0, 360.0),
            &format!("forces over one revolution at location {loc}"),
            "spindle angle (deg)",
            "force on the tool (N)",
            &mut set,
            &format!("plots/curves_location_{loc}.png"),
        )?;
    }
    set.write_bytes("curves.csv", csv.as_bytes())?;
    let along = |f: fn(&LocationForces) -> f64| rows.iter().map(|r| f(&r.f)).collect::<Vec<f64>>();
    plots::curve(
        &along(|f| f.peak_resultant_n),
        "peak resultant force along the program",
        "force (N)",
        &mut set,
        "plots/peak_force.png",
    )?;
    plots::curve(
        &along(|f| f.torque_peak_nm),
        "peak spindle torque along the program",
        "torque (N m)",
        &mut set,
        "plots/torque.png",
    )?;
    plots::curve(
        &along(|f| f.power_peak_w),
        "peak spindle power along the program",
        "power (W)",
        &mut set,
        "plots/power.png",
    )?;
    let mut json = serde_json::to_vec_pretty(summary)?;
    json.push(b'\n');
    set.write_bytes("summary.json", &json)?;
    set.commit()?;
    Ok(())
}
