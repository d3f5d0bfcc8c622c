//! The dense super-element assembly swept over friction (METHOD.md §6-§7; the paper's
//! section 4.4): at each friction value the strategy ([`Strategy`]) picks the super-element,
//! the dense Newton static and the dense CEA run on rank 0 in faer, and every mode is expanded
//! (u = T q) into the reduced-interface model it stands for, where its residual is measured
//! and the unstable ones are drawn.
//!
//! The reduced-interface model (a [`FullModel`] with a reduced interface) is kept: the
//! super-elements are built on it, the per-friction and adaptive strategies solve its static,
//! and its operators measure the expanded modes. Results go through the same sweep, tracking,
//! outputs and `squeal compare` as any other model; tracking compares the modes on the
//! boundary coordinates (every reduced contact node and disc node), which every
//! super-element of a sweep shares.

mod dense;
mod expansion;
mod residual;

use super::full::{mesh_part, FullModel};
use super::SweepSettings;
use super::{
    EquilibriumState, FrictionModel, ModelCheckpoint, PointOutcome, SuperElementState,
    UnstableShape,
};
use crate::analysis::cea::ComplexMode;
use crate::analysis::statics::{self, Configuration, StaticSolution};
use crate::contact::{self, PointState, SlipHistory, Status};
use crate::mesh::hash;
use crate::mesh::Mesh;
use crate::model::Model;
use crate::petsc::{Comm, Vector};
use crate::reduce::assembly::CubicContact;
use crate::reduce::dense_path::DenseState;
use crate::reduce::{self, Decision, LocalBasis, ReducedInterface, Step, Strategy};
use crate::results::{
    ModelInfo, PairReport, SuperElementInfo, SuperElementPoint, SweepPointReport,
};
use crate::study::bench::peak_rss_mib;
use crate::study::StudyError;
use faer::Mat;
use num_complex::Complex64;
use std::time::Instant;

pub use expansion::frequency_error_estimate;

/// What the super-element sweep is asked to do.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SuperElementSettings {
    pub strategy: Strategy,
    /// mu_SE of the single strategy.
    pub friction: f64,
    pub cutoff_hz: f64,
    pub contact: CubicContact,
    pub max_frequency_hz: f64,
    pub unstable_threshold: f64,
    /// Residual vectors of the band's modes at mu_SE in each super-element
    /// ([`reduce::residual_vectors`]): the study's `reduction.residual_vectors`, by default
    /// wherever the interior holds no contact.
    pub residual_vectors: bool,
    /// Whether the study asked for them (a super-element that cannot have them warns).
    pub residual_vectors_asked: bool,
}

/// The super-element in use, with what it needs to be expanded and moved.
struct Current {
    se: reduce::superelement::SuperElement,
    basis: LocalBasis,
    boundary_equations: Vec<usize>,
    /// (pair, point) of the model for each boundary pair.
    boundary_points: Vec<(usize, usize)>,
    /// 1-based: the how-manieth built in this sweep.
    index: usize,
    made_at: f64,
    /// The equilibrium it was made at, with the slip history that was reached from (what a
    /// resumed sweep rebuilds it from).
    made_from: EquilibriumState,
    /// The slip history its equilibrium was reached from (the kept Coulomb pairs' tangent
    /// and states at that equilibrium come from it).
    slip: SlipHistory,
    /// The kept pairs' slipping points' friction forces at the equilibrium it was made at
    /// (what the adaptive strategy measures their turn from).
    slipping: Vec<Vec<Option<[f64; 3]>>>,
}

/// The friction force of each kept (not swept) pair's slipping points, `None` elsewhere.
fn slipping_forces(swept: &[usize], states: &[Vec<PointState>]) -> Vec<Vec<Option<[f64; 3]>>> {
    states
        .iter()
        .enumerate()
        .map(|(i, pair)| {
            pair.iter()
                .map(|s| {
                    (!swept.contains(&i) && s.closed && s.status == Status::Slip)
                        .then_some(s.friction_force)
                })
                .collect()
        })
        .collect()
}

