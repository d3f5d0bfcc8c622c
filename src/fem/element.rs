//! Element matrices of the 10-node tetrahedron (isotropic linear elasticity, small strain)
//! and the consistent loads of its 6-node faces.
//!
//! Conventions:
//! - element coordinates `x: &[[f64; 3]; 10]` in the internal node order
//!   ([`crate::mesh::TET10_EDGES`]); face coordinates `x: &[[f64; 3]; 6]` in the order of a row
//!   of [`crate::mesh::TET10_FACES`] (corners a, b, c, then mid(a,b), mid(b,c), mid(c,a)).
//! - DOF order of an element matrix is node-major: row `3 * node + component`.
//! - Stiffness by the 4-point Gauss rule (as Abaqus/CalculiX C3D10), exact for straight-sided
//!   elements; consistent mass by a degree-5 rule by default ([`MassRule::Exact`]), exact for
//!   straight-sided elements, or by the 4-point rule ([`MassRule::Gauss4`]) to reproduce
//!   CalculiX/Abaqus numbers.
//! - The Jacobian determinant is checked at the ten nodes and at every quadrature point used:
//!   a value `<= 0` (or NaN) means an inverted, folded, degenerate or wrongly numbered element
//!   and is an error, never a silently wrong matrix. The node check matters: the 4-point rule
//!   alone does not see every folded element (see the test
//!   `corners_swapped_without_their_mid_nodes_are_caught_at_the_nodes`).
//!
//! Nothing here allocates: the assembly calls these routines once per element.

use crate::fem::tet10::{self, Rule, GAUSS_4, RADON_7, WALKINGTON_14};
use crate::vector3::cross;

/// Degrees of freedom of one element (10 nodes x 3 components).
pub const DOFS: usize = 30;

/// A dense element matrix, rows and columns in node-major DOF order (`3 * node + component`).
pub type ElementMatrix = [[f64; DOFS]; DOFS];

/// Errors of the element routines. The assembly adds the element label and the file.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
pub enum ElementError {
    /// The Jacobian determinant is zero, negative or not a number at a quadrature point: the
    /// element is inverted or degenerate, or its nodes are numbered in another convention
    /// (e.g. Gmsh's order not converted). `point` indexes the points of the rule used.
    #[error(
        "Jacobian determinant {det:e} at integration point {point} is not positive \
         (inverted or degenerate element, or wrong node order)"
    )]
    NonPositiveJacobian { point: usize, det: f64 },
    /// The Jacobian determinant is zero, negative or not a number at one of the element's
    /// ten nodes (0..=9, internal order): the element map folds over itself there. Two
    /// corners swapped without their mid nodes give such an element that still has a
    /// positive determinant at all four Gauss points.
    #[error(
        "Jacobian determinant {det:e} at element node {node} is not positive \
         (folded element: corners or mid nodes out of place, or wrong node order)"
    )]
    NonPositiveJacobianAtNode { node: usize, det: f64 },
    /// A material constant outside its physical range.
    #[error("{property} = {value} is not allowed: {requirement}")]
    InvalidMaterial {
        property: &'static str,
        value: f64,
        requirement: &'static str,
    },
}

/// Quadrature of the consistent mass matrix.
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    serde::Serialize,
    serde::Deserialize,
    clap::ValueEnum,
)]
#[serde(rename_all = "lowercase")]
pub enum MassRule {
    /// 14-point degree-5 rule ([`tet10::WALKINGTON_14`]): exact for straight-sided elements.
    #[default]
    #[value(help = "a 14-point rule, exact for straight-sided elements")]
    Exact,
    /// The 4-point Gauss rule ([`tet10::GAUSS_4`]) that CalculiX and Abaqus use, so that
    /// frequencies can be matched to theirs. Not exact for the degree-4 mass integrand, but it
    /// still gives the exact total mass of a straight-sided element.
    #[value(help = "the 4-point Gauss rule CalculiX and Abaqus use (to match their frequencies)")]
    Gauss4,
}

impl MassRule {
    /// The quadrature rule this choice stands for.
    pub fn rule(self) -> &'static Rule {
        match self {
            MassRule::Exact => &WALKINGTON_14,
            MassRule::Gauss4 => &GAUSS_4,
        }
    }
}

/// Lamé constants (lambda, mu) of an isotropic material, checking `E > 0` and
/// `-1 < nu < 1/2` (the range in which the elasticity tensor is positive definite).
pub fn lame(young: f64, poisson: f64) -> Result<(f64, f64), ElementError> {
    // NaN is not finite, so it fails the first check, and it fails the second explicitly.
    if young <= 0.0 || !young.is_finite() {
        return Err(ElementError::InvalidMaterial {
            property: "Young's modulus",
            value: young,
            requirement: "it must be positive and finite",
        });
    }
    if poisson.is_nan() || poisson <= -1.0 || poisson >= 0.5 {
        return Err(ElementError::InvalidMaterial {
            property: "Poisson's ratio",
            value: poisson,
            requirement: "it must lie strictly between -1 and 0.5",
        });
    }
    let mu = young / (2.0 * (1.0 + poisson));
    let lambda = young * poisson / ((1.0 + poisson) * (1.0 - 2.0 * poisson));
    Ok((lambda, mu))
}

/// The Jacobian `J[i][j] = dx_i / dp_j` of the element map at a point whose shape-function
/// gradients are `dn`.
fn jacobian(x: &[[f64; 3]; 10], dn: &[[f64; 3]; 10]) -> [[f64; 3]; 3] {
    let mut j = [[0.0; 3]; 3];
    for (xa, ga) in x.iter().zip(dn) {
        for r in 0..3 {
            for c in 0..3 {
                j[r][c] += xa[r] * ga[c];
            }
        }
    }
    j
}

/// Cofactor matrix and determinant of a 3x3 matrix (`J^-T = cofactor / det`).
fn cofactor_and_det(j: &[[f64; 3]; 3]) -> ([[f64; 3]; 3], f64) {
    let c = [
        [
            j[1][1] * j[2][2] - j[1][2] * j[2][1],
            j[1][2] * j[2][0] - j[1][0] * j[2][2],
            j[1][0] * j[2][1] - j[1][1] * j[2][0],
        ],
        [
            j[0][2] * j[2][1] - j[0][1] * j[2][2],
            j[0][0] * j[2][2] - j[0][2] * j[2][0],
            j[0][1] * j[2][0] - j[0][0] * j[2][1],
        ],
        [
            j[0][1] * j[1][2] - j[0][2] * j[1][1],
            j[0][2] * j[1][0] - j[0][0] * j[1][2],
            j[0][0] * j[1][1] - j[0][1] * j[1][0],
        ],
    ];
    let det = j[0][0] * c[0][0] + j[0][1] * c[0][1] + j[0][2] * c[0][2];
    (c, det)
}

/// Determinant of the Jacobian of the element map at parametric point `p` (positive for a
/// valid element). Useful for mesh-quality checks at nodes as well as at quadrature points.
pub fn jacobian_determinant(x: &[[f64; 3]; 10], p: [f64; 3]) -> f64 {
    cofactor_and_det(&jacobian(x, &tet10::shape_gradients(p))).1
}

