//! A sparse (AIJ) matrix times a tall dense matrix of many columns, e.g. M T of a
//! super-element's basis (61,533 rows and 1,801 columns a rank pair on small-caliper).
//! PETSc 3.18's product of the two (MatMatMult, AIJ x dense) runs over the sparse matrix once
//! for every four dense columns: 450 passes over M's ~33 MB a rank there, memory-bound at
//! 2.8 s. Here the dense columns go in blocks of [`WIDTH`], each block's rows packed
//! contiguously, so the sparse matrix is read once a block and each of its entries updates
//! one contiguous row of the block. The same sums as PETSc's (each row's diagonal block,
//! then its off-rank block), in another order: equal to round-off. Measured there (2 ranks):
//! M T 2.4-3.3 s with PETSc's product, 1.1 s blocked; and T^T M T taken block by block
//! ([`Matrix::product_blocks`]), never holding M T, 4.5 -> 3.3 s and 410 MB less at the
//! peak over the two ranks.

use super::dense::DenseMatrix;
use super::error::{check, PetscError, Result};
use super::is::IndexSet;
use super::mat::Matrix;
use super::sys;
use std::ffi::CStr;

/// Dense columns a pass over the sparse matrix serves: a block of 30,000 rows is 7.7 MB,
/// in the last-level cache beside the sparse rows streaming past it.
const WIDTH: usize = 32;

/// One sequential AIJ block's rows (CSR), read in place and restored on drop.
struct Csr {
    mat: sys::Mat,
    rows: usize,
    ia: *const sys::PetscInt,
    ja: *const sys::PetscInt,
    values: *const f64,
}

impl Csr {
    /// # Safety
    /// `mat` is a live, assembled sequential AIJ matrix that outlives the returned value.
    unsafe fn new(mat: sys::Mat) -> Result<Csr> {
        let (mut n, mut ia, mut ja, mut done) =
            (0, std::ptr::null(), std::ptr::null(), sys::PETSC_FALSE);
        check(sys::MatGetRowIJ(
            mat,
            0,
            sys::PETSC_FALSE,
            sys::PETSC_FALSE,
            &mut n,
            &mut ia,
            &mut ja,
            &mut done,
        ))?;
        if done != sys::PETSC_TRUE {
            return Err(PetscError::Invalid(
                "the sparse matrix gave no compressed rows".into(),
            ));
        }
        // From here Drop restores what was taken, the values only once they are.
        let mut csr = Csr {
            mat,
            rows: n as usize,
            ia,
            ja,
            values: std::ptr::null(),
        };
        check(sys::MatSeqAIJGetArrayRead(mat, &mut csr.values))?;
        Ok(csr)
    }

    /// Row i's column indices and values.
    fn row(&self, i: usize) -> (&[sys::PetscInt], &[f64]) {
        // SAFETY: PETSc's CSR: ia holds rows + 1 offsets, ja and values ia[rows] entries,
        // alive until Drop restores them.
        unsafe {
            let start = *self.ia.add(i) as usize;
            let end = *self.ia.add(i + 1) as usize;
            (
                std::slice::from_raw_parts(self.ja.add(start), end - start),
                std::slice::from_raw_parts(self.values.add(start), end - start),
            )
        }
    }
}

impl Drop for Csr {
    fn drop(&mut self) {
        let mut n = self.rows as sys::PetscInt;
        let mut done = sys::PETSC_FALSE;
        // SAFETY: the pairs of the calls in `new`.
        unsafe {
            if !self.values.is_null() {
                sys::MatSeqAIJRestoreArrayRead(self.mat, &mut self.values);
            }
            sys::MatRestoreRowIJ(
                self.mat,
                0,
                sys::PETSC_FALSE,
                sys::PETSC_FALSE,
                &mut n,
                &mut self.ia,
                &mut self.ja,
                &mut done,
            );
        }
    }
}

/// What [`Matrix::product_blocks`] reads of this rank's part of a sparse matrix.
struct Blocks {
    diagonal: Csr,
    off: Option<Csr>,
    /// The global rows of T the off-rank block's columns stand for.
    ghosts: Vec<usize>,
    rows: usize,
    /// The blocks' rows are self's local rows and its local columns T's local rows.
    fits: bool,
}

