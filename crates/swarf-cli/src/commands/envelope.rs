//! `swarf envelope`: the swept envelope of a program's feed moves as STL and glb.

use crate::output::say;
use std::ops::Range;
use std::path::PathBuf;
use std::time::Instant;

use anyhow::{bail, Context, Result};
use clap::Args;
use serde::Serialize;
use swarf_envelope::{envelope, EnvelopeOptions};
use swarf_io::glb::{glb_size_bound, GlbFile};
use swarf_io::output_set::stl_size;
use swarf_io::{write_stl_to, GlbOptions, Shading};
use swarf_sweep::SelfIntersection;

use crate::cli::SetupArgs;
use crate::commands::tools::{defined_tools, load_job};
use crate::output::{check_sizes, output_set, print_json};

#[derive(Debug, Args)]
pub(crate) struct EnvelopeArgs {
    /// The program: G-code, APT CL, Heidenhain conversational or Sinumerik.
    #[arg(long, value_name = "FILE")]
    pub(crate) program: PathBuf,
    /// Cutters, tool library, machine and units.
    #[command(flatten)]
    pub(crate) setup: SetupArgs,
    /// Moves to sweep, by index: `A..B` (B excluded), `A..=B`, `A..`, `..B` or `N`. Rapids in
    /// the range are skipped. Default: all.
    #[arg(long, value_name = "A..B")]
    pub(crate) moves: Option<String>,
    /// Lattice spacing of the envelope, mm.
    #[arg(allow_negative_numbers = true, long, value_name = "H", default_value_t = swarf_envelope::DEFAULT_RESOLUTION_MM)]
    pub(crate) resolution: f64,
    /// Largest distance between an arc or a 5-axis motion and what is swept for it, mm.
    #[arg(allow_negative_numbers = true, long, value_name = "T", default_value_t = swarf_envelope::DEFAULT_CHORDAL_TOLERANCE_MM)]
    pub(crate) tolerance: f64,
    /// Write envelope.stl, envelope.glb and summary.json here.
    #[arg(long, value_name = "DIR")]
    pub(crate) out: PathBuf,
    /// Largest total size of the files written, MB (checked before anything is written).
    #[arg(long, value_name = "MB", default_value_t = crate::output::DEFAULT_MAX_OUTPUT_MB)]
    pub(crate) max_output_mb: u64,
    /// Merge coplanar triangles (walls, floors, strips of a cylinder along a lattice axis)
    /// into few; the vertices stay where they are, the surface within 10⁻⁶ mm of the unmerged.
    #[arg(long)]
    pub(crate) merge_planar: bool,
    /// Merge each 2 × 2 × 2 block of cells into one vertex (on the exact envelope) where the
    /// topology stays and the block's crossings lie within MM of the planes that meet at it:
    /// about a quarter of the triangles where the envelope is smooth, in about half the
    /// contouring's time; sharp edges stay. 0 keeps every cell.
    #[arg(allow_negative_numbers = true, long, value_name = "MM", default_value_t = swarf_envelope::DEFAULT_SIMPLIFY_MM)]
    pub(crate) simplify: f64,
    /// Print the JSON summary (the default output is a short human-readable report).
    #[arg(long)]
    pub(crate) json: bool,
}

/// The JSON summary.
#[derive(Serialize)]
struct EnvelopeSummary {
    /// Feed moves swept.
    moves: usize,
    triangles: usize,
    /// The mesh is closed.
    closed: bool,
    volume_mm3: f64,
    /// Moves whose envelope folds into its own sweep.
    self_intersections: Vec<SelfIntersection>,
    elapsed_s: f64,
    first_move: usize,
    last_move: usize,
    fixed_axis_pieces: usize,
    volume_xyz_mm3: [f64; 3],
    resolution_mm: f64,
    tolerance_mm: f64,
    max_piece_error_mm: f64,
    lattice: [usize; 3],
    /// Mesh vertices put on the exact envelope of the fixed-axis pieces.
    exact_vertices: usize,
    /// With `--merge-planar`: the triangles before the merge.
    #[serde(skip_serializing_if = "Option::is_none")]
    triangles_before_merge: Option<usize>,
    /// The 2 × 2 × 2 blocks of cells merged into one vertex (absent with `--simplify 0`).
    #[serde(skip_serializing_if = "Option::is_none")]
    merged_blocks: Option<usize>,
}

/// Parses `A..B`, `A..=B`, `A..`, `..B` or `N` into a half-open range.
fn parse_moves(text: &str, len: usize) -> Result<Range<usize>> {
    let num = |s: &str| -> Result<usize> {
        s.trim()
            .parse::<usize>()
            .with_context(|| format!("--moves `{text}`: `{s}` is not a move index"))
    };
    let range = if let Some((a, b)) = text.split_once("..") {
        let start = if a.trim().is_empty() { 0 } else { num(a)? };
        let end = match b.strip_prefix('=') {
            Some(b) => num(b)? + 1,
            None if b.trim().is_empty() => len,
            None => num(b)?,
        };
        start..end
    } else {
        let n = num(text)?;
        n..n + 1
    };
    if range.start >= range.end || range.start >= len {
        bail!("--moves `{text}` selects no move (the program has {len} moves, indices 0..{len})");
    }
    // A range past the end is an error as a single index past it is (`1..100` of 4 moves
    // was cut to `1..4` without a word).
    if range.end > len {
        bail!(
            "--moves `{text}` runs past the last move (the program has {len} moves, indices 0..{len}): end it at {len} or leave the end out (`{}..`)",
            range.start
        );
    }
    Ok(range)
}

