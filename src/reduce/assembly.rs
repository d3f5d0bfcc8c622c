//! The super-element assembly (METHOD.md section 7; the paper's sections 3.2.2, 3.2.3): the
//! dense reduced model of a [`SuperElement`] with its swept contact put back as node-to-node
//! cubic springs, its non-linear static at any friction value, its linearisation and the
//! dense complex eigenvalue analysis.
//!
//! Per boundary pair k, from its offset o_k, with u_p = q[o_k..o_k+3] (pad contact node),
//! u_d = q[o_k+3..o_k+6] (disc node), n the disc normal (out of the disc, towards the pad) and
//! t the sliding direction:
//!
//! ```text
//!   g  = g0 + n . (u_p - u_d)            geometric gap, negative = penetration
//!   d  = -g                              approach, positive = penetration
//!   s  = d + xi                          matched approach (xi: eq. 8)
//!   F  = k_l s + k_nl s^3                if s >= 0 or the pair is bilateral, else 0 (eq. 6)
//!   on the pad:  +F (n + mu t)           on the disc node: -F (n + mu t)
//! ```
//!
//! The residual follows the internal-force convention of `crate::contact::penalty`:
//! R(q) = K_r q + F_c(q) - T^T F_ext with F_c = minus the contact forces, so its Jacobian's
//! contact blocks are c_a c_b F'(s) (n + mu t) n^T (c = +1 pad, -1 disc), the same blocks as
//! the full model's penalty law with k A replaced by F'(s).
//!
//! Touching (s = 0) counts as closed, as in the penalty law: the force is 0 there either way,
//! and the pair keeps its stiffness k_l in the tangent.
//!
//! Force matching (eq. 8): xi is chosen per pair so that F(d_s + xi) = F_nl, the full
//! model's normal force at the super-element's equilibrium q_s: then K_r q_s + F_c(q_s) is the
//! full model's K q + F_c at its equilibrium, and R(q_s) = 0 (eq. 5) at the super-element's
//! own friction value. A pair that is open in the full model (F_nl = 0, separation allowed)
//! keeps its geometric gap (xi = 0): it stays open at q_s and closes where the full model's
//! would. (Were its geometric approach d_s >= 0, which a consistent full model cannot give
//! with F_nl = 0 except by exactly touching, it is put exactly at contact, s = 0.)
//!
//! A pair with a patch law ([`super::superelement::BoundaryTilt`], squeal's addition) has its
//! tilt nodes r_p, r_d at q[o_k+6..o_k+12] and carries the reduced-interface model's own law,
//! [`crate::contact::Tilt`]: each quadrature point of its share k_n a max(0, -(g + theta .
//! xi)). It is evaluated by the full model's own code ([`contact::evaluate`] on the pair's
//! four boundary nodes), so the dense model and the reduced-interface model cannot disagree
//! on it, and no force matching is needed: the law is the one F_nl was computed with, at the
//! same coordinates, so R(q_s) = 0 holds as it is. The cubic law's k_l and k_nl stand for a
//! point contact's stiffness and are refused with it.
//!
//! A kept pair reduced onto the boundary ([`BoundaryPair::own_law`]: the super-element's
//! interior then holds no contact, issue 32) carries its own law the same way: its point is
//! evaluated by [`contact::evaluate`] on its two boundary nodes with its own settings
//! (Coulomb stick and slip, its own friction, separation), from the slip history the
//! assembly holds ([`Assembly::with_history`]). The static's return mapping starts from that
//! history (backward Euler, as the full model's increments) and hands the next one on
//! ([`ReducedStatic::anchors`]); the CEA's tangent is formed from the history after the
//! static (the committed one, as [`contact::perturbation_history`] does for the full model).

pub use super::dense_cea::{
    dense_cea, dense_cea_by, DenseCeaOptions, DenseCeaResult, DenseEigensolver,
};
use super::superelement::{BoundaryPair, SuperElement};
use super::tangent_solver::TangentSolver;
use crate::contact::{
    self, ContactPair, ContactPoint, PairSettings, PointContribution, PointState, Status,
};
use crate::vector3::{add, dot, scale, sub};
use faer::Mat;

/// The cubic contact law's stiffnesses (eq. 6), the same for every boundary pair.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct CubicContact {
    /// k_l, N/m; `None`: each pair's full-model stiffness, penalty * area (then with
    /// `k_cubic = 0` the assembly reproduces the full model's linear penalty law exactly).
    pub k_linear: Option<f64>,
    /// k_nl, N/m^3 (>= 0).
    pub k_cubic: f64,
}

impl Default for CubicContact {
    fn default() -> Self {
        CubicContact {
            k_linear: None,
            k_cubic: 0.0,
        }
    }
}

/// One boundary pair's contact law after force matching.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct PairLaw {
    pub k_linear: f64,
    pub k_cubic: f64,
    /// xi of eq. 8: added to the geometric approach.
    pub offset: f64,
    /// Whether the pair may open (else bilateral: the cubic holds for any s, may pull).
    pub separation: bool,
}

impl PairLaw {
    /// Whether the law is active at matched approach s (touching counts as closed).
    pub fn closed(&self, s: f64) -> bool {
        !self.separation || s >= 0.0
    }

    /// F(s) = k_l s + k_nl s^3 where closed, else 0.
    pub fn force(&self, s: f64) -> f64 {
        if self.closed(s) {
            self.k_linear * s + self.k_cubic * (s * s * s)
        } else {
            0.0
        }
    }

    /// dF/ds.
    pub fn tangent(&self, s: f64) -> f64 {
        if self.closed(s) {
            self.k_linear + 3.0 * self.k_cubic * (s * s)
        } else {
            0.0
        }
    }
}

/// Whether a cubic law's k_l stays within 1/eps either way of the contact it stands for,
/// `natural` = penalty x area (a `natural` of 0 has no scale to hold it to). Beyond it
/// double precision cannot weigh one against the other: more than 1/eps times it and the
/// assembled stiffness keeps no digit of the structure's; less than eps times it and the
/// contact is absent in floating point while the static approach f/k_l runs to eps^-1 times
/// the penalty's (`--k-linear 1e-300` once ended in "dense eigensolver: NoConvergence").
pub fn k_linear_resolved(k_linear: f64, natural: f64) -> bool {
    natural <= 0.0 || (f64::EPSILON..=1.0 / f64::EPSILON).contains(&(k_linear / natural))
}

/// The real root s of the monotone cubic k_nl s^3 + k_l s = f (k_l > 0, k_nl >= 0).
///
/// Newton from the upper bound min(|f| / k_l, (|f| / k_nl)^(1/3)) (each term alone reaches
/// |f| there): the cubic is increasing and convex on s > 0, so the iterates decrease
/// monotonically onto the root, and stop when round-off ends the decrease. The odd symmetry
/// gives negative f. Cardano's formula was not used: with k_nl s^2 << k_l its two cube roots
/// nearly cancel and lose the digits that the 1e-12 force match needs.
pub fn cubic_root(k_linear: f64, k_cubic: f64, f: f64) -> f64 {
    if f == 0.0 {
        return 0.0;
    }
    if k_cubic == 0.0 {
        return f / k_linear;
    }
    let target = f.abs();
    let mut s = (target / k_linear).min((target / k_cubic).cbrt());
    for _ in 0..200 {
        let g = k_cubic * (s * s * s) + k_linear * s - target;
        let next = s - g / (k_linear + 3.0 * k_cubic * (s * s));
        if next >= s || !next.is_finite() {
            break;
        }
        s = next;
    }
    s.copysign(f)
}

/// What can go wrong in the dense assembly, its static and its CEA.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum AssemblyError {
    /// The super-element's arrays disagree with its header or with each other.
    #[error("super-element: {0}")]
    Inconsistent(String),
    /// Contact stiffnesses that cannot be used.
    #[error("cubic contact: {0}")]
    InvalidContact(String),
    /// A boundary pair whose data cannot be matched.
    #[error("boundary pair {index} (pair '{pair}'): {why}")]
    InvalidPair {
        index: usize,
        pair: String,
        why: String,
    },
    /// The Jacobian could not be solved (a non-finite Newton step).
    #[error("reduced static at mu = {friction}: singular Jacobian at iteration {iteration}")]
    Singular { friction: f64, iteration: usize },
    /// Newton did not reach the tolerance.
    #[error(
        "reduced static at mu = {friction}: no convergence after {iterations} iteration(s) \
         (|R| must fall to {tolerance:.3e}); residual history {}",
        show_history(.history)
    )]
    NotConverged {
        friction: f64,
        iterations: usize,
        tolerance: f64,
        history: Vec<f64>,
    },
    /// The reduced mass is not symmetric positive definite (its Cholesky failed).
    #[error("the reduced mass is not positive definite (Cholesky failed)")]
    MassNotPositiveDefinite,
    /// The dense eigensolver failed (non-finite input or no convergence).
    #[error("dense eigensolver: {0}")]
    Eigen(String),
}

