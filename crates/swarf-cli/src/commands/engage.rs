//! `swarf engage`: the cutter–workpiece engagement at every cutter location of a program.

use crate::output::say;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{bail, Context, Result};
use clap::Args;
use serde::Serialize;
use swarf_engage::{EngageError, EngageOptions, Engagement, Engager};
use swarf_job::Job;
use swarf_path::Program;
use swarf_stock::TriDexel;
use swarf_tool::ToolSet;

use crate::cli::SetupArgs;
use crate::commands::plots;
use crate::commands::simulate::{build_stock, collision_reports, positive_mm, CollisionReport};
use crate::commands::tools::{defined_tools, job_error, load_job, load_job_setup};
use crate::output::{csv_field, output_set, print_json, DEFAULT_MAX_OUTPUT_MB};

/// What a run along a program needs: the stock, the program, its tools and the engagement's
/// sampling. Shared by `engage`, `forces` and `schedule`.
#[derive(Debug, Args)]
pub(crate) struct RunArgs {
    /// The stock: `box:X0,Y0,Z0,X1,Y1,Z1`, `cyl:CX,CY,Z0,R,H` (axis +Z) or a closed STL file.
    /// Default: the workpiece a CAMotics project (--tools FILE.camotics) states.
    #[arg(long, value_name = "SPEC|FILE.stl")]
    stock: Option<String>,
    /// The program: G-code, APT CL, Heidenhain conversational or Sinumerik (required).
    #[arg(long, value_name = "FILE")]
    program: Option<PathBuf>,
    /// Cutters, tool library, machine and units.
    #[command(flatten)]
    setup: SetupArgs,
    /// Ray spacing of the tri-dexel stock, mm (the engagement's accuracy follows it).
    #[arg(
        long,
        value_name = "H",
        default_value_t = 0.1,
        allow_negative_numbers = true
    )]
    resolution: f64,
    /// Cutter locations every STEP mm of tool-tip travel along a feed move (0: move ends only).
    #[arg(long, value_name = "MM", default_value_t = swarf_engage::DEFAULT_STEP_MM, allow_negative_numbers = true)]
    step: f64,
    /// Height of the axial discs (and width of the bottom rings), mm, at most 1.
    #[arg(long, value_name = "MM", default_value_t = swarf_engage::DEFAULT_DZ_MM, allow_negative_numbers = true)]
    dz: f64,
    /// Immersion-angle sampling, degrees.
    #[arg(long, value_name = "DEG", default_value_t = swarf_engage::DEFAULT_DPHI_DEG, allow_negative_numbers = true)]
    dphi: f64,
    /// Largest distance between an arc or a 5-axis motion and what is cut for it, mm.
    #[arg(long, value_name = "T", default_value_t = swarf_stock::DEFAULT_CHORDAL_TOLERANCE_MM, allow_negative_numbers = true)]
    tolerance: f64,
    /// Build the stock from an STL mesh even if it is not closed.
    #[arg(long)]
    allow_open_mesh: bool,
}

/// A run's inputs, read and checked.
pub(crate) struct Prepared {
    pub(crate) program: Program,
    pub(crate) tools: ToolSet,
    pub(crate) stock: TriDexel,
    pub(crate) opts: EngageOptions,
}

impl RunArgs {
    /// The program file.
    pub(crate) fn program(&self) -> Result<&Path> {
        match &self.program {
            Some(p) => Ok(p),
            None => bail!(
                "--program FILE is required (the G-code, APT CL, Heidenhain or Sinumerik program to run)"
            ),
        }
    }

    /// The files this run reads that an output must not replace: the program, the stock and
    /// machine files, the tool library.
    pub(crate) fn input_files(&self) -> Vec<PathBuf> {
        let mut files: Vec<PathBuf> = self.program.iter().cloned().collect();
        files.extend(self.setup.tools.iter().cloned());
        for spec in [self.stock.as_deref(), Some(self.setup.machine.as_str())]
            .into_iter()
            .flatten()
        {
            if Path::new(spec).is_file() {
                files.push(PathBuf::from(spec));
            }
        }
        files
    }

    /// The tool library given with --tools, if any.
    pub(crate) fn tools_file(&self) -> Option<&Path> {
        self.setup.tools.as_deref()
    }

