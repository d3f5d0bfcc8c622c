//! Gmsh MSH files: a reader for MSH 4.1 (ASCII and binary, either byte order) and MSH 2.2
//! (ASCII), and a writer for MSH 4.1 ASCII.
//!
//! Format reference: the Gmsh manual, section "MSH file format"
//! (<https://gmsh.info/doc/texinfo/gmsh.html#MSH-file-format>) and, for 2.2, "Legacy formats".
//!
//! What becomes what:
//! - 10-node tetrahedra (type 11) are the elements; their node order is converted from
//!   Gmsh's to the internal one (see [`GMSH_TET10`]).
//! - Physical volumes become [`Part`](crate::mesh::Part)s (named by `$PhysicalNames`, else
//!   `volume_<tag>`, no material). Tetrahedra in no physical volume go into a part
//!   `unassigned`, or into a part `all` when the file has no physical groups at all.
//! - 6-node (type 9) or 3-node (type 2) triangles in a physical surface become a
//!   [`Surface`](crate::mesh::Surface) of the tetrahedron faces they cover (outward, as
//!   [`Mesh::face`] gives them), and the surface's nodes become a node set of the same name.
//! - Points (type 15) and lines (types 1 and 8) in physical points and curves become node
//!   sets (`point_<tag>` / `curve_<tag>` when unnamed).
//! - Every other element type is refused by name.
//!
//! Errors name the file and the line (in a binary file: the byte offset) and what was
//! expected there. A file that stops before a section's end marker is an error, never a
//! shorter mesh.
//!
//! One file per concept: `element_types.rs` (what is read, what is refused), `cursor.rs`
//! (tokens, lines and binary numbers with their positions), `sections.rs` (the sections into
//! raw records), `build.rs` (raw records to the mesh) and `writer.rs` (MSH 4.1 ASCII).

mod build;
mod cursor;
mod element_types;
mod sections;
#[cfg(test)]
mod test_support;
mod writer;

use std::path::Path;

use crate::mesh::{Mesh, MeshError};
use build::build;
use sections::Parser;
pub use writer::write;

/// Node order conversion for the 10-node tetrahedron, in both directions (the permutation is
/// its own inverse): `internal[k] = gmsh[GMSH_TET10[k]]` and `gmsh[k] = internal[GMSH_TET10[k]]`.
///
/// Gmsh orders the mid-edge nodes 0-1, 1-2, 2-0, 3-0, 3-2, 3-1 (manual, "Node ordering");
/// the internal (Abaqus C3D10) order is 0-1, 1-2, 2-0, 0-3, 1-3, 2-3. Edge direction does not
/// matter for a mid-edge node, so only the last two nodes trade places.
pub const GMSH_TET10: [usize; 10] = [0, 1, 2, 3, 4, 5, 6, 7, 9, 8];

/// Read a Gmsh mesh file (MSH 4.1 ASCII or binary, or MSH 2.2 ASCII).
pub fn read(path: &Path) -> Result<Mesh, MeshError> {
    let bytes = crate::input_file::read(path).map_err(|source| MeshError::Io {
        file: path.to_path_buf(),
        source,
    })?;
    parse(path, &bytes)
}

/// Parse the contents of a Gmsh mesh file; `file` is only used in error messages.
pub fn parse(file: &Path, bytes: &[u8]) -> Result<Mesh, MeshError> {
    let raw = match Parser::new(file, bytes).run() {
        Ok(raw) => raw,
        // A check word written in the other byte order than the numbers after it made the
        // numbers garbage, reported as "it is truncated" far from the cause: when they read
        // whole against the check word, the check word is what is wrong.
        Err(e @ MeshError::Binary { .. }) => {
            return Err(
                match Parser::new(file, bytes).against_byte_order_check().run() {
                    Ok(_) => MeshError::invalid(
                        file,
                        "the byte-order check (the integer 1 after the $MeshFormat line) is \
                         in the other byte order than the numbers after it, which read whole \
                         in theirs: the check word is wrong (the file was altered after it \
                         was written)",
                    ),
                    Err(_) => e,
                },
            )
        }
        Err(e) => return Err(e),
    };
    build(file, raw)
}

#[cfg(test)]
mod tests {
    use super::test_support::*;
    use super::*;
    use crate::mesh::{TET10_EDGES, TET10_FACES};
    use std::collections::BTreeSet;

