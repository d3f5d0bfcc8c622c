//! Left eigenvectors of a shift-and-invert eigen-solve, from the factorisation it already
//! holds.
//!
//! A solve of A x = s B x about the target sigma factored A - sigma B once and applied
//! (A - sigma B)^{-1} B. The transposed operator (A - sigma B)^{-T} B^T has the eigenvalues
//! theta = 1 / (s - sigma) too, with eigenvectors z: A^T z = s B^T z, so y = conj(z) is the
//! left eigenvector of s (y^H A = s y^H B). The factors' transposed solve (MUMPS solves with
//! A^T from the same factors) applies it at the cost of one triangular solve pair, no new
//! factorisation: a Krylov-Schur solve on it costs iterations only. B is taken symmetric (a
//! mass matrix), so B^T v is B v.

use super::eps::EigenSolver;
use super::error::{check, PetscError, Result};
use super::mat::Matrix;
use super::runtime::Comm;
use super::sys;
use super::vec::{to_int, Vector};
use num_complex::Complex64;
use std::ffi::c_void;
use std::marker::PhantomData;

/// What the shell's product needs: the forward solver's linear solver (borrowed, its
/// factors set up), the mass and a work vector of the mass's row layout.
struct Transposed {
    ksp: sys::KSP,
    mass: sys::Mat,
    work: sys::PetscVec,
}

impl Drop for Transposed {
    fn drop(&mut self) {
        // SAFETY: the work vector is ours; ksp and mass are borrowed and not destroyed.
        unsafe { sys::VecDestroy(&mut self.work) };
    }
}

/// y = (A - sigma B)^{-T} B x.
unsafe extern "C" fn apply_transposed(
    a: sys::Mat,
    x: sys::PetscVec,
    y: sys::PetscVec,
) -> sys::PetscErrorCode {
    let mut ctx: *mut c_void = std::ptr::null_mut();
    // SAFETY: `a` is the shell made in `LeftSolver::solve`, whose context is the boxed
    // `Transposed` the solver owns and keeps alive while the shell exists; x and y are
    // PETSc's live vectors of the shell's layout.
    unsafe {
        let code = sys::MatShellGetContext(a, (&mut ctx as *mut *mut c_void).cast());
        if code != 0 {
            return code;
        }
        let t = &*(ctx as *const Transposed);
        let code = sys::MatMult(t.mass, x, t.work);
        if code != 0 {
            return code;
        }
        sys::KSPSolveTranspose(t.ksp, t.work, y)
    }
}

/// The `count` eigenpairs nearest a forward solver's target of the transposed pencil
/// (A^T, B), solved on the forward solver's factorisation; read as left eigenvectors.
pub struct LeftSolver<'a, 'rt> {
    // Destroyed in this order by `Drop`: the EPS (it holds a reference to the shell), the
    // shell, then the context the shell's product reads.
    eps: sys::EPS,
    shell: sys::Mat,
    _context: Box<Transposed>,
    target: f64,
    converged: usize,
    _forward: PhantomData<&'a EigenSolver<'rt>>,
}

