//! How many eigenvalues of a symmetric pencil (A, B), B positive definite, lie below a shift:
//! by Sylvester's law of inertia, the number of negative pivots of the LDL^T factorisation of
//! A - sigma B. One factorisation gives an exact count, which is what lets a single
//! shift-and-invert run prove that it found a whole band (`analysis::modes`).

use super::error::{check, PetscError, Result};
use super::ksp::{configure, failure_detail, DirectPackage, Factorization, LinearMethod};
use super::mat::Matrix;
use super::runtime::Comm;
use super::sys;

/// The number of eigenvalues lambda < `sigma` of A x = lambda B x (A, B symmetric, B positive
/// definite, both created on `comm`): the negative pivots of MUMPS's LDL^T of A - sigma B.
/// Collective; every rank gets the same count. A factorisation that fails (an eigenvalue
/// exactly at `sigma` makes A - sigma B singular) is an `Err` on every rank.
///
/// MUMPS is the only package here that reports the inertia of a parallel factorisation, and
/// only with ICNTL(13) = 1 (no ScaLAPACK on the root front), as SLEPc's spectrum slicing
/// also requires. Options with the prefix `squeal_inertia_` (e.g.
/// `-squeal_inertia_mat_mumps_icntl_14 40`) reach this factorisation alone.
pub fn eigenvalues_below<'rt>(
    comm: Comm<'rt>,
    a: &Matrix<'rt>,
    b: &Matrix<'rt>,
    sigma: f64,
) -> Result<usize> {
    let mut shifted = a.duplicate()?;
    // SAFETY: both matrices are live; UNKNOWN lets PETSc find out whether the patterns agree
    // (they do for an assembled K and M, and the sum is then done in place, without the
    // preallocation pass DIFFERENT would cost).
    check(unsafe { sys::MatAXPY(shifted.raw, -sigma, b.raw, sys::UNKNOWN_NONZERO_PATTERN) })?;
    shifted.mark_symmetric()?;
    // A - sigma B is indefinite, so MUMPS pivots 2x2 and delays pivots it cannot take, and
    // the fronts then outgrow the workspace its analysis estimated (INFOG(1) = -8 or -9):
    // which pivots are delayed depends on round-off, so one CPU's BLAS fits where another's
    // does not (CI once failed so on a tiny brake's super-element). MUMPS's remedy is a
    // larger ICNTL(14), the estimate's relaxation in percent: each retry doubles it.
    let mut relaxation = None;
    for _ in 0..=WORKSPACE_RETRIES {
        match factorise(comm, &shifted, relaxation)? {
            Attempt::Counted(negative) => {
                return usize::try_from(negative)
                    .map_err(|_| PetscError::Invalid(format!("negative inertia count {negative}")))
            }
            Attempt::Failed { detail, workspace } => match workspace {
                // A relaxation the options pin (`-squeal_inertia_mat_mumps_icntl_14`) wins
                // over ours: retrying would fail the same way.
                Some(used) if used < MAX_RELAXATION && relaxation.is_none_or(|r| r == used) => {
                    let next = (2 * used).clamp(2 * DEFAULT_RELAXATION, MAX_RELAXATION);
                    tracing::info!(
                        "LDL^T at {sigma:e} outgrew MUMPS's workspace with ICNTL(14) = \
                         {used}: refactorising with {next}"
                    );
                    relaxation = Some(next);
                }
                _ => {
                    return Err(PetscError::NotConverged {
                        what: format!("LDL^T factorisation for the inertia at {sigma:e}"),
                        detail,
                    })
                }
            },
        }
    }
    Err(PetscError::NotConverged {
        what: format!("LDL^T factorisation for the inertia at {sigma:e}"),
        detail: format!(
            "MUMPS's workspace too small even with ICNTL(14) = {}",
            relaxation.unwrap_or(MAX_RELAXATION)
        ),
    })
}

/// How many times a factorisation that outgrew its workspace is retried, and the largest
/// relaxation asked for (MUMPS allocates, it does not touch, what a front does not use).
const WORKSPACE_RETRIES: usize = 4;
const MAX_RELAXATION: sys::PetscInt = 1000;
/// MUMPS's default ICNTL(14): a retry asks for at least twice it.
const DEFAULT_RELAXATION: sys::PetscInt = 20;

enum Attempt {
    Counted(sys::PetscInt),
    /// Why it failed on some rank, and the ICNTL(14) it had when the failure was MUMPS's
    /// workspace (INFOG(1) = -8, -9, -11, -12, -14, -15), the failure a larger one cures.
    Failed {
        detail: String,
        workspace: Option<sys::PetscInt>,
    },
}

