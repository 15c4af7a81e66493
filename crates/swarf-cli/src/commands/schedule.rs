//! `swarf schedule`: feeds per move that keep the predicted peak force, torque or power under a
//! limit, written back into the program with only its feed words changed.

use crate::output::say;
use std::collections::BTreeMap;
use std::path::PathBuf;
use std::time::Instant;

use anyhow::{bail, Context, Result};
use clap::Args;
use rayon::prelude::*;
use serde::Serialize;
use swarf_force::{schedule_feeds, Limit, LocationCap, MoveCaps, ScheduleOptions};
use swarf_path::load::ProgramFormat;
use swarf_path::rewrite::SplitPiece;
use swarf_path::{MoveKind, Program};

use crate::commands::engage::RunArgs;
use crate::commands::forces::{model, walk_batches, MaterialArgs};
use crate::output::{output_set, print_json, DEFAULT_MAX_OUTPUT_MB};

#[derive(Debug, Args)]
#[command(group(clap::ArgGroup::new("limit").required(true).args(["limit_force", "limit_torque", "limit_power"])))]
pub(crate) struct ScheduleArgs {
    #[command(flatten)]
    run: RunArgs,
    #[command(flatten)]
    material: MaterialArgs,
    /// Largest peak resultant force on the tool, N.
    #[arg(long, value_name = "N", allow_negative_numbers = true)]
    limit_force: Option<f64>,
    /// Largest peak spindle torque, N·m.
    #[arg(long, value_name = "NM", allow_negative_numbers = true)]
    limit_torque: Option<f64>,
    /// Largest peak spindle power, W.
    #[arg(long, value_name = "W", allow_negative_numbers = true)]
    limit_power: Option<f64>,
    /// Slowest feed, mm/min.
    #[arg(
        long,
        value_name = "MM_MIN",
        default_value_t = 1.0,
        allow_negative_numbers = true
    )]
    min_feed: f64,
    /// Fastest feed, mm/min (default: never faster than programmed).
    #[arg(long, value_name = "MM_MIN", allow_negative_numbers = true)]
    max_feed: Option<f64>,
    /// Largest change of feed between consecutive feed moves, percent.
    #[arg(long, value_name = "P", allow_negative_numbers = true)]
    max_step_percent: Option<f64>,
    /// Split a straight G-code feed move whose engagement varies into pieces with their own
    /// feeds (at the cutter locations, every --step mm; pieces whose caps are within 10 % of
    /// each other merged). The pieces are written as incremental moves in front of the line.
    #[arg(long)]
    split: bool,
    /// The scheduled program (G-code or APT, as the input). A JSON summary goes beside it
    /// (FILE.schedule.json).
    #[arg(long, value_name = "FILE")]
    out: PathBuf,
    /// Print the JSON summary.
    #[arg(long)]
    json: bool,
}

/// A move still over the limit at the scheduled feed.
#[derive(Serialize)]
struct Over {
    #[serde(rename = "move")]
    move_index: usize,
    file: String,
    line: u32,
    feed_mm_min: f64,
    /// The feed the limit allows (0: even the edge forces alone exceed it).
    cap_mm_min: f64,
}

/// The JSON summary; the first four keys are a contract.
#[derive(Serialize)]
struct ScheduleSummary {
    moves_changed: usize,
    time_before_s: f64,
    time_after_s: f64,
    still_over_limit: Vec<Over>,
    lines_changed: usize,
    /// Feed moves split into pieces (`--split`), and the pieces added.
    moves_split: usize,
    pieces_added: usize,
    limit: Limit,
    material: String,
    elapsed_s: f64,
    /// Engaged cutter locations with the spindle stopped: no feed fixes them.
    engaged_without_spindle: usize,
    /// Rapids and holders in the material, as `simulate` reports them: no feed fixes them.
    #[serde(flatten)]
    collisions: crate::commands::engage::Collisions,
}

/// Feed moves must run in the order of their lines in the program's own file: the rewrite
/// works on the text.
fn check_straight_line(program: &Program) -> Result<()> {
    let mut last = 0u32;
    for m in &program.moves {
        if matches!(m.kind, MoveKind::Rapid) {
            continue;
        }
        let file = program
            .files
            .get(m.file as usize)
            .map_or("?", String::as_str);
        if m.file != 0 {
            bail!(
                "{file}:{}: a feed move in another file (a called subroutine): swarf schedule rewrites the feeds of one file, whose feed moves run in line order",
                m.line
            );
        }
        if m.line < last {
            bail!(
                "{file}:{}: this feed move runs after line {last} (a loop or subroutine): swarf schedule rewrites the feeds of straight-line programs, whose feed moves run in line order",
                m.line
            );
        }
        last = m.line;
    }
    Ok(())
}

