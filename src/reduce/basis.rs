//! The Craig-Bampton basis T kept for the life of a super-element, as this rank's rows: what
//! turns reduced coordinates back into the model's displacements (u = T q, METHOD.md §6
//! "Expansion") and a model's equilibrium into reduced coordinates.
//!
//! T is tall and thin (every equation of the model by |B| + modes + 1) and the products
//! asked of it are with a few replicated columns, so each rank keeps its own rows in faer and
//! multiplies locally; only the reductions of T^T v cross ranks.

use super::superelement::SuperElement;
use crate::petsc::{Comm, DenseMatrix, Matrix, PetscError, Vector};
use faer::linalg::solvers::Solve;
use faer::{Mat, MatRef};
use std::ops::Range;

/// This rank's rows of T, in the model's equation order.
pub struct LocalBasis {
    rows: Range<usize>,
    values: Mat<f64>,
}

impl LocalBasis {
    /// This rank's rows of a distributed T (no communication).
    pub fn from_dense(t: &DenseMatrix<'_>) -> Result<LocalBasis, PetscError> {
        let (lo, hi) = t.ownership_range()?;
        Ok(LocalBasis {
            rows: lo..hi,
            values: t.local_values()?,
        })
    }

    /// The equations this rank holds.
    pub fn rows(&self) -> Range<usize> {
        self.rows.clone()
    }

    /// Entry (i, j) of this rank's rows of T (i counts from the first of [`Self::rows`]).
    pub fn value(&self, i: usize, j: usize) -> f64 {
        self.values[(i, j)]
    }

    /// This rank's rows of T.
    pub fn values(&self) -> MatRef<'_, f64> {
        self.values.as_ref()
    }

    /// T with more columns `w` (this rank's rows) after its own.
    pub fn append_columns(&mut self, w: MatRef<'_, f64>) {
        let (rows, n) = (self.values.nrows(), self.values.ncols());
        let mut extended = Mat::<f64>::zeros(rows, n + w.ncols());
        extended
            .as_mut()
            .subcols_mut(0, n)
            .copy_from(self.values.as_ref());
        extended.as_mut().subcols_mut(n, w.ncols()).copy_from(w);
        self.values = extended;
    }

    /// Reduced coordinates: T's columns.
    pub fn size(&self) -> usize {
        self.values.ncols()
    }

    /// T Q for replicated columns Q (size x m): this rank's rows of the expansions.
    pub fn expand(&self, q: MatRef<'_, f64>) -> Mat<f64> {
        &self.values * q
    }

    /// T^T v for v given by its rows on this rank (the model's layout), the same on every
    /// rank (collective).
    pub fn project(&self, comm: Comm<'_>, v: &[f64]) -> Vec<f64> {
        let local = self.values.transpose() * Mat::from_fn(v.len(), 1, |i, _| v[i]);
        let mut sum: Vec<f64> = (0..self.size()).map(|j| local[(j, 0)]).collect();
        comm.sum_in_place(&mut sum);
        sum
    }

    /// The reduced coordinates of a displacement u of the model (all equations, the same on
    /// every rank) that lies in the span of T: the boundary read off u (T is the identity
    /// there), the interior coordinates the M-orthogonal fit of the rest,
    /// (C^T M C) x = C^T M (u - T_B u_B) with C the non-boundary columns, whose Gram matrix
    /// is a block of M_r. Exact for u in span T (then the fit's residual is 0), as the
    /// super-element's own equilibrium is: this is how a super-element is moved to another
    /// equilibrium of the same contact states. Collective.
    pub fn coordinates<'rt>(
        &self,
        comm: Comm<'rt>,
        se: &SuperElement,
        boundary_equations: &[usize],
        mass: &Matrix<'rt>,
        u: &[f64],
    ) -> Result<Vec<f64>, CoordinatesError> {
        let n_b = boundary_equations.len();
        let size = self.size();
        if se.header.size != size || n_b > size {
            return Err(CoordinatesError::Shape(format!(
                "a basis of {size} columns for a super-element of size {} and {n_b} boundary equations",
                se.header.size
            )));
        }
        let u_b: Vec<f64> = boundary_equations.iter().map(|&g| u[g]).collect();
        // w = u - T_B u_B on this rank's rows (0 on the boundary rows: T_B is I there).
        let t_b = self.values.subcols(0, n_b);
        let lifted = t_b * Mat::from_fn(n_b, 1, |i, _| u_b[i]);
        let local: Vec<f64> = self
            .rows
            .clone()
            .enumerate()
            .map(|(i, g)| u[g] - lifted[(i, 0)])
            .collect();
        let mut w = Vector::new(comm, local.len())?;
        w.set_local(&local)?;
        let mut mw = w.duplicate()?;
        mass.mult(&w, &mut mw)?;
        let projected = self.project(comm, &mw.read()?);
        let n_c = size - n_b;
        let gram = Mat::from_fn(n_c, n_c, |i, j| se.mass[(n_b + i, n_b + j)]);
        let rhs = Mat::from_fn(n_c, 1, |i, _| projected[n_b + i]);
        let x = gram
            .llt(faer::Side::Lower)
            .map_err(|e| CoordinatesError::Gram(format!("{e:?}")))?
            .solve(&rhs);
        let mut q = u_b;
        q.extend((0..n_c).map(|i| x[(i, 0)]));
        Ok(q)
    }
}

/// Why reduced coordinates could not be computed.
#[derive(Debug, thiserror::Error)]
pub enum CoordinatesError {
    #[error("{0}")]
    Shape(String),
    #[error("the interior block of the reduced mass is not positive definite ({0})")]
    Gram(String),
    #[error(transparent)]
    Petsc(#[from] PetscError),
}