    /// A check word in the other byte order than the numbers after it is named as such,
    /// not reported as a truncated file far from the cause.
    #[test]
    fn a_check_word_in_the_wrong_byte_order_is_named() {
        for big_endian in [false, true] {
            let mut bytes = two_tets_binary(big_endian);
            let at = b"$MeshFormat\n4.1 1 8\n".len();
            bytes[at..at + 4].reverse();
            let message = parse(&p("b.msh"), &bytes).unwrap_err().to_string();
            assert!(
                message.contains("byte-order check") && message.contains("check word is wrong"),
                "{message}"
            );
            assert!(!message.contains("truncated"), "{message}");
        }
    }

    #[test]
    fn reads_msh41_ascii() {
        check_two_tets(&parse_str(TWO_TETS_41).unwrap());
    }

    #[test]
    fn reads_msh22_ascii() {
        check_two_tets(&parse_str(TWO_TETS_22).unwrap());
    }

    #[test]
    fn reads_msh41_binary_in_both_byte_orders() {
        for big_endian in [false, true] {
            let m = parse(&p("b.msh"), &two_tets_binary(big_endian)).unwrap();
            check_two_tets(&m);
        }
    }

    #[test]
    fn faces_of_surfaces_point_out_of_their_element() {
        let m = parse_str(TWO_TETS_41).unwrap();
        for face in &m.surfaces["friction"].faces {
            let x = |i: usize| m.nodes[face.nodes[i]];
            let conn = m.elements[face.element];
            let centroid = (0..3).map(|d| (0..4).map(|c| m.nodes[conn[c]][d]).sum::<f64>() / 4.0);
            let centroid: Vec<f64> = centroid.collect();
            let (u, v) = (sub3(x(1), x(0)), sub3(x(2), x(0)));
            let n = [
                u[1] * v[2] - u[2] * v[1],
                u[2] * v[0] - u[0] * v[2],
                u[0] * v[1] - u[1] * v[0],
            ];
            let out = sub3(x(0), [centroid[0], centroid[1], centroid[2]]);
            assert!(n[0] * out[0] + n[1] * out[1] + n[2] * out[2] > 0.0);
        }
    }

    #[test]
    fn mid_edge_nodes_sit_on_the_internal_edges() {
        // Every mid-edge node of the straight two-tet mesh is the midpoint of the internal
        // edge TET10_EDGES assigns it; the Gmsh order would put nodes 8 and 9 on 2-3 and 1-3.
        let m = parse_str(TWO_TETS_41).unwrap();
        for conn in &m.elements {
            for (k, [a, b]) in TET10_EDGES.iter().enumerate() {
                let mid = [0, 1, 2].map(|d| 0.5 * (m.nodes[conn[*a]][d] + m.nodes[conn[*b]][d]));
                assert_eq!(m.nodes[conn[4 + k]], mid, "edge {a}-{b}");
            }
        }
    }

