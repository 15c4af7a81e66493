//! Machine kinematics: joint values (X Y Z A B C, program position plus work offsets) to the
//! tool tip and tool axis in the workpiece frame, and back.
//!
//! # Model
//! A [`Machine`] is a serial chain with at most two rotary joints, each on one of two sides:
//!
//! ```text
//!   workpiece ─ table joints ─ bed ── X Y Z slides ── head joints ─ spindle ─ tool tip
//!              (inner … outer)                       (outer … inner)
//! ```
//!
//! * **Table joints** carry the part. They are listed outermost first (the one bolted to the bed,
//!   e.g. the A trunnion of an A/C table, then the C rotary table it carries). Their centres are
//!   points on the rotation axes in machine coordinates (the frame of the joint values: program
//!   position + G5x + G92).
//! * **Head joints** carry the spindle. They are listed outermost first (the one on the ram, e.g.
//!   C of a C/A fork head, then A). Their centres are given relative to the controlled point (the
//!   tool tip) at zero rotation, so a fork head with pivot length L has both centres at
//!   `[0, 0, L]`.
//!
//! All geometry is stated at the **zero pose** (all rotary joints at 0°), where the workpiece
//! frame coincides with the machine frame and the tool axis is +Z.
//!
//! # Signs
//! A rotary joint value θ turns **its own body** (the table, or the head) by θ about the joint's
//! direction (+X for A, +Y for B, +Z for C unless the file says otherwise), by the right-hand
//! rule — thumb along the direction, fingers curl the positive way:
//!
//! ```text
//!         +Z (tool axis at zero pose)
//!          │    A>0 turns the table so that its +Z face tilts towards −Y;
//!          │    seen from the part, the tool axis then leans towards +Y.
//!          │
//!          └──── +Y
//!         ╱
//!       +X  (A's axis, pointing at you: positive A is counter-clockwise)
//! ```
//!
//! So on a table about X (`4axis-a`), A = 90° puts the tool axis along **+Y** of the part frame;
//! on a head about X, A = 90° puts it along **−Y**. A joint's `reverse` flag negates its value
//! for machines that count the other way (ISO 841's "primed" table axes, for instance).
//!
//! # TCP
//! With `tcp` (LinuxCNC's TCP kinematics; programs switch it themselves with Fanuc G43.4,
//! Heidenhain M128, Sinumerik TRAORI: [`crate::Canon::ToolCentrePoint`], and each move records
//! its reading, [`crate::Move::tcp`]) the joint X Y Z are the tool tip in the workpiece frame and
//! only the axis comes from the rotary joints. Without it,
//! X Y Z position the controlled point in the machine frame: the tip is carried by the head
//! joints about their pivots and mapped back into the rotating workpiece frame through the table
//! joints.
//!
//! Motion between two joint positions is linear in joint space, as the controller interpolates
//! it; on a non-TCP machine with rotary motion the tip therefore follows a curve in the
//! workpiece frame (see [`Program::pose_at`](crate::Program::pose_at)).
//!
//! # Machine files
//! A TOML file describes a machine (all keys but `joint` optional):
//!
//! ```toml
//! name = "my-trunnion"          # default: the file stem
//! tcp = false                   # X Y Z are machine coordinates of the controlled point
//!
//! [[table]]                     # rotary tables, outermost (on the bed) first
//! joint = "A"                   # program word driving it: "A", "B" or "C"
//! direction = [1.0, 0.0, 0.0]   # axis at zero pose; default +X / +Y / +Z for A / B / C
//! center = [0.0, 0.0, -50.0]    # a point on the axis, machine coordinates, mm; default origin
//! reverse = false               # true when the joint counts the other way
//!
//! [[table]]
//! joint = "C"
//!
//! [[head]]                      # swivel-head joints, outermost (on the ram) first
//! joint = "B"
//! center = [0.0, 0.0, 150.0]    # relative to the tool tip at zero pose (pivot length 150 mm)
//! ```
//!
//! # Built-in machines
//! [`Machine::from_name`] knows [`BUILTIN_NAMES`]; a `-tcp` suffix (e.g. `table-ac-tcp`) turns
//! TCP on. Table centres are at the machine origin; head pivots are 100 mm above the tip
//! ([`BUILTIN_PIVOT_LENGTH`]).
//!
//! ```
//! use swarf_path::kinematics::Machine;
//! use swarf_path::Axes;
//! let m = Machine::from_name("4axis-a").unwrap();
//! let p = m.pose(&Axes { a: 90.0, ..Axes::default() });
//! assert!((p.axis.y - 1.0).abs() < 1e-12);
//! ```

