//! The one structured TET10 mesher: a mapped hexahedral grid, each cell split into the six
//! Kuhn tetrahedra, with quadratic mid-edge nodes shared between neighbours. The test blocks
//! ([`super::block`]) and every part of the built-in brake ([`super::brake`]) are made by it.
//!
//! The grid lives in parameter space: per axis a list of cell boundaries ("lines"). A cell
//! (i, j, k) is the box between lines i..i+1, j..j+1, k..k+1, and a caller-supplied map takes
//! parameter values to positions (the identity for a block; (r, theta, z) -> Cartesian for a
//! brake part). The map must preserve orientation (positive Jacobian determinant), so that the
//! positively oriented parametric tetrahedra stay positive.
//!
//! Why Kuhn (Freudenthal): the six tetrahedra of a cell are the monotone paths from its low
//! corner to its high one along the cube edges. The split is the same translated pattern in
//! every cell, so the face diagonals of neighbouring cells agree and the mesh conforms without
//! any bookkeeping, also across the seam of a periodic axis (a closed ring).
//!
//! Why the refined grid: every node of the quadratic mesh (corner, mid-edge on a cell edge, a
//! face diagonal or the body diagonal) is a point of the grid refined by two in every
//! direction. A point has integer "refined" coordinates `p`: `p[axis] / 2` is a line index
//! when `p[axis]` is even and the middle of a cell when odd. Mid-edge nodes are placed at the
//! parametric middle (the average of two lines, then mapped), which puts them on the true
//! circular arcs of a cylindrical map, and each refined point is one node, shared by every
//! element that uses it.

use super::{Face, Mesh, TET10_EDGES, TET10_FACES};

/// A structured grid in parameter space.
#[derive(Clone, Debug, PartialEq)]
pub struct Grid {
    /// Cell boundaries per parameter axis, increasing, at least two per axis.
    pub lines: [Vec<f64>; 3],
    /// Axes that wrap around: the last line is the first one again (the angle of a closed
    /// ring), so the last cell's high face is the first cell's low face and the points of
    /// the last line are the points of the first. Their positions come from the first line.
    pub periodic: [bool; 3],
}

/// How the cells, tetrahedra and nodes of a grid are numbered. None of this changes the
/// geometry; it changes the order of nodes and elements, hence the band of the matrices and
/// the bits of every result computed from the mesh.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Numbering {
    /// The axes from the slowest varying to the fastest, for cells and for nodes alike.
    /// Sweeping the longest direction slowest keeps node numbers of neighbours close (a
    /// narrow band): the brake sweeps the angle, the blocks sweep z, then y, then x.
    pub sweep: [usize; 3],
    /// Which nodes come first.
    pub nodes: NodeOrder,
    /// In which order a cell lists its six tetrahedra.
    pub tets: TetOrder,
}

/// Node numbering of a structured mesh. Only points used by an element become nodes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NodeOrder {
    /// Every node (corner or mid-edge) in refined-grid order along the sweep: neighbours in
    /// space are neighbours in number (the brake).
    RefinedGrid,
    /// The cell corners first, in grid order along the sweep, then the mid-edge nodes in the
    /// order the elements first use them (the blocks: the layout of a hand-written mesh).
    CornersFirst,
}

/// The order of the six Kuhn tetrahedra within a cell. A tetrahedron is named by the axis
/// permutation sigma of its path: from the cell's low corner, one step along sigma\[0\], then
/// sigma\[1\], then sigma\[2\]. Two orders exist because the two meshers this one replaced
/// listed them differently and their meshes are pinned (`mesh::fingerprint`); neither is
/// better.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TetOrder {
    /// 012, 021, 102, 120, 201, 210 (the blocks).
    Lexicographic,
    /// The even permutations 012, 120, 201, then the odd ones 021, 210, 102 (the brake).
    EvenFirst,
}

impl TetOrder {
    fn permutations(self) -> [[usize; 3]; 6] {
        match self {
            TetOrder::Lexicographic => [
                [0, 1, 2],
                [0, 2, 1],
                [1, 0, 2],
                [1, 2, 0],
                [2, 0, 1],
                [2, 1, 0],
            ],
            TetOrder::EvenFirst => [
                [0, 1, 2],
                [1, 2, 0],
                [2, 0, 1],
                [0, 2, 1],
                [2, 1, 0],
                [1, 0, 2],
            ],
        }
    }

