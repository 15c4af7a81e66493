//! Turns canonical events into the move stream: [`MoveBuilder`] is the [`CanonSink`] that keeps
//! a program's motion as [`Move`]s with poses in the workpiece frame.
//!
//! It tracks what the events state — work offsets, feed rate and mode, spindle, tool, the tool
//! axis of CL data — and applies the [`Machine`] to every end point: joint values are the
//! program position plus the G92 offset, turned by the XY rotation, plus the G5x offset; poses come from [`Machine::pose`], or, once a
//! program states its own tool axis ([`Canon::ToolAxis`], APT CL data), directly from the
//! program (tip = position, axis = the stated axis, no kinematics).
//!
//! Events are in millimetres already (the readers convert inch programs), so [`Canon::Units`] is
//! informational here. Zero-length moves are kept as moves: later stages must cope with them,
//! and counts stay the same whichever stage does the counting.
//!
//! ```
//! use swarf_path::builder::MoveBuilder;
//! use swarf_path::kinematics::Machine;
//! use swarf_path::{Axes, Canon, CanonSink, Plane};
//! let mut b = MoveBuilder::new(Machine::three_axis(), "demo.ngc");
//! b.emit(1, &Canon::Feed { end: Axes { x: 10.0, ..Axes::default() } });
//! // A full circle (end = start) counter-clockwise about (5, 0).
//! b.emit(2, &Canon::Arc { end: Axes { x: 10.0, ..Axes::default() }, center: [5.0, 0.0], rotation: 1, plane: Plane::XY });
//! let p = b.finish();
//! assert_eq!(p.moves.len(), 2);
//! let swarf_path::MoveKind::Arc(g) = p.moves[1].kind else { panic!() };
//! assert!((g.sweep - std::f64::consts::TAU).abs() < 1e-12);
//! ```

use std::f64::consts::TAU;

use swarf_geom::math::{Mat3, Vec3};

use crate::canon::{Axes, Canon, CanonSink, FeedMode, SpindleDir};
use crate::kinematics::{Machine, RotaryWord};
use crate::moves::{ArcGeom, AxisSource, Move, MoveKind, Pose, Program, SourceLine};
use crate::Warning;

/// The first tool number given to a cutter a program redefines after it has cut (see
/// `MoveBuilder::bind_cutter`): far above the tool numbers programs load, so that a later tool
/// change never finds it.
pub const REDEFINED_TOOLS: u32 = 1_000_000;

/// Builds a [`Program`] from canonical events. See the [module documentation](self).
#[derive(Debug)]
pub struct MoveBuilder {
    machine: Machine,
    /// The files moves come from (the program first), and the current one.
    files: Vec<String>,
    file: u16,
    /// Program position (current coordinate system), mm / degrees.
    pos: Axes,
    g5x: Axes,
    g92: Axes,
    /// Rotation of the XY plane about the G5x origin (G10 L2 R), as cosine and sine.
    xy_rotation: (f64, f64),
    /// A tilted working plane (G68.2): its axes and origin in the untilted program frame.
    tilt: Option<(Mat3, Vec3)>,
    /// The tool axis comes from the tilted plane (G53.1), not from the machine, until G69.
    tilt_axis: bool,
    /// After G69: the tool keeps the plane's axis until [`Canon::MachineAxis`] (the program
    /// turns a rotary axis) hands it back to the machine, at the next move (`release_axis`).
    held_axis: bool,
    release_axis: bool,
    /// Chordal tolerance splines are flattened within, mm.
    spline_tolerance: f64,
    feed: f64,
    feed_mode: FeedMode,
    /// [`Canon::RotaryFeedCombined`]'s rule, stamped on each move.
    rotary_feed_combined: bool,
    /// The program is in inches ([`Canon::Units`]): Fanuc's combined feed counts a degree as
    /// an inch then.
    inch: bool,
    spindle_rpm: f64,
    spindle_dir: SpindleDir,
    tool: u32,
    /// Tool axis of the current position in CL mode.
    axis: Vec3,
    /// Tool axis the next CL move ends with.
    target_axis: Vec3,
    axis_source: AxisSource,
    /// A `CUTTER/` definition not yet bound to a tool: it belongs to the tool loaded next, or to
    /// the current one if motion comes first (CAM systems write it on either side of `LOADTL/`).
    pending_cutter: Option<([f64; 7], u32)>,
    moves: Vec<Move>,
    /// Moves built, those taken by [`MoveBuilder::take_moves`] included.
    built: u64,
    /// A move of tool 0 (no tool loaded) was built.
    tool_zero_moved: bool,
    tools: Vec<u32>,
    cutter_definitions: Vec<(u32, [f64; 7])>,
    cutter_definition_lines: Vec<SourceLine>,
    /// Tools that have moved with the cutter definition bound to them: a different definition
    /// for one of them later is a cutter of its own (see `bind_cutter`).
    defined_tools_moved: Vec<u32>,
    blank: Option<[[f64; 3]; 2]>,
    dwell_s: f64,
    warnings: Vec<Warning>,
    /// Rotary words (A, B, C) already reported as not modelled by the machine.
    unmodelled_warned: [bool; 3],
}