/// A friction sweep of the super-element assembly of a reduced-interface model.
pub struct SuperElementModel<'rt> {
    base: FullModel<'rt>,
    swept: Vec<usize>,
    /// The pairs on the super-element's boundary: the swept ones and every kept pair the
    /// reduction reduced too (`reduction.reduce_pairs`), each with its own law.
    boundary: Vec<usize>,
    /// Every pair of the model is on the boundary, as `reduce_pairs` asked: the interior is
    /// linear elastic and holds no contact, so its basis depends on nothing that changes
    /// along the sweep. It is built once, at rest, with no full-size static (issue 32).
    contact_free: bool,
    /// The first point's load increments (the study's), for the dense ramp from rest.
    increments: usize,
    /// The previous point's dense static with its slip history (where a super-element that
    /// carries history steps on from, [`dense`]).
    dense_previous: Option<DenseState>,
    settings: SuperElementSettings,
    current: Option<Current>,
    /// The previous point's dense static (the single strategy's warm start).
    previous_q: Option<Vec<f64>>,
    built: usize,
    /// The last build's fixed-interface mode count: the next build's first guess.
    interior_modes: Option<usize>,
    mesh_hash: String,
    study_hash: String,
}

/// The reduced interface a super-element is built on.
fn reduced_interface<'a>(base: &'a FullModel<'_>) -> Result<&'a ReducedInterface, StudyError> {
    base.reduced.as_ref().ok_or(StudyError::NoReducedInterface)
}

/// How the point's super-element came about.
struct Choice {
    rebuilt: bool,
    reason: String,
    /// The super-element sits at this point's own equilibrium (made or moved here): the dense
    /// static starts from it and eq. 5 says no step is needed.
    anchored: bool,
    reduced_static_seconds: f64,
    build_seconds: f64,
    static_factorizations: usize,
    /// The reduced-interface model's own equilibrium at this point's mu, when the strategy
    /// solved it (all but the single super-element away from mu_SE): the operator whose
    /// projection the super-element carries here, so the one its modes are checked against.
    equilibrium: Option<StaticSolution>,
}

impl<'rt> SuperElementModel<'rt> {
    /// The reduced-interface model of a sweep whose `[reduction]` asks for super-elements.
    /// Collective.
    pub fn from_settings(comm: Comm<'rt>, sweep: &SweepSettings) -> Result<Self, StudyError> {
        let file = sweep.source;
        let reduction = sweep
            .reduction
            .filter(|r| r.superelements.is_some())
            .ok_or_else(|| StudyError::NoSuperElements {
                file: file.to_string(),
            })?;
        if sweep.analysis.damping.is_some() {
            return Err(StudyError::DampedSuperElements {
                file: file.to_string(),
            });
        }
        let base = FullModel::from_settings(comm, sweep)?;
        let swept: Vec<usize> = base
            .model
            .swept
            .iter()
            .enumerate()
            .filter_map(|(i, &s)| s.then_some(i))
            .collect();
        let reduced = reduced_interface(&base)?;
        let boundary: Vec<usize> = base
            .model
            .pairs
            .iter()
            .enumerate()
            .filter(|(_, p)| reduced.pads.iter().any(|pad| pad.pair == p.settings.name))
            .map(|(i, _)| i)
            .collect();
        let contact_free =
            !reduction.reduce_pairs.is_swept() && boundary.len() == base.model.pairs.len();
        if let Some(k_linear) = reduction.k_linear {
            check_k_linear(&base.model, &swept, k_linear).map_err(StudyError::collective)?;
        }
        let max_frequency_hz = sweep.analysis.max_frequency_hz;
        let settings = SuperElementSettings {
            strategy: reduction.superelements.unwrap_or(Strategy::PerFriction),
            friction: reduction.superelement_friction.unwrap_or(0.5),
            cutoff_hz: reduction
                .cutoff_frequency_hz
                .unwrap_or(2.0 * max_frequency_hz),
            contact: CubicContact {
                k_linear: reduction.k_linear,
                k_cubic: reduction.k_cubic.unwrap_or(0.0),
            },
            max_frequency_hz,
            unstable_threshold: sweep.analysis.unstable_threshold,
            // Only a contact-free interior is symmetric (no kept friction inside) and its
            // basis the same at every mu, so only there are they made by default: from one
            // friction value's modes, mu_SE's, whatever the strategy, they keep every
            // strategy's basis the one basis (issue 32's check).
            residual_vectors: reduction.residual_vectors.unwrap_or(contact_free),
            residual_vectors_asked: reduction.residual_vectors == Some(true),
        };
        Ok(SuperElementModel {
            mesh_hash: hash::mesh_hash(&base.model.mesh),
            study_hash: sweep.hash(),
            base,
            swept,
            boundary,
            contact_free,
            increments: sweep.analysis.increments,
            dense_previous: None,
            settings,
            current: None,
            previous_q: None,
            built: 0,
            interior_modes: None,
        })
    }

