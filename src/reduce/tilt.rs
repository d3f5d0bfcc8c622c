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
}
