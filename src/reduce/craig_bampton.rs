//! Builds a [`SuperElement`] (METHOD.md section 6; the paper's section 3.2.1) from a
//! reduced-interface model at a static equilibrium: the Craig-Bampton reduction onto the
//! reduced contact nodes, with the swept contact removed and every other contact linearised.
//!
//! "Swept" pairs below are the pairs put on the boundary: the disc/pad pairs, and any kept
//! pair the reduction reduced too (issue 32), which keeps its own law on the boundary
//! ([`super::superelement::BoundaryPair::own_law`]). With every pair there, nothing is
//! linearised, K_t = K, and the super-element is the same at any equilibrium: the sweep
//! builds it at rest.
//!
//! - K_t = K + dF_c/dU of every non-swept pair at the equilibrium (supports are already out
//!   of the DOF map).
//! - Boundary B: the equations of c_k then d_k of every swept pair's points, in the order of
//!   [`super::superelement`]; interior I: every other equation.
//! - One LU of K_II (MUMPS) and one block solve for all of [-K_IB | F_I]: the constraint
//!   modes Psi = -K_II^-1 K_IB and the load's static correction r = K_II^-1 F_I.
//! - Fixed-interface modes Phi of (K_II, M_II) below the cut-off, mass-normalised: by
//!   spectrum slicing ([`crate::analysis::modes::real_modes`]) when K_II is symmetric; when a
//!   kept pair's friction makes it unsymmetric, its right eigenvectors (the interior's CEA,
//!   real and imaginary parts, M_II-orthonormalised; see [`unsymmetric_modes`] for why not
//!   the modes of sym(K_II)).
//! - T = [[I, 0, 0], [Psi, Phi, r]] in the model's equation order, distributed like K;
//!   K_r = T^T K_t T, M_r = T^T M T, load T^T F.
//! - A model with linear constraints (a deck's `*TIE`, `*COUPLING`, `*EQUATION`; u = C x):
//!   all of the above in the solvers' free numbering, on C^T K_t C, C^T M C and C^T F (the
//!   constraints are part of the interior; the boundary's extra nodes are never dependent),
//!   and the basis kept as C T, in the model's numbering, for every expansion and
//!   projection after the build. Constraints that prescribe displacements (offsets g) are
//!   refused by name: the static correction would need the offsets' load.
//! - q_s: u_B read off the equilibrium; (eta, alpha) the M_II-weighted least-squares fit of
//!   u_I - Psi u_B by Phi eta + alpha r.
//!
//! Why q_s is exact. The equilibrium satisfies, on the interior rows,
//! K_II u_I + K_IB u_B + F_c,I(u) = F_I. The swept pairs act on B only (their points tie c_k
//! to d_k, both boundary nodes), so F_c,I comes from the kept pairs alone, and at the
//! equilibrium F_c(u) = J_c u + f0 (f0: the constant part of the kept contacts' affine
//! linearisation: slip forces, stick anchors, initial gaps). The super-element's load is
//! F - f0, so this is K_t,II u_I + K_t,IB u_B = F_I - f0_I, i.e.
//! u_I = Psi u_B + K_II^-1 (F_I - f0_I) = Psi u_B + r: the fit returns eta = 0, alpha = 1
//! and T q_s = u to the round-off of the solves and of the static residual. The fit's
//! M-norm residual is logged so that it can be seen.

use super::constraint_modes::{constraint_modes, InteriorBlocks};
use super::interface::ReducedInterface;
use super::residual_vectors::ResidualVectors;
use super::superelement::{BoundaryPair, BoundaryTilt, SuperElement, SuperElementHeader};
use crate::analysis::cea::{self, CeaError, CeaOptions};
use crate::analysis::modes::{self, ModeBand, ModesError, ModesOptions};
use crate::analysis::replicated_factor::ReplicatedFactor;
use crate::analysis::statics::{self, Configuration, StaticsError};
use crate::analysis::{band_count, block_lanczos};
use crate::contact::{self, ContactError, ContactPair};
use crate::model::Operators;
use crate::petsc::{Comm, DenseMatrix, IndexSet, Matrix, PetscError};
use faer::linalg::solvers::Solve;
use faer::Mat;

