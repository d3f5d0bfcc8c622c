//! Sparse matrices (`Mat`, parallel AIJ). The nonzero pattern is given first, exactly, so
//! PETSc never allocates during assembly; values then go in as dense element blocks.

use super::dense::{same_comm, DenseMatrix};
use super::error::{check, PetscError, Result};
use super::is::IndexSet;
use super::runtime::{Comm, Runtime};
use super::sys;
use super::vec::{to_int, Vector};
use std::marker::PhantomData;

/// The exact nonzero pattern of the rows a rank owns, in CSR form with global column indices
/// sorted within each row.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct RowPattern {
    /// Number of columns this rank owns (the local size of the vector the matrix multiplies).
    pub local_cols: usize,
    /// `row_start[i]..row_start[i+1]` indexes `columns` for local row i; length rows + 1.
    pub row_start: std::vec::Vec<sys::PetscInt>,
    pub columns: std::vec::Vec<sys::PetscInt>,
}

impl RowPattern {
    pub fn local_rows(&self) -> usize {
        self.row_start.len().saturating_sub(1)
    }
    pub fn nonzeros(&self) -> usize {
        self.columns.len()
    }
}

/// A PETSc AIJ matrix distributed by rows.
pub struct Matrix<'rt> {
    pub(super) raw: sys::Mat,
    _rt: PhantomData<&'rt Runtime>,
}

/// Whether `add` may assume the same pattern.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Structure {
    Same,
    Subset,
    Different,
    /// Not known: PETSc checks (the same pattern is added in place, any other through a
    /// matrix of the union's pattern), as SLEPc's spectral transform does by default.
    Unknown,
}

impl Structure {
    fn raw(self) -> sys::MatStructure {
        match self {
            Structure::Same => sys::SAME_NONZERO_PATTERN,
            Structure::Subset => sys::SUBSET_NONZERO_PATTERN,
            Structure::Different => sys::DIFFERENT_NONZERO_PATTERN,
            Structure::Unknown => sys::UNKNOWN_NONZERO_PATTERN,
        }
    }
}

