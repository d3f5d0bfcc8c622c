//! Every rank's own factor of the whole of a matrix distributed by rows, and the exchanges
//! that let a block of right-hand sides distributed by rows be solved with each rank taking
//! its share of the columns.
//!
//! MUMPS's parallel solve phase does not scale with many right-hand sides (it gathers them
//! on the host): on small-caliper's super-element interior (61,533 equations, 1,723
//! right-hand sides) the shared block solve took 14.4 s on 2 ranks and 5.9 s on 1, each rank
//! with its own factor and half the columns 6.9 s. The price is a whole copy of the matrix
//! and of its factor on every rank, so callers take this way only up to a size
//! ([`crate::reduce`]'s constraint modes: 300,000 equations).
//!
//! Used for a super-element's constraint modes (one block of |B| + 1 columns) and then, on
//! the same factor, for its fixed-interface modes ([`super::block_lanczos`]: blocks of 32).

use crate::petsc::{Comm, DenseMatrix, DirectPackage, FactoredMatrix, Factorization, Matrix};
use crate::petsc::{PetscError, Result};
use faer::{Mat, MatRef};
use mpi::datatype::{Partition, PartitionMut};
use mpi::traits::CommunicatorCollectives;
use std::ops::Range;

/// This rank's rows of a block, column-major, in the buffer they arrived in.
pub struct RowBlock {
    values: Vec<f64>,
    rows: usize,
    cols: usize,
}

impl RowBlock {
    /// This rank's rows of a dense matrix (copied).
    pub fn from_dense(dense: &DenseMatrix<'_>) -> Result<RowBlock> {
        dense.with_local(|m| {
            let mut values = Vec::with_capacity(m.nrows() * m.ncols());
            for j in 0..m.ncols() {
                values.extend_from_slice(column(m, j));
            }
            RowBlock {
                values,
                rows: m.nrows(),
                cols: m.ncols(),
            }
        })
    }

    /// Column j, this rank's rows.
    pub fn column(&self, j: usize) -> &[f64] {
        &self.values[j * self.rows..(j + 1) * self.rows]
    }

    pub fn as_ref(&self) -> MatRef<'_, f64> {
        MatRef::from_column_major_slice(&self.values, self.rows, self.cols)
    }
}

/// A whole matrix factored on every rank (see the module doc).
pub struct ReplicatedFactor<'rt> {
    comm: Comm<'rt>,
    /// The factor's communicator: this rank alone, or `comm` itself when it has one rank.
    own: Comm<'rt>,
    factored: FactoredMatrix<'rt>,
    /// Every rank's rows, in rank order (they concatenate to the matrix's rows).
    rows: Vec<usize>,
}

