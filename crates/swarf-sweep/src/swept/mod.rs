//! Exact intersection of a line with the volume swept by a convex solid of revolution moving
//! along a straight segment with a fixed axis.
//!
//! # The geometry (re-derived; Aras 2008 §4.2.3 is the starting point)
//! Let `K` be a **convex** solid of revolution about the tool axis (the APT cutting part is
//! one: its profile radius `r(z)` is concave on `[0, h]` for valid parameters, which
//! [`ConvexProfile::from_pieces`] verifies). Moving `K` by `s·v`, `s ∈ [0, 1]`, with a fixed
//! axis sweeps the Minkowski sum `S = K ⊕ [0, v]`, which is convex. For a line `o + t·d` the set
//! `C = {(t, s) : s ∈ [0, 1], o + t·d − s·v ∈ K}` is convex, so `S` meets the line in **one**
//! interval `[t_min, t_max]`, the projection of `C` on `t`.
//!
//! Where is `t_min` attained? Either at `s = 0` or `s = 1` (the line against `K` at the start
//! or end pose: the *caps*), or at an interior `s` where, by the KKT conditions, some normal
//! `n` of `K` at the touching point satisfies `n·v = 0`: the point lies on the **grazing
//! curve** of `K` for direction `v`, which for a fixed axis is fixed on the tool, and the line
//! meets the grazing curve extruded along `v` (the *envelope*). Every candidate we compute is
//! a point `g + s·v` with `g ∈ K` and `s ∈ [0, 1]`, i.e. a point of `S`, and every extreme
//! point is among the candidates; so `[min, max]` of the candidates **is** the interval, and
//! over-including candidates (e.g. all joint circles, grazing or not) is harmless.
//!
//! The grazing curves, in a move frame whose x axis is the horizontal part of `v`
//! (`v = (a, 0, b)`; `a = 0` for plunges along the axis, where any x axis does, unlike the
//! frame of Aras eq. 4.20 which is undefined there):
//! * sphere (ball corner): the great circle `⊥ v`; its extrusion is the cylinder of radius
//!   `r` about the centre's path (a capsule side) — `sphere.rs`;
//! * cone and cylinder sides: the generator lines at `cos θ = −n_z·b / (n_ρ·a)`, whose
//!   extrusions are parallelograms — `line.rs`;
//! * profile joints (sharp or smooth circles, the flat bottom's edge, the top cap's edge): the
//!   circle extruded along `v`, an elliptic cylinder — `circle.rs`;
//! * torus (bull-nose corner): the spine circle offset by `±r·m(θ)`, `m = unit(c′ × v)`, a
//!   degree-8 polynomial in `tan(θ/2)` solved by guaranteed root isolation
//!   (`swarf_geom::poly`), with the horizontal move (where `m` is undefined on two meridians)
//!   in closed form — `torus.rs`. A bull-nose corner (a quarter torus between the flat bottom
//!   and a vertical side) needs none of that: the lozenge it bounds lies in the tool, and the
//!   ends of a line's chord through the lozenge swept along `v` replace its caps and envelope
//!   (the zeros of a convex distance) — `lozenge.rs`.
//!
//! Before any candidate, the stock update tries to prove that a ray's material misses the
//! sweep by a separating plane from the convex sweep's support function — `separation.rs`.
//!
//! Flat faces (discs) parallel to `v` are grazing as a whole, but their extrusion's boundary
//! is made of the joint circles' extrusions and the caps, so they need no candidates of their
//! own.
//!
//! # Closed forms for the common case
//! A ball end (a whole sphere on a cylinder slab that reaches its top) or a slab (flat end,
//! shank) whose axis is a world axis, against rays along world axes, needs none of that: its
//! sweep is a capsule (`capsule.rs`: one quadratic, or one end sphere chosen before any square
//! root) united with a swept slab (`slab.rs`: the positions whose disc holds a ray along the
//! axis; the stadium cross-section for a ray across it). `fast.rs` classifies the profile once,
//! the move once, and shares the per-family constants among the rays
//! ([`SweptConvex::has_closed_form`], [`SweptConvex::axis_ray_interval`]). A slab, ball or
//! bull-nose whose fixed axis is no world axis has one too (`tilted.rs`: the line parameter and
//! the move's, constrained by an ellipse and two strips, reach their extremes at one of fourteen
//! candidate points; a bull-nose's corner keeps its lozenge's Newton steps), and so does an
//! instance at any axis (`instance.rs`).

pub(crate) mod bound;
pub(crate) mod capsule;
pub(crate) mod circle;
pub(crate) mod convex;
pub(crate) mod distance;
pub(crate) mod fast;
pub(crate) mod front;
pub(crate) mod instance;
pub(crate) mod interval;
pub(crate) mod kernel;
pub(crate) mod line;
pub(crate) mod lozenge;
pub(crate) mod planar;
pub(crate) mod profile;
pub(crate) mod separation;
pub(crate) mod slab;
pub(crate) mod sphere;
pub(crate) mod tilted;
pub(crate) mod torus;

pub use bound::SweepBound;
pub use distance::SignedDistance;
pub use front::{Front, FrontBlock};
pub use instance::{InstanceSet, SLIVER_MM};
pub use interval::{overlaps, Interval};
pub use kernel::{DexelKernel, KernelTask};
pub use planar::{KeyBound, PlanarMember, Progress};
pub use profile::{ConvexProfile, Element, SweepShape};

use smallvec::SmallVec;
use swarf_geom::math::Vec3;
use swarf_geom::{Aabb, Frame};

/// Below this relative size a component of the move direction is taken as exactly zero
/// (`|v_h| ≤ AXIS_SNAP·|v|` is a plunge along the axis, `|v_z| ≤ AXIS_SNAP·|v|` a horizontal
/// move). The geometric effect is below `AXIS_SNAP·|v|·tool size`, far under any resolution.
pub const AXIS_SNAP: f64 = 1e-10;

/// Tolerance (mm) with which a candidate point is accepted on a piece's band or a parameter
/// in `[0, 1]`: a candidate accepted this far outside lies within this distance of `S`.
pub const BAND_EPS: f64 = 1e-9;

/// Running minimum and maximum of candidate line parameters.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Acc {
    pub(crate) lo: f64,
    pub(crate) hi: f64,
}

