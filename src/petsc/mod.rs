//! The PETSc/SLEPc layer: the only module with `unsafe` and FFI. Everything above it sees
//! owned Rust values whose `Drop` destroys the PETSc object, and `Result`s carrying PETSc's
//! own messages.

mod eps;
mod error;
mod ksp;
mod mat;
mod pep;
mod runtime;
mod snes;
pub mod sys;
mod vec;

pub use eps::{EigenOptions, EigenProblem, EigenSolver, EigenSummary, Spectrum};
pub use error::{PetscError, Result};
pub use ksp::{DirectPackage, Factorization, LinearMethod, LinearSolver};
pub use mat::{Matrix, RowPattern, Structure};
pub use pep::{QuadraticEigenSolver, QuadraticOptions};
pub use runtime::{Comm, Runtime, RuntimeOptions};
pub use snes::{format_history, JacobianChange, NewtonOptions, NewtonReport, NonlinearSolver};
pub use sys::PetscInt;
pub use vec::Vector;
