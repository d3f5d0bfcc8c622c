//! Real modes: K phi = omega^2 M phi, a generalised Hermitian problem solved by SLEPc with
//! shift-and-invert through a parallel LDL^T factorisation. A frequency band is searched
//! with a proof that it is complete: the inertia of LDL^T(K - sigma M) counts the
//! eigenvalues below sigma (Sylvester), so every mode in the band is found once and none
//! twice. Usually one count at the band's top and one Krylov-Schur run about its bottom
//! settle it; when that run does not return exactly the counted number, SLEPc's spectrum
//! slicing does the band. The N lowest modes of a model with no free body (a deck's
//! `*FREQUENCY, N`) come from one run for N pairs and one count just above the N-th. On a
//! model with no free body that run is block Lanczos on MUMPS's parallel LDL^T
//! ([`block_lanczos_pairs`]), SLEPc's Krylov-Schur where it does not converge or the count
//! disagrees (and everywhere with `-squeal_modes_block 0`). Works on any (K, M).

use super::block_lanczos::{self, Lanczos};
use super::parallel_factor::ParallelFactor;
use super::rigid;
use crate::petsc::{
    eigenvalues_below, Comm, DirectPackage, EigenOptions, EigenProblem, EigenSolver, Factorization,
    LinearMethod, Matrix, PetscError, Spectrum, Vector,
};
use std::f64::consts::PI;

/// Which modes to compute.
#[derive(Clone, Debug, PartialEq)]
pub enum ModeBand {
    /// Every mode from 0 Hz up to this frequency.
    Below { max_frequency_hz: f64 },
    /// The `count` lowest modes.
    Lowest { count: usize },
}

#[derive(Clone, Debug, PartialEq)]
pub struct ModesOptions {
    pub band: ModeBand,
    /// Relative residual tolerance of each pair.
    pub tolerance: f64,
    pub linear: LinearMethod,
    /// How many rigid-body motions the model has, when known (6 per free body, from
    /// [`crate::analysis::restraint::free_bodies`]): confirms where the rigid cluster ends
    /// (see [`crate::analysis::rigid`]).
    pub expected_rigid_modes: Option<usize>,
}

impl Default for ModesOptions {
    fn default() -> Self {
        ModesOptions {
            band: ModeBand::Below {
                max_frequency_hz: 10_000.0,
            },
            tolerance: 1e-10,
            linear: LinearMethod::default(),
            expected_rigid_modes: None,
        }
    }
}

/// One real mode.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct RealMode {
    /// 1-based, in increasing frequency.
    pub index: usize,
    /// sqrt(|omega^2|) / 2 pi (negative round-off of a rigid-body mode gives 0 Hz, not NaN).
    pub frequency_hz: f64,
    /// omega^2 as computed.
    pub eigenvalue: f64,
    /// |K phi - omega^2 M phi| / |omega^2 M phi|, SLEPc's relative error.
    pub residual: f64,
    /// A zero-energy (rigid-body) mode of an unsupported body: an eigenvalue at round-off
    /// level, in the cluster below the spectrum's gap ([`crate::analysis::rigid`]).
    pub rigid_body: bool,
}

/// The modes and their shapes.
pub struct RealModes<'rt> {
    pub modes: Vec<RealMode>,
    /// Mass-normalised shapes (phi^T M phi = 1), distributed like K's columns.
    pub shapes: Vec<Vector<'rt>>,
    /// Pairs SLEPc reported converged (may exceed `modes.len()` for `Lowest`).
    pub converged: usize,
    pub iterations: usize,
    /// How the band was searched.
    pub method: BandMethod,
    /// Which eigensolver found the pairs.
    pub solver: ModeSolver,
}

/// Which eigensolver found a band's pairs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum ModeSolver {
    /// SLEPc's Krylov-Schur (or its spectrum slicing).
    KrylovSchur,
    /// Block Lanczos on MUMPS's parallel LDL^T ([`block_lanczos_pairs`]).
    BlockLanczos,
}