fn show_history(history: &[f64]) -> String {
    let items: Vec<String> = history.iter().map(|r| format!("{r:.3e}")).collect();
    format!("[{}]", items.join(", "))
}

/// One boundary pair's state for some q.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct PairState {
    /// Matched approach s = d + xi (positive = closed with a positive force).
    pub approach: f64,
    /// Normal force F(s) on the pad.
    pub force: f64,
    pub closed: bool,
    /// Open, stick or slip (a closed swept pair slips along its sliding direction).
    pub status: Status,
    /// The friction force on the pad contact node.
    pub friction_force: [f64; 3],
    /// The slip anchor after this state (a kept Coulomb pair's; zero otherwise): the
    /// history the next friction value starts from.
    pub anchor: [f64; 3],
}

/// Newton settings for the reduced static.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StaticOptions {
    /// Converged when |R| <= tolerance * |load|.
    pub tolerance: f64,
    pub max_iterations: usize,
    pub line_search: LineSearch,
}

impl Default for StaticOptions {
    fn default() -> Self {
        StaticOptions {
            tolerance: 1e-10,
            max_iterations: 50,
            line_search: LineSearch::Backtracking,
        }
    }
}

/// How far along the Newton direction d a step goes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LineSearch {
    /// Armijo backtracking on |R|: halved until |R| falls.
    Backtracking,
    /// The critical point of the residual's work along d, <R(q + l d), d> = 0, by secants
    /// from l = 0 and 1, capped at the Newton step (PETSc's `cp`, the full model's first
    /// choice, `crate::analysis::statics`). Backtracking on |R| stalls where a kept Coulomb
    /// point sits at a kink of its law: tiny-caliper with every pair on the boundary kept
    /// 40 % of the residual for 14 iterations from rest, an abutment point touching at a
    /// gap of 1e-15 m, whatever the load increment.
    CriticalPoint,
}

/// Secant steps of the critical-point line search (PETSc's `cp` takes one by default; a
/// few more settle l where a contact changes state inside the step).
const CRITICAL_POINT_SECANTS: usize = 3;

/// A converged reduced static.
#[derive(Clone, Debug, PartialEq)]
pub struct ReducedStatic {
    pub friction: f64,
    pub q: Vec<f64>,
    /// Newton steps taken (0 when the start already satisfied the tolerance); along a path
    /// ([`super::dense_path`]), every step of every increment.
    pub iterations: usize,
    /// Dense LU factorisations those steps made ([`TangentSolver`]: a step is solved on an
    /// earlier LU of the same solve where GMRES gets there).
    pub factorizations: usize,
    /// |R| at the start and after every step (along a path: the last solve's).
    pub residual_history: Vec<f64>,
    pub pairs: Vec<PairState>,
    /// Attempts that failed on the way and were taken again in smaller steps (a path's).
    pub cutbacks: usize,
}

impl ReducedStatic {
    /// The slip history after it, one anchor per boundary pair: what the next friction
    /// value starts from and what the CEA's tangent is formed from.
    pub fn anchors(&self) -> Vec<[f64; 3]> {
        self.pairs.iter().map(|p| p.anchor).collect()
    }
}

/// The assembled reduced model of one super-element with its cubic contact laws matched.
#[derive(Clone, Debug)]
pub struct Assembly<'se> {
    se: &'se SuperElement,
    laws: Vec<PairLaw>,
    /// Each boundary pair's first coordinate in q.
    offsets: Vec<usize>,
    /// A pair evaluated by the full model's code (a patch law or a kept pair's own law) as
    /// the reduced-interface model has it, on local nodes 0 (c), 1 (d) and, with a patch
    /// law, 2 (r_p), 3 (r_d); `None`: a point contact with the cubic law.
    locals: Vec<Option<ContactPair>>,
    /// Where each patch-law pair's tilt nodes are in q (its own after c and d, or the pair's
    /// it reads, [`super::superelement::BoundaryTilt::shared`]).
    tilt_offsets: Vec<Option<usize>>,
    /// The committed slip history, one anchor per boundary pair (zero: no slip yet; only a
    /// kept Coulomb pair's is ever anything else).
    history: Vec<[f64; 3]>,
}

/// The local contact pair of a boundary pair evaluated by the full model's code (see
/// [`Assembly::locals`]): a swept pair's patch law (steady sliding along its own tangent),
/// or a kept pair's own law, over its patch where it has one.
fn local_pair(pair: &BoundaryPair) -> Result<Option<ContactPair>, String> {
    let settings = match (&pair.own_law, &pair.tilt) {
        (Some(own), _) => PairSettings {
            // The penalty in use is the boundary pair's (the model's resolved one).
            penalty: Some(pair.penalty),
            ..own.clone()
        },
        (None, Some(_)) => PairSettings {
            name: pair.pair.clone(),
            friction: 0.0,
            penalty: Some(pair.penalty),
            separation: pair.separation,
            // The point's own tangent below is what the law uses.
            sliding: contact::SlidingDirection::None,
            law: contact::FrictionLaw::SteadySliding,
            calculix: None,
        },
        (None, None) => return Ok(None),
    };
    let point = ContactPoint {
        slave: vec![(0, 1.0)],
        master: vec![(1, 1.0)],
        normal: pair.normal,
        initial_gap: pair.initial_gap,
        area: pair.area,
        tangent: pair.sliding,
        position: pair.pad_position,
        slave_node: 0,
        master_face: None,
        tilt: pair.tilt.as_ref().map(|tilt| contact::Tilt {
            nodes: [2, 3],
            axes: tilt.axes,
            patch: tilt.patch.clone(),
            arm: tilt.arm,
            penalty: pair.penalty,
            bilateral: !pair.separation,
        }),
    };
    contact::node_to_node(settings, pair.penalty, vec![point])
        .map(Some)
        .map_err(|e| e.to_string())
}

/// n + mu t, the direction of a pair's force on the pad.
fn direction(pair: &BoundaryPair, friction: f64) -> [f64; 3] {
    match pair.sliding {
        Some(t) => add(pair.normal, scale(friction, t)),
        None => pair.normal,
    }
}

