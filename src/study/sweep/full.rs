//! A [`Model`] solved with PETSc at each friction value: the full reference model, or a
//! reduced-interface model (a full-size model whose disc/pad interface is reduced). SNES
//! gives the sliding equilibrium, SLEPc the CEA about it.

use super::spread::{node_to_surface_spread, reduced_spread, spread_of, SweptSurface};
use super::SweepSettings;
use super::{
    EquilibriumState, FrictionModel, ModelCheckpoint, PathPoint, PointFields, PointOutcome,
    UnstableShape,
};
use crate::analysis::cea::{self, CeaOptions, RayleighDamping};
use crate::analysis::contact_edge::{self, EdgeMove};
use crate::analysis::continuation::{self, FrictionState};
use crate::analysis::pencil::{self, Pencil};
use crate::analysis::restraint::{self, Body};
use crate::analysis::sensitivity;
use crate::analysis::statics::{self, StaticOptions, StaticProblem};
use crate::contact::{self, SlipHistory};
use crate::fem::element::MassRule;
use crate::mesh::Mesh;
use crate::model::{self, Model, Operators};
use crate::petsc::{Comm, Matrix};
use crate::reduce;
use crate::results::{
    ContactMap, ContactMapPoint, EdgeCheck, ModelInfo, PairReport, SurfacePressure, SurfaceShape,
    SweepPointReport,
};
use crate::study::bench::peak_rss_mib;
use crate::study::report::collective;
use crate::study::StudyError;
use num_complex::Complex64;
use std::time::Instant;

mod why;
use why::LeftShape;

/// A model with its operators, ready for a sweep.
pub struct FullModel<'rt> {
    pub model: Model,
    operators: Operators<'rt>,
    /// C^T M C of a model with constraints, made at its first CEA.
    free_mass: Option<Matrix<'rt>>,
    /// Rayleigh damping, on the solver's unknowns.
    damping: Option<Matrix<'rt>>,
    bodies: Vec<Body>,
    /// Where mode shapes are compared for tracking, and the square root of the mass each
    /// equation stands for: the mesh's mass sample ([`crate::fem::mass_sample`]), so the
    /// shapes' complex MAC is mass-weighted over every body.
    tracked_equations: Vec<(usize, f64)>,
    cea: CeaOptions,
    rayleigh: Option<RayleighDamping>,
    increments: usize,
    ranks: usize,
    /// The previous point's equilibrium (warm start).
    previous: Option<FrictionState>,
    /// The equilibrium before that one: with `previous`, the secant along the friction path
    /// that predicts the next point's displacements ([`FrictionState::predicted`]).
    earlier: Option<PathPoint>,
    /// Where each swept pair's contact forces land on its pad surface.
    spread: Vec<SweptSurface>,
    /// The reduced interface this model was made with (none for the full model): what a
    /// super-element is built on.
    pub(super) reduced: Option<reduce::ReducedInterface>,
    /// At each point, the CEA again with this many points of the contact zone's edge opened,
    /// then closed ([`crate::analysis::contact_edge`]); 0: not done.
    edge_points: usize,
    /// Contributions of the stable modes too (`analysis.contributions_of_every_mode`).
    every_mode: bool,
    /// The mass rule M was assembled with: the bodies' shares of a mode's kinetic energy
    /// use the same.
    mass_rule: MassRule,
}

/// Why a friction sweep of `model` would measure nothing: its swept pairs exist but no load
/// presses them (every pressure and nodal force is zero; supports hold at zero). The static
/// is then zero up to the solver's round-off, and so is every normal force: a deck with a
/// zero `*DSLOAD` once reported an "unstable" mode at 44,670 Hz with a 2e-9 N normal force,
/// where a study file refuses a zero pressure.
fn unloaded(model: &Model) -> Option<String> {
    if !model.swept.iter().any(|&s| s) {
        return None;
    }
    let pressed = model
        .pressures
        .iter()
        .any(|p| p.value != 0.0 && !p.faces.is_empty());
    let forced = model.forces.iter().any(|&(_, _, f)| f != 0.0);
    (!pressed && !forced).then(|| {
        format!(
            "nothing presses the swept contact pairs: the model's {} pressure load(s) and {} \
             nodal force(s) are all zero, so the sliding equilibrium and its normal forces are \
             zero and friction acts on nothing; give the brake pressure (*DSLOAD, *DLOAD or \
             *CLOAD)",
            model.pressures.len(),
            model.forces.len()
        )
    })
}

