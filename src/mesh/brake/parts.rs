//! The brake's parts: the disc and the two pads (lining and backplate) as structured grids in
//! cylindrical coordinates, meshed by [`crate::mesh::structured`], with their materials and a
//! check that no curved element is inverted.

use std::f64::consts::PI;
use std::ops::Range;

use super::{caliper, BrakeError, BrakeParams};
use crate::mesh::structured::{Grid, Meshed, NodeOrder, Numbering, TetOrder};
use crate::mesh::{Material, Mesh, Part, TET10_EDGES};

// Parts, in the order of `Mesh::parts`.
pub(super) const DISC: usize = 0;
pub(super) const INBOARD_FRICTION: usize = 1;
pub(super) const INBOARD_BACKPLATE: usize = 2;
pub(super) const OUTBOARD_FRICTION: usize = 3;
pub(super) const OUTBOARD_BACKPLATE: usize = 4;
pub(super) const PISTON: usize = 5;
pub(super) const CALIPER: usize = 6;
pub(super) const BRACKET: usize = 7;
const PART_NAMES: [&str; 8] = [
    "disc",
    "pad_inboard_friction",
    "pad_inboard_backplate",
    "pad_outboard_friction",
    "pad_outboard_backplate",
    "piston",
    "caliper",
    "bracket",
];
const PART_MATERIALS: [&str; 8] = [
    "cast_iron",
    "friction_material",
    "steel",
    "friction_material",
    "steel",
    "steel",
    "ductile_iron",
    "ductile_iron",
];

// Parameter axes of a block, in this order so that (r, theta, z) -> (r cos, r sin, z) is
// orientation preserving (its Jacobian determinant is r > 0).
pub(super) const R: usize = 0;
pub(super) const THETA: usize = 1;
pub(super) const Z: usize = 2;

/// How the brake's grids are numbered: theta slowest, then r, then z, for cells and nodes,
/// so that node numbers sweep around the disc (a narrow band of the stiffness matrix); all
/// nodes in refined-grid order. Pinned by `mesh::fingerprint`.
const NUMBERING: Numbering = Numbering {
    sweep: [THETA, R, Z],
    nodes: NodeOrder::RefinedGrid,
    tets: TetOrder::EvenFirst,
};

/// How a block's parameters map to positions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Map {
    /// (r, theta, z) about the disc axis.
    Disc,
    /// (rho, phi, z) about the piston's axis at `axis`, phi = 0 along `phase`.
    Local { axis: [f64; 2], phase: f64 },
}

impl Map {
    fn apply(self, x: [f64; 3]) -> [f64; 3] {
        match self {
            Map::Disc => cartesian(x),
            Map::Local { axis, phase } => {
                let [rho, phi, z] = x;
                let t = phi + phase;
                [axis[0] + rho * t.cos(), axis[1] + rho * t.sin(), z]
            }
        }
    }
}

/// One part block: a grid in (r, theta, z) (or the piston's local coordinates) and the part
/// of each of its cells.
pub(super) struct PartGrid {
    pub(super) grid: Grid,
    /// Part of each cell (`None` where the block has none: the lining under the backplate
    /// ears, the caliper's bore), at `(cell[R] * n_theta + cell[THETA]) * n_z + cell[Z]`.
    tags: Vec<Option<usize>>,
    pub(super) map: Map,
}

impl PartGrid {
    fn new(grid: Grid, map: Map, tag: impl Fn([usize; 3]) -> Option<usize>) -> PartGrid {
        let [nr, nt, nz] = grid.cells();
        let mut tags = Vec::with_capacity(nr * nt * nz);
        for i in 0..nr {
            for j in 0..nt {
                for k in 0..nz {
                    tags.push(tag([i, j, k]));
                }
            }
        }
        PartGrid { grid, tags, map }
    }

    pub(super) fn part(&self, cell: [usize; 3]) -> Option<usize> {
        let [_, nt, nz] = self.grid.cells();
        self.tags[(cell[R] * nt + cell[THETA]) * nz + cell[Z]]
    }

    /// (nodes, elements) of the block.
    pub(super) fn count(&self) -> (usize, usize) {
        self.grid.count(|cell| self.part(cell))
    }
}