    /// What holds before the program's first line: whether it is in inches (--initial-units,
    /// else the --ini machine's units) and the --ini machine's start-up code, which runs
    /// first.
    pub(crate) fn initial_state(&self) -> Result<(bool, Option<String>)> {
        let setup = load_job_setup(&self.setup)?;
        let g = &setup.read.gcode;
        let startup = g
            .ini
            .as_ref()
            .and_then(|i| i.startup_code())
            .map(|(c, _)| c.to_string());
        Ok((g.initial_units == swarf_path::Units::Inch, startup))
    }

    /// Reads program text (`name` in messages) with this run's machine and units, its
    /// subroutine files looked for beside the program first.
    pub(crate) fn read_program_str(&self, text: &str, name: &str) -> Result<Program> {
        let mut setup = load_job_setup(&self.setup)?;
        setup.search_program_folder(self.program()?);
        setup.read_program_str(text, name).map_err(job_error)
    }

    /// The stock as given.
    pub(crate) fn stock_label(&self) -> String {
        self.stock
            .clone()
            .unwrap_or_else(|| "from the tool project".into())
    }

    /// A report page for a run: the program, its tools, the stock as given and as machined
    /// (the run's stock after the walk), the toolpath.
    pub(crate) fn report_page(
        &self,
        title: &str,
        run: &Prepared,
    ) -> Result<swarf_io::html::Report> {
        use crate::commands::report;
        let tools = report::program_tools(&run.program, &run.tools);
        let (mesh, _) = run.stock.to_mesh(&swarf_io::ContourOptions::default());
        Ok(
            report::program_page(title, self.program()?, &run.program, &tools)?
                .with_input("stock", self.stock_label())
                .with_input("resolution", format!("{} mm", self.resolution))
                .with_mesh("machined stock", mesh),
        )
    }

    /// Reads the program and tools, builds the stock and checks the options.
    pub(crate) fn prepare(&self) -> Result<Prepared> {
        positive_mm("resolution", self.resolution)?;
        let opts = EngageOptions::default()
            .with_step(self.step)
            .with_dz(self.dz)
            .with_dphi(self.dphi)
            .with_chordal_tolerance(self.tolerance);
        // Before any work: `forces` builds its edges at the discs' height (at `--dz 0` for
        // ever) before the engagement would check it.
        opts.check()?;
        let job = load_job(&self.setup, self.program()?)?;
        defined_tools(&job)?;
        let Job {
            program,
            tools,
            setup,
            ..
        } = job;
        crate::commands::tools::check_resolution(&tools, self.resolution)?;
        let stock = build_stock(
            self.stock.as_deref(),
            setup.table.as_ref(),
            (&program, &tools),
            self.resolution,
            self.allow_open_mesh,
        )?;
        Ok(Prepared {
            program,
            tools,
            stock,
            opts,
        })
    }
}

/// What the engagement's cuts hit besides cutting — rapids through the material, shanks or
/// holders in it — with the keys of `simulate`'s summary (`rapid_collisions` and
/// `holder_collisions` count them, `collisions` lists them). The material is removed, as
/// `simulate` removes it.
#[derive(Serialize)]
pub(crate) struct Collisions {
    rapid_collisions: usize,
    holder_collisions: usize,
    collisions: Vec<CollisionReport>,
}

impl Collisions {
    /// Warns of each collision on stderr, `note` added to a rapid's warning (what the
    /// command does or does not do about it).
    pub(crate) fn warn(&self, rapid_note: &str, holder_note: &str) {
        for c in &self.collisions {
            let (what, note) = if c.kind == "rapid" {
                ("a rapid through the material", rapid_note)
            } else {
                ("the shank or holder in the material", holder_note)
            };
            eprintln!(
                "swarf: warning: {}:{}: {what} (move {}, {:.3} mm³ removed){note}",
                c.collision.file, c.collision.line, c.collision.move_index, c.collision.volume_mm3
            );
        }
    }
}

/// A walk's figures and collisions.
pub(crate) struct Walked {
    pub(crate) stats: swarf_engage::EngageStats,
    pub(crate) collisions: Collisions,
}

