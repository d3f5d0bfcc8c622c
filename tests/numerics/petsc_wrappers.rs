//! Each PETSc/SLEPc wrapper checked against an independent answer, on 1 and on 2 ranks.
//!
//! Each check runs in its own `mpirun` job on 1 and on 2 ranks (see `common/harness.rs`).

use crate::common;

use faer::linalg::solvers::Solve;
use faer::{Mat, Par, Side};
use num_complex::Complex64;
use squeal::analysis::modes::{real_modes, BandMethod, ModeBand, ModesOptions};
use squeal::fem::{assemble, DofMap, StructureOptions};
use squeal::mesh::{block::block, Material};
use squeal::petsc::{
    columns_to_faer, eigenvalues_below, Comm, DenseMatrix, DirectPackage, EigenOptions,
    EigenProblem, EigenSolver, FactoredMatrix, Factorization, IndexSet, JacobianChange,
    LinearMethod, LinearSolver, Matrix, NewtonOptions, NewtonReport, NonlinearSolver, PetscError,
    PetscInt, QuadraticEigenSolver, QuadraticOptions, RowPattern, Runtime, Spectrum, Vector,
};
use std::f64::consts::PI;

use common::harness::Check;

/// Agreement between 1 and 2 ranks: the algorithms are the same, only the distribution of
/// rows differs, so the numbers agree far below the solver tolerance; 1e-10 relative to the
/// largest value leaves room for reordered sums in the factorisations and Krylov bases.
const RANKS_AGREE: f64 = 1e-10;

macro_rules! checks {
    ($($name:literal => $f:ident),* $(,)?) => {
        &[$(Check { name: $name, run: $f, ranks: &[1, 2], agreement: RANKS_AGREE }),*]
    };
}

pub const CHECKS: &[Check] = checks![
    "laplacian_1d_ghep_interval" => laplacian_1d_ghep_interval,
    "laplacian_3d_ghep_target" => laplacian_3d_ghep_target,
    "inertia_counts_laplacian_3d_multiplicities" => inertia_counts,
    "inertia_counts_on_the_solvers_own_factorisation" => inertia_counts_on_the_solver,
    "modes_band_single_shift_laplacian_3d" => modes_band_single_shift,
    "modes_band_falls_back_to_slicing" => modes_band_falls_back,
    "lowest_modes_of_a_held_model_by_one_run_and_one_count" => lowest_counted,
    "lowest_modes_splitting_a_cluster_take_the_band" => lowest_splitting_a_cluster,
    "block_gnhep_complex_shift_invert" => block_gnhep_complex,
    "snes_cubic_reaction_diffusion" => snes_known_solution,
    "snes_callback_error_is_err" => snes_callback_error,
    "snes_kept_factorization_same_solution" => snes_kept_factorization,
    "snes_stops_on_the_roundoff_floor_of_stiff_ties" => snes_roundoff_floor,
    "snes_takes_a_kept_factors_step_at_gmres_limit_and_stops_on_a_failed_factor" => snes_gmres_limit,
    "pep_damped_oscillators" => pep_closed_form,
    "singular_solve_is_err_on_every_rank" => singular_solve,
    "entry_outside_pattern_is_err" => outside_pattern,
    "vector_gather_and_norms" => vector_gather,
    "index_sets_and_submatrices" => index_sets_and_submatrices,
    "constraint_modes_block_solve" => constraint_modes_block_solve,
    "projection_t_k_t" => projection_t_k_t,
    "fixed_interface_modes_of_submatrices" => fixed_interface_modes,
    "singular_block_factorization_is_err" => singular_block_factorization,
    "tet10_block_craig_bampton_basis" => tet10_craig_bampton,
];

// ---------------------------------------------------------------------------------------
// Helpers: row distribution and banded matrices built from a row function.

/// PETSc's default split of n rows: n/size each, the first n%size ranks one more.
fn split(n: usize, comm: Comm) -> (usize, usize) {
    let (r, s) = (comm.rank(), comm.size());
    let base = n / s;
    let extra = n % s;
    let start = r * base + r.min(extra);
    let len = base + usize::from(r < extra);
    (start, start + len)
}

/// A matrix whose row i holds `entries(i)` (global column, value), built with the exact
/// pattern. Collective.
fn matrix<'rt>(
    comm: Comm<'rt>,
    n: usize,
    entries: impl Fn(usize) -> Vec<(usize, f64)>,
) -> Result<Matrix<'rt>, String> {
    let (lo, hi) = split(n, comm);
    let mut pattern = RowPattern {
        local_cols: hi - lo,
        row_start: vec![0],
        columns: vec![],
    };
    for i in lo..hi {
        let mut cols: Vec<PetscInt> = entries(i).iter().map(|&(j, _)| j as PetscInt).collect();
        cols.sort_unstable();
        cols.dedup();
        pattern.columns.extend(cols);
        pattern.row_start.push(pattern.columns.len() as PetscInt);
    }
    let mut m = Matrix::with_pattern(comm, &pattern).map_err(|e| e.to_string())?;
    for i in lo..hi {
        for (j, v) in entries(i) {
            m.add_block(&[i as PetscInt], &[j as PetscInt], &[v])
                .map_err(|e| e.to_string())?;
        }
    }
    m.assemble().map_err(|e| e.to_string())?;
    Ok(m)
}

fn laplacian_1d(i: usize, n: usize) -> Vec<(usize, f64)> {
    let mut row = vec![(i, 2.0)];
    if i > 0 {
        row.push((i - 1, -1.0));
    }
    if i + 1 < n {
        row.push((i + 1, -1.0));
    }
    row
}

/// The 7-point Laplacian on a g^3 grid (Dirichlet) as A, B = 2 I, and the closed-form
/// eigenvalues of (A, B) in increasing order: (sum_d 2 - 2 cos(k_d pi / (g + 1))) / 2,
/// with multiplicities 1, 3, 3, 3, 6 ... from the permutations of (k_1, k_2, k_3).
fn laplacian_3d<'rt>(
    comm: Comm<'rt>,
    g: usize,
) -> Result<(Matrix<'rt>, Matrix<'rt>, Vec<f64>), String> {
    let n = g * g * g;
    let idx = |x: usize, y: usize, z: usize| (z * g + y) * g + x;
    let a = matrix(comm, n, |i| {
        let (x, y, z) = (i % g, (i / g) % g, i / (g * g));
        let mut row = vec![(i, 6.0)];
        for (d, c) in [(0, x), (1, y), (2, z)] {
            let step = |c2: usize| match d {
                0 => idx(c2, y, z),
                1 => idx(x, c2, z),
                _ => idx(x, y, c2),
            };
            if c > 0 {
                row.push((step(c - 1), -1.0));
            }
            if c + 1 < g {
                row.push((step(c + 1), -1.0));
            }
        }
        row
    })?;
    let b = matrix(comm, n, |i| vec![(i, 2.0)])?;
    let one_d: Vec<f64> = (1..=g)
        .map(|k| 2.0 - 2.0 * (k as f64 * PI / (g as f64 + 1.0)).cos())
        .collect();
    let mut exact: Vec<f64> = Vec::new();
    for &p in &one_d {
        for &q in &one_d {
            for &r in &one_d {
                exact.push((p + q + r) / 2.0);
            }
        }
    }
    exact.sort_by(f64::total_cmp);
    Ok((a, b, exact))
}

fn relative(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1e-300)
}

fn e(err: PetscError) -> String {
    err.to_string()
}

// ---------------------------------------------------------------------------------------
// The checks.

/// 1D Laplacian tridiag(-1, 2, -1), n = 400, B = I: lambda_k = 2 - 2 cos(k pi / (n + 1)).
/// Spectrum slicing over [0, 0.05] must find exactly the eigenvalues the formula puts there,
/// each once.
fn laplacian_1d_ghep_interval(rt: &Runtime) -> Result<Vec<f64>, String> {
    let comm = rt.world();
    let n = 400;
    let a = matrix(comm, n, |i| laplacian_1d(i, n))?;
    let b = matrix(comm, n, |i| vec![(i, 1.0)])?;
    let exact: Vec<f64> = (1..=n)
        .map(|k| 2.0 - 2.0 * (k as f64 * PI / (n as f64 + 1.0)).cos())
        .filter(|&l| l <= 0.05)
        .collect();
    let options = EigenOptions {
        problem: EigenProblem::HermitianGeneralized,
        spectrum: Spectrum::Interval {
            low: 0.0,
            high: 0.05,
        },
        tolerance: 1e-12,
        ..Default::default()
    };
    let mut eps = EigenSolver::new(comm, &a, Some(&b), &options).map_err(e)?;
    let summary = eps.solve().map_err(e)?;
    if summary.converged != exact.len() {
        return Err(format!(
            "slicing found {} eigenvalues in [0, 0.05], the formula has {}",
            summary.converged,
            exact.len()
        ));
    }
    let mut found: Vec<f64> = (0..summary.converged)
        .map(|i| eps.value(i).map(|v| v.re))
        .collect::<Result<_, _>>()
        .map_err(e)?;
    found.sort_by(f64::total_cmp);
    for (f, x) in found.iter().zip(&exact) {
        // Eigenvalue error of a Hermitian problem is O(residual^2 / gap); with tolerance 1e-12
        // the eigenvalue is exact to round-off times the condition of the shifted solve.
        if relative(*f, *x) > 1e-9 {
            return Err(format!("eigenvalue {f} but closed form {x}"));
        }
    }
    for i in 0..summary.converged {
        let r = eps.relative_error(i).map_err(e)?;
        if r > 1e-10 {
            return Err(format!("pair {i} residual {r}"));
        }
    }
    Ok(found)
}

