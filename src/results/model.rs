//! The model a sweep ran on, as sweep.json records it.

use super::SuperElementInfo;
use crate::analysis::cea::RayleighDamping;

/// The model a sweep ran on, as sweep.json records it.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct ModelInfo {
    pub source: String,
    /// Mesh and extra nodes (not written by the oldest versions: read as 0, unknown).
    #[serde(default)]
    pub nodes: usize,
    pub elements: usize,
    pub equations: usize,
    pub ranks: usize,
    pub pairs: Vec<String>,
    /// Contact points of all pairs.
    #[serde(skip)]
    pub contact_points: usize,
    /// The pressure resultant the contacts must carry.
    #[serde(skip)]
    pub applied_load: f64,
    pub max_frequency_hz: f64,
    pub damping: Option<RayleighDamping>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub superelements: Option<SuperElementInfo>,
}

impl ModelInfo {
    /// The opening log line of a sweep.
    pub fn describe(&self) -> String {
        format!(
            "{}: {} nodes, {} elements, {} equations on {} rank(s); {} contact pairs ({} points); applied load {:.4e} N",
            self.source,
            self.nodes,
            self.elements,
            self.equations,
            self.ranks,
            self.pairs.len(),
            self.contact_points,
            self.applied_load
        )
    }
}
