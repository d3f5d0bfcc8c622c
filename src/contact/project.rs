//! Projection of a point on 6-node triangular faces, and the search for the face of a surface
//! that a point faces.
//!
//! On one face ([`project_on_face`]): the foot of the normal through the point is found by
//! Newton's method in the face's parametric coordinates `q = [s, t]` on the curved (quadratic)
//! surface, which is extended beyond the triangle so that a point just outside still has a
//! foot; how far the foot lies outside the triangle is measured in barycentric units. The
//! closest point of the closed triangle is the foot when it is inside, else the closest point
//! on the triangle's three (curved) edges.
//!
//! On a surface ([`SurfaceSearch`]): a uniform bucket grid over the faces' bounding boxes,
//! visited in rings of cells around the point, nearest first, until no unvisited face can be
//! nearer than the best one found. A face qualifies when the foot is inside it within the
//! in-face tolerance and the normal distance is within the largest distance allowed; among
//! those the one with the closest point nearest to the point wins.

use crate::fem::element;
use crate::vector3::{dot, norm, sub};
use std::collections::HashSet;

/// Tolerances of the master-surface search.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SearchOptions {
    /// How far outside a master face the foot of the normal may fall and still count as on
    /// the face, in the face's barycentric coordinates: the foot is accepted when
    /// `min(L0, L1, L2) >= -in_face_tolerance` (0.01 = one hundredth of the face's size).
    /// A foot accepted outside keeps its parametric point (the face is extrapolated that
    /// little), so that the gap stays the distance along the normal.
    pub in_face_tolerance: f64,
    /// Largest normal distance `|g0|` between a slave point and the master point it faces;
    /// `None` means the mean master face size `h` (see [`SurfaceSearch::mean_face_size`]):
    /// small sliding assumes the slave surface lies on, or very near, the master one.
    pub max_distance: Option<f64>,
}

impl Default for SearchOptions {
    fn default() -> Self {
        SearchOptions {
            in_face_tolerance: 0.01,
            max_distance: None,
        }
    }
}

impl SearchOptions {
    /// `Err` with a sentence when a tolerance is negative, zero where it must not be, or not
    /// finite. A helper of this module: its public functions report it as a
    /// [`ContactError`](super::ContactError).
    pub(super) fn check(&self) -> Result<(), String> {
        if !(self.in_face_tolerance >= 0.0 && self.in_face_tolerance.is_finite()) {
            return Err(format!(
                "in-face tolerance {} must be finite and >= 0",
                self.in_face_tolerance
            ));
        }
        if let Some(d) = self.max_distance {
            if !(d > 0.0 && d.is_finite()) {
                return Err(format!(
                    "largest contact distance {d} must be finite and > 0"
                ));
            }
        }
        Ok(())
    }
}

/// A point's projection on one 6-node face.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FaceProjection {
    /// Foot of the normal through the point, in face parametric coordinates, on the face's
    /// quadratic surface extended beyond the triangle; `None` when Newton's method found none
    /// (the point lies far outside the face, where the extension is meaningless).
    pub foot: Option<[f64; 2]>,
    /// How far the foot lies outside the triangle: `max(0, -min(L0, L1, L2))`; 0 inside,
    /// infinite without a foot.
    pub outside: f64,
    /// The closest point of the closed triangle (the foot when inside, else a point on its
    /// boundary).
    pub closest: [f64; 2],
    /// Distance from the point to `closest`.
    pub distance: f64,
}

/// Second parametric derivatives `[d2/ds2, d2/dsdt, d2/dt2]` of the six face shape functions
/// (constants: the functions are quadratic). From `N_k = L_k (2 L_k - 1)` and
/// `N_m = 4 L_a L_b` with `grad L0 = (-1, -1)`, `grad L1 = (1, 0)`, `grad L2 = (0, 1)`; the
/// test `second_derivatives_match_finite_differences` checks them.
const FACE_SECOND_DERIVATIVES: [[f64; 3]; 6] = [
    [4.0, 4.0, 4.0],
    [4.0, 0.0, 0.0],
    [0.0, 0.0, 4.0],
    [-8.0, -4.0, 0.0],
    [0.0, 4.0, 0.0],
    [0.0, -4.0, -8.0],
];

