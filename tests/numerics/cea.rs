//! Complex eigenvalue analysis against closed forms, on 1 and 2 ranks.

use crate::common;

use common::harness::Check;
use num_complex::Complex64;
use squeal::analysis::band_count;
use squeal::analysis::cea::{self, CeaOptions};
use squeal::analysis::operators::matrix_from_entries;
use squeal::petsc::{Matrix, PetscError, Runtime};
use std::f64::consts::PI;

pub const CHECKS: &[Check] = &[
    Check {
        name: "two_dof_mode_coupling_closed_form",
        run: two_dof_coupling,
        ranks: &[1, 2],
        agreement: 1e-10,
    },
    Check {
        name: "stepped_targets_find_every_mode_once",
        run: stepped_targets,
        ranks: &[1, 2],
        agreement: 1e-10,
    },
    Check {
        name: "a_window_sized_from_the_expected_count_finds_every_mode_once",
        run: hinted_targets,
        ranks: &[1, 2],
        agreement: 1e-10,
    },
    Check {
        name: "a_first_count_of_the_symmetric_part_covers_the_band_in_one_window",
        run: counted_targets,
        ranks: &[1, 2],
        agreement: 1e-10,
    },
    Check {
        name: "the_first_count_leaves_out_the_symmetric_parts_negative_eigenvalues",
        run: count_without_negatives,
        ranks: &[1, 2],
        agreement: 1e-10,
    },
    Check {
        name: "a_first_count_that_cannot_be_made_leaves_the_stepping_to_find_every_mode",
        run: uncounted_targets,
        ranks: &[1, 2],
        agreement: 1e-10,
    },
    Check {
        name: "a_wrong_expected_count_costs_shifts_not_modes",
        run: wrongly_hinted_targets,
        ranks: &[1, 2],
        agreement: 1e-10,
    },
    Check {
        name: "dense_windows_find_the_band_of_a_dense_pencil_as_every_eigenvalue_does",
        run: dense_windows,
        ranks: &[1, 2],
        agreement: 1e-9,
    },
    Check {
        name: "an_eigenvalue_on_the_edge_between_two_ranks_parts_is_found_once",
        run: eigenvalues_on_the_edges,
        ranks: &[1, 2, 3],
        agreement: 1e-9,
    },
    Check {
        name: "a_block_window_finds_the_eigenvalues_nearest_its_target_and_their_left_vectors",
        run: block_window,
        ranks: &[1, 2],
        agreement: 1e-9,
    },
    Check {
        name: "damping_moves_the_threshold_as_the_closed_form_says",
        run: damped_threshold,
        ranks: &[1, 2],
        agreement: 1e-10,
    },
];

fn e<E: std::fmt::Display>(err: E) -> String {
    err.to_string()
}

/// M = I, K = [[2, 1 - D], [1, 2]]: omega^2 = 2 +/- sqrt(1 - D). Below D = 1 two real modes;
/// at D = 1 they coalesce; above, lambda = +/- sqrt(-2 +/- i sqrt(D - 1)), one pair growing.
fn two_dof_coupling(rt: &Runtime) -> Result<Vec<f64>, String> {
    let comm = rt.world();
    let mut out = Vec::new();
    for d in [0.5, 0.99, 1.01, 1.5, 3.0] {
        let k = matrix_from_entries(
            comm,
            2,
            &[(0, 0, 2.0), (0, 1, 1.0 - d), (1, 0, 1.0), (1, 1, 2.0)],
        )
        .map_err(e)?;
        let m = matrix_from_entries(comm, 2, &[(0, 0, 1.0), (1, 1, 1.0)]).map_err(e)?;
        let options = CeaOptions {
            max_frequency_hz: 1.0,
            tolerance: 1e-13,
            ..Default::default()
        };
        let result = cea::undamped(comm, &k, &m, &options).map_err(e)?;
        let disc = Complex64::new(1.0 - d, 0.0).sqrt();
        let exact: Vec<Complex64> = [2.0 + disc, 2.0 - disc]
            .iter()
            .map(|&w2| cea::lambda_of(w2))
            .collect();
        if result.modes.len() != 2 {
            return Err(format!("D = {d}: {} modes", result.modes.len()));
        }
        for m in &result.modes {
            let found = exact
                .iter()
                .any(|x| (x - m.lambda).norm() < 1e-10 * x.norm());
            if !found {
                return Err(format!("D = {d}: lambda {} not in {exact:?}", m.lambda));
            }
            // lambda^2 = -2 -/+ i sqrt(D - 1) for D > 1 (the form).
            let unstable = d > 1.0 && m.real_part > 0.0;
            if m.unstable != unstable {
                return Err(format!("D = {d}: {m:?} flagged wrongly"));
            }
            out.extend([m.lambda.re, m.lambda.im]);
        }
        let n_unstable = result.modes.iter().filter(|m| m.unstable).count();
        if n_unstable != usize::from(d > 1.0) {
            return Err(format!("D = {d}: {n_unstable} unstable modes"));
        }
    }
    Ok(out)
}