impl std::fmt::Display for ModeSolver {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            ModeSolver::KrylovSchur => "Krylov-Schur",
            ModeSolver::BlockLanczos => "block Lanczos",
        })
    }
}

/// How a band was proved complete.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum BandMethod {
    /// One inertia count at the band's top, one shift-and-invert run that found that many.
    SingleShift,
    /// SLEPc's spectrum slicing: the single shift did not return the counted number of
    /// modes in the band, or the linear solver gives no inertia (not MUMPS).
    Slicing,
    /// The N lowest modes of a model with no free body: one shift-and-invert run below the
    /// spectrum, then one inertia count just above the N-th mode found, which says that no
    /// mode below it was missed ([`lowest_of_a_held_model`]).
    CountedLowest,
}

#[derive(Debug, thiserror::Error)]
pub enum ModesError {
    #[error("the band must be a positive frequency or count, got {0}")]
    BadBand(String),
    #[error("only {converged} of the {requested} lowest modes converged (raise --tolerance or the iteration limit with -eps_max_it)")]
    NotConverged { requested: usize, converged: usize },
    #[error(transparent)]
    Petsc(#[from] PetscError),
}

/// Computes real modes of (K, M). Collective.
pub fn real_modes<'rt>(
    comm: Comm<'rt>,
    k: &Matrix<'rt>,
    m: &Matrix<'rt>,
    options: &ModesOptions,
) -> Result<RealModes<'rt>, ModesError> {
    // The band as an interval of omega^2. For the N lowest modes a first, loose
    // shift-and-invert solve near zero tells how far up the N-th mode lies; the accurate
    // values then come from solving that interval like any band. (Shift-and-invert alone is
    // not accurate enough on a free-free model: the rigid-body modes, ~1e8 times closer to
    // a shift near zero than the elastic ones, swamp their convergence; seen as 1e-5
    // relative errors that differed between rank counts.)
    let purify = !positive_diagonal(comm, m)?;
    // A model with no free body (the restraint check says so) has no rigid-body cluster to
    // swamp a shift near zero: its N lowest modes come from one run, proved complete by one
    // count, instead of the estimate and the band below.
    if let ModeBand::Lowest { count } = options.band {
        if count > 0 && options.expected_rigid_modes == Some(0) && mumps(options) {
            if let Some(band) = lowest_of_a_held_model(comm, k, m, count, options, purify)? {
                return finish(comm, k, m, band, Some(count), options);
            }
        }
    }
    let (high, requested) = match options.band {
        ModeBand::Below { max_frequency_hz } if max_frequency_hz > 0.0 => {
            ((2.0 * PI * max_frequency_hz).powi(2), None)
        }
        ModeBand::Lowest { count } if count > 0 => {
            let estimate = EigenOptions {
                problem: EigenProblem::HermitianGeneralized,
                spectrum: Spectrum::NearTarget {
                    target: -(2.0 * PI).powi(2),
                    count,
                },
                tolerance: 1e-8,
                linear: options.linear.clone(),
                ..Default::default()
            };
            let mut eps = EigenSolver::new(comm, k, Some(m), &estimate)?;
            let summary = eps.solve()?;
            if summary.converged < count {
                return Err(ModesError::NotConverged {
                    requested: count,
                    converged: summary.converged,
                });
            }
            let mut top = 0.0f64;
            for i in 0..summary.converged {
                top = top.max(eps.value(i)?.re);
            }
            // Above the N-th mode by far more than the estimate's error, below it by far
            // less than any real gap would matter: extra modes are cut off after sorting.
            (top * 1.01 + 1.0, Some(count))
        }
        ref other => return Err(ModesError::BadBand(format!("{other:?}"))),
    };
    // A lower end slightly below zero keeps K - sigma M definite when the model is
    // free-free (K singular), while lying far below the first elastic eigenvalue.
    let low = -1e-4 * high;
    let band = match single_shift(comm, k, m, low, high, options, purify)? {
        Some(band) => band,
        None => slicing(comm, k, m, low, high, options, purify)?,
    };
    finish(comm, k, m, band, requested, options)
}

