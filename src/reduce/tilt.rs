//! The patch law of a reduced contact node ([`crate::contact::Tilt`]): squeal's addition to
//! the paper's reduced interface (METHOD.md section 5 has none).
//!
//! Why. A distributing coupling holds its patch's weighted mean translation and nothing
//! else, so a point contact between two reduced nodes lets the pad patch tilt freely against
//! the disc patch under it. The full model's penalty springs over the closed part of the
//! patch resist that tilt with k_n I (I the closed part's second moment of area). On the
//! floating-caliper brake the modes whose pads rock on half their face lose that stiffness:
//! `tiny-caliper`'s 620.5 Hz mode at mu = 0 comes out at 566 Hz with 22 nodes per pad, and
//! neither the penalty, the tie springs nor the couplings' radius bring it back (issue 29).
//!
//! How, keeping the paper's reduced contact nodes. Each reduced contact node gains two tilt
//! nodes (extra nodes at its position and its disc node's: the rotations an Abaqus reference
//! node of a distributing coupling has), r_p on the pad side and r_d on the disc side, each
//! tied by stiff [`ScalarSpring`]s to its own patch only (as c and d are):
//! - along each in-plane axis e_a: `arm` times the slope of its patch's normal displacement,
//!   the weighted least-squares fit of a plane to the patch's normal displacements with the
//!   distributing coupling's weights (exact for a linear field, blind to the mean, which the
//!   translation tie holds);
//! - along the normal: `arm` times its patch's in-plane twist, the weighted least-squares
//!   rotation about the normal (the third rotation of an Abaqus coupling's reference node).
//!   The law does not use it. It is tied to the patch rather than to the ground so that it
//!   has a mass in a super-element, where the tilt nodes are boundary coordinates: tied to
//!   the ground, its constraint mode is zero, M_r is singular and the dense CEA's Cholesky
//!   fails. In the full-size model the component is massless and tied by one spring, so it
//!   carries no force either way.
//!
//! One node tied to both slopes would couple the pad patch's nodes to the disc patch's in
//! every tie: the two meshes would then meet over whole patches, a dense block per reduced
//! contact node in every factorisation, where the translation ties keep them apart.
//!
//! The contact point's normal law then integrates the full model's penalty over the node's
//! share of the pad face at the gap g + theta . xi (theta = e . (u_rp - u_rd) / arm): closed, partly
//! closed or open, the share carries what the full model's springs over it would. A rigid
//! motion of the whole model tilts both patches alike: u_rp = u_rd. Where the couplings
//! are shares the law integrates at the share's face nodes with their tributary areas
//! ([`nodal_share`], [`super::PatchQuadrature::Nodes`]), as the full pair does: the full
//! pair closes a node's whole area once its gap is negative, and a continuous rule closed
//! a strip of the pad mesh's width less along the contact zone's edge.
//!
//! `arm` = sqrt(tr I / (2 A)), the share's radius of gyration, so that r_p, r_d are displacements
//! of the patch's size and the tilt's stiffness is of the point's normal stiffness k_n A:
//! the ties, k_s = 1e3 k_n A like the translation ties, are equally stiff relative to what
//! they hold.

use super::coupling::DistributingCoupling;
use super::grid::{ContactGrid, ReducedNode};
use super::ReduceError;
use crate::contact::Tilt;
use crate::fem::springs::ScalarSpring;
use crate::vector3::{cross, dot, normalize, scale, sub};

/// A patch whose in-plane spread has a condition number beyond this (its nodes about on a
/// line) cannot give a slope across that line.
const COLLINEAR: f64 = 1e8;

/// A share reads its own slope only where its face nodes spread across every in-plane
/// direction by at least 1/5 of its arm: arm^2 over the smallest eigenvalue of their
/// weighted in-plane covariance ([`thinness`]) at most this.
///
/// Why. A slope tie holds arm times the fitted slope, so a face node's normal stiffness
/// from it is k_s (arm g_j)^2, and across a direction in which the nodes spread by s the
/// coefficients g_j grow as 1/s: a thin share's ties put stiffness far above any other on
/// its nodes. Measured on `tiny` at 22 nodes per pad: four edge shares of three nodes
/// nearly on a line (below [`COLLINEAR`]) had a thinness of 595-693 and put 1.4e14 N/m on a
/// face node (80 times k_s), so max K_ii / M_ii grew from 2.1e15 (the paper's interface) to
/// 1.2e18, and the rigid-body level (1e-9 of it, `analysis::rigid`) rose to 5.5 kHz: an
/// unstable mode at 3106.9 Hz, real part +103 1/s, was called rigid. Over the presets'
/// grids (tiny, tiny-caliper, small, small-caliper; 22 to 106 nodes per pad) a share
/// whose nodes spread in both directions has 0.93-6.5 and a thin one 6e2-7e4: 25 lies
/// between them with a factor of 4 and 24 on either side.
const THIN: f64 = 25.0;

