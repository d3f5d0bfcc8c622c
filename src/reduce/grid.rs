//! Reduced contact nodes: an isometric (equilateral triangular) grid laid on a pad friction
//! surface in the surface's mean plane, keeping the grid points that fall inside the surface
//! (the paper's sections 3.3 and 4.1, Fig. 4 and 6; METHOD.md section 5).
//!
//! - Mean plane: the least-squares plane of the surface's nodes, each weighted by its
//!   tributary area so that a graded mesh does not tilt it; in-plane axes along the principal
//!   directions (the first along the surface's longest extent), normal along the surface's
//!   outward normal.
//! - Inside: a grid point is kept when the line through it along the plane's normal meets one
//!   of the surface's (curved, 6-node) faces within the face. Where it meets it is the
//!   reduced contact node's position on the surface, with the face's normal there.
//! - Size: given the side h, the grid is centred on the surface's centroid. Given a count per
//!   pad, h and a small set of grid origins and two orientations are searched, h outward from
//!   the value that gives each node the area of one grid cell, and the first layout that
//!   keeps exactly that count wins; when none does, the nearest count, flagged.
//! - Tributary area: the surface's area split among the reduced contact nodes, each part of
//!   the surface going to the nearest node in the plane (a Voronoi share clipped at the
//!   surface's border). The shares add up to the surface's area to round-off.

use super::ReduceError;
use crate::contact::tributary_areas;
use crate::fem::element;
use crate::mesh::{Mesh, Surface};
use crate::vector3::{add, cross, dot, norm, scale, sub};

/// What the user gives: a number of reduced contact nodes per pad, or the grid side h
/// (in a study file `{ count = 52 }` or `{ spacing = 0.01 }`).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum GridSize {
    /// This many reduced contact nodes on the surface (h is found).
    Count(usize),
    /// Grid side h in mesh units (the count follows).
    Spacing(f64),
}

impl GridSize {
    /// The paper's four reduced models (Table 3): 6, 22, 52 and 106 reduced contact nodes per
    /// pad (Abaqus12, Abaqus44, Abaqus104, Abaqus212).
    pub fn paper_presets() -> [GridSize; 4] {
        [
            GridSize::Count(6),
            GridSize::Count(22),
            GridSize::Count(52),
            GridSize::Count(106),
        ]
    }

    /// The request in words, for messages.
    pub fn describe(&self) -> String {
        match self {
            GridSize::Count(n) => format!("{n} reduced contact node(s) asked for"),
            GridSize::Spacing(h) => format!("grid side h = {h:e} asked for"),
        }
    }
}

/// The least-squares plane of a surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeanPlane {
    /// The area-weighted centroid of the surface's nodes.
    pub origin: [f64; 3],
    /// Unit in-plane axes: `axes[0]` along the largest spread of the surface,
    /// `axes[1] = normal x axes[0]`.
    pub axes: [[f64; 3]; 2],
    /// Unit normal, on the side the surface's faces point to (outward).
    pub normal: [f64; 3],
    /// Largest distance of a surface node from the plane.
    pub deviation: f64,
    /// Largest in-plane extent of the surface (along `axes[0]`).
    pub size: f64,
}

impl MeanPlane {
    /// In-plane coordinates of `x` (its projection on the plane).
    pub fn to_plane(&self, x: [f64; 3]) -> [f64; 2] {
        let d = sub(x, self.origin);
        [dot(d, self.axes[0]), dot(d, self.axes[1])]
    }

    /// The point of the plane with in-plane coordinates `p`.
    pub fn to_space(&self, p: [f64; 2]) -> [f64; 3] {
        add(
            self.origin,
            add(scale(p[0], self.axes[0]), scale(p[1], self.axes[1])),
        )
    }
}

/// One reduced contact node.
#[derive(Clone, Debug, PartialEq)]
pub struct ReducedNode {
    /// The grid point, in the mean plane's coordinates.
    pub plane: [f64; 2],
    /// Where the normal of the mean plane through the grid point meets the surface.
    pub position: [f64; 3],
    /// Unit outward normal of the surface at `position`.
    pub normal: [f64; 3],
    /// Index into the surface's faces of the face `position` lies on.
    pub face: usize,
    /// Parametric point of `position` on that face.
    pub local: [f64; 2],
    /// Tributary area: the node's share of the surface's area.
    pub area: f64,
    /// The share's second moment of area about its own centroid, in the mean plane's axes
    /// (m^4): what a patch of uniform contact stiffness resists tilting with
    /// ([`crate::contact::Tilt`]).
    pub second_moment: [[f64; 2]; 2],
    /// The share as quadrature points: (offset from the node in the mean plane's axes, area),
    /// the sub-triangles' centroids and areas that give `area` (the patch law integrates
    /// the contact over them, [`crate::contact::Tilt`]).
    pub patch: Vec<([f64; 2], f64)>,
}

/// The reduced contact nodes of one surface.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactGrid {
    /// Name of the surface.
    pub surface: String,
    pub plane: MeanPlane,
    /// What was asked for.
    pub requested: GridSize,
    /// Grid side h.
    pub spacing: f64,
    /// In-plane coordinates of one grid point (the lattice's origin).
    pub origin: [f64; 2],
    /// The two lattice vectors in plane coordinates, of length h and 60 degrees apart.
    pub lattice: [[f64; 2]; 2],
    /// False when a count was asked for and no layout searched keeps exactly that many nodes
    /// (`nodes.len()` is then the nearest count found).
    pub count_met: bool,
    /// Area of the surface (sum of its faces' areas).
    pub surface_area: f64,
    /// The reduced contact nodes, row by row along the first lattice vector.
    pub nodes: Vec<ReducedNode>,
}

impl ContactGrid {
    /// Number of reduced contact nodes.
    pub fn count(&self) -> usize {
        self.nodes.len()
    }

