//! The 10-node quadratic tetrahedron and its 6-node triangular faces: shape functions,
//! their parametric derivatives and the quadrature rules the element routines use.
//!
//! Parametric (volume) coordinates of the tetrahedron are `p = [xi, eta, zeta]` with the
//! fourth barycentric coordinate `L0 = 1 - xi - eta - zeta`; corner `k` (1..=3) sits where
//! `L_k = 1`, corner 0 at the origin. Node numbering is the internal one of
//! [`crate::mesh::TET10_EDGES`] (Abaqus C3D10): corners 0-3, then the mid-edge nodes
//! 4 = 0-1, 5 = 1-2, 6 = 2-0, 7 = 0-3, 8 = 1-3, 9 = 2-3.
//!
//! ```text
//!   N_k  = L_k (2 L_k - 1)        corners k = 0..3
//!   N_m  = 4 L_a L_b              mid-edge node m of edge (a, b) = TET10_EDGES[m - 4]
//! ```
//!
//! The triangle has parametric coordinates `q = [s, t]`, `L0 = 1 - s - t`, and its nodes in the
//! order of a row of [`crate::mesh::TET10_FACES`]: corners a (origin), b (`s = 1`), c (`t = 1`),
//! then mid(a,b), mid(b,c), mid(c,a). With that placement `dx/ds x dx/dt` is the right-hand
//! normal of (a, b, c), i.e. it points out of the element.
//!
//! Quadrature rules are plain data on the reference cells; the weights sum to the reference
//! measure (1/6 for the tetrahedron, 1/2 for the triangle), so `sum_q w_q det J(p_q)` is the
//! physical volume (area) directly.

use crate::mesh::TET10_EDGES;

/// Number of nodes of the quadratic tetrahedron.
pub const NODES: usize = 10;

/// Number of nodes of the quadratic triangle (a face of the tetrahedron).
pub const FACE_NODES: usize = 6;

/// Parametric coordinates of the ten nodes (corners, then the mid-edge nodes in
/// [`TET10_EDGES`] order).
pub const NODE_COORDINATES: [[f64; 3]; NODES] = [
    [0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.0, 0.0, 1.0],
    [0.5, 0.0, 0.0],
    [0.5, 0.5, 0.0],
    [0.0, 0.5, 0.0],
    [0.0, 0.0, 0.5],
    [0.5, 0.0, 0.5],
    [0.0, 0.5, 0.5],
];

/// Parametric coordinates of the six face nodes (a, b, c, mid(a,b), mid(b,c), mid(c,a)).
pub const FACE_NODE_COORDINATES: [[f64; 2]; FACE_NODES] = [
    [0.0, 0.0],
    [1.0, 0.0],
    [0.0, 1.0],
    [0.5, 0.0],
    [0.5, 0.5],
    [0.0, 0.5],
];

/// The edges of the 6-node triangle, corner pairs in the order of its mid-side nodes 3, 4, 5.
const FACE_EDGES: [[usize; 2]; 3] = [[0, 1], [1, 2], [2, 0]];

/// Gradients of the barycentric coordinates L0..L3 with respect to (xi, eta, zeta).
const BARYCENTRIC_GRADIENTS: [[f64; 3]; 4] = [
    [-1.0, -1.0, -1.0],
    [1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.0, 0.0, 1.0],
];

/// Gradients of the triangle's barycentric coordinates L0..L2 with respect to (s, t).
const FACE_BARYCENTRIC_GRADIENTS: [[f64; 2]; 3] = [[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0]];

fn barycentric(p: [f64; 3]) -> [f64; 4] {
    [1.0 - p[0] - p[1] - p[2], p[0], p[1], p[2]]
}

fn face_barycentric(q: [f64; 2]) -> [f64; 3] {
    [1.0 - q[0] - q[1], q[0], q[1]]
}

/// Values of the ten shape functions at parametric point `p`.
pub fn shape(p: [f64; 3]) -> [f64; NODES] {
    let l = barycentric(p);
    let mut n = [0.0; NODES];
    for k in 0..4 {
        n[k] = l[k] * (2.0 * l[k] - 1.0);
    }
    for (m, [a, b]) in TET10_EDGES.iter().enumerate() {
        n[4 + m] = 4.0 * l[*a] * l[*b];
    }
    n
}

