//! Newton's method (`SNES`) with the residual and Jacobian written as Rust closures. The
//! closures live in a box owned by the solver; a generic `extern "C"` trampoline finds them
//! through PETSc's context pointer and catches panics there, so none crosses into C.

use super::error::{check, record_callback_error, PetscError, Result};
use super::ksp::{configure, failure_detail, LinearMethod};
use super::mat::Matrix;
use super::runtime::{Comm, Runtime};
use super::sys;
use super::vec::Vector;
use std::marker::PhantomData;
use std::mem::ManuallyDrop;
use std::os::raw::c_void;
use std::panic::{catch_unwind, AssertUnwindSafe};

/// F(x) into `f`. An `Err` stops the solve with that message.
pub type Residual<'f, 'rt> =
    dyn FnMut(&Vector<'rt>, &mut Vector<'rt>) -> std::result::Result<(), String> + 'f;
/// dF/dx at x into the matrix (same pattern every call), and how much it changed.
pub type Jacobian<'f, 'rt> =
    dyn FnMut(&Vector<'rt>, &mut Matrix<'rt>) -> std::result::Result<JacobianChange, String> + 'f;

/// How a Jacobian differs from the one of the previous evaluation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum JacobianChange {
    /// Not known: the linear step factorises it.
    Unknown,
    /// By a matrix of rank at most this (contact points that opened or closed: one each).
    RankAtMost(usize),
}

struct Callbacks<'f, 'rt> {
    residual: Box<Residual<'f, 'rt>>,
    jacobian: Box<Jacobian<'f, 'rt>>,
    /// [`NewtonOptions::keep_factorization_rank`].
    keep_rank: usize,
    /// Rank of the change since the Jacobian last factorised; `None` before the first.
    since_factorised: Option<usize>,
    /// Factorisations asked for so far.
    factorizations: usize,
    /// [`NewtonOptions::roundoff_floor`], and what the convergence test saw: |F0|, the
    /// previous |F|, and whether it stopped the solve as stagnating on the floor.
    floor: f64,
    first_norm: f64,
    last_norm: f64,
    floored: bool,
    /// The last Jacobian's infinity norm (0 before the first), and the residual's
    /// evaluation floor the convergence test last computed from it
    /// ([`evaluation_floor`]).
    jacobian_norm: f64,
    evaluation_floor: f64,
}

/// What round-off alone leaves in |F| = |K u - f| at `u`: each entry is a sum of products
/// `K_ij u_j`, computed with an error up to about eps |K|_inf |u|_inf, and the 2-norm over
/// `n` entries is at most sqrt(n) times the largest. A residual below this cannot be told
/// from zero in floating point (the normwise backward error of the evaluation, Rigal and
/// Gaches): stiff ties (a reduced interface's springs of 1e13-1e14 N/m on the kept pairs of a
/// floating caliper) put |F| there, 1e-8 of a warm start's first residual, where a relative
/// floor alone kept Newton iterating until its line search failed.
fn evaluation_floor(jacobian_inf_norm: f64, x_inf_norm: f64, n: usize) -> f64 {
    f64::EPSILON * jacobian_inf_norm * x_inf_norm * (n as f64).sqrt()
}

/// Newton settings. PETSc options (`-snes_*`) given at start-up override them.
#[derive(Clone, Debug, PartialEq)]
pub struct NewtonOptions {
    /// Stop when |F| < absolute_tolerance ...
    pub absolute_tolerance: f64,
    /// ... or |F| < relative_tolerance |F0|.
    pub relative_tolerance: f64,
    pub max_iterations: usize,
    /// PETSc's line search: backtracking ("bt"), critical point ("cp"), the full step
    /// ("basic")...
    pub line_search: String,
    pub linear: LinearMethod,
    /// With a direct `linear` method: while the Jacobian differs from the last one
    /// factorised by a change of rank at most this (as its callback reports), keep that
    /// factorisation as the preconditioner of GMRES on the new Jacobian, which converges in
    /// about rank + 1 iterations, each a pair of triangular solves, far cheaper than a new
    /// factorisation. 0 factorises every Jacobian.
    pub keep_factorization_rank: usize,
    /// Once |F| <= this * |F0|, or below what round-off alone leaves in |F| at the current
    /// iterate ([`evaluation_floor`]), an iteration that does not halve |F| (Newton is
    /// quadratic there unless round-off stops it), or a line search that finds no descent,
    /// is taken as convergence to the residual's round-off floor (reason
    /// `CONVERGED_ROUNDOFF_FLOOR`) rather than more iterations or a failure. 0: never. See
    /// the caller's reason for its value.
    pub roundoff_floor: f64,
}