impl<'rt> ReplicatedFactor<'rt> {
    /// Every rank factors its own copy of the whole of `a` (square, distributed by rows over
    /// `comm`; marked symmetric for [`Factorization::Cholesky`]). A failed factorisation is
    /// an `Err` on every rank. Collective.
    pub fn new(
        comm: Comm<'rt>,
        a: &Matrix<'rt>,
        factorization: Factorization,
    ) -> Result<ReplicatedFactor<'rt>> {
        let rows = row_counts(comm, a)?;
        if comm.size() == 1 {
            let factored = FactoredMatrix::new(comm, a, DirectPackage::Mumps, factorization)?;
            return Ok(ReplicatedFactor {
                comm,
                own: comm,
                factored,
                rows,
            });
        }
        let n = a.size()?.0;
        let alone = comm.alone();
        let every: Vec<usize> = (0..n).collect();
        let copy = a.sequential_submatrix(alone, &every, &every);
        // Each rank alone from here: agree before the next collective call.
        let factored = copy.and_then(|mut copy| {
            if factorization == Factorization::Cholesky {
                copy.mark_symmetric()?;
            }
            // The factor keeps its own reference to the copy.
            FactoredMatrix::new(alone, &copy, DirectPackage::Mumps, factorization)
        });
        if !comm.all(factored.is_ok()) {
            return Err(factored.err().unwrap_or_else(|| PetscError::NotConverged {
                what: "factorisation".into(),
                detail: "failed on another rank".into(),
            }));
        }
        Ok(ReplicatedFactor {
            comm,
            own: alone,
            factored: factored?,
            rows,
        })
    }

    /// One rank's factor of its matrix, which is the whole matrix (`comm` of one rank).
    pub fn from_one_rank(
        comm: Comm<'rt>,
        factored: FactoredMatrix<'rt>,
        rows: usize,
    ) -> Result<ReplicatedFactor<'rt>> {
        if comm.size() != 1 {
            return Err(PetscError::Invalid(format!(
                "a factor on one rank is every rank's only when there is one, not {}",
                comm.size()
            )));
        }
        Ok(ReplicatedFactor {
            comm,
            own: comm,
            factored,
            rows: vec![rows],
        })
    }

    /// The matrix's order.
    pub fn order(&self) -> usize {
        self.rows.iter().sum()
    }

    /// This rank's rows of the matrix (and of every block laid out like it).
    pub fn local_rows(&self) -> usize {
        self.rows[self.comm.rank()]
    }

    /// This rank's first row.
    pub fn first_row(&self) -> usize {
        self.rows[..self.comm.rank()].iter().sum()
    }

    /// The columns of a block of `columns` that rank `rank` solves.
    pub fn share(&self, rank: usize, columns: usize) -> Range<usize> {
        let size = self.comm.size();
        rank * columns / size..(rank + 1) * columns / size
    }

    /// A^-1 B for whole columns B (every row, `order() x k`, entry (i, j) = `value(i, j)`),
    /// with this rank's factor alone: not collective, so the caller agrees on the outcome
    /// before its next collective call. The result on every row, in PETSc's dense layout
    /// (read it with [`DenseMatrix::with_local`]).
    pub fn solve_columns(
        &self,
        k: usize,
        value: impl Fn(usize, usize) -> f64,
    ) -> Result<DenseMatrix<'rt>> {
        let mut rhs = DenseMatrix::zeros(self.own, self.order(), k)?;
        rhs.write_local(value)?;
        self.factored.solve_block(&rhs)
    }

    /// A^-1 B for a block B distributed by rows like A (`local_rows() x k`): each rank
    /// solves its [`share`](Self::share) of the columns, the rows exchanged there and back.
    /// Collective; a failure on one rank is an `Err` on every rank.
    pub fn solve(&self, b: MatRef<'_, f64>) -> Result<Mat<f64>> {
        let columns = b.ncols();
        let whole = self.to_columns(b)?;
        let solved = self.solve_columns(whole.ncols(), |i, j| whole[(i, j)]);
        if !self.comm.all(solved.is_ok()) {
            return Err(solved.err().unwrap_or_else(|| PetscError::NotConverged {
                what: "solve with the factor".into(),
                detail: "failed on another rank".into(),
            }));
        }
        let rows = self.to_rows(solved?, columns)?;
        Ok(Mat::from_fn(rows.rows, rows.cols, |i, j| {
            rows.as_ref()[(i, j)]
        }))
    }

    /// From rows to columns: this rank's share of a block's `columns`, every row (the
    /// ranks' rows in order). Collective.
    pub fn to_columns(&self, local: MatRef<'_, f64>) -> Result<Mat<f64>> {
        let (rank, size) = (self.comm.rank(), self.comm.size());
        let columns = local.ncols();
        let mine = self.share(rank, columns);
        let prepared = (|| -> Result<Exchange> {
            // To rank d: my rows of d's columns, column by column.
            let mut send = Vec::with_capacity(local.nrows() * columns);
            let mut send_counts = Vec::with_capacity(size);
            for dest in 0..size {
                let theirs = self.share(dest, columns);
                send_counts.push(count(local.nrows() * theirs.len())?);
                for j in theirs {
                    send.extend_from_slice(column(local, j));
                }
            }
            let recv_counts: Vec<mpi::Count> = self
                .rows
                .iter()
                .map(|&r| count(r * mine.len()))
                .collect::<Result<_>>()?;
            Ok((send, send_counts, recv_counts))
        })();
        let (send, send_counts, recv_counts) = self.agreed(prepared)?;
        let received = self.exchange(&send, send_counts, recv_counts)?;
        // From rank s: its rows of my columns, column by column.
        let n = self.order();
        let mut whole = Mat::<f64>::zeros(n, mine.len());
        let (mut at, mut first) = (0, 0);
        for &r in &self.rows {
            for j in 0..mine.len() {
                column_mut(&mut whole, j)[first..first + r]
                    .copy_from_slice(&received[at + j * r..at + (j + 1) * r]);
            }
            at += r * mine.len();
            first += r;
        }
        Ok(whole)
    }

    /// From columns to rows: this rank's rows of a block of `columns`, given this rank's
    /// share of them on every row (as [`solve_columns`](Self::solve_columns) gives it,
    /// freed once read, before the exchange: on small-caliper's constraint modes the block
    /// is 424 MB a rank, and holding it through the exchange made the exchange 2 s slower).
    /// Collective.
    pub fn to_rows(&self, whole: DenseMatrix<'rt>, columns: usize) -> Result<RowBlock> {
        // Every local step that can fail before one decision of all ranks: a rank that left
        // here would leave the others waiting in the all-to-all.
        let prepared = self.rows_to_send(whole, columns);
        let (send, send_counts, recv_counts) = self.agreed(prepared)?;
        // From rank s: my rows of s's columns, column by column; the ranks' shares are
        // consecutive, so what arrives is my rows of every column, column-major.
        let values = self.exchange(&send, send_counts, recv_counts)?;
        Ok(RowBlock {
            values,
            rows: self.local_rows(),
            cols: columns,
        })
    }

    /// [`to_rows`](Self::to_rows)'s local half: what goes to each rank and what comes back.
    fn rows_to_send(&self, whole: DenseMatrix<'rt>, columns: usize) -> Result<Exchange> {
        let (rank, size) = (self.comm.rank(), self.comm.size());
        let mine = self.share(rank, columns);
        let (rows, cols) = (whole.local_rows()?, whole.size()?.1);
        if rows != self.order() || cols != mine.len() {
            return Err(PetscError::Invalid(format!(
                "a {rows}x{cols} block is not this rank's {} of {columns} columns on {} rows",
                mine.len(),
                self.order()
            )));
        }
        // To rank d: d's rows of my columns, column by column.
        let send = whole.with_local(|whole| {
            let mut send = Vec::with_capacity(whole.nrows() * mine.len());
            let mut first = 0;
            for &r in &self.rows {
                for j in 0..mine.len() {
                    send.extend_from_slice(&column(whole, j)[first..first + r]);
                }
                first += r;
            }
            send
        })?;
        drop(whole);
        let send_counts: Vec<mpi::Count> = self
            .rows
            .iter()
            .map(|&r| count(r * mine.len()))
            .collect::<Result<_>>()?;
        let local = self.local_rows();
        let recv_counts: Vec<mpi::Count> = (0..size)
            .map(|src| count(local * self.share(src, columns).len()))
            .collect::<Result<_>>()?;
        Ok((send, send_counts, recv_counts))
    }

    /// `prepared` where every rank prepared its part, else an `Err` on every rank (its own
    /// where it failed). Collective.
    fn agreed(&self, prepared: Result<Exchange>) -> Result<Exchange> {
        if self.comm.all(prepared.is_ok()) {
            return prepared;
        }
        Err(prepared.err().unwrap_or_else(|| {
            PetscError::Invalid("the exchange of a block failed on another rank".into())
        }))
    }

    fn exchange(
        &self,
        send: &[f64],
        send_counts: Vec<mpi::Count>,
        recv_counts: Vec<mpi::Count>,
    ) -> Result<Vec<f64>> {
        let displacements = |counts: &[mpi::Count]| -> Vec<mpi::Count> {
            counts
                .iter()
                .scan(0, |at, &c| {
                    let first = *at;
                    *at += c;
                    Some(first)
                })
                .collect()
        };
        let total: usize = recv_counts.iter().map(|&c| c as usize).sum();
        let (send_at, recv_at) = (displacements(&send_counts), displacements(&recv_counts));
        let mut received = vec![0.0; total];
        let out = Partition::new(send, send_counts, send_at);
        let mut into = PartitionMut::new(&mut received[..], recv_counts, recv_at);
        self.comm.mpi().all_to_all_varcount_into(&out, &mut into);
        Ok(received)
    }
}