/// Parametric gradients `dN_i / d(xi, eta, zeta)` of the ten shape functions at `p`.
pub fn shape_gradients(p: [f64; 3]) -> [[f64; 3]; NODES] {
    let l = barycentric(p);
    let dl = &BARYCENTRIC_GRADIENTS;
    let mut g = [[0.0; 3]; NODES];
    for k in 0..4 {
        let f = 4.0 * l[k] - 1.0;
        g[k] = [f * dl[k][0], f * dl[k][1], f * dl[k][2]];
    }
    for (m, [a, b]) in TET10_EDGES.iter().enumerate() {
        let (a, b) = (*a, *b);
        for j in 0..3 {
            g[4 + m][j] = 4.0 * (l[a] * dl[b][j] + l[b] * dl[a][j]);
        }
    }
    g
}

/// Values of the six face shape functions at face parametric point `q = [s, t]`.
pub fn face_shape(q: [f64; 2]) -> [f64; FACE_NODES] {
    let l = face_barycentric(q);
    let mut n = [0.0; FACE_NODES];
    for k in 0..3 {
        n[k] = l[k] * (2.0 * l[k] - 1.0);
    }
    for (m, [a, b]) in FACE_EDGES.iter().enumerate() {
        n[3 + m] = 4.0 * l[*a] * l[*b];
    }
    n
}

/// Parametric derivatives `dN_i / d(s, t)` of the six face shape functions at `q`.
pub fn face_shape_derivatives(q: [f64; 2]) -> [[f64; 2]; FACE_NODES] {
    let l = face_barycentric(q);
    let dl = &FACE_BARYCENTRIC_GRADIENTS;
    let mut g = [[0.0; 2]; FACE_NODES];
    for k in 0..3 {
        let f = 4.0 * l[k] - 1.0;
        g[k] = [f * dl[k][0], f * dl[k][1]];
    }
    for (m, [a, b]) in FACE_EDGES.iter().enumerate() {
        let (a, b) = (*a, *b);
        for j in 0..2 {
            g[3 + m][j] = 4.0 * (l[a] * dl[b][j] + l[b] * dl[a][j]);
        }
    }
    g
}

/// A quadrature rule on the reference tetrahedron `{xi, eta, zeta >= 0, xi + eta + zeta <= 1}`.
/// The weights sum to 1/6, the reference volume.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rule {
    /// Polynomial degree integrated exactly.
    pub degree: u32,
    /// Points `[xi, eta, zeta]`.
    pub points: &'static [[f64; 3]],
    /// Weights, one per point, all positive.
    pub weights: &'static [f64],
}

/// A quadrature rule on the reference triangle `{s, t >= 0, s + t <= 1}`. The weights sum to
/// 1/2, the reference area.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FaceRule {
    /// Polynomial degree integrated exactly.
    pub degree: u32,
    /// Points `[s, t]`.
    pub points: &'static [[f64; 2]],
    /// Weights, one per point, all positive.
    pub weights: &'static [f64],
}

// 4-point Gauss rule: the orbit of (a, b, b, b) in barycentric coordinates with
// a = (5 + 3 sqrt 5) / 20, b = (5 - sqrt 5) / 20, equal weights. Degree 2. This is the rule
// of Abaqus/CalculiX C3D10 (Hammer, Marlowe & Stroud, Math. Tables Aids Comput. 10 (1956)).
const G4_A: f64 = 0.585_410_196_624_968_5;
const G4_B: f64 = 0.138_196_601_125_010_5;

const GAUSS_4_POINTS: [[f64; 3]; 4] = [
    [G4_B, G4_B, G4_B],
    [G4_A, G4_B, G4_B],
    [G4_B, G4_A, G4_B],
    [G4_B, G4_B, G4_A],
];
const GAUSS_4_WEIGHTS: [f64; 4] = [1.0 / 24.0; 4];

/// 4-point Gauss rule, exact for degree 2: the stiffness rule of Abaqus/CalculiX C3D10, exact
/// for the stiffness of a straight-sided element.
pub const GAUSS_4: Rule = Rule {
    degree: 2,
    points: &GAUSS_4_POINTS,
    weights: &GAUSS_4_WEIGHTS,
};