impl<'rt> FullModel<'rt> {
    /// Builds and assembles the model of a sweep (collective; errors name the settings'
    /// source and key).
    pub fn from_settings(comm: Comm<'rt>, settings: &SweepSettings) -> Result<Self, StudyError> {
        let file = settings.source;
        let analysis = settings.analysis;
        let local = Model::from_spec(&settings.model)
            .map_err(|source| StudyError::StudyModel {
                file: file.to_string(),
                source,
            })
            .and_then(|model| match settings.reduction {
                None => Ok((model, None)),
                Some(r) => r
                    .settings()
                    .and_then(|settings| reduce::reduce_interface(&model, &settings))
                    .map(|reduced| {
                        let spread = reduced_spread(&reduced);
                        (reduced.model.clone(), Some((spread, reduced)))
                    })
                    .map_err(|source| StudyError::Reduction {
                        file: file.to_string(),
                        source,
                    }),
            });
        let (model, reduction) = collective(comm, local)?;
        if let Some(why) = unloaded(&model) {
            return Err(StudyError::DeckStep {
                at: model.source.clone(),
                why,
            }
            .collective());
        }
        if comm.rank() == 0 {
            for w in &model.warnings {
                tracing::warn!("{w}");
            }
            if let Some((_, reduced)) = &reduction {
                for line in reduced.summary().lines() {
                    tracing::info!("reduced interface: {line}");
                }
            }
        }
        let operators = model::assemble(comm, &model, analysis.mass_rule)?;
        let damping = match (analysis.damping, &operators.constraints) {
            (Some(d), None) => Some(d.matrix(&operators.stiffness, &operators.mass)?),
            (Some(d), Some(t)) => {
                Some(t.project(&d.matrix(&operators.stiffness, &operators.mass)?)?)
            }
            (None, _) => None,
        };
        let cea = CeaOptions {
            max_frequency_hz: analysis.max_frequency_hz,
            unstable_threshold: analysis.unstable_threshold,
            modes_per_target: analysis.window,
            solver: analysis.cea_solver,
            count_first: true,
            ..Default::default()
        };
        let mut full = Self::new(comm, model, operators, cea, analysis.increments)
            .map_err(|e| StudyError::from(e).collective())?;
        full.edge_points = analysis.contact_edge_points;
        full.every_mode = analysis.contributions_of_every_mode;
        full.mass_rule = analysis.mass_rule;
        if let Some((spread, reduced)) = reduction {
            full.spread = spread;
            full.reduced = Some(reduced);
        }
        if let (Some(rayleigh), Some(matrix)) = (analysis.damping, damping) {
            full = full.with_damping(rayleigh, matrix);
        }
        Ok(full)
    }

    /// A model already assembled, with the CEA settings and load increments to use.
    pub fn new(
        comm: Comm<'rt>,
        model: Model,
        operators: Operators<'rt>,
        cea: CeaOptions,
        increments: usize,
    ) -> Result<Self, crate::fem::AssemblyError> {
        let dofs = &operators.dofs;
        let sample = crate::fem::mass_sample::mass_sample(
            &model.mesh,
            crate::fem::mass_sample::SAMPLE_NODES,
        )?;
        let tracked_equations = sample
            .nodes
            .iter()
            .zip(&sample.weights)
            .flat_map(|(&n, &w)| {
                (0..3).filter_map(move |c| dofs.equation(n, c).map(|e| (e, w.sqrt())))
            })
            .collect();
        let spread = node_to_surface_spread(&model);
        let bodies = restraint::bodies(&model.mesh);
        let mut cea = cea;
        // Every CEA of a sweep follows a static that proved each body held (it stops on a
        // free one): no mode is rigid, whatever the round-off level says.
        if !bodies.is_empty() {
            cea.expected_rigid_modes.get_or_insert(0);
        }
        Ok(FullModel {
            spread,
            bodies,
            model,
            operators,
            free_mass: None,
            damping: None,
            tracked_equations,
            cea,
            rayleigh: None,
            increments,
            ranks: comm.size(),
            previous: None,
            earlier: None,
            reduced: None,
            edge_points: 0,
            every_mode: false,
            mass_rule: MassRule::default(),
        })
    }

    /// Rayleigh damping: the CEA becomes the quadratic problem with C.
    pub fn with_damping(mut self, rayleigh: RayleighDamping, matrix: Matrix<'rt>) -> Self {
        self.rayleigh = Some(rayleigh);
        self.damping = Some(matrix);
        self
    }