use std::path::Path;

use serde::{Deserialize, Serialize};
use swarf_geom::math::{Mat3, Vec3};

use crate::canon::Axes;

/// Tool tip and tool axis in the workpiece frame. The axis is a unit vector pointing from the
/// tip up the tool, towards the spindle (+Z on a 3-axis machine).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Pose {
    /// Tool tip (the cutter's lowest point on its axis, the APT reference point), mm.
    pub tip: Vec3,
    /// Unit tool axis, tip towards spindle.
    pub axis: Vec3,
}

/// The names [`Machine::from_name`] accepts (each also with a `-tcp` suffix).
pub const BUILTIN_NAMES: &[&str] = &[
    "3axis",
    "4axis-a",
    "4axis-b",
    "table-ac",
    "table-bc",
    "head-ac",
    "head-bc",
    "head-table-ac",
    "head-table-bc",
];

/// Distance from the head pivots to the tool tip on the built-in head machines, mm.
pub const BUILTIN_PIVOT_LENGTH: f64 = 100.0;

/// Tolerance on unit vectors when deciding whether an axis is reachable, and below which a
/// rotation is taken as undetermined (gimbal singularity), dimensionless.
pub const AXIS_TOLERANCE: f64 = 1e-9;

/// Which program word drives a rotary joint.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum RotaryWord {
    /// A (default direction +X).
    A,
    /// B (default direction +Y).
    B,
    /// C (default direction +Z).
    C,
}

impl RotaryWord {
    /// The default rotation direction: +X for A, +Y for B, +Z for C.
    pub fn default_direction(self) -> Vec3 {
        match self {
            RotaryWord::A => Vec3::X,
            RotaryWord::B => Vec3::Y,
            RotaryWord::C => Vec3::Z,
        }
    }
    fn value(self, j: &Axes) -> f64 {
        match self {
            RotaryWord::A => j.a,
            RotaryWord::B => j.b,
            RotaryWord::C => j.c,
        }
    }
    fn set(self, j: &mut Axes, v: f64) {
        match self {
            RotaryWord::A => j.a = v,
            RotaryWord::B => j.b = v,
            RotaryWord::C => j.c = v,
        }
    }
}

/// One rotary joint of a machine, described at the zero pose.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct RotaryJoint {
    /// The program word that drives it.
    pub word: RotaryWord,
    /// Unit rotation direction; a positive value turns the joint's body by the right-hand rule.
    pub direction: Vec3,
    /// A point on the rotation axis: machine coordinates for table joints, relative to the tool
    /// tip at zero pose for head joints. mm.
    pub center: Vec3,
    /// The joint counts the other way (its value is negated).
    pub reverse: bool,
}

impl RotaryJoint {
    /// A joint turning about the word's default direction through `center`.
    pub fn new(word: RotaryWord, center: Vec3) -> Self {
        Self {
            word,
            direction: word.default_direction(),
            center,
            reverse: false,
        }
    }
    /// Signed rotation angle in radians for the given joint values.
    fn angle(&self, j: &Axes) -> f64 {
        let v = self.word.value(j).to_radians();
        if self.reverse {
            -v
        } else {
            v
        }
    }
    /// The joint's rigid motion as (rotation, translation): p ↦ R p + t.
    fn motion(&self, j: &Axes) -> (Mat3, Vec3) {
        let r = Mat3::from_axis_angle(self.direction, self.angle(j));
        (r, self.center - r * self.center)
    }
}

