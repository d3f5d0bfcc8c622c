//! The lowest eigenpairs of (K, M), K positive definite and M positive semi-definite, by
//! block shift-and-invert Lanczos about 0 on every rank's own factor of K
//! ([`ReplicatedFactor`]): the fixed-interface modes of a super-element, whose K_II a
//! boundary holds and whose factor the constraint modes have just made.
//!
//! Why not SLEPc's Krylov-Schur here: it takes one vector at a time. On small-caliper's
//! interior (61,533 equations, 78 modes below 20 kHz) it made 318 single triangular solves
//! through a parallel LDL^T (a factorisation of its own), and about four M-products a
//! solve for its M-inner products, each a pass over M's 70 MB that serves one vector:
//! 10.5 s of a 44 s sweep. Here a block of [`BLOCK`] vectors goes through each step at
//! once: its triangular solves are one multi-right-hand-side solve per rank (each rank its
//! share of the columns, with the factor it already has), its M-product one blocked pass
//! ([`Matrix::mult_tall`]), its orthogonalisation matrix products.
//!
//! The method: V_0 a block of start vectors (the same on any number of ranks), then
//! W = K^-1 M V_j, orthogonalised twice against every block so far in the M-inner product
//! (classical Gram-Schmidt: full reorthogonalisation, so no spurious copies), and
//! M-orthonormalised by Cholesky QR twice: W = V_{j+1} R_j. V^T M K^-1 M V is then the
//! block tridiagonal H of the coefficients, and its Ritz pairs (theta, z) give omega^2 =
//! 1 / theta, x = V z, with the residual of K^-1 M x - theta x in the M-norm exactly
//! |R_j z_j| (z_j the last block's rows of z): no product is needed to test convergence.
//! The caller gives the number of eigenvalues below `top` (an inertia count), and the run
//! stops when that many Ritz pairs below `top` have converged (M-orthonormal pairs of
//! small residual stand for as many distinct eigenvalues, so none was missed), or returns
//! `None` when the subspace reaches its limit first: the caller then solves another way.

use super::blocks::{orthonormalise, start_value, sum_identically, times};
use super::replicated_factor::ReplicatedFactor;
use crate::petsc::{Comm, Matrix, Result};
use faer::{Accum, Mat, MatRef, Par, Side};

/// A factorised K - shift M that solves blocks laid out by rows across the ranks: every
/// rank's own factor ([`ReplicatedFactor`]) or one factor the ranks share
/// ([`super::parallel_factor::ParallelFactor`]).
pub trait BlockSolve {
    /// The matrix's order.
    fn order(&self) -> usize;
    /// This rank's rows.
    fn local_rows(&self) -> usize;
    /// This rank's first row.
    fn first_row(&self) -> usize;
    /// A^-1 B for B of this rank's rows (collective; an `Err` on every rank or none).
    fn solve(&self, b: MatRef<'_, f64>) -> Result<Mat<f64>>;
}

impl BlockSolve for ReplicatedFactor<'_> {
    fn order(&self) -> usize {
        ReplicatedFactor::order(self)
    }
    fn local_rows(&self) -> usize {
        ReplicatedFactor::local_rows(self)
    }
    fn first_row(&self) -> usize {
        ReplicatedFactor::first_row(self)
    }
    fn solve(&self, b: MatRef<'_, f64>) -> Result<Mat<f64>> {
        ReplicatedFactor::solve(self, b)
    }
}

/// Where the run stands: its operator's shift and block, and the band it looks for.
#[derive(Clone, Copy, Debug)]
pub struct Lanczos {
    /// `factor` is K - shift M's, shift below every eigenvalue wanted.
    pub shift: f64,
    /// Columns a step takes.
    pub block: usize,
    /// The eigenvalues wanted: this many, all below `top`.
    pub count: usize,
    pub top: f64,
    pub tolerance: f64,
}

/// Vectors a block step takes: a multi-right-hand-side solve and a pass over M pay for 32
/// columns at once, and 78 modes need about 8 such steps.
pub const BLOCK: usize = 32;

