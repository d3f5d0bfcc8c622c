//! Dense matrices (`MATDENSE`) distributed by rows like the sparse ones: the blocks of many
//! right-hand sides (K_IB), of many solutions (the constraint modes Psi), and reduction
//! bases T. Small dense results (T^T A T) come back as `faer` matrices on every rank.

use super::error::{check, PetscError, Result};
use super::mat::Matrix;
use super::runtime::Comm;
use super::sys;
use super::vec::{to_int, Vector};
use faer::Mat;
use mpi::datatype::PartitionMut;
use mpi::traits::CommunicatorCollectives;

/// A dense matrix distributed by rows: each rank stores its rows, all columns.
pub struct DenseMatrix<'rt> {
    pub(super) raw: sys::Mat,
    /// The communicator it lives on (also ties it to the runtime), for the gathers.
    comm: Comm<'rt>,
}

/// This rank's rows of a dense matrix, read in place (column-major with leading dimension
/// `lda`), restored with the read restore call on drop.
struct LocalRead<'a, 'rt> {
    m: &'a DenseMatrix<'rt>,
    ptr: *const f64,
    rows: usize,
    cols: usize,
    lda: usize,
}

impl LocalRead<'_, '_> {
    fn get(&self, i: usize, j: usize) -> f64 {
        debug_assert!(i < self.rows && j < self.cols);
        // SAFETY: PETSc gave rows x cols entries at stride lda, alive until restore.
        unsafe { *self.ptr.add(j * self.lda + i) }
    }
}

impl Drop for LocalRead<'_, '_> {
    fn drop(&mut self) {
        // SAFETY: matches MatDenseGetArrayRead in `DenseMatrix::local`.
        unsafe { sys::MatDenseRestoreArrayRead(self.m.raw, &mut self.ptr) };
    }
}

impl<'rt> DenseMatrix<'rt> {
    /// Takes ownership of a dense matrix PETSc created on `comm`.
    pub(super) fn from_raw(comm: Comm<'rt>, raw: sys::Mat) -> DenseMatrix<'rt> {
        DenseMatrix { raw, comm }
    }

    /// The communicator the matrix lives on.
    pub fn comm(&self) -> Comm<'rt> {
        self.comm
    }

    /// A zero matrix with `local_rows` rows on this rank and `cols` columns (collective; the
    /// local rows add up to the global row count).
    pub fn zeros(comm: Comm<'rt>, local_rows: usize, cols: usize) -> Result<DenseMatrix<'rt>> {
        let mut raw = std::ptr::null_mut();
        // SAFETY: out-pointer to a local; a null data pointer makes PETSc allocate (zeroed).
        unsafe {
            check(sys::MatCreateDense(
                comm.raw,
                to_int(local_rows)?,
                sys::PETSC_DECIDE,
                sys::PETSC_DETERMINE,
                to_int(cols)?,
                std::ptr::null_mut(),
                &mut raw,
            ))?;
        }
        let mut m = DenseMatrix::from_raw(comm, raw);
        m.assemble()?;
        Ok(m)
    }

    /// The dense copy of a sparse matrix `a` created on `comm`, same row and column layout
    /// (collective; MatConvert). For a block of right-hand sides such as K_IB: the columns
    /// are few, the rows many.
    pub fn from_sparse(comm: Comm<'rt>, a: &Matrix<'rt>) -> Result<DenseMatrix<'rt>> {
        same_comm(a.raw.cast(), comm)?;
        let mut raw = std::ptr::null_mut();
        // SAFETY: live matrix; out-pointer to a local.
        check(unsafe {
            sys::MatConvert(
                a.raw,
                sys::MATDENSE.as_ptr().cast(),
                sys::MAT_INITIAL_MATRIX,
                &mut raw,
            )
        })?;
        Ok(DenseMatrix::from_raw(comm, raw))
    }