    /// The sliding equilibrium at friction `mu` (the swept pairs'), warm-started from the
    /// previous one this model solved, which it then becomes. Collective.
    ///
    /// The first point ramps the load (the study's increments, cut back on failure). Later
    /// points continue in friction from the previous equilibrium under the full load, from
    /// a secant prediction when two points came before ([`continuation::reach`]).
    pub(super) fn static_at(
        &mut self,
        comm: Comm<'rt>,
        mu: f64,
    ) -> Result<statics::StaticSolution, StudyError> {
        let Some(previous) = self.previous.take() else {
            self.warn_held_only_by_friction(comm)
                .map_err(|source| StudyError::Static { mu, source })?;
            let equilibrium = self
                .solve_static(
                    comm,
                    mu,
                    None,
                    self.increments,
                    StaticOptions::default().max_cutbacks,
                )
                .map_err(|source| StudyError::Static { mu, source })?;
            self.previous = Some(FrictionState::after(mu, &equilibrium));
            self.earlier = None;
            return Ok(equilibrium);
        };
        let predicted = self
            .earlier
            .as_ref()
            .and_then(|e| previous.predicted(e.mu, &e.displacement, mu));
        let start = predicted.as_ref().unwrap_or(&previous);
        match continuation::reach(&previous, mu, start, |at, from| {
            self.solve_static(comm, at, Some(from), 1, 0)
        }) {
            Ok(equilibrium) => {
                self.previous = Some(FrictionState::after(mu, &equilibrium));
                self.earlier = Some(PathPoint {
                    mu: previous.mu,
                    displacement: previous.displacement,
                });
                Ok(equilibrium)
            }
            Err(source) => {
                let from = previous.mu;
                self.previous = Some(previous);
                Err(StudyError::StaticFrom { mu, from, source })
            }
        }
    }

    /// One static solve at friction `mu` from `start` (or from rest). Collective.
    fn solve_static(
        &mut self,
        comm: Comm<'rt>,
        mu: f64,
        start: Option<&FrictionState>,
        increments: usize,
        max_cutbacks: usize,
    ) -> Result<statics::StaticSolution, statics::StaticsError> {
        let pairs = self.model.pairs_at(mu);
        let Operators {
            dofs,
            stiffness,
            load,
            ..
        } = &self.operators;
        let no_slip = SlipHistory::default();
        let problem = StaticProblem {
            dofs,
            stiffness,
            load,
            pairs: &pairs,
            slip: start.map_or(&no_slip, |p| &p.slip),
            bodies: &self.bodies,
            constraints: self.operators.constraints.as_ref(),
        };
        statics::solve(
            comm,
            &problem,
            start.map(|p| &p.displacement[..]),
            &StaticOptions {
                increments,
                max_cutbacks,
                ..Default::default()
            },
        )
    }

    /// Names on rank 0's log every body that only friction holds against rigid motion (a
    /// forgotten guide pin): the solve goes on, as Abaqus's would, since stick is a
    /// restraint, but the user learns which body rests on it. Collective.
    fn warn_held_only_by_friction(&self, comm: Comm<'rt>) -> Result<(), statics::StaticsError> {
        let Operators {
            dofs,
            stiffness,
            load,
            ..
        } = &self.operators;
        let problem = StaticProblem {
            dofs,
            stiffness,
            load,
            pairs: &self.model.pairs,
            slip: &SlipHistory::default(),
            bodies: &self.bodies,
            constraints: self.operators.constraints.as_ref(),
        };
        let rest = vec![[0.0; 3]; self.model.node_count()];
        for free in statics::held_only_by_friction(comm, &problem, &rest)? {
            tracing::warn!(
                "only friction holds a body: {free}; give it supports, springs or links \
                 (guide pins) if it is not meant to rest on the stick of its contacts"
            );
        }
        Ok(())
    }

    /// With constraints, the forces they apply at `equilibrium` (every node); `None`
    /// without. Collective.
    fn constraint_forces(
        &self,
        comm: Comm<'rt>,
        pairs: &[contact::ContactPair],
        equilibrium: &statics::StaticSolution,
    ) -> Result<Option<Vec<[f64; 3]>>, statics::StaticsError> {
        let Operators {
            dofs,
            stiffness,
            load,
            constraints,
            ..
        } = &self.operators;
        if constraints.is_none() {
            return Ok(None);
        }
        let problem = StaticProblem {
            dofs,
            stiffness,
            load,
            pairs,
            slip: &equilibrium.slip_before,
            bodies: &self.bodies,
            constraints: constraints.as_ref(),
        };
        statics::constraint_forces(
            comm,
            &problem,
            &equilibrium.slip_before,
            &equilibrium.displacement,
            1.0,
        )
        .map(Some)
    }

