//! The eigenvalues of largest modulus of a real, non-symmetric operator S given by blocks,
//! by block Krylov-Schur: the CEA's shift-and-invert operator (K_t - sigma M)^-1 M, whose
//! largest eigenvalues theta = 1 / (omega^2 - sigma) are the omega^2 nearest the target,
//! and its transpose, whose eigenvectors are the left ones.
//!
//! Why not SLEPc's Krylov-Schur: it applies S to one vector at a time, and each application
//! is one pass through the LU factors. A block of [`BLOCK`] vectors goes through them in one
//! multi-right-hand-side solve: on medium-caliper's 199,791 equations (2 ranks, MUMPS)
//! 0.031 s a column against 0.144 s for a single solve (`examples/block_solve_bench.rs`),
//! where the CEA of a warm point made about 250 single solves after its one factorisation.
//!
//! The method. V_0 a block of start vectors (the same on any number of ranks), then
//! W = S V_j, orthogonalised twice against the whole basis (classical Gram-Schmidt: full
//! reorthogonalisation) and orthonormalised by Cholesky QR twice, W = V_{j+1} R_j. The
//! coefficients make G with S V_act = V G, V one block wider than V_act; its square part H
//! gives the Ritz pairs (theta, y), x = V_act y, whose residual |S x - theta x| is exactly
//! |B y| (B the last block of G's rows): no product tests convergence. When the basis is
//! full it restarts on the wanted Ritz pairs' invariant subspace of H, by the ordered real
//! Schur form (LAPACK's, [`invariant_subspace`]: Z orthonormal with H Z = Z T to
//! round-off, so S V_act Z = V_act Z T + V_next (B Z) holds again and the estimates stay
//! exact), and goes on from the unexpanded last block. Real arithmetic throughout: complex Ritz pairs
//! come in conjugate pairs, both returned, as SLEPc returns them.
//!
//! A pair has converged when |S x - theta x| <= tolerance |theta|: SLEPc's relative test,
//! which its Krylov-Schur takes on the transformed problem under shift-and-invert. The
//! estimate |B y| is the residual only if y is an eigenvector of H to round-off of |H|:
//! the small eigenproblems are LAPACK's ([`eigenpairs`], [`invariant_subspace`]), whose
//! results are backward stable, where faer's eigenvectors, on a super-element's dense pencil
//! with a target next to an eigenvalue (H's eigenvalues 1.6e-4 down to 7e-10), had
//! |H y - theta y| of 1e-4 |theta| and left pairs of relative residual 6.4e-6 in the pencil
//! behind estimates of 1e-20. The run stops when the pairs of largest modulus have converged
//! without a gap, `count` of them at least (a pair not yet converged holds back every pair
//! of smaller modulus), or returns `None` when it cannot (breakdown, too many restarts): the
//! caller then solves another way.

use super::blocks::{orthonormalise, start_value, sum_identically};
use crate::petsc::{eigenpairs, invariant_subspace, Comm, Result};
use faer::{Accum, Mat, MatRef, Par};
use num_complex::Complex64;

/// Columns a step takes. On medium-caliper (2 ranks, MUMPS) a column costs 0.144 s solved
/// alone, and in a block of 4 0.056 s, of 8 0.039 s, of 16 0.031 s, of 32 0.034 s (MUMPS
/// gathers a block's right-hand sides on one rank); but the wider the block, the lower the
/// degree of the Krylov polynomials a basis of a given size holds, and the more columns a
/// window needs: medium-caliper's warm window (93 pairs) took 272 columns in blocks of 8
/// and 384 in blocks of 16, its first point's four windows 600 against 1,264 (71.6 s of CEA
/// against 95.0 s, SLEPc's one vector at a time 90.9 s).
pub const BLOCK: usize = 8;

/// The basis holds this many times the caller's subspace (SLEPc's ncv for the same
/// window): with the subspace alone, small-caliper's 30-pair windows restarted 5-20 times
/// and its 91-pair window did not converge in 50 restarts (blocks of 16); with twice, 0-2.
const SUBSPACE_FACTOR: usize = 2;

/// Restarts allowed before the run gives up (SLEPc's Krylov-Schur converged a CEA window in
/// a handful; a run that needs this many has a spectrum it cannot separate).
const MAX_RESTARTS: usize = 50;