    /// Super-elements built so far.
    pub fn built(&self) -> usize {
        self.built
    }

    pub fn settings(&self) -> &SuperElementSettings {
        &self.settings
    }

    /// The super-element at the reduced-interface equilibrium at friction `mu`, built now
    /// (`squeal superelement`). Collective.
    pub fn make(
        &mut self,
        comm: Comm<'rt>,
        mu: f64,
    ) -> Result<&reduce::superelement::SuperElement, StudyError> {
        if self.contact_free {
            self.build_at_rest(comm, mu)?;
        } else {
            let equilibrium = self.base.static_at(comm, mu)?;
            self.build(comm, &equilibrium, mu)?;
        }
        Ok(&self.current.as_ref().expect("just built").se)
    }

    /// Builds a super-element at `equilibrium` (friction `mu`) and makes it current.
    fn build(
        &mut self,
        comm: Comm<'rt>,
        equilibrium: &StaticSolution,
        mu: f64,
    ) -> Result<(), StudyError> {
        self.build_at(comm, equilibrium.configuration(), mu)
    }

    /// Builds the contact-free super-element (every pair on its boundary) at rest: with no
    /// contact inside, its interior is linear and needs no equilibrium. Collective.
    fn build_at_rest(&mut self, comm: Comm<'rt>, mu: f64) -> Result<(), StudyError> {
        let rest = vec![[0.0; 3]; self.base.model.node_count()];
        let no_slip = SlipHistory::default();
        self.build_at(
            comm,
            Configuration {
                displacement: &rest,
                slip: &no_slip,
            },
            mu,
        )
    }

    /// Builds a super-element at the equilibrium `at` (friction `mu`) and makes it current.
    fn build_at(
        &mut self,
        comm: Comm<'rt>,
        at: Configuration<'_>,
        mu: f64,
    ) -> Result<(), StudyError> {
        let reduced = reduced_interface(&self.base)?;
        let cb = reduce::build_with_basis(
            comm,
            reduced,
            self.base.operators(),
            at,
            &self.boundary,
            &reduce::BuildSettings {
                friction: mu,
                cutoff_hz: self.settings.cutoff_hz,
                interior_modes_hint: self.interior_modes,
                residual_vectors: self.settings.residual_vectors,
            },
        )
        .map_err(|source| StudyError::SuperElement { mu, source })?;
        self.interior_modes = Some(cb.superelement.header.modes);
        let states =
            statics::contact_states(&self.base.model.pairs_at(mu), at.slip, at.displacement)
                .map_err(|e| StudyError::SuperElement {
                    mu,
                    source: e.into(),
                })?;
        let slipping = slipping_forces(&self.boundary, &states);
        let basis = LocalBasis::from_dense(&cb.basis)?;
        // Its rows are `basis` now: not held twice through the residual vectors' solve.
        drop(cb.basis);
        let residual = cb.residual;
        let mut se = cb.superelement;
        se.header.mesh_hash = self.mesh_hash.clone();
        se.header.study_hash = self.study_hash.clone();
        self.built += 1;
        self.current = Some(Current {
            se,
            basis,
            boundary_equations: cb.boundary_equations,
            boundary_points: cb.boundary_points,
            index: self.built,
            made_at: mu,
            made_from: EquilibriumState::new(mu, at.displacement, at.slip),
            slip: at.slip.clone(),
            slipping,
        });
        if let Some(residual) = residual {
            self.add_residual_vectors(comm, residual)?;
        } else if self.settings.residual_vectors_asked {
            tracing::warn!(
                "mu {mu}: no residual vectors: the super-element's interior is unsymmetric \
                 (a kept pair's friction) or has linear constraints"
            );
        }
        Ok(())
    }

    /// The model's slip history with the dense static's anchors on the boundary pairs'
    /// points (the current super-element's own history elsewhere).
    fn dense_slip(&self, anchors: &[[f64; 3]]) -> SlipHistory {
        let Some(current) = self.current.as_ref() else {
            return SlipHistory::default();
        };
        let mut per_pair: Vec<Vec<[f64; 3]>> = self
            .base
            .model
            .pairs
            .iter()
            .enumerate()
            .map(|(i, p)| {
                (0..p.points.len())
                    .map(|k| current.slip.anchor(i, k))
                    .collect()
            })
            .collect();
        for (&(i, k), &a) in current.boundary_points.iter().zip(anchors) {
            per_pair[i][k] = a;
        }
        SlipHistory::from_anchors(per_pair)
    }

