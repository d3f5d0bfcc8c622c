//! Each body's stiffness as the derivative of the model's K with respect to the logarithm of
//! that body's Young's modulus: isotropic linear elasticity at fixed Poisson's ratio is
//! linear in E, so dK / d(ln E_b) = E_b dK/dE_b = K_b, the stiffness of body b's elements
//! alone (issue 33: which part to stiffen or soften). A body is a part of the mesh.
//!
//! Computed element by element on the node arrays (no matrix is assembled): y^H K_b x for
//! modes (y, x), and the nodal forces K_b u of a displacement. One element matrix serves
//! every mode.

use super::assemble::{element_materials, AssemblyError};
use super::element;
use crate::analysis::growth::Shape;
use crate::mesh::Mesh;
use num_complex::Complex64;
use std::collections::BTreeMap;

fn element_error(
    mesh: &Mesh,
    e: usize,
    part: &str,
    reason: element::ElementError,
) -> AssemblyError {
    AssemblyError::Element {
        label: mesh.element_labels.get(e).copied().unwrap_or(e as i64 + 1),
        part: part.to_string(),
        reason,
    }
}

/// The largest node a field must reach: every element's.
fn check_length(mesh: &Mesh, len: usize) -> Result<(), AssemblyError> {
    match mesh.elements.iter().flatten().copied().max() {
        Some(node) if node >= len => Err(AssemblyError::FieldTooShort { given: len, node }),
        _ => Ok(()),
    }
}

/// y^H K_b x per body (each part of `mesh`, by name), for each pair (y, x) of `modes`; the
/// shapes hold every mesh node (shorter is an error, not a panic).
pub fn body_stiffness_forms(
    mesh: &Mesh,
    modes: &[(Shape<'_>, Shape<'_>)],
) -> Result<Vec<BTreeMap<String, Complex64>>, AssemblyError> {
    for (y, x) in modes {
        for s in [y, x] {
            check_length(mesh, s.re.len().min(s.im.len()))?;
        }
    }
    let mut out = vec![BTreeMap::new(); modes.len()];
    let at = |s: &Shape<'_>, n: usize, c: usize| Complex64::new(s.re[n][c], s.im[n][c]);
    each_element(mesh, |part, conn, k| {
        for ((ys, xs), map) in modes.iter().zip(&mut out) {
            let xe: Vec<Complex64> = (0..30).map(|i| at(xs, conn[i / 3], i % 3)).collect();
            let mut sum = Complex64::new(0.0, 0.0);
            for (i, row) in k.iter().enumerate() {
                let yi = at(ys, conn[i / 3], i % 3).conj();
                sum += yi
                    * row
                        .iter()
                        .zip(&xe)
                        .map(|(kij, xj)| kij * xj)
                        .sum::<Complex64>();
            }
            *map.entry(part.to_string())
                .or_insert(Complex64::new(0.0, 0.0)) += sum;
        }
    })?;
    Ok(out)
}

/// Calls `f` with each element's part name, nodes and stiffness matrix, part by part.
fn each_element(
    mesh: &Mesh,
    mut f: impl FnMut(&str, &[usize; 10], &element::ElementMatrix),
) -> Result<(), AssemblyError> {
    let materials = element_materials(mesh)?;
    for part in &mesh.parts {
        for &e in &part.elements {
            let conn = &mesh.elements[e];
            let m = materials[e];
            let k = element::stiffness(&conn.map(|n| mesh.nodes[n]), m.young, m.poisson)
                .map_err(|reason| element_error(mesh, e, &part.name, reason))?;
            f(&part.name, conn, &k);
        }
    }
    Ok(())
}