/// Why a super-element could not be built.
#[derive(Debug, thiserror::Error)]
pub enum SuperElementError {
    #[error("pair index {index} is out of range: the model has {pairs} contact pairs")]
    PairIndex { index: usize, pairs: usize },
    #[error("no swept pair given: a super-element needs a reduced interface to keep")]
    NoSweptPair,
    #[error("contact pair '{pair}' was not reduced (it is no pad of the reduced interface)")]
    NotReduced { pair: String },
    #[error("contact pair '{pair}', point {point}: not the node-to-node contact c_k/d_k of its reduced pad")]
    NotReducedPoint { pair: String, point: usize },
    #[error("node {node} of the reduced interface has a supported component: a reduced contact node must be free")]
    SupportedBoundary { node: usize },
    #[error("the model prescribes displacements through its constraints (a deck's *BOUNDARY with a value in a *TRANSFORM direction or an *EQUATION's offset, first from {first}): super-elements do not take prescribed displacements yet; compare the full model with its reduced interfaces (a study's superelements = [])")]
    Prescribed { first: String },
    #[error("the equilibrium has {given} nodes, the model {expected}")]
    EquilibriumSize { given: usize, expected: usize },
    #[error("the cut-off frequency must be positive and finite, got {0}")]
    Cutoff(f64),
    #[error("the swept pairs' friction must be finite and non-negative, got {0}")]
    Friction(f64),
    #[error("the equilibrium coordinates' normal equations are singular ({0})")]
    Fit(String),
    #[error("tangent of the kept contacts: {0}")]
    Statics(#[from] StaticsError),
    #[error("fixed-interface modes: {0}")]
    Modes(#[from] ModesError),
    #[error("fixed-interface modes of the unsymmetric interior: {0}")]
    InteriorCea(#[from] CeaError),
    #[error(transparent)]
    Contact(#[from] ContactError),
    #[error(transparent)]
    Petsc(#[from] PetscError),
}

/// The boundary in super-element order: for each swept pair's point, (pair, point, c, d).
struct Boundary {
    points: Vec<(usize, usize, usize, usize)>,
    /// Per point with a patch law whose tilt nodes an earlier point holds, that point
    /// ([`super::superelement::BoundaryTilt::shared`]).
    shared: Vec<Option<usize>>,
    /// The equations in super-element order (6 per point, 12 with a patch law's own tilt
    /// nodes), in the model's numbering.
    equations: Vec<usize>,
    /// The same in the solvers' numbering (the free one of a model with constraints: a
    /// reduced contact or tilt node is an extra node, which no constraint makes dependent).
    solver_equations: Vec<usize>,
}

fn boundary(
    reduced: &ReducedInterface,
    operators: &Operators,
    swept: &[usize],
) -> Result<Boundary, SuperElementError> {
    let model = &reduced.model;
    let pairs = model.pairs.len();
    if swept.is_empty() {
        return Err(SuperElementError::NoSweptPair);
    }
    if let Some(&index) = swept.iter().find(|&&i| i >= pairs) {
        return Err(SuperElementError::PairIndex { index, pairs });
    }
    for &i in swept {
        let name = &model.pairs[i].settings.name;
        if !reduced.pads.iter().any(|p| &p.pair == name) {
            return Err(SuperElementError::NotReduced { pair: name.clone() });
        }
    }
    let mut points = Vec::new();
    // Pads in order, nodes in grid order (the pads' order is the model's pair order).
    for pad in &reduced.pads {
        let Some(&i) = swept
            .iter()
            .find(|&&i| model.pairs[i].settings.name == pad.pair)
        else {
            continue;
        };
        let pair = &model.pairs[i];
        if pair.points.len() != pad.contact_nodes.len() {
            return Err(SuperElementError::NotReducedPoint {
                pair: pad.pair.clone(),
                point: pair.points.len().min(pad.contact_nodes.len()),
            });
        }
        for (k, point) in pair.points.iter().enumerate() {
            let (c, d) = (pad.contact_nodes[k], pad.disc_nodes[k]);
            if point.slave != [(c, 1.0)] || point.master != [(d, 1.0)] {
                return Err(SuperElementError::NotReducedPoint {
                    pair: pad.pair.clone(),
                    point: k,
                });
            }
            points.push((i, k, c, d));
        }
    }
    let dofs = &operators.dofs;
    let solver = operators.solver_dofs();
    let mut equations = Vec::with_capacity(12 * points.len());
    let mut solver_equations = Vec::with_capacity(12 * points.len());
    // Each tilt node pair is on the boundary once, after the first point that reads it: a
    // share on one line reads its neighbour's ([`super::tilt::slope_owners`]), and a
    // coordinate twice would make the constraint modes dependent.
    let mut holder = std::collections::HashMap::new();
    let mut shared = Vec::with_capacity(points.len());
    for (index, &(i, k, c, d)) in points.iter().enumerate() {
        // A patch law's tilt nodes follow c and d (the order of `super::superelement`).
        let mut tilt = model.pairs[i].points[k].tilt.as_ref().map(|t| t.nodes);
        let held = tilt.and_then(|nodes| match holder.entry(nodes) {
            std::collections::hash_map::Entry::Occupied(o) => Some(*o.get()),
            std::collections::hash_map::Entry::Vacant(v) => {
                v.insert(index);
                None
            }
        });
        shared.push(held);
        if held.is_some() {
            tilt = None;
        }
        for node in [c, d].into_iter().chain(tilt.into_iter().flatten()) {
            for component in 0..3 {
                let (Some(e), Some(s)) = (
                    dofs.equation(node, component),
                    solver.equation(node, component),
                ) else {
                    return Err(SuperElementError::SupportedBoundary { node });
                };
                equations.push(e);
                solver_equations.push(s);
            }
        }
    }
    Ok(Boundary {
        points,
        shared,
        equations,
        solver_equations,
    })
}

/// A super-element with its basis T (rows laid out like K's, columns in the order of
/// [`super::superelement`]): u = T q expands reduced coordinates to the model's equations.
pub struct CraigBampton<'rt> {
    pub superelement: SuperElement,
    pub basis: DenseMatrix<'rt>,
    /// The model's equations of the boundary coordinates, in super-element order.
    pub boundary_equations: Vec<usize>,
    /// Each boundary pair's contact point in the model: (pair index, point index).
    pub boundary_points: Vec<(usize, usize)>,
    /// What the residual vectors need, when [`BuildSettings::residual_vectors`] asked and
    /// the interior allows them.
    pub residual: Option<ResidualVectors<'rt>>,
}

/// What a super-element is made with besides its model and equilibrium.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BuildSettings {
    /// The swept pairs' mu at the equilibrium (for the header).
    pub friction: f64,
    /// Fixed-interface modes up to this frequency.
    pub cutoff_hz: f64,
    /// How many fixed-interface modes a super-element of the same model had (the previous
    /// one of a sweep): the unsymmetric interior's eigensolve then covers the band in one
    /// shift instead of several. A wrong hint costs time, never modes.
    pub interior_modes_hint: Option<usize>,
    /// Keep what residual vectors need ([`super::residual_vectors`]): the interior's factor
    /// and operators, in [`CraigBampton::residual`], where the interior is symmetric and has
    /// no constraints.
    pub residual_vectors: bool,
}

/// [`build_superelement`], keeping the basis T. Collective.
pub fn build_with_basis<'rt>(
    comm: Comm<'rt>,
    reduced: &ReducedInterface,
    operators: &Operators<'rt>,
    equilibrium: Configuration<'_>,
    swept: &[usize],
    settings: &BuildSettings,
) -> Result<CraigBampton<'rt>, SuperElementError> {
    build(comm, reduced, operators, equilibrium, swept, settings)
}

/// Builds the super-element of `reduced` at `equilibrium` (displacements of every node, mesh
/// and extra), with the contact of the pairs `swept` (indices into the model's pairs, each a
/// pad of `reduced`) removed and every other pair linearised there; fixed-interface modes up
/// to `cutoff_hz`; `friction` is the swept pairs' mu it was made at (for the header).
/// Collective; errors are collective.
pub fn build_superelement<'rt>(
    comm: Comm<'rt>,
    reduced: &ReducedInterface,
    operators: &Operators<'rt>,
    equilibrium: Configuration<'_>,
    swept: &[usize],
    friction: f64,
    cutoff_hz: f64,
) -> Result<SuperElement, SuperElementError> {
    let settings = BuildSettings {
        friction,
        cutoff_hz,
        interior_modes_hint: None,
        residual_vectors: false,
    };
    build(comm, reduced, operators, equilibrium, swept, &settings).map(|b| b.superelement)
}

