//! Exact measures of the discretised brake for its tests: areas swept by the parabolic arcs
//! of quadratic elements, element volumes, face points and normals.

use super::parts::jacobian_det;
use super::{build, preset, BrakeParams};
use crate::mesh::{Face, Mesh, Part};
use crate::vector3::{cross, dot};

pub(super) fn tiny() -> (BrakeParams, Mesh) {
    let p = preset("tiny").unwrap();
    let m = build(&p).unwrap();
    (p, m)
}

pub(super) fn part<'a>(m: &'a Mesh, name: &str) -> &'a Part {
    m.parts.iter().find(|p| p.name == name).unwrap()
}

/// Area swept from the axis by the quadratic (parabolic) arc through three equally spaced
/// points of the circle of radius `r` over the angle `h`: with the arc parametrised as
/// x = r (1 - (1 - c) t^2), y = r s t, t in [-1, 1], c = cos(h/2), s = sin(h/2),
/// (1/2) int (x y' - y x') dt = r^2 s (1 + (1 - c) / 3) = (r^2 h / 2)(1 - (h/2)^4 / 30 + ...).
pub(super) fn fan(r: f64, h: f64) -> f64 {
    let (s, c) = (0.5 * h).sin_cos();
    r * r * s * (1.0 + (1.0 - c) / 3.0)
}

/// (angle, count) of the theta cells of the lining and of the backplate ears.
pub(super) fn pad_cells(p: &BrakeParams) -> [(f64, usize); 2] {
    let o = p.overhang_cells();
    let ear = if o > 0 {
        p.backplate_overhang_deg.to_radians() / o as f64
    } else {
        0.0
    };
    [
        (
            p.pad_arc_deg.to_radians() / p.divisions.pad_circumferential as f64,
            p.divisions.pad_circumferential,
        ),
        (ear, 2 * o),
    ]
}

/// Plan-view area of the discretised (parabolic-arc) ring sector made of `cells`.
pub(super) fn ring_area(r1: f64, r2: f64, cells: &[(f64, usize)]) -> f64 {
    cells
        .iter()
        .map(|&(h, n)| n as f64 * (fan(r2, h) - fan(r1, h)))
        .sum()
}

/// Keast's 5-point rule, exact for cubics: the TET10 Jacobian determinant is a cubic,
/// so this gives the exact volume of the quadratic element.
pub(super) fn element_volume(m: &Mesh, e: usize) -> f64 {
    let x = m.elements[e].map(|n| m.nodes[n]);
    let (a, b) = (0.5, 1.0 / 6.0);
    let points = [
        (-0.8, [0.25; 4]),
        (0.45, [a, b, b, b]),
        (0.45, [b, a, b, b]),
        (0.45, [b, b, a, b]),
        (0.45, [b, b, b, a]),
    ];
    points
        .iter()
        .map(|(w, l)| w * jacobian_det(&x, *l) / 6.0)
        .sum()
}

/// Position and normal (x_s cross x_t, outward for an outward face) of a 6-node face at
/// (s, t), corner a at (0, 0), b at (1, 0), c at (0, 1).
pub(super) fn face_point(m: &Mesh, f: &Face, s: f64, t: f64) -> ([f64; 3], [f64; 3]) {
    let x = f.nodes.map(|n| m.nodes[n]);
    let l = [1.0 - s - t, s, t];
    let dl = [[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0]];
    let mut n = [0.0; 6];
    let mut dn = [[0.0; 2]; 6];
    for i in 0..3 {
        n[i] = l[i] * (2.0 * l[i] - 1.0);
        dn[i] = dl[i].map(|g| (4.0 * l[i] - 1.0) * g);
        let j = (i + 1) % 3;
        n[3 + i] = 4.0 * l[i] * l[j];
        dn[3 + i] = [0, 1].map(|d| 4.0 * (l[i] * dl[j][d] + l[j] * dl[i][d]));
    }
    let mut pos = [0.0; 3];
    let mut xs = [0.0; 3];
    let mut xt = [0.0; 3];
    for k in 0..6 {
        for c in 0..3 {
            pos[c] += n[k] * x[k][c];
            xs[c] += dn[k][0] * x[k][c];
            xt[c] += dn[k][1] * x[k][c];
        }
    }
    (pos, cross(xs, xt))
}

/// Integral of normal . dir over a flat face (the integrand is quadratic, so the
/// 3-point rule is exact), asserting that normal . dir > 0 at every point.
pub(super) fn flat_face_area(m: &Mesh, f: &Face, dir: [f64; 3]) -> f64 {
    let mut area = 0.0;
    for (s, t) in [
        (1.0 / 6.0, 1.0 / 6.0),
        (2.0 / 3.0, 1.0 / 6.0),
        (1.0 / 6.0, 2.0 / 3.0),
    ] {
        let (_, n) = face_point(m, f, s, t);
        let along = dot(n, dir);
        assert!(along > 0.0, "face of element {} points inward", f.element);
        area += along / 6.0;
    }
    area
}

pub(super) fn cylindrical(x: [f64; 3]) -> [f64; 3] {
    [x[0].hypot(x[1]), x[1].atan2(x[0]), x[2]]
}
