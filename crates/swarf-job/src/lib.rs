//! A job: a program read through a machine, with the cutter of every tool it uses — what every
//! operation on a program (simulate, check, engage, forces, verify) starts from.
//!
//! # Model
//! [`JobOptions`] say what a job is made of besides the program, as a user names it: the
//! machine (a built-in name or a TOML file), the cutters (one spec for every tool, or a tool
//! library), the program's initial units, the folders searched for subroutines, the G-code
//! dialect and the most moves a program may make. [`JobSetup::load`] loads them — the machine,
//! then the cutter sources, then the reader options (the tool diameters cutter compensation
//! needs come from the cutters) — and [`JobSetup::read`] reads a program with them into a
//! [`Job`]: the [`Program`] (its moves, and the reader's warnings), its tools resolved to
//! cutters by [`ToolSet::resolve`] (a spec for every tool, else the library's entry, else the
//! program's own `CUTTER/`) and the tool numbers nothing defines, kept apart rather than
//! guessed. A program that is only streamed (never kept as moves) is read by
//! [`JobSetup::stream`] and its tools resolved by [`JobSetup::resolve`].
//!
//! This crate sits above `swarf-path` and `swarf-tool` so that neither knows the other: the
//! readers take tool diameters as numbers, the tool tables know nothing of programs.
//!
//! ```
//! use swarf_job::{JobOptions, JobSetup};
//! let setup = JobSetup::load(&JobOptions {
//!     tool: Some("ball:d=6".into()),
//!     ..JobOptions::default()
//! })
//! .unwrap();
//! let job = setup.read_str("G21 G90\nT1 M6\nG0 X0 Y0 Z5\nG1 Z-1 F100\nG1 X10\n", "a.ngc").unwrap();
//! assert_eq!(job.program.moves.len(), 3);
//! assert!(job.undefined_tools.is_empty());
//! assert_eq!(job.tools.get(1).unwrap().max_diameter(), 6.0);
//! ```

use std::path::{Path, PathBuf};

mod workpiece;
pub use workpiece::{automatic_workpiece, automatic_workpiece_of};

use swarf_path::apt::AptOptions;
use swarf_path::gcode::{GcodeDialect, GcodeOptions, LinuxCncIni};
use swarf_path::kinematics::MachineError;
use swarf_path::limit::{is_move_limit, DEFAULT_MAX_MOVES};
use swarf_path::load::{read_program_str, read_text, stream_program, ProgramFormat, ReadOptions};
use swarf_path::{CanonSink, Machine, PathError, Program, Units};
use swarf_tool::{Cutter, LengthUnit, ResolveError, SpecError, TableError, ToolSet, ToolTable};

/// What a job is made of besides the program, as a user names it.
#[derive(Clone, Debug, PartialEq)]
pub struct JobOptions {
    /// The machine's kinematics: a TOML machine file when this names an existing file, else a
    /// built-in name ([`Machine::from_name`]). Default `3axis`.
    pub machine: String,
    /// One cutter spec for every tool the program uses.
    pub tool: Option<String>,
    /// A tool library: swarf TOML, LinuxCNC `.tbl` or CAMotics `.camotics`.
    pub tools: Option<PathBuf>,
    /// Length unit of a library that does not state its own (LinuxCNC `.tbl`). Default mm.
    pub table_units: LengthUnit,
    /// Length units before the program's first G20/G21; `None`: the machine's (the INI's
    /// `[TRAJ] LINEAR_UNITS`), else mm.
    pub initial_units: Option<Units>,
    /// Folders searched for `name.ngc` when a program calls a subroutine it does not define
    /// (after the program's own folder).
    pub subroutine_dirs: Vec<PathBuf>,
    /// Read G-code as this control does (default: decided from the program).
    pub dialect: Option<GcodeDialect>,
    /// Skip G-code lines starting with `/` (the block-delete switch on). Default false: the
    /// switch off, as LinuxCNC's rs274 and the controls start.
    pub block_delete: bool,
    /// The machine's home (where G-code programs start, and G28/G30 return to), mm, machine
    /// coordinates; `None`: the origin (LinuxCNC's default).
    pub home: Option<[f64; 3]>,
    /// Most moves a program may make: reading stops with [`JobError::MoveLimit`] at the first
    /// move over it. Default [`DEFAULT_MAX_MOVES`].
    pub max_moves: u64,
    /// A LinuxCNC machine INI ([`swarf_path::gcode::LinuxCncIni`]): G-code runs under its
    /// settings, and its `[EMCIO] TOOL_TABLE` is the tool library when neither
    /// [`Self::tool`] nor [`Self::tools`] is given (in its `[TRAJ] LINEAR_UNITS`).
    pub ini: Option<PathBuf>,
}