// 14-point rule, exact for degree 5, all weights positive, all points inside. Two orbits of
// type (a, a, a, 1 - 3a) and one of type (a, a, 1/2 - a, 1/2 - a) in barycentric coordinates:
// N. Walkington, "Quadrature on simplices of arbitrary dimension", CMU tech. report (2000),
// rule p5; also Gellert & Harbord, Commun. Appl. Numer. Methods 7 (1991) 487-495, table VI,
// and C. Felippa, Advanced Finite Element Methods, sec. 17.4 (35 digits; the 20 kept here
// agree). The same numbers are in MFEM's `intrules.cpp` (tetrahedron order 5). The test
// `walkington_14_is_exact_to_degree_5` checks every monomial of degree <= 5 against its
// closed-form integral.
// The digits are kept as published (more than an f64 holds) so they can be compared with the
// sources; the compiler rounds them to the nearest f64.
#[allow(clippy::excessive_precision)]
mod walkington_digits {
    pub(super) const W14_A1: f64 = 0.092_735_250_310_891_226_402;
    pub(super) const W14_B1: f64 = 0.721_794_249_067_326_320_79; // 1 - 3 A1
    pub(super) const W14_W1: f64 = 0.012_248_840_519_393_658_257;
    pub(super) const W14_A2: f64 = 0.310_885_919_263_300_609_80;
    pub(super) const W14_B2: f64 = 0.067_342_242_210_098_170_608; // 1 - 3 A2
    pub(super) const W14_W2: f64 = 0.018_781_320_953_002_641_800;
    pub(super) const W14_A3: f64 = 0.454_496_295_874_350_350_51;
    pub(super) const W14_B3: f64 = 0.045_503_704_125_649_649_492; // 1/2 - A3
    pub(super) const W14_W3: f64 = 0.007_091_003_462_846_911_073; // (1/6 - 4 W1 - 4 W2) / 6
}
use walkington_digits::*;

const WALKINGTON_14_POINTS: [[f64; 3]; 14] = [
    // (a, a, a, 1 - 3a) orbits: barycentric L0 is implied, so the fourth point of each orbit
    // is the one with L0 = 1 - 3a.
    [W14_B1, W14_A1, W14_A1],
    [W14_A1, W14_B1, W14_A1],
    [W14_A1, W14_A1, W14_B1],
    [W14_A1, W14_A1, W14_A1],
    [W14_B2, W14_A2, W14_A2],
    [W14_A2, W14_B2, W14_A2],
    [W14_A2, W14_A2, W14_B2],
    [W14_A2, W14_A2, W14_A2],
    // (a, a, 1/2 - a, 1/2 - a) orbit: the six ways of choosing which two of (L0, L1, L2, L3)
    // equal A3.
    [W14_A3, W14_B3, W14_B3], // L0 = A3
    [W14_B3, W14_A3, W14_B3],
    [W14_B3, W14_B3, W14_A3],
    [W14_A3, W14_A3, W14_B3], // L0 = B3
    [W14_A3, W14_B3, W14_A3],
    [W14_B3, W14_A3, W14_A3],
];
const WALKINGTON_14_WEIGHTS: [f64; 14] = [
    W14_W1, W14_W1, W14_W1, W14_W1, W14_W2, W14_W2, W14_W2, W14_W2, W14_W3, W14_W3, W14_W3, W14_W3,
    W14_W3, W14_W3,
];

/// 14-point rule exact for degree 5 with positive weights (Walkington 2000, rule p5): the
/// consistent-mass rule (the mass integrand `N_i N_j det J` is degree 4 on a straight-sided
/// element) and the volume rule (`det J` is at most cubic).
pub const WALKINGTON_14: Rule = Rule {
    degree: 5,
    points: &WALKINGTON_14_POINTS,
    weights: &WALKINGTON_14_WEIGHTS,
};

// 7-point triangle rule of Radon (1948), exact for degree 5, closed form (Stroud T2:5-1,
// also Dunavant's degree-5 rule): the centroid with weight 9/80, and the orbits (a, a, 1 - 2a)
// with a = (6 -+ sqrt 15) / 21, weights (155 -+ sqrt 15) / 2400 (on the area-1/2 triangle).
// The test `radon_7_matches_its_closed_form` recomputes these digits.
// 24 places, evaluated from the closed form in 40-digit arithmetic.
#[allow(clippy::excessive_precision)]
mod radon_digits {
    pub(super) const R7_A1: f64 = 0.101_286_507_323_456_338_800_987;
    pub(super) const R7_B1: f64 = 0.797_426_985_353_087_322_398_025; // 1 - 2 A1
    pub(super) const R7_W1: f64 = 0.062_969_590_272_413_576_297_842;
    pub(super) const R7_A2: f64 = 0.470_142_064_105_115_089_770_441;
    pub(super) const R7_B2: f64 = 0.059_715_871_789_769_820_459_118; // 1 - 2 A2
    pub(super) const R7_W2: f64 = 0.066_197_076_394_253_090_368_825;
}
use radon_digits::*;
const R7_C: f64 = 1.0 / 3.0;

