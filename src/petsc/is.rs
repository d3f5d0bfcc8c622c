//! Index sets (`IS`): the global rows or columns each rank takes into a sub-matrix, e.g. the
//! interior (I) and boundary (B) equations of a Craig-Bampton super-element.

use super::error::{check, PetscError, Result};
use super::runtime::{Comm, Runtime};
use super::sys;
use super::vec::to_int;
use std::marker::PhantomData;
use std::ops::Range;

/// A set of global indices distributed over a communicator: each rank holds its own part.
/// In [`Matrix::submatrix`](super::Matrix::submatrix) a rank's part of the row set is the
/// rows it gets of the sub-matrix, and its part of the column set the columns it owns there.
pub struct IndexSet<'rt> {
    pub(super) raw: sys::IS,
    _rt: PhantomData<&'rt Runtime>,
}

impl<'rt> IndexSet<'rt> {
    fn from_raw(raw: sys::IS) -> IndexSet<'rt> {
        IndexSet {
            raw,
            _rt: PhantomData,
        }
    }

    /// An index set whose part on this rank is `indices` (global, in the given order; PETSc
    /// copies them). Collective: every rank of `comm` calls it, with its own part.
    pub fn new(comm: Comm<'rt>, indices: &[usize]) -> Result<IndexSet<'rt>> {
        let indices: std::vec::Vec<sys::PetscInt> =
            indices.iter().map(|&i| to_int(i)).collect::<Result<_>>()?;
        let mut raw = std::ptr::null_mut();
        // SAFETY: `indices` holds len entries; PETSC_COPY_VALUES makes PETSc keep its own copy.
        check(unsafe {
            sys::ISCreateGeneral(
                comm.raw,
                to_int(indices.len())?,
                indices.as_ptr(),
                sys::PETSC_COPY_VALUES,
                &mut raw,
            )
        })?;
        Ok(IndexSet::from_raw(raw))
    }

    /// The equations of `sorted` (strictly increasing global indices: all of them, or at
    /// least those in `owned`) that this rank owns, `owned` being its ownership range
    /// ([`Matrix::ownership_range`](super::Matrix::ownership_range)). Collective; an unsorted
    /// list on any rank is an `Err` on every rank.
    pub fn owned_subset(
        comm: Comm<'rt>,
        owned: Range<usize>,
        sorted: &[usize],
    ) -> Result<IndexSet<'rt>> {
        let increasing = sorted.windows(2).all(|w| w[0] < w[1]);
        if !comm.all(increasing) {
            return Err(PetscError::Invalid(
                "the equations of an index set must be strictly increasing".into(),
            ));
        }
        let lo = sorted.partition_point(|&i| i < owned.start);
        let hi = sorted.partition_point(|&i| i < owned.end);
        IndexSet::new(comm, &sorted[lo..hi])
    }

    /// The indices of `owned` that this set does not hold on this rank, e.g. the interior
    /// equations from the boundary ones (ISComplement). This rank's part must be sorted and
    /// inside `owned` (true of [`IndexSet::owned_subset`]). Collective.
    pub fn complement(&self, owned: Range<usize>) -> Result<IndexSet<'rt>> {
        let mut raw = std::ptr::null_mut();
        // SAFETY: live IS; out-pointer to a local. ISComplement checks sortedness and range.
        check(unsafe {
            sys::ISComplement(self.raw, to_int(owned.start)?, to_int(owned.end)?, &mut raw)
        })?;
        Ok(IndexSet::from_raw(raw))
    }

    /// Number of indices on this rank.
    pub fn local_size(&self) -> Result<usize> {
        let mut n = 0;
        // SAFETY: out-pointer to a local.
        check(unsafe { sys::ISGetLocalSize(self.raw, &mut n) })?;
        Ok(n as usize)
    }

    /// Number of indices over all ranks.
    pub fn global_size(&self) -> Result<usize> {
        let mut n = 0;
        // SAFETY: out-pointer to a local.
        check(unsafe { sys::ISGetSize(self.raw, &mut n) })?;
        Ok(n as usize)
    }

    /// This rank's indices (global), copied out.
    pub fn indices(&self) -> Result<std::vec::Vec<usize>> {
        let n = self.local_size()?;
        let mut ptr = std::ptr::null();
        // SAFETY: ISGetIndices / ISRestoreIndices pair; the n entries are copied in between.
        unsafe {
            check(sys::ISGetIndices(self.raw, &mut ptr))?;
            let out = if n == 0 {
                vec![]
            } else {
                std::slice::from_raw_parts(ptr, n)
                    .iter()
                    .map(|&i| i as usize)
                    .collect()
            };
            check(sys::ISRestoreIndices(self.raw, &mut ptr))?;
            Ok(out)
        }
    }
}

impl Drop for IndexSet<'_> {
    fn drop(&mut self) {
        // SAFETY: we own the handle; the runtime outlives us ('rt).
        unsafe { sys::ISDestroy(&mut self.raw) };
    }
}