/// A reduced node's tilt: the law its contact point carries, and the ties of its tilt node.
#[derive(Clone, Debug, PartialEq)]
pub struct NodeTilt {
    pub law: Tilt,
    pub ties: Vec<ScalarSpring>,
    pub arm: f64,
}

/// In-plane axes at a point of normal `n`: the grid plane's axes made orthogonal to `n` (so
/// that the second moment, taken in the plane's axes, applies along them).
pub fn axes(plane_axes: [[f64; 3]; 2], n: [f64; 3]) -> Option<[[f64; 3]; 2]> {
    let along = |a: [f64; 3], b: [f64; 3]| sub(a, scale(dot(a, b), b));
    let e1 = normalize(along(plane_axes[0], n))?;
    let e2 = normalize(cross(n, e1))?;
    // Keep e2 on the side of the plane's second axis (the moment's off-diagonal sign).
    let e2 = if dot(e2, plane_axes[1]) < 0.0 {
        scale(-1.0, e2)
    } else {
        e2
    };
    Some([e1, e2])
}

/// The weighted centre of a patch of `(position, node, weight)`; `None` when the weights do
/// not add up to a positive total.
fn weighted_centre(patch: &[([f64; 3], usize, f64)]) -> Option<[f64; 3]> {
    let total: f64 = patch.iter().map(|p| p.2).sum();
    if total.is_nan() || total <= 0.0 {
        return None;
    }
    Some(patch.iter().fold([0.0; 3], |c, &(x, _, w)| {
        crate::vector3::add(c, scale(w / total, x))
    }))
}

/// One slope as a sum over a patch's nodes: (node, g) with slope = sum g . u_node.
pub type SlopeTerms = Vec<(usize, [f64; 3])>;

/// A 2x2 in-plane covariance and the offsets it was made of.
type Covariance = ([[f64; 2]; 2], Vec<[f64; 2]>);

/// The weighted covariance of a patch's in-plane offsets from its weighted centre,
/// sum_j w_j xi_j xi_j^T / sum_j w_j (xi_j along `axes`), and those offsets; `None` when
/// the weights do not add up to a positive total.
fn covariance(patch: &[([f64; 3], usize, f64)], axes: [[f64; 3]; 2]) -> Option<Covariance> {
    let centre = weighted_centre(patch)?;
    let total: f64 = patch.iter().map(|p| p.2).sum();
    let offsets: Vec<[f64; 2]> = patch
        .iter()
        .map(|&(x, _, _)| {
            let d = sub(x, centre);
            [dot(d, axes[0]), dot(d, axes[1])]
        })
        .collect();
    let mut g = [[0.0; 2]; 2];
    for (xi, p) in offsets.iter().zip(patch) {
        for a in 0..2 {
            for b in 0..2 {
                g[a][b] += p.2 / total * xi[a] * xi[b];
            }
        }
    }
    Some((g, offsets))
}

/// arm^2 over the smallest eigenvalue of a patch's in-plane covariance: how much thinner
/// than its arm the patch's nodes spread across their thinnest direction, squared (see
/// [`THIN`]). Infinite for nodes on one line.
pub fn thinness(patch: &[([f64; 3], usize, f64)], axes: [[f64; 3]; 2], arm: f64) -> f64 {
    let Some((g, _)) = covariance(patch, axes) else {
        return f64::INFINITY;
    };
    let half = 0.5 * (g[0][0] + g[1][1]);
    let det = g[0][0] * g[1][1] - g[0][1] * g[1][0];
    // det / largest: the difference half - sqrt(...) would lose the small one to cancellation.
    let largest = half + (half * half - det).max(0.0).sqrt();
    let smallest = if largest > 0.0 { det / largest } else { 0.0 };
    if smallest > 0.0 {
        arm * arm / smallest
    } else {
        f64::INFINITY
    }
}

/// The arm of a share of area `area` and second moment `second_moment`: its radius of
/// gyration, sqrt(tr I / (2 A)); `None` for a share with no area or no second moment.
pub fn arm(area: f64, second_moment: [[f64; 2]; 2]) -> Option<f64> {
    let trace = second_moment[0][0] + second_moment[1][1];
    (area > 0.0 && trace > 0.0).then(|| (trace / (2.0 * area)).sqrt())
}

/// The coefficients of the least-squares slope of the normal displacement of a patch of
/// nodes (`(position, node, weight)`): slope_a = sum_j g_ja . u_j, g_ja = (G^-1 w_j xi_j)_a n,
/// xi_j the in-plane offsets from the weighted centre, G = sum_j w_j xi_j xi_j^T. `None`
/// when the nodes are about on a line.
pub fn slope_terms(
    patch: &[([f64; 3], usize, f64)],
    axes: [[f64; 3]; 2],
    n: [f64; 3],
) -> Option<[SlopeTerms; 2]> {
    let (g, offsets) = covariance(patch, axes)?;
    let total: f64 = patch.iter().map(|p| p.2).sum();
    let trace = g[0][0] + g[1][1];
    let det = g[0][0] * g[1][1] - g[0][1] * g[1][0];
    // Condition number of the symmetric 2x2 G: (l1 / l2) ~ trace^2 / det for l1 >> l2.
    if det.is_nan() || det <= 0.0 || trace * trace / det > COLLINEAR {
        return None;
    }
    let inverse = [
        [g[1][1] / det, -g[0][1] / det],
        [-g[1][0] / det, g[0][0] / det],
    ];
    let terms = |a: usize| {
        offsets
            .iter()
            .zip(patch)
            .map(|(xi, &(_, node, w))| {
                let c = w / total * (inverse[a][0] * xi[0] + inverse[a][1] * xi[1]);
                (node, scale(c, n))
            })
            .collect::<Vec<_>>()
    };
    Some([terms(0), terms(1)])
}

