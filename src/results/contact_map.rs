//! contact.json: a point's static contact state on the swept pairs (every contact point,
//! the pad surface pressure) and the unstable modes' shapes on the pad surface, what `squeal
//! compare` pairs two models' instabilities and pressures by.

/// One contact point's state at the equilibrium (contact.json).
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct ContactMapPoint {
    pub pair: String,
    pub position: [f64; 3],
    pub closed: bool,
    /// N (the penalty force p of the point).
    pub normal_force: f64,
}

/// The contact pressure on one node of a swept pair's slave (pad) surface: a
/// node-to-surface point's force over its node's tributary area; for a reduced interface,
/// the reduced contact nodes' pressures (force over tributary area) interpolated to the pad
/// nodes with the coupling weights, so that a uniform pressure comes back uniform. `squeal
/// compare` compares two models of the same mesh patch by patch (see its `pressure_l2`).
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct SurfacePressure {
    pub pair: String,
    pub node: usize,
    pub position: [f64; 3],
    pub area: f64,
    pub pressure: f64,
}

/// An unstable mode's shape on the swept pairs' pad surface nodes: what two models of the
/// same mesh share, so `squeal compare` can pair their instabilities by the complex MAC.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct SurfaceShape {
    pub frequency_hz: f64,
    pub real_part: f64,
    /// Real and imaginary parts, (x, y, z) per node of [`ContactMap::shape_nodes`].
    pub re: Vec<[f64; 3]>,
    pub im: Vec<[f64; 3]>,
}

/// The static contact state of a point (contact.json): every swept pair's contact points,
/// the pressure on their pad surfaces, and the unstable modes' shapes there.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct ContactMap {
    pub points: Vec<ContactMapPoint>,
    pub surface: Vec<SurfacePressure>,
    /// The pad surface nodes (sorted) the shapes are given on.
    #[serde(default)]
    pub shape_nodes: Vec<usize>,
    #[serde(default)]
    pub unstable_shapes: Vec<SurfaceShape>,
}
