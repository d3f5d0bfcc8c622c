//! The numerical checks that run squeal's library on PETSc: each one in its own `mpirun` job
//! on 1 and 2 ranks (`common/harness.rs`), verified against an independent answer and
//! compared between the rank counts. One test binary for all of them: each binary links the
//! whole crate with PETSc, SLEPc and MPI (about 2.4 s a link), and in one binary the checks
//! of all files share the cores instead of waiting at each file's end for its slowest one.
//!
//! A check is named `file::check`: `cargo test --release --test numerics -- structure::`
//! runs one file's checks.

#[path = "../common/mod.rs"]
mod common;
#[path = "../reference/mod.rs"]
mod reference;

mod body_energy;
mod cea;
mod contact_statics;
mod coulomb_statics;
mod deck_constraints;
mod deck_discrete;
mod floating_caliper;
mod petsc_wrappers;
mod reduced_interface;
mod structure;
mod superelement;

fn main() {
    common::harness::main(&[
        ("body_energy", body_energy::CHECKS),
        ("cea", cea::CHECKS),
        ("contact_statics", contact_statics::CHECKS),
        ("coulomb_statics", coulomb_statics::CHECKS),
        ("deck_constraints", deck_constraints::CHECKS),
        ("deck_discrete", deck_discrete::CHECKS),
        ("floating_caliper", floating_caliper::CHECKS),
        ("petsc_wrappers", petsc_wrappers::CHECKS),
        ("reduced_interface", reduced_interface::CHECKS),
        ("structure", structure::CHECKS),
        ("superelement", superelement::CHECKS),
    ]);
}