/// 80 uncoupled 2x2 blocks [[k, c], [-c, k]] (M = I): omega^2 = k +/- i c, with k spread over
/// two decades and some blocks real (c = 0, a double eigenvalue). Every eigenvalue below the
/// band's top must be found exactly once through the stepped targets.
fn stepped_targets(rt: &Runtime) -> Result<Vec<f64>, String> {
    let (modes, targets) = blocks_band(rt, None, Band::AT_BLOCK_52)?;
    if targets < 3 {
        return Err("the band was covered by one target: the stepping is not tested".into());
    }
    Ok(modes)
}

/// The same band with its mode count known (as in a sweep after its first point): one
/// shift-and-invert window must hold it all.
fn hinted_targets(rt: &Runtime) -> Result<Vec<f64>, String> {
    let (modes, targets) = blocks_band(rt, Some(BAND_MODES), Band::AT_BLOCK_52)?;
    if targets != 1 {
        return Err(format!(
            "{targets} targets with the exact count given, expected 1"
        ));
    }
    Ok(modes)
}

/// Counts far too low and far too high: every mode still found once.
fn wrongly_hinted_targets(rt: &Runtime) -> Result<Vec<f64>, String> {
    let (mut low, _) = blocks_band(rt, Some(3), Band::AT_BLOCK_52)?;
    let (high, _) = blocks_band(rt, Some(4 * BAND_MODES), Band::AT_BLOCK_52)?;
    low.extend(high);
    Ok(low)
}

/// With the count of the symmetric part made first (as the sweep's first point and `squeal
/// cea` do): the symmetric part of block b is k_b I (the friction-like coupling is skew), so
/// 106 eigenvalues lie below 706.25 Hz, those of blocks 0..=52, and the band holds the same
/// 106 modes (block 52's pair at 700.009 Hz). One window must hold it all.
fn counted_targets(rt: &Runtime) -> Result<Vec<f64>, String> {
    let band = Band {
        max_frequency_hz: 706.25,
        modes: BAND_MODES + 2,
        count_first: true,
    };
    let (modes, targets) = blocks_band(rt, None, band)?;
    if targets != 1 {
        return Err(format!(
            "{targets} targets after the first count, expected 1"
        ));
    }
    Ok(modes)
}

/// Ten blocks [[k, 4k], [k / 100, k]] (k at 50 + 12.5 b Hz), as a slipping point's
/// coupling makes them: real eigenvalues k (1 +/- 0.2), all in a 706.25 Hz band, while the
/// symmetric part [[k, 2.005 k], [2.005 k, k]] has 3.005 k (below the top) and -1.005 k.
/// The guess counts the symmetric part from 0 to the top: 10 (its 10 negative eigenvalues
/// left out), and the CEA, short-guessed, still finds all 20 modes.
fn count_without_negatives(rt: &Runtime) -> Result<Vec<f64>, String> {
    let comm = rt.world();
    let blocks = 10;
    let mut entries = Vec::new();
    for b in 0..blocks {
        let (i, j) = (2 * b, 2 * b + 1);
        entries.extend([
            (i, i, kk(b)),
            (i, j, 4.0 * kk(b)),
            (j, i, 0.01 * kk(b)),
            (j, j, kk(b)),
        ]);
    }
    let (k, m) = over_identity(comm, 2 * blocks, &entries)?;
    let f_max = 706.25;
    let guess = band_count::guess(comm, &k, &m, f_max).map_err(e)?;
    if guess != Some(blocks) {
        return Err(format!("guess {guess:?}, expected Some({blocks})"));
    }
    let options = CeaOptions {
        max_frequency_hz: f_max,
        modes_per_target: 12,
        tolerance: 1e-12,
        count_first: true,
        ..Default::default()
    };
    let result = cea::undamped(comm, &k, &m, &options).map_err(e)?;
    let mut exact: Vec<f64> = (0..blocks)
        .flat_map(|b| [0.8 * kk(b), 1.2 * kk(b)])
        .collect();
    exact.sort_by(f64::total_cmp);
    let mut found: Vec<f64> = result
        .modes
        .iter()
        .map(|m| (2.0 * PI * m.frequency_hz).powi(2))
        .collect();
    found.sort_by(f64::total_cmp);
    if found.len() != exact.len() {
        return Err(format!(
            "{} modes found, {} expected",
            found.len(),
            exact.len()
        ));
    }
    for (f, x) in found.iter().zip(&exact) {
        if (f - x).abs() > 1e-9 * x {
            return Err(format!("omega^2 {f} where {x} was expected"));
        }
    }
    Ok(found)
}