const RADON_7_POINTS: [[f64; 2]; 7] = [
    [R7_C, R7_C],
    [R7_A1, R7_A1],
    [R7_B1, R7_A1],
    [R7_A1, R7_B1],
    [R7_A2, R7_A2],
    [R7_B2, R7_A2],
    [R7_A2, R7_B2],
];
const RADON_7_WEIGHTS: [f64; 7] = [9.0 / 80.0, R7_W1, R7_W1, R7_W1, R7_W2, R7_W2, R7_W2];

/// 7-point triangle rule exact for degree 5 with positive weights (Radon 1948). The pressure
/// load of a curved 6-node face (integrand `N_i dx/ds x dx/dt`, degree 4) is exact with it.
pub const RADON_7: FaceRule = FaceRule {
    degree: 5,
    points: &RADON_7_POINTS,
    weights: &RADON_7_WEIGHTS,
};

#[cfg(test)]
// Index loops mirror the index notation of the formulas being checked.
#[allow(clippy::needless_range_loop)]
mod tests {
    use super::*;
    use crate::mesh::TET10_FACES;

    fn factorial(n: u32) -> f64 {
        (1..=n).map(f64::from).product()
    }

    /// Exact integral of xi^a eta^b zeta^c over the reference tetrahedron.
    fn tet_monomial_integral(a: u32, b: u32, c: u32) -> f64 {
        factorial(a) * factorial(b) * factorial(c) / factorial(a + b + c + 3)
    }

    /// Exact integral of s^a t^b over the reference triangle.
    fn triangle_monomial_integral(a: u32, b: u32) -> f64 {
        factorial(a) * factorial(b) / factorial(a + b + 2)
    }

    /// Some points inside and outside the reference cell (the polynomial identities hold
    /// everywhere, not just inside).
    fn sample_points() -> Vec<[f64; 3]> {
        vec![
            [0.1, 0.2, 0.3],
            [0.25, 0.25, 0.25],
            [0.7, 0.05, 0.1],
            [0.0, 0.0, 0.0],
            [0.33, 0.61, 0.02],
            [-0.3, 1.2, 0.4],
        ]
    }

    #[test]
    fn tet_shape_functions_are_a_partition_of_unity() {
        for p in sample_points() {
            let sum: f64 = shape(p).iter().sum();
            assert!((sum - 1.0).abs() < 1e-14, "sum {sum} at {p:?}");
            let g = shape_gradients(p);
            for j in 0..3 {
                let s: f64 = g.iter().map(|gi| gi[j]).sum();
                assert!(s.abs() < 1e-13, "gradient sum {s} at {p:?}");
            }
        }
    }

    #[test]
    fn tet_shape_functions_are_lagrangian_on_the_node_order_of_the_mesh() {
        // Mid nodes are the mid-points of the edges of TET10_EDGES.
        for (m, [a, b]) in TET10_EDGES.iter().enumerate() {
            for j in 0..3 {
                let mid = 0.5 * (NODE_COORDINATES[*a][j] + NODE_COORDINATES[*b][j]);
                assert_eq!(NODE_COORDINATES[4 + m][j], mid);
            }
        }
        for (j, p) in NODE_COORDINATES.iter().enumerate() {
            let n = shape(*p);
            for (i, ni) in n.iter().enumerate() {
                let delta = if i == j { 1.0 } else { 0.0 };
                assert!((ni - delta).abs() < 1e-15, "N_{i}(node {j}) = {ni}");
            }
        }
    }

    #[test]
    fn tet_gradients_match_central_differences() {
        // Central differences are exact for quadratics, so only round-off remains:
        // about eps * |N| / h = 1e-16 / 1e-5 = 1e-11.
        let h = 1e-5;
        for p in sample_points() {
            let g = shape_gradients(p);
            for j in 0..3 {
                let mut pp = p;
                let mut pm = p;
                pp[j] += h;
                pm[j] -= h;
                let (np, nm) = (shape(pp), shape(pm));
                for i in 0..NODES {
                    let fd = (np[i] - nm[i]) / (2.0 * h);
                    assert!(
                        (fd - g[i][j]).abs() < 1e-9,
                        "dN{i}/dp{j}: {fd} vs {}",
                        g[i][j]
                    );
                }
            }
        }
    }

