//! LAPACK's eigenvalue routines for the small dense matrices of a Krylov method, from the
//! LAPACK PETSc itself links: the ordered real Schur form (dgees, then dtrsen), an
//! orthonormal basis of the invariant subspace of chosen eigenvalues, which is the restart a
//! Krylov-Schur method keeps; and eigenpairs (dgeev), its Ritz pairs
//! ([`crate::analysis::block_krylov_schur`]).
//!
//! Why Schur vectors for the restart and not the chosen eigenvectors: a basis of
//! eigenvectors spans an invariant subspace only to the eigenvectors' accuracy (eps times
//! their condition), and a restart on a subspace that is not invariant carries that error
//! into every later residual estimate. Schur vectors are orthonormal and invariant to
//! round-off whatever the eigenvectors' condition; faer's Schur form is not public, LAPACK's
//! is, with its reordering (dtrsen). Why LAPACK's eigenvectors: see [`eigenpairs`].

use super::error::{PetscError, Result};
use faer::{Mat, MatRef};
use num_complex::Complex64;
use std::ffi::c_char;

extern "C" {
    fn dgeev_(
        jobvl: *const c_char,
        jobvr: *const c_char,
        n: *const i32,
        a: *mut f64,
        lda: *const i32,
        wr: *mut f64,
        wi: *mut f64,
        vl: *mut f64,
        ldvl: *const i32,
        vr: *mut f64,
        ldvr: *const i32,
        work: *mut f64,
        lwork: *const i32,
        info: *mut i32,
        jobvl_len: usize,
        jobvr_len: usize,
    );
    // Fortran: character arguments by pointer with hidden lengths at the end, LOGICAL and
    // INTEGER as 32-bit ints (LAPACK's default integers, as PETSc's are here).
    fn dgees_(
        jobvs: *const c_char,
        sort: *const c_char,
        select: *const std::ffi::c_void,
        n: *const i32,
        a: *mut f64,
        lda: *const i32,
        sdim: *mut i32,
        wr: *mut f64,
        wi: *mut f64,
        vs: *mut f64,
        ldvs: *const i32,
        work: *mut f64,
        lwork: *const i32,
        bwork: *mut i32,
        info: *mut i32,
        jobvs_len: usize,
        sort_len: usize,
    );
    fn dtrsen_(
        job: *const c_char,
        compq: *const c_char,
        select: *const i32,
        n: *const i32,
        t: *mut f64,
        ldt: *const i32,
        q: *mut f64,
        ldq: *const i32,
        wr: *mut f64,
        wi: *mut f64,
        m: *mut i32,
        s: *mut f64,
        sep: *mut f64,
        work: *mut f64,
        lwork: *const i32,
        iwork: *mut i32,
        liwork: *const i32,
        info: *mut i32,
        job_len: usize,
        compq_len: usize,
    );
}

/// The invariant subspace of `a` (square) belonging to the eigenvalues `chosen` selects (a
/// conjugate pair is chosen or left whole: chosen when either member is): Q (`n x m`,
/// orthonormal columns spanning it) and T = Q^T A Q (`m x m`, quasi-triangular). `Err` when
/// LAPACK reports a failure (no convergence of the QR algorithm, or a reordering of too
/// close eigenvalues). Pure, rank-local.
pub fn invariant_subspace(
    a: MatRef<'_, f64>,
    chosen: impl Fn(Complex64) -> bool,
) -> Result<(Mat<f64>, Mat<f64>)> {
    let n = a.nrows();
    if a.ncols() != n {
        return Err(PetscError::Invalid(format!(
            "a Schur form of a {n}x{} matrix",
            a.ncols()
        )));
    }
    if n == 0 {
        return Ok((Mat::zeros(0, 0), Mat::zeros(0, 0)));
    }
    let order = i32::try_from(n)
        .map_err(|_| PetscError::Invalid(format!("order {n} beyond LAPACK's integers")))?;
    let mut t: Vec<f64> = (0..n)
        .flat_map(|j| (0..n).map(move |i| (i, j)))
        .map(|(i, j)| a[(i, j)])
        .collect();
    let mut q = vec![0.0; n * n];
    let (mut wr, mut wi) = (vec![0.0; n], vec![0.0; n]);
    let mut work = vec![0.0; 8 * n];
    let lwork = order * 8;
    let (mut sdim, mut info) = (0i32, 0i32);
    let mut bwork = vec![0i32; n];
    // SAFETY: every array has the length LAPACK reads or writes for order n (A and VS n x n
    // with leading dimension n, WR and WI n, WORK lwork >= 3n, BWORK n, unreferenced with
    // SORT = 'N', as SELECT is); the characters are single bytes.
    unsafe {
        dgees_(
            c"V".as_ptr(),
            c"N".as_ptr(),
            std::ptr::null(),
            &order,
            t.as_mut_ptr(),
            &order,
            &mut sdim,
            wr.as_mut_ptr(),
            wi.as_mut_ptr(),
            q.as_mut_ptr(),
            &order,
            work.as_mut_ptr(),
            &lwork,
            bwork.as_mut_ptr(),
            &mut info,
            1,
            1,
        );
    }
    if info != 0 {
        return Err(PetscError::Invalid(format!(
            "LAPACK's real Schur form (dgees) of order {n} failed: info {info}"
        )));
    }
    let mut select: Vec<i32> = (0..n)
        .map(|i| i32::from(chosen(Complex64::new(wr[i], wi[i]))))
        .collect();
    // A pair stands in two consecutive entries: chosen whole when either member is.
    let mut i = 0;
    while i < n {
        if wi[i] != 0.0 && i + 1 < n {
            let pair = select[i] | select[i + 1];
            select[i] = pair;
            select[i + 1] = pair;
            i += 2;
        } else {
            i += 1;
        }
    }
    let (mut m, mut s, mut sep) = (0i32, 0.0, 0.0);
    let mut iwork = [0i32; 1];
    let (liwork, lwork) = (1i32, order.max(1));
    // SAFETY: as above; with JOB = 'N' dtrsen needs WORK of n and IWORK of 1, and writes
    // T, Q (n x n), WR, WI (n), M, S and SEP.
    unsafe {
        dtrsen_(
            c"N".as_ptr(),
            c"V".as_ptr(),
            select.as_ptr(),
            &order,
            t.as_mut_ptr(),
            &order,
            q.as_mut_ptr(),
            &order,
            wr.as_mut_ptr(),
            wi.as_mut_ptr(),
            &mut m,
            &mut s,
            &mut sep,
            work.as_mut_ptr(),
            &lwork,
            iwork.as_mut_ptr(),
            &liwork,
            &mut info,
            1,
            1,
        );
    }
    if info != 0 {
        return Err(PetscError::Invalid(format!(
            "LAPACK's reordering of a Schur form (dtrsen) of order {n} failed: info {info} \
             (eigenvalues too close to swap)"
        )));
    }
    let m = usize::try_from(m).unwrap_or(0).min(n);
    Ok((
        Mat::from_fn(n, m, |i, j| q[j * n + i]),
        Mat::from_fn(m, m, |i, j| t[j * n + i]),
    ))
}