/// Whether every diagonal entry of M is positive (collective). For a mass matrix assembled
/// from elements (each one's mass positive definite on its nodes) and point masses, and for
/// C^T M C of one, that is M positive definite: x^T M x = 0 needs x = 0 on every node of
/// an element. A massless DOF (a coupling's reference node, a tilt node) shows as a zero.
/// On a positive definite M the shift-and-invert vectors have no null-space part for
/// SLEPc's purification to remove, and skipping it saves a triangular solve a pair: on
/// small-caliper's fixed-interface modes (78 pairs) 409 solves -> 318, 13.3 -> 10.6 s.
fn positive_diagonal<'rt>(comm: Comm<'rt>, m: &Matrix<'rt>) -> Result<bool, ModesError> {
    let diagonal = m.diagonal()?;
    let local = diagonal.read()?.iter().all(|&d| d > 0.0);
    Ok(comm.all(local))
}

/// The modes of a band, sorted, cut to the `requested` lowest, rigid-body modes flagged.
fn finish<'rt>(
    comm: Comm<'rt>,
    k: &Matrix<'rt>,
    m: &Matrix<'rt>,
    band: Band<'rt>,
    requested: Option<usize>,
    options: &ModesOptions,
) -> Result<RealModes<'rt>, ModesError> {
    if let Some(requested) = requested {
        if band.found.len() < requested {
            return Err(ModesError::NotConverged {
                requested,
                converged: band.found.len(),
            });
        }
    }
    let mut found = band.found;
    found.sort_by(|a, b| a.0.total_cmp(&b.0));
    if let Some(count) = requested {
        found.truncate(count);
    }
    let level = rigid::roundoff_level(comm, k, m)?;
    let values: Vec<f64> = found.iter().map(|f| f.0).collect();
    let rigid = rigid::rigid_body_flags(&values, level, options.expected_rigid_modes);
    let mut modes = Vec::with_capacity(found.len());
    let mut shapes = Vec::with_capacity(found.len());
    for (i, ((value, residual, shape), rigid_body)) in found.into_iter().zip(rigid).enumerate() {
        modes.push(RealMode {
            index: i + 1,
            frequency_hz: value.max(0.0).sqrt() / (2.0 * PI),
            eigenvalue: value,
            residual,
            rigid_body,
        });
        shapes.push(shape);
    }
    Ok(RealModes {
        modes,
        shapes,
        converged: band.converged,
        iterations: band.iterations,
        method: band.method,
        solver: band.solver,
    })
}

/// The pairs in [low, high] (omega^2, SLEPc's relative error, mass-normalised shape), in
/// any order, and what the eigen-solve that found them reported.
struct Band<'rt> {
    found: Vec<(f64, f64, Vector<'rt>)>,
    converged: usize,
    iterations: usize,
    method: BandMethod,
    solver: ModeSolver,
}

