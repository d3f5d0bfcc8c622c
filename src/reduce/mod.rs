//! The reduced contact interface (METHOD.md section 5; the paper's sections 3.1, 3.3, 4.1),
//! its pure-geometry half: plain Rust data, no PETSc, so that the reduced-interface model and
//! the Craig-Bampton super-elements can be built on it.
//!
//! - [`grid`]: the reduced contact nodes, an isometric (equilateral triangular) grid laid on a
//!   pad friction surface in its mean plane ([`isometric_grid`], [`GridSize`]), each node with
//!   its position and normal on the surface and its tributary area.
//! - [`coupling`]: the distributing coupling of a reference point to the surface nodes within
//!   the radius of influence ([`distributing_coupling`], [`Weighting`]), forces only.
//! - [`interface`]: the reduced-interface model, the full model with its swept pairs
//!   replaced by node-to-node contacts between reduced contact nodes ([`reduce_interface`]).
//! - [`pairs`]: which pairs are reduced (the swept ones, all, or named kept pairs too) and
//!   each kept pair's grid.
//! - [`superelement`]: the Craig-Bampton super-element as plain data (the contract with the
//!   dense assembly); [`craig_bampton`] builds one from a reduced-interface model at a static
//!   equilibrium ([`build_superelement`], [`build_with_basis`] to keep T for expansions).
//! - [`radius`]: the optimal radius of influence per weighting degree, the paper's elementary
//!   triangle (Table 2) and the whole-grid optimum ([`radius_table`]).
//! - [`superelement`]: the Craig-Bampton super-element as plain data (the contract between its
//!   builder and the dense assembly); [`superelement_file`]: its checked file format.
//! - [`basis`]: the basis T kept as each rank's rows, for expansions u = T q and for the
//!   reduced coordinates of another equilibrium ([`LocalBasis`]).
//! - [`strategy`]: which super-element serves each friction value (single, per-friction,
//!   adaptive: rebuilt only when a kept contact changes state).
//! - [`assembly`]: the dense super-element assembly: cubic node-to-node contact with force
//!   matching (eq. 8), the reduced Newton static at any mu, and the dense CEA;
//!   [`dense_path`]: that static along a sweep's path (load ramp, friction steps), carrying
//!   the slip history of kept Coulomb pairs reduced onto the boundary.

pub mod assembly;
pub mod basis;
pub mod constraint_modes;
pub mod coupling;
pub mod craig_bampton;
pub mod dense_cea;
pub mod dense_path;
mod error;
pub mod grid;
pub mod interface;
mod interface_summary;
pub mod pairs;
pub mod radius;
pub mod residual_vectors;
pub mod strategy;
pub mod superelement;
pub mod superelement_file;
pub mod tangent_solver;
pub mod tilt;
pub mod warp;

pub use basis::{CoordinatesError, LocalBasis};
pub use coupling::{
    couple_grid, couple_points, distributing_coupling, CouplingNode, DistributingCoupling,
    Weighting,
};
pub use craig_bampton::{
    build_superelement, build_with_basis, reproject, BuildSettings, CraigBampton, SuperElementError,
};
pub use error::ReduceError;
pub use grid::{isometric_grid, ContactGrid, GridSize, MeanPlane, ReducedNode};
pub use interface::{
    reduce_interface, DiscCoupling, InterfaceSettings, PadCoupling, RadiusChoice, ReducedInterface,
    ReducedPad,
};
pub use pairs::{PairGrid, ReducePairs};
pub use radius::{radius_table, table_text, DegreeRadius, RadiusTable};
pub use strategy::{decide, Decision, Step, Strategy};
pub use tilt::PatchQuadrature;