/// The eigenvalues and right eigenvectors of a real square matrix (LAPACK's dgeev):
/// eigenvector j of unit 2-norm in column j, a conjugate pair's two eigenvalues and
/// vectors next to each other, the one of positive imaginary part first. `Err` when the QR
/// algorithm does not converge. Pure, rank-local.
///
/// Why not faer's: on a Krylov-Schur projection whose eigenvalues span five orders
/// (1.6e-4 down to 7e-10, a target next to an eigenvalue), faer 0.24's eigenvectors of the
/// smallest had |H y - theta y| of 1e-4 |theta|, 5e-10 |H| where LAPACK's backward stable
/// ones give round-off.
pub fn eigenpairs(a: MatRef<'_, f64>) -> Result<(Vec<Complex64>, Mat<Complex64>)> {
    let n = a.nrows();
    if a.ncols() != n {
        return Err(PetscError::Invalid(format!(
            "eigenpairs of a {n}x{} matrix",
            a.ncols()
        )));
    }
    if n == 0 {
        return Ok((Vec::new(), Mat::zeros(0, 0)));
    }
    let order = i32::try_from(n)
        .map_err(|_| PetscError::Invalid(format!("order {n} beyond LAPACK's integers")))?;
    let mut m: Vec<f64> = (0..n)
        .flat_map(|j| (0..n).map(move |i| (i, j)))
        .map(|(i, j)| a[(i, j)])
        .collect();
    let (mut wr, mut wi) = (vec![0.0; n], vec![0.0; n]);
    let mut vr = vec![0.0; n * n];
    let mut vl = [0.0; 1];
    let lwork = order * 8;
    let mut work = vec![0.0; 8 * n];
    let (one, mut info) = (1i32, 0i32);
    // SAFETY: A and VR are n x n with leading dimension n, WR and WI n, WORK lwork >= 4n;
    // VL is not referenced with JOBVL = 'N' (its leading dimension 1 is allowed then).
    unsafe {
        dgeev_(
            c"N".as_ptr(),
            c"V".as_ptr(),
            &order,
            m.as_mut_ptr(),
            &order,
            wr.as_mut_ptr(),
            wi.as_mut_ptr(),
            vl.as_mut_ptr(),
            &one,
            vr.as_mut_ptr(),
            &order,
            work.as_mut_ptr(),
            &lwork,
            &mut info,
            1,
            1,
        );
    }
    if info != 0 {
        return Err(PetscError::Invalid(format!(
            "LAPACK's eigenvalues (dgeev) of order {n} did not converge: info {info}"
        )));
    }
    let values: Vec<Complex64> = (0..n).map(|j| Complex64::new(wr[j], wi[j])).collect();
    let mut vectors = Mat::<Complex64>::zeros(n, n);
    let mut j = 0;
    while j < n {
        if wi[j] != 0.0 && j + 1 < n {
            // Columns j, j + 1 hold re and im of the vector of wr + i wi; its conjugate's
            // is re - i im.
            for i in 0..n {
                let (re, im) = (vr[j * n + i], vr[(j + 1) * n + i]);
                vectors[(i, j)] = Complex64::new(re, im);
                vectors[(i, j + 1)] = Complex64::new(re, -im);
            }
            j += 2;
        } else {
            for i in 0..n {
                vectors[(i, j)] = Complex64::new(vr[j * n + i], 0.0);
            }
            j += 1;
        }
    }
    for j in 0..n {
        let norm = (0..n)
            .map(|i| vectors[(i, j)].norm_sqr())
            .sum::<f64>()
            .sqrt();
        if norm > 0.0 {
            for i in 0..n {
                vectors[(i, j)] /= norm;
            }
        }
    }
    Ok((values, vectors))
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::linalg::solvers::Solve;

    /// Eigenpairs of a matrix whose eigenvalues span ten orders (a diagonal scaled by
    /// 1e-10 ... 1 with a conjugate pair among them, then a similarity): each pair's
    /// |A y - lambda y| is round-off of |A|, however small lambda is.
    #[test]
    fn eigenpairs_are_backward_stable_across_a_wide_spectrum() {
        let n = 8;
        let d = Mat::<f64>::from_fn(n, n, |i, j| match (i, j) {
            (0, 0) | (1, 1) => 1.0,
            (0, 1) => 0.5,
            (1, 0) => -0.5,
            (i, j) if i == j => 10f64.powi(-(i as i32) - 3),
            _ => 0.0,
        });
        let p = Mat::<f64>::from_fn(n, n, |i, j| {
            if i == j {
                1.0
            } else {
                ((i * 5 + j * 3) % 7) as f64 / 20.0
            }
        });
        let p_inv = p.partial_piv_lu().solve(Mat::<f64>::identity(n, n));
        let a = &p * &d * &p_inv;
        let (values, vectors) = eigenpairs(a.as_ref()).unwrap();
        let scale = a.norm_l2();
        for (j, lambda) in values.iter().enumerate() {
            let mut residual = 0.0;
            for i in 0..n {
                let mut acc = -lambda * vectors[(i, j)];
                for k in 0..n {
                    acc += a[(i, k)] * vectors[(k, j)];
                }
                residual += acc.norm_sqr();
            }
            assert!(
                residual.sqrt() < 1e-14 * scale,
                "{lambda}: {}",
                residual.sqrt()
            );
        }
        let pair = values
            .iter()
            .filter(|v| (v.norm() - 1.118).abs() < 1e-3)
            .count();
        assert_eq!(pair, 2, "{values:?}");
    }

    /// A real matrix with a conjugate pair, a double real eigenvalue and others: the chosen
    /// ones' subspace is invariant (A Q = Q T to round-off), Q orthonormal, T's eigenvalues
    /// exactly the chosen ones (a pair kept whole when one member is chosen).
    #[test]
    fn the_chosen_eigenvalues_invariant_subspace_is_orthonormal_and_invariant() {
        // Block diagonal [[2, 3], [-3, 2]] (2 +/- 3i), 5, 5, 1, 7, then a similarity.
        let d = Mat::<f64>::from_fn(6, 6, |i, j| match (i, j) {
            (0, 0) | (1, 1) => 2.0,
            (0, 1) => 3.0,
            (1, 0) => -3.0,
            (2, 2) | (3, 3) => 5.0,
            (4, 4) => 1.0,
            (5, 5) => 7.0,
            _ => 0.0,
        });
        let p = Mat::<f64>::from_fn(6, 6, |i, j| {
            if i == j {
                2.0
            } else {
                ((i * 7 + j * 3) % 5) as f64 / 10.0
            }
        });
        let p_inv = p.partial_piv_lu().solve(Mat::<f64>::identity(6, 6));
        let a = &p * &d * &p_inv;
        // Modulus above 4: the pair (|2 +/- 3i| = 3.6) only through its partner's rule, so
        // chose 2 + 3i alone by its imaginary part: the pair must come whole.
        let (q, t) = invariant_subspace(a.as_ref(), |z| z.re > 4.0 || z.im > 0.0).unwrap();
        assert_eq!(q.ncols(), 5);
        let qtq = q.transpose() * &q;
        for i in 0..5 {
            for j in 0..5 {
                let want = if i == j { 1.0 } else { 0.0 };
                assert!((qtq[(i, j)] - want).abs() < 1e-13, "Q^T Q {i} {j}");
            }
        }
        let residual = &a * &q - &q * &t;
        let scale = a.norm_l2();
        for v in residual.col_iter().flat_map(|c| c.iter().copied()) {
            assert!(v.abs() < 1e-13 * scale, "A Q - Q T: {v}");
        }
        let mut found: Vec<Complex64> = t.eigenvalues().unwrap().into_iter().collect();
        found.sort_by(|a, b| a.re.total_cmp(&b.re).then(a.im.total_cmp(&b.im)));
        let want = [
            Complex64::new(2.0, -3.0),
            Complex64::new(2.0, 3.0),
            Complex64::new(5.0, 0.0),
            Complex64::new(5.0, 0.0),
            Complex64::new(7.0, 0.0),
        ];
        for (f, w) in found.iter().zip(&want) {
            assert!((f - w).norm() < 1e-10, "{found:?}");
        }
    }
}