impl Default for JobOptions {
    fn default() -> Self {
        Self {
            machine: "3axis".into(),
            tool: None,
            tools: None,
            table_units: LengthUnit::Mm,
            initial_units: None,
            subroutine_dirs: Vec::new(),
            dialect: None,
            block_delete: false,
            home: None,
            max_moves: DEFAULT_MAX_MOVES,
            ini: None,
        }
    }
}

/// Why a job could not be set up or read. The messages name what the user gave, once
/// (`machine file FILE`, ``machine `NAME` ``, ``tool spec `SPEC` ``; the tool table's source
/// names its file), with the cause as the error's source.
#[derive(Debug, thiserror::Error)]
pub enum JobError {
    /// The machine file could not be read.
    #[error("machine file {file}")]
    MachineFile {
        /// The file as given.
        file: String,
        /// Why.
        #[source]
        source: MachineError,
    },
    /// No file and no built-in machine has this name.
    #[error("machine `{name}` (no such file)")]
    MachineName {
        /// The name as given.
        name: String,
        /// Why.
        #[source]
        source: MachineError,
    },
    /// The tool spec is not a valid cutter.
    #[error("tool spec `{spec}`")]
    ToolSpec {
        /// The spec as given.
        spec: String,
        /// Why.
        #[source]
        source: SpecError,
    },
    /// The LinuxCNC INI could not be read or holds a bad setting (the error names the file
    /// and line).
    #[error(transparent)]
    Ini(PathError),
    /// The tool library could not be read.
    #[error("tool table")]
    ToolTable {
        /// The library file.
        path: PathBuf,
        /// Why.
        #[source]
        source: TableError,
    },
    /// The program could not be read (the reader's error names file, line and column).
    #[error(transparent)]
    Read(PathError),
    /// The program makes more moves than [`JobOptions::max_moves`].
    #[error(transparent)]
    MoveLimit(PathError),
    /// A `CUTTER/` record of the program is not a valid cutter.
    #[error(transparent)]
    Resolve(#[from] ResolveError),
    /// A cutter definition of the program (`CUTTER/`, `TLDATA/`) is not a valid cutter, at
    /// the record that made it.
    #[error("{file}:{line}: the cutter definition of {what}")]
    Definition {
        /// The program file.
        file: String,
        /// 1-based line of the record.
        line: u32,
        /// Which tool, in words ("tool 3", or the tool in use before any tool change).
        what: String,
        /// What is wrong with it.
        #[source]
        source: swarf_tool::ToolError,
    },
}

/// A job's options loaded: the machine, the cutter sources and the reader options.
#[derive(Clone, Debug)]
pub struct JobSetup {
    /// The machine programs are read through.
    pub machine: Machine,
    /// The cutter for every tool ([`JobOptions::tool`]), if given.
    pub single: Option<Cutter>,
    /// The tool library ([`JobOptions::tools`]), if given; a CAMotics project also states the
    /// workpiece ([`ToolTable::workpiece`]).
    pub table: Option<ToolTable>,
    /// How programs are read: initial units, subroutine folders, dialect, move limit, and the
    /// diameter of every tool for cutter compensation.
    pub read: ReadOptions,
}

impl JobSetup {
    /// Loads `options`: the machine first, then the tool spec and the tool library, then the
    /// reader options.
    ///
    /// # Errors
    /// The first of: a machine that cannot be loaded, a tool spec that is not a cutter, a tool
    /// library that cannot be read.
    pub fn load(options: &JobOptions) -> Result<Self, JobError> {
        let machine = load_machine(&options.machine)?;
        let single = options
            .tool
            .as_deref()
            .map(|s| {
                Cutter::from_spec(s).map_err(|source| JobError::ToolSpec {
                    spec: s.to_string(),
                    source,
                })
            })
            .transpose()?;
        let ini = options
            .ini
            .as_deref()
            .map(LinuxCncIni::read)
            .transpose()
            .map_err(JobError::Ini)?;
        // The machine's tool table when no tools are given: in the machine's units.
        let ini_table = ini
            .as_ref()
            .filter(|_| options.tool.is_none() && options.tools.is_none())
            .and_then(|i| {
                let units = match i.linear_units() {
                    Ok(Some(Units::Inch)) => LengthUnit::Inch,
                    Ok(Some(Units::Mm)) => LengthUnit::Mm,
                    _ => options.table_units,
                };
                i.tool_table().map(|(t, at)| (t, units, Some(at)))
            });
        let table = match (options.tools.as_deref(), ini_table) {
            (Some(t), _) => Some((t.to_path_buf(), options.table_units, None)),
            (None, t) => t,
        };
        let table = table
            .map(|(t, units, named_at)| {
                ToolTable::read(&t, units).map_err(|source| match named_at {
                    // The INI's line that names it, and why it cannot be read.
                    Some(at) => JobError::Ini(PathError::new(
                        at,
                        swarf_path::PathErrorKind::Io,
                        format!("cannot read the tool table [EMCIO] TOOL_TABLE names: {source}"),
                        t.display().to_string(),
                        "a LinuxCNC tool table",
                    )),
                    None => JobError::ToolTable { path: t, source },
                })
            })
            .transpose()?;
        let read = read_options(options, ini, single.as_ref(), table.as_ref())?;
        Ok(Self {
            machine,
            single,
            table,
            read,
        })
    }