/// With the band's top on block 52's double eigenvalue of the symmetric part, K_s - top M is
/// singular and its LDL^T fails: the CEA goes on without a count, stepping as without one.
fn uncounted_targets(rt: &Runtime) -> Result<Vec<f64>, String> {
    let band = Band {
        count_first: true,
        ..Band::AT_BLOCK_52
    };
    let (k, m) = blocks_pencil(rt.world())?;
    let top = (2.0 * PI * band.max_frequency_hz).powi(2);
    match band_count::symmetric_part_below(rt.world(), &k, &m, top) {
        Err(PetscError::NotConverged { .. }) => {}
        other => {
            return Err(format!(
                "the count on a singular K_s - top M gave {other:?}"
            ))
        }
    }
    let (modes, targets) = blocks_band(rt, None, band)?;
    if targets < 3 {
        return Err(format!(
            "{targets} targets: a count was made on a singular K_s - top M"
        ));
    }
    Ok(modes)
}

/// Eigenvalues of the 80-block problem with frequency at most 700 Hz: both of blocks 0..=51
/// (block b at 50 + 12.5 b Hz); block 52's pair, k (1 +/- 0.01 i) at 700 Hz, has its
/// frequency raised by Re sqrt(1 +/- 0.01 i) - 1 = 1.25e-5 and falls just outside.
const BAND_MODES: usize = 104;

/// The band asked of [`blocks_band`] and how many modes it holds.
#[derive(Clone, Copy)]
struct Band {
    max_frequency_hz: f64,
    modes: usize,
    count_first: bool,
}

impl Band {
    const AT_BLOCK_52: Band = Band {
        max_frequency_hz: 700.0,
        modes: BAND_MODES,
        count_first: false,
    };
}

/// The 80 blocks [[k_b, c_b], [-c_b, k_b]] (k_b at 50 + 12.5 b Hz, c_b = 0.01 k_b on two
/// blocks in three) over M = I.
const BLOCKS: usize = 80;

fn kk(b: usize) -> f64 {
    (2.0 * PI * (50.0 + 12.5 * b as f64)).powi(2)
}

fn cc(b: usize) -> f64 {
    if b.is_multiple_of(3) {
        0.0
    } else {
        0.01 * kk(b)
    }
}

fn blocks_pencil(comm: squeal::petsc::Comm<'_>) -> Result<(Matrix<'_>, Matrix<'_>), String> {
    let mut entries = Vec::new();
    for b in 0..BLOCKS {
        let (i, j) = (2 * b, 2 * b + 1);
        entries.extend([(i, i, kk(b)), (i, j, cc(b)), (j, i, -cc(b)), (j, j, kk(b))]);
    }
    over_identity(comm, 2 * BLOCKS, &entries)
}

/// K of size n from its entries, over M = I.
fn over_identity<'rt>(
    comm: squeal::petsc::Comm<'rt>,
    n: usize,
    entries: &[(usize, usize, f64)],
) -> Result<(Matrix<'rt>, Matrix<'rt>), String> {
    let k = matrix_from_entries(comm, n, entries).map_err(e)?;
    let identity: Vec<_> = (0..n).map(|i| (i, i, 1.0)).collect();
    let m = matrix_from_entries(comm, n, &identity).map_err(e)?;
    Ok((k, m))
}