impl Default for NewtonOptions {
    fn default() -> Self {
        NewtonOptions {
            absolute_tolerance: 1e-50,
            relative_tolerance: 1e-10,
            max_iterations: 50,
            line_search: "bt".into(),
            linear: LinearMethod::default(),
            keep_factorization_rank: 0,
            roundoff_floor: 0.0,
        }
    }
}

/// How a converged solve went.
#[derive(Clone, Debug, PartialEq)]
pub struct NewtonReport {
    pub iterations: usize,
    /// |F| before each iteration and at the end.
    pub residual_history: std::vec::Vec<f64>,
    /// PETSc's name for why it stopped ("CONVERGED_FNORM_RELATIVE"...).
    pub reason: String,
    /// Jacobians factorised (the others reused a factorisation inside GMRES).
    pub factorizations: usize,
}

pub struct NonlinearSolver<'f, 'rt> {
    raw: sys::SNES,
    // Declared after `raw` is destroyed in Drop: PETSc may call the closures until then.
    callbacks: Box<Callbacks<'f, 'rt>>,
    jacobian: Matrix<'rt>,
    history: std::vec::Vec<f64>,
    roundoff_floor: f64,
    _rt: PhantomData<&'rt Runtime>,
}

fn run<F: FnOnce() -> std::result::Result<(), String>>(what: &str, f: F) -> sys::PetscErrorCode {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(Ok(())) => 0,
        Ok(Err(message)) => {
            record_callback_error(format!("{what}: {message}"));
            sys::PETSC_ERR_USER as sys::PetscErrorCode
        }
        Err(panic) => {
            let text = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic".into());
            record_callback_error(format!("{what} panicked: {text}"));
            sys::PETSC_ERR_USER as sys::PetscErrorCode
        }
    }
}

unsafe extern "C" fn residual_trampoline(
    _snes: sys::SNES,
    x: sys::PetscVec,
    f: sys::PetscVec,
    ctx: *mut c_void,
) -> sys::PetscErrorCode {
    // SAFETY: ctx is the Box<Callbacks> the solver owns; x and f are live for the call and
    // wrapped without taking ownership.
    let callbacks = unsafe { &mut *(ctx as *mut Callbacks) };
    let x = ManuallyDrop::new(Vector::from_raw(x));
    let mut f = ManuallyDrop::new(Vector::from_raw(f));
    run("residual", || (callbacks.residual)(&x, &mut f))
}

unsafe extern "C" fn jacobian_trampoline(
    snes: sys::SNES,
    x: sys::PetscVec,
    j: sys::Mat,
    _p: sys::Mat,
    ctx: *mut c_void,
) -> sys::PetscErrorCode {
    // SAFETY: as residual_trampoline; j is the matrix we registered.
    let callbacks = unsafe { &mut *(ctx as *mut Callbacks) };
    let x = ManuallyDrop::new(Vector::from_raw(x));
    let mut j = ManuallyDrop::new(Matrix::from_raw(j));
    let mut change = JacobianChange::Unknown;
    let code = run("Jacobian", || {
        change = (callbacks.jacobian)(&x, &mut j)?;
        Ok(())
    });
    if code != 0 {
        return code;
    }
    if callbacks.floor > 0.0 {
        let mut norm = 0.0;
        // SAFETY: the live matrix PETSc handed us, assembled by the callback.
        let code = unsafe { sys::MatNorm(j.raw, sys::NORM_INFINITY, &mut norm) };
        if code != 0 {
            return code;
        }
        callbacks.jacobian_norm = norm;
    }
    // SNES reads its preconditioner lag right after this callback: -2 refactorises once,
    // -1 keeps the factorisation (PETSc's SNESComputeJacobian).
    let keep = match (change, callbacks.since_factorised) {
        (JacobianChange::RankAtMost(r), Some(before)) if callbacks.keep_rank > 0 => {
            let total = before + r;
            // A Krylov solve that struggled (or failed) last time asks for a new one too.
            let mut ksp = std::ptr::null_mut();
            let (mut its, mut reason) = (0, 0);
            // SAFETY: live SNES; out-pointers to locals.
            let ok = unsafe {
                sys::SNESGetKSP(snes, &mut ksp) == 0
                    && sys::KSPGetIterationNumber(ksp, &mut its) == 0
                    && sys::KSPGetConvergedReason(ksp, &mut reason) == 0
            };
            (ok && reason >= 0
                && (its as usize) <= callbacks.keep_rank / 2 + 2
                && total <= callbacks.keep_rank)
                .then_some(total)
        }
        _ => None,
    };
    callbacks.since_factorised = Some(keep.unwrap_or(0));
    if keep.is_none() {
        callbacks.factorizations += 1;
    }
    // SAFETY: live SNES.
    unsafe { sys::SNESSetLagPreconditioner(snes, if keep.is_some() { -1 } else { -2 }) }
}