/// (r, theta, z) -> (r cos theta, r sin theta, z).
fn cartesian([r, theta, z]: [f64; 3]) -> [f64; 3] {
    [r * theta.cos(), r * theta.sin(), z]
}

/// `n` cells between `a` and `b`; the end values are exactly `a` and `b`, so that touching
/// parts share bit-identical coordinates.
fn linspace(a: f64, b: f64, n: usize) -> Vec<f64> {
    (0..=n)
        .map(|i| {
            if i == n {
                b
            } else {
                a + (b - a) * (i as f64 / n as f64)
            }
        })
        .collect()
}

/// The part blocks: disc, inboard pad, outboard pad, and for the floating-caliper layout the
/// piston, caliper and bracket. Also returns the theta-cell range of the lining (same in
/// both pads).
pub(super) fn grids(p: &BrakeParams) -> (Vec<PartGrid>, Range<usize>) {
    let d = &p.divisions;
    let half = 0.5 * p.disc_thickness;
    let disc = PartGrid::new(
        Grid {
            lines: [
                linspace(p.disc_inner_radius, p.disc_outer_radius, d.disc_radial),
                linspace(0.0, 2.0 * PI, d.disc_circumferential),
                linspace(-half, half, d.disc_thickness),
            ],
            periodic: [false, true, false],
        },
        Map::Disc,
        |_| Some(DISC),
    );

    let o = p.overhang_cells();
    let centre = p.pad_centre_deg.to_radians();
    let half_arc = 0.5 * p.pad_arc_deg.to_radians();
    let ear = p.backplate_overhang_deg.to_radians();
    let (radii, lining_theta) = if p.floating_caliper() {
        let (radii, thetas) = caliper::pad_lines(p);
        (radii.lines, thetas.lines)
    } else {
        (
            linspace(p.pad_inner_radius, p.pad_outer_radius, d.pad_radial),
            linspace(centre - half_arc, centre + half_arc, d.pad_circumferential),
        )
    };
    let lining_cells = lining_theta.len() - 1;
    let mut theta = Vec::with_capacity(lining_cells + 2 * o + 1);
    if o > 0 {
        let left = linspace(centre - half_arc - ear, centre - half_arc, o);
        theta.extend_from_slice(&left[..o]);
    }
    theta.extend(lining_theta);
    if o > 0 {
        let right = linspace(centre + half_arc, centre + half_arc + ear, o);
        theta.extend_from_slice(&right[1..]);
    }
    let lining = o..o + lining_cells;

    // Inboard pad from the friction face up: lining layers first, then the backplate.
    let z0 = half + p.pad_gap;
    let z1 = z0 + p.friction_thickness;
    let z2 = z1 + p.backplate_thickness;
    let mut z_in = linspace(z0, z1, d.friction_thickness);
    z_in.extend_from_slice(&linspace(z1, z2, d.backplate_thickness)[1..]);
    let (nf, nb) = (d.friction_thickness, d.backplate_thickness);
    let pad = |friction_first: bool, friction: usize, backplate: usize| {
        let lining = lining.clone();
        move |cell: [usize; 3]| {
            let k = cell[Z];
            let is_friction = if friction_first { k < nf } else { k >= nb };
            if !is_friction {
                Some(backplate)
            } else if lining.contains(&cell[THETA]) {
                Some(friction)
            } else {
                None
            }
        }
    };
    let inboard = PartGrid::new(
        Grid {
            lines: [radii.clone(), theta.clone(), z_in.clone()],
            periodic: [false; 3],
        },
        Map::Disc,
        pad(true, INBOARD_FRICTION, INBOARD_BACKPLATE),
    );
    // Outboard pad: the mirror image in z = 0 (exact negation), z increasing from the
    // backplate's back face to the friction face.
    let z_out: Vec<f64> = z_in.iter().rev().map(|z| -z).collect();
    let outboard = PartGrid::new(
        Grid {
            lines: [radii, theta, z_out],
            periodic: [false; 3],
        },
        Map::Disc,
        pad(false, OUTBOARD_FRICTION, OUTBOARD_BACKPLATE),
    );
    let mut blocks = vec![disc, inboard, outboard];
    if p.floating_caliper() {
        let piston = caliper::piston(p);
        blocks.push(PartGrid::new(
            piston.grid.clone(),
            Map::Local {
                axis: piston.axis,
                phase: piston.phase,
            },
            |_| Some(PISTON),
        ));
        for (block, part) in [
            (caliper::caliper(p), CALIPER),
            (caliper::bracket(p), BRACKET),
        ] {
            blocks.push(PartGrid::new(block.grid(), Map::Disc, |cell| {
                block.has(cell).then_some(part)
            }));
        }
    }
    (blocks, lining)
}

