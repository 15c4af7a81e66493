//! Reading a program file of either language: format detection and the whole read into a
//! [`Program`], or into any [`CanonSink`].

use std::path::Path;

use crate::apt::{read_apt, AptOptions};
use crate::gcode::{read_gcode, GcodeOptions};
use crate::{CanonSink, Machine, MoveBuilder, PathError, PathErrorKind, Program, SourcePos};

/// The language of a program file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ProgramFormat {
    /// RS274/NGC G-code (LinuxCNC, Fanuc and alike).
    Gcode,
    /// APT CL data (CLDATA text).
    Apt,
    /// Heidenhain conversational (Klartext) programs (`BEGIN PGM …`, `.h`).
    Heidenhain,
    /// Siemens Sinumerik 840D programs (`CR=`, `TRAORI`, `CYCLE800(…)`, `.mpf`, `.spf`).
    Sinumerik,
}

impl ProgramFormat {
    /// Decides the language from the file extension, and for unknown extensions from the text:
    /// a file whose first statements are APT records (`GOTO/`, `PARTNO`, `CUTTER/`, …) is APT.
    /// A file whose first statement is `BEGIN PGM` is Heidenhain whatever its extension (CAM
    /// systems write them as `.h`, `.ptp`, `.nc`).
    pub fn detect(path: &Path, text: &str) -> Self {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .unwrap_or("")
            .to_ascii_lowercase();
        match ext.as_str() {
            // (`.ncl`: Creo's CL files.)
            "apt" | "cls" | "cl" | "cldata" | "aptsource" | "ncl" => return ProgramFormat::Apt,
            // Siemens main programs and subprograms, whatever words they use.
            "mpf" | "spf" => return ProgramFormat::Sinumerik,
            _ => {}
        }
        if crate::heidenhain::is_heidenhain(text) {
            return ProgramFormat::Heidenhain;
        }
        let gcode_ext = matches!(
            ext.as_str(),
            "ngc" | "nc" | "gcode" | "g" | "gc" | "tap" | "cnc" | "ptp" | "h" | "eia"
        );
        // An APT file of unknown extension (whose records may mention Siemens words in their
        // text) before the Sinumerik test.
        if !gcode_ext && Self::apt_text(text) {
            return ProgramFormat::Apt;
        }
        if crate::sinumerik::is_sinumerik(text) {
            return ProgramFormat::Sinumerik;
        }
        ProgramFormat::Gcode
    }

    /// True when the first statements are APT records (`GOTO/`, `PARTNO`, `CUTTER/`, …).
    fn apt_text(text: &str) -> bool {
        const APT_WORDS: [&str; 10] = [
            "GOTO/",
            "FROM/",
            "PARTNO",
            "CUTTER/",
            "LOADTL",
            "TOOL PATH/",
            "FEDRAT/",
            "MULTAX",
            "UNITS/",
            "TLDATA/",
        ];
        let first = text
            .lines()
            .map(str::trim)
            .filter(|l| !l.is_empty() && !l.starts_with("$$"))
            .take(20);
        for line in first {
            // Creo and CATIA space the slash: `GOTO / 1, 2, 3`, `UNITS / MM`.
            let upper = match line.split_once('/') {
                Some((head, tail)) => format!("{}/{tail}", head.trim_end()),
                None => line.to_string(),
            }
            .to_ascii_uppercase();
            if APT_WORDS.iter().any(|w| upper.starts_with(w)) {
                return true;
            }
        }
        false
    }
}

/// The lines of a program's text as its reader numbers them (line 1 first), each with its own
/// line end: G-code lines end at `\n`, `\r\n` or a lone `\r` (old Mac editors' line end), as
/// the G-code reader splits them; APT lines at `\n`. The last line may have none. Tools that
/// point at or rewrite lines by the readers' numbers (`swarf schedule`, the report pages) use
/// this, so that their line N is the reader's.
pub fn program_lines_with_ends(text: &str, format: ProgramFormat) -> impl Iterator<Item = &str> {
    let mut pos = 0;
    std::iter::from_fn(move || {
        (pos < text.len()).then(|| {
            let rest = &text.as_bytes()[pos..];
            let end = match format {
                ProgramFormat::Gcode | ProgramFormat::Heidenhain | ProgramFormat::Sinumerik => {
                    crate::gcode::lexer::memchr_nl(rest)
                }
                ProgramFormat::Apt => rest.iter().position(|&c| c == b'\n'),
            };
            let next = end.map_or(text.len(), |i| pos + i + 1);
            let line = &text[pos..next];
            pos = next;
            line
        })
    })
}

