//! The dense complex eigenvalue analysis of a reduced model (the super-element assembly's
//! linearisation, [`super::assembly::Assembly::cea`]): every mode of the band of a dense
//! unsymmetric stiffness against a dense symmetric positive definite mass, classified as the
//! sparse CEA classifies its own.
//!
//! Two ways to the same modes ([`DenseEigensolver`]): faer's every eigenvalue and eigenvector
//! of the whole problem (about 25 n^3 flops whatever the band holds), or the full model's
//! shift-and-invert windows over the band alone on PETSc dense copies (LAPACK LU, then
//! Krylov-Schur's solves of n^2 each). A super-element's band holds a few per cent of its
//! modes (small-caliper, every pair on the boundary: 56 of 1,801 below 10 kHz), so the
//! windows pay from a few hundred on: `examples/dense_cea_bench.rs`, medians of three,
//! interleaved, on pencils of that spectrum: size 400 0.057 s every / 0.009 s windows, 800
//! 0.252 / 0.040, 1,200 0.602 / 0.253, 1,800 1.61 / 1.20. In small-caliper's nine-value
//! sweep the dense CEA went from 1.9-2.1 s to 1.0-1.3 s a point. The windows are shared
//! between the ranks ([`band_share`]): on 2 ranks, small-caliper's super-element of size
//! 1,801 (every pair reduced, single), nine values, interleaved runs: the dense CEA's
//! median 1.2 -> 0.8 s a point, the point's 2.2 -> 1.8 s. Its lower half holds 44 of the 56
//! modes (3 windows against 1-2), but parts of equal mode counts (from the previous point's
//! modes) were slower (0.8-1.1 -> 1.0-1.1 s a point, tried 2026-12-02): a window's reach in
//! omega^2 grows with its target, so the upper part's fewer modes took more windows. Wider
//! windows did better ([`window_pairs`]): 60 pairs on that super-element, two interleaved
//! pairs of nine-value sweeps, the dense CEA's median 0.94 / 0.81 -> 0.56 / 0.55 s a point,
//! the point's 2.26 / 2.19 -> 1.98 / 1.95 s, the sweeps 55.6 / 52.7 -> 50.6 / 49.4 s.

use super::assembly::AssemblyError;
use crate::analysis::cea::{
    self, by_frequency, lambda_of, mode_from_lambda, CeaOptions, ComplexMode,
};
use crate::analysis::rigid;
use crate::petsc::{Comm, DirectPackage, Factorization, LinearMethod, Matrix, PetscError};
use faer::{Mat, MatRef, Side};
use num_complex::Complex64;
use std::f64::consts::PI;

/// Settings of the dense CEA.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DenseCeaOptions {
    /// Modes from 0 Hz up to this frequency.
    pub max_frequency_hz: f64,
    /// As [`CeaOptions::unstable_threshold`] (the same default).
    pub unstable_threshold: f64,
    /// As [`CeaOptions::expected_rigid_modes`]: `Some(0)` after a static solve, which
    /// converges only on a regular Jacobian, so no body is free.
    pub expected_rigid_modes: Option<usize>,
}

impl Default for DenseCeaOptions {
    fn default() -> Self {
        let sparse = CeaOptions::default();
        DenseCeaOptions {
            max_frequency_hz: sparse.max_frequency_hz,
            unstable_threshold: sparse.unstable_threshold,
            expected_rigid_modes: sparse.expected_rigid_modes,
        }
    }
}

/// The modes of the band and their shapes in q, sorted by [`by_frequency`].
#[derive(Clone, Debug)]
pub struct DenseCeaResult {
    pub modes: Vec<ComplexMode>,
    /// One per mode, in q (expand with u = T q), the largest component scaled to 1 + 0i.
    pub shapes: Vec<Vec<Complex64>>,
}

/// The size from which [`DenseEigensolver::choose`] takes the windows. Below it either way
/// takes a few hundredths of a second (the module doc), and faer's, which needs no PETSc and
/// steps through no windows, is kept.
pub const WINDOWS_FROM: usize = 400;

