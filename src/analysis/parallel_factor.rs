//! One parallel factorisation of a symmetric K - shift M (MUMPS's LDL^T, the ranks sharing
//! its factors) that solves blocks held by rows, for block Lanczos
//! ([`super::block_lanczos`]) on a model's real modes: each step's block goes through the
//! factors in one multi-right-hand-side solve where SLEPc's Krylov-Schur makes one pass per
//! vector.

use super::block_lanczos::BlockSolve;
use crate::petsc::{
    Comm, DenseMatrix, DirectPackage, FactoredMatrix, Factorization, Matrix, Result, Structure,
};
use faer::{Mat, MatRef};

pub struct ParallelFactor<'rt> {
    comm: Comm<'rt>,
    factor: FactoredMatrix<'rt>,
    order: usize,
    rows: (usize, usize),
}

impl<'rt> ParallelFactor<'rt> {
    /// LDL^T of K - shift M by MUMPS (collective; a failed factorisation is an `Err` on
    /// every rank).
    pub fn new(
        comm: Comm<'rt>,
        k: &Matrix<'rt>,
        m: &Matrix<'rt>,
        shift: f64,
    ) -> Result<ParallelFactor<'rt>> {
        let mut shifted = k.duplicate()?;
        shifted.add(-shift, m, Structure::Unknown)?;
        shifted.mark_symmetric()?;
        let factor = FactoredMatrix::new(
            comm,
            &shifted,
            DirectPackage::Mumps,
            Factorization::Cholesky,
        )?;
        Ok(ParallelFactor {
            comm,
            factor,
            order: shifted.size()?.0,
            rows: shifted.ownership_range()?,
        })
    }
}

impl BlockSolve for ParallelFactor<'_> {
    fn order(&self) -> usize {
        self.order
    }
    fn local_rows(&self) -> usize {
        self.rows.1 - self.rows.0
    }
    fn first_row(&self) -> usize {
        self.rows.0
    }
    fn solve(&self, b: MatRef<'_, f64>) -> Result<Mat<f64>> {
        let mut rhs = DenseMatrix::zeros(self.comm, b.nrows(), b.ncols())?;
        rhs.write_local(|i, j| b[(i, j)])?;
        self.factor.solve_block(&rhs)?.local_values()
    }
}
