//! The PETSc/SLEPc layer: the only module with `unsafe` and FFI. Everything above it sees
//! owned Rust values whose `Drop` destroys the PETSc object, and `Result`s carrying PETSc's
//! own messages.
// The crate denies `unsafe_code` (src/lib.rs); this module is the one place allowed it.
#![allow(unsafe_code)]

mod dense;
mod eps;
mod error;
mod factor;
mod inertia;
mod is;
mod ksp;
mod lapack;
mod left;
mod mat;
mod pep;
mod runtime;
mod snes;
mod sparse_dense;
pub mod sys;
mod vec;

pub use dense::{columns_to_faer, DenseMatrix};
pub use eps::{EigenOptions, EigenProblem, EigenSolver, EigenSummary, Spectrum};
pub use error::{PetscError, Result};
pub use factor::FactoredMatrix;
pub use inertia::eigenvalues_below;
pub use is::IndexSet;
pub use ksp::{DirectPackage, Factorization, LinearMethod, LinearSolver};
pub use lapack::{eigenpairs, invariant_subspace};
pub use left::LeftSolver;
pub use mat::{Matrix, RowPattern, Structure};
pub use pep::{QuadraticEigenSolver, QuadraticOptions};
pub use runtime::{Comm, Runtime, RuntimeOptions};
pub use snes::{format_history, JacobianChange, NewtonOptions, NewtonReport, NonlinearSolver};
pub use sys::PetscInt;
pub use vec::Vector;