    /// The last equilibrium solved, as a checkpoint keeps it.
    pub(super) fn previous_state(&self) -> Option<EquilibriumState> {
        self.previous
            .as_ref()
            .map(|p| EquilibriumState::new(p.mu, &p.displacement, &p.slip))
    }

    /// The equilibrium before the last, as a checkpoint keeps it (the secant predictor's).
    pub(super) fn earlier_state(&self) -> Option<PathPoint> {
        self.earlier.clone()
    }

    /// Makes `point` the equilibrium before the last (after [`Self::restore_previous`], which
    /// clears it).
    pub(super) fn restore_earlier(&mut self, point: Option<&PathPoint>) -> Result<(), StudyError> {
        let nodes = self.model.node_count();
        if let Some(p) = point.filter(|p| p.displacement.len() != nodes) {
            return Err(StudyError::Checkpoint(format!(
                "its earlier equilibrium holds {} displacements for a model of {nodes} nodes",
                p.displacement.len()
            )));
        }
        self.earlier = point.cloned();
        Ok(())
    }

    /// Makes `state` the last equilibrium solved (none: the next point starts from rest).
    pub(super) fn restore_previous(
        &mut self,
        state: Option<&EquilibriumState>,
    ) -> Result<(), StudyError> {
        let nodes = self.model.node_count();
        self.earlier = None;
        self.previous = match state {
            None => None,
            Some(s) if s.displacement.len() != nodes || s.slip.len() > self.model.pairs.len() => {
                return Err(StudyError::Checkpoint(format!(
                    "it holds {} displacements and {} pairs' slip for a model of {nodes} \
                     nodes and {} pairs",
                    s.displacement.len(),
                    s.slip.len(),
                    self.model.pairs.len()
                )));
            }
            Some(s) => Some(FrictionState {
                mu: s.mu,
                displacement: s.displacement.clone(),
                slip: s.slip_history(),
            }),
        };
        Ok(())
    }

    pub(super) fn operators(&self) -> &Operators<'rt> {
        &self.operators
    }

    /// The equations a mode is compared on across the sweep, each with the square root of
    /// the mass it stands for (see the field).
    pub(super) fn tracked_equations(&self) -> &[(usize, f64)] {
        &self.tracked_equations
    }

    /// Runs `f` on the operators with the contact tangent at `u` (every pair, the swept ones
    /// at friction `mu`) formed in K, taken out again afterwards (see `solve_point`).
    /// Collective.
    pub(super) fn with_tangent<T>(
        &mut self,
        comm: Comm<'rt>,
        mu: f64,
        u: &[[f64; 3]],
        slip: &SlipHistory,
        f: impl FnOnce(&Operators<'rt>) -> Result<T, StudyError>,
    ) -> Result<T, StudyError> {
        let pairs = &self.model.pairs_at(mu);
        pencil::with_tangent(
            &mut self.operators,
            |ops, scale| {
                let Operators {
                    dofs, stiffness, ..
                } = ops;
                statics::add_contact_tangent(comm, stiffness, dofs, pairs, slip, u, scale)
                    .map(drop)
                    .map_err(|source| StudyError::Tangent { mu, source })
            },
            f,
        )
    }
}