/// The band by one inertia count and one shift-and-invert run: the LDL^T factorisation of
/// K - high M says exactly how many eigenvalues lie below the band's top (Sylvester), then a
/// Krylov-Schur run about the band's lower end asks for that many. When it returns exactly
/// that many in [low, high] the band is complete, multiplicities included (the pairs are
/// M-orthogonal, so no eigenvalue is counted twice, and none is missing since the count
/// holds every eigenvalue below high).
///
/// A single-vector Krylov method sees the copies of an exactly multiple eigenvalue only
/// through round-off, so a run can stop with copies missing (the 12^3 Laplacian's six-fold
/// cluster: 4 of 6 found, pairs above the band converged instead). Then the same
/// factorisation searches the M-orthogonal complement of the pairs found, for as many as
/// are missing, up to [`MAX_ROUNDS`] runs in all. When that does not complete the count:
/// `None`, and the caller slices.
///
/// Why not always slice: SLEPc's slicing over [low, high] does the same two factorisations
/// (the inertia at each end, the solve about the lower one) but then runs Krylov-Schur with
/// its own sub-solver's dimensions (nev 40, ncv 80 here) and stops only once it has seen
/// past the top of the band. Measured on the clamped disc of 64,512 equations (16 modes
/// below 10 kHz, 1 rank): 97 triangular solves and 1.7 s of orthogonalisation against 80
/// vectors, 13.0 s for the eigen-solve; this path, one run with nev 16 (SLEPc's ncv 32):
/// 70 solves, 1.1 s of orthogonalisation, 10.3 s. Tried on that disc: ncv 40, 48, 64 (73,
/// 66, 85 solves), nev 20 (88), a shift inside the band (5e8 with nev 20: 86; 1e9 with nev
/// 24: 117, the band's ends being no nearer the shift than the modes above it).
fn single_shift<'rt>(
    comm: Comm<'rt>,
    k: &Matrix<'rt>,
    m: &Matrix<'rt>,
    low: f64,
    high: f64,
    options: &ModesOptions,
    purify: bool,
) -> Result<Option<Band<'rt>>, ModesError> {
    if !mumps(options) {
        return Ok(None);
    }
    let count = eigenvalues_below(comm, k, m, high)?;
    if count == 0 {
        return Ok(Some(Band {
            found: Vec::new(),
            converged: 0,
            iterations: 0,
            method: BandMethod::SingleShift,
            solver: ModeSolver::KrylovSchur,
        }));
    }
    // A held model's band by block Lanczos first (a free body's rigid-body modes, far
    // nearer the shift than the elastic ones, are left to SLEPc's run, as in
    // [`real_modes`]).
    if options.expected_rigid_modes == Some(0) {
        if let Some(found) = block_lanczos_pairs(comm, (k, m), low, (count, high), options)? {
            let inside: Vec<Pair<'rt>> = found
                .into_iter()
                .filter(|f| (low..high).contains(&f.0))
                .collect();
            // Rank 0's sums on every rank: the same branch everywhere.
            if inside.len() == count {
                tracing::debug!(
                    "single-shift modes: the {count} eigenvalues below {high:e} by block Lanczos"
                );
                return Ok(Some(Band {
                    found: inside,
                    converged: count,
                    iterations: 0,
                    method: BandMethod::SingleShift,
                    solver: ModeSolver::BlockLanczos,
                }));
            }
        }
    }
    let mut eps = near(comm, (k, m), low, count, options, purify, false)?;
    let mut found: Vec<(f64, f64, Vector<'rt>)> = Vec::with_capacity(count);
    let (mut converged, mut iterations) = (0, 0);
    for round in 1..=MAX_ROUNDS {
        let summary = eps.solve()?;
        converged += summary.converged;
        iterations += summary.iterations;
        let mut inside = Vec::new();
        for i in 0..summary.converged {
            if (low..high).contains(&eps.value(i)?.re) {
                inside.push(i);
            }
        }
        found.extend(pairs(&eps, k, m, &inside)?);
        // The values are replicated, but the branch must be the same on every rank.
        if comm.all(found.len() == count) {
            tracing::debug!(
                "single-shift modes: the {count} eigenvalues below {high:e} in {round} \
                 Krylov-Schur run(s), {iterations} iterations"
            );
            return Ok(Some(Band {
                found,
                converged,
                iterations,
                method: BandMethod::SingleShift,
                solver: ModeSolver::KrylovSchur,
            }));
        }
        // More than counted cannot be (the pairs are M-orthogonal) unless they are
        // inaccurate, and a round that adds nothing will not be helped by another.
        if !comm.all(found.len() < count && !inside.is_empty()) || round == MAX_ROUNDS {
            break;
        }
        let shapes: Vec<&Vector<'rt>> = found.iter().map(|f| &f.2).collect();
        eps.search_beyond(&shapes, count - found.len())?;
    }
    tracing::info!(
        "single-shift modes: {} of the {count} eigenvalues below {high:e} found in \
         [{low:e}, {high:e}]; slicing the band instead",
        found.len()
    );
    Ok(None)
}

