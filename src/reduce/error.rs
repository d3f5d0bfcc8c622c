//! Errors of the reduction layer.

/// What can go wrong when laying reduced contact nodes on a surface or coupling them to it.
/// Every variant names the surface or the reduced contact node, and what was asked.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ReduceError {
    /// The grid size asked for cannot be used (a count of 0, a spacing that is not finite and
    /// positive).
    #[error("surface '{surface}': {requested}: {why}")]
    InvalidSize {
        surface: String,
        /// The request in words ("6 reduced contact nodes", "spacing h = 0.01").
        requested: String,
        why: String,
    },
    /// The surface has no faces, refers to nodes outside the mesh, or has a degenerate face.
    #[error("surface '{surface}': {why}")]
    InvalidSurface { surface: String, why: String },
    /// The surface is not close enough to a plane for an isometric grid in its mean plane to
    /// be laid on it.
    #[error(
        "surface '{surface}' is not planar enough for a grid of reduced contact nodes: its \
         nodes lie up to {deviation:.3e} from its mean plane, more than {limit:.3e} \
         ({fraction} of its in-plane size {size:.3e})"
    )]
    NotPlanar {
        surface: String,
        deviation: f64,
        limit: f64,
        fraction: f64,
        size: f64,
    },
    /// Patch laws on a pair they cannot carry: CalculiX's contact law (they integrate
    /// squeal's penalty), or a kept pair's face without share couplings.
    #[error("pair '{pair}': patch laws (reduction.tilt) integrate squeal's penalty over share couplings, and this pair has {law}")]
    PatchLaw { pair: String, law: String },
    /// A reduced contact node's tilt law cannot be made (its patch gives no slope).
    #[error("warping springs (reduction.warp_springs) stand on patch laws over share couplings: ask for those too (reduction.tilt = true, reduction.pad_coupling = \"share\"), or leave reduction.warp_springs out")]
    WarpSprings,

    #[error("pair '{pair}', reduced contact node {reduced_node}: no tilt law: {why}")]
    Tilt {
        pair: String,
        reduced_node: usize,
        why: String,
    },
    /// No grid point falls inside the surface.
    #[error("surface '{surface}': {requested} leaves no reduced contact node on the surface")]
    NoNode { surface: String, requested: String },
    /// A distributing coupling would not hold its reference point: fewer than 3 surface nodes
    /// within the radius of influence, or all of them on one line.
    #[error(
        "reduced contact node {reduced_node} at ({:.6e}, {:.6e}, {:.6e}): the radius of \
         influence R = {radius:.6e} catches {found} surface node(s){}; a distributing \
         coupling needs at least 3 not on one line",
        position[0], position[1], position[2],
        if *collinear { ", all on one line" } else { "" }
    )]
    TooFewCouplingNodes {
        reduced_node: usize,
        position: [f64; 3],
        radius: f64,
        found: usize,
        collinear: bool,
    },
    /// A share coupling ([`super::coupling::couple_shares`]) without a face node: the grid is
    /// finer than the mesh.
    #[error(
        "surface '{surface}': the share of reduced contact node {reduced_node} at ({:.6e}, \
         {:.6e}, {:.6e}) holds no surface node (the grid is finer than the mesh there): ask \
         for fewer reduced contact nodes, or pad_coupling = \"distributing\"",
        position[0], position[1], position[2]
    )]
    ShareTooSmall {
        surface: String,
        reduced_node: usize,
        position: [f64; 3],
    },
    /// A radius of influence that is not finite and positive.
    #[error("reduced contact node {reduced_node}: radius of influence R = {radius} must be finite and > 0")]
    InvalidRadius { reduced_node: usize, radius: f64 },
    /// A study or flag names a contact pair the model does not have.
    #[error("{key} names the pair '{name}', which the model does not have; its pairs are: {}", known.join(", "))]
    UnknownPair {
        key: String,
        name: String,
        known: Vec<String>,
    },
    /// `[reduction.pairs."NAME"]` gives a grid or `tilt` to a pair that is not reduced as
    /// a kept pair.
    #[error(
        "reduction.pairs.\"{pair}\": a grid or tilt for a pair that is not reduced as a kept pair: {why}"
    )]
    PairGridUnused { pair: String, why: &'static str },
    /// A kept pair's own grid that is no grid (both or neither of its keys, no node, a side
    /// that is not finite and positive).
    #[error("reduction.pairs.\"{pair}\": {why}")]
    PairGrid { pair: String, why: String },
    /// A reduction was asked for but no contact pair is swept.
    #[error(
        "a reduced interface replaces the swept (disc/pad) pairs, and no pair has sweep = true"
    )]
    NothingToReduce,
    /// A swept pair that is not node-to-surface has no surfaces to lay a grid on.
    #[error("pair '{pair}' is not a node-to-surface pair between two surfaces: nothing to reduce")]
    NotNodeToSurface { pair: String },
    /// A reduced contact node that faces no disc face.
    #[error(
        "pair '{pair}': reduced contact node {reduced_node} at ({:.6e}, {:.6e}, {:.6e}) does not project on the master surface '{surface}'",
        position[0], position[1], position[2]
    )]
    Unprojected {
        pair: String,
        reduced_node: usize,
        position: [f64; 3],
        surface: String,
    },
}
