//! **CalculiX** `*FREQUENCY, SOLVER=MATRIXSTORAGE` output: `jobname.sti` (stiffness) and
//! `jobname.mas` (mass). What ccx 2.20 writes (seen by running it, see
//! `tests/data/ccx_free_beam.inp`): one stored entry per line, `row col value`, 1-based
//! equation numbers, `row <= col` (the upper triangle with the diagonal, column by column),
//! value as `%.13e`; constrained DOFs are not equations. `jobname.dof` lists, one line per
//! equation and in equation order, the `node.direction` it stands for; it is read when it
//! lies beside the matrix file.

use std::path::{Path, PathBuf};

use super::entries::{assemble, RawEntry, Storage};
use super::lines::{fields, file_len, parse_index, parse_real, shorten, Lines};
use super::{MatrixFileError, NodeDof, NodeDofMap, Triplets};

/// `jobname.dof` beside `jobname.sti` / `jobname.mas`.
pub(super) fn calculix_dof_path(matrix: &Path) -> PathBuf {
    matrix.with_extension("dof")
}

/// Reads a CalculiX `jobname.dof`: line k is `node.direction` of equation k.
pub fn read_calculix_dof(path: &Path) -> Result<NodeDofMap, MatrixFileError> {
    let mut lines = Lines::open(path)?;
    let mut by_equation = Vec::new();
    let mut line_of = Vec::new();
    while lines.advance()? {
        let text = lines.text();
        if text.is_empty() {
            continue;
        }
        let parsed = text.split_once('.').and_then(|(n, d)| {
            Some(NodeDof {
                node: n.trim().parse().ok()?,
                dof: d.trim().parse().ok()?,
            })
        });
        let nd = parsed.ok_or_else(|| {
            lines.error(format!(
                "expected 'node.direction' (e.g. 12.3), found '{}'",
                shorten(text)
            ))
        })?;
        by_equation.push(nd);
        line_of.push(lines.number());
    }
    NodeDofMap::new(by_equation).map_err(|(a, b, nd)| {
        MatrixFileError::parse(
            path,
            line_of[b],
            format!(
                "DOF {nd} listed again (first on line {}): each equation is one DOF",
                line_of[a]
            ),
        )
    })
}

/// Reads `row col value` lines. `size`: the equation count and the .dof file it came from;
/// without it the size is the largest index met.
pub(super) fn read_calculix(
    path: &Path,
    size: Option<(usize, &Path)>,
) -> Result<Triplets, MatrixFileError> {
    let bytes = file_len(path)?;
    let mut lines = Lines::open(path)?;
    // ccx writes about 28 bytes an entry ("%d %d %.13e"): a first guess, the vector grows.
    let mut raw: Vec<RawEntry<usize>> = Vec::with_capacity(bytes / 28);
    let mut largest = 0usize;
    while lines.advance()? {
        let text = lines.text();
        if text.is_empty() {
            continue;
        }
        let tokens: Vec<&str> = fields(text).collect();
        if tokens.len() != 3 {
            return Err(lines.error(format!(
                "expected 'row column value', found {} fields in '{}'",
                tokens.len(),
                shorten(text)
            )));
        }
        let limit = size.map_or(usize::MAX, |(n, _)| n);
        let index = |token: &str, what: &str| {
            parse_index(token, what, limit).map_err(|m| match size {
                Some((_, dof)) if m.contains("out of range") => {
                    lines.error(format!("{m}: {} lists {limit} equations", dof.display()))
                }
                _ => lines.error(m),
            })
        };
        let row = index(tokens[0], "row")?;
        let col = index(tokens[1], "column")?;
        let value = parse_real(tokens[2]).map_err(|m| lines.error(m))?;
        largest = largest.max(row + 1).max(col + 1);
        raw.push(RawEntry {
            row,
            col,
            value,
            line: lines.number(),
        });
    }
    let n = size.map_or(largest, |(n, _)| n);
    assemble(path, n, n, raw, Storage::HalfOrFull)
}

#[cfg(test)]
mod tests {
    use super::super::test_support::*;
    use super::super::*;
    use std::collections::HashMap;

    // --- CalculiX -------------------------------------------------------------------------

