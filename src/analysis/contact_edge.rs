//! The edge of a contact zone as a perturbation: the displacement a tangent is taken at, with
//! the r closed points of the swept pairs that carry the least force opened, or the r open
//! ones nearest to touching closed, and nothing else changed.
//!
//! Why. A penalty contact's tangent holds k_n a on a closed point whatever its force and
//! nothing on an open one, so the points at the edge of a disc/pad zone, with a newton of
//! force or a few nanometres of gap, hold the pads as the middle does. A mode, or an
//! instability, that moves when a handful of them change state is decided by how the mesh
//! resolves the edge, not by the brake: measured on small-caliper without friction, one point
//! 4.3 nm from touching moves the 2342.4 Hz mode by +1.22 %; on tiny-caliper at mu 0.3 the
//! 3057.5 Hz instability is stable once four such points close (issue 29). Comparing the
//! modes at these displacements with the modes at the equilibrium says which results stand
//! on the edge.
//!
//! How. A point changes state by moving its slave node along the contact normal until its
//! gap changes sign (to 1e-12 of the gap, so that its force is nil), in the displacement the
//! tangent is taken at only: the penalty is linear in the gap, so every other point keeps its
//! state and its stiffness, and the change of the tangent is the r points' own k_n a c c^T
//! (rank one each; `examples/contact_edge` checks the interlacing this implies). Only points
//! of one slave node without a patch law are candidates (a full model's node-to-surface
//! points): a reduced contact's patch law closes part of its share at a time.

use crate::contact::{ContactPair, PointState};

/// Which way the edge moves.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum EdgeMove {
    /// The closed points of least normal force open.
    Open,
    /// The open points of least gap close.
    Close,
}

/// The displacement `u` with up to `r` points of the swept pairs (`swept[i]`) moved across
/// the edge, the states being `states[i][j]` at `u`, and how many moved (fewer than `r` when
/// fewer are candidates).
pub fn moved_edge(
    pairs: &[ContactPair],
    swept: &[bool],
    states: &[Vec<PointState>],
    u: &[[f64; 3]],
    r: usize,
    direction: EdgeMove,
) -> (Vec<[f64; 3]>, usize) {
    // (sort key, slave node, normal, gap) of every candidate.
    let mut candidates: Vec<(f64, usize, [f64; 3], f64)> = Vec::new();
    for ((pair, states), _) in pairs
        .iter()
        .zip(states)
        .zip(swept)
        .filter(|&(_, &swept)| swept)
    {
        for (point, state) in pair.points.iter().zip(states) {
            if point.tilt.is_some() || point.slave.len() != 1 {
                continue;
            }
            let key = match (direction, state.closed) {
                (EdgeMove::Open, true) => state.normal_force,
                (EdgeMove::Close, false) => state.gap,
                _ => continue,
            };
            candidates.push((key, point.slave_node, point.normal, state.gap));
        }
    }
    // Ties broken by node number, so that every rank and every run moves the same points.
    candidates.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    let sign = match direction {
        EdgeMove::Open => 1.0,
        EdgeMove::Close => -1.0,
    };
    let mut moved = u.to_vec();
    let count = candidates.len().min(r);
    for &(_, node, normal, gap) in &candidates[..count] {
        let target = sign * 1e-12 * gap.abs().max(f64::MIN_POSITIVE);
        for (x, n) in moved[node].iter_mut().zip(normal) {
            *x += (target - gap) * n;
        }
    }
    (moved, count)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::{node_to_node, point_state, ContactPoint, PairSettings, SlidingDirection};

    /// Six point contacts along z, slave node k over master node 6 + k, their gaps at rest
    /// `gaps`; point 5 has two slave nodes (not a candidate).
    fn pair(gaps: [f64; 6]) -> ContactPair {
        let settings = PairSettings {
            name: "disc/pad".into(),
            friction: 0.0,
            penalty: None,
            separation: true,
            sliding: SlidingDirection::Fixed([1.0, 0.0, 0.0]),
            law: crate::contact::FrictionLaw::SteadySliding,
            calculix: None,
        };
        let points = gaps
            .iter()
            .enumerate()
            .map(|(k, &g)| ContactPoint {
                slave: if k == 5 {
                    vec![(5, 0.5), (12, 0.5)]
                } else {
                    vec![(k, 1.0)]
                },
                master: vec![(6 + k, 1.0)],
                normal: [0.0, 0.0, 1.0],
                initial_gap: g,
                area: 1e-4,
                tangent: Some([1.0, 0.0, 0.0]),
                position: [k as f64, 0.0, 0.0],
                slave_node: k,
                master_face: None,
                tilt: None,
            })
            .collect();
        node_to_node(settings, 1e12, points).unwrap()
    }

    fn states(p: &ContactPair, u: &[[f64; 3]]) -> Vec<PointState> {
        p.points
            .iter()
            .map(|q| point_state(p, q, [0.0; 3], u).unwrap())
            .collect()
    }

    #[test]
    fn the_weakest_closed_points_open_and_the_nearest_open_ones_close_alone() {
        // Penetrations 3e-8, 1e-8, 2e-8 (forces 3, 1, 2 N), gaps 5e-9 and 2e-9, and a
        // closed two-node point.
        let p = pair([-3e-8, -1e-8, -2e-8, 5e-9, 2e-9, -1e-9]);
        let u = vec![[0.0; 3]; 13];
        let before = states(&p, &u);
        let closed: Vec<bool> = before.iter().map(|s| s.closed).collect();
        assert_eq!(closed, [true, true, true, false, false, true]);
        let pairs = [p.clone()];
        let all = [before.clone()];
        let (opened, count) = moved_edge(&pairs, &[true], &all, &u, 2, EdgeMove::Open);
        assert_eq!(count, 2);
        let after = states(&p, &opened);
        // Points 1 and 2 (1 and 2 N) open; 0 keeps its force; the two-node point is no
        // candidate however weak.
        let closed: Vec<bool> = after.iter().map(|s| s.closed).collect();
        assert_eq!(closed, [true, false, false, false, false, true]);
        assert_eq!(after[0], before[0]);
        assert_eq!(after[5], before[5]);
        for k in [1, 2] {
            assert!(
                after[k].gap > 0.0 && after[k].gap <= 1e-12 * 3e-8,
                "{:?}",
                after[k]
            );
        }
        let (shut, count) = moved_edge(&pairs, &[true], &all, &u, 1, EdgeMove::Close);
        assert_eq!(count, 1);
        let after = states(&p, &shut);
        let closed: Vec<bool> = after.iter().map(|s| s.closed).collect();
        assert_eq!(closed, [true, true, true, false, true, true]);
        // Closed at a nil force: its stiffness, none of the load (k A times the 1e-12 of the
        // gap it is moved to, and the round-off of moving it, a few ulps of 2e-9).
        let nil = 1e12 * 1e-4 * (1e-12 + 1e-15) * 2e-9;
        assert!(after[4].normal_force.abs() <= nil, "{:?}", after[4]);
        assert_eq!(after[3], before[3]);
        // More asked than there are: every candidate, and a pair that is not swept none.
        let (_, count) = moved_edge(&pairs, &[true], &all, &u, 10, EdgeMove::Close);
        assert_eq!(count, 2);
        let (same, count) = moved_edge(&pairs, &[false], &all, &u, 10, EdgeMove::Open);
        assert_eq!((count, same), (0, u));
    }
}
