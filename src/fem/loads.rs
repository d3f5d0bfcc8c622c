//! Resultants of applied loads, for balance checks: the sum of a pressure's consistent
//! nodal forces, which is what contact must carry at equilibrium.

use super::element::face_pressure_load;
use crate::mesh::{Face, Mesh};

/// The resultant of a uniform pressure on faces (positive pushes into the body): the sum
/// of its consistent nodal forces, exactly what the load vector holds.
pub fn pressure_resultant(mesh: &Mesh, faces: &[Face], pressure: f64) -> [f64; 3] {
    let mut r = [0.0; 3];
    for face in faces {
        let x = face.nodes.map(|n| mesh.nodes[n]);
        for f in face_pressure_load(&x, pressure) {
            for c in 0..3 {
                r[c] += f[c];
            }
        }
    }
    r
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::block::block;
    use crate::mesh::Material;

    /// A pressure p on the top face of a box pushes down with p times its area.
    #[test]
    fn resultant_of_a_pressure_on_a_flat_face_is_p_times_area() {
        let steel = Material {
            name: "s".into(),
            young: 2e11,
            poisson: 0.3,
            density: 7800.0,
        };
        let mesh = block([0.0; 3], [0.3, 0.2, 0.1], [3, 2, 1], steel).unwrap();
        // Faces whose nodes all lie on z = 0.1.
        let mut faces = Vec::new();
        for e in 0..mesh.elements.len() {
            for side in 0..4 {
                let f = mesh.face(e, side);
                if f.nodes
                    .iter()
                    .all(|&n| (mesh.nodes[n][2] - 0.1).abs() < 1e-12)
                {
                    faces.push(f);
                }
            }
        }
        let r = pressure_resultant(&mesh, &faces, 2e6);
        let expected = 2e6 * 0.3 * 0.2;
        assert!((r[2].abs() - expected).abs() <= 1e-12 * expected, "{r:?}");
        assert!(r[0].abs() + r[1].abs() <= 1e-9 * expected);
    }
}