fn build<'rt>(
    comm: Comm<'rt>,
    reduced: &ReducedInterface,
    operators: &Operators<'rt>,
    equilibrium: Configuration<'_>,
    swept: &[usize],
    settings: &BuildSettings,
) -> Result<CraigBampton<'rt>, SuperElementError> {
    let BuildSettings {
        friction,
        cutoff_hz,
        interior_modes_hint,
        residual_vectors,
    } = *settings;
    let model = &reduced.model;
    let Configuration {
        displacement: equilibrium,
        slip,
    } = equilibrium;
    if !(cutoff_hz.is_finite() && cutoff_hz > 0.0) {
        return Err(SuperElementError::Cutoff(cutoff_hz));
    }
    if !(friction.is_finite() && friction >= 0.0) {
        return Err(SuperElementError::Friction(friction));
    }
    let (kept, kept_slip) = kept_pairs(reduced, equilibrium, slip, swept)?;
    let boundary = boundary(reduced, operators, swept)?;
    let dofs = operators.solver_dofs();

    // 1. K_t and the load less the kept contacts' constant part (see [`linearised`]).
    let (k_t, effective_load) = linearised(comm, operators, &kept, &kept_slip, equilibrium)?;
    // A model with constraints (u = C x): the reduction is made in the solvers' numbering,
    // on C^T K_t C, C^T M C and C^T F, the constraints inside the interior; T goes back to
    // the model's equations as C T at the end, so that everything that expands with T or
    // projects on it sees the model's numbering either way.
    let constraints = operators.constraints.as_ref();
    if constraints.is_some_and(|c| c.prescribes) {
        return Err(SuperElementError::Prescribed {
            first: model
                .constraints
                .first()
                .map_or_else(String::new, |c| c.source.clone()),
        });
    }
    let projected_mass;
    let (k_t, effective_load, mass) = match constraints {
        Some(c) => {
            let mut f = c.free_vector()?;
            c.restrict_into(&effective_load, &mut f)?;
            projected_mass = c.project(&operators.mass)?;
            (c.project(&k_t)?, f, &projected_mass)
        }
        None => (k_t, effective_load, &operators.mass),
    };
    // Only friction of a kept pair makes K_t unsymmetric (decided from the data, the same on
    // every rank, rather than by a tolerance on the entries).
    let symmetric = kept.iter().all(|p| p.settings.friction == 0.0);

    // 2. Boundary and interior index sets (sorted for PETSc; `column` maps a sorted position
    // to the super-element's column).
    let n_b = boundary.solver_equations.len();
    let mut order: Vec<usize> = (0..n_b).collect();
    order.sort_by_key(|&j| boundary.solver_equations[j]);
    let sorted: Vec<usize> = order
        .iter()
        .map(|&j| boundary.solver_equations[j])
        .collect();
    let column = order;
    let (lo, hi) = k_t.ownership_range()?;
    let b_set = IndexSet::owned_subset(comm, lo..hi, &sorted)?;
    let i_set = b_set.complement(lo..hi)?;
    let mut k_ii = k_t.submatrix(&i_set, &i_set)?;
    let k_ib = k_t.submatrix(&i_set, &b_set)?;
    let mut m_ii = mass.submatrix(&i_set, &i_set)?;
    m_ii.mark_symmetric()?;
    let interior = i_set.indices()?;

    // 3. [Psi | r] = K_II^-1 [-K_IB | F_I] ([`constraint_modes`]).
    let load = effective_load.gather_all()?;
    // K_IB is sparse (only the interior neighbours of the boundary nodes have entries):
    // read by rows rather than made dense, which on the medium brake was 2 GB more at the
    // peak (a dense copy in PETSc and one in faer).
    let (sub_lo, _) = k_ib.ownership_range()?;
    let k_ib_rows: Vec<Vec<(usize, f64)>> = (0..interior.len())
        .map(|i| {
            let mut row = k_ib.row(sub_lo + i)?;
            row.sort_unstable_by_key(|&(c, _)| c);
            Ok(row)
        })
        .collect::<Result<_, PetscError>>()?;
    drop(k_ib);
    let started = std::time::Instant::now();
    let (solved_block, interior_factor) = constraint_modes(
        comm,
        InteriorBlocks {
            k_t: &k_t,
            k_ii: &mut k_ii,
            k_ib_rows,
            boundary: &sorted,
            interior: &interior,
            load: &load,
            symmetric,
        },
    )?;
    let constraint_seconds = started.elapsed().as_secs_f64();
    // Read by columns' slices: a faer view's element access cost 2 s more in writing T.
    let solved = &solved_block;
    let started = std::time::Instant::now();
    let (shapes, n_fixed, interior_factor) = if symmetric {
        k_ii.mark_symmetric()?;
        let (shapes, n) = symmetric_modes(comm, &k_ii, &m_ii, interior_factor.as_ref(), cutoff_hz)?;
        (shapes, n, interior_factor)
    } else {
        // Its LU is of K_II, not of the shifted pencils the CEA factors.
        drop(interior_factor);
        let (shapes, n) = unsymmetric_modes(comm, &k_ii, &m_ii, cutoff_hz, interior_modes_hint)?;
        (shapes, n, None)
    };
    let n_m = shapes.len();
    tracing::info!(
        "super-element: {n_b} boundary equations, {} interior, {n_fixed} fixed-interface modes below {cutoff_hz} Hz; constraint modes {constraint_seconds:.1} s, fixed-interface modes {:.1} s",
        k_t.size()?.0 - n_b,
        started.elapsed().as_secs_f64()
    );
    let started = std::time::Instant::now();

    // T in the model's equation order, this rank's rows, written straight into PETSc's
    // column-major array: each column's interior rows read one column of `solved` in
    // order. (Through a faer copy filled row by row, strided in both, this took 2.1 of the
    // 7.2 s of projections on small-caliper, and 430 MB a rank more at the peak.)
    let size = n_b + n_m + 1;
    // Per local row: its interior position, or its boundary column.
    enum Row {
        Interior(usize),
        Boundary(usize),
    }
    let mut rows: Vec<Option<Row>> = (lo..hi).map(|_| None).collect();
    for (p, &g) in interior.iter().enumerate() {
        rows[g - lo] = Some(Row::Interior(p));
    }
    for (s, &g) in sorted.iter().enumerate() {
        if (lo..hi).contains(&g) {
            rows[g - lo] = Some(Row::Boundary(column[s]));
        }
    }
    let rows: Vec<Row> = rows
        .into_iter()
        .map(|r| r.expect("interior and boundary partition the rank's rows"))
        .collect();
    // T's boundary column j is `solved`'s column position s with column[s] = j.
    let mut position = vec![0; n_b];
    for (s, &j) in column.iter().enumerate() {
        position[j] = s;
    }
    let mut t = DenseMatrix::zeros(comm, hi - lo, size)?;
    t.write_local(|i, j| match rows[i] {
        Row::Interior(p) if j < n_b => solved.column(position[j])[p],
        Row::Interior(p) if j < n_b + n_m => shapes[j - n_b][p],
        Row::Interior(p) => solved.column(n_b)[p],
        Row::Boundary(c) if c == j => 1.0,
        Row::Boundary(_) => 0.0,
    })?;
    // T's last n_m + 1 columns (fixed-interface modes, static correction), zero on the
    // boundary, for K_t's projection on them.
    let mut t_modal = DenseMatrix::zeros(comm, hi - lo, n_m + 1)?;
    t_modal.write_local(|i, j| match rows[i] {
        Row::Interior(p) if j < n_m => shapes[j][p],
        Row::Interior(p) => solved.column(n_b)[p],
        Row::Boundary(_) => 0.0,
    })?;
    drop(rows);

    // 4. Projections.
    let stiffness = project_stiffness(comm, &k_t, &b_set, &t, &t_modal, &column)?;
    drop(t_modal);
    let mass_r = mass.project_symmetric(&t)?;
    let f = DenseMatrix::from_columns(comm, &[effective_load.copy()?])?;
    let projected_load = t.transpose_mult(&f)?;
    let load_r: Vec<f64> = (0..size).map(|i| projected_load[(i, 0)]).collect();

    tracing::info!(
        "super-element: T and the projections K_r = T^T K_t T, M_r = T^T M T {:.1} s",
        started.elapsed().as_secs_f64()
    );

    // q_s: boundary from the equilibrium; (eta, alpha) fitting w = u_I - Psi u_B in the
    // M_II norm: C = [Phi r], (C^T M_II C) x = C^T M_II w.
    let u_all = {
        let mut u = vec![0.0; dofs.equations()];
        for (node, d) in equilibrium.iter().enumerate() {
            for (c, &v) in d.iter().enumerate() {
                if let Some(eq) = dofs.equation(node, c) {
                    u[eq] = v;
                }
            }
        }
        u
    };
    let u_b: Vec<f64> = boundary
        .solver_equations
        .iter()
        .map(|&g| u_all[g])
        .collect();
    let mut fit = DenseMatrix::zeros(comm, interior.len(), n_m + 2)?;
    fit.write_local(|p, j| {
        if j < n_m {
            shapes[j][p]
        } else if j == n_m {
            solved.column(n_b)[p]
        } else {
            let psi_u: f64 = (0..n_b).map(|s| solved.column(s)[p] * u_b[column[s]]).sum();
            u_all[interior[p]] - psi_u
        }
    })?;
    let m_fit = m_ii.mult_tall(&fit)?;
    let gram = fit.transpose_mult(&m_fit)?;
    let n_c = n_m + 1;
    let g = Mat::<f64>::from_fn(n_c, n_c, |i, j| gram[(i, j)]);
    let b = Mat::<f64>::from_fn(n_c, 1, |i, _| gram[(i, n_c)]);
    let x = g
        .llt(faer::Side::Lower)
        .map_err(|e| SuperElementError::Fit(format!("{e:?}")))?
        .solve(&b);
    // |w - C x|_M^2 = w^T M w - 2 x^T b + x^T G x.
    let mut residual = gram[(n_c, n_c)];
    for i in 0..n_c {
        residual -= 2.0 * x[(i, 0)] * b[(i, 0)];
        for j in 0..n_c {
            residual += x[(i, 0)] * g[(i, j)] * x[(j, 0)];
        }
    }
    tracing::info!(
        "super-element equilibrium fit: alpha = {:.15}, M-norm residual {:.3e} of {:.3e}",
        x[(n_m, 0)],
        residual.max(0.0).sqrt(),
        gram[(n_c, n_c)].max(0.0).sqrt()
    );
    let mut q_s = u_b;
    q_s.extend((0..n_c).map(|i| x[(i, 0)]));
    let residual = match (residual_vectors, interior_factor) {
        (true, Some(factor)) if constraints.is_none() => {
            let c = fit.local_values()?;
            let m_c = m_fit.local_values()?;
            Some(ResidualVectors {
                factor,
                mass: mass.duplicate()?,
                m_ii,
                load: effective_load.copy()?,
                interior: interior.clone(),
                first_row: lo,
                c: c.subcols(0, n_c).to_owned(),
                m_c: m_c.subcols(0, n_c).to_owned(),
                gram: g.clone(),
                k_t,
            })
        }
        _ => None,
    };

    // 5. The header.
    let mut pairs_out = Vec::with_capacity(boundary.points.len());
    for (&(i, k, c, d), &shared) in boundary.points.iter().zip(&boundary.shared) {
        let pair = &model.pairs[i];
        let point = &pair.points[k];
        let state = contact::point_state(pair, point, slip.anchor(i, k), equilibrium)?;
        pairs_out.push(BoundaryPair {
            pair: pair.settings.name.clone(),
            pad_position: model.position(c),
            disc_position: model.position(d),
            normal: point.normal,
            sliding: point.tangent,
            initial_gap: point.initial_gap,
            area: point.area,
            penalty: pair.penalty,
            separation: pair.settings.separation,
            normal_force: state.normal_force,
            tilt: point.tilt.as_ref().map(|t| BoundaryTilt {
                axes: t.axes,
                patch: t.patch.clone(),
                arm: t.arm,
                shared,
            }),
            // A kept pair on the boundary keeps its own law (the sweep's friction is the
            // swept pairs').
            own_law: (!model.swept[i]).then(|| pair.settings.clone()),
        });
    }
    let other_contacts = kept
        .iter()
        .enumerate()
        .map(|(i, pair)| {
            let states = pair
                .points
                .iter()
                .enumerate()
                .map(|(k, pt)| {
                    contact::point_state(pair, pt, kept_slip.anchor(i, k), equilibrium)
                        .map(|s| s.status)
                })
                .collect::<Result<Vec<_>, _>>()?;
            Ok((pair.settings.name.clone(), states))
        })
        .collect::<Result<Vec<_>, ContactError>>()?;
    let superelement = SuperElement {
        header: SuperElementHeader {
            units: "SI".into(),
            friction,
            cutoff_hz,
            modes: n_m,
            size,
            residual_vectors: 0,
            other_contacts,
            mesh_hash: String::new(),
            study_hash: String::new(),
            boundary: pairs_out,
        },
        stiffness,
        mass: mass_r,
        load: load_r,
        equilibrium: q_s,
    };
    let basis = match constraints {
        Some(c) => c.matrix.mult_dense(&t)?,
        None => t,
    };
    Ok(CraigBampton {
        superelement,
        basis,
        boundary_points: boundary.points.iter().map(|&(i, k, _, _)| (i, k)).collect(),
        boundary_equations: boundary.equations,
        residual,
    })
}

