//! What the tests of the Gmsh reader and writer share: a two-tetrahedron mesh worked out by
//! hand, in MSH 4.1 ASCII and binary and MSH 2.2, and small helpers.

use std::path::PathBuf;

use super::parse;
use crate::mesh::{Mesh, MeshError};

// Two tetrahedra sharing the face B C D:
//   corners A=1 (0,0,0)  B=2 (1,0,0)  C=3 (0,1,0)  D=4 (0,0,1)  E=5 (1,1,1)
//   mid-edge nodes 11=AB 12=BC 13=CA 14=AD 15=BD 16=CD 17=BE 18=CE 19=DE
// Element 7 = A B C D, element 8 = B C D E, written in Gmsh's node order
// (edges 0-1, 1-2, 2-0, 3-0, 3-2, 3-1). Element 7 is in physical volume "disc",
// element 8 in none. Physical surface "friction" holds triangle 20 = C E D (a boundary
// face of element 8, given inward on purpose) and triangle 21 = B C D (the shared face,
// turning like element 7's outward face). Physical curve "edge" is the 3-node line A B,
// physical point "corner" is E.
pub(super) const TWO_TETS_41: &str = r#"$MeshFormat
4.1 0 8
$EndMeshFormat
$Comments
anything at all, even $Nodes and $Elements
$EndComments
$PhysicalNames
4
0 5 "corner"
1 4 "edge"
2 3 "friction"
3 1 "disc"
$EndPhysicalNames
$Entities
1 1 1 2
1 1 1 1 1 5
1 0 0 0 1 0 0 1 4 0
1 0 0 0 1 1 1 1 3 0
1 0 0 0 1 1 1 1 1 0
2 0 0 0 1 1 1 0 0
$EndEntities
$Nodes
3 14 1 19
3 1 0 5
1
2
3
4
5
0 0 0
1 0 0
0 1 0
0 0 1
1 1 1
2 1 1 3
11
12
13
0.5 0 0 0.5 0
0.5 0.5 0 0.5 0.5
0 0.5 0 0 0.5
3 2 0 6
14
15
16
17
18
19
0 0 0.5
0.5 0 0.5
0 0.5 0.5
1 0.5 0.5
0.5 1 0.5
0.5 0.5 1
$EndNodes
$Elements
5 6 7 40
3 1 11 1
7 1 2 3 4 11 12 13 14 16 15
3 2 11 1
8 2 3 4 5 12 16 15 17 19 18
2 1 9 2
20 3 5 4 18 19 16
21 2 3 4 12 16 15
1 1 8 1
30 1 2 11
0 1 15 1
40 5
$EndElements
"#;

// The same mesh in MSH 2.2 (physical tag first among each element's tags; 0 = none).
pub(super) const TWO_TETS_22: &str = r#"$MeshFormat
2.2 0 8
$EndMeshFormat
$PhysicalNames
4
0 5 "corner"
1 4 "edge"
2 3 "friction"
3 1 "disc"
$EndPhysicalNames
$Nodes
14
1 0 0 0
2 1 0 0
3 0 1 0
4 0 0 1
5 1 1 1
11 0.5 0 0
12 0.5 0.5 0
13 0 0.5 0
14 0 0 0.5
15 0.5 0 0.5
16 0 0.5 0.5
17 1 0.5 0.5
18 0.5 1 0.5
19 0.5 0.5 1
$EndNodes
$Elements
6
40 15 2 5 1 5
30 8 2 4 1 1 2 11
7 11 2 1 1 1 2 3 4 11 12 13 14 16 15
8 11 2 0 2 2 3 4 5 12 16 15 17 19 18
20 9 2 3 1 3 5 4 18 19 16
21 9 2 3 1 2 3 4 12 16 15
$EndElements
"#;

