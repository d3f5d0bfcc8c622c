//! One window of the undamped CEA: the eigenpairs of (K_t, M) nearest a target by
//! shift-and-invert, and the left eigenvectors of some of them on the same factorisation.
//!
//! Two solvers do it. Block Krylov-Schur ([`super::block_krylov_schur`]) on one MUMPS LU of
//! K_t - sigma M applies the operator to blocks of vectors, one multi-right-hand-side solve
//! each, and the transposed operator the same way for the left vectors; SLEPc's
//! Krylov-Schur ([`EigenSolver`], [`LeftSolver`]) applies it one vector at a time. The block
//! solver is used where the factorisation is MUMPS's LU and the operator is larger than its
//! subspace (and PETSc's dense LU of a super-element's dense pencil, on one rank); SLEPc's
//! otherwise, where `-st_matmode inplace` asks for SLEPc's memory trimming, and wherever
//! the block solver does not converge (it says so), so that a window always has an answer
//! by one of them.

use super::block_krylov_schur::{self, BlockPairs};
use super::blocks::times;
use crate::petsc::{
    Comm, DenseMatrix, DirectPackage, EigenOptions, EigenProblem, EigenSolver, FactoredMatrix,
    Factorization, LeftSolver, LinearMethod, Matrix, PetscError, Spectrum, Structure, Vector,
};
use faer::{Mat, MatRef};
use num_complex::Complex64;

/// Which solver a CEA window uses.
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    serde::Serialize,
    serde::Deserialize,
    clap::ValueEnum,
)]
#[serde(rename_all = "kebab-case")]
pub enum WindowSolver {
    /// Block Krylov-Schur on multi-right-hand-side solves where the factorisation is MUMPS's
    /// LU, SLEPc's Krylov-Schur otherwise or where the block solver does not converge.
    #[default]
    Block,
    /// SLEPc's Krylov-Schur, one vector at a time.
    KrylovSchur,
}

/// A window's eigenpairs: omega^2, shapes and residuals, by whichever solver found them.
pub enum Window<'rt> {
    /// SLEPc's solver and how many pairs converged.
    Slepc(EigenSolver<'rt>, usize),
    Block(BlockWindow<'rt>),
}

/// The block solver's window: its factorisation (kept for the left vectors) and pairs.
pub struct BlockWindow<'rt> {
    factor: FactoredMatrix<'rt>,
    /// omega^2 = sigma + 1 / theta, nearest the target first.
    values: Vec<Complex64>,
    re: Mat<f64>,
    im: Mat<f64>,
}

/// What a window is asked for.
#[derive(Clone, Copy, Debug)]
pub struct WindowRequest<'a> {
    pub target: f64,
    pub count: usize,
    /// SLEPc's ncv; the block solver's basis at most (grown to the count and three blocks).
    pub subspace: usize,
    pub tolerance: f64,
    pub linear: &'a LinearMethod,
    pub solver: WindowSolver,
}