/// K_r = T^T K_t T by the Craig-Bampton structure of T = [[I, 0, 0], [Psi, Phi, r]]
/// (boundary rows, then interior). K_t T's interior rows in the boundary columns are
/// K_IB + K_II Psi = 0, the constraint modes' own equation (to the block solve's residual,
/// whatever K_t's symmetry), so T^T K_t T_B is K_t T_B's boundary rows, K_BB + K_BI Psi, over
/// zeros in the modal and load rows: K_t's boundary rows times T, a product of a few
/// thousand sparse rows. Only the n_m + 1 other columns (`t_modal`) need K_t T_m on every
/// row and T^T (K_t T_m). On small-caliper (every pair on the boundary, 1,722 of 1,801
/// columns) K_t T on every row and every column took 1.7 s, of which this keeps a tenth.
/// `column[s]` is the column of T of the s-th boundary equation in increasing order, the
/// order of `b_set`'s rows. Collective; every rank gets the same bits.
fn project_stiffness<'rt>(
    comm: Comm<'rt>,
    k_t: &Matrix<'rt>,
    b_set: &IndexSet<'rt>,
    t: &DenseMatrix<'rt>,
    t_modal: &DenseMatrix<'rt>,
    column: &[usize],
) -> Result<Mat<f64>, PetscError> {
    let size = t.size()?.1;
    let n_b = column.len();
    // K_t's boundary rows, every column distributed as K_t's (so as T's rows).
    let (lo, hi) = k_t.ownership_range()?;
    let owned: Vec<usize> = (lo..hi).collect();
    let all = IndexSet::new(comm, &owned)?;
    let k_b = k_t.submatrix(b_set, &all)?;
    drop(all);
    let boundary_rows = k_b.mult_tall(t)?.to_faer()?;
    drop(k_b);
    let kt = k_t.mult_tall(t_modal)?;
    let mut local = Mat::<f64>::zeros(size, size - n_b);
    t.with_local(|tl| {
        kt.with_local(|kl| {
            faer::linalg::matmul::matmul(
                local.as_mut(),
                faer::Accum::Replace,
                tl.transpose(),
                kl,
                1.0,
                faer::Par::Seq,
            );
        })
    })??;
    let mut values: Vec<f64> = (0..size - n_b)
        .flat_map(|j| (0..size).map(move |i| (i, j)))
        .map(|(i, j)| local[(i, j)])
        .collect();
    comm.sum_identically(&mut values);
    let mut k_r = Mat::<f64>::zeros(size, size);
    for (s, &j) in column.iter().enumerate() {
        for c in 0..n_b {
            k_r[(j, c)] = boundary_rows[(s, c)];
        }
    }
    for j in n_b..size {
        for i in 0..size {
            k_r[(i, j)] = values[(j - n_b) * size + i];
        }
    }
    Ok(k_r)
}