/// The windows' SLEPc tolerance. A converged pair's relative error |K x - lambda M x| /
/// |lambda x| is bounded by tol |K - sigma M| / |lambda| (the test is on the inverted
/// problem), and a reduced model's |K| is that of its stiffest boundary coordinates (its
/// spectrum reaches hundreds of kHz). Two more orders than the sparse CEA's cost no
/// measurable time on these sizes. The band's first window is always at 0 Hz (no count
/// from the previous point, which would put one window at 0.6 of the band's top): on
/// small-caliper's super-element that window left the 447 Hz mode at 1.7e-6 and 2.4e-6
/// with 1e-10 and up to 4.1e-7 with 1e-12, against the CEA's bound of 1e-6; from 0 Hz every
/// point's worst was 4e-12 to 2.6e-11 (backward errors 2e-15 to 2e-14), for 1.0-1.3 s
/// instead of 0.8 s a point.
pub const WINDOWS_TOLERANCE: f64 = 1e-12;

/// The pairs a dense window asks for on size `n`: [`WIDE_WINDOW`] from [`WIDE_WINDOWS_FROM`]
/// on, the sparse CEA's 30 below. A window costs one LU (2/3 n^3) and a Krylov-Schur solve
/// of n^2 a step, so the larger the pencil, the more pairs pay for one factorisation.
pub fn window_pairs(n: usize) -> usize {
    if n >= WIDE_WINDOWS_FROM {
        WIDE_WINDOW
    } else {
        CeaOptions::default().modes_per_target
    }
}

/// See [`window_pairs`]. small-caliper's single super-element (size 1,801, every pair
/// reduced, 52 per pad, nine values, 2 ranks): the dense CEA's median 0.86 s a point with 30
/// pairs (22 windows on rank 0 over the sweep), 0.60 s with 60 (9: one a point), 0.9 s with
/// 90; the same 503 eigenvalues to 3.3e-11 in frequency, the same flags, backward errors
/// 2e-15 at worst against 2e-14. `examples/dense_cea_bench.rs` (one rank, the spectrum of
/// `tests/common/pencils.rs`, two runs each, interleaved): at size 400, 0.055 s against 0.027
/// with 30; at 800 0.121 / 0.145, 1,200 0.27 / 0.36, 1,800 1.16 / 1.55.
pub const WIDE_WINDOW: usize = 60;

/// The size from which the dense windows ask for [`WIDE_WINDOW`] pairs (see there).
pub const WIDE_WINDOWS_FROM: usize = 800;

/// How the dense CEA finds its eigenvalues.
#[derive(Clone, Copy)]
pub enum DenseEigensolver<'rt> {
    /// faer: every eigenvalue and eigenvector of the whole problem (about 25 n^3 flops).
    Every,
    /// The full model's CEA ([`crate::analysis::cea::undamped`]) on PETSc dense copies of
    /// K and M: shift-and-invert windows over the band only, each one LAPACK LU (2/3 n^3)
    /// and Krylov-Schur's solves (n^2 each). Each rank of `shared` takes its share of the
    /// band ([`band_share`]) on `solo`, a communicator of that rank alone, and every rank
    /// gets every share's modes: on 2 ranks each runs about half the windows, where rank 1
    /// used to wait for rank 0's. Every rank of `shared` calls it with the same K and M.
    Windows { solo: Comm<'rt>, shared: Comm<'rt> },
}

impl<'rt> DenseEigensolver<'rt> {
    /// [`Self::Windows`] over the ranks of `shared` from [`WINDOWS_FROM`] on, [`Self::Every`]
    /// below.
    pub fn choose(size: usize, shared: Comm<'rt>) -> Self {
        if size >= WINDOWS_FROM {
            DenseEigensolver::Windows {
                solo: shared.alone(),
                shared,
            }
        } else {
            DenseEigensolver::Every
        }
    }
}

/// Rank `rank`'s share of the band [0, top] in Re omega^2 among `ranks`: equal parts, the
/// first open below (divergence modes, Re omega^2 < 0, are the first rank's) and the last
/// open above (the band's top is decided by frequency, as for one rank). Each window costs
/// one LU whatever it holds, so what balances the ranks is the windows' count: on
/// small-caliper's super-element (56 modes, 4 windows on one rank) the lower half of
/// omega^2 holds 44 modes and takes 3 windows, the upper 1-2 (the module doc). A mode on an
/// edge between two parts is found by both (each keeps [`cea::EDGE_OVERLAP`] past its
/// edges) and kept once, the lower rank's (`gathered`); the higher part's first window
/// does not sit on such a mode (`cea::undamped` moves a target off an eigenvalue).
pub fn band_share(rank: usize, ranks: usize, top: f64) -> (f64, f64) {
    let at = |k: usize| top * k as f64 / ranks as f64;
    let from = if rank == 0 {
        f64::NEG_INFINITY
    } else {
        at(rank)
    };
    let to = if rank + 1 >= ranks {
        f64::INFINITY
    } else {
        at(rank + 1)
    };
    (from, to)
}

