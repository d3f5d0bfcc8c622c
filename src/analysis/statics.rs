//! The sliding static equilibrium K U + F_c(U) = lambda F_ext (METHOD §3), by PETSc SNES:
//! Newton with a line search, the Jacobian K + dF_c/dU assembled in Rust from the contact
//! pairs (unsymmetric with friction), MUMPS for the linear steps. The load goes on in
//! increments, and a step that fails is cut back.

use super::restraint::{self, Body, FreeBody};
use crate::contact::{self, ContactPair, PointState};
use crate::fem::DofMap;
use crate::petsc::{
    format_history, Comm, JacobianChange, Matrix, NewtonOptions, NonlinearSolver, PetscError,
    PetscInt, Structure, Vector,
};

/// What the equilibrium is solved for: assembled structure, loads and contact pairs.
pub struct StaticProblem<'a, 'rt> {
    pub dofs: &'a DofMap,
    /// Structural stiffness (with supports and springs) on a pattern that also holds every
    /// contact coupling.
    pub stiffness: &'a Matrix<'rt>,
    /// External load at factor 1.
    pub load: &'a Vector<'rt>,
    pub pairs: &'a [ContactPair],
    /// The bodies checked for rigid motions the initial tangent leaves free (empty: none).
    pub bodies: &'a [Body],
}

#[derive(Clone, Debug, PartialEq)]
pub struct StaticOptions {
    /// Load increments to start with.
    pub increments: usize,
    /// How many times a failed increment may be halved.
    pub max_cutbacks: usize,
    pub newton: NewtonOptions,
}

impl Default for StaticOptions {
    fn default() -> Self {
        StaticOptions {
            increments: 1,
            max_cutbacks: 6,
            // A factorisation costs ~50 triangular-solve pairs on the brake presets (7 s vs
            // 0.13 s medium, 57 s vs 0.7 s industrial): keeping it pays up to ~40 switches.
            newton: NewtonOptions {
                keep_factorization_rank: 40,
                // Stiff ties (a reduced interface's springs, 1e12-1e13 N/m on the brake)
                // put a floor of eps k_s |u| ~ 1e-8 N under |K u - F|, ~1e-9 of the load:
                // Newton lands on it in one step and the line search then finds no descent.
                // Below 1e-8 of the initial residual the balance is exact to the sweep's
                // own check (1e-8), so that is accepted as converged, and said so.
                roundoff_floor: 1e-8,
                ..NewtonOptions::default()
            },
        }
    }
}

/// One converged load increment.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct IncrementReport {
    pub load_factor: f64,
    pub iterations: usize,
    /// Tangents factorised (the other iterations kept one inside GMRES).
    pub factorizations: usize,
    pub residual_history: Vec<f64>,
    pub reason: String,
}

/// The equilibrium.
pub struct StaticSolution {
    /// Displacement of every node (mesh and extra), the same on every rank.
    pub displacement: Vec<[f64; 3]>,
    pub increments: Vec<IncrementReport>,
    /// Failed attempts that were cut back: (load factor tried, why).
    pub cutbacks: Vec<(f64, String)>,
    /// State of every contact point, per pair.
    pub contact: Vec<Vec<PointState>>,
}

#[derive(Debug, thiserror::Error)]
pub enum StaticsError {
    #[error("the static solve did not converge: increment to load factor {load_factor:.4} failed after {cutbacks} cut-backs; last attempt: {last}")]
    NotConverged {
        load_factor: f64,
        cutbacks: usize,
        last: String,
    },
    #[error("the tangent stiffness is singular at the start of the static solve: {}; hold every body with supports, springs or contact pairs (guides, abutments)", .0.iter().map(|m| m.to_string()).collect::<Vec<_>>().join("; "))]
    Unrestrained(Vec<FreeBody>),
    #[error("a contact point failed on another rank (its message is printed by that rank)")]
    OtherRank,
    #[error("contact: {0}")]
    Contact(#[from] contact::ContactError),
    #[error(transparent)]
    Petsc(#[from] PetscError),
}

/// The points a rank evaluates: those whose first slave node it owns.
fn owned_points<'p>(
    pairs: &'p [ContactPair],
    dofs: &'p DofMap,
) -> impl Iterator<Item = (&'p ContactPair, &'p contact::ContactPoint)> + 'p {
    let owned = dofs.owned_nodes();
    pairs.iter().flat_map(move |pair| {
        let owned = owned.clone();
        pair.points
            .iter()
            .filter(move |pt| pt.slave.first().is_some_and(|s| owned.contains(&s.0)))
            .map(move |pt| (pair, pt))
    })
}