/// 7-point 3D Laplacian on a 12^3 grid (Dirichlet), B = 2 I: eigenvalues
/// (sum_d 2 - 2 cos(k_d pi / 13)) / 2, with multiplicities 1, 3, 3, 3, 6 ... The 10 closest
/// to 0 (shift-and-invert with MUMPS) must be the 10 smallest of the closed form.
fn laplacian_3d_ghep_target(rt: &Runtime) -> Result<Vec<f64>, String> {
    let comm = rt.world();
    let (a, b, exact) = laplacian_3d(comm, 12)?;
    let count = 10;
    let options = EigenOptions {
        problem: EigenProblem::HermitianGeneralized,
        spectrum: Spectrum::NearTarget { target: 0.0, count },
        tolerance: 1e-12,
        ..Default::default()
    };
    let mut eps = EigenSolver::new(comm, &a, Some(&b), &options).map_err(e)?;
    let summary = eps.solve().map_err(e)?;
    if summary.converged < count {
        return Err(format!("{} of {count} converged", summary.converged));
    }
    let mut found: Vec<f64> = (0..count)
        .map(|i| eps.value(i).map(|v| v.re))
        .collect::<Result<_, _>>()
        .map_err(e)?;
    found.sort_by(f64::total_cmp);
    for (f, x) in found.iter().zip(&exact) {
        if relative(*f, *x) > 1e-9 {
            return Err(format!("eigenvalue {f} but closed form {x}"));
        }
    }
    Ok(found)
}

/// The closed-form spectrum grouped into clusters of equal eigenvalues (the permutations of
/// (k_1, k_2, k_3) sum in different orders, so equal values differ by round-off): each
/// cluster's value and multiplicity.
fn clusters(sorted: &[f64]) -> Vec<(f64, usize)> {
    let mut out: Vec<(f64, usize)> = Vec::new();
    for &v in sorted {
        match out.last_mut() {
            Some((w, n)) if relative(v, *w) < 1e-12 => *n += 1,
            _ => out.push((v, 1)),
        }
    }
    out
}

/// The inertia of LDL^T(A - sigma B) on the 12^3 Laplacian: at a shift halfway between each
/// of the first 12 clusters of equal eigenvalues (multiplicities 1, 3, 3, 3, 6, ...) and the
/// next, the number of eigenvalues below it must be the closed-form count, every copy of a
/// multiple eigenvalue included; at a shift below the spectrum, none.
fn inertia_counts(rt: &Runtime) -> Result<Vec<f64>, String> {
    let comm = rt.world();
    let (a, b, exact) = laplacian_3d(comm, 12)?;
    let groups = clusters(&exact);
    if groups.iter().take(12).all(|g| g.1 == 1) {
        return Err("the first clusters should hold multiple eigenvalues".into());
    }
    closed_form_counts(&exact, |sigma| {
        eigenvalues_below(comm, &a, &b, sigma).map_err(e)
    })
}

/// The counts of `count_at` below half the lowest eigenvalue of `exact` (none) and halfway
/// between each of its first 12 clusters of equal eigenvalues and the next (the closed
/// form's, every copy included), as numbers.
fn closed_form_counts(
    exact: &[f64],
    mut count_at: impl FnMut(f64) -> Result<usize, String>,
) -> Result<Vec<f64>, String> {
    let mut counts = vec![count_at(0.5 * exact[0])? as f64];
    if counts[0] != 0.0 {
        return Err(format!("{} eigenvalues below half the lowest", counts[0]));
    }
    let mut below = 0;
    for pair in clusters(exact).windows(2).take(12) {
        below += pair[0].1;
        let sigma = 0.5 * (pair[0].0 + pair[1].0);
        let count = count_at(sigma)?;
        if count != below {
            return Err(format!(
                "{count} eigenvalues below {sigma}, the closed form has {below}"
            ));
        }
        counts.push(count as f64);
    }
    Ok(counts)
}

/// The shift-and-invert solver's own factorisation counts as a fresh one does: on the 12^3
/// Laplacian, after a solve for the 4 eigenvalues nearest a target below the spectrum (as
/// the lowest modes' run has it; at a zero target SLEPc factorises A itself, and the first
/// move makes a new matrix, whose factorisation has MUMPS's defaults and, on 2 ranks, no
/// inertia), the counts of [`closed_form_counts`]. The counts move the transform's shift
/// away from the target, so a search after them for the next 6 pairs (deflating the 4
/// found) must run at the target (the solve puts the factorisation back there first) and
/// find eigenvalues of the closed form nearest it. A Krylov search may miss a copy of a multiple
/// eigenvalue and take the next one instead (CI's CPU once gave 0.3436 for the third copy
/// of 0.3096 after the counts, where a twin that never counted did not: that is what the
/// counts themselves are there to catch), so the bound is the first cluster above the 10th
/// eigenvalue. A search left at a count's shift would still converge to them, only slower,
/// which is why the shift itself is read back. Only the counts, exact integers, are compared
/// between rank counts.
fn inertia_counts_on_the_solver(rt: &Runtime) -> Result<Vec<f64>, String> {
    let comm = rt.world();
    let (a, b, exact) = laplacian_3d(comm, 12)?;
    let options = EigenOptions {
        problem: EigenProblem::HermitianGeneralized,
        spectrum: Spectrum::NearTarget {
            target: -0.5 * exact[0],
            count: 4,
        },
        tolerance: 1e-12,
        linear: LinearMethod::Direct {
            package: DirectPackage::Mumps,
            factorization: Factorization::Cholesky,
        },
        inertia: true,
        ..Default::default()
    };
    let mut eps = EigenSolver::new(comm, &a, Some(&b), &options).map_err(e)?;
    let first = eps.solve().map_err(e)?;
    if first.converged < 4 {
        return Err(format!("{} of 4 converged", first.converged));
    }
    let counts = closed_form_counts(&exact, |sigma| {
        eps.eigenvalues_below(comm, sigma)
            .map_err(e)?
            .ok_or_else(|| format!("the solver's factorisation gave no count at {sigma}"))
    })?;
    let values = search_after_the_first(&mut eps, &a)?;
    let target = -0.5 * exact[0];
    let shift = eps.shift().map_err(e)?;
    if shift != target {
        return Err(format!(
            "the search after the counts ran at shift {shift}, not at the target {target}"
        ));
    }
    let groups = clusters(&exact);
    let (mut below, mut bound) = (0, f64::INFINITY);
    for &(value, copies) in &groups {
        if below >= 10 {
            bound = value;
            break;
        }
        below += copies;
    }
    for f in &values {
        if !exact.iter().any(|v| relative(*f, *v) <= 1e-9) {
            return Err(format!(
                "after the counts: {f} is no eigenvalue of the closed form"
            ));
        }
        if *f > bound * (1.0 + 1e-9) {
            return Err(format!(
                "after the counts: {f} found, above {bound}, the first cluster past the \
                 10 nearest the target: {values:?}"
            ));
        }
    }
    Ok(counts)
}

/// The next 6 pairs nearest the target after a solve's first 4 (deflated), sorted.
fn search_after_the_first<'rt>(
    eps: &mut EigenSolver<'rt>,
    a: &Matrix<'rt>,
) -> Result<Vec<f64>, String> {
    let (template, _) = a.vectors().map_err(e)?;
    let found: Vec<Vector> = (0..4)
        .map(|i| eps.pair(i, &template).map(|p| p.1))
        .collect::<Result<_, _>>()
        .map_err(e)?;
    let refs: Vec<&Vector> = found.iter().collect();
    eps.search_beyond(&refs, 6).map_err(e)?;
    let next = eps.solve().map_err(e)?;
    if next.converged < 6 {
        return Err(format!("{} of the next 6 converged", next.converged));
    }
    let mut values: Vec<f64> = (0..6)
        .map(|i| eps.value(i).map(|v| v.re))
        .collect::<Result<_, _>>()
        .map_err(e)?;
    values.sort_by(f64::total_cmp);
    Ok(values)
}

/// `real_modes` over a band of the 12^3 Laplacian (B = 2 I) whose top lies between the 10th
/// and 11th clusters of equal eigenvalues: the single shift (one inertia count, one
/// Krylov-Schur run) must settle it, with every copy of each multiple eigenvalue exactly
/// once, as the closed form has them.
fn modes_band_single_shift(rt: &Runtime) -> Result<Vec<f64>, String> {
    let comm = rt.world();
    let (a, b, exact) = laplacian_3d(comm, 12)?;
    let groups = clusters(&exact);
    let high = 0.5 * (groups[9].0 + groups[10].0);
    let count: usize = groups[..10].iter().map(|g| g.1).sum();
    let options = ModesOptions {
        band: ModeBand::Below {
            max_frequency_hz: high.sqrt() / (2.0 * PI),
        },
        ..Default::default()
    };
    let found = real_modes(comm, &a, &b, &options).map_err(|e| e.to_string())?;
    if found.method != BandMethod::SingleShift {
        return Err(format!("band searched by {:?}", found.method));
    }
    let values: Vec<f64> = found.modes.iter().map(|m| m.eigenvalue).collect();
    if values.len() != count {
        return Err(format!(
            "{} modes in the band, the closed form has {count}: {values:?}",
            values.len()
        ));
    }
    for (f, x) in values.iter().zip(&exact) {
        if relative(*f, *x) > 1e-9 {
            return Err(format!("eigenvalue {f} but closed form {x}"));
        }
    }
    Ok(values)
}

/// The `count` lowest modes of (a, b) with `expected_rigid_modes` 0 (no free body), as
/// `real_modes` is asked for `*FREQUENCY, N`: found by one of `methods`, the values the
/// closed form's `exact` (sorted), each copy of a multiple eigenvalue once.
fn lowest_against(
    comm: Comm<'_>,
    (a, b, exact): (Matrix<'_>, Matrix<'_>, Vec<f64>),
    count: usize,
    methods: &[BandMethod],
) -> Result<Vec<f64>, String> {
    let options = ModesOptions {
        band: ModeBand::Lowest { count },
        expected_rigid_modes: Some(0),
        ..Default::default()
    };
    let found = real_modes(comm, &a, &b, &options).map_err(|e| e.to_string())?;
    if !methods.contains(&found.method) {
        return Err(format!("searched by {:?}, not {methods:?}", found.method));
    }
    let values: Vec<f64> = found.modes.iter().map(|m| m.eigenvalue).collect();
    if values.len() != count {
        return Err(format!("{} modes, {count} asked: {values:?}", values.len()));
    }
    // The tolerance 1e-10 bounds SLEPc's relative error of each pair; 1e-9 on the value.
    for (f, x) in values.iter().zip(&exact) {
        if relative(*f, *x) > 1e-9 {
            return Err(format!("eigenvalue {f} but closed form {x}"));
        }
    }
    if found.modes.iter().any(|m| m.rigid_body) {
        return Err("a mode of a held model flagged rigid".into());
    }
    Ok(values)
}