/// The pairs a super-element keeps (every pair but the swept ones) with their slip history,
/// after checking that the equilibrium is one of this model's.
fn kept_pairs(
    reduced: &ReducedInterface,
    equilibrium: &[[f64; 3]],
    slip: &contact::SlipHistory,
    swept: &[usize],
) -> Result<(Vec<ContactPair>, contact::SlipHistory), SuperElementError> {
    let model = &reduced.model;
    if equilibrium.len() != model.node_count() {
        return Err(SuperElementError::EquilibriumSize {
            given: equilibrium.len(),
            expected: model.node_count(),
        });
    }
    let kept_indices: Vec<usize> = (0..model.pairs.len())
        .filter(|i| !swept.contains(i))
        .collect();
    let kept = kept_indices
        .iter()
        .map(|&i| model.pairs[i].clone())
        .collect();
    Ok((kept, slip.subset(&kept_indices)))
}

/// The model linearised at an equilibrium with the swept contact removed: K_t = K + the
/// kept pairs' tangent (Coulomb pairs: the consistent tangent of their stick or slip state),
/// and the load less the constant part of the kept contacts' affine linearisation.
///
/// The kept contacts linearised at the equilibrium are affine, not linear:
/// F_c(u) ~ F_c(u_s) + J_c (u - u_s) = J_c u + f0 with f0 = F_c(u_s) - J_c u_s (a slipping
/// point's force mu p s and a sticking point's anchor are not J_c u). The constant part acts
/// as a load: the super-element carries F - f0, so that T holds the equilibrium exactly
/// (eq. 5) whatever the kept pairs' states. Without it, a per-friction super-element of the
/// floating-caliper brake missed its own equilibrium by 10 % of the load (alpha 0.995 in the
/// fit) at every mu where a kept pair slipped. Collective.
fn linearised<'rt>(
    comm: Comm<'rt>,
    operators: &Operators<'rt>,
    kept: &[ContactPair],
    kept_slip: &contact::SlipHistory,
    equilibrium: &[[f64; 3]],
) -> Result<(Matrix<'rt>, crate::petsc::Vector<'rt>), SuperElementError> {
    let dofs = &operators.dofs;
    let mut k_t = operators.stiffness.duplicate()?;
    if !kept.is_empty() {
        statics::add_contact_tangent(comm, &mut k_t, dofs, kept, kept_slip, equilibrium, 1.0)?;
    }
    let mut f = operators.load.copy()?;
    if !kept.is_empty() {
        let (mut u_s, mut k_u) = operators.stiffness.vectors()?;
        let (lo, hi) = u_s.ownership_range()?;
        let mut local = vec![0.0; hi - lo];
        for (node, d) in equilibrium.iter().enumerate() {
            for (c, &v) in d.iter().enumerate() {
                if let Some(eq) = dofs.equation(node, c) {
                    if (lo..hi).contains(&eq) {
                        local[eq - lo] = v;
                    }
                }
            }
        }
        u_s.set_local(&local)?;
        // f0 = F_c(u_s) - (K_t - K) u_s, subtracted from F.
        let mut f0 = u_s.duplicate()?;
        f0.set(0.0)?;
        statics::add_contact_forces(comm, &mut f0, dofs, kept, kept_slip, equilibrium)?;
        k_t.mult(&u_s, &mut k_u)?;
        f0.axpy(-1.0, &k_u)?;
        operators.stiffness.mult(&u_s, &mut k_u)?;
        f0.axpy(1.0, &k_u)?;
        f.axpy(-1.0, &f0)?;
    }
    Ok((k_t, f))
}