pub(crate) fn run(args: &ScheduleArgs) -> Result<()> {
    let t0 = Instant::now();
    let limit = match (args.limit_force, args.limit_torque, args.limit_power) {
        (Some(v), None, None) => Limit::Force(v),
        (None, Some(v), None) => Limit::Torque(v),
        (None, None, Some(v)) => Limit::Power(v),
        _ => bail!("give exactly one of --limit-force, --limit-torque, --limit-power"),
    };
    if !(limit.value().is_finite() && limit.value() > 0.0) {
        bail!("the limit must be a positive number, got {}", limit.value());
    }
    if !(args.min_feed.is_finite() && args.min_feed > 0.0) {
        bail!(
            "--min-feed must be a positive feed in mm/min, got {}",
            args.min_feed
        );
    }
    if let Some(m) = args.max_feed {
        if !(m.is_finite() && m >= args.min_feed) {
            bail!(
                "--max-feed must be at least --min-feed ({}), got {m}",
                args.min_feed
            );
        }
    }
    if let Some(p) = args.max_step_percent {
        if !(p.is_finite() && p > 0.0) {
            bail!("--max-step-percent must be positive, got {p}");
        }
    }
    let material = args.material.load()?;
    let file = args.run.program()?.to_path_buf();
    // The scheduled program never replaces what the run reads (the program's old feeds, the
    // tool library, the coefficients would be lost with it).
    if let Ok(out) = args.out.canonicalize() {
        let inputs = args.run.input_files();
        let inputs = inputs
            .iter()
            .map(PathBuf::as_path)
            .chain(args.material.file());
        for input in inputs {
            if input.canonicalize().is_ok_and(|i| i == out) {
                bail!(
                    "--out {} is one of the run's inputs ({}): write the scheduled program to \
                     another file",
                    args.out.display(),
                    input.display()
                );
            }
        }
    }
    let text = swarf_path::load::read_text(&file)?;
    let format = ProgramFormat::detect(&file, &text);
    let mut run = args.run.prepare()?;
    check_straight_line(&run.program)?;
    let model = model(&run, &args.run, &args.material, material)?;
    let mut caps = MoveCaps::new(run.program.moves.len());
    let max_feed = args.max_feed;
    // Engaged locations with the spindle stopped, and the first one's (file, line): no feed
    // makes such a cut safe, so they are reported, not scheduled.
    let (mut without_spindle, mut first_without_spindle) = (0usize, None);
    let walked = walk_batches(&mut run, &file, |batch| {
        for e in batch
            .iter()
            .filter(|e| e.is_engaged() && e.spindle_rpm <= 0.0)
        {
            without_spindle += 1;
            first_without_spindle.get_or_insert_with(|| (e.file.clone(), e.line));
        }
        let found: Vec<(usize, f64, LocationCap)> = batch
            .par_iter()
            .map(|e| {
                let ev = model.evaluate(e);
                let per_tooth = e.spindle_rpm * ev.flutes as f64;
                let ceiling = max_feed.unwrap_or(e.feed_mm_min).max(args.min_feed);
                let c_max = if per_tooth > 0.0 {
                    ceiling / per_tooth
                } else {
                    0.0
                };
                (
                    e.move_index,
                    e.s,
                    LocationCap::of(&model, &ev, limit, c_max),
                )
            })
            .collect();
        for (i, s, c) in found {
            caps.add(i, s, c);
        }
        Ok(())
    })?;
    let opts = ScheduleOptions {
        limit,
        min_feed_mm_min: args.min_feed,
        max_feed_mm_min: args.max_feed,
        max_step_percent: args.max_step_percent,
        split: args.split,
    };
    let program = &run.program;
    let modes = match args.run.initial_state()? {
        // The machine's start-up code runs first: its G20/G91 hold at the program's first line.
        (inch, Some(code)) => {
            let mut m = swarf_path::rewrite::gcode_line_modes(&format!("{code}\n{text}"), inch);
            m.remove(0);
            m
        }
        (inch, None) => swarf_path::rewrite::gcode_line_modes(&text, inch),
    };
    let mut per_line: BTreeMap<u32, usize> = BTreeMap::new();
    for m in &program.moves {
        *per_line.entry(m.line).or_default() += 1;
    }
    // A move can be split when its pieces can be written as incremental straight moves: a
    // straight 3-axis G-code feed alone on its line, in G90, with no rotation or scaling of
    // the program frame, not in inverse time, on a line of nothing but its motion and feed
    // (pieces in front of `S… M3` or `G21` would run before those took effect).
    let can_split = |i: usize| {
        let m = &program.moves[i];
        let mode = modes.get(m.line as usize - 1);
        format == ProgramFormat::Gcode
            && matches!(m.kind, MoveKind::Linear)
            && m.feed_mode != swarf_path::FeedMode::InverseTime
            && (m.start.axis - m.end.axis).length() < 1e-12
            && m.start_joints.to_array()[3..] == m.end_joints.to_array()[3..]
            && per_line.get(&m.line) == Some(&1)
            && mode.is_some_and(|md| md.absolute && !md.transformed && md.plain)
    };
    // A G33/G33.1 move's speed is its lead times the spindle speed: no feed word changes it.
    let fixed = |i: usize| program.moves[i].feed_mode == swarf_path::FeedMode::SpindleSynchronised;
    let schedule = schedule_feeds(program, &caps, &opts, &can_split, &fixed);
    // One factor per line: moves sharing a line share its feed word, so the slowest wins; a
    // split move's line gets its last piece's factor and its other pieces go in front of it.
    let mut factors: BTreeMap<u32, f64> = BTreeMap::new();
    let mut splits: BTreeMap<u32, Vec<SplitPiece>> = BTreeMap::new();
    for m in &schedule.moves {
        // (A synchronised line keeps its text: no feed word carried over matters to it.)
        if m.old_feed_mm_min <= 0.0 || fixed(m.move_index) {
            continue;
        }
        let mv = &program.moves[m.move_index];
        let last = m.pieces.last().map_or(m.new_feed_mm_min, |p| p.feed_mm_min);
        let f = last / m.old_feed_mm_min;
        factors
            .entry(mv.line)
            .and_modify(|x| *x = x.min(f))
            .or_insert(f);
        if m.pieces.len() > 1 {
            let unit = if modes[mv.line as usize - 1].inch {
                25.4
            } else {
                1.0
            };
            let d = (mv.end.tip - mv.start.tip) / unit;
            let mut s0 = 0.0;
            let pieces = m.pieces[..m.pieces.len() - 1]
                .iter()
                .map(|p| {
                    let part = d * (p.s_end - s0);
                    s0 = p.s_end;
                    SplitPiece {
                        delta: [part.x, part.y, part.z],
                        factor: p.feed_mm_min / m.old_feed_mm_min,
                    }
                })
                .collect();
            splits.insert(mv.line, pieces);
        }
    }
    let name = file.display().to_string();
    let rewritten = swarf_path::rewrite::rewrite_feeds(&text, &name, format, &factors, &splits)?;
    // The new program must read back with the scheduled feeds and the same motion.
    let again = args
        .run
        .read_program_str(&rewritten.text, &args.out.display().to_string())
        .context("reading the scheduled program back")?;
    let inserted: usize = schedule.moves.iter().map(|m| m.pieces.len() - 1).sum();
    if again.moves.len() != program.moves.len() + inserted {
        bail!(
            "internal error: the scheduled program has {} moves, not {} ({} input moves, {inserted} pieces added); nothing written",
            again.moves.len(),
            program.moves.len() + inserted,
            program.moves.len()
        );
    }
    let mut moves_changed = 0;
    let mut shift = 0usize;
    let mut scheduled = schedule.moves.iter().peekable();
    for (i, old) in program.moves.iter().enumerate() {
        let Some(m) = scheduled.next_if(|m| m.move_index == i) else {
            continue;
        };
        let line = old.line;
        let n = m.pieces.len();
        let mut changed = false;
        for (k, p) in m.pieces.iter().enumerate() {
            let new = &again.moves[i + shift + k];
            let got = swarf_engage::feed_rate(new, swarf_engage::path_length(&again, new));
            let want = if k + 1 == n {
                m.old_feed_mm_min * factors.get(&line).copied().unwrap_or(1.0)
            } else {
                p.feed_mm_min
            };
            if (got - want).abs() > 1e-5 * want.max(1.0) {
                bail!(
                    "internal error: {name}:{line}: the scheduled program reads back at {got} mm/min, not {want}; nothing written"
                );
            }
            changed |= (got - m.old_feed_mm_min).abs() > 1e-9 * m.old_feed_mm_min;
        }
        let end = &again.moves[i + shift + n - 1];
        if (end.end.tip - old.end.tip).length() > 1e-6 {
            bail!("internal error: {name}:{line}: the split move ends elsewhere; nothing written");
        }
        shift += n - 1;
        moves_changed += usize::from(changed);
    }
    let still_over_limit: Vec<Over> = schedule
        .moves
        .iter()
        .filter(|m| m.over_limit)
        .map(|m| {
            let mv = &run.program.moves[m.move_index];
            Over {
                move_index: m.move_index,
                file: name.clone(),
                line: mv.line,
                feed_mm_min: m.new_feed_mm_min,
                cap_mm_min: m.cap_mm_min.unwrap_or(0.0),
            }
        })
        .collect();
    let summary = ScheduleSummary {
        moves_changed,
        time_before_s: swarf_path::summarize(&run.program).machining_time_s,
        time_after_s: swarf_path::summarize(&again).machining_time_s,
        still_over_limit,
        lines_changed: rewritten.lines_changed.len(),
        moves_split: schedule.moves.iter().filter(|m| m.pieces.len() > 1).count(),
        pieces_added: inserted,
        limit,
        material: model.material().name.clone(),
        elapsed_s: t0.elapsed().as_secs_f64(),
        engaged_without_spindle: without_spindle,
        collisions: walked.collisions,
    };
    summary.collisions.warn(
        " — not fixed by feeds: a rapid's speed is the machine's; change the program",
        " — not fixed by feeds: a longer tool or another path",
    );
    // `--min-feed` wins over "never faster than programmed": say so where it did.
    let raised = schedule
        .moves
        .iter()
        .filter(|m| {
            m.old_feed_mm_min > 0.0
                && m.old_feed_mm_min < args.min_feed
                && m.new_feed_mm_min > m.old_feed_mm_min
        })
        .count();
    if raised > 0 && args.max_feed.is_none() {
        eprintln!(
            "swarf: warning: {raised} feed moves programmed slower than --min-feed {} mm/min now run at it, faster than programmed",
            args.min_feed
        );
    }
    if let Some((file, line)) = &first_without_spindle {
        eprintln!(
            "swarf: warning: {without_spindle} engaged cutter locations with the spindle stopped ({}), the first at {file}:{line}: not fixed by feeds; start the spindle before the cut",
            crate::commands::forces::SPINDLE_STOPPED
        );
    }
    let mut json = serde_json::to_vec_pretty(&summary)?;
    json.push(b'\n');
    // The program and its summary as one set: both, or neither.
    let Some(out_name) = args
        .out
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
    else {
        bail!("--out {}: not a file name", args.out.display());
    };
    let parent = match args.out.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let mut set = output_set(&parent, DEFAULT_MAX_OUTPUT_MB)?;
    set.write_bytes(&out_name, rewritten.text.as_bytes())?;
    set.write_bytes(&format!("{out_name}.schedule.json"), &json)?;
    set.commit()?;
    if args.json {
        return print_json(&summary);
    }
    say!(
        "{} of {} feed moves changed on {} lines; machining time {:.1} s -> {:.1} s; {} moves still over the limit (at the minimum feed, or following the spindle)",
        summary.moves_changed,
        schedule.moves.len(),
        summary.lines_changed,
        summary.time_before_s,
        summary.time_after_s,
        summary.still_over_limit.len()
    );
    for o in summary.still_over_limit.iter().take(10) {
        eprintln!(
            "swarf: warning: {}:{}: over the limit at {:.1} mm/min (the limit allows {:.1}){}",
            o.file,
            o.line,
            o.feed_mm_min,
            o.cap_mm_min,
            if fixed(o.move_index) {
                "; G33/G33.1 follow the spindle, so no feed word slows them: lower S"
            } else {
                ""
            }
        );
    }
    Ok(())
}