/// Column j of a column-major block (PETSc's dense blocks and faer's matrices are).
fn column<'a>(m: MatRef<'a, f64>, j: usize) -> &'a [f64] {
    m.col(j)
        .try_as_col_major()
        .expect("a dense block's columns are contiguous")
        .as_slice()
}

/// Every rank's rows of `a`, in rank order (collective).
fn row_counts(comm: Comm<'_>, a: &Matrix<'_>) -> Result<Vec<usize>> {
    let (lo, hi) = a.ownership_range()?;
    let mut counts = vec![0u64; comm.size()];
    comm.mpi()
        .all_gather_into(&((hi - lo) as u64), &mut counts[..]);
    Ok(counts.into_iter().map(|c| c as usize).collect())
}

/// What one rank sends, and how much it sends to and receives from each rank.
type Exchange = (Vec<f64>, Vec<mpi::Count>, Vec<mpi::Count>);

fn count(n: usize) -> Result<mpi::Count> {
    mpi::Count::try_from(n)
        .map_err(|_| PetscError::Invalid(format!("{n} values are too many for one MPI message")))
}

fn column_mut(m: &mut Mat<f64>, j: usize) -> &mut [f64] {
    m.col_mut(j)
        .try_as_col_major_mut()
        .expect("a matrix's columns are contiguous")
        .as_slice_mut()
}
