//! The built-in parametric disc brake: a solid disc clamped at its hub and two pads (friction
//! lining glued to a steel backplate) on either face, meshed with 10-node tetrahedra. squeal
//! uses it when the user gives no mesh, and the tests use it as a model of known geometry.
//!
//! Geometry (SI units), disc axis = z through the origin, disc mid-plane z = 0. Section
//! through the pad centre (r to the right, z up, not to scale):
//!
//! ```text
//!                                pad_inner_radius          pad_outer_radius
//!                                        +-------------------------+
//!                                        |  backplate (steel)      |  inboard pad: the
//!                                        +-------------------------+  piston presses here
//!                                        |  lining (friction mat.) |
//!   hub, clamped (disc_hub) +------------+-------------------------+----+  z = +t/2
//!                           |  disc (grey cast iron), solid             |
//!                           +------------+-------------------------+----+  z = -t/2
//!                    disc_inner_radius   |  lining                 |    disc_outer_radius
//!                                        +-------------------------+
//!                                        |  backplate              |  outboard pad: the
//!                                        +-------------------------+  caliper fingers
//! ```
//!
//! Seen from +z, both pads are centred on `pad_centre_deg` and their linings span
//! `pad_arc_deg`; each backplate extends `backplate_overhang_deg` beyond the lining at both
//! ends: the ears that bear on the bracket abutments.
//!
//! Every part is a structured block in cylindrical coordinates (r, theta, z), meshed by the
//! structured mesher ([`crate::mesh::structured`]): hexahedral cells split into 6 tetrahedra by
//! the Kuhn (Freudenthal) rule, which conforms across cells and across the theta = 0 / 2 pi
//! seam of the disc (a periodic axis). The mid-edge nodes sit at the parametric middle in
//! (r, theta, z): on the true circular arcs.
//! The friction lining and its backplate are one block (shared nodes); the disc and the pads
//! are separate blocks whose meshes do not match at the friction interface, as in an
//! industrial model, while the pad friction face lies exactly on the disc face plane when the
//! gap is zero.
//!
//! The disc is clamped at its inner edge (node set `disc_hub`); the hat is not modelled. The
//! pads are held by what a real caliper provides: normally by contact with the disc and by
//! the piston / caliper fingers (surfaces `backplate_inboard_piston`,
//! `backplate_outboard_caliper`), tangentially by the bracket abutments bearing on the
//! backplate ears (`pad_*_abutment_leading` / `_trailing`) and radially by the guides
//! (node sets `pad_*_guides`, the outer radial edge of the backplates), which the study
//! supports or ties to springs.
//!
//! The floating-caliper layout (`layout = "floating-caliper"`, presets `*-caliper`) adds the
//! piston, the caliper body and the bracket as meshed bodies (see `caliper.rs`): the study
//! then presses the piston and the caliper with the hydraulic pressure and the pads bear on
//! real bodies through the paper's Table 1 contact pairs.
//!
//! Files: `params.rs` (dimensions, materials, divisions, presets and their validation),
//! `parts.rs` (the grids and their mesh), `caliper.rs` (the floating-caliper layout's
//! bodies), `sets.rs` (named node sets and surfaces).

mod caliper;
mod params;
mod parts;
mod sets;
#[cfg(test)]
mod test_geometry;

pub use params::{
    preset, BrakeParams, Divisions, Elastic, Layout, Rotation, DEFAULT_PRESET, PRESETS,
};

use crate::mesh::{Mesh, MeshError};

/// Why a set of brake parameters cannot be meshed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BrakeError {
    /// A size that must be a finite number greater than zero.
    #[error("brake parameter `{name}` must be a finite number greater than zero (got {value})")]
    NotPositive { name: &'static str, value: f64 },
    /// A size that may be zero but must be finite and not negative.
    #[error("brake parameter `{name}` must be a finite number >= 0 (got {value})")]
    Negative { name: &'static str, value: f64 },
    /// A value that must merely be finite (an angle).
    #[error("brake parameter `{name}` must be a finite number (got {value})")]
    NotFinite { name: &'static str, value: f64 },
    /// A mesh division count out of its range.
    #[error("brake mesh division `{name}` must lie in {min}..={max} (got {value})")]
    Divisions {
        name: &'static str,
        value: usize,
        min: usize,
        max: usize,
    },
    /// A Poisson's ratio outside the range a stable isotropic solid allows.
    #[error("brake material `{material}`: Poisson's ratio must lie strictly between -1 and 0.5 (got {value})")]
    Poisson { material: &'static str, value: f64 },
    /// Parameters that are each fine but contradict one another.
    #[error("brake parameters: {0}")]
    Inconsistent(String),
    /// The mesh would be larger than the program is meant to handle.
    #[error("the brake mesh would have {nodes} nodes, more than the limit of {limit}; reduce the divisions")]
    TooLarge { nodes: u128, limit: u128 },
    /// An element came out with a non-positive Jacobian (cannot happen for parameters that
    /// pass the checks above; kept as an error rather than a panic).
    #[error("brake element {label} of part `{part}` has a non-positive Jacobian ({det:e}); the mesh is too coarse for its curvature")]
    Inverted { part: String, label: i64, det: f64 },
}

impl From<BrakeError> for MeshError {
    fn from(err: BrakeError) -> Self {
        MeshError::invalid("<built-in brake>", err.to_string())
    }
}

/// Builds the brake mesh. Node and element labels are 1-based and contiguous; nodes are
/// numbered block by block (disc, inboard pad, outboard pad, then piston, caliper and
/// bracket for the floating-caliper layout), theta-major.
pub fn build(params: &BrakeParams) -> Result<Mesh, BrakeError> {
    params.validate()?;
    let (mut mesh, meshed) = parts::mesh(params)?;
    sets::add(&mut mesh, params, &meshed);
    Ok(mesh)
}