fn blocks_band(
    rt: &Runtime,
    expected: Option<usize>,
    band: Band,
) -> Result<(Vec<f64>, usize), String> {
    let comm = rt.world();
    let blocks = BLOCKS;
    let (k, m) = blocks_pencil(comm)?;
    let f_max = band.max_frequency_hz;
    let options = CeaOptions {
        max_frequency_hz: f_max,
        modes_per_target: 12,
        tolerance: 1e-12,
        expected_modes: expected,
        count_first: band.count_first,
        ..Default::default()
    };
    let result = cea::undamped(comm, &k, &m, &options).map_err(e)?;
    let mut exact: Vec<Complex64> = (0..blocks)
        .flat_map(|b| {
            [
                cea::lambda_of(Complex64::new(kk(b), cc(b))),
                cea::lambda_of(Complex64::new(kk(b), -cc(b))),
            ]
        })
        .filter(|l| l.im / (2.0 * PI) <= f_max)
        .collect();
    exact.sort_by(|a, b| a.im.total_cmp(&b.im).then(a.re.total_cmp(&b.re)));
    if result.modes.len() != exact.len() {
        return Err(format!(
            "{} modes found, {} in the band ({} targets)",
            result.modes.len(),
            exact.len(),
            result.targets.len()
        ));
    }
    // Each exact eigenvalue matched by exactly as many found ones as its multiplicity.
    for x in &exact {
        let want = exact
            .iter()
            .filter(|y| (*y - x).norm() < 1e-9 * x.norm())
            .count();
        let got = result
            .modes
            .iter()
            .filter(|m| (m.lambda - x).norm() < 1e-9 * x.norm())
            .count();
        if want != got {
            return Err(format!("lambda {x}: found {got} times, expected {want}"));
        }
    }
    if exact.len() != band.modes {
        return Err(format!(
            "{} modes in the band, not {}",
            exact.len(),
            band.modes
        ));
    }
    Ok((
        result
            .modes
            .iter()
            .flat_map(|m| [m.lambda.re, m.lambda.im])
            .collect(),
        result.targets.len(),
    ))
}

