//! Blocks of vectors held by rows across the ranks, as the block Krylov methods
//! ([`super::block_lanczos`], [`super::block_krylov_schur`]) hold their bases: products with
//! a distributed sparse matrix, sums of small matrices over the ranks, start blocks.

use crate::petsc::{Comm, DenseMatrix, Matrix, Result};
use faer::{Mat, MatRef, Side};

/// A x for a block x of this rank's rows. Collective.
pub fn times(comm: Comm<'_>, a: &Matrix<'_>, x: MatRef<'_, f64>) -> Result<Mat<f64>> {
    // Every rank has the same columns, so every rank returns here alike.
    if x.ncols() == 0 {
        return Ok(Mat::zeros(x.nrows(), 0));
    }
    let mut dense = DenseMatrix::zeros(comm, x.nrows(), x.ncols())?;
    dense.write_local(|i, j| x[(i, j)])?;
    a.mult_tall(&dense)?.local_values()
}

/// The ranks' sum of a small matrix, with rank 0's bits on every rank (collective).
pub fn sum_identically(comm: Comm<'_>, a: &mut Mat<f64>) {
    let (rows, cols) = (a.nrows(), a.ncols());
    let mut values: Vec<f64> = (0..cols)
        .flat_map(|j| (0..rows).map(move |i| (i, j)))
        .map(|(i, j)| a[(i, j)])
        .collect();
    comm.sum_identically(&mut values);
    *a = Mat::from_fn(rows, cols, |i, j| values[j * rows + i]);
}

/// W made orthonormal in place by Cholesky QR, twice (once leaves errors of cond(W)^2 eps;
/// twice, of eps, while cond(W) is below about 1e7): in the M-inner product when `mw` is
/// M W (kept equal to M W), else in the Euclidean one. Returns R with W_before = W_after R,
/// or `None` when W's columns are (nearly) dependent. Collective.
pub fn orthonormalise(
    comm: Comm<'_>,
    w: &mut Mat<f64>,
    mut mw: Option<&mut Mat<f64>>,
) -> Result<Option<Mat<f64>>> {
    let b = w.ncols();
    let mut r = Mat::<f64>::identity(b, b);
    for pass in 0..2 {
        let mut g = match mw.as_deref() {
            Some(mw) => w.transpose() * mw,
            None => w.transpose() * &*w,
        };
        sum_identically(comm, &mut g);
        let g = Mat::from_fn(b, b, |p, q| 0.5 * (g[(p, q)] + g[(q, p)]));
        let Ok(llt) = g.llt(Side::Lower) else {
            return Ok(None);
        };
        let l = llt.L();
        // A second pass that has much left to do means the first lost too much to trust.
        if pass == 1 {
            let off = (0..b)
                .flat_map(|p| (0..b).map(move |q| (p, q)))
                .map(|(p, q)| (l[(p, q)] - if p == q { 1.0 } else { 0.0 }).abs())
                .fold(0.0f64, f64::max);
            if off > 1e-6 {
                return Ok(None);
            }
        }
        let mut l_inv = Mat::<f64>::identity(b, b);
        l.solve_lower_triangular_in_place(l_inv.as_mut());
        *w = &*w * l_inv.transpose();
        if let Some(mw) = mw.as_deref_mut() {
            *mw = &*mw * l_inv.transpose();
        }
        r = l.transpose() * &r;
    }
    Ok(Some(r))
}

/// A start vector's entry, uniform in [-1, 1) from its global row and column (splitmix64):
/// the same block on any number of ranks, so that one and two ranks take the same steps.
pub fn start_value(row: usize, column: usize) -> f64 {
    let mut z = ((row as u64) << 6 | column as u64).wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
}
