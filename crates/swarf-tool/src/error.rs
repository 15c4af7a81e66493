//! Errors of cutter construction, tool-spec parsing and tool-table reading.

use thiserror::Error;

/// A cutter description that cannot be built. Every variant names the parameter and value.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ToolError {
    /// A parameter is NaN or infinite.
    #[error("{param} must be a finite number, got {value}")]
    NotFinite {
        /// Parameter name (APT letter and meaning).
        param: String,
        /// The value given.
        value: f64,
    },
    /// A parameter that must be > 0 (or ≥ 0) is not.
    #[error("{param} must be {requirement}, got {}", shown(*value))]
    OutOfRange {
        /// Parameter name.
        param: String,
        /// The value given (degrees for angles).
        value: f64,
        /// What is required, e.g. "> 0 mm" or "in [0°, 90°)".
        requirement: String,
    },
    /// The corner radius does not fit the diameter (its centre would cross the axis).
    #[error("corner radius r = {r} mm is too large: r·cos β = {r_cos_beta} mm exceeds half the diameter d/2 = {half_d} mm")]
    CornerTooLarge {
        /// Corner radius.
        r: f64,
        /// Radial extent of the corner below the side, r·cos β.
        r_cos_beta: f64,
        /// Half the diameter.
        half_d: f64,
    },
    /// The bottom angle and side angle leave no room for the corner: α + β > 90°.
    #[error("bottom angle α = {alpha_deg}° plus side angle β = {beta_deg}° exceeds 90°: the bottom cone and the side would cross instead of being joined by the corner")]
    AnglesDoNotJoin {
        /// Bottom angle, degrees.
        alpha_deg: f64,
        /// Side angle, degrees.
        beta_deg: f64,
    },
    /// A redundant APT parameter disagrees with the value the others imply: the pieces would
    /// not join.
    #[error(
        "{param} = {given} does not join the pieces: {why} gives {expected} (tolerance {tol} mm)"
    )]
    Inconsistent {
        /// The parameter checked (`e` or `f`).
        param: String,
        /// The value given.
        given: f64,
        /// The value implied by the others.
        expected: f64,
        /// The relation used.
        why: String,
        /// Tolerance of the check.
        tol: f64,
    },
    /// The height does not reach the top of the corner.
    #[error("height h = {h} mm is below the top of the corner at z = {needed} mm")]
    HeightTooSmall {
        /// The height given.
        h: f64,
        /// The smallest admissible height.
        needed: f64,
    },
    /// A back-tapered side reaches the axis below the height.
    #[error("side angle β = {beta_deg}° makes the radius reach zero at z = {z_zero} mm, below the height h = {h} mm")]
    SideReachesAxis {
        /// Side angle, degrees.
        beta_deg: f64,
        /// Where the radius becomes zero.
        z_zero: f64,
        /// The height given.
        h: f64,
    },
    /// One length exceeds another that must contain it.
    #[error("{inner} = {inner_value} mm is longer than {outer} = {outer_value} mm")]
    LongerThan {
        /// The part that must fit (e.g. "flute length").
        inner: String,
        /// Its value.
        inner_value: f64,
        /// The part it must fit in (e.g. "overall length").
        outer: String,
        /// Its value.
        outer_value: f64,
    },
}

/// A tool spec string (`bull:d=16,r=2`) that cannot be used.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SpecError {
    /// The text does not follow the grammar.
    #[error("tool spec column {column}: found {found}, expected {expected}")]
    Syntax {
        /// 1-based character column in the spec string.
        column: usize,
        /// What was found there.
        found: String,
        /// What was expected.
        expected: String,
    },
    /// The numbers parse but describe no valid cutter. (Not a `source`: its text is the
    /// whole message, and a report that prints the chain would print it twice.)
    #[error("{0}")]
    Tool(ToolError),
}

impl From<ToolError> for SpecError {
    fn from(e: ToolError) -> Self {
        Self::Tool(e)
    }
}

/// A tool table file that cannot be read.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum TableError {
    /// The file cannot be opened or read.
    #[error("{file}: cannot read: {message}")]
    Io {
        /// File name as given.
        file: String,
        /// The operating system's message.
        message: String,
    },
    /// The content is malformed or describes an invalid tool.
    #[error("{file}:{line}:{column}: found {found}, expected {expected}")]
    Parse {
        /// File name as given.
        file: String,
        /// 1-based line (0 when the format gives none).
        line: usize,
        /// 1-based column (0 when the format gives none).
        column: usize,
        /// What was found.
        found: String,
        /// What was expected.
        expected: String,
    },
}

/// A value as a reader wants it: plain, or with an exponent when it is huge or tiny (`1e300`
/// printed in full was three hundred digits).
fn shown(v: f64) -> String {
    if v != 0.0 && !(1e-4..1e9).contains(&v.abs()) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}