/// `[x_ss, x_st, x_tt]` of a face (constant over it).
fn second_derivatives(x: &[[f64; 3]; 6]) -> [[f64; 3]; 3] {
    let mut d = [[0.0; 3]; 3];
    for (xa, sa) in x.iter().zip(FACE_SECOND_DERIVATIVES) {
        for (dk, sk) in d.iter_mut().zip(sa) {
            for i in 0..3 {
                dk[i] += sk * xa[i];
            }
        }
    }
    d
}

fn barycentric_excess(q: [f64; 2]) -> f64 {
    let l = [1.0 - q[0] - q[1], q[0], q[1]];
    (-l[0].min(l[1]).min(l[2])).max(0.0)
}

/// Newton iterations allowed: quadratic convergence from the flat-triangle start needs 3 to 5
/// on a reasonably curved face; the Gauss-Newton fallback converges linearly.
const MAX_ITERATIONS: usize = 50;
/// Parametric step below which Newton has converged: the step after it is of order its
/// square, far below round-off.
const STEP_TOLERANCE: f64 = 1e-13;
/// The extension of the face beyond the triangle is followed this far (barycentric units)
/// before Newton gives up: farther out, a quadratic surface may fold back.
const EXTENSION_LIMIT: f64 = 1.0;

/// The foot of the normal from `p` on the quadratic surface of face `x`: Newton on
/// `f(q) = |x(q) - p|^2 / 2`, gradient `T^T r` and Hessian `T^T T + r . x_qq`
/// (`r = x(q) - p`, `T = [x_s, x_t]`), falling back to Gauss-Newton (`T^T T`) where the
/// Hessian is not positive definite (the point beyond the centre of curvature). Starts at the
/// projection on the plane of the corners, which is the answer on a flat straight-sided face.
fn foot(x: &[[f64; 3]; 6], p: [f64; 3], xqq: &[[f64; 3]; 3]) -> Option<[f64; 2]> {
    let e1 = sub(x[1], x[0]);
    let e2 = sub(x[2], x[0]);
    let d = sub(p, x[0]);
    let (g11, g12, g22) = (dot(e1, e1), dot(e1, e2), dot(e2, e2));
    let det = g11 * g22 - g12 * g12;
    if det.is_nan() || det <= 0.0 {
        return None;
    }
    let (b1, b2) = (dot(e1, d), dot(e2, d));
    let mut q = [(g22 * b1 - g12 * b2) / det, (g11 * b2 - g12 * b1) / det];
    // Start inside the triangle (or just on it): Newton is safest where the face is defined.
    q = clamp_to_triangle(q);
    for _ in 0..MAX_ITERATIONS {
        let r = sub(element::face_point(x, q), p);
        let (ts, tt) = element::face_tangents(x, q);
        let grad = [dot(ts, r), dot(tt, r)];
        let (a11, a12, a22) = (dot(ts, ts), dot(ts, tt), dot(tt, tt));
        let (h11, h12, h22) = (
            a11 + dot(r, xqq[0]),
            a12 + dot(r, xqq[1]),
            a22 + dot(r, xqq[2]),
        );
        let hdet = h11 * h22 - h12 * h12;
        let (m11, m12, m22, mdet) = if h11 > 0.0 && hdet > 0.0 {
            (h11, h12, h22, hdet)
        } else {
            (a11, a12, a22, a11 * a22 - a12 * a12)
        };
        if mdet.is_nan() || mdet <= 0.0 {
            return None;
        }
        let step = [
            -(m22 * grad[0] - m12 * grad[1]) / mdet,
            -(m11 * grad[1] - m12 * grad[0]) / mdet,
        ];
        // Keep a step within half the parametric triangle: a far-off Gauss-Newton step on a
        // curved face would otherwise jump to where the extension folds.
        let size = step[0].abs().max(step[1].abs());
        let damp = if size > 0.5 { 0.5 / size } else { 1.0 };
        q = [q[0] + damp * step[0], q[1] + damp * step[1]];
        if !(q[0].is_finite() && q[1].is_finite()) || barycentric_excess(q) > EXTENSION_LIMIT {
            return None;
        }
        if size <= STEP_TOLERANCE {
            return Some(q);
        }
    }
    None
}