    /// The matrix whose column j is `columns[j]`, rows laid out like the vectors (collective;
    /// all vectors must have the same layout, and there must be at least one).
    pub fn from_columns(comm: Comm<'rt>, columns: &[Vector<'rt>]) -> Result<DenseMatrix<'rt>> {
        let first = columns
            .first()
            .ok_or_else(|| PetscError::Invalid("a dense matrix needs a column".into()))?;
        let range = first.ownership_range()?;
        let mut same = true;
        for v in columns {
            same &= v.ownership_range()? == range;
        }
        if !comm.all(same) {
            return Err(PetscError::Invalid(
                "the columns of a dense matrix must share one row layout".into(),
            ));
        }
        let rows = range.1 - range.0;
        let mut m = DenseMatrix::zeros(comm, rows, columns.len())?;
        let values: std::vec::Vec<std::vec::Vec<f64>> = columns
            .iter()
            .map(|v| Ok(v.read()?.to_vec()))
            .collect::<Result<_>>()?;
        m.write_local(|i, j| values[j][i])?;
        Ok(m)
    }

    /// Sets this rank's rows: entry (local row i, column j) becomes `value(i, j)`, then
    /// assembles (collective).
    pub fn write_local(&mut self, value: impl Fn(usize, usize) -> f64) -> Result<()> {
        let (rows, cols) = (self.local_rows()?, self.size()?.1);
        let lda = self.lda()?;
        let mut ptr = std::ptr::null_mut();
        // SAFETY: MatDenseGetArrayWrite / MatDenseRestoreArrayWrite pair; we write only the
        // rows x cols entries at stride lda that PETSc stores for this rank.
        unsafe {
            check(sys::MatDenseGetArrayWrite(self.raw, &mut ptr))?;
            for j in 0..cols {
                for i in 0..rows {
                    *ptr.add(j * lda + i) = value(i, j);
                }
            }
            check(sys::MatDenseRestoreArrayWrite(self.raw, &mut ptr))?;
        }
        self.assemble()
    }

    /// `f` on this rank's rows written in place, as a `local_rows x cols` faer view (no copy),
    /// then the matrix assembled (collective).
    pub(super) fn with_local_mut<R>(
        &mut self,
        f: impl FnOnce(faer::MatMut<'_, f64>) -> R,
    ) -> Result<R> {
        let (rows, cols) = (self.local_rows()?, self.size()?.1);
        let lda = self.lda()?;
        let mut ptr = std::ptr::null_mut();
        // SAFETY: MatDenseGetArray / MatDenseRestoreArray pair; PETSc holds rows x cols
        // entries at stride lda >= rows from `ptr`, writable until restored.
        let result = unsafe {
            check(sys::MatDenseGetArray(self.raw, &mut ptr))?;
            let view = if rows == 0 || cols == 0 {
                faer::MatMut::from_column_major_slice_mut(&mut [], rows, cols)
            } else {
                let len = (cols - 1) * lda + rows;
                faer::MatMut::from_column_major_slice_with_stride_mut(
                    std::slice::from_raw_parts_mut(ptr, len),
                    rows,
                    cols,
                    lda,
                )
            };
            let result = f(view);
            check(sys::MatDenseRestoreArray(self.raw, &mut ptr))?;
            result
        };
        self.assemble()?;
        Ok(result)
    }

    fn assemble(&mut self) -> Result<()> {
        // SAFETY: live matrix.
        unsafe {
            check(sys::MatAssemblyBegin(self.raw, sys::MAT_FINAL_ASSEMBLY))?;
            check(sys::MatAssemblyEnd(self.raw, sys::MAT_FINAL_ASSEMBLY))
        }
    }

    /// Global (rows, cols).
    pub fn size(&self) -> Result<(usize, usize)> {
        let (mut m, mut n) = (0, 0);
        // SAFETY: out-pointers to locals.
        check(unsafe { sys::MatGetSize(self.raw, &mut m, &mut n) })?;
        Ok((m as usize, n as usize))
    }

    /// Number of rows this rank stores.
    pub fn local_rows(&self) -> Result<usize> {
        let (mut m, mut n) = (0, 0);
        // SAFETY: out-pointers to locals.
        check(unsafe { sys::MatGetLocalSize(self.raw, &mut m, &mut n) })?;
        Ok(m as usize)
    }

    /// The global rows `[start, end)` this rank owns.
    pub fn ownership_range(&self) -> Result<(usize, usize)> {
        let (mut lo, mut hi) = (0, 0);
        // SAFETY: out-pointers to locals.
        check(unsafe { sys::MatGetOwnershipRange(self.raw, &mut lo, &mut hi) })?;
        Ok((lo as usize, hi as usize))
    }

    fn lda(&self) -> Result<usize> {
        let mut lda = 0;
        // SAFETY: out-pointer to a local.
        check(unsafe { sys::MatDenseGetLDA(self.raw, &mut lda) })?;
        Ok(lda as usize)
    }

    fn local(&self) -> Result<LocalRead<'_, 'rt>> {
        let (rows, cols, lda) = (self.local_rows()?, self.size()?.1, self.lda()?);
        let mut ptr = std::ptr::null();
        // SAFETY: restored by LocalRead's Drop with the matching read call.
        check(unsafe { sys::MatDenseGetArrayRead(self.raw, &mut ptr) })?;
        Ok(LocalRead {
            m: self,
            ptr,
            rows,
            cols,
            lda,
        })
    }

    /// `f` on this rank's rows read in place, as a `local_rows x cols` faer view (no copy:
    /// for products over bases of hundreds of megabytes).
    pub fn with_local<R>(&self, f: impl FnOnce(faer::MatRef<'_, f64>) -> R) -> Result<R> {
        let local = self.local()?;
        if local.rows == 0 || local.cols == 0 {
            return Ok(f(faer::MatRef::from_column_major_slice(
                &[],
                local.rows,
                local.cols,
            )));
        }
        let len = (local.cols - 1) * local.lda + local.rows;
        // SAFETY: PETSc holds rows x cols entries at stride lda >= rows from `ptr`, readable
        // until `local` restores them (after `f` returns: the view cannot outlive it).
        let slice = unsafe { std::slice::from_raw_parts(local.ptr, len) };
        Ok(f(faer::MatRef::from_column_major_slice_with_stride(
            slice, local.rows, local.cols, local.lda,
        )))
    }

    /// This rank's rows, as a `local_rows x cols` faer matrix.
    pub fn local_values(&self) -> Result<Mat<f64>> {
        // Column by column from the view: entry by entry through `get` took 1.6 s for
        // small-caliper's T (31,000 rows x 1,800 columns a rank).
        self.with_local(|m| m.to_owned())
    }

    /// Column j as a vector laid out like the rows (collective).
    pub fn column(&self, j: usize) -> Result<Vector<'rt>> {
        let cols = self.size()?.1;
        if j >= cols {
            return Err(PetscError::Invalid(format!(
                "column {j} of a matrix with {cols} columns"
            )));
        }
        let mut left = std::ptr::null_mut();
        // SAFETY: out-pointer; a null right vector is not created.
        check(unsafe { sys::MatCreateVecs(self.raw, std::ptr::null_mut(), &mut left) })?;
        let mut v = Vector::from_raw(left);
        {
            let local = self.local()?;
            let mut w = v.write()?;
            for (i, x) in w.iter_mut().enumerate() {
                *x = local.get(i, j);
            }
        }
        Ok(v)
    }

    /// self *= alpha (collective).
    pub fn scale(&mut self, alpha: f64) -> Result<()> {
        // SAFETY: live matrix.
        check(unsafe { sys::MatScale(self.raw, alpha) })
    }

    /// self^T * other, both distributed alike by rows (collective; MatTransposeMatMult).
    /// The (cols x other's cols) result is gathered to every rank, see
    /// [`DenseMatrix::to_faer`].
    pub fn transpose_mult(&self, other: &DenseMatrix<'rt>) -> Result<Mat<f64>> {
        same_comm(other.raw.cast(), self.comm)?;
        let mut raw = std::ptr::null_mut();
        // SAFETY: live matrices; PETSc checks that the row layouts agree.
        check(unsafe {
            sys::MatTransposeMatMult(
                self.raw,
                other.raw,
                sys::MAT_INITIAL_MATRIX,
                sys::PETSC_DEFAULT as f64,
                &mut raw,
            )
        })?;
        DenseMatrix::from_raw(self.comm, raw).to_faer()
    }

    /// The whole matrix on every rank (collective: an all-gather; allocates rows x cols on
    /// each rank, so meant for bases with few columns or small reduced matrices). Every rank
    /// receives the same bits, so dense decisions taken on each rank from it agree.
    pub fn to_faer(&self) -> Result<Mat<f64>> {
        let (rows, cols) = self.size()?;
        // Decided from the global size, the same on every rank, before any collective; then
        // every count and displacement below fits too.
        if mpi::Count::try_from(rows * cols).is_err() {
            return Err(PetscError::Invalid(format!(
                "a {rows}x{cols} dense matrix is too large to gather with 32-bit MPI counts"
            )));
        }
        let comm = self.comm.mpi();
        let mut counts = vec![0 as mpi::Count; self.comm.size()];
        let send: std::vec::Vec<f64> = {
            // Row by row, so the ranks' pieces concatenate to the row-major global matrix
            // (ownership ranges are contiguous and increase with the rank).
            let local = self.local()?;
            (0..local.rows)
                .flat_map(|i| (0..local.cols).map(move |j| (i, j)))
                .map(|(i, j)| local.get(i, j))
                .collect()
        };
        let mine = send.len() as mpi::Count;
        comm.all_gather_into(&mine, &mut counts[..]);
        let mut displs = std::vec::Vec::with_capacity(counts.len());
        let mut total: usize = 0;
        for &c in &counts {
            displs.push(total as mpi::Count);
            total += c as usize;
        }
        if total != rows * cols {
            return Err(PetscError::Invalid(format!(
                "gathered {total} entries of a {rows}x{cols} matrix"
            )));
        }
        let mut all = vec![0.0; total];
        {
            let mut partition = PartitionMut::new(&mut all[..], counts, displs);
            comm.all_gather_varcount_into(&send[..], &mut partition);
        }
        Ok(Mat::from_fn(rows, cols, |i, j| all[i * cols + j]))
    }
}

