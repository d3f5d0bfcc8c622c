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
use crate::petsc::{Comm, Matrix, PetscError};

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
    /// Other bodies that move with it in its free motions (empty: it is free alone).
    pub with: Vec<String>,
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
        if self.with.is_empty() {
            write!(f, "'{}' is free: ", self.body)?;
        } else {
            let others: Vec<String> = self.with.iter().map(|b| format!("'{b}'")).collect();
            write!(
                f,
                "'{}' is free together with {} (moving as one): ",
                self.body,
                others.join(", ")
            )?;
        }
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
///
/// The motions of all bodies are tested together, not one body at a time: a piston tied to
/// a caliper by its seal is held against moving alone, yet the two may be free to move as
/// one (both slide off with nothing but friction holding them). Each body's six motions are
/// scaled by its own reference `k_max sqrt(n)`, so a motion of one body is judged exactly
/// as before; the null space of the joint Gram matrix is then split into groups of bodies
/// that move together (its projector has no block between independent groups).
pub fn free_bodies<'rt>(
    comm: Comm<'rt>,
    stiffness: &Matrix<'rt>,
    dofs: &DofMap,
    bodies: &[Body],
) -> Result<Vec<FreeBody>, PetscError> {
    let owned = dofs.owned_equations();
    let diagonal = stiffness.diagonal()?.read()?.to_vec();
    // The tested bodies and the scaled images K r / reference of their six motions (this
    // rank's rows), body-major.
    let mut tested: Vec<&Body> = Vec::new();
    let mut references: Vec<f64> = Vec::new();
    let mut images: Vec<Vec<f64>> = Vec::new();
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
        let reference = k_max[0] * counts[0].sqrt();
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
            images.push(y.read()?.iter().map(|v| v / reference).collect());
        }
        tested.push(body);
        references.push(reference);
    }
    let m = images.len();
    if m == 0 {
        return Ok(Vec::new());
    }
    // One reduction for the whole Gram matrix: every rank then holds the same bits and
    // takes the same decisions.
    let mut gram = vec![0.0; m * m];
    for a in 0..m {
        for b in a..m {
            gram[a * m + b] = images[a].iter().zip(&images[b]).map(|(x, y)| x * y).sum();
        }
    }
    comm.sum_in_place(&mut gram);
    let (values, vectors) = symmetric_eigen_dense(m, |a, b| gram[a.min(b) * m + a.max(b)]);
    let null: Vec<(f64, &Vec<f64>)> = values
        .iter()
        .zip(&vectors)
        .map(|(&v, x)| (v.max(0.0).sqrt(), x))
        .filter(|(level, _)| *level < FREE_LEVEL)
        .collect();
    if null.is_empty() {
        return Ok(Vec::new());
    }
    // A null vector x holds each body's motion times its reference (sum_a x_a K r_a / ref_a
    // = 0 is the displacement u = sum_a (x_a / ref_a) r_a): a soft body moving with a stiff
    // one has coefficients ref_soft / ref_stiff of the stiff body's, and with steel on
    // rubber its share would fall below any fixed threshold. Who moves, and how, is read
    // off the amplitudes x_a / ref_a (dimensionless: the rotations are scaled by the body's
    // size), orthonormalised.
    let amplitudes = orthonormal(
        &null
            .iter()
            .map(|(_, x)| {
                x.iter()
                    .enumerate()
                    .map(|(i, v)| v / references[i / 6])
                    .collect()
            })
            .collect::<Vec<Vec<f64>>>(),
    );
    // Each free motion's level beside its amplitude direction (unit length).
    let unit = |x: &Vec<f64>| -> Vec<f64> {
        let y: Vec<f64> = x
            .iter()
            .enumerate()
            .map(|(i, v)| v / references[i / 6])
            .collect();
        let norm = y
            .iter()
            .map(|v| v * v)
            .sum::<f64>()
            .sqrt()
            .max(f64::MIN_POSITIVE);
        y.iter().map(|v| v / norm).collect()
    };
    let levels: Vec<(f64, Vec<f64>)> = null.iter().map(|(l, x)| (*l, unit(x))).collect();
    let null: Vec<&Vec<f64>> = amplitudes.iter().collect();
    // The projector P = N N^T onto the free motions, by 6x6 blocks between bodies.
    let n_bodies = tested.len();
    let block = |b: usize, c: usize| -> f64 {
        let mut sum = 0.0;
        for i in 6 * b..6 * b + 6 {
            for j in 6 * c..6 * c + 6 {
                let p: f64 = null.iter().map(|x| x[i] * x[j]).sum();
                sum += p * p;
            }
        }
        sum.sqrt()
    };
    // Bodies that move in some free motion, grouped by the motions they share. A body's
    // share of a free motion is at least ~1/6 of it when it takes part (its diagonal block
    // of P then has norm >= ~0.1); round-off leaves ~1e-8.
    const SHARE: f64 = 1e-3;
    let moving: Vec<usize> = (0..n_bodies).filter(|&b| block(b, b) > SHARE).collect();
    let mut group: Vec<usize> = (0..n_bodies).collect();
    fn root(group: &mut [usize], mut i: usize) -> usize {
        while group[i] != i {
            group[i] = group[group[i]];
            i = group[i];
        }
        i
    }
    for (k, &b) in moving.iter().enumerate() {
        for &c in &moving[k + 1..] {
            if block(b, c) > SHARE {
                let (rb, rc) = (root(&mut group, b), root(&mut group, c));
                group[rb.max(rc)] = rb.min(rc);
            }
        }
    }
    let mut free = Vec::new();
    for &b in &moving {
        if root(&mut group, b) != b {
            continue;
        }
        let members: Vec<usize> = moving
            .iter()
            .copied()
            .filter(|&c| root(&mut group, c) == b)
            .collect();
        // The free motions this group takes part in, and how far below the threshold.
        let share = |x: &[f64]| -> f64 {
            members
                .iter()
                .map(|&c| x[6 * c..6 * c + 6].iter().map(|v| v * v).sum::<f64>())
                .sum()
        };
        let level = levels
            .iter()
            .filter(|(_, x)| share(x) > 0.5)
            .map(|(level, _)| *level)
            .fold(0.0, f64::max);
        // Described on the member that moves most, in its own frame: an orthonormal basis
        // of its six-vectors in the group's free motions.
        let lead = *members
            .iter()
            .max_by(|&&c, &&d| block(c, c).total_cmp(&block(d, d)))
            .expect("a group has a member");
        let mut own = [[0.0; 6]; 6];
        for x in &null {
            for i in 0..6 {
                for j in 0..6 {
                    own[i][j] += x[6 * lead + i] * x[6 * lead + j];
                }
            }
        }
        let (weights, basis) = symmetric_eigen(own);
        let largest = weights[5].max(f64::MIN_POSITIVE);
        let motions: Vec<[f64; 6]> = (0..6)
            .rev()
            .filter(|&k| weights[k] > SHARE * largest)
            .map(|k| basis[k])
            .collect();
        free.push(FreeBody {
            body: tested[lead].name(),
            with: members
                .iter()
                .filter(|&&c| c != lead)
                .map(|&c| tested[c].name())
                .collect(),
            centre: tested[lead].centre,
            level,
            motions,
        });
    }
    Ok(free)
}