/// The coefficients of the weighted least-squares twist of a patch about its normal `n`
/// (`(position, node, weight)`): twist = sum g_j . u_j with g_j = w_j (n x xi_j) / S,
/// xi_j the in-plane offsets from the weighted centre and S = sum w_j |xi_j|^2. Exact for a
/// rigid rotation about n (the weighted centre cancels any translation); `None` when S = 0.
pub fn twist_terms(patch: &[([f64; 3], usize, f64)], n: [f64; 3]) -> Option<SlopeTerms> {
    let centre = weighted_centre(patch)?;
    let offsets: Vec<[f64; 3]> = patch
        .iter()
        .map(|&(x, _, _)| {
            let d = sub(x, centre);
            sub(d, scale(dot(d, n), n))
        })
        .collect();
    let spread: f64 = offsets
        .iter()
        .zip(patch)
        .map(|(xi, p)| p.2 * dot(*xi, *xi))
        .sum();
    if spread.is_nan() || spread <= 0.0 {
        return None;
    }
    Some(
        offsets
            .iter()
            .zip(patch)
            .map(|(xi, &(_, node, w))| (node, scale(w / spread, cross(n, *xi))))
            .collect(),
    )
}

/// The tilt of reduced node `reduced_node` of pair `pair`: tilt nodes `nodes` (pad side,
/// disc side; each tied to its own patch only, as the translation's c and d are, so that
/// the pad and disc meshes meet only at the contact point: one spring over both patches
/// made their factorisation ~10 times slower on `small-caliper`), contact normal
/// `n`, the pad and disc patches, the share's area and second moment (in the grid plane's
/// axes `plane_axes`), the pair's penalty per unit area and the ties' stiffness. `None` when
/// the share has no second moment to give (a sliver at the border).
#[allow(clippy::too_many_arguments)]
pub fn node_tilt(
    pair: &str,
    reduced_node: usize,
    nodes: [usize; 2],
    n: [f64; 3],
    plane_axes: [[f64; 3]; 2],
    pad: &[([f64; 3], usize, f64)],
    disc: &[([f64; 3], usize, f64)],
    area: f64,
    second_moment: [[f64; 2]; 2],
    share: &[([f64; 2], f64)],
    penalty: f64,
    tie_stiffness: f64,
) -> Result<Option<NodeTilt>, ReduceError> {
    let Some(arm) = arm(area, second_moment) else {
        return Ok(None);
    };
    let invalid = |why: String| ReduceError::Tilt {
        pair: pair.to_string(),
        reduced_node,
        why,
    };
    let e =
        axes(plane_axes, n).ok_or_else(|| invalid("its normal lies in the grid's plane".into()))?;
    let side = |patch: &[([f64; 3], usize, f64)], which: &str| {
        slope_terms(patch, e, n).ok_or_else(|| {
            invalid(format!(
                "the {which} patch's {} nodes lie about on a line: no slope across it",
                patch.len()
            ))
        })
    };
    let (pad_slope, disc_slope) = (side(pad, "pad")?, side(disc, "disc")?);
    // A patch with a slope has a spread, so a twist.
    let twist = |patch: &[([f64; 3], usize, f64)], which: &str| {
        twist_terms(patch, n)
            .ok_or_else(|| invalid(format!("the {which} patch has no in-plane spread")))
    };
    let (pad_twist, disc_twist) = (twist(pad, "pad")?, twist(disc, "disc")?);
    let mut ties = Vec::with_capacity(6);
    let sides = [(&pad_slope, &pad_twist), (&disc_slope, &disc_twist)];
    for (node, (slope, twist)) in nodes.into_iter().zip(sides) {
        for (axis, terms) in [(e[0], &slope[0]), (e[1], &slope[1]), (n, twist)] {
            let mut spring = vec![(node, axis)];
            spring.extend(terms.iter().map(|&(j, g)| (j, scale(-arm, g))));
            ties.push(ScalarSpring {
                terms: spring,
                stiffness: tie_stiffness,
            });
        }
    }
    // The share's offsets, in the grid plane's axes, along e.
    let patch = share_offsets(share, plane_axes, e);
    Ok(Some(NodeTilt {
        law: Tilt {
            nodes,
            axes: e,
            patch,
            arm,
            penalty,
            bilateral: false,
        },
        ties,
        arm,
    }))
}