/// The dense CEA by `solver`: [`dense_cea`] or its windows (the same modes: the windows
/// find every eigenvalue of the band to the CEA's tolerance, and the result is classified,
/// normalised and its residuals measured exactly as [`dense_cea`] does). With windows over
/// several ranks, collective: a failure on one rank is every rank's.
pub fn dense_cea_by(
    solver: DenseEigensolver<'_>,
    stiffness: MatRef<'_, f64>,
    mass: MatRef<'_, f64>,
    options: &DenseCeaOptions,
) -> Result<DenseCeaResult, AssemblyError> {
    let DenseEigensolver::Windows { solo, shared } = solver else {
        return dense_cea(stiffness, mass, options);
    };
    check_input(stiffness, mass, options)?;
    // Rigid-body flags are decided over the whole band's magnitudes; after a static
    // (no free body) none is rigid, and the band splits with nothing to decide.
    let ranks = if options.expected_rigid_modes == Some(0) {
        shared.size()
    } else {
        1
    };
    let rank = shared.rank();
    let top = (2.0 * PI * options.max_frequency_hz).powi(2);
    let local = (rank < ranks).then(|| {
        let strip = (ranks > 1).then(|| band_share(rank, ranks, top));
        windows(solo, stiffness, mass, options, strip)
    });
    if shared.size() == 1 {
        return local.unwrap_or_else(|| unreachable!("rank 0 of one always has a share"));
    }
    let failed = local
        .as_ref()
        .and_then(|r| r.as_ref().err().map(|e| e.to_string()));
    if let Some((at, message)) = shared.first_message(failed) {
        return Err(match local {
            Some(Err(own)) if at == rank => own,
            _ => AssemblyError::Eigen(format!("the dense CEA's windows on rank {at}: {message}")),
        });
    }
    let mine = match local {
        Some(Ok(r)) => r,
        _ => DenseCeaResult {
            modes: Vec::new(),
            shapes: Vec::new(),
        },
    };
    let n = stiffness.nrows();
    // Rank r's part starts where rank r - 1's ends; each keeps a little past its edges.
    let edges: Vec<f64> = (1..ranks).map(|r| band_share(r, ranks, top).0).collect();
    let all = gathered(shared, mine, n, options.unstable_threshold, &edges);
    // A part may hold none; the band as a whole is held to what one rank's windows say of
    // it (every rank has the same count here, so every rank says it).
    if all.modes.is_empty() {
        return Err(AssemblyError::Eigen(format!(
            "the dense CEA's windows on size {n}: {}",
            cea::CeaError::EmptyBand(options.max_frequency_hz)
        )));
    }
    Ok(all)
}

/// Rank 0's modes (`Some` there, `None` elsewhere) on every rank, with the same bits.
/// Collective.
pub fn from_root(
    shared: Comm<'_>,
    on_root: Option<DenseCeaResult>,
    n: usize,
    unstable_threshold: f64,
) -> DenseCeaResult {
    let mine = on_root.unwrap_or(DenseCeaResult {
        modes: Vec::new(),
        shapes: Vec::new(),
    });
    gathered(shared, mine, n, unstable_threshold, &[])
}