    /// One line saying what was asked and what was found (both the count and h).
    pub fn summary(&self) -> String {
        let met = match self.requested {
            GridSize::Count(n) if !self.count_met => {
                format!(" (no layout keeps exactly {n}: nearest count)")
            }
            _ => String::new(),
        };
        format!(
            "surface '{}': {} reduced contact nodes, grid side h = {:.6e}{met}; point contacts \
             hold {:.1} % of the face's second moment of area",
            self.surface,
            self.nodes.len(),
            self.spacing,
            100.0 * self.second_moment_held()
        )
    }

    /// The fraction of the face's second moment of area (about its centroid, trace) that
    /// point contacts at the nodes hold, sum A_k |x_k - c|^2 over sum_share a |x - c|^2: a
    /// uniformly pressed face resists a rigid rocking with k_n times this second moment, and
    /// point contacts lose their shares' own (the parallel-axis remainder), which patch laws
    /// keep ([`crate::reduce::tilt`]).
    pub fn second_moment_held(&self) -> f64 {
        let area: f64 = self.nodes.iter().map(|n| n.area).sum();
        if area <= 0.0 {
            return 0.0;
        }
        // The face's centroid, from the shares' quadrature points.
        let c = [0, 1].map(|i| {
            self.nodes
                .iter()
                .flat_map(|n| n.patch.iter().map(move |&(xi, a)| a * (n.plane[i] + xi[i])))
                .sum::<f64>()
                / area
        });
        let d2 = |x: [f64; 2]| (x[0] - c[0]).powi(2) + (x[1] - c[1]).powi(2);
        let points: f64 = self.nodes.iter().map(|n| n.area * d2(n.plane)).sum();
        let face: f64 = self
            .nodes
            .iter()
            .flat_map(|n| {
                n.patch
                    .iter()
                    .map(move |&(xi, a)| a * d2([n.plane[0] + xi[0], n.plane[1] + xi[1]]))
            })
            .sum();
        if face > 0.0 {
            points / face
        } else {
            0.0
        }
    }
}

/// Out-of-plane deviation allowed, as a fraction of the surface's in-plane size. A surface
/// bowed as a parabola over a size L lies up to d = a L^2 / 6 from its mean plane and has
/// slopes up to a L = 6 d / L against it; at d = 0.05 L that is 0.3, where a length on the
/// surface exceeds its projection by 4.4 % at the very edge and by 1.5 % on average. The grid
/// is laid out in the plane, so its spacing on the surface stays within those few per cent
/// of h (the tributary areas are measured on the surface and are exact either way). A flat
/// friction face is far below it; a drum-brake shoe or a wrapped surface is far above.
pub const PLANARITY_FRACTION: f64 = 0.05;

/// How far outside a face (barycentric units) a grid point may fall and still count as on it:
/// round-off only, so that points on a shared edge or on the border are kept.
const IN_FACE_TOLERANCE: f64 = 1e-9;

/// The count search looks at h from H_RANGE^-1 to H_RANGE times the estimate, by relative
/// steps of H_STEP. Steps this small move about 2 N H_STEP grid points across the border,
/// so that every count near the target is passed through.
const H_RANGE: f64 = 1.5;
const H_STEP: f64 = 0.002;

/// Grid origins tried for a count, in lattice coordinates (fractions of the two lattice
/// vectors) from the surface's centroid: a node on the centroid, the centroid on an edge's
/// middle (three ways), on a triangle's centre (both triangles).
const ORIGINS: [[f64; 2]; 6] = [
    [0.0, 0.0],
    [0.5, 0.0],
    [0.0, 0.5],
    [0.5, 0.5],
    [1.0 / 3.0, 1.0 / 3.0],
    [2.0 / 3.0, 2.0 / 3.0],
];

/// Rows of the grid along the surface's longest extent, then across it.
const ORIENTATIONS: [f64; 2] = [0.0, std::f64::consts::FRAC_PI_2];

/// Sub-triangles per grid side for the tributary areas: each face is cut into sub-triangles
/// no larger than h / 8 across, each given whole to the nearest node, so that a share is
/// resolved to about 1/8 of a cell's width along the Voronoi edges.
const AREA_RESOLUTION: f64 = 8.0;

/// Most reduced contact nodes one surface may get: beyond, the "reduced" interface has more
/// nodes than an industrial pad's mesh (1370 in the paper) by orders of magnitude.
const MAX_NODES: f64 = 1e6;

