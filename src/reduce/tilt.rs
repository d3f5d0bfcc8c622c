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
//! motion of the whole model tilts both patches alike: u_rp = u_rd.
//!
//! `arm` = sqrt(tr I / (2 A)), the share's radius of gyration, so that r_p, r_d are displacements
//! of the patch's size and the tilt's stiffness is of the point's normal stiffness k_n A:
//! the ties, k_s = 1e3 k_n A like the translation ties, are equally stiff relative to what
//! they hold.

use super::coupling::DistributingCoupling;
use super::grid::ContactGrid;
use super::ReduceError;
use crate::contact::Tilt;
use crate::fem::springs::ScalarSpring;
use crate::vector3::{cross, dot, normalize, scale, sub};

/// A patch whose in-plane spread has a condition number beyond this (its nodes about on a
/// line) cannot give a slope across that line.
const COLLINEAR: f64 = 1e8;

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

/// The coefficients of the least-squares slope of the normal displacement of a patch of
/// nodes (`(position, node, weight)`): slope_a = sum_j g_ja . u_j, g_ja = (G^-1 w_j xi_j)_a n,
/// xi_j the in-plane offsets from the weighted centre, G = sum_j w_j xi_j xi_j^T. `None`
/// when the nodes are about on a line.
pub fn slope_terms(
    patch: &[([f64; 3], usize, f64)],
    axes: [[f64; 3]; 2],
    n: [f64; 3],
) -> Option<[SlopeTerms; 2]> {
    let centre = weighted_centre(patch)?;
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
                g[a][b] += p.2 * xi[a] * xi[b];
            }
        }
    }
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
                let c = w * (inverse[a][0] * xi[0] + inverse[a][1] * xi[1]);
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
    let trace = second_moment[0][0] + second_moment[1][1];
    if !(area > 0.0 && trace > 0.0) {
        return Ok(None);
    }
    let invalid = |why: String| ReduceError::Tilt {
        pair: pair.to_string(),
        reduced_node,
        why,
    };
    let e =
        axes(plane_axes, n).ok_or_else(|| invalid("its normal lies in the grid's plane".into()))?;
    let arm = (trace / (2.0 * area)).sqrt();
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
    let patch = share
        .iter()
        .map(|&(xi, a)| {
            let v = crate::vector3::add(scale(xi[0], plane_axes[0]), scale(xi[1], plane_axes[1]));
            ([dot(v, e[0]), dot(v, e[1])], a)
        })
        .collect();
    Ok(Some(NodeTilt {
        law: Tilt {
            nodes,
            axes: e,
            patch,
            arm,
            penalty,
        },
        ties,
        arm,
    }))
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

/// The largest condition number of a borrowed slope patch's in-plane spread: a share that
/// borrows lay about on a line, and the first neighbour may extend that line (the next edge
/// share) rather than cross it; the slope across it is then read from a patch nearly as
/// thin, round-off amplified by the condition number. 100 is a patch ten times longer than
/// wide; two rows of nodes along an edge share give about 10.
const BORROWED_CONDITION: f64 = 100.0;

/// The condition number of the weighted in-plane spread G of a patch about its weighted
/// centre (`trace^2 / det`, about l1 / l2 when l1 >> l2), `None` when G is singular.
fn spread_condition(patch: &[([f64; 3], usize, f64)], axes: [[f64; 3]; 2]) -> Option<f64> {
    let centre = weighted_centre(patch)?;
    let mut g = [[0.0; 2]; 2];
    for &(x, _, w) in patch {
        let d = sub(x, centre);
        let xi = [dot(d, axes[0]), dot(d, axes[1])];
        for a in 0..2 {
            for b in 0..2 {
                g[a][b] += w * xi[a] * xi[b];
            }
        }
    }
    let (trace, det) = (g[0][0] + g[1][1], g[0][0] * g[1][1] - g[0][1] * g[1][0]);
    (det > 0.0).then(|| trace * trace / det)
}

/// The patch a share's tilt node reads its slope and twist from (`(position, node, weight)`,
/// each node weighted by its tributary area): share `k`'s own nodes where they give both,
/// else with the nodes of the other shares added, nearest grid point first, one share at a
/// time, until they give one whose spread is no thinner than [`BORROWED_CONDITION`]. Returns
/// the patch and how many shares it borrowed from.
///
/// Why. On a grid about as fine as the mesh an edge share can hold one row of face nodes
/// (medium-caliper at 90 and 106 nodes per pad: 4 nodes on one line). Its translation
/// coupling is sound, but no slope across the row can be read from it; before, one such
/// share sent the whole interface back to the paper's couplings and point contacts, and 106
/// nodes per pad came out worse than 52 (mean shift of the modes without friction 0.413 %
/// against 0.163 %, issue 29; the default still does where the borrowed slopes' ties depend
/// on the others', [`share_ties_independence`]). The borrowed nodes enter the slope alone: the share's force
/// still lands on its own nodes. The fit stays exact for a linear field (any patch whose
/// nodes are off one line gives the slope of a plane), and only such edge shares overlap
/// their neighbours.
pub fn share_slope_patch(
    couplings: &[DistributingCoupling],
    grid: &ContactGrid,
    k: usize,
    positions: &[[f64; 3]],
    n: [f64; 3],
) -> (Vec<([f64; 3], usize, f64)>, usize) {
    // Share weights add up to 1 over each share: times the share's area, the nodes' areas.
    let nodes_of = |j: usize| {
        couplings[j]
            .nodes
            .iter()
            .map(move |c| (positions[c.node], c.node, c.weight * grid.nodes[j].area))
    };
    let mut patch: Vec<_> = nodes_of(k).collect();
    let Some(e) = axes(grid.plane.axes, n) else {
        return (patch, 0);
    };
    // Its own nodes where they give a slope at all (what every share did before shares
    // could borrow); a borrowed patch until it gives a well-conditioned one.
    let reads = |patch: &[([f64; 3], usize, f64)], bound: f64| {
        slope_terms(patch, e, n).is_some()
            && twist_terms(patch, n).is_some()
            && spread_condition(patch, e).is_some_and(|c| c <= bound)
    };
    if reads(&patch, COLLINEAR) {
        return (patch, 0);
    }
    let at = grid.nodes[k].plane;
    let mut others: Vec<(f64, usize)> = (0..couplings.len())
        .filter(|&j| j != k)
        .map(|j| {
            let q = grid.nodes[j].plane;
            ((q[0] - at[0]).powi(2) + (q[1] - at[1]).powi(2), j)
        })
        .collect();
    others.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    for (borrowed, &(_, j)) in others.iter().enumerate() {
        patch.extend(nodes_of(j));
        if reads(&patch, BORROWED_CONDITION) {
            return (patch, borrowed + 1);
        }
    }
    (patch, others.len())
}