    /// Gradients of the internal-order TET10 shape functions at (xi, eta, zeta):
    /// corners N_i = L_i (2 L_i - 1), mid-edge N = 4 L_a L_b.
    fn shape_gradients(xi: [f64; 3]) -> [[f64; 3]; 10] {
        let l = [1.0 - xi[0] - xi[1] - xi[2], xi[0], xi[1], xi[2]];
        let dl = [
            [-1.0, -1.0, -1.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ];
        let mut g = [[0.0; 3]; 10];
        for i in 0..4 {
            g[i] = dl[i].map(|d| (4.0 * l[i] - 1.0) * d);
        }
        for (k, [a, b]) in TET10_EDGES.iter().enumerate() {
            g[4 + k] = [0, 1, 2].map(|d| 4.0 * (l[*b] * dl[*a][d] + l[*a] * dl[*b][d]));
        }
        g
    }

    fn jacobian_det(x: &[[f64; 3]; 10], xi: [f64; 3]) -> f64 {
        let g = shape_gradients(xi);
        let mut j = [[0.0; 3]; 3];
        for n in 0..10 {
            for r in 0..3 {
                for c in 0..3 {
                    j[r][c] += x[n][r] * g[n][c];
                }
            }
        }
        det3(j)
    }

    /// Volume of a quadratic tetrahedron, integral of det J over the reference element by a
    /// collapsed (Duffy) 3x3x3 Gauss rule: xi = u, eta = (1-u) v, zeta = (1-u)(1-v) w, with
    /// weight (1-u)^2 (1-v). det J is cubic, so the integrand has degree <= 5 in each of u, v,
    /// w, and the 3-point Gauss rule (exact to degree 5) integrates it exactly. Also returns
    /// the smallest det J met at the quadrature points.
    fn volume(x: &[[f64; 3]; 10]) -> (f64, f64) {
        let s = (0.6f64).sqrt();
        let points = [(1.0 - s) / 2.0, 0.5, (1.0 + s) / 2.0];
        let weights = [5.0 / 18.0, 8.0 / 18.0, 5.0 / 18.0];
        let (mut v, mut min) = (0.0, f64::INFINITY);
        for (u, wu) in points.iter().zip(weights) {
            for (t, wt) in points.iter().zip(weights) {
                for (w, ww) in points.iter().zip(weights) {
                    let xi = [*u, (1.0 - u) * t, (1.0 - u) * (1.0 - t) * w];
                    let d = jacobian_det(x, xi);
                    min = min.min(d);
                    v += wu * wt * ww * (1.0 - u) * (1.0 - u) * (1.0 - t) * d;
                }
            }
        }
        (v, min)
    }

    #[test]
    fn curved_element_keeps_its_volume_and_a_positive_jacobian() {
        // The unit tetrahedron with the mid node of edge 1-3 (Gmsh's last node, "3-1") pushed
        // out by d. With the straight element mapping x = xi (J0 = I), moving one node by d
        // is a rank-one update: det J = 1 + d . grad N_m, so the volume is exactly
        //   1/6 + d . integral(grad N_m) = 1/6 + d . (boundary integral of N_m n).
        // N_m = 4 L1 L3 lives on the faces y = 0 (area 1/2, n = -e_y) and x+y+z = 1
        // (area sqrt(3)/2, n = (1,1,1)/sqrt(3)); each integral of L1 L3 is area/12, so
        // integral(grad N_m) = (1, 0, 1)/6 and V = 1/6 + (d_x + d_z)/6.
        let delta = 0.1;
        let d = [delta / 2f64.sqrt(), 0.0, delta / 2f64.sqrt()];
        let gmsh = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [0.5, 0.0, 0.0],
            [0.5, 0.5, 0.0],
            [0.0, 0.5, 0.0],
            [0.0, 0.0, 0.5],
            [0.0, 0.5, 0.5],
            [0.5 + d[0], d[1], 0.5 + d[2]],
        ];
        let mut text = String::from("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 10 1 10\n");
        text += "3 1 0 10\n";
        for i in 1..=10 {
            text += &format!("{i}\n");
        }
        for x in gmsh {
            text += &format!("{} {} {}\n", x[0], x[1], x[2]);
        }
        text += "$EndNodes\n$Elements\n1 1 1 1\n3 1 11 1\n1 1 2 3 4 5 6 7 8 9 10\n$EndElements\n";
        let m = parse_str(&text).unwrap();
        assert_eq!(m.parts.len(), 1);
        assert_eq!(
            (m.parts[0].name.as_str(), m.parts[0].elements.as_slice()),
            ("all", &[0][..])
        );
        let x: [[f64; 3]; 10] = m.elements[0].map(|k| m.nodes[k]);
        let (v, min_det) = volume(&x);
        let exact = 1.0 / 6.0 + (d[0] + d[2]) / 6.0;
        // Exact quadrature of a polynomial: only round-off (a few ulps of 1/6) remains.
        assert!((v - exact).abs() < 1e-14, "volume {v}, expected {exact}");
        assert!(min_det > 0.0);
        for corner in [[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]] {
            assert!(jacobian_det(&x, corner) > 0.0);
        }

        // The same nodes without the swap (Gmsh order taken as internal): at corner 3 the
        // Jacobian of the straight element would be det[(-1,2,0),(2,-1,0),(0,0,1)] = -3, so
        // this test cannot pass with the wrong order.
        let (v_wrong, min_wrong) = volume(&gmsh);
        assert!((v_wrong - exact).abs() > 1e-3, "{v_wrong}");
        assert!(min_wrong < 0.0);
        assert!(jacobian_det(&gmsh, [0.0, 0.0, 1.0]) < 0.0);
        let mut straight = gmsh;
        straight[9] = [0.5, 0.0, 0.5];
        assert!((jacobian_det(&straight, [0.0, 0.0, 1.0]) + 3.0).abs() < 1e-14);
    }

