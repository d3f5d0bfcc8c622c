//! The dense static along a friction sweep, the path the reduced-interface model's own
//! sweep takes (`crate::analysis::statics`, `crate::analysis::continuation`), so that a kept
//! Coulomb pair on the boundary ([`super::superelement::BoundaryPair::own_law`]) reaches
//! each friction value with the slip history the full-size model would carry there:
//!
//! - the first point ramps the load from rest over the study's increments, each from the
//!   history the one before committed; an increment that fails is halved, at most
//!   `max_cutbacks` times;
//! - a later point steps in friction from the previous one under the full load, and when the
//!   direct step fails, takes it again in 2, 4, 8 and 16 equal friction steps
//!   ([`crate::analysis::continuation::SUBSTEPS`]), each carrying its history to the next.
//!   The load is never cut from a loaded state: unloading would make the contacts slip back.
//!
//! With no kept Coulomb pair on the boundary the history is empty and each point is the one
//! Newton solve it always was.

use super::assembly::{Assembly, AssemblyError, LineSearch, ReducedStatic, StaticOptions};
use super::tangent_solver::TangentSolver;
use crate::analysis::continuation::SUBSTEPS;

/// Where a dense static starts from: an equilibrium at friction `mu`, its q and the slip
/// history after it.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct DenseState {
    pub mu: f64,
    pub q: Vec<f64>,
    /// One anchor per boundary pair ([`ReducedStatic::anchors`]).
    pub anchors: Vec<[f64; 3]>,
}

impl DenseState {
    /// Where the next point starts after `statics`.
    pub fn after(statics: &ReducedStatic) -> DenseState {
        DenseState {
            mu: statics.friction,
            q: statics.q.clone(),
            anchors: statics.anchors(),
        }
    }
}

impl Assembly<'_> {
    /// One increment as the full model takes it: Newton with the critical-point line
    /// search, then, if that fails, with backtracking ([`LineSearch`]); the steps by
    /// `solver`, which the point's increments share.
    fn increment(
        &self,
        start: &[f64],
        mu: f64,
        factor: f64,
        history: &[[f64; 3]],
        options: &StaticOptions,
        solver: &mut TangentSolver,
    ) -> Result<ReducedStatic, AssemblyError> {
        let first = StaticOptions {
            line_search: LineSearch::CriticalPoint,
            ..*options
        };
        self.newton(start, mu, factor, history, &first, solver)
            .or_else(|e| {
                tracing::debug!(
                    "reduced static at mu {mu}, load factor {factor}: {e}; retrying with \
                     backtracking"
                );
                let second = StaticOptions {
                    line_search: LineSearch::Backtracking,
                    ..*options
                };
                self.newton(start, mu, factor, history, &second, solver)
            })
    }

    /// The first point of a sweep at friction `mu`: the load ramped from `start` (rest, or
    /// the super-element's own equilibrium) with no slip yet, over `increments` equal load
    /// steps, each halved on failure at most `max_cutbacks` times in all.
    pub fn static_from_rest(
        &self,
        start: &[f64],
        mu: f64,
        increments: usize,
        max_cutbacks: usize,
        options: &StaticOptions,
    ) -> Result<ReducedStatic, AssemblyError> {
        let mut q = start.to_vec();
        let mut history = vec![[0.0; 3]; self.super_element().header.boundary.len()];
        let mut factor = 0.0;
        let mut step = 1.0 / increments.max(1) as f64;
        let (mut halvings, mut iterations) = (0, 0);
        let mut last = None;
        let mut solver = TangentSolver::new();
        while factor < 1.0 - 1e-12 {
            let target = (factor + step).min(1.0);
            match self.increment(&q, mu, target, &history, options, &mut solver) {
                Ok(solved) => {
                    iterations += solved.iterations;
                    factor = target;
                    q.clone_from(&solved.q);
                    // The last increment's history is the one its states came from: the
                    // one the CEA's tangent is formed after (`anchors`).
                    if factor < 1.0 - 1e-12 {
                        history = solved.anchors();
                    }
                    last = Some(solved);
                }
                Err(e) => {
                    halvings += 1;
                    if halvings > max_cutbacks {
                        return Err(e);
                    }
                    tracing::warn!(
                        "reduced static at mu {mu}: load factor {target:.3} failed ({e}); \
                         cutting back"
                    );
                    step *= 0.5;
                }
            }
        }
        let mut solved =
            last.ok_or_else(|| AssemblyError::Inconsistent("no load increment was taken".into()))?;
        solved.iterations = iterations;
        solved.factorizations = solver.factorizations;
        solved.cutbacks = halvings;
        Ok(solved)
    }

    /// A later point at friction `mu` from `previous` (its q and history): one friction step,
    /// or, when it fails, 2, 4, 8 and 16 equal ones in turn until a sequence gets through.
    /// Errors with the direct step's error when every sequence fails.
    pub fn static_from_previous(
        &self,
        previous: &DenseState,
        mu: f64,
        options: &StaticOptions,
    ) -> Result<ReducedStatic, AssemblyError> {
        let mut solver = TangentSolver::new();
        let first_error = match self.increment(
            &previous.q,
            mu,
            1.0,
            &previous.anchors,
            options,
            &mut solver,
        ) {
            Ok(mut solved) => {
                solved.factorizations = solver.factorizations;
                return Ok(solved);
            }
            Err(e) => e,
        };
        let from = previous.mu;
        let mut cutbacks = 1;
        for parts in SUBSTEPS {
            tracing::warn!(
                "reduced static: mu {from} -> {mu} in one step failed; trying {parts} \
                 friction steps"
            );
            let mut at_start = previous.clone();
            let mut iterations = 0;
            let mut reached = None;
            for k in 1..=parts {
                let at = from + (mu - from) * k as f64 / parts as f64;
                match self.increment(
                    &at_start.q,
                    at,
                    1.0,
                    &at_start.anchors,
                    options,
                    &mut solver,
                ) {
                    Ok(solved) => {
                        iterations += solved.iterations;
                        at_start = DenseState::after(&solved);
                        reached = Some(solved);
                    }
                    Err(_) => {
                        cutbacks += 1;
                        reached = None;
                        break;
                    }
                }
            }
            if let Some(mut solved) = reached {
                solved.iterations = iterations;
                solved.factorizations = solver.factorizations;
                solved.cutbacks = cutbacks;
                return Ok(solved);
            }
        }
        Err(first_error)
    }
}