    /// Moves the current super-element to another equilibrium with the same kept-contact
    /// states: its reduced coordinates there and the swept pairs' forces (eq. 8 is matched to
    /// them). Collective.
    fn move_to(&mut self, comm: Comm<'rt>, equilibrium: &StaticSolution) -> Result<(), StudyError> {
        let operators = self.base.operators();
        let model = &self.base.model;
        let current = self.current.as_mut().ok_or(StudyError::NoSuperElement)?;
        let dofs = &operators.dofs;
        let mut u = vec![0.0; dofs.equations()];
        for (node, d) in equilibrium.displacement.iter().enumerate() {
            for (c, &v) in d.iter().enumerate() {
                if let Some(eq) = dofs.equation(node, c) {
                    u[eq] = v;
                }
            }
        }
        let q = current.basis.coordinates(
            comm,
            &current.se,
            &current.boundary_equations,
            &operators.mass,
            &u,
        )?;
        current.se.equilibrium = q;
        for (pair, &(i, k)) in current
            .se
            .header
            .boundary
            .iter_mut()
            .zip(&current.boundary_points)
        {
            let p = &model.pairs[i];
            let anchor = equilibrium.slip_after.anchor(i, k);
            pair.normal_force =
                contact::point_state(p, &p.points[k], anchor, &equilibrium.displacement)?
                    .normal_force;
        }
        current.slip = equilibrium.slip_after.clone();
        Ok(())
    }

    /// Projects the model linearised at `equilibrium` (friction `mu`) onto the current
    /// super-element's basis ([`reduce::reproject`]). Collective.
    fn reproject(
        &mut self,
        comm: Comm<'rt>,
        equilibrium: &StaticSolution,
        mu: f64,
    ) -> Result<(), StudyError> {
        let reduced = reduced_interface(&self.base)?;
        let current = self.current.as_mut().ok_or(StudyError::NoSuperElement)?;
        reduce::reproject(
            comm,
            reduced,
            self.base.operators(),
            equilibrium.configuration(),
            &self.boundary,
            &current.basis,
            &mut current.se,
        )
        .map_err(|source| StudyError::SuperElement { mu, source })
    }

    /// The kept (non-swept) pairs' states at an equilibrium.
    fn kept_states(&self, equilibrium: &StaticSolution) -> Vec<(String, Vec<Status>)> {
        self.base
            .model
            .pairs
            .iter()
            .enumerate()
            .filter(|(i, _)| !self.boundary.contains(i))
            .map(|(i, p)| {
                (
                    p.settings.name.clone(),
                    equilibrium.contact[i].iter().map(|s| s.status).collect(),
                )
            })
            .collect()
    }

