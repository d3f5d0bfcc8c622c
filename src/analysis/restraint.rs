//! Whether a stiffness holds every body against rigid-body motion (METHOD §3: "detect a
//! singular tangent and name the part"). A pad held by the disc's contact normally and by its
//! abutment tangentially still slides radially unless guides hold it; the LU of such a
//! tangent fails, or worse succeeds on a round-off pivot and throws the pad off. Looking at
//! what the tangent does to each body's six rigid-body motions names the body and the motion
//! instead.
//!
//! A body is a connected set of elements (a pad and its backplate sharing nodes are one). For
//! its rigid motions R (3 translations, 3 rotations about its centre scaled by its size, so
//! every motion moves nodes by at most 1), the smallest singular values of K R are those of
//! the Gram matrix (K R)^T (K R). A motion nothing restrains leaves only assembly round-off,
//! |K r| ~ 1e-15 k_max sqrt(n) (k_max the body's largest diagonal stiffness, n its equations);
//! any support, spring or closed contact gives at least its own stiffness, many decades more.
//! The threshold 1e-9 k_max sqrt(n) sits between the two.

use crate::fem::DofMap;
use crate::mesh::Mesh;
use crate::petsc::{Comm, Matrix, PetscError, Vector};

/// Relative level below which a rigid motion counts as unrestrained (see the module doc).
const FREE_LEVEL: f64 = 1e-9;

/// A connected set of elements.
#[derive(Clone, Debug, PartialEq)]
pub struct Body {
    /// Names of the parts its elements belong to.
    pub parts: Vec<String>,
    /// Its nodes (mesh numbering), sorted, and where they are.
    pub nodes: Vec<usize>,
    pub positions: Vec<[f64; 3]>,
    /// Centroid of its nodes.
    pub centre: [f64; 3],
    /// Largest distance of a node from the centre.
    pub size: f64,
}

impl Body {
    /// "pad_inboard" or "pad_inboard + backplate_inboard".
    pub fn name(&self) -> String {
        if self.parts.is_empty() {
            "(elements in no part)".into()
        } else {
            self.parts.join(" + ")
        }
    }
}

/// The bodies of a mesh: connected components of its elements (sharing a node connects).
pub fn bodies(mesh: &Mesh) -> Vec<Body> {
    let n = mesh.nodes.len();
    let mut parent: Vec<usize> = (0..n).collect();
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    for element in &mesh.elements {
        let first = root(&mut parent, element[0]);
        for &node in &element[1..] {
            let r = root(&mut parent, node);
            if r != first {
                parent[r] = first;
            }
        }
    }
    let owner = mesh.element_parts();
    // Component of each used node -> body index, in order of first element.
    let mut index = std::collections::HashMap::new();
    let mut members: Vec<(Vec<usize>, std::collections::BTreeSet<usize>, bool)> = Vec::new();
    let mut used = vec![false; n];
    for (e, element) in mesh.elements.iter().enumerate() {
        let r = root(&mut parent, element[0]);
        let b = *index.entry(r).or_insert_with(|| {
            members.push((Vec::new(), Default::default(), false));
            members.len() - 1
        });
        match owner[e] {
            Some(p) => {
                members[b].1.insert(p);
            }
            None => members[b].2 = true,
        }
        for &node in element {
            if !used[node] {
                used[node] = true;
                members[b].0.push(node);
            }
        }
    }
    members
        .into_iter()
        .map(|(mut nodes, parts, _)| {
            nodes.sort_unstable();
            let mut centre = [0.0; 3];
            for &k in &nodes {
                for (sum, x) in centre.iter_mut().zip(mesh.nodes[k]) {
                    *sum += x / nodes.len() as f64;
                }
            }
            let size = nodes
                .iter()
                .map(|&k| distance(mesh.nodes[k], centre))
                .fold(0.0, f64::max);
            Body {
                parts: parts.iter().map(|&p| mesh.parts[p].name.clone()).collect(),
                positions: nodes.iter().map(|&k| mesh.nodes[k]).collect(),
                nodes,
                centre,
                size,
            }
        })
        .collect()
}

fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// A body with rigid motions a stiffness does not restrain.
#[derive(Clone, Debug, PartialEq)]
pub struct FreeBody {
    pub body: String,
    pub centre: [f64; 3],
    /// Orthonormal basis of its free motions: (translation x, y, z, rotation x, y, z).
    pub motions: Vec<[f64; 6]>,
    /// Largest |K r| / (k_max sqrt(n)) among them (how far below the threshold).
    pub level: f64,
}

const AXES: [&str; 3] = ["x", "y", "z"];