/// GMRES around Newton's factorisation, kept or fresh: PETSc's default test, with the
/// iteration limit taken as the end of a usable step (`KSP_CONVERGED_ITS`) instead of
/// `KSP_DIVERGED_ITS`, which would end Newton. `ctx` is PETSc's default test's context.
unsafe extern "C" fn kept_factor_convergence(
    ksp: sys::KSP,
    it: sys::PetscInt,
    rnorm: sys::PetscReal,
    reason: *mut sys::KSPConvergedReason,
    ctx: *mut c_void,
) -> sys::PetscErrorCode {
    // SAFETY: PETSc calls this with a live KSP, its out-pointer and the context it was given.
    unsafe {
        let code = sys::KSPConvergedDefault(ksp, it, rnorm, reason, ctx);
        if code != 0 || *reason != sys::KSP_CONVERGED_ITERATING {
            return code;
        }
        let (mut rtol, mut abstol, mut dtol, mut limit) = (0.0, 0.0, 0.0, 0);
        let code = sys::KSPGetTolerances(ksp, &mut rtol, &mut abstol, &mut dtol, &mut limit);
        if code == 0 && it >= limit {
            *reason = sys::KSP_CONVERGED_ITS;
        }
        code
    }
}

/// PETSc's default test, and the stagnation on the round-off floor
/// ([`NewtonOptions::roundoff_floor`]): stiff ties leave |F| at eps k |u|, where a Newton step
/// gains nothing and, before this test, each further iteration cost a factorisation until the
/// line search failed (ten of twenty on the tiny caliper's reduced interface).
unsafe extern "C" fn convergence_trampoline(
    snes: sys::SNES,
    it: sys::PetscInt,
    xnorm: sys::PetscReal,
    snorm: sys::PetscReal,
    fnorm: sys::PetscReal,
    reason: *mut sys::SNESConvergedReason,
    ctx: *mut c_void,
) -> sys::PetscErrorCode {
    // SAFETY: live SNES; `reason` is PETSc's out-pointer; ctx is the Box<Callbacks> the
    // solver owns.
    let code = unsafe {
        sys::SNESConvergedDefault(snes, it, xnorm, snorm, fnorm, reason, std::ptr::null_mut())
    };
    if code != 0 {
        return code;
    }
    let callbacks = unsafe { &mut *(ctx as *mut Callbacks) };
    if callbacks.jacobian_norm > 0.0 {
        let (mut x, mut x_inf, mut n) = (std::ptr::null_mut(), 0.0, 0);
        // SAFETY: live SNES; out-pointers to locals; the solution vector is PETSc's.
        let code = unsafe {
            let mut code = sys::SNESGetSolution(snes, &mut x);
            if code == 0 {
                code = sys::VecNorm(x, sys::NORM_INFINITY, &mut x_inf);
            }
            if code == 0 {
                code = sys::VecGetSize(x, &mut n);
            }
            code
        };
        if code != 0 {
            return code;
        }
        callbacks.evaluation_floor =
            evaluation_floor(callbacks.jacobian_norm, x_inf, n.max(0) as usize);
    }
    if it == 0 {
        callbacks.first_norm = fnorm;
        callbacks.floored = false;
    } else if unsafe { *reason } == sys::SNES_CONVERGED_ITERATING
        && (fnorm <= callbacks.floor * callbacks.first_norm || fnorm <= callbacks.evaluation_floor)
        && fnorm > 0.5 * callbacks.last_norm
    {
        callbacks.floored = true;
        // SAFETY: as above.
        unsafe { *reason = sys::SNES_CONVERGED_FNORM_ABS };
    }
    callbacks.last_norm = fnorm;
    0
}