/// A CEA window by block Krylov-Schur ([`squeal::analysis::cea_window`]) on a pencil of
/// known eigenvalues ([`common::pencils::super_element_pencil`], size 600: 300 eigenvalues
/// a side of the real axis, two in three in conjugate pairs, the rest double real ones),
/// about a target amid them: its pairs must be the closed form's eigenvalues nearest the
/// target, each to 1e-8 of its modulus (the window's 1e-12 on the transformed problem over
/// K's condition), the 30 asked for and whatever converged with them without a gap, with
/// relative residuals below 1e-8; and the transposed operator on the same factorisation must
/// give, for the 10 nearest, left vectors y with y^H K = omega^2 y^H M to a backward error of
/// 1e-10. The window must have been the block solver's (the pencil is larger than its space).
fn block_window(rt: &Runtime) -> Result<Vec<f64>, String> {
    use squeal::analysis::cea_window::{Window, WindowRequest, WindowSolver};
    let comm = rt.world();
    let n = 600;
    let (k, m, omega2) = common::pencils::super_element_pencil(n);
    let entries = |a: &faer::Mat<f64>| -> Vec<(usize, usize, f64)> {
        (0..n)
            .flat_map(|i| (0..n).map(move |j| (i, j)))
            .map(|(i, j)| (i, j, a[(i, j)]))
            .collect()
    };
    let (k, m) = (
        matrix_from_entries(comm, n, &entries(&k)).map_err(e)?,
        matrix_from_entries(comm, n, &entries(&m)).map_err(e)?,
    );
    let target = (2.0 * PI * 100_000.0f64).powi(2);
    let count = 30;
    let linear = squeal::petsc::LinearMethod::default();
    let request = WindowRequest {
        target,
        count,
        subspace: 2 * count,
        tolerance: 1e-12,
        linear: &linear,
        solver: WindowSolver::Block,
    };
    let window = Window::solve(comm, &k, &m, request).map_err(e)?;
    if !matches!(window, Window::Block(_)) {
        return Err("the window was not the block solver's".into());
    }
    let found = window.converged().map_err(e)?;
    if found < count {
        return Err(format!("{found} of {count} pairs"));
    }
    let mut exact = omega2.clone();
    exact.sort_by(|a, b| (a - target).norm().total_cmp(&(b - target).norm()));
    let mut values = Vec::with_capacity(found);
    // A window that keeps none of its pairs (the band's top past its last ones) asks for
    // no residual: none, and no product with no column (which once divided by zero inside
    // PETSc's blocked fetch).
    if !window
        .relative_errors(comm, (&k, &m), &[])
        .map_err(e)?
        .is_empty()
    {
        return Err("residuals of no pair".into());
    }
    let all: Vec<usize> = (0..found).collect();
    let residuals = window.relative_errors(comm, (&k, &m), &all).map_err(e)?;
    for (i, residual) in residuals.into_iter().enumerate() {
        let value = window.value(i).map_err(e)?;
        if residual > 1e-8 {
            return Err(format!("omega^2 {value}: relative residual {residual:e}"));
        }
        values.push(value);
    }
    // The found ones are the `found` nearest, each as often as the closed form has it (the
    // farthest found may tie with the next exact one across a conjugate pair: the solver
    // keeps pairs whole).
    let nearest = &exact[..found];
    for x in nearest {
        let want = nearest
            .iter()
            .filter(|y| (*y - x).norm() <= 1e-8 * x.norm())
            .count();
        let got = values
            .iter()
            .filter(|v| (*v - x).norm() <= 1e-8 * x.norm())
            .count();
        if want != got {
            return Err(format!(
                "omega^2 {x} (|omega^2 - target| {:e}): found {got} times, expected {want}",
                (x - target).norm()
            ));
        }
    }
    // A target next to an eigenvalue (1e-7 of it off a double real one): the operator's
    // eigenvalues then span seven orders, S V's columns are all mostly that eigenvector
    // (the block Cholesky QR breaks down; the columns go one at a time), and the pairs
    // farthest in the window are only as good as the small eigenproblems' eigenvectors
    // (faer's had backward errors of 1e-4 of the smallest theta there, and residuals of
    // 1e-5). K - sigma M's condition is then ~1e7 times its own, and its solves' errors
    // with it: the bound is the CEA's own acceptance (`cea::residual_bound`, 1e-6;
    // measured 1.5e-8 to 2.4e-8 at worst, and so SLEPc's Krylov-Schur on the same window,
    // 1.5e-8 to 2.4e-8, on 1 and 2 ranks).
    let near = omega2
        .iter()
        .filter(|w| w.im == 0.0)
        .min_by(|a, b| (a.re - target).abs().total_cmp(&(b.re - target).abs()))
        .expect("real eigenvalues")
        .re;
    let close = WindowRequest {
        target: near * (1.0 + 1e-7),
        ..request
    };
    let window_close = Window::solve(comm, &k, &m, close).map_err(e)?;
    if !matches!(window_close, Window::Block(_)) {
        return Err("the window by an eigenvalue was not the block solver's".into());
    }
    let n_close = window_close.converged().map_err(e)?;
    let all: Vec<usize> = (0..n_close).collect();
    for (i, r) in window_close
        .relative_errors(comm, (&k, &m), &all)
        .map_err(e)?
        .into_iter()
        .enumerate()
    {
        if r > 1e-6 {
            return Err(format!(
                "by an eigenvalue: omega^2 {}: relative residual {r:e}",
                window_close.value(i).map_err(e)?
            ));
        }
    }
    let left_count = 10;
    let left = window
        .left(comm, &m, target, (left_count, 2 * left_count, 1e-12))
        .map_err(e)?;
    if left.converged() < left_count {
        return Err(format!("{} of {left_count} left pairs", left.converged()));
    }
    let (template, _) = k.vectors().map_err(e)?;
    let mut left_values = Vec::new();
    for i in 0..left.converged() {
        let s = left.value(i).map_err(e)?;
        if !exact[..found]
            .iter()
            .any(|x| (x - s).norm() <= 1e-8 * x.norm())
        {
            return Err(format!("left omega^2 {s} is none of the window's"));
        }
        let (yr, yi) = left.left_vector(i, &template).map_err(e)?;
        // z = conj(y): K^T z = s M z, i.e. (K^T zr - Re(s) M zr + Im(s) M zi) + i (...) = 0.
        let (zr, mut zi) = (yr.copy().map_err(e)?, yi.copy().map_err(e)?);
        zi.scale(-1.0).map_err(e)?;
        let (mut kr, mut ki) = (zr.duplicate().map_err(e)?, zr.duplicate().map_err(e)?);
        let (mut mr, mut mi) = (zr.duplicate().map_err(e)?, zr.duplicate().map_err(e)?);
        k.mult_transpose(&zr, &mut kr).map_err(e)?;
        k.mult_transpose(&zi, &mut ki).map_err(e)?;
        m.mult(&zr, &mut mr).map_err(e)?;
        m.mult(&zi, &mut mi).map_err(e)?;
        let mut rr = kr.copy().map_err(e)?;
        rr.axpy(-s.re, &mr).map_err(e)?;
        rr.axpy(s.im, &mi).map_err(e)?;
        let mut ri = ki.copy().map_err(e)?;
        ri.axpy(-s.re, &mi).map_err(e)?;
        ri.axpy(-s.im, &mr).map_err(e)?;
        let norm = |a: &squeal::petsc::Vector, b: &squeal::petsc::Vector| {
            Ok::<f64, squeal::petsc::PetscError>((a.norm2()?.powi(2) + b.norm2()?.powi(2)).sqrt())
        };
        let backward = norm(&rr, &ri).map_err(e)?
            / (norm(&kr, &ki).map_err(e)? + s.norm() * norm(&mr, &mi).map_err(e)?);
        if backward > 1e-10 {
            return Err(format!("left vector of {s}: backward error {backward:e}"));
        }
        left_values.push(s);
    }
    // Compared between rank counts in one order, whatever order each found them in.
    let sorted = |mut v: Vec<Complex64>| {
        v.sort_by(|a, b| a.re.total_cmp(&b.re).then(a.im.total_cmp(&b.im)));
        v
    };
    Ok(sorted(values)
        .into_iter()
        .chain(sorted(left_values))
        .flat_map(|v| [v.re, v.im])
        .collect())
}

