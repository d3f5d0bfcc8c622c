//! The 6x6 rigid-pad stiffness of each disc/pad interface, the full model's against a reduced
//! interface's (issue 29, step 1): at each model's own sliding equilibrium, the linearised
//! contact forces and moments on a pad face moved as a rigid body against a held disc face,
//! about the full model's closed-zone centroid, in the frame (e1, e2, n) of the pad face
//! (n the disc normal towards the pad). Friction is in it: the tangential forces and the
//! moment about n that a normal approach or a rocking of the pad brings (the unsymmetric
//! part the instabilities come from). Run it with
//!
//!     cargo run --release --example rigid_pad_stiffness -- [PRESET] [NODES] [MU] [warp] [pushed]
//!     mpirun -n 2 target/release/examples/rigid_pad_stiffness small-caliper 52 0.5
//!
//! (defaults: tiny-caliper, 22 nodes per pad, mu 0.5; squeal's default interface: share
//! couplings on both sides and patch laws where the mesh holds them; `warp` adds the warping
//! springs; `pushed` takes, instead of the equilibria, each pad face pushed 10 um into the
//! disc and everything else at rest, so that every point of both models is closed and the
//! two interfaces' laws are compared apart from their contact zones).
//!
//! How. The full model's pad face nodes are its pairs' slave nodes: K6 = R^T J R, J the
//! contact Jacobian's block on them, R the rigid motion u(X) = t + w x (X - O). A reduced
//! interface acts on the pad face through extra nodes (reduced contact nodes, disc nodes,
//! tilt nodes) tied to it by stiff springs: those are condensed out with the disc face held,
//! K6 = R^T (J_ff - J_fe J_ee^-1 J_ef) R, which is what the pad feels, the ties' compliance
//! included.
//!
//! It also puts the full model's own gaps through the reduced interface's patch laws (each
//! share's least-squares plane through its nodes' gaps): what the laws' quadrature closes
//! where the faces move exactly as the full model's, against what the full model's nodes
//! close (issue 29: the area rule closed 48.0 / 47.5 % against 51.2 % on small-caliper at 52
//! nodes per pad, mu 0; at the nodes, the default since 2026-12-07, 49.9 / 50.2 %).
//!
//! What it checks, whatever the reduction: both models' stiffness is finite, and a rigid
//! translation along n of the full model gives the closed zone's k_n A (the sum over closed
//! points) to round-off. It exits with failure otherwise.

use faer::linalg::solvers::Solve;
use faer::Mat;
use squeal::analysis::restraint;
use squeal::analysis::statics::{self, StaticOptions, StaticProblem};
use squeal::contact::{self, ContactPair, SlipHistory};
use squeal::fem::element::MassRule;
use squeal::model::{self, Model, Operators};
use squeal::petsc::{Runtime, RuntimeOptions};
use squeal::reduce::{reduce_interface, GridSize, InterfaceSettings};
use squeal::study::config::Study;
use squeal::vector3::{cross, dot, normalize, scale, sub};
use std::collections::{BTreeMap, BTreeSet};
use std::process::ExitCode;

/// The generalised coordinates' names: translations along e1, e2, n, rotations about them.
const NAMES: [&str; 6] = ["u1", "u2", "un", "r1", "r2", "rn"];

/// A spring on one combination of components: (node, coefficient per component), N/m.
type Tie = (Vec<(usize, [f64; 3])>, f64);

/// A pad face's frame: the origin O and the axes (e1, e2, n).
#[derive(Clone, Copy, Debug)]
struct Frame {
    origin: [f64; 3],
    axes: [[f64; 3]; 3],
}

impl Frame {
    /// The 3x6 rigid-motion block at X: column q the displacement of X under unit
    /// coordinate q (translations along the axes, rotations about them through O).
    fn rigid(&self, x: [f64; 3]) -> [[f64; 6]; 3] {
        let mut r = [[0.0; 6]; 3];
        let arm = sub(x, self.origin);
        for (q, e) in self.axes.iter().enumerate() {
            let rot = cross(*e, arm);
            for c in 0..3 {
                r[c][q] = e[c];
                r[c][q + 3] = rot[c];
            }
        }
        r
    }
}

