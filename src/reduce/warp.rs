//! Warping springs of a share: the full model's penalty against the pad face's warping
//! within a reduced contact node's share, which a patch law cannot see (issue 29).
//!
//! Why. Over a closed share the full model holds every pad face node j by its own penalty
//! spring k_n a_j against the disc. Write the pad face's normal displacement over the share
//! as its plane P (the share's mean and slope, which the reduced node c and its tilt node r_p
//! hold through their ties) plus the rest r, the warping: r_j = w_j - P(x_j). With the
//! share's fit weighted by the tributary areas a_j (share couplings are), r is a-orthogonal
//! to every linear field, so where the disc surface under the share moves as a plane D the
//! full model's energy splits exactly:
//!
//! ```text
//!   sum_j k_n a_j (P - D + r)_j^2 / 2 = sum_j k_n a_j (P - D)_j^2 / 2 + sum_j k_n a_j r_j^2 / 2
//! ```
//!
//! The first sum is the patch law's (the share's gap and tilt). The second is these springs:
//! one per face node, (k_n a_j / 2) r_j^2 with r_j = n . (u_j - u_c) - sum_a xi_ja theta_pa,
//! xi_j the node's in-plane offset from the share's weighted centre and theta_pa =
//! e_a . u_rp / arm the share's slope read from its tilt node. They touch the pad side only
//! (its face nodes, c and r_p), and vanish on any planar motion of the share, rigid or not:
//! they add nothing to the mean or the slope, only the stiffness against the face warping
//! inside a share that the full model's springs have and a distributing coupling lets go.
//!
//! Measured before they existed (session 24): small-caliper's 2272.9 Hz inboard-pad mode
//! came out 2.7-2.9 % low with every interface, and the reduced model's mode put 1.5e8 of
//! contact energy in the full model's springs against 1.3e7 in its own: the pad face warped
//! inside its shares where the full model's penalty holds every closed node.
//!
//! They are linear and always on: a super-element's interior stays linear elastic (issue
//! 32). Where a share is open the full model's face is free and these springs hold it flat
//! within the share; a mode's face is nearly flat over a share of a pad's open edge, so what
//! that costs is measured (README, issue 29's note), not assumed.

use super::coupling::DistributingCoupling;
use crate::contact::{ContactPoint, Tilt};
use crate::fem::springs::ScalarSpring;
use crate::vector3::{add, dot, scale, sub};

/// The warping springs of one share: its coupling's face nodes (weights adding up to 1,
/// by tributary area), the reduced contact node `contact_node` (c) tied to their weighted
/// mean, the patch law `tilt` whose pad-side tilt node reads the share's slope, the contact
/// normal `n`, the share's area and the pair's penalty per unit area. One spring per face
/// node, of stiffness k_n times the node's part of the share's area.
pub fn warp_springs(
    coupling: &DistributingCoupling,
    positions: &[[f64; 3]],
    contact_node: usize,
    tilt: &Tilt,
    n: [f64; 3],
    area: f64,
    penalty: f64,
) -> Vec<ScalarSpring> {
    let total: f64 = coupling.nodes.iter().map(|c| c.weight).sum();
    if total.is_nan() || total <= 0.0 {
        return Vec::new();
    }
    let centre = coupling.nodes.iter().fold([0.0; 3], |x, c| {
        add(x, scale(c.weight / total, positions[c.node]))
    });
    let [e0, e1] = tilt.axes;
    coupling
        .nodes
        .iter()
        .map(|c| {
            let d = sub(positions[c.node], centre);
            let xi = [dot(d, e0), dot(d, e1)];
            // sum_a xi_a e_a . u_rp / arm, along the pad-side tilt node's components.
            let slope = add(scale(xi[0] / tilt.arm, e0), scale(xi[1] / tilt.arm, e1));
            ScalarSpring {
                terms: vec![
                    (c.node, n),
                    (contact_node, scale(-1.0, n)),
                    (tilt.nodes[0], scale(-1.0, slope)),
                ],
                stiffness: penalty * area * c.weight / total,
            }
        })
        .collect()
}