impl<'rt> Matrix<'rt> {
    pub(super) fn from_raw(raw: sys::Mat) -> Matrix<'rt> {
        Matrix {
            raw,
            _rt: PhantomData,
        }
    }

    /// A square or rectangular AIJ matrix with exactly the given pattern, all values zero
    /// (collective). Adding outside the pattern is an error, not a silent reallocation.
    pub fn with_pattern(comm: Comm<'rt>, pattern: &RowPattern) -> Result<Matrix<'rt>> {
        let rows = pattern.local_rows();
        if pattern.row_start.first().copied().unwrap_or(0) != 0
            || pattern.row_start.last().map(|&n| n as usize) != Some(pattern.columns.len())
        {
            return Err(PetscError::Invalid("malformed CSR row pattern".into()));
        }
        let mut raw = std::ptr::null_mut();
        // SAFETY: CSR arrays checked above; PETSc copies them.
        unsafe {
            check(sys::MatCreate(comm.raw, &mut raw))?;
            let m = Matrix::from_raw(raw);
            check(sys::MatSetSizes(
                raw,
                to_int(rows)?,
                to_int(pattern.local_cols)?,
                sys::PETSC_DETERMINE,
                sys::PETSC_DETERMINE,
            ))?;
            check(sys::MatSetType(raw, sys::MATAIJ.as_ptr().cast()))?;
            check(sys::MatSetFromOptions(raw))?;
            let start = if rows == 0 {
                vec![0]
            } else {
                pattern.row_start.clone()
            };
            // The CSR calls put the pattern in as explicit zeros: PETSc's assembly squeezes
            // out preallocated places never written, and the Jacobian must keep every
            // contact coupling whatever the current contact state.
            if comm.size() == 1 {
                check(sys::MatSeqAIJSetPreallocationCSR(
                    raw,
                    start.as_ptr(),
                    pattern.columns.as_ptr(),
                    std::ptr::null(),
                ))?;
            } else {
                check(sys::MatMPIAIJSetPreallocationCSR(
                    raw,
                    start.as_ptr(),
                    pattern.columns.as_ptr(),
                    std::ptr::null(),
                ))?;
            }
            check(sys::MatSetOption(
                raw,
                sys::MAT_NEW_NONZERO_ALLOCATION_ERR,
                sys::PETSC_TRUE,
            ))?;
            Ok(m)
        }
    }

    /// Adds a dense block: `values[i * cols.len() + j]` goes to `(rows[i], cols[j])` (global
    /// indices, any rank may add to any row). Negative indices are skipped, as in PETSc, so a
    /// constrained DOF can be passed as -1.
    pub fn add_block(
        &mut self,
        rows: &[sys::PetscInt],
        cols: &[sys::PetscInt],
        values: &[f64],
    ) -> Result<()> {
        self.block(rows, cols, values, sys::ADD_VALUES)
    }

    /// Sets a dense block (see [`Matrix::add_block`]).
    pub fn set_block(
        &mut self,
        rows: &[sys::PetscInt],
        cols: &[sys::PetscInt],
        values: &[f64],
    ) -> Result<()> {
        self.block(rows, cols, values, sys::INSERT_VALUES)
    }

    fn block(
        &mut self,
        rows: &[sys::PetscInt],
        cols: &[sys::PetscInt],
        values: &[f64],
        mode: sys::InsertMode,
    ) -> Result<()> {
        if rows.len() * cols.len() != values.len() {
            return Err(PetscError::Invalid(format!(
                "block of {}x{} but {} values",
                rows.len(),
                cols.len(),
                values.len()
            )));
        }
        // SAFETY: lengths checked; PETSc copies.
        check(unsafe {
            sys::MatSetValues(
                self.raw,
                to_int(rows.len())?,
                rows.as_ptr(),
                to_int(cols.len())?,
                cols.as_ptr(),
                values.as_ptr(),
                mode,
            )
        })
    }

    /// A sequential dense matrix (MATSEQDENSE) holding `values`, on a communicator of one
    /// rank: a reduced model's small dense operator handed to the same solvers as the full
    /// model's (a shift-and-invert eigensolve then factors it with LAPACK through PETSc's own
    /// LU, [`super::DirectPackage::Petsc`]).
    pub fn sequential_dense(comm: Comm<'rt>, values: faer::MatRef<'_, f64>) -> Result<Matrix<'rt>> {
        if comm.size() != 1 {
            return Err(PetscError::Invalid(format!(
                "a sequential dense matrix lives on one rank, not {}",
                comm.size()
            )));
        }
        let (rows, cols) = (values.nrows(), values.ncols());
        let mut raw = std::ptr::null_mut();
        // SAFETY: out-pointer to a local; a null data pointer makes PETSc allocate its own
        // column-major rows x cols array (leading dimension asked of it), which we fill
        // through the MatDenseGetArrayWrite / MatDenseRestoreArrayWrite pair, then assemble.
        unsafe {
            check(sys::MatCreateSeqDense(
                comm.raw,
                to_int(rows)?,
                to_int(cols)?,
                std::ptr::null_mut(),
                &mut raw,
            ))?;
            let mut m = Matrix::from_raw(raw);
            let mut lda = 0;
            check(sys::MatDenseGetLDA(raw, &mut lda))?;
            let lda = lda as usize;
            let mut ptr = std::ptr::null_mut();
            check(sys::MatDenseGetArrayWrite(raw, &mut ptr))?;
            for j in 0..cols {
                for i in 0..rows {
                    *ptr.add(j * lda + i) = values[(i, j)];
                }
            }
            check(sys::MatDenseRestoreArrayWrite(raw, &mut ptr))?;
            m.assemble()?;
            Ok(m)
        }
    }

    /// Rows `rows` and columns `cols` (global indices, increasing) of self, the whole block
    /// on this rank as a sequential AIJ matrix on `alone` (a communicator of this rank only),
    /// numbered in the order given. Collective over self's communicator (MatCreateSubMatrices),
    /// each rank asking for its own block: how a rank gets its own copy of a block to factor.
    pub fn sequential_submatrix(
        &self,
        alone: Comm<'rt>,
        rows: &[usize],
        cols: &[usize],
    ) -> Result<Matrix<'rt>> {
        if alone.size() != 1 {
            return Err(PetscError::Invalid(format!(
                "a sequential sub-matrix lives on one rank, not {}",
                alone.size()
            )));
        }
        let rows = IndexSet::new(alone, rows)?;
        let cols = IndexSet::new(alone, cols)?;
        let mut subs: *mut sys::Mat = std::ptr::null_mut();
        // SAFETY: live matrix and index sets; PETSc allocates the array of one matrix, which
        // MatDestroySubMatrices frees with the matrix; the reference taken first keeps the
        // matrix alive for the `Matrix` that owns it from then on.
        unsafe {
            check(sys::MatCreateSubMatrices(
                self.raw,
                1,
                &rows.raw,
                &cols.raw,
                sys::MAT_INITIAL_MATRIX,
                &mut subs,
            ))?;
            let sub = *subs;
            check(sys::PetscObjectReference(sub.cast()))?;
            check(sys::MatDestroySubMatrices(1, &mut subs))?;
            Ok(Matrix::from_raw(sub))
        }
    }

    /// Final assembly: communicates off-rank entries (collective).
    pub fn assemble(&mut self) -> Result<()> {
        // SAFETY: live matrix.
        unsafe {
            check(sys::MatAssemblyBegin(self.raw, sys::MAT_FINAL_ASSEMBLY))?;
            check(sys::MatAssemblyEnd(self.raw, sys::MAT_FINAL_ASSEMBLY))
        }
    }

    /// Sets all values to zero, keeping the pattern (collective).
    pub fn zero(&mut self) -> Result<()> {
        // SAFETY: live matrix.
        check(unsafe { sys::MatZeroEntries(self.raw) })
    }

    /// A copy with the same pattern and values (collective).
    pub fn duplicate(&self) -> Result<Matrix<'rt>> {
        let mut raw = std::ptr::null_mut();
        // SAFETY: live matrix.
        check(unsafe { sys::MatDuplicate(self.raw, sys::MAT_COPY_VALUES, &mut raw) })?;
        Ok(Matrix::from_raw(raw))
    }

    /// self += alpha * x (collective).
    pub fn add(&mut self, alpha: f64, x: &Matrix<'rt>, structure: Structure) -> Result<()> {
        // SAFETY: both live.
        check(unsafe { sys::MatAXPY(self.raw, alpha, x.raw, structure.raw()) })
    }

    /// self *= alpha (collective).
    pub fn scale(&mut self, alpha: f64) -> Result<()> {
        // SAFETY: live matrix.
        check(unsafe { sys::MatScale(self.raw, alpha) })
    }

    /// y = self * x (collective).
    pub fn mult(&self, x: &Vector<'rt>, y: &mut Vector<'rt>) -> Result<()> {
        // SAFETY: live objects of compatible layouts (PETSc checks sizes).
        check(unsafe { sys::MatMult(self.raw, x.raw, y.raw) })
    }

    /// y = self^T * x (collective).
    pub fn mult_transpose(&self, x: &Vector<'rt>, y: &mut Vector<'rt>) -> Result<()> {
        // SAFETY: as mult.
        check(unsafe { sys::MatMultTranspose(self.raw, x.raw, y.raw) })
    }

    /// Vectors compatible with the matrix: (right = x in A x, left = y) (collective).
    pub fn vectors(&self) -> Result<(Vector<'rt>, Vector<'rt>)> {
        let (mut r, mut l) = (std::ptr::null_mut(), std::ptr::null_mut());
        // SAFETY: out-pointers to locals.
        check(unsafe { sys::MatCreateVecs(self.raw, &mut r, &mut l) })?;
        Ok((Vector::from_raw(r), Vector::from_raw(l)))
    }

    /// Global (rows, cols).
    pub fn size(&self) -> Result<(usize, usize)> {
        let (mut m, mut n) = (0, 0);
        // SAFETY: out-pointers to locals.
        check(unsafe { sys::MatGetSize(self.raw, &mut m, &mut n) })?;
        Ok((m as usize, n as usize))
    }

    /// The global rows `[start, end)` this rank owns.
    pub fn ownership_range(&self) -> Result<(usize, usize)> {
        let (mut lo, mut hi) = (0, 0);
        // SAFETY: out-pointers to locals.
        check(unsafe { sys::MatGetOwnershipRange(self.raw, &mut lo, &mut hi) })?;
        Ok((lo as usize, hi as usize))
    }

    /// Whether self equals its transpose to `tolerance` (collective).
    pub fn is_symmetric(&self, tolerance: f64) -> Result<bool> {
        let mut flag = sys::PETSC_FALSE;
        // SAFETY: out-pointer to a local.
        check(unsafe { sys::MatIsSymmetric(self.raw, tolerance, &mut flag) })?;
        Ok(flag == sys::PETSC_TRUE)
    }

    /// The diagonal, as a vector laid out like the rows (collective).
    pub fn diagonal(&self) -> Result<Vector<'rt>> {
        let (_, d) = self.vectors()?;
        // SAFETY: live matrix; `d` has the row layout.
        check(unsafe { sys::MatGetDiagonal(self.raw, d.raw) })?;
        Ok(d)
    }

    /// Frobenius norm (collective).
    pub fn norm_frobenius(&self) -> Result<f64> {
        let mut n = 0.0;
        // SAFETY: out-pointer to a local.
        check(unsafe { sys::MatNorm(self.raw, sys::NORM_FROBENIUS, &mut n) })?;
        Ok(n)
    }

    /// Tells PETSc the matrix is symmetric (lets Cholesky be used on it).
    pub fn mark_symmetric(&mut self) -> Result<()> {
        // SAFETY: live matrix.
        unsafe {
            check(sys::MatSetOption(
                self.raw,
                sys::MAT_SYMMETRIC,
                sys::PETSC_TRUE,
            ))?;
            check(sys::MatSetOption(
                self.raw,
                sys::MAT_SYMMETRY_ETERNAL,
                sys::PETSC_TRUE,
            ))
        }
    }

    /// The entries of a locally owned row as (global column, value) pairs.
    pub fn row(&self, row: usize) -> Result<std::vec::Vec<(usize, f64)>> {
        let mut ncols = 0;
        let mut cols = std::ptr::null();
        let mut vals = std::ptr::null();
        let row = to_int(row)?;
        // SAFETY: MatGetRow / MatRestoreRow pair; the slices are copied before restore.
        unsafe {
            check(sys::MatGetRow(
                self.raw, row, &mut ncols, &mut cols, &mut vals,
            ))?;
            let n = ncols as usize;
            let out = if n == 0 {
                vec![]
            } else {
                let c = std::slice::from_raw_parts(cols, n);
                let v = std::slice::from_raw_parts(vals, n);
                c.iter().zip(v).map(|(&c, &v)| (c as usize, v)).collect()
            };
            check(sys::MatRestoreRow(
                self.raw, row, &mut ncols, &mut cols, &mut vals,
            ))?;
            Ok(out)
        }
    }

    /// The sub-matrix of the rows in `rows` and the columns in `cols`, e.g. K_II, K_IB or
    /// M_II of a super-element (collective; MatCreateSubMatrix with MAT_INITIAL_MATRIX, a
    /// new matrix with its own copy of the values). This rank gets the rows of its part of
    /// `rows`, normally rows it owns (as from [`IndexSet::owned_subset`]), and owns the
    /// columns of its part of `cols`; with both sets made from one split of the ownership
    /// ranges the sub-matrix is distributed like the original.
    pub fn submatrix(&self, rows: &IndexSet<'rt>, cols: &IndexSet<'rt>) -> Result<Matrix<'rt>> {
        let mut raw = std::ptr::null_mut();
        // SAFETY: live matrix and index sets; out-pointer to a local.
        check(unsafe {
            sys::MatCreateSubMatrix(
                self.raw,
                rows.raw,
                cols.raw,
                sys::MAT_INITIAL_MATRIX,
                &mut raw,
            )
        })?;
        Ok(Matrix::from_raw(raw))
    }

    /// A new matrix holding self^T (collective; MatTranspose with MAT_INITIAL_MATRIX), e.g.
    /// for the symmetric part (A + A^T) / 2 of an unsymmetric tangent.
    pub fn transpose(&self) -> Result<Matrix<'rt>> {
        let mut raw = std::ptr::null_mut();
        // SAFETY: live matrix; out-pointer to a local.
        check(unsafe { sys::MatTranspose(self.raw, sys::MAT_INITIAL_MATRIX, &mut raw) })?;
        Ok(Matrix::from_raw(raw))
    }

    /// P^T self P, a new sparse matrix (collective; MatPtAP with MAT_INITIAL_MATRIX). P's
    /// rows are laid out like self's rows and columns. The product's pattern comes from
    /// the patterns of self and P (explicit zeros included), so it holds whatever coupling
    /// self's pattern holds.
    pub fn ptap(&self, p: &Matrix<'rt>) -> Result<Matrix<'rt>> {
        let mut raw = std::ptr::null_mut();
        // SAFETY: live matrices; PETSc checks the layouts; out-pointer to a local.
        check(unsafe {
            sys::MatPtAP(
                self.raw,
                p.raw,
                sys::MAT_INITIAL_MATRIX,
                sys::PETSC_DEFAULT as f64,
                &mut raw,
            )
        })?;
        Ok(Matrix::from_raw(raw))
    }

    /// P^T self P into `out`, which [`Matrix::ptap`] made from P and a matrix of self's
    /// pattern (collective; MatPtAP with MAT_REUSE_MATRIX, the symbolic product kept).
    pub fn ptap_into(&self, p: &Matrix<'rt>, out: &mut Matrix<'rt>) -> Result<()> {
        let mut raw = out.raw;
        // SAFETY: live matrices; `out` was made by MatPtAP, so it carries the product
        // data MAT_REUSE_MATRIX needs (PETSc checks it); the handle stays the same.
        check(unsafe {
            sys::MatPtAP(
                self.raw,
                p.raw,
                sys::MAT_REUSE_MATRIX,
                sys::PETSC_DEFAULT as f64,
                &mut raw,
            )
        })?;
        out.raw = raw;
        Ok(())
    }

    /// self * t for a dense block t whose rows are laid out like self's columns (collective;
    /// MatMatMult). `t`'s communicator must be the one self lives on.
    pub fn mult_dense(&self, t: &DenseMatrix<'rt>) -> Result<DenseMatrix<'rt>> {
        same_comm(self.raw.cast(), t.comm())?;
        let mut raw = std::ptr::null_mut();
        // SAFETY: live matrices; PETSc checks that the layouts agree.
        check(unsafe {
            sys::MatMatMult(
                self.raw,
                t.raw,
                sys::MAT_INITIAL_MATRIX,
                sys::PETSC_DEFAULT as f64,
                &mut raw,
            )
        })?;
        Ok(DenseMatrix::from_raw(t.comm(), raw))
    }

    /// The projection T^T self T onto the columns of a distributed dense basis T (rows laid
    /// out like self's rows and columns), e.g. K_r = T^T K T of a super-element. Collective:
    /// A T by MatMatMult, then T^T (A T) by MatTransposeMatMult, whose m x m result is
    /// gathered to every rank with the same bits on each (see [`DenseMatrix::to_faer`]).
    /// Symmetric only to round-off when self is symmetric: not symmetrised here.
    pub fn project(&self, t: &DenseMatrix<'rt>) -> Result<faer::Mat<f64>> {
        let at = self.mult_dense(t)?;
        t.transpose_mult(&at)
    }

    /// [`Self::project`] for a symmetric self: T^T (A T) block column by block column, the
    /// blocks on and below the diagonal only (half the products), mirrored; the ranks'
    /// pieces summed with the same bits on every rank. Exactly symmetric. Collective.
    pub fn project_symmetric(&self, t: &DenseMatrix<'rt>) -> Result<faer::Mat<f64>> {
        // Wide enough for matrix-product speed, narrow enough that the skipped upper blocks
        // are most of the upper triangle.
        const BLOCK: usize = 128;
        let n = t.size()?.1;
        let mut lower = faer::Mat::<f64>::zeros(n, n);
        let mut block_product =
            |b0: usize, al: faer::MatRef<'_, f64>, tl: faer::MatRef<'_, f64>| {
                faer::linalg::matmul::matmul(
                    lower.as_mut().submatrix_mut(b0, b0, n - b0, al.ncols()),
                    faer::Accum::Replace,
                    tl.subcols(b0, n - b0).transpose(),
                    al,
                    1.0,
                    faer::Par::Seq,
                );
            };
        // A T a block of columns at a time, each block's products taken at once: the whole
        // of A T (as large as T) is never held.
        if !self.product_blocks(t, BLOCK, &mut block_product)? {
            let at = self.mult_dense(t)?;
            t.with_local(|tl| {
                at.with_local(|al| {
                    for b0 in (0..n).step_by(BLOCK) {
                        block_product(b0, al.subcols(b0, BLOCK.min(n - b0)), tl);
                    }
                })
            })??;
        }
        let mut values: std::vec::Vec<f64> = (0..n)
            .flat_map(|j| (0..n).map(move |i| (i, j)))
            .map(|(i, j)| if i >= j { lower[(i, j)] } else { lower[(j, i)] })
            .collect();
        t.comm().sum_identically(&mut values);
        Ok(faer::Mat::from_fn(n, n, |i, j| values[j * n + i]))
    }
}

impl Drop for Matrix<'_> {
    fn drop(&mut self) {
        // SAFETY: we own the handle; the runtime outlives us.
        unsafe { sys::MatDestroy(&mut self.raw) };
    }
}