/// The point of the closed parametric triangle nearest to `q` in the (s, t) plane.
fn clamp_to_triangle(q: [f64; 2]) -> [f64; 2] {
    let (s, t) = (q[0], q[1]);
    if s >= 0.0 && t >= 0.0 && s + t <= 1.0 {
        return q;
    }
    // Candidates on the three edges; the nearest wins.
    let on_edges = [[s.clamp(0.0, 1.0), 0.0], [0.0, t.clamp(0.0, 1.0)], {
        let u = (0.5 * (s - t + 1.0)).clamp(0.0, 1.0);
        [u, 1.0 - u]
    }];
    let d2 = |c: [f64; 2]| (c[0] - s).powi(2) + (c[1] - t).powi(2);
    on_edges
        .into_iter()
        .min_by(|a, b| d2(*a).total_cmp(&d2(*b)))
        .unwrap_or([1.0 / 3.0, 1.0 / 3.0])
}

/// Closest point to `p` on the boundary of the face: on each curved edge `q(u) = q_i + u d`,
/// `u` in [0, 1], minimise `|x(q(u)) - p|^2 / 2` by a clamped 1-D Newton from the projection on
/// the chord, and compare with the edge's ends.
fn closest_on_boundary(x: &[[f64; 3]; 6], p: [f64; 3], xqq: &[[f64; 3]; 3]) -> ([f64; 2], f64) {
    const CORNERS: [[f64; 2]; 3] = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
    let mut best = (CORNERS[0], f64::INFINITY);
    let mut consider = |q: [f64; 2]| {
        let d = norm(sub(element::face_point(x, q), p));
        if d < best.1 {
            best = (q, d);
        }
    };
    for (i, j) in [(0, 1), (1, 2), (2, 0)] {
        consider(CORNERS[i]);
        let (qi, qj) = (CORNERS[i], CORNERS[j]);
        let dq = [qj[0] - qi[0], qj[1] - qi[1]];
        let at = |u: f64| [qi[0] + u * dq[0], qi[1] + u * dq[1]];
        // d2x/du2 = dq^T x_qq dq, constant along the edge.
        let xuu: [f64; 3] = std::array::from_fn(|k| {
            dq[0] * dq[0] * xqq[0][k] + 2.0 * dq[0] * dq[1] * xqq[1][k] + dq[1] * dq[1] * xqq[2][k]
        });
        let chord = sub(x[j], x[i]);
        let mut u = (dot(sub(p, x[i]), chord) / dot(chord, chord)).clamp(0.0, 1.0);
        if !u.is_finite() {
            continue;
        }
        for _ in 0..MAX_ITERATIONS {
            let q = at(u);
            let r = sub(element::face_point(x, q), p);
            let (ts, tt) = element::face_tangents(x, q);
            let xu: [f64; 3] = std::array::from_fn(|k| dq[0] * ts[k] + dq[1] * tt[k]);
            let slope = dot(r, xu);
            let mut curvature = dot(xu, xu) + dot(r, xuu);
            if curvature.is_nan() || curvature <= 0.0 {
                curvature = dot(xu, xu);
            }
            if curvature.is_nan() || curvature <= 0.0 {
                break;
            }
            let next = (u - slope / curvature).clamp(0.0, 1.0);
            let done = (next - u).abs() <= STEP_TOLERANCE;
            u = next;
            if done {
                break;
            }
        }
        consider(at(u));
    }
    best
}

/// Projects `p` on the 6-node face `x` (nodes in [`crate::mesh::TET10_FACES`] order). See
/// [`FaceProjection`].
pub fn project_on_face(x: &[[f64; 3]; 6], p: [f64; 3]) -> FaceProjection {
    let xqq = second_derivatives(x);
    let foot = foot(x, p, &xqq);
    let outside = foot.map_or(f64::INFINITY, barycentric_excess);
    match foot {
        Some(q) if outside == 0.0 => FaceProjection {
            foot,
            outside,
            closest: q,
            distance: norm(sub(element::face_point(x, q), p)),
        },
        _ => {
            let (closest, distance) = closest_on_boundary(x, p, &xqq);
            FaceProjection {
                foot,
                outside,
                closest,
                distance,
            }
        }
    }
}

/// The master point a point faces, found by [`SurfaceSearch::nearest`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceHit {
    /// Index of the face in the list the search was built from.
    pub face: usize,
    /// Parametric point on that face (the foot of the normal).
    pub q: [f64; 2],
    /// The master point `x(q)`.
    pub point: [f64; 3],
    /// Unit outward normal of the face at `q`.
    pub normal: [f64; 3],
    /// Signed normal distance `n . (p - x(q))`: positive on the outer side of the face.
    pub gap: f64,
    /// How far `q` lies outside the triangle (barycentric units, 0 inside).
    pub outside: f64,
    /// Distance from the point to the closest point of the (closed) face.
    pub distance: f64,
}