/// The 1D Laplacian scaled as a structure's stiffness (n = 400, A = 1e8 L, B = I, definite;
/// distinct eigenvalues 1e8 (2 - 2 cos(k pi / 401)), the lowest that of 12.5 Hz, far above
/// the run's shift of -(1 Hz)^2): its 12 lowest by one run and one count. Then the 12^3 Laplacian's first ten clusters (32
/// eigenvalues, multiplicities up to 6): a single-vector Krylov run misses copies, which the
/// count finds missing and a search of the complement then finds, or the band search does;
/// either way the closed form's values, each copy once.
fn lowest_counted(rt: &Runtime) -> Result<Vec<f64>, String> {
    let comm = rt.world();
    let n = 400;
    let scale = 1e8;
    let a = matrix(comm, n, |i| {
        laplacian_1d(i, n)
            .into_iter()
            .map(|(j, v)| (j, scale * v))
            .collect()
    })?;
    let b = matrix(comm, n, |i| vec![(i, 1.0)])?;
    let exact: Vec<f64> = (1..=n)
        .map(|k| scale * (2.0 - 2.0 * (k as f64 * PI / (n as f64 + 1.0)).cos()))
        .collect();
    let mut values = lowest_against(comm, (a, b, exact), 12, &[BandMethod::CountedLowest])?;
    let cube = laplacian_3d(comm, 12)?;
    let count: usize = clusters(&cube.2)[..10].iter().map(|g| g.1).sum();
    let any = [BandMethod::CountedLowest, BandMethod::SingleShift];
    values.extend(lowest_against(comm, cube, count, &any)?);
    Ok(values)
}

/// A count that ends inside the second cluster (three equal eigenvalues): which copies lie
/// below a shift between them is round-off, so the held model's path must leave it to the
/// band search (an estimate of the top, then the single shift), which gives the closed
/// form's first `count` values all the same.
fn lowest_splitting_a_cluster(rt: &Runtime) -> Result<Vec<f64>, String> {
    let comm = rt.world();
    let cube = laplacian_3d(comm, 12)?;
    let groups = clusters(&cube.2);
    if groups[1].1 != 3 {
        return Err(format!("the second cluster is {:?}", groups[1]));
    }
    let count = groups[0].1 + 1;
    lowest_against(comm, cube, count, &[BandMethod::SingleShift])
}

/// A stiffness with eigenvalues below the band's bottom (the 1D Laplacian, n = 400, shifted
/// down by 1e-3, B = I: four eigenvalues below -1e-4 of the band's top 0.05). The inertia
/// at the top counts them, the band [-5e-6, 0.05] does not hold them, so the single shift
/// cannot match its count and `real_modes` must slice instead, returning exactly the
/// closed-form eigenvalues inside the band.
fn modes_band_falls_back(rt: &Runtime) -> Result<Vec<f64>, String> {
    let comm = rt.world();
    let n = 400;
    let shift = 1e-3;
    let a = matrix(comm, n, |i| {
        let mut row = laplacian_1d(i, n);
        row[0].1 -= shift;
        row
    })?;
    let b = matrix(comm, n, |i| vec![(i, 1.0)])?;
    let high: f64 = 0.05;
    let low = -1e-4 * high;
    let all: Vec<f64> = (1..=n)
        .map(|k| 2.0 - 2.0 * (k as f64 * PI / (n as f64 + 1.0)).cos() - shift)
        .collect();
    if all.iter().filter(|&&l| l < low).count() != 4 {
        return Err("the shifted Laplacian should have four eigenvalues below the band".into());
    }
    let exact: Vec<f64> = all
        .into_iter()
        .filter(|&l| (low..=high).contains(&l))
        .collect();
    let options = ModesOptions {
        band: ModeBand::Below {
            max_frequency_hz: high.sqrt() / (2.0 * PI),
        },
        ..Default::default()
    };
    let found = real_modes(comm, &a, &b, &options).map_err(|e| e.to_string())?;
    if found.method != BandMethod::Slicing {
        return Err(format!("band searched by {:?}", found.method));
    }
    let values: Vec<f64> = found.modes.iter().map(|m| m.eigenvalue).collect();
    if values.len() != exact.len() {
        return Err(format!(
            "{} modes in the band, the closed form has {}: {values:?}",
            values.len(),
            exact.len()
        ));
    }
    for (f, x) in values.iter().zip(&exact) {
        if relative(*f, *x) > 1e-9 {
            return Err(format!("eigenvalue {f} but closed form {x}"));
        }
    }
    Ok(values)
}

/// A x = lambda B x with A block upper-bidiagonal: 2x2 diagonal blocks [[a, b], [-b, a]] and
/// coupling blocks above them, B = diag(c_k I). Block-triangular, so the eigenvalues are
/// (a_k +/- i b_k) / c_k however strong the (non-normal) coupling. Shift-and-invert about
/// a real target with MUMPS LU must return the conjugate pairs nearest the target.
fn block_gnhep_complex(rt: &Runtime) -> Result<Vec<f64>, String> {
    let comm = rt.world();
    let blocks = 60;
    let n = 2 * blocks;
    let (ak, bk, ck) = (
        |k: usize| 1.0 + 0.5 * k as f64,
        |k: usize| 0.3 + 0.01 * k as f64,
        |k: usize| 1.0 + 0.1 * (k % 3) as f64,
    );
    let a = matrix(comm, n, |i| {
        let k = i / 2;
        let (a, b) = (ak(k), bk(k));
        let mut row = if i % 2 == 0 {
            vec![(i, a), (i + 1, b)]
        } else {
            vec![(i - 1, -b), (i, a)]
        };
        if k + 1 < blocks {
            row.push((2 * (k + 1), 0.7));
            row.push((2 * (k + 1) + 1, -0.4));
        }
        row
    })?;
    let b = matrix(comm, n, |i| vec![(i, ck(i / 2))])?;
    let target = 6.0;
    let count = 6;
    let options = EigenOptions {
        problem: EigenProblem::NonHermitianGeneralized,
        spectrum: Spectrum::NearTarget { target, count },
        tolerance: 1e-12,
        linear: LinearMethod::Direct {
            package: DirectPackage::Mumps,
            factorization: Factorization::Lu,
        },
        ..Default::default()
    };
    let mut eps = EigenSolver::new(comm, &a, Some(&b), &options).map_err(e)?;
    let summary = eps.solve().map_err(e)?;
    if summary.converged < count {
        return Err(format!("{} of {count} converged", summary.converged));
    }
    let mut exact: Vec<Complex64> = (0..blocks)
        .flat_map(|k| {
            let c = ck(k);
            [
                Complex64::new(ak(k) / c, bk(k) / c),
                Complex64::new(ak(k) / c, -bk(k) / c),
            ]
        })
        .collect();
    exact.sort_by(|x, y| (x - target).norm().total_cmp(&(y - target).norm()));
    let mut out = Vec::new();
    for i in 0..count {
        let v = eps.value(i).map_err(e)?;
        let nearest = exact
            .iter()
            .map(|x| (x - v).norm() / x.norm())
            .fold(f64::INFINITY, f64::min);
        // Non-normal coupling amplifies the backward error by the eigenvector condition
        // number (about 1e2 here), so 1e-12 tolerance gives ~1e-10 in the eigenvalue.
        if nearest > 1e-9 {
            return Err(format!(
                "eigenvalue {v} is {nearest:e} from every closed-form value"
            ));
        }
        // It must also be among the `count` nearest to the target (ties broken by conjugation).
        let d = (v - target).norm();
        if d > (exact[count - 1] - target).norm() * (1.0 + 1e-9) {
            return Err(format!(
                "eigenvalue {v} is not among the {count} nearest the target"
            ));
        }
        out.push(v);
    }
    // Conjugates must come as pairs.
    for v in &out {
        if v.im != 0.0 && !out.iter().any(|w| (w - v.conj()).norm() < 1e-8 * v.norm()) {
            return Err(format!("eigenvalue {v} without its conjugate"));
        }
    }
    out.sort_by(|x, y| x.re.total_cmp(&y.re).then(x.im.total_cmp(&y.im)));
    Ok(out.iter().flat_map(|v| [v.re, v.im]).collect())
}

/// F(x) = A x + x^3 - b with A the 1D Laplacian and b made from x*_i = sin(pi (i+1)/(n+1)):
/// Newton from 0 must converge quadratically to x*.
fn snes_known_solution(rt: &Runtime) -> Result<Vec<f64>, String> {
    let comm = rt.world();
    let n = 100;
    let exact: Vec<f64> = (0..n)
        .map(|i| 2.0 * (PI * (i + 1) as f64 / (n as f64 + 1.0)).sin())
        .collect();
    let (lo, hi) = split(n, comm);
    let a_exact = |i: usize, x: &dyn Fn(usize) -> f64| -> f64 {
        laplacian_1d(i, n).iter().map(|&(j, v)| v * x(j)).sum()
    };
    let rhs: Vec<f64> = (0..n)
        .map(|i| a_exact(i, &|j| exact[j]) + exact[i].powi(3))
        .collect();
    let jac = matrix(comm, n, |i| laplacian_1d(i, n))?;
    let residual = Box::new(|x: &Vector, f: &mut Vector| -> Result<(), String> {
        let all = x.gather_all().map_err(e)?;
        let mut out = f.write().map_err(e)?;
        for (k, i) in (lo..hi).enumerate() {
            out[k] = a_exact(i, &|j| all[j]) + all[i].powi(3) - rhs[i];
        }
        Ok(())
    });
    let jacobian = Box::new(
        |x: &Vector, j: &mut Matrix| -> Result<JacobianChange, String> {
            let local = x.read().map_err(e)?.to_vec();
            j.zero().map_err(e)?;
            for (k, i) in (lo..hi).enumerate() {
                for (c, v) in laplacian_1d(i, n) {
                    let d = if c == i {
                        3.0 * local[k] * local[k]
                    } else {
                        0.0
                    };
                    j.add_block(&[i as PetscInt], &[c as PetscInt], &[v + d])
                        .map_err(e)?;
                }
            }
            j.assemble().map_err(e)?;
            Ok(JacobianChange::Unknown)
        },
    );
    let options = NewtonOptions {
        relative_tolerance: 1e-12,
        ..Default::default()
    };
    let mut snes = NonlinearSolver::new(comm, residual, jacobian, jac, &options).map_err(e)?;
    let mut x = Vector::new(comm, hi - lo).map_err(e)?;
    let report = snes.solve(&mut x).map_err(e)?;
    let all = x.gather_all().map_err(e)?;
    let err = all
        .iter()
        .zip(&exact)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    if err > 1e-10 {
        return Err(format!("|x - x*| = {err:e} after {report:?}"));
    }
    // Newton's quadratic convergence: the last ratios r_{k+1} / r_k^2 stay bounded, and it
    // takes few iterations.
    if report.iterations > 10 {
        return Err(format!("{} Newton iterations", report.iterations));
    }
    Ok(all)
}

