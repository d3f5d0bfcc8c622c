//! What a friction sweep carries from one point to the next, saved with every finished point
//! ([`super::point_cache`]) so that an interrupted sweep resumes after its last finished
//! point and computes the rest with the same numbers as a run that was never stopped.
//!
//! A point's equilibrium is warm-started from the previous one and, for Coulomb pairs,
//! reached from the previous slip history (stick anchors): the path matters, so a resumed
//! model must stand exactly where the uninterrupted one stood. Floats are kept to the bit
//! (serde_json's `float_roundtrip`).

use crate::contact::SlipHistory;

/// An equilibrium as the next solve needs it: the friction value, every node's
/// displacement and the slip history (each Coulomb point's anchor, per pair and point).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct EquilibriumState {
    pub mu: f64,
    pub displacement: Vec<[f64; 3]>,
    pub slip: Vec<Vec<[f64; 3]>>,
}

impl EquilibriumState {
    pub fn new(mu: f64, displacement: &[[f64; 3]], slip: &SlipHistory) -> Self {
        EquilibriumState {
            mu,
            displacement: displacement.to_vec(),
            slip: slip.anchors().to_vec(),
        }
    }

    pub fn slip_history(&self) -> SlipHistory {
        SlipHistory::from_anchors(self.slip.clone())
    }
}

/// A super-element sweep's own state between points.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct SuperElementState {
    /// Super-elements built so far in the sweep.
    pub built: usize,
    /// The current super-element: its number in the sweep and the equilibrium it was made
    /// at, with the slip history that equilibrium was reached from (its kept Coulomb pairs'
    /// states and tangent follow from the two). A resumed sweep rebuilds it from there,
    /// which gives the same basis; a point that reuses it then projects its own tangent on
    /// it, as the uninterrupted sweep did.
    pub current: Option<(usize, EquilibriumState)>,
    /// The fixed-interface mode count of the last build (the next build's starting guess).
    pub interior_modes: Option<usize>,
    /// The previous point's dense static (the single strategy's warm start).
    pub previous_q: Option<Vec<f64>>,
    /// The previous point's dense static with its slip history, where a super-element with
    /// kept pairs on its boundary steps on from (issue 32); none in older checkpoints.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dense_previous: Option<crate::reduce::dense_path::DenseState>,
}

/// An equilibrium on the friction path, as far as predicting the next one needs it.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PathPoint {
    pub mu: f64,
    pub displacement: Vec<[f64; 3]>,
}

/// Everything a model carries to its next point.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct ModelCheckpoint {
    /// The last equilibrium the (full or reduced-interface) model solved.
    pub previous: Option<EquilibriumState>,
    /// The one before it: the next point's warm start is predicted along the two (a
    /// resumed sweep must predict as the uninterrupted one did to give its numbers).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub earlier: Option<PathPoint>,
    pub superelement: Option<SuperElementState>,
}