impl Acc {
    pub(crate) const EMPTY: Acc = Acc {
        lo: f64::INFINITY,
        hi: f64::NEG_INFINITY,
    };
    #[inline]
    pub(crate) fn add(&mut self, t: f64) {
        if t < self.lo {
            self.lo = t;
        }
        if t > self.hi {
            self.hi = t;
        }
    }
    pub(crate) fn get(&self) -> Option<(f64, f64)> {
        (self.lo <= self.hi).then_some((self.lo, self.hi))
    }
}

/// Two crossings of a line with a tool instance this far apart (mm) are its entry and exit
/// (closer ones may be one crossing found on two elements meeting there).
const INSTANCE_CROSSINGS_APART: f64 = 1e-6;

/// Real roots of `a·t² + b·t + c` (cancellation-free; linear when `a = 0`), inlined here for
/// the per-ray loop (same convention as `swarf_geom::poly::quadratic_roots`).
#[inline(always)]
pub(crate) fn quad(a: f64, b: f64, c: f64) -> ([f64; 2], usize) {
    if a == 0.0 {
        if b != 0.0 {
            return ([-c / b, 0.0], 1);
        }
        return ([0.0; 2], 0);
    }
    let disc = b * b - 4.0 * a * c;
    if disc.is_nan() || disc < 0.0 {
        return ([0.0; 2], 0);
    }
    if disc == 0.0 {
        return ([-b / (2.0 * a), 0.0], 1);
    }
    let q = -0.5 * (b + b.signum() * disc.sqrt());
    ([q / a, c / q], 2)
}

/// Per-thread scratch space (root lists) so the per-ray loop never allocates, and the planes
/// that last separated a family's rays from a sweep (`separation.rs`).
#[derive(Debug, Default)]
pub struct Scratch {
    pub(crate) roots: Vec<f64>,
    pub(crate) planes: separation::Planes,
}

impl Scratch {
    /// Empty scratch with room for the largest root list.
    pub fn new() -> Self {
        Self {
            roots: Vec::with_capacity(32),
            planes: separation::Planes::default(),
        }
    }
}

/// A piece of work for one line: an element (its two caps and its envelope) or a joint
/// circle's extrusion, with the bounding box of what it can contribute.
#[derive(Clone, Copy, Debug)]
struct Unit {
    /// Element index, or joint index when `joint`.
    index: usize,
    joint: bool,
    /// Workpiece-frame box holding every candidate point of the unit.
    bbox: Aabb,
}

/// A convex profile moving with a fixed axis along a segment, prepared for line queries.
#[derive(Clone, Debug)]
pub struct SweptConvex<'a> {
    prof: &'a ConvexProfile,
    frame: Frame,
    /// Move in the move frame: `(a, 0, b)`.
    v: Vec3,
    bbox: Aabb,
    units: SmallVec<[Unit; 10]>,
    /// When the tool axis is a world axis `k` (+1 along it): the tip's cross coordinates at the
    /// start and end, and its lowest coordinate along `k` over the move.
    axial: Option<Axial>,
    /// The closed-form kernel for dexels, when the profile and the move qualify.
    closed: Option<ClosedForm>,
    /// Elements (bit `i`: element `i`) whose envelope is left out
    /// ([`SweptConvex::with_envelope_slack`]).
    skip_envelope: u64,
    /// Bull-nose corners (bit `i`: element `i`) swept as a lozenge (`lozenge.rs`) instead of by
    /// their caps and the torus envelope.
    lozenges: u64,
}

/// Which closed form answers a sweep's dexel queries (chosen once, in [`SweptConvex::new`]).
#[derive(Clone, Copy, Debug)]
enum ClosedForm {
    /// A slab, ball or bull-nose profile on a move whose tool axis is a world axis
    /// (`fast.rs`).
    Axial(fast::FastSweep),
    /// A slab, ball or bull-nose instance (no motion) at any other axis (`instance.rs`).
    Instance(instance::InstanceShape),
    /// A slab, ball or bull-nose moving with its axis fixed off the world axes (`tilted.rs`).
    Tilted(tilted::TiltedSweep),
}

/// The move seen along a tool axis that is the world axis `k`.
#[derive(Clone, Copy, Debug)]
struct Axial {
    k: usize,
    c0: (f64, f64),
    c1: (f64, f64),
    low: f64,
    high: f64,
}

/// Box of the band `z ∈ [z0, z1]` of radius ≤ `rho` about `axis` from `tip`, at the start and
/// at the end (`tip + delta`) of a move: it holds the band's sweep (convex hull of the two).
fn band_box(tip: Vec3, axis: Vec3, delta: Vec3, z0: f64, z1: f64, rho: f64) -> Aabb {
    // A disc of radius rho ⊥ axis reaches rho·√(1 − a_k²) along k; written as the other two
    // components (1 − a_k² cancels for an axis within 1e-7 of k: 1e-8 mm short on 10 mm).
    let (x2, y2, z2) = (axis.x * axis.x, axis.y * axis.y, axis.z * axis.z);
    let ext = Vec3::new(
        rho * (y2 + z2).sqrt(),
        rho * (x2 + z2).sqrt(),
        rho * (x2 + y2).sqrt(),
    );
    let c0 = tip + axis * z0;
    let mut bbox = Aabb::new(c0, c0);
    for c in [c0, tip + axis * z1, c0 + delta, tip + delta + axis * z1] {
        bbox = bbox.extended(c - ext).extended(c + ext);
    }
    bbox.inflated(1e-9)
}

/// Line queries sharing one direction against one sweep (see [`SweptConvex::lines`]).
#[derive(Debug)]
pub struct LineBatch<'s, 'a> {
    sweep: &'s SweptConvex<'a>,
    dc: DirConsts,
    scratch: Scratch,
}

impl LineBatch<'_, '_> {
    /// The interval of the line through `origin` inside the sweep (as
    /// [`SweptConvex::ray_interval`]).
    pub fn interval(&mut self, origin: Vec3) -> Option<(f64, f64)> {
        self.sweep
            .line_interval(origin, &self.dc, None, &mut self.scratch)
    }
}