/// Every rank's share of the modes on every rank, sorted by frequency. Each rank writes its
/// own slots of one buffer and the buffers are summed: a slot holds one rank's value and
/// zeros, so every rank gets the same bits. `edges[r - 1]` is where rank r's part of the
/// band starts (none when one rank found them all): a mode both sides of an edge found is
/// kept once, the lower rank's ([`cea::new_across_edge`]). Collective.
fn gathered(
    shared: Comm<'_>,
    mine: DenseCeaResult,
    n: usize,
    unstable_threshold: f64,
    edges: &[f64],
) -> DenseCeaResult {
    let mut counts = vec![0.0; shared.size()];
    counts[shared.rank()] = mine.modes.len() as f64;
    shared.sum_in_place(&mut counts);
    let counts: Vec<usize> = counts.iter().map(|&c| c as usize).collect();
    // Per mode: lambda (re, im), residual, rigid flag, then the shape's re and im parts.
    let record = 4 + 2 * n;
    let total: usize = counts.iter().sum();
    let mut buffer = vec![0.0; total * record];
    let first: usize = counts[..shared.rank()].iter().sum();
    for (k, (mode, shape)) in mine.modes.iter().zip(&mine.shapes).enumerate() {
        let slot = &mut buffer[(first + k) * record..(first + k + 1) * record];
        slot[..4].copy_from_slice(&[
            mode.lambda.re,
            mode.lambda.im,
            mode.residual,
            f64::from(u8::from(mode.rigid_body)),
        ]);
        for (i, z) in shape.iter().enumerate() {
            slot[4 + i] = z.re;
            slot[4 + n + i] = z.im;
        }
    }
    shared.sum_in_place(&mut buffer);
    // The slots are in rank order: rank r's are those from the sum of the counts before it.
    let mut keep = vec![true; total];
    let omega2 = |slot: usize| {
        let lambda = Complex64::new(buffer[slot * record], buffer[slot * record + 1]);
        -(lambda * lambda)
    };
    let mut start = 0;
    for (r, window) in counts.windows(2).enumerate() {
        let (below, above) = (
            start..start + window[0],
            start + window[0]..start + window[0] + window[1],
        );
        start += window[0];
        let Some(&edge) = edges.get(r) else { continue };
        let earlier: Vec<Complex64> = below.map(omega2).collect();
        let later: Vec<Complex64> = above.clone().map(omega2).collect();
        for (slot, new) in above.zip(cea::new_across_edge(&earlier, &later, edge)) {
            keep[slot] &= new;
        }
    }
    let mut found: Vec<(ComplexMode, Vec<Complex64>)> = buffer
        .chunks(record)
        .zip(&keep)
        .filter(|(_, &k)| k)
        .map(|(slot, _)| {
            let mode = mode_from_lambda(
                Complex64::new(slot[0], slot[1]),
                slot[2],
                unstable_threshold,
                slot[3] != 0.0,
            );
            let shape = (0..n)
                .map(|i| Complex64::new(slot[4 + i], slot[4 + n + i]))
                .collect();
            (mode, shape)
        })
        .collect();
    found.sort_by(|a, b| by_frequency(&a.0, &b.0));
    let (modes, shapes) = found.into_iter().unzip();
    DenseCeaResult { modes, shapes }
}

/// The windows' modes of the band, or of `strip` (Re omega^2 in [from, to)), on `solo`.
fn windows(
    solo: Comm<'_>,
    stiffness: MatRef<'_, f64>,
    mass: MatRef<'_, f64>,
    options: &DenseCeaOptions,
    strip: Option<(f64, f64)>,
) -> Result<DenseCeaResult, AssemblyError> {
    let n = stiffness.nrows();
    let petsc = |e: PetscError| AssemblyError::Eigen(format!("the dense CEA's windows: {e}"));
    let k = Matrix::sequential_dense(solo, stiffness).map_err(petsc)?;
    let m = Matrix::sequential_dense(solo, mass).map_err(petsc)?;
    let found = cea::undamped(
        solo,
        &k,
        &m,
        &CeaOptions {
            max_frequency_hz: options.max_frequency_hz,
            unstable_threshold: options.unstable_threshold,
            expected_rigid_modes: options.expected_rigid_modes,
            tolerance: WINDOWS_TOLERANCE,
            linear: LinearMethod::Direct {
                package: DirectPackage::Petsc,
                factorization: Factorization::Lu,
            },
            strip,
            modes_per_target: window_pairs(n),
            ..Default::default()
        },
    )
    .map_err(|e| AssemblyError::Eigen(format!("the dense CEA's windows on size {n}: {e}")))?;
    let relative = found.modes.iter().map(|m| m.residual).fold(0.0, f64::max);
    let count = found.modes.len();
    // The shapes side by side: K X and M X as two products, not 4 count products of n^2
    // each (each one reads the whole matrix: memory-bound).
    let mut xr = Mat::<f64>::zeros(n, count);
    let mut xi = Mat::<f64>::zeros(n, count);
    for (c, (re, im)) in found.shapes.iter().enumerate() {
        let (re, im) = (re.read().map_err(petsc)?, im.read().map_err(petsc)?);
        for i in 0..n {
            xr[(i, c)] = re[i];
            xi[(i, c)] = im[i];
        }
    }
    let (kr, ki) = (stiffness * &xr, stiffness * &xi);
    let (mr, mi) = (mass * &xr, mass * &xi);
    let (k_norm, m_norm) = (frobenius(stiffness), frobenius(mass));
    let mut modes = Vec::with_capacity(count);
    let mut shapes = Vec::with_capacity(count);
    for (c, mode) in found.modes.into_iter().enumerate() {
        let w2 = -(mode.lambda * mode.lambda);
        let residual = backward_error(
            (0..n).map(|i| {
                (
                    Complex64::new(xr[(i, c)], xi[(i, c)]),
                    Complex64::new(kr[(i, c)], ki[(i, c)]),
                    Complex64::new(mr[(i, c)], mi[(i, c)]),
                )
            }),
            w2,
            k_norm,
            m_norm,
        );
        let shape = largest_to_one(
            (0..n)
                .map(|i| Complex64::new(xr[(i, c)], xi[(i, c)]))
                .collect(),
        );
        modes.push(ComplexMode { residual, ..mode });
        shapes.push(shape);
    }
    let backward = modes.iter().map(|m| m.residual).fold(0.0, f64::max);
    tracing::debug!(
        "dense CEA's windows, size {n}{}: {} modes, largest relative error {relative:.1e} \
         (SLEPc's), largest backward error {backward:.1e}",
        strip.map_or(String::new(), |(from, to)| format!(
            ", Re omega^2 in [{from:.4e}, {to:.4e})"
        )),
        modes.len()
    );
    Ok(DenseCeaResult { modes, shapes })
}

