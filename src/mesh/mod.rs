//! The mesh stage: the model's geometry and topology as plain Rust data, the readers that
//! make it from files, the built-in brake, and the VTU writer that shows it.

pub mod abaqus;
pub mod block;
pub mod brake;
mod error;
#[cfg(test)]
mod fingerprint;
pub mod gmsh;
mod model;
pub mod structured;
pub mod vtu;

pub use error::MeshError;
pub use model::*;
