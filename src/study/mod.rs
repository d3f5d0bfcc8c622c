//! What a user asks for: one function per subcommand, called by `main.rs`.

pub mod assemble;
pub mod bench;
pub mod blas;
pub mod cea;
pub mod compare;
pub mod config;
pub mod info;
pub mod modes;
pub mod plot;
pub mod radius;
pub mod report;
pub mod sweep;
pub mod write_mesh;