    #[test]
    fn msh22_merges_repeated_elements_and_reads_3_node_triangles() {
        // MSH 2.2 writes an element once per physical group: triangle 21 again (as 22) in a
        // second physical surface, as a 3-node triangle.
        let text = TWO_TETS_22
            .replace("6\n40 15", "7\n40 15")
            .replace("$EndElements", "22 2 2 6 1 2 3 4\n$EndElements");
        let m = parse_str(&text).unwrap();
        let interface = &m.surfaces["surface_6"];
        assert_eq!(interface.faces, [m.face(0, 2)]);
        assert_eq!(m.node_sets["surface_6"], [1, 2, 3, 6, 9, 10]);
        assert_eq!(m.elements.len(), 2);

        // The same tetrahedron in two physical volumes cannot be in two parts.
        let text = TWO_TETS_22.replace("6\n40 15", "7\n40 15").replace(
            "$EndElements",
            "9 11 2 2 1 1 2 3 4 11 12 13 14 16 15\n$EndElements",
        );
        let err = parse_str(&text).unwrap_err().to_string();
        assert!(
            err.contains("element 7 is in two physical volumes, 'disc' and 'volume_2'"),
            "{err}"
        );
    }
    #[test]
    fn node_counts_the_file_cannot_hold_are_refused_and_element_counts_cannot_overflow() {
        // Found by fuzzing: a binary element block declaring 2^64 - 1 elements after a block
        // of one overflowed the tally of elements.
        let mut bytes = two_tets_binary(false);
        let at = bytes.windows(10).position(|w| w == b"$Elements\n").unwrap() + 10;
        // 4 size_t (blocks, elements, smallest and largest tag), the first block (3 ints, its
        // count, one element of 11 size_t), then the second block's 3 ints and its count.
        let count = at + 4 * 8 + (3 * 4 + 8 + 11 * 8) + 3 * 4;
        bytes[count..count + 8].copy_from_slice(&u64::MAX.to_le_bytes());
        let e = parse(&p("b.msh"), &bytes).unwrap_err().to_string();
        assert!(
            e.contains("b.msh") && e.contains("this block declares 18446744073709551615"),
            "{e}"
        );
        // A node count sizes the node arrays: refused on its line when the rest of the file
        // cannot hold that many nodes, before anything is allocated.
        for (text, words) in [
            (
                "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 4000000000 1 4000000000\n\
                 1 1 0 1\n1\n0 0 0\n$EndNodes\n",
                "the number of nodes is 4000000000",
            ),
            (
                "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n99999999999\n1 0 0 0\n\
                 $EndNodes\n",
                "the number of nodes is 99999999999",
            ),
        ] {
            let (line, message) = parse_error(text);
            assert_eq!(line, 5, "{message}");
            assert!(
                message.contains(words) && message.contains("hold at most"),
                "{message}"
            );
        }
    }