impl<'f, 'rt> NonlinearSolver<'f, 'rt> {
    /// A Newton solver for F(x) = 0 with the Jacobian assembled into `jacobian` (whose
    /// pattern must hold every entry the closure adds). Collective.
    pub fn new(
        comm: Comm<'rt>,
        residual: Box<Residual<'f, 'rt>>,
        jacobian_fn: Box<Jacobian<'f, 'rt>>,
        jacobian: Matrix<'rt>,
        options: &NewtonOptions,
    ) -> Result<Self> {
        let mut raw = std::ptr::null_mut();
        // SAFETY: out-pointer to a local.
        check(unsafe { sys::SNESCreate(comm.raw, &mut raw) })?;
        let mut solver = NonlinearSolver {
            raw,
            callbacks: Box::new(Callbacks {
                residual,
                jacobian: jacobian_fn,
                keep_rank: match options.linear {
                    LinearMethod::Direct { .. } => options.keep_factorization_rank,
                    LinearMethod::Iterative { .. } => 0,
                },
                since_factorised: None,
                factorizations: 0,
                floor: options.roundoff_floor,
                first_norm: 0.0,
                last_norm: 0.0,
                floored: false,
                jacobian_norm: 0.0,
                evaluation_floor: 0.0,
            }),
            jacobian,
            history: vec![0.0; options.max_iterations + 2],
            roundoff_floor: options.roundoff_floor,
            _rt: PhantomData,
        };
        let ctx = &mut *solver.callbacks as *mut Callbacks as *mut c_void;
        let line_search = std::ffi::CString::new(options.line_search.as_str())
            .map_err(|_| PetscError::Invalid("NUL in line search name".into()))?;
        // SAFETY: the box and the history buffer live as long as the SNES (both owned by
        // `solver`, destroyed after SNESDestroy in Drop).
        unsafe {
            check(sys::SNESSetType(raw, sys::SNESNEWTONLS.as_ptr().cast()))?;
            check(sys::SNESSetFunction(
                raw,
                std::ptr::null_mut(),
                Some(residual_trampoline),
                ctx,
            ))?;
            check(sys::SNESSetJacobian(
                raw,
                solver.jacobian.raw,
                solver.jacobian.raw,
                Some(jacobian_trampoline),
                ctx,
            ))?;
            check(sys::SNESSetTolerances(
                raw,
                options.absolute_tolerance,
                options.relative_tolerance,
                0.0,
                super::vec::to_int(options.max_iterations)?,
                -1,
            ))?;
            let mut ls = std::ptr::null_mut();
            check(sys::SNESGetLineSearch(raw, &mut ls))?;
            check(sys::SNESLineSearchSetType(ls, line_search.as_ptr()))?;
            if options.line_search == "cp" {
                // The secant step of the critical-point search may extrapolate past the
                // Newton step (lambda > 1); its maxstep is the largest lambda it takes, and
                // past it the full step is kept. Unbounded, the extrapolated steps blew the
                // residual up (1e2 to 1e8) on the small caliper and Newton diverged; capped
                // at 1, the same sweep took 41 Newton iterations against 55 (and 56 with
                // backtracking), to the same equilibria.
                // Three secant steps instead of PETSc's one: loading a floating caliper
                // from rest flips stick, slip and open states along the Newton direction,
                // and one secant step from the end points stopped far from the critical
                // point, so Newton crept (the residual down a few per cent per step).
                // From rest: tiny-caliper 15 Newton iterations instead of 20, small-caliper
                // 16 instead of 27, medium-caliper 36 instead of 79; warm points the same (a
                // residual evaluation per extra step, against a factorisation per Newton
                // iteration).
                let (mut steptol, mut maxstep, mut rtol, mut atol, mut ltol, mut its) =
                    (0.0, 0.0, 0.0, 0.0, 0.0, 0);
                check(sys::SNESLineSearchGetTolerances(
                    ls,
                    &mut steptol,
                    &mut maxstep,
                    &mut rtol,
                    &mut atol,
                    &mut ltol,
                    &mut its,
                ))?;
                check(sys::SNESLineSearchSetTolerances(
                    ls,
                    steptol,
                    1.0,
                    rtol,
                    atol,
                    ltol,
                    its.max(3),
                ))?;
            }
            let mut ksp = std::ptr::null_mut();
            check(sys::SNESGetKSP(raw, &mut ksp))?;
            configure(ksp, &options.linear)?;
            if solver.callbacks.keep_rank > 0 {
                // GMRES around the (possibly kept) factorisation: one iteration when it is
                // fresh, about rank + 1 when kept; the restart never comes into play.
                let limit = super::vec::to_int(2 * solver.callbacks.keep_rank + 10)?;
                check(sys::KSPSetType(ksp, sys::KSPGMRES.as_ptr().cast()))?;
                check(sys::KSPGMRESSetRestart(ksp, limit))?;
                check(sys::KSPSetTolerances(ksp, 1e-12, 1e-50, 1e10, limit))?;
                // A kept factorisation that no longer preconditions the tangent well (many
                // contact points changed, or stiff ties hold GMRES on a round-off floor above
                // its tolerance) ends GMRES at its limit. That is a poor preconditioner, not a
                // failed Newton step: the step is taken as GMRES left it, the line search
                // judges it, and the next Jacobian is factorised afresh (the callback sees more
                // iterations than a kept factor may take). Ending Newton there instead made the
                // from-rest static of tiny-caliper with every pair reduced fail at every load
                // cut-back under one BLAS kernel: GMRES reached 1e-9 relative, not 1e-12, on
                // its third iteration's kept factor (2026-12-07; with this, 11 Newton
                // iterations). A failed preconditioner (a zero pivot, no memory) still ends
                // the solve: only the limit is accepted.
                let mut default_ctx = std::ptr::null_mut();
                check(sys::KSPConvergedDefaultCreate(&mut default_ctx))?;
                check(sys::KSPSetConvergenceTest(
                    ksp,
                    Some(kept_factor_convergence),
                    default_ctx,
                    Some(sys::KSPConvergedDefaultDestroy),
                ))?;
            }
            if options.roundoff_floor > 0.0 {
                check(sys::SNESSetConvergenceTest(
                    raw,
                    Some(convergence_trampoline),
                    ctx,
                    None,
                ))?;
            }
            check(sys::SNESSetConvergenceHistory(
                raw,
                solver.history.as_mut_ptr(),
                std::ptr::null_mut(),
                super::vec::to_int(solver.history.len())?,
                sys::PETSC_TRUE,
            ))?;
            check(sys::SNESSetFromOptions(raw))?;
        }
        Ok(solver)
    }

