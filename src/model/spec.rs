//! The model as a user describes it in a study file: mesh source, materials, supports,
//! springs, links, pressures and contact pairs, by name. Plain serde data; the study file embeds
//! these tables and [`crate::model::Model::from_spec`] resolves the names against the mesh.

use crate::contact::SlidingDirection;
use crate::mesh::brake::BrakeParams;
use std::path::PathBuf;

/// The model tables of a study, borrowed from it.
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct ModelSpec<'a> {
    pub mesh: &'a MeshSpec,
    pub materials: &'a [MaterialSpec],
    pub supports: &'a [SupportSpec],
    pub springs: &'a [SpringSpec],
    pub links: &'a [LinkSpec],
    pub pressures: &'a [PressureSpec],
    pub contacts: &'a [ContactSpec],
}

/// Where the mesh comes from: a file, or the built-in brake (a preset, optionally with
/// changed parameters).
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MeshSpec {
    /// A .msh or .inp file, relative to the study file.
    pub file: Option<PathBuf>,
    /// Built-in brake preset (tiny, small, medium, industrial; tiny-caliper ... industrial-caliper for the floating-caliper layout); default small.
    pub preset: Option<String>,
    /// Built-in brake parameters (replace the preset's).
    pub brake: Option<BrakeParams>,
    /// A deck `file`: the `*SURFACE INTERACTION` whose pairs the disc slides under (their
    /// friction law becomes steady sliding along `sliding`, and the friction sweep sets
    /// their mu); default: the one whose pairs the deck's `*MOTION` moves, else the deck's
    /// only interaction.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub interaction: Option<String>,
    /// A deck `file`: the sliding direction of the pairs of `interaction`; it replaces the
    /// deck's `*MOTION` (absent: the deck's `*MOTION` gives it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sliding: Option<SlidingDirection>,
    /// A deck `file`: the law of its contact pairs, "squeal" (default) or "calculix"
    /// (CalculiX's slave areas, smoothed linear law and perturbation tangent, to compare
    /// like with like: [`crate::contact::variant`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contact_variant: Option<crate::contact::ContactVariant>,
}

#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialSpec {
    pub part: String,
    pub young: f64,
    pub poisson: f64,
    pub density: f64,
}

#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SupportSpec {
    /// Node set (or surface) name.
    pub set: String,
    /// Held components, e.g. "xyz" or "z".
    #[serde(default = "all_components")]
    pub components: String,
}

fn all_components() -> String {
    "xyz".into()
}

/// Direction of a spring to ground.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SpringDirection {
    /// A fixed vector.
    Vector([f64; 3]),
    /// Radial from the disc axis (z through the origin) at each node.
    Radial,
    /// Circumferential about the disc axis at each node (the normal of a radial plane such
    /// as a pad abutment).
    Circumferential,
}

#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpringSpec {
    pub set: String,
    pub direction: SpringDirection,
    /// Total stiffness of the set (N/m), shared equally by its nodes.
    pub stiffness: f64,
}

/// Springs between two bodies (guide pins, a piston seal): each node of `set` tied to the
/// nearest node of `to` by springs along `axis` (stiffness `axial`) and across it (two
/// springs perpendicular to it and to each other, each of stiffness `transverse`: the same
/// radially and tangentially). Totals of the link, shared equally by the nodes of `set`.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LinkSpec {
    /// For messages and reports.
    pub name: String,
    /// Node set (or surface) whose every node gets the springs.
    pub set: String,
    /// Node set (or surface) of the other body: each node of `set` is tied to its nearest.
    pub to: String,
    /// The link's axis (any length; default z, the disc axis).
    #[serde(default = "z_axis")]
    pub axis: [f64; 3],
    /// Total stiffness along the axis, N/m (>= 0).
    pub axial: f64,
    /// Total stiffness across the axis in every direction, N/m (>= 0).
    pub transverse: f64,
}

fn z_axis() -> [f64; 3] {
    [0.0, 0.0, 1.0]
}

#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PressureSpec {
    pub surface: String,
    /// Pa (positive pushes into the body).
    pub value: f64,
}

#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactSpec {
    pub name: String,
    /// Slave surface (the pad).
    pub slave: String,
    /// Master surface (the disc).
    pub master: String,
    pub friction: f64,
    /// Penalty per unit area; default 10 E_min / h.
    pub penalty: Option<f64>,
    #[serde(default = "yes")]
    pub separation: bool,
    /// Friction direction: disc rotation, fixed, or none.
    #[serde(default = "no_sliding")]
    pub sliding: SlidingDirection,
    /// Whether the friction sweep sets this pair's mu.
    #[serde(default)]
    pub sweep: bool,
    /// `steady-sliding` (friction `mu p` along `sliding` wherever closed: the disc under
    /// the pads) or `coulomb` (stick and slip, for surfaces with no imposed sliding).
    #[serde(default)]
    pub friction_law: FrictionLawName,
    /// Coulomb pairs: tangential stiffness per unit area while sticking (Pa/m); default the
    /// penalty / 100.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stick_stiffness: Option<f64>,
}

/// The friction law of a contact pair, as a study file names it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum FrictionLawName {
    #[default]
    SteadySliding,
    Coulomb,
}

fn yes() -> bool {
    true
}

fn no_sliding() -> SlidingDirection {
    SlidingDirection::None
}