/// Bucket grid over the faces of a surface, for finding the face a point faces.
#[derive(Clone, Debug)]
pub struct SurfaceSearch {
    faces: Vec<[[f64; 3]; 6]>,
    /// Axis-aligned box of each face: `[min, max]`.
    boxes: Vec<[[f64; 3]; 2]>,
    origin: [f64; 3],
    cell: f64,
    dims: [usize; 3],
    /// Faces of cell `c` are `items[starts[c]..starts[c + 1]]`.
    starts: Vec<usize>,
    items: Vec<usize>,
    mean_size: f64,
    largest_box: f64,
}

/// Box containing a 6-node face: that of its quadratic Bezier control net (corners, and
/// `2 m - (a + b) / 2` per edge), which the face lies within by the convex-hull property.
fn face_box(x: &[[f64; 3]; 6]) -> [[f64; 3]; 2] {
    let mut lo = x[0];
    let mut hi = x[0];
    let control = [
        x[0],
        x[1],
        x[2],
        std::array::from_fn(|i| 2.0 * x[3][i] - 0.5 * (x[0][i] + x[1][i])),
        std::array::from_fn(|i| 2.0 * x[4][i] - 0.5 * (x[1][i] + x[2][i])),
        std::array::from_fn(|i| 2.0 * x[5][i] - 0.5 * (x[2][i] + x[0][i])),
    ];
    for c in control {
        for i in 0..3 {
            lo[i] = lo[i].min(c[i]);
            hi[i] = hi[i].max(c[i]);
        }
    }
    [lo, hi]
}

fn box_distance(b: &[[f64; 3]; 2], p: [f64; 3]) -> f64 {
    let d: [f64; 3] = std::array::from_fn(|i| (b[0][i] - p[i]).max(0.0).max(p[i] - b[1][i]));
    norm(d)
}

/// Cells per face the grid may have at most: a flat surface in a tall box leaves most cells
/// empty, and the grid must stay of the surface's size.
const CELLS_PER_FACE: f64 = 8.0;