/// Lays the reduced contact nodes of `surface`. See the module documentation.
pub fn isometric_grid(
    mesh: &Mesh,
    surface: &Surface,
    size: GridSize,
) -> Result<ContactGrid, ReduceError> {
    let projected = ProjectedSurface::new(mesh, surface)?;
    let area = projected.area;
    let cell_area = |h: f64| 0.75f64.sqrt() * h * h;
    let invalid = |why: String| ReduceError::InvalidSize {
        surface: surface.name.clone(),
        requested: size.describe(),
        why,
    };
    let (spacing, origin_fraction, angle, count_met) = match size {
        GridSize::Count(0) => return Err(invalid("a pad needs at least one node".into())),
        GridSize::Count(n) if n as f64 > MAX_NODES => {
            return Err(invalid(format!("more than {MAX_NODES:e} nodes")))
        }
        // More reduced nodes than the face has nodes is no reduction, and a search for
        // that layout ran for minutes without a word (100,000 on a 273-node pad).
        GridSize::Count(n) if n > mesh.surface_nodes(surface).len() => {
            return Err(invalid(format!(
                "the surface has {} nodes: a reduced interface has fewer (the paper's 6 to 106 \
                 on faces of hundreds to thousands)",
                mesh.surface_nodes(surface).len()
            )))
        }
        GridSize::Spacing(h) if !(h > 0.0 && h.is_finite()) => {
            return Err(invalid("h must be finite and > 0".into()))
        }
        GridSize::Spacing(h) if area / cell_area(h) > MAX_NODES => {
            return Err(invalid(format!(
                "about {:.0} nodes on a surface of area {area:e}, more than {MAX_NODES:e}",
                area / cell_area(h)
            )))
        }
        GridSize::Spacing(h) => (h, ORIGINS[0], ORIENTATIONS[0], true),
        GridSize::Count(n) => projected.search(n),
    };
    let lattice = lattice_vectors(spacing, angle);
    let origin = lattice_origin(&lattice, origin_fraction);
    let kept = projected.grid_points(origin, &lattice);
    if kept.is_empty() {
        return Err(ReduceError::NoNode {
            surface: surface.name.clone(),
            requested: format!("{} (grid side h = {spacing:e})", size.describe()),
        });
    }
    let (shares, patches) = projected.tributary_areas(&kept, spacing);
    let nodes = kept
        .iter()
        .zip(shares)
        .zip(patches)
        .map(|((hit, share), patch)| {
            let x = &projected.faces[hit.face];
            ReducedNode {
                plane: hit.plane,
                position: element::face_point(x, hit.local),
                normal: element::face_normal_at(x, hit.local).unwrap_or(projected.plane.normal),
                face: hit.face,
                local: hit.local,
                area: share.area,
                second_moment: share.central_second_moment(),
                patch,
            }
        })
        .collect();
    Ok(ContactGrid {
        surface: surface.name.clone(),
        plane: projected.plane,
        requested: size,
        spacing,
        origin,
        lattice,
        count_met,
        surface_area: area,
        nodes,
    })
}

fn lattice_vectors(h: f64, angle: f64) -> [[f64; 2]; 2] {
    let at = |a: f64| [h * a.cos(), h * a.sin()];
    [at(angle), at(angle + std::f64::consts::FRAC_PI_3)]
}

fn lattice_origin(lattice: &[[f64; 2]; 2], fraction: [f64; 2]) -> [f64; 2] {
    [
        fraction[0] * lattice[0][0] + fraction[1] * lattice[1][0],
        fraction[0] * lattice[0][1] + fraction[1] * lattice[1][1],
    ]
}

/// A grid point found on the surface.
#[derive(Clone, Copy, Debug)]
struct Hit {
    plane: [f64; 2],
    face: usize,
    local: [f64; 2],
}

/// A surface seen in its mean plane: the faces' coordinates in space and in the plane, and a
/// bucket grid over the faces' boxes in the plane.
struct ProjectedSurface {
    plane: MeanPlane,
    area: f64,
    faces: Vec<[[f64; 3]; 6]>,
    /// The faces' nodes in plane coordinates, third coordinate 0, so that the face functions
    /// of [`element`] give the projected map.
    flat: Vec<[[f64; 3]; 6]>,
    lo: [f64; 2],
    hi: [f64; 2],
    cell: f64,
    dims: [usize; 2],
    buckets: Vec<Vec<usize>>,
}

impl ProjectedSurface {
    fn new(mesh: &Mesh, surface: &Surface) -> Result<Self, ReduceError> {
        let invalid = |why: String| ReduceError::InvalidSurface {
            surface: surface.name.clone(),
            why,
        };
        if surface.faces.is_empty() {
            return Err(invalid("has no faces".into()));
        }
        if let Some(f) = surface
            .faces
            .iter()
            .find(|f| f.nodes.iter().any(|&n| n >= mesh.nodes.len()))
        {
            return Err(invalid(format!(
                "face (element index {}, side {}) refers to a node outside the mesh",
                f.element, f.side
            )));
        }
        let faces: Vec<[[f64; 3]; 6]> = surface
            .faces
            .iter()
            .map(|f| f.nodes.map(|n| mesh.nodes[n]))
            .collect();
        let area: f64 = faces.iter().map(element::face_area).sum();
        if !(area > 0.0 && area.is_finite()) {
            return Err(invalid(format!("area {area:e} is not positive")));
        }
        let plane = mean_plane(mesh, surface, &faces)?;
        if plane.deviation > PLANARITY_FRACTION * plane.size {
            return Err(ReduceError::NotPlanar {
                surface: surface.name.clone(),
                deviation: plane.deviation,
                limit: PLANARITY_FRACTION * plane.size,
                fraction: PLANARITY_FRACTION,
                size: plane.size,
            });
        }
        let flat: Vec<[[f64; 3]; 6]> = faces
            .iter()
            .map(|x| {
                x.map(|p| {
                    let q = plane.to_plane(p);
                    [q[0], q[1], 0.0]
                })
            })
            .collect();
        let boxes: Vec<[[f64; 2]; 2]> = flat.iter().map(control_box).collect();
        let mut lo = [f64::INFINITY; 2];
        let mut hi = [f64::NEG_INFINITY; 2];
        let mut mean_extent = 0.0;
        for b in &boxes {
            for i in 0..2 {
                lo[i] = lo[i].min(b[0][i]);
                hi[i] = hi[i].max(b[1][i]);
            }
            mean_extent += (b[1][0] - b[0][0]).max(b[1][1] - b[0][1]) / boxes.len() as f64;
        }
        // About one face per cell; at most a few cells per face however the faces are spread.
        let mut cell = mean_extent.max(1e-300);
        let dims_for = |cell: f64| -> [usize; 2] {
            [0, 1].map(|i| (((hi[i] - lo[i]) / cell).ceil() as usize).max(1))
        };
        let mut dims = dims_for(cell);
        while (dims[0] * dims[1]) as f64 > 4.0 * faces.len() as f64 + 16.0 {
            cell *= 1.5;
            dims = dims_for(cell);
        }
        let mut buckets = vec![Vec::new(); dims[0] * dims[1]];
        for (k, b) in boxes.iter().enumerate() {
            let c0 = cell_of(lo, cell, dims, b[0]);
            let c1 = cell_of(lo, cell, dims, b[1]);
            for j in c0[1]..=c1[1] {
                for i in c0[0]..=c1[0] {
                    buckets[j * dims[0] + i].push(k);
                }
            }
        }
        Ok(ProjectedSurface {
            plane,
            area,
            faces,
            flat,
            lo,
            hi,
            cell,
            dims,
            buckets,
        })
    }

