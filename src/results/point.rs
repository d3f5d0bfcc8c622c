//! One friction value's results as sweep.json holds them: the static solve, each contact
//! pair's state and closed zone, the CEA's eigenvalues, costs, and what a super-element did.

use crate::analysis::cea::ComplexMode;
use crate::contact::{PairSummary, ZoneStiffness};

/// One friction value's results, as written to sweep.json.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct SweepPointReport {
    pub friction: f64,
    pub static_iterations: usize,
    /// Tangents factorised by the static solve (other iterations kept one inside GMRES).
    pub static_factorizations: usize,
    pub static_residuals: Vec<f64>,
    pub cutbacks: usize,
    /// Per pair: name, closed points, total normal force, |friction force|, pressure range.
    pub contact: Vec<PairReport>,
    /// Sum of the swept (disc/pad) pairs' normal forces over the applied pressure resultant
    /// (1 when the pads carry the whole brake load to the disc).
    pub balance_ratio: f64,
    pub eigenvalues: Vec<ComplexMode>,
    pub static_seconds: f64,
    pub cea_seconds: f64,
    /// Shift-and-invert targets the CEA used.
    pub cea_shifts: usize,
    /// (Not written by the oldest versions: read as 0.)
    #[serde(default)]
    pub seconds: f64,
    /// Peak resident memory (VmHWM) up to this point: the largest rank's and the sum, MiB.
    pub peak_rss_mib_max_rank: f64,
    pub peak_rss_mib_all_ranks: f64,
    /// A super-element assembly's point: which super-element served it and what it cost.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub superelement: Option<SuperElementPoint>,
    /// The CEA again with the contact zone's edge moved, where asked
    /// (`analysis.contact_edge_points`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contact_edge: Option<EdgeCheck>,
    /// A friction value the sweep inserted between two others where tracking was unsure
    /// (`analysis.refine_points`), solved from the lower neighbour's equilibrium.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub inserted: bool,
    /// An inserted point's friction path: the values solved on the way to it (the asked
    /// ones up to its lower neighbour's path), then its own. A sweep of exactly these values
    /// gives its numbers. Empty for asked points, whose path is the asked list up to them.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub path: Vec<f64>,
    /// Whether some pair's counts of open, sticking and slipping points differ from the point
    /// before ([`Self::contact_state_differs`]): the links reaching this point cross a change
    /// of the contact state, which can move modes at once however fine the step.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub contact_changed: bool,
}

/// The point's modes with the edge of the swept pairs' contact zones moved
/// ([`crate::analysis::contact_edge`]): what a few points at the edge, with a newton of force
/// or nanometres of gap, decide of each mode.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct EdgeCheck {
    /// Points asked to open, and to close.
    pub points: usize,
    /// Closed points opened (those of least normal force), and open points closed (those of
    /// least gap): fewer than `points` where fewer were there.
    pub opened: usize,
    pub closed: usize,
    /// For each of the point's eigenvalues, in their order, its nearest with the points
    /// opened, and with the points closed.
    pub with_opened: Vec<ComplexMode>,
    pub with_closed: Vec<ComplexMode>,
    /// The two CEAs' time.
    pub seconds: f64,
}

impl EdgeCheck {
    /// The largest relative change of eigenvalue `i`'s frequency either way.
    pub fn frequency_change(&self, i: usize, base: &ComplexMode) -> f64 {
        [&self.with_opened, &self.with_closed]
            .iter()
            .filter_map(|list| list.get(i))
            .map(|m| (m.frequency_hz / base.frequency_hz - 1.0).abs())
            .fold(0.0, f64::max)
    }

    /// Whether eigenvalue `i` (unstable at the point) is stable with the edge moved either
    /// way.
    pub fn loses_instability(&self, i: usize) -> bool {
        [&self.with_opened, &self.with_closed]
            .iter()
            .any(|list| list.get(i).is_some_and(|m| !m.unstable))
    }
}

impl SweepPointReport {
    /// Whether some pair has another count of open, sticking or slipping points at `other`:
    /// the contact's state changed between the two friction values (a node changing state
    /// while another changes back is not seen; the counts are what every point keeps).
    pub fn contact_state_differs(&self, other: &SweepPointReport) -> bool {
        let state = |r: &SweepPointReport| -> Vec<(String, usize, usize, usize)> {
            r.contact
                .iter()
                .map(|c| (c.name.clone(), c.closed, c.stick, c.slip))
                .collect()
        };
        state(self) != state(other)
    }

    /// "; open/stick/slip points: name a/b/c, ..." for the pairs with sticking points (only
    /// Coulomb pairs stick); empty when none does.
    fn sticking_pairs(&self) -> String {
        let list: Vec<String> = self
            .contact
            .iter()
            .filter(|c| c.stick > 0)
            .map(|c| format!("{} {}/{}/{}", c.name, c.points - c.closed, c.stick, c.slip))
            .collect();
        if list.is_empty() {
            String::new()
        } else {
            format!("; open/stick/slip points: {}", list.join(", "))
        }
    }

