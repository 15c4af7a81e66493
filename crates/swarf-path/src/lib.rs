//! Toolpath input for swarf: G-code, APT CL, Heidenhain and Sinumerik interpreters, machine
//! kinematics and the move stream that every later stage reads.
//!
//! # Model
//! Reading a program happens in two steps, as in LinuxCNC:
//!
//! 1. An interpreter ([`gcode`], [`apt`], [`heidenhain`] or [`sinumerik`]) turns text into
//!    [`Canon`] events — the canonical machining calls: straight traverse, straight feed, arc
//!    feed, units, offsets, tool change —
//!    in **joint space** (X Y Z A B C as the program commands them), lengths in millimetres,
//!    angles in degrees, positions in the program's current coordinate system. It never
//!    allocates per event and never keeps the program's motion: it hands each event to a
//!    [`CanonSink`]. [`canonical`] prints events in LinuxCNC's format; [`MoveBuilder`] keeps
//!    them as moves.
//! 2. [`MoveBuilder`] applies the work offsets and the [`Machine`] kinematics and produces a
//!    [`Program`]: a list of [`Move`]s with the tool tip and tool axis at both ends in the
//!    **workpiece frame** (the machine frame with G54–G59/G92 offsets applied, attached to the
//!    part: on a machine with a rotary table the frame turns with the table).
//!
//! Units: millimetres, degrees, minutes (feed in mm/min) at every interface; inch programs are
//! converted on input. Every move carries the file and line it came from.

pub mod apt;
pub mod builder;
pub mod canon;
pub mod canonical;
pub mod error;
pub(crate) mod formula;
pub mod gcode;
pub mod heidenhain;
pub mod kinematics;
pub mod limit;
pub mod load;
pub mod moves;
pub(crate) mod part_frame;
pub(crate) mod reader_core;
pub mod rewrite;
pub mod sinumerik;
pub mod spline;
pub mod summary;

pub use builder::MoveBuilder;
pub use canon::{
    Axes, Canon, CanonSink, FeedMode, MessageKind, Plane, SpindleDir, Units, WorkPlane,
};
pub use error::{PathError, PathErrorKind, SourcePos, Warning};
pub use kinematics::Machine;
pub use moves::{ArcGeom, AxisSource, Move, MoveKind, Pose, Program, SourceLine};
pub use summary::{summarize, ProgramSummary};
