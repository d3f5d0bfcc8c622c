//! The mesh stage: the model's geometry and topology as plain Rust data, the built-in brake
//! and the block mesher, and the errors of reading and writing meshes (the readers and
//! writers themselves are in [`crate::io`]).

pub mod block;
pub mod brake;
mod error;
#[cfg(test)]
mod fingerprint;
pub mod hash;
mod model;
pub mod structured;

pub use error::MeshError;
pub use model::*;