/// Refuses an object that does not live on `comm` (or a copy of it: PETSc keeps its own
/// duplicate of the user's communicator, so the handles differ but compare congruent).
pub(super) fn same_comm(object: sys::PetscObject, comm: Comm<'_>) -> Result<()> {
    let mut raw = std::mem::MaybeUninit::<sys::MPI_Comm>::uninit();
    let mut relation = 0;
    // SAFETY: a live PETSc object; PetscObjectGetComm writes its handle, which is then live.
    unsafe {
        check(sys::PetscObjectGetComm(object, raw.as_mut_ptr()))?;
        let code = sys::MPI_Comm_compare(raw.assume_init(), comm.raw, &mut relation);
        if code != 0 {
            return Err(PetscError::Invalid(format!(
                "MPI_Comm_compare failed with code {code}"
            )));
        }
        if relation != sys::RSMPI_IDENT && relation != sys::RSMPI_CONGRUENT {
            return Err(PetscError::Invalid(
                "a matrix was given with a communicator it does not live on".into(),
            ));
        }
    }
    Ok(())
}

impl Drop for DenseMatrix<'_> {
    fn drop(&mut self) {
        // SAFETY: we own the handle; the runtime outlives us ('rt).
        unsafe { sys::MatDestroy(&mut self.raw) };
    }
}

/// Gathers vectors of one layout to the columns of a faer matrix on every rank (collective;
/// one all-gather per vector).
pub fn columns_to_faer(columns: &[Vector<'_>]) -> Result<Mat<f64>> {
    let gathered: std::vec::Vec<std::vec::Vec<f64>> = columns
        .iter()
        .map(|v| v.gather_all())
        .collect::<Result<_>>()?;
    let rows = gathered.first().map_or(0, |c| c.len());
    if gathered.iter().any(|c| c.len() != rows) {
        return Err(PetscError::Invalid(
            "vectors of different sizes cannot be the columns of one matrix".into(),
        ));
    }
    Ok(Mat::from_fn(rows, columns.len(), |i, j| gathered[j][i]))
}
