//! The sliding static equilibrium K U + F_c(U) = lambda F_ext (METHOD §3), by PETSc SNES:
//! Newton with a line search, the Jacobian K + dF_c/dU assembled in Rust from the contact
//! pairs (unsymmetric with friction), MUMPS for the linear steps. The load goes on in
//! increments, and a step that fails is cut back.
//!
//! Coulomb pairs carry a slip history ([`SlipHistory`]): each increment's Newton solve
//! evaluates their return mapping from the history the increment started from (backward
//! Euler: the state at the end of the increment does not depend on the Newton path), and
//! the history is committed once the increment converges.

use super::restraint::{self, Body, FreeBody};
use crate::contact::{self, ContactPair, PointState, SlipHistory, Status};
use crate::fem::transform::Transform;
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
    /// The Coulomb pairs' slip history the solve starts from (the previous equilibrium's
    /// [`StaticSolution::slip_after`]; empty: the surfaces have just closed).
    pub slip: &'a SlipHistory,
    /// The bodies checked for rigid motions the initial tangent leaves free (empty: none).
    pub bodies: &'a [Body],
    /// The constraints' transformation u = C x + lambda g (`None`: no constraints). With
    /// it, the unknowns are the free DOFs: the residual is C^T (K u - lambda F + F_c(u)),
    /// the Jacobian C^T (K + dF_c/dU) C, and the prescribed displacements g grow with the
    /// load factor.
    pub constraints: Option<&'a Transform<'rt>>,
}