/// Checks that `det J > 0` at the ten nodes of the element (corners and mid-edge nodes), the
/// usual validity test of a quadratic element: a valid element's map is one-to-one on the
/// closed element, so its determinant is positive there too. [`stiffness`], [`mass`] and
/// [`volume`] call it first.
pub fn check_node_jacobians(x: &[[f64; 3]; 10]) -> Result<(), ElementError> {
    for (node, p) in tet10::NODE_COORDINATES.iter().enumerate() {
        // NaN (from non-finite coordinates) is refused as well.
        let det = jacobian_determinant(x, *p);
        if det <= 0.0 || det.is_nan() {
            return Err(ElementError::NonPositiveJacobianAtNode { node, det });
        }
    }
    Ok(())
}

/// Physical gradients `dN_a/dx` and `det J` at quadrature point number `point` of a rule.
fn physical_gradients(
    x: &[[f64; 3]; 10],
    p: [f64; 3],
    point: usize,
) -> Result<([[f64; 3]; 10], f64), ElementError> {
    let dn = tet10::shape_gradients(p);
    let (c, det) = cofactor_and_det(&jacobian(x, &dn));
    // NaN (from non-finite coordinates) is refused as well.
    if det <= 0.0 || det.is_nan() {
        return Err(ElementError::NonPositiveJacobian { point, det });
    }
    let inv = 1.0 / det;
    let mut g = [[0.0; 3]; 10];
    for (ga, da) in g.iter_mut().zip(&dn) {
        for (i, gai) in ga.iter_mut().enumerate() {
            *gai = (c[i][0] * da[0] + c[i][1] * da[1] + c[i][2] * da[2]) * inv;
        }
    }
    Ok((g, det))
}

/// The stress (xx, yy, zz, yz, xz, xy) of an isotropic material at parametric point `p` of
/// an element with nodal displacements `u`: sigma = lambda tr(eps) I + 2 mu eps, eps the
/// symmetric gradient of u. Recovered at the nodes, it is discontinuous between elements.
pub fn stress_at(
    x: &[[f64; 3]; 10],
    u: &[[f64; 3]; 10],
    p: [f64; 3],
    lambda: f64,
    mu: f64,
) -> Result<[f64; 6], ElementError> {
    let (g, _) = physical_gradients(x, p, 0)?;
    // grad u [i][j] = du_i / dx_j
    let mut h = [[0.0; 3]; 3];
    for (ua, ga) in u.iter().zip(&g) {
        for i in 0..3 {
            for j in 0..3 {
                h[i][j] += ua[i] * ga[j];
            }
        }
    }
    let e = |i: usize, j: usize| 0.5 * (h[i][j] + h[j][i]);
    let trace = h[0][0] + h[1][1] + h[2][2];
    Ok([
        lambda * trace + 2.0 * mu * e(0, 0),
        lambda * trace + 2.0 * mu * e(1, 1),
        lambda * trace + 2.0 * mu * e(2, 2),
        2.0 * mu * e(1, 2),
        2.0 * mu * e(0, 2),
        2.0 * mu * e(0, 1),
    ])
}

/// The von Mises equivalent of a stress (xx, yy, zz, yz, xz, xy).
pub fn von_mises(s: [f64; 6]) -> f64 {
    let d = (s[0] - s[1]).powi(2) + (s[1] - s[2]).powi(2) + (s[2] - s[0]).powi(2);
    (0.5 * d + 3.0 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5])).sqrt()
}

/// `det J` at quadrature point number `point`, checked positive.
fn checked_determinant(x: &[[f64; 3]; 10], p: [f64; 3], point: usize) -> Result<f64, ElementError> {
    let det = jacobian_determinant(x, p);
    if det <= 0.0 || det.is_nan() {
        return Err(ElementError::NonPositiveJacobian { point, det });
    }
    Ok(det)
}

/// Copies the upper triangle onto the lower one, so the matrix is symmetric to the bit.
fn mirror_upper(k: &mut ElementMatrix) {
    for r in 1..DOFS {
        let (upper, lower) = k.split_at_mut(r);
        for (c, row) in upper.iter().enumerate() {
            lower[0][c] = row[r];
        }
    }
}

/// Stiffness matrix of isotropic linear elasticity (4-point Gauss), node-major DOF order.
///
/// `K[3a+i][3b+j] = sum_q w_q det J (lambda g_a,i g_b,j + mu g_a,j g_b,i + mu delta_ij g_a.g_b)`
/// with `g_a = dN_a/dx`. Exact for straight-sided elements. On curved elements the 4-point
/// rule is not exact: a linear displacement field is then reproduced only to the
/// discretisation error (as in CalculiX/Abaqus C3D10), not to round-off.
pub fn stiffness(
    x: &[[f64; 3]; 10],
    young: f64,
    poisson: f64,
) -> Result<ElementMatrix, ElementError> {
    stiffness_with_rule(x, young, poisson, &GAUSS_4)
}

/// [`stiffness`] with another quadrature rule. A rule of degree >= 3 integrates the internal
/// forces of a constant stress exactly on curved elements too (see the curved patch test).
pub fn stiffness_with_rule(
    x: &[[f64; 3]; 10],
    young: f64,
    poisson: f64,
    rule: &Rule,
) -> Result<ElementMatrix, ElementError> {
    let (lambda, mu) = lame(young, poisson)?;
    check_node_jacobians(x)?;
    let mut k = [[0.0; DOFS]; DOFS];
    for (q, (p, w)) in rule.points.iter().zip(rule.weights).enumerate() {
        let (g, det) = physical_gradients(x, *p, q)?;
        let f = w * det;
        let (fl, fm) = (f * lambda, f * mu);
        for a in 0..10 {
            let ga = g[a];
            for b in a..10 {
                let gb = g[b];
                let shear = fm * (ga[0] * gb[0] + ga[1] * gb[1] + ga[2] * gb[2]);
                for i in 0..3 {
                    // Only the upper triangle; `mirror_upper` fills the rest.
                    let j0 = if a == b { i } else { 0 };
                    let row = &mut k[3 * a + i];
                    for j in j0..3 {
                        let mut v = fl * ga[i] * gb[j] + fm * ga[j] * gb[i];
                        if i == j {
                            v += shear;
                        }
                        row[3 * b + j] += v;
                    }
                }
            }
        }
    }
    mirror_upper(&mut k);
    Ok(k)
}

/// Consistent mass matrix `M[3a+i][3b+j] = delta_ij rho int N_a N_b dV`, node-major DOF
/// order, integrated with `rule`. `density` must be finite and `>= 0`.
pub fn mass(
    x: &[[f64; 3]; 10],
    density: f64,
    rule: MassRule,
) -> Result<ElementMatrix, ElementError> {
    let m = scalar_mass(x, density, rule)?;
    let mut full = [[0.0; DOFS]; DOFS];
    for a in 0..10 {
        for b in 0..10 {
            for i in 0..3 {
                full[3 * a + i][3 * b + i] = m[a][b];
            }
        }
    }
    Ok(full)
}