/// Shift-and-invert Krylov-Schur for the `count` pairs nearest `target`, at the options'
/// tolerance. The operator is symmetric: MUMPS's LDL^T halves LU's factor, and with it the
/// cost of each triangular solve, which is most of the run. `inertia`: its factorisation can
/// count ([`EigenSolver::eigenvalues_below`]). Collective.
fn near<'rt>(
    comm: Comm<'rt>,
    (k, m): (&Matrix<'rt>, &Matrix<'rt>),
    target: f64,
    count: usize,
    options: &ModesOptions,
    purify: bool,
    inertia: bool,
) -> Result<EigenSolver<'rt>, ModesError> {
    let eps_options = EigenOptions {
        problem: EigenProblem::HermitianGeneralized,
        spectrum: Spectrum::NearTarget { target, count },
        tolerance: options.tolerance,
        linear: LinearMethod::Direct {
            package: DirectPackage::Mumps,
            factorization: Factorization::Cholesky,
        },
        purify,
        inertia,
        ..Default::default()
    };
    Ok(EigenSolver::new(comm, k, Some(m), &eps_options)?)
}

/// Single-shift runs before the band is sliced instead: the first, then searches for copies
/// of multiple eigenvalues that it missed (see [`single_shift`]).
const MAX_ROUNDS: usize = 4;

/// Whether the linear solver is MUMPS, the only one that gives the inertia of a parallel
/// factorisation.
fn mumps(options: &ModesOptions) -> bool {
    matches!(
        options.linear,
        LinearMethod::Direct {
            package: DirectPackage::Mumps,
            ..
        }
    )
}

/// The `count` lowest modes of a model with no free body, by one shift-and-invert run just
/// below zero for that many pairs, then one inertia count at a shift h above the `count`-th
/// eigenvalue found (halfway to the next one found, when there is one): when LDL^T(K - h M)
/// counts exactly as many eigenvalues below h as the run found there, none below h was
/// missed, so the `count` lowest found are the `count` lowest (the pairs are M-orthogonal,
/// none is counted twice). Two factorisations and one Krylov-Schur run, the count's on the
/// run's own transform, which keeps the run's symbolic analysis (on the clamped disc of
/// 64,512 equations, 2 ranks, five interleaved rounds: 5.79 -> 5.51 s, median), where the
/// general path takes three and two (a loose run to place the band's top, then the band); that one
/// stays for free bodies, whose rigid-body modes, ~1e8 times nearer a shift at zero than the
/// elastic ones, swamp the elastic ones' accuracy (see [`real_modes`]). `None` when the run
/// falls short or the count disagrees (a multiple eigenvalue whose copies the run did not
/// all see, or one that the `count`-th splits): the caller then takes the general path.
fn lowest_of_a_held_model<'rt>(
    comm: Comm<'rt>,
    k: &Matrix<'rt>,
    m: &Matrix<'rt>,
    count: usize,
    options: &ModesOptions,
    purify: bool,
) -> Result<Option<Band<'rt>>, ModesError> {
    if let Some(band) = block_lowest_of_a_held_model(comm, k, m, count, options)? {
        return Ok(Some(band));
    }
    // A shift of -(1 Hz)^2: K - sigma M is definite, and far below the first mode.
    // Its factorisation reports its inertia, so that the count below reuses its analysis.
    let mut eps = near(
        comm,
        (k, m),
        -(2.0 * PI).powi(2),
        count,
        options,
        purify,
        true,
    )?;
    let summary = eps.solve()?;
    let (mut converged, mut iterations) = (summary.converged, summary.iterations);
    let all: Vec<usize> = (0..summary.converged).collect();
    let mut found = pairs(&eps, k, m, &all)?;
    found.sort_by(|a, b| a.0.total_cmp(&b.0));
    // SLEPc's eigenvalues are replicated, so every branch below is the same on every rank.
    if found.len() < count || found[0].0 <= 0.0 {
        tracing::debug!(
            "lowest modes: {} of {count} converged, lowest {:e}; taking the general path",
            found.len(),
            found.first().map_or(f64::NAN, |f| f.0)
        );
        return Ok(None);
    }
    let splits = |found: &[Pair<'rt>]| splits_a_cluster(found, count);
    let h = count_shift(&found, count);
    let counted = match eps.eigenvalues_below(comm, h)? {
        Some(counted) => counted,
        None => eigenvalues_below(comm, k, m, h)?,
    };
    for round in 1..=MAX_ROUNDS {
        let found_below = found.iter().filter(|f| f.0 < h).count();
        if counted == found_below {
            // Every eigenvalue below h is found, and at least `count` lie there. A count-th
            // inside a cluster of equal eigenvalues (copies found since the first run may
            // have joined it) is left to the general path, which returns the cluster whole
            // and then cuts: which copies lie below a shift between them is round-off.
            if splits(&found) {
                tracing::debug!("lowest modes: the {count}-th splits a multiple eigenvalue");
                return Ok(None);
            }
            tracing::debug!(
                "lowest modes: the {count} lowest in {round} Krylov-Schur run(s), \
                 {iterations} iterations, {counted} eigenvalues below {h:e}"
            );
            return Ok(Some(Band {
                found,
                converged,
                iterations,
                method: BandMethod::CountedLowest,
                solver: ModeSolver::KrylovSchur,
            }));
        }
        // Copies of a multiple eigenvalue that a single-vector Krylov method saw only
        // through round-off (see [`single_shift`]): the same factorisation searches the
        // complement of the pairs found for as many as the count says are missing.
        if counted < found_below || round == MAX_ROUNDS {
            break;
        }
        let shapes: Vec<&Vector<'rt>> = found.iter().map(|f| &f.2).collect();
        eps.search_beyond(&shapes, counted - found_below)?;
        let summary = eps.solve()?;
        converged += summary.converged;
        iterations += summary.iterations;
        let all: Vec<usize> = (0..summary.converged).collect();
        found.extend(pairs(&eps, k, m, &all)?);
        found.sort_by(|a, b| a.0.total_cmp(&b.0));
    }
    tracing::info!(
        "lowest modes: {counted} eigenvalues below {h:e}, the run found {}; searching the \
         band instead",
        found.iter().filter(|f| f.0 < h).count()
    );
    Ok(None)
}