/// The static equilibrium of `model`.
fn equilibrium(rt: &Runtime, model: &Model) -> Result<Vec<[f64; 3]>, String> {
    let comm = rt.world();
    let Operators {
        dofs,
        stiffness,
        load,
        ..
    } = model::assemble(comm, model, MassRule::Exact).map_err(|e| e.to_string())?;
    let problem = StaticProblem {
        dofs: &dofs,
        stiffness: &stiffness,
        load: &load,
        pairs: &model.pairs,
        slip: &SlipHistory::default(),
        bodies: &restraint::bodies(&model.mesh),
        constraints: None,
    };
    let solved = statics::solve(comm, &problem, None, &StaticOptions::default())
        .map_err(|e| e.to_string())?;
    Ok(solved.displacement)
}

/// The frame of a full pair at its equilibrium: O the closed points' k-weighted centroid
/// (their areas' centroid, the penalty being the pair's), n the points' mean normal, e1 the
/// global x made orthogonal to n.
fn frame(pair: &ContactPair, u: &[[f64; 3]]) -> Result<(Frame, f64), String> {
    let (mut area, mut first, mut normal) = (0.0, [0.0; 3], [0.0; 3]);
    for point in &pair.points {
        let state = contact::point_state(pair, point, [0.0; 3], u).map_err(|e| e.to_string())?;
        normal = squeal::vector3::add(normal, scale(point.area, point.normal));
        if state.closed {
            area += point.area;
            first = squeal::vector3::add(first, scale(point.area, point.position));
        }
    }
    if area <= 0.0 {
        return Err(format!("pair '{}' is open", pair.settings.name));
    }
    let n = normalize(normal).ok_or("no mean normal")?;
    let x = [1.0, 0.0, 0.0];
    let e1 = normalize(sub(x, scale(dot(x, n), n))).ok_or("normal along x")?;
    let e2 = cross(n, e1);
    Ok((
        Frame {
            origin: scale(1.0 / area, first),
            axes: [e1, e2, n],
        },
        pair.penalty * area,
    ))
}

/// Over a reduced pad's shares: the patch laws' closed stiffness k0 at the weighted
/// least-squares plane through the full model's gaps at each share's pad nodes (at `u`, the
/// full model's equilibrium; the plane's mean where the translation tie holds it, its slope
/// as the slope ties do), and the full model's closed k_n a over the same nodes. Their ratio
/// is what the patch laws' quadrature loses even where the reduced model's faces move
/// exactly as the full model's (issue 29: 0.94 with the area rule on small-caliper at 52
/// nodes per pad, mu 0, whatever the grid).
fn plane_law_on_full_field(
    full: &ContactPair,
    reduced: &ContactPair,
    pad: &squeal::reduce::ReducedPad,
    u: &[[f64; 3]],
) -> Result<(f64, f64), String> {
    let mut gaps = BTreeMap::new();
    for p in &full.points {
        let state = contact::point_state(full, p, [0.0; 3], u).map_err(|e| e.to_string())?;
        gaps.insert(p.slave_node, (state.gap, p.area, p.position));
    }
    let (mut planes, mut nodes) = (0.0, 0.0);
    let mut seen = BTreeSet::new();
    for (r, coupling) in pad.couplings.iter().enumerate() {
        let point = reduced
            .points
            .iter()
            .find(|p| p.slave_node == pad.contact_nodes[r])
            .ok_or("a reduced node without its point")?;
        let Some(tilt) = &point.tilt else { continue };
        // Normal equations of g = a + b . xi, weighted by the coupling's weights.
        let mut n = [[0.0; 3]; 3];
        let mut rhs = [0.0; 3];
        for c in &coupling.nodes {
            let Some(&(g, area, x)) = gaps.get(&c.node) else {
                continue;
            };
            let d = sub(x, point.position);
            let row = [1.0, dot(d, tilt.axes[0]), dot(d, tilt.axes[1])];
            for i in 0..3 {
                rhs[i] += c.weight * row[i] * g;
                for j in 0..3 {
                    n[i][j] += c.weight * row[i] * row[j];
                }
            }
            if g <= 0.0 && seen.insert(c.node) {
                nodes += full.penalty * area;
            }
        }
        let m = Mat::from_fn(3, 3, |i, j| n[i][j]);
        let b = Mat::from_fn(3, 1, |i, _| rhs[i]);
        let x = m.full_piv_lu().solve(&b);
        // The gap as the translation tie reads it: the weighted mean.
        planes += tilt.law(rhs[0] / n[0][0], [x[(1, 0)], x[(2, 0)]]).k0;
    }
    Ok((planes, nodes))
}