/// What [`largest`] found: the pairs of largest modulus that converged without a gap,
/// largest first, a conjugate pair's two members next to each other.
pub struct BlockPairs {
    /// The operator's eigenvalues theta.
    pub values: Vec<Complex64>,
    /// The eigenvectors' real and imaginary parts, this rank's rows (`local x count`), each
    /// eigenvector of unit 2-norm.
    pub re: Mat<f64>,
    pub im: Mat<f64>,
    /// |S x - theta x| / |theta| of each.
    pub estimates: Vec<f64>,
    /// Columns the operator was applied to.
    pub applied: usize,
    pub restarts: usize,
    /// Seconds in the operator's applications, in the orthogonalisation, and in the Ritz
    /// pairs and restarts.
    pub seconds: [f64; 3],
}

/// Ritz pairs of the square part of G: theta, y (unit 2-norm) and the estimate |B y| / |theta|,
/// largest |theta| first.
struct Ritz {
    values: Vec<Complex64>,
    vectors: Mat<Complex64>,
    estimates: Vec<f64>,
}

fn ritz(h: MatRef<'_, f64>, b: MatRef<'_, f64>) -> Option<Ritz> {
    let (s, u) = eigenpairs(h).ok()?;
    let n = h.nrows();
    let mut order: Vec<usize> = (0..n).collect();
    // Largest modulus first; a conjugate pair (equal moduli) positive imaginary part first.
    order.sort_by(|&p, &q| {
        let (a, c) = (s[p], s[q]);
        c.norm().total_cmp(&a.norm()).then(c.im.total_cmp(&a.im))
    });
    let mut values = Vec::with_capacity(n);
    let mut vectors = Mat::<Complex64>::zeros(n, n);
    let mut estimates = Vec::with_capacity(n);
    for (k, &p) in order.iter().enumerate() {
        let theta = Complex64::new(s[p].re, s[p].im);
        let norm = (0..n).map(|i| u[(i, p)].norm_sqr()).sum::<f64>().sqrt();
        if !(norm > 0.0 && norm.is_finite() && theta.norm() > 0.0) {
            return None;
        }
        for i in 0..n {
            let z = u[(i, p)];
            vectors[(i, k)] = Complex64::new(z.re, z.im) / norm;
        }
        let mut residual = 0.0;
        for r in 0..b.nrows() {
            let mut acc = Complex64::new(0.0, 0.0);
            for i in 0..n {
                acc += b[(r, i)] * vectors[(i, k)];
            }
            residual += acc.norm_sqr();
        }
        values.push(theta);
        estimates.push(residual.sqrt() / theta.norm());
    }
    Some(Ritz {
        values,
        vectors,
        estimates,
    })
}

/// How many of the leading pairs have converged without a gap, never ending between the two
/// members of a conjugate pair.
fn converged_prefix(r: &Ritz, tolerance: f64) -> usize {
    let mut n = r.estimates.iter().take_while(|&&e| e <= tolerance).count();
    if n > 0 && n < r.values.len() && is_first_of_pair(&r.values, n - 1) {
        n -= 1;
    }
    n
}

/// Whether value k is the first member of a conjugate pair (its partner next).
fn is_first_of_pair(values: &[Complex64], k: usize) -> bool {
    values[k].im > 0.0
        && k + 1 < values.len()
        && (values[k + 1] - values[k].conj()).norm() <= 1e-10 * values[k].norm()
}