    /// The face and parametric point the plane's normal through `p` meets, if any: among the
    /// faces whose box holds `p`, the one that holds it deepest (a point on a shared edge
    /// goes to one face, always the same).
    fn locate(&self, p: [f64; 2]) -> Option<Hit> {
        let slack = 1e-9 * self.plane.size;
        if p[0] < self.lo[0] - slack
            || p[1] < self.lo[1] - slack
            || p[0] > self.hi[0] + slack
            || p[1] > self.hi[1] + slack
        {
            return None;
        }
        let c = cell_of(self.lo, self.cell, self.dims, p);
        let mut best: Option<(f64, Hit)> = None;
        for &k in &self.buckets[c[1] * self.dims[0] + c[0]] {
            if let Some(q) = invert(&self.flat[k], p) {
                let l = [1.0 - q[0] - q[1], q[0], q[1]];
                let depth = l[0].min(l[1]).min(l[2]);
                if depth >= -IN_FACE_TOLERANCE && best.is_none_or(|(d, _)| depth > d) {
                    best = Some((
                        depth,
                        Hit {
                            plane: p,
                            face: k,
                            local: q,
                        },
                    ));
                }
            }
        }
        best.map(|(_, hit)| hit)
    }

    /// The grid points of the lattice (`origin` + integer combinations of `lattice`) that fall
    /// on the surface, row by row.
    fn grid_points(&self, origin: [f64; 2], lattice: &[[f64; 2]; 2]) -> Vec<Hit> {
        // Lattice coordinates of the box's corners bound the rows and columns to visit.
        let [a, b] = *lattice;
        let det = a[0] * b[1] - a[1] * b[0];
        let to_lattice = |p: [f64; 2]| {
            let d = [p[0] - origin[0], p[1] - origin[1]];
            [
                (d[0] * b[1] - d[1] * b[0]) / det,
                (a[0] * d[1] - a[1] * d[0]) / det,
            ]
        };
        let corners = [
            self.lo,
            [self.hi[0], self.lo[1]],
            [self.lo[0], self.hi[1]],
            self.hi,
        ]
        .map(to_lattice);
        let range = |k: usize| {
            let (mn, mx) = corners
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(mn, mx), c| {
                    (mn.min(c[k]), mx.max(c[k]))
                });
            (mn.floor() as i64 - 1)..=(mx.ceil() as i64 + 1)
        };
        let mut hits = Vec::new();
        for j in range(1) {
            for i in range(0) {
                let p = [
                    origin[0] + i as f64 * a[0] + j as f64 * b[0],
                    origin[1] + i as f64 * a[1] + j as f64 * b[1],
                ];
                if let Some(hit) = self.locate(p) {
                    hits.push(hit);
                }
            }
        }
        hits
    }

    /// How many grid points of the lattice fall on the surface (as [`Self::grid_points`],
    /// without keeping them).
    fn count_points(&self, h: f64, fraction: [f64; 2], angle: f64) -> usize {
        let lattice = lattice_vectors(h, angle);
        self.grid_points(lattice_origin(&lattice, fraction), &lattice)
            .len()
    }

    /// The layout for `count` nodes: (h, origin in lattice fractions, orientation, met).
    /// h is tried outward from the estimate `h0` at which `count` cells of the grid cover the
    /// surface (alternately above and below), every origin and orientation at each h; the
    /// first exact count wins, so among exact layouts the one whose nodes' mean share is
    /// nearest a full cell. Without one, the nearest count other than 0, nearest `h0` first.
    fn search(&self, count: usize) -> (f64, [f64; 2], f64, bool) {
        let h0 = (self.area / (count as f64 * 0.75f64.sqrt())).sqrt();
        let steps = (H_RANGE.ln() / H_STEP).ceil() as i64;
        let mut best: Option<(usize, f64, [f64; 2], f64)> = None;
        for k in 0..=2 * steps {
            // 0, +1, -1, +2, -2, ...
            let signed = if k % 2 == 1 { (k + 1) / 2 } else { -(k / 2) };
            let h = h0 * (signed as f64 * H_STEP).exp();
            for angle in ORIENTATIONS {
                for fraction in ORIGINS {
                    let found = self.count_points(h, fraction, angle);
                    if found == count {
                        return (h, fraction, angle, true);
                    }
                    // No node is never the nearest count: a pad needs one.
                    let miss = found.abs_diff(count);
                    if found > 0 && best.is_none_or(|(m, ..)| miss < m) {
                        best = Some((miss, h, fraction, angle));
                    }
                }
            }
        }
        match best {
            Some((_, h, fraction, angle)) => (h, fraction, angle, false),
            None => (h0, ORIGINS[0], ORIENTATIONS[0], false),
        }
    }

    /// Each node's share of the surface: every face cut into sub-triangles (in its parametric
    /// coordinates) no larger than h / `AREA_RESOLUTION`, each sub-triangle's area (centroid
    /// rule) given to the node nearest its centroid in the plane; then each face's shares
    /// scaled to the face's area so that they add up to the surface's area to round-off (the
    /// scaling is 1 on flat straight-sided faces and differs from it by the centroid rule's
    /// error on curved ones).
    #[allow(clippy::type_complexity)]
    fn tributary_areas(&self, nodes: &[Hit], h: f64) -> (Vec<Share>, Vec<Vec<([f64; 2], f64)>>) {
        let mut areas = vec![Share::default(); nodes.len()];
        let mut shares = vec![Share::default(); nodes.len()];
        let mut patches: Vec<Vec<([f64; 2], f64)>> = vec![Vec::new(); nodes.len()];
        let mut pending: Vec<(usize, [f64; 2], f64)> = Vec::new();
        let mut touched: Vec<usize> = Vec::new();
        for (x, flat) in self.faces.iter().zip(&self.flat) {
            let across = [(0, 1), (1, 2), (2, 0)]
                .iter()
                .map(|&(i, j)| norm(sub(x[i], x[j])))
                .fold(0.0, f64::max);
            let m = ((across * AREA_RESOLUTION / h).ceil() as usize).max(1);
            let third = 1.0 / (3 * m) as f64;
            let weight = 0.5 / (m * m) as f64;
            let mut face_sum = 0.0;
            let mut give = |q: [f64; 2]| {
                let a = weight * norm(element::face_area_vector_at(x, q));
                let p = element::face_point(flat, q);
                let nearest = nearest_node(nodes, [p[0], p[1]]);
                if shares[nearest].area == 0.0 {
                    touched.push(nearest);
                }
                let o = nodes[nearest].plane;
                shares[nearest].add(a, [p[0] - o[0], p[1] - o[1]]);
                pending.push((nearest, [p[0] - o[0], p[1] - o[1]], a));
                face_sum += a;
            };
            for i in 0..m {
                for j in 0..m - i {
                    give([(3 * i + 1) as f64 * third, (3 * j + 1) as f64 * third]);
                    if i + j + 1 < m {
                        give([(3 * i + 2) as f64 * third, (3 * j + 2) as f64 * third]);
                    }
                }
            }
            let scale = element::face_area(x) / face_sum;
            for &k in &touched {
                areas[k].add_scaled(scale, &shares[k]);
                shares[k] = Share::default();
            }
            touched.clear();
            for (k, r, a) in pending.drain(..) {
                patches[k].push((r, scale * a));
            }
        }
        (areas, patches)
    }
}