    /// The six tetrahedra of the unit cell as corner offsets (0 or 1 per axis), each ordered
    /// so that its parametric volume is positive. The volume of path sigma is
    /// det[e_sigma0, e_sigma1, e_sigma2], the sign of the permutation: odd ones swap corners
    /// 1 and 2.
    fn tets(self) -> [[[usize; 3]; 4]; 6] {
        self.permutations().map(|sigma| {
            let mut corners = [[0usize; 3]; 4];
            for step in 0..3 {
                corners[step + 1] = corners[step];
                corners[step + 1][sigma[step]] = 1;
            }
            let inversions = usize::from(sigma[0] > sigma[1])
                + usize::from(sigma[0] > sigma[2])
                + usize::from(sigma[1] > sigma[2]);
            if inversions % 2 == 1 {
                corners.swap(1, 2);
            }
            corners
        })
    }
}

/// Where one element of a structured mesh came from: what the caller needs to pick faces
/// and sets by grid position instead of by coordinates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Origin<T> {
    /// Cell indices per axis.
    pub cell: [usize; 3],
    /// The caller's tag of the cell (a part).
    pub tag: T,
    /// Refined coordinates of the element's 4 corners, not wrapped on a periodic axis (the
    /// last cell's high corners are at 2 x cells).
    pub corners: [[usize; 3]; 4],
}

/// The elements one [`Grid::mesh`] call appended to a mesh.
#[derive(Clone, Debug)]
pub struct Meshed<T> {
    /// Index in [`Mesh::elements`] of the first element appended.
    pub first_element: usize,
    /// One entry per appended element, in element order.
    pub elements: Vec<Origin<T>>,
}

impl<T> Meshed<T> {
    /// The outward faces of the elements accepted by `keep` that lie on grid plane `line`
    /// of `axis` (all three corners on it), in element order then side order. Outward
    /// because every element is positively oriented and [`TET10_FACES`] lists faces outward.
    pub fn faces_on(
        &self,
        mesh: &Mesh,
        axis: usize,
        line: usize,
        keep: impl Fn(&Origin<T>) -> bool,
    ) -> Vec<Face> {
        let mut faces = Vec::new();
        for (e, origin) in self.elements.iter().enumerate() {
            if !keep(origin) {
                continue;
            }
            for (side, local) in TET10_FACES.iter().enumerate() {
                if local[..3]
                    .iter()
                    .all(|&c| origin.corners[c][axis] == 2 * line)
                {
                    faces.push(mesh.face(self.first_element + e, side as u8));
                }
            }
        }
        faces
    }
}

/// Marks a refined point as used before it has a number.
const USED: usize = usize::MAX - 1;
const UNUSED: usize = usize::MAX;

impl Grid {
    /// Cells per axis.
    pub fn cells(&self) -> [usize; 3] {
        self.lines.each_ref().map(|l| l.len() - 1)
    }

    /// Distinct refined points per axis: 2 n + 1, or 2 n along a periodic axis.
    fn points(&self) -> [usize; 3] {
        let c = self.cells();
        [0, 1, 2].map(|a| 2 * c[a] + usize::from(!self.periodic[a]))
    }

    /// Index of a refined point in sweep order; a periodic axis wraps.
    fn key(&self, sweep: [usize; 3], p: [usize; 3]) -> usize {
        let n = self.points();
        sweep.iter().fold(0, |key, &a| key * n[a] + p[a] % n[a])
    }

    fn unkey(&self, sweep: [usize; 3], key: usize) -> [usize; 3] {
        let n = self.points();
        let mut p = [0; 3];
        let mut rest = key;
        for &a in sweep.iter().rev() {
            p[a] = rest % n[a];
            rest /= n[a];
        }
        p
    }

