//! Linear eigenvalue problems (SLEPc `EPS`): A x = lambda B x, Hermitian or not, with
//! shift-and-invert around a target through a direct factorisation. Partial convergence is a
//! result that says how many pairs converged, never a panic.

use super::error::{check, PetscError, Result};
use super::ksp::{configure, failure_detail, DirectPackage, Factorization, LinearMethod};
use super::mat::Matrix;
use super::runtime::{Comm, Runtime};
use super::sys;
use super::vec::{to_int, Vector};
use num_complex::Complex64;
use std::marker::PhantomData;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EigenProblem {
    /// A, B symmetric, B positive definite (real modes).
    HermitianGeneralized,
    /// A unsymmetric (friction), B = mass.
    NonHermitianGeneralized,
    /// A x = lambda x, A symmetric.
    Hermitian,
    /// A x = lambda x.
    NonHermitian,
}

/// Which eigenvalues to compute.
#[derive(Clone, Debug, PartialEq)]
pub enum Spectrum {
    /// The `count` eigenvalues closest to `target` (shift-and-invert about it).
    NearTarget { target: f64, count: usize },
    /// Every eigenvalue in [low, high] (Hermitian problems only: spectrum slicing with the
    /// inertia of LDL^T factorisations, so none is missed or found twice).
    Interval { low: f64, high: f64 },
    /// The `count` eigenvalues of largest magnitude (no transform).
    Largest { count: usize },
}

#[derive(Clone, Debug, PartialEq)]
pub struct EigenOptions {
    pub problem: EigenProblem,
    pub spectrum: Spectrum,
    /// Relative tolerance of the residual.
    pub tolerance: f64,
    pub max_iterations: usize,
    /// Factorisation of (A - target B) for shift-and-invert.
    pub linear: LinearMethod,
    /// Krylov subspace size (SLEPc's ncv) for `NearTarget` and `Largest`; SLEPc's default
    /// (about twice the count) when `None`.
    pub subspace: Option<usize>,
    /// SLEPc's eigenvector purification after a generalised Hermitian shift-and-invert solve
    /// (one more operator application, a triangular solve, per converged pair): it removes
    /// the components in B's null space that a singular B lets into the vectors. Useless
    /// where B is positive definite; SLEPc's default (on) otherwise. A user's
    /// `-eps_purify` still wins.
    pub purify: bool,
    /// The shift-and-invert factorisation reports its inertia, so that
    /// [`EigenSolver::eigenvalues_below`] can count on it after a solve: MUMPS's ICNTL(13) = 1
    /// (no ScaLAPACK on the root front), the parallel inertia's condition. For a `NearTarget`
    /// solver with MUMPS's Cholesky; ignored otherwise.
    pub inertia: bool,
}

impl Default for EigenOptions {
    fn default() -> Self {
        EigenOptions {
            problem: EigenProblem::HermitianGeneralized,
            spectrum: Spectrum::NearTarget {
                target: 0.0,
                count: 10,
            },
            tolerance: 1e-10,
            max_iterations: 1000,
            linear: LinearMethod::default(),
            subspace: None,
            purify: true,
            inertia: false,
        }
    }
}

/// What an eigen-solve (EPS or PEP) found.
#[derive(Clone, Debug, PartialEq)]
pub struct EigenSummary {
    /// How many pairs were asked for (0 for an interval: unknown in advance).
    pub requested: usize,
    pub converged: usize,
    pub iterations: usize,
    /// SLEPc's reason code, EPSConvergedReason or PEPConvergedReason (both: 1 converged to
    /// the tolerance, -1 out of iterations, -2 breakdown; negative: stopped before all
    /// requested pairs converged).
    pub reason: i32,
}

pub struct EigenSolver<'rt> {
    pub(super) raw: sys::EPS,
    summary: Option<EigenSummary>,
    requested: usize,
    /// Whether [`Self::eigenvalues_below`] moved the transform's shift off the target, to
    /// be put back before the next solve.
    moved: bool,
    _rt: PhantomData<&'rt Runtime>,
}