impl SurfaceSearch {
    /// A search over `faces` (coordinates of 6-node faces in [`crate::mesh::TET10_FACES`]
    /// order). `Err(k)`: face `k` has a non-finite coordinate or is degenerate (no normal at
    /// a corner or at its centroid).
    pub fn new(faces: Vec<[[f64; 3]; 6]>) -> Result<Self, usize> {
        let mut area_sum = 0.0;
        for (k, x) in faces.iter().enumerate() {
            let q_points = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0 / 3.0, 1.0 / 3.0]];
            if x.iter().flatten().any(|c| !c.is_finite())
                || q_points
                    .iter()
                    .any(|q| element::face_normal_at(x, *q).is_none())
            {
                return Err(k);
            }
            area_sum += element::face_area(x);
        }
        let boxes: Vec<[[f64; 3]; 2]> = faces.iter().map(face_box).collect();
        let n = faces.len().max(1);
        let mean_size = (area_sum / n as f64).sqrt();
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        let mut largest_box: f64 = 0.0;
        let mut mean_extent = 0.0;
        for b in &boxes {
            for i in 0..3 {
                lo[i] = lo[i].min(b[0][i]);
                hi[i] = hi[i].max(b[1][i]);
            }
            let extent = (0..3).map(|i| b[1][i] - b[0][i]).fold(0.0, f64::max);
            mean_extent += extent / n as f64;
            largest_box = largest_box.max(norm(sub(b[1], b[0])));
        }
        if boxes.is_empty() {
            lo = [0.0; 3];
            hi = [0.0; 3];
        }
        // Cells about one face across; coarser if the box is much larger than the surface.
        let mut cell = if mean_extent > 0.0 { mean_extent } else { 1.0 };
        let dims_for = |cell: f64| -> [usize; 3] {
            std::array::from_fn(|i| (((hi[i] - lo[i]) / cell).ceil() as usize).max(1))
        };
        let mut dims = dims_for(cell);
        let budget = CELLS_PER_FACE * n as f64 + 64.0;
        while (dims[0] as f64) * (dims[1] as f64) * (dims[2] as f64) > budget {
            let total = (dims[0] as f64) * (dims[1] as f64) * (dims[2] as f64);
            cell *= (total / budget).cbrt().max(1.01);
            dims = dims_for(cell);
        }
        let mut search = SurfaceSearch {
            faces,
            boxes,
            origin: lo,
            cell,
            dims,
            starts: Vec::new(),
            items: Vec::new(),
            mean_size,
            largest_box,
        };
        // Compressed rows: count, prefix sums, fill.
        let cells = dims[0] * dims[1] * dims[2];
        let mut counts = vec![0usize; cells + 1];
        for b in &search.boxes {
            search.for_cells_of_box(b, |c| counts[c + 1] += 1);
        }
        for c in 0..cells {
            counts[c + 1] += counts[c];
        }
        let mut next = counts.clone();
        let mut items = vec![0usize; counts[cells]];
        for (k, b) in search.boxes.iter().enumerate() {
            search.for_cells_of_box(b, |c| {
                items[next[c]] = k;
                next[c] += 1;
            });
        }
        search.starts = counts;
        search.items = items;
        Ok(search)
    }

    /// A search over the faces of `surface` of `mesh`; `Err` with the first degenerate face
    /// (see [`SurfaceSearch::new`]).
    pub fn of_surface(
        mesh: &crate::mesh::Mesh,
        surface: &crate::mesh::Surface,
    ) -> Result<Self, crate::mesh::Face> {
        let faces = surface
            .faces
            .iter()
            .map(|f| f.nodes.map(|n| mesh.nodes[n]))
            .collect();
        SurfaceSearch::new(faces).map_err(|k| surface.faces[k])
    }

    /// `sqrt` of the mean face area: the face size `h` of the default penalty and of the
    /// default largest contact distance.
    pub fn mean_face_size(&self) -> f64 {
        self.mean_size
    }

    /// The faces searched.
    pub fn faces(&self) -> &[[[f64; 3]; 6]] {
        &self.faces
    }

    fn cell_of(&self, p: [f64; 3]) -> [usize; 3] {
        std::array::from_fn(|i| {
            let k = ((p[i] - self.origin[i]) / self.cell).floor();
            if k.is_nan() || k < 0.0 {
                0
            } else {
                (k as usize).min(self.dims[i] - 1)
            }
        })
    }

    fn cell_index(&self, c: [usize; 3]) -> usize {
        (c[2] * self.dims[1] + c[1]) * self.dims[0] + c[0]
    }

    fn for_cells_of_box(&self, b: &[[f64; 3]; 2], mut f: impl FnMut(usize)) {
        let lo = self.cell_of(b[0]);
        let hi = self.cell_of(b[1]);
        for k in lo[2]..=hi[2] {
            for j in lo[1]..=hi[1] {
                for i in lo[0]..=hi[0] {
                    f(self.cell_index([i, j, k]));
                }
            }
        }
    }

    /// The face `p` faces: among the faces on which the foot of the normal through `p` lies
    /// inside within `in_face_tolerance`, with `|gap| <= max_distance`, the one whose closest
    /// point is nearest to `p` (ties: the one the foot is less outside). `None` if there is
    /// none. `max_distance` here is the resolved value (not an option).
    pub fn nearest(
        &self,
        p: [f64; 3],
        in_face_tolerance: f64,
        max_distance: f64,
    ) -> Option<SurfaceHit> {
        if self.faces.is_empty() || p.iter().any(|c| !c.is_finite()) {
            return None;
        }
        // A qualifying face can have its closest point a little farther than its normal
        // distance (a foot accepted outside the triangle): allow for that in the pruning.
        let radius = max_distance + 2.0 * (in_face_tolerance + 1e-9) * self.largest_box;
        let k0 = self.cell_of(p);
        let rings = (0..3)
            .map(|i| k0[i].max(self.dims[i] - 1 - k0[i]))
            .max()
            .unwrap_or(0);
        let mut best: Option<SurfaceHit> = None;
        let mut seen: HashSet<usize> = HashSet::with_capacity(64);
        for ring in 0..=rings {
            // Every cell at Chebyshev distance `ring` from p's (clamped) cell lies at least
            // (ring - 1) cells from p, whether p is in the grid or outside it.
            let bound = best.map_or(radius, |b| b.distance.min(radius));
            if (ring as f64 - 1.0) * self.cell > bound {
                break;
            }
            let range = |i: usize| {
                (
                    k0[i].saturating_sub(ring),
                    (k0[i] + ring).min(self.dims[i] - 1),
                )
            };
            let (rx, ry, rz) = (range(0), range(1), range(2));
            for k in rz.0..=rz.1 {
                for j in ry.0..=ry.1 {
                    for i in rx.0..=rx.1 {
                        let chebyshev = i
                            .abs_diff(k0[0])
                            .max(j.abs_diff(k0[1]))
                            .max(k.abs_diff(k0[2]));
                        if chebyshev != ring {
                            continue;
                        }
                        let c = self.cell_index([i, j, k]);
                        for &f in &self.items[self.starts[c]..self.starts[c + 1]] {
                            let bound = best.map_or(radius, |b| b.distance.min(radius));
                            if box_distance(&self.boxes[f], p) > bound || !seen.insert(f) {
                                continue;
                            }
                            if let Some(hit) = self.try_face(f, p, in_face_tolerance, max_distance)
                            {
                                let better = match best {
                                    None => true,
                                    Some(b) => {
                                        hit.distance < b.distance
                                            || (hit.distance == b.distance
                                                && hit.outside < b.outside)
                                    }
                                };
                                if better {
                                    best = Some(hit);
                                }
                            }
                        }
                    }
                }
            }
        }
        best
    }

    fn try_face(
        &self,
        f: usize,
        p: [f64; 3],
        in_face_tolerance: f64,
        max_distance: f64,
    ) -> Option<SurfaceHit> {
        let x = &self.faces[f];
        let projection = project_on_face(x, p);
        let q = projection.foot?;
        if projection.outside > in_face_tolerance {
            return None;
        }
        let point = element::face_point(x, q);
        let normal = element::face_normal_at(x, q)?;
        let gap = dot(normal, sub(p, point));
        (gap.abs() <= max_distance).then_some(SurfaceHit {
            face: f,
            q,
            point,
            normal,
            gap,
            outside: projection.outside,
            distance: projection.distance,
        })
    }
}