/// A pair as [`pairs`] gives it: omega^2, relative residual, M-normalised shape.
type Pair<'rt> = (f64, f64, Vector<'rt>);

/// Columns a block Lanczos step takes on a parallel LDL^T (see [`block_lanczos_pairs`]). On
/// the clamped disc (20 lowest, 2 ranks), blocks of 4, 8 and 16 took 112, 152 and more than
/// 176 columns (not converged in the subspace) and 4.9, 4.3-4.7 and 9.2 s (then SLEPc's
/// run) for the eigen-solve, SLEPc's Krylov-Schur 5.4-6.0 s, single runs.
const MODES_BLOCK: usize = 8;

/// The `count` lowest pairs above `shift` (all below `top`) by block Lanczos on MUMPS's
/// parallel LDL^T of K - shift M ([`ParallelFactor`]), as [`pairs`] gives them (omega^2,
/// relative residual, M-normalised shape); `None` where the run does not converge in its
/// subspace (the caller then runs SLEPc's Krylov-Schur). Why: SLEPc's Krylov-Schur makes
/// one pass through the factors per vector, and on the clamped disc of 64,512 equations
/// (20 lowest, 2 ranks) its 68 single solves were 1.9 s of a 5.0 s eigen-solve; a block
/// goes through them in one multi-right-hand-side solve. Collective.
fn block_lanczos_pairs<'rt>(
    comm: Comm<'rt>,
    (k, m): (&Matrix<'rt>, &Matrix<'rt>),
    shift: f64,
    (count, top): (usize, f64),
    options: &ModesOptions,
) -> Result<Option<Vec<Pair<'rt>>>, ModesError> {
    // `-squeal_modes_block N` sets the block (0: SLEPc's Krylov-Schur alone, as before
    // 2026-12-07). Rank 0 reads it and every rank takes its answer, a number or -1 for one
    // that is not, before any rank returns: ranks whose option databases differ (a
    // per-rank `PETSC_OPTIONS`) can then neither part ways nor leave one waiting.
    let asked = if comm.rank() == 0 {
        comm.option(c"-squeal_modes_block")
            .unwrap_or_else(|e| Some(format!("(unreadable: {e})")))
    } else {
        None
    };
    let mut block = vec![match asked.as_deref().map(str::parse::<usize>) {
        None => MODES_BLOCK as f64,
        Some(Ok(b)) => b as f64,
        Some(Err(_)) => -1.0,
    }];
    comm.broadcast_from_root(&mut block);
    if block[0] < 0.0 {
        return Err(ModesError::Petsc(PetscError::Invalid(format!(
            "-squeal_modes_block {}: a number of columns (0 for SLEPc's Krylov-Schur) was \
             expected",
            asked.as_deref().unwrap_or("(as rank 0 read it)")
        ))));
    }
    let block = block[0] as usize;
    if block == 0 || !block_lanczos::subspace_fits(comm.size(), k.size()?.0, count, block) {
        return Ok(None);
    }
    // MUMPS's parallel factor fails on every rank alike (its error is collective); SLEPc's
    // run then factorises at the same shift itself and says what failed in its own words.
    let factor = match ParallelFactor::new(comm, k, m, shift) {
        Ok(f) => f,
        Err(e) => {
            if comm.rank() == 0 {
                tracing::warn!(
                    "block Lanczos: the factorisation at {shift:e} failed ({e}); SLEPc's \
                     Krylov-Schur takes the modes"
                );
            }
            return Ok(None);
        }
    };
    let run = Lanczos {
        shift,
        block,
        count,
        top,
        tolerance: options.tolerance,
    };
    let Some(found) = block_lanczos::lowest(comm, &factor, (k, m), run)? else {
        return Ok(None);
    };
    drop(factor);
    let (template, _) = k.vectors()?;
    let (mut kx, mut mx) = (template.duplicate()?, template.duplicate()?);
    let mut pairs = Vec::with_capacity(count);
    for q in 0..found.eigenvalues.len() {
        let mut shape = template.duplicate()?;
        shape.set_local(&found.shapes.col(q).iter().copied().collect::<Vec<_>>())?;
        // SLEPc's relative error, |K x - omega^2 M x| / (|omega^2| |x|), as the other paths
        // report it (the run's own residuals are over |omega^2 M x|, which a mass matrix's
        // small entries make a larger number for the same pair).
        let value = found.eigenvalues[q];
        k.mult(&shape, &mut kx)?;
        m.mult(&shape, &mut mx)?;
        kx.axpy(-value, &mx)?;
        let residual = kx.norm2()? / (value.abs() * shape.norm2()?);
        pairs.push((value, residual, shape));
    }
    tracing::debug!(
        "block Lanczos: {count} pairs above {shift:e} in {} steps of {block} ({} solves)",
        found.steps,
        found.solves
    );
    Ok(Some(pairs))
}

