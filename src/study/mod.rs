//! What a user asks for: one function per subcommand, called by `main.rs`. Every one
//! returns a [`StudyError`] on failure.

pub mod assemble;
pub mod bench;
pub mod blas;
pub mod blas_kernel;
pub mod cea;
pub mod compare;
pub mod config;
pub mod error;
pub mod info;
pub mod interrupt;
pub mod manifest;
pub mod modes;
pub mod ownership;
pub mod paths;
pub mod pipeline;
pub mod plot;
pub mod progress;
pub mod radius;
pub mod reduction_spec;
pub mod report;
pub mod run;
pub mod staging;
pub mod sweep;
pub mod write_mesh;

pub use error::StudyError;
