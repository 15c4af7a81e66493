//! Why a trim in a file is not honoured: the reader then uses the whole patch (or face) and
//! says why in a [`ReadNote::TrimNotHonoured`](crate::ReadNote::TrimNotHonoured), whose
//! [`UnhonouredTrim`](crate::UnhonouredTrim) names the trimming entity and holds this error. Entities are named as in their file: STEP instances `#id`, IGES directory
//! entries `D<n>`.

use swarf_geom::math::Vec3;

use super::ReadError;
use crate::curve::CurveError;
use crate::surface::invert::InvertError;
use crate::trim::TrimError;

/// Why a file's trim (a STEP face's bounds, an IGES 144) is not honoured.
#[derive(Debug, thiserror::Error)]
pub enum TrimFailure {
    /// An entity the trim needs is malformed or missing.
    #[error(transparent)]
    Entity(Box<ReadError>),
    /// Too many points for one trim or for the file's trims.
    #[error("the trim needs more than {trim} points (or the file more than {file})")]
    TooManyPoints {
        /// The limit for one trim.
        trim: usize,
        /// The limit for the file.
        file: usize,
    },
    /// The loops are not a valid trim.
    #[error(transparent)]
    Trim(#[from] TrimError),
    /// Points could not be mapped onto the surface.
    #[error("more than {limit} points needed a search for their parameters")]
    SearchesSpent {
        /// How many searches a trim may make.
        limit: usize,
    },
    /// A boundary point is not on the surface.
    #[error("the point ({:.6}, {:.6}, {:.6}) is {distance:.3e} mm off the surface", .point.x, .point.y, .point.z)]
    OffSurface {
        /// The point, mm.
        point: Vec3,
        /// Its distance to the surface, mm.
        distance: f64,
    },
    /// A boundary point maps to parameters that are not finite.
    #[error("a point maps to non-finite parameters")]
    NonFiniteParameters,

    // STEP edge curves.
    /// Curves nest too deep.
    #[error("#{curve}: curves nest more than {max} deep")]
    CurveNesting {
        /// The curve.
        curve: u64,
        /// The deepest nesting read.
        max: usize,
    },
    /// A line's direction is not a `VECTOR`.
    #[error("#{vector}: found {found}, expected VECTOR")]
    NotVector {
        /// The entity.
        vector: u64,
        /// Its entity name.
        found: String,
    },
    /// A line's direction vector has no length.
    #[error("#{vector}: a line's vector has no length")]
    ZeroLine {
        /// The `VECTOR`.
        vector: u64,
    },
    /// A circle or ellipse with a radius that is not positive.
    #[error("#{curve}: a conic's radii must be positive")]
    ConicRadii {
        /// The conic.
        curve: u64,
    },
    /// A polyline with too few or too many points.
    #[error("#{curve}: a polyline needs 2 to {max} points")]
    PolylinePoints {
        /// The polyline.
        curve: u64,
        /// The most points read.
        max: usize,
    },
    /// A simple `B_SPLINE_CURVE_WITH_KNOTS` with the wrong number of attributes.
    #[error("#{curve}: B_SPLINE_CURVE_WITH_KNOTS has {count} attributes, expected 9")]
    SplineAttributes {
        /// The curve.
        curve: u64,
        /// Its attributes.
        count: usize,
    },
    /// A B-spline curve's degree out of range.
    #[error("#{curve}: curve degree {degree} is not 1 to {max}")]
    SplineDegree {
        /// The curve.
        curve: u64,
        /// The degree read.
        degree: f64,
        /// The highest degree read.
        max: usize,
    },
    /// Too few (or too many) control points for the degree.
    #[error("#{curve}: {points} control points for degree {degree}")]
    SplinePoints {
        /// The curve.
        curve: u64,
        /// Its control points.
        points: usize,
        /// Its degree.
        degree: usize,
    },
    /// Knots not finite or decreasing, or an empty range.
    #[error("#{curve}: knots are not increasing")]
    SplineKnots {
        /// The curve.
        curve: u64,
    },
    /// Not one weight per control point.
    #[error("#{curve}: {weights} weights for {points} control points")]
    SplineWeightCount {
        /// The curve.
        curve: u64,
        /// Its weights.
        weights: usize,
        /// Its control points.
        points: usize,
    },
    /// A weight that is not positive.
    #[error("#{curve}: weights must be positive")]
    SplineWeights {
        /// The curve.
        curve: u64,
    },
    /// A STEP B-spline curve the evaluator refuses.
    #[error("#{curve}: {reason}")]
    SplineCurve {
        /// The curve.
        curve: u64,
        /// Why (in the message, not a separate source).
        reason: CurveError,
    },
    /// An edge curve of a kind that is not evaluated.
    #[error("edge curve #{curve} is a {kind}, which is not evaluated")]
    CurveKind {
        /// The curve.
        curve: u64,
        /// Its entity name.
        kind: String,
    },

    // STEP face bounds.
    /// A face bound of another kind than `FACE_BOUND` / `FACE_OUTER_BOUND`.
    #[error("bound #{bound} is a {kind}")]
    BoundKind {
        /// The bound.
        bound: u64,
        /// Its entity name.
        kind: String,
    },
    /// A `POLY_LOOP` with too many points.
    #[error("poly loop #{lp} has too many points")]
    PolyLoopTooLong {
        /// The loop.
        lp: u64,
    },
    /// A `POLY_LOOP` with fewer than 3 points.
    #[error("poly loop #{lp} has fewer than 3 points")]
    PolyLoopTooShort {
        /// The loop.
        lp: u64,
    },
    /// A loop of another kind than edge, poly or vertex loop.
    #[error("loop #{lp} is a {kind}, which is not read")]
    LoopKind {
        /// The loop.
        lp: u64,
        /// Its entity name.
        kind: String,
    },
    /// An edge of a loop that is not the entity expected there.
    #[error("edge #{edge} is a {found}, expected {expected}")]
    EdgeKind {
        /// The entity.
        edge: u64,
        /// Its entity name.
        found: String,
        /// What was expected (`ORIENTED_EDGE`, `EDGE_CURVE`).
        expected: &'static str,
    },
    /// A poly loop that cannot be mapped, for `reason`.
    #[error("poly loop #{lp}: {reason}")]
    InPolyLoop {
        /// The loop.
        lp: u64,
        /// Why.
        reason: Box<TrimFailure>,
    },
    /// An edge that cannot be mapped, for `reason`.
    #[error("edge #{edge}: {reason}")]
    InEdge {
        /// The edge.
        edge: u64,
        /// Why.
        reason: Box<TrimFailure>,
    },
    /// An edge's vertex is not on its curve.
    #[error("a vertex of edge #{edge} is {distance:.3e} mm off its curve")]
    VertexOffCurve {
        /// The edge.
        edge: u64,
        /// The larger of its vertices' distances, mm.
        distance: f64,
    },
    /// An edge from a vertex to itself along an open curve.
    #[error("edge #{edge} starts and ends at one vertex, but its curve is open")]
    OpenCurveOnOneVertex {
        /// The edge.
        edge: u64,
    },
    /// Consecutive edges of a loop that do not join.
    #[error("edge #{edge} does not start where the previous edge ends")]
    EdgesDoNotJoin {
        /// The edge.
        edge: u64,
    },
    /// A bound that gave no point.
    #[error("loop {index} has no points")]
    EmptyLoop {
        /// The bound's index in the face.
        index: usize,
    },
    /// A loop that does not close in the surface's parameters.
    #[error("loop {index} does not close in the surface's parameters")]
    LoopNotClosed {
        /// The bound's index in the face.
        index: usize,
    },
    /// A loop winding around the surface more than once.
    #[error("loop {index} winds around the surface more than once")]
    LoopWindsTwice {
        /// The bound's index in the face.
        index: usize,
    },
    /// Loops winding around the surface other than as one or two bands' edges.
    #[error("the loops wind around the surface in a way not read")]
    WindingNotRead,
    /// The two loops around a surface face the same way.
    #[error("the two loops around the surface face the same way")]
    BandEdgesAlike,
    /// The band between two loops around a surface is wider than a turn.
    #[error("the band between the loops around the surface is wider than a turn")]
    BandTooWide,
    /// One loop around both angles of a torus.
    #[error("one loop around both angles of the surface bounds nothing")]
    LoopAroundBothAngles,
    /// The loops enclose no area.
    #[error("the loops span no area")]
    NoArea,

    // STEP curve-bounded surfaces.
    /// A boundary of a `CURVE_BOUNDED_SURFACE` that is not a boundary curve.
    #[error("#{boundary} is a {kind}, expected BOUNDARY_CURVE or OUTER_BOUNDARY_CURVE")]
    BoundaryKind {
        /// The entity.
        boundary: u64,
        /// Its entity name.
        kind: String,
    },
    /// A segment of a boundary curve that is not a composite curve segment.
    #[error("segment #{segment} is a {kind}, expected COMPOSITE_CURVE_SEGMENT")]
    SegmentKind {
        /// The entity.
        segment: u64,
        /// Its entity name.
        kind: String,
    },
    /// A `PCURVE` on another surface than the basis it bounds.
    #[error("pcurve #{pcurve} lies on #{surface}, not on the basis surface #{basis}")]
    PcurveElsewhere {
        /// The pcurve.
        pcurve: u64,
        /// The surface it lies on.
        surface: u64,
        /// The basis surface.
        basis: u64,
    },
    /// A `PCURVE` on a basis whose parameters the reader does not keep as the file's.
    #[error(
        "pcurve #{pcurve}: the parameters of a {kind} are not read as the file's (its boundary \
         in model space would be)"
    )]
    PcurveParameters {
        /// The pcurve.
        pcurve: u64,
        /// The kind of its basis surface.
        kind: String,
    },
    /// A `PCURVE` whose curve is not given by a definitional representation.
    #[error("pcurve #{pcurve}: its reference_to_curve is a {kind}, expected DEFINITIONAL_REPRESENTATION")]
    PcurveRepresentation {
        /// The pcurve.
        pcurve: u64,
        /// What it refers to.
        kind: String,
    },
    /// A boundary segment along a whole (unbounded) line.
    #[error("#{curve} is an unbounded line (a TRIMMED_CURVE of it would bound)")]
    UnboundedLine {
        /// The line.
        curve: u64,
    },
    /// A `TRIMMED_CURVE` that is not read (the message names it).
    #[error("{why}")]
    TrimmedCurve {
        /// Why.
        why: String,
    },
    /// A boundary that cannot be honoured, for `reason`.
    #[error("boundary #{boundary}: {reason}")]
    InBoundary {
        /// The boundary curve.
        boundary: u64,
        /// Why.
        reason: Box<TrimFailure>,
    },

    // IGES boundaries (a 142 of a 144, a 141 of a 143).
    /// A boundary's model-space curve that jumps in the surface's parameters.
    #[error("model-space curve of {de} does not map to a continuous loop in the surface's parameters (it crosses a seam or a pole?)")]
    ModelJumps {
        /// The boundary (142 or 141).
        de: IgesBoundary,
    },
    /// A boundary's model-space curve needs too many points.
    #[error("model-space curve of {de} needs more than {trim} points, or the file's trims more than {file}")]
    ModelTooManyPoints {
        /// The boundary (142 or 141).
        de: IgesBoundary,
        /// The limit for one trim.
        trim: usize,
        /// The limit for the file.
        file: usize,
    },
    /// A boundary's model-space curve off the surface.
    #[error("model-space curve of {de} lies {distance:.3e} mm off the surface (at ({:.6}, {:.6}, {:.6}) mm; more than {tolerance:.1e} mm)", .point.x, .point.y, .point.z)]
    ModelOffSurface {
        /// The boundary (142 or 141).
        de: IgesBoundary,
        /// The distance, mm.
        distance: f64,
        /// The point, mm.
        point: Vec3,
        /// The largest distance accepted, mm.
        tolerance: f64,
    },
    /// A boundary's model-space curve needs more point searches than a trim may make.
    #[error(
        "model-space curve of {de}: more than {limit} points needed a search for their parameters"
    )]
    ModelSearchesSpent {
        /// The boundary (142 or 141).
        de: IgesBoundary,
        /// How many searches a trim may make.
        limit: usize,
    },
    /// A boundary's model-space curve maps to parameters that are not finite.
    #[error("model-space curve of {de} maps to non-finite parameters")]
    ModelNonFinite {
        /// The boundary (142 or 141).
        de: IgesBoundary,
    },
    /// A boundary's model-space curve gave no point.
    #[error("model-space curve of {de} maps to no point")]
    ModelNoPoint {
        /// The boundary (142 or 141).
        de: IgesBoundary,
    },
    /// A boundary's model-space curve maps to fewer than 3 distinct points.
    #[error("model-space curve of {de} maps to {points} distinct point(s) of the surface's parameters; a loop needs at least 3")]
    ModelTooFewPoints {
        /// The boundary (142 or 141).
        de: IgesBoundary,
        /// The distinct points.
        points: usize,
    },
    /// A boundary whose curve fails, for `reason`.
    #[error("{de}: {reason}")]
    Boundary {
        /// The boundary (142 or 141).
        de: IgesBoundary,
        /// Why.
        reason: Box<TrimFailure>,
    },
    /// A boundary with neither curve.
    #[error("{de} has neither a parameter-space nor a model-space curve")]
    NoCurve {
        /// The boundary (142 or 141).
        de: IgesBoundary,
    },
    /// A boundary's model-space curve that is malformed.
    #[error("{de}: its model-space curve cannot be read ({reason})")]
    ModelUnreadable {
        /// The boundary (142 or 141).
        de: IgesBoundary,
        /// Why (in the message, not a separate source).
        reason: Box<ReadError>,
    },
    /// A boundary whose parameter-space curve is of a kind not read and whose model-space curve
    /// fails too.
    #[error("{de}: {parameter}; {model}")]
    BothCurves {
        /// The boundary (142 or 141).
        de: IgesBoundary,
        /// Why the parameter-space curve is not used.
        parameter: Box<TrimFailure>,
        /// Why the model-space curve is not used.
        model: Box<TrimFailure>,
    },
    /// A face of a manifold solid B-rep (IGES 510), whose loops (508) are not read.
    #[error("its loops (entity 508 of a manifold solid B-rep) are not read")]
    FaceLoopsNotRead,
    /// More curves than a trim may have.
    #[error("its loops are made of more than {max} curves")]
    TooManyCurves {
        /// The limit.
        max: usize,
    },
    /// Too many points for the loops or the file's trims.
    #[error("its loops need more than {trim} points, or the file's trims more than {file}")]
    LoopsTooManyPoints {
        /// The limit for one trim.
        trim: usize,
        /// The limit for the file.
        file: usize,
    },
    /// A 126 the evaluator refuses.
    #[error("entity 126 at D{de}: {reason}")]
    Curve126 {
        /// The 126.
        de: usize,
        /// Why (in the message, not a separate source).
        reason: CurveError,
    },
    /// A curve entity of a kind not read.
    #[error("its {space} curve D{de} is an entity {kind}, which is not supported")]
    UnsupportedCurve {
        /// `parameter-space` or `model-space`.
        space: &'static str,
        /// The curve.
        de: i64,
        /// Its entity type.
        kind: u32,
    },
    /// A parameter-space curve outside the patch's parameter box.
    #[error(
        "its parameter-space curve D{de} reaches ({u}, {v}), outside the patch's parameter box"
    )]
    OutsideBox {
        /// The curve.
        de: i64,
        /// The point's u.
        u: f64,
        /// The point's v.
        v: f64,
    },
}