/// [`lowest_of_a_held_model`] by block Lanczos ([`block_lanczos_pairs`]) and an inertia
/// count of its own: `None` where the run does not converge or the count disagrees (the
/// caller then takes SLEPc's run, which can search for missed copies on its own
/// factorisation). Collective.
fn block_lowest_of_a_held_model<'rt>(
    comm: Comm<'rt>,
    k: &Matrix<'rt>,
    m: &Matrix<'rt>,
    count: usize,
    options: &ModesOptions,
) -> Result<Option<Band<'rt>>, ModesError> {
    let shift = -(2.0 * PI).powi(2);
    // Just the count: one pair more (to take the count halfway to it) cost 24 columns more
    // on the clamped disc, whose 21st mode converges late (4.2-4.4 s against 4.7-5.3 s).
    let Some(mut found) =
        block_lanczos_pairs(comm, (k, m), shift, (count, f64::INFINITY), options)?
    else {
        return Ok(None);
    };
    found.sort_by(|a, b| a.0.total_cmp(&b.0));
    // The values are sums every rank holds with the same bits: the same branch everywhere.
    if found.len() < count || found[0].0 <= 0.0 {
        return Ok(None);
    }
    if splits_a_cluster(&found, count) {
        return Ok(None);
    }
    let h = count_shift(&found, count);
    let counted = eigenvalues_below(comm, k, m, h)?;
    let below = found.iter().filter(|f| f.0 < h).count();
    if counted != below {
        tracing::info!(
            "lowest modes: {counted} eigenvalues below {h:e}, block Lanczos found {below}; \
             SLEPc's Krylov-Schur instead"
        );
        return Ok(None);
    }
    tracing::debug!("lowest modes: the {count} lowest by block Lanczos, {counted} below {h:e}");
    let converged = found.len();
    Ok(Some(Band {
        found,
        converged,
        iterations: 0,
        method: BandMethod::CountedLowest,
        solver: ModeSolver::BlockLanczos,
    }))
}