    #[test]
    fn face_shape_functions_are_a_partition_of_unity_and_lagrangian() {
        for q in [[0.2, 0.3], [1.0 / 3.0, 1.0 / 3.0], [0.9, 0.05], [-0.2, 1.1]] {
            let sum: f64 = face_shape(q).iter().sum();
            assert!((sum - 1.0).abs() < 1e-14);
            let d = face_shape_derivatives(q);
            for j in 0..2 {
                assert!(d.iter().map(|di| di[j]).sum::<f64>().abs() < 1e-13);
            }
        }
        for (m, [a, b]) in FACE_EDGES.iter().enumerate() {
            for j in 0..2 {
                let mid = 0.5 * (FACE_NODE_COORDINATES[*a][j] + FACE_NODE_COORDINATES[*b][j]);
                assert_eq!(FACE_NODE_COORDINATES[3 + m][j], mid);
            }
        }
        for (j, q) in FACE_NODE_COORDINATES.iter().enumerate() {
            for (i, ni) in face_shape(*q).iter().enumerate() {
                let delta = if i == j { 1.0 } else { 0.0 };
                assert!((ni - delta).abs() < 1e-15, "N_{i}(face node {j}) = {ni}");
            }
        }
    }

    #[test]
    fn face_derivatives_match_central_differences() {
        let h = 1e-5;
        for q in [[0.2, 0.3], [0.05, 0.8], [0.6, 0.1]] {
            let d = face_shape_derivatives(q);
            for j in 0..2 {
                let mut qp = q;
                let mut qm = q;
                qp[j] += h;
                qm[j] -= h;
                let (np, nm) = (face_shape(qp), face_shape(qm));
                for i in 0..FACE_NODES {
                    let fd = (np[i] - nm[i]) / (2.0 * h);
                    assert!((fd - d[i][j]).abs() < 1e-9);
                }
            }
        }
    }

    #[test]
    fn tet_shape_functions_restricted_to_a_face_are_the_face_shape_functions() {
        // On face f, the point q = (s, t) is p = P_a + s (P_b - P_a) + t (P_c - P_a). The tet's
        // face nodes must carry the triangle's functions in TET10_FACES order, the other four
        // nodes must vanish: this ties the triangle numbering to the mesh's face table.
        for face in TET10_FACES {
            let corner = |k: usize| NODE_COORDINATES[face[k]];
            for q in [[0.2, 0.3], [0.7, 0.1], [0.15, 0.6]] {
                let p: [f64; 3] = std::array::from_fn(|j| {
                    corner(0)[j]
                        + q[0] * (corner(1)[j] - corner(0)[j])
                        + q[1] * (corner(2)[j] - corner(0)[j])
                });
                let n_tet = shape(p);
                let n_face = face_shape(q);
                for (k, node) in face.iter().enumerate() {
                    assert!((n_tet[*node] - n_face[k]).abs() < 1e-14);
                }
                for i in (0..NODES).filter(|i| !face.contains(i)) {
                    assert!(n_tet[i].abs() < 1e-14, "node {i} off face {face:?}");
                }
            }
        }
    }

    fn check_tet_rule(rule: &Rule) {
        assert_eq!(rule.points.len(), rule.weights.len());
        let total: f64 = rule.weights.iter().sum();
        assert!((total - 1.0 / 6.0).abs() < 1e-15, "weights sum {total}");
        for (p, w) in rule.points.iter().zip(rule.weights) {
            assert!(*w > 0.0);
            let l = barycentric(*p);
            assert!(l.iter().all(|&x| x > 0.0), "point {p:?} not inside");
        }
        // Every monomial up to the claimed degree. All weights are positive and the
        // integrand is non-negative on the cell, so the sum has no cancellation: the error is
        // a few ulps of the result (14 terms -> 1e-14 relative is generous).
        for a in 0..=rule.degree {
            for b in 0..=rule.degree - a {
                for c in 0..=rule.degree - a - b {
                    let q: f64 = rule
                        .points
                        .iter()
                        .zip(rule.weights)
                        .map(|(p, w)| {
                            w * p[0].powi(a as i32) * p[1].powi(b as i32) * p[2].powi(c as i32)
                        })
                        .sum();
                    let exact = tet_monomial_integral(a, b, c);
                    assert!(
                        ((q - exact) / exact).abs() < 1e-14,
                        "x^{a} y^{b} z^{c}: {q} vs {exact}"
                    );
                }
            }
        }
    }

