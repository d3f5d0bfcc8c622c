//! Friction continuation: the sliding equilibrium at a new friction value, reached from the
//! last one. After the first point the brake is under its full load and the friction is
//! what changes, so each solve starts from the previous equilibrium (or a secant prediction
//! of this one), and when the direct step fails it is taken again from there in 2, 4, 8 and
//! 16 equal friction steps, each carrying the slip history to the next: the path a Coulomb
//! contact follows as the disc friction rises. Cutting the load back from a loaded state
//! would unload the brake and make the contacts slip back, so the load is never cut here.

use super::statics::StaticSolution;
use crate::contact::SlipHistory;

/// The friction steps a failed direct step is split into, in turn.
pub const SUBSTEPS: [usize; 4] = [2, 4, 8, 16];

/// An equilibrium a static solve starts from: its friction, displacements and the slip
/// history after it (where the Coulomb pairs start from).
#[derive(Clone, Debug, PartialEq)]
pub struct FrictionState {
    pub mu: f64,
    pub displacement: Vec<[f64; 3]>,
    pub slip: SlipHistory,
}

impl FrictionState {
    /// Where the next solve starts after `equilibrium`, reached at `mu`.
    pub fn after(mu: f64, equilibrium: &StaticSolution) -> FrictionState {
        FrictionState {
            mu,
            displacement: equilibrium.displacement.clone(),
            slip: equilibrium.slip_after.clone(),
        }
    }

    /// The secant prediction of the equilibrium at `mu` from `earlier` (an equilibrium at
    /// `earlier_mu`) and this one: u + ratio (u - u_earlier), ratio = (mu - this mu) / (this
    /// mu - earlier_mu). Only forward and at most two of the step that made it (0 < ratio
    /// <= 2): farther, the path may have turned. It keeps this state's friction and slip
    /// history (the solve starts there).
    ///
    /// Why: from the previous equilibrium alone, Newton spends its first iterations finding
    /// which Coulomb points stick, slip or open at the new friction (the residual rises and
    /// falls for 4-5 iterations before the quadratic tail). The secant puts most of them in
    /// their new state at once: tiny-caliper, mu 0.3 to 0.7 by 0.1, the warm points took
    /// 8, 5, 4, 4 Newton iterations (each a factorisation) where they took 8, 8, 8, 8.
    pub fn predicted(
        &self,
        earlier_mu: f64,
        earlier: &[[f64; 3]],
        mu: f64,
    ) -> Option<FrictionState> {
        let step = self.mu - earlier_mu;
        let ratio = (mu - self.mu) / step;
        if !(step.abs() > 1e-12 && ratio > 0.0 && ratio <= 2.0) {
            return None;
        }
        let displacement = self
            .displacement
            .iter()
            .zip(earlier)
            .map(|(a, b)| std::array::from_fn(|c| a[c] + ratio * (a[c] - b[c])))
            .collect();
        Some(FrictionState {
            mu: self.mu,
            displacement,
            slip: self.slip.clone(),
        })
    }
}