fn unit(v: &[f64]) -> String {
    let n = v
        .iter()
        .map(|x| x * x)
        .sum::<f64>()
        .sqrt()
        .max(f64::MIN_POSITIVE);
    let parts: Vec<String> = v.iter().map(|x| format!("{:.3}", x / n + 0.0)).collect();
    format!("({})", parts.join(", "))
}

impl std::fmt::Display for FreeBody {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let c = self.centre;
        let at = format!("through ({:.4}, {:.4}, {:.4})", c[0], c[1], c[2]);
        let describe = |m: &[f64; 6]| {
            let t = m[..3].iter().map(|x| x * x).sum::<f64>().sqrt();
            let r = m[3..].iter().map(|x| x * x).sum::<f64>().sqrt();
            if r < 0.1 * t {
                format!("translation along {}", unit(&m[..3]))
            } else if t < 0.1 * r {
                format!("rotation about {} {at}", unit(&m[3..]))
            } else {
                format!(
                    "translation {} with rotation about {} {at}",
                    unit(&m[..3]),
                    unit(&m[3..])
                )
            }
        };
        write!(f, "'{}' is free: ", self.body)?;
        if self.motions.len() == 1 {
            return write!(f, "{}", describe(&self.motions[0]));
        }
        // Several: name the coordinate motions that lie in the free space, then the rest.
        let mut named = Vec::new();
        for axis in 0..6 {
            let inside: f64 = self.motions.iter().map(|m| m[axis] * m[axis]).sum();
            if inside > 0.99 {
                named.push(if axis < 3 {
                    format!("translation along {}", AXES[axis])
                } else {
                    format!("rotation about {} {at}", AXES[axis - 3])
                });
            }
        }
        if named.len() == self.motions.len() {
            write!(f, "{}", named.join(", "))
        } else {
            let all: Vec<String> = self.motions.iter().map(describe).collect();
            write!(
                f,
                "{} rigid motions, spanned by {}",
                self.motions.len(),
                all.join("; ")
            )
        }
    }
}

/// The rigid motions of `bodies` that `stiffness` leaves unrestrained (collective).
/// Supported DOFs are eliminated from `stiffness`, so supports restrain by construction.
pub fn free_bodies<'rt>(
    comm: Comm<'rt>,
    stiffness: &Matrix<'rt>,
    dofs: &DofMap,
    bodies: &[Body],
) -> Result<Vec<FreeBody>, PetscError> {
    let owned = dofs.owned_equations();
    let diagonal = stiffness.diagonal()?.read()?.to_vec();
    let mut free = Vec::new();
    for body in bodies {
        let scale = body.size.max(f64::MIN_POSITIVE);
        // Equations of the body (global count) and its stiffest diagonal entry.
        let mut counts = [0.0, 0.0];
        let mut k_max = [0.0f64];
        for &node in &body.nodes {
            for c in 0..3 {
                if let Some(e) = dofs.equation(node, c) {
                    if owned.contains(&e) {
                        counts[0] += 1.0;
                        k_max[0] = k_max[0].max(diagonal[e - owned.start].abs());
                    }
                }
            }
        }
        comm.sum_in_place(&mut counts);
        comm.max_in_place(&mut k_max);
        if counts[0] == 0.0 || k_max[0] == 0.0 {
            continue;
        }
        let mut images: Vec<Vector<'rt>> = Vec::with_capacity(6);
        for motion in 0..6 {
            let mut local = vec![0.0; owned.len()];
            for (&node, &x) in body.nodes.iter().zip(&body.positions) {
                let d = [
                    (x[0] - body.centre[0]) / scale,
                    (x[1] - body.centre[1]) / scale,
                    (x[2] - body.centre[2]) / scale,
                ];
                // Translations e_m, then rotations e_(m-3) x d.
                let u = match motion {
                    0 => [1.0, 0.0, 0.0],
                    1 => [0.0, 1.0, 0.0],
                    2 => [0.0, 0.0, 1.0],
                    3 => [0.0, -d[2], d[1]],
                    4 => [d[2], 0.0, -d[0]],
                    _ => [-d[1], d[0], 0.0],
                };
                for (c, value) in u.into_iter().enumerate() {
                    if let Some(e) = dofs.equation(node, c) {
                        if owned.contains(&e) {
                            local[e - owned.start] = value;
                        }
                    }
                }
            }
            let (mut r, mut y) = stiffness.vectors()?;
            r.set_local(&local)?;
            stiffness.mult(&r, &mut y)?;
            images.push(y);
        }
        let mut gram = [[0.0; 6]; 6];
        for a in 0..6 {
            for b in a..6 {
                let g = images[a].dot(&images[b])?;
                gram[a][b] = g;
                gram[b][a] = g;
            }
        }
        let reference = k_max[0] * counts[0].sqrt();
        let (values, vectors) = symmetric_eigen(gram);
        let levels = values.map(|v| v.max(0.0).sqrt() / reference);
        let motions: Vec<[f64; 6]> = (0..6)
            .filter(|&k| levels[k] < FREE_LEVEL)
            .map(|k| vectors[k])
            .collect();
        if !motions.is_empty() {
            free.push(FreeBody {
                body: body.name(),
                centre: body.centre,
                level: levels[motions.len() - 1],
                motions,
            });
        }
    }
    Ok(free)
}