/// A reduced node's share of a surface: its area and the first and second moments of that
/// area about the node (in the mean plane's coordinates), summed over the sub-triangles'
/// centroids (the same one-point rule that gives the area).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Share {
    area: f64,
    first: [f64; 2],
    second: [[f64; 2]; 2],
}

impl Share {
    fn add(&mut self, a: f64, r: [f64; 2]) {
        self.area += a;
        for i in 0..2 {
            self.first[i] += a * r[i];
            for j in 0..2 {
                self.second[i][j] += a * r[i] * r[j];
            }
        }
    }

    fn add_scaled(&mut self, scale: f64, other: &Share) {
        self.area += scale * other.area;
        for i in 0..2 {
            self.first[i] += scale * other.first[i];
            for j in 0..2 {
                self.second[i][j] += scale * other.second[i][j];
            }
        }
    }

    /// The second moment about the share's centroid (parallel-axis theorem).
    fn central_second_moment(&self) -> [[f64; 2]; 2] {
        if self.area <= 0.0 {
            return [[0.0; 2]; 2];
        }
        let c = self.first.map(|f| f / self.area);
        [0, 1].map(|i| [0, 1].map(|j| self.second[i][j] - self.area * c[i] * c[j]))
    }
}

/// Index of the node nearest to `p` in the plane (the first of equals). A plain scan: the
/// counts are small (a few hundred nodes) and the scan is cheaper than building a tree.
fn nearest_node(nodes: &[Hit], p: [f64; 2]) -> usize {
    let mut best = (0, f64::INFINITY);
    for (k, n) in nodes.iter().enumerate() {
        let d = distance2d(n.plane, p);
        if d < best.1 {
            best = (k, d);
        }
    }
    best.0
}

fn cell_of(lo: [f64; 2], cell: f64, dims: [usize; 2], p: [f64; 2]) -> [usize; 2] {
    [0, 1].map(|i| (((p[i] - lo[i]) / cell).floor().max(0.0) as usize).min(dims[i] - 1))
}

/// Box in the plane holding a projected 6-node face: that of its quadratic Bezier control net
/// (corners, and `2 m - (a + b) / 2` per edge), which holds the face (convex hull property).
fn control_box(x: &[[f64; 3]; 6]) -> [[f64; 2]; 2] {
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    let control = |k: usize, a: usize, b: usize| -> [f64; 2] {
        [0, 1].map(|i| 2.0 * x[k][i] - 0.5 * (x[a][i] + x[b][i]))
    };
    let points = [
        [x[0][0], x[0][1]],
        [x[1][0], x[1][1]],
        [x[2][0], x[2][1]],
        control(3, 0, 1),
        control(4, 1, 2),
        control(5, 2, 0),
    ];
    for p in points {
        for i in 0..2 {
            lo[i] = lo[i].min(p[i]);
            hi[i] = hi[i].max(p[i]);
        }
    }
    [lo, hi]
}

/// Newton iterations allowed for the inversion of a projected face: from the straight-sided
/// start it converges in 2 to 4 on the faces of a mesh.
const MAX_ITERATIONS: usize = 30;