/// The `count` eigenvalues of largest modulus of S (and those that converged with them), S
/// applied to a block of this rank's rows by `apply` (collective). `global` the operator's
/// order, `first_row` this rank's first global row, `subspace` the basis's columns at most
/// (grown to hold `count` and three blocks). Collective: every decision is taken from sums
/// every rank holds with the same bits.
pub fn largest(
    comm: Comm<'_>,
    (global, first_row, local): (usize, usize, usize),
    mut apply: impl FnMut(MatRef<'_, f64>) -> Result<Mat<f64>>,
    count: usize,
    subspace: usize,
    tolerance: f64,
) -> Result<Option<BlockPairs>> {
    let p = BLOCK;
    let cap = (SUBSPACE_FACTOR * subspace).max(count + 3 * p).div_ceil(p) * p;
    if count == 0 || cap + p > global {
        return Ok(None);
    }
    let mut v = Mat::<f64>::zeros(local, cap + p);
    let mut g = Mat::<f64>::zeros(cap + p, cap + p);
    let mut start = Mat::from_fn(local, p, |i, j| start_value(first_row + i, j));
    if orthonormalise(comm, &mut start, None)?.is_none() {
        return Ok(None);
    }
    v.as_mut().submatrix_mut(0, 0, local, p).copy_from(&start);
    // S V[.., ..active] = V[.., ..active + p] G[..active + p, ..active].
    let (mut active, mut applied, mut restarts) = (0usize, 0usize, 0usize);
    let mut seconds = [0.0; 3];
    loop {
        let clock = std::time::Instant::now();
        let mut w = apply(v.as_ref().submatrix(0, active, local, p))?;
        applied += p;
        seconds[0] += clock.elapsed().as_secs_f64();
        let clock = std::time::Instant::now();
        let k = active + p;
        // Kept for the column-wise fallback, should the block's QR break down.
        let original = w.clone();
        let (coefficients, r) =
            match block_gram_schmidt(comm, v.as_ref().submatrix(0, 0, local, k), &mut w)? {
                Some(done) => done,
                // The block is (nearly) rank deficient: a target next to an eigenvalue makes
                // every column of S V mostly that eigenvector. Column by column, a column with
                // nothing left replaced by a fresh vector.
                None => {
                    w = original;
                    column_gram_schmidt(
                        comm,
                        v.as_ref().submatrix(0, 0, local, k),
                        &mut w,
                        first_row,
                        applied,
                    )?
                }
            };
        g.as_mut()
            .submatrix_mut(0, active, k, p)
            .copy_from(&coefficients);
        v.as_mut().submatrix_mut(0, k, local, p).copy_from(&w);
        g.as_mut().submatrix_mut(k, active, p, p).copy_from(&r);
        active = k;
        seconds[1] += clock.elapsed().as_secs_f64();
        let clock = std::time::Instant::now();
        let Some(ritz) = ritz(
            g.as_ref().submatrix(0, 0, active, active),
            g.as_ref().submatrix(active, 0, p, active),
        ) else {
            return Ok(None);
        };
        let done = converged_prefix(&ritz, tolerance);
        if done >= count {
            let mut pairs = extract(v.as_ref(), &ritz, done, applied, restarts);
            seconds[2] += clock.elapsed().as_secs_f64();
            pairs.seconds = seconds;
            return Ok(Some(pairs));
        }
        if active + p <= cap {
            seconds[2] += clock.elapsed().as_secs_f64();
            continue;
        }
        // Restart on the wanted pairs: the converged ones and about half the rest of the
        // space, a conjugate pair kept whole.
        restarts += 1;
        if restarts > MAX_RESTARTS {
            tracing::debug!(
                "block Krylov-Schur: {done} of {count} converged after {MAX_RESTARTS} restarts"
            );
            return Ok(None);
        }
        // At most active - p - 1 before a pair is made whole, so that the expansion's block
        // still fits.
        let mut keep = (done + (cap - done) / 2).max(count).min(active - p - 1);
        if is_first_of_pair(&ritz.values, keep - 1) {
            keep += 1;
        }
        // The kept pairs' invariant subspace of H by its ordered Schur form: everything of
        // modulus above the midpoint between the last kept Ritz value and the first left.
        let threshold = if keep < ritz.values.len() {
            0.5 * (ritz.values[keep - 1].norm() + ritz.values[keep].norm())
        } else {
            0.0
        };
        let h = g.as_ref().submatrix(0, 0, active, active);
        let b = g.as_ref().submatrix(active, 0, p, active);
        let Ok((z, h_z)) = invariant_subspace(h, |theta| theta.norm() > threshold) else {
            tracing::debug!("block Krylov-Schur: no ordered Schur form at {active} columns");
            return Ok(None);
        };
        let kept = z.ncols();
        if kept == 0 || kept + p > cap {
            return Ok(None);
        }
        let b_z = b * &z;
        let next = v.as_ref().submatrix(0, active, local, p).to_owned();
        let u = v.as_ref().submatrix(0, 0, local, active) * &z;
        v.as_mut().submatrix_mut(0, 0, local, kept).copy_from(&u);
        v.as_mut().submatrix_mut(0, kept, local, p).copy_from(&next);
        g.fill(0.0);
        g.as_mut().submatrix_mut(0, 0, kept, kept).copy_from(&h_z);
        g.as_mut().submatrix_mut(kept, 0, p, kept).copy_from(&b_z);
        active = kept;
        seconds[2] += clock.elapsed().as_secs_f64();
    }
}

/// W orthogonalised against the orthonormal `basis` and orthonormalised, by blocks: block
/// classical Gram-Schmidt twice, each pass followed by the block's own Cholesky QR (BCGS2:
/// where W lies nearly in the basis already, what is left after one pass is small and
/// ill-conditioned, and its QR alone would magnify what it keeps of the basis; the second
/// pass takes that out). Returns (C, R) with W_before = basis C + W_after R, or `None` when
/// a Cholesky QR breaks down (W's remainder rank deficient). Collective.
fn block_gram_schmidt(
    comm: Comm<'_>,
    basis: MatRef<'_, f64>,
    w: &mut Mat<f64>,
) -> Result<Option<(Mat<f64>, Mat<f64>)>> {
    let (k, p) = (basis.ncols(), w.ncols());
    // W_0 = V (C_1 + C_2 R_1) + W_2 (R_2 R_1).
    let mut coefficients = Mat::<f64>::zeros(k, p);
    let mut r = Mat::<f64>::identity(p, p);
    for _ in 0..2 {
        let mut c = basis.transpose() * &*w;
        sum_identically(comm, &mut c);
        faer::linalg::matmul::matmul(w.as_mut(), Accum::Add, basis, c.as_ref(), -1.0, Par::Seq);
        coefficients += &c * &r;
        let Some(r_pass) = orthonormalise(comm, w, None)? else {
            return Ok(None);
        };
        r = &r_pass * &r;
    }
    Ok(Some((coefficients, r)))
}

/// [`block_gram_schmidt`] one column at a time, each against the basis and the block's
/// earlier columns, twice: a column with nothing left (below 1e-13 of its size: round-off)
/// is replaced by a start vector made orthogonal to all (its R column zero, so the relation
/// W_before = basis C + W_after R holds to that round-off). For blocks the Cholesky QR
/// cannot take. Collective: the same sums, so the same decisions, on every rank.
fn column_gram_schmidt(
    comm: Comm<'_>,
    basis: MatRef<'_, f64>,
    w: &mut Mat<f64>,
    first_row: usize,
    seed: usize,
) -> Result<(Mat<f64>, Mat<f64>)> {
    let (local, k, p) = (basis.nrows(), basis.ncols(), w.ncols());
    let mut coefficients = Mat::<f64>::zeros(k, p);
    let mut r = Mat::<f64>::zeros(p, p);
    let norm = |x: MatRef<'_, f64>| -> f64 {
        let mut s = Mat::from_fn(1, 1, |_, _| x.col(0).squared_norm_l2());
        sum_identically(comm, &mut s);
        s[(0, 0)].sqrt()
    };
    for j in 0..p {
        let size = norm(w.as_ref().subcols(j, 1));
        // Against the basis and the columns before j: c = [V, W_<j]^T w_j, twice.
        let orthogonalise = |w: &mut Mat<f64>, into: Option<(&mut Mat<f64>, &mut Mat<f64>)>| {
            let (done, rest) = w.as_mut().split_at_col_mut(j);
            let mut column = rest.subcols_mut(0, 1);
            let mut c = basis.transpose() * column.as_ref();
            let mut d = done.as_ref().transpose() * column.as_ref();
            sum_identically(comm, &mut c);
            sum_identically(comm, &mut d);
            faer::linalg::matmul::matmul(
                column.as_mut(),
                Accum::Add,
                basis,
                c.as_ref(),
                -1.0,
                Par::Seq,
            );
            faer::linalg::matmul::matmul(
                column.as_mut(),
                Accum::Add,
                done.as_ref(),
                d.as_ref(),
                -1.0,
                Par::Seq,
            );
            if let Some((coefficients, r)) = into {
                for i in 0..k {
                    coefficients[(i, j)] += c[(i, 0)];
                }
                for i in 0..j {
                    r[(i, j)] += d[(i, 0)];
                }
            }
        };
        for _ in 0..2 {
            orthogonalise(w, Some((&mut coefficients, &mut r)));
        }
        let left = norm(w.as_ref().subcols(j, 1));
        if left > 1e-13 * size && left > 0.0 {
            r[(j, j)] = left;
            for i in 0..local {
                w[(i, j)] /= left;
            }
            continue;
        }
        // Nothing left: a fresh direction, orthogonal to everything so far.
        for i in 0..local {
            w[(i, j)] = start_value(first_row + i, (seed + j) % 64 + 64);
        }
        for _ in 0..2 {
            orthogonalise(w, None);
        }
        let fresh = norm(w.as_ref().subcols(j, 1));
        for i in 0..local {
            w[(i, j)] /= fresh;
        }
    }
    Ok((coefficients, r))
}

/// The first `count` Ritz pairs as eigenpairs of S: x = V_act y.
fn extract(
    v: MatRef<'_, f64>,
    ritz: &Ritz,
    count: usize,
    applied: usize,
    restarts: usize,
) -> BlockPairs {
    let active = ritz.vectors.nrows();
    let basis = v.submatrix(0, 0, v.nrows(), active);
    let y_re = Mat::from_fn(active, count, |i, j| ritz.vectors[(i, j)].re);
    let y_im = Mat::from_fn(active, count, |i, j| ritz.vectors[(i, j)].im);
    BlockPairs {
        values: ritz.values[..count].to_vec(),
        re: basis * &y_re,
        im: basis * &y_im,
        estimates: ritz.estimates[..count].to_vec(),
        applied,
        restarts,
        seconds: [0.0; 3],
    }
}