/// The scalar consistent mass `rho int N_a N_b dV` (10 x 10, symmetric): the element's mass
/// matrix is this on each of the three displacement components. `density` must be finite
/// and `>= 0`.
pub fn scalar_mass(
    x: &[[f64; 3]; 10],
    density: f64,
    rule: MassRule,
) -> Result<[[f64; 10]; 10], ElementError> {
    if density < 0.0 || !density.is_finite() {
        return Err(ElementError::InvalidMaterial {
            property: "density",
            value: density,
            requirement: "it must be finite and not negative",
        });
    }
    check_node_jacobians(x)?;
    let rule = rule.rule();
    let mut m = [[0.0; 10]; 10];
    for (q, (p, w)) in rule.points.iter().zip(rule.weights).enumerate() {
        let det = checked_determinant(x, *p, q)?;
        let n = tet10::shape(*p);
        let f = density * w * det;
        for a in 0..10 {
            let fa = f * n[a];
            for b in a..10 {
                m[a][b] += fa * n[b];
            }
        }
    }
    // The lower triangle from the upper.
    for a in 1..10 {
        let (upper, lower) = m.split_at_mut(a);
        for (b, row) in upper.iter().enumerate() {
            lower[0][b] = row[a];
        }
    }
    Ok(m)
}

/// Volume of the (possibly curved) element, `int det J dp`, exact (det J is a cubic and the
/// rule has degree 5). Errors if `det J <= 0` at a node or at any of the rule's points.
pub fn volume(x: &[[f64; 3]; 10]) -> Result<f64, ElementError> {
    check_node_jacobians(x)?;
    let rule = &WALKINGTON_14;
    let mut v = 0.0;
    for (q, (p, w)) in rule.points.iter().zip(rule.weights).enumerate() {
        v += w * checked_determinant(x, *p, q)?;
    }
    Ok(v)
}

/// Position on a 6-node face at face parametric point `q = [s, t]`.
pub fn face_point(x: &[[f64; 3]; 6], q: [f64; 2]) -> [f64; 3] {
    let n = tet10::face_shape(q);
    let mut p = [0.0; 3];
    for (xa, na) in x.iter().zip(n) {
        for i in 0..3 {
            p[i] += na * xa[i];
        }
    }
    p
}

/// Tangents `dx/ds` and `dx/dt` of a 6-node face at `q`.
pub fn face_tangents(x: &[[f64; 3]; 6], q: [f64; 2]) -> ([f64; 3], [f64; 3]) {
    let d = tet10::face_shape_derivatives(q);
    let mut ts = [0.0; 3];
    let mut tt = [0.0; 3];
    for (xa, da) in x.iter().zip(d) {
        for i in 0..3 {
            ts[i] += da[0] * xa[i];
            tt[i] += da[1] * xa[i];
        }
    }
    (ts, tt)
}

/// `dx/ds x dx/dt` at `q`: the outward normal scaled by the area element, so that
/// `dA = |.| ds dt` and `int n dA = int (dx/ds x dx/dt) ds dt`.
pub fn face_area_vector_at(x: &[[f64; 3]; 6], q: [f64; 2]) -> [f64; 3] {
    let (ts, tt) = face_tangents(x, q);
    cross(ts, tt)
}

/// Unit outward normal of a 6-node face at `q`, or `None` where the face is degenerate
/// (zero or non-finite area element).
pub fn face_normal_at(x: &[[f64; 3]; 6], q: [f64; 2]) -> Option<[f64; 3]> {
    let a = face_area_vector_at(x, q);
    let len = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    (len > 0.0 && len.is_finite()).then(|| a.map(|c| c / len))
}