impl MoveBuilder {
    /// A builder for a program read from `file_name`, on `machine`. The tool starts at the
    /// program origin with all offsets zero, as LinuxCNC's interpreter does.
    pub fn new(machine: Machine, file_name: &str) -> Self {
        Self {
            machine,
            files: vec![file_name.to_string()],
            file: 0,
            pos: Axes::default(),
            g5x: Axes::default(),
            g92: Axes::default(),
            xy_rotation: (1.0, 0.0),
            tilt: None,
            tilt_axis: false,
            held_axis: false,
            release_axis: false,
            spline_tolerance: crate::spline::DEFAULT_TOLERANCE_MM,
            feed: 0.0,
            feed_mode: FeedMode::PerMinute,
            rotary_feed_combined: false,
            inch: false,
            spindle_rpm: 0.0,
            spindle_dir: SpindleDir::Stopped,
            tool: 0,
            axis: Vec3::Z,
            target_axis: Vec3::Z,
            axis_source: AxisSource::Machine,
            pending_cutter: None,
            moves: Vec::new(),
            built: 0,
            tool_zero_moved: false,
            tools: Vec::new(),
            cutter_definitions: Vec::new(),
            cutter_definition_lines: Vec::new(),
            defined_tools_moved: Vec::new(),
            blank: None,
            dwell_s: 0.0,
            warnings: Vec::new(),
            unmodelled_warned: [false; 3],
        }
    }

    /// Sets the chordal tolerance splines (G5, G5.1, G5.2) are flattened within, mm (default
    /// [`crate::spline::DEFAULT_TOLERANCE_MM`]).
    pub fn with_spline_tolerance(mut self, tolerance_mm: f64) -> Self {
        self.spline_tolerance = tolerance_mm;
        self
    }