impl<'a, 'rt> LeftSolver<'a, 'rt> {
    /// Solves for the `count` eigenvalues of (A^T, B) nearest `forward`'s target, `forward`
    /// a shift-and-invert solver of (A, B) about `target` that has solved (so its
    /// factorisation is made), `mass` its B. `subspace`: SLEPc's ncv. Collective.
    pub fn solve(
        comm: Comm<'rt>,
        forward: &'a EigenSolver<'rt>,
        mass: &Matrix<'rt>,
        target: f64,
        count: usize,
        subspace: usize,
        tolerance: f64,
    ) -> Result<Self> {
        let (mut rows, mut cols) = (0, 0);
        let (mut big_rows, mut big_cols) = (0, 0);
        let mut st = std::ptr::null_mut();
        let mut ksp = std::ptr::null_mut();
        let mut work = std::ptr::null_mut();
        // SAFETY: live handles of the forward solver and the mass; out-pointers to locals.
        unsafe {
            check(sys::EPSGetST(forward.raw, &mut st))?;
            check(sys::STGetKSP(st, &mut ksp))?;
            // With `-st_matmode inplace` SLEPc shifted A itself to A - sigma B and shifted
            // it back after its solve: the KSP would see its operator changed and factorise
            // A afresh, whose transposed solves have the eigenvalues 1 / s, not
            // 1 / (s - sigma), and no left vector would match (every target but 0). The
            // factors of A - sigma B are the ones wanted: keep them.
            check(sys::KSPSetReusePreconditioner(ksp, sys::PETSC_TRUE))?;
            check(sys::MatGetLocalSize(mass.raw, &mut rows, &mut cols))?;
            check(sys::MatGetSize(mass.raw, &mut big_rows, &mut big_cols))?;
            check(sys::MatCreateVecs(
                mass.raw,
                std::ptr::null_mut(),
                &mut work,
            ))?;
        }
        let mut context = Box::new(Transposed {
            ksp,
            mass: mass.raw,
            work,
        });
        // The box's contents stay where they are when the box moves into the solver.
        let ctx = (&mut *context as *mut Transposed).cast::<c_void>();
        let mut solver = LeftSolver {
            eps: std::ptr::null_mut(),
            shell: std::ptr::null_mut(),
            _context: context,
            target,
            converged: 0,
            _forward: PhantomData,
        };
        // SAFETY: the context is boxed and owned by `solver`, which destroys the shell (and
        // the EPS holding it) before dropping it; the function pointer has the signature
        // PETSc calls MATOP_MULT with.
        unsafe {
            check(sys::MatCreateShell(
                comm.raw,
                rows,
                cols,
                big_rows,
                big_cols,
                ctx,
                &mut solver.shell,
            ))?;
            let apply: unsafe extern "C" fn(sys::Mat, sys::PetscVec, sys::PetscVec) -> i32 =
                apply_transposed;
            check(sys::MatShellSetOperation(
                solver.shell,
                sys::MATOP_MULT,
                Some(std::mem::transmute::<
                    unsafe extern "C" fn(sys::Mat, sys::PetscVec, sys::PetscVec) -> i32,
                    unsafe extern "C" fn(),
                >(apply)),
            ))?;
            check(sys::EPSCreate(comm.raw, &mut solver.eps))?;
            let eps = solver.eps;
            check(sys::EPSSetOperators(
                eps,
                solver.shell,
                std::ptr::null_mut(),
            ))?;
            check(sys::EPSSetProblemType(eps, sys::EPS_NHEP))?;
            check(sys::EPSSetType(eps, sys::EPSKRYLOVSCHUR.as_ptr().cast()))?;
            check(sys::EPSSetTolerances(eps, tolerance, 1000))?;
            check(sys::EPSSetDimensions(
                eps,
                to_int(count)?,
                to_int(subspace.max(count + 1))?,
                sys::PETSC_DEFAULT,
            ))?;
            check(sys::EPSSetWhichEigenpairs(eps, sys::EPS_LARGEST_MAGNITUDE))?;
            let mut own_st = std::ptr::null_mut();
            check(sys::EPSGetST(eps, &mut own_st))?;
            check(sys::STSetType(own_st, sys::STSHIFT.as_ptr().cast()))?;
            // `-squeal_left_eps_*` reach this solve alone (`-squeal_left_eps_view` shows its
            // restarts; measured on `small` at mu 0.6: 52 transposed solves for 16 pairs, the
            // same at tolerances 1e-8 and 1e-6, 48 with ncv 48, 65 with ncv 24).
            check(sys::EPSSetOptionsPrefix(eps, c"squeal_left_".as_ptr()))?;
            check(sys::EPSSetFromOptions(eps))?;
            check(sys::EPSSolve(eps))?;
            let mut nconv = 0;
            check(sys::EPSGetConverged(eps, &mut nconv))?;
            solver.converged = nconv as usize;
        }
        Ok(solver)
    }

    /// How many pairs converged.
    pub fn converged(&self) -> usize {
        self.converged
    }

    fn index(&self, i: usize) -> Result<sys::PetscInt> {
        if i >= self.converged {
            return Err(PetscError::Invalid(format!(
                "left eigenpair {i} requested but {} converged",
                self.converged
            )));
        }
        to_int(i)
    }

    /// Eigenvalue i of the pencil, s = target + 1 / theta.
    pub fn value(&self, i: usize) -> Result<Complex64> {
        let i = self.index(i)?;
        let (mut re, mut im) = (0.0, 0.0);
        // SAFETY: index checked; out-pointers.
        check(unsafe { sys::EPSGetEigenvalue(self.eps, i, &mut re, &mut im) })?;
        Ok(self.target + Complex64::new(re, im).inv())
    }

    /// The left eigenvector y of value i (y^H A = s y^H B): real and imaginary parts, laid
    /// out like `template`. Collective.
    pub fn left_vector(
        &self,
        i: usize,
        template: &Vector<'rt>,
    ) -> Result<(Vector<'rt>, Vector<'rt>)> {
        let i = self.index(i)?;
        let zr = template.duplicate()?;
        let mut zi = template.duplicate()?;
        let (mut re, mut im) = (0.0, 0.0);
        // SAFETY: index checked; vectors have the shell's layout.
        check(unsafe { sys::EPSGetEigenpair(self.eps, i, &mut re, &mut im, zr.raw, zi.raw) })?;
        // y = conj(z).
        zi.scale(-1.0)?;
        Ok((zr, zi))
    }
}

impl Drop for LeftSolver<'_, '_> {
    fn drop(&mut self) {
        // SAFETY: we own both handles; the EPS (which references the shell) goes first, and
        // the context box outlives both (dropped after this body).
        unsafe {
            sys::EPSDestroy(&mut self.eps);
            sys::MatDestroy(&mut self.shell);
        }
    }
}