/// The parametric point `q` of the projected face `flat` (plane coordinates, third 0) at
/// which it passes through `p`: Newton on the 2x2 map, started from the straight-sided
/// triangle of the corners. `None` when it does not converge or runs far off the triangle
/// (where the quadratic extension may fold: such a point is not on this face anyway).
fn invert(flat: &[[f64; 3]; 6], p: [f64; 2]) -> Option<[f64; 2]> {
    let e1 = sub(flat[1], flat[0]);
    let e2 = sub(flat[2], flat[0]);
    let d = [p[0] - flat[0][0], p[1] - flat[0][1]];
    let det = e1[0] * e2[1] - e1[1] * e2[0];
    if det.is_nan() || det == 0.0 {
        return None;
    }
    let mut q = [
        (d[0] * e2[1] - d[1] * e2[0]) / det,
        (e1[0] * d[1] - e1[1] * d[0]) / det,
    ];
    let size = norm(e1).max(norm(e2));
    for _ in 0..MAX_ITERATIONS {
        if (1.0 - q[0] - q[1]).min(q[0]).min(q[1]) < -0.5 {
            return None;
        }
        let x = element::face_point(flat, q);
        let r = [x[0] - p[0], x[1] - p[1]];
        let (ts, tt) = element::face_tangents(flat, q);
        let jdet = ts[0] * tt[1] - ts[1] * tt[0];
        if jdet.is_nan() || jdet == 0.0 {
            return None;
        }
        let step = [
            -(r[0] * tt[1] - r[1] * tt[0]) / jdet,
            -(ts[0] * r[1] - ts[1] * r[0]) / jdet,
        ];
        q = [q[0] + step[0], q[1] + step[1]];
        if step[0].abs().max(step[1].abs()) < 1e-14 || (r[0].hypot(r[1]) < 1e-15 * size) {
            return Some(q);
        }
    }
    None
}

/// The mean plane of a surface. See [`MeanPlane`].
fn mean_plane(
    mesh: &Mesh,
    surface: &Surface,
    faces: &[[[f64; 3]; 6]],
) -> Result<MeanPlane, ReduceError> {
    let weighted = tributary_areas(mesh, surface);
    let total: f64 = weighted.iter().map(|(_, a)| a).sum();
    let origin = weighted.iter().fold([0.0; 3], |acc, (n, a)| {
        add(acc, scale(a / total, mesh.nodes[*n]))
    });
    let mut covariance = [[0.0; 3]; 3];
    for (n, a) in &weighted {
        let d = sub(mesh.nodes[*n], origin);
        for i in 0..3 {
            for j in 0..3 {
                covariance[i][j] += a / total * d[i] * d[j];
            }
        }
    }
    let (_, vectors) = symmetric_eigen3(covariance);
    let invalid = |why: &str| ReduceError::InvalidSurface {
        surface: surface.name.clone(),
        why: why.into(),
    };
    // Outward: the side the faces' area vectors point to on the whole.
    let area_vector = faces.iter().fold([0.0; 3], |acc, x| {
        let c = element::face_area_vector_at(x, [1.0 / 3.0, 1.0 / 3.0]);
        add(acc, c)
    });
    let mut normal = vectors[0];
    if dot(normal, area_vector) < 0.0 {
        normal = scale(-1.0, normal);
    }
    // A deterministic sign for the first axis: its largest component positive.
    let mut first = vectors[2];
    let largest = first
        .iter()
        .copied()
        .max_by(|a, b| a.abs().total_cmp(&b.abs()))
        .unwrap_or(1.0);
    if largest < 0.0 {
        first = scale(-1.0, first);
    }
    let second = cross(normal, first);
    // NaN (non-finite coordinates) fails this too.
    if norm(second).is_nan() || norm(second) <= 0.5 {
        return Err(invalid("its nodes do not span a plane"));
    }
    let mut plane = MeanPlane {
        origin,
        axes: [first, second],
        normal,
        deviation: 0.0,
        size: 0.0,
    };
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for n in mesh.surface_nodes(surface) {
        let d = sub(mesh.nodes[n], origin);
        plane.deviation = plane.deviation.max(dot(d, normal).abs());
        lo = lo.min(dot(d, first));
        hi = hi.max(dot(d, first));
    }
    plane.size = hi - lo;
    Ok(plane)
}

/// Eigenvalues (ascending) and unit eigenvectors of a symmetric 3x3 matrix (faer).
fn symmetric_eigen3(a: [[f64; 3]; 3]) -> ([f64; 3], [[f64; 3]; 3]) {
    let m = faer::Mat::<f64>::from_fn(3, 3, |i, j| a[i][j]);
    match m.self_adjoint_eigen(faer::Side::Lower) {
        Ok(evd) => {
            let (s, u) = (evd.S().column_vector(), evd.U());
            let mut order = [0, 1, 2];
            order.sort_by(|&i, &j| s[i].total_cmp(&s[j]));
            (
                order.map(|k| s[k]),
                order.map(|k| [0, 1, 2].map(|i| u[(i, k)])),
            )
        }
        // Only non-finite coordinates fail; the checks after it report them as no plane.
        Err(_) => ([f64::NAN; 3], [[f64::NAN; 3]; 3]),
    }
}