/// The warping springs of a pad face's every share that carries a patch law: `points` the
/// reduced contacts (each with its share's `couplings` entry and its contact node), in the
/// grid's order.
pub fn pad_springs(
    points: &[ContactPoint],
    couplings: &[DistributingCoupling],
    contact_nodes: &[usize],
    positions: &[[f64; 3]],
    penalty: f64,
) -> Vec<ScalarSpring> {
    points
        .iter()
        .zip(couplings)
        .zip(contact_nodes)
        .filter_map(|((point, coupling), &c)| {
            let tilt = point.tilt.as_ref()?;
            Some(warp_springs(
                coupling,
                positions,
                c,
                tilt,
                point.normal,
                point.area,
                penalty,
            ))
        })
        .flatten()
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reduce::coupling::CouplingNode;
    use crate::reduce::{tilt, Weighting};

    /// A share of nine face nodes (0..9) on the plane z = 0.01 with uneven areas, its
    /// contact node 9 and tilt nodes 10 (pad), 11 (disc); normal +z.
    fn share() -> (DistributingCoupling, Vec<[f64; 3]>, Tilt, Vec<f64>) {
        let mut positions = Vec::new();
        let mut areas = Vec::new();
        for j in 0..9 {
            let (a, b) = ((j % 3) as f64, (j / 3) as f64);
            positions.push([0.003 * a + 0.0007 * b, 0.0025 * b - 0.0004 * a * a, 0.01]);
            areas.push(1e-6 * (1.0 + 0.3 * a + 0.1 * b * b));
        }
        let total: f64 = areas.iter().sum();
        let nodes = (0..9)
            .map(|j| CouplingNode {
                node: j,
                position: positions[j],
                distance: 0.0,
                weight: areas[j] / total,
            })
            .collect();
        positions.extend([[0.003, 0.0025, 0.01]; 3]);
        let coupling = DistributingCoupling {
            reduced_node: 0,
            reference: positions[9],
            radius: 0.005,
            weighting: Weighting::Uniform,
            nodes,
        };
        let tilt = Tilt {
            nodes: [10, 11],
            axes: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            patch: Vec::new(),
            arm: 0.002,
            penalty: 3e12,
            bilateral: false,
        };
        (coupling, positions, tilt, areas)
    }

    fn energy(springs: &[ScalarSpring], u: &[[f64; 3]]) -> f64 {
        springs
            .iter()
            .map(|s| {
                let r: f64 = s.terms.iter().map(|&(j, g)| dot(g, u[j])).sum();
                0.5 * s.stiffness * r * r
            })
            .sum()
    }

    /// The face's normal displacements `w` with c and r_p where their ties put them: c the
    /// weighted mean, r_p arm times the least-squares slope (`tilt::slope_terms`).
    fn field(
        coupling: &DistributingCoupling,
        positions: &[[f64; 3]],
        tilt: &Tilt,
        w: &[f64],
    ) -> Vec<[f64; 3]> {
        let n = [0.0, 0.0, 1.0];
        let mut u: Vec<[f64; 3]> = w.iter().map(|&w| [1e-7, -2e-7, w]).collect();
        let mean: f64 = coupling.nodes.iter().map(|c| c.weight * w[c.node]).sum();
        u.push([1e-7, -2e-7, mean]);
        let patch = tilt::patch(coupling, positions);
        let slopes = tilt::slope_terms(&patch, tilt.axes, n).unwrap();
        let slope = slopes.map(|terms| terms.iter().map(|&(j, g)| dot(g, u[j])).sum::<f64>());
        u.push(add(
            scale(tilt.arm * slope[0], tilt.axes[0]),
            scale(tilt.arm * slope[1], tilt.axes[1]),
        ));
        u.push([0.0; 3]);
        u
    }

    #[test]
    fn a_planar_share_stores_nothing_and_a_warped_one_what_the_full_penalty_adds_to_the_patch() {
        let (coupling, positions, tilt, areas) = share();
        let area: f64 = areas.iter().sum();
        let n = [0.0, 0.0, 1.0];
        let springs = warp_springs(&coupling, &positions, 9, &tilt, n, area, tilt.penalty);
        assert_eq!(springs.len(), 9);
        let k: f64 = springs.iter().map(|s| s.stiffness).sum();
        assert!((k - tilt.penalty * area).abs() <= 1e-12 * k, "{k}");
        // Any plane, whatever its tilt: no warping.
        let plane: Vec<f64> = positions[..9]
            .iter()
            .map(|x| 2e-6 + 3e-4 * x[0] - 7e-4 * x[1])
            .collect();
        let u = field(&coupling, &positions, &tilt, &plane);
        let scale_energy = 0.5 * tilt.penalty * area * 1e-12;
        assert!(
            energy(&springs, &u) <= 1e-20 * scale_energy,
            "{}",
            energy(&springs, &u)
        );
        // A warped field: the full model's penalty energy over the share (every node closed,
        // the disc at rest) is the patch law's (mean and slope, about the weighted centre)
        // plus the springs', exactly.
        let warped: Vec<f64> = positions[..9]
            .iter()
            .enumerate()
            .map(|(j, x)| 2e-6 + 3e-4 * x[0] + 1e-6 * ((j * j) as f64).sin() + 0.02 * x[1] * x[1])
            .collect();
        let u = field(&coupling, &positions, &tilt, &warped);
        let full: f64 = (0..9)
            .map(|j| 0.5 * tilt.penalty * areas[j] * warped[j] * warped[j])
            .sum();
        let centre = [0, 1].map(|a| (0..9).map(|j| areas[j] * positions[j][a]).sum::<f64>() / area);
        let slope = [0, 1].map(|a| u[10][a] / tilt.arm);
        let mean = u[9][2];
        let patch: f64 = (0..9)
            .map(|j| {
                let g = mean
                    + slope[0] * (positions[j][0] - centre[0])
                    + slope[1] * (positions[j][1] - centre[1]);
                0.5 * tilt.penalty * areas[j] * g * g
            })
            .sum();
        let warp = energy(&springs, &u);
        assert!(warp > 1e-3 * full, "{warp} of {full}");
        assert!(
            (patch + warp - full).abs() <= 1e-12 * full,
            "{patch} + {warp} against {full}"
        );
    }
}
