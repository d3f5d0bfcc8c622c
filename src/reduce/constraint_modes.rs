//! The constraint modes of a Craig-Bampton super-element and the brake pressure's static
//! correction, [Psi | r] = K_II^-1 [-K_IB | F_I]: one factorisation of the interior block and
//! one solve of |B| + 1 right-hand sides, returned on this rank's interior rows.
//!
//! Two ways to the same numbers:
//! - **shared**: K_II factored once over all ranks (MUMPS), the whole block solved there;
//! - **each rank its own columns**: every rank factors its own copy of K_II (sequential
//!   MUMPS, [`ReplicatedFactor`]), solves its share of the right-hand sides, and the ranks
//!   exchange rows; the factor is kept for the fixed-interface modes. MUMPS's
//!   parallel solve phase does not scale with many right-hand sides: on small-caliper with
//!   every pair on the boundary (61,533 interior equations, 1,723 right-hand sides) the
//!   shared block solve took 14.4 s on 2 ranks and 5.9 s on 1, for a factorisation of
//!   0.5-0.7 s; each rank with its own factor and half the columns, 6.9 s, and the run's
//!   peak memory fell from 7.2 to 3.6 GB (the shared solve's gathered right-hand sides).
//!   The price is a whole copy of K_II and of its factor on every rank, so it is taken only
//!   up to [`EACH_RANK_MAX_INTERIOR`] interior equations. One rank takes the shared way (it
//!   is the same), so a check run on 1 and 2 ranks compares the two.

use crate::analysis::replicated_factor::{ReplicatedFactor, RowBlock};
use crate::petsc::{
    Comm, DenseMatrix, DirectPackage, FactoredMatrix, Factorization, Matrix, PetscError,
};

/// The most interior equations for which every rank factors its own copy of K_II: a 3D
/// quadratic-tetrahedron factor grows faster than the equations (small-caliper's 61,533
/// give 18 million entries, 150 MB, LDL^T), and beyond a few hundred thousand a copy per
/// rank would compete with the model itself for memory.
pub const EACH_RANK_MAX_INTERIOR: usize = 300_000;

/// The blocks of K_t the constraint modes are made of.
pub(super) struct InteriorBlocks<'a, 'rt> {
    /// The whole tangent (its sub-matrices are copied from it).
    pub k_t: &'a Matrix<'rt>,
    /// K_II over all ranks (marked symmetric here when `symmetric`).
    pub k_ii: &'a mut Matrix<'rt>,
    /// This rank's rows of K_IB, each sorted by column (the boundary's sorted positions).
    pub k_ib_rows: Vec<Vec<(usize, f64)>>,
    /// The boundary equations, sorted (global).
    pub boundary: &'a [usize],
    /// This rank's interior equations (global, increasing; the ranks' lists concatenate to
    /// every interior equation in order).
    pub interior: &'a [usize],
    /// The load at every equation.
    pub load: &'a [f64],
    /// K_II is symmetric (no kept friction inside): LDL^T.
    pub symmetric: bool,
}

/// [Psi | r] on this rank's interior rows (`interior.len() x (|B| + 1)`, the columns in the
/// boundary's sorted order, then r), and K_II's factor on every rank where every rank has
/// one (on one rank, its only one), for the fixed-interface modes to solve with. Collective.
pub(super) fn constraint_modes<'rt>(
    comm: Comm<'rt>,
    blocks: InteriorBlocks<'_, 'rt>,
) -> Result<(RowBlock, Option<ReplicatedFactor<'rt>>), PetscError> {
    // A symmetric K_II (no kept friction inside: always so with every pair on the boundary)
    // is factored LDL^T: half the factor's memory (small-caliper, every pair on the
    // boundary: 0.52 s instead of 0.69 s, 200 MB less at the peak).
    let factorization = if blocks.symmetric {
        blocks.k_ii.mark_symmetric()?;
        Factorization::Cholesky
    } else {
        Factorization::Lu
    };
    let interior_total = blocks.k_ii.size()?.0;
    if comm.size() > 1 && interior_total <= EACH_RANK_MAX_INTERIOR {
        let (modes, factor) = each_rank(comm, &blocks, factorization)?;
        Ok((modes, Some(factor)))
    } else {
        let (modes, factored) = shared(comm, &blocks, factorization)?;
        let factor = if comm.size() == 1 {
            Some(ReplicatedFactor::from_one_rank(
                comm,
                factored,
                blocks.interior.len(),
            )?)
        } else {
            None
        };
        Ok((modes, factor))
    }
}