fn norm2(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

impl<'se> Assembly<'se> {
    /// Checks the super-element and matches every pair's force (eq. 8).
    pub fn new(se: &'se SuperElement, contact: &CubicContact) -> Result<Self, AssemblyError> {
        let n = se.header.size;
        let shape = |what: &str, rows: usize, cols: usize| {
            if (rows, cols) == (n, n) {
                Ok(())
            } else {
                Err(AssemblyError::Inconsistent(format!(
                    "{what} is {rows}x{cols}, the header's size is {n}"
                )))
            }
        };
        shape("K_r", se.stiffness.nrows(), se.stiffness.ncols())?;
        shape("M_r", se.mass.nrows(), se.mass.ncols())?;
        shape("load", se.load.len(), n)?;
        shape("equilibrium", se.equilibrium.len(), n)?;
        if se.boundary_size() > n {
            return Err(AssemblyError::Inconsistent(format!(
                "{} boundary pairs need {} coordinates, the size is {n}",
                se.header.boundary.len(),
                se.boundary_size()
            )));
        }
        if !(contact.k_cubic >= 0.0 && contact.k_cubic.is_finite()) {
            return Err(AssemblyError::InvalidContact(format!(
                "k_nl = {} must be finite and >= 0",
                contact.k_cubic
            )));
        }
        let offsets = se.boundary_offsets();
        let tilt_offsets = se.header.tilt_offsets();
        let mut laws = Vec::with_capacity(se.header.boundary.len());
        let mut locals = Vec::with_capacity(se.header.boundary.len());
        for (index, pair) in se.header.boundary.iter().enumerate() {
            let invalid = |why: String| AssemblyError::InvalidPair {
                index,
                pair: pair.pair.clone(),
                why,
            };
            let local = local_pair(pair).map_err(&invalid)?;
            let patch = local.as_ref().filter(|_| pair.tilt.is_some());
            if patch.is_some() && tilt_offsets[index].is_none() {
                return Err(invalid(
                    "it reads the tilt nodes of a pair that has none of its own".into(),
                ));
            }
            if patch.is_some() && *contact != CubicContact::default() {
                return Err(AssemblyError::InvalidContact(format!(
                    "boundary pair {index} (pair '{}') carries a patch law (reduction.tilt), \
                     the reduced-interface model's penalty over its share: k_linear and \
                     k_cubic are a point contact's and cannot be set with it",
                    pair.pair
                )));
            }
            let natural = pair.penalty * pair.area;
            let k_linear = match pair.own_law {
                // The cubic law is the swept pairs' alone.
                Some(_) => natural,
                None => contact.k_linear.unwrap_or(natural),
            };
            if !(k_linear > 0.0 && k_linear.is_finite()) {
                return Err(invalid(format!("k_l = {k_linear} must be finite and > 0")));
            }
            if !k_linear_resolved(k_linear, natural) {
                return Err(invalid(format!(
                    "k_l = {k_linear:e} N/m is {:.1e} times the contact's penalty x area \
                     ({natural:.3e} N/m), beyond the 1/eps ratio double precision resolves",
                    k_linear / natural
                )));
            }
            if local.is_some() && pair.tilt.is_none() {
                // A kept pair's own law: the reduced-interface model's, no offset to match.
                laws.push(PairLaw {
                    k_linear: natural,
                    k_cubic: 0.0,
                    offset: 0.0,
                    separation: pair.separation,
                });
                locals.push(local);
                continue;
            }
            let f = pair.normal_force;
            if !f.is_finite() || (pair.separation && f < 0.0) {
                return Err(invalid(format!(
                    "normal force {f} (a pair that may open carries a finite force >= 0)"
                )));
            }
            let at = offsets[index];
            let d = geometric_approach(pair, &se.equilibrium[at..at + 6]);
            if !d.is_finite() {
                return Err(invalid("non-finite gap at the equilibrium".into()));
            }
            // A patch law is the reduced-interface model's own: no offset to match.
            let s = if local.is_some() {
                d
            } else if pair.separation && f == 0.0 {
                d.min(0.0)
            } else {
                cubic_root(k_linear, contact.k_cubic, f)
            };
            laws.push(PairLaw {
                k_linear,
                k_cubic: contact.k_cubic,
                offset: s - d,
                separation: pair.separation,
            });
            locals.push(local);
        }
        let assembly = Assembly {
            se,
            laws,
            offsets,
            locals,
            tilt_offsets,
            history: vec![[0.0; 3]; se.header.boundary.len()],
        };
        let mismatch = assembly.force_mismatch();
        if mismatch > 1e-12 {
            // Only when a pair's geometric approach dwarfs its matched one (|d_s| >> |s|):
            // s = d + xi then carries the round-off of d.
            tracing::warn!(
                "super-element force matching: a pair's force at q_s is off by {mismatch:.3e} \
                 (relative) from the full model's"
            );
        }
        Ok(assembly)
    }

    /// The largest relative difference between a pair's force at q_s and the full model's
    /// F_nl (absolute, in N, for pairs with F_nl = 0): round-off, and checked to be at most
    /// 1e-12 by the tests.
    pub fn force_mismatch(&self) -> f64 {
        self.pair_states(&self.se.equilibrium, self.se.header.friction)
            .iter()
            .zip(&self.se.header.boundary)
            .map(|(state, pair)| {
                let f = pair.normal_force;
                let scale = if f != 0.0 { f.abs() } else { 1.0 };
                (state.force - f).abs() / scale
            })
            .fold(0.0, f64::max)
    }

    pub fn super_element(&self) -> &SuperElement {
        self.se
    }

    /// The matched laws, one per boundary pair.
    pub fn laws(&self) -> &[PairLaw] {
        &self.laws
    }

    /// The matched approach s = d + xi of pair k for q.
    fn approach(&self, k: usize, q: &[f64]) -> f64 {
        let at = self.offsets[k];
        geometric_approach(&self.se.header.boundary[k], &q[at..at + 6]) + self.laws[k].offset
    }

    /// Sets the committed slip history (one anchor per boundary pair, as
    /// [`ReducedStatic::anchors`] gives it): the return mapping of a kept Coulomb pair
    /// starts from it.
    pub fn with_history(mut self, anchors: Vec<[f64; 3]>) -> Result<Self, AssemblyError> {
        if anchors.len() != self.laws.len() {
            return Err(AssemblyError::Inconsistent(format!(
                "a slip history of {} anchors for {} boundary pairs",
                anchors.len(),
                self.laws.len()
            )));
        }
        self.history = anchors;
        Ok(self)
    }

    /// The committed slip history.
    pub fn history(&self) -> &[[f64; 3]] {
        &self.history
    }

    /// A pair evaluated by the full model's code (patch law or own law): its state and, when
    /// closed, its contribution on its local coordinates ([`Self::local_coordinates`]);
    /// `None` for a point contact with the cubic law. A swept pair takes the sweep's
    /// `friction`, a kept pair its own.
    fn local_law(
        &self,
        k: usize,
        q: &[f64],
        friction: f64,
        anchor: [f64; 3],
    ) -> Option<(PointState, Option<PointContribution>)> {
        let local = self.locals[k].as_ref()?;
        let at = self.local_coordinates(k);
        let u: Vec<[f64; 3]> = at.chunks(3).map(|c| [q[c[0]], q[c[1]], q[c[2]]]).collect();
        let swept = self.se.header.boundary[k].swept();
        let evaluated = if swept {
            let mut pair = local.clone();
            pair.settings.friction = friction;
            contact::evaluate(&pair, &pair.points[0], anchor, &u)
        } else {
            contact::evaluate(local, &local.points[0], anchor, &u)
        };
        // Not `.ok()`: a `None` here would read as a point contact and take the cubic law.
        Some(evaluated.expect("a local pair's nodes are 0..u.len()"))
    }

    /// Where a locally evaluated pair's coordinates are in q: c and d, then a patch law's
    /// tilt nodes r_p, r_d (its own after c and d, or the pair's it reads).
    fn local_coordinates(&self, k: usize) -> Vec<usize> {
        let at = self.offsets[k];
        let mut coordinates: Vec<usize> = (at..at + 6).collect();
        if self.se.header.boundary[k].tilt.is_some() {
            let tilt = self.tilt_offsets[k].unwrap_or(at + 6);
            coordinates.extend(tilt..tilt + 6);
        }
        coordinates
    }

    /// Every pair's state for q at friction `friction` (from the committed history).
    pub fn pair_states(&self, q: &[f64], friction: f64) -> Vec<PairState> {
        self.pair_states_from(q, friction, &self.history)
    }

    fn pair_states_from(&self, q: &[f64], friction: f64, history: &[[f64; 3]]) -> Vec<PairState> {
        (0..self.laws.len())
            .map(|k| match self.local_law(k, q, friction, history[k]) {
                Some((state, _)) => PairState {
                    approach: -state.gap,
                    force: state.normal_force,
                    closed: state.closed,
                    status: state.status,
                    friction_force: state.friction_force,
                    anchor: state.anchor,
                },
                None => {
                    let (s, law) = (self.approach(k, q), &self.laws[k]);
                    let force = law.force(s);
                    let closed = law.closed(s);
                    let sliding = self.se.header.boundary[k].sliding;
                    PairState {
                        approach: s,
                        force,
                        closed,
                        status: if closed { Status::Slip } else { Status::Open },
                        friction_force: sliding
                            .map(|t| scale(friction * force, t))
                            .unwrap_or_default(),
                        anchor: [0.0; 3],
                    }
                }
            })
            .collect()
    }

    /// R(q) = K_r q + F_c(q; mu) - load (see the module doc), from the committed history.
    pub fn residual(&self, q: &[f64], friction: f64) -> Vec<f64> {
        self.residual_from(q, friction, 1.0, &self.history)
    }

    /// R(q) = K_r q + F_c(q; mu) - factor load, the return mapping from `history`.
    fn residual_from(
        &self,
        q: &[f64],
        friction: f64,
        factor: f64,
        history: &[[f64; 3]],
    ) -> Vec<f64> {
        let k = &self.se.stiffness;
        let mut r: Vec<f64> = self.se.load.iter().map(|f| -factor * f).collect();
        for (j, &qj) in q.iter().enumerate() {
            if qj != 0.0 {
                for (i, ri) in r.iter_mut().enumerate() {
                    *ri += k[(i, j)] * qj;
                }
            }
        }
        for (k, law) in self.laws.iter().enumerate() {
            let at = self.offsets[k];
            if let Some((_, contribution)) = self.local_law(k, q, friction, history[k]) {
                if let Some(c) = contribution {
                    for (&i, ci) in self.local_coordinates(k).iter().zip(&c.residual) {
                        r[i] += ci;
                    }
                }
                continue;
            }
            let force = law.force(self.approach(k, q));
            if force != 0.0 {
                let f = scale(force, direction(&self.se.header.boundary[k], friction));
                for i in 0..3 {
                    r[at + i] -= f[i];
                    r[at + 3 + i] += f[i];
                }
            }
        }
        r
    }

    /// dR/dq: K_r plus, per closed pair, c_a c_b F'(s) (n + mu t) n^T (a locally evaluated
    /// pair's: [`contact::evaluate`]'s block), from the committed history: the CEA's
    /// tangent once the history is the static's ([`Self::with_history`]).
    pub fn jacobian(&self, q: &[f64], friction: f64) -> Mat<f64> {
        self.jacobian_from(q, friction, &self.history)
    }

    fn jacobian_from(&self, q: &[f64], friction: f64, history: &[[f64; 3]]) -> Mat<f64> {
        let mut j = self.se.stiffness.clone();
        for (k, law) in self.laws.iter().enumerate() {
            let at = self.offsets[k];
            if let Some((_, contribution)) = self.local_law(k, q, friction, history[k]) {
                if let Some(c) = contribution {
                    let local = self.local_coordinates(k);
                    let width = local.len();
                    for (r, &row) in local.iter().enumerate() {
                        for (col, &column) in local.iter().enumerate() {
                            j[(row, column)] += c.jacobian[r * width + col];
                        }
                    }
                }
                continue;
            }
            let s = self.approach(k, q);
            if !law.closed(s) {
                continue;
            }
            let pair = &self.se.header.boundary[k];
            let (dir, n, kt) = (direction(pair, friction), pair.normal, law.tangent(s));
            for (a, ca) in [(0, 1.0), (1, -1.0)] {
                for (b, cb) in [(0, 1.0), (1, -1.0)] {
                    let c = kt * (ca * cb);
                    for r in 0..3 {
                        for col in 0..3 {
                            j[(at + 3 * a + r, at + 3 * b + col)] += c * (dir[r] * n[col]);
                        }
                    }
                }
            }
        }
        j
    }

    /// |R(q_s)| / |load| at friction mu: round-off at the super-element's own friction when
    /// its load is consistent (eq. 5).
    pub fn equilibrium_residual(&self, friction: f64) -> f64 {
        self.relative_residual(&self.se.equilibrium, friction)
    }

    /// |R(q)| / |load| at friction mu.
    pub fn relative_residual(&self, q: &[f64], friction: f64) -> f64 {
        norm2(&self.residual(q, friction)) / norm2(&self.se.load)
    }

    /// The reduced non-linear static at friction mu, by Newton from q_s with the analytic
    /// Jacobian (dense LU) and a backtracking line search on |R|.
    pub fn solve_static(
        &self,
        friction: f64,
        options: &StaticOptions,
    ) -> Result<ReducedStatic, AssemblyError> {
        self.solve_static_from(&self.se.equilibrium, friction, options)
    }

    /// [`Assembly::solve_static`] from another start (a neighbouring sweep point's q), the
    /// return mapping from the committed history.
    pub fn solve_static_from(
        &self,
        start: &[f64],
        friction: f64,
        options: &StaticOptions,
    ) -> Result<ReducedStatic, AssemblyError> {
        let mut solver = TangentSolver::new();
        self.newton(start, friction, 1.0, &self.history, options, &mut solver)
    }

    /// Newton on R(q) = K_r q + F_c(q) - factor load from `start`, the return mapping of
    /// the kept Coulomb pairs from `history` (backward Euler: one increment), its steps by
    /// `solver` (which may hold an LU of an earlier solve of the same point).
    pub(super) fn newton(
        &self,
        start: &[f64],
        friction: f64,
        factor: f64,
        history: &[[f64; 3]],
        options: &StaticOptions,
        solver: &mut TangentSolver,
    ) -> Result<ReducedStatic, AssemblyError> {
        let factorizations_before = solver.factorizations;
        if start.len() != self.se.header.size {
            return Err(AssemblyError::Inconsistent(format!(
                "a start of {} coordinates for size {}",
                start.len(),
                self.se.header.size
            )));
        }
        if history.len() != self.laws.len() {
            return Err(AssemblyError::Inconsistent(format!(
                "a slip history of {} anchors for {} boundary pairs",
                history.len(),
                self.laws.len()
            )));
        }
        let residual = |q: &[f64]| self.residual_from(q, friction, factor, history);
        let mut q = start.to_vec();
        let mut r = residual(&q);
        let mut norm = norm2(&r);
        let reference = match factor * norm2(&self.se.load) {
            l if l > 0.0 => l,
            _ => norm.max(f64::MIN_POSITIVE),
        };
        let tolerance = options.tolerance * reference;
        let mut history_of_norms = vec![norm];
        let mut iterations = 0;
        while norm > tolerance {
            if iterations >= options.max_iterations {
                return Err(AssemblyError::NotConverged {
                    friction,
                    iterations,
                    tolerance,
                    history: history_of_norms,
                });
            }
            let jac = self.jacobian_from(&q, friction, history);
            let step = solver.step(&jac, &r);
            if step.iter().any(|x| !x.is_finite()) {
                return Err(AssemblyError::Singular {
                    friction,
                    iteration: iterations,
                });
            }
            iterations += 1;
            if options.line_search == LineSearch::CriticalPoint {
                let d = &step;
                let l = critical_point(&q, d, &r, &residual);
                q = (0..q.len()).map(|i| q[i] + l * d[i]).collect();
                r = residual(&q);
                let previous = norm;
                norm = norm2(&r);
                history_of_norms.push(norm);
                // As below: no decrease at the round-off floor is convergence.
                if norm >= previous && norm <= 1e-8 * reference {
                    break;
                }
                continue;
            }
            // Armijo backtracking on |R|: the Newton step is a descent direction wherever
            // R is smooth; halving copes with a pair changing state inside the step.
            let mut alpha = 1.0;
            let mut accepted = None;
            for _ in 0..30 {
                let trial: Vec<f64> = q.iter().zip(&step).map(|(a, b)| a + alpha * b).collect();
                let rt = residual(&trial);
                let nt = norm2(&rt);
                if nt <= (1.0 - 1e-4 * alpha) * norm {
                    accepted = Some((trial, rt, nt));
                    break;
                }
                alpha *= 0.5;
            }
            match accepted {
                Some((trial, rt, nt)) => {
                    q = trial;
                    r = rt;
                    norm = nt;
                    history_of_norms.push(norm);
                }
                None => {
                    // No decrease: the round-off floor, accepted well below any physical
                    // imbalance (as the full model's Newton does), or a failure.
                    if norm <= 1e-8 * reference {
                        break;
                    }
                    return Err(AssemblyError::NotConverged {
                        friction,
                        iterations,
                        tolerance,
                        history: history_of_norms,
                    });
                }
            }
        }
        let pairs = self.pair_states_from(&q, friction, history);
        Ok(ReducedStatic {
            friction,
            q,
            iterations,
            factorizations: solver.factorizations - factorizations_before,
            residual_history: history_of_norms,
            pairs,
            cutbacks: 0,
        })
    }

    /// The dense CEA of the linearisation at q (normally a [`ReducedStatic`]'s q).
    pub fn cea(
        &self,
        q: &[f64],
        friction: f64,
        options: &DenseCeaOptions,
    ) -> Result<DenseCeaResult, AssemblyError> {
        dense_cea(
            self.jacobian(q, friction).as_ref(),
            self.se.mass.as_ref(),
            options,
        )
    }

    /// [`Self::cea`] by the eigensolver given ([`DenseEigensolver::choose`] picks the band's
    /// windows on a large model).
    pub fn cea_by(
        &self,
        solver: DenseEigensolver<'_>,
        q: &[f64],
        friction: f64,
        options: &DenseCeaOptions,
    ) -> Result<DenseCeaResult, AssemblyError> {
        dense_cea_by(
            solver,
            self.jacobian(q, friction).as_ref(),
            self.se.mass.as_ref(),
            options,
        )
    }
}

/// The step length l along d where <R(q + l d), d> = 0 ([`LineSearch::CriticalPoint`]):
/// secants from (0, <R(q), d>) and (1, <R(q + d), d>), each new l kept in (0, 1]; the
/// Newton step itself (l = 1) when the secant has no root there.
fn critical_point(q: &[f64], d: &[f64], r: &[f64], residual: &impl Fn(&[f64]) -> Vec<f64>) -> f64 {
    let work = |l: f64| {
        let trial: Vec<f64> = q.iter().zip(d).map(|(a, b)| a + l * b).collect();
        residual(&trial)
            .iter()
            .zip(d)
            .map(|(a, b)| a * b)
            .sum::<f64>()
    };
    let dot0: f64 = r.iter().zip(d).map(|(a, b)| a * b).sum();
    let (mut l0, mut w0) = (0.0, dot0);
    let (mut l1, mut w1) = (1.0, work(1.0));
    for _ in 0..CRITICAL_POINT_SECANTS {
        if w1 == w0 {
            break;
        }
        let l2 = l1 - w1 * (l1 - l0) / (w1 - w0);
        if !(l2.is_finite() && l2 > 0.0) {
            break;
        }
        let l2 = l2.min(1.0);
        if (l2 - l1).abs() <= 1e-3 * l1 {
            l1 = l2;
            break;
        }
        (l0, w0) = (l1, w1);
        l1 = l2;
        w1 = work(l1);
    }
    l1
}

/// d = -(g0 + n . (u_pad - u_disc)) for a pair's six coordinates.
fn geometric_approach(pair: &BoundaryPair, q: &[f64]) -> f64 {
    let pad = [q[0], q[1], q[2]];
    let disc = [q[3], q[4], q[5]];
    -(pair.initial_gap + dot(pair.normal, sub(pad, disc)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::cea::{by_frequency, lambda_of};
    use crate::contact::{self, ContactPoint, PairSettings, SlidingDirection};
    use crate::reduce::superelement::{BoundaryTilt, SuperElementHeader};
    use num_complex::Complex64;
    use std::f64::consts::PI;

    /// Deterministic numbers in [-1, 1).
    struct Lcg(u64);
    impl Lcg {
        fn next(&mut self) -> f64 {
            self.0 = self
                .0
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((self.0 >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
        }
    }

    /// B^T B / n + shift I, symmetric positive definite.
    fn spd(n: usize, rng: &mut Lcg, scale: f64, shift: f64) -> Mat<f64> {
        let b = Mat::from_fn(n, n, |_, _| rng.next());
        let mut a = b.transpose() * &b;
        for j in 0..n {
            for i in 0..n {
                a[(i, j)] = scale * (a[(i, j)] / n as f64 + if i == j { shift } else { 0.0 });
            }
        }
        a
    }

    const MU_SE: f64 = 0.5;

    /// The full model's penalty pair of boundary pair k, on nodes 2k (pad), 2k+1 (disc).
    fn penalty_pair(k: usize, b: &BoundaryPair, friction: f64) -> contact::ContactPair {
        let settings = PairSettings {
            name: b.pair.clone(),
            friction,
            penalty: None,
            separation: b.separation,
            sliding: SlidingDirection::None,
            law: contact::FrictionLaw::SteadySliding,
            calculix: None,
        };
        let point = ContactPoint {
            slave: vec![(2 * k, 1.0)],
            master: vec![(2 * k + 1, 1.0)],
            normal: b.normal,
            initial_gap: b.initial_gap,
            area: b.area,
            tangent: b.sliding,
            position: b.pad_position,
            slave_node: 2 * k,
            master_face: None,
            tilt: None,
        };
        contact::node_to_node(settings, b.penalty, vec![point]).unwrap()
    }

    fn nodes(q: &[f64], pairs: usize) -> Vec<[f64; 3]> {
        (0..2 * pairs)
            .map(|i| [q[3 * i], q[3 * i + 1], q[3 * i + 2]])
            .collect()
    }

    /// The full model's penalty residual and Jacobian restricted to the boundary (reduced
    /// size), from `crate::contact::penalty`: the independent reference.
    fn penalty_terms(se: &SuperElement, q: &[f64], friction: f64) -> (Vec<f64>, Mat<f64>) {
        let size = se.header.size;
        let u = nodes(q, se.header.boundary.len());
        let mut r = vec![0.0; size];
        let mut j = Mat::zeros(size, size);
        for (k, b) in se.header.boundary.iter().enumerate() {
            let pair = penalty_pair(k, b, friction);
            let (_, c) = contact::evaluate(&pair, &pair.points[0], [0.0; 3], &u).unwrap();
            if let Some(c) = c {
                for (a, &node) in c.nodes.iter().enumerate() {
                    for i in 0..3 {
                        r[3 * node + i] += c.residual[3 * a + i];
                        for (bb, &other) in c.nodes.iter().enumerate() {
                            for jj in 0..3 {
                                j[(3 * node + i, 3 * other + jj)] +=
                                    c.jacobian[(3 * a + i) * 6 + 3 * bb + jj];
                            }
                        }
                    }
                }
            }
        }
        (r, j)
    }

    /// Three boundary pairs (closed, open, bilateral in tension), 2 modes + the static
    /// correction: size 21. K_r SPD plus an unsymmetric part (the other contacts' friction),
    /// M_r SPD, q_s of micrometres; the normal forces and the load are the full penalty
    /// model's at q_s and mu_SE (load := K_r q_s + F_c,penalty(q_s)), so eq. 5 holds there.
    fn synthetic() -> SuperElement {
        let mut rng = Lcg(42);
        let size = 21;
        let mut stiffness = spd(size, &mut rng, 1e8, 1.0);
        let skew = Mat::from_fn(size, size, |_, _| rng.next());
        for j in 0..size {
            for i in 0..size {
                stiffness[(i, j)] += 2e6 * (skew[(i, j)] - skew[(j, i)]);
            }
        }
        let mass = spd(size, &mut rng, 0.1, 0.5);
        let equilibrium: Vec<f64> = (0..size).map(|_| 1e-6 * rng.next()).collect();
        let unit = |v: [f64; 3]| scale(1.0 / dot(v, v).sqrt(), v);
        // (normal, sliding, separation, gap at q_s)
        let specs = [
            ([0.0, 0.0, 1.0], Some([1.0, 0.0, 0.0]), true, -3e-6),
            (unit([0.6, 0.0, 0.8]), Some([0.0, 1.0, 0.0]), true, 4e-6),
            (unit([0.0, 0.6, 0.8]), None, false, 1e-6),
        ];
        let mut boundary = Vec::new();
        for (k, (normal, sliding, separation, gap)) in specs.into_iter().enumerate() {
            let q = &equilibrium[6 * k..6 * k + 6];
            let rel = sub([q[0], q[1], q[2]], [q[3], q[4], q[5]]);
            boundary.push(BoundaryPair {
                pair: format!("pad{}", k % 2),
                pad_position: [0.1 * k as f64, 0.0, 0.0],
                disc_position: [0.1 * k as f64, 0.0, -0.001],
                normal,
                sliding,
                initial_gap: gap - dot(normal, rel),
                area: 1e-4,
                penalty: 1e12,
                separation,
                normal_force: 0.0,
                tilt: None,
                own_law: None,
            });
        }
        let other = vec![(
            "piston".into(),
            vec![contact::Status::Stick, contact::Status::Open],
        )];
        let mut se = superelement(boundary, other, stiffness, mass, equilibrium);
        let u = nodes(&se.equilibrium, 3);
        for k in 0..3 {
            let pair = penalty_pair(k, &se.header.boundary[k], MU_SE);
            se.header.boundary[k].normal_force =
                contact::point_state(&pair, &pair.points[0], [0.0; 3], &u)
                    .unwrap()
                    .normal_force;
        }
        let (rc, _) = penalty_terms(&se, &se.equilibrium, MU_SE);
        se.load = (0..size)
            .map(|i| {
                rc[i]
                    + (0..size)
                        .map(|j| se.stiffness[(i, j)] * se.equilibrium[j])
                        .sum::<f64>()
            })
            .collect();
        se
    }

    /// A super-element of 2 modes at MU_SE with no load yet (the tests make it consistent).
    fn superelement(
        boundary: Vec<BoundaryPair>,
        other_contacts: Vec<(String, Vec<contact::Status>)>,
        stiffness: Mat<f64>,
        mass: Mat<f64>,
        equilibrium: Vec<f64>,
    ) -> SuperElement {
        let size = equilibrium.len();
        SuperElement {
            header: SuperElementHeader {
                units: "SI".into(),
                friction: MU_SE,
                cutoff_hz: 2e4,
                modes: 2,
                size,
                residual_vectors: 0,
                other_contacts,
                mesh_hash: "mesh".into(),
                study_hash: "study".into(),
                boundary,
            },
            stiffness,
            mass,
            load: vec![0.0; size],
            equilibrium,
        }
    }

    /// A cubic stiffness whose cubic term is 4 times the linear one at the closed pair's
    /// 3 micrometres: a strongly non-linear law.
    fn strong_cubic(se: &SuperElement) -> CubicContact {
        let kl = se.header.boundary[0].penalty * se.header.boundary[0].area;
        CubicContact {
            k_linear: None,
            k_cubic: 4.0 * kl / (3e-6f64).powi(2),
        }
    }

    #[test]
    fn cubic_root_solves_the_cubic_to_round_off_at_every_balance() {
        // From a negligible cubic term to a dominant one, both signs.
        for (kl, knl) in [
            (1e8, 1e-3),
            (1e8, 1e19),
            (1e8, 1e30),
            (1.0, 1e40),
            (3.0, 0.0),
        ] {
            for f in [1e-6, 0.37, 300.0, 1e7, -250.0] {
                let s = cubic_root(kl, knl, f);
                let back = kl * s + knl * s * s * s;
                assert!(
                    (back - f).abs() <= 1e-14 * f.abs(),
                    "k_l {kl}, k_nl {knl}, F {f}: s {s} gives {back}"
                );
            }
        }
        assert_eq!(cubic_root(1.0, 1.0, 0.0), 0.0);
    }

    #[test]
    fn force_matching_reproduces_the_full_forces_and_keeps_open_pairs_open() {
        let se = synthetic();
        let forces: Vec<f64> = se.header.boundary.iter().map(|b| b.normal_force).collect();
        // The synthetic model has what it should: closed, open, bilateral pulling.
        assert!(
            forces[0] > 100.0 && forces[1] == 0.0 && forces[2] < -50.0,
            "{forces:?}"
        );
        for contact in [CubicContact::default(), strong_cubic(&se)] {
            let asm = Assembly::new(&se, &contact).unwrap();
            let states = asm.pair_states(&se.equilibrium, MU_SE);
            for (k, (state, f)) in states.iter().zip(&forces).enumerate() {
                assert!(
                    (state.force - f).abs() <= 1e-12 * f.abs(),
                    "{contact:?} pair {k}: F(d_s + xi) = {} against F_nl = {f}",
                    state.force
                );
            }
            assert!(!states[1].closed && states[1].approach < 0.0);
            assert!(asm.force_mismatch() <= 1e-12);
            // The open pair keeps its geometric gap.
            assert_eq!(asm.laws()[1].offset, 0.0);
            assert!(states[0].closed && states[2].closed);
        }
        // The linear law with the full stiffness needs no offset (round-off only).
        let asm = Assembly::new(&se, &CubicContact::default()).unwrap();
        for law in asm.laws() {
            assert!(law.offset.abs() <= 1e-12 * 3e-6, "{law:?}");
        }
        // With a stiffer law the closed pair needs less penetration: a negative offset.
        let asm = Assembly::new(&se, &strong_cubic(&se)).unwrap();
        assert!(asm.laws()[0].offset < -1e-7);
    }

    #[test]
    fn the_super_element_sits_at_its_own_equilibrium_eq_5() {
        let se = synthetic();
        for contact in [CubicContact::default(), strong_cubic(&se)] {
            let asm = Assembly::new(&se, &contact).unwrap();
            let relative = asm.equilibrium_residual(MU_SE);
            assert!(
                relative <= 1e-12,
                "{contact:?}: |R(q_s)| / |load| = {relative:e}"
            );
            let st = asm.solve_static(MU_SE, &StaticOptions::default()).unwrap();
            assert_eq!(st.iterations, 0);
            assert_eq!(st.q, se.equilibrium);
        }
    }

    #[test]
    fn newton_converges_at_other_friction_values() {
        let se = synthetic();
        let load = norm2(&se.load);
        for contact in [CubicContact::default(), strong_cubic(&se)] {
            let asm = Assembly::new(&se, &contact).unwrap();
            for mu in [0.1, 0.3, 0.9] {
                let st = asm.solve_static(mu, &StaticOptions::default()).unwrap();
                let r = norm2(&asm.residual(&st.q, mu));
                assert!(r <= 1e-10 * load, "mu {mu}: |R| {r:e}, load {load:e}");
                assert!(
                    st.iterations >= 1 && st.iterations <= 10,
                    "{:?}",
                    st.residual_history
                );
                assert_eq!(st.residual_history.len(), st.iterations + 1);
                assert!(st.pairs[0].closed && !st.pairs[1].closed);
            }
        }
    }

    #[test]
    fn the_jacobian_is_the_derivative_of_the_residual() {
        // Central differences, step 1e-12 m on q of ~1e-6 m: truncation is zero for the
        // linear parts and O(h^2 k_nl s) ~ 1e-24 relative for the cubic; round-off is
        // eps |R| / h ~ 2e-16 * 1e3 / 1e-12 ~ 0.2 N/m against entries of ~1e8 N/m: 1e-6 of
        // the largest entry leaves four decades of margin. No pair is near s = 0.
        let se = synthetic();
        let asm = Assembly::new(&se, &strong_cubic(&se)).unwrap();
        let mu = 0.7;
        let q = asm.solve_static(mu, &StaticOptions::default()).unwrap().q;
        let j = asm.jacobian(&q, mu);
        let size = q.len();
        let h = 1e-12;
        let mut biggest: f64 = 0.0;
        let mut worst: f64 = 0.0;
        for c in 0..size {
            let (mut qp, mut qm) = (q.clone(), q.clone());
            qp[c] += h;
            qm[c] -= h;
            let (rp, rm) = (asm.residual(&qp, mu), asm.residual(&qm, mu));
            for i in 0..size {
                let fd = (rp[i] - rm[i]) / (2.0 * h);
                worst = worst.max((fd - j[(i, c)]).abs());
                biggest = biggest.max(j[(i, c)].abs());
            }
        }
        assert!(worst <= 1e-6 * biggest, "worst {worst:e} of {biggest:e}");
        // Friction makes it unsymmetric in the closed pair's block.
        assert!((j[(0, 2)] - j[(2, 0)]).abs() > 1e-3 * biggest);
    }

    /// The synthetic super-element with its closed pair 0 a kept Coulomb pair on the
    /// boundary (its own mu 0.3, the default stick stiffness: k_n / 100).
    fn synthetic_kept_coulomb() -> SuperElement {
        let mut se = synthetic();
        se.header.boundary[0].pair = "piston/pad".into();
        make_kept_coulomb(&mut se.header.boundary[0]);
        se
    }

    /// Makes `b` a kept Coulomb pair of its own name: mu 0.3, the default stick stiffness,
    /// no imposed sliding.
    fn make_kept_coulomb(b: &mut BoundaryPair) {
        b.sliding = None;
        b.own_law = Some(PairSettings {
            name: b.pair.clone(),
            friction: 0.3,
            penalty: None,
            separation: true,
            sliding: SlidingDirection::None,
            law: contact::FrictionLaw::Coulomb {
                stick_stiffness: None,
            },
            calculix: None,
        });
    }

    /// Central differences of R against the analytic Jacobian, both from `asm`'s history.
    fn jacobian_error(asm: &Assembly<'_>, q: &[f64], mu: f64) -> (f64, f64) {
        let j = asm.jacobian(q, mu);
        let h = 1e-12;
        let (mut worst, mut biggest): (f64, f64) = (0.0, 0.0);
        for c in 0..q.len() {
            let (mut qp, mut qm) = (q.to_vec(), q.to_vec());
            qp[c] += h;
            qm[c] -= h;
            let (rp, rm) = (asm.residual(&qp, mu), asm.residual(&qm, mu));
            for i in 0..q.len() {
                let fd = (rp[i] - rm[i]) / (2.0 * h);
                worst = worst.max((fd - j[(i, c)]).abs());
                biggest = biggest.max(j[(i, c)].abs());
            }
        }
        (worst, biggest)
    }

    #[test]
    fn a_kept_coulomb_pair_on_the_boundary_sticks_and_slips_by_its_own_law() {
        // Pair 0 is closed at q_s by 3 micrometres: p = k_n A 3e-6 = 300 N, mu p = 90 N;
        // its stick spring k_t A = 1e6 N/m against a tangential motion of ~1e-6 m holds it
        // (|f_trial| ~ 1 N) from a zero anchor, and a 1 mm anchor makes it slip (1e3 N).
        let se = synthetic_kept_coulomb();
        let q = se.equilibrium.clone();
        let rel = sub([q[0], q[1], q[2]], [q[3], q[4], q[5]]);
        let n = se.header.boundary[0].normal;
        let tangential = sub(rel, scale(dot(n, rel), n));
        let far = add(tangential, [1e-3, 0.0, 0.0]);
        for (anchor, status) in [([0.0; 3], Status::Stick), (far, Status::Slip)] {
            let mut history = vec![[0.0; 3]; 3];
            history[0] = anchor;
            let asm = Assembly::new(&se, &CubicContact::default())
                .unwrap()
                .with_history(history)
                .unwrap();
            for mu in [0.2, 0.8] {
                let state = asm.pair_states(&q, mu)[0];
                assert_eq!(state.status, status);
                let f = crate::vector3::norm(state.friction_force);
                // Its own mu, whatever the sweep's: on the cone when slipping.
                if status == Status::Slip {
                    assert!((f - 0.3 * state.force).abs() <= 1e-12 * f, "{f} {state:?}");
                } else {
                    assert!(f < 0.3 * state.force, "{f} {state:?}");
                }
                // Same truncation and round-off argument as the test above.
                let (worst, biggest) = jacobian_error(&asm, &q, mu);
                assert!(
                    worst <= 1e-6 * biggest,
                    "{status:?}: worst {worst:e} of {biggest:e}"
                );
            }
        }
        // The sweep's friction does not reach it: its residual rows are the same at any mu.
        let asm = Assembly::new(&se, &CubicContact::default()).unwrap();
        let (a, b) = (asm.residual(&q, 0.2), asm.residual(&q, 0.8));
        assert_eq!(a[..6], b[..6]);
    }

    #[test]
    fn the_dense_path_ramps_from_rest_and_carries_the_history() {
        let se = synthetic_kept_coulomb();
        let asm = Assembly::new(&se, &CubicContact::default()).unwrap();
        let load = norm2(&se.load);
        let rest = vec![0.0; se.header.size];
        let first = asm
            .static_from_rest(&rest, 0.4, 4, 3, &StaticOptions::default())
            .unwrap();
        assert_eq!(first.cutbacks, 0);
        // The last increment's equilibrium, from the history the ones before committed.
        let next = crate::reduce::dense_path::DenseState::after(&first);
        let second = asm
            .static_from_previous(&next, 0.6, &StaticOptions::default())
            .unwrap();
        for (st, mu, from) in [(&first, 0.4, None), (&second, 0.6, Some(&next))] {
            // Re-evaluated from the history it was solved from, R vanishes: the start
            // history of the second is the first's after-history.
            if let Some(from) = from {
                let asm = asm.clone().with_history(from.anchors.clone()).unwrap();
                let r = norm2(&asm.residual(&st.q, mu));
                assert!(r <= 1e-10 * load, "mu {mu}: |R| {r:e}");
            }
            let kept = st.pairs[0];
            assert!(kept.closed);
            let f = crate::vector3::norm(kept.friction_force);
            assert!(f <= 0.3 * kept.force * (1.0 + 1e-12), "{kept:?}");
        }
        // From the after-history at its own q, the kept point keeps its state (a slipping
        // one stays on the cone: the CEA's tangent is the committed one's).
        let asm2 = asm.clone().with_history(second.anchors()).unwrap();
        assert_eq!(
            asm2.pair_states(&second.q, 0.6)[0].status,
            second.pairs[0].status
        );
        assert!(asm.clone().with_history(vec![[0.0; 3]; 2]).is_err());
    }

    /// A point contact (6 coordinates) then a patch-law pair (12: c, d, r_p, r_d), 2 modes +
    /// the static correction: size 21. The patch (4 x 4 quadrature points over 1 cm^2) is
    /// pressed 1e-6 m at its centre and tilted 5e-4 rad along e_1, so that its points at
    /// xi_1 > 2 mm are open: partly closed at q_s. The load makes q_s an equilibrium at MU_SE.
    fn synthetic_patch() -> SuperElement {
        let mut rng = Lcg(7);
        let size = 21;
        let stiffness = spd(size, &mut rng, 1e8, 1.0);
        let mass = spd(size, &mut rng, 0.1, 0.5);
        let mut equilibrium: Vec<f64> = (0..size).map(|_| 1e-7 * rng.next()).collect();
        let (arm, theta) = (2e-3, 5e-4);
        let axes = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        // u_rp - u_rd = arm theta e_1.
        equilibrium[6 + 9] = equilibrium[6 + 6] - arm * theta;
        let step = 2.5e-3;
        let patch: Vec<([f64; 2], f64)> = (0..16)
            .map(|j| {
                let at = |i: usize| (i as f64 - 1.5) * step;
                ([at(j % 4), at(j / 4)], 1e-4 / 16.0)
            })
            .collect();
        let pair = |k: usize, tilt: Option<BoundaryTilt>, gap: f64, q: &[f64]| {
            let normal = [0.0, 0.0, 1.0];
            let rel = sub([q[0], q[1], q[2]], [q[3], q[4], q[5]]);
            BoundaryPair {
                pair: format!("pad{k}"),
                pad_position: [0.1 * k as f64, 0.0, 0.0],
                disc_position: [0.1 * k as f64, 0.0, -0.001],
                normal,
                sliding: Some([0.0, 1.0, 0.0]),
                initial_gap: gap - dot(normal, rel),
                area: 1e-4,
                penalty: 1e12,
                separation: true,
                normal_force: 0.0,
                tilt,
                own_law: None,
            }
        };
        let boundary = vec![
            pair(0, None, -2e-6, &equilibrium[0..6]),
            pair(
                1,
                Some(BoundaryTilt {
                    axes,
                    patch,
                    arm,
                    shared: None,
                }),
                -1e-6,
                &equilibrium[6..12],
            ),
        ];
        let mut se = superelement(boundary, Vec::new(), stiffness, mass, equilibrium);
        // The point contact's force is k A d; the patch law needs none (it is the law).
        se.header.boundary[0].normal_force = 1e12 * 1e-4 * 2e-6;
        let unloaded = se.clone();
        let asm = Assembly::new(&unloaded, &CubicContact::default()).unwrap();
        se.header.boundary[1].normal_force = asm.pair_states(&unloaded.equilibrium, MU_SE)[1].force;
        se.load = asm.residual(&unloaded.equilibrium, MU_SE);
        se
    }

    #[test]
    fn a_patch_law_pair_takes_twelve_coordinates_and_its_jacobian_is_the_derivative() {
        let se = synthetic_patch();
        assert_eq!(se.boundary_offsets(), vec![0, 6]);
        assert_eq!(se.boundary_size(), 18);
        let asm = Assembly::new(&se, &CubicContact::default()).unwrap();
        // Partly closed at q_s: theta = e_1 . (u_rp - u_rd) / arm = +5e-4 puts the gap at
        // -1e-6 + 5e-4 * 3.75e-3 > 0 on the column xi_1 = +3.75 mm, which is open; the other three columns carry
        // k a (0.375 + 1.625 + 2.875) 1e-6 each 4 times, k a = 1e12 * 1e-4 / 16: 121.875 N,
        // where the whole patch closed would carry k A d = 100 N.
        let states = asm.pair_states(&se.equilibrium, MU_SE);
        assert!(
            states[1].closed && (states[1].force - 121.875).abs() <= 1e-12 * 121.875,
            "{states:?}"
        );
        assert!(states[0].closed && (states[0].force - 200.0).abs() <= 1e-12 * 200.0);
        assert!(asm.equilibrium_residual(MU_SE) <= 1e-12);
        // Central differences as in the point-contact test; the patch's closed set does not
        // change within h = 1e-12 m (its nearest point is 3.75e-7 m from g = 0).
        for mu in [MU_SE, 0.7] {
            let q = &se.equilibrium;
            let j = asm.jacobian(q, mu);
            let h = 1e-12;
            let (mut biggest, mut worst) = (0.0f64, 0.0f64);
            for c in 0..se.header.size {
                let (mut qp, mut qm) = (q.clone(), q.clone());
                qp[c] += h;
                qm[c] -= h;
                let (rp, rm) = (asm.residual(&qp, mu), asm.residual(&qm, mu));
                for i in 0..se.header.size {
                    let fd = (rp[i] - rm[i]) / (2.0 * h);
                    worst = worst.max((fd - j[(i, c)]).abs());
                    biggest = biggest.max(j[(i, c)].abs());
                }
            }
            assert!(
                worst <= 1e-6 * biggest,
                "mu {mu}: worst {worst:e} of {biggest:e}"
            );
            // The tilt nodes are coupled to the contact nodes (k1 != 0: partly closed).
            assert!(j[(6 + 2, 6 + 6)].abs() > 1e-6 * biggest, "{}", j[(8, 12)]);
        }
        // Newton at other friction values.
        for mu in [0.1, 0.9] {
            let st = asm.solve_static(mu, &StaticOptions::default()).unwrap();
            assert!(asm.relative_residual(&st.q, mu) <= 1e-10, "{st:?}");
        }
        // A cubic law is a point contact's: refused with a patch law, by pair.
        let cubic = CubicContact {
            k_linear: None,
            k_cubic: 1e17,
        };
        let e = Assembly::new(&se, &cubic).unwrap_err().to_string();
        assert!(e.contains("pad1") && e.contains("patch law"), "{e}");
    }

    /// The patch-law pair of [`synthetic_patch`] as a kept Coulomb pair on the boundary (its
    /// own mu 0.3, `[reduction.pairs."name"] tilt = true`): sticking from an anchor at its
    /// tangential position, slipping on its own cone from one 1 mm away, and in both the
    /// Jacobian is the derivative of the residual, the tilt nodes' columns included (the
    /// cone's radius follows the patch's tilt).
    #[test]
    fn a_kept_coulomb_pair_with_a_patch_law_sticks_and_slips_by_its_own_law() {
        let mut se = synthetic_patch();
        make_kept_coulomb(&mut se.header.boundary[1]);
        let q = se.equilibrium.clone();
        let rel = sub([q[6], q[7], q[8]], [q[9], q[10], q[11]]);
        let n = se.header.boundary[1].normal;
        let tangential = sub(rel, scale(dot(n, rel), n));
        let far = add(tangential, [1e-3, 0.0, 0.0]);
        for (anchor, status) in [(tangential, Status::Stick), (far, Status::Slip)] {
            let asm = Assembly::new(&se, &CubicContact::default())
                .unwrap()
                .with_history(vec![[0.0; 3], anchor])
                .unwrap();
            // The sweep's friction does not reach it.
            for mu in [0.2, 0.8] {
                let state = asm.pair_states(&q, mu)[1];
                assert_eq!(state.status, status);
                assert!(
                    (state.force - 121.875).abs() <= 1e-12 * 121.875,
                    "{state:?}"
                );
                let f = crate::vector3::norm(state.friction_force);
                if status == Status::Slip {
                    assert!((f - 0.3 * state.force).abs() <= 1e-12 * f, "{f} {state:?}");
                } else {
                    assert!(f < 1e-9 * state.force, "{f} {state:?}");
                }
                let (worst, biggest) = jacobian_error(&asm, &q, mu);
                assert!(
                    worst <= 1e-6 * biggest,
                    "{status:?}: worst {worst:e} of {biggest:e}"
                );
            }
            // Slipping, the friction on c (its x row, the slip's direction) follows the
            // tilt node r_p; sticking it does not (K_r's own entry taken away).
            let j = asm.jacobian(&q, 0.5);
            let k = &se.stiffness;
            let contact = |r: usize, c: usize| j[(r, c)] - k[(r, c)];
            let coupled = contact(6, 12).abs() > 1e-9 * contact(8, 12).abs();
            assert_eq!(coupled, status == Status::Slip, "{status:?}");
        }
    }

    #[test]
    fn the_linear_law_linearises_to_k_r_plus_the_penalty_contact_matrix() {
        let se = synthetic();
        let asm = Assembly::new(&se, &CubicContact::default()).unwrap();
        for mu in [MU_SE, 0.2] {
            let j = asm.jacobian(&se.equilibrium, mu);
            let (_, contact) = penalty_terms(&se, &se.equilibrium, mu);
            let mut worst: f64 = 0.0;
            for c in 0..se.header.size {
                for i in 0..se.header.size {
                    let expect = se.stiffness[(i, c)] + contact[(i, c)];
                    worst = worst.max((j[(i, c)] - expect).abs());
                }
            }
            // The same products in the same order up to K_r's addition: round-off of 1e8.
            assert!(worst <= 1e-12 * 1e8, "mu {mu}: {worst:e}");
        }
    }

    /// M = I, K = [[2, 1 - D], [1, 2]]: omega^2 = 2 +/- sqrt(1 - D) (tests/numerics/cea.rs).
    #[test]
    fn dense_cea_of_the_two_dof_mode_coupling_model() {
        for d in [0.5, 0.99, 1.01, 1.5, 3.0] {
            let k = Mat::from_fn(2, 2, |i, j| [[2.0, 1.0 - d], [1.0, 2.0]][i][j]);
            let m = Mat::<f64>::identity(2, 2);
            let options = DenseCeaOptions {
                max_frequency_hz: 1.0,
                ..Default::default()
            };
            let result = dense_cea(k.as_ref(), m.as_ref(), &options).unwrap();
            let disc = Complex64::new(1.0 - d, 0.0).sqrt();
            let exact = [2.0 + disc, 2.0 - disc].map(lambda_of);
            assert_eq!(result.modes.len(), 2, "D = {d}");
            for mode in &result.modes {
                // A 2x2 QR iteration: a few eps, amplified by at most 1/|w1 - w2| = 10 at
                // D = 0.99 and 1.01.
                assert!(
                    exact
                        .iter()
                        .any(|x| (x - mode.lambda).norm() <= 1e-13 * x.norm()),
                    "D = {d}: {} not in {exact:?}",
                    mode.lambda
                );
                assert_eq!(mode.unstable, d > 1.0 && mode.real_part > 0.0);
                assert!(!mode.rigid_body && mode.residual < 1e-15, "{mode:?}");
            }
            let unstable = result.modes.iter().filter(|m| m.unstable).count();
            assert_eq!(unstable, usize::from(d > 1.0), "D = {d}");
            if d > 1.0 {
                // One frequency, opposite real parts; by_frequency puts the stable first.
                let (a, b) = (&result.modes[0], &result.modes[1]);
                assert!((a.frequency_hz - b.frequency_hz).abs() < 1e-14);
                assert!(a.real_part < 0.0 && b.real_part > 0.0 && b.unstable);
            }
        }
    }

    #[test]
    fn dense_cea_agrees_with_qz_and_its_shapes_are_eigenvectors() {
        let se = synthetic();
        let asm = Assembly::new(&se, &strong_cubic(&se)).unwrap();
        let mu = 0.9;
        let q = asm.solve_static(mu, &StaticOptions::default()).unwrap().q;
        let k = asm.jacobian(&q, mu);
        let options = DenseCeaOptions {
            max_frequency_hz: 1e9,
            ..Default::default()
        };
        let result = dense_cea(k.as_ref(), se.mass.as_ref(), &options).unwrap();
        assert_eq!(result.modes.len(), se.header.size);
        let qz = k.generalized_eigen(&se.mass).unwrap();
        let (alpha, beta) = (qz.S_a().column_vector(), qz.S_b().column_vector());
        let reference: Vec<Complex64> = (0..se.header.size)
            .map(|i| lambda_of(alpha[i] / beta[i]))
            .collect();
        for mode in &result.modes {
            // Both backward stable on a matrix of condition ~1e2 (M_r's): 1e-10 relative is
            // far above their round-off and far below any difference between modes.
            let nearest = reference
                .iter()
                .map(|r| (r - mode.lambda).norm() / r.norm())
                .fold(f64::INFINITY, f64::min);
            assert!(nearest <= 1e-10, "{mode:?}: {nearest:e}");
            assert!(mode.residual <= 1e-13, "{mode:?}");
        }
        // Sorted by frequency; shapes normalised to a largest component of 1 + 0i.
        for w in result.modes.windows(2) {
            assert_ne!(by_frequency(&w[0], &w[1]), std::cmp::Ordering::Greater);
        }
        for (mode, shape) in result.modes.iter().zip(&result.shapes) {
            let w2 = -(mode.lambda * mode.lambda);
            let big = shape.iter().map(|v| v.norm()).fold(0.0, f64::max);
            assert!((big - 1.0).abs() < 1e-14);
            let mut r2: f64 = 0.0;
            for i in 0..se.header.size {
                let mut v = Complex64::new(0.0, 0.0);
                for j in 0..se.header.size {
                    v += k[(i, j)] * shape[j] - w2 * se.mass[(i, j)] * shape[j];
                }
                r2 = r2.max(v.norm());
            }
            assert!(r2 <= 1e-12 * (1e8 + w2.norm()), "{r2:e}");
        }
    }

    #[test]
    fn a_free_motion_is_rigid_and_never_unstable() {
        // Two unit masses on a spring, nothing holding them: omega^2 = 0 (round-off) and 2k.
        let k = Mat::from_fn(2, 2, |i, j| if i == j { 1e6 } else { -1e6 });
        let m = Mat::<f64>::identity(2, 2);
        let r = dense_cea(k.as_ref(), m.as_ref(), &DenseCeaOptions::default()).unwrap();
        assert_eq!(r.modes.len(), 2);
        assert!(
            r.modes[0].rigid_body && !r.modes[0].unstable,
            "{:?}",
            r.modes[0]
        );
        assert!(!r.modes[1].rigid_body);
        let f = (2e6f64).sqrt() / (2.0 * PI);
        assert!((r.modes[1].frequency_hz - f).abs() <= 1e-12 * f);
    }

    #[test]
    fn newton_from_a_neighbouring_point() {
        let se = synthetic();
        let asm = Assembly::new(&se, &strong_cubic(&se)).unwrap();
        let options = StaticOptions::default();
        let a = asm.solve_static(0.6, &options).unwrap();
        let b = asm.solve_static_from(&a.q, 0.7, &options).unwrap();
        let c = asm.solve_static(0.7, &options).unwrap();
        let gap =
            b.q.iter()
                .zip(&c.q)
                .map(|(x, y)| (x - y).abs())
                .fold(0.0, f64::max);
        // One equilibrium, reached from two starts: agreement to the tolerance's scale.
        assert!(gap <= 1e-12, "{gap:e}");
        assert!(asm.solve_static_from(&a.q[1..], 0.7, &options).is_err());
    }

    #[test]
    fn bad_input_is_refused_with_its_reason() {
        let mut se = synthetic();
        se.header.boundary[0].normal_force = -1.0;
        let e = Assembly::new(&se, &CubicContact::default()).unwrap_err();
        assert!(e.to_string().contains("boundary pair 0"), "{e}");
        let se = synthetic();
        let e = Assembly::new(
            &se,
            &CubicContact {
                k_linear: Some(0.0),
                k_cubic: 0.0,
            },
        )
        .unwrap_err();
        assert!(e.to_string().contains("k_l"), "{e}");
        let m = Mat::from_fn(2, 2, |i, j| [[1.0, 2.0], [2.0, 1.0]][i][j]);
        let e = dense_cea(m.as_ref(), m.as_ref(), &DenseCeaOptions::default()).unwrap_err();
        assert_eq!(e, AssemblyError::MassNotPositiveDefinite);
        // A NaN in K: named with where it is, not faer's bare `NoConvergence`.
        let k = Mat::from_fn(2, 2, |i, j| if (i, j) == (1, 0) { f64::NAN } else { 1.0 });
        let m = Mat::<f64>::identity(2, 2);
        let e = dense_cea(k.as_ref(), m.as_ref(), &DenseCeaOptions::default())
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("reduced stiffness matrix holds NaN at (1, 0)"),
            "{e}"
        );
    }
}
