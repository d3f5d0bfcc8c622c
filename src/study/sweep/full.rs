//! A [`Model`] solved with PETSc at each friction value: the full reference model, or a
//! reduced-interface model (a full-size model whose disc/pad interface is reduced). SNES
//! gives the sliding equilibrium, SLEPc the CEA about it.

use super::output::{ModelInfo, PairReport, SweepPointReport};
use super::{
    ContactMap, ContactMapPoint, FrictionModel, PointFields, PointOutcome, SurfacePressure,
    SurfaceShape, UnstableShape,
};
use crate::analysis::cea::{self, CeaOptions, RayleighDamping};
use crate::analysis::restraint::{self, Body};
use crate::analysis::statics::{self, StaticOptions, StaticProblem};
use crate::contact;
use crate::mesh::Mesh;
use crate::model::{self, Model, Operators};
use crate::petsc::{Comm, Matrix};
use crate::reduce;
use crate::study::bench::peak_rss_mib;
use crate::study::config::Study;
use crate::study::report::collective;
use anyhow::Context;
use num_complex::Complex64;
use std::time::Instant;

/// A model with its operators, ready for a sweep.
pub struct FullModel<'rt> {
    pub model: Model,
    operators: Operators<'rt>,
    damping: Option<Matrix<'rt>>,
    bodies: Vec<Body>,
    /// Equations on which mode shapes are compared for tracking: every DOF of the swept
    /// pairs' nodes (where the friction coupling happens).
    tracked_equations: Vec<usize>,
    cea: CeaOptions,
    rayleigh: Option<RayleighDamping>,
    increments: usize,
    ranks: usize,
    /// The previous point's equilibrium (warm start).
    previous: Option<Vec<[f64; 3]>>,
    /// Where each swept pair's contact forces land on its pad surface.
    spread: Vec<SweptSurface>,
    /// The reduced interface this model was made with (none for the full model): what a
    /// super-element is built on.
    pub(super) reduced: Option<reduce::ReducedInterface>,
}

/// A swept pair's pad surface: per contact point, the surface nodes its force goes to with
/// their weights, and every surface node's tributary area.
struct SweptSurface {
    pair: usize,
    per_point: Vec<Vec<(usize, f64)>>,
    areas: std::collections::BTreeMap<usize, f64>,
}

impl<'rt> FullModel<'rt> {
    /// Builds and assembles the model of a study (collective; errors name the study file
    /// and key).
    pub fn from_study(comm: Comm<'rt>, study: &Study, file: &str) -> anyhow::Result<Self> {
        let local = Model::from_spec(&study.model_spec())
            .map_err(|e| anyhow::anyhow!("{file}: {e}"))
            .and_then(|model| match &study.reduction {
                None => Ok((model, None)),
                Some(r) => reduce::reduce_interface(&model, &r.settings())
                    .map(|reduced| {
                        let spread = reduced_spread(&reduced);
                        (reduced.model.clone(), Some((spread, reduced)))
                    })
                    .map_err(|e| anyhow::anyhow!("{file}: reduction: {e}")),
            });
        let (model, reduction) = collective(comm, local)?;
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
        let operators = model::assemble(comm, &model, study.analysis.mass_rule)?;
        let damping = match study.analysis.damping {
            Some(d) => Some(d.matrix(&operators.stiffness, &operators.mass)?),
            None => None,
        };
        let cea = CeaOptions {
            max_frequency_hz: study.analysis.max_frequency_hz,
            unstable_threshold: study.analysis.unstable_threshold,
            modes_per_target: study.analysis.window,
            ..Default::default()
        };
        let mut full = Self::new(comm, model, operators, cea, study.analysis.increments);
        if let Some((spread, reduced)) = reduction {
            full.spread = spread;
            full.reduced = Some(reduced);
        }
        if let (Some(rayleigh), Some(matrix)) = (study.analysis.damping, damping) {
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
    ) -> Self {
        let dofs = &operators.dofs;
        let tracked_equations = model
            .swept_nodes()
            .iter()
            .flat_map(|&n| (0..3).filter_map(move |c| dofs.equation(n, c)))
            .collect();
        let spread = node_to_surface_spread(&model);
        FullModel {
            spread,
            bodies: restraint::bodies(&model.mesh),
            model,
            operators,
            damping: None,
            tracked_equations,
            cea,
            rayleigh: None,
            increments,
            ranks: comm.size(),
            previous: None,
            reduced: None,
        }
    }

    /// Rayleigh damping: the CEA becomes the quadratic problem with C.
    pub fn with_damping(mut self, rayleigh: RayleighDamping, matrix: Matrix<'rt>) -> Self {
        self.rayleigh = Some(rayleigh);
        self.damping = Some(matrix);
        self
    }

    /// The sliding equilibrium at friction `mu` (the swept pairs'), warm-started from the
    /// previous one this model solved, which it then becomes. Collective.
    pub(super) fn static_at(
        &mut self,
        comm: Comm<'rt>,
        mu: f64,
    ) -> anyhow::Result<statics::StaticSolution> {
        self.model.set_swept_friction(mu);
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
            bodies: &self.bodies,
        };
        let equilibrium = statics::solve(
            comm,
            &problem,
            self.previous.as_deref(),
            &StaticOptions {
                increments: self.increments,
                ..Default::default()
            },
        )
        .with_context(|| format!("static equilibrium at mu = {mu}"))?;
        self.previous = Some(equilibrium.displacement.clone());
        Ok(equilibrium)
    }