pub(crate) fn run(args: &EnvelopeArgs) -> Result<()> {
    // A few arrays of tens of MB each (rays, line store, mesh): freed ones go back at once.
    crate::alloc::return_large_blocks();
    let t0 = Instant::now();
    let job = load_job(&args.setup, &args.program)?;
    let tools = defined_tools(&job)?;
    crate::commands::tools::check_resolution(tools, args.resolution)?;
    let program = &job.program;
    let range = match &args.moves {
        Some(m) => parse_moves(m, program.moves.len())?,
        None => 0..program.moves.len(),
    };
    let simplify = crate::commands::simulate::simplify_mm(args.simplify)?;
    let options = EnvelopeOptions::default()
        .with_resolution(args.resolution)
        .with_tolerance(args.tolerance)
        .with_merge_planar(args.merge_planar)
        .with_simplify(simplify);
    let env = envelope(program, tools, range, &options)
        .with_context(|| format!("sweeping {}", args.program.display()))?;
    let stl = args.out.join("envelope.stl");
    let glb = args.out.join("envelope.glb");
    let mut set = output_set(&args.out, args.max_output_mb)?;
    let (v, t) = (env.mesh.vertices.len(), env.mesh.triangles.len());
    check_sizes(
        &set,
        &[
            ("envelope.stl", stl_size(t as u64)),
            ("envelope.glb", glb_size_bound(v, t, false, Shading::Flat)),
        ],
    )?;
    let glb_file =
        GlbFile::new(&env.mesh, &GlbOptions::default()).context("encoding envelope.glb")?;
    set.write_all(vec![
        ("envelope.stl", Box::new(|w| write_stl_to(w, &env.mesh))),
        ("envelope.glb", Box::new(|w| glb_file.write_to(w))),
    ])
    .context("writing the envelope's meshes")?;
    drop(glb_file);
    let r = env.report;
    let summary = EnvelopeSummary {
        moves: r.moves.len(),
        triangles: r.triangles,
        closed: r.closed,
        volume_mm3: r.volume_mm3,
        self_intersections: r.self_intersections,
        elapsed_s: t0.elapsed().as_secs_f64(),
        first_move: r.moves[0],
        last_move: r.moves[r.moves.len() - 1],
        fixed_axis_pieces: r.pieces,
        volume_xyz_mm3: r.volume_xyz_mm3,
        resolution_mm: r.resolution_mm,
        tolerance_mm: r.tolerance_mm,
        max_piece_error_mm: r.max_piece_error_mm,
        lattice: r.lattice,
        exact_vertices: r.exact_vertices,
        triangles_before_merge: r.triangles_before_merge,
        merged_blocks: r.merged_blocks,
    };
    let json = serde_json::to_vec_pretty(&summary).context("encoding the summary")?;
    set.write_bytes("summary.json", &json)?;
    set.commit()?;
    if args.json {
        return print_json(&summary);
    }
    say!(
        "{} feed moves (indices {}..={}), {} fixed-axis pieces",
        summary.moves,
        summary.first_move,
        summary.last_move,
        summary.fixed_axis_pieces
    );
    say!(
        "envelope: {} triangles, {:.3} mm³, h = {} mm, tolerance {} mm, {:.2} s",
        summary.triangles,
        summary.volume_mm3,
        summary.resolution_mm,
        summary.tolerance_mm,
        summary.elapsed_s
    );
    for s in &summary.self_intersections {
        say!("warning: {}", s.message);
    }
    say!("wrote {} and {}", stl.display(), glb.display());
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::parse_moves;

    #[test]
    fn move_ranges() {
        assert_eq!(parse_moves("2..5", 10).unwrap(), 2..5);
        assert_eq!(parse_moves("2..=5", 10).unwrap(), 2..6);
        assert_eq!(parse_moves("3..", 10).unwrap(), 3..10);
        assert_eq!(parse_moves("..4", 10).unwrap(), 0..4);
        assert_eq!(parse_moves("7", 10).unwrap(), 7..8);
        assert!(parse_moves("5..2", 10).is_err());
        assert!(parse_moves("12", 10).is_err());
        assert!(parse_moves("1..100", 10).is_err());
        assert!(parse_moves("0..=10", 10).is_err());
        assert_eq!(parse_moves("0..=9", 10).unwrap(), 0..10);
        assert!(parse_moves("a..b", 10).is_err());
    }
}