impl<'rt> Window<'rt> {
    /// The `count` eigenpairs of (stiffness, mass) nearest `target` (collective). A target on
    /// an eigenvalue is an `Err` (a singular factorisation), as SLEPc's.
    pub fn solve(
        comm: Comm<'rt>,
        stiffness: &Matrix<'rt>,
        mass: &Matrix<'rt>,
        request: WindowRequest<'_>,
    ) -> Result<Window<'rt>, PetscError> {
        // MUMPS's LU solves blocks in parallel; PETSc's own (a super-element's dense
        // pencil, on one rank) with LAPACK's multi-right-hand-side solves.
        let package = match request.linear {
            LinearMethod::Direct {
                package: package @ DirectPackage::Mumps,
                factorization: Factorization::Lu,
            } => Some(*package),
            LinearMethod::Direct {
                package: package @ DirectPackage::Petsc,
                factorization: Factorization::Lu,
            } if comm.size() == 1 => Some(*package),
            _ => None,
        };
        // `-st_matmode inplace` asks for the CEA's memory to be trimmed by shifting the
        // tangent in place: only SLEPc's solver does that (the block window factors a shifted
        // copy and holds twice SLEPc's basis: industrial-caliper ran out of 24 GiB with it
        // where SLEPc's in place fitted), so the request is SLEPc's.
        // Every rank reads the same command line, but the ranks must not part ways on a
        // collective path whatever their databases hold: in place if any rank was asked.
        let asked = comm
            .option(c"-st_matmode")?
            .is_some_and(|mode| mode.eq_ignore_ascii_case("inplace"));
        let in_place = !comm.all(!asked);
        if in_place && request.solver == WindowSolver::Block && package.is_some() {
            tracing::debug!("CEA window: -st_matmode inplace, so SLEPc's Krylov-Schur");
        }
        if let (WindowSolver::Block, Some(package), false) = (request.solver, package, in_place) {
            if let Some(window) = BlockWindow::solve(comm, stiffness, mass, package, request)? {
                return Ok(Window::Block(window));
            }
        }
        let options = EigenOptions {
            problem: EigenProblem::NonHermitianGeneralized,
            spectrum: Spectrum::NearTarget {
                target: request.target,
                count: request.count,
            },
            tolerance: request.tolerance,
            linear: request.linear.clone(),
            subspace: Some(request.subspace),
            ..Default::default()
        };
        let mut eps = EigenSolver::new(comm, stiffness, Some(mass), &options)?;
        let converged = eps.solve()?.converged;
        Ok(Window::Slepc(eps, converged))
    }

    /// How many pairs converged.
    pub fn converged(&self) -> Result<usize, PetscError> {
        match self {
            Window::Slepc(_, converged) => Ok(*converged),
            Window::Block(b) => Ok(b.values.len()),
        }
    }

    /// omega^2 of pair i.
    pub fn value(&self, i: usize) -> Result<Complex64, PetscError> {
        match self {
            Window::Slepc(eps, _) => eps.value(i),
            Window::Block(b) => b
                .values
                .get(i)
                .copied()
                .ok_or_else(|| out_of(i, b.values.len())),
        }
    }

    /// The relative residuals |K x - omega^2 M x| / (|omega^2| |x|) of the pairs `indices`
    /// (collective): only the pairs a window keeps are worth the products (the block
    /// solver's in one pass over K and M for all of them).
    pub fn relative_errors(
        &self,
        comm: Comm<'rt>,
        (stiffness, mass): (&Matrix<'rt>, &Matrix<'rt>),
        indices: &[usize],
    ) -> Result<Vec<f64>, PetscError> {
        match self {
            Window::Slepc(eps, _) => indices.iter().map(|&i| eps.relative_error(i)).collect(),
            Window::Block(b) => {
                if let Some(&i) = indices.iter().find(|&&i| i >= b.values.len()) {
                    return Err(out_of(i, b.values.len()));
                }
                let pick = |m: &Mat<f64>| {
                    Mat::from_fn(m.nrows(), indices.len(), |r, c| m[(r, indices[c])])
                };
                let values: Vec<Complex64> = indices.iter().map(|&i| b.values[i]).collect();
                residuals(
                    comm,
                    (stiffness, mass),
                    &values,
                    (&pick(&b.re), &pick(&b.im)),
                )
            }
        }
    }

    /// The shape of pair i: real and imaginary parts laid out like `template` (collective).
    pub fn pair(
        &self,
        i: usize,
        template: &Vector<'rt>,
    ) -> Result<(Vector<'rt>, Vector<'rt>), PetscError> {
        match self {
            Window::Slepc(eps, _) => eps.pair(i, template).map(|(_, re, im)| (re, im)),
            Window::Block(b) => {
                if i >= b.values.len() {
                    return Err(out_of(i, b.values.len()));
                }
                Ok((
                    column(template, &b.re, i, 1.0)?,
                    column(template, &b.im, i, 1.0)?,
                ))
            }
        }
    }

    /// The `count` eigenpairs of the transposed pencil (K_t^T, M) nearest `target`, read as
    /// left eigenvectors, on this window's factorisation (collective).
    pub fn left(
        &self,
        comm: Comm<'rt>,
        mass: &Matrix<'rt>,
        target: f64,
        (count, subspace, tolerance): (usize, usize, f64),
    ) -> Result<LeftPairs<'_, 'rt>, PetscError> {
        match self {
            Window::Slepc(eps, _) => Ok(LeftPairs::Slepc(LeftSolver::solve(
                comm, eps, mass, target, count, subspace, tolerance,
            )?)),
            Window::Block(b) => {
                let (global, first, local) = layout(mass)?;
                let pairs = block_krylov_schur::largest(
                    comm,
                    (global, first, local),
                    shift_invert(comm, mass, &b.factor, Side::Left),
                    count,
                    subspace,
                    tolerance,
                )?;
                Ok(match pairs {
                    Some(pairs) => LeftPairs::Block { target, pairs },
                    // Left vectors cost sensitivities, never modes: SLEPc's would need a
                    // factorisation of their own here; none is what the caller handles, and
                    // it is said here because the caller only sees no pairs.
                    None => {
                        if comm.rank() == 0 {
                            tracing::warn!(
                                "CEA window at {target:e}: block Krylov-Schur on the \
                                 transposed operator did not converge {count} left vectors; \
                                 this window's modes get no sensitivities or shares"
                            );
                        }
                        LeftPairs::None
                    }
                })
            }
        }
    }
}