    /// The strategy's super-element for friction `mu`. Collective.
    fn choose(&mut self, comm: Comm<'rt>, mu: f64) -> Result<Choice, StudyError> {
        let mut choice = Choice {
            rebuilt: false,
            reason: String::new(),
            anchored: false,
            reduced_static_seconds: 0.0,
            build_seconds: 0.0,
            static_factorizations: 0,
            equilibrium: None,
        };
        let strategy = self.settings.strategy;
        if self.contact_free {
            let first = self.current.is_none();
            if first || strategy == Strategy::PerFriction {
                let t = Instant::now();
                self.build_at_rest(comm, mu)?;
                choice.build_seconds = t.elapsed().as_secs_f64();
                choice.rebuilt = true;
                choice.reason = format!(
                    "{}: made at rest, with no full-size static: every pair is on its \
                     boundary, so its interior holds no contact and its basis does not \
                     depend on mu{}",
                    strategy.name(),
                    if first {
                        ""
                    } else {
                        " (made again as the strategy asks)"
                    }
                );
            } else {
                let made_at = self.current.as_ref().map_or(mu, |c| c.made_at);
                choice.reason = format!(
                    "{}: the super-element made at mu {made_at} serves every friction value \
                     (no contact inside it)",
                    strategy.name()
                );
            }
            return Ok(choice);
        }
        let at = match strategy.step(mu, self.settings.friction, self.current.is_some()) {
            Step::Keep(why) => {
                choice.reason = why;
                return Ok(choice);
            }
            Step::StaticAt(at) => at,
        };
        let t = Instant::now();
        let equilibrium =
            self.base
                .static_at(comm, at)
                .map_err(|e| StudyError::SuperElementStatic {
                    source: Box::new(e),
                })?;
        choice.reduced_static_seconds = t.elapsed().as_secs_f64();
        choice.static_factorizations = equilibrium
            .increments
            .iter()
            .map(|i| i.factorizations)
            .sum();
        let decision = strategy.decide(
            at,
            self.current.as_ref().map(|c| reduce::strategy::Kept {
                states: &c.se.header.other_contacts,
                slipping: &c.slipping,
            }),
            || {
                (
                    self.kept_states(&equilibrium),
                    slipping_forces(&self.boundary, &equilibrium.contact),
                )
            },
        );
        let t = Instant::now();
        match decision {
            Decision::Rebuild(why) => {
                self.build(comm, &equilibrium, at)?;
                choice.rebuilt = true;
                choice.reason = why;
            }
            Decision::Reuse(why) => {
                self.reproject(comm, &equilibrium, mu)?;
                self.move_to(comm, &equilibrium)?;
                choice.reason = format!(
                    "{why}; its basis reused, this mu's tangent projected on it, moved to this \
                     mu's equilibrium"
                );
            }
        }
        choice.build_seconds = t.elapsed().as_secs_f64();
        // Single: made at mu_SE, which is this point only when mu = mu_SE.
        choice.anchored = at == mu;
        if at == mu {
            choice.equilibrium = Some(equilibrium);
        }
        Ok(choice)
    }
}

