//! The dense static and CEA of the current super-element at one friction value: the static
//! on rank 0 (broadcast), the CEA's windows shared between the ranks (each its part of the
//! band, every part's modes on every rank) or, on a small model, faer's solve on rank 0.
//!
//! The static starts where the strategy says: at the super-element's own equilibrium when it
//! was made or moved to this friction value (eq. 5: no step needed), else from the previous
//! point's dense static. A super-element with kept pairs on its boundary (issue 32:
//! `reduction.reduce_pairs`) carries their slip history along the sweep instead, on the
//! reduced-interface model's own path ([`crate::reduce::dense_path`]): the first point ramps
//! the load from rest, the later ones step in friction from the previous, and the CEA's
//! tangent is formed from the history after the static.

use super::SuperElementModel;
use crate::analysis::statics;
use crate::petsc::Comm;
use crate::reduce::assembly::{
    Assembly, AssemblyError, DenseCeaOptions, DenseCeaResult, DenseEigensolver, ReducedStatic,
    StaticOptions,
};
use crate::reduce::dense_cea::from_root;
use crate::reduce::dense_path::DenseState;
use crate::study::report::collective;
use crate::study::StudyError;
use num_complex::Complex64;
use std::time::Instant;

/// Rank 0's dense results, as every rank needs them.
pub(super) struct Dense {
    /// Each mode's lambda (the CEA's, (lambda^2 M + K_t) x = 0).
    pub lambdas: Vec<Complex64>,
    pub q_static: Vec<f64>,
    /// The slip history after the static, one anchor per boundary pair.
    pub anchors: Vec<[f64; 3]>,
    /// Each mode's shape in q.
    pub shapes: Vec<Vec<Complex64>>,
    /// Rank 0 only: the static, the modes, the start's relative residual, the static's and
    /// the CEA's seconds.
    pub root: Option<(ReducedStatic, DenseCeaResult, f64, f64, f64)>,
}

impl<'rt> SuperElementModel<'rt> {
    /// Whether the dense static carries a slip history along the sweep: a kept pair sits on
    /// the boundary with its own law, or nothing is inside the super-element at all.
    pub(super) fn carries_history(&self) -> bool {
        self.contact_free
            || self
                .current
                .as_ref()
                .is_some_and(|c| c.se.header.boundary.iter().any(|b| !b.swept()))
    }

    /// The dense static at `mu` (see the module doc).
    fn dense_static(
        &self,
        assembly: &Assembly<'_>,
        mu: f64,
        anchored: bool,
    ) -> Result<ReducedStatic, AssemblyError> {
        let se = assembly.super_element();
        let options = StaticOptions::default();
        if !self.carries_history() {
            let start = match (&self.previous_q, anchored) {
                (Some(q), false) => q.as_slice(),
                _ => se.equilibrium.as_slice(),
            };
            return assembly.solve_static_from(start, mu, &options);
        }
        match &self.dense_previous {
            None => assembly.static_from_rest(
                &vec![0.0; se.header.size],
                mu,
                self.increments,
                statics::StaticOptions::default().max_cutbacks,
                &options,
            ),
            Some(previous) => {
                let mut from = previous.clone();
                // A super-element made or moved here has another basis than the previous
                // point's q was in: start from its own equilibrium, with the history carried.
                if anchored {
                    from.q.clone_from(&se.equilibrium);
                }
                assembly.static_from_previous(&from, mu, &options)
            }
        }
    }