impl TrimFailure {
    /// True for the failures of a boundary's model-space curve that name the boundary themselves.
    pub(crate) fn names_its_boundary(&self) -> bool {
        matches!(
            self,
            TrimFailure::ModelJumps { .. }
                | TrimFailure::ModelTooManyPoints { .. }
                | TrimFailure::ModelSearchesSpent { .. }
                | TrimFailure::ModelOffSurface { .. }
                | TrimFailure::ModelNonFinite { .. }
                | TrimFailure::ModelNoPoint { .. }
                | TrimFailure::ModelTooFewPoints { .. }
        )
    }
}

impl From<ReadError> for TrimFailure {
    fn from(e: ReadError) -> Self {
        TrimFailure::Entity(Box::new(e))
    }
}

impl From<InvertError> for TrimFailure {
    fn from(e: InvertError) -> Self {
        match e {
            InvertError::GridSearchesSpent { limit } => TrimFailure::SearchesSpent { limit },
        }
    }
}

/// An IGES boundary entity that a trim failure names: a 142 (curve on a parametric surface) of
/// a 144, or a 141 (boundary) of a 143. Shown as `142 at D5`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct IgesBoundary {
    /// The entity type (142 or 141).
    pub kind: u32,
    /// Its directory entry.
    pub de: usize,
}

impl std::fmt::Display for IgesBoundary {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} at D{}", self.kind, self.de)
    }
}