/// `-K_IB` entry (row's sorted entries, column).
fn minus(row: &[(usize, f64)], column: usize) -> f64 {
    row.binary_search_by_key(&column, |&(c, _)| c)
        .map_or(0.0, |at| -row[at].1)
}

/// One factorisation over all ranks, one block solve.
fn shared<'rt>(
    comm: Comm<'rt>,
    b: &InteriorBlocks<'_, 'rt>,
    factorization: Factorization,
) -> Result<(RowBlock, FactoredMatrix<'rt>), PetscError> {
    let n_b = b.boundary.len();
    let mut rhs = DenseMatrix::zeros(comm, b.interior.len(), n_b + 1)?;
    rhs.write_local(|i, j| {
        if j < n_b {
            minus(&b.k_ib_rows[i], j)
        } else {
            b.load[b.interior[i]]
        }
    })?;
    let factored = FactoredMatrix::new(comm, b.k_ii, DirectPackage::Mumps, factorization)?;
    let modes = RowBlock::from_dense(&factored.solve_block(&rhs)?)?;
    Ok((modes, factored))
}

/// Every rank its own factor and its own share of the columns, then rows exchanged.
fn each_rank<'rt>(
    comm: Comm<'rt>,
    b: &InteriorBlocks<'_, 'rt>,
    factorization: Factorization,
) -> Result<(RowBlock, ReplicatedFactor<'rt>), PetscError> {
    let n_b = b.boundary.len();
    let columns = n_b + 1;
    let factor = ReplicatedFactor::new(comm, b.k_ii, factorization)?;
    let n_i = factor.order();
    let every_interior = {
        let mut all = Vec::with_capacity(n_i);
        let mut boundary = b.boundary.iter().peekable();
        let n = b.k_t.size()?.0;
        for eq in 0..n {
            if boundary.peek() == Some(&&eq) {
                boundary.next();
            } else {
                all.push(eq);
            }
        }
        all
    };
    // The same on every rank (from global sizes alone): the rows exchanged below are these.
    if every_interior.len() != n_i {
        return Err(PetscError::Invalid(format!(
            "the ranks hold {n_i} interior rows, but the boundary leaves {}",
            every_interior.len()
        )));
    }
    let mine = factor.share(comm.rank(), columns);
    let my_boundary = &b.boundary[mine.start.min(n_b)..mine.end.min(n_b)];
    let k_ib = b
        .k_t
        .sequential_submatrix(comm.alone(), &every_interior, my_boundary)?;
    // Each rank alone from here to the exchange: agree before it, so that no rank waits
    // there for one that failed.
    let solved = (|| {
        let k_ib_rows: Vec<Vec<(usize, f64)>> = (0..n_i)
            .map(|i| {
                let mut row = k_ib.row(i)?;
                row.sort_unstable_by_key(|&(c, _)| c);
                Ok(row)
            })
            .collect::<Result<_, PetscError>>()?;
        factor.solve_columns(mine.len(), |i, j| {
            if mine.start + j < n_b {
                minus(&k_ib_rows[i], j)
            } else {
                b.load[every_interior[i]]
            }
        })
    })();
    if !comm.all(solved.is_ok()) {
        return Err(solved.err().unwrap_or_else(|| PetscError::NotConverged {
            what: "constraint modes".into(),
            detail: "failed on another rank".into(),
        }));
    }
    drop(k_ib);
    let result = factor.to_rows(solved?, columns)?;
    Ok((result, factor))
}