/// The obstacle problem's residual on this rank's rows `lo..hi`: -u'' + k max(0, u - c) - 1
/// on n interior nodes of (0, 1) (see [`snes_kept_factorization`]).
#[allow(clippy::type_complexity)]
fn obstacle_residual<'rt>(
    n: usize,
    k: f64,
    c: f64,
    (lo, hi): (usize, usize),
) -> Box<dyn FnMut(&Vector<'rt>, &mut Vector<'rt>) -> Result<(), String>> {
    let h2 = 1.0 / ((n + 1) as f64).powi(2);
    Box::new(move |x: &Vector, f: &mut Vector| -> Result<(), String> {
        let all = x.gather_all().map_err(e)?;
        let mut out = f.write().map_err(e)?;
        for (r, i) in (lo..hi).enumerate() {
            let au: f64 = laplacian_1d(i, n).iter().map(|&(j, v)| v * all[j]).sum();
            out[r] = au / h2 + k * (all[i] - c).max(0.0) - 1.0;
        }
        Ok(())
    })
}

/// The obstacle problem's tangent at `x` into `j` (its rows `lo..hi`): A / h^2 + k on the
/// nodes past the obstacle, whose flags it returns; `empty_row`: row 0 all zeros (its
/// pattern kept), a tangent whose LU meets a zero pivot.
fn obstacle_tangent(
    x: &Vector,
    j: &mut Matrix,
    n: usize,
    k: f64,
    c: f64,
    (lo, hi): (usize, usize),
    empty_row: bool,
) -> Result<Vec<bool>, String> {
    let h2 = 1.0 / ((n + 1) as f64).powi(2);
    let active: Vec<bool> = x.read().map_err(e)?.iter().map(|&u| u > c).collect();
    j.zero().map_err(e)?;
    for (r, i) in (lo..hi).enumerate() {
        for (col, v) in laplacian_1d(i, n) {
            let d = if col == i && active[r] { k } else { 0.0 };
            let value = if empty_row && i == 0 { 0.0 } else { v / h2 + d };
            j.add_block(&[i as PetscInt], &[col as PetscInt], &[value])
                .map_err(e)?;
        }
    }
    j.assemble().map_err(e)?;
    Ok(active)
}

/// |a - b| in the 2-norm.
fn distance(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(a, b)| (a - b).powi(2))
        .sum::<f64>()
        .sqrt()
}

/// Newton on the obstacle problem from u = 0, to 1e-10 of the first residual, keeping
/// factorisations up to rank `keep`: the solution (every rank's copy) and the report. Full
/// steps: on a piecewise-linear F, Newton then moves from active set to active set (a
/// semismooth Newton), where backtracking would crawl.
#[allow(clippy::type_complexity)]
fn obstacle_solve<'f, 'rt>(
    comm: Comm<'rt>,
    n: usize,
    (lo, hi): (usize, usize),
    keep: usize,
    residual: Box<dyn FnMut(&Vector<'rt>, &mut Vector<'rt>) -> Result<(), String> + 'f>,
    jacobian: Box<dyn FnMut(&Vector<'rt>, &mut Matrix<'rt>) -> Result<JacobianChange, String> + 'f>,
) -> Result<(Vec<f64>, NewtonReport), String> {
    let jac = matrix(comm, n, |i| laplacian_1d(i, n))?;
    let options = NewtonOptions {
        relative_tolerance: 1e-10,
        line_search: "basic".into(),
        keep_factorization_rank: keep,
        ..Default::default()
    };
    let mut snes = NonlinearSolver::new(comm, residual, jacobian, jac, &options).map_err(e)?;
    let mut x = Vector::new(comm, hi - lo).map_err(e)?;
    let report = snes.solve(&mut x).map_err(e)?;
    Ok((x.gather_all().map_err(e)?, report))
}

/// A piecewise-linear problem like penalty contact: -u'' = 1 on (0, 1), u(0) = u(1) = 0,
/// with a stiff spring k max(0, u - c) where u passes the obstacle c. Newton's Jacobian
/// A + k diag(u > c) changes by one rank per node that enters or leaves the active set. With
/// the factorisation kept across small changes, the solution must be the same (to the
/// solve's tolerance), F = 0 must hold, and fewer factorisations must have been made.
fn snes_kept_factorization(rt: &Runtime) -> Result<Vec<f64>, String> {
    let comm = rt.world();
    let n = 400;
    let h2 = 1.0 / ((n + 1) as f64).powi(2);
    let (k, c) = (1e4, 0.1);
    let (lo, hi) = split(n, comm);
    let solve = |keep: usize| -> Result<(Vec<f64>, usize, usize), String> {
        let residual = obstacle_residual(n, k, c, (lo, hi));
        let mut previous: Option<Vec<bool>> = None;
        let jacobian = Box::new(
            move |x: &Vector, j: &mut Matrix| -> Result<JacobianChange, String> {
                let active = obstacle_tangent(x, j, n, k, c, (lo, hi), false)?;
                let change = match &previous {
                    None => JacobianChange::Unknown,
                    Some(p) => {
                        let mut flips =
                            [p.iter().zip(&active).filter(|(a, b)| a != b).count() as f64];
                        comm.sum_in_place(&mut flips);
                        JacobianChange::RankAtMost(flips[0] as usize)
                    }
                };
                previous = Some(active);
                Ok(change)
            },
        );
        let (x, report) = obstacle_solve(comm, n, (lo, hi), keep, residual, jacobian)?;
        Ok((x, report.iterations, report.factorizations))
    };
    let (fresh, its_fresh, lu_fresh) = solve(0)?;
    let (kept, its_kept, lu_kept) = solve(40)?;
    if lu_fresh != its_fresh {
        return Err(format!(
            "{lu_fresh} factorisations for {its_fresh} Newton steps without keeping"
        ));
    }
    if its_fresh < 3 || lu_kept >= lu_fresh {
        return Err(format!(
            "kept: {lu_kept} factorisations in {its_kept} steps; fresh: {lu_fresh} in {its_fresh}"
        ));
    }
    // F(u) = 0 checked here, independently of SNES's norm; scale: the load, 1 per node.
    let mut worst: f64 = 0.0;
    for i in 0..n {
        let au: f64 = laplacian_1d(i, n).iter().map(|&(j, v)| v * kept[j]).sum();
        worst = worst.max((au / h2 + k * (kept[i] - c).max(0.0) - 1.0).abs());
    }
    // Both stop at |F| <= 1e-10 |F(0)| = 1e-10 sqrt(n) (F(0) = -1 per node). F is strongly
    // monotone with constant lambda_min(A / h^2) > pi^2 - 1 (the spring term only adds), so
    // two such solutions differ by at most 2e-10 sqrt(n) / (pi^2 - 1) in the 2-norm, and
    // each |F_i| is at most 1e-10 sqrt(n).
    let f0 = (n as f64).sqrt();
    let differ = distance(&fresh, &kept);
    if worst > 1e-10 * f0 || differ > 2e-10 * f0 / (PI * PI - 1.0) {
        return Err(format!("|F| = {worst:e}, kept vs fresh {differ:e}"));
    }
    eprintln!(
        "kept factorisation: {lu_kept} LU in {its_kept} steps (fresh: {lu_fresh} in {its_fresh})"
    );
    Ok(kept)
}

/// A chain of soft springs (the 1-D Laplacian, unit loads) whose node pairs (0, 1), (2, 3),
/// ... are tied by springs `K_T` times stiffer: a reduced interface's stiff ties in
/// miniature. The residual |K u - f| cannot be computed below about eps |K|_inf |u|_inf
/// (~1e-6 here, 1e-7 of |F0|), above both the relative tolerance (1e-10 |F0|) and the
/// relative floor (1e-8 |F0|): Newton lands there in one step and can only stagnate. With
/// the floor on, that is convergence (`CONVERGED_ROUNDOFF_FLOOR`), and |F| is then within
/// the evaluation bound, checked here by recomputing it; with the floor off, the same solve
/// is a failure: the test sees the criterion at work.
fn snes_roundoff_floor(rt: &Runtime) -> Result<Vec<f64>, String> {
    const K_T: f64 = 2.3e7 * std::f64::consts::SQRT_2;
    let comm = rt.world();
    let n = 40;
    let (lo, hi) = split(n, comm);
    let row = move |i: usize| {
        let mut r = laplacian_1d(i, n);
        let partner = i ^ 1;
        r.push((i, K_T));
        r.push((partner, -K_T));
        r
    };
    let solve = |floor: f64| -> Result<(Vec<f64>, String), PetscError> {
        let jac = matrix(comm, n, row).map_err(PetscError::Invalid)?;
        let residual = Box::new(move |x: &Vector, f: &mut Vector| -> Result<(), String> {
            let all = x.gather_all().map_err(e)?;
            let mut out = f.write().map_err(e)?;
            for (r, i) in (lo..hi).enumerate() {
                out[r] = row(i).iter().map(|&(j, v)| v * all[j]).sum::<f64>() - 1.0;
            }
            Ok(())
        });
        let jacobian = Box::new(
            |_x: &Vector, _j: &mut Matrix| -> Result<JacobianChange, String> {
                Ok(JacobianChange::Unknown)
            },
        );
        let options = NewtonOptions {
            roundoff_floor: floor,
            ..Default::default()
        };
        let mut snes = NonlinearSolver::new(comm, residual, jacobian, jac, &options)?;
        let mut x = Vector::new(comm, hi - lo)?;
        let report = snes.solve(&mut x)?;
        Ok((x.gather_all()?, report.reason))
    };
    let (u, reason) = solve(1e-8).map_err(e)?;
    if reason != "CONVERGED_ROUNDOFF_FLOOR" {
        return Err(format!("stopped by {reason}, not on the round-off floor"));
    }
    let k_inf = 4.0 + 2.0 * K_T;
    let u_inf = u.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let bound = f64::EPSILON * k_inf * u_inf * (n as f64).sqrt();
    let f = (0..n)
        .map(|i| (row(i).iter().map(|&(j, v)| v * u[j]).sum::<f64>() - 1.0).powi(2))
        .sum::<f64>()
        .sqrt();
    if !(f <= bound && bound < 1e-5 * (n as f64).sqrt()) {
        return Err(format!(
            "|F| = {f:e} against the evaluation bound {bound:e}"
        ));
    }
    match solve(0.0) {
        Ok((_, reason)) => Err(format!(
            "without the floor the solve stopped by {reason}: the case does not reach the floor"
        )),
        Err(_) => Ok(vec![1.0]),
    }
}