impl<'rt> FrictionModel<'rt> for FullModel<'rt> {
    fn checkpoint(&self) -> ModelCheckpoint {
        ModelCheckpoint {
            previous: self.previous_state(),
            earlier: self.earlier.clone(),
            superelement: None,
        }
    }

    fn restore(
        &mut self,
        _comm: Comm<'rt>,
        checkpoint: &ModelCheckpoint,
    ) -> Result<(), StudyError> {
        self.restore_previous(checkpoint.previous.as_ref())?;
        self.restore_earlier(checkpoint.earlier.as_ref())
    }

    fn info(&self) -> ModelInfo {
        let mesh = &self.model.mesh;
        ModelInfo {
            source: self.model.source.clone(),
            nodes: self.model.node_count(),
            elements: mesh.elements.len(),
            equations: self.operators.solver_dofs().equations(),
            ranks: self.ranks,
            pairs: self
                .model
                .pairs
                .iter()
                .map(|p| p.settings.name.clone())
                .collect(),
            contact_points: self.model.pairs.iter().map(|p| p.points.len()).sum(),
            applied_load: self.model.applied_load(),
            max_frequency_hz: self.cea.max_frequency_hz,
            damping: self.rayleigh,
            superelements: None,
        }
    }

    fn mesh(&self) -> &Mesh {
        &self.model.mesh
    }

    fn solve_point(&mut self, comm: Comm<'rt>, mu: f64) -> Result<PointOutcome, StudyError> {
        let root = comm.rank() == 0;
        let t = Instant::now();
        let t_static = Instant::now();
        let equilibrium = self.static_at(comm, mu)?;
        let u = &equilibrium.displacement;
        let pairs = &self.model.pairs_at(mu);
        let constraint_forces = self
            .constraint_forces(comm, pairs, &equilibrium)
            .map_err(|source| StudyError::Static { mu, source })?;
        let mut contact_reports = Vec::new();
        let mut normal_total = 0.0;
        for ((pair, states), &swept) in pairs
            .iter()
            .zip(&equilibrium.contact)
            .zip(&self.model.swept)
        {
            let s = contact::summarize_states(pair, states);
            // The disc/pad pairs carry the brake load to the disc; the other pairs of a
            // floating caliper (piston, fingers, abutments) carry it on the way there.
            if swept {
                normal_total += s.normal_force;
            }
            contact_reports.push(PairReport::new(&pair.settings.name, &s));
        }
        let static_seconds = t_static.elapsed().as_secs_f64();
        tracing::debug!(
            "after the static solve: peak memory {:.0} MiB on this rank",
            peak_rss_mib()
        );
        let t_cea = Instant::now();
        // M does not change with mu: with constraints, C^T M C is made once.
        if self.free_mass.is_none() {
            self.free_mass = pencil::projected_mass(&self.operators)?;
        }
        let after = &equilibrium.slip_after;
        // Left vectors (for the sensitivities) only where the derivative is the sweep's.
        let held = self.kept_slipping_points(pairs, &equilibrium);
        if held > 0 && self.damping.is_none() {
            tracing::debug!(
                "mu {mu}: no friction sensitivities: {held} points of the kept pairs slip ({})",
                sensitivity::HELD_SLIP
            );
        }
        let sensitivities = held == 0 && self.damping.is_none();
        let mut result = self.cea_about(comm, mu, pairs, after, u, sensitivities)?;
        // Friction moves modes little from one point to the next, and an edge check's moved
        // contacts little more: the next CEA sizes its first window on this one's count.
        self.cea.expected_modes = Some(result.modes.len());
        let t_edge = Instant::now();
        let edge = if self.edge_points > 0 {
            let mut check = EdgeCheck {
                points: self.edge_points,
                ..Default::default()
            };
            for direction in [EdgeMove::Open, EdgeMove::Close] {
                let (moved, count) = contact_edge::moved_edge(
                    pairs,
                    &self.model.swept,
                    &equilibrium.contact,
                    u,
                    self.edge_points,
                    direction,
                );
                let modes = if count == 0 {
                    result.modes.clone()
                } else {
                    let moved = self.cea_about(comm, mu, pairs, after, &moved, false)?;
                    result
                        .modes
                        .iter()
                        .map(|m| nearest(&moved.modes, m).unwrap_or_else(|| m.clone()))
                        .collect()
                };
                match direction {
                    EdgeMove::Open => (check.opened, check.with_opened) = (count, modes),
                    EdgeMove::Close => (check.closed, check.with_closed) = (count, modes),
                }
            }
            check.seconds = t_edge.elapsed().as_secs_f64();
            // A reduced interface's contacts are no candidates: nothing was checked.
            (check.opened + check.closed > 0).then_some(check)
        } else {
            None
        };
        for (re, im) in &mut result.shapes {
            pencil::expand_shape(&self.operators, re)?;
            pencil::expand_shape(&self.operators, im)?;
        }
        // The unstable modes' friction sensitivities: du/dmu once for all of them.
        let t_rate = Instant::now();
        let du = if result.left.iter().any(Option::is_some) {
            self.equilibrium_rate(comm, mu, &equilibrium)
        } else {
            None
        };
        for left in result.left.iter_mut().flatten() {
            pencil::expand_shape(&self.operators, &mut left.re)?;
            pencil::expand_shape(&self.operators, &mut left.im)?;
        }
        let rate_seconds = t_rate.elapsed().as_secs_f64();
        let Operators { dofs, .. } = &self.operators;
        // The edge's CEAs are their own cost (EdgeCheck::seconds).
        let cea_seconds = t_cea.elapsed().as_secs_f64() - edge.as_ref().map_or(0.0, |c| c.seconds);
        // Shapes to rank 0: restricted for tracking; full for the unstable ones' VTU.
        let mut tracking_shapes = Vec::with_capacity(result.shapes.len());
        let mut unstable = Vec::new();
        let mut modes = result.modes.clone();
        // What the unstable modes' shapes say of their cause: rank 0's time, for the log.
        let mut why_seconds = 0.0;
        for ((mode, (re, im)), left) in modes.iter_mut().zip(&result.shapes).zip(&result.left) {
            let (re, im) = (re.gather_to_zero()?, im.gather_to_zero()?);
            // The same modes have left vectors on every rank: the gathers stay collective.
            let left = match left {
                Some(l) => Some((l.re.gather_to_zero()?, l.im.gather_to_zero()?, l.mass_form)),
                None => None,
            };
            if root {
                tracking_shapes.push(
                    self.tracked_equations
                        .iter()
                        .map(|&(e, w)| w * Complex64::new(re[e], im[e]))
                        .collect::<Vec<_>>(),
                );
                if mode.unstable {
                    let (re, im) = (dofs.displacements(&re), dofs.displacements(&im));
                    let t_why = Instant::now();
                    let feed = self.contributions(mode, pairs, &equilibrium, &re, &im);
                    if let (Some((yr, yi, mass_form)), Some(rates)) = (left, &du) {
                        let left = LeftShape {
                            re: dofs.displacements(&yr),
                            im: dofs.displacements(&yi),
                            mass_form,
                        };
                        mode.sensitivity = self.friction_sensitivity(
                            mode,
                            mu,
                            &equilibrium,
                            &re,
                            &im,
                            &left,
                            &rates.friction,
                        );
                        mode.modulus_sensitivity = self.modulus_sensitivities(
                            mode,
                            mu,
                            &equilibrium,
                            &re,
                            &im,
                            &left,
                            rates,
                        );
                    }
                    why_seconds += t_why.elapsed().as_secs_f64();
                    let re = mesh_part(re, &self.model.mesh);
                    let im = mesh_part(im, &self.model.mesh);
                    unstable.push(UnstableShape {
                        mode: mode.clone(),
                        re,
                        im,
                        feed,
                    });
                } else if self.every_mode && !mode.rigid_body {
                    // The parts add up to the real part: a coupled pair's stable partner has
                    // them negative; a mode with no real part (to the unstable threshold) has
                    // parts that cancel, and shares of a zero sum say nothing: none then.
                    let (re, im) = (dofs.displacements(&re), dofs.displacements(&im));
                    let t_why = Instant::now();
                    self.contributions(mode, pairs, &equilibrium, &re, &im);
                    if mode.real_part.abs() <= self.cea.unstable_threshold * mode.lambda.norm() {
                        mode.pair_shares = None;
                    }
                    why_seconds += t_why.elapsed().as_secs_f64();
                }
            }
        }
        if root && why_seconds > 0.0 {
            tracing::debug!(
                "mu {mu}: bodies' and pairs' shares and sensitivities of the unstable modes in \
                 {why_seconds:.3} s, du/dmu in {rate_seconds:.3} s"
            );
        }
        // Peak resident memory so far (VmHWM), largest rank and all ranks together.
        let mut peak = [peak_rss_mib()];
        let mut peak_sum = peak;
        comm.max_in_place(&mut peak);
        comm.sum_in_place(&mut peak_sum);
        let applied = self.model.applied_load();
        let report = SweepPointReport {
            friction: mu,
            static_iterations: equilibrium.increments.iter().map(|i| i.iterations).sum(),
            static_factorizations: equilibrium
                .increments
                .iter()
                .map(|i| i.factorizations)
                .sum(),
            static_residuals: equilibrium
                .increments
                .last()
                .map(|i| i.residual_history.clone())
                .unwrap_or_default(),
            cutbacks: equilibrium.cutbacks.len(),
            contact: contact_reports,
            balance_ratio: if applied > 0.0 {
                normal_total / applied
            } else {
                0.0
            },
            eigenvalues: modes,
            static_seconds,
            cea_seconds,
            cea_shifts: result.targets.len(),
            contact_edge: edge,
            inserted: false,
            path: Vec::new(),
            contact_changed: false,
            seconds: t.elapsed().as_secs_f64(),
            peak_rss_mib_max_rank: peak[0],
            peak_rss_mib_all_ranks: peak_sum[0],
            superelement: None,
        };
        let fields = root.then(|| {
            let mut fields =
                self.point_fields(&equilibrium.displacement, &equilibrium.contact, unstable);
            fields.constraint_forces = constraint_forces.map(|f| mesh_part(f, &self.model.mesh));
            fields
        });
        Ok(PointOutcome {
            report,
            tracking_shapes,
            fields,
        })
    }
}

