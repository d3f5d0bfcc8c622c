//! Distributing-coupling weights, one implementation for the reduction layer's reduced
//! contact nodes (the paper's eqs. 9-11, [`crate::reduce::coupling`]) and a deck's
//! `*COUPLING` + `*DISTRIBUTING` (Abaqus's WEIGHTING METHOD): the nodes of a cloud within a
//! radius of influence R of a reference point, each weighted by `w(r / R)`, normalised to
//! `wbar_i = w_i / sum_j w_j`. And the motion of a reference point tied to a cloud the way
//! Abaqus's distributing coupling ties it ([`reference_motion`]).

use crate::vector3::{cross, dot, norm, sub};
use serde::{Deserialize, Serialize};

/// How a coupling node's weight falls with its distance r from the reference point
/// (`s = r / R`, zero from `s = 1` on).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, clap::ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum Weighting {
    /// `w = 1`: every node within R alike (Abaqus's default).
    Uniform,
    /// `w = 1 - s` (eq. 9).
    Linear,
    /// `w = 1 - s^2` (eq. 10).
    Quadratic,
    /// `w = 1 - 3 s^2 + 2 s^3` (eq. 11): zero slope at both ends.
    Cubic,
}

impl Weighting {
    /// The weight at `s = r / R`; 0 for `s >= 1`.
    pub fn weight(self, s: f64) -> f64 {
        if s >= 1.0 {
            return 0.0;
        }
        self.profile(s)
    }

    /// The weight's formula at `s` in [0, 1], the end included (1 for uniform at `s = 1`:
    /// Abaqus's default radius is the farthest node's distance, and a uniform coupling
    /// keeps that node).
    pub fn profile(self, s: f64) -> f64 {
        match self {
            Weighting::Uniform => 1.0,
            Weighting::Linear => 1.0 - s,
            Weighting::Quadratic => 1.0 - s * s,
            Weighting::Cubic => 1.0 - s * s * (3.0 - 2.0 * s),
        }
    }

    /// The polynomial degree of the paper's Table 2 (`None` for uniform).
    pub fn degree(self) -> Option<u32> {
        match self {
            Weighting::Uniform => None,
            Weighting::Linear => Some(1),
            Weighting::Quadratic => Some(2),
            Weighting::Cubic => Some(3),
        }
    }

    /// The weighting of a Table 2 degree (1, 2, 3).
    pub fn from_degree(degree: u32) -> Option<Weighting> {
        match degree {
            1 => Some(Weighting::Linear),
            2 => Some(Weighting::Quadratic),
            3 => Some(Weighting::Cubic),
            _ => None,
        }
    }
}

/// One node of a coupling's cloud.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CloudNode {
    /// Node index.
    pub node: usize,
    /// Its reference coordinates.
    pub position: [f64; 3],
    /// Its distance r from the reference point.
    pub distance: f64,
    /// Its normalised weight `wbar = w / sum w` (the weights of a coupling add up to 1).
    pub weight: f64,
}

/// Why a cloud cannot carry a reference point.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CloudError {
    #[error("the radius of influence must be positive and finite, got {radius:e}")]
    InvalidRadius { radius: f64 },
    #[error("{found} node(s) with a positive weight{}, at least 3 not on one line are needed to hold the reference point in every direction", if *.collinear { ", all on one line" } else { "" })]
    TooFew { found: usize, collinear: bool },
}

/// The radius of influence of a coupling.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Radius {
    /// The nodes strictly within R.
    Within(f64),
    /// Every candidate, R the farthest one's distance (Abaqus's default when no
    /// INFLUENCE RADIUS is given).
    Farthest,
}

/// The weighted cloud of `candidates` (node, position) about `reference`: the nodes within
/// the radius with a positive weight `w(r / R)`, normalised. Errors when fewer than 3 nodes
/// not on one line are left.
pub fn weigh(
    candidates: &[(usize, [f64; 3])],
    reference: [f64; 3],
    radius: Radius,
    weighting: Weighting,
) -> Result<Vec<CloudNode>, CloudError> {
    let distances: Vec<f64> = candidates
        .iter()
        .map(|&(_, p)| norm(sub(p, reference)))
        .collect();
    let (r, inclusive) = match radius {
        Radius::Within(r) => (r, false),
        Radius::Farthest => (distances.iter().copied().fold(0.0, f64::max), true),
    };
    if !(r > 0.0 && r.is_finite()) {
        return Err(CloudError::InvalidRadius { radius: r });
    }
    // Strictly within R: at r = R the weighted forms are 0 anyway, and excluding the sphere
    // itself keeps "caught" the same set for every weighting.
    let mut nodes: Vec<CloudNode> = candidates
        .iter()
        .zip(&distances)
        .filter_map(|(&(node, position), &distance)| {
            let weight = if inclusive {
                weighting.profile(distance / r)
            } else if distance < r {
                weighting.weight(distance / r)
            } else {
                return None;
            };
            (weight > 0.0).then_some(CloudNode {
                node,
                position,
                distance,
                weight,
            })
        })
        .collect();
    let collinear = nodes.len() >= 3 && on_one_line(&nodes, r);
    if nodes.len() < 3 || collinear {
        return Err(CloudError::TooFew {
            found: nodes.len(),
            collinear,
        });
    }
    normalise(&mut nodes);
    Ok(nodes)
}

