//! The tests of squeal as a program: its commands run under `mpirun -n 2` on meshes, decks
//! and studies (`*_cli`, `deck_*`), their outputs and refusals, the build's probe of PETSc,
//! the reference solutions other tests lean on, and the source's layout. One test binary for
//! all of them: each binary links the whole crate with PETSc, SLEPc and MPI, and in one
//! binary the tests of all files share the cores instead of waiting at each file's end for
//! its slowest one.
//!
//! A test is named `file::test`: `cargo test --release --test program -- sweep_cli::` runs
//! one file's tests.

#[path = "../common/mod.rs"]
mod common;
#[path = "../reference/mod.rs"]
mod reference;

mod build_probe;
mod cli;
mod contact_free_superelement;
mod deck_contact;
mod deck_steps;
mod layout;
mod model_sources;
mod modes_cli;
mod outputs_cli;
mod reference_solutions;
mod refine_cli;
mod refusals_cli;
mod sensitivity_cli;
mod study_cli;
mod superelement_sweep;
mod sweep_cli;