/// Projects the model linearised at another equilibrium onto an existing super-element's
/// basis: K_r = T^T K_t T and the load T^T (F - f0), with K_t and f0 from the kept contacts
/// at `equilibrium` (see [`linearised`]). M_r, the basis and the boundary stay.
///
/// This is how the adaptive strategy reuses a super-element whose kept contacts kept their
/// states: the basis T was made at another friction value, but the operator it reduces is
/// this one's. Reusing the old K_r instead carries the old tangent (a slipping point's
/// friction block follows its pressure and slip direction, which change with mu even when
/// the state does not), a first-order error in the eigenvalues: on the floating caliper the
/// reused points were 1.1-2.0 % off where the built ones were 0.4 %. Projected anew, only
/// the basis is old, an error of second order (Rayleigh-Ritz). The cost is one sparse
/// product with T and one dense product, against a build's factorisation and eigensolve.
/// Collective.
pub fn reproject<'rt>(
    comm: Comm<'rt>,
    reduced: &ReducedInterface,
    operators: &Operators<'rt>,
    equilibrium: Configuration<'_>,
    swept: &[usize],
    basis: &super::LocalBasis,
    superelement: &mut SuperElement,
) -> Result<(), SuperElementError> {
    let Configuration {
        displacement: equilibrium,
        slip,
    } = equilibrium;
    let (kept, kept_slip) = kept_pairs(reduced, equilibrium, slip, swept)?;
    let (k_t, effective_load) = linearised(comm, operators, &kept, &kept_slip, equilibrium)?;
    let rows = basis.rows();
    let mut t = DenseMatrix::zeros(comm, rows.len(), basis.size())?;
    t.write_local(|i, j| basis.value(i, j))?;
    superelement.stiffness = k_t.project(&t)?;
    superelement.load = basis.project(comm, &effective_load.read()?);
    Ok(())
}

