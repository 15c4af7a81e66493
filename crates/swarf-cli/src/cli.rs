//! The argument groups several commands share (flattened into each command's arguments, which
//! live beside the command in `commands`; the top-level grammar is in `main.rs`). Names here are
//! a contract: options may be added, not renamed.

use std::path::PathBuf;

use clap::{Args, ValueEnum};

/// Length unit for tool tables that do not state their own (LinuxCNC `.tbl`).
#[derive(Clone, Copy, Debug, ValueEnum)]
pub(crate) enum TableUnits {
    /// Millimetres.
    Mm,
    /// Inches.
    Inch,
}

/// What every command that reads a program needs besides the program: which cutter each tool
/// is, the machine's kinematics and the program's initial units.
#[derive(Debug, Args)]
pub(crate) struct SetupArgs {
    /// One cutter for every tool the program uses.
    #[arg(long, value_name = "SPEC", conflicts_with = "tools")]
    pub(crate) tool: Option<String>,
    /// Tool library: swarf TOML, LinuxCNC .tbl, CAMotics .camotics or Heidenhain TOOL.T.
    #[arg(long, value_name = "FILE")]
    pub(crate) tools: Option<PathBuf>,
    /// Units of a LinuxCNC .tbl tool table.
    #[arg(long, value_enum, default_value = "mm")]
    pub(crate) table_units: TableUnits,
    /// Machine kinematics: a built-in name (3axis, 4axis-a, 4axis-b, table-ac, table-bc,
    /// head-ac, head-bc, head-table-ac, head-table-bc; add -tcp for TCP) or a TOML file.
    #[arg(long, value_name = "FILE|NAME", default_value = "3axis")]
    pub(crate) machine: String,
    /// Length units before the program's first G20/G21 (default: the --ini machine's, else mm).
    #[arg(long, value_enum)]
    pub(crate) initial_units: Option<TableUnits>,
    /// A LinuxCNC machine INI: G-code runs as that machine runs it (its start-up code,
    /// subroutine path, `#<_ini[…]>` values, units, M6 settings), and its TOOL_TABLE is the
    /// tool library when --tool/--tools are not given.
    #[arg(long, value_name = "FILE")]
    pub(crate) ini: Option<PathBuf>,
    /// A folder searched for `name.ngc` when the program calls a subroutine it does not define
    /// (after the program's own folder; LinuxCNC's SUBROUTINE_PATH). May be repeated.
    #[arg(long, value_name = "DIR")]
    pub(crate) subroutine_path: Vec<PathBuf>,
    /// Read G-code as this control does (default: decided from the program).
    #[arg(long, value_enum)]
    pub(crate) dialect: Option<Dialect>,
    /// Skip G-code lines starting with `/` (the block-delete switch on); by default they are
    /// read, as LinuxCNC, Fanuc and Sinumerik controls do with the switch off, their default,
    /// and a warning says so at the first one.
    #[arg(long, conflicts_with = "no_block_delete")]
    pub(crate) block_delete: bool,
    /// Read lines starting with `/` (the default; kept for scripts that state it).
    #[arg(long, hide = true)]
    pub(crate) no_block_delete: bool,
    /// The machine's home, mm in the work frame with no offsets: where a G-code program starts,
    /// where G28/G30 return to, and the origin of G53's machine coordinates (Heidenhain's
    /// M91/M92, Sinumerik's SUPA/G153) for the whole program, whatever work offsets or G92 it
    /// sets (machine zero is the home on Fanuc, Haas, GRBL, Mach3). Default 0,0,0 (LinuxCNC's);
    /// a program's `G28 G91 Z0.`, `G53 G0 Z0.`, `L Z+0 R0 FMAX M91` or `G0 SUPA Z0` means
    /// "retract", so give its home above the part.
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_home, allow_hyphen_values = true)]
    pub(crate) home: Option<[f64; 3]>,
    /// Most moves a program may make: reading stops with an error at the first move over it,
    /// which bounds the memory the moves take (about 300 bytes each). Default 4000000;
    /// `swarf path` keeps no moves and has no limit unless this is given.
    #[arg(long, value_name = "N")]
    pub(crate) max_moves: Option<u64>,
}