/// The mesh nodes' values of a field over all nodes (extra nodes are not drawn).
pub(super) fn mesh_part(mut values: Vec<[f64; 3]>, mesh: &Mesh) -> Vec<[f64; 3]> {
    values.truncate(mesh.nodes.len());
    values
}

impl FullModel<'_> {
    /// The static displacement, the contact map and the pad surfaces' pressure (rank 0).
    pub(super) fn point_fields(
        &self,
        displacement: &[[f64; 3]],
        contact: &[Vec<contact::PointState>],
        unstable: Vec<UnstableShape>,
    ) -> PointFields {
        fields_with(&self.model, &self.spread, displacement, contact, unstable)
    }
}

/// The fields of a node-to-surface model's equilibrium (rank 0), as a sweep point writes
/// them, every element-based pair in its contact map: what `squeal run` writes for a deck's
/// steps.
pub fn equilibrium_fields(
    model: &Model,
    displacement: &[[f64; 3]],
    contact: &[Vec<contact::PointState>],
    unstable: Vec<UnstableShape>,
) -> PointFields {
    fields_with(
        model,
        &spread_of(model, |_| true),
        displacement,
        contact,
        unstable,
    )
}

/// The static displacement, the contact map and the pressure on the pad surfaces `spread`.
fn fields_with(
    model: &Model,
    spread: &[SweptSurface],
    displacement: &[[f64; 3]],
    contact: &[Vec<contact::PointState>],
    unstable: Vec<UnstableShape>,
) -> PointFields {
    {
        let n = model.mesh.nodes.len();
        let mut contact_pressure = vec![0.0; n];
        let mut contact_closed = vec![-1.0; n];
        // Every pair's state at its slave nodes (node-to-surface pairs; a reduced
        // interface's own nodes are not drawn).
        let mut contact_state = vec![-1.0; n];
        for (pair, states) in model.pairs.iter().zip(contact) {
            for (pt, s) in pair.points.iter().zip(states) {
                if pt.slave_node < n && pt.master_face.is_some() {
                    contact_state[pt.slave_node] = match s.status {
                        contact::Status::Open => 0.0,
                        contact::Status::Stick => 1.0,
                        contact::Status::Slip => 2.0,
                    };
                }
            }
        }
        let mut map = ContactMap::default();
        for swept in spread {
            let pair = &model.pairs[swept.pair];
            let states = &contact[swept.pair];
            for (pt, s) in pair.points.iter().zip(states) {
                map.points.push(ContactMapPoint {
                    pair: pair.settings.name.clone(),
                    position: pt.position,
                    closed: s.closed,
                    normal_force: s.normal_force,
                });
                if pt.slave_node < n {
                    contact_closed[pt.slave_node] = if s.closed { 1.0 } else { 0.0 };
                }
            }
            let forces: Vec<f64> = states.iter().map(|s| s.normal_force).collect();
            let pressure_at = swept.pressure(&forces);
            // Every surface node, loaded or not, so that two models compare node by node.
            for (&node, &area) in &swept.areas {
                let pressure = pressure_at.get(&node).copied().unwrap_or(0.0);
                contact_pressure[node] = pressure;
                map.surface.push(SurfacePressure {
                    pair: pair.settings.name.clone(),
                    node,
                    position: model.mesh.nodes[node],
                    area,
                    pressure,
                });
            }
        }
        // The assembly already checked every element and material.
        let von_mises = crate::fem::stress::nodal_von_mises(&model.mesh, displacement)
            .unwrap_or_else(|e| {
                tracing::warn!("von Mises stress not computed: {e}");
                vec![0.0; n]
            });
        let mut nodes: Vec<usize> = spread
            .iter()
            .flat_map(|swept| swept.areas.keys().copied())
            .collect();
        nodes.sort_unstable();
        nodes.dedup();
        map.unstable_shapes = unstable
            .iter()
            .map(|shape| SurfaceShape {
                frequency_hz: shape.mode.frequency_hz,
                real_part: shape.mode.real_part,
                re: nodes.iter().map(|&n| shape.re[n]).collect(),
                im: nodes.iter().map(|&n| shape.im[n]).collect(),
            })
            .collect();
        map.shape_nodes = nodes;
        PointFields {
            contact: map,
            von_mises,
            static_displacement: mesh_part(displacement.to_vec(), &model.mesh),
            contact_pressure,
            contact_closed,
            contact_state,
            unstable,
            constraint_forces: None,
        }
    }
}

