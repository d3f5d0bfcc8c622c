//! Distributed vectors (`Vec` in PETSc): owned handles destroyed on `Drop`, and guards for
//! the local array so that a read view is restored with the read restore call.

use super::error::{check, PetscError, Result};
use super::runtime::{Comm, Runtime};
use super::sys;
use std::marker::PhantomData;
use std::ops::{Deref, DerefMut};

/// A PETSc vector distributed over a communicator.
pub struct Vector<'rt> {
    pub(super) raw: sys::PetscVec,
    _rt: PhantomData<&'rt Runtime>,
}

pub(super) fn to_int(n: usize) -> Result<sys::PetscInt> {
    sys::PetscInt::try_from(n).map_err(|_| {
        PetscError::Invalid(format!(
            "{n} does not fit in PETSc's {}-byte index: build squeal with --features index64",
            std::mem::size_of::<sys::PetscInt>()
        ))
    })
}

impl<'rt> Vector<'rt> {
    /// Takes ownership of a handle PETSc created.
    pub(super) fn from_raw(raw: sys::PetscVec) -> Vector<'rt> {
        Vector {
            raw,
            _rt: PhantomData,
        }
    }

    /// A vector with `local` entries on this rank (collective; the sizes add up to the
    /// global size).
    pub fn new(comm: Comm<'rt>, local: usize) -> Result<Vector<'rt>> {
        let mut raw = std::ptr::null_mut();
        // SAFETY: out-pointer to a local; the comm is live while 'rt is.
        unsafe {
            check(sys::VecCreate(comm.raw, &mut raw))?;
            let v = Vector::from_raw(raw);
            check(sys::VecSetSizes(raw, to_int(local)?, sys::PETSC_DETERMINE))?;
            check(sys::VecSetFromOptions(raw))?;
            Ok(v)
        }
    }

    /// A new vector with the same layout (collective), zeroed.
    pub fn duplicate(&self) -> Result<Vector<'rt>> {
        let mut raw = std::ptr::null_mut();
        // SAFETY: self.raw is a live vector.
        check(unsafe { sys::VecDuplicate(self.raw, &mut raw) })?;
        let v = Vector::from_raw(raw);
        v.set(0.0)?;
        Ok(v)
    }

    /// A copy of this vector (collective).
    pub fn copy(&self) -> Result<Vector<'rt>> {
        let v = self.duplicate()?;
        // SAFETY: both live, same layout.
        check(unsafe { sys::VecCopy(self.raw, v.raw) })?;
        Ok(v)
    }

    /// Copies `other`'s values into this vector (same layout; collective).
    pub fn copy_from(&mut self, other: &Vector<'rt>) -> Result<()> {
        // SAFETY: both live.
        check(unsafe { sys::VecCopy(other.raw, self.raw) })
    }

    pub fn global_size(&self) -> Result<usize> {
        let mut n = 0;
        // SAFETY: out-pointer to a local.
        check(unsafe { sys::VecGetSize(self.raw, &mut n) })?;
        Ok(n as usize)
    }

    pub fn local_size(&self) -> Result<usize> {
        let mut n = 0;
        // SAFETY: out-pointer to a local.
        check(unsafe { sys::VecGetLocalSize(self.raw, &mut n) })?;
        Ok(n as usize)
    }

    /// The global indices `[start, end)` this rank owns.
    pub fn ownership_range(&self) -> Result<(usize, usize)> {
        let (mut lo, mut hi) = (0, 0);
        // SAFETY: out-pointers to locals.
        check(unsafe { sys::VecGetOwnershipRange(self.raw, &mut lo, &mut hi) })?;
        Ok((lo as usize, hi as usize))
    }

    /// Sets every entry to `value` (collective).
    pub fn set(&self, value: f64) -> Result<()> {
        // SAFETY: live vector.
        check(unsafe { sys::VecSet(self.raw, value) })
    }

    /// Adds `values` at global `indices` (any rank may add to any entry); negative indices
    /// are skipped (a supported DOF, as for matrices). Call [`Vector::assemble`] afterwards.
    pub fn add_values(&mut self, indices: &[sys::PetscInt], values: &[f64]) -> Result<()> {
        self.values(indices, values, sys::ADD_VALUES)
    }

    /// Sets `values` at global `indices` (negative ones skipped); call [`Vector::assemble`]
    /// afterwards.
    pub fn set_values(&mut self, indices: &[sys::PetscInt], values: &[f64]) -> Result<()> {
        self.values(indices, values, sys::INSERT_VALUES)
    }

    fn values(&mut self, idx: &[sys::PetscInt], val: &[f64], mode: sys::InsertMode) -> Result<()> {
        if idx.len() != val.len() {
            return Err(PetscError::Invalid(format!(
                "{} indices but {} values",
                idx.len(),
                val.len()
            )));
        }
        // Unlike MatSetValues, VecSetValues does not skip negative indices by default, and an
        // optimised PETSc does not check them: it would write before the array.
        let (idx, val): (std::vec::Vec<sys::PetscInt>, std::vec::Vec<f64>) = idx
            .iter()
            .zip(val)
            .filter(|(&i, _)| i >= 0)
            .map(|(&i, &v)| (i, v))
            .unzip();
        let global = self.global_size()?;
        if let Some(&bad) = idx.iter().find(|&&i| i as usize >= global) {
            return Err(PetscError::Invalid(format!(
                "index {bad} outside a vector of {global} entries"
            )));
        }
        // SAFETY: lengths equal, indices in range; PETSc copies the data.
        check(unsafe {
            sys::VecSetValues(
                self.raw,
                to_int(idx.len())?,
                idx.as_ptr(),
                val.as_ptr(),
                mode,
            )
        })
    }

    /// Communicates off-rank contributions (collective).
    pub fn assemble(&mut self) -> Result<()> {
        // SAFETY: live vector.
        unsafe {
            check(sys::VecAssemblyBegin(self.raw))?;
            check(sys::VecAssemblyEnd(self.raw))
        }
    }

    /// Euclidean norm (collective).
    pub fn norm2(&self) -> Result<f64> {
        let mut n = 0.0;
        // SAFETY: out-pointer to a local.
        check(unsafe { sys::VecNorm(self.raw, sys::NORM_2, &mut n) })?;
        Ok(n)
    }

    /// Max norm (collective).
    pub fn norm_max(&self) -> Result<f64> {
        let mut n = 0.0;
        // SAFETY: out-pointer to a local.
        check(unsafe { sys::VecNorm(self.raw, sys::NORM_INFINITY, &mut n) })?;
        Ok(n)
    }

    /// Dot product (collective).
    pub fn dot(&self, other: &Vector<'rt>) -> Result<f64> {
        let mut d = 0.0;
        // SAFETY: both live.
        check(unsafe { sys::VecDot(self.raw, other.raw, &mut d) })?;
        Ok(d)
    }

    /// self += alpha * x (collective).
    pub fn axpy(&mut self, alpha: f64, x: &Vector<'rt>) -> Result<()> {
        // SAFETY: both live.
        check(unsafe { sys::VecAXPY(self.raw, alpha, x.raw) })
    }

    /// self *= alpha.
    pub fn scale(&mut self, alpha: f64) -> Result<()> {
        // SAFETY: live vector.
        check(unsafe { sys::VecScale(self.raw, alpha) })
    }

    /// Read-only view of this rank's entries.
    pub fn read(&self) -> Result<ReadGuard<'_, 'rt>> {
        let mut ptr = std::ptr::null();
        let n = self.local_size()?;
        // SAFETY: restored by the guard's Drop with the matching read call.
        check(unsafe { sys::VecGetArrayRead(self.raw, &mut ptr) })?;
        Ok(ReadGuard { v: self, ptr, n })
    }

    /// Read-write view of this rank's entries.
    pub fn write(&mut self) -> Result<WriteGuard<'_, 'rt>> {
        let mut ptr = std::ptr::null_mut();
        let n = self.local_size()?;
        // SAFETY: restored by the guard's Drop with the matching read-write call.
        check(unsafe { sys::VecGetArray(self.raw, &mut ptr) })?;
        Ok(WriteGuard { v: self, ptr, n })
    }

    /// Every entry of the vector on every rank (collective; allocates the global size on
    /// each rank).
    pub fn gather_all(&self) -> Result<std::vec::Vec<f64>> {
        self.gather(false)
    }

    /// Every entry of the vector on rank 0, an empty Vec elsewhere (collective).
    pub fn gather_to_zero(&self) -> Result<std::vec::Vec<f64>> {
        self.gather(true)
    }

    fn gather(&self, to_zero: bool) -> Result<std::vec::Vec<f64>> {
        let mut scatter = std::ptr::null_mut();
        let mut all = std::ptr::null_mut();
        // SAFETY: creates a scatter and a sequential vector, both destroyed below.
        unsafe {
            if to_zero {
                check(sys::VecScatterCreateToZero(
                    self.raw,
                    &mut scatter,
                    &mut all,
                ))?;
            } else {
                check(sys::VecScatterCreateToAll(self.raw, &mut scatter, &mut all))?;
            }
            let all = Vector::from_raw(all);
            let result = (|| {
                check(sys::VecScatterBegin(
                    scatter,
                    self.raw,
                    all.raw,
                    sys::INSERT_VALUES,
                    sys::SCATTER_FORWARD,
                ))?;
                check(sys::VecScatterEnd(
                    scatter,
                    self.raw,
                    all.raw,
                    sys::INSERT_VALUES,
                    sys::SCATTER_FORWARD,
                ))?;
                Ok(all.read()?.to_vec())
            })();
            sys::VecScatterDestroy(&mut scatter);
            result
        }
    }

    /// Sets this rank's entries from a slice of the local size.
    pub fn set_local(&mut self, values: &[f64]) -> Result<()> {
        let mut w = self.write()?;
        if w.len() != values.len() {
            return Err(PetscError::Invalid(format!(
                "local size {} but {} values",
                w.len(),
                values.len()
            )));
        }
        w.copy_from_slice(values);
        Ok(())
    }
}