/// Quantities of one line direction against one move, shared by all parallel lines.
#[derive(Clone, Debug)]
pub(crate) struct DirConsts {
    /// Direction in the move frame (unit).
    pub(crate) d: Vec3,
    /// The move in the move frame, `(a, 0, b)`.
    pub(crate) v: Vec3,
    /// `d × v`.
    pub(crate) w: Vec3,
    /// `d·v`.
    pub(crate) dv: f64,
    /// `v·v`.
    pub(crate) vv: f64,
    /// `|d × v|²`; the envelope is skipped when the line is parallel to the move.
    pub(crate) det: f64,
    /// False when the line is parallel to the move or the move has zero length.
    pub(crate) envelope: bool,
    /// The pre-test's projection: basis of the plane ⊥ d, projected axis-segment start,
    /// axis segment and move, the parallelogram's determinant and scale.
    near: Near,
    /// Order in which units are evaluated for axis-aligned rays: the unit reaching lowest
    /// along the ray, the one reaching highest, then the rest (so the skip test of the
    /// others usually succeeds).
    order: [u8; MAX_UNITS],
}

/// The per-direction state of dexel queries against one sweep (see
/// [`SweptConvex::dexel_rays`]); opaque, made once per sweep and ray family.
#[derive(Clone, Debug)]
pub struct DexelRays(RaysKind);

impl DexelRays {
    /// The instance closed form, when these rays have it.
    pub(crate) fn instance(&self) -> Option<&instance::InstanceRays> {
        match &self.0 {
            RaysKind::Instance(i) => Some(i),
            _ => None,
        }
    }
}

/// Which kernel answers a family's rays.
#[derive(Clone, Debug)]
// The closed-form variant is the hot one; it stays inline (a few per move and family, kept
// for one batch of moves).
#[allow(clippy::large_enum_variant)]
enum RaysKind {
    /// Closed-form kernels.
    Fast(fast::FastRays),
    /// Closed-form kernels of an instance.
    Instance(instance::InstanceRays),
    /// The closed form of a slab, ball or bull-nose at a tilted axis.
    Tilted(tilted::TiltedRays),
    /// The general candidates, and a number no other `DexelRays` of the process has (the
    /// separating planes found for its rays are kept under it).
    General(Box<DirConsts>, u64),
}

/// Most units (elements + joints) a profile may have for the batched query.
const MAX_UNITS: usize = 16;

/// Precomputed projection for [`SweptConvex::near`].
#[derive(Clone, Copy, Debug)]
struct Near {
    e1: Vec3,
    e2: Vec3,
    a: (f64, f64),
    ax: (f64, f64),
    vv: (f64, f64),
    det: f64,
    scale: f64,
    rr: f64,
}

impl DirConsts {
    /// Solves `o + t·d = g + s·v` (coplanar by construction) for `(t, s)` by least squares.
    #[inline]
    pub(crate) fn solve_ts(&self, o: Vec3, g: Vec3) -> (f64, f64) {
        let r0 = g - o;
        let dr = self.d.dot(r0);
        let vr = self.v.dot(r0);
        let t = (dr * self.vv - self.dv * vr) / self.det;
        let s = (self.dv * dr - vr) / self.det;
        (t, s)
    }
}

impl<'a> SweptConvex<'a> {
    /// `prof` (tool frame: tip at the origin, axis +Z) placed with its tip at `tip` and axis
    /// `axis` (unit), moving by `delta` (workpiece frame) with the axis fixed.
    pub fn new(prof: &'a ConvexProfile, tip: Vec3, axis: Vec3, delta: Vec3) -> Self {
        let axis = axis.normalize();
        let len = delta.length();
        let mut b = delta.dot(axis);
        let horiz = delta - axis * b;
        let mut a = horiz.length();
        let frame = if a > AXIS_SNAP * len {
            Frame::from_axis_and_x(tip, axis, horiz)
        } else {
            a = 0.0;
            Frame::from_axis(tip, axis)
        };
        if b.abs() <= AXIS_SNAP * len {
            b = 0.0;
        }
        let v = Vec3::new(a, 0.0, b);
        let delta = frame.vector_to_world(v);
        let bbox = band_box(tip, axis, delta, prof.z_min(), prof.z_max(), prof.r_max());
        let mut units = SmallVec::new();
        for i in 0..prof.elements().len() {
            let (z0, z1, rho) = prof.element_extent(i);
            units.push(Unit {
                index: i,
                joint: false,
                bbox: band_box(tip, axis, delta, z0, z1, rho),
            });
        }
        for (j, c) in prof.joints().iter().enumerate() {
            units.push(Unit {
                index: j,
                joint: true,
                bbox: band_box(tip, axis, delta, c.y, c.y, c.x),
            });
        }
        let axial = (0..3).find(|&k| axis[k] == 1.0).map(|k| {
            let (u, w) = ((k + 1) % 3, (k + 2) % 3);
            let end = tip + delta;
            Axial {
                k,
                c0: (tip[u], tip[w]),
                c1: (end[u], end[w]),
                low: tip[k].min(end[k]),
                high: tip[k].max(end[k]),
            }
        });
        let closed = match (axial, prof.fast()) {
            (Some(ax), _) => fast::FastSweep::new(prof, ax.k, tip, delta).map(ClosedForm::Axial),
            (None, Some(shape)) if v == Vec3::ZERO => Some(ClosedForm::Instance(
                instance::InstanceShape::new(shape, frame),
            )),
            (None, Some(shape)) => Some(ClosedForm::Tilted(tilted::TiltedSweep::new(
                shape, frame, v,
            ))),
            (None, None) => None,
        };
        Self {
            prof,
            frame,
            v,
            bbox,
            units,
            axial,
            closed,
            skip_envelope: 0,
            lozenges: prof.lozenge_corners(),
        }
    }