/// Scales the weights to add up to 1.
pub fn normalise(nodes: &mut [CloudNode]) {
    let total: f64 = nodes.iter().map(|c| c.weight).sum();
    for c in nodes {
        c.weight /= total;
    }
}

/// Relative size below which the caught nodes count as on one line: the triangle they span
/// at best is smaller than this fraction of R^2 (round-off on nodes placed along an edge is
/// some 1e-16 R^2; a real triangle of nodes within R spans far more).
const COLLINEAR_AREA: f64 = 1e-10;

/// True when all the nodes lie on one line: from the node farthest from the first, the
/// largest triangle any third node spans with those two is negligible.
pub(crate) fn on_one_line(nodes: &[CloudNode], radius: f64) -> bool {
    let a = nodes[0].position;
    let b = nodes
        .iter()
        .map(|c| c.position)
        .max_by(|p, q| norm(sub(*p, a)).total_cmp(&norm(sub(*q, a))))
        .unwrap_or(a);
    let largest = nodes
        .iter()
        .map(|c| 0.5 * norm(cross(sub(b, a), sub(c.position, a))))
        .fold(0.0, f64::max);
    largest <= COLLINEAR_AREA * radius * radius
}

/// The displacement of a reference point tied to a weighted cloud as Abaqus's distributing
/// coupling ties it (Abaqus Theory Manual, "Distributing coupling constraints"): the point
/// moves as a point of a rigid body that has the cloud's weighted mean translation and mean
/// rotation, `u_ref = sum_i wbar_i u_i + phi x (x_ref - xbar)`, with `xbar = sum_i wbar_i
/// x_i`, `r_i = x_i - xbar` and `phi = T^-1 sum_i wbar_i r_i x u_i`, T = sum_i wbar_i
/// (|r_i|^2 I - r_i r_i^T) the cloud's inertia tensor. Its transpose spreads a force F at
/// the reference as `f_i = wbar_i (F + (T^-1 ((x_ref - xbar) x F)) x r_i)`: the forces add up
/// to F and their moment about the reference point is zero (F's own moment about the cloud
/// is carried), Abaqus's force distribution with no moment at the reference node. Returns
/// per cloud node the 3x3 block B_i of `u_ref = sum_i B_i u_i`; `None` when T is singular
/// (a cloud on one line).
pub fn reference_motion(
    nodes: &[CloudNode],
    reference: [f64; 3],
) -> Option<Vec<(usize, [[f64; 3]; 3])>> {
    let mut centre = [0.0; 3];
    for c in nodes {
        for (sum, x) in centre.iter_mut().zip(c.position) {
            *sum += c.weight * x;
        }
    }
    let mut t = [[0.0; 3]; 3];
    let mut size = 0.0f64;
    for c in nodes {
        let r = sub(c.position, centre);
        size = size.max(norm(r));
        let rr = dot(r, r);
        for i in 0..3 {
            for j in 0..3 {
                t[i][j] += c.weight * (if i == j { rr } else { 0.0 } - r[i] * r[j]);
            }
        }
    }
    let t_inverse = invert(t, size * size)?;
    let offset = sub(reference, centre);
    // [a]x, the matrix of a x (.)
    let skew = |a: [f64; 3]| [[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]];
    // u_ref = sum wbar_i (I - [offset]x T^-1 [r_i]x) u_i  (phi x offset = -[offset]x phi)
    let so = skew(offset);
    let mut so_t = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            so_t[i][j] = (0..3).map(|k| so[i][k] * t_inverse[k][j]).sum();
        }
    }
    Some(
        nodes
            .iter()
            .map(|c| {
                let sr = skew(sub(c.position, centre));
                let mut b = [[0.0; 3]; 3];
                for i in 0..3 {
                    for j in 0..3 {
                        let moment: f64 = (0..3).map(|k| so_t[i][k] * sr[k][j]).sum();
                        b[i][j] = c.weight * (if i == j { 1.0 } else { 0.0 } - moment);
                    }
                }
                (c.node, b)
            })
            .collect(),
    )
}