    #[test]
    fn calculix_triangle_is_mirrored_and_sized_by_the_dof_file() {
        let dir = TempDir::new("ccx");
        let sti = dir.file(
            "job.sti",
            "1 1  4.0e+00\n1 2 -1.0e+00\n2 2  4.0e+00\n2 3 -1.0e+00\n3 3  4.0e+00\n",
        );
        // Without job.dof the size is the largest index.
        assert_eq!(detect_format(&sti).unwrap(), MatrixFormat::CalculixTriangle);
        let t = read(&sti).unwrap();
        assert_eq!(
            dense(&t),
            vec![
                vec![4.0, -1.0, 0.0],
                vec![-1.0, 4.0, -1.0],
                vec![0.0, -1.0, 4.0]
            ]
        );
        // With it, the size is its line count (the 4th equation has no entry here).
        dir.file("job.dof", "1.1\n1.2\n1.3\n5.1\n");
        let t = read(&sti).unwrap();
        assert_eq!((t.rows, t.cols, t.entries.len()), (4, 4, 7));
        let map = read_calculix_dof(&dir.0.join("job.dof")).unwrap();
        assert_eq!(map.len(), 4);
        assert_eq!(map.node_dof(3), Some(NodeDof { node: 5, dof: 1 }));
        assert_eq!(map.equation(NodeDof { node: 1, dof: 3 }), Some(2));
        assert_eq!(map.equation(NodeDof { node: 2, dof: 1 }), None);

        // A file giving a position both ways is a full matrix, read as written.
        let full = dir.file("full.txt", "1 1 1\n1 2 3\n2 1 5\n");
        assert_eq!(
            dense(&read(&full).unwrap()),
            vec![vec![1.0, 3.0], vec![5.0, 0.0]]
        );
    }

    #[test]
    fn calculix_errors_name_the_line() {
        let dir = TempDir::new("ccx-errors");
        let (line, message) = parse_error(read(&dir.file("a.sti", "1 1 1\n\n0 1 2\n")));
        assert_eq!(line, 3);
        assert!(message.contains("row index 0 out of range"), "{message}");
        let (line, message) = parse_error(read(&dir.file("b.sti", "1 1 1\n1 2 x\n")));
        assert_eq!(line, 2);
        assert!(
            message.contains("expected a number, found 'x'"),
            "{message}"
        );
        let (line, message) = parse_error(read(&dir.file("c.mas", "1 1 1 1\n")));
        assert_eq!(line, 1);
        assert!(message.contains("found 4 fields"), "{message}");
        dir.file("d.dof", "1.1\n1.2\n");
        let (line, message) = parse_error(read(&dir.file("d.sti", "1 1 1\n2 3 1\n")));
        assert_eq!(line, 2);
        assert!(
            message.contains("column index 3 out of range 1..=2"),
            "{message}"
        );
        assert!(message.contains("d.dof lists 2 equations"), "{message}");
        let dof = dir.file("e.dof", "1.1\n1.2\n1.1\n");
        let (line, message) = parse_error(read_calculix_dof(&dof));
        assert_eq!(line, 3);
        assert!(
            message.contains("DOF 1.1 listed again (first on line 1)"),
            "{message}"
        );
        let dof = dir.file("f.dof", "1.1\n1,2\n");
        let (line, message) = parse_error(read_calculix_dof(&dof));
        assert_eq!(line, 2);
        assert!(message.contains("expected 'node.direction'"), "{message}");
        std::fs::write(dir.0.join("g.sti"), b"1 1 1\n1 2 \xff\n").unwrap();
        let (line, message) = parse_error(read(&dir.0.join("g.sti")));
        assert_eq!(line, 2);
        assert!(message.contains("not UTF-8"), "{message}");
    }