/// Left eigenpairs about a target.
pub enum LeftPairs<'a, 'rt> {
    Slepc(LeftSolver<'a, 'rt>),
    Block { target: f64, pairs: BlockPairs },
    None,
}

impl<'rt> LeftPairs<'_, 'rt> {
    pub fn converged(&self) -> usize {
        match self {
            LeftPairs::Slepc(l) => l.converged(),
            LeftPairs::Block { pairs, .. } => pairs.values.len(),
            LeftPairs::None => 0,
        }
    }

    /// omega^2 of left pair i.
    pub fn value(&self, i: usize) -> Result<Complex64, PetscError> {
        match self {
            LeftPairs::Slepc(l) => l.value(i),
            LeftPairs::Block { target, pairs } => pairs
                .values
                .get(i)
                .map(|theta| target + theta.inv())
                .ok_or_else(|| out_of(i, pairs.values.len())),
            LeftPairs::None => Err(out_of(i, 0)),
        }
    }

    /// The left eigenvector y of pair i (y^H K_t = omega^2 y^H M): real and imaginary
    /// parts laid out like `template` (collective).
    pub fn left_vector(
        &self,
        i: usize,
        template: &Vector<'rt>,
    ) -> Result<(Vector<'rt>, Vector<'rt>), PetscError> {
        match self {
            LeftPairs::Slepc(l) => l.left_vector(i, template),
            LeftPairs::Block { pairs, .. } => {
                if i >= pairs.values.len() {
                    return Err(out_of(i, pairs.values.len()));
                }
                // y = conj(z).
                Ok((
                    column(template, &pairs.re, i, 1.0)?,
                    column(template, &pairs.im, i, -1.0)?,
                ))
            }
            LeftPairs::None => Err(out_of(i, 0)),
        }
    }
}

/// Column i of a block of local rows, times `sign`, as a vector laid out like `template`.
fn column<'rt>(
    template: &Vector<'rt>,
    block: &Mat<f64>,
    i: usize,
    sign: f64,
) -> Result<Vector<'rt>, PetscError> {
    let mut v = template.duplicate()?;
    v.set_local(
        &(0..block.nrows())
            .map(|r| sign * block[(r, i)])
            .collect::<Vec<_>>(),
    )?;
    Ok(v)
}

/// Which eigenvectors an operator is for.
#[derive(Clone, Copy)]
enum Side {
    /// (K_t - sigma M)^-1 M: right eigenvectors.
    Right,
    /// (K_t - sigma M)^-T M: left ones (M is symmetric), on the same factors.
    Left,
}

