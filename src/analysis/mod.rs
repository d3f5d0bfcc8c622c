//! What is solved on a model of any size: real modes, static equilibrium, complex
//! eigenvalues. Every analysis takes assembled operators, not meshes.

pub mod band_count;
pub mod block_krylov_schur;
pub mod block_lanczos;
pub mod blocks;
pub mod cea;
pub mod cea_window;
pub mod contact_edge;
pub mod continuation;
pub mod growth;
pub mod modes;
pub mod operators;
pub mod parallel_factor;
pub mod pencil;
pub mod replicated_factor;
pub mod restraint;
pub mod rigid;
pub mod sensitivity;
pub mod spectrum_match;
pub mod statics;
pub mod tracking;