    /// `tests/data/ccx_free_beam.*`: ccx 2.20's SOLVER=MATRIXSTORAGE output for a free steel
    /// beam 0.1 x 0.01 x 0.01 m (4 x 1 x 1 cubes of 6 C3D10, 81 nodes, no supports). The
    /// checks need nothing but physics:
    /// - K annihilates the six rigid-body motions (a linear field is reproduced exactly by
    ///   the quadratic tet and has zero strain);
    /// - u^T M u for a unit translation is the total mass rho V = 7850 * 1e-5 = 0.0785 kg.
    ///   ccx integrates the C3D10 mass with the 4-point Gauss rule (its corner diagonal on
    ///   the unit tet is V/100, not the exact V/70), so its M is not the exact consistent
    ///   mass, yet the total is exact: sum_ij M_ij = sum_q w_q |J| rho (sum_i N_i)(sum_j N_j)
    ///   and the shape functions sum to 1 at every point, leaving sum_q w_q |J| rho = rho V
    ///   for any rule whose weights sum to the volume (|J| is constant on straight tets).
    #[test]
    fn calculix_beam_matrices_have_rigid_body_modes_and_the_total_mass() {
        let sti = data("ccx_free_beam.sti");
        let set = read_pair(&sti, &data("ccx_free_beam.mas"), None).unwrap();
        assert_eq!(set.format, MatrixFormat::CalculixTriangle);
        let map = set.node_dofs.as_ref().expect("ccx_free_beam.dof is read");
        let (k, m) = (&set.stiffness, &set.mass);
        // 81 nodes x 3 directions; the files hold 6345 upper-triangle entries, 243 of them
        // diagonal, so the full matrices have 2 * 6345 - 243 entries.
        assert_eq!((map.len(), k.rows, k.cols, m.rows), (243, 243, 243, 243));
        assert_eq!((k.entries.len(), m.entries.len()), (12447, 12447));
        assert!(k.is_symmetric(0.0) && m.is_symmetric(0.0));

        // Node coordinates from the deck, by label.
        let deck = std::fs::read_to_string(data("ccx_free_beam.inp")).unwrap();
        let mut xyz: HashMap<i64, [f64; 3]> = HashMap::new();
        let mut in_nodes = false;
        for line in deck.lines() {
            if line.starts_with('*') {
                in_nodes = line.to_ascii_uppercase().starts_with("*NODE,")
                    || line.eq_ignore_ascii_case("*NODE");
                continue;
            }
            if in_nodes {
                let v: Vec<&str> = line.split(',').map(str::trim).collect();
                let c = [1, 2, 3].map(|i| v[i].parse::<f64>().unwrap());
                xyz.insert(v[0].parse().unwrap(), c);
            }
        }
        assert_eq!(xyz.len(), 81);
        // A displacement field u(node position) as an equation vector, through the .dof map.
        let field = |u: &dyn Fn([f64; 3]) -> [f64; 3]| -> Vec<f64> {
            map.as_slice()
                .iter()
                .map(|nd| u(xyz[&nd.node])[nd.dof as usize - 1])
                .collect()
        };
        let rigid: [fn([f64; 3]) -> [f64; 3]; 6] = [
            |_| [1.0, 0.0, 0.0],
            |_| [0.0, 1.0, 0.0],
            |_| [0.0, 0.0, 1.0],
            |p| [0.0, -p[2], p[1]],
            |p| [p[2], 0.0, -p[0]],
            |p| [-p[1], p[0], 0.0],
        ];
        let abs_k = Triplets {
            entries: k.entries.iter().map(|&(r, c, v)| (r, c, v.abs())).collect(),
            ..k.clone()
        };
        for (mode, u) in rigid.iter().enumerate() {
            let x = field(u);
            let kx = k.mul_vec(&x);
            let scale = abs_k.mul_vec(&x.iter().map(|v| v.abs()).collect::<Vec<_>>());
            // ccx prints 14 significant digits, so each entry carries a relative error up to
            // 5e-14 and (K x)_i, exactly 0 for the printed-from matrix, can be off by
            // 5e-14 * sum_j |K_ij x_j|; 1e-13 leaves room for ccx's own rounding. (Measured:
            // at most 1.5e-14.)
            for i in 0..k.rows {
                assert!(
                    kx[i].abs() <= 1e-13 * scale[i],
                    "rigid mode {mode}: (K u)_{i} = {:e}, scale {:e}",
                    kx[i],
                    scale[i]
                );
            }
        }
        // Total mass in each direction; the mass does not couple directions.
        let rho_v = 7850.0 * 0.1 * 0.01 * 0.01;
        let abs_m = Triplets {
            entries: m.entries.iter().map(|&(r, c, v)| (r, c, v.abs())).collect(),
            ..m.clone()
        };
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
        for d in 0..3 {
            let u = field(&|_| {
                let mut e = [0.0; 3];
                e[d] = 1.0;
                e
            });
            let total = dot(&u, &m.mul_vec(&u));
            // Same printing bound as above: 5e-14 relative on each term of the sum, whose
            // magnitudes add up to 1.96 rho V. (Measured: 9.4e-15 rho V.)
            let bound = 1e-13 * dot(&u, &abs_m.mul_vec(&u));
            assert!(
                (total - rho_v).abs() <= bound,
                "direction {d}: u^T M u = {total:e}, rho V = {rho_v:e}, bound {bound:e}"
            );
            let other = field(&|_| {
                let mut e = [0.0; 3];
                e[(d + 1) % 3] = 1.0;
                e
            });
            assert_eq!(dot(&other, &m.mul_vec(&u)), 0.0);
        }
        assert!(k.entries.iter().all(|&(r, c, v)| r != c || v > 0.0));
        assert!(m.entries.iter().all(|&(r, c, v)| r != c || v > 0.0));

        // The same matrices through the Matrix Market writer and back: identical.
        let dir = TempDir::new("ccx-roundtrip");
        let out = dir.0.join("k.mtx");
        write_matrix_market(&out, k, true).unwrap();
        assert_eq!(&read(&out).unwrap(), k);
    }
}