/// Barycentric points where [`mesh`] checks the Jacobian: the 4 corners and the 4-point
/// Gauss rule used for the stiffness.
pub(super) const CHECK_POINTS: [[f64; 4]; 8] = {
    const A: f64 = 0.585_410_196_624_968_5;
    const B: f64 = 0.138_196_601_125_010_5;
    [
        [1.0, 0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0],
        [0.0, 0.0, 0.0, 1.0],
        [A, B, B, B],
        [B, A, B, B],
        [B, B, A, B],
        [B, B, B, A],
    ]
};

/// Determinant of the Jacobian of the TET10 map at barycentric point `l` (l[0] = 1 - xi -
/// eta - zeta, l[1] = xi, l[2] = eta, l[3] = zeta), node order of [`TET10_EDGES`].
pub(super) fn jacobian_det(x: &[[f64; 3]; 10], l: [f64; 4]) -> f64 {
    // d l_i / d(xi, eta, zeta).
    const DL: [[f64; 3]; 4] = [
        [-1.0, -1.0, -1.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    let mut jac = [[0.0f64; 3]; 3];
    let mut add = |node: usize, grad: [f64; 3]| {
        for (row, coord) in jac.iter_mut().zip(x[node]) {
            for (entry, g) in row.iter_mut().zip(grad) {
                *entry += coord * g;
            }
        }
    };
    for i in 0..4 {
        // N_i = l_i (2 l_i - 1).
        add(i, DL[i].map(|g| (4.0 * l[i] - 1.0) * g));
    }
    for (m, [a, b]) in TET10_EDGES.iter().enumerate() {
        // N = 4 l_a l_b.
        add(
            4 + m,
            [0, 1, 2].map(|d| 4.0 * (l[*a] * DL[*b][d] + l[*b] * DL[*a][d])),
        );
    }
    jac[0][0] * (jac[1][1] * jac[2][2] - jac[1][2] * jac[2][1])
        - jac[0][1] * (jac[1][0] * jac[2][2] - jac[1][2] * jac[2][0])
        + jac[0][2] * (jac[1][0] * jac[2][1] - jac[1][1] * jac[2][0])
}

/// The meshed part blocks, for picking the named sets.
pub(super) struct MeshedParts {
    /// Disc, inboard pad, outboard pad (then piston, caliper, bracket for the
    /// floating-caliper layout); each element tagged with its part.
    pub(super) blocks: Vec<Meshed<usize>>,
    /// Cells per axis of the disc and of a pad.
    pub(super) disc_cells: [usize; 3],
    pub(super) pad_cells: [usize; 3],
    /// The theta-cell range of the lining (same in both pads).
    pub(super) lining: Range<usize>,
}

/// The mesh of the parts with labels, parts and materials (no sets yet). Each block's nodes
/// are every used point of its refined grid, one node per point shared by all elements
/// around it; numbered block after block. Errors if a curved element is inverted.
pub(super) fn mesh(params: &BrakeParams) -> Result<(Mesh, MeshedParts), BrakeError> {
    let (grids, lining) = grids(params);
    let mut mesh = Mesh::default();
    mesh.elements.reserve(params.element_count());
    mesh.nodes.reserve(params.node_count());
    let blocks: Vec<Meshed<usize>> = grids
        .iter()
        .map(|g| {
            g.grid.mesh(
                &mut mesh,
                &NUMBERING,
                |cell| g.part(cell),
                |x| g.map.apply(x),
            )
        })
        .collect();
    mesh.node_labels = (1..=mesh.nodes.len() as i64).collect();
    mesh.element_labels = (1..=mesh.elements.len() as i64).collect();

    let part_count = if params.floating_caliper() {
        PART_NAMES.len()
    } else {
        OUTBOARD_BACKPLATE + 1
    };
    let mut parts: Vec<Vec<usize>> = vec![Vec::new(); part_count];
    for block in &blocks {
        for (e, origin) in block.elements.iter().enumerate() {
            let e = block.first_element + e;
            let x = mesh.elements[e].map(|n| mesh.nodes[n]);
            let bad = CHECK_POINTS
                .iter()
                .map(|l| jacobian_det(&x, *l))
                .find(|det| det.is_nan() || *det <= 0.0);
            if let Some(det) = bad {
                return Err(BrakeError::Inverted {
                    part: PART_NAMES[origin.tag].to_string(),
                    label: mesh.element_labels[e],
                    det,
                });
            }
            parts[origin.tag].push(e);
        }
    }
    mesh.parts = PART_NAMES
        .iter()
        .zip(PART_MATERIALS)
        .zip(parts)
        .map(|((name, material), elements)| Part {
            name: name.to_string(),
            elements,
            material: Some(material.to_string()),
        })
        .collect();
    let mut materials = vec![
        ("cast_iron", params.cast_iron),
        ("friction_material", params.friction_material),
        ("steel", params.steel),
    ];
    if params.floating_caliper() {
        materials.push(("ductile_iron", params.ductile_iron));
    }
    for (name, e) in materials {
        mesh.materials.insert(
            name.to_string(),
            Material {
                name: name.to_string(),
                young: e.young,
                poisson: e.poisson,
                density: e.density,
            },
        );
    }
    let (disc_cells, pad_cells) = (grids[DISC].grid.cells(), grids[1].grid.cells());
    let meshed = MeshedParts {
        blocks,
        disc_cells,
        pad_cells,
        lining,
    };
    Ok((mesh, meshed))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::brake::test_geometry::*;
    use crate::mesh::brake::{build, preset, PRESETS};
    use crate::vector3::{dot, sub};
    use std::collections::HashMap;

    #[test]
    fn tiny_builds_well_under_a_second() {
        let start = std::time::Instant::now();
        let m = build(&preset("tiny").unwrap()).unwrap();
        assert!(!m.nodes.is_empty());
        // Debug build on a loaded machine: a generous bound; it takes a few milliseconds.
        assert!(start.elapsed().as_secs_f64() < 1.0, "{:?}", start.elapsed());
    }

    #[test]
    fn every_element_is_positive_and_its_mid_nodes_sit_on_the_parametric_middle() {
        for name in ["tiny", "small"] {
            let m = build(&preset(name).unwrap()).unwrap();
            let (a, b) = (0.5, 1.0 / 6.0);
            let mut points: Vec<[f64; 4]> = CHECK_POINTS.to_vec();
            points.extend([
                [0.25; 4],
                [a, b, b, b],
                [b, a, b, b],
                [b, b, a, b],
                [b, b, b, a],
            ]);
            for [i, j] in TET10_EDGES {
                let mut l = [0.0; 4];
                l[i] = 0.5;
                l[j] = 0.5;
                points.push(l);
            }
            for (e, conn) in m.elements.iter().enumerate() {
                assert!(m.corner_volume(e) > 0.0, "{name}: element {e}");
                let x = conn.map(|n| m.nodes[n]);
                for l in &points {
                    assert!(jacobian_det(&x, *l) > 0.0, "{name}: element {e} at {l:?}");
                }
                // Mid node = (r, theta, z) average of its corners, theta unwrapped across
                // the seam: on the circle, not on the chord. Coordinates are ~0.1 m and
                // exact to a few ulps; 1e-12 m leaves margin for atan2's rounding.
                for (k, [i, j]) in TET10_EDGES.iter().enumerate() {
                    let (ci, cj) = (cylindrical(x[*i]), cylindrical(x[*j]));
                    let mut dt = cj[1] - ci[1];
                    if dt > PI {
                        dt -= 2.0 * PI;
                    } else if dt < -PI {
                        dt += 2.0 * PI;
                    }
                    let (r, t, z) = (
                        0.5 * (ci[0] + cj[0]),
                        ci[1] + 0.5 * dt,
                        0.5 * (ci[2] + cj[2]),
                    );
                    let expect = [r * t.cos(), r * t.sin(), z];
                    let d = sub(x[4 + k], expect);
                    assert!(dot(d, d).sqrt() < 1e-12, "{name}: element {e} edge {k}");
                }
            }
        }
    }

    #[test]
    fn part_volumes_match_the_discretised_and_the_true_geometry() {
        for name in ["tiny", "small"] {
            let p = preset(name).unwrap();
            let m = build(&p).unwrap();
            let d = &p.divisions;
            let h_disc = 2.0 * PI / d.disc_circumferential as f64;
            let cells = pad_cells(&p);
            let (r1, r2) = (p.pad_inner_radius, p.pad_outer_radius);
            let disc_cells = [(h_disc, d.disc_circumferential)];
            let lining_area = ring_area(r1, r2, &cells[..1]);
            let backplate_area = ring_area(r1, r2, &cells);
            let backplate_arc = (p.pad_arc_deg + 2.0 * p.backplate_overhang_deg).to_radians();
            let lining_arc = p.pad_arc_deg.to_radians();
            let exact_sector = |arc: f64| 0.5 * (r2 * r2 - r1 * r1) * arc;
            let expected = [
                (
                    "disc",
                    p.disc_thickness
                        * ring_area(p.disc_inner_radius, p.disc_outer_radius, &disc_cells),
                    p.disc_thickness
                        * PI
                        * (p.disc_outer_radius.powi(2) - p.disc_inner_radius.powi(2)),
                    h_disc,
                ),
                (
                    "pad_inboard_friction",
                    p.friction_thickness * lining_area,
                    p.friction_thickness * exact_sector(lining_arc),
                    cells[0].0,
                ),
                (
                    "pad_inboard_backplate",
                    p.backplate_thickness * backplate_area,
                    p.backplate_thickness * exact_sector(backplate_arc),
                    cells[0].0.max(cells[1].0),
                ),
                (
                    "pad_outboard_friction",
                    p.friction_thickness * lining_area,
                    p.friction_thickness * exact_sector(lining_arc),
                    cells[0].0,
                ),
                (
                    "pad_outboard_backplate",
                    p.backplate_thickness * backplate_area,
                    p.backplate_thickness * exact_sector(backplate_arc),
                    cells[0].0.max(cells[1].0),
                ),
            ];
            for (part_name, discretised, exact, h) in expected {
                let v: f64 = part(&m, part_name)
                    .elements
                    .iter()
                    .map(|&e| element_volume(&m, e))
                    .sum();
                // The elements tile the region bounded by flat faces and parabolic arcs
                // exactly (shared quadratic faces cancel), so only summation round-off is
                // left: ~n * eps relative.
                let rel = (v - discretised).abs() / discretised;
                assert!(
                    rel < 1e-11,
                    "{name} {part_name}: {v} vs {discretised} ({rel:e})"
                );
                // The parabolic arc lies inside the circle by (h/2)^4 / 30 of the sector
                // area to leading order (expansion of `fan`); allow 10 % for the next term.
                let chord = (exact - v) / exact;
                let bound = 1.1 * (0.5 * h).powi(4) / 30.0;
                assert!(
                    chord >= 0.0 && chord < bound,
                    "{name} {part_name}: {v} vs {exact} ({chord:e} > {bound:e})"
                );
            }
        }
    }

    #[test]
    fn mesh_is_conforming_across_the_seam_and_the_glued_interface() {
        let (p, m) = tiny();
        let owner = m.element_parts();
        let mut faces: HashMap<[usize; 3], Vec<(usize, [usize; 6])>> = HashMap::new();
        for e in 0..m.elements.len() {
            for side in 0..4u8 {
                let f = m.face(e, side);
                let mut corners = [f.nodes[0], f.nodes[1], f.nodes[2]];
                corners.sort_unstable();
                let mut all = f.nodes;
                all.sort_unstable();
                faces.entry(corners).or_default().push((e, all));
            }
        }
        let d = &p.divisions;
        let mut boundary = 0;
        let mut seam = 0;
        let mut glued = 0;
        for (corners, users) in &faces {
            assert!(
                users.len() <= 2,
                "face {corners:?} shared by {} elements",
                users.len()
            );
            if users.len() == 1 {
                boundary += 1;
                continue;
            }
            let ((e0, n0), (e1, n1)) = (users[0], users[1]);
            assert_eq!(n0, n1, "shared face {corners:?} with different mid nodes");
            let (p0, p1) = (owner[e0].unwrap(), owner[e1].unwrap());
            if p0 != p1 {
                // Only lining and backplate of one pad may share faces.
                let pair = [p0.min(p1), p0.max(p1)];
                assert!(
                    pair == [INBOARD_FRICTION, INBOARD_BACKPLATE]
                        || pair == [OUTBOARD_FRICTION, OUTBOARD_BACKPLATE],
                    "parts {p0} and {p1} share a face"
                );
                glued += 1;
            }
            if p0 == DISC
                && corners
                    .iter()
                    .all(|&n| m.nodes[n][1] == 0.0 && m.nodes[n][0] > 0.0)
            {
                seam += 1;
            }
        }
        // Independent count of boundary quads (2 triangles each). Disc: 2 faces + inner
        // and outer cylinder, no theta ends (it is closed). Pad: T = lining + ear cells;
        // backplate top, ear bottoms, inner/outer edges, ends; lining friction face, inner
        // and outer edges, ends.
        let (nt, nr, nz) = (d.disc_circumferential, d.disc_radial, d.disc_thickness);
        let (pt, pr, pf, pb) = (
            d.pad_circumferential,
            d.pad_radial,
            d.friction_thickness,
            d.backplate_thickness,
        );
        let t = pt + 2 * p.overhang_cells();
        let disc_quads = 2 * nt * nr + 2 * nt * nz;
        let pad_quads =
            t * pr + (t - pt) * pr + 2 * t * pb + 2 * pr * pb + pt * pr + 2 * pt * pf + 2 * pr * pf;
        assert_eq!(boundary, 2 * (disc_quads + 2 * pad_quads));
        // The theta = 0 half-plane inside the disc: every quad there is shared.
        assert_eq!(seam, 2 * nr * nz);
        assert_eq!(glued, 2 * 2 * pt * pr);
    }

    #[test]
    fn no_unused_or_duplicate_nodes_and_contiguous_labels() {
        for name in ["tiny", "small"] {
            let m = build(&preset(name).unwrap()).unwrap();
            let mut used = vec![false; m.nodes.len()];
            for conn in &m.elements {
                for &n in conn {
                    used[n] = true;
                }
            }
            assert!(used.iter().all(|&u| u), "{name}: unused node");
            let mut order: Vec<usize> = (0..m.nodes.len()).collect();
            order.sort_by(|&a, &b| m.nodes[a][0].total_cmp(&m.nodes[b][0]));
            for (k, &a) in order.iter().enumerate() {
                for &b in &order[k + 1..] {
                    if m.nodes[b][0] - m.nodes[a][0] > 1e-9 {
                        break;
                    }
                    let d = sub(m.nodes[a], m.nodes[b]);
                    assert!(
                        dot(d, d).sqrt() > 1e-9,
                        "{name}: nodes {a} and {b} coincide"
                    );
                }
            }
            assert!(m
                .node_labels
                .iter()
                .enumerate()
                .all(|(i, &l)| l == i as i64 + 1));
            assert!(m
                .element_labels
                .iter()
                .enumerate()
                .all(|(i, &l)| l == i as i64 + 1));
            let mut in_parts: Vec<usize> =
                m.parts.iter().flat_map(|p| p.elements.clone()).collect();
            in_parts.sort_unstable();
            assert_eq!(
                in_parts,
                (0..m.elements.len()).collect::<Vec<_>>(),
                "{name}"
            );
            for part in &m.parts {
                let material = part.material.as_ref().unwrap();
                assert!(m.materials.contains_key(material), "{}", part.name);
            }
        }
    }

    #[test]
    fn pads_touch_the_disc_faces_without_matching_nodes() {
        for name in ["tiny", "small"] {
            let p = preset(name).unwrap();
            let m = build(&p).unwrap();
            for (pad, disc) in [
                ("pad_inboard_friction_face", "disc_inboard_face"),
                ("pad_outboard_friction_face", "disc_outboard_face"),
            ] {
                let disc_nodes = &m.node_sets[disc];
                let z = m.nodes[disc_nodes[0]][2];
                assert_eq!(z.abs(), 0.5 * p.disc_thickness);
                for &n in &m.node_sets[pad] {
                    // Bit-identical plane: zero initial gap.
                    assert_eq!(m.nodes[n][2], z, "{name} {pad}");
                    for &q in disc_nodes {
                        let d = sub(m.nodes[n], m.nodes[q]);
                        assert!(
                            dot(d, d).sqrt() > 1e-9,
                            "{name}: pad node {n} on disc node {q}"
                        );
                    }
                }
            }
        }
    }

    /// For every preset, not only the ones built here: the disc and pad grids are tensor
    /// products, so a pad friction-face node sits on a disc face node only if some refined
    /// radius and some refined angle of the two grids coincide.
    #[test]
    fn no_preset_has_pad_nodes_on_disc_nodes() {
        let refined = |lines: &[f64]| {
            let mut v: Vec<f64> = lines.to_vec();
            v.extend(lines.windows(2).map(|w| 0.5 * (w[0] + w[1])));
            v
        };
        let common = |a: &[f64], b: &[f64], period: Option<f64>| {
            a.iter().any(|x| {
                b.iter().any(|y| {
                    let mut d = (x - y).abs();
                    if let Some(p) = period {
                        d = d.rem_euclid(p).min(p - d.rem_euclid(p));
                    }
                    d < 1e-9
                })
            })
        };
        for &name in PRESETS {
            let p = preset(name).unwrap();
            let (blocks, _) = grids(&p);
            let (disc, pad) = (&blocks[DISC], &blocks[1]);
            let radii = common(
                &refined(&disc.grid.lines[R]),
                &refined(&pad.grid.lines[R]),
                None,
            );
            let angles = common(
                &refined(&disc.grid.lines[THETA]),
                &refined(&pad.grid.lines[THETA]),
                Some(2.0 * PI),
            );
            assert!(
                !(radii && angles),
                "{name}: matching nodes at the interface"
            );
        }
    }

    #[test]
    fn the_gap_moves_the_pads_off_the_disc() {
        let p = BrakeParams {
            pad_gap: 5e-4,
            ..preset("tiny").unwrap()
        };
        let m = build(&p).unwrap();
        let z = 0.5 * p.disc_thickness + p.pad_gap;
        for &n in &m.node_sets["pad_inboard_friction_face"] {
            assert_eq!(m.nodes[n][2], z);
        }
        for &n in &m.node_sets["pad_outboard_friction_face"] {
            assert_eq!(m.nodes[n][2], -z);
        }
        // Without ears the backplate ends with the lining.
        let flush = build(&BrakeParams {
            backplate_overhang_deg: 0.0,
            ..p
        })
        .unwrap();
        assert_eq!(
            flush.nodes.len(),
            BrakeParams {
                backplate_overhang_deg: 0.0,
                ..preset("tiny").unwrap()
            }
            .node_count()
        );
        assert!(!flush.surfaces["pad_inboard_abutment_leading"]
            .faces
            .is_empty());
    }

    /// `cargo test --release -- --ignored --nocapture` prints the sizes and the build time.
    #[test]
    #[ignore]
    fn industrial_preset_builds_and_prints_sizes() {
        for &name in PRESETS {
            let p = preset(name).unwrap();
            let start = std::time::Instant::now();
            let m = build(&p).unwrap();
            let elapsed = start.elapsed();
            assert_eq!(m.nodes.len(), p.node_count());
            assert_eq!(m.elements.len(), p.element_count());
            println!(
                "{name:>18}: {:>7} nodes {:>7} elements, built in {:.3} s",
                m.nodes.len(),
                m.elements.len(),
                elapsed.as_secs_f64()
            );
            let (blocks, _) = grids(&p);
            let sizes: Vec<(usize, usize)> = blocks.iter().map(|b| b.count()).collect();
            println!("{:>18}  per block (nodes, elements): {sizes:?}", "");
        }
    }
}