/// Area of a (possibly curved) 6-node face by the 7-point rule: exact for a flat face with
/// straight edges; on a curved face `|dx/ds x dx/dt|` is not a polynomial and the result is
/// an approximation (contact tributary areas use flat sub-triangles instead, see METHOD.md).
pub fn face_area(x: &[[f64; 3]; 6]) -> f64 {
    RADON_7
        .points
        .iter()
        .zip(RADON_7.weights)
        .map(|(q, w)| {
            let a = face_area_vector_at(x, *q);
            w * (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
        })
        .sum()
}

/// Consistent nodal forces of a uniform pressure on a 6-node face:
/// `f_a = -p int N_a n dA = -p int N_a (dx/ds x dx/dt) ds dt`, so a positive pressure pushes
/// into the body (the normal of the face order points out). The integrand is a polynomial of
/// degree 4 in (s, t) and the 7-point rule is exact for it, curved faces included. On a flat
/// face with straight edges the corners get nothing and each mid-side node `-p n A / 3`.
pub fn face_pressure_load(x: &[[f64; 3]; 6], pressure: f64) -> [[f64; 3]; 6] {
    let mut f = [[0.0; 3]; 6];
    for (q, w) in RADON_7.points.iter().zip(RADON_7.weights) {
        let a = face_area_vector_at(x, *q);
        let n = tet10::face_shape(*q);
        for (fa, na) in f.iter_mut().zip(n) {
            let s = -pressure * w * na;
            for i in 0..3 {
                fa[i] += s * a[i];
            }
        }
    }
    f
}

#[cfg(test)]
// Index loops mirror the index notation of the formulas being checked.
#[allow(clippy::needless_range_loop)]
mod tests {
    use super::*;
    use crate::mesh::{TET10_EDGES, TET10_FACES};
    use std::collections::BTreeMap;

    const E: f64 = 210e9;
    const NU: f64 = 0.3;
    const RHO: f64 = 7850.0;

    fn with_mid_nodes(c: [[f64; 3]; 4]) -> [[f64; 3]; 10] {
        let mut x = [[0.0; 3]; 10];
        x[..4].copy_from_slice(&c);
        for (m, [a, b]) in TET10_EDGES.iter().enumerate() {
            x[4 + m] = std::array::from_fn(|i| 0.5 * (c[*a][i] + c[*b][i]));
        }
        x
    }

    fn reference_element() -> [[f64; 3]; 10] {
        with_mid_nodes([
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ])
    }

    /// A straight-sided element far from the reference shape.
    fn skewed_element() -> [[f64; 3]; 10] {
        with_mid_nodes([
            [0.1, -0.2, 0.05],
            [1.7, 0.1, -0.1],
            [0.3, 1.2, 0.2],
            [0.2, 0.4, 1.1],
        ])
    }

    /// The skewed element with every mid node moved off its edge (curved edges and faces).
    fn curved_element() -> [[f64; 3]; 10] {
        let mut x = skewed_element();
        let offsets = [
            [0.05, -0.03, 0.02],
            [-0.04, 0.06, 0.03],
            [0.02, 0.03, -0.05],
            [-0.03, -0.02, 0.04],
            [0.06, 0.01, -0.02],
            [-0.02, 0.05, 0.03],
        ];
        for (m, d) in offsets.iter().enumerate() {
            for i in 0..3 {
                x[4 + m][i] += d[i];
            }
        }
        x
    }

    fn face_coordinates(x: &[[f64; 3]; 10], side: usize) -> [[f64; 3]; 6] {
        TET10_FACES[side].map(|k| x[k])
    }

    /// Volume as one third of the flux of x through the four faces (divergence theorem):
    /// `V = 1/3 sum_faces int x . (dx/ds x dx/dt) ds dt`. The integrand has degree 4 and the
    /// 7-point triangle rule is exact for it, so this is an independent exact volume.
    fn volume_from_faces(x: &[[f64; 3]; 10]) -> f64 {
        let mut v = 0.0;
        for side in 0..4 {
            let xf = face_coordinates(x, side);
            for (q, w) in RADON_7.points.iter().zip(RADON_7.weights) {
                let p = face_point(&xf, *q);
                let a = face_area_vector_at(&xf, *q);
                v += w * (p[0] * a[0] + p[1] * a[1] + p[2] * a[2]) / 3.0;
            }
        }
        v
    }

    fn max_abs(k: &ElementMatrix) -> f64 {
        k.iter().flatten().fold(0.0, |m, v| m.max(v.abs()))
    }

    fn mat_vec(k: &ElementMatrix, u: &[f64; DOFS]) -> [f64; DOFS] {
        std::array::from_fn(|r| (0..DOFS).map(|c| k[r][c] * u[c]).sum())
    }

    fn dot30(a: &[f64; DOFS], b: &[f64; DOFS]) -> f64 {
        a.iter().zip(b).map(|(x, y)| x * y).sum()
    }

    /// Nodal values of a displacement field given as a function of position.
    fn interpolate(x: &[[f64; 3]; 10], f: impl Fn([f64; 3]) -> [f64; 3]) -> [f64; DOFS] {
        let mut u = [0.0; DOFS];
        for (a, xa) in x.iter().enumerate() {
            u[3 * a..3 * a + 3].copy_from_slice(&f(*xa));
        }
        u
    }

    /// The six rigid-body motions: three translations and three infinitesimal rotations about
    /// the element's first corner.
    fn rigid_body_modes(x: &[[f64; 3]; 10]) -> Vec<[f64; DOFS]> {
        let o = x[0];
        let mut modes = Vec::new();
        for i in 0..3 {
            modes.push(interpolate(x, |_| {
                std::array::from_fn(|k| f64::from(u8::from(k == i)))
            }));
        }
        for i in 0..3 {
            let w: [f64; 3] = std::array::from_fn(|k| f64::from(u8::from(k == i)));
            modes.push(interpolate(x, |p| {
                cross(w, [p[0] - o[0], p[1] - o[1], p[2] - o[2]])
            }));
        }
        modes
    }

    /// Eigenvalues (ascending) of a symmetric matrix by the cyclic Jacobi method. Jacobi
    /// rotations are orthogonal, so the eigenvalues come out with an absolute error of a few
    /// eps * ||A||, enough to tell round-off zeros from the smallest elastic eigenvalue.
    fn symmetric_eigenvalues(a: &ElementMatrix) -> Vec<f64> {
        let n = DOFS;
        let mut a: Vec<Vec<f64>> = a.iter().map(|r| r.to_vec()).collect();
        let norm = a.iter().flatten().map(|v| v * v).sum::<f64>().sqrt();
        for _sweep in 0..100 {
            let off: f64 = (0..n)
                .flat_map(|p| (p + 1..n).map(move |q| (p, q)))
                .map(|(p, q)| a[p][q] * a[p][q])
                .sum::<f64>()
                .sqrt();
            if off <= 1e-15 * norm {
                break;
            }
            for p in 0..n {
                for q in p + 1..n {
                    if a[p][q] == 0.0 {
                        continue;
                    }
                    let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
                    let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
                    let c = 1.0 / (t * t + 1.0).sqrt();
                    let s = t * c;
                    for row in a.iter_mut() {
                        let (akp, akq) = (row[p], row[q]);
                        row[p] = c * akp - s * akq;
                        row[q] = s * akp + c * akq;
                    }
                    for k in 0..n {
                        let (apk, aqk) = (a[p][k], a[q][k]);
                        a[p][k] = c * apk - s * aqk;
                        a[q][k] = s * apk + c * aqk;
                    }
                }
            }
        }
        let mut eig: Vec<f64> = (0..n).map(|i| a[i][i]).collect();
        eig.sort_by(f64::total_cmp);
        eig
    }

    #[test]
    fn jacobi_eigenvalues_of_a_known_matrix() {
        // diag(1..30) rotated by a Householder reflection H = I - 2 v v^T / v.v (orthogonal),
        // so the eigenvalues must come back as 1..30.
        let v: [f64; DOFS] = std::array::from_fn(|i| (i as f64 * 0.7).sin() + 0.1);
        let vv: f64 = v.iter().map(|x| x * x).sum();
        let h: ElementMatrix = std::array::from_fn(|i| {
            std::array::from_fn(|j| f64::from(u8::from(i == j)) - 2.0 * v[i] * v[j] / vv)
        });
        let a: ElementMatrix = std::array::from_fn(|i| {
            std::array::from_fn(|j| (0..DOFS).map(|k| h[i][k] * (k + 1) as f64 * h[k][j]).sum())
        });
        for (k, l) in symmetric_eigenvalues(&a).iter().enumerate() {
            assert!((l - (k + 1) as f64).abs() < 1e-12, "{k}: {l}");
        }
    }

    #[test]
    fn stiffness_is_symmetric_with_a_positive_diagonal() {
        for x in [reference_element(), skewed_element(), curved_element()] {
            let k = stiffness(&x, E, NU).unwrap();
            for r in 0..DOFS {
                assert!(k[r][r] > 0.0);
                for c in 0..DOFS {
                    assert_eq!(k[r][c], k[c][r]);
                }
            }
        }
    }

    #[test]
    fn rigid_body_motions_have_zero_energy() {
        // K u for a rigid motion is a sum of terms |K| |u| that cancel exactly in exact
        // arithmetic: what remains is round-off, a few hundred eps relative to |K| |u|.
        for x in [reference_element(), skewed_element(), curved_element()] {
            let k = stiffness(&x, E, NU).unwrap();
            let scale = max_abs(&k);
            for u in rigid_body_modes(&x) {
                let umax = u.iter().fold(0.0, |m: f64, v| m.max(v.abs()));
                let ku = mat_vec(&k, &u);
                let worst = ku.iter().fold(0.0, |m: f64, v| m.max(v.abs()));
                assert!(
                    worst < 1e-13 * scale * umax,
                    "|K u| = {worst}, |K| = {scale}"
                );
            }
        }
    }

    #[test]
    fn stiffness_has_exactly_six_zero_eigenvalues() {
        for x in [reference_element(), skewed_element(), curved_element()] {
            let k = stiffness(&x, E, NU).unwrap();
            let eig = symmetric_eigenvalues(&k);
            let top = eig[DOFS - 1];
            // Six round-off zeros (|lambda| ~ eps |K|), then a clear gap: the smallest
            // deformation mode of these shapes is over 1e-3 of the largest.
            for l in &eig[..6] {
                assert!(l.abs() < 1e-12 * top, "{eig:?}");
            }
            assert!(eig[6] > 1e-3 * top, "7th eigenvalue {} of {top}", eig[6]);
        }
    }

    /// Constant strain and stress of the linear field u = A x: eps = sym(A),
    /// sigma = lambda tr(eps) I + 2 mu eps.
    fn constant_state(a: [[f64; 3]; 3]) -> ([[f64; 3]; 3], [[f64; 3]; 3]) {
        let (lambda, mu) = lame(E, NU).unwrap();
        let eps: [[f64; 3]; 3] =
            std::array::from_fn(|i| std::array::from_fn(|j| 0.5 * (a[i][j] + a[j][i])));
        let tr = eps[0][0] + eps[1][1] + eps[2][2];
        let sigma = std::array::from_fn(|i| {
            std::array::from_fn(|j| 2.0 * mu * eps[i][j] + if i == j { lambda * tr } else { 0.0 })
        });
        (eps, sigma)
    }

    const GRADIENT: [[f64; 3]; 3] = [
        [1.0e-3, 2.0e-3, -1.0e-3],
        [0.5e-3, -2.0e-3, 1.5e-3],
        [3.0e-3, 1.0e-3, 0.7e-3],
    ];

    #[test]
    fn constant_strain_energy_equals_volume_times_eps_c_eps() {
        // For a straight-sided element a linear field has constant strain, so
        // u^T K u = V eps : C : eps exactly (independent of any quadrature).
        let x = skewed_element();
        let k = stiffness(&x, E, NU).unwrap();
        let u = interpolate(&x, |p| {
            std::array::from_fn(|i| (0..3).map(|j| GRADIENT[i][j] * p[j]).sum::<f64>() + 0.01)
        });
        let (eps, sigma) = constant_state(GRADIENT);
        let density: f64 = (0..3)
            .flat_map(|i| (0..3).map(move |j| (i, j)))
            .map(|(i, j)| eps[i][j] * sigma[i][j])
            .sum();
        let c = [x[0], x[1], x[2], x[3]];
        let corner_volume = {
            let e = |k: usize| [c[k][0] - c[0][0], c[k][1] - c[0][1], c[k][2] - c[0][2]];
            let n = cross(e(2), e(3));
            (e(1)[0] * n[0] + e(1)[1] * n[1] + e(1)[2] * n[2]) / 6.0
        };
        let energy = dot30(&u, &mat_vec(&k, &u));
        let expect = corner_volume * density;
        assert!(
            ((energy - expect) / expect).abs() < 1e-13,
            "{energy} vs {expect}"
        );
    }

    #[test]
    fn constant_stress_gives_the_consistent_traction_loads() {
        // K u = int B^T sigma dV = sum over faces of int N_a sigma n dA (divergence theorem,
        // sigma constant). On flat straight faces the corners get nothing and each mid-side
        // node sigma n A / 3, per face it touches.
        let x = skewed_element();
        let k = stiffness(&x, E, NU).unwrap();
        let u = interpolate(&x, |p| {
            std::array::from_fn(|i| (0..3).map(|j| GRADIENT[i][j] * p[j]).sum())
        });
        let (_, sigma) = constant_state(GRADIENT);
        let mut expect = [0.0; DOFS];
        for face in TET10_FACES {
            // n A = (x_b - x_a) x (x_c - x_a) / 2, outward.
            let d = |k: usize| [0, 1, 2].map(|i| x[face[k]][i] - x[face[0]][i]);
            let na = cross(d(1), d(2)).map(|v| 0.5 * v);
            for mid in &face[3..] {
                for i in 0..3 {
                    expect[3 * mid + i] += (0..3).map(|j| sigma[i][j] * na[j]).sum::<f64>() / 3.0;
                }
            }
        }
        let ku = mat_vec(&k, &u);
        let scale = expect.iter().fold(0.0, |m: f64, v| m.max(v.abs()));
        for r in 0..DOFS {
            assert!(
                (ku[r] - expect[r]).abs() < 1e-12 * scale,
                "dof {r}: {} vs {}",
                ku[r],
                expect[r]
            );
        }
    }

    #[test]
    fn quadratic_fields_on_the_reference_element_match_closed_form_energies() {
        // On the reference element x = p, the strain of a quadratic field is linear and the
        // energy integrand quadratic, integrated exactly by 4-point Gauss. Closed forms with
        // int x^2 dV = 2!/5! = 1/60:
        //   u = (x^2, 0, 0): eps_xx = 2x, 2W = (lambda + 2 mu) 4 x^2
        //                    -> u^T K u = (lambda + 2 mu) / 15
        //   u = (0, 0, x y): eps_xz = y/2, eps_yz = x/2, 2W = mu (x^2 + y^2) -> mu / 30
        let (lambda, mu) = lame(E, NU).unwrap();
        let x = reference_element();
        let k = stiffness(&x, E, NU).unwrap();
        let u = interpolate(&x, |p| [p[0] * p[0], 0.0, 0.0]);
        let energy = dot30(&u, &mat_vec(&k, &u));
        let expect = (lambda + 2.0 * mu) / 15.0;
        assert!(
            ((energy - expect) / expect).abs() < 1e-13,
            "{energy} vs {expect}"
        );
        let u = interpolate(&x, |p| [0.0, 0.0, p[0] * p[1]]);
        let energy = dot30(&u, &mat_vec(&k, &u));
        let expect = mu / 30.0;
        assert!(
            ((energy - expect) / expect).abs() < 1e-13,
            "{energy} vs {expect}"
        );
    }

    #[test]
    fn volume_matches_the_divergence_theorem_on_a_curved_element() {
        for x in [reference_element(), skewed_element(), curved_element()] {
            let v = volume(&x).unwrap();
            let vf = volume_from_faces(&x);
            assert!(((v - vf) / vf).abs() < 1e-14, "{v} vs {vf}");
        }
        assert!((volume(&reference_element()).unwrap() - 1.0 / 6.0).abs() < 1e-16);
    }

    fn direction_sums(m: &ElementMatrix) -> [[f64; 3]; 3] {
        let mut s = [[0.0; 3]; 3];
        for r in 0..DOFS {
            for c in 0..DOFS {
                s[r % 3][c % 3] += m[r][c];
            }
        }
        s
    }

    #[test]
    fn mass_is_symmetric_and_its_total_is_rho_v_on_a_curved_element() {
        // sum_ab int N_a N_b det J = int det J = V since sum N = 1; the degree-5 rule
        // integrates the cubic det J of a curved element exactly. V comes from the faces.
        let x = curved_element();
        let v = volume_from_faces(&x);
        let m = mass(&x, RHO, MassRule::Exact).unwrap();
        for r in 0..DOFS {
            for c in 0..DOFS {
                assert_eq!(m[r][c], m[c][r]);
                if r % 3 != c % 3 {
                    assert_eq!(m[r][c], 0.0);
                }
            }
        }
        let s = direction_sums(&m);
        for i in 0..3 {
            assert!(
                ((s[i][i] - RHO * v) / (RHO * v)).abs() < 1e-14,
                "{} vs {}",
                s[i][i],
                RHO * v
            );
        }
    }

    #[test]
    fn both_mass_rules_give_the_exact_total_on_a_straight_element() {
        // det J is constant, so even the degree-2 rule gets int det J right.
        let x = skewed_element();
        let v = volume_from_faces(&x);
        for rule in [MassRule::Exact, MassRule::Gauss4] {
            let s = direction_sums(&mass(&x, RHO, rule).unwrap());
            for i in 0..3 {
                assert!(((s[i][i] - RHO * v) / (RHO * v)).abs() < 1e-14, "{rule:?}");
            }
        }
    }

    /// `int N_a N_b dV` of a straight-sided element in closed form: write every shape
    /// function as a homogeneous quadratic in the barycentric coordinates (using
    /// L0 + L1 + L2 + L3 = 1: N_k = L_k^2 - sum_{j != k} L_k L_j, N_ab = 4 L_a L_b), expand the
    /// product and integrate each monomial by int L^e dV = 6 V e0! e1! e2! e3! / (|e| + 3)!.
    fn closed_form_mass(volume: f64) -> [[f64; 10]; 10] {
        type Poly = BTreeMap<[u32; 4], f64>;
        let mut basis: Vec<Poly> = Vec::new();
        let unit = |a: usize, b: usize| {
            let mut e = [0u32; 4];
            e[a] += 1;
            e[b] += 1;
            e
        };
        for k in 0..4 {
            let mut p = Poly::new();
            p.insert(unit(k, k), 1.0);
            for j in (0..4).filter(|&j| j != k) {
                *p.entry(unit(k, j)).or_default() -= 1.0;
            }
            basis.push(p);
        }
        for [a, b] in TET10_EDGES {
            basis.push(Poly::from([(unit(a, b), 4.0)]));
        }
        let fact = |n: u32| (1..=n).map(f64::from).product::<f64>();
        std::array::from_fn(|a| {
            std::array::from_fn(|b| {
                let mut sum = 0.0;
                for (ea, ca) in &basis[a] {
                    for (eb, cb) in &basis[b] {
                        let e: [u32; 4] = std::array::from_fn(|i| ea[i] + eb[i]);
                        let num: f64 = e.iter().map(|&k| fact(k)).product();
                        sum += ca * cb * 6.0 * volume * num / fact(e.iter().sum::<u32>() + 3);
                    }
                }
                sum
            })
        })
    }

    #[test]
    fn exact_mass_of_a_straight_element_matches_the_closed_form() {
        let x = skewed_element();
        let v = volume_from_faces(&x);
        let m = mass(&x, RHO, MassRule::Exact).unwrap();
        let exact = closed_form_mass(v);
        // The textbook entries: corner diagonal 6 V / 420 = V / 70, mid diagonal 32 V / 420.
        assert!((exact[0][0] - v / 70.0).abs() < 1e-15 * v);
        assert!((exact[4][4] - 32.0 * v / 420.0).abs() < 1e-15 * v);
        for a in 0..10 {
            for b in 0..10 {
                for i in 0..3 {
                    let got = m[3 * a + i][3 * b + i];
                    assert!(
                        (got - RHO * exact[a][b]).abs() < 1e-14 * RHO * v,
                        "({a},{b}): {got}"
                    );
                }
            }
        }
        // The 4-point rule is not exact for this degree-4 integrand: it must differ.
        let g = mass(&x, RHO, MassRule::Gauss4).unwrap();
        assert!((g[0][0] - m[0][0]).abs() > 1e-3 * m[0][0]);
    }

    fn is_jacobian_error(e: ElementError) -> bool {
        match e {
            ElementError::NonPositiveJacobian { det, .. }
            | ElementError::NonPositiveJacobianAtNode { det, .. } => det <= 0.0 || det.is_nan(),
            ElementError::InvalidMaterial { .. } => false,
        }
    }

    #[test]
    fn inverted_element_is_rejected_everywhere() {
        // Mirror image: corners 1 and 2 swapped together with their mid nodes, a consistent
        // but left-handed element (det J = -det J0 everywhere).
        let x = skewed_element();
        let mut mirrored = x;
        mirrored.swap(1, 2);
        mirrored.swap(4, 6); // 0-1 <-> 0-2
        mirrored.swap(8, 9); // 1-3 <-> 2-3
        assert!(matches!(
            stiffness(&mirrored, E, NU),
            Err(ElementError::NonPositiveJacobianAtNode { node: 0, .. })
        ));
        assert!(is_jacobian_error(
            mass(&mirrored, RHO, MassRule::Exact).unwrap_err()
        ));
        assert!(is_jacobian_error(
            mass(&mirrored, RHO, MassRule::Gauss4).unwrap_err()
        ));
        assert!(is_jacobian_error(volume(&mirrored).unwrap_err()));
        // Degenerate (flat) and non-finite elements too.
        let mut flat = x;
        flat[3] = x[0];
        flat[7] = x[0];
        flat[8] = std::array::from_fn(|i| 0.5 * (x[0][i] + x[1][i]));
        flat[9] = std::array::from_fn(|i| 0.5 * (x[0][i] + x[2][i]));
        assert!(is_jacobian_error(stiffness(&flat, E, NU).unwrap_err()));
        let mut nan = x;
        nan[5][1] = f64::NAN;
        assert!(is_jacobian_error(stiffness(&nan, E, NU).unwrap_err()));
        assert!(is_jacobian_error(
            mass(&nan, RHO, MassRule::Exact).unwrap_err()
        ));
    }

    #[test]
    fn corners_swapped_without_their_mid_nodes_are_caught_at_the_nodes() {
        // Swapping corners 1 and 2 alone leaves the mid nodes of 0-1/0-2 and 1-3/2-3 on each
        // other's edges: the map folds (det J = -det J0 at corners 1, 2 and mid node 5) yet
        // det J is positive at all four Gauss points, so a Gauss-point check alone would
        // return a plausible-looking stiffness. The 14-point rule does see it (points 0, 1, 11);
        // the node check sees it first.
        for x in [reference_element(), skewed_element()] {
            let det0 = volume(&x).unwrap() * 6.0;
            let mut swapped = x;
            swapped.swap(1, 2);
            for p in GAUSS_4.points {
                assert!(jacobian_determinant(&swapped, *p) > 0.0);
            }
            for (node, factor) in [(1, -1.0), (2, -1.0), (5, -1.0), (0, 3.0), (3, 3.0)] {
                let det = jacobian_determinant(&swapped, crate::fem::tet10::NODE_COORDINATES[node]);
                assert!(
                    (det - factor * det0).abs() < 1e-13 * det0,
                    "node {node}: {det}"
                );
            }
            assert!(matches!(
                stiffness(&swapped, E, NU),
                Err(ElementError::NonPositiveJacobianAtNode { node: 1, .. })
            ));
            assert!(is_jacobian_error(
                mass(&swapped, RHO, MassRule::Gauss4).unwrap_err()
            ));
            assert!(is_jacobian_error(volume(&swapped).unwrap_err()));
        }
    }

    #[test]
    fn gmsh_node_order_is_detected() {
        // Gmsh numbers the last two mid nodes 3-2, 3-1 where the internal order has 1-3, 2-3.
        // Reading a Gmsh element without conversion puts nodes 8 and 9 on each other's edges,
        // which folds the element near corner 3: for a straight element det J at corner 3 is
        // -3 det J0, and at mid nodes 7, 8, 9 it is -det J0. Gauss point 3 (the one nearest
        // corner 3) is negative too, for the straight and the curved element alike, so even a
        // Gauss-point-only check would refuse it; here the node check names corner 3.
        for x in [reference_element(), curved_element()] {
            let mut gmsh = x;
            gmsh.swap(8, 9);
            assert!(jacobian_determinant(&gmsh, GAUSS_4.points[3]) < 0.0);
            assert!(matches!(
                stiffness(&gmsh, E, NU),
                Err(ElementError::NonPositiveJacobianAtNode { node: 3, .. })
            ));
            assert!(is_jacobian_error(
                mass(&gmsh, RHO, MassRule::Exact).unwrap_err()
            ));
            assert!(is_jacobian_error(
                mass(&gmsh, RHO, MassRule::Gauss4).unwrap_err()
            ));
            assert!(is_jacobian_error(volume(&gmsh).unwrap_err()));
        }
        let mut gmsh = reference_element();
        gmsh.swap(8, 9);
        for (node, expect) in [
            (3, -3.0),
            (7, -1.0),
            (8, -1.0),
            (9, -1.0),
            (0, 1.0),
            (5, 1.0),
        ] {
            let det = jacobian_determinant(&gmsh, crate::fem::tet10::NODE_COORDINATES[node]);
            assert!((det - expect).abs() < 1e-14, "node {node}: {det}");
        }
    }

    #[test]
    fn invalid_materials_are_rejected() {
        let x = skewed_element();
        for (e, nu) in [
            (0.0, 0.3),
            (-1.0, 0.3),
            (f64::NAN, 0.3),
            (f64::INFINITY, 0.3),
            (E, 0.5),
            (E, -1.0),
            (E, f64::NAN),
        ] {
            assert!(
                matches!(
                    stiffness(&x, e, nu),
                    Err(ElementError::InvalidMaterial { .. })
                ),
                "{e} {nu}"
            );
        }
        for rho in [-1.0, f64::NAN, f64::INFINITY] {
            assert!(matches!(
                mass(&x, rho, MassRule::Exact),
                Err(ElementError::InvalidMaterial { .. })
            ));
        }
        assert!(stiffness(&x, E, 0.4999).is_ok());
        assert!(stiffness(&x, E, -0.9).is_ok());
        assert!(mass(&x, 0.0, MassRule::Exact).is_ok());
    }

    #[test]
    fn flat_face_pressure_goes_to_the_mid_side_nodes_in_thirds() {
        let x = skewed_element();
        let p = 2.5e6;
        for side in 0..4 {
            let xf = face_coordinates(&x, side);
            let d = |k: usize| [0, 1, 2].map(|i| xf[k][i] - xf[0][i]);
            let na = cross(d(1), d(2)).map(|v| 0.5 * v);
            let area = (na[0] * na[0] + na[1] * na[1] + na[2] * na[2]).sqrt();
            assert!((face_area(&xf) - area).abs() < 1e-15 * area * 10.0);
            let f = face_pressure_load(&xf, p);
            for k in 0..3 {
                for i in 0..3 {
                    assert!(f[k][i].abs() < 1e-14 * p * area, "corner {k}: {:?}", f[k]);
                }
            }
            for k in 3..6 {
                for i in 0..3 {
                    let expect = -p * na[i] / 3.0;
                    assert!((f[k][i] - expect).abs() < 1e-14 * p * area, "mid {k}");
                }
            }
            let n = face_normal_at(&xf, [0.3, 0.2]).unwrap();
            for i in 0..3 {
                assert!((n[i] - na[i] / area).abs() < 1e-15);
            }
            // Outward: pointing away from the element's centroid.
            let centroid: [f64; 3] =
                std::array::from_fn(|i| x[..4].iter().map(|c| c[i]).sum::<f64>() / 4.0);
            let out: f64 = (0..3).map(|i| n[i] * (xf[0][i] - centroid[i])).sum();
            assert!(out > 0.0);
        }
    }

    #[test]
    fn pressure_on_a_closed_curved_surface_is_self_equilibrated() {
        // A uniform pressure on the closed boundary of the curved element has zero resultant
        // and zero moment, and its virtual work on the field u = x is
        // sum f . x = -p int x . n dA = -3 p V.
        let x = curved_element();
        let p = 1.0e5;
        let mut resultant = [0.0; 3];
        let mut moment = [0.0; 3];
        let mut work = 0.0;
        let mut total_abs = 0.0;
        for side in 0..4 {
            let xf = face_coordinates(&x, side);
            let f = face_pressure_load(&xf, p);
            for (fa, xa) in f.iter().zip(&xf) {
                let m = cross(*xa, *fa);
                for i in 0..3 {
                    resultant[i] += fa[i];
                    moment[i] += m[i];
                    work += fa[i] * xa[i];
                    total_abs += fa[i].abs();
                }
            }
        }
        for i in 0..3 {
            assert!(resultant[i].abs() < 1e-14 * total_abs, "{resultant:?}");
            assert!(moment[i].abs() < 1e-14 * total_abs, "{moment:?}");
        }
        let v = volume(&x).unwrap();
        assert!(
            ((work + 3.0 * p * v) / (3.0 * p * v)).abs() < 1e-14,
            "{work} vs {}",
            -3.0 * p * v
        );
    }

    #[test]
    fn curved_face_resultant_matches_the_boundary_integral() {
        // int n dA over an open surface = 1/2 closed-integral of x x dx along its boundary
        // (Stokes). Each edge is a parabola through its two corners and its mid node;
        // x x dx/dr is a cubic in r, integrated exactly by 2-point Gauss-Legendre.
        let x = curved_element();
        let xf = face_coordinates(&x, 2);
        let edges = [(0, 3, 1), (1, 4, 2), (2, 5, 0)];
        let gl = [0.5 - 0.5 / 3f64.sqrt(), 0.5 + 0.5 / 3f64.sqrt()];
        let mut vector_area = [0.0; 3];
        for (a, m, b) in edges {
            for r in gl {
                // Quadratic Lagrange on [0, 1] through a (r = 0), m (1/2), b (1).
                let n = [
                    2.0 * (r - 0.5) * (r - 1.0),
                    -4.0 * r * (r - 1.0),
                    2.0 * r * (r - 0.5),
                ];
                let dn = [4.0 * r - 3.0, 4.0 - 8.0 * r, 4.0 * r - 1.0];
                let pos: [f64; 3] =
                    std::array::from_fn(|i| n[0] * xf[a][i] + n[1] * xf[m][i] + n[2] * xf[b][i]);
                let tan: [f64; 3] =
                    std::array::from_fn(|i| dn[0] * xf[a][i] + dn[1] * xf[m][i] + dn[2] * xf[b][i]);
                let c = cross(pos, tan);
                for i in 0..3 {
                    vector_area[i] += 0.25 * c[i]; // 1/2 (Stokes) x 1/2 (Gauss weight)
                }
            }
        }
        let p = 3.0;
        let f = face_pressure_load(&xf, p);
        let scale = vector_area.iter().fold(0.0, |m: f64, v| m.max(v.abs()));
        for i in 0..3 {
            let total: f64 = f.iter().map(|fa| fa[i]).sum();
            assert!(
                (total + p * vector_area[i]).abs() < 1e-14 * p * scale,
                "{total} vs {}",
                -p * vector_area[i]
            );
        }
        // The corners of a curved face do carry load (unlike a flat one).
        assert!(f[0].iter().any(|v| v.abs() > 1e-3 * p * scale));
    }

    #[test]
    fn degenerate_face_has_no_normal() {
        let xf = [[1.0, 2.0, 3.0]; 6];
        assert_eq!(face_normal_at(&xf, [0.2, 0.2]), None);
        assert_eq!(face_area(&xf), 0.0);
    }

    /// A cube [0, n]^3 of n^3 unit cells, each split into the six Kuhn tetrahedra around its
    /// main diagonal (a conforming mesh), with vertices moved by `shift` and mid nodes at the
    /// edge mid-points plus `bow`. Nodes are keyed by twice their undistorted coordinates.
    struct PatchMesh {
        nodes: Vec<[f64; 3]>,
        on_boundary: Vec<bool>,
        elements: Vec<[usize; 10]>,
    }

    fn patch_mesh(
        n: i64,
        shift: impl Fn([i64; 3]) -> [f64; 3],
        bow: impl Fn([i64; 3]) -> [f64; 3],
    ) -> PatchMesh {
        let mut index: BTreeMap<[i64; 3], usize> = BTreeMap::new();
        let mut mesh = PatchMesh {
            nodes: Vec::new(),
            on_boundary: Vec::new(),
            elements: Vec::new(),
        };
        let boundary = |k: [i64; 3]| k.iter().any(|&c| c == 0 || c == 2 * n);
        let vertex = |k: [i64; 3]| -> [f64; 3] {
            let s = shift(k);
            std::array::from_fn(|i| 0.5 * k[i] as f64 + s[i])
        };
        let perms = [
            [0, 1, 2],
            [0, 2, 1],
            [1, 0, 2],
            [1, 2, 0],
            [2, 0, 1],
            [2, 1, 0],
        ];
        for cell in 0..n * n * n {
            let base = [2 * (cell % n), 2 * ((cell / n) % n), 2 * (cell / (n * n))];
            for perm in perms {
                let mut keys = [base; 4];
                for s in 0..3 {
                    keys[s + 1] = keys[s];
                    keys[s + 1][perm[s]] += 2;
                }
                let corners = keys.map(vertex);
                let e = |k: usize| [0, 1, 2].map(|i| corners[k][i] - corners[0][i]);
                let n3 = cross(e(2), e(3));
                if e(1)[0] * n3[0] + e(1)[1] * n3[1] + e(1)[2] * n3[2] < 0.0 {
                    keys.swap(1, 2);
                }
                let mut conn = [0usize; 10];
                for (a, key) in keys.iter().enumerate() {
                    let len = index.len();
                    let id = *index.entry(*key).or_insert(len);
                    if id == len {
                        mesh.nodes.push(vertex(*key));
                        mesh.on_boundary.push(boundary(*key));
                    }
                    conn[a] = id;
                }
                for (m, [a, b]) in TET10_EDGES.iter().enumerate() {
                    let key: [i64; 3] = std::array::from_fn(|i| (keys[*a][i] + keys[*b][i]) / 2);
                    let len = index.len();
                    let id = *index.entry(key).or_insert(len);
                    if id == len {
                        let (pa, pb) = (vertex(keys[*a]), vertex(keys[*b]));
                        let d = bow(key);
                        mesh.nodes
                            .push(std::array::from_fn(|i| 0.5 * (pa[i] + pb[i]) + d[i]));
                        mesh.on_boundary.push(boundary(key));
                    }
                    conn[4 + m] = id;
                }
                mesh.elements.push(conn);
            }
        }
        mesh
    }

    /// Dense Gaussian elimination with partial pivoting.
    fn solve_dense(mut a: Vec<Vec<f64>>, mut b: Vec<f64>) -> Vec<f64> {
        let n = b.len();
        for col in 0..n {
            let piv = (col..n)
                .max_by(|&i, &j| a[i][col].abs().total_cmp(&a[j][col].abs()))
                .unwrap();
            a.swap(col, piv);
            b.swap(col, piv);
            for r in col + 1..n {
                let f = a[r][col] / a[col][col];
                if f != 0.0 {
                    for c in col..n {
                        a[r][c] -= f * a[col][c];
                    }
                    b[r] -= f * b[col];
                }
            }
        }
        let mut x = vec![0.0; n];
        for r in (0..n).rev() {
            let s: f64 = (r + 1..n).map(|c| a[r][c] * x[c]).sum();
            x[r] = (b[r] - s) / a[r][r];
        }
        x
    }

    /// Imposes u = u0 + A x on the boundary nodes of `mesh`, solves for the interior nodes
    /// and returns the largest error at an interior DOF relative to the largest |u|.
    fn patch_test_error(mesh: &PatchMesh, rule: &Rule) -> f64 {
        let ndof = 3 * mesh.nodes.len();
        let mut k = vec![vec![0.0; ndof]; ndof];
        for conn in &mesh.elements {
            let x = conn.map(|a| mesh.nodes[a]);
            let ke = stiffness_with_rule(&x, E, NU, rule).unwrap();
            for a in 0..10 {
                for b in 0..10 {
                    for i in 0..3 {
                        for j in 0..3 {
                            k[3 * conn[a] + i][3 * conn[b] + j] += ke[3 * a + i][3 * b + j];
                        }
                    }
                }
            }
        }
        let exact: Vec<f64> = mesh
            .nodes
            .iter()
            .flat_map(|p| {
                let u0 = [0.01, -0.02, 0.005];
                (0..3).map(move |i| u0[i] + (0..3).map(|j| GRADIENT[i][j] * p[j]).sum::<f64>())
            })
            .collect();
        let interior: Vec<usize> = (0..ndof).filter(|d| !mesh.on_boundary[d / 3]).collect();
        let fixed: Vec<usize> = (0..ndof).filter(|d| mesh.on_boundary[d / 3]).collect();
        assert!(!interior.is_empty());
        let a: Vec<Vec<f64>> = interior
            .iter()
            .map(|&r| interior.iter().map(|&c| k[r][c]).collect())
            .collect();
        let b: Vec<f64> = interior
            .iter()
            .map(|&r| -fixed.iter().map(|&c| k[r][c] * exact[c]).sum::<f64>())
            .collect();
        let u = solve_dense(a, b);
        let umax = exact.iter().fold(0.0, |m: f64, v| m.max(v.abs()));
        interior
            .iter()
            .zip(&u)
            .map(|(&d, v)| (v - exact[d]).abs())
            .fold(0.0, f64::max)
            / umax
    }

    /// A deterministic pseudo-random displacement of size ~ `amplitude`, zero along the axes
    /// in which a key lies on the cube's boundary (boundary vertices slide in their faces).
    fn wobble(key: [i64; 3], n: i64, amplitude: f64) -> [f64; 3] {
        std::array::from_fn(|i| {
            if key[i] == 0 || key[i] == 2 * n {
                0.0
            } else {
                let k = key.map(|c| c as f64);
                amplitude * (1.3 * k[0] + 2.1 * k[1] + 0.7 * k[2] + 1.9 * i as f64).sin()
            }
        })
    }

    #[test]
    fn linear_patch_test_on_a_distorted_mesh() {
        // A linear field lies in the span of the isoparametric functions and the strain it
        // makes is constant, so the assembled interior equations are satisfied by it exactly:
        // the solve must return it to round-off (condition number ~1e3 x eps).
        let n = 2;
        let mesh = patch_mesh(n, |k| wobble(k, n, 0.15), |_| [0.0; 3]);
        assert_eq!(mesh.elements.len(), 48);
        let err = patch_test_error(&mesh, &GAUSS_4);
        assert!(err < 1e-12, "patch test error {err:e}");
    }

    #[test]
    fn curved_patch_test_is_exact_only_with_a_degree_3_stiffness_rule() {
        // Interior mid nodes bowed off their edges (0.05 on edges of ~0.5-0.7): the linear
        // field is still in the isoparametric span, but the internal force of a constant
        // stress, sum_q w_q cof(J) grad_p N_a sigma, is a cubic in p on a curved element. The
        // 4-point (degree 2) rule leaves a discretisation-size error, as CalculiX/Abaqus C3D10
        // do; any rule of degree >= 3 integrates it exactly and recovers the field to round-off.
        let n = 2;
        let mesh = patch_mesh(n, |k| wobble(k, n, 0.15), |k| wobble(k, n, 0.05));
        let gauss = patch_test_error(&mesh, &GAUSS_4);
        assert!(gauss > 1e-8 && gauss < 1e-3, "4-point error {gauss:e}");
        let exact = patch_test_error(&mesh, &WALKINGTON_14);
        assert!(exact < 1e-12, "14-point error {exact:e}");
    }
}