    pub(super) fn operators(&self) -> &Operators<'rt> {
        &self.operators
    }

    /// Runs `f` on the operators with the contact tangent at `u` (every pair, the swept ones
    /// at friction `mu`) formed in K, taken out again afterwards (see `solve_point`).
    /// Collective.
    pub(super) fn with_tangent<T>(
        &mut self,
        comm: Comm<'rt>,
        mu: f64,
        u: &[[f64; 3]],
        f: impl FnOnce(&Operators<'rt>) -> anyhow::Result<T>,
    ) -> anyhow::Result<T> {
        self.model.set_swept_friction(mu);
        let Operators {
            dofs, stiffness, ..
        } = &mut self.operators;
        statics::add_contact_tangent(comm, stiffness, dofs, &self.model.pairs, u, 1.0)?;
        let result = f(&self.operators);
        let Operators {
            dofs, stiffness, ..
        } = &mut self.operators;
        statics::add_contact_tangent(comm, stiffness, dofs, &self.model.pairs, u, -1.0)?;
        result
    }
}

impl<'rt> FrictionModel<'rt> for FullModel<'rt> {
    fn info(&self) -> ModelInfo {
        let mesh = &self.model.mesh;
        ModelInfo {
            source: self.model.source.clone(),
            nodes: self.model.node_count(),
            elements: mesh.elements.len(),
            equations: self.operators.dofs.equations(),
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

    fn solve_point(&mut self, comm: Comm<'rt>, mu: f64) -> anyhow::Result<PointOutcome> {
        let root = comm.rank() == 0;
        let t = Instant::now();
        let t_static = Instant::now();
        let equilibrium = self.static_at(comm, mu)?;
        let u = &equilibrium.displacement;
        let mut contact_reports = Vec::new();
        let mut normal_total = 0.0;
        for pair in &self.model.pairs {
            let s = contact::summarize(pair, u)?;
            normal_total += s.normal_force;
            contact_reports.push(PairReport::new(&pair.settings.name, &s));
        }
        let static_seconds = t_static.elapsed().as_secs_f64();
        let Operators {
            dofs,
            stiffness: k,
            mass: m,
            ..
        } = &mut self.operators;
        tracing::debug!(
            "after the static solve: peak memory {:.0} MiB on this rank",
            peak_rss_mib()
        );
        let t_cea = Instant::now();
        // K_t = K + dF_c/dU is formed in K itself and taken out after the CEA: on the
        // industrial preset a separate tangent is 0.5 GB more at the memory peak, and K
        // comes back to within one rounding per entry, far below anything the next static
        // solve resolves.
        statics::add_contact_tangent(comm, k, dofs, &self.model.pairs, u, 1.0)?;
        let result = collective(
            comm,
            cea::solve(comm, k, m, self.damping.as_ref(), &self.cea),
        );
        statics::add_contact_tangent(comm, k, dofs, &self.model.pairs, u, -1.0)?;
        let result = result?;
        let cea_seconds = t_cea.elapsed().as_secs_f64();
        // Friction moves modes little from one point to the next: the next CEA sizes its
        // first window on this one's count.
        self.cea.expected_modes = Some(result.modes.len());
        // Shapes to rank 0: restricted for tracking; full for the unstable ones' VTU.
        let mut tracking_shapes = Vec::with_capacity(result.shapes.len());
        let mut unstable = Vec::new();
        for (mode, (re, im)) in result.modes.iter().zip(&result.shapes) {
            let (re, im) = (re.gather_to_zero()?, im.gather_to_zero()?);
            if root {
                tracking_shapes.push(
                    self.tracked_equations
                        .iter()
                        .map(|&e| Complex64::new(re[e], im[e]))
                        .collect::<Vec<_>>(),
                );
                if mode.unstable {
                    unstable.push(UnstableShape {
                        mode: mode.clone(),
                        re: mesh_part(dofs.displacements(&re), &self.model.mesh),
                        im: mesh_part(dofs.displacements(&im), &self.model.mesh),
                    });
                }
            }
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
            eigenvalues: result.modes.clone(),
            static_seconds,
            cea_seconds,
            cea_shifts: result.targets.len(),
            seconds: t.elapsed().as_secs_f64(),
            peak_rss_mib_max_rank: peak[0],
            peak_rss_mib_all_ranks: peak_sum[0],
            superelement: None,
        };
        let fields = root
            .then(|| self.point_fields(&equilibrium.displacement, &equilibrium.contact, unstable));
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

/// Where a node-to-surface model's contact forces go: each swept pair's points to their
/// slave node.
fn node_to_surface_spread(model: &Model) -> Vec<SweptSurface> {
    let mut spread = Vec::new();
    for (i, pair) in model.pairs.iter().enumerate() {
        let Some(Some((slave, _))) = model.pair_surfaces.get(i) else {
            continue;
        };
        let Some(surface) = model.mesh.surfaces.get(slave) else {
            continue;
        };
        if model.swept[i] {
            spread.push(SweptSurface {
                pair: i,
                per_point: pair.points.iter().map(|p| p.slave.clone()).collect(),
                areas: contact::tributary_areas(&model.mesh, surface)
                    .into_iter()
                    .collect(),
            });
        }
    }
    spread
}

/// A reduced interface's contact forces go to its distributing couplings' pad nodes.
fn reduced_spread(reduced: &reduce::ReducedInterface) -> Vec<SweptSurface> {
    let model = &reduced.model;
    let mut spread = Vec::new();
    for pad in &reduced.pads {
        let Some(i) = model.pairs.iter().position(|p| p.settings.name == pad.pair) else {
            continue;
        };
        let Some(surface) = model.mesh.surfaces.get(&pad.grid.surface) else {
            continue;
        };
        spread.push(SweptSurface {
            pair: i,
            per_point: pad
                .couplings
                .iter()
                .map(|c| c.nodes.iter().map(|n| (n.node, n.weight)).collect())
                .collect(),
            areas: contact::tributary_areas(&model.mesh, surface)
                .into_iter()
                .collect(),
        });
    }
    spread
}

impl FullModel<'_> {
    /// The static displacement, the contact map and the pad surfaces' pressure (rank 0).
    pub(super) fn point_fields(
        &self,
        displacement: &[[f64; 3]],
        contact: &[Vec<contact::PointState>],
        unstable: Vec<UnstableShape>,
    ) -> PointFields {
        let model = &self.model;
        let n = model.mesh.nodes.len();
        let mut contact_pressure = vec![0.0; n];
        let mut contact_closed = vec![-1.0; n];
        let mut map = ContactMap::default();
        for swept in &self.spread {
            let pair = &model.pairs[swept.pair];
            let states = &contact[swept.pair];
            let mut force_on: std::collections::BTreeMap<usize, f64> = Default::default();
            for ((pt, s), nodes) in pair.points.iter().zip(states).zip(&swept.per_point) {
                map.points.push(ContactMapPoint {
                    pair: pair.settings.name.clone(),
                    position: pt.position,
                    closed: s.closed,
                    normal_force: s.normal_force,
                });
                for &(node, w) in nodes {
                    *force_on.entry(node).or_default() += w * s.normal_force;
                }
                if pt.slave_node < n {
                    contact_closed[pt.slave_node] = if s.closed { 1.0 } else { 0.0 };
                }
            }
            // Every surface node, loaded or not, so that two models compare node by node.
            for (&node, &area) in &swept.areas {
                let pressure = force_on.get(&node).copied().unwrap_or(0.0) / area;
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
        let mut nodes: Vec<usize> = self
            .spread
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
            unstable,
        }
    }
}