impl<'rt> EigenSolver<'rt> {
    /// Sets up the problem A x = lambda B x (collective). SLEPc options (`-eps_*`, `-st_*`)
    /// given at start-up override `options`.
    pub fn new(
        comm: Comm<'rt>,
        a: &Matrix<'rt>,
        b: Option<&Matrix<'rt>>,
        options: &EigenOptions,
    ) -> Result<Self> {
        let mut raw = std::ptr::null_mut();
        // SAFETY: out-pointer; matrices are live and outlive the solver's use of them
        // (SLEPc holds references).
        check(unsafe { sys::EPSCreate(comm.raw, &mut raw) })?;
        let mut solver = EigenSolver {
            raw,
            summary: None,
            requested: 0,
            moved: false,
            _rt: PhantomData,
        };
        let problem = match options.problem {
            EigenProblem::HermitianGeneralized => sys::EPS_GHEP,
            EigenProblem::NonHermitianGeneralized => sys::EPS_GNHEP,
            EigenProblem::Hermitian => sys::EPS_HEP,
            EigenProblem::NonHermitian => sys::EPS_NHEP,
        };
        // SAFETY: live handles; constants are NUL-terminated.
        unsafe {
            check(sys::EPSSetOperators(
                raw,
                a.raw,
                b.map_or(std::ptr::null_mut(), |b| b.raw),
            ))?;
            check(sys::EPSSetProblemType(raw, problem))?;
            check(sys::EPSSetType(raw, sys::EPSKRYLOVSCHUR.as_ptr().cast()))?;
            check(sys::EPSSetTolerances(
                raw,
                options.tolerance,
                to_int(options.max_iterations)?,
            ))?;
            let mut st = std::ptr::null_mut();
            check(sys::EPSGetST(raw, &mut st))?;
            match options.spectrum {
                Spectrum::NearTarget { target, count } => {
                    solver.requested = count;
                    let ncv = match options.subspace {
                        Some(n) => to_int(n)?,
                        None => sys::PETSC_DEFAULT,
                    };
                    check(sys::EPSSetDimensions(
                        raw,
                        to_int(count)?,
                        ncv,
                        sys::PETSC_DEFAULT,
                    ))?;
                    check(sys::EPSSetTarget(raw, target))?;
                    check(sys::EPSSetWhichEigenpairs(raw, sys::EPS_TARGET_MAGNITUDE))?;
                    check(sys::STSetType(st, sys::STSINVERT.as_ptr().cast()))?;
                    let mut ksp = std::ptr::null_mut();
                    check(sys::STGetKSP(st, &mut ksp))?;
                    configure(ksp, &options.linear)?;
                    if options.inertia && counts_inertia(&options.linear) {
                        ask_for_inertia(ksp, a)?;
                    }
                }
                Spectrum::Interval { low, high } => {
                    if !matches!(
                        options.problem,
                        EigenProblem::HermitianGeneralized | EigenProblem::Hermitian
                    ) {
                        return Err(PetscError::Invalid(
                            "an eigenvalue interval needs a Hermitian problem".into(),
                        ));
                    }
                    check(sys::EPSSetInterval(raw, low, high))?;
                    check(sys::EPSSetWhichEigenpairs(raw, sys::EPS_ALL))?;
                    check(sys::STSetType(st, sys::STSINVERT.as_ptr().cast()))?;
                    // Slicing counts eigenvalues by the inertia of LDL^T factorisations made
                    // inside SLEPc's own sub-solvers, which take their settings from the
                    // options database, not from our ST. A prefix of our own keeps these
                    // settings away from every other solver in the process.
                    let package = match &options.linear {
                        LinearMethod::Direct {
                            package: super::ksp::DirectPackage::SuperluDist,
                            ..
                        } => "superlu_dist",
                        _ => "mumps",
                    };
                    check(sys::EPSSetOptionsPrefix(raw, c"squeal_slice_".as_ptr()))?;
                    for (key, value) in [
                        ("-squeal_slice_st_ksp_type", "preonly"),
                        ("-squeal_slice_st_pc_type", "cholesky"),
                        ("-squeal_slice_st_pc_factor_mat_solver_type", package),
                        // MUMPS computes the inertia in parallel only when asked (ICNTL 13).
                        ("-squeal_slice_st_mat_mumps_icntl_13", "1"),
                    ] {
                        let key = std::ffi::CString::new(key).expect("no NUL");
                        let value = std::ffi::CString::new(value).expect("no NUL");
                        check(sys::PetscOptionsSetValue(
                            std::ptr::null_mut(),
                            key.as_ptr(),
                            value.as_ptr(),
                        ))?;
                    }
                }
                Spectrum::Largest { count } => {
                    solver.requested = count;
                    check(sys::EPSSetDimensions(
                        raw,
                        to_int(count)?,
                        sys::PETSC_DEFAULT,
                        sys::PETSC_DEFAULT,
                    ))?;
                    check(sys::EPSSetWhichEigenpairs(raw, sys::EPS_LARGEST_MAGNITUDE))?;
                }
            }
            if !options.purify {
                check(sys::EPSSetPurify(raw, sys::PETSC_FALSE))?;
            }
            check(sys::EPSSetFromOptions(raw))?;
        }
        Ok(solver)
    }