/// Walks the engagement along the program, handing each location to `each`, with a progress
/// bar and Ctrl-C (which stops the run with an error: no output is written).
pub(crate) fn walk(
    run: &mut Prepared,
    file: &Path,
    mut each: impl FnMut(Engagement) -> Result<()>,
) -> Result<Walked> {
    let progress = crate::output::MovesProgress::new(run.program.moves.len());
    let mut engager =
        Engager::new(&run.program, &run.tools, &mut run.stock, run.opts)?.observed(&progress);
    for e in engager.by_ref() {
        let e = match e {
            Err(EngageError::Cancelled { locations }) => {
                progress.finish();
                bail!("stopped by Ctrl-C after {locations} cutter locations; no output written");
            }
            e => e.with_context(|| format!("engagement along {}", file.display()))?,
        };
        each(e)?;
    }
    progress.finish();
    let (rapid, holder) = (engager.rapid_collisions(), engager.holder_collisions());
    Ok(Walked {
        stats: engager.stats(),
        collisions: Collisions {
            rapid_collisions: rapid.len(),
            holder_collisions: holder.len(),
            collisions: collision_reports(rapid, holder),
        },
    })
}

#[derive(Debug, Args)]
pub(crate) struct EngageArgs {
    #[command(flatten)]
    run: RunArgs,
    /// Also draw the φ–z maps of these locations (comma-separated indices).
    #[arg(long, value_name = "N,...", value_delimiter = ',')]
    map_at: Vec<usize>,
    /// Write engagement.csv, discs.csv, bottom.csv, maps/ and summary.json here.
    #[arg(long, value_name = "DIR")]
    out: PathBuf,
    /// Also write one self-contained HTML report here (inputs, tools, the machined stock and
    /// the toolpath in 3-D, the φ–z maps and the area and MRR curves, the summary's figures).
    #[arg(long, value_name = "FILE.html")]
    report: Option<PathBuf>,
    /// Print the JSON summary.
    #[arg(long)]
    json: bool,
}

/// The JSON summary (`summary.json`). The first seven keys are a contract.
#[derive(Serialize)]
struct EngageSummary {
    locations: usize,
    engaged_locations: usize,
    max_area_mm2: f64,
    max_ap_mm: f64,
    removed_volume_mm3: f64,
    elapsed_s: f64,
    simulate_elapsed_s: f64,
    /// Location of the largest area (its φ–z map is `maps/largest.png`).
    max_area_location: Option<usize>,
    resolution_mm: [f64; 3],
    options: EngageOptions,
    /// Rapids and holders in the material, as `simulate` reports them.
    #[serde(flatten)]
    collisions: Collisions,
}

pub(crate) fn run(args: &EngageArgs) -> Result<()> {
    crate::commands::report::prepare(args.report.as_deref())?;
    let t0 = Instant::now();
    let mut run = args.run.prepare()?;
    let opts = run.opts;
    let mut locations: Vec<Engagement> = Vec::new();
    let Walked { stats, collisions } = walk(&mut run, args.run.program()?, |e| {
        locations.push(e);
        Ok(())
    })?;
    collisions.warn(
        " — its volume is in removed_volume_mm3 but at no cutter location",
        " — its volume is in removed_volume_mm3, not in the engagement",
    );
    let resolution_mm = run.stock.grid().h;
    let largest = locations
        .iter()
        .filter(|e| e.is_engaged())
        .max_by(|a, b| a.area_mm2.total_cmp(&b.area_mm2));
    let summary = EngageSummary {
        locations: stats.locations,
        engaged_locations: stats.engaged_locations,
        max_area_mm2: largest.map_or(0.0, |e| e.area_mm2),
        max_ap_mm: locations.iter().map(|e| e.ap_mm).fold(0.0, f64::max),
        removed_volume_mm3: stats.removed_volume_mm3,
        elapsed_s: t0.elapsed().as_secs_f64(),
        simulate_elapsed_s: stats.simulate_elapsed_s,
        max_area_location: largest.map(|e| e.location),
        resolution_mm,
        options: opts,
        collisions,
    };
    write_outputs(
        &args.out,
        &locations,
        largest,
        &args.map_at,
        opts.dz_mm,
        &summary,
    )?;
    if let Some(path) = &args.report {
        let page = args.run.report_page("swarf engage", &run)?;
        let page = page
            .with_pngs_in(&args.out.join("maps"))?
            .with_summary(serde_json::to_value(&summary)?, SUMMARY_KEYS);
        crate::commands::report::write(&page, path)?;
    }
    if args.json {
        print_json(&summary)
    } else {
        say!(
            "{} cutter locations, {} engaged; largest area {:.3} mm², deepest {:.3} mm; {:.3} mm³ removed; {:.2} s ({:.2} s cutting the stock)",
            summary.locations,
            summary.engaged_locations,
            summary.max_area_mm2,
            summary.max_ap_mm,
            summary.removed_volume_mm3,
            summary.elapsed_s,
            summary.simulate_elapsed_s
        );
        Ok(())
    }
}