fn equations(dofs: &DofMap, nodes: &[usize]) -> Vec<PetscInt> {
    nodes
        .iter()
        .flat_map(|&n| dofs.node_equations(n))
        .map(|e| e as PetscInt)
        .collect()
}

/// Adds the contact internal forces at displacement `u` into `f` (ADD, then assembles).
/// Collective: a point that fails on one rank is an error on every rank, so no rank is left
/// waiting in the solver's next collective call.
pub fn add_contact_forces(
    comm: Comm,
    f: &mut Vector,
    dofs: &DofMap,
    pairs: &[ContactPair],
    u: &[[f64; 3]],
) -> Result<(), StaticsError> {
    let mut failure = None;
    for (pair, point) in owned_points(pairs, dofs) {
        match contact::evaluate(pair, point, u) {
            Ok((_, Some(c))) => f.add_values(&equations(dofs, &c.nodes), &c.residual)?,
            Ok((_, None)) => {}
            Err(e) => {
                failure = Some(e);
                break;
            }
        }
    }
    f.assemble()?;
    collective_failure(comm, failure)
}

/// Every rank's outcome of a loop over its own contact points, made collective.
fn collective_failure(
    comm: Comm,
    failure: Option<contact::ContactError>,
) -> Result<(), StaticsError> {
    let all_ok = comm.all(failure.is_none());
    match failure {
        Some(e) => Err(e.into()),
        None if !all_ok => Err(StaticsError::OtherRank),
        None => Ok(()),
    }
}

/// J = K + dF_c/dU at `u`, into `j` (same pattern as K). Collective, failures included.
/// Returns whether each of this rank's contact points is closed (owned-point order).
pub fn tangent_into<'rt>(
    comm: Comm<'rt>,
    j: &mut Matrix<'rt>,
    stiffness: &Matrix<'rt>,
    dofs: &DofMap,
    pairs: &[ContactPair],
    u: &[[f64; 3]],
) -> Result<Vec<bool>, StaticsError> {
    j.zero()?;
    j.add(1.0, stiffness, Structure::Same)?;
    add_contact_tangent(comm, j, dofs, pairs, u, 1.0)
}

/// Adds `scale` dF_c/dU at `u` into `j` (whose pattern holds the contact couplings) and
/// assembles. With scale 1 then -1 around a use, a stiffness serves as the tangent without a
/// second matrix, and comes back to within one rounding per entry. Collective. Returns
/// whether each of this rank's contact points is closed (owned-point order).
pub fn add_contact_tangent<'rt>(
    comm: Comm<'rt>,
    j: &mut Matrix<'rt>,
    dofs: &DofMap,
    pairs: &[ContactPair],
    u: &[[f64; 3]],
    scale: f64,
) -> Result<Vec<bool>, StaticsError> {
    let mut failure = None;
    let mut closed = Vec::new();
    for (pair, point) in owned_points(pairs, dofs) {
        match contact::evaluate(pair, point, u) {
            Ok((state, contribution)) => {
                closed.push(state.closed);
                if let Some(mut c) = contribution {
                    let idx = equations(dofs, &c.nodes);
                    if scale != 1.0 {
                        c.jacobian.iter_mut().for_each(|v| *v *= scale);
                    }
                    j.add_block(&idx, &idx, &c.jacobian)?;
                }
            }
            Err(e) => {
                failure = Some(e);
                break;
            }
        }
    }
    j.assemble()?;
    collective_failure(comm, failure)?;
    Ok(closed)
}

/// The tangent stiffness K_t = K + dF_c/dU at `u`, as a new matrix. Collective.
pub fn tangent<'rt>(
    comm: Comm<'rt>,
    stiffness: &Matrix<'rt>,
    dofs: &DofMap,
    pairs: &[ContactPair],
    u: &[[f64; 3]],
) -> Result<Matrix<'rt>, StaticsError> {
    let mut j = stiffness.duplicate()?;
    tangent_into(comm, &mut j, stiffness, dofs, pairs, u)?;
    Ok(j)
}

/// Node displacements from a distributed solution vector (collective: all ranks get all).
pub fn node_displacements(x: &Vector, dofs: &DofMap) -> Result<Vec<[f64; 3]>, PetscError> {
    Ok(dofs.displacements(&x.gather_all()?))
}