impl Drop for Vector<'_> {
    fn drop(&mut self) {
        // SAFETY: we own the handle; the runtime outlives us ('rt).
        unsafe { sys::VecDestroy(&mut self.raw) };
    }
}

pub struct ReadGuard<'a, 'rt> {
    v: &'a Vector<'rt>,
    ptr: *const f64,
    n: usize,
}

impl Deref for ReadGuard<'_, '_> {
    type Target = [f64];
    fn deref(&self) -> &[f64] {
        if self.n == 0 {
            return &[];
        }
        // SAFETY: PETSc gave n valid entries, alive until restore.
        unsafe { std::slice::from_raw_parts(self.ptr, self.n) }
    }
}

impl Drop for ReadGuard<'_, '_> {
    fn drop(&mut self) {
        // SAFETY: matches VecGetArrayRead.
        unsafe { sys::VecRestoreArrayRead(self.v.raw, &mut self.ptr) };
    }
}

pub struct WriteGuard<'a, 'rt> {
    v: &'a mut Vector<'rt>,
    ptr: *mut f64,
    n: usize,
}

impl Deref for WriteGuard<'_, '_> {
    type Target = [f64];
    fn deref(&self) -> &[f64] {
        if self.n == 0 {
            return &[];
        }
        // SAFETY: as for ReadGuard.
        unsafe { std::slice::from_raw_parts(self.ptr, self.n) }
    }
}

impl DerefMut for WriteGuard<'_, '_> {
    fn deref_mut(&mut self) -> &mut [f64] {
        if self.n == 0 {
            return &mut [];
        }
        // SAFETY: exclusive borrow of the vector; PETSc gave n writable entries.
        unsafe { std::slice::from_raw_parts_mut(self.ptr, self.n) }
    }
}

impl Drop for WriteGuard<'_, '_> {
    fn drop(&mut self) {
        // SAFETY: matches VecGetArray.
        unsafe { sys::VecRestoreArray(self.v.raw, &mut self.ptr) };
    }
}