    /// Runs the solver (collective). Returns how many pairs converged; fewer than requested
    /// is reported in the summary, not as an error.
    pub fn solve(&mut self) -> Result<EigenSummary> {
        self.shift_back()?;
        let (mut nconv, mut its, mut reason) = (0, 0, 0);
        // SAFETY: live EPS; out-pointers to locals.
        unsafe {
            check(sys::EPSSolve(self.raw))?;
            check(sys::EPSGetConverged(self.raw, &mut nconv))?;
            check(sys::EPSGetIterationNumber(self.raw, &mut its))?;
            check(sys::EPSGetConvergedReason(self.raw, &mut reason))?;
        }
        let summary = EigenSummary {
            requested: self.requested,
            converged: nconv as usize,
            iterations: its as usize,
            reason,
        };
        self.summary = Some(summary.clone());
        Ok(summary)
    }

    /// Asks the next [`solve`](Self::solve) for `count` pairs nearest the target, in the
    /// B-orthogonal complement of `found` (SLEPc's deflation space: pairs already known are
    /// not found again). For a `NearTarget` solver only. The shift-and-invert factorisation
    /// is kept: the operators have not changed, so the next solve costs only its Krylov
    /// iterations. Collective.
    pub fn search_beyond(&mut self, found: &[&Vector<'rt>], count: usize) -> Result<()> {
        if self.requested == 0 {
            return Err(PetscError::Invalid(
                "only a solver for a count of eigenvalues can search beyond found pairs".into(),
            ));
        }
        let mut raw: std::vec::Vec<sys::PetscVec> = found.iter().map(|v| v.raw).collect();
        // SAFETY: live EPS and vectors; SLEPc copies the vectors into its own basis.
        unsafe {
            check(sys::EPSSetDeflationSpace(
                self.raw,
                to_int(raw.len())?,
                raw.as_mut_ptr(),
            ))?;
            check(sys::EPSSetDimensions(
                self.raw,
                to_int(count)?,
                sys::PETSC_DEFAULT,
                sys::PETSC_DEFAULT,
            ))?;
        }
        self.requested = count;
        self.summary = None;
        Ok(())
    }

    /// The number of eigenvalues below `sigma` of this solver's pencil (A, B symmetric, B
    /// positive definite), by Sylvester's law from the LDL^T of A - sigma B that its own
    /// shift-and-invert transform makes: the factorisation keeps the symbolic analysis
    /// (ordering, fronts) of the solve's, so the count costs a numeric factorisation alone,
    /// where [`super::eigenvalues_below`] analyses the pattern again (on the clamped disc
    /// of 64,512 equations, 2 ranks: 0.26 of its 0.9 s, and the shifted copy's 0.1 s).
    /// For a `NearTarget` solver made with [`EigenOptions::inertia`], after a solve.
    ///
    /// `None` when this factorisation cannot count: made without `inertia`, replaced by
    /// options, or failed (an indefinite A - sigma B delays pivots, and its fronts can
    /// outgrow the workspace that the analysis estimated at the solve's shift): the caller
    /// then counts with a factorisation of its own, which retries with a larger workspace.
    /// The next [`Self::solve`] factorises at the target again first. Collective; every
    /// rank gets the same answer.
    pub fn eigenvalues_below(&mut self, comm: Comm<'rt>, sigma: f64) -> Result<Option<usize>> {
        if self.requested == 0 {
            return Ok(None);
        }
        let (mut st, mut ksp, mut pc, mut factor) = (
            std::ptr::null_mut(),
            std::ptr::null_mut(),
            std::ptr::null_mut(),
            std::ptr::null_mut(),
        );
        // SAFETY: live EPS; out-pointers to locals; the factor belongs to the PC.
        unsafe {
            check(sys::EPSGetST(self.raw, &mut st))?;
            check(sys::STGetKSP(st, &mut ksp))?;
            check(sys::KSPGetPC(ksp, &mut pc))?;
            // The same on every rank: the options and the solver type are. A PC that does
            // not factorise has no factor matrix to ask for.
            if !cholesky(pc)? {
                return Ok(None);
            }
            check(sys::PCFactorGetMatrix(pc, &mut factor))?;
            if !mumps(factor)? {
                return Ok(None);
            }
            let mut icntl13: sys::PetscInt = 0;
            check(sys::MatMumpsGetIcntl(factor, 13, &mut icntl13))?;
            if comm.size() > 1 && icntl13 != 1 {
                return Ok(None);
            }
            // SLEPc's own spectrum slicing counts so: the transform's matrix becomes
            // A - sigma B in place (the same pattern), and the KSP's set-up factorises it.
            self.moved = true;
            check(sys::STSetShift(st, sigma))?;
            check(sys::KSPSetUp(ksp))?;
            let failure = failure_detail(ksp)?;
            if !comm.all(failure.is_none()) {
                tracing::debug!(
                    "inertia at {sigma:e} on the solver's factorisation: {}; counting anew",
                    failure.unwrap_or_else(|| "failed on another rank".into())
                );
                return Ok(None);
            }
            // At a zero target the transform factorised A itself; the first move then makes
            // a new matrix, whose factorisation (analysed anew) has MUMPS's defaults.
            check(sys::PCFactorGetMatrix(pc, &mut factor))?;
            check(sys::MatMumpsGetIcntl(factor, 13, &mut icntl13))?;
            if comm.size() > 1 && icntl13 != 1 {
                tracing::debug!(
                    "inertia at {sigma:e}: the transform's new factorisation cannot count"
                );
                return Ok(None);
            }
            let negative = super::inertia::negative_pivots(factor)?;
            usize::try_from(negative)
                .map(Some)
                .map_err(|_| PetscError::Invalid(format!("negative inertia count {negative}")))
        }
    }

    /// Puts the transform back at the target after [`Self::eigenvalues_below`] moved it
    /// (its factorisation is redone at the next set-up). Collective.
    fn shift_back(&mut self) -> Result<()> {
        if !self.moved {
            return Ok(());
        }
        let (mut st, mut target) = (std::ptr::null_mut(), 0.0);
        // SAFETY: live EPS; out-pointers to locals.
        unsafe {
            check(sys::EPSGetST(self.raw, &mut st))?;
            check(sys::EPSGetTarget(self.raw, &mut target))?;
            check(sys::STSetShift(st, target))?;
        }
        self.moved = false;
        Ok(())
    }

    fn check_index(&self, i: usize) -> Result<sys::PetscInt> {
        let n = self.summary.as_ref().map_or(0, |s| s.converged);
        if i >= n {
            return Err(PetscError::Invalid(format!(
                "eigenpair {i} requested but {n} converged"
            )));
        }
        to_int(i)
    }

    /// Eigenvalue i (complex in general; a conjugate pair is two consecutive indices).
    pub fn value(&self, i: usize) -> Result<Complex64> {
        let i = self.check_index(i)?;
        let (mut re, mut im) = (0.0, 0.0);
        // SAFETY: index checked; out-pointers.
        check(unsafe { sys::EPSGetEigenvalue(self.raw, i, &mut re, &mut im) })?;
        Ok(Complex64::new(re, im))
    }

    /// The spectral transform's shift: the target, or where [`Self::eigenvalues_below`] last
    /// moved it until the next solve puts it back.
    pub fn shift(&self) -> Result<f64> {
        let (mut st, mut sigma) = (std::ptr::null_mut(), 0.0);
        // SAFETY: live EPS; out-pointers to locals.
        unsafe {
            check(sys::EPSGetST(self.raw, &mut st))?;
            check(sys::STGetShift(st, &mut sigma))?;
        }
        Ok(sigma)
    }

    /// Relative residual |A x - lambda B x| / |lambda x| of pair i (collective).
    pub fn relative_error(&self, i: usize) -> Result<f64> {
        let i = self.check_index(i)?;
        let mut e = 0.0;
        // SAFETY: index checked.
        check(unsafe { sys::EPSComputeError(self.raw, i, sys::EPS_ERROR_RELATIVE, &mut e) })?;
        Ok(e)
    }

    /// Pair i: the eigenvalue and the real and imaginary parts of its vector, laid out like
    /// `template` (a vector of the operator's column layout). Collective.
    pub fn pair(
        &self,
        i: usize,
        template: &Vector<'rt>,
    ) -> Result<(Complex64, Vector<'rt>, Vector<'rt>)> {
        let i = self.check_index(i)?;
        let xr = template.duplicate()?;
        let xi = template.duplicate()?;
        let (mut re, mut im) = (0.0, 0.0);
        // SAFETY: index checked; vectors have the operator's layout.
        check(unsafe { sys::EPSGetEigenpair(self.raw, i, &mut re, &mut im, xr.raw, xi.raw) })?;
        Ok((Complex64::new(re, im), xr, xi))
    }
}

/// Whether `method` is a factorisation whose inertia can be read ([`EigenOptions::inertia`]).
fn counts_inertia(method: &LinearMethod) -> bool {
    matches!(
        method,
        LinearMethod::Direct {
            package: DirectPackage::Mumps,
            factorization: Factorization::Cholesky,
        }
    )
}

/// Sets MUMPS's ICNTL(13) = 1 on the factorisation `ksp` will make. It must be set before
/// the analysis, which SLEPc runs inside its set-up, and the factor matrix exists only
/// once the PC has an operator: `a` stands in for the transform's A - sigma B until SLEPc
/// sets that (same size and pattern; the PC keeps its factor matrix across the change).
///
/// # Safety
/// `ksp` and `a` are live.
unsafe fn ask_for_inertia(ksp: sys::KSP, a: &Matrix<'_>) -> Result<()> {
    let (mut pc, mut factor) = (std::ptr::null_mut(), std::ptr::null_mut());
    check(sys::KSPSetOperators(ksp, a.raw, a.raw))?;
    check(sys::KSPGetPC(ksp, &mut pc))?;
    check(sys::PCFactorSetUpMatSolverType(pc))?;
    check(sys::PCFactorGetMatrix(pc, &mut factor))?;
    check(sys::MatMumpsSetIcntl(factor, 13, 1))
}

/// Whether `pc` factorises by Cholesky (LDL^T for an indefinite matrix).
///
/// # Safety
/// `pc` is live.
unsafe fn cholesky(pc: sys::PC) -> Result<bool> {
    let mut same = sys::PETSC_FALSE;
    check(sys::PetscObjectTypeCompare(
        pc.cast(),
        sys::PCCHOLESKY.as_ptr().cast(),
        &mut same,
    ))?;
    Ok(same == sys::PETSC_TRUE)
}

/// Whether `factor` is MUMPS's (a factor matrix keeps its operator's type name; the package
/// is its solver type).
///
/// # Safety
/// `factor` is live.
unsafe fn mumps(factor: sys::Mat) -> Result<bool> {
    let mut name = std::ptr::null();
    check(sys::MatFactorGetSolverType(factor, &mut name))?;
    Ok(!name.is_null()
        && std::ffi::CStr::from_ptr(name).to_bytes_with_nul() == &sys::MATSOLVERMUMPS[..])
}

impl Drop for EigenSolver<'_> {
    fn drop(&mut self) {
        // SAFETY: we own the handle.
        unsafe { sys::EPSDestroy(&mut self.raw) };
    }
}