/// Solves the equilibrium from `initial` (a previous solution, or zero). Collective.
pub fn solve<'rt>(
    comm: Comm<'rt>,
    problem: &StaticProblem<'_, 'rt>,
    initial: Option<&[[f64; 3]]>,
    options: &StaticOptions,
) -> Result<StaticSolution, StaticsError> {
    let dofs = problem.dofs;
    let owned = dofs.owned_equations();
    let mut x = Vector::new(comm, owned.len())?;
    if let Some(u0) = initial {
        let mut local = vec![0.0; owned.len()];
        for (n, u) in u0.iter().enumerate() {
            for (c, &value) in u.iter().enumerate() {
                if let Some(e) = dofs.equation(n, c) {
                    if owned.contains(&e) {
                        local[e - owned.start] = value;
                    }
                }
            }
        }
        x.set_local(&local)?;
    }
    if !problem.bodies.is_empty() {
        let u0 = node_displacements(&x, dofs)?;
        let j0 = tangent(comm, problem.stiffness, dofs, problem.pairs, &u0)?;
        let free = restraint::free_bodies(comm, &j0, dofs, problem.bodies)?;
        if !free.is_empty() {
            return Err(StaticsError::Unrestrained(free));
        }
    }
    let mut increments = Vec::new();
    let mut cutbacks = Vec::new();
    let mut factor = 0.0;
    let mut step = 1.0 / options.increments.max(1) as f64;
    let mut halvings = 0;
    while factor < 1.0 - 1e-12 {
        let target = (factor + step).min(1.0);
        let saved = x.copy()?;
        match newton(comm, problem, target, &mut x, &options.newton) {
            Ok(report) => {
                tracing::info!(
                    "load factor {target:.3}: {} Newton iterations ({} factorisations), residual {}",
                    report.iterations,
                    report.factorizations,
                    format_history(&report.residual_history)
                );
                increments.push(IncrementReport {
                    load_factor: target,
                    iterations: report.iterations,
                    factorizations: report.factorizations,
                    residual_history: report.residual_history,
                    reason: report.reason,
                });
                factor = target;
            }
            // Set-up and library faults (a bad option, no memory) are not cured by a smaller
            // load step: only divergence and failed contact evaluations are cut back.
            Err(err @ StaticsError::Petsc(PetscError::Library { .. } | PetscError::Invalid(_))) => {
                return Err(err)
            }
            Err(err) => {
                let why = err.to_string();
                tracing::warn!("load factor {target:.3} failed ({why}); cutting back");
                cutbacks.push((target, why.clone()));
                halvings += 1;
                if halvings > options.max_cutbacks {
                    return Err(StaticsError::NotConverged {
                        load_factor: target,
                        cutbacks: halvings - 1,
                        last: why,
                    });
                }
                x.copy_from(&saved)?;
                step *= 0.5;
            }
        }
    }
    let displacement = node_displacements(&x, dofs)?;
    let contact = problem
        .pairs
        .iter()
        .map(|pair| {
            pair.points
                .iter()
                .map(|pt| contact::point_state(pair, pt, &displacement))
                .collect::<Result<Vec<_>, _>>()
        })
        .collect::<Result<Vec<_>, _>>()?;
    Ok(StaticSolution {
        displacement,
        increments,
        cutbacks,
        contact,
    })
}

fn newton<'rt>(
    comm: Comm<'rt>,
    problem: &StaticProblem<'_, 'rt>,
    load_factor: f64,
    x: &mut Vector<'rt>,
    options: &NewtonOptions,
) -> Result<crate::petsc::NewtonReport, StaticsError> {
    let dofs = problem.dofs;
    let k = problem.stiffness;
    let load = problem.load;
    let pairs = problem.pairs;
    let residual = Box::new(move |x: &Vector<'rt>, f: &mut Vector<'rt>| {
        // R = K x - lambda F + F_c(x)
        k.mult(x, f).map_err(|e| e.to_string())?;
        f.axpy(-load_factor, load).map_err(|e| e.to_string())?;
        let u = node_displacements(x, dofs).map_err(|e| e.to_string())?;
        add_contact_forces(comm, f, dofs, pairs, &u).map_err(|e| e.to_string())
    });
    // The tangent depends on u only through which points are closed (small sliding: fixed
    // normals and directions), and each point that opens or closes changes it by a rank-one
    // term: Newton may keep a factorisation while few points switch.
    let mut previous: Option<Vec<bool>> = None;
    let jacobian = Box::new(move |x: &Vector<'rt>, j: &mut Matrix<'rt>| {
        let u = node_displacements(x, dofs).map_err(|e| e.to_string())?;
        let closed = tangent_into(comm, j, k, dofs, pairs, &u).map_err(|e| e.to_string())?;
        let change = match &previous {
            None => JacobianChange::Unknown,
            Some(p) => {
                let mut flips = [p.iter().zip(&closed).filter(|(a, b)| a != b).count() as f64];
                comm.sum_in_place(&mut flips);
                JacobianChange::RankAtMost(flips[0] as usize)
            }
        };
        previous = Some(closed);
        Ok(change)
    });
    let j = k.duplicate()?;
    let mut snes = NonlinearSolver::new(comm, residual, jacobian, j, options)?;
    let result = snes.solve(x);
    Ok(result?)
}