#[cfg(test)]
// Index loops mirror the index notation of the formulas being checked.
#[allow(clippy::needless_range_loop)]
mod tests {
    use super::*;
    use crate::fem::tet10;
    use crate::vector3::{add, scale};

    /// A curved face: the flat corner triangle (0,0,0), (1,0,0), (0,1,0) with its mid-side
    /// nodes lifted out of the plane and moved along the edges.
    fn bowed_face() -> [[f64; 3]; 6] {
        [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.52, 0.01, 0.10],
            [0.49, 0.52, 0.15],
            [-0.01, 0.47, 0.05],
        ]
    }

    /// Deterministic pseudo-random numbers in [0, 1) (64-bit LCG, top 53 bits).
    pub(crate) struct Lcg(pub u64);
    impl Lcg {
        pub fn next(&mut self) -> f64 {
            self.0 = self
                .0
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (self.0 >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    #[test]
    fn second_derivatives_match_finite_differences() {
        // The shape functions are quadratic, so central differences of their first
        // derivatives are exact up to round-off (~1e-16 / h = 1e-12 with h = 1e-4).
        let q = [0.23, 0.41];
        let h = 1e-4;
        let dp = tet10::face_shape_derivatives([q[0] + h, q[1]]);
        let dm = tet10::face_shape_derivatives([q[0] - h, q[1]]);
        let tp = tet10::face_shape_derivatives([q[0], q[1] + h]);
        let tm = tet10::face_shape_derivatives([q[0], q[1] - h]);
        for a in 0..6 {
            let ss = (dp[a][0] - dm[a][0]) / (2.0 * h);
            let st = (dp[a][1] - dm[a][1]) / (2.0 * h);
            let ts = (tp[a][0] - tm[a][0]) / (2.0 * h);
            let tt = (tp[a][1] - tm[a][1]) / (2.0 * h);
            let expect = FACE_SECOND_DERIVATIVES[a];
            for (got, want) in [
                (ss, expect[0]),
                (st, expect[1]),
                (ts, expect[1]),
                (tt, expect[2]),
            ] {
                assert!((got - want).abs() < 1e-9, "node {a}: {got} vs {want}");
            }
        }
    }

    #[test]
    fn projection_recovers_known_points_on_a_curved_face() {
        // Points built as x(q) + d n(q): the foot of the normal through them is q exactly, and
        // the signed distance d. Newton converges quadratically, so the answer is at round-off:
        // 1e-12 in q leaves a margin of 1e3 over the ~1e-15 reached.
        let x = bowed_face();
        for &q in &[
            [0.2, 0.3],
            [0.05, 0.9],
            [0.6, 0.35],
            [1.0 / 3.0, 1.0 / 3.0],
            [0.0, 0.5],
        ] {
            for d in [-0.05, 0.0, 0.02, 0.1] {
                let n = element::face_normal_at(&x, q).unwrap();
                let p = add(element::face_point(&x, q), scale(d, n));
                let proj = project_on_face(&x, p);
                let got = proj.foot.unwrap();
                assert!(
                    (got[0] - q[0]).abs() < 1e-12 && (got[1] - q[1]).abs() < 1e-12,
                    "q = {q:?}, d = {d}: got {got:?}"
                );
                // On the edge s = 0 the foot may fall outside by round-off.
                assert!(proj.outside < 1e-15);
                assert!((proj.distance - d.abs()).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn a_point_outside_gets_its_excess_and_the_closest_boundary_point() {
        // Flat right triangle in z = 0 (mid nodes at mid-edges): the foot of the normal from
        // (-0.1, 0.3, 0.2) is (s, t) = (-0.1, 0.3), 0.1 outside; the closest point of the
        // triangle is (0, 0.3, 0) at distance sqrt(0.1^2 + 0.2^2).
        let c = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let mid = |a: usize, b: usize| std::array::from_fn(|i| 0.5 * (c[a][i] + c[b][i]));
        let x = [c[0], c[1], c[2], mid(0, 1), mid(1, 2), mid(2, 0)];
        let proj = project_on_face(&x, [-0.1, 0.3, 0.2]);
        let foot = proj.foot.unwrap();
        assert!((foot[0] + 0.1).abs() < 1e-14 && (foot[1] - 0.3).abs() < 1e-14);
        assert!((proj.outside - 0.1).abs() < 1e-14);
        assert!((proj.closest[0]).abs() < 1e-14 && (proj.closest[1] - 0.3).abs() < 1e-14);
        assert!((proj.distance - 0.05f64.sqrt()).abs() < 1e-14);
        // Beyond the hypotenuse: closest point (0.5, 0.5) for p = (0.8, 0.8, -0.1).
        let proj = project_on_face(&x, [0.8, 0.8, -0.1]);
        assert!((proj.outside - 0.6).abs() < 1e-14);
        assert!((proj.closest[0] - 0.5).abs() < 1e-12 && (proj.closest[1] - 0.5).abs() < 1e-12);
        assert!((proj.distance - (0.18f64 + 0.01).sqrt()).abs() < 1e-12);
    }

    #[test]
    fn closest_boundary_point_on_a_curved_face_is_a_minimum() {
        // Brute force: sample each curved edge densely; the Newton answer may not be farther
        // than the best sample (it may be nearer, being a true minimum). The sample spacing
        // 1e-4 bounds the brute force's own error by O(1e-8) in distance.
        let x = bowed_face();
        let mut rng = Lcg(7);
        for _ in 0..50 {
            let p = [
                -1.0 + 3.0 * rng.next(),
                -1.0 + 3.0 * rng.next(),
                -0.5 + rng.next(),
            ];
            let xqq = second_derivatives(&x);
            let (_, d) = closest_on_boundary(&x, p, &xqq);
            let mut brute = f64::INFINITY;
            for k in 0..=10_000 {
                let u = k as f64 / 10_000.0;
                for q in [[u, 0.0], [1.0 - u, u], [0.0, 1.0 - u]] {
                    brute = brute.min(norm(sub(element::face_point(&x, q), p)));
                }
            }
            assert!(d <= brute + 1e-12, "p = {p:?}: {d} vs brute {brute}");
            assert!(d >= brute - 1e-7, "p = {p:?}: {d} vs brute {brute}");
        }
    }

    /// Faces of a wavy surface z = 0.05 sin(3x) cos(2y) over [0, 1]^2, n x n squares split in
    /// two triangles each, mid nodes on the surface.
    fn wavy_faces(n: usize) -> Vec<[[f64; 3]; 6]> {
        let z = |x: f64, y: f64| 0.05 * (3.0 * x).sin() * (2.0 * y).cos();
        let pt = |x: f64, y: f64| [x, y, z(x, y)];
        let h = 1.0 / n as f64;
        let mut faces = Vec::new();
        for i in 0..n {
            for j in 0..n {
                let (x0, y0) = (i as f64 * h, j as f64 * h);
                let a = [x0, y0];
                let b = [x0 + h, y0];
                let c = [x0 + h, y0 + h];
                let d = [x0, y0 + h];
                for tri in [[a, b, c], [a, c, d]] {
                    let m = |u: [f64; 2], v: [f64; 2]| pt(0.5 * (u[0] + v[0]), 0.5 * (u[1] + v[1]));
                    faces.push([
                        pt(tri[0][0], tri[0][1]),
                        pt(tri[1][0], tri[1][1]),
                        pt(tri[2][0], tri[2][1]),
                        m(tri[0], tri[1]),
                        m(tri[1], tri[2]),
                        m(tri[2], tri[0]),
                    ]);
                }
            }
        }
        faces
    }

    #[test]
    fn bucket_search_agrees_with_brute_force() {
        // The grid is only an accelerator: for random points the face it returns must be the
        // one a loop over every face with the same acceptance rule returns.
        let faces = wavy_faces(12);
        let search = SurfaceSearch::new(faces.clone()).unwrap();
        let (tol, dmax) = (0.01, 0.2);
        let mut rng = Lcg(11);
        let mut found = 0;
        for _ in 0..300 {
            let p = [
                -0.2 + 1.4 * rng.next(),
                -0.2 + 1.4 * rng.next(),
                -0.3 + 0.6 * rng.next(),
            ];
            let got = search.nearest(p, tol, dmax);
            let mut brute: Option<SurfaceHit> = None;
            for f in 0..faces.len() {
                if let Some(hit) = search.try_face(f, p, tol, dmax) {
                    if brute.is_none_or(|b| {
                        hit.distance < b.distance
                            || (hit.distance == b.distance && hit.outside < b.outside)
                    }) {
                        brute = Some(hit);
                    }
                }
            }
            match (got, brute) {
                (None, None) => {}
                (Some(g), Some(b)) => {
                    found += 1;
                    assert_eq!(g.distance, b.distance, "p = {p:?}");
                    assert!((g.gap - b.gap).abs() < 1e-14);
                }
                _ => panic!("p = {p:?}: grid {got:?} vs brute force {brute:?}"),
            }
        }
        assert!(found > 100, "only {found} points found a face");
    }

    #[test]
    fn degenerate_faces_are_refused_by_index() {
        // All six nodes on one line: no normal anywhere.
        let mut faces = wavy_faces(2);
        faces[3] = std::array::from_fn(|k| [0.1 * k as f64, 0.2 * k as f64, 0.0]);
        assert_eq!(SurfaceSearch::new(faces).unwrap_err(), 3);
        let mut faces = wavy_faces(2);
        faces[5][4][2] = f64::NAN;
        assert_eq!(SurfaceSearch::new(faces).unwrap_err(), 5);
    }

    #[test]
    fn options_are_checked() {
        assert!(SearchOptions::default().check().is_ok());
        let bad = SearchOptions {
            in_face_tolerance: -0.1,
            ..Default::default()
        };
        assert!(bad.check().unwrap_err().contains("-0.1"));
        let bad = SearchOptions {
            max_distance: Some(f64::INFINITY),
            ..Default::default()
        };
        assert!(bad.check().unwrap_err().contains("inf"));
    }

    /// Timing of the search at an industrial size: run with
    /// `cargo test --release -- --ignored --nocapture search_timing`.
    #[test]
    #[ignore]
    fn search_timing() {
        let n = 160; // 2 n^2 = 51,200 master faces
        let faces = wavy_faces(n);
        let count = faces.len();
        let t0 = std::time::Instant::now();
        let search = SurfaceSearch::new(faces).unwrap();
        let build = t0.elapsed();
        let mut rng = Lcg(3);
        let points: Vec<[f64; 3]> = (0..5000)
            .map(|_| {
                let (x, y) = (0.1 + 0.8 * rng.next(), 0.1 + 0.8 * rng.next());
                [x, y, 0.05 * (3.0 * x).sin() * (2.0 * y).cos() + 1e-4]
            })
            .collect();
        let t1 = std::time::Instant::now();
        let hits = points
            .iter()
            .filter(|p| search.nearest(**p, 0.01, search.mean_face_size()).is_some())
            .count();
        let query = t1.elapsed();
        println!(
            "{count} faces: grid built in {build:?}; {} points searched in {query:?}, {hits} found",
            points.len()
        );
        assert_eq!(hits, points.len());
    }
}