/// The 2-DOF model with damping C = c I: each omega^2 gives lambda^2 + c lambda + omega^2 = 0,
/// lambda = (-c +/- sqrt(c^2 - 4 omega^2)) / 2, and the instability starts where
/// Re sqrt(c^2/4 - omega^2) = c/2, i.e. at D = 1 + 2 c^2 instead of 1.
fn damped_threshold(rt: &Runtime) -> Result<Vec<f64>, String> {
    let comm = rt.world();
    let c = 0.1;
    let d_critical = 1.0 + 2.0 * c * c;
    let mut out = Vec::new();
    for d in [d_critical - 0.005, d_critical + 0.005, 1.5] {
        let k = matrix_from_entries(
            comm,
            2,
            &[(0, 0, 2.0), (0, 1, 1.0 - d), (1, 0, 1.0), (1, 1, 2.0)],
        )
        .map_err(e)?;
        let m = matrix_from_entries(comm, 2, &[(0, 0, 1.0), (1, 1, 1.0)]).map_err(e)?;
        let cm = matrix_from_entries(comm, 2, &[(0, 0, c), (1, 1, c)]).map_err(e)?;
        let options = CeaOptions {
            max_frequency_hz: 1.0,
            tolerance: 1e-13,
            ..Default::default()
        };
        let result = cea::damped(comm, &k, &cm, &m, 2, &options).map_err(e)?;
        let disc = Complex64::new(1.0 - d, 0.0).sqrt();
        let exact: Vec<Complex64> = [2.0 + disc, 2.0 - disc]
            .iter()
            .map(|&w2| {
                let s = (Complex64::new(c * c, 0.0) - 4.0 * w2).sqrt();
                let a = (-c + s) / 2.0;
                let b = (-c - s) / 2.0;
                if a.im >= 0.0 {
                    a
                } else {
                    b
                }
            })
            .collect();
        if result.modes.len() != 2 {
            return Err(format!(
                "D = {d}: {} modes: {:?}",
                result.modes.len(),
                result.modes
            ));
        }
        for m in &result.modes {
            if !exact
                .iter()
                .any(|x| (x - m.lambda).norm() < 1e-10 * x.norm())
            {
                return Err(format!("D = {d}: lambda {} not in {exact:?}", m.lambda));
            }
            out.extend([m.lambda.re, m.lambda.im]);
        }
        let unstable = result.modes.iter().filter(|m| m.unstable).count();
        if unstable != usize::from(d > d_critical) {
            return Err(format!(
                "D = {d} (threshold {d_critical}): {unstable} unstable: {:?}",
                result.modes
            ));
        }
    }
    Ok(out)
}