/// Relative size (of the largest) below which a direction of the interior basis is taken
/// as already in the span of the others.
const SPAN_TOLERANCE: f64 = 1e-10;

/// The fixed-interface modes' convergence (the shift-and-invert residual against theta) in
/// the block run: 1e-8 rather than the 1e-10 of real modes. A super-element's modes are
/// Rayleigh-Ritz values over span(T), so a basis vector off by e moves them by about e times
/// their own truncation error: measured on small-caliper (nine friction values), the same
/// 503 eigenvalues as with SLEPc's modes at 1e-10 to 1.2e-8 in frequency and 1.1e-4 1/s in
/// real part, the same flags. And 1e-10 lies at the estimate's round-off floor there
/// (eps theta_max / theta, theta_max of the interior's lowest mode): the last pairs' estimates
/// stalled between 1e-10 and 1e-9 from step 16 on.
const FIXED_INTERFACE_TOLERANCE: f64 = 1e-8;

/// The fixed-interface modes of a symmetric K_II below the cut-off (this rank's rows of
/// each, M-orthonormal) and their count: by block Lanczos on the constraint modes' own
/// factor where every rank has one ([`block_lanczos`]), the band's count from one inertia
/// (as SLEPc's path counts it); by SLEPc's real modes where the ranks share a factor, or
/// where the block run does not converge within its subspace.
fn symmetric_modes<'rt>(
    comm: Comm<'rt>,
    k_ii: &Matrix<'rt>,
    m_ii: &Matrix<'rt>,
    factor: Option<&ReplicatedFactor<'rt>>,
    cutoff_hz: f64,
) -> Result<(Vec<Vec<f64>>, usize), SuperElementError> {
    if let Some(factor) = factor {
        let top = (2.0 * std::f64::consts::PI * cutoff_hz).powi(2);
        let count = crate::petsc::eigenvalues_below(comm, k_ii, m_ii, top)?;
        if let Some(found) = block_lanczos::lowest_modes(
            comm,
            factor,
            k_ii,
            m_ii,
            count,
            top,
            FIXED_INTERFACE_TOLERANCE,
        )? {
            let shapes: Vec<Vec<f64>> = (0..count)
                .map(|q| found.shapes.col(q).iter().copied().collect())
                .collect();
            tracing::info!(
                "fixed-interface modes: {count} below {cutoff_hz} Hz by block Lanczos on the \
                 constraint modes' factor, {} steps ({} solves)",
                found.steps,
                found.solves,
            );
            return Ok((shapes, count));
        }
        tracing::info!(
            "fixed-interface modes: block Lanczos did not converge for the {count} below \
             {cutoff_hz} Hz; SLEPc's Krylov-Schur instead"
        );
    }
    let found = modes::real_modes(
        comm,
        k_ii,
        m_ii,
        &ModesOptions {
            band: ModeBand::Below {
                max_frequency_hz: cutoff_hz,
            },
            ..Default::default()
        },
    )?;
    let shapes: Vec<Vec<f64>> = found
        .shapes
        .iter()
        .map(|v| Ok(v.read()?.to_vec()))
        .collect::<Result<_, PetscError>>()?;
    let n = shapes.len();
    Ok((shapes, n))
}