/// The obstacle problem of [`snes_kept_factorization`] with a Jacobian that understates how
/// much it changed (rank at most 1 whatever the flips) and a kept rank of 1, so GMRES's limit
/// is 12 iterations: the first Newton step puts about 180 of the 400 nodes past the obstacle
/// (u = x (1 - x) / 2 > 0.1 on (0.276, 0.724)), and the kept LU of the Laplacian
/// preconditions a tangent that differs from it by k on those 180 nodes (a rank-180 change,
/// eigenvalues spread over decades): GMRES cannot reach 1e-12 in 12 iterations. That limit
/// is a poor preconditioner, not a failed Newton step: the step must be taken, the next
/// tangent factorised afresh, and Newton must reach the solution a fresh factor at every
/// step reaches (the same bound as there). Before 2026-12-07 it ended Newton
/// (DIVERGED_LINEAR_SOLVE), which made a floating caliper's static fail under one BLAS
/// kernel. And a factorisation that fails (a tangent with an empty row: a zero pivot) must
/// still end the solve at once, with the pivot named, on every rank.
fn snes_gmres_limit(rt: &Runtime) -> Result<Vec<f64>, String> {
    let comm = rt.world();
    let n = 400;
    let (k, c) = (1e4, 0.1);
    let (lo, hi) = split(n, comm);
    // `empty_row`: the tangent's row 0 is zero (its pattern kept), so its LU has a zero pivot.
    let solve = |keep: usize, understate: bool, empty_row: bool| {
        let residual = obstacle_residual(n, k, c, (lo, hi));
        let mut first = true;
        let jacobian = Box::new(
            move |x: &Vector, j: &mut Matrix| -> Result<JacobianChange, String> {
                obstacle_tangent(x, j, n, k, c, (lo, hi), empty_row)?;
                let change = if first || !understate {
                    JacobianChange::Unknown
                } else {
                    JacobianChange::RankAtMost(1)
                };
                first = false;
                Ok(change)
            },
        );
        obstacle_solve(comm, n, (lo, hi), keep, residual, jacobian)
    };
    let (fresh, _) = solve(0, false, false)?;
    let (kept, report) = solve(1, true, false)
        .map_err(|err| format!("GMRES's limit around a kept factor ended Newton: {err}"))?;
    // As in snes_kept_factorization: two solutions with |F| <= 1e-10 |F(0)| of a strongly
    // monotone F (constant > pi^2 - 1) differ by at most 2e-10 sqrt(n) / (pi^2 - 1).
    let f0 = (n as f64).sqrt();
    let differ = distance(&fresh, &kept);
    if differ > 2e-10 * f0 / (PI * PI - 1.0) {
        return Err(format!("kept vs fresh {differ:e} after {report:?}"));
    }
    match solve(1, false, true) {
        Ok((_, r)) => Err(format!("a tangent with a zero pivot gave Ok({r:?})")),
        Err(err) if err.contains("zero pivot") => Ok(kept),
        Err(err) => Err(format!("a zero pivot not named: {err}")),
    }
}

/// A residual or Jacobian closure that fails must surface as an Err carrying its message on
/// every rank, not as a crash or a hang, and the solver must then be destroyed cleanly.
fn snes_callback_error(rt: &Runtime) -> Result<Vec<f64>, String> {
    snes_residual_error(rt)?;
    snes_jacobian_error(rt)
}

fn snes_jacobian_error(rt: &Runtime) -> Result<Vec<f64>, String> {
    let comm = rt.world();
    let n = 10;
    let (lo, hi) = split(n, comm);
    let jac = matrix(comm, n, |i| laplacian_1d(i, n))?;
    let residual =
        Box::new(|_x: &Vector, f: &mut Vector| -> Result<(), String> { f.set(1.0).map_err(e) });
    let jacobian = Box::new(
        |_x: &Vector, j: &mut Matrix| -> Result<JacobianChange, String> {
            // Fail half-way through an assembly, as a real Jacobian might.
            j.add_block(&[0], &[0], &[1.0]).map_err(e)?;
            Err("tangent failed on purpose".into())
        },
    );
    let mut snes = NonlinearSolver::new(comm, residual, jacobian, jac, &NewtonOptions::default())
        .map_err(e)?;
    let mut x = Vector::new(comm, hi - lo).map_err(e)?;
    let result = match snes.solve(&mut x) {
        Ok(r) => Err(format!("a failing Jacobian gave Ok({r:?})")),
        Err(err) if err.to_string().contains("tangent failed on purpose") => Ok(vec![1.0]),
        Err(err) => Err(format!("error without the callback's message: {err}")),
    };
    drop(snes);
    result
}

fn snes_residual_error(rt: &Runtime) -> Result<Vec<f64>, String> {
    let comm = rt.world();
    let n = 10;
    let (lo, hi) = split(n, comm);
    let jac = matrix(comm, n, |i| laplacian_1d(i, n))?;
    let residual = Box::new(|_x: &Vector, _f: &mut Vector| -> Result<(), String> {
        Err("contact search failed on purpose".into())
    });
    let jacobian = Box::new(
        |_x: &Vector, _j: &mut Matrix| -> Result<JacobianChange, String> {
            Ok(JacobianChange::Unknown)
        },
    );
    let mut snes = NonlinearSolver::new(comm, residual, jacobian, jac, &NewtonOptions::default())
        .map_err(e)?;
    let mut x = Vector::new(comm, hi - lo).map_err(e)?;
    match snes.solve(&mut x) {
        Ok(r) => Err(format!("a failing residual gave Ok({r:?})")),
        Err(err) if err.to_string().contains("contact search failed on purpose") => Ok(vec![1.0]),
        Err(err) => Err(format!("error without the callback's message: {err}")),
    }
}

/// (K + lambda C + lambda^2 M) x = 0 with diagonal K, C, M: each DOF is an oscillator,
/// lambda = (-c +/- sqrt(c^2 - 4 m k)) / (2 m). The 8 nearest 0 must match.
fn pep_closed_form(rt: &Runtime) -> Result<Vec<f64>, String> {
    let comm = rt.world();
    let n = 50;
    let (kk, cc, mm) = (
        |i: usize| 1.0 + i as f64,
        |i: usize| 0.05 + 0.01 * i as f64,
        |i: usize| 1.0 + 0.02 * i as f64,
    );
    let k = matrix(comm, n, |i| vec![(i, kk(i))])?;
    let c = matrix(comm, n, |i| vec![(i, cc(i))])?;
    let m = matrix(comm, n, |i| vec![(i, mm(i))])?;
    let count = 8;
    let options = QuadraticOptions {
        target: 0.0,
        count,
        tolerance: 1e-12,
        ..Default::default()
    };
    let mut pep = QuadraticEigenSolver::new(comm, &k, &c, &m, &options).map_err(e)?;
    let summary = pep.solve().map_err(e)?;
    let converged = summary.converged;
    if converged < count {
        return Err(format!("{converged} of {count} converged: {summary:?}"));
    }
    // SLEPc's PEP_CONVERGED_TOL, the same code as EPS's, and the count asked for.
    if summary.reason != 1 || summary.requested != count || summary.iterations == 0 {
        return Err(format!("unexpected summary {summary:?}"));
    }
    let exact: Vec<Complex64> = (0..n)
        .flat_map(|i| {
            let (k, c, m) = (kk(i), cc(i), mm(i));
            let disc = Complex64::new(c * c - 4.0 * m * k, 0.0).sqrt();
            [(-c + disc) / (2.0 * m), (-c - disc) / (2.0 * m)]
        })
        .collect();
    let (_, template) = k.vectors().map_err(e)?;
    let mut out = Vec::new();
    for i in 0..count {
        let (v, _xr, _xi) = pep.pair(i, &template).map_err(e)?;
        let nearest = exact
            .iter()
            .map(|x| (x - v).norm() / x.norm())
            .fold(f64::INFINITY, f64::min);
        if nearest > 1e-9 {
            return Err(format!(
                "eigenvalue {v} is {nearest:e} from the closed form"
            ));
        }
        out.push(v);
    }
    out.sort_by(|x, y| x.im.total_cmp(&y.im));
    Ok(out.iter().flat_map(|v| [v.re, v.im]).collect())
}

/// A matrix with a zero row cannot be factorised: the solve must return Err (with MUMPS's
/// reason) on every rank.
fn singular_solve(rt: &Runtime) -> Result<Vec<f64>, String> {
    let comm = rt.world();
    let n = 20;
    let a = matrix(comm, n, |i| {
        if i == n / 2 {
            vec![(i, 0.0)]
        } else {
            vec![(i, 1.0)]
        }
    })?;
    let method = LinearMethod::Direct {
        package: DirectPackage::Mumps,
        factorization: Factorization::Lu,
    };
    let mut ksp = LinearSolver::new(comm, &a, &method).map_err(e)?;
    let (mut x, b) = a.vectors().map_err(e)?;
    b.set(1.0).map_err(e)?;
    match ksp.solve(&b, &mut x) {
        Ok(its) => Err(format!("singular solve returned Ok({its})")),
        Err(err) => {
            let text = err.to_string();
            if text.is_empty() {
                Err("empty error message".into())
            } else {
                Ok(vec![1.0])
            }
        }
    }
}

/// Adding an entry the pattern does not hold is an error (the exact preallocation is a
/// contract), reported with PETSc's message.
fn outside_pattern(rt: &Runtime) -> Result<Vec<f64>, String> {
    let comm = rt.world();
    let n = 8;
    let (lo, _) = split(n, comm);
    let mut m = matrix(comm, n, |i| vec![(i, 1.0)])?;
    let far = (lo + n / 2 + 1) % n;
    let local = m.add_block(&[lo as PetscInt], &[far as PetscInt], &[1.0]);
    match local {
        Err(err) if err.to_string().to_lowercase().contains("new nonzero") => Ok(vec![1.0]),
        Err(err) => Err(format!("unexpected message: {err}")),
        Ok(()) => Err("an entry outside the pattern was accepted".into()),
    }
}

