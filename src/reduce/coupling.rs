//! Distributing coupling (Abaqus `*COUPLING` + `*DISTRIBUTING`, forces only): a reference
//! point tied to the surface nodes within its radius of influence R (the paper's section 3.3,
//! eqs. 9-11; METHOD.md section 5).
//!
//! With `w_i = w(r_i / R)` the weight of coupling node i at distance `r_i` from the reference
//! point and `wbar_i = w_i / sum_j w_j`:
//! - the reference point moves as the weighted mean `u_ref = sum_i wbar_i u_i`;
//! - a force F at the reference point goes to the coupling nodes as `f_i = wbar_i F`, the
//!   transpose of the same relation, so the force resultant is transferred exactly.
//!
//! Forces only, as in the paper ("the contact forces (but not the moment)"): the moment of the
//! distributed forces about the reference point, `sum_i wbar_i (x_i - x_ref) x F`, is whatever
//! the layout of the coupling nodes makes it (zero when their weighted centroid is the
//! reference point, e.g. a symmetric layout) and is NOT made to vanish: Abaqus's distributing
//! coupling with rotations would add a moment-balancing correction; this one does not, and
//! the reference point has no rotational degrees of freedom.

use super::grid::ContactGrid;
use super::ReduceError;
use crate::mesh::{Mesh, Surface};
use crate::vector3::{add, cross, scale, sub};

pub use crate::fem::distributing::Weighting;

/// One surface node of a distributing coupling (the weights' own type, shared with a deck's
/// `*DISTRIBUTING`).
pub type CouplingNode = crate::fem::distributing::CloudNode;

/// A reference point tied to surface nodes by normalised weights.
#[derive(Clone, Debug, PartialEq)]
pub struct DistributingCoupling {
    /// Index of the reduced contact node this coupling belongs to (for messages).
    pub reduced_node: usize,
    pub reference: [f64; 3],
    /// Radius of influence R.
    pub radius: f64,
    pub weighting: Weighting,
    /// The surface nodes strictly within R (all with a positive weight), by node index.
    pub nodes: Vec<CouplingNode>,
}

impl DistributingCoupling {
    /// `u_ref = sum_i wbar_i u_i`, `displacement` indexed by mesh node.
    pub fn reference_displacement(&self, displacement: &[[f64; 3]]) -> [f64; 3] {
        self.nodes.iter().fold([0.0; 3], |acc, c| {
            add(acc, scale(c.weight, displacement[c.node]))
        })
    }

    /// The force at the reference point spread on the coupling nodes: `(node, wbar_i F)`.
    pub fn distribute(&self, force: [f64; 3]) -> Vec<(usize, [f64; 3])> {
        self.nodes
            .iter()
            .map(|c| (c.node, scale(c.weight, force)))
            .collect()
    }

    /// The same coupling with each node's weight times its tributary area `A_i` (from
    /// `areas`, by node), normalised again: `wbar_i = w_i A_i / sum_j w_j A_j`, the
    /// mesh-size weighting of Abaqus 6.10's distributing coupling, which the paper leaves out.
    /// A force then lands on the nodes in proportion to the surface each stands for, so a
    /// uniformly loaded grid loads a graded or quadratic mesh (whose corner and mid-side nodes
    /// stand for different areas) with a uniform pressure rather than with uniform nodal
    /// forces. Errors (naming the node) when a coupled node has no positive area in `areas`.
    pub fn area_weighted(
        mut self,
        areas: &std::collections::BTreeMap<usize, f64>,
    ) -> Result<Self, ReduceError> {
        for c in &mut self.nodes {
            match areas.get(&c.node) {
                Some(&a) if a > 0.0 && a.is_finite() => c.weight *= a,
                other => {
                    return Err(ReduceError::InvalidSurface {
                        surface: format!(
                            "(coupling of reduced contact node {})",
                            self.reduced_node
                        ),
                        why: format!(
                            "node {} has tributary area {other:?}, not a positive number",
                            c.node
                        ),
                    })
                }
            }
        }
        let total: f64 = self.nodes.iter().map(|c| c.weight).sum();
        for c in &mut self.nodes {
            c.weight /= total;
        }
        Ok(self)
    }