    /// The same sweep, except that the envelope of each torus band whose neighbours join it
    /// tangentially is left out where that moves the swept solid by at most `slack` mm
    /// (Hausdorff distance), and the largest such distance.
    ///
    /// Why that bound: the envelope of a band is made of the points `g + s·v` with `g` on its
    /// grazing curve (normal `⊥ v`) and `s ∈ [0, 1]`. Such a point lies in the band's tangent
    /// plane at `g`, at `s·|v|` from `g` along it; the surface, whose curvature is at most
    /// `1/r` there (`r` the tube radius: the other principal radius of an outer torus band is
    /// larger), and — the joints being tangent — on its smooth neighbours too, comes within
    /// `(s·|v|)²/(2r)` of it at the start instance, and within `((1 − s)·|v|)²/(2r)` at the end
    /// one: within `|v|²/(8r)` of the caps, which stay. So leaving the envelope out removes
    /// only points of the true sweep that lie within that distance of what is kept: the cut
    /// can only leave that much more material, never take more. The short fixed-axis pieces
    /// of a 5-axis move (a few µm each) are where it pays: their tori's envelopes (a
    /// degree-8 root isolation per ray) move the solid by ~10⁻¹¹ mm.
    pub fn with_envelope_slack(mut self, slack: f64) -> (Self, f64) {
        let vv = self.v.length_squared();
        let mut worst = 0.0f64;
        for i in 0..self.prof.elements().len().min(64) {
            if let Some(r) = self.prof.smooth_torus_radius(i) {
                let moved = vv / (8.0 * r);
                if moved <= slack {
                    self.skip_envelope |= 1 << i;
                    worst = worst.max(moved);
                }
            }
        }
        (self, worst)
    }

    /// Where this move can change a line when its start instance has already been cut (a
    /// chained move): the front of the start instance swept along the move (`front.rs`).
    pub fn front(&self) -> Front {
        Front::of(self)
    }

    /// Bounding box of the swept volume, workpiece frame.
    pub fn bbox(&self) -> Aabb {
        self.bbox
    }

    /// The interval of the line `origin + t·dir` (workpiece frame, `dir` unit) inside the
    /// swept volume, `None` when the line misses it. (The stock update uses a batched form of
    /// this query that shares the per-direction constants among parallel rays and skips work
    /// that cannot change the material.)
    pub fn ray_interval(&self, origin: Vec3, dir: Vec3) -> Option<(f64, f64)> {
        let dir = dir.normalize();
        let dc = self.dir_consts(dir);
        self.line_interval(origin, &dc, None, &mut Scratch::new())
    }

    /// The interval of the ray along world axis `k` through `origin` (`origin[k]` ignored)
    /// inside the swept volume, in world coordinates along `k`: by the closed-form kernels
    /// when [`SweptConvex::has_closed_form`], else as [`SweptConvex::ray_interval`].
    pub fn axis_ray_interval(&self, origin: Vec3, k: usize) -> Option<(f64, f64)> {
        let (cu, cv) = (origin[(k + 1) % 3], origin[(k + 2) % 3]);
        // (Only the general candidates use the scratch; an empty one allocates nothing.)
        self.dexel_interval((cu, cv), k, &self.dexel_rays(k), &mut Scratch::default())
    }

    /// The whole interval of the ray along world axis `k` through `(cu, cv)` on the cross axes
    /// `(k+1) % 3`, `(k+2) % 3` inside the swept volume, world coordinates along `k` (`rays`
    /// from [`SweptConvex::dexel_rays`] for `k`): [`SweptConvex::axis_ray_interval`] with the
    /// family's constants made once, for many rays — the closed forms where the stock's cut
    /// has them, else the general candidates.
    pub fn dexel_interval(
        &self,
        (cu, cv): (f64, f64),
        k: usize,
        rays: &DexelRays,
        scratch: &mut Scratch,
    ) -> Option<(f64, f64)> {
        match &rays.0 {
            RaysKind::Fast(f) => f.interval(cu, cv, None),
            RaysKind::Instance(i) => i.interval(cu, cv),
            RaysKind::Tilted(t) => t.interval(cu, cv),
            RaysKind::General(dc, _) => {
                let mut origin = Vec3::ZERO;
                origin[(k + 1) % 3] = cu;
                origin[(k + 2) % 3] = cv;
                self.line_interval(origin, dc, None, scratch)
            }
        }
    }

    /// True when rays along world axes are answered in closed form: a slab, ball-end or
    /// bull-nose profile at any axis, moving or not (`fast.rs`, `instance.rs`, `tilted.rs`);
    /// other profiles (tapers, chamfers, drills, APT's generic cutter) take the general
    /// candidates.
    pub fn has_closed_form(&self) -> bool {
        self.closed.is_some()
    }

    /// What the dexel queries along world axis `k` share: the closed-form kernels' constants
    /// when available, else the general path's direction constants. (The one place where
    /// the kind of kernel is decided; [`SweptConvex::with_kernel`] dispatches on it.)
    pub fn dexel_rays(&self, k: usize) -> DexelRays {
        DexelRays(match &self.closed {
            Some(ClosedForm::Axial(f)) => RaysKind::Fast(f.rays(k)),
            Some(ClosedForm::Instance(i)) => RaysKind::Instance(i.rays(k)),
            Some(ClosedForm::Tilted(t)) => RaysKind::Tilted(t.rays(k, 0.0)),
            None => RaysKind::General(
                Box::new(self.dir_consts(Vec3::AXES[k])),
                separation::Planes::new_owner(),
            ),
        })
    }

    /// The stock update's query for the dexel `d` along world axis `k` whose coordinates on
    /// the cross axes `(k+1) % 3`, `(k+2) % 3` are `(cu, cv)` (`rays` from
    /// [`SweptConvex::dexel_rays`] for `k`): whether an exact query ran, and the interval to
    /// remove (exact where it meets the material). Closed form when available; otherwise the
    /// material-first range test, a separating plane between the material and the sweep
    /// (`separation.rs`), then the general candidates pruned to the material.
    #[inline]
    pub fn dexel_cut(
        &self,
        (cu, cv): (f64, f64),
        k: usize,
        d: &[Interval],
        rays: &DexelRays,
        scratch: &mut Scratch,
    ) -> (bool, Option<(f64, f64)>) {
        /// One ray's query.
        struct One<'d, 's> {
            at: (f64, f64),
            d: &'d [Interval],
            scratch: &'s mut Scratch,
        }
        impl KernelTask for One<'_, '_> {
            type Output = (bool, Option<(f64, f64)>);
            #[inline(always)]
            fn run<K: DexelKernel>(self, kernel: &K) -> Self::Output {
                kernel.cut(self.at.0, self.at.1, self.d, self.scratch)
            }
        }
        self.with_kernel(
            k,
            rays,
            One {
                at: (cu, cv),
                d,
                scratch,
            },
        )
    }