/// A dense pencil with known eigenvalues and a super-element's spectrum
/// ([`common::pencils::super_element_pencil`], size 500, above [`WINDOWS_FROM`]; 18 of its
/// modes below 10 kHz, 6 unstable). The dense CEA's windows (PETSc's dense LU under the full
/// model's shift-and-invert windows, on this rank alone) must find every eigenvalue of the
/// band once, to 1e-9 of its modulus (the windows' tolerance over a well-conditioned basis),
/// with the same classification as faer's every-eigenvalue path, and eigenvectors to a
/// backward error of 1e-10 (faer's: 1e-15).
fn dense_windows(rt: &Runtime) -> Result<Vec<f64>, String> {
    use squeal::reduce::dense_cea::{
        dense_cea, dense_cea_by, DenseCeaOptions, DenseEigensolver, WINDOWS_FROM,
    };
    let n = 500;
    if n < WINDOWS_FROM {
        return Err(format!("size {n} is below the windows' {WINDOWS_FROM}"));
    }
    let (k, m, omega2) = common::pencils::super_element_pencil(n);
    let f_max = 10_000.0;
    let options = DenseCeaOptions {
        max_frequency_hz: f_max,
        ..Default::default()
    };
    let solver = DenseEigensolver::Windows {
        solo: rt.self_comm(),
        shared: rt.self_comm(),
    };
    let windows = dense_cea_by(solver, k.as_ref(), m.as_ref(), &options).map_err(e)?;
    let every = dense_cea(k.as_ref(), m.as_ref(), &options).map_err(e)?;
    let exact: Vec<Complex64> = omega2
        .iter()
        .map(|&w2| cea::lambda_of(w2))
        .filter(|l| l.im / (2.0 * PI) <= f_max)
        .collect();
    for (name, found) in [("windows", &windows), ("every", &every)] {
        if found.modes.len() != exact.len() {
            return Err(format!(
                "{name}: {} modes, {} in the band",
                found.modes.len(),
                exact.len()
            ));
        }
        for x in &exact {
            let near = |l: Complex64| (l - x).norm() < 1e-9 * x.norm();
            let want = exact.iter().filter(|y| near(**y)).count();
            let got = found.modes.iter().filter(|m| near(m.lambda)).count();
            if want != got {
                return Err(format!(
                    "{name}: lambda {x} found {got} times, expected {want}"
                ));
            }
        }
    }
    // Both sorted by frequency: mode by mode, the same eigenvalue and the same flags.
    for (w, v) in windows.modes.iter().zip(&every.modes) {
        if (w.lambda - v.lambda).norm() > 1e-9 * v.lambda.norm()
            || w.unstable != v.unstable
            || w.rigid_body != v.rigid_body
        {
            return Err(format!("windows {w:?} against every {v:?}"));
        }
        if w.residual > 1e-10 {
            return Err(format!("windows' backward error {:e} at {w:?}", w.residual));
        }
    }
    let unstable = windows.modes.iter().filter(|m| m.unstable).count();
    if unstable == 0 || unstable == windows.modes.len() {
        return Err(format!(
            "{unstable} unstable of {}: the band should hold both",
            windows.modes.len()
        ));
    }
    let worst = windows.modes.iter().map(|m| m.residual).fold(0.0, f64::max);
    if rt.world().rank() == 0 {
        eprintln!(
            "dense windows: {} modes below {f_max} Hz ({unstable} unstable) as every eigenvalue \
             and the closed form; largest backward error {worst:.1e}",
            windows.modes.len()
        );
    }
    // Shapes normalised as faer's are: largest component 1 + 0i.
    for shape in &windows.shapes {
        let big = shape.iter().map(|z| z.norm()).fold(0.0, f64::max);
        if (big - 1.0).abs() > 1e-14 || shape.len() != n {
            return Err(format!("a shape of {} entries, largest {big}", shape.len()));
        }
    }
    // The band split between the ranks (no rigid body to decide: each rank its share's
    // windows, every share's modes on every rank): the windows' modes again, to the same
    // 1e-9 of their modulus (each found by another shift), the same flags, backward errors
    // to 1e-10, and the same bits on every rank. What is returned is this result, so the 1
    // and 2 rank runs (one share and two) are held to each other as well.
    let held = DenseCeaOptions {
        expected_rigid_modes: Some(0),
        ..options
    };
    let solver = DenseEigensolver::Windows {
        solo: rt.self_comm(),
        shared: rt.world(),
    };
    let split = dense_cea_by(solver, k.as_ref(), m.as_ref(), &held).map_err(e)?;
    if split.modes.len() != windows.modes.len() || split.shapes.len() != split.modes.len() {
        return Err(format!(
            "split between {} ranks: {} modes, {} shapes; one rank's windows {}",
            rt.world().size(),
            split.modes.len(),
            split.shapes.len(),
            windows.modes.len()
        ));
    }
    for (s, w) in split.modes.iter().zip(&windows.modes) {
        if (s.lambda - w.lambda).norm() > 1e-9 * w.lambda.norm()
            || s.unstable != w.unstable
            || s.rigid_body
            || s.residual > 1e-10
        {
            return Err(format!("split {s:?} against one rank's {w:?}"));
        }
    }
    // A band below every mode (the lowest is 300 Hz) is an error split or not, as one
    // rank's windows say it: no part's empty answer stands for the band's.
    let below = DenseCeaOptions {
        max_frequency_hz: 100.0,
        ..held
    };
    let solver = DenseEigensolver::Windows {
        solo: rt.self_comm(),
        shared: rt.world(),
    };
    match dense_cea_by(solver, k.as_ref(), m.as_ref(), &below) {
        Err(err) if err.to_string().contains("no mode in the band") => {}
        Err(err) => return Err(format!("a band below every mode: {err}")),
        Ok(r) => {
            return Err(format!(
                "a band below every mode gave {} modes",
                r.modes.len()
            ))
        }
    }
    let bits: Vec<f64> = split
        .modes
        .iter()
        .flat_map(|m| [m.lambda.re, m.lambda.im, m.residual])
        .chain(split.shapes.iter().flatten().flat_map(|z| [z.re, z.im]))
        .collect();
    let (mut most, mut least) = (bits.clone(), bits.iter().map(|v| -v).collect::<Vec<_>>());
    rt.world().max_in_place(&mut most);
    rt.world().max_in_place(&mut least);
    if most != bits || least.iter().zip(&bits).any(|(l, b)| -l != *b) {
        return Err("the split's modes differ between the ranks".into());
    }
    Ok(split
        .modes
        .iter()
        .flat_map(|m| [m.lambda.re, m.lambda.im])
        .collect())
}