    /// The dense static on rank 0, broadcast; the dense CEA about it on every rank (each its
    /// share of the band's windows, [`DenseEigensolver::Windows`]); rank 0's results on every
    /// rank. Collective.
    pub(super) fn dense(
        &self,
        comm: Comm<'rt>,
        mu: f64,
        anchored: bool,
    ) -> Result<Dense, StudyError> {
        let current = self.current.as_ref().ok_or(StudyError::NoSuperElement)?;
        let se = &current.se;
        let n = se.header.size;
        let pairs = se.header.boundary.len();
        // The static: [1, q_static, the anchors] from rank 0, or [0].
        let mut reached = Vec::new();
        let mut root_static = None;
        let local = if comm.rank() == 0 {
            let run = || -> Result<_, AssemblyError> {
                let assembly = Assembly::new(se, &self.settings.contact)?;
                // Where the static starts, with the history it starts from.
                let start_residual = match (&self.dense_previous, &self.previous_q, anchored) {
                    (Some(p), _, _) if self.carries_history() => {
                        let from = if anchored { &se.equilibrium } else { &p.q };
                        assembly
                            .clone()
                            .with_history(p.anchors.clone())?
                            .relative_residual(from, mu)
                    }
                    (_, Some(q), false) => assembly.relative_residual(q, mu),
                    _ => assembly.relative_residual(&se.equilibrium, mu),
                };
                let t = Instant::now();
                let statics = self.dense_static(&assembly, mu, anchored)?;
                Ok((statics, start_residual, t.elapsed().as_secs_f64()))
            };
            match run() {
                Ok(r) => {
                    reached.push(1.0);
                    reached.extend_from_slice(&r.0.q);
                    reached.extend(r.0.anchors().iter().flatten());
                    root_static = Some(r);
                    Ok(())
                }
                Err(e) => {
                    reached.push(0.0);
                    Err(StudyError::DenseAssembly { mu, source: e })
                }
            }
        } else {
            Ok(())
        };
        comm.broadcast_from_root(&mut reached);
        let local = local.and_then(|()| {
            if reached.first() == Some(&1.0) {
                Ok(())
            } else {
                Err(StudyError::FailedOnRoot("super-element assembly"))
            }
        });
        collective(comm, local)?;
        let q_static = reached[1..1 + n].to_vec();
        let anchors: Vec<[f64; 3]> = reached[1 + n..1 + n + 3 * pairs]
            .chunks(3)
            .map(|a| [a[0], a[1], a[2]])
            .collect();
        // The CEA's tangent from the history after the static (a kept Coulomb point that
        // slipped stays slipping, with the full stick stiffness across), on every rank from
        // the same bits.
        let t = Instant::now();
        let solver = DenseEigensolver::choose(n, comm);
        let options = DenseCeaOptions {
            max_frequency_hz: self.settings.max_frequency_hz,
            unstable_threshold: self.settings.unstable_threshold,
            // After a converged static: every body is held, no mode is rigid whatever the
            // round-off level (its ties' stiffness) says.
            expected_rigid_modes: Some(0),
        };
        let dense = |source| StudyError::DenseAssembly { mu, source };
        let cea = if let DenseEigensolver::Windows { .. } = solver {
            // Every rank takes part in the windows: the assembly is agreed on first, so that
            // no rank waits inside them for one that failed before.
            let assembly = Assembly::new(se, &self.settings.contact)
                .and_then(|a| a.with_history(anchors.clone()))
                .map_err(dense);
            let assembly = collective(comm, assembly)?;
            let cea = assembly
                .cea_by(solver, &q_static, mu, &options)
                .map_err(dense);
            collective(comm, cea)?
        } else {
            // faer's solve (a small model) is rank 0's alone, as the static: ranks on unlike
            // CPUs could round it differently, and every rank must decide from the same bits.
            let local = (comm.rank() == 0)
                .then(|| {
                    Assembly::new(se, &self.settings.contact)
                        .and_then(|a| a.with_history(anchors.clone()))
                        .and_then(|a| a.cea_by(solver, &q_static, mu, &options))
                        .map_err(dense)
                })
                .transpose();
            let on_root = collective(comm, local)?;
            from_root(comm, on_root, n, self.settings.unstable_threshold)
        };
        let cea_seconds = t.elapsed().as_secs_f64();
        let lambdas = cea.modes.iter().map(|m| m.lambda).collect();
        let shapes = cea.shapes.clone();
        let root = root_static.map(|(statics, start_residual, static_seconds)| {
            (statics, cea, start_residual, static_seconds, cea_seconds)
        });
        Ok(Dense {
            lambdas,
            q_static,
            anchors,
            shapes,
            root,
        })
    }

    /// Where the next point's dense static starts.
    pub(super) fn carry(&mut self, mu: f64, dense: &Dense) {
        self.previous_q = Some(dense.q_static.clone());
        self.dense_previous = Some(DenseState {
            mu,
            q: dense.q_static.clone(),
            anchors: dense.anchors.clone(),
        });
    }
}