/// The smallest singular value over the largest of the ties a pad face's shares put on its
/// nodes' normal displacements (rows scaled to unit length): each share's mean (its
/// translation tie's normal part) and its two slopes, read from its slope patch
/// ([`share_slope_patch`]). 0 when the shares put more such ties than the face has nodes.
///
/// Why. Each tie holds a boundary coordinate of a super-element (a reduced contact node or a
/// tilt node); a tie that the others already fix has a constraint mode that moves no mass
/// (its tilt node is massless), and the super-element's reduced mass is singular: measured
/// on `tiny` with 22 nodes per pad (65 face nodes, 66 such ties; 19 shares of 44 borrowed),
/// the single super-element's Cholesky failed. A share that borrows reads its slope across
/// its line from its neighbours' nodes, which their own three ties may already fix.
pub fn share_ties_independence(
    couplings: &[DistributingCoupling],
    grid: &ContactGrid,
    positions: &[[f64; 3]],
) -> f64 {
    let mut columns = std::collections::BTreeMap::new();
    for c in couplings {
        for node in &c.nodes {
            let next = columns.len();
            columns.entry(node.node).or_insert(next);
        }
    }
    let rows = 3 * couplings.len();
    if rows > columns.len() {
        return 0.0;
    }
    let mut m = faer::Mat::<f64>::zeros(rows, columns.len());
    for (k, c) in couplings.iter().enumerate() {
        let n = grid.nodes[k].normal;
        for node in &c.nodes {
            m[(3 * k, columns[&node.node])] += node.weight;
        }
        let (patch, _) = share_slope_patch(couplings, grid, k, positions, n);
        let Some(terms) = axes(grid.plane.axes, n).and_then(|e| slope_terms(&patch, e, n)) else {
            return 0.0;
        };
        for (a, terms) in terms.iter().enumerate() {
            for &(node, g) in terms {
                m[(3 * k + 1 + a, columns[&node])] += dot(g, n);
            }
        }
    }
    for i in 0..rows {
        let norm = (0..m.ncols())
            .map(|j| m[(i, j)].powi(2))
            .sum::<f64>()
            .sqrt();
        if norm == 0.0 {
            return 0.0;
        }
        (0..m.ncols()).for_each(|j| m[(i, j)] /= norm);
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
    /// the mesh) reads its slope with the nearest shares' nodes, and reads it exactly; the
    /// other shares read theirs from their own nodes alone.
    #[test]
    fn a_share_on_one_line_borrows_its_neighbours_nodes_for_its_slope() {
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
            let axes = axes(grid.plane.axes, n).unwrap();
            for k in 0..couplings.len() {
                let own = patch(&couplings[k], &mesh.nodes);
                let (slope_patch, borrowed) =
                    share_slope_patch(&couplings, &grid, k, &mesh.nodes, n);
                let reads_alone =
                    slope_terms(&own, axes, n).is_some() && twist_terms(&own, n).is_some();
                assert_eq!(borrowed == 0, reads_alone, "h {h}, share {k}");
                // The share's own nodes first, then whole shares.
                assert!(slope_patch.len() >= own.len());
                assert!(slope_patch.iter().zip(&own).all(|(a, b)| a.1 == b.1));
                borrowing += usize::from(borrowed > 0);
                assert!(
                    borrowed == 0
                        || spread_condition(&slope_patch, axes).unwrap() <= BORROWED_CONDITION
                );
                let terms = slope_terms(&slope_patch, axes, n).expect("a slope");
                // A linear normal field of gradient `grad`, plus an in-plane motion that must
                // not count; its slope along each of the patch's axes.
                let grad = [0.7, -1.9, 0.0];
                for a in 0..2 {
                    let s: f64 = terms[a]
                        .iter()
                        .map(|&(j, g)| {
                            let w = 0.3 + dot(grad, mesh.nodes[j]);
                            dot(g, [0.2 * mesh.nodes[j][1], -0.1, w])
                        })
                        .sum();
                    let expected = dot(grad, axes[a]);
                    // Round-off: eps times the patch's condition (<= 100 when borrowed) times
                    // the field's size over the patch's (~ 2 / 0.05), summed over ~30 nodes.
                    assert!(
                        (s - expected).abs() < 1e-10,
                        "h {h}, share {k}: {s} {expected}"
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