/// The condensed 6x6 stiffness of the pad face `face` (nodes moved rigidly by `frame`)
/// through `pair` and the ties `springs` ((terms, stiffness) with a term's coefficient per
/// component), every other node held, the extra nodes (index >= `mesh_nodes`) condensed;
/// `positions` of every node, `u` the equilibrium's displacements.
fn rigid_stiffness(
    pair: &ContactPair,
    springs: &[Tie],
    (positions, u): (&[[f64; 3]], &[[f64; 3]]),
    face: &BTreeSet<usize>,
    mesh_nodes: usize,
    frame: &Frame,
) -> Result<[[f64; 6]; 6], String> {
    // The extra nodes, numbered.
    let mut extra: BTreeMap<usize, usize> = BTreeMap::new();
    let number = |node: usize, extra: &mut BTreeMap<usize, usize>| {
        if node >= mesh_nodes {
            let next = extra.len();
            extra.entry(node).or_insert(next);
        }
    };
    let mut blocks: Vec<(Vec<usize>, Vec<f64>)> = Vec::new();
    for point in &pair.points {
        let (_, contribution) =
            contact::evaluate(pair, point, [0.0; 3], u).map_err(|e| e.to_string())?;
        if let Some(c) = contribution {
            for &n in &c.nodes {
                number(n, &mut extra);
            }
            blocks.push((c.nodes, c.jacobian));
        }
    }
    // The ties of those extra nodes (every other spring stores nothing under a rigid motion
    // of the face with the rest held, or touches no node of the pad face).
    for (terms, k) in springs {
        if terms.iter().any(|t| extra.contains_key(&t.0)) {
            for t in terms {
                number(t.0, &mut extra);
            }
            let g: Vec<f64> = terms.iter().flat_map(|t| t.1).collect();
            let n = g.len();
            let mut jacobian = vec![0.0; n * n];
            for a in 0..n {
                for b in 0..n {
                    jacobian[a * n + b] = k * g[a] * g[b];
                }
            }
            blocks.push((terms.iter().map(|t| t.0).collect(), jacobian));
        }
    }
    let ne = 3 * extra.len();
    let mut k_ff = [[0.0; 6]; 6];
    let mut k_ef = Mat::<f64>::zeros(ne, 6);
    let mut k_fe = Mat::<f64>::zeros(6, ne);
    let mut k_ee = Mat::<f64>::zeros(ne, ne);
    // Row/column kinds: a pad face node (its rigid block), an extra node (its index), or
    // held.
    enum Kind {
        Face([[f64; 6]; 3]),
        Extra(usize),
        Held,
    }
    let kind = |node: usize| {
        if let Some(&e) = extra.get(&node) {
            Kind::Extra(3 * e)
        } else if face.contains(&node) {
            Kind::Face(frame.rigid(positions[node]))
        } else {
            Kind::Held
        }
    };
    for (nodes, jacobian) in &blocks {
        let size = 3 * nodes.len();
        let kinds: Vec<Kind> = nodes.iter().map(|&n| kind(n)).collect();
        for (a, ka) in kinds.iter().enumerate() {
            for (b, kb) in kinds.iter().enumerate() {
                let j = |i: usize, l: usize| jacobian[(3 * a + i) * size + 3 * b + l];
                match (ka, kb) {
                    (Kind::Face(ra), Kind::Face(rb)) => {
                        for p in 0..6 {
                            for q in 0..6 {
                                let mut s = 0.0;
                                for (i, row) in ra.iter().enumerate() {
                                    for (l, col) in rb.iter().enumerate() {
                                        s += row[p] * j(i, l) * col[q];
                                    }
                                }
                                k_ff[p][q] += s;
                            }
                        }
                    }
                    (Kind::Extra(ea), Kind::Face(rb)) => {
                        for i in 0..3 {
                            for q in 0..6 {
                                let s: f64 = (0..3).map(|l| j(i, l) * rb[l][q]).sum();
                                k_ef[(ea + i, q)] += s;
                            }
                        }
                    }
                    (Kind::Face(ra), Kind::Extra(eb)) => {
                        for p in 0..6 {
                            for l in 0..3 {
                                let s: f64 = (0..3).map(|i| ra[i][p] * j(i, l)).sum();
                                k_fe[(p, eb + l)] += s;
                            }
                        }
                    }
                    (Kind::Extra(ea), Kind::Extra(eb)) => {
                        for i in 0..3 {
                            for l in 0..3 {
                                k_ee[(ea + i, eb + l)] += j(i, l);
                            }
                        }
                    }
                    _ => {}
                }
            }
        }
    }
    if ne > 0 {
        let x = k_ee.partial_piv_lu().solve(&k_ef);
        let correction = &k_fe * &x;
        for p in 0..6 {
            for q in 0..6 {
                k_ff[p][q] -= correction[(p, q)];
            }
        }
    }
    Ok(k_ff)
}

