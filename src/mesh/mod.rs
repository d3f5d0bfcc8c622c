//! The mesh stage: the model's geometry and topology as plain Rust data, the readers that
//! make it from files, and the built-in brake.

pub mod abaqus;
pub mod block;
pub mod brake;
mod error;
mod model;

pub use error::MeshError;
pub use model::*;