/// The lines of [`program_lines_with_ends`] without their line ends (`\n`, `\r\n`, `\r`).
pub fn program_lines(text: &str, format: ProgramFormat) -> impl Iterator<Item = &str> {
    program_lines_with_ends(text, format).map(|l| {
        let l = l.strip_suffix('\n').unwrap_or(l);
        l.strip_suffix('\r').unwrap_or(l)
    })
}

/// Options for reading a program of either language.
#[derive(Clone, Debug, Default)]
pub struct ReadOptions {
    /// G-code reader options.
    pub gcode: GcodeOptions,
    /// APT reader options.
    pub apt: AptOptions,
    /// Force a language instead of detecting it.
    pub format: Option<ProgramFormat>,
}

/// Reads a program file's bytes (non-UTF-8 bytes are replaced, as old post-processors write
/// Latin-1 comments).
///
/// # Errors
/// [`PathErrorKind::Io`] naming the file.
pub fn read_text(path: &Path) -> Result<String, PathError> {
    read_text_of(path, "the program")
}

/// [`read_text`] of a file that is `what` (`the program`, `the INI file`), which its error
/// names.
pub(crate) fn read_text_of(path: &Path, what: &str) -> Result<String, PathError> {
    let bytes = std::fs::read(path).map_err(|e| {
        PathError::new(
            SourcePos {
                file: path.display().to_string(),
                line: 0,
                column: 0,
            },
            PathErrorKind::Io,
            format!("cannot read {what}: {e}"),
            "",
            "",
        )
    })?;
    Ok(decode_text(bytes))
}

/// A program file's bytes as text: UTF-16 with its byte-order mark (as Windows editors save
/// "Unicode" text) decoded, anything else read as UTF-8, with bytes that are not UTF-8 (Latin-1
/// comments from old post-processors) replaced rather than rejected. A UTF-8 byte-order mark
/// is left for the readers, which skip it.
pub fn decode_text(bytes: Vec<u8>) -> String {
    let utf16 = |be: bool| {
        let units = bytes[2..].chunks(2).map(|c| match c {
            [a, b] if be => u16::from_be_bytes([*a, *b]),
            [a, b] => u16::from_le_bytes([*a, *b]),
            // An odd last byte: not a whole unit.
            _ => 0xFFFD,
        });
        char::decode_utf16(units)
            .map(|c| c.unwrap_or(char::REPLACEMENT_CHARACTER))
            .collect::<String>()
    };
    match bytes.get(..2) {
        Some([0xFF, 0xFE]) => utf16(false),
        Some([0xFE, 0xFF]) => utf16(true),
        _ => match String::from_utf8(bytes) {
            Ok(s) => s,
            Err(e) => String::from_utf8_lossy(e.as_bytes()).into_owned(),
        },
    }
}

/// Streams the program `text` (named `file` in messages) into `sink`.
///
/// # Errors
/// The reader's first error.
pub fn stream_program(
    text: &str,
    file: &str,
    options: &ReadOptions,
    sink: &mut dyn CanonSink,
) -> Result<ProgramFormat, PathError> {
    let format = options
        .format
        .unwrap_or_else(|| ProgramFormat::detect(Path::new(file), text));
    match format {
        ProgramFormat::Gcode => read_gcode(text, file, &options.gcode, sink)?,
        ProgramFormat::Apt => read_apt(text, file, &options.apt, sink)?,
        ProgramFormat::Heidenhain => {
            crate::heidenhain::read_heidenhain(text, file, &options.gcode, sink)?
        }
        ProgramFormat::Sinumerik => {
            crate::sinumerik::read_sinumerik(text, file, &options.gcode, sink)?
        }
    }
    Ok(format)
}

/// Reads a program file into moves through `machine`.
///
/// ```
/// use swarf_path::{load::{read_program_str, ReadOptions}, Machine, summarize};
/// let p = read_program_str("G21 G90\nG0 X0 Y0 Z5\nG1 Z-1 F100\nG1 X10\nM30\n", "a.ngc",
///     Machine::three_axis(), &ReadOptions::default()).unwrap();
/// let s = summarize(&p);
/// assert_eq!(s.feed_moves, 2);
/// assert!((s.feed_length_mm - 16.0).abs() < 1e-12);
/// ```
///
/// # Errors
/// The file cannot be read, or the reader's first error.
pub fn read_program(
    path: &Path,
    machine: Machine,
    options: &ReadOptions,
) -> Result<Program, PathError> {
    let text = read_text(path)?;
    read_program_str(&text, &path.display().to_string(), machine, options)
}

/// Reads program text into moves through `machine` (see [`read_program`]).
///
/// # Errors
/// The reader's first error.
pub fn read_program_str(
    text: &str,
    file: &str,
    machine: Machine,
    options: &ReadOptions,
) -> Result<Program, PathError> {
    let mut builder = MoveBuilder::new(machine, file);
    stream_program(text, file, options, &mut builder)?;
    Ok(builder.finish())
}