/// One LDL^T of `shifted` and its negative pivots; `relaxation` sets ICNTL(14). Collective:
/// every rank gets the same outcome.
fn factorise<'rt>(
    comm: Comm<'rt>,
    shifted: &Matrix<'rt>,
    relaxation: Option<sys::PetscInt>,
) -> Result<Attempt> {
    let mut ksp = std::ptr::null_mut();
    // SAFETY: out-pointer to a local.
    check(unsafe { sys::KSPCreate(comm.raw, &mut ksp) })?;
    let solver = Ksp(ksp);
    let negative;
    // SAFETY: live KSP and matrix; the factor matrix belongs to the PC (not destroyed here);
    // the prefix is NUL-terminated.
    unsafe {
        check(sys::KSPSetOptionsPrefix(
            solver.0,
            c"squeal_inertia_".as_ptr(),
        ))?;
        check(sys::KSPSetOperators(solver.0, shifted.raw, shifted.raw))?;
        configure(
            solver.0,
            &LinearMethod::Direct {
                package: DirectPackage::Mumps,
                factorization: Factorization::Cholesky,
            },
        )?;
        let mut pc = std::ptr::null_mut();
        check(sys::KSPGetPC(solver.0, &mut pc))?;
        // The factor matrix exists only once the solver type is fixed; ICNTL(13) must be set
        // on it before the factorisation.
        check(sys::PCFactorSetUpMatSolverType(pc))?;
        let mut factor = std::ptr::null_mut();
        check(sys::PCFactorGetMatrix(pc, &mut factor))?;
        check(sys::MatMumpsSetIcntl(factor, 13, 1))?;
        // PETSc 3.18 gives the factor matrix no prefix of the solver's, so without this
        // `-squeal_inertia_mat_mumps_*` would be left unused.
        check(sys::MatSetOptionsPrefix(
            factor,
            c"squeal_inertia_".as_ptr(),
        ))?;
        check(sys::KSPSetFromOptions(solver.0))?;
        // The factor may have been replaced by KSPSetFromOptions: ask again. PETSc reads
        // the options at the factorisation, so an ICNTL(14) they give beats a retry's.
        check(sys::PCFactorGetMatrix(pc, &mut factor))?;
        if let Some(percent) = relaxation {
            check(sys::MatMumpsSetIcntl(factor, 14, percent))?;
        }
        check(sys::KSPSetUp(solver.0))?;
        let failure = failure_detail(solver.0)?;
        check(sys::PCFactorGetMatrix(pc, &mut factor))?;
        let workspace = match failure {
            Some(_) => {
                let mut infog1: sys::PetscInt = 0;
                let mut icntl14: sys::PetscInt = 0;
                check(sys::MatMumpsGetInfog(factor, 1, &mut infog1))?;
                check(sys::MatMumpsGetIcntl(factor, 14, &mut icntl14))?;
                matches!(infog1, -8 | -9 | -11 | -12 | -14 | -15).then_some(icntl14)
            }
            None => None,
        };
        // INFOG is global, so every failing rank agrees on the cause; a rank whose part
        // factorised says nothing, and the largest relaxation among the failing ones wins.
        let failed = !comm.all(failure.is_none());
        if failed {
            let mut largest = [workspace.map_or(-1.0, f64::from)];
            comm.max_in_place(&mut largest);
            return Ok(Attempt::Failed {
                detail: failure.unwrap_or_else(|| "failed on another rank".into()),
                workspace: (largest[0] >= 0.0).then_some(largest[0] as sys::PetscInt),
            });
        }
        negative = negative_pivots(factor)?;
    }
    Ok(Attempt::Counted(negative))
}

/// The negative pivots of a factorised LDL^T (MUMPS's global count: the same on every rank).
///
/// # Safety
/// `factor` is a live, factorised matrix (in parallel, MUMPS's with ICNTL(13) = 1).
pub(super) unsafe fn negative_pivots(factor: sys::Mat) -> Result<sys::PetscInt> {
    let mut negative: sys::PetscInt = 0;
    check(sys::MatGetInertia(
        factor,
        &mut negative,
        std::ptr::null_mut(),
        std::ptr::null_mut(),
    ))?;
    Ok(negative)
}

/// Owns a KSP for the span of one function, so every early return destroys it.
struct Ksp(sys::KSP);

impl Drop for Ksp {
    fn drop(&mut self) {
        // SAFETY: we own the handle.
        unsafe { sys::KSPDestroy(&mut self.0) };
    }
}