/// Where a patch law integrates the full pair's penalty over its share of the pad face.
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    serde::Serialize,
    serde::Deserialize,
    clap::ValueEnum,
)]
#[serde(rename_all = "kebab-case")]
pub enum PatchQuadrature {
    /// At the share's face nodes, each with its tributary area, about their area-weighted
    /// centre ([`nodal_share`]): the full model's node-to-surface penalty
    /// itself, so that a gap field linear over the share closes, loads and stiffens each
    /// node as the full model does. On share couplings; distributing couplings (which hold
    /// no share of nodes) take [`PatchQuadrature::Area`].
    ///
    /// Why. The full model closes a node's whole tributary area as soon as its gap is
    /// negative, half an element past where a continuous gap field changes sign; the area
    /// rule closes only up to the sign change. Along the contact zone's edge that strip is
    /// a fixed width of the pad mesh, whatever the grid: on small-caliper at mu = 0 the
    /// area rule closed 46.3 / 47.1 % of the face against the full model's 51.2 % (normal
    /// stiffness 0.90 / 0.92), and put through the full model's own gaps, a plane per
    /// share, still 48.0 / 47.5 % (47.1 / 47.7 % at 106 nodes per pad: no convergence);
    /// the nodes closed 50.9 / 50.6 % (0.993 / 0.988), and the real modes at mu = 0 moved
    /// 0.130 % on average against 0.365 % (issue 29's note, 2026-12-07).
    #[default]
    Nodes,
    /// At sub-triangles of the share no larger than h / 8 (the grid's own split of the face,
    /// [`super::grid`]): the share's area integrated as a continuum; the rule before
    /// 2026-12-07.
    Area,
}

/// Each share's part of the pad face as its patch law integrates it, in the grid's order:
/// at its face nodes ([`nodal_share`]) given the face's tributary areas by node, else the
/// grid's sub-triangles.
pub fn shares(
    grid: &ContactGrid,
    couplings: &[DistributingCoupling],
    areas: Option<&std::collections::BTreeMap<usize, f64>>,
) -> Vec<Vec<([f64; 2], f64)>> {
    grid.nodes
        .iter()
        .zip(couplings)
        .map(|(node, coupling)| match areas {
            Some(areas) => nodal_share(coupling, areas, &grid.plane, node.plane),
            None => node.patch.clone(),
        })
        .collect()
}

/// A share's part of the pad face as the full pair integrates it: each of its face nodes
/// (a share coupling's) with its tributary area (`areas`, by node), at its offset in the
/// grid plane from the share's area-weighted centre (the point the translation tie and the
/// slope ties hold the plane at), so that a field linear over the share closes and loads
/// each node as the full model's node-to-surface penalty does.
pub fn nodal_share(
    coupling: &DistributingCoupling,
    areas: &std::collections::BTreeMap<usize, f64>,
    plane: &super::grid::MeanPlane,
    node: [f64; 2],
) -> Vec<([f64; 2], f64)> {
    let points: Vec<([f64; 2], f64)> = coupling
        .nodes
        .iter()
        .filter_map(|c| {
            let a = *areas.get(&c.node)?;
            let p = plane.to_plane(c.position);
            Some(([p[0] - node[0], p[1] - node[1]], a))
        })
        .collect();
    let total: f64 = points.iter().map(|p| p.1).sum();
    if total <= 0.0 {
        // No face node with an area: an empty share (its law carries nothing), rather than
        // NaN offsets from a centre of 0 / 0. reduce_interface's shares all hold face nodes.
        return Vec::new();
    }
    let centre = [0, 1].map(|i| points.iter().map(|p| p.1 * p.0[i]).sum::<f64>() / total);
    points
        .into_iter()
        .map(|(xi, a)| ([xi[0] - centre[0], xi[1] - centre[1]], a))
        .collect()
}

/// A coupling's patch as (position, node, weight).
pub fn patch(
    coupling: &DistributingCoupling,
    positions: &[[f64; 3]],
) -> Vec<([f64; 3], usize, f64)> {
    coupling
        .nodes
        .iter()
        .map(|c| (positions[c.node], c.node, c.weight))
        .collect()
}

