//! What the tests of the deck reader share: a temporary folder, parse errors, the unit
//! tetrahedron, a box mesher (Kuhn split) and the committed beam deck.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::{read, Deck};
use crate::mesh::{MeshError, TET10_EDGES};
use crate::vector3::{cross, dot};

/// A directory under the system temp dir, removed when dropped.
pub(super) struct TempDir(pub(super) PathBuf);

impl TempDir {
    pub(super) fn new(test: &str) -> TempDir {
        let dir = std::env::temp_dir().join(format!("squeal-abaqus-{test}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("create temp dir");
        TempDir(dir)
    }

    pub(super) fn write(&self, name: &str, text: &str) -> PathBuf {
        let path = self.0.join(name);
        if let Some(parent) = path.parent() {
            std::fs::create_dir_all(parent).expect("create dir");
        }
        std::fs::write(&path, text).expect("write deck");
        path
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

pub(super) fn read_text(test: &str, text: &str) -> Result<Deck, MeshError> {
    let dir = TempDir::new(test);
    read(&dir.write("deck.inp", text))
}

pub(super) fn parse_error(result: Result<Deck, MeshError>) -> (PathBuf, usize, String) {
    match result {
        Err(MeshError::Parse {
            file,
            line,
            message,
        }) => (file, line, message),
        other => panic!("expected a parse error, got {other:?}"),
    }
}

/// Corners of the unit tetrahedron and its 10 nodes in C3D10 order.
pub(super) fn unit_tet_points() -> Vec<[f64; 3]> {
    let c = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    let mut p = c.to_vec();
    for [a, b] in TET10_EDGES {
        p.push([0, 1, 2].map(|k| 0.5 * (c[a][k] + c[b][k])));
    }
    p
}

/// `*NODE` lines of the unit tet with labels `first, first + 1, ...`.
pub(super) fn unit_tet_nodes(first: i64) -> String {
    let mut s = String::new();
    for (i, x) in unit_tet_points().iter().enumerate() {
        writeln!(s, "{}, {}, {}, {}", first + i as i64, x[0], x[1], x[2]).unwrap();
    }
    s
}

pub(super) fn unit_tet_element(label: i64, first: i64) -> String {
    let nodes: Vec<String> = (0..10).map(|k| (first + k).to_string()).collect();
    format!("{label}, {}\n", nodes.join(", "))
}

pub(super) const STEEL: &str = "*MATERIAL, NAME=Steel\n*ELASTIC\n210e9, 0.3\n*DENSITY\n7850.\n";

/// One unit tet, nodes 11..20, element 7, in set EALL with steel.
pub(super) fn one_tet() -> String {
    format!(
        "*NODE, NSET=NALL\n{}*ELEMENT, TYPE=C3D10, ELSET=EALL\n{}{STEEL}\
         *SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n",
        unit_tet_nodes(11),
        unit_tet_element(7, 11)
    )
}

/// A box of `n[0] x n[1] x n[2]` cubes, each split into the six Kuhn tetrahedra (a
/// conforming mesh), with quadratic nodes at the edge midpoints. Returns the `*NODE` and
/// `*ELEMENT` text and, per node label, its half-grid index. Node labels are odd numbers
/// (so not contiguous), element labels start at 101.
pub(super) fn box_mesh(n: [usize; 3], size: [f64; 3], elset: &str) -> String {
    let m = [2 * n[0] + 1, 2 * n[1] + 1, 2 * n[2] + 1];
    let label = |h: [usize; 3]| 2 * (h[0] + m[0] * (h[1] + m[1] * h[2])) + 1;
    let mut s = String::from("*NODE, NSET=NALL\n");
    for k in 0..m[2] {
        for j in 0..m[1] {
            for i in 0..m[0] {
                let x = [i, j, k]
                    .iter()
                    .zip(size.iter().zip(n))
                    .map(|(&h, (&l, n))| h as f64 * l / (2 * n) as f64)
                    .collect::<Vec<_>>();
                writeln!(
                    s,
                    "{}, {:.8}, {:.8}, {:.8}",
                    label([i, j, k]),
                    x[0],
                    x[1],
                    x[2]
                )
                .unwrap();
            }
        }
    }
    writeln!(s, "*ELEMENT, TYPE=C3D10, ELSET={elset}").unwrap();
    let perms = [
        [0, 1, 2],
        [0, 2, 1],
        [1, 0, 2],
        [1, 2, 0],
        [2, 0, 1],
        [2, 1, 0],
    ];
    let mut e = 101;
    for k in 0..n[2] {
        for j in 0..n[1] {
            for i in 0..n[0] {
                for p in perms {
                    // Path from the cube's (0,0,0) corner to (1,1,1) along p.
                    let mut v = [[2 * i, 2 * j, 2 * k]; 4];
                    for step in 0..3 {
                        v[step + 1] = v[step];
                        v[step + 1][p[step]] += 2;
                    }
                    // Odd permutations give negative volumes: swap two corners.
                    let d = |a: usize| [0, 1, 2].map(|c| v[a][c] as f64 - v[0][c] as f64);
                    if dot(d(1), cross(d(2), d(3))) < 0.0 {
                        v.swap(1, 2);
                    }
                    let mut nodes: Vec<usize> = v.iter().map(|&h| label(h)).collect();
                    for [a, b] in TET10_EDGES {
                        nodes.push(label([0, 1, 2].map(|c| (v[a][c] + v[b][c]) / 2)));
                    }
                    let list: Vec<String> = nodes.iter().map(|x| x.to_string()).collect();
                    writeln!(s, "{e}, {}", list.join(", ")).unwrap();
                    e += 1;
                }
            }
        }
    }
    s
}

/// The committed test deck: a 0.1 x 0.01 x 0.01 m steel cantilever, clamped at x = 0,
/// with a 10-mode *FREQUENCY step, as CalculiX runs it.
pub(super) fn beam_deck() -> String {
    let n = [10, 2, 2];
    let mut s = String::from(
        "*HEADING\nCantilever beam 0.1 x 0.01 x 0.01 m, 10 x 2 x 2 cubes of 6 C3D10, steel, \
         clamped at x = 0\n** Written by write_beam_deck in src/io/abaqus/mod.rs (squeal).\n",
    );
    s.push_str(&box_mesh(n, [0.1, 0.01, 0.01], "EBEAM"));
    s.push_str("*NSET, NSET=FIX\n");
    let m = [2 * n[0] + 1, 2 * n[1] + 1, 2 * n[2] + 1];
    let fixed: Vec<String> = (0..m[1] * m[2])
        .map(|jk| (2 * m[0] * jk + 1).to_string())
        .collect();
    for chunk in fixed.chunks(8) {
        writeln!(s, "{}", chunk.join(", ")).unwrap();
    }
    s.push_str(
        "*MATERIAL, NAME=STEEL\n*ELASTIC\n210e9, 0.3\n*DENSITY\n7850.\n\
         *SOLID SECTION, ELSET=EBEAM, MATERIAL=STEEL\n\
         *BOUNDARY\nFIX, 1, 3\n\
         *STEP\n*FREQUENCY\n10\n*NODE FILE\nU\n*EL FILE\nS\n*END STEP\n",
    );
    s
}

pub(super) fn beam_path() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/beam_c3d10.inp")
}
