//! A sample of the mesh's corner nodes with the mass each stands for, so that two mode
//! shapes can be compared over the whole model at a bounded size (issue 36).
//!
//! Tracking links the modes of neighbouring friction values by the similarity of their
//! shapes. Compared on the disc/pad faces alone, two modes that differ in the caliper or the
//! bracket look alike wherever those parts barely touch the faces; the kinetic-energy inner
//! product a^H M b sees every part in proportion to its mass. Holding whole shapes for every
//! point of a sweep is too much memory on a large model (200,000 DOFs x 60 modes x 16 bytes
//! is 190 MB a point), so the product is taken over a sample:
//!
//! - the mass is lumped on the corner nodes: each element's rho V split in four (the
//!   straight-sided volume), which is the linear interpolant's lumped mass, positive
//!   everywhere (a TET10's consistent row sums are negative at its corners);
//! - each part (body) keeps a share of [`SAMPLE_NODES`] in proportion to its corner count,
//!   at least [`MIN_PER_BODY`], evenly spaced through its corners in index order;
//! - each kept node's weight is its lumped mass scaled so that the part's sampled weights add
//!   up to the part's mass: a sparse sample of a small part does not make it weigh less.
//!
//! sum_n w_n conj(a_n) . b_n over the sample is then a quadrature of a^H M b at the sample's
//! resolution: every body counted by its mass, which is what matters to tell two modes
//! apart; the fine detail a stride skips is where the disc/pad faces' own sample serves.

use super::assemble::{element_materials, AssemblyError};
use crate::mesh::Mesh;

/// How many nodes a sample holds at most (besides the per-body minimum): 3 x 3,000 DOFs of
/// 60 modes is 4.3 MB a point.
pub const SAMPLE_NODES: usize = 3_000;
/// Each body is seen by at least this many nodes (or all its corners when it has fewer).
pub const MIN_PER_BODY: usize = 64;

/// Nodes and their weights (kg), sorted by node.
#[derive(Clone, Debug, PartialEq)]
pub struct MassSample {
    pub nodes: Vec<usize>,
    pub weights: Vec<f64>,
}

/// The sample of `mesh` with at most about `budget` nodes ([`SAMPLE_NODES`] in use).
pub fn mass_sample(mesh: &Mesh, budget: usize) -> Result<MassSample, AssemblyError> {
    let materials = element_materials(mesh)?;
    let mut lumped = vec![0.0; mesh.nodes.len()];
    // The body of each corner node: the first part whose element holds it.
    let mut body = vec![usize::MAX; mesh.nodes.len()];
    let mut body_mass = vec![0.0; mesh.parts.len()];
    for (b, part) in mesh.parts.iter().enumerate() {
        for &e in &part.elements {
            let mass = materials[e].density * mesh.corner_volume(e).abs();
            body_mass[b] += mass;
            for &n in &mesh.elements[e][..4] {
                lumped[n] += mass / 4.0;
                if body[n] == usize::MAX {
                    body[n] = b;
                }
            }
        }
    }
    let mut corners: Vec<Vec<usize>> = vec![Vec::new(); mesh.parts.len()];
    for (n, &b) in body.iter().enumerate() {
        if b != usize::MAX {
            corners[b].push(n);
        }
    }
    let total: usize = corners.iter().map(Vec::len).sum();
    let mut sample: Vec<(usize, f64)> = Vec::new();
    for (b, nodes) in corners.iter().enumerate() {
        if nodes.is_empty() {
            continue;
        }
        let share = (budget as f64 * nodes.len() as f64 / total as f64).round() as usize;
        let quota = share.max(MIN_PER_BODY).min(nodes.len());
        // Evenly through the corners in index order: exactly `quota` of them.
        let kept: Vec<usize> = (0..quota).map(|k| nodes[k * nodes.len() / quota]).collect();
        let sampled: f64 = kept.iter().map(|&n| lumped[n]).sum();
        let scale = if sampled > 0.0 {
            body_mass[b] / sampled
        } else {
            0.0
        };
        sample.extend(kept.into_iter().map(|n| (n, lumped[n] * scale)));
    }
    sample.sort_unstable_by_key(|&(n, _)| n);
    Ok(MassSample {
        nodes: sample.iter().map(|s| s.0).collect(),
        weights: sample.iter().map(|s| s.1).collect(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::block::block;
    use crate::mesh::{Material, Part};
    use std::collections::BTreeSet;

    fn material(name: &str, density: f64) -> Material {
        Material {
            name: name.into(),
            young: 1.0,
            poisson: 0.3,
            density,
        }
    }

    /// A 2 x 1 x 1 block split at x = 1 into two bodies of volume 1, of densities 7,800 and
    /// 2,500: each body's sampled weights add up to its rho V (straight-sided elements, so
    /// the corner volumes are the volumes), however sparse its sample.
    #[test]
    fn each_body_weighs_its_mass_and_the_budget_bounds_the_sample() {
        let mut mesh = block(
            [0.0; 3],
            [2.0, 1.0, 1.0],
            [8, 4, 4],
            material("steel", 7_800.0),
        )
        .unwrap();
        let centre_x = |e: usize| {
            mesh.elements[e][..4]
                .iter()
                .map(|&n| mesh.nodes[n][0])
                .sum::<f64>()
                / 4.0
        };
        let (left, right): (Vec<usize>, Vec<usize>) =
            (0..mesh.elements.len()).partition(|&e| centre_x(e) < 1.0);
        mesh.parts = vec![
            Part {
                name: "left".into(),
                elements: left,
                material: Some("steel".into()),
            },
            Part {
                name: "right".into(),
                elements: right,
                material: Some("light".into()),
            },
        ];
        mesh.materials
            .insert("light".into(), material("light", 2_500.0));
        let corners = (9 * 5 * 5) as usize;
        for budget in [10, 100, 100_000] {
            let s = mass_sample(&mesh, budget).unwrap();
            assert!(s.nodes.windows(2).all(|w| w[0] < w[1]), "sorted, unique");
            assert!(s.weights.iter().all(|&w| w > 0.0));
            let mut seen = BTreeSet::new();
            for (part, mass) in mesh.parts.iter().zip([7_800.0, 2_500.0]) {
                // The part's corner nodes not already counted by the part before it.
                let held: BTreeSet<usize> = part
                    .elements
                    .iter()
                    .flat_map(|&e| mesh.elements[e][..4].to_vec())
                    .filter(|n| !seen.contains(n))
                    .collect();
                seen.extend(held.iter().copied());
                let (count, weight) = s
                    .nodes
                    .iter()
                    .zip(&s.weights)
                    .filter(|(n, _)| held.contains(n))
                    .fold((0, 0.0), |(c, w), (_, x)| (c + 1, w + x));
                assert!(
                    (weight - mass).abs() <= 1e-12 * mass,
                    "{budget}: {weight} {mass}"
                );
                assert!(count >= MIN_PER_BODY.min(held.len()), "{budget}: {count}");
                if budget >= corners {
                    assert_eq!(count, held.len(), "every corner when the budget allows");
                }
            }
            assert_eq!(seen.len(), corners);
            assert!(
                s.nodes.len() <= budget.max(2 * MIN_PER_BODY) + 2,
                "{budget}: {}",
                s.nodes.len()
            );
        }
    }
}