impl<'rt> Matrix<'rt> {
    /// self T for a dense T laid out by rows as self's columns, as [`Matrix::mult_dense`]
    /// gives it, by column blocks (see the module doc): for T of many columns. Falls back on
    /// PETSc's product for a matrix that is not AIJ. Collective.
    pub fn mult_tall(&self, t: &DenseMatrix<'rt>) -> Result<DenseMatrix<'rt>> {
        let (lo, hi) = self.ownership_range()?;
        let cols = t.size()?.1;
        let mut product = DenseMatrix::zeros(t.comm(), hi - lo, cols)?;
        // No column, no product (the blocked fetch divides by the width it is given).
        if cols == 0 {
            return Ok(product);
        }
        let blocked = product.with_local_mut(|mut out| {
            self.product_blocks(t, WIDTH, |start, block, _| {
                out.as_mut()
                    .subcols_mut(start, block.ncols())
                    .copy_from(block);
            })
        })??;
        if blocked {
            Ok(product)
        } else {
            self.mult_dense(t)
        }
    }

    /// The columns of self T, `width` at a time (a multiple of [`WIDTH`] is best), handed to
    /// `f` with their first column's index and this rank's rows of T: f(start, (self
    /// T)[:, start..start + w] on this rank's rows, T's rows on this rank). For a consumer
    /// of the product block by block, e.g. T^T (A T), which then never holds the whole
    /// product. `Ok(false)`, and `f` never called, when self is not AIJ (decided from the
    /// type, the same on every rank). Collective.
    pub(super) fn product_blocks(
        &self,
        t: &DenseMatrix<'rt>,
        width: usize,
        mut f: impl FnMut(usize, faer::MatRef<'_, f64>, faer::MatRef<'_, f64>),
    ) -> Result<bool> {
        let width = width.max(1);
        let cols = t.size()?.1;
        // Everything this rank reads of its own first, then one decision of every rank
        // together before the collective calls below, so that no rank leaves while another
        // waits in them.
        let local = self.local_blocks(t);
        if !t.comm().all(matches!(&local, Ok(Some(b)) if b.fits)) {
            // Not AIJ on every rank (the type is the same on all): PETSc's product instead.
            if t.comm().all(matches!(&local, Ok(None))) {
                return Ok(false);
            }
            local?;
            return Err(PetscError::Invalid(
                "a sparse matrix times a dense one whose rows are not laid out as its columns \
                 (or another rank could not read its blocks)"
                    .into(),
            ));
        }
        let Some(Blocks {
            diagonal,
            off,
            ghosts,
            rows,
            ..
        }) = local?
        else {
            unreachable!("every rank has its blocks")
        };
        // The rows of T this rank's off-rank block reads, from their owners (collective:
        // every rank asks, for none or some).
        let alone = t.comm().alone();
        let all: Vec<usize> = (0..cols).collect();
        let ghost_rows = IndexSet::new(alone, &ghosts)?;
        let every_column = IndexSet::new(alone, &all)?;
        let mut subs: *mut sys::Mat = std::ptr::null_mut();
        // SAFETY: live matrix and index sets; PETSc allocates the array of one matrix,
        // freed with it by MatDestroySubMatrices below.
        check(unsafe {
            sys::MatCreateSubMatrices(
                t.raw,
                1,
                &ghost_rows.raw,
                &every_column.raw,
                sys::MAT_INITIAL_MATRIX,
                &mut subs,
            )
        })?;
        let remote = DenseMatrix::from_raw(alone, {
            // SAFETY: the one matrix just made; the reference keeps it for `remote` when
            // the array is freed.
            unsafe {
                let sub = *subs;
                check(sys::PetscObjectReference(sub.cast()))?;
                check(sys::MatDestroySubMatrices(1, &mut subs))?;
                sub
            }
        });
        t.with_local(|own| {
            remote.with_local(|far| {
                let mut near_block = vec![0.0; own.nrows() * WIDTH];
                let mut far_block = vec![0.0; far.nrows() * WIDTH];
                let mut out_block = vec![0.0; rows * WIDTH];
                let mut columns = faer::Mat::<f64>::zeros(rows, width.min(cols));
                // The block loop compiled for the CPU's vector width (AVX2 where there is
                // one, as faer's kernels are): a block row is 32 independent sums, so the
                // width changes no rounding, only how many go at once.
                pulp::Arch::new().dispatch(|| {
                    for start in (0..cols).step_by(width) {
                        let end = cols.min(start + width);
                        for first in (start..end).step_by(WIDTH) {
                            let w = WIDTH.min(end - first);
                            pack(own, first, w, &mut near_block);
                            pack(far, first, w, &mut far_block);
                            for i in 0..rows {
                                let mut sum = [0.0; WIDTH];
                                let (ja, a) = diagonal.row(i);
                                accumulate(&mut sum, ja, a, &near_block);
                                if let Some(off) = &off {
                                    let (ja, a) = off.row(i);
                                    accumulate(&mut sum, ja, a, &far_block);
                                }
                                out_block[i * WIDTH..(i + 1) * WIDTH].copy_from_slice(&sum);
                            }
                            unpack(&out_block, first - start, w, columns.as_mut());
                        }
                        f(start, columns.as_ref().subcols(0, end - start), own);
                    }
                });
            })
        })??;
        Ok(true)
    }

    /// This rank's CSR blocks of self (diagonal, off-rank) and the global rows of T the
    /// off-rank block reads; `None` when self is not AIJ. Local: no collective call.
    fn local_blocks(&self, t: &DenseMatrix<'rt>) -> Result<Option<Blocks>> {
        let (diagonal, off, ghosts): (sys::Mat, sys::Mat, Vec<usize>) = match self
            .type_name()?
            .as_str()
        {
            "seqaij" => (self.raw, std::ptr::null_mut(), Vec::new()),
            "mpiaij" => {
                let (mut ad, mut ao, mut colmap) =
                    (std::ptr::null_mut(), std::ptr::null_mut(), std::ptr::null());
                // SAFETY: a live MPIAIJ matrix; the blocks and the column map are
                // borrowed from it (not to be destroyed), alive while self is.
                check(unsafe { sys::MatMPIAIJGetSeqAIJ(self.raw, &mut ad, &mut ao, &mut colmap) })?;
                let (mut rows, mut cols) = (0, 0);
                // SAFETY: a live matrix; out-pointers to locals.
                check(unsafe { sys::MatGetSize(ao, &mut rows, &mut cols) })?;
                // SAFETY: PETSc's map of the off-rank block's cols columns to global ones.
                let map = unsafe { std::slice::from_raw_parts(colmap, cols as usize) };
                (ad, ao, map.iter().map(|&g| g as usize).collect())
            }
            _ => return Ok(None),
        };
        let (lo, hi) = self.ownership_range()?;
        let rows = hi - lo;
        let mut local_columns = 0;
        // SAFETY: a live matrix; out-pointers to locals.
        check(unsafe { sys::MatGetLocalSize(self.raw, &mut 0, &mut local_columns) })?;
        // SAFETY: live assembled AIJ blocks of self, alive while self is.
        let diagonal = unsafe { Csr::new(diagonal)? };
        let off = if off.is_null() {
            None
        } else {
            // SAFETY: as above.
            Some(unsafe { Csr::new(off)? })
        };
        let fits = diagonal.rows == rows
            && off.as_ref().is_none_or(|o| o.rows == rows)
            && local_columns as usize == t.local_rows()?;
        Ok(Some(Blocks {
            diagonal,
            off,
            ghosts,
            rows,
            fits,
        }))
    }

    /// PETSc's type name of the matrix ("mpiaij", "seqaij", ...).
    fn type_name(&self) -> Result<String> {
        let mut name = std::ptr::null();
        // SAFETY: a live matrix; PETSc returns a static NUL-terminated name.
        check(unsafe { sys::MatGetType(self.raw, &mut name) })?;
        if name.is_null() {
            return Ok(String::new());
        }
        // SAFETY: as above.
        Ok(unsafe { CStr::from_ptr(name) }
            .to_string_lossy()
            .into_owned())
    }
}

/// Rows a tile of [`pack`] and [`unpack`] moves at once: a tile of 64 x 32 values is 16 kB,
/// in the first-level cache, so the transposition reads and writes whole cache lines.
const TILE: usize = 64;

/// Columns [start, start + width) of `m`, row by row at stride [`WIDTH`], zeros after.
fn pack(m: faer::MatRef<'_, f64>, start: usize, width: usize, block: &mut [f64]) {
    let columns: Vec<&[f64]> = (start..start + width)
        .map(|j| {
            m.col(j)
                .try_as_col_major()
                .expect("a dense matrix's columns are contiguous")
                .as_slice()
        })
        .collect();
    let rows = m.nrows();
    for first in (0..rows).step_by(TILE) {
        let last = rows.min(first + TILE);
        for (l, column) in columns.iter().enumerate() {
            for i in first..last {
                block[i * WIDTH + l] = column[i];
            }
        }
        for i in first..last {
            block[i * WIDTH + width..(i + 1) * WIDTH].fill(0.0);
        }
    }
}

/// The first `width` values of each row of `block` into columns [start, start + width).
fn unpack(block: &[f64], start: usize, width: usize, m: faer::MatMut<'_, f64>) {
    let rows = m.nrows();
    let mut columns: Vec<&mut [f64]> = m
        .subcols_mut(start, width)
        .col_iter_mut()
        .map(|c| {
            c.try_as_col_major_mut()
                .expect("a dense matrix's columns are contiguous")
                .as_slice_mut()
        })
        .collect();
    for first in (0..rows).step_by(TILE) {
        let last = rows.min(first + TILE);
        for (l, column) in columns.iter_mut().enumerate() {
            for i in first..last {
                column[i] = block[i * WIDTH + l];
            }
        }
    }
}

/// sum += a_k block[ja_k] over one sparse row.
#[inline(always)]
fn accumulate(sum: &mut [f64; WIDTH], ja: &[sys::PetscInt], a: &[f64], block: &[f64]) {
    for (&j, &a) in ja.iter().zip(a) {
        let row: &[f64; WIDTH] = block[j as usize * WIDTH..(j as usize + 1) * WIDTH]
            .try_into()
            .expect("a block row is WIDTH wide");
        for l in 0..WIDTH {
            sum[l] += a * row[l];
        }
    }
}