/// An orthonormal basis of the span of `vectors` (modified Gram-Schmidt, twice: the
/// amplitudes of motions of bodies of very different stiffness can be far from orthogonal);
/// a vector already in the span of the others (below 1e-10 of its length) is dropped.
fn orthonormal(vectors: &[Vec<f64>]) -> Vec<Vec<f64>> {
    let mut basis: Vec<Vec<f64>> = Vec::new();
    for v in vectors {
        let length = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        let mut w = v.clone();
        for _ in 0..2 {
            for b in &basis {
                let dot: f64 = w.iter().zip(b).map(|(x, y)| x * y).sum();
                w.iter_mut().zip(b).for_each(|(x, y)| *x -= dot * y);
            }
        }
        let norm = w.iter().map(|x| x * x).sum::<f64>().sqrt();
        if norm > 1e-10 * length {
            basis.push(w.iter().map(|x| x / norm).collect());
        }
    }
    basis
}

/// Eigenvalues (ascending) and unit eigenvectors of the symmetric `n x n` matrix `a(i, j)`.
fn symmetric_eigen_dense(n: usize, a: impl Fn(usize, usize) -> f64) -> (Vec<f64>, Vec<Vec<f64>>) {
    let m = faer::Mat::<f64>::from_fn(n, n, a);
    match m.self_adjoint_eigen(faer::Side::Lower) {
        Ok(evd) => {
            let (s, u) = (evd.S().column_vector(), evd.U());
            let mut order: Vec<usize> = (0..n).collect();
            order.sort_by(|&i, &j| s[i].total_cmp(&s[j]));
            (
                order.iter().map(|&k| s[k]).collect(),
                order
                    .iter()
                    .map(|&k| (0..n).map(|i| u[(i, k)]).collect())
                    .collect(),
            )
        }
        // Only non-finite input fails: nothing can be said here, and the solve that follows
        // reports the non-finite tangent itself.
        Err(_) => (Vec::new(), Vec::new()),
    }
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
            with: Vec::new(),
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