/// Eigenvalues (ascending) and unit eigenvectors of a symmetric 6x6 matrix (faer).
pub fn symmetric_eigen(a: [[f64; 6]; 6]) -> ([f64; 6], [[f64; 6]; 6]) {
    let m = faer::Mat::<f64>::from_fn(6, 6, |i, j| a[i][j]);
    match m.self_adjoint_eigen(faer::Side::Lower) {
        Ok(evd) => {
            let (s, u) = (evd.S().column_vector(), evd.U());
            let mut order: Vec<usize> = (0..6).collect();
            order.sort_by(|&i, &j| s[i].total_cmp(&s[j]));
            (
                std::array::from_fn(|k| s[order[k]]),
                std::array::from_fn(|k| std::array::from_fn(|i| u[(i, order[k])])),
            )
        }
        // Only non-finite input fails: nothing can be said here, and the solve that follows
        // reports the non-finite tangent itself.
        Err(_) => ([f64::NAN; 6], [[0.0; 6]; 6]),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eigen_recovers_a_known_spectrum() {
        // A = Q diag(w) Q^T with Q a product of plane rotations.
        let w = [-2.0, 0.0, 1e-12, 1.0, 3.0, 7.5];
        let mut q = [[0.0; 6]; 6];
        for (i, row) in q.iter_mut().enumerate() {
            row[i] = 1.0;
        }
        for (p, r, angle) in [
            (0, 3, 0.3),
            (1, 4, 1.1),
            (2, 5, -0.7),
            (0, 5, 0.4),
            (1, 2, 2.0),
        ] {
            let (c, s): (f64, f64) = (f64::cos(angle), f64::sin(angle));
            for row in q.iter_mut() {
                let (a, b) = (row[p], row[r]);
                row[p] = c * a - s * b;
                row[r] = s * a + c * b;
            }
        }
        let mut a = [[0.0; 6]; 6];
        for i in 0..6 {
            for j in 0..6 {
                a[i][j] = (0..6).map(|k| q[i][k] * w[k] * q[j][k]).sum();
            }
        }
        let (values, vectors) = symmetric_eigen(a);
        for k in 0..6 {
            assert!((values[k] - w[k]).abs() < 1e-13, "{values:?}");
            // A v = w v.
            let v = vectors[k];
            for i in 0..6 {
                let av: f64 = (0..6).map(|j| a[i][j] * v[j]).sum();
                assert!((av - w[k] * v[i]).abs() < 1e-13);
            }
        }
    }

    #[test]
    fn free_motions_are_described_in_words() {
        let one = FreeBody {
            body: "pad".into(),
            centre: [0.1, 0.0, 0.0],
            motions: vec![[0.0, 0.999, 0.0, 0.0, 0.0, 0.01]],
            level: 1e-15,
        };
        assert_eq!(
            one.to_string(),
            "'pad' is free: translation along (0.000, 1.000, 0.000)"
        );
        let plane = FreeBody {
            motions: vec![
                [0.6, 0.8, 0.0, 0.0, 0.0, 0.0],
                [0.8, -0.6, 0.0, 0.0, 0.0, 0.0],
                [0.0, 0.0, 0.0, 0.0, 0.0, -1.0],
            ],
            ..one.clone()
        };
        assert_eq!(
            plane.to_string(),
            "'pad' is free: translation along x, translation along y, rotation about z through (0.1000, 0.0000, 0.0000)"
        );
        let skew = FreeBody {
            motions: vec![
                [0.6, 0.8, 0.0, 0.0, 0.0, 0.0],
                [0.0, 0.0, 0.0, 0.0, 0.0, 1.0],
            ],
            ..one
        };
        assert!(skew.to_string().starts_with("'pad' is free: 2 rigid motions, spanned by translation along (0.600, 0.800, 0.000); rotation about (0.000, 0.000, 1.000)"));
    }
}