/// The shift-and-invert operator on a block of columns of local rows: one product with M,
/// one multi-right-hand-side solve with the factorisation (collective).
fn shift_invert<'a, 'rt>(
    comm: Comm<'rt>,
    mass: &'a Matrix<'rt>,
    factor: &'a FactoredMatrix<'rt>,
    side: Side,
) -> impl FnMut(MatRef<'_, f64>) -> Result<Mat<f64>, PetscError> + 'a
where
    'rt: 'a,
{
    move |x| {
        let mx = times(comm, mass, x)?;
        let mut rhs = DenseMatrix::zeros(comm, x.nrows(), x.ncols())?;
        rhs.write_local(|i, j| mx[(i, j)])?;
        match side {
            Side::Right => factor.solve_block(&rhs),
            Side::Left => factor.solve_block_transposed(&rhs),
        }?
        .local_values()
    }
}

fn out_of(i: usize, n: usize) -> PetscError {
    PetscError::Invalid(format!("eigenpair {i} requested but {n} converged"))
}

/// A matrix's global rows, this rank's first row and its row count.
fn layout(a: &Matrix<'_>) -> Result<(usize, usize, usize), PetscError> {
    let (lo, hi) = a.ownership_range()?;
    Ok((a.size()?.0, lo, hi - lo))
}

impl<'rt> BlockWindow<'rt> {
    /// `None` when the block solver cannot serve this window (too small an operator, or it
    /// did not converge); an `Err` for a factorisation that fails (a target on an
    /// eigenvalue). Collective.
    fn solve(
        comm: Comm<'rt>,
        stiffness: &Matrix<'rt>,
        mass: &Matrix<'rt>,
        package: DirectPackage,
        request: WindowRequest<'_>,
    ) -> Result<Option<BlockWindow<'rt>>, PetscError> {
        let (global, first, local) = layout(stiffness)?;
        if request.count == 0
            || request
                .subspace
                .max(request.count + 3 * block_krylov_schur::BLOCK)
                + block_krylov_schur::BLOCK
                > global
        {
            return Ok(None);
        }
        let sigma = request.target;
        // K_t - sigma M beside K_t, as SLEPc's transform makes it.
        let mut shifted = stiffness.duplicate()?;
        shifted.add(-sigma, mass, Structure::Unknown)?;
        let factor =
            FactoredMatrix::with_prefix(comm, &shifted, package, Factorization::Lu, Some(c"st_"))?;
        drop(shifted);
        let started = std::time::Instant::now();
        let pairs = block_krylov_schur::largest(
            comm,
            (global, first, local),
            shift_invert(comm, mass, &factor, Side::Right),
            request.count,
            request.subspace,
            request.tolerance,
        )?;
        let Some(pairs) = pairs else {
            tracing::debug!(
                "CEA window at {sigma:e}: block Krylov-Schur did not converge {} pairs; \
                 SLEPc's Krylov-Schur takes it",
                request.count
            );
            return Ok(None);
        };
        let values: Vec<Complex64> = pairs.values.iter().map(|t| sigma + t.inv()).collect();
        let [applying, orthogonalising, ritz] = pairs.seconds;
        tracing::debug!(
            "CEA window at {sigma:e}: block Krylov-Schur, {} pairs from {} columns, {} \
             restarts ({:.2} s: the operator {applying:.2} s, orthogonalisation \
             {orthogonalising:.2} s, Ritz pairs and restarts {ritz:.2} s)",
            values.len(),
            pairs.applied,
            pairs.restarts,
            started.elapsed().as_secs_f64(),
        );
        Ok(Some(BlockWindow {
            factor,
            values,
            re: pairs.re,
            im: pairs.im,
        }))
    }
}

/// |K x - s M x| / (|s| |x|) of each pair (x = re + i im, columns; s its omega^2), as
/// SLEPc's relative error. Collective.
fn residuals(
    comm: Comm<'_>,
    (k, m): (&Matrix<'_>, &Matrix<'_>),
    values: &[Complex64],
    (re, im): (&Mat<f64>, &Mat<f64>),
) -> Result<Vec<f64>, PetscError> {
    let (kr, ki) = (times(comm, k, re.as_ref())?, times(comm, k, im.as_ref())?);
    let (mr, mi) = (times(comm, m, re.as_ref())?, times(comm, m, im.as_ref())?);
    let n = values.len();
    let mut sums = vec![0.0; 2 * n];
    for (j, s) in values.iter().enumerate() {
        for i in 0..re.nrows() {
            let rr = kr[(i, j)] - (s.re * mr[(i, j)] - s.im * mi[(i, j)]);
            let ri = ki[(i, j)] - (s.re * mi[(i, j)] + s.im * mr[(i, j)]);
            sums[j] += rr * rr + ri * ri;
            sums[n + j] += re[(i, j)] * re[(i, j)] + im[(i, j)] * im[(i, j)];
        }
    }
    comm.sum_identically(&mut sums);
    Ok(values
        .iter()
        .enumerate()
        .map(|(j, s)| sums[j].sqrt() / (s.norm() * sums[n + j].sqrt()))
        .collect())
}
