//! What the reference's own contact edge decides (`--contact-edge-points`,
//! [`crate::analysis::contact_edge`]): its instabilities that are stable with a few points of
//! the disc/pad zones' edge moved, and its modes that move by 1 % or more. A reduced model that
//! misses such an instability, or is off by that much on such a mode, differs from the full
//! model by less than the full mesh resolves its own contact edge (issue 29).

use super::matching::pair_indices;
use super::Sweep;
use crate::analysis::tracking::Instability;

/// A mode moving by at least this fraction with the edge moved is listed: the paper's
/// tolerance for a reduced model's frequency error.
pub const EDGE_NOTED: f64 = 0.01;

/// A reference mode the contact edge moves by [`EDGE_NOTED`] or more.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct EdgeSensitiveMode {
    pub friction: f64,
    pub frequency_hz: f64,
    /// Its nearest frequency with the edge's points opened, and closed.
    pub opened_hz: f64,
    pub closed_hz: f64,
    /// The points moved each way.
    pub points: usize,
}

impl EdgeSensitiveMode {
    /// "+0.71 % / -2.55 %" (closed, opened).
    pub fn shift_text(&self) -> String {
        let rel = |f: f64| 100.0 * (f / self.frequency_hz - 1.0);
        format!(
            "{:+.2} % closed / {:+.2} % opened",
            rel(self.closed_hz),
            rel(self.opened_hz)
        )
    }
}

/// Whether the reference checked its edge at any point.
pub fn checked(r: &Sweep) -> bool {
    r.points.iter().any(|p| p.contact_edge.is_some())
}

/// The friction values at which instability `i` of the reference is stable with the edge moved
/// either way (its unstable mode's nearest with the points moved is stable); `None` when the
/// reference has no edge check.
pub fn instability_on_edge(r: &Sweep, i: &Instability) -> Option<Vec<f64>> {
    if !checked(r) {
        return None;
    }
    let mut at = Vec::new();
    for (k, point) in r.points.iter().enumerate() {
        let (Some(edge), Some(indices)) = (&point.contact_edge, pair_indices(r, i, k)) else {
            continue;
        };
        let lost = indices
            .iter()
            .any(|&n| point.eigenvalues[n].unstable && edge.loses_instability(n));
        if lost {
            at.push(point.friction);
        }
    }
    Some(at)
}

/// The reference's modes that the edge moves by [`EDGE_NOTED`] or more, at every point.
pub fn sensitive_modes(r: &Sweep) -> Vec<EdgeSensitiveMode> {
    let mut modes = Vec::new();
    for point in &r.points {
        let Some(edge) = &point.contact_edge else {
            continue;
        };
        for (n, m) in point.eigenvalues.iter().enumerate() {
            if edge.frequency_change(n, m) < EDGE_NOTED {
                continue;
            }
            let (Some(o), Some(c)) = (edge.with_opened.get(n), edge.with_closed.get(n)) else {
                continue;
            };
            modes.push(EdgeSensitiveMode {
                friction: point.friction,
                frequency_hz: m.frequency_hz,
                opened_hz: o.frequency_hz,
                closed_hz: c.frequency_hz,
                points: edge.points,
            });
        }
    }
    modes
}