/// The dense pencil with eigenvalues put exactly on the edges between the ranks' parts of the
/// band (omega^2 = top / 2 for 2 ranks, top / 3 and 2 top / 3 for 3): on each edge a double
/// real eigenvalue and a coupled pair whose real part is the edge. Each rank finds what lies
/// on its edges by another shift, with its own round-off, so each copy may fall on either
/// side: every eigenvalue of the band must still be found exactly as often as the closed form
/// has it, on any number of ranks (one rank steps its own windows over the same values).
fn eigenvalues_on_the_edges(rt: &Runtime) -> Result<Vec<f64>, String> {
    use squeal::reduce::dense_cea::{dense_cea_by, DenseCeaOptions, DenseEigensolver};
    let f_max = 10_000.0;
    let top = (2.0 * PI * f_max).powi(2);
    // Blocks 100.. lie far above the band; b % 3 == 2 is a double real one, else a pair.
    let placed = [
        (100, top / 2.0),
        (101, top / 2.0),
        (102, top / 3.0),
        (104, top / 3.0),
        (103, 2.0 * top / 3.0),
        (107, 2.0 * top / 3.0),
    ];
    let (k, m, omega2) = common::pencils::super_element_pencil_with(500, &placed);
    let exact: Vec<Complex64> = omega2
        .iter()
        .map(|&w2| cea::lambda_of(w2))
        .filter(|l| l.im / (2.0 * PI) <= f_max)
        .collect();
    let options = DenseCeaOptions {
        max_frequency_hz: f_max,
        expected_rigid_modes: Some(0),
        ..Default::default()
    };
    let solver = DenseEigensolver::Windows {
        solo: rt.self_comm(),
        shared: rt.world(),
    };
    let found = dense_cea_by(solver, k.as_ref(), m.as_ref(), &options).map_err(e)?;
    let near = |a: Complex64, b: Complex64| (a - b).norm() < 1e-9 * b.norm();
    for x in &exact {
        let want = exact.iter().filter(|y| near(**y, *x)).count();
        let got = found.modes.iter().filter(|m| near(m.lambda, *x)).count();
        if want != got {
            return Err(format!(
                "{} ranks: lambda {x} (omega^2 {:.6e}) found {got} times, expected {want}",
                rt.world().size(),
                -(x * x).re
            ));
        }
    }
    if found.modes.len() != exact.len() || found.shapes.len() != exact.len() {
        return Err(format!(
            "{} ranks: {} modes and {} shapes, {} in the band",
            rt.world().size(),
            found.modes.len(),
            found.shapes.len(),
            exact.len()
        ));
    }
    if let Some(bad) = found.modes.iter().find(|m| m.residual > 1e-10) {
        return Err(format!("backward error {:e} at {bad:?}", bad.residual));
    }
    if rt.world().rank() == 0 {
        eprintln!(
            "{} ranks: {} modes, the 12 on the parts' edges each as often as the closed form",
            rt.world().size(),
            found.modes.len()
        );
    }
    Ok(found
        .modes
        .iter()
        .flat_map(|m| [m.lambda.re, m.lambda.im])
        .collect())
}