/// A machine's kinematic description. See the [module documentation](self).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Machine {
    /// Name (built-in name or the file's `name`).
    pub name: String,
    /// X Y Z are the tool tip in the workpiece frame (TCP/RTCP active).
    pub tcp: bool,
    /// Table joints, outermost (on the bed) first.
    pub table: Vec<RotaryJoint>,
    /// Head joints, outermost (on the ram) first.
    pub head: Vec<RotaryJoint>,
}

impl Default for Machine {
    fn default() -> Self {
        Self::three_axis()
    }
}

/// A machine description that could not be used.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum MachineError {
    /// No built-in machine has that name.
    #[error("not a built-in machine (built-in machines: {list})", list = BUILTIN_NAMES.join(", "))]
    UnknownName(String),
    /// The file could not be read. (The messages of the file's errors leave the file to the
    /// caller, which names it once.)
    #[error("{message}")]
    Io {
        /// File name.
        file: String,
        /// The system's message.
        message: String,
    },
    /// The file is not valid TOML or does not match the schema.
    #[error("{message}")]
    Parse {
        /// File name.
        file: String,
        /// The parser's message (with line and column).
        message: String,
    },
    /// The description is well-formed but not a machine swarf can model.
    #[error("{0}")]
    Invalid(String),
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct MachineFile {
    name: Option<String>,
    #[serde(default)]
    tcp: bool,
    #[serde(default)]
    table: Vec<JointFile>,
    #[serde(default)]
    head: Vec<JointFile>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct JointFile {
    joint: RotaryWord,
    direction: Option<[f64; 3]>,
    center: Option<[f64; 3]>,
    #[serde(default)]
    reverse: bool,
}

impl JointFile {
    fn into_joint(self) -> RotaryJoint {
        RotaryJoint {
            word: self.joint,
            direction: self
                .direction
                .map_or(self.joint.default_direction(), Vec3::from_array),
            center: self.center.map_or(Vec3::ZERO, Vec3::from_array),
            reverse: self.reverse,
        }
    }
}

impl Machine {
    /// A 3-axis machine: the tool axis is always +Z, the tip is X Y Z.
    pub fn three_axis() -> Self {
        Self {
            name: "3axis".into(),
            tcp: false,
            table: Vec::new(),
            head: Vec::new(),
        }
    }

    /// Builds and validates a machine from its joints.
    ///
    /// # Errors
    /// [`MachineError::Invalid`] for more than two rotary joints, a word used twice, a zero or
    /// non-finite direction, or two parallel rotation directions.
    pub fn new(
        name: impl Into<String>,
        tcp: bool,
        table: Vec<RotaryJoint>,
        head: Vec<RotaryJoint>,
    ) -> Result<Self, MachineError> {
        let mut m = Self {
            name: name.into(),
            tcp,
            table,
            head,
        };
        let n = m.table.len() + m.head.len();
        if n > 2 {
            return Err(MachineError::Invalid(format!(
                "machine `{}` has {n} rotary joints; swarf models at most two",
                m.name
            )));
        }
        for j in m.table.iter_mut().chain(m.head.iter_mut()) {
            let len = j.direction.length();
            let usable = len.is_finite() && len > 1e-12 && j.center.is_finite();
            if !usable {
                return Err(MachineError::Invalid(format!(
                    "machine `{}`: joint {:?} needs a finite, non-zero direction and a finite centre",
                    m.name, j.word
                )));
            }
            j.direction /= len;
        }
        let joints: Vec<&RotaryJoint> = m.table.iter().chain(m.head.iter()).collect();
        if joints.len() == 2 {
            if joints[0].word == joints[1].word {
                return Err(MachineError::Invalid(format!(
                    "machine `{}`: joint {:?} appears twice",
                    m.name, joints[0].word
                )));
            }
            if joints[0].direction.cross(joints[1].direction).length() < 1e-6 {
                return Err(MachineError::Invalid(format!(
                    "machine `{}`: the two rotary joints are parallel",
                    m.name
                )));
            }
        }
        Ok(m)
    }

    /// A built-in machine (see [`BUILTIN_NAMES`]; append `-tcp` for TCP).
    ///
    /// # Errors
    /// [`MachineError::UnknownName`] when the name is not built in.
    pub fn from_name(name: &str) -> Result<Self, MachineError> {
        let (base, tcp) = match name.strip_suffix("-tcp") {
            Some(b) => (b, true),
            None => (name, false),
        };
        use RotaryWord::{A, B, C};
        let t = |w| RotaryJoint::new(w, Vec3::ZERO);
        let h = |w| RotaryJoint::new(w, Vec3::new(0.0, 0.0, BUILTIN_PIVOT_LENGTH));
        let (table, head) = match base {
            "3axis" => (vec![], vec![]),
            "4axis-a" => (vec![t(A)], vec![]),
            "4axis-b" => (vec![t(B)], vec![]),
            "table-ac" => (vec![t(A), t(C)], vec![]),
            "table-bc" => (vec![t(B), t(C)], vec![]),
            "head-ac" => (vec![], vec![h(C), h(A)]),
            "head-bc" => (vec![], vec![h(C), h(B)]),
            "head-table-ac" => (vec![t(C)], vec![h(A)]),
            "head-table-bc" => (vec![t(C)], vec![h(B)]),
            _ => return Err(MachineError::UnknownName(name.to_string())),
        };
        Self::new(name, tcp, table, head)
    }

    /// Reads a machine description (TOML, schema in the [module documentation](self)).
    ///
    /// # Errors
    /// I/O, TOML or schema errors, and the checks of [`Machine::new`].
    pub fn from_file(path: &Path) -> Result<Self, MachineError> {
        let file = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| MachineError::Io {
            file: file.clone(),
            message: e.to_string(),
        })?;
        let stem = path
            .file_stem()
            .map_or_else(|| file.clone(), |s| s.to_string_lossy().into());
        Self::from_toml(&text, &file, &stem)
    }

    /// Reads a machine description from TOML text; `file` is kept in the errors (their `file`
    /// field: their messages leave naming it to the caller, which names it once),
    /// `default_name` is used when the text has no `name`.
    ///
    /// # Errors
    /// As [`Machine::from_file`].
    pub fn from_toml(text: &str, file: &str, default_name: &str) -> Result<Self, MachineError> {
        let f: MachineFile = toml::from_str(text).map_err(|e| MachineError::Parse {
            file: file.to_string(),
            message: e.to_string(),
        })?;
        Self::new(
            f.name.unwrap_or_else(|| default_name.to_string()),
            f.tcp,
            f.table.into_iter().map(JointFile::into_joint).collect(),
            f.head.into_iter().map(JointFile::into_joint).collect(),
        )
    }

    /// This machine with TCP switched on or off.
    pub fn with_tcp(mut self, tcp: bool) -> Self {
        self.tcp = tcp;
        self
    }

    /// True when the machine has any rotary joint.
    pub fn has_rotary(&self) -> bool {
        !(self.table.is_empty() && self.head.is_empty())
    }

    /// Composition of a chain listed outermost first: p_outer_frame = R p + t.
    fn chain(joints: &[RotaryJoint], j: &Axes) -> (Mat3, Vec3) {
        joints
            .iter()
            .rev()
            .fold((Mat3::IDENTITY, Vec3::ZERO), |(r, t), joint| {
                let (ro, to) = joint.motion(j);
                (ro * r, ro * t + to)
            })
    }

    /// The table's motion: a point fixed to the part at `p` (workpiece frame) is at `R p + t` in
    /// the machine frame.
    pub fn table_motion(&self, j: &Axes) -> (Mat3, Vec3) {
        Self::chain(&self.table, j)
    }

    /// The head's motion relative to the controlled point: the tip is at `X Y Z + t` (machine
    /// frame) and the tool axis is `R·Z`.
    pub fn head_motion(&self, j: &Axes) -> (Mat3, Vec3) {
        Self::chain(&self.head, j)
    }

    /// Tool tip and axis in the workpiece frame for joint values `j` (program + offsets).
    pub fn pose(&self, j: &Axes) -> Pose {
        self.pose_with(j, self.tcp)
    }

    /// [`Machine::pose`] with tool centre point control on or off (`tcp`) whatever the
    /// machine's own setting: a program may turn it on and off ([`crate::Canon::ToolCentrePoint`];
    /// each move says which, [`crate::Move::tcp`]).
    pub fn pose_with(&self, j: &Axes, tcp: bool) -> Pose {
        let xyz = Vec3::new(j.x, j.y, j.z);
        if !self.has_rotary() {
            return Pose {
                tip: xyz,
                axis: Vec3::Z,
            };
        }
        let (tr, tt) = self.table_motion(j);
        let (hr, ht) = self.head_motion(j);
        let tr_inv = tr.transpose();
        let axis = (tr_inv * (hr * Vec3::Z)).normalize();
        let tip = if tcp { xyz } else { tr_inv * (xyz + ht - tt) };
        Pose { tip, axis }
    }

    /// The X Y Z joint values that put the tip at `tip` (workpiece frame) with the rotary joints
    /// of `rotary` (whose A B C are kept). Exact and cheap: the inverse of [`Machine::pose`]'s
    /// position part.
    pub fn joints_for_tip(&self, tip: Vec3, rotary: &Axes) -> Axes {
        let xyz = if self.tcp || !self.has_rotary() {
            tip
        } else {
            let (tr, tt) = self.table_motion(rotary);
            let (_, ht) = self.head_motion(rotary);
            tr * tip + tt - ht
        };
        Axes {
            x: xyz.x,
            y: xyz.y,
            z: xyz.z,
            ..*rotary
        }
    }

    /// Maps a point given in the machine's joint X Y Z space at fixed rotary joints `rotary` to
    /// the workpiece frame — the rigid map that [`Machine::pose`] applies to the controlled
    /// point. Vectors map with the returned rotation.
    pub fn joint_space_to_workpiece(&self, rotary: &Axes) -> (Mat3, Vec3) {
        self.joint_space_to_workpiece_with(rotary, self.tcp)
    }

    /// [`Machine::joint_space_to_workpiece`] with tool centre point control on or off (`tcp`).
    pub fn joint_space_to_workpiece_with(&self, rotary: &Axes, tcp: bool) -> (Mat3, Vec3) {
        if tcp || !self.has_rotary() {
            return (Mat3::IDENTITY, Vec3::ZERO);
        }
        let (tr, tt) = self.table_motion(rotary);
        let (_, ht) = self.head_motion(rotary);
        let tr_inv = tr.transpose();
        (tr_inv, tr_inv * (ht - tt))
    }

    /// Joint values giving `pose`, choosing among the solutions (two per axis on a 5-axis
    /// machine, plus turns of 360°) the one whose rotary values are nearest to `near`'s. At a
    /// singularity (the axis along a rotary direction) the undetermined joint keeps `near`'s
    /// value. `None` when the machine cannot reach the axis (within [`AXIS_TOLERANCE`]).
    pub fn inverse(&self, pose: &Pose, near: &Axes) -> Option<Axes> {
        let w = pose.axis.try_normalize()?;
        // axis_w = T⁻¹·H·Z, a product of the joints' rotations in this order (rightmost first):
        // inner table joint (negated) … outer table joint (negated), outer head … inner head.
        let mut seq: Vec<(RotaryJoint, f64)> = Vec::with_capacity(2);
        for j in self.table.iter().rev() {
            seq.push((*j, -1.0));
        }
        for j in &self.head {
            seq.push((*j, 1.0));
        }
        // Effective sign σ: the rotation about `direction` is σ·(joint value).
        let sigma = |(j, s): &(RotaryJoint, f64)| if j.reverse { -s } else { *s };
        let mut rot = *near;
        match seq.len() {
            0 => {
                if (w - Vec3::Z).length() > AXIS_TOLERANCE.sqrt() {
                    return None;
                }
            }
            1 => {
                let u = seq[0].0.direction;
                if (u.dot(Vec3::Z) - u.dot(w)).abs() > AXIS_TOLERANCE.sqrt() {
                    return None;
                }
                let near_phi = sigma(&seq[0]) * seq[0].0.word.value(near).to_radians();
                let phi = rotation_angle(u, Vec3::Z, w).unwrap_or(near_phi);
                seq[0]
                    .0
                    .word
                    .set(&mut rot, unwrap_near(phi / sigma(&seq[0]), near, seq[0].0));
            }
            2 => {
                // R(u1, φ1)·R(u2, φ2)·Z = w (Paden–Kahan subproblem 2).
                let (j1, j2) = (seq[0].0, seq[1].0);
                let (s1, s2) = (sigma(&seq[0]), sigma(&seq[1]));
                let (u1, u2) = (j1.direction, j2.direction);
                let v = Vec3::Z;
                let c = u1.dot(u2);
                let den = c * c - 1.0;
                let alpha = (c * u2.dot(v) - u1.dot(w)) / den;
                let beta = (c * u1.dot(w) - u2.dot(v)) / den;
                let cross = u1.cross(u2);
                let g2 = (1.0 - alpha * alpha - beta * beta - 2.0 * alpha * beta * c)
                    / cross.length_squared();
                if g2 < -AXIS_TOLERANCE.sqrt() {
                    return None;
                }
                let g = g2.max(0.0).sqrt();
                let near1 = s1 * j1.word.value(near).to_radians();
                let near2 = s2 * j2.word.value(near).to_radians();
                let mut best: Option<(f64, f64, f64)> = None;
                for sign in [1.0, -1.0] {
                    let z = alpha * u1 + beta * u2 + sign * g * cross;
                    let phi2 = rotation_angle(u2, v, z).unwrap_or(near2);
                    let phi1 = rotation_angle(u1, z, w).unwrap_or(near1);
                    let t1 = unwrap_near(phi1 / s1, near, j1);
                    let t2 = unwrap_near(phi2 / s2, near, j2);
                    let d = (t1 - j1.word.value(near)).abs() + (t2 - j2.word.value(near)).abs();
                    if best.map_or(true, |b| d < b.0) {
                        best = Some((d, t1, t2));
                    }
                }
                let (_, t1, t2) = best?;
                j1.word.set(&mut rot, t1);
                j2.word.set(&mut rot, t2);
            }
            _ => return None,
        }
        let out = self.joints_for_tip(pose.tip, &rot);
        out.to_array().iter().all(|v| v.is_finite()).then_some(out)
    }
}