    /// Parameter values of a refined point: a line, or the middle of a cell.
    fn parameters(&self, p: [usize; 3]) -> [f64; 3] {
        [0, 1, 2].map(|axis| {
            let l = &self.lines[axis];
            let i = p[axis] / 2;
            if p[axis] % 2 == 1 {
                0.5 * (l[i] + l[i + 1])
            } else {
                l[i]
            }
        })
    }

    /// (nodes, elements) that [`Self::mesh`] would make with this `cell_tag`: every refined
    /// point of a meshed cell (all 27 are used by its six tetrahedra) counted once.
    pub fn count<T>(&self, cell_tag: impl Fn([usize; 3]) -> Option<T>) -> (usize, usize) {
        let cells = self.cells();
        let n = self.points();
        let mut used = vec![false; n[0] * n[1] * n[2]];
        let mut elements = 0;
        let sweep = [0, 1, 2];
        for i in 0..cells[0] {
            for j in 0..cells[1] {
                for k in 0..cells[2] {
                    if cell_tag([i, j, k]).is_none() {
                        continue;
                    }
                    elements += 6;
                    for a in 0..3 {
                        for b in 0..3 {
                            for c in 0..3 {
                                used[self.key(sweep, [2 * i + a, 2 * j + b, 2 * k + c])] = true;
                            }
                        }
                    }
                }
            }
        }
        (used.iter().filter(|&&u| u).count(), elements)
    }