/// Whether the `count`-th of the pairs `found` (sorted, at least `count`) and the next one
/// found are copies of one multiple eigenvalue ([`CLUSTER`]).
fn splits_a_cluster(found: &[Pair<'_>], count: usize) -> bool {
    let nth = found[count - 1].0;
    found
        .get(count)
        .is_some_and(|next| next.0 - nth <= CLUSTER * nth)
}

/// Where the N lowest are counted (`found` sorted, at least `count`): halfway from the
/// `count`-th to the next one found, or just above the `count`-th.
fn count_shift(found: &[Pair<'_>], count: usize) -> f64 {
    let nth = found[count - 1].0;
    match found.get(count) {
        Some(next) => 0.5 * (nth + next.0),
        // Above the count-th by far more than its error (the run's tolerance), by far less
        // than a gap a mode could hide in unseen: a mode missed below h fails the count.
        None => nth * (1.0 + 1e-6),
    }
}

/// Two eigenvalues this close (relative) are copies of one multiple eigenvalue for
/// [`lowest_of_a_held_model`]: far above the run's tolerance (1e-10 by default), far below
/// any two distinct modes of a structure.
const CLUSTER: f64 = 1e-8;

/// Every pair in [low, high] by SLEPc's spectrum slicing (inertia at each shift).
fn slicing<'rt>(
    comm: Comm<'rt>,
    k: &Matrix<'rt>,
    m: &Matrix<'rt>,
    low: f64,
    high: f64,
    options: &ModesOptions,
    purify: bool,
) -> Result<Band<'rt>, ModesError> {
    let eps_options = EigenOptions {
        problem: EigenProblem::HermitianGeneralized,
        spectrum: Spectrum::Interval { low, high },
        tolerance: options.tolerance,
        linear: options.linear.clone(),
        purify,
        ..Default::default()
    };
    let mut eps = EigenSolver::new(comm, k, Some(m), &eps_options)?;
    let summary = eps.solve()?;
    let all: Vec<usize> = (0..summary.converged).collect();
    Ok(Band {
        found: pairs(&eps, k, m, &all)?,
        converged: summary.converged,
        iterations: summary.iterations,
        method: BandMethod::Slicing,
        solver: ModeSolver::KrylovSchur,
    })
}

/// Pairs `indices` of a solved EPS: omega^2, relative error, shape with phi^T M phi = 1.
fn pairs<'rt>(
    eps: &EigenSolver<'rt>,
    k: &Matrix<'rt>,
    m: &Matrix<'rt>,
    indices: &[usize],
) -> Result<Vec<(f64, f64, Vector<'rt>)>, ModesError> {
    let (template, _) = k.vectors()?;
    let (_, mut m_phi) = m.vectors()?;
    let mut found = Vec::with_capacity(indices.len());
    for &i in indices {
        let (value, mut shape, _) = eps.pair(i, &template)?;
        // Normalise explicitly: phi^T M phi = 1 whatever SLEPc's convention.
        m.mult(&shape, &mut m_phi)?;
        let norm = shape.dot(&m_phi)?;
        if norm > 0.0 {
            shape.scale(1.0 / norm.sqrt())?;
        }
        found.push((value.re, eps.relative_error(i)?, shape));
    }
    Ok(found)
}