/// The angle (radians) of the rotation about unit `u` taking `p` to `q` (Paden–Kahan
/// subproblem 1), or `None` when either lies along `u` and any angle would do.
fn rotation_angle(u: Vec3, p: Vec3, q: Vec3) -> Option<f64> {
    let pp = p - u * u.dot(p);
    let qp = q - u * u.dot(q);
    if pp.length() < AXIS_TOLERANCE.sqrt() || qp.length() < AXIS_TOLERANCE.sqrt() {
        return None;
    }
    Some(u.dot(pp.cross(qp)).atan2(pp.dot(qp)))
}

/// `angle_rad` in degrees, shifted by whole turns to lie nearest the joint's value in `near`.
fn unwrap_near(angle_rad: f64, near: &Axes, joint: RotaryJoint) -> f64 {
    let deg = angle_rad.to_degrees();
    let n = joint.word.value(near);
    deg + 360.0 * ((n - deg) / 360.0).round()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: Vec3, b: Vec3) -> bool {
        (a - b).length() < 1e-12
    }

    #[test]
    fn head_a_tilts_axis_towards_minus_y() {
        let m = Machine::from_name("head-ac-tcp").unwrap();
        let p = m.pose(&Axes {
            a: 90.0,
            ..Axes::default()
        });
        assert!(close(p.axis, -Vec3::Y), "{:?}", p.axis);
    }

    #[test]
    fn rotation_angle_quarter_turn() {
        let a = rotation_angle(Vec3::Z, Vec3::X, Vec3::Y).unwrap();
        assert!((a - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
        assert!(rotation_angle(Vec3::Z, Vec3::Z, Vec3::Z).is_none());
    }
}
