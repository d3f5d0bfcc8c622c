//! What a user asks for: one function per subcommand, called by `main.rs`.

pub mod info;
