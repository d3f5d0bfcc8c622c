//! Quadratic eigenvalue problems (SLEPc `PEP`): (K + lambda C + lambda^2 M) x = 0, the damped
//! complex eigenvalue analysis.

use super::eps::EigenSummary;
use super::error::{check, PetscError, Result};
use super::ksp::{configure, LinearMethod};
use super::mat::Matrix;
use super::runtime::{Comm, Runtime};
use super::sys;
use super::vec::{to_int, Vector};
use num_complex::Complex64;
use std::marker::PhantomData;

#[derive(Clone, Debug, PartialEq)]
pub struct QuadraticOptions {
    /// The `count` eigenvalues closest to `target` (real: this build of SLEPc is real).
    pub target: f64,
    pub count: usize,
    pub tolerance: f64,
    pub max_iterations: usize,
    pub linear: LinearMethod,
}

impl Default for QuadraticOptions {
    fn default() -> Self {
        QuadraticOptions {
            target: 0.0,
            count: 10,
            tolerance: 1e-10,
            max_iterations: 1000,
            linear: LinearMethod::default(),
        }
    }
}

pub struct QuadraticEigenSolver<'rt> {
    raw: sys::PEP,
    requested: usize,
    converged: usize,
    _rt: PhantomData<&'rt Runtime>,
}

impl<'rt> QuadraticEigenSolver<'rt> {
    /// (K + lambda C + lambda^2 M) x = 0 (collective). `-pep_*` options override.
    pub fn new(
        comm: Comm<'rt>,
        k: &Matrix<'rt>,
        c: &Matrix<'rt>,
        m: &Matrix<'rt>,
        options: &QuadraticOptions,
    ) -> Result<Self> {
        let mut raw = std::ptr::null_mut();
        // SAFETY: out-pointer; the matrices outlive the solver's use.
        check(unsafe { sys::PEPCreate(comm.raw, &mut raw) })?;
        let solver = QuadraticEigenSolver {
            raw,
            requested: options.count,
            converged: 0,
            _rt: PhantomData,
        };
        let mut ops = [k.raw, c.raw, m.raw];
        // SAFETY: live handles; PEP copies the array of matrices.
        unsafe {
            check(sys::PEPSetOperators(raw, 3, ops.as_mut_ptr()))?;
            check(sys::PEPSetProblemType(raw, sys::PEP_GENERAL))?;
            check(sys::PEPSetType(raw, sys::PEPTOAR.as_ptr().cast()))?;
            check(sys::PEPSetDimensions(
                raw,
                to_int(options.count)?,
                sys::PETSC_DEFAULT,
                sys::PETSC_DEFAULT,
            ))?;
            check(sys::PEPSetTolerances(
                raw,
                options.tolerance,
                to_int(options.max_iterations)?,
            ))?;
            check(sys::PEPSetTarget(raw, options.target))?;
            check(sys::PEPSetWhichEigenpairs(raw, sys::PEP_TARGET_MAGNITUDE))?;
            let mut st = std::ptr::null_mut();
            check(sys::PEPGetST(raw, &mut st))?;
            check(sys::STSetType(st, sys::STSINVERT.as_ptr().cast()))?;
            let mut ksp = std::ptr::null_mut();
            check(sys::STGetKSP(st, &mut ksp))?;
            configure(ksp, &options.linear)?;
            check(sys::PEPSetFromOptions(raw))?;
        }
        Ok(solver)
    }

    /// Runs the solver (collective). Returns what it found, as for EPS: fewer converged
    /// pairs than requested is reported in the summary (with SLEPc's reason), not as an
    /// error.
    pub fn solve(&mut self) -> Result<EigenSummary> {
        let (mut nconv, mut its, mut reason) = (0, 0, 0);
        // SAFETY: live PEP; out-pointers to locals.
        unsafe {
            check(sys::PEPSolve(self.raw))?;
            check(sys::PEPGetConverged(self.raw, &mut nconv))?;
            check(sys::PEPGetIterationNumber(self.raw, &mut its))?;
            check(sys::PEPGetConvergedReason(self.raw, &mut reason))?;
        }
        self.converged = nconv as usize;
        Ok(EigenSummary {
            requested: self.requested,
            converged: self.converged,
            iterations: its as usize,
            reason,
        })
    }

    fn index(&self, i: usize) -> Result<sys::PetscInt> {
        if i >= self.converged {
            return Err(PetscError::Invalid(format!(
                "eigenpair {i} requested but {} converged",
                self.converged
            )));
        }
        to_int(i)
    }

    /// Pair i: eigenvalue, real and imaginary parts of the vector (collective).
    pub fn pair(
        &self,
        i: usize,
        template: &Vector<'rt>,
    ) -> Result<(Complex64, Vector<'rt>, Vector<'rt>)> {
        let i = self.index(i)?;
        let xr = template.duplicate()?;
        let xi = template.duplicate()?;
        let (mut re, mut im) = (0.0, 0.0);
        // SAFETY: index checked.
        check(unsafe { sys::PEPGetEigenpair(self.raw, i, &mut re, &mut im, xr.raw, xi.raw) })?;
        Ok((Complex64::new(re, im), xr, xi))
    }

    /// Relative backward error of pair i (collective).
    pub fn relative_error(&self, i: usize) -> Result<f64> {
        let i = self.index(i)?;
        let mut e = 0.0;
        // SAFETY: index checked.
        check(unsafe { sys::PEPComputeError(self.raw, i, sys::PEP_ERROR_BACKWARD, &mut e) })?;
        Ok(e)
    }
}

impl Drop for QuadraticEigenSolver<'_> {
    fn drop(&mut self) {
        // SAFETY: we own the handle.
        unsafe { sys::PEPDestroy(&mut self.raw) };
    }
}