/// What no eigensolver can use, said before one is tried: a wrong shape, a band that is
/// not positive, a NaN or infinite entry (which faer reports as `NoConvergence`).
fn check_input(
    stiffness: MatRef<'_, f64>,
    mass: MatRef<'_, f64>,
    options: &DenseCeaOptions,
) -> Result<(), AssemblyError> {
    let n = stiffness.nrows();
    if stiffness.ncols() != n || mass.nrows() != n || mass.ncols() != n {
        return Err(AssemblyError::Inconsistent(format!(
            "K is {}x{}, M is {}x{}",
            stiffness.nrows(),
            stiffness.ncols(),
            mass.nrows(),
            mass.ncols()
        )));
    }
    if options.max_frequency_hz.is_nan() || options.max_frequency_hz <= 0.0 {
        return Err(AssemblyError::Inconsistent(format!(
            "the band must be positive, got {} Hz",
            options.max_frequency_hz
        )));
    }
    for (name, m) in [("stiffness", stiffness), ("mass", mass)] {
        if let Some((i, j)) = (0..n)
            .flat_map(|i| (0..n).map(move |j| (i, j)))
            .find(|&(i, j)| !m[(i, j)].is_finite())
        {
            return Err(AssemblyError::Eigen(format!(
                "the reduced {name} matrix holds {} at ({i}, {j}): a NaN or infinite value in \
                 the super-element or the contact law's stiffnesses",
                m[(i, j)]
            )));
        }
    }
    Ok(())
}