/// Distance between two points of the mean plane.
fn distance2d(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::project_on_face;
    use crate::mesh::brake;
    use crate::mesh::Face;

    /// A flat-or-bowed annular sector surface `r_in..r_out` x `-arc/2..arc/2` (degrees) with
    /// `nr x nt` cells, each cut into two 6-node triangles whose mid nodes sit at the polar
    /// midpoints (curved edges), height `z(x, y)`, normal +z.
    fn sector(
        r_in: f64,
        r_out: f64,
        arc_deg: f64,
        [nr, nt]: [usize; 2],
        z: impl Fn(f64, f64) -> f64,
    ) -> (Mesh, Surface) {
        let (mr, mt) = (2 * nr + 1, 2 * nt + 1);
        let arc = arc_deg.to_radians();
        let mut mesh = Mesh::default();
        for j in 0..mt {
            for i in 0..mr {
                let r = r_in + (r_out - r_in) * i as f64 / (mr - 1) as f64;
                let t = -0.5 * arc + arc * j as f64 / (mt - 1) as f64;
                let (x, y) = (r * t.cos(), r * t.sin());
                mesh.nodes.push([x, y, z(x, y)]);
            }
        }
        mesh.node_labels = (1..=mesh.nodes.len() as i64).collect();
        let at = |i: usize, j: usize| j * mr + i;
        let mut faces = Vec::new();
        for cj in 0..nt {
            for ci in 0..nr {
                let (i, j) = (2 * ci, 2 * cj);
                for [a, b, c] in [[(0, 0), (2, 0), (2, 2)], [(0, 0), (2, 2), (0, 2)]] {
                    let node = |p: (usize, usize)| at(i + p.0, j + p.1);
                    let mid = |p: (usize, usize), q: (usize, usize)| {
                        at(i + (p.0 + q.0) / 2, j + (p.1 + q.1) / 2)
                    };
                    faces.push(Face {
                        element: 0,
                        side: 0,
                        nodes: [node(a), node(b), node(c), mid(a, b), mid(b, c), mid(c, a)],
                    });
                }
            }
        }
        let surface = Surface {
            name: "pad".into(),
            faces,
        };
        (mesh, surface)
    }

    /// A pad of a passenger-car front brake like the paper's: 50 mm tall, 60 degrees of arc
    /// at 90-140 mm, meshed with about the paper's 1370 surface nodes.
    fn paper_pad() -> (Mesh, Surface) {
        sector(0.090, 0.140, 60.0, [12, 28], |_, _| 0.0)
    }

    fn check_areas(grid: &ContactGrid) {
        let sum: f64 = grid.nodes.iter().map(|n| n.area).sum();
        assert!(
            (sum - grid.surface_area).abs() <= 1e-12 * grid.surface_area,
            "{}: {sum} vs {}",
            grid.surface,
            grid.surface_area
        );
        assert!(grid.nodes.iter().all(|n| n.area >= 0.0));
    }

    #[test]
    fn paper_counts_on_a_paper_like_pad() {
        let (mesh, surface) = paper_pad();
        for size in GridSize::paper_presets() {
            let grid = isometric_grid(&mesh, &surface, size).unwrap();
            eprintln!("paper pad: {}", grid.summary());
            let GridSize::Count(n) = size else {
                unreachable!()
            };
            assert!(grid.count_met, "{}", grid.summary());
            assert_eq!(grid.count(), n);
            check_areas(&grid);
            // Each node's share is about a grid cell's area: an interior node's exactly, a
            // border node's from half a cell (the grid runs on past the border) to about 1.6
            // cells (it also owns the strip between it and the border; measured 1.64 at 106).
            let cell = 0.75f64.sqrt() * grid.spacing * grid.spacing;
            let largest = grid.nodes.iter().map(|n| n.area / cell).fold(0.0, f64::max);
            assert!(largest < 2.0, "largest share {largest} cells");
        }
    }

    #[test]
    fn paper_counts_on_the_built_in_brake_pads() {
        for preset in ["tiny", "small"] {
            let mesh = brake::build(&brake::preset(preset).unwrap()).unwrap();
            for name in ["pad_inboard_friction_face", "pad_outboard_friction_face"] {
                let surface = &mesh.surfaces[name];
                for size in GridSize::paper_presets() {
                    let GridSize::Count(n) = size else {
                        unreachable!()
                    };
                    // The tiny brake's pads have 65 nodes: 106 is no reduction of them.
                    if n > mesh.surface_nodes(surface).len() {
                        assert!(isometric_grid(&mesh, surface, size).is_err());
                        continue;
                    }
                    let grid = isometric_grid(&mesh, surface, size).unwrap();
                    eprintln!("{preset} brake: {}", grid.summary());
                    check_areas(&grid);
                    assert!(grid.count_met, "{}", grid.summary());
                    assert_eq!(grid.count(), n);
                    // The friction faces are flat: the nodes lie on them, normals along the plane's.
                    for node in &grid.nodes {
                        let x = surface.faces[node.face].nodes.map(|k| mesh.nodes[k]);
                        assert!(project_on_face(&x, node.position).distance < 1e-12);
                        assert!(dot(node.normal, grid.plane.normal) > 1.0 - 1e-12);
                    }
                }
            }
        }
    }

    #[test]
    fn a_given_spacing_gives_the_count_and_an_interior_node_owns_a_cell() {
        let (mesh, surface) = paper_pad();
        let h = 0.01;
        let grid = isometric_grid(&mesh, &surface, GridSize::Spacing(h)).unwrap();
        assert!(grid.count_met);
        assert_eq!(grid.spacing, h);
        check_areas(&grid);
        // About area / cell nodes.
        let cell = 0.75f64.sqrt() * h * h;
        let estimate = grid.surface_area / cell;
        assert!(
            (grid.count() as f64 / estimate - 1.0).abs() < 0.15,
            "{}",
            grid.summary()
        );
        // The node nearest the centroid is interior: its Voronoi cell is a whole hexagon of
        // area sqrt(3)/2 h^2, resolved to the sub-triangle size.
        let centre = grid
            .nodes
            .iter()
            .min_by(|a, b| {
                let d = |n: &ReducedNode| n.plane[0].hypot(n.plane[1]);
                d(a).total_cmp(&d(b))
            })
            .unwrap();
        assert!(
            (centre.area / cell - 1.0).abs() < 0.02,
            "{}",
            centre.area / cell
        );
        // Its quadrature points (the patch law's) hold its area to round-off and give its
        // second moment; a regular hexagon's about any in-plane axis through its centre is
        // (5 sqrt 3 / 16) s^4 with s = h / sqrt 3, i.e. (10 / 144) A h^2, to the resolution.
        let area: f64 = centre.patch.iter().map(|p| p.1).sum();
        assert!((area / centre.area - 1.0).abs() < 1e-12);
        let first = [0, 1].map(|i| centre.patch.iter().map(|p| p.1 * p.0[i]).sum::<f64>() / area);
        let second = [0, 1].map(|i| {
            [0, 1].map(|j| {
                centre
                    .patch
                    .iter()
                    .map(|p| p.1 * p.0[i] * p.0[j])
                    .sum::<f64>()
                    - area * first[i] * first[j]
            })
        });
        let hexagon = 10.0 / 144.0 * centre.area * h * h;
        for i in 0..2 {
            for j in 0..2 {
                let d = second[i][j] - centre.second_moment[i][j];
                assert!(
                    d.abs() <= 1e-9 * hexagon,
                    "{second:?} vs {:?}",
                    centre.second_moment
                );
            }
            assert!((second[i][i] / hexagon - 1.0).abs() < 0.02, "{second:?}");
        }
        assert!(second[0][1].abs() < 0.02 * hexagon, "{second:?}");
        // Lattice vectors of length h, 60 degrees apart.
        let [a, b] = grid.lattice;
        assert!((a[0].hypot(a[1]) - h).abs() < 1e-15);
        assert!(((a[0] * b[0] + a[1] * b[1]) / (h * h) - 0.5).abs() < 1e-12);
    }

    #[test]
    fn nodes_lie_on_a_bowed_surface_with_its_normal() {
        let (mesh, surface) = sector(0.090, 0.140, 60.0, [6, 14], |x, _| {
            0.3 * (x - 0.115).powi(2)
        });
        let grid = isometric_grid(&mesh, &surface, GridSize::Count(22)).unwrap();
        check_areas(&grid);
        for node in &grid.nodes {
            let x = surface.faces[node.face].nodes.map(|k| mesh.nodes[k]);
            // On the curved face, and straight above its grid point along the plane's normal.
            assert!(project_on_face(&x, node.position).distance < 1e-12);
            let back = grid.plane.to_plane(node.position);
            assert!(distance2d(back, node.plane) < 1e-12);
            let expect = element::face_normal_at(&x, node.local).unwrap();
            assert!(norm(sub(node.normal, expect)) < 1e-15);
            assert!(node.normal[2] > 0.99);
        }
    }

    #[test]
    fn a_surface_far_from_planar_is_an_error_naming_it() {
        let (mesh, surface) = sector(0.090, 0.140, 60.0, [6, 14], |x, _| {
            50.0 * (x - 0.115).powi(2)
        });
        let err = isometric_grid(&mesh, &surface, GridSize::Count(6)).unwrap_err();
        assert!(matches!(err, ReduceError::NotPlanar { .. }), "{err}");
        assert!(err.to_string().contains("'pad'"), "{err}");
    }

    #[test]
    fn a_count_of_zero_or_a_spacing_leaving_no_node_is_an_error() {
        let (mesh, surface) = paper_pad();
        let err = isometric_grid(&mesh, &surface, GridSize::Count(0)).unwrap_err();
        let text = err.to_string();
        assert!(
            text.contains("'pad'") && text.contains("0 reduced contact node"),
            "{text}"
        );
        // More nodes than the face has: no reduction, refused before any search.
        let nodes = mesh.surface_nodes(&surface).len();
        let text = isometric_grid(&mesh, &surface, GridSize::Count(nodes + 1))
            .unwrap_err()
            .to_string();
        assert!(
            text.contains(&format!("the surface has {nodes} nodes")),
            "{text}"
        );
        // A thin ring of 300 degrees: its centroid, where the grid's origin goes, lies off it,
        // and h = 1 m puts no other grid point near it.
        let (mesh, surface) = sector(0.090, 0.100, 300.0, [1, 20], |_, _| 0.0);
        let err = isometric_grid(&mesh, &surface, GridSize::Spacing(1.0)).unwrap_err();
        assert!(matches!(err, ReduceError::NoNode { .. }), "{err}");
        assert!(
            err.to_string().contains("h = 1e0") && err.to_string().contains("'pad'"),
            "{err}"
        );
        for h in [0.0, -1.0, f64::NAN] {
            assert!(matches!(
                isometric_grid(&mesh, &surface, GridSize::Spacing(h)),
                Err(ReduceError::InvalidSize { .. })
            ));
        }
    }

    #[test]
    fn a_count_no_layout_reaches_gives_the_nearest_one_flagged() {
        // A strip 1 x 0.001: only grid points on one line through it can fall on it, about
        // 1 / h of them, and h is searched around the h0 at which 2 cells cover the strip's
        // area (h0 = 0.034): no layout keeps as few as 2.
        let material = crate::mesh::Material {
            name: "m".into(),
            young: 1.0,
            poisson: 0.3,
            density: 1.0,
        };
        let mesh =
            crate::mesh::block::block([0.0; 3], [1.0, 0.001, 0.001], [40, 1, 1], material).unwrap();
        let surface = &mesh.surfaces["z1"];
        let grid = isometric_grid(&mesh, surface, GridSize::Count(2)).unwrap();
        assert!(!grid.count_met);
        assert!(grid.count() > 2);
        assert!(
            grid.summary().contains("no layout keeps exactly 2"),
            "{}",
            grid.summary()
        );
        check_areas(&grid);
    }

    #[test]
    fn grid_sizes_read_as_count_or_spacing() {
        let count: GridSize = serde_json::from_str(r#"{"count": 52}"#).unwrap();
        assert_eq!(count, GridSize::Count(52));
        let spacing: GridSize = serde_json::from_str(r#"{"spacing": 0.01}"#).unwrap();
        assert_eq!(spacing, GridSize::Spacing(0.01));
    }

    #[test]
    fn the_mean_plane_of_a_flat_pad_is_its_plane() {
        let (mesh, surface) = sector(0.090, 0.140, 60.0, [4, 8], |_, _| 0.25);
        let grid = isometric_grid(&mesh, &surface, GridSize::Count(6)).unwrap();
        let plane = grid.plane;
        assert!(plane.deviation < 1e-15);
        assert!((plane.normal[2] - 1.0).abs() < 1e-15);
        assert!((plane.origin[2] - 0.25).abs() < 1e-15);
        // The first axis along the longest extent: across the arc (y).
        assert!(plane.axes[0][1].abs() > 0.999);
    }
}