fn opt(x: Option<f64>) -> String {
    x.map(|v| format!("{v}")).unwrap_or_default()
}

/// `engagement.csv`, `discs.csv`, `bottom.csv`.
fn tables(locations: &[Engagement]) -> [String; 3] {
    let mut main = String::from(
        "location,move,file,line,s,x,y,z,i,j,k,area_mm2,ap_mm,phi_entry_deg,phi_exit_deg,removed_mm3,mrr_mm3_min\n",
    );
    let mut discs = String::from("location,z_mm,phi_start_deg,phi_end_deg\n");
    let mut bottom = String::from("location,r_mm,phi_start_deg,phi_end_deg\n");
    for e in locations {
        let _ = writeln!(
            main,
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
            e.location,
            e.move_index,
            csv_field(&e.file),
            e.line,
            e.s,
            e.tip.x,
            e.tip.y,
            e.tip.z,
            e.axis.x,
            e.axis.y,
            e.axis.z,
            e.area_mm2,
            e.ap_mm,
            opt(e.phi_entry_deg),
            opt(e.phi_exit_deg),
            e.removed_mm3,
            e.mrr_mm3_min
        );
        for (out, circles) in [(&mut discs, &e.discs), (&mut bottom, &e.bottom)] {
            for c in circles {
                for iv in &c.intervals {
                    for (a, b) in iv.split_at_zero() {
                        if b > a {
                            let _ = writeln!(out, "{},{},{a},{b}", e.location, c.at_mm);
                        }
                    }
                }
            }
        }
    }
    [main, discs, bottom]
}

/// Every output as one set: all of the files, or none.
fn write_outputs(
    dir: &Path,
    locations: &[Engagement],
    largest: Option<&Engagement>,
    map_at: &[usize],
    dz: f64,
    summary: &EngageSummary,
) -> Result<()> {
    for &n in map_at {
        if n >= locations.len() {
            bail!(
                "--map-at {n}: the program has {} cutter locations",
                locations.len()
            );
        }
    }
    let mut set = output_set(dir, DEFAULT_MAX_OUTPUT_MB)?;
    set.owns_files("maps", &["location_", "largest"]);
    let [main, discs, bottom] = tables(locations);
    set.write_bytes("engagement.csv", main.as_bytes())?;
    set.write_bytes("discs.csv", discs.as_bytes())?;
    set.write_bytes("bottom.csv", bottom.as_bytes())?;
    if let Some(e) = largest {
        plots::phi_z_map(e, dz, &mut set, "maps/largest.png")?;
        plots::bottom_map(e, dz, &mut set, "maps/largest_bottom.png")?;
    }
    for &n in map_at {
        let e = &locations[n];
        plots::phi_z_map(e, dz, &mut set, &format!("maps/location_{n}.png"))?;
        plots::bottom_map(e, dz, &mut set, &format!("maps/location_{n}_bottom.png"))?;
    }
    plots::along_program(locations, &mut set, "maps/")?;
    let mut json = serde_json::to_vec_pretty(summary)?;
    json.push(b'\n');
    set.write_bytes("summary.json", &json)?;
    set.commit()?;
    Ok(())
}

/// The contract keys of the summary, shown first on the report page.
const SUMMARY_KEYS: &[&str] = &[
    "locations",
    "engaged_locations",
    "max_area_mm2",
    "max_ap_mm",
    "removed_volume_mm3",
    "elapsed_s",
    "simulate_elapsed_s",
];