/// Whose tilt nodes each share's patch law reads, in the grid's order: its own where its
/// face nodes give a slope and a twist and spread across the share ([`reads_own_slope`]),
/// else the nearest such share's (grid points in the plane, the lower index on a tie).
/// `None` when no share of the face gives one.
///
/// Why. On a grid about as fine as the mesh an edge share can hold one row of face nodes
/// (medium-caliper at 90 and 106 nodes per pad: 4 nodes on one line). Its translation
/// coupling is sound, but no slope across the row can be read from its nodes. Read with its
/// neighbours' nodes (squeal's first answer), its slope tie binds nodes their own ties
/// already fix: the ties are dependent, the tilt node's constraint mode moves no mass and a
/// super-element's reduced mass is singular (measured: `tiny` at 22 nodes per pad, 19 of 44
/// shares borrowing, the Cholesky failed; the ties' independence 0 or 1e-19 on every grid
/// where shares borrowed). Reading the nearest neighbour's tilt nodes adds no tie at all: the
/// ties stay those of the shares with a slope of their own, on disjoint nodes, independent
/// by construction. The share's own law still integrates the penalty over its own part of
/// the face, at the neighbour's tilt (the pad and disc patches there move about as its own).
pub fn slope_owners(
    couplings: &[DistributingCoupling],
    grid: &ContactGrid,
    positions: &[[f64; 3]],
) -> Option<Vec<usize>> {
    let reads: Vec<bool> = couplings
        .iter()
        .zip(&grid.nodes)
        .map(|(c, node)| reads_own_slope(c, node, grid.plane.axes, positions))
        .collect();
    (0..couplings.len())
        .map(|k| {
            if reads[k] {
                return Some(k);
            }
            let at = grid.nodes[k].plane;
            (0..couplings.len())
                .filter(|&j| reads[j])
                .map(|j| {
                    let q = grid.nodes[j].plane;
                    ((q[0] - at[0]).powi(2) + (q[1] - at[1]).powi(2), j)
                })
                .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)))
                .map(|(_, j)| j)
        })
        .collect()
}

/// Whether the share of reduced node `node`, coupled by `coupling`, gives a slope and a
/// twist of its own that its ties can hold without stiffening its nodes far beyond the
/// rest of the face: its nodes off one line and no thinner than [`THIN`] allows.
pub fn reads_own_slope(
    coupling: &DistributingCoupling,
    node: &ReducedNode,
    plane_axes: [[f64; 3]; 2],
    positions: &[[f64; 3]],
) -> bool {
    let own = patch(coupling, positions);
    let (Some(e), Some(arm)) = (
        axes(plane_axes, node.normal),
        arm(node.area, node.second_moment),
    ) else {
        return false;
    };
    slope_terms(&own, e, node.normal).is_some()
        && twist_terms(&own, node.normal).is_some()
        && thinness(&own, e, arm) <= THIN
}

/// The patch law of a share that reads another's tilt nodes ([`slope_owners`]): the
/// owner's nodes and arm (its tilt nodes hold arm times its slopes), the share's own axes
/// (the in-plane axes at its normal `n`: the owner's where the face is flat), its own part
/// of the pad face (`share`, offsets in the grid plane's axes `plane_axes`, and areas) and
/// the pair's penalty per unit area.
pub fn shared_tilt(
    owner: &Tilt,
    n: [f64; 3],
    plane_axes: [[f64; 3]; 2],
    share: &[([f64; 2], f64)],
    penalty: f64,
) -> Option<Tilt> {
    let e = axes(plane_axes, n)?;
    Some(Tilt {
        nodes: owner.nodes,
        axes: e,
        patch: share_offsets(share, plane_axes, e),
        arm: owner.arm,
        penalty,
        bilateral: owner.bilateral,
    })
}

/// A share's quadrature points (offsets in the grid plane's axes, areas) with their offsets
/// along the in-plane axes `e`.
fn share_offsets(
    share: &[([f64; 2], f64)],
    plane_axes: [[f64; 3]; 2],
    e: [[f64; 3]; 2],
) -> Vec<([f64; 2], f64)> {
    share
        .iter()
        .map(|&(xi, a)| {
            let v = crate::vector3::add(scale(xi[0], plane_axes[0]), scale(xi[1], plane_axes[1]));
            ([dot(v, e[0]), dot(v, e[1])], a)
        })
        .collect()
}