impl<'rt> FullModel<'rt> {
    /// The CEA about the equilibrium `u` at friction `mu`: the tangent of the perturbation
    /// (the consistent one from the committed history `after`, with CalculiX's additions for
    /// pairs with its law: contact::variant) formed in K for the CEA (`analysis::pencil`), taken out after.
    fn cea_about(
        &mut self,
        comm: Comm<'rt>,
        mu: f64,
        pairs: &[contact::ContactPair],
        after: &SlipHistory,
        u: &[[f64; 3]],
        left_vectors: bool,
    ) -> Result<cea::CeaResult<'rt>, StudyError> {
        let options = &CeaOptions {
            left_vectors,
            ..self.cea.clone()
        };
        let (free_mass, damping) = (&self.free_mass, self.damping.as_ref());
        pencil::with_tangent(
            &mut self.operators,
            |ops, scale| {
                let Operators {
                    dofs, stiffness, ..
                } = ops;
                statics::add_perturbation_tangent(comm, stiffness, dofs, pairs, after, u, scale)
                    .map_err(|source| StudyError::Tangent { mu, source })
            },
            |ops| {
                let pencil = match free_mass {
                    Some(m) => Pencil::with_mass(ops, m)?,
                    None => Pencil::of(ops)?,
                };
                collective(
                    comm,
                    cea::solve(comm, pencil.stiffness(), pencil.mass(), damping, options)
                        .map_err(|source| StudyError::CeaAt { mu, source }),
                )
            },
        )
    }
}

