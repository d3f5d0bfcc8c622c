//! The public records a deck is read into: supports, loads, procedures and steps, each with
//! the file and line it came from.

use std::fmt;
use std::path::PathBuf;

use crate::mesh::Face;

/// A file and 1-based line number in the deck (for messages further down the pipeline).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SourceLine {
    pub file: PathBuf,
    pub line: usize,
}

impl fmt::Display for SourceLine {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}", self.file.display(), self.line)
    }
}

/// What a `*BOUNDARY` or `*CLOAD` line names.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum NodeTarget {
    /// A node set (or node-based surface), by its upper-case name.
    Set(String),
    /// One node, by its label in the file.
    Node(i64),
}

/// One `*BOUNDARY` line: prescribed displacement `value` on DOFs `first_dof..=last_dof`.
#[derive(Clone, Debug, PartialEq)]
pub struct Boundary {
    pub target: NodeTarget,
    /// Internal node indices of the target, sorted.
    pub nodes: Vec<usize>,
    /// Abaqus DOF numbers, 1 = x, 2 = y, 3 = z, with `1 <= first_dof <= last_dof <= 3`.
    pub first_dof: u8,
    pub last_dof: u8,
    pub value: f64,
    /// `*BOUNDARY, FIXED`: held at the displacement the step starts from (`value` 0).
    pub fixed: bool,
    pub source: SourceLine,
}

/// One `*CLOAD` line: force `value` on DOF `dof` of every target node.
#[derive(Clone, Debug, PartialEq)]
pub struct ConcentratedLoad {
    pub target: NodeTarget,
    /// Internal node indices of the target, sorted.
    pub nodes: Vec<usize>,
    /// Abaqus DOF number, 1..=3.
    pub dof: u8,
    pub value: f64,
    pub source: SourceLine,
}

/// What a pressure line names.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum PressureTarget {
    /// `*DSLOAD` on an element-based surface (upper-case name).
    Surface(String),
    /// `*DLOAD` on an element set (upper-case name).
    ElementSet(String),
    /// `*DLOAD` on one element, by its label in the file.
    Element(i64),
}

/// One `*DSLOAD` or `*DLOAD` line: uniform pressure on a list of faces.
#[derive(Clone, Debug, PartialEq)]
pub struct PressureLoad {
    pub target: PressureTarget,
    pub faces: Vec<Face>,
    /// Pressure, Abaqus sign: positive pushes into the element.
    pub value: f64,
    pub source: SourceLine,
}

/// The `*FREQUENCY` request (see the module documentation for the field layouts).
#[derive(Clone, Debug, PartialEq, Default)]
pub struct FrequencyRequest {
    /// Number of eigenvalues wanted (`None`: blank, i.e. all in the range).
    pub eigenvalues: Option<usize>,
    /// Lower end of the frequency range of interest, cycles per time.
    pub lower_frequency: Option<f64>,
    /// Upper end of the frequency range of interest, cycles per time.
    pub upper_frequency: Option<f64>,
    /// Shift point, cycles per time.
    pub shift: Option<f64>,
}

/// The `*STATIC` data line (time incrementation), blanks as `None`.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct StaticRequest {
    pub initial_increment: Option<f64>,
    pub time_period: Option<f64>,
    pub minimum_increment: Option<f64>,
    pub maximum_increment: Option<f64>,
}

/// The `*COMPLEX FREQUENCY` data line (Abaqus' CEA step), blanks as `None`.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct ComplexFrequencyRequest {
    /// Number of complex eigenmodes wanted (`None`: all in the range).
    pub eigenvalues: Option<usize>,
    /// Minimum frequency of interest, cycles per time.
    pub lower_frequency: Option<f64>,
    /// Maximum frequency of interest, cycles per time.
    pub upper_frequency: Option<f64>,
    /// Shift point, cycles per time: with a number of modes, those whose frequency is
    /// nearest to it are kept.
    pub shift: Option<f64>,
}

/// The analysis procedure of a step.
#[derive(Clone, Debug, PartialEq)]
pub enum Procedure {
    Static(StaticRequest),
    Frequency(FrequencyRequest),
    ComplexFrequency(ComplexFrequencyRequest),
    /// A procedure this reader recognises but does not read, e.g. `*COMPLEX FREQUENCY`.
    Unsupported {
        keyword: String,
    },
}

/// Which kinds of load had `OP=NEW` in a step (everything of that kind in force before the
/// step is removed).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Replaced {
    pub boundaries: bool,
    pub concentrated_loads: bool,
    /// `*DSLOAD`.
    pub surface_pressures: bool,
    /// `*DLOAD`.
    pub element_pressures: bool,
}

/// One `*STEP` ... `*END STEP`, with the supports and loads defined inside it.
#[derive(Clone, Debug, PartialEq)]
pub struct Step {
    /// `NAME=` on `*STEP`.
    pub name: Option<String>,
    /// The optional data line of `*STEP`.
    pub title: Option<String>,
    pub procedure: Procedure,
    /// A linear-perturbation step: its own supports and loads act in this step only.
    pub perturbation: bool,
    /// `NLGEOM` on `*STEP`.
    pub nlgeom: bool,
    pub boundaries: Vec<Boundary>,
    pub concentrated_loads: Vec<ConcentratedLoad>,
    pub pressures: Vec<PressureLoad>,
    pub replaced: Replaced,
    /// `*MOTION`s given in this step (in force from this step on).
    pub motions: Vec<Motion>,
    /// The `*STEP` line.
    pub source: SourceLine,
}