    /// The per-point log line.
    pub fn log_line(&self) -> String {
        format!(
            "static {} Newton iterations, {} factorisations ({:.1} s), balance {:.6}; CEA {} modes, {} unstable, {} shifts ({:.1} s); {:.1} s, peak memory {:.0} MiB (all ranks)",
            self.static_iterations,
            self.static_factorizations,
            self.static_seconds,
            self.balance_ratio,
            self.eigenvalues.len(),
            self.eigenvalues.iter().filter(|m| m.unstable).count(),
            self.cea_shifts,
            self.cea_seconds,
            self.seconds,
            self.peak_rss_mib_all_ranks
        ) + &self.sticking_pairs()
            + &self
            .superelement
            .as_ref()
            .map(|se| {
                let worst = se
                    .frequency_error_estimates
                    .iter()
                    .fold(0.0, |a: f64, &b| a.max(b));
                format!(
                    "; super-element #{} of size {} ({}: {}), dense static {} iterations ({} LU) from {:.1e}, largest estimated frequency error {:.1e}",
                    se.index,
                    se.size,
                    if se.rebuilt { "built" } else { "reused" },
                    se.reason,
                    se.dense_static_iterations,
                    se.dense_static_factorizations,
                    se.start_residual,
                    worst
                )
            })
            .unwrap_or_default()
    }
}

#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct PairReport {
    pub name: String,
    pub points: usize,
    pub closed: usize,
    /// Closed points sticking (Coulomb pairs) and slipping (every closed point of a
    /// steady-sliding pair); open = points - closed.
    pub stick: usize,
    pub slip: usize,
    pub normal_force: f64,
    /// Magnitude of the resultant friction force on the slave.
    pub friction_force: f64,
    /// Friction moment about the disc axis: the braking torque.
    pub braking_torque: f64,
    /// braking_torque / (mu N): where the friction acts on average.
    pub effective_radius: f64,
    pub pressure_min: f64,
    pub pressure_max: f64,
    pub pressure_mean: f64,
    /// The closed zone's normal stiffness and its moments ([`crate::contact::zone`]), by the
    /// pair's own law; absent where another law decided the states (a super-element's dense
    /// contacts) and in folders written before it existed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub zone: Option<ZoneStiffness>,
}

impl PairReport {
    pub fn new(name: &str, s: &PairSummary) -> PairReport {
        let (pressure_min, pressure_max, pressure_mean) = s
            .pressure
            .map_or((0.0, 0.0, 0.0), |p| (p.min, p.max, p.mean));
        PairReport {
            name: name.to_string(),
            points: s.points,
            closed: s.closed,
            stick: s.stick,
            slip: s.slip,
            normal_force: s.normal_force,
            friction_force: s.friction_force.iter().map(|c| c * c).sum::<f64>().sqrt(),
            braking_torque: s.braking_torque,
            effective_radius: s.effective_radius,
            pressure_min,
            pressure_max,
            pressure_mean,
            zone: Some(s.zone),
        }
    }
}

/// What the super-element assembly did at one friction value (sweep.json).
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct SuperElementPoint {
    pub strategy: String,
    /// Which super-element (1 = the first built in this sweep) served this point.
    pub index: usize,
    /// The friction value it was made at.
    pub made_at_friction: f64,
    /// Whether it was built at this point, and why; or why it was reused.
    pub rebuilt: bool,
    pub reason: String,
    /// Reduced unknowns: 6 per boundary pair, the fixed-interface modes, the static
    /// correction and the residual vectors.
    pub size: usize,
    pub boundary: usize,
    pub modes: usize,
    /// Residual vectors of the band's modes in the basis (`--residual-vectors`).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub residual_vectors: usize,
    /// The reduced-interface static at this point (0 when none was needed), s.
    pub reduced_interface_static_seconds: f64,
    /// Building the super-element at this point (0 when reused), s.
    pub build_seconds: f64,
    /// |R| / |load| of the dense static at its start: eq. 5's residual where the
    /// super-element was made or moved to this point's equilibrium.
    pub start_residual: f64,
    pub dense_static_iterations: usize,
    /// Dense LU factorisations those iterations made (the others were solved on an earlier
    /// one: `reduce::tangent_solver`); absent from files written before it was counted.
    #[serde(default)]
    pub dense_static_factorizations: usize,
    pub dense_static_seconds: f64,
    pub dense_cea_seconds: f64,
    /// Expanding the modes (u = T q) and their residuals in the reduced-interface model, s.
    pub expansion_seconds: f64,
    /// Per mode (the order of `eigenvalues`): |K_t u + lambda^2 M u| / (|K_t u| +
    /// |lambda|^2 |M u|) of its expansion in the reduced-interface model, with K_t that
    /// model's tangent at the expanded equilibrium: how far the reduced mode is from being
    /// one of the model it stands for.
    pub expansion_residuals: Vec<f64>,
    /// Per mode: the relative frequency error this residual implies, an upper estimate
    /// (see `frequency_error_estimate`): whether the reduced answer can be trusted at this
    /// mu without the reduced-interface CEA.
    pub frequency_error_estimates: Vec<f64>,
}

/// The super-element settings of a sweep (sweep.json's model).
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct SuperElementInfo {
    pub strategy: String,
    /// mu_SE of the single strategy.
    pub friction: f64,
    pub cutoff_hz: f64,
    /// k_l; `None`: each pair's penalty times its area.
    pub k_linear: Option<f64>,
    pub k_cubic: f64,
}

fn is_zero(n: &usize) -> bool {
    *n == 0
}