    /// Appends the TET10 mesh of the grid's cells to `mesh`: nodes numbered from
    /// `mesh.nodes.len()`, elements from `mesh.elements.len()`. A cell is meshed when
    /// `cell_tag` gives it a tag (`None` leaves a hole: the lining under a backplate ear).
    /// `map` takes parameter values to a position; it must preserve orientation.
    ///
    /// Each element's connectivity is in the internal TET10 order, which is Abaqus C3D10's
    /// (0-based here): corners 1-4, then the mid-edge nodes of edges 1-2, 2-3, 3-1, 1-4, 2-4,
    /// 3-4 ([`TET10_EDGES`]); the corners are ordered so that the element is positive.
    /// Labels, parts and sets are the caller's.
    pub fn mesh<T: Copy>(
        &self,
        mesh: &mut Mesh,
        numbering: &Numbering,
        cell_tag: impl Fn([usize; 3]) -> Option<T>,
        map: impl Fn([f64; 3]) -> [f64; 3],
    ) -> Meshed<T> {
        // Callers validate their sizes first; an empty axis here is a bug, not bad input.
        assert!(
            self.lines.iter().all(|l| l.len() >= 2),
            "a structured grid needs at least one cell per axis"
        );
        let cells = self.cells();
        let sweep = numbering.sweep;
        let tets = numbering.tets.tets();
        // Refined-grid keys of every element first, then node numbers for the used points.
        let mut keys: Vec<[usize; 10]> = Vec::new();
        let mut elements: Vec<Origin<T>> = Vec::new();
        for a in 0..cells[sweep[0]] {
            for b in 0..cells[sweep[1]] {
                for c in 0..cells[sweep[2]] {
                    let mut cell = [0; 3];
                    cell[sweep[0]] = a;
                    cell[sweep[1]] = b;
                    cell[sweep[2]] = c;
                    let Some(tag) = cell_tag(cell) else {
                        continue;
                    };
                    for tet in &tets {
                        let corners = tet.map(|off| [0, 1, 2].map(|x| 2 * (cell[x] + off[x])));
                        // Internal TET10 order = Abaqus C3D10: corners 1-4, then the mid-edge
                        // nodes of edges 1-2, 2-3, 3-1, 1-4, 2-4, 3-4.
                        let mut element = [0usize; 10];
                        for (k, corner) in corners.iter().enumerate() {
                            element[k] = self.key(sweep, *corner);
                        }
                        for (m, [i, j]) in TET10_EDGES.iter().enumerate() {
                            let mid = [0, 1, 2].map(|x| (corners[*i][x] + corners[*j][x]) / 2);
                            element[4 + m] = self.key(sweep, mid);
                        }
                        keys.push(element);
                        elements.push(Origin { cell, tag, corners });
                    }
                }
            }
        }

        let n = self.points();
        let mut number = vec![UNUSED; n[0] * n[1] * n[2]];
        let add_node = |number: &mut usize, key: usize, mesh: &mut Mesh| {
            *number = mesh.nodes.len();
            mesh.nodes
                .push(map(self.parameters(self.unkey(sweep, key))));
        };
        let in_key_order = match numbering.nodes {
            NodeOrder::RefinedGrid => 0..10,
            NodeOrder::CornersFirst => 0..4,
        };
        for element in &keys {
            for &key in &element[in_key_order.clone()] {
                number[key] = USED;
            }
        }
        for (key, id) in number.iter_mut().enumerate() {
            if *id == USED {
                add_node(id, key, mesh);
            }
        }
        // Mid-edge nodes in order of first use (none left for `RefinedGrid`).
        for element in &keys {
            for &key in &element[4..] {
                if number[key] == UNUSED {
                    add_node(&mut number[key], key, mesh);
                }
            }
        }

        let first_element = mesh.elements.len();
        mesh.elements
            .extend(keys.iter().map(|element| element.map(|key| number[key])));
        Meshed {
            first_element,
            elements,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;

    const IDENTITY: fn([f64; 3]) -> [f64; 3] = |x| x;

    fn unit_grid(cells: [usize; 3], periodic: [bool; 3]) -> Grid {
        Grid {
            lines: cells.map(|n| (0..=n).map(|i| i as f64).collect()),
            periodic,
        }
    }

    /// Faces by sorted corner nodes, with the number of elements using each.
    fn face_use(m: &Mesh) -> HashMap<[usize; 3], Vec<[usize; 6]>> {
        let mut faces: HashMap<[usize; 3], Vec<[usize; 6]>> = HashMap::new();
        for e in 0..m.elements.len() {
            for s in 0..4u8 {
                let f = m.face(e, s);
                let mut key = [f.nodes[0], f.nodes[1], f.nodes[2]];
                key.sort_unstable();
                let mut all = f.nodes;
                all.sort_unstable();
                faces.entry(key).or_default().push(all);
            }
        }
        faces
    }

    #[test]
    fn both_tet_orders_give_the_same_six_positive_tetrahedra() {
        let lex = TetOrder::Lexicographic.tets();
        let even = TetOrder::EvenFirst.tets();
        for tet in &lex {
            assert!(even.contains(tet));
            let x = tet.map(|c| c.map(|v| v as f64));
            let d = |i: usize| [0, 1, 2].map(|a| x[i][a] - x[0][a]);
            let (u, v, w) = (d(1), d(2), d(3));
            let det = u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
                + u[2] * (v[0] * w[1] - v[1] * w[0]);
            assert_eq!(det, 1.0, "{tet:?}");
        }
    }

    #[test]
    fn every_numbering_conforms_and_uses_every_refined_point_once() {
        for sweep in [[0, 1, 2], [2, 1, 0], [1, 0, 2]] {
            for nodes in [NodeOrder::RefinedGrid, NodeOrder::CornersFirst] {
                for tets in [TetOrder::Lexicographic, TetOrder::EvenFirst] {
                    let numbering = Numbering { sweep, nodes, tets };
                    let grid = unit_grid([3, 2, 2], [false; 3]);
                    let mut m = Mesh::default();
                    let meshed = grid.mesh(&mut m, &numbering, |_| Some(()), IDENTITY);
                    assert_eq!(m.elements.len(), 6 * 12);
                    assert_eq!(meshed.elements.len(), m.elements.len());
                    assert_eq!(m.nodes.len(), 7 * 5 * 5);
                    assert!((0..m.elements.len()).all(|e| m.corner_volume(e) > 0.0));
                    // Mid nodes in the middle of their edges.
                    for conn in &m.elements {
                        for (k, [i, j]) in TET10_EDGES.iter().enumerate() {
                            let (a, b) = (m.nodes[conn[*i]], m.nodes[conn[*j]]);
                            let mid = [0, 1, 2].map(|x| 0.5 * (a[x] + b[x]));
                            assert_eq!(m.nodes[conn[4 + k]], mid);
                        }
                    }
                    let faces = face_use(&m);
                    assert!(faces
                        .values()
                        .all(|u| u.len() <= 2 && u[0] == u[u.len() - 1]));
                    let boundary = faces.values().filter(|u| u.len() == 1).count();
                    assert_eq!(boundary, 2 * 2 * (3 * 2 + 3 * 2 + 2 * 2));
                    let on_planes: usize = (0..3)
                        .map(|axis| {
                            meshed.faces_on(&m, axis, 0, |_| true).len()
                                + meshed
                                    .faces_on(&m, axis, grid.cells()[axis], |_| true)
                                    .len()
                        })
                        .sum();
                    assert_eq!(on_planes, boundary);
                }
            }
        }
    }

    #[test]
    fn a_periodic_axis_closes_the_ring_and_holes_leave_no_nodes() {
        let numbering = Numbering {
            sweep: [1, 0, 2],
            nodes: NodeOrder::RefinedGrid,
            tets: TetOrder::EvenFirst,
        };
        let grid = unit_grid([2, 4, 1], [false, true, false]);
        let mut m = Mesh::default();
        let meshed = grid.mesh(
            &mut m,
            &numbering,
            |_| Some(()),
            |[r, t, z]| {
                let theta = t * std::f64::consts::FRAC_PI_2;
                [(1.0 + r) * theta.cos(), (1.0 + r) * theta.sin(), z]
            },
        );
        assert_eq!(m.nodes.len(), 5 * 8 * 3);
        // Closed: no boundary face on the theta planes, the seam plane is shared.
        let faces = face_use(&m);
        let boundary = faces.values().filter(|u| u.len() == 1).count();
        // Two triangles per quad on the two z planes (2 x 4 cells) and the two r planes (4 x 1).
        assert_eq!(boundary, 2 * 2 * (2 * 4 + 4));
        assert!(meshed.faces_on(&m, 1, 0, |_| true).len() == 2 * 2);
        assert!((0..m.elements.len()).all(|e| m.corner_volume(e) > 0.0));

        // A hole: the middle column of cells, and nothing of it left behind.
        let grid = unit_grid([3, 1, 1], [false; 3]);
        let mut m = Mesh::default();
        let meshed = grid.mesh(
            &mut m,
            &numbering,
            |c| (c[0] != 1).then_some(c[0]),
            IDENTITY,
        );
        assert_eq!(m.elements.len(), 12);
        assert_eq!(m.nodes.len(), 2 * 3 * 3 * 3);
        let hole = |c: [usize; 3]| (c[0] != 1).then_some(());
        assert_eq!(grid.count(hole), (m.nodes.len(), m.elements.len()));
        let ring = unit_grid([2, 4, 1], [false, true, false]);
        assert_eq!(ring.count(|_| Some(())), (5 * 8 * 3, 6 * 8));
        assert!(meshed.elements.iter().all(|o| o.tag == o.cell[0]));
    }

    #[test]
    fn appended_grids_number_after_what_is_there() {
        let numbering = Numbering {
            sweep: [2, 1, 0],
            nodes: NodeOrder::CornersFirst,
            tets: TetOrder::Lexicographic,
        };
        let grid = unit_grid([1, 1, 1], [false; 3]);
        let mut m = Mesh::default();
        grid.mesh(&mut m, &numbering, |_| Some(()), IDENTITY);
        let second = grid.mesh(&mut m, &numbering, |_| Some(()), |x| x.map(|v| v + 5.0));
        assert_eq!(second.first_element, 6);
        assert_eq!(m.nodes.len(), 2 * 27);
        assert!(m.elements[6..].iter().flatten().all(|&n| n >= 27));
        // Corners first: the 8 cube corners are nodes 27..35.
        assert_eq!(m.nodes[27], [5.0; 3]);
        assert_eq!(m.nodes[27 + 7], [6.0; 3]);
        let top = second.faces_on(&m, 2, 1, |_| true);
        assert_eq!(top.len(), 2);
        assert!(top
            .iter()
            .all(|f| f.element >= 6 && f.nodes.iter().all(|&n| m.nodes[n][2] == 6.0)));
    }
}