/// The most a rank holds of the basis V and its M-products, bytes: the subspace's bound
/// where the mode count would make it larger (hundreds of modes, as a high cut-off on a
/// large interior asks; beyond it SLEPc's Krylov-Schur, which restarts, takes over). At
/// 2 GiB: small-caliper's 61,533 interior equations on 2 ranks allow 4,352 columns (221
/// modes below 40 kHz took 1,440 and did not converge), medium-caliper's ~200,000 on one
/// rank 640 (its 78 modes below 20 kHz need about 480).
const MAX_BASIS_BYTES: usize = 2 << 30;

/// A subspace of at least this many times the count accepts estimates up to
/// [`FLOOR_REACH`] times the tolerance. Why. The estimates of converged pairs bottom out
/// at a floor that rises with the subspace: on small-caliper's interior, 78 pairs (480
/// columns) at 1e-10 to 1e-9; 221 pairs below 40 kHz (1,440 columns) at 1e-8 to 6e-8, the
/// top pairs' Ritz values moving by about 1e-8 of themselves from step to step and the
/// count below 1e-8 going 169, 149, 200, 218, 219, 206 over steps 40-45, so that the run
/// never stopped and SLEPc's Krylov-Schur took 50 s more. (Not sym(H)'s doing: H's
/// asymmetry was 3.7e-24, 2.3e-13 of the top pair's theta.) An estimate e bounds a shape's
/// error by about e / gap, and a basis vector off by that moves the super-element's modes
/// by about that times their own truncation error: 1e-7 is as good for the basis as
/// 1e-8 there (`FIXED_INTERFACE_TOLERANCE` in `reduce::craig_bampton`).
const FLOOR_SPACE: usize = 3;

/// How far above the tolerance a large subspace's estimates may be (see [`FLOOR_SPACE`]).
const FLOOR_REACH: f64 = 10.0;

/// The blocks a run for `count` pairs may take: a space of about 6 count and four blocks of
/// [`BLOCK`] more (see [`lowest`]), at most the operator's order. The spare is in columns, not
/// in steps: narrower blocks need more columns, not fewer (the clamped disc's 21 lowest took
/// 152 columns in blocks of 8, where 6 count and four blocks of 8 allow 158).
fn subspace_blocks(n: usize, count: usize, block: usize) -> usize {
    let block = block.max(1);
    ((6 * count + 4 * block.max(BLOCK)) / block).min(n / block)
}

/// The blocks of V and M V that [`MAX_BASIS_BYTES`] holds on the largest rank (n / ranks
/// rounded up: the same bound on every rank).
fn memory_blocks(ranks: usize, n: usize, block: usize) -> usize {
    let rows_bound = n.div_ceil(ranks.max(1)).max(1);
    MAX_BASIS_BYTES / (2 * std::mem::size_of::<f64>() * rows_bound * block.max(1))
}

/// Whether a run for `count` pairs of an operator of order `n` has its whole subspace
/// within [`MAX_BASIS_BYTES`] a rank: where it has not, a caller with another solver at hand
/// (SLEPc's Krylov-Schur, which restarts) is better off with it than with a run that may
/// stop short of converging after all its steps.
pub fn subspace_fits(ranks: usize, n: usize, count: usize, block: usize) -> bool {
    subspace_blocks(n, count, block) <= memory_blocks(ranks, n, block)
}

/// What [`lowest_modes`] found.
pub struct LanczosModes {
    /// omega^2 (Rayleigh quotients of the shapes), increasing.
    pub eigenvalues: Vec<f64>,
    /// M-orthonormal shapes in the eigenvalues' order, this rank's rows (`local x count`).
    pub shapes: Mat<f64>,
    /// |K x - omega^2 M x| / |omega^2 M x| of each, from products with K and M.
    pub residuals: Vec<f64>,
    /// Block steps taken.
    pub steps: usize,
    /// Right-hand sides solved in all.
    pub solves: usize,
}