/// The fixed-interface modes when a kept contact's friction makes K_II unsymmetric: the
/// right eigenvectors of (K_II, M_II) below the cut-off (the CEA of the interior), real and
/// imaginary parts of each, M_II-orthonormalised. Returns the basis and the number of
/// eigenvalues it came from.
///
/// Why not the modes of sym(K_II). A slipping point of a kept pair adds `mu k A s n^T`,
/// whose symmetric part `mu k A (s n^T + n s^T) / 2` is indefinite on the point's (n, s)
/// plane: with penalty stiffness, sym(K_II) of the floating-caliper brake has eigenvalues
/// far below zero, which no band [0, f_cut] holds, and the Galerkin projection of K_t onto
/// the modes of sym(K_II) (even with their static corrections for the skew part) placed
/// five spurious divergence modes at 0 Hz in the per-friction super-element at mu 0.5
/// (tiny-caliper, 22 nodes per pad, 18 kHz). A subspace invariant under
/// (K_II, M_II) projects to exactly its own eigenvalues, whatever the symmetry.
fn unsymmetric_modes<'rt>(
    comm: Comm<'rt>,
    k_ii: &Matrix<'rt>,
    m_ii: &Matrix<'rt>,
    cutoff_hz: f64,
    expected: Option<usize>,
) -> Result<(Vec<Vec<f64>>, usize), SuperElementError> {
    let expected = match expected {
        Some(n) => Some(n),
        // A guess that cannot be made (its LDL^T failed on every rank alike) costs the
        // CEA a few windows, never modes: go on without it.
        None => match symmetric_part_count(comm, k_ii, m_ii, cutoff_hz) {
            Ok(n) => Some(n),
            Err(SuperElementError::Petsc(failure @ PetscError::NotConverged { .. })) => {
                tracing::warn!(
                    "the fixed-interface modes are found without a first count: {failure}"
                );
                None
            }
            Err(other) => return Err(other),
        },
    };
    let found = cea::undamped(
        comm,
        k_ii,
        m_ii,
        &CeaOptions {
            max_frequency_hz: cutoff_hz,
            expected_modes: expected,
            ..Default::default()
        },
    )?;
    let count = found.modes.len();
    let mut columns = Vec::with_capacity(2 * count);
    for (re, im) in &found.shapes {
        columns.push(re.read()?.to_vec());
        columns.push(im.read()?.to_vec());
    }
    drop(found);
    Ok((m_orthonormal(comm, m_ii, &columns)?, count))
}

/// How many modes the symmetric part (K_II + K_II^T) / 2 has below the cut-off
/// ([`band_count`]): the first build's guess of how many the band holds, the CEA's
/// `expected_modes`, where stepping up from 0 Hz window by window took 8-9 shifts on the
/// small caliper. Later builds of a sweep take the previous build's count instead.
fn symmetric_part_count<'rt>(
    comm: Comm<'rt>,
    k_ii: &Matrix<'rt>,
    m_ii: &Matrix<'rt>,
    cutoff_hz: f64,
) -> Result<usize, SuperElementError> {
    let top = (2.0 * std::f64::consts::PI * cutoff_hz).powi(2);
    Ok(band_count::symmetric_part_below(comm, k_ii, m_ii, top)?)
}

/// An M-orthonormal basis of the span of `columns` (this rank's rows), without the
/// directions below [`SPAN_TOLERANCE`] of the largest: the eigenvectors of their Gram matrix.
/// Every rank holds the same Gram matrix, so every rank keeps the same directions.
fn m_orthonormal<'rt>(
    comm: Comm<'rt>,
    m: &Matrix<'rt>,
    columns: &[Vec<f64>],
) -> Result<Vec<Vec<f64>>, SuperElementError> {
    let n = columns.len();
    if n == 0 {
        return Ok(Vec::new());
    }
    let rows = columns[0].len();
    // Unit M-norm first, so that the tolerance compares directions, not lengths.
    let mut v = DenseMatrix::zeros(comm, rows, n)?;
    v.write_local(|i, j| columns[j][i])?;
    let gram = v.transpose_mult(&m.mult_dense(&v)?)?;
    let scale: Vec<f64> = (0..n)
        .map(|j| {
            let d = gram[(j, j)];
            if d > 0.0 {
                1.0 / d.sqrt()
            } else {
                0.0
            }
        })
        .collect();
    let g = Mat::<f64>::from_fn(n, n, |i, j| scale[i] * gram[(i, j)] * scale[j]);
    let evd = g
        .self_adjoint_eigen(faer::Side::Lower)
        .map_err(|err| SuperElementError::Fit(format!("interior basis' Gram matrix: {err:?}")))?;
    let (values, vectors) = (evd.S().column_vector(), evd.U());
    let largest = (0..n).map(|k| values[k]).fold(0.0, f64::max);
    let keep: Vec<usize> = (0..n)
        .filter(|&k| values[k] > SPAN_TOLERANCE * largest)
        .collect();
    Ok(keep
        .iter()
        .map(|&k| {
            let s = 1.0 / values[k].sqrt();
            (0..rows)
                .map(|i| {
                    s * (0..n)
                        .map(|j| columns[j][i] * scale[j] * vectors[(j, k)])
                        .sum::<f64>()
                })
                .collect()
        })
        .collect())
}