    /// The moment about the reference point of the forces [`Self::distribute`] gives for
    /// `force`: `sum_i wbar_i (x_i - x_ref) x F`. Not zero in general (forces only).
    pub fn moment_about_reference(&self, force: [f64; 3]) -> [f64; 3] {
        let arm = self.nodes.iter().fold([0.0; 3], |acc, c| {
            add(acc, scale(c.weight, sub(c.position, self.reference)))
        });
        cross(arm, force)
    }
}

/// The distributing coupling of reduced contact node `reduced_node`, whose reference point is
/// `reference`, to the nodes (corner and mid-side) of `surface` within the radius of
/// influence `radius`. Errors when fewer than 3 nodes not on one line are caught (the
/// reference point would not be held in every direction of the surface's plane).
pub fn distributing_coupling(
    mesh: &Mesh,
    surface: &Surface,
    reduced_node: usize,
    reference: [f64; 3],
    radius: f64,
    weighting: Weighting,
) -> Result<DistributingCoupling, ReduceError> {
    let candidates = surface_points(mesh, surface)?;
    couple(&candidates, reduced_node, reference, radius, weighting)
}

/// The distributing couplings of all the reduced contact nodes of `grid` to `surface`, each
/// with its reference point at the node's position on the surface, in the grid's order.
pub fn couple_grid(
    mesh: &Mesh,
    surface: &Surface,
    grid: &ContactGrid,
    radius: f64,
    weighting: Weighting,
) -> Result<Vec<DistributingCoupling>, ReduceError> {
    let references: Vec<[f64; 3]> = grid.nodes.iter().map(|n| n.position).collect();
    couple_points(mesh, surface, &references, radius, weighting)
}

/// The distributing couplings of reference points `references` (reduced contact node k at
/// `references[k]`) to the nodes of `surface` within `radius`: [`couple_grid`] for any
/// points, e.g. the disc-side points facing a pad's reduced contact nodes.
pub fn couple_points(
    mesh: &Mesh,
    surface: &Surface,
    references: &[[f64; 3]],
    radius: f64,
    weighting: Weighting,
) -> Result<Vec<DistributingCoupling>, ReduceError> {
    let candidates = surface_points(mesh, surface)?;
    references
        .iter()
        .enumerate()
        .map(|(k, &x)| couple(&candidates, k, x, radius, weighting))
        .collect()
}

/// The share couplings of a grid: each node of `surface` goes to the reduced contact node
/// whose share of the surface it lies in (the nearest grid point in the mean plane, the rule
/// that splits the surface's area among the nodes, [`super::grid`]), weighted by its
/// tributary area, the area the full pair's penalty gives it.
///
/// Why. The paper's couplings reach a radius of influence around each node with weights
/// that fall off with distance, so neighbouring couplings overlap and a share's force lands
/// on the pad as a bump centred on the node. Share couplings partition the surface: node k's
/// force lands on its own share as the uniform pressure the full model's springs would
/// carry there, and a patch law's slope is read over the nodes its share integrates. On
/// small-caliper (52 nodes per pad, no friction) the pad-rocking mode's error went from
/// -1.93 % to -0.48 % with them (issue 29).
///
/// In Abaqus's terms each is a distributing coupling with uniform weights and mesh-size
/// weighting, over the share's nodes instead of a radius. A share's translation is the
/// weighted mean of its nodes, which one node already gives: a share of one node, or of a
/// row of nodes on one line (an edge share of a grid about as fine as the mesh), couples
/// soundly, and its patch law reads its nearest neighbour's tilt nodes
/// ([`super::tilt::slope_owners`]). Errors (naming the node) when a share holds no
/// face node: the grid is then finer than the mesh.
pub fn couple_shares(
    mesh: &Mesh,
    surface: &Surface,
    grid: &ContactGrid,
) -> Result<Vec<DistributingCoupling>, ReduceError> {
    use crate::fem::distributing::normalise;
    // Checked as `couple_points` checks them, before any node is looked up.
    surface_points(mesh, surface)?;
    let mut couplings: Vec<DistributingCoupling> = grid
        .nodes
        .iter()
        .enumerate()
        .map(|(k, node)| DistributingCoupling {
            reduced_node: k,
            reference: node.position,
            radius: 0.0,
            weighting: Weighting::Uniform,
            nodes: Vec::new(),
        })
        .collect();
    if couplings.is_empty() {
        return Ok(couplings);
    }
    for (node, area) in crate::contact::tributary_areas(mesh, surface) {
        let x = mesh.nodes[node];
        let p = grid.plane.to_plane(x);
        let squared = |k: usize| {
            let q = grid.nodes[k].plane;
            (q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2)
        };
        // The first of equally near nodes: a node on the border of two shares goes to one.
        let k = (1..grid.nodes.len()).fold(
            0,
            |best, k| {
                if squared(k) < squared(best) {
                    k
                } else {
                    best
                }
            },
        );
        let c = &mut couplings[k];
        c.nodes.push(CouplingNode {
            node,
            position: x,
            distance: crate::vector3::norm(sub(x, c.reference)),
            weight: area,
        });
    }
    for c in &mut couplings {
        // The share's reach stands for a radius: the coupling's extent in messages and the
        // scale of the collinearity test.
        c.radius = c.nodes.iter().map(|n| n.distance).fold(0.0, f64::max);
        if c.nodes.is_empty() {
            return Err(ReduceError::ShareTooSmall {
                surface: surface.name.clone(),
                reduced_node: c.reduced_node,
                position: c.reference,
            });
        }
        normalise(&mut c.nodes);
    }
    Ok(couplings)
}