/// The nodal forces K_b u of each body (each part of `mesh`, by name) at the displacement
/// `u` (every mesh node).
pub fn body_forces(
    mesh: &Mesh,
    u: &[[f64; 3]],
) -> Result<BTreeMap<String, Vec<[f64; 3]>>, AssemblyError> {
    check_length(mesh, u.len())?;
    let mut out: BTreeMap<String, Vec<[f64; 3]>> = mesh
        .parts
        .iter()
        .map(|p| (p.name.clone(), vec![[0.0; 3]; u.len()]))
        .collect();
    each_element(mesh, |part, conn, k| {
        let forces = out.get_mut(part).expect("every part has its forces");
        for (i, row) in k.iter().enumerate() {
            let f: f64 = row
                .iter()
                .enumerate()
                .map(|(j, kij)| kij * u[conn[j / 3]][j % 3])
                .sum();
            forces[conn[i / 3]][i % 3] += f;
        }
    })?;
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::test_models::pad_on_disc;

    /// Two bodies whose stiffnesses add up to K: the forms and forces, summed over the
    /// bodies, are the assembled K's (a brute-force check on a small box); and a rigid
    /// translation has no force in any body.
    #[test]
    fn the_bodies_stiffnesses_add_up_to_the_models() {
        // Two blocks (E 210 GPa and 1 GPa), one part each.
        let mesh = pad_on_disc(0.0);
        let nodes = mesh.nodes.len();
        let wave = |k: f64| -> Vec<[f64; 3]> {
            mesh.nodes
                .iter()
                .map(|p| {
                    [
                        (k * p[0]).sin(),
                        (k * p[1] + 0.3).cos(),
                        (k * p[2]).sin() * p[0],
                    ]
                })
                .collect()
        };
        let (xr, xi, yr, yi) = (wave(1.0), wave(2.0), wave(3.0), wave(0.5));
        let x = Shape { re: &xr, im: &xi };
        let y = Shape { re: &yr, im: &yi };
        let forms = body_stiffness_forms(&mesh, &[(y, x)]).unwrap();
        let total: Complex64 = forms[0].values().sum();
        // The assembled K, densely, element by element.
        let materials = element_materials(&mesh).unwrap();
        let mut k = vec![vec![0.0; 3 * nodes]; 3 * nodes];
        for (e, conn) in mesh.elements.iter().enumerate() {
            let ke = element::stiffness(
                &conn.map(|n| mesh.nodes[n]),
                materials[e].young,
                materials[e].poisson,
            )
            .unwrap();
            for i in 0..30 {
                for j in 0..30 {
                    k[3 * conn[i / 3] + i % 3][3 * conn[j / 3] + j % 3] += ke[i][j];
                }
            }
        }
        let c = |s: &Shape<'_>, d: usize| Complex64::new(s.re[d / 3][d % 3], s.im[d / 3][d % 3]);
        let mut expected = Complex64::new(0.0, 0.0);
        let mut scale = 0.0;
        for (i, row) in k.iter().enumerate() {
            for (j, kij) in row.iter().enumerate() {
                let t = c(&y, i).conj() * kij * c(&x, j);
                expected += t;
                scale += t.norm();
            }
        }
        assert_eq!(forms[0].len(), 2);
        assert!(
            (total - expected).norm() <= 1e-12 * scale,
            "{total} {expected}"
        );
        let forces = body_forces(&mesh, &xr).unwrap();
        for d in 0..3 * nodes {
            let sum: f64 = forces.values().map(|f| f[d / 3][d % 3]).sum();
            let row: f64 = (0..3 * nodes).map(|j| k[d][j] * xr[j / 3][j % 3]).sum();
            let size: f64 = (0..3 * nodes)
                .map(|j| (k[d][j] * xr[j / 3][j % 3]).abs())
                .sum();
            assert!(
                (sum - row).abs() <= 1e-12 * size.max(1.0),
                "{d}: {sum} {row}"
            );
        }
        let rigid = vec![[1e-3, -2e-3, 5e-4]; nodes];
        for f in body_forces(&mesh, &rigid).unwrap().values() {
            let largest = f.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
            // K u of a rigid motion is round-off of the element sums: E h |u| eps.
            let stiff = materials[0].young * 1e-3;
            assert!(largest <= 1e-9 * stiff, "{largest}");
        }
    }
}