/// gather_all returns the same global vector on every rank; norms agree with a direct sum.
fn vector_gather(rt: &Runtime) -> Result<Vec<f64>, String> {
    let comm = rt.world();
    let n = 37;
    let (lo, hi) = split(n, comm);
    let mut v = Vector::new(comm, hi - lo).map_err(e)?;
    v.set_local(&(lo..hi).map(|i| i as f64 - 10.0).collect::<Vec<_>>())
        .map_err(e)?;
    let all = v.gather_all().map_err(e)?;
    let expect: Vec<f64> = (0..n).map(|i| i as f64 - 10.0).collect();
    if all != expect {
        return Err(format!("gathered {all:?}"));
    }
    let norm = v.norm2().map_err(e)?;
    let direct = expect.iter().map(|x| x * x).sum::<f64>().sqrt();
    if relative(norm, direct) > 1e-15 {
        return Err(format!("norm {norm} vs {direct}"));
    }
    let mut w = v.copy().map_err(e)?;
    w.axpy(-1.0, &v).map_err(e)?;
    if w.norm_max().map_err(e)? != 0.0 {
        return Err("copy differs".into());
    }
    Ok(vec![norm, v.dot(&v).map_err(e)?])
}

// ---------------------------------------------------------------------------------------
// Craig-Bampton building blocks: index sets, sub-matrices, block solves, dense exports.

/// Row i of a five-point stencil on a g x g grid (`diagonal`, `off` to the 4 neighbours, none
/// past the edges). With (4, -1) the Dirichlet Laplacian (SPD, condition ~ 0.4 (g+1)^2);
/// with (1, 0.1) a diagonally dominant SPD "mass".
fn five_point(i: usize, g: usize, diagonal: f64, off: f64) -> Vec<(usize, f64)> {
    let (x, y) = (i % g, i / g);
    let mut row = vec![(i, diagonal)];
    if x > 0 {
        row.push((i - 1, off));
    }
    if x + 1 < g {
        row.push((i + 1, off));
    }
    if y > 0 {
        row.push((i - g, off));
    }
    if y + 1 < g {
        row.push((i + g, off));
    }
    row
}

/// The test super-element: a 12 x 12 grid whose boundary (interface) equations are the left
/// and right grid columns plus one inner node; uneven over 2 ranks on purpose (rank 0 owns
/// rows 0..72, with 13 of the 25 boundary equations).
struct Element<'rt> {
    n: usize,
    stiffness: Matrix<'rt>,
    mass: Matrix<'rt>,
    boundary: Vec<usize>,
    interior: Vec<usize>,
    /// The same matrices, dense, built from the same row function on every rank.
    stiffness_dense: Mat<f64>,
    mass_dense: Mat<f64>,
}

const GRID: usize = 12;

fn element(comm: Comm<'_>) -> Result<Element<'_>, String> {
    // Each rank computes only its own block, and this PETSc is not thread-safe anyway.
    faer::set_global_parallelism(Par::Seq);
    let g = GRID;
    let n = g * g;
    let k_row = |i: usize| five_point(i, g, 4.0, -1.0);
    let m_row = |i: usize| five_point(i, g, 1.0, 0.1);
    let dense = |row: &dyn Fn(usize) -> Vec<(usize, f64)>| {
        let mut d = Mat::<f64>::zeros(n, n);
        for i in 0..n {
            for (j, v) in row(i) {
                d[(i, j)] += v;
            }
        }
        d
    };
    let mut boundary: Vec<usize> = (0..g).flat_map(|y| [y * g, y * g + g - 1]).collect();
    boundary.push(5 * g + 6);
    boundary.sort_unstable();
    let interior = (0..n)
        .filter(|i| boundary.binary_search(i).is_err())
        .collect();
    Ok(Element {
        n,
        stiffness: matrix(comm, n, k_row)?,
        mass: matrix(comm, n, m_row)?,
        boundary,
        interior,
        stiffness_dense: dense(&k_row),
        mass_dense: dense(&m_row),
    })
}

/// `a[rows, cols]` of a dense matrix.
fn dense_block(a: &Mat<f64>, rows: &[usize], cols: &[usize]) -> Mat<f64> {
    Mat::from_fn(rows.len(), cols.len(), |i, j| a[(rows[i], cols[j])])
}

/// The whole of a distributed sparse matrix on every rank (through the dense conversion).
fn gathered(comm: Comm<'_>, a: &Matrix<'_>) -> Result<Mat<f64>, String> {
    DenseMatrix::from_sparse(comm, a)
        .and_then(|d| d.to_faer())
        .map_err(e)
}

fn flatten(a: &Mat<f64>) -> Vec<f64> {
    (0..a.nrows())
        .flat_map(|i| (0..a.ncols()).map(move |j| (i, j)))
        .map(|(i, j)| a[(i, j)])
        .collect()
}

/// The interior/boundary split of the owned rows, as index sets (I, B).
fn split_sets<'rt>(
    comm: Comm<'rt>,
    el: &Element<'rt>,
) -> Result<(IndexSet<'rt>, IndexSet<'rt>), String> {
    let (lo, hi) = el.stiffness.ownership_range().map_err(e)?;
    let b = IndexSet::owned_subset(comm, lo..hi, &el.boundary).map_err(e)?;
    let i = b.complement(lo..hi).map_err(e)?;
    Ok((i, b))
}

/// IS from a sorted list and its complement hold exactly this rank's boundary and interior
/// equations; K_II, K_IB, M_II extracted from the distributed matrices equal the dense
/// blocks entry for entry (copies, so exactly: tolerance 0). An unsorted list is an Err on
/// every rank.
fn index_sets_and_submatrices(rt: &Runtime) -> Result<Vec<f64>, String> {
    let comm = rt.world();
    let el = element(comm)?;
    let (lo, hi) = el.stiffness.ownership_range().map_err(e)?;
    let (i_set, b_set) = split_sets(comm, &el)?;
    let owned = |list: &[usize]| -> Vec<usize> {
        list.iter()
            .copied()
            .filter(|&i| lo <= i && i < hi)
            .collect()
    };
    if b_set.indices().map_err(e)? != owned(&el.boundary)
        || i_set.indices().map_err(e)? != owned(&el.interior)
    {
        return Err("index sets differ from the owned boundary/interior equations".into());
    }
    if b_set.global_size().map_err(e)? != el.boundary.len()
        || i_set.global_size().map_err(e)? != el.interior.len()
        || i_set.local_size().map_err(e)? + b_set.local_size().map_err(e)? != hi - lo
    {
        return Err("index set sizes".into());
    }
    if IndexSet::owned_subset(comm, lo..hi, &[3, 1]).is_ok() {
        return Err("an unsorted list was accepted".into());
    }
    let k_ii = el.stiffness.submatrix(&i_set, &i_set).map_err(e)?;
    let k_ib = el.stiffness.submatrix(&i_set, &b_set).map_err(e)?;
    let m_ii = el.mass.submatrix(&i_set, &i_set).map_err(e)?;
    let mut out = Vec::new();
    for (name, sub, full, cols) in [
        ("K_II", &k_ii, &el.stiffness_dense, &el.interior),
        ("K_IB", &k_ib, &el.stiffness_dense, &el.boundary),
        ("M_II", &m_ii, &el.mass_dense, &el.interior),
    ] {
        let expect = dense_block(full, &el.interior, cols);
        let (rows, ncols) = sub.size().map_err(e)?;
        if (rows, ncols) != (expect.nrows(), expect.ncols()) {
            return Err(format!("{name} is {rows}x{ncols}"));
        }
        // Distributed like the original: this rank's rows of the sub-matrix are its own
        // interior equations.
        let (slo, shi) = sub.ownership_range().map_err(e)?;
        if shi - slo != owned(&el.interior).len() {
            return Err(format!("{name} rows {slo}..{shi} on this rank"));
        }
        let got = gathered(comm, sub)?;
        if got != expect {
            return Err(format!("{name} differs from the dense block"));
        }
        out.push(sub.norm_frobenius().map_err(e)?);
    }
    out.extend(flatten(&gathered(comm, &k_ib)?));
    Ok(out)
}