/// The smallest singular value over the largest of the ties the shares of a pad face that
/// read their own slopes ([`slope_owners`]) put on its nodes' normal displacements (rows
/// scaled to unit length): each share's mean (its translation tie's normal part), and each
/// owner's two slopes. 0 when they are more than the face has nodes.
///
/// Why. Each tie holds a boundary coordinate of a super-element (a reduced contact node or a
/// tilt node); a tie that the others already fix has a constraint mode that moves no mass
/// (its tilt node is massless), and the super-element's reduced mass is singular.
#[cfg(test)]
pub fn share_ties_independence(
    couplings: &[DistributingCoupling],
    grid: &ContactGrid,
    positions: &[[f64; 3]],
) -> f64 {
    let Some(owners) = slope_owners(couplings, grid, positions) else {
        return 0.0;
    };
    let mut columns = std::collections::BTreeMap::new();
    for c in couplings {
        for node in &c.nodes {
            let next = columns.len();
            columns.entry(node.node).or_insert(next);
        }
    }
    let mut rows: Vec<Vec<f64>> = Vec::new();
    for (k, c) in couplings.iter().enumerate() {
        let n = grid.nodes[k].normal;
        let mut mean = vec![0.0; columns.len()];
        for node in &c.nodes {
            mean[columns[&node.node]] += node.weight;
        }
        rows.push(mean);
        if owners[k] != k {
            continue;
        }
        let own = patch(c, positions);
        let Some(terms) = axes(grid.plane.axes, n).and_then(|e| slope_terms(&own, e, n)) else {
            return 0.0;
        };
        for terms in &terms {
            let mut row = vec![0.0; columns.len()];
            for &(node, g) in terms {
                row[columns[&node]] += dot(g, n);
            }
            rows.push(row);
        }
    }
    if rows.len() > columns.len() {
        return 0.0;
    }
    let mut m = faer::Mat::<f64>::zeros(rows.len(), columns.len());
    for (i, row) in rows.iter().enumerate() {
        let norm = row.iter().map(|v| v * v).sum::<f64>().sqrt();
        if norm == 0.0 {
            return 0.0;
        }
        for (j, v) in row.iter().enumerate() {
            m[(i, j)] = v / norm;
        }
    }
    match m.singular_values() {
        Ok(s) => {
            let (large, small) = s
                .iter()
                .fold((0.0f64, f64::INFINITY), |(l, sm), &v| (l.max(v), sm.min(v)));
            if large > 0.0 {
                small / large
            } else {
                0.0
            }
        }
        Err(_) => 0.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The slope terms read the slope of any linear normal field exactly, whatever its mean
    /// and whatever the in-plane motion, and ignore in-plane displacements.
    #[test]
    fn slope_terms_are_exact_for_a_linear_field() {
        let n = normalize([0.1, -0.2, 1.0]).unwrap();
        let e = axes([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], n).unwrap();
        assert!(dot(e[0], n).abs() < 1e-15 && dot(e[1], n).abs() < 1e-15);
        assert!(dot(e[0], e[1]).abs() < 1e-15);
        let points = [[0.0, 0.0], [1.0, 0.2], [0.3, 1.1], [-0.8, 0.4], [0.2, -0.9]];
        let patch: Vec<([f64; 3], usize, f64)> = points
            .iter()
            .enumerate()
            .map(|(j, p)| {
                let x = crate::vector3::add(scale(p[0], e[0]), scale(p[1], e[1]));
                (x, j, 0.1 + 0.05 * j as f64)
            })
            .collect();
        let terms = slope_terms(&patch, e, n).unwrap();
        let (mean, slope) = (0.3, [0.7, -1.9]);
        let u: Vec<[f64; 3]> = patch
            .iter()
            .map(|&(x, _, _)| {
                let normal = mean + slope[0] * dot(x, e[0]) + slope[1] * dot(x, e[1]);
                // An in-plane part that must not count.
                crate::vector3::add(scale(normal, n), scale(0.4 * x[0], e[1]))
            })
            .collect();
        for a in 0..2 {
            let s: f64 = terms[a].iter().map(|&(j, g)| dot(g, u[j])).sum();
            assert!((s - slope[a]).abs() < 1e-14, "{s} vs {}", slope[a]);
        }
        // Nodes on a line: no slope across it.
        let line: Vec<([f64; 3], usize, f64)> =
            (0..4).map(|j| (scale(j as f64, e[0]), j, 0.25)).collect();
        assert!(slope_terms(&line, e, n).is_none());
    }

    /// With nodal quadrature a share's patch law is the full pair's node-to-surface penalty
    /// over the share's nodes for any gap field linear over the share: read at the field's
    /// area-weighted mean (what the translation tie holds) and its slope (what the slope ties
    /// hold), it closes the same nodes and gives the same force, stiffness and moment about
    /// the nodes' centre, to round-off, wherever the grid node sits in the share.
    #[test]
    fn nodal_share_is_the_full_penalty_for_a_linear_field() {
        let plane = super::super::grid::MeanPlane {
            origin: [0.3, -0.2, 1.0],
            axes: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            normal: [0.0, 0.0, 1.0],
            deviation: 0.0,
            size: 1.0,
        };
        let at = [
            [0.1, 0.0],
            [1.0, 0.2],
            [0.3, 1.1],
            [-0.8, 0.4],
            [0.2, -0.9],
            [0.9, -0.7],
        ];
        let areas: std::collections::BTreeMap<usize, f64> = (0..at.len())
            .map(|j| (10 + j, 0.1 + 0.05 * j as f64))
            .collect();
        let total: f64 = areas.values().sum();
        let coupling = DistributingCoupling {
            reduced_node: 0,
            reference: plane.origin,
            radius: 0.0,
            weighting: super::super::coupling::Weighting::Uniform,
            nodes: at
                .iter()
                .enumerate()
                .map(|(j, p)| super::super::coupling::CouplingNode {
                    node: 10 + j,
                    position: [plane.origin[0] + p[0], plane.origin[1] + p[1], 1.0],
                    distance: 0.0,
                    weight: areas[&(10 + j)] / total,
                })
                .collect(),
        };
        let share = nodal_share(&coupling, &areas, &plane, [0.05, 0.1]);
        assert!((share.iter().map(|q| q.1).sum::<f64>() - total).abs() < 1e-15);
        // None of its nodes on the face (no area): an empty share, not NaN offsets.
        assert!(nodal_share(&coupling, &Default::default(), &plane, [0.05, 0.1]).is_empty());
        let penalty = 3.0e13;
        let law = Tilt {
            nodes: [0, 1],
            axes: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            patch: share_offsets(&share, plane.axes, [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]),
            arm: 1.0,
            penalty,
            bilateral: false,
        };
        let centre = [0, 1].map(|i| {
            at.iter()
                .zip(areas.values())
                .map(|(p, a)| a * p[i])
                .sum::<f64>()
                / total
        });
        // Closed on one side of a line through the share, open on the other; all closed;
        // all open.
        for (g0, slope) in [
            (1e-7, [-2e-6, 1e-6]),
            (-1e-5, [1e-7, 2e-7]),
            (1e-5, [1e-7, 0.0]),
        ] {
            let gap = |p: &[f64; 2]| g0 + slope[0] * p[0] + slope[1] * p[1];
            let mean = at
                .iter()
                .zip(areas.values())
                .map(|(p, a)| a * gap(p))
                .sum::<f64>()
                / total;
            let (mut force, mut k0, mut moment) = (0.0, 0.0, [0.0; 2]);
            for (p, a) in at.iter().zip(areas.values()) {
                if gap(p) <= 0.0 {
                    let f = -penalty * a * gap(p);
                    force += f;
                    k0 += penalty * a;
                    for i in 0..2 {
                        moment[i] += f * (p[i] - centre[i]);
                    }
                }
            }
            let l = law.law(mean, slope);
            let close = |a: f64, b: f64, scale: f64| (a - b).abs() <= 1e-12 * scale;
            assert!(
                close(l.force, force, force.abs() + 1.0),
                "{} vs {force}",
                l.force
            );
            assert!(close(l.k0, k0, penalty * total), "{} vs {k0}", l.k0);
            for i in 0..2 {
                assert!(
                    close(l.moment[i], moment[i], force.abs() + 1.0),
                    "{:?} vs {moment:?}",
                    l.moment
                );
            }
        }
    }

    /// Thinness against hand computation: a unit square share with a node at each corner
    /// (arm^2 = tr I / 2A = 1/12, covariance 1/4 I: 1/3), and a strip of nodes at
    /// (+-1/2, +-d) in the same share (covariance diag(1/4, d^2): arm^2 / d^2). Across the
    /// strip the slope tie's largest coefficient grows as its thinness: arm^2 |g|^2 =
    /// arm^2 / (16 d^2) per node, which is why [`THIN`] exists.
    #[test]
    fn thinness_is_the_arm_over_the_thinnest_spread_squared() {
        let n = [0.0, 0.0, 1.0];
        let e = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let area = 1.0;
        let moment = [[1.0 / 12.0, 0.0], [0.0, 1.0 / 12.0]];
        let arm = arm(area, moment).unwrap();
        assert!((arm * arm - 1.0 / 12.0).abs() < 1e-15);
        let corners = |d: f64| -> Vec<([f64; 3], usize, f64)> {
            [[-0.5, -d], [0.5, -d], [0.5, d], [-0.5, d]]
                .iter()
                .enumerate()
                .map(|(j, p)| ([p[0], p[1], 0.0], j, 0.25))
                .collect()
        };
        assert!((thinness(&corners(0.5), e, arm) - 1.0 / 3.0).abs() < 1e-14);
        for d in [0.1, 0.01, 1e-3] {
            let strip = corners(d);
            let t = thinness(&strip, e, arm);
            let want = arm * arm / (d * d);
            assert!((t - want).abs() < 1e-12 * want, "d {d}: {t} vs {want}");
            let across = &slope_terms(&strip, e, n).unwrap()[1];
            for &(_, g) in across {
                let c = arm * arm * dot(g, g);
                assert!(
                    (c - t / 16.0).abs() < 1e-10 * c,
                    "d {d}: {c} vs {}",
                    t / 16.0
                );
            }
        }
        assert!(thinness(&corners(0.0), e, arm).is_infinite());
        assert!(super::arm(0.0, moment).is_none() && super::arm(1.0, [[0.0; 2]; 2]).is_none());
    }

    /// The twist terms read a rigid rotation about the normal exactly, whatever the
    /// translation and the normal field added to it; a single node has no twist.
    #[test]
    fn twist_terms_are_exact_for_a_rigid_rotation() {
        let n = normalize([0.1, -0.2, 1.0]).unwrap();
        let e = axes([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], n).unwrap();
        let patch: Vec<([f64; 3], usize, f64)> = [[0.0, 0.0], [1.0, 0.2], [0.3, 1.1], [-0.8, 0.4]]
            .iter()
            .enumerate()
            .map(|(j, p)| {
                let x = crate::vector3::add(scale(p[0], e[0]), scale(p[1], e[1]));
                (
                    crate::vector3::add(x, [5.0, -2.0, 0.5]),
                    j,
                    0.1 + 0.05 * j as f64,
                )
            })
            .collect();
        let terms = twist_terms(&patch, n).unwrap();
        let (omega, shift) = (0.37, [0.2, -0.1, 0.05]);
        let u: Vec<[f64; 3]> = patch
            .iter()
            .map(|&(x, _, _)| {
                let rotation = scale(omega, cross(n, x));
                let bend = scale(0.3 * dot(x, e[0]), n);
                crate::vector3::add(crate::vector3::add(rotation, shift), bend)
            })
            .collect();
        let twist: f64 = terms.iter().map(|&(j, g)| dot(g, u[j])).sum();
        assert!((twist - omega).abs() < 1e-14, "{twist} vs {omega}");
        assert!(twist_terms(&patch[..1], n).is_none());
    }

    /// A share whose face nodes lie on one line (an edge share of a grid about as fine as
    /// the mesh) reads its nearest neighbour's tilt nodes, and the ties of the shares that
    /// read their own stay independent; a borrower's law reads the owner's tilt with its own
    /// axes and arm, which for a linear field over a flat face is its own tilt exactly.
    #[test]
    fn a_share_on_one_line_reads_its_nearest_neighbours_tilt_nodes() {
        use crate::mesh::{block::block, Material};
        use crate::reduce::{coupling::couple_shares, grid::isometric_grid, GridSize};
        let material = Material {
            name: "m".into(),
            young: 1.0,
            poisson: 0.3,
            density: 1.0,
        };
        // Top face z = 0.1: nodes every 0.05 over [0, 1] x [0, 1].
        let mesh = block([0.0, 0.0, 0.0], [1.0, 1.0, 0.1], [10, 10, 1], material).unwrap();
        let surface = &mesh.surfaces["z1"];
        let n = [0.0, 0.0, 1.0];
        // The finest grids whose shares all hold a node: some of their edge shares hold one
        // row of nodes, or fewer than three.
        let mut borrowing = 0;
        for h in [0.08, 0.09, 0.1, 0.11, 0.12] {
            let grid = isometric_grid(&mesh, surface, GridSize::Spacing(h)).unwrap();
            let Ok(couplings) = couple_shares(&mesh, surface, &grid) else {
                continue;
            };
            let owners = slope_owners(&couplings, &grid, &mesh.nodes).expect("a share reads");
            // The predicate itself is checked by hand values above; here, that the owners
            // follow it and are the nearest that satisfy it.
            let reads = |k: usize| {
                reads_own_slope(&couplings[k], &grid.nodes[k], grid.plane.axes, &mesh.nodes)
            };
            for (k, &owner) in owners.iter().enumerate() {
                assert_eq!(owner == k, reads(k), "h {h}, share {k}");
                assert!(
                    reads(owner),
                    "h {h}: share {k} reads {owner}, which has no slope"
                );
                // No reader is nearer than the owner.
                let d = |j: usize| {
                    let (p, q) = (grid.nodes[k].plane, grid.nodes[j].plane);
                    (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)
                };
                assert!((0..owners.len()).all(|j| !reads(j) || d(j) >= d(owner)));
                borrowing += usize::from(owner != k);
            }
            // The ties of the owners: measured 0.29-0.65 on the presets' grids where every
            // share reads its own; a dependent set has 0 to round-off.
            let independence = share_ties_independence(&couplings, &grid, &mesh.nodes);
            assert!(independence > 1e-3, "h {h}: independence {independence:e}");

            // A tilt of the whole face: each owner's tilt nodes hold arm times its slope, and
            // every share's law, its own or borrowed, reads that slope.
            let grad = [0.7, -1.9];
            let u = |x: [f64; 3]| [0.2 * x[1], -0.1, 0.3 + grad[0] * x[0] + grad[1] * x[1]];
            for (k, &owner) in owners.iter().enumerate() {
                let node = &grid.nodes[owner];
                let own = patch(&couplings[owner], &mesh.nodes);
                let made = node_tilt(
                    "p",
                    owner,
                    [0, 1],
                    n,
                    grid.plane.axes,
                    &own,
                    &own,
                    node.area,
                    node.second_moment,
                    &node.patch,
                    1.0,
                    1.0,
                )
                .unwrap()
                .expect("an owner has a second moment");
                // The tilt node's displacement that satisfies the owner's pad ties.
                let mut rp = [0.0; 3];
                for tie in made.ties.iter().take(3) {
                    let axis = tie.terms[0].1;
                    let held: f64 = tie.terms[1..]
                        .iter()
                        .map(|&(j, g)| dot(g, u(mesh.nodes[j])))
                        .sum();
                    rp = crate::vector3::add(rp, scale(-held, axis));
                }
                let law = if owner == k {
                    made.law.clone()
                } else {
                    let node = &grid.nodes[k];
                    shared_tilt(&made.law, n, grid.plane.axes, &node.patch, 1.0).unwrap()
                };
                assert_eq!(law.nodes, made.law.nodes);
                for a in 0..2 {
                    let theta = dot(law.axes[a], rp) / law.arm;
                    let expected = grad[0] * law.axes[a][0] + grad[1] * law.axes[a][1];
                    assert!(
                        (theta - expected).abs() < 1e-12,
                        "h {h}, share {k}: {theta} {expected}"
                    );
                }
            }
        }
        assert!(
            borrowing > 0,
            "no grid had a share on one line: the test sees nothing"
        );
    }
}
