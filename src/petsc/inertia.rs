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
    let mut ksp = std::ptr::null_mut();
    // SAFETY: out-pointer to a local.
    check(unsafe { sys::KSPCreate(comm.raw, &mut ksp) })?;
    let solver = Ksp(ksp);
    let mut negative: sys::PetscInt = 0;
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
        check(sys::KSPSetFromOptions(solver.0))?;
        check(sys::KSPSetUp(solver.0))?;
        let failure = failure_detail(solver.0)?;
        if !comm.all(failure.is_none()) {
            return Err(PetscError::NotConverged {
                what: format!("LDL^T factorisation for the inertia at {sigma:e}"),
                detail: failure.unwrap_or_else(|| "failed on another rank".into()),
            });
        }
        // The factor may have been replaced by KSPSetFromOptions/KSPSetUp: ask again.
        check(sys::PCFactorGetMatrix(pc, &mut factor))?;
        check(sys::MatGetInertia(
            factor,
            &mut negative,
            std::ptr::null_mut(),
            std::ptr::null_mut(),
        ))?;
    }
    usize::try_from(negative)
        .map_err(|_| PetscError::Invalid(format!("negative inertia count {negative}")))
}

/// Owns a KSP for the span of one function, so every early return destroys it.
struct Ksp(sys::KSP);

impl Drop for Ksp {
    fn drop(&mut self) {
        // SAFETY: we own the handle.
        unsafe { sys::KSPDestroy(&mut self.0) };
    }
}