impl<'rt> FrictionModel<'rt> for SuperElementModel<'rt> {
    fn checkpoint(&self) -> ModelCheckpoint {
        // Per friction value a new super-element is built at every point: the current one
        // is never used again, so a resumed sweep need not rebuild it.
        let keeps_current = self.settings.strategy.reuses();
        ModelCheckpoint {
            previous: self.base.previous_state(),
            earlier: self.base.earlier_state(),
            superelement: Some(SuperElementState {
                built: self.built,
                current: self
                    .current
                    .as_ref()
                    .filter(|_| keeps_current)
                    .map(|c| (c.index, c.made_from.clone())),
                interior_modes: self.interior_modes,
                previous_q: self.previous_q.clone(),
                dense_previous: self.dense_previous.clone(),
            }),
        }
    }

    fn restore(&mut self, comm: Comm<'rt>, checkpoint: &ModelCheckpoint) -> Result<(), StudyError> {
        let state = checkpoint.superelement.as_ref().ok_or_else(|| {
            StudyError::Checkpoint("it was taken of a model without super-elements".into())
        })?;
        // The super-element the checkpoint stood on may be the one in hand (a refinement
        // going back to an earlier point of the same super-element: always so for the
        // single strategy): the same build, at the same equilibrium, need not be made again.
        let in_hand = matches!(
            (&state.current, &self.current),
            (Some((index, made)), Some(c)) if c.index == *index && c.made_from == *made
        );
        if !in_hand {
            self.current = None;
        }
        self.interior_modes = state.interior_modes;
        if let Some((index, made)) = state.current.as_ref().filter(|_| !in_hand) {
            self.base.restore_previous(Some(made))?;
            let slip = made.slip_history();
            let at = Configuration {
                displacement: &made.displacement,
                slip: &slip,
            };
            self.build_at(comm, at, made.mu)?;
            if let Some(c) = self.current.as_mut() {
                c.index = *index;
            }
            if comm.rank() == 0 {
                tracing::info!(
                    "resumed: super-element #{index} rebuilt at its equilibrium (mu {})",
                    made.mu
                );
            }
        }
        self.interior_modes = state.interior_modes;
        self.built = state.built;
        self.previous_q = state.previous_q.clone();
        self.dense_previous = state.dense_previous.clone();
        self.base.restore_previous(checkpoint.previous.as_ref())?;
        self.base.restore_earlier(checkpoint.earlier.as_ref())
    }

    fn info(&self) -> ModelInfo {
        let mut info = self.base.info();
        let s = &self.settings;
        info.superelements = Some(SuperElementInfo {
            strategy: s.strategy.name().into(),
            friction: s.friction,
            cutoff_hz: s.cutoff_hz,
            k_linear: s.contact.k_linear,
            k_cubic: s.contact.k_cubic,
        });
        info.source = format!(
            "{} ({} super-elements, modes to {} Hz)",
            info.source,
            s.strategy.name(),
            s.cutoff_hz
        );
        info
    }

    fn mesh(&self) -> &Mesh {
        self.base.mesh()
    }

    fn solve_point(&mut self, comm: Comm<'rt>, mu: f64) -> Result<PointOutcome, StudyError> {
        let root = comm.rank() == 0;
        let t = Instant::now();
        let choice = self.choose(comm, mu)?;
        let dense = self.dense(comm, mu, choice.anchored)?;
        self.carry(mu, &dense);

        // Expansion (u = T q) of the static and every mode, and each mode's residual in the
        // reduced-interface model.
        let t_expand = Instant::now();
        let current = self.current.as_ref().expect("chosen above");
        let n = current.se.header.size;
        let m = dense.shapes.len();
        let q = Mat::from_fn(n, 1 + 2 * m, |i, c| match c {
            0 => dense.q_static[i],
            c if c % 2 == 1 => dense.shapes[(c - 1) / 2][i].re,
            c => dense.shapes[(c - 1) / 2][i].im,
        });
        let expanded = current.basis.expand(q.as_ref());
        let slip_static = if self.carries_history() {
            self.dense_slip(&dense.anchors)
        } else {
            current.slip.clone()
        };
        let rows = current.basis.rows();
        let local_rows = rows.len();
        // Tracking compares each mode expanded onto the mesh's mass sample, as the full-size
        // models do: a kinetic-energy MAC over every body, whichever super-element each point
        // stands on. (The boundary coordinates alone left the interior's motion out and
        // weighed the reduced nodes' coordinates as if they were masses.) Each rank fills the
        // sample's equations it holds; the sum is the whole sample on every rank.
        let tracked = self.base.tracked_equations();
        let mut sampled = vec![0.0; 2 * m * tracked.len()];
        for (s, &(e, w)) in tracked.iter().enumerate() {
            if rows.contains(&e) {
                for j in 0..m {
                    let at = 2 * (j * tracked.len() + s);
                    sampled[at] = w * expanded[(e - rows.start, 1 + 2 * j)];
                    sampled[at + 1] = w * expanded[(e - rows.start, 2 + 2 * j)];
                }
            }
        }
        comm.sum_in_place(&mut sampled);
        let per_mode = 2 * tracked.len();
        let tracking: Vec<Vec<Complex64>> = (0..m)
            .map(|j| {
                sampled[j * per_mode..(j + 1) * per_mode]
                    .chunks(2)
                    .map(|z| Complex64::new(z[0], z[1]))
                    .collect()
            })
            .collect();
        let column = |c: usize| -> Vec<f64> { (0..local_rows).map(|i| expanded[(i, c)]).collect() };
        let mut static_vector = Vector::new(comm, local_rows)?;
        static_vector.set_local(&column(0))?;
        let u_static = self
            .base
            .operators()
            .dofs
            .displacements(&static_vector.gather_all()?);
        // The tangent the modes are checked against (see [`expansion::residuals`]): the
        // reduced-interface model's own equilibrium at this mu where it was solved, else
        // the expanded dense static.
        let (u_tangent, slip_tangent) = match &choice.equilibrium {
            Some(e) => (&e.displacement, &e.slip_after),
            None => (&u_static, &slip_static),
        };
        let residuals = expansion::residuals(
            &mut self.base,
            comm,
            mu,
            (u_tangent, slip_tangent),
            &expanded,
            &dense.lambdas,
        )?;

        // Unstable shapes on the mesh (rank 0); the flags travel with the eigenvalues.
        let mut flags = vec![0.0; m];
        if let Some((_, cea, ..)) = &dense.root {
            for (f, mode) in flags.iter_mut().zip(&cea.modes) {
                *f = if mode.unstable { 1.0 } else { 0.0 };
            }
        }
        comm.broadcast_from_root(&mut flags);
        let mut unstable = Vec::new();
        for (j, &flag) in flags.iter().enumerate() {
            if flag != 1.0 {
                continue;
            }
            let mut parts = Vec::with_capacity(2);
            for c in [1 + 2 * j, 2 + 2 * j] {
                let mut v = Vector::new(comm, local_rows)?;
                v.set_local(&column(c))?;
                parts.push(v.gather_to_zero()?);
            }
            if let Some((_, cea, ..)) = &dense.root {
                let mesh = &self.base.model.mesh;
                let dofs = &self.base.operators().dofs;
                let (re, im) = (dofs.displacements(&parts[0]), dofs.displacements(&parts[1]));
                let mut mode = cea.modes[j].clone();
                // The pairs' parts from the expanded shape, in the reduced-interface model's
                // pairs (the boundary's laws are theirs), about the equilibrium the modes'
                // residuals are checked at (see there).
                let growth = self.base.pair_growth(
                    &mode,
                    &self.base.model.pairs_at(mu),
                    slip_tangent,
                    u_tangent,
                    &re,
                    &im,
                );
                mode.pair_shares = growth.as_ref().map(crate::analysis::growth::shares);
                mode.pair_growth = growth;
                let re = mesh_part(re, mesh);
                let im = mesh_part(im, mesh);
                mode.body_shares = self.base.body_shares(&re, &im);
                unstable.push(UnstableShape {
                    mode,
                    re,
                    im,
                    feed: None,
                });
            }
        }
        let expansion_seconds = t_expand.elapsed().as_secs_f64();

        let mut peak = [peak_rss_mib()];
        let mut peak_sum = peak;
        comm.max_in_place(&mut peak);
        comm.sum_in_place(&mut peak_sum);

        let model = &self.base.model;
        // The pairs at this point's friction: a swept pair's summary divides its torque by
        // mu N (the effective radius).
        let pairs = model.pairs_at(mu);
        let n_b = current.se.boundary_size();
        // Contact states: every pair's from the penalty law at the expanded equilibrium, on
        // every rank (the same data, so a failure is every rank's); the swept pairs' are then
        // replaced on rank 0 by the dense laws'.
        let mut states: Vec<Vec<PointState>> =
            statics::contact_states(&pairs, &slip_static, &u_static)?;
        let (report, tracking_shapes, fields) = match &dense.root {
            Some((statics, cea, start_residual, static_seconds, cea_seconds)) if root => {
                for (state, &(i, k)) in statics.pairs.iter().zip(&current.boundary_points) {
                    let point = &model.pairs[i].points[k];
                    let area = point.area;
                    states[i][k] = PointState {
                        gap: -state.approach,
                        normal_force: state.force,
                        pressure: if area > 0.0 { state.force / area } else { 0.0 },
                        closed: state.closed,
                        // A swept pair slides steadily (mu F along its sliding direction), a
                        // kept pair on the boundary sticks or slips by its own law.
                        status: state.status,
                        friction_force: state.friction_force,
                        anchor: state.anchor,
                        // Not the pair's own law: the dense law's zone is not reported
                        // (`PairReport::zone` is cleared below).
                        slope: 0.0,
                        theta: [0.0; 2],
                    };
                }
                let mut normal_total = 0.0;
                let contact_reports = pairs
                    .iter()
                    .zip(&states)
                    .enumerate()
                    .map(|(i, (p, s))| {
                        let summary = contact::summarize_states(p, s);
                        // As the full model's: the swept (disc/pad) pairs carry the load.
                        if self.swept.contains(&i) {
                            normal_total += summary.normal_force;
                        }
                        let mut report = PairReport::new(&p.settings.name, &summary);
                        if self.boundary.contains(&i) {
                            report.zone = None;
                        }
                        report
                    })
                    .collect();
                let applied = model.applied_load();
                let report = SweepPointReport {
                    friction: mu,
                    static_iterations: statics.iterations,
                    static_factorizations: choice.static_factorizations,
                    static_residuals: statics.residual_history.clone(),
                    cutbacks: 0,
                    contact: contact_reports,
                    balance_ratio: if applied > 0.0 {
                        normal_total / applied
                    } else {
                        0.0
                    },
                    // The unstable ones with their bodies' shares (from the expanded shapes).
                    eigenvalues: cea
                        .modes
                        .iter()
                        .enumerate()
                        .map(|(j, m)| {
                            unstable
                                .iter()
                                .find(|s| s.mode.lambda == m.lambda && flags[j] == 1.0)
                                .map_or_else(|| m.clone(), |s| s.mode.clone())
                        })
                        .collect(),
                    static_seconds: choice.reduced_static_seconds + static_seconds,
                    cea_seconds: *cea_seconds,
                    cea_shifts: 0,
                    seconds: t.elapsed().as_secs_f64(),
                    peak_rss_mib_max_rank: peak[0],
                    peak_rss_mib_all_ranks: peak_sum[0],
                    contact_edge: None,
                    inserted: false,
                    path: Vec::new(),
                    contact_changed: false,
                    superelement: Some(SuperElementPoint {
                        strategy: self.settings.strategy.name().into(),
                        index: current.index,
                        made_at_friction: current.made_at,
                        rebuilt: choice.rebuilt,
                        reason: choice.reason.clone(),
                        size: n,
                        boundary: n_b,
                        modes: current.se.header.modes,
                        residual_vectors: current.se.header.residual_vectors,
                        reduced_interface_static_seconds: choice.reduced_static_seconds,
                        build_seconds: choice.build_seconds,
                        start_residual: *start_residual,
                        dense_static_iterations: statics.iterations,
                        dense_static_factorizations: statics.factorizations,
                        dense_static_seconds: *static_seconds,
                        dense_cea_seconds: *cea_seconds,
                        expansion_seconds,
                        frequency_error_estimates: cea
                            .modes
                            .iter()
                            .zip(&residuals)
                            .map(|(mode, &eps)| {
                                frequency_error_estimate(
                                    eps,
                                    mode.frequency_hz,
                                    self.settings.cutoff_hz,
                                )
                            })
                            .collect(),
                        expansion_residuals: residuals,
                    }),
                };
                let fields = self.base.point_fields(&u_static, &states, unstable);
                (report, tracking, Some(fields))
            }
            _ => (
                empty_report(mu, t.elapsed().as_secs_f64(), peak[0], peak_sum[0]),
                Vec::new(),
                None,
            ),
        };
        Ok(PointOutcome {
            report,
            tracking_shapes,
            fields,
        })
    }
}