/// Psi = -K_II^-1 K_IB from one MUMPS factorisation (LU, and Cholesky on the symmetric K_II)
/// with the 25 right-hand sides solved as one dense block, against faer's dense Cholesky
/// solve. Also: a column read out, the gathered vectors and a matrix rebuilt from its
/// columns equal the gathered block bit for bit (copies).
fn constraint_modes_block_solve(rt: &Runtime) -> Result<Vec<f64>, String> {
    let comm = rt.world();
    let el = element(comm)?;
    let (i_set, b_set) = split_sets(comm, &el)?;
    let mut k_ii = el.stiffness.submatrix(&i_set, &i_set).map_err(e)?;
    let k_ib = el.stiffness.submatrix(&i_set, &b_set).map_err(e)?;
    let rhs = DenseMatrix::from_sparse(comm, &k_ib).map_err(e)?;

    let k_ii_dense = dense_block(&el.stiffness_dense, &el.interior, &el.interior);
    let k_ib_dense = dense_block(&el.stiffness_dense, &el.interior, &el.boundary);
    let llt = k_ii_dense.llt(Side::Lower).map_err(|x| format!("{x:?}"))?;
    let reference = -llt.solve(&k_ib_dense);
    let eigenvalues = k_ii_dense
        .self_adjoint_eigenvalues(Side::Lower)
        .map_err(|x| format!("{x:?}"))?;
    let condition = eigenvalues[eigenvalues.len() - 1] / eigenvalues[0];
    let n_i = el.interior.len() as f64;
    // A backward-stable solve (MUMPS with its pivoting, faer's Cholesky) of an SPD system
    // has relative forward error <= condition * backward error, and the backward error is
    // c(n) eps with c(n) ~ sqrt(n) for rounding errors that do not all line up (Higham,
    // Accuracy and Stability, 3.5). Two such solutions differ by twice that; a factor 10
    // covers the constant in c(n) and MUMPS's scaling. Here condition = 39 (computed below;
    // O(g^2) for the grid's Laplacian), n_I = 119: a bound of 1.9e-12; measured 1.3e-15 for
    // both LU and Cholesky, on 1 and 2 ranks.
    let bound = 2.0 * 10.0 * n_i.sqrt() * f64::EPSILON * condition;

    let mut out = Vec::new();
    for factorization in [Factorization::Lu, Factorization::Cholesky] {
        if factorization == Factorization::Cholesky {
            k_ii.mark_symmetric().map_err(e)?;
        }
        let factored =
            FactoredMatrix::new(comm, &k_ii, DirectPackage::Mumps, factorization).map_err(e)?;
        let mut psi = factored.solve_block(&rhs).map_err(e)?;
        psi.scale(-1.0).map_err(e)?;
        let psi_all = psi.to_faer().map_err(e)?;
        if (psi_all.nrows(), psi_all.ncols()) != (el.interior.len(), el.boundary.len()) {
            return Err(format!("Psi is {}x{}", psi_all.nrows(), psi_all.ncols()));
        }
        let mut worst: f64 = 0.0;
        for j in 0..psi_all.ncols() {
            let (mut diff, mut norm) = (0.0, 0.0);
            for i in 0..psi_all.nrows() {
                diff += (psi_all[(i, j)] - reference[(i, j)]).powi(2);
                norm += reference[(i, j)].powi(2);
            }
            worst = worst.max((diff / norm).sqrt());
        }
        if worst > bound {
            return Err(format!(
                "{factorization:?}: column error {worst:e} > {bound:e} (condition {condition:.1})"
            ));
        }
        if comm.rank() == 0 {
            eprintln!("{factorization:?}: Psi column error {worst:.2e}, bound {bound:.2e}");
        }
        // Column access and the exports agree with the gathered block exactly.
        let columns: Vec<Vector> = (0..psi_all.ncols())
            .map(|j| psi.column(j))
            .collect::<Result<_, _>>()
            .map_err(e)?;
        if columns_to_faer(&columns).map_err(e)? != psi_all {
            return Err("gathered columns differ from the gathered block".into());
        }
        let rebuilt = DenseMatrix::from_columns(comm, &columns).map_err(e)?;
        if rebuilt.to_faer().map_err(e)? != psi_all {
            return Err("a matrix rebuilt from its columns differs".into());
        }
        let (lo, hi) = psi.ownership_range().map_err(e)?;
        let local = psi.local_values().map_err(e)?;
        if local != psi_all.subrows(lo, hi - lo).to_owned() {
            return Err("local rows differ from the gathered block".into());
        }
        out.extend(flatten(&psi_all));
    }
    Ok(out)
}

/// T^T A T for a distributed sparse A and distributed dense T, on every rank: A = K with
/// a smooth 7-column T, and A = K_II, M_II with T = Psi (as the super-element's K_r, M_r).
/// Each entry is compared with the dense product from the same numbers
/// ([`check_projection`]).
fn projection_t_k_t(rt: &Runtime) -> Result<Vec<f64>, String> {
    let comm = rt.world();
    let el = element(comm)?;
    let (lo, hi) = el.stiffness.ownership_range().map_err(e)?;
    let columns = 7;
    let basis = |i: usize, j: usize| (0.3 * i as f64 + 0.7 * j as f64).cos() + 0.01 * j as f64;
    let mut t = DenseMatrix::zeros(comm, hi - lo, columns).map_err(e)?;
    t.write_local(|i, j| basis(lo + i, j)).map_err(e)?;
    let t_all = Mat::from_fn(el.n, columns, basis);

    let (i_set, b_set) = split_sets(comm, &el)?;
    let k_ii = el.stiffness.submatrix(&i_set, &i_set).map_err(e)?;
    let m_ii = el.mass.submatrix(&i_set, &i_set).map_err(e)?;
    let k_ib = el.stiffness.submatrix(&i_set, &b_set).map_err(e)?;
    let factored =
        FactoredMatrix::new(comm, &k_ii, DirectPackage::Mumps, Factorization::Lu).map_err(e)?;
    let mut psi = factored
        .solve_block(&DenseMatrix::from_sparse(comm, &k_ib).map_err(e)?)
        .map_err(e)?;
    psi.scale(-1.0).map_err(e)?;
    let psi_all = psi.to_faer().map_err(e)?;

    let mut out = Vec::new();
    for (name, a, a_dense, t, t_all) in [
        (
            "T^T K T",
            &el.stiffness,
            el.stiffness_dense.clone(),
            &t,
            &t_all,
        ),
        (
            "Psi^T K_II Psi",
            &k_ii,
            dense_block(&el.stiffness_dense, &el.interior, &el.interior),
            &psi,
            &psi_all,
        ),
        (
            "Psi^T M_II Psi",
            &m_ii,
            dense_block(&el.mass_dense, &el.interior, &el.interior),
            &psi,
            &psi_all,
        ),
    ] {
        let got = a.project(t).map_err(e)?;
        check_projection(name, &got, &a_dense, t_all)?;
        out.extend(flatten(&got));
        // The symmetric one: the same bound, and exactly symmetric.
        let half = a.project_symmetric(t).map_err(e)?;
        check_projection(&format!("{name} (symmetric)"), &half, &a_dense, t_all)?;
        check_symmetric(name, &half)?;
        out.extend(flatten(&half));
    }
    // More columns than the symmetric projection's block (128): its blocks below the
    // diagonal, and the mirrored ones above, against the dense product.
    let wide = 2 * 128 + 17;
    let mut t = DenseMatrix::zeros(comm, hi - lo, wide).map_err(e)?;
    t.write_local(|i, j| basis(lo + i, j)).map_err(e)?;
    let t_all = Mat::from_fn(el.n, wide, basis);
    let half = el.mass.project_symmetric(&t).map_err(e)?;
    check_projection(
        "T^T M T (symmetric, 273 columns)",
        &half,
        &el.mass_dense,
        &t_all,
    )?;
    check_symmetric("T^T M T", &half)?;
    out.extend(flatten(&half));
    // The blocked sparse-times-dense product (32 columns a pass: 273 is 8 blocks and 17)
    // against PETSc's: each entry one sparse row times one column, summed in another order
    // by each, so within 2 gamma_n (|A| |T|)_ij of each other (see check_projection).
    let ours = el.mass.mult_tall(&t).map_err(e)?.to_faer().map_err(e)?;
    let petsc = el.mass.mult_dense(&t).map_err(e)?.to_faer().map_err(e)?;
    let gamma = {
        let k = 2.0 * el.n as f64 * f64::EPSILON;
        k / (1.0 - k)
    };
    for i in 0..el.n {
        for j in 0..wide {
            let magnitude: f64 = (0..el.n)
                .map(|k| el.mass_dense[(i, k)].abs() * t_all[(k, j)].abs())
                .sum();
            let gap = (ours[(i, j)] - petsc[(i, j)]).abs();
            if gap > 2.0 * gamma * magnitude {
                return Err(format!(
                    "M T [{i},{j}]: {} blocked against {} from PETSc",
                    ours[(i, j)],
                    petsc[(i, j)]
                ));
            }
        }
    }
    out.extend(flatten(&ours));
    Ok(out)
}

fn check_symmetric(name: &str, a: &Mat<f64>) -> Result<(), String> {
    for j in 0..a.ncols() {
        for i in 0..j {
            if a[(i, j)] != a[(j, i)] {
                return Err(format!(
                    "{name}: [{i},{j}] = {} but [{j},{i}] = {}",
                    a[(i, j)],
                    a[(j, i)]
                ));
            }
        }
    }
    Ok(())
}

/// Checks `got` = T^T A T entry by entry against the dense product of the same numbers.
/// Each entry is a dot product of length n nested in another (T^T (A T), in whatever order
/// either side sums): both computations are within gamma_{2n} (|T|^T |A| |T|)_pq of the
/// exact value (gamma_k = k eps / (1 - k eps), Higham, Accuracy and Stability, 3.5), so
/// they differ by at most twice that. A rigorous bound, not a guess.
fn check_projection(name: &str, got: &Mat<f64>, a: &Mat<f64>, t: &Mat<f64>) -> Result<(), String> {
    let (n, m) = (t.nrows(), t.ncols());
    if (got.nrows(), got.ncols()) != (m, m) {
        return Err(format!("{name} is {}x{}", got.nrows(), got.ncols()));
    }
    let mut at = Mat::<f64>::zeros(n, m);
    let mut abs_at = Mat::<f64>::zeros(n, m);
    for i in 0..n {
        for j in 0..n {
            let v = a[(i, j)];
            if v != 0.0 {
                for q in 0..m {
                    at[(i, q)] += v * t[(j, q)];
                    abs_at[(i, q)] += (v * t[(j, q)]).abs();
                }
            }
        }
    }
    let gamma = |k: f64| k * f64::EPSILON / (1.0 - k * f64::EPSILON);
    for p in 0..m {
        for q in 0..m {
            let (mut exact, mut magnitude) = (0.0, 0.0);
            for i in 0..n {
                exact += t[(i, p)] * at[(i, q)];
                magnitude += t[(i, p)].abs() * abs_at[(i, q)];
            }
            let allowed = 2.0 * gamma(2.0 * n as f64) * magnitude;
            if (got[(p, q)] - exact).abs() > allowed {
                return Err(format!(
                    "{name}[{p},{q}] = {} but dense {exact} (allowed {allowed:e})",
                    got[(p, q)]
                ));
            }
        }
    }
    Ok(())
}

