//! What a user asks for: one function per subcommand, called by `main.rs`.

pub mod bench;
pub mod info;
pub mod model;
pub mod modes;
pub mod report;
pub mod write_mesh;