/// The two-tet mesh as MSH 4.1 binary, built byte by byte from the format description
/// (size_t = 8 bytes, int = 4 bytes, double = 8 bytes, in the given byte order).
pub(super) fn two_tets_binary(big_endian: bool) -> Vec<u8> {
    struct B(Vec<u8>, bool);
    impl B {
        fn text(&mut self, s: &str) {
            self.0.extend_from_slice(s.as_bytes());
        }
        fn size(&mut self, v: u64) {
            let b = if self.1 {
                v.to_be_bytes()
            } else {
                v.to_le_bytes()
            };
            self.0.extend_from_slice(&b);
        }
        fn int(&mut self, v: i32) {
            let b = if self.1 {
                v.to_be_bytes()
            } else {
                v.to_le_bytes()
            };
            self.0.extend_from_slice(&b);
        }
        fn double(&mut self, v: f64) {
            let b = if self.1 {
                v.to_be_bytes()
            } else {
                v.to_le_bytes()
            };
            self.0.extend_from_slice(&b);
        }
    }
    let mut b = B(Vec::new(), big_endian);
    b.text("$MeshFormat\n4.1 1 8\n");
    b.int(1);
    b.text("\n$EndMeshFormat\n");
    b.text("$PhysicalNames\n4\n0 5 \"corner\"\n1 4 \"edge\"\n2 3 \"friction\"\n");
    b.text("3 1 \"disc\"\n$EndPhysicalNames\n");
    b.text("$Entities\n");
    for n in [1, 1, 1, 2] {
        b.size(n);
    }
    // point 1 at E, physical 5
    b.int(1);
    for x in [1.0, 1.0, 1.0] {
        b.double(x);
    }
    b.size(1);
    b.int(5);
    // curve 1, physical 4, no bounding points
    b.int(1);
    for x in [0.0, 0.0, 0.0, 1.0, 0.0, 0.0] {
        b.double(x);
    }
    b.size(1);
    b.int(4);
    b.size(0);
    // surface 1, physical 3
    b.int(1);
    for x in [0.0, 0.0, 0.0, 1.0, 1.0, 1.0] {
        b.double(x);
    }
    b.size(1);
    b.int(3);
    b.size(0);
    // volume 1 physical 1, volume 2 no physical
    for (tag, physicals) in [(1, vec![1]), (2, vec![])] {
        b.int(tag);
        for x in [0.0, 0.0, 0.0, 1.0, 1.0, 1.0] {
            b.double(x);
        }
        b.size(physicals.len() as u64);
        for p in physicals {
            b.int(p);
        }
        b.size(0);
    }
    b.text("\n$EndEntities\n$Nodes\n");
    for n in [3, 14, 1, 19] {
        b.size(n);
    }
    type Block<'a> = (i32, i32, i32, &'a [u64], &'a [[f64; 5]]);
    let blocks: [Block; 3] = [
        (
            3,
            1,
            0,
            &[1, 2, 3, 4, 5],
            &[
                [0.0, 0.0, 0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0, 0.0, 0.0],
                [0.0, 1.0, 0.0, 0.0, 0.0],
                [0.0, 0.0, 1.0, 0.0, 0.0],
                [1.0, 1.0, 1.0, 0.0, 0.0],
            ],
        ),
        (
            2,
            1,
            1,
            &[11, 12, 13],
            &[
                [0.5, 0.0, 0.0, 0.5, 0.0],
                [0.5, 0.5, 0.0, 0.5, 0.5],
                [0.0, 0.5, 0.0, 0.0, 0.5],
            ],
        ),
        (
            3,
            2,
            0,
            &[14, 15, 16, 17, 18, 19],
            &[
                [0.0, 0.0, 0.5, 0.0, 0.0],
                [0.5, 0.0, 0.5, 0.0, 0.0],
                [0.0, 0.5, 0.5, 0.0, 0.0],
                [1.0, 0.5, 0.5, 0.0, 0.0],
                [0.5, 1.0, 0.5, 0.0, 0.0],
                [0.5, 0.5, 1.0, 0.0, 0.0],
            ],
        ),
    ];
    for (dim, tag, parametric, tags, coords) in blocks {
        b.int(dim);
        b.int(tag);
        b.int(parametric);
        b.size(tags.len() as u64);
        for &t in tags {
            b.size(t);
        }
        for x in coords {
            let n = if parametric == 1 { 3 + dim as usize } else { 3 };
            for &v in &x[..n] {
                b.double(v);
            }
        }
    }
    b.text("\n$EndNodes\n$Elements\n");
    for n in [5, 6, 7, 40] {
        b.size(n);
    }
    let blocks: [(i32, i32, i32, &[&[u64]]); 5] = [
        (3, 1, 11, &[&[7, 1, 2, 3, 4, 11, 12, 13, 14, 16, 15]]),
        (3, 2, 11, &[&[8, 2, 3, 4, 5, 12, 16, 15, 17, 19, 18]]),
        (
            2,
            1,
            9,
            &[&[20, 3, 5, 4, 18, 19, 16], &[21, 2, 3, 4, 12, 16, 15]],
        ),
        (1, 1, 8, &[&[30, 1, 2, 11]]),
        (0, 1, 15, &[&[40, 5]]),
    ];
    for (dim, tag, element_type, elements) in blocks {
        b.int(dim);
        b.int(tag);
        b.int(element_type);
        b.size(elements.len() as u64);
        for element in elements {
            for &v in element.iter() {
                b.size(v);
            }
        }
    }
    b.text("\n$EndElements\n");
    b.0
}

