//! Where a swept pair's contact forces land on its pad surface: the pressure drawn on the pad
//! faces, and any other per-point quantity spread the same way (where a mode is fed).

use crate::contact;
use crate::model::Model;
use crate::reduce;

/// A swept pair's pad surface: per contact point, the surface nodes it stands for with their
/// weights c_ik and its own tributary area A_k, and every surface node's tributary area.
///
/// The pressure written at surface node i is the contact points' pressures F_k / A_k
/// interpolated with the weights: `p_i = sum_k c_ik F_k / sum_k c_ik A_k`. A node-to-surface
/// point stands for its own node alone (c = 1, A_k the node's area): `p_i = F_i / A_i`, the
/// full model's nodal penalty pressure. A reduced contact node stands for its distributing
/// coupling's nodes (c_ik = wbar_ik): a partition of unity, so that reduced contact nodes all
/// at one pressure give exactly that pressure at every node they reach. (Dividing the
/// spread force `sum_k wbar_ik F_k` by the node's own area instead, as before, gives a
/// uniform pressure back with an 18 % L2 scatter on the small brake at 106 nodes per pad,
/// because the weights ignore how much surface each node stands for.)
pub(super) struct SweptSurface {
    pub(super) pair: usize,
    pub(super) per_point: Vec<Vec<(usize, f64)>>,
    pub(super) point_area: Vec<f64>,
    pub(super) areas: std::collections::BTreeMap<usize, f64>,
}

impl SweptSurface {
    /// The pressure at every surface node for the contact points' normal forces (see the
    /// type's documentation); 0 where no point reaches.
    pub(super) fn pressure(&self, forces: &[f64]) -> std::collections::BTreeMap<usize, f64> {
        let mut sums: std::collections::BTreeMap<usize, (f64, f64)> =
            self.areas.keys().map(|&n| (n, (0.0, 0.0))).collect();
        for ((nodes, &area), &force) in self.per_point.iter().zip(&self.point_area).zip(forces) {
            for &(node, c) in nodes {
                let s = sums.entry(node).or_default();
                s.0 += c * force;
                s.1 += c * area;
            }
        }
        sums.into_iter()
            .map(|(n, (f, a))| (n, if a > 0.0 { f / a } else { 0.0 }))
            .collect()
    }
}

/// Where a node-to-surface model's contact forces go: each swept pair's points to their
/// slave node.
pub(super) fn node_to_surface_spread(model: &Model) -> Vec<SweptSurface> {
    spread_of(model, |i| model.swept[i])
}

/// [`node_to_surface_spread`] of the pairs `which` picks.
pub(super) fn spread_of(model: &Model, which: impl Fn(usize) -> bool) -> Vec<SweptSurface> {
    let mut spread = Vec::new();
    for (i, pair) in model.pairs.iter().enumerate() {
        let Some(Some((slave, _))) = model.pair_surfaces.get(i) else {
            continue;
        };
        let Some(surface) = model.mesh.surfaces.get(slave) else {
            continue;
        };
        if which(i) {
            spread.push(SweptSurface {
                pair: i,
                per_point: pair.points.iter().map(|p| p.slave.clone()).collect(),
                point_area: pair.points.iter().map(|p| p.area).collect(),
                areas: contact::tributary_areas(&model.mesh, surface)
                    .into_iter()
                    .collect(),
            });
        }
    }
    spread
}

/// A reduced interface's contact points stand for their distributing couplings' pad nodes.
pub(super) fn reduced_spread(reduced: &reduce::ReducedInterface) -> Vec<SweptSurface> {
    let model = &reduced.model;
    let mut spread = Vec::new();
    for pad in reduced.pads.iter().filter(|p| p.swept) {
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
            point_area: pad.grid.nodes.iter().map(|n| n.area).collect(),
            areas: contact::tributary_areas(&model.mesh, surface)
                .into_iter()
                .collect(),
        });
    }
    spread
}