/// The undamped CEA of (K, M) on dense matrices, K unsymmetric, M symmetric positive
/// definite: M = L L^T, the standard problem A y = omega^2 y with A = L^-1 K L^-T (faer's
/// dense non-symmetric eigensolver), then x = L^-T y. (The QZ path, `generalized_eigen`, is
/// minutes at n ~ 1000, see TOOLCHAIN.md.) Modes are classified exactly as the sparse CEA
/// classifies its own ([`mode_from_lambda`], rigid-body flags from [`rigid`]). Each mode's
/// residual is |K x - omega^2 M x| / ((|K|_F + |omega^2| |M|_F) |x|), a backward error.
pub fn dense_cea(
    stiffness: MatRef<'_, f64>,
    mass: MatRef<'_, f64>,
    options: &DenseCeaOptions,
) -> Result<DenseCeaResult, AssemblyError> {
    check_input(stiffness, mass, options)?;
    let n = stiffness.nrows();
    let llt = mass
        .llt(Side::Lower)
        .map_err(|_| AssemblyError::MassNotPositiveDefinite)?;
    let l = llt.L();
    // A = L^-1 K L^-T: X = L^-1 K, then A^T = L^-1 X^T.
    let mut x = stiffness.to_owned();
    l.solve_lower_triangular_in_place(x.as_mut());
    let mut at = x.transpose().to_owned();
    l.solve_lower_triangular_in_place(at.as_mut());
    let a = at.transpose().to_owned();
    let evd = a.eigen().map_err(|e| {
        let span = (0..n)
            .flat_map(|i| (0..n).map(move |j| (i, j)))
            .map(|(i, j)| stiffness[(i, j)].abs())
            .filter(|v| *v > 0.0)
            .fold((f64::INFINITY, 0.0f64), |(lo, hi), v| {
                (lo.min(v), hi.max(v))
            });
        AssemblyError::Eigen(format!(
            "no convergence ({e:?}) on the reduced model of size {n}, whose stiffness entries \
             span {:.3e} to {:.3e}: a contact stiffness (k_linear, k_cubic) far out of scale \
             with the super-element's?",
            span.0, span.1
        ))
    })?;
    let values = evd.S().column_vector();
    let vectors = evd.U();
    let kept: Vec<usize> = (0..n)
        .filter(|&j| {
            let f = lambda_of(values[j]).im / (2.0 * PI);
            f.is_finite() && f <= options.max_frequency_hz
        })
        .collect();
    let m = kept.len();
    // x = L^-T y, real and imaginary parts apart (L is real).
    let mut xr = Mat::from_fn(n, m, |i, c| vectors[(i, kept[c])].re);
    let mut xi = Mat::from_fn(n, m, |i, c| vectors[(i, kept[c])].im);
    l.transpose().solve_upper_triangular_in_place(xr.as_mut());
    l.transpose().solve_upper_triangular_in_place(xi.as_mut());
    let (kr, ki) = (stiffness * &xr, stiffness * &xi);
    let (mr, mi) = (mass * &xr, mass * &xi);
    let (k_norm, m_norm) = (frobenius(stiffness), frobenius(mass));
    let level =
        rigid::ROUNDOFF * rigid::local_reference((0..n).map(|i| (stiffness[(i, i)], mass[(i, i)])));
    let magnitudes: Vec<f64> = kept.iter().map(|&j| values[j].norm()).collect();
    let rigid_flags = rigid::rigid_body_flags(&magnitudes, level, options.expected_rigid_modes);
    let mut found: Vec<(ComplexMode, Vec<Complex64>)> = Vec::with_capacity(m);
    for (c, &j) in kept.iter().enumerate() {
        let w2 = values[j];
        let residual = backward_error(
            (0..n).map(|i| {
                (
                    Complex64::new(xr[(i, c)], xi[(i, c)]),
                    Complex64::new(kr[(i, c)], ki[(i, c)]),
                    Complex64::new(mr[(i, c)], mi[(i, c)]),
                )
            }),
            w2,
            k_norm,
            m_norm,
        );
        let shape = largest_to_one(
            (0..n)
                .map(|i| Complex64::new(xr[(i, c)], xi[(i, c)]))
                .collect(),
        );
        let mode = mode_from_lambda(
            lambda_of(w2),
            residual,
            options.unstable_threshold,
            rigid_flags[c],
        );
        found.push((mode, shape));
    }
    found.sort_by(|a, b| by_frequency(&a.0, &b.0));
    let (modes, shapes) = found.into_iter().unzip();
    Ok(DenseCeaResult { modes, shapes })
}

/// The Frobenius norm.
fn frobenius(a: MatRef<'_, f64>) -> f64 {
    let mut s = 0.0;
    for j in 0..a.ncols() {
        for i in 0..a.nrows() {
            s += a[(i, j)] * a[(i, j)];
        }
    }
    s.sqrt()
}

/// |K x - omega^2 M x| / ((|K|_F + |omega^2| |M|_F) |x|) from (x_i, (K x)_i, (M x)_i).
fn backward_error(
    rows: impl Iterator<Item = (Complex64, Complex64, Complex64)>,
    w2: Complex64,
    k_norm: f64,
    m_norm: f64,
) -> f64 {
    let (mut r2, mut x2) = (0.0, 0.0);
    for (x, kx, mx) in rows {
        r2 += (kx - w2 * mx).norm_sqr();
        x2 += x.norm_sqr();
    }
    r2.sqrt() / ((k_norm + w2.norm() * m_norm) * x2.sqrt())
}

/// The shape scaled so that its largest component is 1 + 0i.
fn largest_to_one(mut shape: Vec<Complex64>) -> Vec<Complex64> {
    let biggest = shape
        .iter()
        .copied()
        .max_by(|a, b| a.norm_sqr().total_cmp(&b.norm_sqr()))
        .unwrap_or(Complex64::new(1.0, 0.0));
    if biggest.norm() > 0.0 {
        let s = biggest.inv();
        shape.iter_mut().for_each(|v| *v *= s);
    }
    shape
}