/// Every tie spring of `model` as (terms with per-component coefficients, stiffness).
fn springs(model: &Model) -> Vec<Tie> {
    let mut out = Vec::new();
    for c in &model.couplings {
        // Isotropic: the same coefficient in each component, one spring per component.
        for axis in 0..3 {
            let terms = c
                .terms
                .iter()
                .map(|&(n, a)| {
                    let mut g = [0.0; 3];
                    g[axis] = a;
                    (n, g)
                })
                .collect();
            out.push((terms, c.stiffness));
        }
    }
    for s in &model.scalar_springs {
        out.push((s.terms.clone(), s.stiffness));
    }
    out
}

fn print_matrix(label: &str, k: &[[f64; 6]; 6]) {
    println!("  {label}");
    println!("        {}", NAMES.map(|n| format!("{n:>11}")).join(""));
    for (p, row) in k.iter().enumerate() {
        println!(
            "    {:>3} {}",
            NAMES[p],
            row.map(|v| format!("{v:>11.3e}")).join("")
        );
    }
}

fn run(rt: &Runtime) -> Result<Vec<String>, String> {
    let root = rt.world().rank() == 0;
    let args: Vec<String> = std::env::args().skip(1).collect();
    let preset = args.first().map_or("tiny-caliper", String::as_str);
    let nodes: usize = match args.get(1) {
        Some(n) => n.parse().map_err(|_| format!("NODES: a count, got {n}"))?,
        None => 22,
    };
    let mu: f64 = match args.get(2) {
        Some(m) => m.parse().map_err(|_| format!("MU: a number, got {m}"))?,
        None => 0.5,
    };
    let flags: Vec<&str> = args.iter().skip(3).map(String::as_str).collect();
    if let Some(other) = flags.iter().find(|f| !["warp", "pushed"].contains(f)) {
        return Err(format!("expected warp or pushed, got {other}"));
    }
    let warp = flags.contains(&"warp");
    let pushed = flags.contains(&"pushed");
    let mut study = Study::builtin(preset);
    for c in study.contacts.iter_mut().filter(|c| c.sweep) {
        c.friction = mu;
    }
    let full = Model::from_spec(&study.model_spec()).map_err(|e| e.to_string())?;
    let settings = InterfaceSettings {
        size: GridSize::Count(nodes),
        warp_springs: warp,
        ..Default::default()
    };
    let reduced = reduce_interface(&full, &settings).map_err(|e| e.to_string())?;
    // Pushed, every point of the faces is closed: the interfaces' laws alone, apart from
    // where each model's equilibrium closes them.
    let (u_full, u_reduced) = if pushed {
        // Every swept pair's slave side pushed 10 um into the disc along its normal.
        let pushed = |model: &Model| {
            let mut u = vec![[0.0; 3]; model.node_count()];
            for (i, pair) in model.pairs.iter().enumerate() {
                if model.swept[i] {
                    for p in &pair.points {
                        u[p.slave_node] = scale(-1e-5, p.normal);
                    }
                }
            }
            u
        };
        (pushed(&full), pushed(&reduced.model))
    } else {
        (equilibrium(rt, &full)?, equilibrium(rt, &reduced.model)?)
    };
    let mesh_nodes = full.mesh.nodes.len();
    let positions: Vec<[f64; 3]> = (0..reduced.model.node_count())
        .map(|n| reduced.model.position(n))
        .collect();
    let full_springs = springs(&full);
    let reduced_springs = springs(&reduced.model);
    let mut failures = Vec::new();
    if root {
        println!("{}", reduced.summary());
        println!(
            "{preset}, mu {mu}: the rigid-pad stiffness (N/m, N, N m) about the full model's \
             closed-zone centroid, at each model's own equilibrium"
        );
    }
    for (i, pair) in full.pairs.iter().enumerate() {
        if !full.swept[i] {
            continue;
        }
        let name = &pair.settings.name;
        let face: BTreeSet<usize> = pair.points.iter().map(|p| p.slave_node).collect();
        let (frame, closed_stiffness) = frame(pair, &u_full)?;
        let k_full = rigid_stiffness(
            pair,
            &full_springs,
            (&positions, &u_full),
            &face,
            mesh_nodes,
            &frame,
        )?;
        let reduced_pair = reduced
            .model
            .pairs
            .iter()
            .find(|p| &p.settings.name == name)
            .ok_or_else(|| format!("the reduced model has no pair '{name}'"))?;
        let k_reduced = rigid_stiffness(
            reduced_pair,
            &reduced_springs,
            (&positions, &u_reduced),
            &face,
            mesh_nodes,
            &frame,
        )?;
        if k_full
            .iter()
            .chain(&k_reduced)
            .flatten()
            .any(|v| !v.is_finite())
        {
            failures.push(format!("{name}: a stiffness is not finite"));
        }
        if (k_full[2][2] / closed_stiffness - 1.0).abs() > 1e-9 {
            failures.push(format!(
                "{name}: the full model's normal stiffness {:e} is not its closed zone's k_n A {:e}",
                k_full[2][2], closed_stiffness
            ));
        }
        if root {
            println!(
                "{name}: O = ({:.2}, {:.2}, {:.2}) mm, n = ({:.3}, {:.3}, {:.3})",
                1e3 * frame.origin[0],
                1e3 * frame.origin[1],
                1e3 * frame.origin[2],
                frame.axes[2][0],
                frame.axes[2][1],
                frame.axes[2][2]
            );
            // The closed zone's share of the face's k_n A, and its centroid's offset from
            // O along e1, e2: a rotation about e1 moves X by (X - O) . e2 along n, about e2
            // by -(X - O) . e1.
            let face_stiffness: f64 =
                pair.penalty * pair.points.iter().map(|p| p.area).sum::<f64>();
            for (model, k) in [("full", &k_full), ("reduced", &k_reduced)] {
                println!(
                    "  {model:7}: closed {:.1} % of the face's k_n A, its centroid {:+.3}, {:+.3} mm from O",
                    100.0 * k[2][2] / face_stiffness,
                    -1e3 * k[2][4] / k[2][2],
                    1e3 * k[2][3] / k[2][2]
                );
            }
            // The plane law on the full model's own field: each share's weighted
            // least-squares plane through the full model's gaps at its pad nodes, put
            // through the share's patch law. What it closes against what the full model's
            // nodes close says whether a plane per share can hold the closed zone even
            // where the reduced model's faces moved exactly as the full model's.
            if let Some(pad) = reduced.pads.iter().find(|p| &p.pair == name) {
                let (planes, nodes) = plane_law_on_full_field(pair, reduced_pair, pad, &u_full)?;
                println!(
                    "  the patch laws on the full model's gaps: close {:.1} % of the face's \
                     k_n A, its nodes {:.1} %",
                    100.0 * planes / face_stiffness,
                    100.0 * nodes / face_stiffness
                );
            }
            print_matrix("full", &k_full);
            print_matrix("reduced", &k_reduced);
            // The entries that matter: the normal and rocking stiffnesses and what friction
            // couples to them (tangential forces and the moment about n from a normal
            // approach or a rocking).
            println!("  reduced / full:");
            for (p, q) in [
                (2, 2),
                (3, 3),
                (4, 4),
                (3, 4),
                (2, 3),
                (2, 4),
                (0, 2),
                (1, 2),
                (0, 3),
                (0, 4),
                (1, 3),
                (1, 4),
                (5, 2),
                (5, 3),
                (5, 4),
            ] {
                println!(
                    "    K[{}][{}]: full {:+.4e}, reduced {:+.4e}, ratio {:.4}",
                    NAMES[p],
                    NAMES[q],
                    k_full[p][q],
                    k_reduced[p][q],
                    k_reduced[p][q] / k_full[p][q]
                );
            }
        }
    }
    Ok(failures)
}

fn main() -> ExitCode {
    let rt = match Runtime::init(&RuntimeOptions::default()) {
        Ok(rt) => rt,
        Err(e) => {
            eprintln!("rigid_pad_stiffness: PETSc did not start: {e}");
            return ExitCode::FAILURE;
        }
    };
    let root = rt.world().rank() == 0;
    match run(&rt) {
        Ok(failures) if failures.is_empty() => ExitCode::SUCCESS,
        Ok(failures) => {
            if root {
                eprintln!("rigid_pad_stiffness: FAILED: {}", failures.join("; "));
            }
            ExitCode::FAILURE
        }
        Err(e) => {
            if root {
                eprintln!("rigid_pad_stiffness: {e}");
            }
            ExitCode::FAILURE
        }
    }
}