/// Fixed-interface modes: the 4 lowest eigenvalues of (K_II, M_II), extracted as
/// sub-matrices and solved by SLEPc (shift-and-invert with MUMPS), equal the dense ones
/// (faer: M_II = L L^T, eigenvalues of L^-1 K_II L^-T). Hermitian problem, tolerance
/// 1e-12: the eigenvalue error is O(residual^2), so 1e-9 relative is far above it.
fn fixed_interface_modes(rt: &Runtime) -> Result<Vec<f64>, String> {
    let comm = rt.world();
    let el = element(comm)?;
    let (i_set, _) = split_sets(comm, &el)?;
    let k_ii = el.stiffness.submatrix(&i_set, &i_set).map_err(e)?;
    let m_ii = el.mass.submatrix(&i_set, &i_set).map_err(e)?;
    let count = 4;
    let options = EigenOptions {
        problem: EigenProblem::HermitianGeneralized,
        spectrum: Spectrum::NearTarget { target: 0.0, count },
        tolerance: 1e-12,
        ..Default::default()
    };
    let mut eps = EigenSolver::new(comm, &k_ii, Some(&m_ii), &options).map_err(e)?;
    let summary = eps.solve().map_err(e)?;
    if summary.converged < count {
        return Err(format!("{summary:?}"));
    }
    let mut found: Vec<f64> = (0..count)
        .map(|i| eps.value(i).map(|v| v.re))
        .collect::<Result<_, _>>()
        .map_err(e)?;
    found.sort_by(f64::total_cmp);

    let k = dense_block(&el.stiffness_dense, &el.interior, &el.interior);
    let m = dense_block(&el.mass_dense, &el.interior, &el.interior);
    let l = m
        .llt(Side::Lower)
        .map_err(|x| format!("{x:?}"))?
        .L()
        .to_owned();
    let mut l_inv = Mat::<f64>::identity(l.nrows(), l.nrows());
    faer::linalg::triangular_solve::solve_lower_triangular_in_place(
        l.as_ref(),
        l_inv.as_mut(),
        Par::Seq,
    );
    let c = &l_inv * &k * l_inv.transpose();
    let exact = c
        .self_adjoint_eigenvalues(Side::Lower)
        .map_err(|x| format!("{x:?}"))?;
    for (f, x) in found.iter().zip(&exact) {
        if relative(*f, *x) > 1e-9 {
            return Err(format!("eigenvalue {f} but dense {x}"));
        }
    }
    Ok(found)
}

/// A block factorisation of a singular matrix is an Err on every rank, before any solve.
fn singular_block_factorization(rt: &Runtime) -> Result<Vec<f64>, String> {
    let comm = rt.world();
    let n = 20;
    let a = matrix(comm, n, |i| vec![(i, if i == n / 2 { 0.0 } else { 1.0 })])?;
    match FactoredMatrix::new(comm, &a, DirectPackage::Mumps, Factorization::Lu) {
        Ok(_) => Err("a singular matrix was factorised".into()),
        Err(err) if !err.to_string().is_empty() => Ok(vec![1.0]),
        Err(_) => Err("empty error message".into()),
    }
}

/// A free-free steel tet10 block (3 x 2 x 1 cells, 315 equations, K and M from
/// `fem::assemble`) whose interface is every DOF of its two end faces x0 and x1 (90
/// equations). The constraint modes Psi from one MUMPS Cholesky with a block solve must
/// (1) match faer's dense solve within the condition-based bound of
/// `constraint_modes_block_solve` (condition 1.5e3, bound 9.8e-11, measured 2e-14), and
/// (2) carry a rigid translation of the interface to the same translation of the interior,
/// as K r = 0 demands (measured errors <= 2e-14). The Craig-Bampton basis
/// T = [Psi; I] is then laid out in the model's own equation order (each rank its own
/// rows, as the super-element code will), and K_r = T^T K T must equal the dense product
/// within the rigorous rounding bound of [`check_projection`].
fn tet10_craig_bampton(rt: &Runtime) -> Result<Vec<f64>, String> {
    let comm = rt.world();
    faer::set_global_parallelism(Par::Seq);
    let steel = Material {
        name: "steel".into(),
        young: 210e9,
        poisson: 0.3,
        density: 7850.0,
    };
    let mesh = block([0.0; 3], [0.1, 0.04, 0.02], [3, 2, 1], steel).map_err(|e| e.to_string())?;
    let dofs = DofMap::new(mesh.nodes.len(), 0, &[], comm.size(), comm.rank())
        .map_err(|e| e.to_string())?;
    let pattern = assemble::pattern(&dofs, mesh.elements.iter().map(|c| &c[..]));
    let (k, _m) =
        assemble::stiffness_and_mass(comm, &mesh, &dofs, &pattern, StructureOptions::default())
            .map_err(|x| x.to_string())?;
    let n = dofs.equations();
    // The displacement component (x, y, z) of each equation.
    let mut component = vec![0; n];
    for node in 0..mesh.nodes.len() {
        for c in 0..3 {
            if let Some(eq) = dofs.equation(node, c) {
                component[eq] = c;
            }
        }
    }
    let dofs = &dofs;
    let mut boundary: Vec<usize> = ["x0", "x1"]
        .iter()
        .flat_map(|set| mesh.node_sets[*set].iter())
        .flat_map(|&node| (0..3).filter_map(move |c| dofs.equation(node, c)))
        .collect();
    boundary.sort_unstable();
    boundary.dedup();
    let interior: Vec<usize> = (0..n)
        .filter(|i| boundary.binary_search(i).is_err())
        .collect();
    let (lo, hi) = k.ownership_range().map_err(e)?;
    let b_set = IndexSet::owned_subset(comm, lo..hi, &boundary).map_err(e)?;
    let i_set = b_set.complement(lo..hi).map_err(e)?;
    let mut k_ii = k.submatrix(&i_set, &i_set).map_err(e)?;
    k_ii.mark_symmetric().map_err(e)?;
    let k_ib = k.submatrix(&i_set, &b_set).map_err(e)?;
    let factored = FactoredMatrix::new(comm, &k_ii, DirectPackage::Mumps, Factorization::Cholesky)
        .map_err(e)?;
    let mut psi = factored
        .solve_block(&DenseMatrix::from_sparse(comm, &k_ib).map_err(e)?)
        .map_err(e)?;
    psi.scale(-1.0).map_err(e)?;
    let psi_all = psi.to_faer().map_err(e)?;

    // (1) Against the dense solve, as in constraint_modes_block_solve.
    let k_dense = gathered(comm, &k)?;
    let k_ii_dense = dense_block(&k_dense, &interior, &interior);
    let k_ib_dense = dense_block(&k_dense, &interior, &boundary);
    let reference = -k_ii_dense
        .llt(Side::Lower)
        .map_err(|x| format!("{x:?}"))?
        .solve(&k_ib_dense);
    let eigenvalues = k_ii_dense
        .self_adjoint_eigenvalues(Side::Lower)
        .map_err(|x| format!("{x:?}"))?;
    let (lambda_max, condition) = (
        eigenvalues[eigenvalues.len() - 1],
        eigenvalues[eigenvalues.len() - 1] / eigenvalues[0],
    );
    let n_i = interior.len() as f64;
    let solve_bound = 2.0 * 10.0 * n_i.sqrt() * f64::EPSILON * condition;
    let column_error = |x: &Mat<f64>, y: &Mat<f64>, j: usize| {
        let (mut diff, mut norm) = (0.0, 0.0);
        for i in 0..x.nrows() {
            diff += (x[(i, j)] - y[(i, j)]).powi(2);
            norm += y[(i, j)].powi(2);
        }
        (diff / norm).sqrt()
    };
    let worst = (0..psi_all.ncols())
        .map(|j| column_error(&psi_all, &reference, j))
        .fold(0.0, f64::max);
    if worst > solve_bound {
        return Err(format!(
            "Psi column error {worst:e} > {solve_bound:e} (condition {condition:.3e})"
        ));
    }

    // (2) Rigid translations. The assembled K annihilates r only to its own rounding, so
    // the exact solution of K_II x = -K_IB r_B is r_I plus K_II^-1 (K_II r_I + K_IB r_B):
    // the bound adds condition * |K_II r_I + K_IB r_B| / (lambda_max |r_I|) to the solve's.
    let mut rigid_errors = Vec::new();
    for c in 0..3 {
        let is_c = |eq: usize| component[eq] == c;
        let r_b: Vec<f64> = boundary
            .iter()
            .map(|&b| f64::from(u8::from(is_c(b))))
            .collect();
        let r_i: Vec<f64> = interior
            .iter()
            .map(|&i| f64::from(u8::from(is_c(i))))
            .collect();
        let norm_i = r_i.iter().map(|x| x * x).sum::<f64>().sqrt();
        let mut residual = 0.0;
        let mut error = 0.0;
        for i in 0..interior.len() {
            let mut k_r = 0.0;
            let mut psi_r = 0.0;
            for (j, &rj) in r_i.iter().enumerate() {
                k_r += k_ii_dense[(i, j)] * rj;
            }
            for (j, &rj) in r_b.iter().enumerate() {
                k_r += k_ib_dense[(i, j)] * rj;
                psi_r += psi_all[(i, j)] * rj;
            }
            residual += k_r * k_r;
            error += (psi_r - r_i[i]).powi(2);
        }
        let (residual, error) = (residual.sqrt(), error.sqrt() / norm_i);
        let bound = solve_bound + condition * residual / (lambda_max * norm_i);
        if error > bound {
            return Err(format!(
                "Psi r_B differs from r_I by {error:e} (bound {bound:e}) in direction {c}"
            ));
        }
        rigid_errors.push(error);
    }
    if comm.rank() == 0 {
        eprintln!(
            "tet10 block: condition {condition:.2e}, Psi error {worst:.2e} (bound \
             {solve_bound:.2e}), rigid translation errors {rigid_errors:?}"
        );
    }

    // The basis in the model's equation order: this rank's interior rows are Psi's local
    // rows, in the same order (the interior index set is Psi's row layout); its boundary
    // rows are rows of the identity.
    let psi_local = psi.local_values().map_err(e)?;
    let local_interior = i_set.indices().map_err(e)?;
    let mut t = DenseMatrix::zeros(comm, hi - lo, boundary.len()).map_err(e)?;
    t.write_local(|i, j| {
        let g = lo + i;
        match local_interior.binary_search(&g) {
            Ok(k) => psi_local[(k, j)],
            Err(_) => f64::from(u8::from(boundary[j] == g)),
        }
    })
    .map_err(e)?;
    let t_all = t.to_faer().map_err(e)?;
    for (row, &g) in interior.iter().enumerate() {
        for j in 0..boundary.len() {
            if t_all[(g, j)] != psi_all[(row, j)] {
                return Err(format!("T[{g},{j}] is not Psi[{row},{j}]"));
            }
        }
    }
    let k_r = k.project(&t).map_err(e)?;
    check_projection("K_r", &k_r, &k_dense, &t_all)?;
    // K_r (~1e10, steel in pascals) scaled to the size of Psi (~1), so that the comparison
    // between rank counts, relative to the largest number, weighs both.
    let scale = flatten(&k_r).iter().fold(0.0, |m: f64, x| m.max(x.abs()));
    let mut out = flatten(&psi_all);
    out.extend(flatten(&k_r).iter().map(|x| x / scale));
    Ok(out)
}