    /// Solves F(x) = 0 from the initial guess in `x` (collective). Not converging is an
    /// `Err` that says why, with the residual history.
    pub fn solve(&mut self, x: &mut Vector<'rt>) -> Result<NewtonReport> {
        // SAFETY: live SNES and vector.
        let code = unsafe { sys::SNESSolve(self.raw, std::ptr::null_mut(), x.raw) };
        check(code)?;
        let mut reason = 0;
        let mut its = 0;
        let mut n_hist = 0;
        let mut hist_ptr = std::ptr::null_mut();
        let mut text = std::ptr::null();
        // SAFETY: out-pointers; the history pointer is our own buffer.
        unsafe {
            check(sys::SNESGetConvergedReason(self.raw, &mut reason))?;
            check(sys::SNESGetIterationNumber(self.raw, &mut its))?;
            check(sys::SNESGetConvergenceHistory(
                self.raw,
                &mut hist_ptr,
                std::ptr::null_mut(),
                &mut n_hist,
            ))?;
            check(sys::SNESGetConvergedReasonString(self.raw, &mut text))?;
        }
        let history = self.history[..(n_hist.max(0) as usize).min(self.history.len())].to_vec();
        // SAFETY: PETSc's reason strings are static.
        let reason_text = unsafe { std::ffi::CStr::from_ptr(text) }
            .to_string_lossy()
            .into_owned();
        let floor = match (history.first(), history.last()) {
            (Some(&first), Some(&last)) => {
                last <= self.roundoff_floor * first || last <= self.callbacks.evaluation_floor
            }
            _ => false,
        };
        if self.callbacks.floored || (reason == sys::SNES_DIVERGED_LINE_SEARCH && floor) {
            return Ok(NewtonReport {
                iterations: its as usize,
                residual_history: history,
                reason: "CONVERGED_ROUNDOFF_FLOOR".into(),
                factorizations: self.callbacks.factorizations,
            });
        }
        if reason < 0 {
            let mut ksp = std::ptr::null_mut();
            // SAFETY: out-pointer.
            check(unsafe { sys::SNESGetKSP(self.raw, &mut ksp) })?;
            let linear = failure_detail(ksp)?
                .map(|d| format!("; last linear solve: {d}"))
                .unwrap_or_default();
            return Err(PetscError::NotConverged {
                what: "Newton (SNES)".into(),
                detail: format!(
                    "{reason_text} after {its} iterations{linear}; residual history {}",
                    format_history(&history)
                ),
            });
        }
        Ok(NewtonReport {
            iterations: its as usize,
            residual_history: history,
            reason: reason_text,
            factorizations: self.callbacks.factorizations,
        })
    }

    /// The Jacobian matrix as last assembled.
    pub fn jacobian(&self) -> &Matrix<'rt> {
        &self.jacobian
    }
}

pub fn format_history(h: &[f64]) -> String {
    let items: std::vec::Vec<String> = h.iter().map(|r| format!("{r:.3e}")).collect();
    format!("[{}]", items.join(", "))
}

impl Drop for NonlinearSolver<'_, '_> {
    fn drop(&mut self) {
        // SAFETY: we own the SNES; the callbacks and matrix are dropped after this.
        unsafe { sys::SNESDestroy(&mut self.raw) };
    }
}
