//! Where a mode's kinetic energy is: x^H M_b x for each body b of the model (the mesh's parts,
//! and the point masses together), with M_b the consistent mass of that body alone. The M_b
//! add up to the model's M, so the shares x^H M_b x / x^H M x sum to 1 (issue 33: which part
//! moves in an unstable mode).
//!
//! Computed on one process from the shape on every mesh node: per element, with the scalar
//! mass m_ab = rho int N_a N_b dV, x_e^H M_e x_e = sum_ab m_ab (Re x_a . Re x_b + Im x_a . Im x_b)
//! (M_e is m on each displacement component, real and symmetric). About 100 dot products per
//! element and mode, far below a CEA's cost.

use super::assemble::{element_materials, AssemblyError};
use super::element::{self, MassRule};
use super::point_mass::PointMass;
use crate::mesh::Mesh;
use std::collections::BTreeMap;

/// What the point masses are called among the bodies.
pub const POINT_MASSES: &str = "point masses";

/// x^H M_b x per body: each part of `mesh` by name, and [`POINT_MASSES`] when there are
/// any. `re` and `im` hold the shape's displacement at every mesh node (and at any further
/// node a point mass sits on); shorter is an error, not a panic.
pub fn body_kinetic_energies(
    mesh: &Mesh,
    point_masses: &[PointMass],
    rule: MassRule,
    re: &[[f64; 3]],
    im: &[[f64; 3]],
) -> Result<BTreeMap<String, f64>, AssemblyError> {
    let materials = element_materials(mesh)?;
    let needed = mesh
        .elements
        .iter()
        .flatten()
        .copied()
        .chain(point_masses.iter().map(|p| p.node))
        .max();
    if let Some(node) = needed.filter(|&n| n >= re.len().min(im.len())) {
        return Err(AssemblyError::FieldTooShort {
            given: re.len().min(im.len()),
            node,
        });
    }
    let dot = |a: &[f64; 3], b: &[f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let mut energies = BTreeMap::new();
    for part in &mesh.parts {
        let mut sum = 0.0;
        for &e in &part.elements {
            let conn = &mesh.elements[e];
            let x = conn.map(|n| mesh.nodes[n]);
            let m = element::scalar_mass(&x, materials[e].density, rule).map_err(|reason| {
                AssemblyError::Element {
                    label: mesh.element_labels.get(e).copied().unwrap_or(e as i64 + 1),
                    part: part.name.clone(),
                    reason,
                }
            })?;
            for a in 0..10 {
                let (ra, ia) = (&re[conn[a]], &im[conn[a]]);
                for b in 0..10 {
                    let (rb, ib) = (&re[conn[b]], &im[conn[b]]);
                    sum += m[a][b] * (dot(ra, rb) + dot(ia, ib));
                }
            }
        }
        *energies.entry(part.name.clone()).or_insert(0.0) += sum;
    }
    if !point_masses.is_empty() {
        let sum = point_masses
            .iter()
            .map(|p| p.mass * (dot(&re[p.node], &re[p.node]) + dot(&im[p.node], &im[p.node])))
            .sum();
        energies.insert(POINT_MASSES.to_string(), sum);
    }
    Ok(energies)
}

/// The energies as shares of their sum (summing to 1); empty when the sum is 0.
pub fn shares(energies: &BTreeMap<String, f64>) -> BTreeMap<String, f64> {
    let total: f64 = energies.values().sum();
    if total <= 0.0 {
        return BTreeMap::new();
    }
    energies
        .iter()
        .map(|(name, e)| (name.clone(), e / total))
        .collect()
}

/// The shares of a mode's shape, as a result reports them: `None`, said in the log, when
/// they cannot be had (the assembly checked the materials, so only an element that turned
/// bad since); a missing share never fails the analysis it describes.
pub fn mode_shares(
    mesh: &Mesh,
    point_masses: &[PointMass],
    rule: MassRule,
    re: &[[f64; 3]],
    im: &[[f64; 3]],
) -> Option<BTreeMap<String, f64>> {
    match body_kinetic_energies(mesh, point_masses, rule, re, im) {
        Ok(energies) => Some(shares(&energies)),
        Err(e) => {
            tracing::warn!("no body shares of a mode: {e}");
            None
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A rigid translation's energy in each body is that body's mass (|x|^2 = 1 at every
    /// node, and sum_ab m_ab = rho int (sum_a N_a)^2 dV = rho V): rho times the elements'
    /// volumes, curved ones included (the exact rule integrates det J, a cubic, exactly), and
    /// a point mass its m.
    #[test]
    fn a_rigid_translation_puts_each_body_s_mass_in_it() {
        // The floating-caliper brake: five bodies of three materials.
        let params = crate::mesh::brake::preset("tiny-caliper").unwrap();
        let mesh = crate::mesh::brake::build(&params).unwrap();
        let n = mesh.nodes.len();
        let (re, im) = (vec![[0.6, 0.0, 0.8]; n], vec![[0.0; 3]; n]);
        let masses = [PointMass {
            node: 3,
            mass: 0.25,
        }];
        {
            let e = body_kinetic_energies(&mesh, &masses, MassRule::Exact, &re, &im).unwrap();
            assert_eq!(e.len(), mesh.parts.len() + 1);
            for part in &mesh.parts {
                let rho = mesh.materials[part.material.as_ref().unwrap()].density;
                let volume: f64 = part
                    .elements
                    .iter()
                    .map(|&k| element::volume(&mesh.elements[k].map(|n| mesh.nodes[n])).unwrap())
                    .sum();
                let got = e[&part.name];
                assert!(
                    (got - rho * volume).abs() <= 1e-12 * rho * volume,
                    "{}: {got} against {}",
                    part.name,
                    rho * volume
                );
            }
            assert!((e[POINT_MASSES] - 0.25).abs() <= 1e-15);
            let s = shares(&e);
            assert!((s.values().sum::<f64>() - 1.0).abs() <= 1e-12);
        }
        // The same motion as the imaginary part: the same energies.
        let e = body_kinetic_energies(&mesh, &[], MassRule::Exact, &im, &re).unwrap();
        let f = body_kinetic_energies(&mesh, &[], MassRule::Exact, &re, &im).unwrap();
        assert_eq!(e, f);
        assert!(shares(&BTreeMap::from([("a".to_string(), 0.0)])).is_empty());
        // A shape on fewer nodes than a point mass sits on is refused, not read out of range.
        let far = [PointMass { node: n, mass: 1.0 }];
        let e = body_kinetic_energies(&mesh, &far, MassRule::Exact, &re, &im).unwrap_err();
        assert!(
            matches!(e, AssemblyError::FieldTooShort { node, .. } if node == n),
            "{e}"
        );
    }
}