/// The `count` lowest eigenpairs of (K, M), which the caller knows to be the eigenvalues
/// below `top`, each converged to `tolerance` relative (the shift-and-invert residual
/// against theta, as SLEPc's own test). `factor` is K's; K and M are laid out by rows like
/// it. `Ok(None)` when they did not converge within a subspace of about 6 count + 4 blocks
/// (at most [`MAX_BASIS_BYTES`] a rank), or the basis broke down (a space invariant so early
/// has no more to give). Collective: every decision is taken from sums every rank holds with
/// the same bits.
pub fn lowest_modes(
    comm: Comm<'_>,
    factor: &ReplicatedFactor<'_>,
    k: &Matrix<'_>,
    m: &Matrix<'_>,
    count: usize,
    top: f64,
    tolerance: f64,
) -> Result<Option<LanczosModes>> {
    lowest(
        comm,
        factor,
        (k, m),
        Lanczos {
            shift: 0.0,
            block: BLOCK,
            count,
            top,
            tolerance,
        },
    )
}

/// [`lowest_modes`] on any [`BlockSolve`] of K - shift M, in steps of `block` columns:
/// theta = 1 / (omega^2 - shift), largest for the lowest omega^2 above the shift.
pub fn lowest(
    comm: Comm<'_>,
    factor: &impl BlockSolve,
    (k, m): (&Matrix<'_>, &Matrix<'_>),
    Lanczos {
        shift,
        block,
        count,
        top,
        tolerance,
    }: Lanczos,
) -> Result<Option<LanczosModes>> {
    let (n, local) = (factor.order(), factor.local_rows());
    if count == 0 {
        return Ok(Some(LanczosModes {
            eigenvalues: Vec::new(),
            shapes: Mat::zeros(local, 0),
            residuals: Vec::new(),
            steps: 0,
            solves: 0,
        }));
    }
    let b = block.max(1);
    // Shift-and-invert converges the pairs nearest the shift first; the last ones, near
    // `top`, where the spectrum is dense, took a space of 6 count on small-caliper's
    // interior (78 pairs: 15 steps of 32); four blocks of 32 more to spare.
    // And never more than the basis's memory bound: V and M V, this rank's rows.
    let max_blocks = subspace_blocks(n, count, b).min(memory_blocks(comm.size(), n, b));
    if max_blocks < 2 {
        return Ok(None);
    }
    let first = factor.first_row();
    let mut w = Mat::from_fn(local, b, |i, j| start_value(first + i, j));
    let mut mw = times(comm, m, w.as_ref())?;
    if orthonormalise(comm, &mut w, Some(&mut mw))?.is_none() {
        return Ok(None);
    }
    let (mut v, mut mv) = (vec![w], vec![mw]);
    let mut h = Mat::<f64>::zeros((max_blocks + 1) * b, max_blocks * b);
    let mut solves = 0;
    let started = std::time::Instant::now();
    for j in 0..max_blocks {
        let mut w = factor.solve(mv[j].as_ref())?;
        solves += b;
        let d = (j + 1) * b;
        for _ in 0..2 {
            let mut c = Mat::<f64>::zeros(d, b);
            for (i, mv_i) in mv.iter().enumerate() {
                c.as_mut()
                    .submatrix_mut(i * b, 0, b, b)
                    .copy_from(mv_i.transpose() * &w);
            }
            sum_identically(comm, &mut c);
            for (i, v_i) in v.iter().enumerate() {
                faer::linalg::matmul::matmul(
                    w.as_mut(),
                    Accum::Add,
                    v_i.as_ref(),
                    c.as_ref().submatrix(i * b, 0, b, b),
                    -1.0,
                    Par::Seq,
                );
            }
            let mut column = h.as_mut().submatrix_mut(0, j * b, d, b);
            column += &c;
        }
        let mut mw = times(comm, m, w.as_ref())?;
        let Some(r) = orthonormalise(comm, &mut w, Some(&mut mw))? else {
            tracing::debug!("block Lanczos: the basis broke down at step {}", j + 1);
            return Ok(None);
        };
        h.as_mut().submatrix_mut(d, j * b, b, b).copy_from(&r);
        if d >= count {
            let hs = Mat::from_fn(d, d, |p, q| 0.5 * (h[(p, q)] + h[(q, p)]));
            let Ok(evd) = hs.self_adjoint_eigen(Side::Lower) else {
                return Ok(None);
            };
            let (theta, z) = (evd.S().column_vector(), evd.U());
            // The count largest theta, largest first: the lowest omega^2 in order.
            let wanted: Vec<usize> = (d - count..d).rev().collect();
            let ratios: Vec<f64> = wanted
                .iter()
                .map(|&p| (&r * z.submatrix(j * b, p, b, 1)).norm_l2() / theta[p])
                .collect();
            // Past FLOOR_SPACE times the count, the estimates' floor is allowed for.
            let bound = if d >= FLOOR_SPACE * count {
                FLOOR_REACH * tolerance
            } else {
                tolerance
            };
            let converged = wanted.iter().zip(&ratios).all(|(&p, &ratio)| {
                theta[p] > 0.0 && shift + 1.0 / theta[p] < top * (1.0 + 1e-8) && ratio <= bound
            });
            tracing::debug!(
                "block Lanczos step {}: {} of {count} converged, the last {:e} (top {top:e}), \
                 residuals {:.1e} .. {:.1e}; {:.2} s",
                j + 1,
                ratios.iter().filter(|&&x| x <= bound).count(),
                shift + 1.0 / theta[wanted[count - 1]],
                ratios[0],
                ratios[count - 1],
                started.elapsed().as_secs_f64()
            );
            if converged {
                let zw = Mat::from_fn(d, count, |p, q| z[(p, wanted[q])]);
                let mut shapes = Mat::<f64>::zeros(local, count);
                for (i, v_i) in v.iter().enumerate() {
                    faer::linalg::matmul::matmul(
                        shapes.as_mut(),
                        Accum::Add,
                        v_i.as_ref(),
                        zw.as_ref().submatrix(i * b, 0, b, count),
                        1.0,
                        Par::Seq,
                    );
                }
                let (eigenvalues, residuals) = checked(comm, k, m, shapes.as_ref())?;
                tracing::debug!(
                    "block Lanczos: {count} pairs below {top:e} in {} steps of {b} ({solves} \
                     solves), largest residual {:.1e}",
                    j + 1,
                    residuals.iter().fold(0.0f64, |a, &r| a.max(r))
                );
                return Ok(Some(LanczosModes {
                    eigenvalues,
                    shapes,
                    residuals,
                    steps: j + 1,
                    solves,
                }));
            }
        }
        v.push(w);
        mv.push(mw);
    }
    tracing::debug!(
        "block Lanczos: {count} pairs below {top:e} not converged in {max_blocks} steps of {b}"
    );
    Ok(None)
}