impl<'rt> StaticProblem<'_, 'rt> {
    /// The numbering of the solve's unknowns.
    pub fn solver_dofs(&self) -> &DofMap {
        self.constraints.map_or(self.dofs, |t| &t.free)
    }

    /// Node displacements (every node, every rank) of the unknowns `x` at load factor
    /// `load_factor` (the prescribed displacements' share). Collective.
    pub fn displacements(
        &self,
        x: &Vector<'rt>,
        load_factor: f64,
    ) -> Result<Vec<[f64; 3]>, PetscError> {
        match self.constraints {
            None => node_displacements(x, self.dofs),
            Some(t) => node_displacements(&t.expand(x, load_factor)?, self.dofs),
        }
    }

    /// A full-numbering matrix on the solve's unknowns: C^T A C with constraints, A itself
    /// without. Collective.
    pub fn on_unknowns(&self, a: Matrix<'rt>) -> Result<Matrix<'rt>, PetscError> {
        match self.constraints {
            None => Ok(a),
            Some(t) => t.project(&a),
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct StaticOptions {
    /// Load increments to start with.
    pub increments: usize,
    /// How many times a failed increment may be halved.
    pub max_cutbacks: usize,
    pub newton: NewtonOptions,
    /// A line search to retry a failed increment with before cutting the load back.
    pub fallback_line_search: Option<String>,
}

impl Default for StaticOptions {
    fn default() -> Self {
        StaticOptions {
            increments: 1,
            max_cutbacks: 6,
            // A factorisation costs ~50 triangular-solve pairs on the brake presets (7 s vs
            // 0.13 s medium, 57 s vs 0.7 s industrial): keeping it pays up to ~40 switches.
            newton: NewtonOptions {
                // The critical-point line search: the step length where the residual does
                // no more work along the Newton direction, <F(x + l d), d> = 0, found by
                // secants. Backtracking on |F|^2 crept: a full Newton step from a warm
                // start flips stick, slip and open states by the hundred, |F| jumps, and
                // backtracking took l = 0.1 (its floor) for ten or twenty iterations, each a
                // factorisation. The floating caliper, to the same equilibria (with the
                // secant step capped at the Newton step, see snes.rs): tiny, mu 0.1 to 0.9,
                // 87 Newton iterations against 131 (8 instead of 9-36 per warm point);
                // small, mu 0.3 to 0.6, 41 against 56; from rest at mu 0.3, 15 against 17
                // (where l2, the other secant search, diverged). Backtracking stays as the
                // fallback: a failed increment is retried with it before being cut back.
                line_search: "cp".into(),
                keep_factorization_rank: 40,
                // Stiff ties (a reduced interface's springs, 1e12-1e13 N/m on the brake)
                // put a floor of eps k_s |u| ~ 1e-8 N under |K u - F|, ~1e-9 of the load:
                // Newton lands on it in one step and the line search then finds no descent.
                // Below 1e-8 of the initial residual the balance is exact to the sweep's
                // own check (1e-8), so that is accepted as converged, and said so.
                roundoff_floor: 1e-8,
                ..NewtonOptions::default()
            },
            fallback_line_search: Some("bt".into()),
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
    /// The slip history the last increment started from: with it, the contact law at
    /// `displacement` gives `contact` and the consistent tangent (pass it with
    /// `displacement` to [`tangent`] and [`add_contact_tangent`]).
    pub slip_before: SlipHistory,
    /// The history after the equilibrium, committed: where a following solve (the next
    /// friction value) starts from, and what a perturbation step's tangent is evaluated
    /// with ([`contact::perturbation_history`]).
    pub slip_after: SlipHistory,
}

/// An equilibrium as the contact law sees it: the displacements and their committed slip
/// history (their states and the perturbation tangent follow from the two:
/// [`contact::perturbation_history`]).
#[derive(Clone, Copy, Debug)]
pub struct Configuration<'a> {
    pub displacement: &'a [[f64; 3]],
    pub slip: &'a SlipHistory,
}

impl StaticSolution {
    pub fn configuration(&self) -> Configuration<'_> {
        Configuration {
            displacement: &self.displacement,
            slip: &self.slip_after,
        }
    }
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
    #[error("a contact point failed on rank {rank}: {message}")]
    OtherRank { rank: usize, message: String },
    #[error("contact: {0}")]
    Contact(#[from] contact::ContactError),
    #[error(transparent)]
    Petsc(#[from] PetscError),
}

/// The points a rank evaluates: those whose first slave node it owns, with their anchors.
fn owned_points<'p>(
    pairs: &'p [ContactPair],
    slip: &'p SlipHistory,
    dofs: &'p DofMap,
) -> impl Iterator<Item = (&'p ContactPair, &'p contact::ContactPoint, [f64; 3])> + 'p {
    let owned = dofs.owned_nodes();
    pairs.iter().enumerate().flat_map(move |(i, pair)| {
        let owned = owned.clone();
        pair.points
            .iter()
            .enumerate()
            .filter(move |(_, pt)| pt.slave.first().is_some_and(|s| owned.contains(&s.0)))
            .map(move |(k, pt)| (pair, pt, slip.anchor(i, k)))
    })
}

/// Every point's state at `u` from the history `slip`, per pair. Each rank evaluates every
/// point (cheap beside a solve; `u` is replicated).
pub fn contact_states(
    pairs: &[ContactPair],
    slip: &SlipHistory,
    u: &[[f64; 3]],
) -> Result<Vec<Vec<PointState>>, contact::ContactError> {
    pairs
        .iter()
        .enumerate()
        .map(|(i, pair)| {
            pair.points
                .iter()
                .enumerate()
                .map(|(k, pt)| contact::point_state(pair, pt, slip.anchor(i, k), u))
                .collect()
        })
        .collect()
}

/// The history after states `states` (each point's anchor).
pub fn committed(states: &[Vec<PointState>]) -> SlipHistory {
    SlipHistory::from_anchors(
        states
            .iter()
            .map(|pair| pair.iter().map(|s| s.anchor).collect())
            .collect(),
    )
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
    slip: &SlipHistory,
    u: &[[f64; 3]],
) -> Result<(), StaticsError> {
    let mut failure = None;
    for (pair, point, anchor) in owned_points(pairs, slip, dofs) {
        match contact::evaluate(pair, point, anchor, u) {
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
    let first = comm.first_message(failure.as_ref().map(|e| e.to_string()));
    match (failure, first) {
        (Some(e), _) => Err(e.into()),
        (None, Some((rank, message))) => Err(StaticsError::OtherRank { rank, message }),
        (None, None) => Ok(()),
    }
}

/// A point's tangent, as far as deciding how much a new one differs from the last.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointTangent {
    pub status: Status,
    /// Coulomb pairs' blocks change with their state and, while slipping, with every step.
    pub coulomb: bool,
    /// The block the point adds at its first node (zero when open): a slipping point's
    /// moves with its slip direction and trial force, by less and less as Newton converges.
    pub block: [[f64; 3]; 3],
    /// The point has a tilt law (rank 2 more when it opens or closes).
    pub tilt: bool,
}

/// A slipping point whose block moved by at most this fraction (Frobenius norm) counts as
/// unchanged: GMRES around the kept factorisation then meets a perturbation of the
/// preconditioned operator of about this size per such point, not a rank-2 change, and
/// converges in a few iterations. On the brake every one of the hundreds of slipping points
/// moves at every iteration, so counting each as rank 2 refactorised at every Newton step,
/// the quadratic last ones included, where the directions have settled to 1e-4 and below.
const SETTLED_SLIP: f64 = 1e-3;

impl PointTangent {
    /// An upper bound on the rank of the change of this point's tangent block since
    /// `before`: 1 for a steady-sliding point opening or closing (`k A (n + mu t) n^T`),
    /// 3 for a Coulomb point changing state, 2 for one that keeps slipping (its tangential
    /// block moves with the slip direction) unless its block has settled ([`SETTLED_SLIP`]).
    pub fn rank_of_change(&self, before: &PointTangent) -> usize {
        let tilt = if self.tilt { 2 } else { 0 };
        match (self.coulomb, self.status == before.status) {
            // A patch law's block moves as its quadrature points open and close.
            (false, true) if self.tilt && self.block != before.block => 3,
            (false, true) => 0,
            (false, false) => 1 + tilt,
            (true, false) => 3 + tilt,
            (true, true) if self.status != Status::Slip => 0,
            (true, true) => {
                let squared = |b: &[[f64; 3]; 3]| b.iter().flatten().map(|v| v * v).sum::<f64>();
                let mut change = [[0.0; 3]; 3];
                for (i, row) in change.iter_mut().enumerate() {
                    for (j, v) in row.iter_mut().enumerate() {
                        *v = self.block[i][j] - before.block[i][j];
                    }
                }
                if squared(&change) <= SETTLED_SLIP * SETTLED_SLIP * squared(&before.block) {
                    0
                } else {
                    2
                }
            }
        }
    }
}

/// J = K + dF_c/dU at `u`, into `j` (same pattern as K). Collective, failures included.
/// Returns each of this rank's contact points' tangent kind (owned-point order).
pub fn tangent_into<'rt>(
    comm: Comm<'rt>,
    j: &mut Matrix<'rt>,
    stiffness: &Matrix<'rt>,
    dofs: &DofMap,
    pairs: &[ContactPair],
    slip: &SlipHistory,
    u: &[[f64; 3]],
) -> Result<Vec<PointTangent>, StaticsError> {
    j.zero()?;
    j.add(1.0, stiffness, Structure::Same)?;
    add_contact_tangent(comm, j, dofs, pairs, slip, u, 1.0)
}

/// Adds `scale` dF_c/dU at `u` into `j` (whose pattern holds the contact couplings) and
/// assembles. With scale 1 then -1 around a use, a stiffness serves as the tangent without a
/// second matrix, and comes back to within one rounding per entry. Collective. Returns
/// each of this rank's contact points' tangent kind (owned-point order).
pub fn add_contact_tangent<'rt>(
    comm: Comm<'rt>,
    j: &mut Matrix<'rt>,
    dofs: &DofMap,
    pairs: &[ContactPair],
    slip: &SlipHistory,
    u: &[[f64; 3]],
    scale: f64,
) -> Result<Vec<PointTangent>, StaticsError> {
    let mut failure = None;
    let mut closed = Vec::new();
    for (pair, point, anchor) in owned_points(pairs, slip, dofs) {
        match contact::evaluate(pair, point, anchor, u) {
            Ok((state, contribution)) => {
                let mut tangent = PointTangent {
                    status: state.status,
                    coulomb: pair.stick_stiffness().is_some(),
                    block: [[0.0; 3]; 3],
                    tilt: point.tilt.is_some(),
                };
                if let Some(mut c) = contribution {
                    let width = 3 * c.nodes.len();
                    tangent.block = [0, 1, 2].map(|i| [0, 1, 2].map(|j| c.jacobian[i * width + j]));
                    let idx = equations(dofs, &c.nodes);
                    if scale != 1.0 {
                        c.jacobian.iter_mut().for_each(|v| *v *= scale);
                    }
                    j.add_block(&idx, &idx, &c.jacobian)?;
                }
                closed.push(tangent);
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

/// Adds `scale` times the contact tangent of a perturbation step about the equilibrium
/// `u` (a CEA, a `*FREQUENCY` after a `*STATIC`) into `j`, and assembles: the consistent
/// tangent from the equilibrium's committed history `after`
/// ([`contact::perturbation_history`]), and for pairs with CalculiX's law the stick slope
/// across a steady-sliding point's direction ([`contact::variant`]). Collective.
pub fn add_perturbation_tangent<'rt>(
    comm: Comm<'rt>,
    j: &mut Matrix<'rt>,
    dofs: &DofMap,
    pairs: &[ContactPair],
    after: &SlipHistory,
    u: &[[f64; 3]],
    scale: f64,
) -> Result<(), StaticsError> {
    let history = contact::perturbation_history(pairs, after);
    add_contact_tangent(comm, j, dofs, pairs, &history, u, scale)?;
    if pairs.iter().all(|p| p.settings.calculix.is_none()) {
        return Ok(());
    }
    let mut failure = None;
    for (pair, point, anchor) in owned_points(pairs, &history, dofs) {
        match contact::point_state(pair, point, anchor, u) {
            Ok(state) => {
                if let Some(mut c) = contact::variant::across_sliding(pair, point, &state) {
                    c.jacobian.iter_mut().for_each(|v| *v *= scale);
                    j.add_block(
                        &equations(dofs, &c.nodes),
                        &equations(dofs, &c.nodes),
                        &c.jacobian,
                    )?;
                }
            }
            Err(e) => {
                failure = Some(e);
                break;
            }
        }
    }
    j.assemble()?;
    collective_failure(comm, failure)
}

/// The tangent stiffness K_t = K + dF_c/dU at `u`, as a new matrix. Collective.
pub fn tangent<'rt>(
    comm: Comm<'rt>,
    stiffness: &Matrix<'rt>,
    dofs: &DofMap,
    pairs: &[ContactPair],
    slip: &SlipHistory,
    u: &[[f64; 3]],
) -> Result<Matrix<'rt>, StaticsError> {
    let mut j = stiffness.duplicate()?;
    tangent_into(comm, &mut j, stiffness, dofs, pairs, slip, u)?;
    Ok(j)
}

/// Node displacements from a distributed solution vector (collective: all ranks get all).
pub fn node_displacements(x: &Vector, dofs: &DofMap) -> Result<Vec<[f64; 3]>, PetscError> {
    Ok(dofs.displacements(&x.gather_all()?))
}

/// The rigid motions of `problem.bodies` that only friction holds at `u`: the restraint
/// check on the tangent with every pair's friction taken out (normal contact, supports,
/// springs and links kept). A caliper whose guide pins are missing is still held by the
/// stick of its fingers on the pad, so the equilibrium exists and [`solve`] does not fail;
/// but its modes then rest on a stick stiffness that is a numerical setting, and a user
/// should be told which body it is. Collective.
pub fn held_only_by_friction<'rt>(
    comm: Comm<'rt>,
    problem: &StaticProblem<'_, 'rt>,
    u: &[[f64; 3]],
) -> Result<Vec<FreeBody>, StaticsError> {
    if problem.bodies.is_empty() {
        return Ok(Vec::new());
    }
    let pairs: Vec<ContactPair> = problem.pairs.iter().map(|p| p.frictionless()).collect();
    let j = problem.on_unknowns(tangent(
        comm,
        problem.stiffness,
        problem.dofs,
        &pairs,
        &SlipHistory::default(),
        u,
    )?)?;
    Ok(restraint::free_bodies(
        comm,
        &j,
        problem.solver_dofs(),
        problem.bodies,
    )?)
}

/// The forces the constraints apply at an equilibrium `u` (every node, the same on every
/// rank): the unconstrained residual K u + F_c(u) - lambda F in the full numbering, node by
/// node. It vanishes (to the solve's tolerance) at every DOF no constraint involves; at a
/// prescribed DOF it is the reaction force; around an `*EQUATION` or a coupling, the tie's
/// forces (they balance each other). Supported DOFs are eliminated: 0 there. Collective.
pub fn constraint_forces<'rt>(
    comm: Comm<'rt>,
    problem: &StaticProblem<'_, 'rt>,
    slip: &SlipHistory,
    u: &[[f64; 3]],
    load_factor: f64,
) -> Result<Vec<[f64; 3]>, StaticsError> {
    let dofs = problem.dofs;
    let owned = dofs.owned_equations();
    let mut x = Vector::new(comm, owned.len())?;
    let mut local = vec![0.0; owned.len()];
    for (n, un) in u.iter().enumerate() {
        for (c, &value) in un.iter().enumerate() {
            if let Some(e) = dofs.equation(n, c) {
                if owned.contains(&e) {
                    local[e - owned.start] = value;
                }
            }
        }
    }
    x.set_local(&local)?;
    let mut f = x.duplicate()?;
    problem.stiffness.mult(&x, &mut f)?;
    f.axpy(-load_factor, problem.load)?;
    add_contact_forces(comm, &mut f, dofs, problem.pairs, slip, u)?;
    Ok(node_displacements(&f, dofs)?)
}

/// Solves the equilibrium from `initial` (a previous solution, or zero). Collective.
pub fn solve<'rt>(
    comm: Comm<'rt>,
    problem: &StaticProblem<'_, 'rt>,
    initial: Option<&[[f64; 3]]>,
    options: &StaticOptions,
) -> Result<StaticSolution, StaticsError> {
    solve_from(comm, problem, initial, None, options)
}

