//! Nodal von Mises stress of a displacement field, for the static comparison of two models
//! of the same mesh (the paper's Figures 9-11): the stress of each element evaluated at its
//! own nodes, averaged over the elements sharing a node (the usual unweighted nodal
//! averaging of a post-processor; exact for a uniform stress state).

use super::assemble::element_materials;
use super::element::{lame, stress_at, von_mises, ElementError};
use super::tet10::NODE_COORDINATES;
use super::AssemblyError;
use crate::mesh::Mesh;

/// The von Mises stress at every mesh node (0 at nodes in no element). `u` holds at least
/// the mesh nodes' displacements.
pub fn nodal_von_mises(mesh: &Mesh, u: &[[f64; 3]]) -> Result<Vec<f64>, AssemblyError> {
    let materials = element_materials(mesh)?;
    let mut sum = vec![0.0; mesh.nodes.len()];
    let mut count = vec![0u32; mesh.nodes.len()];
    for (e, conn) in mesh.elements.iter().enumerate() {
        let m = materials[e];
        let (lambda, mu) = lame(m.young, m.poisson).map_err(|r| element_error(mesh, e, r))?;
        let x = conn.map(|n| mesh.nodes[n]);
        let ue = conn.map(|n| u[n]);
        for (k, &node) in conn.iter().enumerate() {
            let s = stress_at(&x, &ue, NODE_COORDINATES[k], lambda, mu)
                .map_err(|r| element_error(mesh, e, r))?;
            sum[node] += von_mises(s);
            count[node] += 1;
        }
    }
    Ok(sum
        .into_iter()
        .zip(count)
        .map(|(s, c)| if c > 0 { s / c as f64 } else { 0.0 })
        .collect())
}

fn element_error(mesh: &Mesh, e: usize, reason: ElementError) -> AssemblyError {
    let parts = mesh.element_parts();
    AssemblyError::Element {
        label: mesh.element_labels.get(e).copied().unwrap_or(e as i64 + 1),
        part: parts[e].map_or(String::new(), |p| mesh.parts[p].name.clone()),
        reason,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::block::block;
    use crate::mesh::Material;

    /// A linear displacement field is a uniform strain, reproduced exactly by quadratic
    /// elements (the patch test): every node carries the analytic von Mises stress.
    #[test]
    fn uniform_strain_gives_the_analytic_von_mises_stress_everywhere() {
        let (young, poisson) = (2e11, 0.3);
        let steel = Material {
            name: "s".into(),
            young,
            poisson,
            density: 7800.0,
        };
        let mesh = block([0.0; 3], [0.3, 0.2, 0.1], [3, 2, 2], steel).unwrap();
        // eps_xx = 1e-4, eps_yy = -2e-5, gamma_xy = 6e-5 (eps_xy = 3e-5).
        let u: Vec<[f64; 3]> = mesh
            .nodes
            .iter()
            .map(|x| [1e-4 * x[0] + 3e-5 * x[1], -2e-5 * x[1] + 3e-5 * x[0], 0.0])
            .collect();
        let (lambda, mu) = lame(young, poisson).unwrap();
        let tr = 1e-4 - 2e-5;
        let s = [
            lambda * tr + 2.0 * mu * 1e-4,
            lambda * tr - 2.0 * mu * 2e-5,
            lambda * tr,
            0.0,
            0.0,
            2.0 * mu * 3e-5,
        ];
        let expected = von_mises(s);
        // Hand check of the formula: sqrt(((sx-sy)^2 + (sy-sz)^2 + (sz-sx)^2)/2 + 3 txy^2).
        let by_hand = ((s[0] - s[1]).powi(2) + (s[1] - s[2]).powi(2) + (s[2] - s[0]).powi(2)) / 2.0
            + 3.0 * s[5] * s[5];
        assert!((expected - by_hand.sqrt()).abs() <= 1e-12 * expected);
        let vm = nodal_von_mises(&mesh, &u).unwrap();
        for (n, v) in vm.iter().enumerate() {
            assert!(
                (v - expected).abs() <= 1e-9 * expected,
                "node {n}: {v} vs {expected}"
            );
        }
    }
}