/// Rayleigh quotients x^T K x / x^T M x and relative residuals of the shapes. Collective.
fn checked(
    comm: Comm<'_>,
    k: &Matrix<'_>,
    m: &Matrix<'_>,
    x: MatRef<'_, f64>,
) -> Result<(Vec<f64>, Vec<f64>)> {
    let (kx, mx) = (times(comm, k, x)?, times(comm, m, x)?);
    let count = x.ncols();
    let mut quotients = vec![0.0; 2 * count];
    for q in 0..count {
        for i in 0..x.nrows() {
            quotients[q] += x[(i, q)] * kx[(i, q)];
            quotients[count + q] += x[(i, q)] * mx[(i, q)];
        }
    }
    comm.sum_identically(&mut quotients);
    let values: Vec<f64> = (0..count)
        .map(|q| quotients[q] / quotients[count + q])
        .collect();
    let mut norms = vec![0.0; 2 * count];
    for (q, &value) in values.iter().enumerate() {
        for i in 0..x.nrows() {
            norms[q] += (kx[(i, q)] - value * mx[(i, q)]).powi(2);
            norms[count + q] += (value * mx[(i, q)]).powi(2);
        }
    }
    comm.sum_identically(&mut norms);
    let residuals = (0..count)
        .map(|q| (norms[q] / norms[count + q]).sqrt())
        .collect();
    Ok((values, residuals))
}