    /// The rule is not exact one degree higher (so the claimed degree is the real one).
    fn check_tet_rule_degree_is_sharp(rule: &Rule) {
        let d = rule.degree + 1;
        let mut worst: f64 = 0.0;
        for a in 0..=d {
            for b in 0..=d - a {
                let c = d - a - b;
                let q: f64 = rule
                    .points
                    .iter()
                    .zip(rule.weights)
                    .map(|(p, w)| {
                        w * p[0].powi(a as i32) * p[1].powi(b as i32) * p[2].powi(c as i32)
                    })
                    .sum();
                let exact = tet_monomial_integral(a, b, c);
                worst = worst.max(((q - exact) / exact).abs());
            }
        }
        assert!(worst > 1e-6, "rule is exact to degree {d} too");
    }

    #[test]
    fn gauss_4_is_exact_to_degree_2() {
        // Closed forms of the abscissae.
        let s5 = 5f64.sqrt();
        assert!((G4_A - (5.0 + 3.0 * s5) / 20.0).abs() < 1e-16);
        assert!((G4_B - (5.0 - s5) / 20.0).abs() < 1e-16);
        check_tet_rule(&GAUSS_4);
        check_tet_rule_degree_is_sharp(&GAUSS_4);
    }

    #[test]
    fn walkington_14_is_exact_to_degree_5() {
        assert!((W14_B1 - (1.0 - 3.0 * W14_A1)).abs() < 1e-16);
        assert!((W14_B2 - (1.0 - 3.0 * W14_A2)).abs() < 1e-16);
        assert!((W14_B3 - (0.5 - W14_A3)).abs() < 1e-16);
        check_tet_rule(&WALKINGTON_14);
        check_tet_rule_degree_is_sharp(&WALKINGTON_14);
        // The six points of the third orbit are distinct and each has two coordinates
        // (of four barycentric ones) equal to A3.
        for p in &WALKINGTON_14_POINTS[8..] {
            let l = barycentric(*p);
            let n_a3 = l.iter().filter(|&&x| (x - W14_A3).abs() < 1e-15).count();
            assert_eq!(n_a3, 2, "{l:?}");
        }
        for i in 0..14 {
            for j in 0..i {
                assert_ne!(WALKINGTON_14_POINTS[i], WALKINGTON_14_POINTS[j]);
            }
        }
    }

    #[test]
    fn radon_7_matches_its_closed_form() {
        let s15 = 15f64.sqrt();
        let close = |a: f64, b: f64| (a - b).abs() < 2e-16;
        assert!(close(R7_A1, (6.0 - s15) / 21.0));
        assert!(close(R7_B1, (9.0 + 2.0 * s15) / 21.0));
        assert!(close(R7_W1, (155.0 - s15) / 2400.0));
        assert!(close(R7_A2, (6.0 + s15) / 21.0));
        assert!(close(R7_B2, (9.0 - 2.0 * s15) / 21.0));
        assert!(close(R7_W2, (155.0 + s15) / 2400.0));
    }

    #[test]
    fn radon_7_is_exact_to_degree_5() {
        let rule = &RADON_7;
        let total: f64 = rule.weights.iter().sum();
        assert!((total - 0.5).abs() < 1e-15);
        for (q, w) in rule.points.iter().zip(rule.weights) {
            assert!(*w > 0.0);
            assert!(face_barycentric(*q).iter().all(|&x| x > 0.0));
        }
        let integrate = |a: u32, b: u32| -> f64 {
            rule.points
                .iter()
                .zip(rule.weights)
                .map(|(q, w)| w * q[0].powi(a as i32) * q[1].powi(b as i32))
                .sum()
        };
        for a in 0..=rule.degree {
            for b in 0..=rule.degree - a {
                let exact = triangle_monomial_integral(a, b);
                let q = integrate(a, b);
                assert!(
                    ((q - exact) / exact).abs() < 1e-14,
                    "s^{a} t^{b}: {q} vs {exact}"
                );
            }
        }
        // ... and not to degree 6.
        let worst = (0..=6)
            .map(|a| {
                let exact = triangle_monomial_integral(a, 6 - a);
                ((integrate(a, 6 - a) - exact) / exact).abs()
            })
            .fold(0.0, f64::max);
        assert!(worst > 1e-6);
    }
}