/// [`solve`] with the load going from `start_load` (the load the `initial` equilibrium
/// carries: a deck's previous step) to `problem.load` over the increments, as a step of
/// Abaqus or CalculiX ramps from the previous step's loads to its own; `None`: from zero.
/// Collective.
pub fn solve_from<'rt>(
    comm: Comm<'rt>,
    problem: &StaticProblem<'_, 'rt>,
    initial: Option<&[[f64; 3]]>,
    start_load: Option<&Vector<'rt>>,
    options: &StaticOptions,
) -> Result<StaticSolution, StaticsError> {
    let dofs = problem.dofs;
    let unknowns = problem.solver_dofs();
    let owned = unknowns.owned_equations();
    let mut x = Vector::new(comm, owned.len())?;
    if let Some(u0) = initial {
        let mut local = vec![0.0; owned.len()];
        for (n, u) in u0.iter().enumerate() {
            for (c, &value) in u.iter().enumerate() {
                if let Some(e) = unknowns.equation(n, c) {
                    if owned.contains(&e) {
                        local[e - owned.start] = value;
                    }
                }
            }
        }
        x.set_local(&local)?;
    }
    if !problem.bodies.is_empty() {
        let u0 = problem.displacements(&x, 0.0)?;
        let j0 = problem.on_unknowns(tangent(
            comm,
            problem.stiffness,
            dofs,
            problem.pairs,
            problem.slip,
            &u0,
        )?)?;
        let free = restraint::free_bodies(comm, &j0, unknowns, problem.bodies)?;
        if !free.is_empty() {
            return Err(StaticsError::Unrestrained(free));
        }
    }
    let mut increments = Vec::new();
    let mut cutbacks = Vec::new();
    let mut factor = 0.0;
    let mut step = 1.0 / options.increments.max(1) as f64;
    let mut halvings = 0;
    let mut slip = problem.slip.clone();
    let mut slip_before = slip.clone();
    // A fallback that is the primary search again would only repeat the failure.
    let fallback = options
        .fallback_line_search
        .as_ref()
        .filter(|l| **l != options.newton.line_search)
        .map(|l| NewtonOptions {
            line_search: l.clone(),
            ..options.newton.clone()
        });
    let mut retried = false;
    while factor < 1.0 - 1e-12 {
        let target = (factor + step).min(1.0);
        let saved = x.copy()?;
        let newton_options = match &fallback {
            Some(f) if retried => f,
            _ => &options.newton,
        };
        match newton(
            comm,
            problem,
            start_load,
            &slip,
            target,
            &mut x,
            newton_options,
        ) {
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
                retried = false;
                // Commit the increment's slip: every rank computes it from the same
                // replicated displacements.
                let u = problem.displacements(&x, target)?;
                let after = committed(&contact_states(problem.pairs, &slip, &u)?);
                slip_before = std::mem::replace(&mut slip, after);
            }
            // Set-up and library faults (a bad option, no memory) are not cured by a smaller
            // load step: only divergence and failed contact evaluations are cut back.
            Err(err @ StaticsError::Petsc(PetscError::Library { .. } | PetscError::Invalid(_))) => {
                return Err(err)
            }
            Err(err) if !retried && fallback.is_some() => {
                let line_search = fallback.as_ref().map_or("", |f| f.line_search.as_str());
                tracing::warn!(
                    "load factor {target:.3} failed ({err}); retrying with the {line_search} line search"
                );
                retried = true;
                x.copy_from(&saved)?;
            }
            Err(err) => {
                retried = false;
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
    let displacement = problem.displacements(&x, factor)?;
    let contact = contact_states(problem.pairs, &slip_before, &displacement)?;
    Ok(StaticSolution {
        displacement,
        increments,
        cutbacks,
        contact,
        slip_before,
        slip_after: slip,
    })
}

fn newton<'rt>(
    comm: Comm<'rt>,
    problem: &StaticProblem<'_, 'rt>,
    start_load: Option<&Vector<'rt>>,
    slip: &SlipHistory,
    load_factor: f64,
    x: &mut Vector<'rt>,
    options: &NewtonOptions,
) -> Result<crate::petsc::NewtonReport, StaticsError> {
    let dofs = problem.dofs;
    let k = problem.stiffness;
    let load = problem.load;
    let pairs = problem.pairs;
    let constraints = problem.constraints;
    // With constraints the full-numbering residual and tangent are made as without, in
    // these, then carried to the unknowns.
    let (mut u_full, mut f_full, mut j_full) = match constraints {
        Some(t) => (
            Some(t.full_vector()?),
            Some(t.full_vector()?),
            Some(k.duplicate()?),
        ),
        None => (None, None, None),
    };
    let residual = Box::new(move |x: &Vector<'rt>, f: &mut Vector<'rt>| {
        // R = K u - lambda F - (1 - lambda) F_start + F_c(u), u = x (or C x + lambda g, and
        // R carried by C^T)
        let (Some(t), Some(u_full), Some(f_full)) = (constraints, &mut u_full, &mut f_full) else {
            k.mult(x, f).map_err(|e| e.to_string())?;
            f.axpy(-load_factor, load).map_err(|e| e.to_string())?;
            if let Some(start) = start_load {
                f.axpy(load_factor - 1.0, start)
                    .map_err(|e| e.to_string())?;
            }
            let u = node_displacements(x, dofs).map_err(|e| e.to_string())?;
            return add_contact_forces(comm, f, dofs, pairs, slip, &u).map_err(|e| e.to_string());
        };
        t.expand_into(x, load_factor, u_full)
            .map_err(|e| e.to_string())?;
        k.mult(u_full, f_full).map_err(|e| e.to_string())?;
        f_full.axpy(-load_factor, load).map_err(|e| e.to_string())?;
        if let Some(start) = start_load {
            f_full
                .axpy(load_factor - 1.0, start)
                .map_err(|e| e.to_string())?;
        }
        let u = node_displacements(u_full, dofs).map_err(|e| e.to_string())?;
        add_contact_forces(comm, f_full, dofs, pairs, slip, &u).map_err(|e| e.to_string())?;
        t.restrict_into(f_full, f).map_err(|e| e.to_string())
    });
    // A steady-sliding point's tangent depends on u only through whether it is closed
    // (small sliding: fixed normals and directions), and opening or closing changes it by a
    // rank-one term; a Coulomb point's by at most rank 3 (see PointTangent): Newton may keep
    // a factorisation while few points switch.
    let mut previous: Option<Vec<PointTangent>> = None;
    let jacobian = Box::new(move |x: &Vector<'rt>, j: &mut Matrix<'rt>| {
        let closed = match (constraints, &mut j_full) {
            (Some(t), Some(j_full)) => {
                let full = t.expand(x, load_factor).map_err(|e| e.to_string())?;
                let u = node_displacements(&full, dofs).map_err(|e| e.to_string())?;
                let closed = tangent_into(comm, j_full, k, dofs, pairs, slip, &u)
                    .map_err(|e| e.to_string())?;
                t.project_into(j_full, j).map_err(|e| e.to_string())?;
                closed
            }
            _ => {
                let u = node_displacements(x, dofs).map_err(|e| e.to_string())?;
                tangent_into(comm, j, k, dofs, pairs, slip, &u).map_err(|e| e.to_string())?
            }
        };
        let change = match &previous {
            None => JacobianChange::Unknown,
            Some(p) => {
                let rank: usize = p
                    .iter()
                    .zip(&closed)
                    .map(|(a, b)| b.rank_of_change(a))
                    .sum();
                let mut flips = [rank as f64];
                comm.sum_in_place(&mut flips);
                JacobianChange::RankAtMost(flips[0] as usize)
            }
        };
        previous = Some(closed);
        Ok(change)
    });
    let j = match constraints {
        Some(t) => t.project(k)?,
        None => k.duplicate()?,
    };
    let mut snes = NonlinearSolver::new(comm, residual, jacobian, j, options)?;
    let result = snes.solve(x);
    Ok(result?)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::coulomb::{return_mapping, PointLaw};

    /// A point of a Coulomb pair pressed with 1 kN, its tangent block as
    /// [`add_contact_tangent`] stores it (k A n n^T - d f_T / d w, one node of weight 1).
    fn point(w: [f64; 3]) -> PointTangent {
        let law = PointLaw {
            normal: [0.0, 0.0, 1.0],
            friction: 0.3,
            normal_stiffness: 1e9,
            stick_stiffness: 1e9,
            cone_tolerance: 0.0,
        };
        let t = return_mapping(&law, w, [0.0; 3], 1e3, true);
        PointTangent {
            status: t.status,
            coulomb: true,
            block: [0, 1, 2]
                .map(|i| [0, 1, 2].map(|j| 1e9 * law.normal[i] * law.normal[j] - t.jacobian[i][j])),
            tilt: false,
        }
    }

    #[test]
    fn a_settled_slip_keeps_the_factorisation_and_a_turning_one_does_not() {
        // Trial force 1e9 * 1e-5 = 1e4 N against a cone of 300 N: slipping.
        let slipping = point([1e-5, 0.0, 0.0]);
        assert_eq!(slipping.status, Status::Slip);
        // Newton's last steps: the slip direction turns by 1e-7 rad and the trial grows.
        let settled = point([1.00001e-5, 1e-12, 0.0]);
        assert_eq!(settled.rank_of_change(&slipping), 0);
        // An early step: the direction turns by 0.1 rad.
        let turned = point([1e-5, 1e-6, 0.0]);
        assert_eq!(turned.rank_of_change(&slipping), 2);
        // Slip to stick (trial 100 N inside the cone), and a point that keeps sticking.
        let stuck = point([1e-7, 0.0, 0.0]);
        assert_eq!(stuck.status, Status::Stick);
        assert_eq!(stuck.rank_of_change(&slipping), 3);
        assert_eq!(point([0.0, 1e-7, 0.0]).rank_of_change(&stuck), 0);
    }
}