/// The mode of `modes` nearest to `m` in eigenvalue.
fn nearest(modes: &[cea::ComplexMode], m: &cea::ComplexMode) -> Option<cea::ComplexMode> {
    modes
        .iter()
        .min_by(|a, b| {
            (a.lambda - m.lambda)
                .norm()
                .total_cmp(&(b.lambda - m.lambda).norm())
        })
        .cloned()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::study::config::Study;

    /// The patch test of the written pressure: reduced contact nodes all at one pressure p
    /// (F_k = p A_k) give p at every pad node they reach, to round-off, whatever the
    /// weights; the full model's points at p give p at every node. Before, the reduced
    /// spread came back with an 18 % L2 scatter (small brake, 106 nodes per pad).
    #[test]
    fn a_uniform_pressure_is_written_uniform_by_both_models() {
        let full = Model::from_spec(&Study::builtin("tiny").model_spec()).unwrap();
        let p = 1.7e6;
        for spread in node_to_surface_spread(&full) {
            let forces: Vec<f64> = spread.point_area.iter().map(|a| p * a).collect();
            for (node, q) in spread.pressure(&forces) {
                assert!((q - p).abs() < 1e-12 * p, "full, node {node}: {q}");
            }
        }
        for area_weighting in [false, true] {
            let settings = reduce::InterfaceSettings {
                area_weighting,
                ..reduce::InterfaceSettings::paper(reduce::GridSize::Count(22))
            };
            let reduced = reduce::reduce_interface(&full, &settings).unwrap();
            let spreads = reduced_spread(&reduced);
            assert_eq!(spreads.len(), 2);
            for spread in spreads {
                let forces: Vec<f64> = spread.point_area.iter().map(|a| p * a).collect();
                let written = spread.pressure(&forces);
                let reached = written.values().filter(|&&q| q != 0.0).count();
                // The grid-optimal radius leaves no pad node out of every coupling.
                assert_eq!(reached, spread.areas.len());
                for (node, q) in written {
                    assert!((q - p).abs() < 1e-12 * p, "reduced, node {node}: {q}");
                }
            }
        }
    }
}