/// A non-root rank's report: nothing it holds is written.
fn empty_report(mu: f64, seconds: f64, peak: f64, peak_sum: f64) -> SweepPointReport {
    SweepPointReport {
        friction: mu,
        static_iterations: 0,
        static_factorizations: 0,
        static_residuals: Vec::new(),
        cutbacks: 0,
        contact: Vec::new(),
        balance_ratio: 0.0,
        eigenvalues: Vec::<ComplexMode>::new(),
        static_seconds: 0.0,
        cea_seconds: 0.0,
        cea_shifts: 0,
        seconds,
        peak_rss_mib_max_rank: peak,
        peak_rss_mib_all_ranks: peak_sum,
        superelement: None,
        contact_edge: None,
        inserted: false,
        path: Vec::new(),
        contact_changed: false,
    }
}

/// Refuses, before any work, a cubic law's k_l that double precision cannot weigh against
/// the reduced contacts it replaces ([`crate::reduce::assembly::k_linear_resolved`], which
/// the assembly checks again per pair).
fn check_k_linear(model: &Model, swept: &[usize], k_linear: f64) -> Result<(), StudyError> {
    let bad = |why: String| StudyError::BadFlag {
        flag: "--k-linear (reduction.k_linear)",
        why,
    };
    if !(k_linear.is_finite() && k_linear > 0.0) {
        return Err(bad(format!("must be finite and > 0, got {k_linear}")));
    }
    let defaults = swept
        .iter()
        .flat_map(|&i| {
            let pair = &model.pairs[i];
            pair.points.iter().map(move |p| pair.penalty * p.area)
        })
        .filter(|d| *d > 0.0);
    let (lo, hi) = defaults.fold((f64::INFINITY, 0.0_f64), |(lo, hi), d| {
        (lo.min(d), hi.max(d))
    });
    if hi == 0.0 {
        return Ok(());
    }
    // The smallest and largest are the first to fall outside.
    let resolved = crate::reduce::assembly::k_linear_resolved;
    if !(resolved(k_linear, lo) && resolved(k_linear, hi)) {
        return Err(bad(format!(
            "k_l = {k_linear:e} N/m against the reduced contacts' penalty x area of \
             {lo:.3e} ... {hi:.3e} N/m: outside the 1/eps = {:.1e} ratio double precision \
             resolves either way (leave it out for the penalty x area)",
            1.0 / f64::EPSILON
        )));
    }
    Ok(())
}
