//! Building distributed operators from plain data: a global list of (row, col, value)
//! entries becomes a PETSc matrix with rows split evenly over the ranks, exact pattern.

use crate::petsc::{Comm, Matrix, PetscError, PetscInt, RowPattern};

/// PETSc's default split of n rows: n/size each, the first n % size ranks one more.
pub fn row_split(n: usize, comm: Comm) -> std::ops::Range<usize> {
    let (rank, size) = (comm.rank(), comm.size());
    let base = n / size;
    let extra = n % size;
    let start = rank * base + rank.min(extra);
    start..start + base + usize::from(rank < extra)
}

/// A square n x n matrix from global entries (every rank passes the same list; each keeps
/// its rows). Duplicates are summed. Collective.
pub fn matrix_from_entries<'rt>(
    comm: Comm<'rt>,
    n: usize,
    entries: &[(usize, usize, f64)],
) -> Result<Matrix<'rt>, PetscError> {
    let rows = row_split(n, comm);
    let mut local: Vec<(usize, usize, f64)> = entries
        .iter()
        .copied()
        .filter(|e| rows.contains(&e.0))
        .collect();
    if let Some(bad) = entries.iter().find(|e| e.0 >= n || e.1 >= n) {
        return Err(PetscError::Invalid(format!(
            "entry ({}, {}) outside a {n} x {n} matrix",
            bad.0, bad.1
        )));
    }
    local.sort_by_key(|e| (e.0, e.1));
    let mut pattern = RowPattern {
        local_cols: rows.len(),
        row_start: vec![0],
        columns: Vec::with_capacity(local.len()),
    };
    let mut k = 0;
    for r in rows.clone() {
        let mut last = None;
        while k < local.len() && local[k].0 == r {
            if last != Some(local[k].1) {
                pattern.columns.push(local[k].1 as PetscInt);
                last = Some(local[k].1);
            }
            k += 1;
        }
        pattern.row_start.push(pattern.columns.len() as PetscInt);
    }
    let mut m = Matrix::with_pattern(comm, &pattern)?;
    for (r, c, v) in local {
        m.add_block(&[r as PetscInt], &[c as PetscInt], &[v])?;
    }
    m.assemble()?;
    Ok(m)
}
