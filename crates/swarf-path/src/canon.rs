//! Canonical machining events: the vocabulary between the interpreters and everything after.
//!
//! These mirror LinuxCNC's canonical machining functions (`STRAIGHT_TRAVERSE`, `ARC_FEED`, …) so
//! that swarf's G-code reading can be diffed against LinuxCNC's interpreter, and so that an APT
//! reader and a G-code reader feed the same [`MoveBuilder`](crate::MoveBuilder).
//!
//! Conventions: lengths in millimetres, angles in degrees, positions in the program's *current*
//! coordinate system (work offsets not applied; the [`Canon::Offsets`] event says what they are).

use serde::Serialize;
use std::borrow::Cow;

/// Joint-space position as the program commands it: X Y Z in mm, A B C in degrees.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Axes {
    /// X, mm.
    pub x: f64,
    /// Y, mm.
    pub y: f64,
    /// Z, mm.
    pub z: f64,
    /// A (rotation about X), degrees.
    pub a: f64,
    /// B (rotation about Y), degrees.
    pub b: f64,
    /// C (rotation about Z), degrees.
    pub c: f64,
}

impl Axes {
    /// All six values as an array, in X Y Z A B C order.
    pub fn to_array(self) -> [f64; 6] {
        [self.x, self.y, self.z, self.a, self.b, self.c]
    }
    /// From an array in X Y Z A B C order.
    pub fn from_array(v: [f64; 6]) -> Self {
        Self {
            x: v[0],
            y: v[1],
            z: v[2],
            a: v[3],
            b: v[4],
            c: v[5],
        }
    }
    /// Component-wise sum.
    // A named method rather than `ops::Add`: joint vectors are added and taken apart in one
    // place (offsets), and an operator would suggest an algebra the type does not have.
    #[allow(clippy::should_implement_trait)]
    pub fn add(self, o: Self) -> Self {
        let (a, b) = (self.to_array(), o.to_array());
        Self::from_array(std::array::from_fn(|i| a[i] + b[i]))
    }
    /// Component-wise difference (see [`Axes::add`]).
    #[allow(clippy::should_implement_trait)]
    pub fn sub(self, o: Self) -> Self {
        let (a, b) = (self.to_array(), o.to_array());
        Self::from_array(std::array::from_fn(|i| a[i] - b[i]))
    }
    /// True when any rotary value differs from `o`.
    pub fn rotary_differs(&self, o: &Self) -> bool {
        self.a != o.a || self.b != o.b || self.c != o.c
    }
}

/// Length units of a program.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Units {
    /// Millimetres (G21, `UNITS/MM`).
    Mm,
    /// Inches (G20, `UNITS/INCHES`); converted to mm on input.
    Inch,
}

impl Units {
    /// Millimetres per program unit.
    pub fn mm_per_unit(self) -> f64 {
        match self {
            Units::Mm => 1.0,
            Units::Inch => 25.4,
        }
    }
}

/// The plane of circular interpolation (G17/G18/G19).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum Plane {
    /// G17: arcs in XY about Z. First axis X, second Y.
    XY,
    /// G18: arcs in ZX about Y. First axis Z, second X (LinuxCNC's order).
    XZ,
    /// G19: arcs in YZ about X. First axis Y, second Z.
    YZ,
}

impl Plane {
    /// Indices (into X Y Z) of the first, second and normal axes, LinuxCNC's order.
    pub fn axes(self) -> (usize, usize, usize) {
        match self {
            Plane::XY => (0, 1, 2),
            Plane::XZ => (2, 0, 1),
            Plane::YZ => (1, 2, 0),
        }
    }
}

/// How the F word is read.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum FeedMode {
    /// G94: mm per minute (after unit conversion).
    PerMinute,
    /// G93: inverse time, the move takes 1/F minutes.
    InverseTime,
    /// G95: mm per spindle revolution.
    PerRevolution,
    /// G33/G33.1: the lead, mm per spindle revolution, as in [`FeedMode::PerRevolution`],
    /// but the motion follows the spindle: no feed word changes its speed.
    SpindleSynchronised,
}

/// Spindle direction.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum SpindleDir {
    /// M3.
    Clockwise,
    /// M4.
    CounterClockwise,
    /// M5.
    Stopped,
}

/// What a program message is for (LinuxCNC's active comments).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum MessageKind {
    /// `(MSG,…)`: shown to the operator as written.
    Msg,
    /// `(DEBUG,…)`: shown with parameters (`#5420`, `#<name>`) replaced by their values.
    Debug,
    /// `(PRINT,…)`: written to the control's terminal, parameters replaced.
    Print,
}