    /// [`SweptConvex::dexel_cut`] by the general candidates (`dc` the direction's constants,
    /// `owner` the number the separating planes of these rays are kept under).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn general_cut(
        &self,
        (cu, cv): (f64, f64),
        k: usize,
        d: &[Interval],
        dc: &DirConsts,
        owner: u64,
        scratch: &mut Scratch,
    ) -> (bool, Option<(f64, f64)>) {
        let (first, last) = match (d.first(), d.last()) {
            (Some(f), Some(l)) => (f.enter, l.exit),
            _ => return (false, None),
        };
        let mut origin = Vec3::ZERO;
        origin[(k + 1) % 3] = cu;
        origin[(k + 2) % 3] = cv;
        let Some((a, b)) = self.dexel_range(origin, k) else {
            return (false, None);
        };
        if !overlaps(d, a, b) || self.misses_material(origin, k, d, (a, b), owner, scratch) {
            return (false, None);
        }
        let (m_lo, m_hi) = (first.max(a), last.min(b));
        (
            true,
            self.line_interval(origin, dc, Some((k, m_lo, m_hi)), scratch),
        )
    }

    /// Runs `task` over the rays along world axis `k` with their kernel (`rays` from
    /// [`SweptConvex::dexel_rays`] for `k`) chosen once: each of the task's queries answers as
    /// [`SweptConvex::dexel_cut`] does (`kernel.rs`).
    #[inline]
    pub fn with_kernel<T: KernelTask>(&self, k: usize, rays: &DexelRays, task: T) -> T::Output {
        match &rays.0 {
            RaysKind::Fast(fast::FastRays::Along(a)) => task.run(a),
            RaysKind::Fast(fast::FastRays::Across(a)) => task.run(a),
            RaysKind::Instance(i) => task.run(i),
            RaysKind::Tilted(t) => task.run(t),
            RaysKind::General(dc, owner) => task.run(&kernel::General {
                sweep: self,
                k,
                dc,
                owner: *owner,
            }),
        }
    }

    /// A range along the ray through `origin` (with `origin[k] = 0`) parallel to world axis
    /// `k` that holds the ray's whole intersection with the sweep; `None` when the ray misses
    /// the sweep. Cheap bounds for the common 3-axis case (tool axis = a world axis):
    /// * a ray along the tool axis: from the lowest tip height plus the profile's lower height
    ///   at the ray's least distance from the tip's path (exact for moves perpendicular to the
    ///   axis);
    /// * a ray across the tool axis: the chord of the stadium around the tip's path whose
    ///   radius is the largest profile radius at the heights the ray can meet (exact for moves
    ///   perpendicular to the axis).
    ///
    /// For a tool instance (no motion) of a flat, ball or bull-nose profile at any other axis:
    /// the chord of the cylinder holding it (`instance.rs`); for such a profile moving at any
    /// other axis, the exact chord (`tilted.rs`; for a block of rays, the centre ray's chord of
    /// the shape grown by the block's half-diagonal). Otherwise the sweep's bounding box.
    pub fn dexel_range(&self, origin: Vec3, k: usize) -> Option<(f64, f64)> {
        self.block_range(k, origin, 0.0)
    }

    /// [`SweptConvex::dexel_range`] for all the rays along axis `k` whose cross coordinates
    /// are within `half` of those of `centre` (a square block of rays, e.g. a tile).
    pub fn block_range(&self, k: usize, centre: Vec3, half: f64) -> Option<(f64, f64)> {
        let origin = centre;
        let bb = &self.bbox;
        let full = (bb.min[k], bb.max[k]);
        let Some(ax) = self.axial else {
            let (cu, cv) = (origin[(k + 1) % 3], origin[(k + 2) % 3]);
            return match &self.closed {
                Some(ClosedForm::Instance(i)) => i.rays(k).block(cu, cv, half),
                // Every ray of the block is within half·√2 of the centre's: inside the sweep
                // of the shape grown by that, along the centre's ray.
                Some(ClosedForm::Tilted(t)) => t
                    .rays(k, half * std::f64::consts::SQRT_2)
                    .interval(cu, cv)
                    .map(|(lo, hi)| (lo.max(full.0), hi.min(full.1))),
                _ => Some(full),
            };
        };
        let (u, w) = ((ax.k + 1) % 3, (ax.k + 2) % 3);
        if ax.k == k {
            let q = (origin[u] - ax.c0.0, origin[w] - ax.c0.1);
            let e = (ax.c1.0 - ax.c0.0, ax.c1.1 - ax.c0.1);
            let ee = e.0 * e.0 + e.1 * e.1;
            let t = if ee > 0.0 {
                ((q.0 * e.0 + q.1 * e.1) / ee).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let (dx, dy) = (q.0 - t * e.0, q.1 - t * e.1);
            // Every ray of the block is within half·√2 of the centre's distance.
            let rho = ((dx * dx + dy * dy).sqrt() - half * std::f64::consts::SQRT_2).max(0.0);
            let z = self.prof.lower_z(rho)?;
            return Some((ax.low + z, full.1));
        }
        // Across the axis: the ray's height along the tool axis is fixed (within ±half); a
        // stadium grown by `half` holds the chords of all the block's rays.
        let zr = origin[ax.k];
        let r = self
            .prof
            .max_radius_in(zr - half - ax.high, zr + half - ax.low)?
            * (1.0 + 1e-12)
            + 1e-9
            + half;
        // 2-D, in the plane ⊥ tool axis: coordinates (along the ray, across it).
        let j = 3 - k - ax.k;
        let pick = |c: (f64, f64), axis: usize| if axis == u { c.0 } else { c.1 };
        let (a0, b0) = (pick(ax.c0, k), pick(ax.c0, j));
        let (a1, b1) = (pick(ax.c1, k), pick(ax.c1, j));
        let qr = origin[j];
        let (lo, hi) = slab::stadium_chord((a0, b0), (a1, b1), r, qr)?;
        (lo <= hi).then_some((lo.max(full.0), hi.min(full.1)))
    }

    /// A ball end moving with its axis along a world axis, in a plane normal to the rays along
    /// world axis `k`, seen in that plane: chords nested from one move to the next in the same
    /// plane, so that a run of them can be cut together (`planar.rs`). `None` for other tools,
    /// moves and families.
    pub fn planar(&self, k: usize) -> Option<PlanarMember> {
        match &self.closed {
            Some(ClosedForm::Axial(f)) => f.planar(k),
            _ => None,
        }
    }

    /// Queries for many lines sharing the direction `dir` (unit, workpiece frame): the
    /// per-direction constants are computed once.
    pub fn lines(&self, dir: Vec3) -> LineBatch<'_, 'a> {
        LineBatch {
            sweep: self,
            dc: self.dir_consts(dir.normalize()),
            scratch: Scratch::new(),
        }
    }

    /// Constants for lines with world direction `dir` (unit).
    pub(crate) fn dir_consts(&self, dir: Vec3) -> DirConsts {
        let d = self.frame.vector_to_local(dir);
        let v = self.v;
        let w = d.cross(v);
        let vv = v.dot(v);
        let dv = d.dot(v);
        let det = w.length_squared();
        let p = self.prof;
        let (e1, e2) = d.any_orthonormal_pair();
        let pr = |x: Vec3| (x.dot(e1), x.dot(e2));
        let ax = pr(Vec3::new(0.0, 0.0, p.z_max() - p.z_min()));
        let vp = pr(v);
        let r = p.bound_radius() * (1.0 + 1e-12) + 1e-9;
        let near = Near {
            e1,
            e2,
            a: pr(Vec3::new(0.0, 0.0, p.z_min())),
            ax,
            vv: vp,
            det: ax.0 * vp.1 - ax.1 * vp.0,
            scale: (ax.0 * ax.0 + ax.1 * ax.1).max(vp.0 * vp.0 + vp.1 * vp.1),
            rr: r * r,
        };
        let mut order = [0u8; MAX_UNITS];
        let n = self.units.len().min(MAX_UNITS);
        for (i, o) in order.iter_mut().enumerate().take(n) {
            *o = i as u8;
        }
        if let Some(k) = (0..3).find(|&k| dir[k].abs() == 1.0) {
            let lowest = (0..n)
                .min_by(|&a, &b| self.units[a].bbox.min[k].total_cmp(&self.units[b].bbox.min[k]));
            let highest = (0..n)
                .max_by(|&a, &b| self.units[a].bbox.max[k].total_cmp(&self.units[b].bbox.max[k]));
            let mut w = 0;
            for first in [lowest, highest].into_iter().flatten() {
                if let Some(pos) = order[w..n].iter().position(|&x| x as usize == first) {
                    order.swap(w, w + pos);
                    w += 1;
                }
            }
        }
        if v == Vec3::ZERO {
            // An instance: its crossings are final once two are found (below), so the cheap
            // elements go first and the tori, a tenth of a microsecond each, last.
            let torus = |ui: u8| {
                let unit = &self.units[ui as usize];
                !unit.joint && matches!(p.elements()[unit.index], Element::Arc { e, .. } if e > 0.0)
            };
            order[..n].sort_by_key(|&ui| torus(ui));
        }
        DirConsts {
            d,
            v,
            w,
            dv,
            vv,
            det,
            envelope: vv > 0.0 && det > 1e-20 * vv,
            near,
            order,
        }
    }

    /// The interval of the line `origin + t·dir` inside the swept volume (`dc` from
    /// [`SweptConvex::dir_consts`] for `dir`).
    ///
    /// With `dexel = Some((k, m_lo, m_hi))` the line is a ray along world axis `k` with
    /// `origin[k] = 0` whose material lies within `[m_lo, m_hi]`; then work that cannot change
    /// `[lo, hi] ∩ [m_lo, m_hi]` is skipped, so the returned interval is exact where it meets
    /// the material (and may be shorter outside it).
    pub(crate) fn line_interval(
        &self,
        origin: Vec3,
        dc: &DirConsts,
        dexel: Option<(usize, f64, f64)>,
        scratch: &mut Scratch,
    ) -> Option<(f64, f64)> {
        let d = dc.d;
        let o_full = self.frame.to_local(origin);
        // Re-base the line at its point nearest the tool origin, for precision (t values of a
        // few mm instead of hundreds in the quartic and octic).
        let t0 = -o_full.dot(d);
        let o = o_full + d * t0;
        // (In dexel mode with the tool axis along a world axis, the caller's range test has
        // already placed the ray near the sweep.)
        let prechecked = dexel.is_some() && self.axial.is_some();
        if !prechecked && !self.near(o, dc) {
            return None;
        }
        let mut acc = Acc::EMPTY;
        let prof = self.prof;
        let v = self.v;
        // (Profiles of more than MAX_UNITS units — never built from APT cutters or holders —
        // are evaluated without the skip test.)
        let dexel = if self.units.len() > MAX_UNITS {
            None
        } else {
            dexel
        };
        let all: SmallVec<[u8; 32]>;
        let order: &[u8] = if dexel.is_some() {
            &dc.order[..self.units.len()]
        } else {
            all = (0..self.units.len() as u8).collect();
            &all
        };
        for &ui in order {
            let unit = &self.units[ui as usize];
            if let Some((k, m_lo, m_hi)) = dexel {
                let (u, w) = ((k + 1) % 3, (k + 2) % 3);
                let b = &unit.bbox;
                if origin[u] < b.min[u]
                    || origin[u] > b.max[u]
                    || origin[w] < b.min[w]
                    || origin[w] > b.max[w]
                {
                    continue;
                }
                // Local parameter = world coordinate along k − t0.
                let need_lo = b.min[k] - t0 < acc.lo && acc.lo > m_lo - t0;
                let need_hi = b.max[k] - t0 > acc.hi && acc.hi < m_hi - t0;
                if !(need_lo || need_hi) {
                    continue;
                }
            }
            if v == Vec3::ZERO && acc.hi - acc.lo > INSTANCE_CROSSINGS_APART {
                // A line meets the boundary of a convex solid twice, unless it lies in a face:
                // two crossings apart are its entry and exit.
                break;
            }
            if unit.joint {
                if dc.envelope {
                    prof.envelope_joint(unit.index, o, dc, &mut acc);
                }
            } else if self.lozenges & (1 << unit.index) != 0
                && (v == Vec3::ZERO || (dc.envelope && self.skip_envelope & (1 << unit.index) == 0))
            {
                prof.swept_corner(unit.index, o, d, v, &mut acc);
            } else {
                prof.cap_element(unit.index, o, d, &mut acc, scratch);
                if v != Vec3::ZERO {
                    prof.cap_element(unit.index, o - v, d, &mut acc, scratch);
                }
                if dc.envelope && self.skip_envelope & (1 << unit.index) == 0 {
                    prof.envelope_element(unit.index, o, dc, &mut acc, scratch);
                }
            }
        }
        acc.get().map(|(lo, hi)| (lo + t0, hi + t0))
    }

    /// False when the line (move frame, re-based at its point nearest the tool origin) stays
    /// farther than the profile's largest radius from the parallelogram swept by the axis
    /// segment `[z_min, z_max]`, hence misses the sweep; a conservative pre-test.
    #[inline]
    fn near(&self, o: Vec3, dc: &DirConsts) -> bool {
        let n = &dc.near;
        let q = (o.dot(n.e1), o.dot(n.e2));
        let sub = |x: (f64, f64), y: (f64, f64)| (x.0 - y.0, x.1 - y.1);
        let (a, ax, vv) = (n.a, n.ax, n.vv);
        let rel = sub(q, a);
        // Inside the projected parallelogram a + α·ax + s·vv (α, s ∈ [0, 1])?
        if n.det.abs() > 1e-12 * n.scale {
            let al = (rel.0 * vv.1 - rel.1 * vv.0) / n.det;
            let s = (ax.0 * rel.1 - ax.1 * rel.0) / n.det;
            if (0.0..=1.0).contains(&al) && (0.0..=1.0).contains(&s) {
                return true;
            }
        }
        // Distance to the four edges.
        let seg = |p0: (f64, f64), e: (f64, f64)| {
            let w = sub(q, p0);
            let ee = e.0 * e.0 + e.1 * e.1;
            let t = if ee > 0.0 {
                ((w.0 * e.0 + w.1 * e.1) / ee).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let dx = (w.0 - t * e.0, w.1 - t * e.1);
            dx.0 * dx.0 + dx.1 * dx.1
        };
        let a2 = (a.0 + ax.0, a.1 + ax.1);
        let a3 = (a.0 + vv.0, a.1 + vv.1);
        let m = seg(a, ax).min(seg(a, vv)).min(seg(a2, vv)).min(seg(a3, ax));
        m <= n.rr
    }
}

/// The unit tests' deterministic generator: uniform in `[0, 1)` from `seed` (a 64-bit LCG).
#[cfg(test)]
pub(crate) fn test_rng(mut seed: u64) -> impl FnMut() -> f64 {
    move || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((seed >> 11) as f64) / ((1u64 << 53) as f64)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use swarf_tool::Cutter;

    fn interval(
        c: &Cutter,
        tip: Vec3,
        axis: Vec3,
        delta: Vec3,
        o: Vec3,
        dir: Vec3,
    ) -> Option<(f64, f64)> {
        let prof = ConvexProfile::from_solid(c.cutting_solid()).unwrap();
        let sw = SweptConvex::new(&prof, tip, axis, delta);
        let dc = sw.dir_consts(dir);
        sw.line_interval(o, &dc, None, &mut Scratch::new())
    }

    /// The bull-nose corner swept as a lozenge (`lozenge.rs`) gives the same intervals as its
    /// caps and the torus envelope's degree-8 polynomial: random lines in every direction
    /// against sweeps rising, falling, level, oblique and along the axis, and static instances,
    /// on vertical and tilted axes, for corners small and large against the radius.
    #[test]
    fn lozenge_corner_equals_caps_and_envelope() {
        let mut rnd = test_rng(5);
        let (mut compared, mut hits) = (0, 0);
        for spec in ["bull:d=10,r=2", "bull:d=6,r=0.5", "bull:d=20,r=4"] {
            let c = swarf_tool::spec::parse(spec).unwrap();
            let prof = ConvexProfile::from_solid(c.cutting_solid()).unwrap();
            assert_ne!(prof.lozenge_corners(), 0, "{spec}");
            for m in 0..40 {
                let axis = if m % 2 == 0 {
                    Vec3::Z
                } else {
                    Vec3::new(rnd() - 0.5, rnd() - 0.5, 1.0).normalize()
                };
                let delta = match m % 5 {
                    0 => Vec3::new(rnd() - 0.5, rnd() - 0.5, 0.0) * 4.0,
                    1 => axis * (rnd() - 0.5) * 3.0,
                    2 => Vec3::ZERO,
                    _ => Vec3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5) * 4.0,
                };
                let tip = Vec3::new(rnd(), rnd(), rnd()) * 5.0;
                let new = SweptConvex::new(&prof, tip, axis, delta);
                assert_ne!(new.lozenges, 0);
                let mut old = new.clone();
                old.lozenges = 0;
                let mut scratch = Scratch::new();
                for _ in 0..300 {
                    let dir = Vec3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5).normalize();
                    let o = tip + delta * rnd() + Vec3::new(rnd() - 0.5, rnd() - 0.5, rnd()) * 14.0;
                    let dc = new.dir_consts(dir);
                    let a = new.line_interval(o, &dc, None, &mut scratch);
                    let b = old.line_interval(o, &dc, None, &mut scratch);
                    compared += 1;
                    match (a, b) {
                        (None, None) => {}
                        (Some(x), Some(y)) => {
                            hits += 1;
                            assert!(
                                (x.0 - y.0).abs() < 1e-9 && (x.1 - y.1).abs() < 1e-9,
                                "{spec} axis {axis} move {delta}: {x:?} vs {y:?}"
                            );
                        }
                        // A line grazing the sweep within the tolerance.
                        (Some(x), None) | (None, Some(x)) => {
                            assert!(x.1 - x.0 < 1e-6, "{spec}: {a:?} vs {b:?}")
                        }
                    }
                }
            }
        }
        assert!(hits > compared / 4, "{hits} of {compared}");
    }

    #[test]
    fn flat_slot_vertical_ray() {
        // Flat Ø10 moving +X by 20 at z = 0: a vertical ray at (10, 4) enters at z = 0 and
        // leaves at the top of the cutting part (h = 30); t is measured from z = −50.
        let c = Cutter::flat(10.0).unwrap();
        let (lo, hi) = interval(
            &c,
            Vec3::ZERO,
            Vec3::Z,
            Vec3::new(20.0, 0.0, 0.0),
            Vec3::new(10.0, 4.0, -50.0),
            Vec3::Z,
        )
        .unwrap();
        assert!(
            (lo - 50.0).abs() < 1e-12 && (hi - 80.0).abs() < 1e-12,
            "{lo} {hi}"
        );
        // Outside the slot width: no hit.
        assert!(interval(
            &c,
            Vec3::ZERO,
            Vec3::Z,
            Vec3::new(20.0, 0.0, 0.0),
            Vec3::new(10.0, 5.01, -50.0),
            Vec3::Z
        )
        .is_none());
        // A ray along X at y = 3, z = 1: from x = −4 to 24.
        let (lo, hi) = interval(
            &c,
            Vec3::ZERO,
            Vec3::Z,
            Vec3::new(20.0, 0.0, 0.0),
            Vec3::new(-100.0, 3.0, 1.0),
            Vec3::X,
        )
        .unwrap();
        assert!(
            (lo - 96.0).abs() < 1e-12 && (hi - 124.0).abs() < 1e-12,
            "{lo} {hi}"
        );
    }

    #[test]
    fn ball_groove_x_ray_across() {
        // Ball Ø10 along +Y: a ray along X at z = 2 (3 below the centre) crosses the capsule
        // where x² + 3² ≤ 25: x ∈ [−4, 4].
        let c = Cutter::ball(10.0).unwrap();
        let (lo, hi) = interval(
            &c,
            Vec3::ZERO,
            Vec3::Z,
            Vec3::new(0.0, 20.0, 0.0),
            Vec3::new(-50.0, 10.0, 2.0),
            Vec3::X,
        )
        .unwrap();
        assert!(
            (lo - 46.0).abs() < 1e-9 && (hi - 54.0).abs() < 1e-9,
            "{lo} {hi}"
        );
    }

    #[test]
    fn plunge_vertical_and_side_rays() {
        // Flat Ø10 plunging 20 mm down along its axis (the thesis frame is undefined here).
        let c = Cutter::flat(10.0).unwrap();
        let (lo, hi) = interval(
            &c,
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::Z,
            Vec3::new(0.0, 0.0, -20.0),
            Vec3::new(-50.0, 1.0, -10.0),
            Vec3::X,
        )
        .unwrap();
        let x = (25.0f64 - 1.0).sqrt();
        assert!(
            (lo - (50.0 - x)).abs() < 1e-9 && (hi - (50.0 + x)).abs() < 1e-9,
            "{lo} {hi}"
        );
    }

    #[test]
    fn dexel_pruning_keeps_the_material_part_exact() {
        // The pruned query must agree with the full one wherever the material is.
        let mut rnd = test_rng(7);
        let cutters = [
            "ball:d=10",
            "flat:d=8",
            "bull:d=12,r=3",
            "drill:d=6,angle=118",
            "taper-ball:d=6,taper=8",
        ];
        let mut compared = 0;
        for (ci, spec) in cutters.iter().cycle().take(60).enumerate() {
            let c = Cutter::from_spec(spec).unwrap();
            let prof = ConvexProfile::from_solid(c.cutting_solid()).unwrap();
            let axis = if ci % 2 == 0 {
                Vec3::Z
            } else {
                Vec3::new(rnd() - 0.5, rnd() - 0.5, 1.0).normalize()
            };
            let delta = Vec3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5) * 10.0;
            let sw = SweptConvex::new(&prof, Vec3::ZERO, axis, delta);
            let bb = sw.bbox();
            for k in 0..3 {
                let dc = sw.dir_consts(Vec3::AXES[k]);
                for _ in 0..200 {
                    let mut o = bb.min + (bb.max - bb.min) * Vec3::new(rnd(), rnd(), rnd());
                    o[k] = 0.0;
                    let (a, b) = (
                        bb.min[k] + rnd() * (bb.max[k] - bb.min[k]),
                        bb.min[k] + rnd() * (bb.max[k] - bb.min[k]),
                    );
                    let (m_lo, m_hi) = (a.min(b), a.max(b));
                    let full = sw.line_interval(o, &dc, None, &mut Scratch::new());
                    if let Some(f) = full {
                        // Every block holding this ray must have a range holding its hit.
                        let half = 0.4 * rnd();
                        let mut centre = o;
                        centre[(k + 1) % 3] += (2.0 * rnd() - 1.0) * half;
                        centre[(k + 2) % 3] += (2.0 * rnd() - 1.0) * half;
                        let br = sw
                            .block_range(k, centre, half)
                            .expect("block range misses a hit");
                        assert!(
                            f.0 >= br.0 - 1e-9 && f.1 <= br.1 + 1e-9,
                            "{spec} k={k}: {f:?} not in block {br:?}"
                        );
                        // The cheap range must hold the whole intersection.
                        let r = sw.dexel_range(o, k).expect("range misses a hit");
                        assert!(
                            f.0 >= r.0 - 1e-9 && f.1 <= r.1 + 1e-9,
                            "{spec} k={k}: {f:?} not in {r:?}"
                        );
                    }
                    let pruned =
                        sw.line_interval(o, &dc, Some((k, m_lo, m_hi)), &mut Scratch::new());
                    let clip = |x: Option<(f64, f64)>| {
                        x.and_then(|(l, h)| {
                            let (l, h) = (l.max(m_lo), h.min(m_hi));
                            (l < h).then_some((l, h))
                        })
                    };
                    match (clip(full), clip(pruned)) {
                        (None, None) => {}
                        (Some(f), Some(p)) => {
                            assert!(
                                (f.0 - p.0).abs() < 1e-9 && (f.1 - p.1).abs() < 1e-9,
                                "{spec} {f:?} {p:?}"
                            );
                            compared += 1;
                        }
                        (f, p) => panic!("{spec}: full {f:?} vs pruned {p:?}"),
                    }
                }
            }
        }
        assert!(compared > 1000, "{compared}");
    }
}