/// The inverse of a symmetric 3x3 matrix, `None` when its determinant is negligible beside
/// `scale^3` (scale: the size of its entries).
fn invert(a: [[f64; 3]; 3], scale: f64) -> Option<[[f64; 3]; 3]> {
    let c = |i: usize, j: usize| {
        let (r0, r1) = ((i + 1) % 3, (i + 2) % 3);
        let (c0, c1) = ((j + 1) % 3, (j + 2) % 3);
        a[r0][c0] * a[r1][c1] - a[r0][c1] * a[r1][c0]
    };
    let det = a[0][0] * c(0, 0) + a[0][1] * c(0, 1) + a[0][2] * c(0, 2);
    if det.is_nan() || det.abs() <= 1e-12 * scale.powi(3) {
        return None;
    }
    Some([0, 1, 2].map(|i| [0, 1, 2].map(|j| c(j, i) / det)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::vector3::add;

    fn cloud() -> Vec<(usize, [f64; 3])> {
        // A lopsided patch of a plane z = 1, and a point above it.
        let mut c = Vec::new();
        for i in 0..5 {
            for j in 0..4 {
                let x = [0.1 * i as f64 + 0.03 * j as f64, 0.13 * j as f64, 1.0];
                c.push((c.len(), x));
            }
        }
        c
    }

    #[test]
    fn the_reference_follows_rigid_motions_and_a_force_keeps_its_moment() {
        let candidates = cloud();
        let reference = [0.35, 0.1, 1.4];
        for weighting in [Weighting::Uniform, Weighting::Cubic] {
            let nodes = weigh(&candidates, reference, Radius::Farthest, weighting).unwrap();
            let sum: f64 = nodes.iter().map(|c| c.weight).sum();
            assert!((sum - 1.0).abs() < 1e-14);
            let blocks = reference_motion(&nodes, reference).unwrap();
            let apply = |u: &dyn Fn([f64; 3]) -> [f64; 3]| {
                blocks.iter().fold([0.0; 3], |acc, (n, b)| {
                    let un = u(candidates[*n].1);
                    add(acc, [0, 1, 2].map(|i| dot(b[i], un)))
                })
            };
            // A rigid translation and a rigid rotation about any point move the reference
            // with them.
            let t = [1e-3, -2e-3, 5e-4];
            let moved = apply(&|_| t);
            assert!(norm(sub(moved, t)) < 1e-15, "{weighting:?}: {moved:?}");
            let (w, o) = ([0.3, -0.2, 0.7], [0.5, -1.0, 2.0]);
            let rotation = |x: [f64; 3]| cross(w, sub(x, o));
            let moved = apply(&rotation);
            assert!(
                norm(sub(moved, rotation(reference))) < 1e-14,
                "{weighting:?}: {moved:?} vs {:?}",
                rotation(reference)
            );
            // The transpose: a force at the reference spreads into forces adding up to it,
            // with no moment about the reference.
            let f = [2.0, -1.0, 3.0];
            let mut total = [0.0; 3];
            let mut moment = [0.0; 3];
            for (n, b) in &blocks {
                let fi = [0, 1, 2].map(|j| (0..3).map(|i| b[i][j] * f[i]).sum::<f64>());
                total = add(total, fi);
                moment = add(moment, cross(sub(candidates[*n].1, reference), fi));
            }
            assert!(norm(sub(total, f)) < 1e-14, "{total:?}");
            assert!(norm(moment) < 1e-14, "{moment:?}");
        }
    }

    #[test]
    fn the_default_radius_keeps_the_farthest_node_only_when_uniform() {
        let candidates = cloud();
        let reference = [0.0, 0.0, 1.0];
        let uniform = weigh(&candidates, reference, Radius::Farthest, Weighting::Uniform).unwrap();
        assert_eq!(uniform.len(), candidates.len());
        let linear = weigh(&candidates, reference, Radius::Farthest, Weighting::Linear).unwrap();
        assert_eq!(
            linear.len(),
            candidates.len() - 1,
            "the farthest, at r = R, weighs 0"
        );
        assert!(matches!(
            weigh(
                &candidates,
                reference,
                Radius::Within(1e-3),
                Weighting::Linear
            ),
            Err(CloudError::TooFew { found: 1, .. })
        ));
    }
}