fn surface_points(mesh: &Mesh, surface: &Surface) -> Result<Vec<(usize, [f64; 3])>, ReduceError> {
    let nodes = mesh.surface_nodes(surface);
    if let Some(&bad) = nodes.iter().find(|&&n| n >= mesh.nodes.len()) {
        return Err(ReduceError::InvalidSurface {
            surface: surface.name.clone(),
            why: format!(
                "refers to node index {bad}, the mesh has {}",
                mesh.nodes.len()
            ),
        });
    }
    Ok(nodes.into_iter().map(|n| (n, mesh.nodes[n])).collect())
}

fn couple(
    candidates: &[(usize, [f64; 3])],
    reduced_node: usize,
    reference: [f64; 3],
    radius: f64,
    weighting: Weighting,
) -> Result<DistributingCoupling, ReduceError> {
    use crate::fem::distributing::{weigh, CloudError, Radius};
    let nodes =
        weigh(candidates, reference, Radius::Within(radius), weighting).map_err(|e| match e {
            CloudError::InvalidRadius { .. } => ReduceError::InvalidRadius {
                reduced_node,
                radius,
            },
            CloudError::TooFew { found, collinear } => ReduceError::TooFewCouplingNodes {
                reduced_node,
                position: reference,
                radius,
                found,
                collinear,
            },
        })?;
    Ok(DistributingCoupling {
        reduced_node,
        reference,
        radius,
        weighting,
        nodes,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::block::block;
    use crate::mesh::Material;
    use crate::vector3::norm;

    fn plate() -> Mesh {
        let material = Material {
            name: "m".into(),
            young: 1.0,
            poisson: 0.3,
            density: 1.0,
        };
        // Top surface z1: nodes every 0.05 (corners and mid-sides) over [0, 1] x [0, 1].
        block([0.0, 0.0, 0.0], [1.0, 1.0, 0.1], [10, 10, 1], material).unwrap()
    }

    const ALL: [Weighting; 4] = [
        Weighting::Uniform,
        Weighting::Linear,
        Weighting::Quadratic,
        Weighting::Cubic,
    ];

    #[test]
    fn weights_follow_eqs_9_to_11() {
        assert_eq!(Weighting::Linear.weight(0.25), 0.75);
        assert_eq!(Weighting::Quadratic.weight(0.5), 0.75);
        assert_eq!(Weighting::Cubic.weight(0.5), 0.5);
        for w in ALL {
            assert_eq!(w.weight(0.0), 1.0);
            assert_eq!(w.weight(1.0), 0.0);
            assert_eq!(w.weight(1.5), 0.0);
        }
        for w in [Weighting::Linear, Weighting::Quadratic, Weighting::Cubic] {
            assert_eq!(Weighting::from_degree(w.degree().unwrap()), Some(w));
        }
    }

    #[test]
    fn weightings_have_lowercase_serde_names() {
        let names: Vec<String> = ALL
            .iter()
            .map(|w| serde_json::to_string(w).unwrap())
            .collect();
        assert_eq!(
            names,
            ["\"uniform\"", "\"linear\"", "\"quadratic\"", "\"cubic\""]
        );
        let back: Weighting = serde_json::from_str("\"cubic\"").unwrap();
        assert_eq!(back, Weighting::Cubic);
    }

    #[test]
    fn coupling_is_normalised_and_transfers_the_force_and_a_rigid_translation() {
        let mesh = plate();
        let surface = &mesh.surfaces["z1"];
        // Off the node lattice, so that the layout is not symmetric about the reference.
        let reference = [0.431, 0.377, 0.1];
        for weighting in ALL {
            let c = distributing_coupling(&mesh, surface, 7, reference, 0.13, weighting).unwrap();
            assert!(c.nodes.len() > 10);
            assert!(c.nodes.iter().all(|n| n.weight > 0.0 && n.distance < 0.13));
            let sum: f64 = c.nodes.iter().map(|n| n.weight).sum();
            assert!((sum - 1.0).abs() < 1e-14, "{weighting:?}: {sum}");

            let force = [3.0, -2.0, 7.5];
            let resultant = c
                .distribute(force)
                .iter()
                .fold([0.0; 3], |acc, (_, f)| add(acc, *f));
            assert!(norm(sub(resultant, force)) < 1e-13 * norm(force));

            let t = [1e-3, -2e-3, 5e-4];
            let u = vec![t; mesh.nodes.len()];
            assert!(norm(sub(c.reference_displacement(&u), t)) < 1e-16);
        }
    }

    #[test]
    fn the_moment_about_the_reference_is_not_balanced_only_computed_consistently() {
        let mesh = plate();
        let surface = &mesh.surfaces["z1"];
        let force = [0.0, 0.0, -1.0];
        let moment_of = |c: &DistributingCoupling| {
            c.distribute(force).iter().fold([0.0; 3], |acc, (n, f)| {
                add(acc, cross(sub(mesh.nodes[*n], c.reference), *f))
            })
        };
        // Lopsided: near the plate's edge, more nodes on one side.
        let edge =
            distributing_coupling(&mesh, surface, 0, [0.02, 0.5, 0.1], 0.12, Weighting::Cubic)
                .unwrap();
        let direct = moment_of(&edge);
        assert!(norm(sub(edge.moment_about_reference(force), direct)) < 1e-15);
        assert!(
            norm(direct) > 1e-3,
            "a lopsided layout has a moment: {direct:?}"
        );
        // Symmetric: the reference on a node of the regular lattice, far from the edges.
        let centre =
            distributing_coupling(&mesh, surface, 1, [0.5, 0.5, 0.1], 0.12, Weighting::Cubic)
                .unwrap();
        assert!(norm(moment_of(&centre)) < 1e-15);
        assert!(norm(centre.moment_about_reference(force)) < 1e-15);
    }

    #[test]
    fn a_grid_couples_every_reduced_node_and_passes_the_whole_load() {
        use crate::reduce::grid::{isometric_grid, GridSize};
        use crate::reduce::radius::grid_optimal;
        let mesh = plate();
        let surface = &mesh.surfaces["z1"];
        let grid = isometric_grid(&mesh, surface, GridSize::Count(22)).unwrap();
        let (factor, _) = grid_optimal(Weighting::Cubic).unwrap();
        let couplings = couple_grid(
            &mesh,
            surface,
            &grid,
            factor * grid.spacing,
            Weighting::Cubic,
        )
        .unwrap();
        assert_eq!(couplings.len(), grid.count());
        // A pressure p carried by the reduced contact nodes (p times each node's tributary
        // area) reaches the surface nodes whole.
        let p = -2.5e5;
        let mut total = [0.0; 3];
        for (c, node) in couplings.iter().zip(&grid.nodes) {
            assert_eq!(c.reference, node.position);
            for (_, f) in c.distribute(scale(p * node.area, node.normal)) {
                total = add(total, f);
            }
        }
        let expect = p * grid.surface_area;
        assert!(
            (total[2] - expect).abs() < 1e-12 * expect.abs(),
            "{total:?}"
        );
        // Too small a radius names the first reduced contact node it fails for.
        let err = couple_grid(&mesh, surface, &grid, 1e-3, Weighting::Cubic).unwrap_err();
        assert!(
            matches!(
                err,
                ReduceError::TooFewCouplingNodes {
                    reduced_node: 0,
                    ..
                }
            ),
            "{err}"
        );
    }

    /// Share couplings partition the surface: every node in exactly one, in the share of
    /// the grid point nearest to it in the plane, weighted by its tributary area; so a
    /// pressure carried by the reduced nodes (p times the nodes' area in each share) reaches
    /// every surface node as the full pair's p a_i, and the weights add up to 1.
    #[test]
    fn share_couplings_partition_the_surface_and_carry_a_uniform_pressure_node_by_node() {
        use crate::reduce::grid::{isometric_grid, GridSize};
        let mesh = plate();
        let surface = &mesh.surfaces["z1"];
        let grid = isometric_grid(&mesh, surface, GridSize::Count(22)).unwrap();
        let couplings = couple_shares(&mesh, surface, &grid).unwrap();
        assert_eq!(couplings.len(), grid.count());
        let areas: std::collections::BTreeMap<usize, f64> =
            crate::contact::tributary_areas(&mesh, surface)
                .into_iter()
                .collect();
        let mut seen = std::collections::BTreeMap::new();
        let p = -2.5e5;
        for (k, c) in couplings.iter().enumerate() {
            assert_eq!(c.reference, grid.nodes[k].position);
            let sum: f64 = c.nodes.iter().map(|n| n.weight).sum();
            assert!((sum - 1.0).abs() < 1e-14, "{sum}");
            let share: f64 = c.nodes.iter().map(|n| areas[&n.node]).sum();
            for (node, f) in c.distribute([0.0, 0.0, p * share]) {
                let expect = p * areas[&node];
                assert!(
                    (f[2] - expect).abs() < 1e-12 * expect.abs(),
                    "{f:?} {expect}"
                );
                assert!(seen.insert(node, k).is_none(), "node {node} in two shares");
            }
            for n in &c.nodes {
                let q = grid.plane.to_plane(mesh.nodes[n.node]);
                let d = |j: usize| {
                    let g = grid.nodes[j].plane;
                    (g[0] - q[0]).powi(2) + (g[1] - q[1]).powi(2)
                };
                assert!((0..grid.count()).all(|j| d(k) <= d(j)), "node {}", n.node);
            }
        }
        assert_eq!(seen.len(), areas.len());
        let total: f64 = areas.values().sum();
        assert!((total - grid.surface_area).abs() < 1e-12 * total);
        // A grid finer than the mesh leaves a share without a node, named (nodes every
        // 0.05, shares of 0.03).
        let fine = isometric_grid(&mesh, surface, GridSize::Spacing(0.03)).unwrap();
        let err = couple_shares(&mesh, surface, &fine).unwrap_err();
        assert!(matches!(err, ReduceError::ShareTooSmall { .. }), "{err}");
        let text = err.to_string();
        assert!(
            text.contains("'z1'")
                && text.contains("holds no surface node")
                && text.contains("fewer reduced contact nodes"),
            "{text}"
        );
    }

    #[test]
    fn too_few_or_collinear_nodes_is_an_error_naming_the_reduced_node() {
        let mesh = plate();
        let surface = &mesh.surfaces["z1"];
        // R = 0.03 around a node catches only that node.
        let err =
            distributing_coupling(&mesh, surface, 4, [0.5, 0.5, 0.1], 0.03, Weighting::Linear)
                .unwrap_err();
        let text = err.to_string();
        assert!(
            text.contains("reduced contact node 4") && text.contains("3.000000e-2"),
            "{text}"
        );
        assert!(matches!(
            err,
            ReduceError::TooFewCouplingNodes {
                found: 1,
                collinear: false,
                ..
            }
        ));
        // Between two rows of nodes... on the x0 edge of the top, 3 nodes on one line.
        let err = distributing_coupling(
            &mesh,
            surface,
            9,
            [-0.03, 0.5, 0.1],
            0.07,
            Weighting::Uniform,
        )
        .unwrap_err();
        assert!(
            matches!(
                err,
                ReduceError::TooFewCouplingNodes {
                    collinear: true,
                    reduced_node: 9,
                    ..
                }
            ),
            "{err}"
        );
        assert!(matches!(
            distributing_coupling(&mesh, surface, 2, [0.5; 3], 0.0, Weighting::Linear),
            Err(ReduceError::InvalidRadius { .. })
        ));
    }
}