pub(super) fn p(name: &str) -> PathBuf {
    PathBuf::from(name)
}

pub(super) fn parse_str(text: &str) -> Result<Mesh, MeshError> {
    parse(&p("test.msh"), text.as_bytes())
}

/// The two-tet mesh as worked out by hand from the comment above.
pub(super) fn check_two_tets(m: &Mesh) {
    assert_eq!(
        m.node_labels,
        [1, 2, 3, 4, 5, 11, 12, 13, 14, 15, 16, 17, 18, 19]
    );
    assert_eq!(m.nodes[4], [1.0, 1.0, 1.0]);
    assert_eq!(m.nodes[10], [0.0, 0.5, 0.5]);
    assert_eq!(m.element_labels, [7, 8]);
    // Internal order: corners, then mid 0-1, 1-2, 2-0, 0-3, 1-3, 2-3 (node indices).
    assert_eq!(m.elements[0], [0, 1, 2, 3, 5, 6, 7, 8, 9, 10]);
    assert_eq!(m.elements[1], [1, 2, 3, 4, 6, 10, 9, 11, 12, 13]);
    let parts: Vec<(&str, &[usize], Option<&String>)> = m
        .parts
        .iter()
        .map(|p| (p.name.as_str(), p.elements.as_slice(), p.material.as_ref()))
        .collect();
    assert_eq!(
        parts,
        [("disc", &[0][..], None), ("unassigned", &[1][..], None)]
    );
    let friction = &m.surfaces["friction"];
    assert_eq!(friction.name, "friction");
    let sides: Vec<(usize, u8)> = friction.faces.iter().map(|f| (f.element, f.side)).collect();
    // C D E is side 2 (internal 1 2 3) of element 8; B C D is side 2 of element 7.
    assert_eq!(sides, [(1, 2), (0, 2)]);
    for face in &friction.faces {
        assert_eq!(*face, m.face(face.element, face.side));
    }
    assert_eq!(m.surfaces.len(), 1);
    let sets: Vec<(&str, &[usize])> = m
        .node_sets
        .iter()
        .map(|(k, v)| (k.as_str(), v.as_slice()))
        .collect();
    assert_eq!(
        sets,
        [
            ("corner", &[4][..]),
            ("edge", &[0, 1, 5][..]),
            ("friction", &[1, 2, 3, 4, 6, 9, 10, 12, 13][..]),
        ]
    );
    assert!(m.materials.is_empty());
}

pub(super) fn assert_same(a: &Mesh, b: &Mesh) {
    assert_eq!(a.nodes, b.nodes);
    assert_eq!(a.node_labels, b.node_labels);
    assert_eq!(a.elements, b.elements);
    assert_eq!(a.element_labels, b.element_labels);
    assert_eq!(a.parts, b.parts);
    assert_eq!(a.surfaces, b.surfaces);
    assert_eq!(a.node_sets, b.node_sets);
}

pub(super) fn sub3(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

pub(super) fn det3(c: [[f64; 3]; 3]) -> f64 {
    c[0][0] * (c[1][1] * c[2][2] - c[1][2] * c[2][1])
        - c[0][1] * (c[1][0] * c[2][2] - c[1][2] * c[2][0])
        + c[0][2] * (c[1][0] * c[2][1] - c[1][1] * c[2][0])
}

pub(super) fn line_of(text: &str, needle: &str) -> usize {
    let at = text.find(needle).expect("needle in text");
    text[..at].matches('\n').count() + 1
}

pub(super) fn parse_error(text: &str) -> (usize, String) {
    match parse_str(text).unwrap_err() {
        MeshError::Parse {
            line,
            message,
            file,
        } => {
            assert_eq!(file, p("test.msh"));
            (line, message)
        }
        other => panic!("expected a parse error, got {other}"),
    }
}

pub(super) fn cross3(u: [f64; 3], v: [f64; 3]) -> [f64; 3] {
    [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ]
}

pub(super) fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("squeal-gmsh-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}