    /// Takes the moves built since the last call out of the builder, for consumers that handle
    /// moves as they come and need memory independent of the program's length (see
    /// [`crate::summary::SummarySink`]). [`MoveBuilder::finish`] then holds only the moves
    /// built after the last call.
    pub fn take_moves(&mut self) -> std::vec::Drain<'_, Move> {
        self.moves.drain(..)
    }

    /// Moves built so far, taken ones included.
    pub fn moves_built(&self) -> u64 {
        self.built
    }

    /// True when a move was built with no tool loaded (tool 0).
    pub fn tool_zero_moved(&self) -> bool {
        self.tool_zero_moved
    }

    /// The machine, and where the tool axis comes from now.
    pub fn context(&self) -> (&Machine, AxisSource) {
        (&self.machine, self.axis_source)
    }

    /// The program read so far.
    pub fn finish(mut self) -> Program {
        // A definition after the last move cuts nothing: it only names the cutter of a tool
        // that has none.
        if let Some(def) = self.pending_cutter.take() {
            if !self.cutter_definitions.iter().any(|(t, _)| *t == self.tool) {
                self.bind_cutter(self.tool, def);
            }
        }
        Program {
            cutter_definition_lines: self.cutter_definition_lines,
            moves: self.moves,
            files: self.files,
            tools: self.tools,
            cutter_definitions: self.cutter_definitions,
            warnings: self.warnings,
            machine: self.machine,
            axis_source: self.axis_source,
            blank: self.blank,
            dwell_s: self.dwell_s,
        }
    }

    /// Joint values of a program position: the G92 offset, then the XY rotation, then the G5x
    /// offset (LinuxCNC's canon layer).
    fn joints(&self, p: &Axes) -> Axes {
        let q = self.untilted(p).add(self.g92);
        let (c, s) = self.xy_rotation;
        let r = Axes {
            x: c * q.x - s * q.y,
            y: s * q.x + c * q.y,
            ..q
        };
        r.add(self.g5x)
    }

    /// The program position of joint values `j`: [`MoveBuilder::joints`] inverted.
    fn program_of(&self, j: &Axes) -> Axes {
        let q = j.sub(self.g5x);
        let (c, s) = self.xy_rotation;
        let r = Axes {
            x: c * q.x + s * q.y,
            y: -s * q.x + c * q.y,
            ..q
        };
        self.tilted(&r.sub(self.g92))
    }

    /// Program position `p` in the untilted program frame (the tilted plane's origin plus its
    /// axes times `p`).
    fn untilted(&self, p: &Axes) -> Axes {
        match self.tilt {
            None => *p,
            Some((r, o)) => {
                let q = o + r * Vec3::new(p.x, p.y, p.z);
                Axes {
                    x: q.x,
                    y: q.y,
                    z: q.z,
                    ..*p
                }
            }
        }
    }

    /// [`MoveBuilder::untilted`] inverted.
    fn tilted(&self, q: &Axes) -> Axes {
        match self.tilt {
            None => *q,
            Some((r, o)) => {
                let p = r.transpose() * (Vec3::new(q.x, q.y, q.z) - o);
                Axes {
                    x: p.x,
                    y: p.y,
                    z: p.z,
                    ..*q
                }
            }
        }
    }

    /// A direction of the program frame in joint space: the tilted plane's rotation, then the
    /// XY rotation.
    fn direction(&self, v: Vec3) -> Vec3 {
        let v = self.tilt.map_or(v, |(r, _)| r * v);
        let (cos, sin) = self.xy_rotation;
        Vec3::new(cos * v.x - sin * v.y, sin * v.x + cos * v.y, v.z)
    }

    /// Changes the program frame (offsets, rotation) with the tool where it is: the current
    /// position is re-expressed in the new frame, as LinuxCNC's interpreter does, so the next
    /// move starts where the last one ended on the machine.
    fn change_frame(&mut self, change: impl FnOnce(&mut Self)) {
        let at = self.joints(&self.pos);
        change(self);
        self.pos = self.program_of(&at);
    }

    /// The tool axis is one a G-code-like program stated as a vector (the axis source is the
    /// program, and not through a tilted plane's G53.1): a rotary word or the end of tool
    /// centre point control hands it back to the machine. (CL data states every axis and has
    /// no rotary words.)
    fn axis_stated(&self) -> bool {
        self.axis_source == AxisSource::Program && !self.tilt_axis && !self.held_axis
    }

    /// Hands a stated tool axis back to the machine where the tool stands: the rotary joints
    /// that give the axis (nearest to the program's own rotary values), and X Y Z the machine's
    /// reading of the tip for them.
    fn axis_to_machine(&mut self, line: u32) {
        let joints = self.joints(&self.pos);
        let pose = Pose {
            tip: Vec3::new(joints.x, joints.y, joints.z),
            axis: self.axis,
        };
        match self.machine.inverse(&pose, &joints) {
            Some(j) => self.pos = self.program_of(&j),
            None => {
                // The tip stays where it is: X Y Z become the machine's reading of it with the
                // rotary axes as the program left them.
                let kept = self.machine.joints_for_tip(pose.tip, &joints);
                self.pos = self.program_of(&kept);
                self.warn_at(
                    line,
                    format!(
                        "machine `{}` cannot turn the tool to the axis the program stated \
                         ({:.4}, {:.4}, {:.4}): the rotary axes keep the program's values",
                        self.machine.name, self.axis.x, self.axis.y, self.axis.z
                    ),
                );
            }
        }
        self.axis_source = AxisSource::Machine;
        self.release_axis = false;
        let end = self.machine.pose(&self.joints(&self.pos)).axis;
        (self.axis, self.target_axis) = (end, end);
    }

    fn pose(&self, joints: &Axes, axis: Vec3) -> Pose {
        match self.axis_source {
            AxisSource::Machine => self.machine.pose(joints),
            AxisSource::Program => Pose {
                tip: Vec3::new(joints.x, joints.y, joints.z),
                axis,
            },
        }
    }

    /// Binds a cutter definition to `tool`; returns the tool it was bound to. A definition
    /// that differs from the one `tool` has already moved with is a different cutter (NX writes
    /// a `TLDATA/` per operation, APT a `CUTTER/`, often with no `LOADTL/` between them): the
    /// moves before it keep their cutter, and the moves after it are given a tool number of
    /// their own, from [`REDEFINED_TOOLS`] up, with a warning.
    fn bind_cutter(&mut self, tool: u32, (def, line): ([f64; 7], u32)) -> u32 {
        let at = SourceLine {
            file: self.file,
            line,
        };
        let same = |a: &[f64; 7], b: &[f64; 7]| {
            a.iter()
                .zip(b)
                .all(|(x, y)| (x - y).abs() <= 1e-9 * x.abs().max(y.abs()).max(1.0))
        };
        let mut tool = tool;
        if let Some(i) = self.cutter_definitions.iter().position(|(t, _)| *t == tool) {
            let moved = self.defined_tools_moved.contains(&tool);
            if !moved || same(&self.cutter_definitions[i].1, &def) {
                self.cutter_definitions[i].1 = def;
                self.cutter_definition_lines[i] = at;
                return tool;
            }
            let earlier = self.cutter_definition_lines[i].line;
            // From a range of numbers programs do not load (a later `LOADTL/1` must not find
            // this cutter).
            let fresh = self
                .tools
                .iter()
                .chain(self.cutter_definitions.iter().map(|(t, _)| t))
                .chain([&tool])
                .max()
                .map_or(REDEFINED_TOOLS, |t| {
                    t.saturating_add(1).max(REDEFINED_TOOLS)
                });
            self.warn_at(
                line,
                format!(
                    "a different cutter for {} than the one it cut with (defined at line \
                     {earlier}): the moves from here are given tool {fresh}, a tool of its own, \
                     and the moves before keep theirs",
                    match tool {
                        0 => "the tool in use (no tool change)".to_string(),
                        n => format!("tool {n}"),
                    }
                ),
            );
            tool = fresh;
            if !self.tools.contains(&tool) {
                self.tools.push(tool);
            }
        }
        self.cutter_definitions.push((tool, def));
        self.cutter_definition_lines.push(at);
        tool
    }

    fn warn_at(&mut self, line: u32, message: String) {
        self.warnings.push(Warning {
            file: self.files[usize::from(self.file)].clone(),
            line,
            column: 0,
            message,
        });
    }

    /// A program that turns a rotary axis the machine does not have would silently be simulated
    /// with a wrong tool axis: say so once per axis, naming the machine.
    fn check_rotary_modelled(&mut self, line: u32, joints: &Axes) {
        if self.axis_source == AxisSource::Program {
            return;
        }
        let words = [
            (RotaryWord::A, joints.a),
            (RotaryWord::B, joints.b),
            (RotaryWord::C, joints.c),
        ];
        for (i, (word, value)) in words.into_iter().enumerate() {
            let modelled = self
                .machine
                .table
                .iter()
                .chain(&self.machine.head)
                .any(|j| j.word == word);
            if value != 0.0 && !modelled && !self.unmodelled_warned[i] {
                self.unmodelled_warned[i] = true;
                self.warn_at(
                    line,
                    format!(
                        "{word:?} moves ({word:?}{value}) but machine `{}` has no {word:?} axis: \
                         the tool axis ignores it (choose the machine with --machine)",
                        self.machine.name
                    ),
                );
            }
        }
    }

    /// Appends a move from the current position to `end` (program coordinates).
    fn push(&mut self, line: u32, end: &Axes, kind: impl FnOnce(&Self, &Axes, &Axes) -> MoveKind) {
        if let Some(def) = self.pending_cutter.take() {
            self.tool = self.bind_cutter(self.tool, def);
        }
        if !self.defined_tools_moved.contains(&self.tool)
            && self.cutter_definitions.iter().any(|(t, _)| *t == self.tool)
        {
            self.defined_tools_moved.push(self.tool);
        }
        let start_joints = self.joints(&self.pos);
        let end_joints = self.joints(end);
        self.check_rotary_modelled(line, &end_joints);
        let kind = kind(self, &start_joints, &end_joints);
        let start_pose = self.pose(&start_joints, self.axis);
        // The move that hands the axis back to the machine turns the tool from the held axis
        // to the machine's, as a CL move does (tip straight, axis turning evenly).
        let axis_source = self.axis_source;
        if std::mem::take(&mut self.release_axis) {
            self.axis_source = AxisSource::Machine;
        }
        let end_pose = self.pose(&end_joints, self.target_axis);
        if self.axis_source == AxisSource::Machine {
            self.target_axis = end_pose.axis;
        }
        let m = Move {
            kind,
            start: start_pose,
            end: end_pose,
            start_joints,
            end_joints,
            feed: self.feed,
            feed_mode: self.feed_mode,
            spindle_rpm: self.spindle_rpm,
            spindle_dir: self.spindle_dir,
            tool: self.tool,
            file: self.file,
            line,
            axis_source,
            tcp: self.machine.tcp,
            rotary_feed_combined: self.rotary_feed_combined.then_some(if self.inch {
                25.4
            } else {
                1.0
            }),
        };
        self.tool_zero_moved |= m.tool == 0;
        self.moves.push(m);
        self.built += 1;
        self.pos = *end;
        self.axis = self.target_axis;
    }

    /// Arc geometry in the workpiece frame for an arc whose joint-space (X Y Z) centre is
    /// `center` and whose motion is counter-clockwise about unit `normal`, with `turns` ≥ 1.
    fn arc_geom(
        &self,
        start: &Axes,
        end: &Axes,
        center: Vec3,
        normal: Vec3,
        turns: u32,
    ) -> MoveKind {
        let q0 = Vec3::new(start.x, start.y, start.z);
        let q1 = Vec3::new(end.x, end.y, end.z);
        let r0 = (q0 - center) - normal * normal.dot(q0 - center);
        let r1 = (q1 - center) - normal * normal.dot(q1 - center);
        let mut sweep = normal.dot(r0.cross(r1)).atan2(r0.dot(r1));
        // As LinuxCNC: an end at or before the start angle goes round; equal angles (start =
        // end) make a full circle.
        if sweep <= 0.0 {
            sweep += TAU;
        }
        sweep += f64::from(turns.saturating_sub(1)) * TAU;
        // The axis point in the start's plane.
        let c_start = center + normal * normal.dot(q0 - center);
        let (r, t) = match self.axis_source {
            AxisSource::Machine => self.machine.joint_space_to_workpiece(start),
            AxisSource::Program => (swarf_geom::math::Mat3::IDENTITY, Vec3::ZERO),
        };
        MoveKind::Arc(ArcGeom {
            center: r * c_start + t,
            normal: r * normal,
            sweep,
            start_radius: r0.length(),
            end_radius: r1.length(),
            helix: normal.dot(q1 - q0),
        })
    }
}