impl SetupArgs {
    /// The job options these arguments give; `max_moves` when `--max-moves` is not given.
    pub(crate) fn job_options(&self, max_moves: u64) -> swarf_job::JobOptions {
        let units = |u: TableUnits| match u {
            TableUnits::Mm => (swarf_path::Units::Mm, swarf_tool::LengthUnit::Mm),
            TableUnits::Inch => (swarf_path::Units::Inch, swarf_tool::LengthUnit::Inch),
        };
        swarf_job::JobOptions {
            machine: self.machine.clone(),
            tool: self.tool.clone(),
            tools: self.tools.clone(),
            table_units: units(self.table_units).1,
            initial_units: self.initial_units.map(|u| units(u).0),
            subroutine_dirs: self.subroutine_path.clone(),
            dialect: self.dialect.map(|d| match d {
                Dialect::Linuxcnc => swarf_path::gcode::GcodeDialect::LinuxCnc,
                Dialect::Fanuc => swarf_path::gcode::GcodeDialect::Fanuc,
            }),
            block_delete: self.block_delete,
            home: self.home,
            max_moves: self.max_moves.unwrap_or(max_moves),
            ini: self.ini.clone(),
        }
    }
}

/// `X,Y,Z` in mm, finite and within the machine range.
fn parse_home(s: &str) -> Result<[f64; 3], String> {
    let v: Vec<f64> = s
        .split(',')
        .map(|t| t.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("expected X,Y,Z in mm, found `{s}`"))?;
    match v[..] {
        [x, y, z]
            if v.iter()
                .all(|c| c.is_finite() && c.abs() <= swarf_geom::math::MACHINE_RANGE_MM) =>
        {
            Ok([x, y, z])
        }
        _ => Err(format!(
            "expected three finite numbers X,Y,Z within ±1e6 mm, found `{s}`"
        )),
    }
}

/// Where a part file lies in the program's frame (`--part-at`): `X,Y,Z` (a translation, mm),
/// `X,Y,Z,RZ` or `X,Y,Z,RX,RY,RZ` (turns in degrees about the fixed X, Y and Z axes through
/// the file's origin, in that order, before the translation).
pub(crate) fn parse_part_at(s: &str) -> Result<swarf_geom::RigidMotion, String> {
    let v: Vec<f64> = s
        .split(',')
        .map(|t| t.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("expected X,Y,Z[,RZ] or X,Y,Z,RX,RY,RZ (mm, degrees), found `{s}`"))?;
    let finite = v.iter().all(|c| c.is_finite());
    let within = v[..3.min(v.len())]
        .iter()
        .all(|c| c.abs() <= swarf_geom::math::MACHINE_RANGE_MM);
    let [rx, ry, rz] = match v[..] {
        [_, _, _] => [0.0; 3],
        [_, _, _, rz] => [0.0, 0.0, rz],
        [_, _, _, rx, ry, rz] => [rx, ry, rz],
        _ => {
            return Err(format!(
                "expected 3, 4 or 6 numbers (X,Y,Z[,RZ] or X,Y,Z,RX,RY,RZ), found {} in `{s}`",
                v.len()
            ))
        }
    };
    if !finite || !within {
        return Err(format!(
            "expected finite numbers, X, Y and Z within ±1e6 mm, found `{s}`"
        ));
    }
    use swarf_geom::math::{Quat, Vec3};
    let turn = Quat::from_rotation_z(rz.to_radians())
        * Quat::from_rotation_y(ry.to_radians())
        * Quat::from_rotation_x(rx.to_radians());
    Ok(swarf_geom::RigidMotion::new(
        turn,
        Vec3::new(v[0], v[1], v[2]),
    ))
}

/// The G-code dialects.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub(crate) enum Dialect {
    /// LinuxCNC (RS274/NGC).
    Linuxcnc,
    /// Fanuc 0i/30i-M style.
    Fanuc,
}

/// An error in how the command was called (a required choice not made), which exits with
/// status 2 like clap's own usage errors, not 1 as bad input does.
#[derive(Debug)]
pub(crate) struct UsageError(pub(crate) String);

impl std::fmt::Display for UsageError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for UsageError {}

#[cfg(test)]
mod tests {
    use super::parse_part_at;
    use swarf_geom::math::Vec3;

    #[test]
    fn part_at_turns_about_x_then_y_then_z_then_moves() {
        // X+90 takes +Y to +Z; Y+90 takes +Z to +X; Z+90 takes +X to +Y: +Y ends on +Y, then
        // moved by (1, 2, 3). And +X: X+90 keeps it, Y+90 takes it to −Z, Z+90 keeps −Z.
        let m = parse_part_at("1,2,3,90,90,90").unwrap();
        let close = |a: Vec3, b: Vec3| (a - b).length() < 1e-12;
        assert!(close(m.apply_point(Vec3::Y), Vec3::new(1.0, 3.0, 3.0)));
        assert!(close(m.apply_point(Vec3::X), Vec3::new(1.0, 2.0, 2.0)));
        // Four numbers: a turn about Z alone.
        let m = parse_part_at("0,0,0,90").unwrap();
        assert!(close(m.apply_point(Vec3::X), Vec3::Y));
        assert!(close(
            parse_part_at("5,-6,7").unwrap().apply_point(Vec3::ZERO),
            Vec3::new(5.0, -6.0, 7.0)
        ));
    }
}