/// The equilibrium at `mu` from `previous`: one step from `start` (`previous` itself or a
/// prediction of this equilibrium), then, if it fails, for each of [`SUBSTEPS`] that many
/// equal friction steps from `previous`, each starting from the one before, until one
/// sequence gets through. `solve(at, from)` is one static solve at friction `at` from
/// `from`. The solution's increments are its sequence's, and its cut-backs every attempt
/// that failed on the way (the friction tried, why). Every rank must take the same path:
/// `solve` must fail on all ranks alike (the statics' errors are collective). Errors with
/// the direct step's error when every sequence fails.
pub fn reach<E: std::fmt::Display>(
    previous: &FrictionState,
    mu: f64,
    start: &FrictionState,
    mut solve: impl FnMut(f64, &FrictionState) -> Result<StaticSolution, E>,
) -> Result<StaticSolution, E> {
    let first_error = match solve(mu, start) {
        Ok(equilibrium) => return Ok(equilibrium),
        Err(e) => e,
    };
    let from = previous.mu;
    let mut cutbacks = vec![(mu, first_error.to_string())];
    for parts in SUBSTEPS {
        tracing::warn!("mu {from} -> {mu} in one step failed; trying {parts} friction steps");
        let mut at_start = previous.clone();
        let mut increments = Vec::new();
        let mut reached = None;
        for k in 1..=parts {
            let at = from + (mu - from) * k as f64 / parts as f64;
            match solve(at, &at_start) {
                Ok(e) => {
                    increments.extend(e.increments.iter().cloned());
                    at_start = FrictionState::after(at, &e);
                    reached = Some(e);
                }
                Err(e) => {
                    cutbacks.push((at, e.to_string()));
                    reached = None;
                    break;
                }
            }
        }
        if let Some(mut equilibrium) = reached {
            equilibrium.increments = increments;
            equilibrium.cutbacks = cutbacks;
            return Ok(equilibrium);
        }
    }
    Err(first_error)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::statics::IncrementReport;

    fn state(mu: f64, u: f64) -> FrictionState {
        FrictionState {
            mu,
            displacement: vec![[u, 0.0, -u]],
            slip: SlipHistory::default(),
        }
    }

    /// A "solve" whose answer is u = mu, and which fails when asked to go farther than
    /// `reach` in friction from where it starts.
    fn solver(
        reach: f64,
        calls: &mut Vec<(f64, f64)>,
    ) -> impl FnMut(f64, &FrictionState) -> Result<StaticSolution, String> + '_ {
        move |at, from| {
            calls.push((from.mu, at));
            if (at - from.mu).abs() > reach + 1e-12 {
                return Err(format!("too far: {} -> {at}", from.mu));
            }
            Ok(StaticSolution {
                displacement: vec![[at, 0.0, -at]],
                increments: vec![IncrementReport {
                    load_factor: 1.0,
                    iterations: 1,
                    factorizations: 1,
                    residual_history: vec![at],
                    reason: String::new(),
                }],
                cutbacks: Vec::new(),
                contact: Vec::new(),
                slip_before: SlipHistory::default(),
                slip_after: SlipHistory::default(),
            })
        }
    }

    /// A direct step that fails is taken in 2 steps, then 4: the 4 steps' increments come
    /// back, and every failed attempt is listed as a cut-back; each step starts where the
    /// one before ended.
    #[test]
    fn a_failed_step_is_split_until_the_steps_get_through() {
        let previous = state(0.1, 0.1);
        let mut calls = Vec::new();
        let e = reach(&previous, 0.5, &previous, solver(0.1, &mut calls)).unwrap();
        assert_eq!(e.displacement, vec![[0.5, 0.0, -0.5]]);
        let steps: Vec<f64> = e.increments.iter().map(|i| i.residual_history[0]).collect();
        let close = |a: &[f64], b: &[f64]| a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-12);
        assert!(close(&steps, &[0.2, 0.3, 0.4, 0.5]), "{steps:?}");
        let tried: Vec<f64> = e.cutbacks.iter().map(|c| c.0).collect();
        assert!(close(&tried, &[0.5, 0.3]), "{tried:?}");
        assert!(e.cutbacks[0].1.contains("too far"));
        // direct, 2 steps (the first fails), 4 steps each from the last.
        let froms: Vec<f64> = calls.iter().map(|c| c.0).collect();
        assert!(close(&froms, &[0.1, 0.1, 0.1, 0.2, 0.3, 0.4]), "{calls:?}");
    }

    /// A direct step that gets through is the answer, untouched; one that no split gets
    /// through gives the direct step's error.
    #[test]
    fn a_direct_step_is_kept_and_an_impossible_one_gives_its_own_error() {
        let previous = state(0.1, 0.1);
        let start = state(0.1, 0.3);
        let mut calls = Vec::new();
        let e = reach(&previous, 0.2, &start, solver(0.1, &mut calls)).unwrap();
        assert!(e.cutbacks.is_empty() && e.increments.len() == 1);
        assert_eq!(calls.len(), 1);
        let mut calls = Vec::new();
        let Err(err) = reach(&previous, 0.9, &previous, solver(0.01, &mut calls)) else {
            panic!("no split gets through a solver that reaches 0.01");
        };
        assert!(err.starts_with("too far: 0.1 -> 0.9"), "{err}");
        assert_eq!(calls.len(), 1 + 4, "each split stops at its first failure");
    }

    /// The secant predictor extrapolates linearly, forward and no more than twice the last
    /// step, and keeps the state's friction and history.
    #[test]
    fn the_prediction_is_the_secant_within_twice_the_last_step() {
        // Friction values exact in binary, so that twice the step is exactly 2.
        let now = state(0.5, 3.0);
        let earlier = [[2.0, 0.0, -2.0]];
        let p = now.predicted(0.25, &earlier, 1.0).unwrap();
        assert_eq!(p.displacement, vec![[5.0, 0.0, -5.0]]);
        assert_eq!(p.mu, 0.5);
        let half = now.predicted(0.25, &earlier, 0.625).unwrap();
        assert_eq!(half.displacement, vec![[3.5, 0.0, -3.5]]);
        assert!(now.predicted(0.25, &earlier, 1.125).is_none());
        assert!(now.predicted(0.25, &earlier, 0.375).is_none());
        assert!(now.predicted(0.5, &earlier, 1.0).is_none());
    }
}