/// How a `*MOTION` moves its nodes (a transport velocity, `TYPE=VELOCITY`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MotionKind {
    /// `*MOTION, ROTATION`: angular velocity `speed` (radians per time, signed) about the
    /// axis from `from` to `to`.
    Rotation {
        speed: f64,
        from: [f64; 3],
        to: [f64; 3],
    },
    /// `*MOTION, TRANSLATION`: the velocity (the lines of one keyword on one target add up
    /// their components).
    Translation { velocity: [f64; 3] },
}

/// A `*MOTION, TYPE=VELOCITY` data line: the velocity of a body's nodes, from which the
/// contact pairs whose master (or slave) surface those nodes carry get their sliding
/// direction.
#[derive(Clone, Debug, PartialEq)]
pub struct Motion {
    pub target: NodeTarget,
    /// Internal node indices of the target, sorted.
    pub nodes: Vec<usize>,
    pub kind: MotionKind,
    pub source: SourceLine,
}

/// The normal law of a surface interaction (`*SURFACE BEHAVIOR`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum NormalBehavior {
    /// `PRESSURE-OVERCLOSURE=LINEAR`: the slope of the pressure-overclosure line, pressure
    /// per unit overclosure: squeal's penalty per unit area.
    Linear { slope: f64 },
    /// `PRESSURE-OVERCLOSURE=HARD`, or no `*SURFACE BEHAVIOR` (Abaqus' default): squeal's
    /// penalty law with its default penalty 10 E_min / h (a study's `[[contacts]]` table of
    /// the pair's name can give another).
    Hard,
}

/// A `*SURFACE INTERACTION` with its `*SURFACE BEHAVIOR` and `*FRICTION`.
#[derive(Clone, Debug, PartialEq)]
pub struct SurfaceInteraction {
    /// Upper-case name.
    pub name: String,
    pub normal: NormalBehavior,
    /// `false` with `*SURFACE BEHAVIOR, NO SEPARATION` (bilateral: the law may pull).
    pub separation: bool,
    /// Friction coefficient (0 without `*FRICTION`).
    pub friction: f64,
    /// CalculiX's stick slope (second field of the `*FRICTION` data line), tangential
    /// stiffness per unit area while sticking; `None`: squeal's default (penalty / 100).
    pub stick_slope: Option<f64>,
    /// `PRESSURE-OVERCLOSURE=LINEAR`'s 2nd field, CalculiX's tension at large clearance
    /// (pressure), used by the CalculiX contact variant; `None` when blank.
    pub tension: Option<f64>,
    /// The 3rd field, CalculiX's c0: no contact spring beyond c0 sqrt(slave area) of
    /// clearance; `None` when blank.
    pub clearance_factor: Option<f64>,
    /// The `*SURFACE INTERACTION` line.
    pub source: SourceLine,
}

/// The slave side of a deck contact pair.
#[derive(Clone, Debug, PartialEq)]
pub enum SlaveSurface {
    /// An element-based surface (upper-case name, in [`Mesh::surfaces`](crate::mesh::Mesh)):
    /// its nodes, with tributary areas from its faces.
    Faces(String),
    /// A node-based surface (upper-case name): its nodes with the area each stands for
    /// (the `*SURFACE, TYPE=NODE` data line's second field; 1 when blank, as in Abaqus).
    Nodes {
        name: String,
        nodes: Vec<(usize, f64)>,
    },
}

/// One data line of `*CONTACT PAIR, TYPE=NODE TO SURFACE`: a node-to-surface pair.
#[derive(Clone, Debug, PartialEq)]
pub struct DeckContactPair {
    /// `SLAVE:MASTER` (upper case): the name a study's `[[contacts]]` table uses to replace
    /// the pair.
    pub name: String,
    /// The interaction's upper-case name (a key of [`super::Deck::interactions`]).
    pub interaction: String,
    pub slave: SlaveSurface,
    /// Element-based master surface, upper-case name.
    pub master: String,
    /// `ADJUST=` distance: slave nodes whose gap is below it start exactly in contact.
    pub adjust: Option<f64>,
    pub source: SourceLine,
}

/// Where a discrete spring's ends are.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SpringEnds {
    /// `SPRING1`: a node (internal index) tied to the ground.
    Ground(usize),
    /// `SPRING2` and `SPRINGA`: two nodes (internal indices), in the element's order.
    Nodes([usize; 2]),
}

/// A `SPRING1`, `SPRING2` or `SPRINGA` element with the stiffness of its `*SPRING`: a
/// linear spring along one fixed direction.
#[derive(Clone, Debug, PartialEq)]
pub struct DeckSpring {
    /// The element's label in the file.
    pub label: i64,
    /// `SPRING1`, `SPRING2` or `SPRINGA`.
    pub element_type: &'static str,
    pub ends: SpringEnds,
    /// Unit direction: the axis of the `*SPRING` DOF (SPRING1, SPRING2), or from the first
    /// node to the second in the initial configuration (SPRINGA).
    pub direction: [f64; 3],
    /// Force per displacement along `direction`.
    pub stiffness: f64,
    /// The element's line.
    pub source: SourceLine,
}

/// A `MASS` element with the mass of its `*MASS`: a point mass on the translations of a
/// node.
#[derive(Clone, Debug, PartialEq)]
pub struct DeckMass {
    pub label: i64,
    /// Internal node index.
    pub node: usize,
    pub mass: f64,
    /// The element's line.
    pub source: SourceLine,
}