/// A tilted working plane (Fanuc and Haas `G68.2`): the feature coordinate system program
/// positions are given in while it is on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WorkPlane {
    /// The feature frame's origin in the untilted program frame, mm.
    pub origin: [f64; 3],
    /// The feature frame's axes in the untilted program frame: its columns are the feature's
    /// X, Y and Z (row-major: `rotation[row][column]`).
    pub rotation: [[f64; 3]; 3],
    /// `G53.1` was given: the tool axis is the feature's Z.
    pub tool_axis: bool,
}

impl WorkPlane {
    /// The rotation as a matrix.
    pub fn matrix(&self) -> swarf_geom::math::Mat3 {
        let r = self.rotation;
        swarf_geom::math::Mat3::from_cols_array_2d(&[
            [r[0][0], r[1][0], r[2][0]],
            [r[0][1], r[1][1], r[2][1]],
            [r[0][2], r[1][2], r[2][2]],
        ])
    }
}

/// One canonical machining event. Borrowed text (comments) avoids allocation per event.
#[derive(Clone, Debug, PartialEq)]
pub enum Canon<'a> {
    /// The program's length units changed (G20/G21, `UNITS/`).
    Units(Units),
    /// The active work offsets, in mm/degrees: `g5x` is the active G54–G59.x offset (index 1 =
    /// G54), `g92` the G92 (and G52) offset. Machine position = program position + g5x + g92,
    /// with the XY part of program position + g92 turned by the [`Canon::XyRotation`] that
    /// follows.
    Offsets {
        /// 1 for G54 … 9 for G59.3.
        index: u8,
        /// The G5x offset.
        g5x: Axes,
        /// The G92 offset.
        g92: Axes,
    },
    /// The rotation of the XY plane (degrees, counter-clockwise about Z) of the active
    /// coordinate system (G10 L2 R), stated after every [`Canon::Offsets`] (LinuxCNC's
    /// `SET_XY_ROTATION`). Machine position = rotate(program position + g92) + g5x.
    XyRotation(f64),
    /// A tilted working plane (G68.2; `None`: G69): the position in the untilted program
    /// frame is `origin + rotation · p` for program position `p` (X Y Z; rotary words as
    /// they are), then the G92 offset, XY rotation and G5x offset apply as for
    /// [`Canon::Offsets`]. With [`WorkPlane::tool_axis`] (G53.1) the tool axis is the feature's
    /// Z, taken from the program — as [`Canon::ToolAxis`] — rather than from the machine's
    /// rotary joints, until the plane is cancelled. The tool stays where it is.
    WorkPlane(Option<WorkPlane>),
    /// After a tilted working plane turned the tool (G53.1) and G69 cancelled the plane, the
    /// tool keeps its axis until the program turns a rotary axis: this event, before that
    /// block's motion, hands the axis back to the machine's rotary joints.
    MachineAxis,
    /// The program turns tool centre point control on (`true`: Fanuc G43.4 / G43.5, Haas
    /// G234, Heidenhain M128 / FUNCTION TCPM, Sinumerik TRAORI) or off (G49 or a plain G43,
    /// M129, TRAFOOF): while it is on, X Y Z are tool-tip positions in the part frame whatever
    /// the rotary joints (as a `-tcp` machine reads them throughout); while off, the machine's
    /// joint positions. The tool stays where it is. Nothing changes on a machine without rotary
    /// joints, or while the program states its tool axis (CL data).
    ToolCentrePoint(bool),
    /// The arc plane changed.
    Plane(Plane),
    /// Feed rate: mm/min, 1/min (inverse time) or mm/rev as the feed mode says.
    FeedRate(f64),
    /// Feed mode changed.
    FeedMode(FeedMode),
    /// How a per-minute or per-revolution feed applies to a move that turns rotary axes:
    /// `true` (Fanuc, Haas, Mach3) to the combined distance of X Y Z and the rotary angles,
    /// degrees counted as mm; `false` (LinuxCNC, Heidenhain, Sinumerik's `FGROUP(X,Y,Z)`, the
    /// default) to X Y Z alone, and to the angles only when X Y Z stand still.
    RotaryFeedCombined(bool),
    /// Spindle speed (rpm) and direction.
    Spindle {
        /// Revolutions per minute.
        rpm: f64,
        /// Direction.
        dir: SpindleDir,
    },
    /// A tool was loaded into the spindle (M6 after T, `LOADTL/`).
    ToolChange {
        /// Tool number.
        tool: u32,
    },
    /// Tool length offset now in effect (G43/G49), mm. Informational: swarf's programs are
    /// tool-tip programs.
    ToolLengthOffset(f64),
    /// Rapid move to `end`.
    Traverse {
        /// End point.
        end: Axes,
    },
    /// Linear feed move to `end`.
    Feed {
        /// End point.
        end: Axes,
    },
    /// Circular or helical feed move (LinuxCNC's `ARC_FEED`).
    Arc {
        /// End point (including the helix axis and rotary axes).
        end: Axes,
        /// Centre: the coordinates along the plane's first and second axes.
        center: [f64; 2],
        /// Turns: positive counter-clockwise (G3), negative clockwise (G2) seen from the plane
        /// normal's positive side; |rotation| − 1 extra full turns.
        rotation: i32,
        /// The plane.
        plane: Plane,
    },
    /// A spline feed in the XY plane (G5, G5.1, G5.2/G5.3) from the current position: the exact
    /// curve (see [`crate::spline`]). The canonical print keeps it; the move stream flattens it
    /// into straight feeds.
    Spline {
        /// End point (the last control point's X and Y; the other axes stay).
        end: Axes,
        /// Cubic, quadratic or NURBS.
        kind: crate::spline::SplineKind,
        /// The control points after the start, `(x, y, weight)`, mm, the end included.
        controls: Cow<'a, [[f64; 3]]>,
    },
    /// A dwell of this many seconds.
    Dwell(f64),
    /// A comment or message from the program (borrowed while streaming, owned when kept).
    Comment(Cow<'a, str>),
    /// An operator message (`(MSG,…)`, `(DEBUG,…)`, `(PRINT,…)`), parameters already replaced
    /// by their values as LinuxCNC prints them (`%f`).
    Message {
        /// Which kind of active comment.
        kind: MessageKind,
        /// The text after the comma.
        text: Cow<'a, str>,
    },
    /// A definition of the active tool's geometry from the program (APT `CUTTER/`): the seven
    /// APT numbers d, r, e, f, α, β, h (mm, degrees); h = 0 means the program did not give it.
    CutterDefinition([f64; 7]),
    /// The workpiece blank the program declares (Heidenhain `BLK FORM`): a box, corners in the
    /// program's coordinates (mm) where it is declared.
    Blank {
        /// The least corner.
        min: [f64; 3],
        /// The greatest corner.
        max: [f64; 3],
    },
    /// M2/M30/`FINI`: the end of the program.
    ProgramEnd,
    /// The events that follow come from this file (a subroutine file of a G-code program, or
    /// back to the program); their lines are lines of it.
    SourceFile(Cow<'a, str>),
    /// CL data only (APT `GOTO/x,y,z,i,j,k`): the tool axis — a unit vector from the tip towards
    /// the spindle, in the workpiece frame — for the moves that follow. Once a program states
    /// its axis this way, [`MoveBuilder`](crate::builder::MoveBuilder) takes the axis from the
    /// program instead of from the machine's rotary joints (the positions are then tool tips in
    /// the workpiece frame). The axis turns from the previous one to this one over the next move.
    ToolAxis([f64; 3]),
    /// The tool is at `pos` without having moved there (APT `FROM/`, the first point of a CL
    /// file; G88's hand retract, which the operator makes). No move is made.
    SetPosition(Axes),
    /// LinuxCNC's G33.1 rigid tap to `end` (rs274's `RIGID_TAP(x, y, z)`), announced before
    /// the events that make it (over the hole, down, the spindle reversed, back out, the feed
    /// mode restored), which follow as ordinary moves: a sink that follows the moves ignores
    /// it; the canonical print prints it instead of them.
    RigidTap {
        /// The bottom of the tap.
        end: Axes,
    },
    /// CL data only (APT `CIRCLE/` with an axis that is not ±X, ±Y or ±Z): a circular or helical
    /// feed move about an arbitrary axis through `center`. The motion is counter-clockwise about
    /// `normal` (right-hand rule); `turns` ≥ 1 counts full or partial turns as `|rotation|` does
    /// in [`Canon::Arc`] (start = end with `turns` = 1 is one full circle).
    ArcAxis {
        /// End point.
        end: Axes,
        /// A point on the arc's axis, mm.
        center: [f64; 3],
        /// Unit normal; the motion is counter-clockwise about it.
        normal: [f64; 3],
        /// 1 for an arc of at most one turn, n for n − 1 extra full turns.
        turns: u32,
    },
}

/// Receives canonical events in program order, with the source line of each.
pub trait CanonSink {
    /// Called once per event. `line` is the 1-based source line in the file being read.
    fn emit(&mut self, line: u32, event: &Canon<'_>);
    /// A harmless thing the reader did not act on.
    fn warn(&mut self, warning: crate::Warning);
    /// The program position the sink holds now, when it keeps one (a
    /// [`MoveBuilder`](crate::builder::MoveBuilder), which knows the machine). Turning tool
    /// centre point control on or off re-expresses the position where the tool stands
    /// ([`Canon::ToolCentrePoint`]): a reader takes its X Y Z back from here, so that the axes a
    /// later block leaves out (a `G53 G0 Z0` retract, an incremental move) start where the
    /// machine is rather than from the coordinates of the other reading.
    fn position(&self) -> Option<Axes> {
        None
    }
}

/// A sink that keeps every event (owned) — for tests and small programs.
#[derive(Default, Debug)]
pub struct Recorder {
    /// The events, with their lines.
    pub events: Vec<(u32, OwnedCanon)>,
    /// The warnings.
    pub warnings: Vec<crate::Warning>,
}

/// An owned copy of a [`Canon`] event.
pub type OwnedCanon = Canon<'static>;

impl Recorder {
    /// The texts of the operator messages (`(MSG,…)`, `(DEBUG,…)`, `(PRINT,…)`), in order.
    pub fn messages(&self) -> Vec<String> {
        self.events
            .iter()
            .filter_map(|(_, e)| match e {
                Canon::Message { text, .. } => Some(text.to_string()),
                _ => None,
            })
            .collect()
    }
}

impl Canon<'_> {
    /// An owned copy of the event (borrowed comment text is copied).
    pub fn to_owned_event(&self) -> OwnedCanon {
        let event = self;
        match event {
            Canon::Comment(c) => Canon::Comment(Cow::Owned(c.to_string())),
            Canon::Message { kind, text } => Canon::Message {
                kind: *kind,
                text: Cow::Owned(text.to_string()),
            },
            Canon::Units(u) => Canon::Units(*u),
            Canon::Offsets { index, g5x, g92 } => Canon::Offsets {
                index: *index,
                g5x: *g5x,
                g92: *g92,
            },
            Canon::Plane(p) => Canon::Plane(*p),
            Canon::WorkPlane(w) => Canon::WorkPlane(*w),
            Canon::MachineAxis => Canon::MachineAxis,
            Canon::ToolCentrePoint(on) => Canon::ToolCentrePoint(*on),
            Canon::XyRotation(r) => Canon::XyRotation(*r),
            Canon::FeedRate(f) => Canon::FeedRate(*f),
            Canon::FeedMode(m) => Canon::FeedMode(*m),
            Canon::RotaryFeedCombined(on) => Canon::RotaryFeedCombined(*on),
            Canon::Spindle { rpm, dir } => Canon::Spindle {
                rpm: *rpm,
                dir: *dir,
            },
            Canon::ToolChange { tool } => Canon::ToolChange { tool: *tool },
            Canon::ToolLengthOffset(l) => Canon::ToolLengthOffset(*l),
            Canon::Traverse { end } => Canon::Traverse { end: *end },
            Canon::Feed { end } => Canon::Feed { end: *end },
            Canon::Arc {
                end,
                center,
                rotation,
                plane,
            } => Canon::Arc {
                end: *end,
                center: *center,
                rotation: *rotation,
                plane: *plane,
            },
            Canon::Dwell(d) => Canon::Dwell(*d),
            Canon::Spline {
                end,
                kind,
                controls,
            } => Canon::Spline {
                end: *end,
                kind: *kind,
                controls: Cow::Owned(controls.to_vec()),
            },
            Canon::CutterDefinition(p) => Canon::CutterDefinition(*p),
            Canon::ProgramEnd => Canon::ProgramEnd,
            Canon::Blank { min, max } => Canon::Blank {
                min: *min,
                max: *max,
            },
            Canon::SourceFile(f) => Canon::SourceFile(Cow::Owned(f.to_string())),
            Canon::ToolAxis(a) => Canon::ToolAxis(*a),
            Canon::SetPosition(p) => Canon::SetPosition(*p),
            Canon::RigidTap { end } => Canon::RigidTap { end: *end },
            Canon::ArcAxis {
                end,
                center,
                normal,
                turns,
            } => Canon::ArcAxis {
                end: *end,
                center: *center,
                normal: *normal,
                turns: *turns,
            },
        }
    }
}

impl CanonSink for Recorder {
    fn emit(&mut self, line: u32, event: &Canon<'_>) {
        self.events.push((line, event.to_owned_event()));
    }
    fn warn(&mut self, warning: crate::Warning) {
        self.warnings.push(warning);
    }
}