impl CanonSink for MoveBuilder {
    fn emit(&mut self, line: u32, event: &Canon<'_>) {
        match event {
            Canon::SourceFile(name) => {
                self.file = match self.files.iter().position(|f| f == name) {
                    Some(i) => i as u16,
                    None => {
                        self.files.push(name.to_string());
                        (self.files.len() - 1) as u16
                    }
                };
            }
            Canon::XyRotation(deg) => {
                let a = deg.to_radians();
                self.change_frame(|b| b.xy_rotation = (a.cos(), a.sin()));
            }
            Canon::Offsets { g5x, g92, .. } => self.change_frame(|b| {
                b.g5x = *g5x;
                b.g92 = *g92;
            }),
            Canon::FeedRate(f) => self.feed = *f,
            Canon::FeedMode(m) => self.feed_mode = *m,
            Canon::RotaryFeedCombined(on) => self.rotary_feed_combined = *on,
            Canon::Spindle { rpm, dir } => {
                self.spindle_rpm = if *dir == SpindleDir::Stopped {
                    0.0
                } else {
                    *rpm
                };
                self.spindle_dir = *dir;
            }
            Canon::ToolChange { tool } => {
                self.tool = *tool;
                if !self.tools.contains(tool) {
                    self.tools.push(*tool);
                }
                if let Some(def) = self.pending_cutter.take() {
                    self.tool = self.bind_cutter(*tool, def);
                }
            }
            Canon::CutterDefinition(def) => {
                if let Some(prev) = self.pending_cutter.replace((*def, line)) {
                    self.tool = self.bind_cutter(self.tool, prev);
                }
            }
            Canon::Spline {
                end,
                kind,
                controls,
            } => {
                let start = [self.pos.x, self.pos.y];
                let pts = crate::spline::flatten(start, *kind, controls, self.spline_tolerance);
                for p in pts {
                    let to = Axes {
                        x: p[0],
                        y: p[1],
                        ..*end
                    };
                    self.push(line, &to, |_, _, _| MoveKind::Linear);
                }
                // The exact end, whatever the last piece's rounding.
                self.pos = *end;
            }
            Canon::Traverse { end } => self.push(line, end, |_, _, _| MoveKind::Rapid),
            Canon::Feed { end } => self.push(line, end, |_, _, _| MoveKind::Linear),
            Canon::Arc {
                end,
                center,
                rotation,
                plane,
            } => {
                if *rotation == 0 {
                    self.warn_at(
                        line,
                        "arc with zero rotation taken as a straight feed".into(),
                    );
                    self.push(line, end, |_, _, _| MoveKind::Linear);
                    return;
                }
                let (i1, i2, n) = plane.axes();
                let (center, rotation) = (*center, *rotation);
                let start = self.pos.to_array();
                self.push(line, end, |b, s, e| {
                    let mut c = start;
                    c[i1] = center[0];
                    c[i2] = center[1];
                    let c = b.joints(&Axes::from_array(c));
                    let mut normal = Vec3::ZERO;
                    normal[n] = if rotation > 0 { 1.0 } else { -1.0 };
                    let normal = b.direction(normal);
                    b.arc_geom(
                        s,
                        e,
                        Vec3::new(c.x, c.y, c.z),
                        normal,
                        rotation.unsigned_abs(),
                    )
                });
            }
            Canon::ArcAxis {
                end,
                center,
                normal,
                turns,
            } => {
                let n = Vec3::from_array(*normal);
                let Some(n) = n.try_normalize() else {
                    self.warn_at(
                        line,
                        "arc about a zero axis taken as a straight feed".into(),
                    );
                    self.push(line, end, |_, _, _| MoveKind::Linear);
                    return;
                };
                let (center, turns) = (*center, (*turns).max(1));
                self.push(line, end, |b, s, e| {
                    let off = b.g5x.add(b.g92);
                    let c = Vec3::from_array(center) + Vec3::new(off.x, off.y, off.z);
                    b.arc_geom(s, e, c, n, turns)
                });
            }
            Canon::ToolAxis(a) => {
                let Some(a) = Vec3::from_array(*a).try_normalize() else {
                    self.warn_at(line, "zero tool axis ignored".into());
                    return;
                };
                if self.axis_source == AxisSource::Machine {
                    if self.built > 0 {
                        self.warn_at(
                            line,
                            "the program states its tool axis after moving: earlier moves used \
                             the machine kinematics, later ones take the axis from the program"
                                .into(),
                        );
                    } else {
                        self.axis = a;
                    }
                    self.axis_source = AxisSource::Program;
                }
                self.target_axis = a;
            }
            Canon::WorkPlane(w) => {
                self.change_frame(|b| {
                    b.tilt = w.map(|w| (w.matrix(), Vec3::from_array(w.origin)));
                });
                match w {
                    // G53.1: the tool turns to the plane's Z where it stands (its tip where the
                    // machine put it), and the axis comes from the program from here on.
                    Some(w) if w.tool_axis => {
                        if self.axis_source == AxisSource::Machine {
                            let tip = self.machine.pose(&self.joints(&self.pos)).tip;
                            let mut j = self.joints(&self.pos);
                            (j.x, j.y, j.z) = (tip.x, tip.y, tip.z);
                            self.axis_source = AxisSource::Program;
                            self.pos = self.program_of(&j);
                        }
                        let a = self.direction(Vec3::Z);
                        (self.axis, self.target_axis) = (a, a);
                        (self.tilt_axis, self.held_axis) = (true, false);
                        // A reset's hand-back not yet made (no move since) is void: the tool
                        // turns to this plane instead.
                        self.release_axis = false;
                    }
                    // A plane without G53.1 leaves the tool as it is.
                    Some(_) => {}
                    // G69 cancels the plane, not the rotary axes' position: the tool keeps its
                    // axis until the program turns a rotary axis.
                    None => {
                        if std::mem::take(&mut self.tilt_axis) {
                            self.held_axis = true;
                        }
                    }
                }
            }
            Canon::ToolCentrePoint(on) => {
                // The tool stays where it is: its position is re-expressed in the new reading
                // of X Y Z (tip in the part frame, or the machine's controlled point), so the
                // next move starts where the last one ended.
                let turns = self.machine.tcp != *on && self.machine.has_rotary();
                if turns && self.axis_source == AxisSource::Machine {
                    let joints = self.joints(&self.pos);
                    let tip = self.machine.pose(&joints).tip;
                    self.machine.tcp = *on;
                    let moved = self.machine.joints_for_tip(tip, &joints);
                    self.pos = self.program_of(&moved);
                } else if turns && !*on && self.axis_stated() {
                    // The axis a program stated as a vector (LN TX TY TZ, A3= B3= C3=, G43.5
                    // I J K) lives only under tool centre point control: once it is off, the
                    // rotary axes hold the tool where the vector put it, and X Y Z are the
                    // machine's controlled point for them.
                    self.machine.tcp = false;
                    self.axis_to_machine(line);
                } else {
                    self.machine.tcp = *on;
                }
            }
            Canon::MachineAxis => {
                self.release_axis |= std::mem::take(&mut self.held_axis);
                // A rotary word after a stated vector: the machine's axes set the tool axis
                // again, from the next move on (which turns the tool from the stated axis).
                self.release_axis |= self.axis_stated();
            }
            Canon::SetPosition(p) => {
                self.pos = *p;
                self.axis = self.target_axis;
            }
            Canon::Blank { min, max } => {
                // The box of its corners in the workpiece frame (the rotary axes at zero).
                let corner = |i: usize| {
                    let p = |k: usize| if i >> k & 1 == 0 { min[k] } else { max[k] };
                    let j = self.joints(&Axes {
                        x: p(0),
                        y: p(1),
                        z: p(2),
                        ..Axes::default()
                    });
                    [j.x, j.y, j.z]
                };
                let mut b = [[f64::INFINITY; 3], [f64::NEG_INFINITY; 3]];
                for c in (0..8).map(corner) {
                    for k in 0..3 {
                        b[0][k] = b[0][k].min(c[k]);
                        b[1][k] = b[1][k].max(c[k]);
                    }
                }
                self.blank = Some(b);
            }
            // (A negative or non-finite dwell is no wait.)
            Canon::Dwell(s) if s.is_finite() && *s > 0.0 => self.dwell_s += s,
            Canon::Units(u) => self.inch = *u == crate::Units::Inch,
            Canon::Plane(_)
            | Canon::ToolLengthOffset(_)
            | Canon::Dwell(_)
            | Canon::Comment(_)
            | Canon::Message { .. }
            | Canon::RigidTap { .. }
            | Canon::ProgramEnd => {}
        }
    }

    fn warn(&mut self, warning: Warning) {
        self.warnings.push(warning);
    }

    fn position(&self) -> Option<Axes> {
        Some(self.pos)
    }
}