    // Real Gmsh 4.8.4 output (tests/data), made from:
    //   SetFactory("OpenCASCADE");
    //   Box(1) = {0, 0, 0, 1, 1, 0.3};  Box(2) = {0.2, 0.2, 0.3, 0.5, 0.5, 0.2};
    //   BooleanFragments{ Volume{1}; Delete; }{ Volume{2}; Delete; }
    //   Physical Volume("disc") = {1};  Physical Volume("pad") = {2};
    //   Physical Surface("contact") = Surface In BoundingBox{0.19,0.19,0.29, 0.71,0.71,0.31};
    //   Physical Surface("pad_top") = Surface In BoundingBox{0.19,0.19,0.49, 0.71,0.71,0.51};
    //   Physical Surface("bottom") = Surface In BoundingBox{-0.01,-0.01,-0.01, 1.01,1.01,0.01};
    //   Physical Point("origin") = Point In BoundingBox{-0.01,-0.01,-0.01, 0.01,0.01,0.01};
    //   Mesh.MeshSizeMin = 0.4;  Mesh.MeshSizeMax = 0.4;
    // with gmsh -3 -order 2 two_boxes.geo -format msh41 [-bin] (or -format msh22).
    const REAL_41: &[u8] = include_bytes!("../../../tests/data/gmsh_two_boxes_41.msh");
    const REAL_41_BINARY: &[u8] =
        include_bytes!("../../../tests/data/gmsh_two_boxes_41_binary.msh");
    const REAL_22: &[u8] = include_bytes!("../../../tests/data/gmsh_two_boxes_22.msh");
    #[test]
    fn real_gmsh_output_gives_exact_volumes_areas_and_outward_faces() {
        let ascii = parse(&p("a.msh"), REAL_41).unwrap();
        let binary = parse(&p("b.msh"), REAL_41_BINARY).unwrap();
        let legacy = parse(&p("c.msh"), REAL_22).unwrap();
        assert_same(&ascii, &legacy);
        // Binary holds the exact doubles, ASCII Gmsh's 16 significant digits: coordinates
        // (all <= 1 in size) agree to a few 1e-16, everything else exactly.
        assert_eq!(ascii.elements, binary.elements);
        assert_eq!(ascii.node_labels, binary.node_labels);
        assert_eq!(ascii.element_labels, binary.element_labels);
        assert_eq!(ascii.parts, binary.parts);
        assert_eq!(ascii.surfaces, binary.surfaces);
        assert_eq!(ascii.node_sets, binary.node_sets);
        for (a, b) in ascii.nodes.iter().zip(&binary.nodes) {
            for d in 0..3 {
                assert!((a[d] - b[d]).abs() <= 1e-15, "{a:?} {b:?}");
            }
        }

        let m = binary;
        // The meshes of the two boxes are straight-sided, so their corner tetrahedra tile
        // the boxes exactly: volumes 1 x 1 x 0.3 and 0.5 x 0.5 x 0.2 up to round-off.
        let names: Vec<&str> = m.parts.iter().map(|p| p.name.as_str()).collect();
        assert_eq!(names, ["disc", "pad"]);
        for (part, exact) in m.parts.iter().zip([0.3, 0.05]) {
            let v: f64 = part.elements.iter().map(|&e| m.corner_volume(e)).sum();
            assert!((v - exact).abs() < 1e-13, "{} volume {v}", part.name);
        }
        assert_eq!(
            m.parts[0].elements.len() + m.parts[1].elements.len(),
            m.elements.len()
        );

        // Surface areas and outward normals: bottom faces look down (-z), the pad's top
        // faces up (+z); the contact faces (between disc and pad) all come from one part and
        // look away from it.
        let part_of = m.element_parts();
        let mut contact_parts = BTreeSet::new();
        for (name, area_exact) in [("bottom", 1.0), ("pad_top", 0.25), ("contact", 0.25)] {
            let surface = &m.surfaces[name];
            let mut area = 0.0;
            for face in &surface.faces {
                assert_eq!(*face, m.face(face.element, face.side));
                let x = |i: usize| m.nodes[face.nodes[i]];
                let n = cross3(sub3(x(1), x(0)), sub3(x(2), x(0)));
                let norm = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
                area += 0.5 * norm;
                // Flat faces of axis-aligned boxes: the normal is +-z to round-off.
                let nz = n[2] / norm;
                match name {
                    "bottom" => assert!((nz + 1.0).abs() < 1e-12),
                    "pad_top" => assert!((nz - 1.0).abs() < 1e-12),
                    _ => {
                        let part = part_of[face.element].unwrap();
                        contact_parts.insert(part);
                        let expect = if part == 0 { 1.0 } else { -1.0 };
                        assert!((nz - expect).abs() < 1e-12);
                    }
                }
            }
            assert!((area - area_exact).abs() < 1e-13, "{name} area {area}");
            assert_eq!(m.node_sets[name], m.surface_nodes(surface));
        }
        assert_eq!(contact_parts.len(), 1);
        let origin = &m.node_sets["origin"];
        assert_eq!(origin.len(), 1);
        assert_eq!(m.nodes[origin[0]], [0.0, 0.0, 0.0]);

        // Writing and reading it back changes nothing.
        let dir = temp_dir("real");
        let path = dir.join("boxes.msh");
        write(&path, &m).unwrap();
        assert_same(&read(&path).unwrap(), &m);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn the_node_order_table_matches_the_documented_faces() {
        // Gmsh's face 0-1-2 of the tet is internal face S1 with the same mid nodes.
        let gmsh_face_012_mids = [4, 5, 6].map(|k| GMSH_TET10[k]);
        assert_eq!(gmsh_face_012_mids, [4, 5, 6]);
        let mut face = TET10_FACES[0];
        face.sort_unstable();
        assert_eq!(face, [0, 1, 2, 4, 5, 6]);
        // The permutation is an involution, so it converts both ways.
        for k in 0..10 {
            assert_eq!(GMSH_TET10[GMSH_TET10[k]], k);
        }
    }
}