    /// Reads the program file `path` and resolves its tools.
    ///
    /// # Errors
    /// The reader's error ([`JobError::Read`], [`JobError::MoveLimit`]) or a program `CUTTER/`
    /// that is not a cutter.
    pub fn read(mut self, path: &Path) -> Result<Job, JobError> {
        let text = read_text(path).map_err(JobError::Read)?;
        self.search_program_folder(path);
        self.read_str(&text, &path.display().to_string())
    }

    /// Makes subroutine files be looked for beside the program file `path` first (the current
    /// folder for `prog.ngc`), whatever name the text is then read under: program text read
    /// from memory has no folder of its own and searches none, and `swarf schedule` reads its
    /// output back under the output's name.
    pub fn search_program_folder(&mut self, path: &Path) {
        let dir = path
            .parent()
            .filter(|d| !d.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        self.read.gcode.subroutine_path.insert(0, dir.to_path_buf());
    }

    /// [`JobSetup::read`] of program text named `file` in messages.
    ///
    /// # Errors
    /// As [`JobSetup::read`].
    pub fn read_str(self, text: &str, file: &str) -> Result<Job, JobError> {
        let program = self.read_program_str(text, file)?;
        let tool_zero_moved = program.moves.iter().any(|m| m.tool == 0);
        let (tools, undefined_tools) = self.resolve(&program, tool_zero_moved)?;
        Ok(Job {
            program,
            tools,
            undefined_tools,
            setup: self,
        })
    }

    /// Program text named `file` in messages, read through the machine (its tools are not
    /// resolved).
    ///
    /// # Errors
    /// The reader's error ([`JobError::Read`], [`JobError::MoveLimit`]).
    pub fn read_program_str(&self, text: &str, file: &str) -> Result<Program, JobError> {
        read_program_str(text, file, self.machine.clone(), &self.read)
            .map_err(|e| self.reader_error(e))
    }

    /// Streams program text named `file` in messages into `sink` (no move is kept).
    ///
    /// # Errors
    /// The reader's error ([`JobError::Read`], [`JobError::MoveLimit`]).
    pub fn stream(
        &self,
        text: &str,
        file: &str,
        sink: &mut dyn CanonSink,
    ) -> Result<ProgramFormat, JobError> {
        stream_program(text, file, &self.read, sink).map_err(|e| self.reader_error(e))
    }

    /// Resolves each tool number `program` uses (tool 0 too when `tool_zero_moved`: a move
    /// was made before any tool was loaded) by [`ToolSet::resolve`]; returns the set and the
    /// numbers nothing defines. `program.moves` is not read (it may be empty for a streamed
    /// program).
    ///
    /// # Errors
    /// A program `CUTTER/` that is not a cutter.
    pub fn resolve(
        &self,
        program: &Program,
        tool_zero_moved: bool,
    ) -> Result<(ToolSet, Vec<u32>), JobError> {
        resolve_tools(
            program,
            tool_zero_moved,
            self.single.as_ref(),
            self.table.as_ref(),
        )
        .map_err(|e| {
            let at = program
                .cutter_definitions
                .iter()
                .position(|(t, _)| *t == e.tool)
                .and_then(|i| program.cutter_definition_lines.get(i));
            match at {
                Some(at) => JobError::Definition {
                    file: program
                        .files
                        .get(usize::from(at.file))
                        .cloned()
                        .unwrap_or_default(),
                    line: at.line,
                    what: match e.tool {
                        0 => "the tool in use (no tool change before it)".into(),
                        n => format!("tool {n}"),
                    },
                    source: e.source,
                },
                None => JobError::Resolve(e),
            }
        })
    }

    fn reader_error(&self, e: PathError) -> JobError {
        if is_move_limit(&e, self.read.gcode.max_moves)
            || is_move_limit(&e, self.read.apt.max_moves)
        {
            JobError::MoveLimit(e)
        } else {
            JobError::Read(e)
        }
    }
}

/// A program read through a machine, with its tools resolved.
#[derive(Clone, Debug)]
pub struct Job {
    /// The program: moves, files, tools loaded, the reader's warnings.
    pub program: Program,
    /// The cutter of every tool number the program uses that something defines.
    pub tools: ToolSet,
    /// Tool numbers the program uses that nothing defines (tool 0 when a move was made before
    /// any tool was loaded), in order of first use.
    pub undefined_tools: Vec<u32>,
    /// What it was read with.
    pub setup: JobSetup,
}

impl Job {
    /// Reads the program file `path` with `options` ([`JobSetup::load`], then
    /// [`JobSetup::read`]).
    ///
    /// # Errors
    /// As [`JobSetup::load`] and [`JobSetup::read`].
    pub fn read(path: &Path, options: &JobOptions) -> Result<Self, JobError> {
        JobSetup::load(options)?.read(path)
    }
}

/// A built-in machine name, or a TOML machine file when `arg` names an existing file.
fn load_machine(arg: &str) -> Result<Machine, JobError> {
    let p = Path::new(arg);
    if p.is_file() {
        Machine::from_file(p).map_err(|source| JobError::MachineFile {
            file: arg.to_string(),
            source,
        })
    } else {
        Machine::from_name(arg).map_err(|source| JobError::MachineName {
            name: arg.to_string(),
            source,
        })
    }
}

/// The reader options of `options`, with the tool diameters cutter compensation needs: the
/// single cutter's for every tool, else the library's; and the library's tool offsets and
/// pockets.
fn read_options(
    options: &JobOptions,
    ini: Option<LinuxCncIni>,
    single: Option<&Cutter>,
    table: Option<&ToolTable>,
) -> Result<ReadOptions, JobError> {
    let mut gcode = GcodeOptions::default().with_block_delete(options.block_delete);
    if let Some(ini) = ini {
        gcode = gcode.with_linuxcnc_ini(ini).map_err(JobError::Ini)?;
    }
    if let Some(u) = options.initial_units {
        gcode = gcode.with_initial_units(u);
    }
    // CL data is the CAM system's, not the machine's: its units are not the INI's.
    let apt_units = options.initial_units.unwrap_or(Units::Mm);
    if let Some(h) = options.home {
        gcode = gcode.with_home(h);
    }
    for dir in &options.subroutine_dirs {
        gcode = gcode.with_subroutine_dir(dir.clone());
    }
    if let Some(d) = options.dialect {
        gcode = gcode.with_dialect(d);
    }
    match single {
        Some(c) => gcode = gcode.with_default_tool_diameter(c.apt_params().d),
        None => {
            for (n, t) in table.map(|t| &t.tools).into_iter().flatten() {
                gcode = gcode.with_tool_diameter(*n, t.cutter.apt_params().d);
            }
            // (A tool without a diameter: 0, as LinuxCNC reads it.)
            for n in table
                .map(|t| t.left_out_offsets.keys())
                .into_iter()
                .flatten()
            {
                gcode = gcode.with_tool_diameter(*n, 0.0);
            }
        }
    }
    // The table's tool offsets (a LinuxCNC `.tbl`'s X Y Z A B C: G43 applies them) and
    // pockets (`#<_current_pocket>`).
    let kept = table.map(|t| &t.tools).into_iter().flatten();
    let kept = kept.map(|(n, t)| (n, t.offsets, t.pocket));
    let left_out = table.map(|t| &t.left_out_offsets).into_iter().flatten();
    for (n, offsets, pocket) in kept.chain(left_out.map(|(n, &(o, p))| (n, o, p))) {
        if let Some(o) = offsets {
            gcode = gcode.with_tool_offsets(*n, o);
        }
        if let Some(p) = pocket {
            gcode = gcode.with_tool_pocket(*n, p);
        }
    }
    // Named tools (a Heidenhain TOOL.T): the programs' `TOOL CALL "NAME"` finds them.
    for (n, t) in table.map(|t| &t.tools).into_iter().flatten() {
        if let Some(name) = &t.name {
            // (Two tools of one name: the first, as the control finds it.)
            gcode
                .tool_names
                .entry(name.to_ascii_uppercase())
                .or_insert(*n);
        }
    }
    Ok(ReadOptions {
        gcode: gcode.with_max_moves(options.max_moves),
        apt: AptOptions::default()
            .with_max_moves(options.max_moves)
            .with_initial_units(apt_units),
        ..ReadOptions::default()
    })
}

/// Each tool number `program` uses (`program.tools`, and tool 0 first when `tool_zero_moved`)
/// resolved by [`ToolSet::resolve`] from `single`, `table` and the program's `CUTTER/`
/// records: the set and the numbers nothing defines.
///
/// # Errors
/// A program `CUTTER/` that is not a cutter.
pub fn resolve_tools(
    program: &Program,
    tool_zero_moved: bool,
    single: Option<&Cutter>,
    table: Option<&ToolTable>,
) -> Result<(ToolSet, Vec<u32>), ResolveError> {
    let mut used: Vec<u32> = program.tools.clone();
    if tool_zero_moved && !used.contains(&0) {
        used.insert(0, 0);
    }
    ToolSet::resolve(&used, &program.cutter_definitions, single, table)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn undefined_tools_are_kept_apart_and_errors_name_what_was_given() {
        let setup = JobSetup::load(&JobOptions::default()).unwrap();
        let job = setup
            .read_str("G21 G90\nG0 X0 Y0 Z5\nT2 M6\nG1 Z-1 F100\n", "t.ngc")
            .unwrap();
        // A move before any tool was loaded: tool 0, then tool 2.
        assert_eq!(job.undefined_tools, vec![0, 2]);
        assert!(job.tools.resolved().is_empty());

        let e = JobSetup::load(&JobOptions {
            machine: "no-such-machine".into(),
            ..JobOptions::default()
        })
        .unwrap_err();
        assert!(
            e.to_string() == "machine `no-such-machine` (no such file)",
            "{e}"
        );
        let e = JobSetup::load(&JobOptions {
            tool: Some("bogus:d=1".into()),
            ..JobOptions::default()
        })
        .unwrap_err();
        assert_eq!(e.to_string(), "tool spec `bogus:d=1`");

        let setup = JobSetup::load(&JobOptions {
            max_moves: 2,
            ..JobOptions::default()
        })
        .unwrap();
        let e = setup
            .read_str("G0 X1\nG0 X2\nG0 X3\nG0 X4\n", "t.ngc")
            .unwrap_err();
        assert!(matches!(e, JobError::MoveLimit(_)), "{e:?}");
    }

    /// A LinuxCNC table's Z column is the tool length G43 applies: with `T1 … Z10` under
    /// G43, `G53 G0 Z0` puts the controlled point at machine Z0 and the tip at Z −10.
    #[test]
    fn the_tool_tables_offsets_reach_g43() {
        let dir = std::env::temp_dir().join(format!("swarf-job-tbl-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let tbl = dir.join("tools.tbl");
        std::fs::write(&tbl, "T1 P3 D2.0 Z10\n").unwrap();
        let setup = JobSetup::load(&JobOptions {
            tools: Some(tbl),
            ..JobOptions::default()
        })
        .unwrap();
        std::fs::remove_dir_all(&dir).ok();
        let g = &setup.read.gcode;
        assert_eq!(g.tool_offsets[&1], [0.0, 0.0, 10.0, 0.0, 0.0, 0.0]);
        assert_eq!(g.tool_pockets[&1], 3);
        let p = setup
            .read_program_str("G21 G90\nT1 M6 G43 H1\nG53 G0 Z0\nM2\n", "t.ngc")
            .unwrap();
        let end = p.moves.last().unwrap().end.tip;
        assert!((end.z + 10.0).abs() < 1e-12, "{end:?}");
    }

    /// NX operations with no tool change, the second's `TLDATA/MILL` a Ø6 ball with a 5°
    /// taper: its moves cut with exactly swarf's `taper-ball:d=6,taper=5` (and a 118° drill's
    /// with `drill:d=8,angle=118`), not with the first operation's Ø10 flat end mill.
    #[test]
    fn nx_tapered_and_drill_tldata_are_the_cutters_they_name() {
        let text = "TOOL PATH/OP1,TOOL,D10\nTLDATA/MILL,10.0000,0.0000,75.0000,0.0000,0.0000\n\
            MSYS/0,0,0,1,0,0,0,1,0\nRAPID\nGOTO/0,0,10,0,0,1\nFEDRAT/MMPM,250\nGOTO/0,0,-1\n\
            GOTO/10,0,-1\nEND-OF-PATH\nTOOL PATH/OP2,TOOL,TB6\n\
            TLDATA/MILL,6.0000,3.0000,50.0000,5.0000,0.0000\nMSYS/0,0,0,1,0,0,0,1,0\nRAPID\n\
            GOTO/0,20,10,0,0,1\nFEDRAT/MMPM,250\nGOTO/0,20,-1\nGOTO/10,20,-1\nEND-OF-PATH\n\
            TOOL PATH/OP3,TOOL,DR8\nTLDATA/DRILL,8.0000,0.0000,60.0000,118.0000,40.0000\n\
            GOTO/20,20,-1\n";
        let job = JobSetup::load(&JobOptions::default())
            .unwrap()
            .read_str(text, "t.cls")
            .unwrap();
        let tools = job.tools.resolved();
        let cutter_of = |line: u32| {
            let m = job.program.moves.iter().find(|m| m.line == line).unwrap();
            tools[&m.tool].cutter.apt_params()
        };
        let spec = |s: &str| Cutter::from_spec(s).unwrap().apt_params();
        let (ball, taper_ball) = (cutter_of(17), spec("taper-ball:d=6,taper=5"));
        // The same profile (h is the record's length, the spec's its default).
        for (got, want) in [
            (ball.d, taper_ball.d),
            (ball.r, taper_ball.r),
            (ball.e, taper_ball.e),
            (ball.f, taper_ball.f),
            (ball.alpha_deg, taper_ball.alpha_deg),
            (ball.beta_deg, taper_ball.beta_deg),
        ] {
            assert!((got - want).abs() < 1e-12, "{ball:?} != {taper_ball:?}");
        }
        assert_eq!(ball.h, 50.0);
        assert_eq!(cutter_of(7).d, 10.0);
        let (drill, want) = (cutter_of(21), spec("drill:d=8,angle=118"));
        assert!(
            (drill.f - want.f).abs() < 1e-12 && drill.alpha_deg == want.alpha_deg,
            "{drill:?} != {want:?}"
        );
    }

    #[test]
    fn a_bad_cutter_definition_names_its_record() {
        let read = |text: &str| {
            let setup = JobSetup::load(&JobOptions::default()).unwrap();
            setup.read_str(text, "t.apt").unwrap_err().to_string()
        };
        let e = read("UNITS/MM\nLOADTL/3\nTLDATA/MILL,10,6,50,0,0\nFROM/0,0,10\nGOTO/5,0,10\n");
        assert!(
            e.starts_with("t.apt:3: the cutter definition of tool 3"),
            "{e}"
        );
        // Defined twice: the record in force is named; no tool change: said in words.
        let e = read("CUTTER/10,0\nCUTTER/10,6\nFROM/0,0,10\nGOTO/5,0,10\n");
        assert!(
            e.starts_with("t.apt:2: the cutter definition of the tool in use"),
            "{e}"
        );
    }
}
