//! Linear solvers (`KSP`): direct factorisations with a named parallel package, or a
//! preconditioned Krylov method. The same configuration serves SNES's linear steps and the
//! shift-and-invert transforms of EPS and PEP.

use super::error::{check, PetscError, Result};
use super::mat::Matrix;
use super::runtime::{Comm, Runtime};
use super::sys;
use super::vec::Vector;
use std::ffi::CString;
use std::marker::PhantomData;

/// Which package factorises. PETSc's own LU runs on one rank only; MUMPS and SuperLU_dist
/// are the parallel direct solvers Debian's PETSc has.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DirectPackage {
    Mumps,
    SuperluDist,
    Petsc,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Factorization {
    Lu,
    /// For symmetric matrices (MUMPS LDL^T; also gives the inertia for spectrum slicing).
    Cholesky,
}

/// How to solve A x = b.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LinearMethod {
    Direct {
        package: DirectPackage,
        factorization: Factorization,
    },
    /// A Krylov method (`"gmres"`, `"cg"`...) with a preconditioner (`"gamg"`, `"hypre"`...).
    Iterative {
        method: String,
        preconditioner: String,
        relative_tolerance: f64,
    },
}

impl Default for LinearMethod {
    fn default() -> Self {
        LinearMethod::Direct {
            package: DirectPackage::Mumps,
            factorization: Factorization::Lu,
        }
    }
}

fn cstring(s: &str) -> Result<CString> {
    CString::new(s).map_err(|_| PetscError::Invalid(format!("NUL in {s:?}")))
}

/// Applies `method` to a KSP that PETSc or SLEPc owns (ours, SNES's or ST's).
pub(super) fn configure(ksp: sys::KSP, method: &LinearMethod) -> Result<()> {
    let mut pc = std::ptr::null_mut();
    // SAFETY: ksp is live; the type names are NUL-terminated constants or CStrings that
    // outlive the calls (PETSc copies them).
    unsafe {
        check(sys::KSPGetPC(ksp, &mut pc))?;
        match method {
            LinearMethod::Direct {
                package,
                factorization,
            } => {
                check(sys::KSPSetType(ksp, sys::KSPPREONLY.as_ptr().cast()))?;
                let pc_type = match factorization {
                    Factorization::Lu => sys::PCLU.as_ptr(),
                    Factorization::Cholesky => sys::PCCHOLESKY.as_ptr(),
                };
                check(sys::PCSetType(pc, pc_type.cast()))?;
                let solver = match package {
                    DirectPackage::Mumps => sys::MATSOLVERMUMPS.as_ptr(),
                    DirectPackage::SuperluDist => sys::MATSOLVERSUPERLU_DIST.as_ptr(),
                    DirectPackage::Petsc => sys::MATSOLVERPETSC.as_ptr(),
                };
                check(sys::PCFactorSetMatSolverType(pc, solver.cast()))?;
            }
            LinearMethod::Iterative {
                method,
                preconditioner,
                relative_tolerance,
            } => {
                let m = cstring(method)?;
                let p = cstring(preconditioner)?;
                check(sys::KSPSetType(ksp, m.as_ptr()))?;
                check(sys::PCSetType(pc, p.as_ptr()))?;
                check(sys::KSPSetTolerances(
                    ksp,
                    *relative_tolerance,
                    sys::PETSC_DEFAULT as f64,
                    sys::PETSC_DEFAULT as f64,
                    sys::PETSC_DEFAULT,
                ))?;
            }
        }
    }
    Ok(())
}

/// Why a KSP stopped, as PETSc names it, and the preconditioner's failure if any.
pub(super) fn failure_detail(ksp: sys::KSP) -> Result<Option<String>> {
    let mut reason = 0;
    // SAFETY: out-pointers to locals; reason strings are static.
    unsafe {
        check(sys::KSPGetConvergedReason(ksp, &mut reason))?;
        if reason >= 0 {
            return Ok(None);
        }
        let mut text = std::ptr::null();
        check(sys::KSPGetConvergedReasonString(ksp, &mut text))?;
        let mut detail = std::ffi::CStr::from_ptr(text)
            .to_string_lossy()
            .into_owned();
        let mut pc = std::ptr::null_mut();
        check(sys::KSPGetPC(ksp, &mut pc))?;
        let mut pc_reason = 0;
        check(sys::PCGetFailedReason(pc, &mut pc_reason))?;
        if pc_reason != sys::PC_NOERROR {
            let why = match pc_reason {
                sys::PC_FACTOR_STRUCT_ZEROPIVOT | sys::PC_FACTOR_NUMERIC_ZEROPIVOT => {
                    "zero pivot in the factorisation: the matrix is singular \
                     (a part not held against rigid-body motion?)"
                }
                sys::PC_FACTOR_OUTMEMORY => "out of memory in the factorisation",
                _ => "the preconditioner failed",
            };
            detail.push_str(&format!(" ({why})"));
        }
        Ok(Some(detail))
    }
}

/// A linear solver bound to one operator.
pub struct LinearSolver<'rt> {
    raw: sys::KSP,
    _rt: PhantomData<&'rt Runtime>,
}

impl<'rt> LinearSolver<'rt> {
    /// Sets up the solver for `a` (collective). PETSc options (`-ksp_*`, `-pc_*`,
    /// `-mat_mumps_*`) given at start-up override `method`.
    pub fn new(comm: Comm<'rt>, a: &Matrix<'rt>, method: &LinearMethod) -> Result<Self> {
        let mut raw = std::ptr::null_mut();
        // SAFETY: out-pointer; `a` is live and outlives the factorisation (PETSc references it).
        unsafe {
            check(sys::KSPCreate(comm.raw, &mut raw))?;
            let s = LinearSolver {
                raw,
                _rt: PhantomData,
            };
            check(sys::KSPSetOperators(raw, a.raw, a.raw))?;
            configure(raw, method)?;
            check(sys::KSPSetFromOptions(raw))?;
            Ok(s)
        }
    }

    /// Factorises (direct) or builds the preconditioner now (collective); otherwise the first
    /// solve does it.
    pub fn set_up(&mut self) -> Result<()> {
        // SAFETY: live KSP.
        check(unsafe { sys::KSPSetUp(self.raw) })?;
        match failure_detail(self.raw)? {
            None => Ok(()),
            Some(detail) => Err(PetscError::NotConverged {
                what: "factorisation".into(),
                detail,
            }),
        }
    }

    /// Solves A x = b (collective). Returns the iteration count; a failed factorisation or a
    /// Krylov method that does not converge is an `Err` saying why.
    pub fn solve(&mut self, b: &Vector<'rt>, x: &mut Vector<'rt>) -> Result<usize> {
        // SAFETY: live objects; PETSc checks layouts.
        check(unsafe { sys::KSPSolve(self.raw, b.raw, x.raw) })?;
        if let Some(detail) = failure_detail(self.raw)? {
            return Err(PetscError::NotConverged {
                what: "linear solve".into(),
                detail,
            });
        }
        let mut its = 0;
        // SAFETY: out-pointer.
        check(unsafe { sys::KSPGetIterationNumber(self.raw, &mut its) })?;
        Ok(its as usize)
    }
}

impl Drop for LinearSolver<'_> {
    fn drop(&mut self) {
        // SAFETY: we own the handle.
        unsafe { sys::KSPDestroy(&mut self.raw) };
    }
}
