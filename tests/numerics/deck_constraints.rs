//! Linear constraints from decks, on 1 and 2 ranks (see `common/harness.rs`): a distributing
//! coupling against the closed form of a rigid block on springs, prescribed displacements
//! against the exact linear fields they impose (and the reaction E A d / L), in global and
//! in cylindrical (`*TRANSFORM`) directions. The decks are tests/data/coupled_block.inp,
//! prescribed_bar.inp, prescribed_tube.inp and tied_pads_clamped.inp (written by
//! constraint_decks.py there; the ties' force balance); the
//! frequencies against CalculiX are in `tests/program/modes_cli.rs`.

use crate::common;

use common::harness::Check;
use squeal::analysis::modes::{real_modes, ModeBand, ModesOptions};
use squeal::analysis::statics::{self, StaticOptions, StaticProblem, StaticSolution};
use squeal::contact::SlipHistory;
use squeal::fem::element::MassRule;
use squeal::model::{self, source, Model, Operators};
use squeal::petsc::Runtime;
use std::path::Path;

pub const CHECKS: &[Check] = &[
    Check {
        name: "a_mass_on_a_distributing_coupling_moves_with_the_block_it_is_tied_to",
        run: coupled_block_modes,
        ranks: &[1, 2],
        // The rigid-body modes sit 5e8 below the block's own modes: their omega^2 carry
        // eps x 5e8 ~ 1e-7 of round-off, whatever the rank count.
        agreement: 1e-6,
    },
    Check {
        name: "a_force_on_a_coupling_reference_carries_its_moment",
        run: coupled_block_static,
        ranks: &[1, 2],
        agreement: 1e-6,
    },
    Check {
        name: "a_prescribed_end_displacement_stretches_a_bar_exactly",
        run: prescribed_bar,
        ranks: &[1, 2],
        agreement: 1e-8,
    },
    Check {
        name: "prescribed_radial_displacements_in_a_cylindrical_system_expand_a_tube_exactly",
        run: prescribed_tube,
        ranks: &[1, 2],
        agreement: 1e-8,
    },
    Check {
        name: "tied_pads_pass_their_loads_to_the_plate_through_the_tie",
        run: tied_pads_loaded,
        ranks: &[1, 2],
        agreement: 1e-8,
    },
    Check {
        name: "a_pad_pressed_on_a_plate_by_a_prescribed_displacement_balances_its_reaction",
        run: pressed_pad,
        ranks: &[1, 2],
        agreement: 1e-8,
    },
];

fn deck(name: &str) -> Result<Model, String> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name);
    source::read(&path).map_err(|e| e.to_string())
}

fn text<E: std::fmt::Display>(e: E) -> String {
    e.to_string()
}

/// The static equilibrium of a model without contact, and the forces its constraints apply.
fn solve_static(rt: &Runtime, model: &Model) -> Result<(StaticSolution, Vec<[f64; 3]>), String> {
    let comm = rt.world();
    let Operators {
        dofs,
        stiffness,
        load,
        constraints,
        ..
    } = model::assemble(comm, model, MassRule::Exact).map_err(text)?;
    let slip = SlipHistory::default();
    let problem = StaticProblem {
        dofs: &dofs,
        stiffness: &stiffness,
        load: &load,
        pairs: &model.pairs,
        slip: &slip,
        bodies: &[],
        constraints: constraints.as_ref(),
    };
    let solution = statics::solve(comm, &problem, None, &StaticOptions::default()).map_err(text)?;
    let forces = statics::constraint_forces(comm, &problem, &slip, &solution.displacement, 1.0)
        .map_err(text)?;
    Ok((solution, forces))
}

// --- the coupled block -------------------------------------------------------------------

/// tests/data/coupled_block.inp: a 20 x 20 x 10 mm steel block (density 7850) on SPRING1 of
/// 10 N/m in x, y and z at each of the 25 nodes of its bottom face, and 0.5 kg on a node
/// 15 mm above the centre of its top face, tied to that face by a uniform distributing
/// coupling.
const BLOCK: [f64; 3] = [0.02, 0.02, 0.01];
const DENSITY: f64 = 7850.0;
const REFERENCE_MASS: f64 = 0.5;
const REFERENCE_HEIGHT: f64 = 0.025;
const SPRING: f64 = 10.0;

/// The spring layout: 25 nodes on a 5 x 5 grid of pitch 5 mm about the centre.
fn springs() -> (f64, f64) {
    let offsets = [-0.01, -0.005, 0.0, 0.005, 0.01];
    let count = 25.0;
    let second_moment: f64 = 5.0 * offsets.iter().map(|d| d * d).sum::<f64>();
    (count * SPRING, SPRING * second_moment)
}

/// The six rigid-body eigenvalues omega^2 of block + reference mass on the springs, the
/// reference moving rigidly with the block (Abaqus's distributing coupling: the reference
/// point follows the cloud's mean translation and rotation). Axes through the centre of the
/// bottom face: z translation and z rotation apart, x translation with y rotation coupled
/// (and y with x, the same by symmetry).
fn closed_form() -> Vec<f64> {
    let [a, b, c] = BLOCK;
    let block = DENSITY * a * b * c;
    let mass = block + REFERENCE_MASS;
    let (k_translation, k_rocking) = springs();
    let z = k_translation / mass;
    let torsion = 2.0 * k_rocking / (block * (a * a + b * b) / 12.0);
    // (u, theta): u_x = u + theta z, u_z = -theta (x - x_c).
    let s = block * c / 2.0 + REFERENCE_MASS * REFERENCE_HEIGHT;
    let j = block * (c * c / 3.0 + a * a / 12.0) + REFERENCE_MASS * REFERENCE_HEIGHT.powi(2);
    let (p, q, r) = (
        mass * j - s * s,
        k_translation * j + k_rocking * mass,
        k_translation * k_rocking,
    );
    let root = (q * q - 4.0 * p * r).sqrt();
    // The small root without cancellation.
    let (low, high) = (2.0 * r / (q + root), (q + root) / (2.0 * p));
    let mut all = vec![low, low, z, torsion, high, high];
    all.sort_by(f64::total_cmp);
    all
}

/// The block's six lowest modes are its rigid-body modes on the springs (its own, elastic,
/// modes start near 60 kHz), with omega^2 from [`closed_form`]. The block's elasticity
/// shifts them by about k / k_block, the springs' stiffness over the block's own under the
/// same motions (250 N/m over ~1e9 N/m), and round-off puts eps x 5e8 on modes 5e8 below
/// the block's own, so 1e-6 is the tolerance; measured 9e-8 (1 and 2 ranks). Without the
/// moment term of the coupling (the reference moving as the top face's mean only, as if it
/// sat on the face), the closed form's x-rocking pair would be 160 and 17,919 rad^2/s^2
/// instead of 36.7 and 12,191.
fn coupled_block_modes(rt: &Runtime) -> Result<Vec<f64>, String> {
    let comm = rt.world();
    let model = deck("coupled_block.inp")?;
    if model.constraints.len() != 3 {
        return Err(format!(
            "{} constraints, expected 3",
            model.constraints.len()
        ));
    }
    let ops = model::assemble(comm, &model, MassRule::Exact).map_err(text)?;
    let t = ops.constraints.as_ref().ok_or("no transformation")?;
    let k = t.project(&ops.stiffness).map_err(text)?;
    let m = t.project(&ops.mass).map_err(text)?;
    let modes = real_modes(
        comm,
        &k,
        &m,
        &ModesOptions {
            band: ModeBand::Lowest { count: 6 },
            ..Default::default()
        },
    )
    .map_err(text)?;
    let ours: Vec<f64> = modes.modes.iter().map(|m| m.eigenvalue).collect();
    let exact = closed_form();
    for (i, (a, b)) in ours.iter().zip(&exact).enumerate() {
        let error = (a - b).abs() / b;
        if rt.world().rank() == 0 {
            println!(
                "mode {}: omega^2 {a:.12e}, closed form {b:.12e}, relative {error:.2e}",
                i + 1
            );
        }
        if error > 1e-6 {
            return Err(format!(
                "mode {}: omega^2 = {a}, the rigid block on springs has {b} (all: {ours:?} vs \
                 {exact:?})",
                i + 1
            ));
        }
    }
    Ok(ours)
}

/// A 1 N force along x at the reference node: the block tilts on its springs as a rigid
/// body loaded by the force at the reference point, so the reference moves by
/// F / k_x + F z_R^2 / k_rocking (0.004 + 0.05 m). Its force along z moves everything by F /
/// k_z. The coupling's forces on the top face add up to the load with no moment about the
/// reference (Abaqus's distribution). Tolerance 1e-6 as for the modes (the block's
/// elasticity); measured 6e-8 (without the moment term: 0.012 m instead of 0.054 m).
fn coupled_block_static(rt: &Runtime) -> Result<Vec<f64>, String> {
    let mut out = Vec::new();
    let (k_translation, k_rocking) = springs();
    for (axis, exact) in [
        (
            0,
            1.0 / k_translation + REFERENCE_HEIGHT.powi(2) / k_rocking,
        ),
        (2, 1.0 / k_translation),
    ] {
        let mut model = deck("coupled_block.inp")?;
        let reference = model
            .mesh
            .node_labels
            .iter()
            .position(|&l| l == 9001)
            .ok_or("no node 9001")?;
        model.forces.push((reference, axis, 1.0));
        let (solution, forces) = solve_static(rt, &model)?;
        let moved = solution.displacement[reference][axis];
        let error = (moved - exact).abs() / exact;
        if rt.world().rank() == 0 {
            println!("force along {axis}: reference moved {moved:.12e}, rigid block {exact:.12e}, relative {error:.1e}");
        }
        if error > 1e-6 {
            return Err(format!(
                "force along {axis}: the reference moved {moved}, the rigid block gives {exact}"
            ));
        }
        // The constraint's forces: on the reference, minus the load; on the face, the load
        // spread with no moment about the reference.
        let x_ref = model.mesh.nodes[reference];
        let mut resultant = [0.0; 3];
        let mut moment = [0.0; 3];
        for (n, f) in forces.iter().enumerate() {
            if n == reference {
                continue;
            }
            let x = model.mesh.nodes[n];
            let d = [x[0] - x_ref[0], x[1] - x_ref[1], x[2] - x_ref[2]];
            for k in 0..3 {
                resultant[k] += f[k];
            }
            moment[0] += d[1] * f[2] - d[2] * f[1];
            moment[1] += d[2] * f[0] - d[0] * f[2];
            moment[2] += d[0] * f[1] - d[1] * f[0];
        }
        // On the reference the residual is minus the load (nothing else acts there); on
        // the face, the load spread by the coupling (C^T r = 0: r_i = B_i^T F). K u of a
        // rigid motion of 54 mm cancels entries of some 1e10 N/m x 0.05 m: 5e-8 N of
        // round-off per node, so 1e-6 N for the sums.
        let mut load = [0.0; 3];
        load[axis] = 1.0;
        if rt.world().rank() == 0 {
            println!("force along {axis}: face forces {resultant:?}, moment about the reference {moment:?}");
        }
        for k in 0..3 {
            if (resultant[k] - load[k]).abs() > 1e-6
                || (forces[reference][k] + load[k]).abs() > 1e-12
            {
                return Err(format!(
                    "force along {axis}: the coupling's forces on the face add up to \
                     {resultant:?} and {:?} on the reference, not the load and minus it",
                    forces[reference]
                ));
            }
        }
        if moment.iter().any(|m| m.abs() > 1e-6 * REFERENCE_HEIGHT) {
            return Err(format!(
                "force along {axis}: the coupling's forces have a moment {moment:?} about the \
                 reference"
            ));
        }
        out.extend([moved, resultant[0], resultant[2], moment[1]]);
    }
    Ok(out)
}

// --- prescribed displacements ------------------------------------------------------------

const YOUNG: f64 = 210e9;
const POISSON: f64 = 0.3;

/// tests/data/prescribed_bar.inp: a 100 x 10 x 10 mm steel bar, x held at x = 0, y on its y
/// = 0 face and z on its z = 0 face, and x = 100 mm moved by d = 0.05 mm in its *STATIC
/// step. Uniaxial stress: u = d (x, -nu y, -nu z) / L exactly (quadratic tets reproduce a
/// linear field), and the reaction at the moved end is E A d / L = 10.5 kN. Tolerances:
/// round-off of a solve of condition ~1e6 (1e-9 of d and of the force); measured 3e-15 of d
/// and 1e-12 of the force.
fn prescribed_bar(rt: &Runtime) -> Result<Vec<f64>, String> {
    let model = deck("prescribed_bar.inp")?;
    let (length, area, d) = (0.1, 1e-4, 5e-5);
    let (solution, forces) = solve_static(rt, &model)?;
    let mut worst = 0.0f64;
    for (x, u) in model.mesh.nodes.iter().zip(&solution.displacement) {
        let exact = [
            d * x[0] / length,
            -POISSON * d * x[1] / length,
            -POISSON * d * x[2] / length,
        ];
        for k in 0..3 {
            worst = worst.max((u[k] - exact[k]).abs() / d);
        }
    }
    if worst > 1e-9 {
        return Err(format!(
            "the displacement is off the linear field by {worst} of d"
        ));
    }
    let end = &model.mesh.node_sets["X1"];
    let reaction: f64 = end.iter().map(|&n| forces[n][0]).sum();
    let exact = YOUNG * area * d / length;
    if ((reaction - exact) / exact).abs() > 1e-9 {
        return Err(format!(
            "reaction {reaction} N at the moved end, E A d / L = {exact} N"
        ));
    }
    if rt.world().rank() == 0 {
        println!(
            "bar: displacement off by {worst:.1e} of d; reaction {reaction:.9} N, E A d / L = \
             {exact} N"
        );
    }
    let tip = end[0];
    Ok(vec![
        reaction,
        solution.displacement[tip][0],
        worst.max(1e-300),
    ])
}

/// tests/data/prescribed_tube.inp: a 60 degree sector of a tube (r 20..30 mm, 10 mm high)
/// in a cylindrical *TRANSFORM about z: u_r = eps r on its inner and outer faces, u_theta =
/// 0 on its cut faces, u_z = 0 at the bottom, top free. The exact solution is the linear
/// field u = eps (x, y, 0) + (0, 0, w z), w = -2 lambda eps / (lambda + 2 mu) (sigma_zz = 0).
/// Tolerance 1e-9 of eps r as for the bar; measured 1.2e-14.
fn prescribed_tube(rt: &Runtime) -> Result<Vec<f64>, String> {
    let model = deck("prescribed_tube.inp")?;
    let eps = 1e-3;
    let lambda = YOUNG * POISSON / ((1.0 + POISSON) * (1.0 - 2.0 * POISSON));
    let mu = YOUNG / (2.0 * (1.0 + POISSON));
    let w = -2.0 * lambda * eps / (lambda + 2.0 * mu);
    let (solution, forces) = solve_static(rt, &model)?;
    let scale = eps * 0.03;
    let mut worst = 0.0f64;
    for (x, u) in model.mesh.nodes.iter().zip(&solution.displacement) {
        let exact = [eps * x[0], eps * x[1], w * x[2]];
        for k in 0..3 {
            worst = worst.max((u[k] - exact[k]).abs() / scale);
        }
    }
    if worst > 1e-9 {
        return Err(format!(
            "the displacement is off the linear field by {worst} of eps r_out"
        ));
    }
    // Every node's forces are the constraints' reactions: they balance (no load acts).
    let mut total = [0.0; 3];
    let mut largest = 0.0f64;
    for f in &forces {
        for k in 0..3 {
            total[k] += f[k];
            largest = largest.max(f[k].abs());
        }
    }
    if rt.world().rank() == 0 {
        println!("tube: displacement off by {worst:.1e}; reactions add up to {total:?}");
    }
    // Only supports along z act besides the constraints: the in-plane reactions balance.
    if total[0].abs().max(total[1].abs()) > 1e-9 * largest {
        return Err(format!(
            "the in-plane reactions add up to {total:?} (largest nodal one {largest})"
        ));
    }
    Ok(vec![
        worst.max(1e-300),
        largest,
        solution.displacement[0][0],
    ])
}

/// tests/data/pad_on_plate.inp with its 1 MPa on the pad's top replaced by a prescribed
/// 0.2 micrometre down (the top's x and y held as in the deck): contact, Newton and the
/// constraints together. The reaction at the pad's top (the constraint forces along z)
/// carries exactly what the contact carries (equilibrium of the pad: nothing else acts on
/// it along z), to the solve's tolerance (1e-8 of the force; measured 2e-15); the CEA of
/// C^T K_t C (frictionless: symmetric) finds the modes the real-mode solver finds.
fn pressed_pad(rt: &Runtime) -> Result<Vec<f64>, String> {
    let comm = rt.world();
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    let original = std::fs::read_to_string(data.join("pad_on_plate.inp")).map_err(text)?;
    let mesh = data.join("pad_on_plate_mesh.inp");
    let pressed = original
        .replace(
            "INPUT=pad_on_plate_mesh.inp",
            &format!("INPUT={}", mesh.display()),
        )
        .replace(
            "*DSLOAD\nPADTOPFACES, P, 1e6\n",
            "*BOUNDARY\nPADTOP, 3, 3, -2e-7\n",
        );
    let dir = std::env::temp_dir().join(format!(
        "squeal-pressed-pad-{}-{}",
        comm.size(),
        std::process::id()
    ));
    std::fs::create_dir_all(&dir).map_err(text)?;
    let path = dir.join(format!("pressed-{}.inp", comm.rank()));
    std::fs::write(&path, pressed).map_err(text)?;
    let model = source::read(&path).map_err(text)?;
    let _ = std::fs::remove_file(&path);
    let (solution, forces) = solve_static(rt, &model)?;
    let top = &model.mesh.node_sets["PADTOP"];
    let reaction: f64 = top.iter().map(|&n| forces[n][2]).sum();
    let contact: f64 = model
        .pairs
        .iter()
        .zip(&solution.contact)
        .map(|(pair, states)| squeal::contact::summarize_states(pair, states).normal_force)
        .sum();
    if rt.world().rank() == 0 {
        println!("pressed pad: reaction {reaction:.12e} N, contact {contact:.12e} N");
    }
    // The constraint pushes the pad down (negative z) and the plate pushes back.
    if contact <= 0.0 || ((reaction + contact) / contact).abs() > 1e-8 {
        return Err(format!(
            "the prescribed displacement's reaction {reaction} N does not balance the contact \
             force {contact} N"
        ));
    }
    // The CEA sees the constraints: at mu 0 it finds the real modes of C^T K_t C and
    // C^T M C (a symmetric pencil).
    let ops = model::assemble(comm, &model, MassRule::Exact).map_err(text)?;
    let t = ops.constraints.as_ref().ok_or("no transformation")?;
    let kt = statics::tangent(
        comm,
        &ops.stiffness,
        &ops.dofs,
        &model.pairs,
        &solution.slip_before,
        &solution.displacement,
    )
    .map_err(text)?;
    let (k, m) = (
        t.project(&kt).map_err(text)?,
        t.project(&ops.mass).map_err(text)?,
    );
    let fmax = 60_000.0;
    let cea = squeal::analysis::cea::solve(
        comm,
        &k,
        &m,
        None,
        &squeal::analysis::cea::CeaOptions {
            max_frequency_hz: fmax,
            ..Default::default()
        },
    )
    .map_err(text)?;
    let real = real_modes(
        comm,
        &k,
        &m,
        &ModesOptions {
            band: ModeBand::Below {
                max_frequency_hz: fmax,
            },
            ..Default::default()
        },
    )
    .map_err(text)?;
    let a: Vec<f64> = cea.modes.iter().map(|m| m.frequency_hz).collect();
    let b: Vec<f64> = real.modes.iter().map(|m| m.frequency_hz).collect();
    let worst = a
        .iter()
        .zip(&b)
        .map(|(x, y)| (x - y).abs() / y)
        .fold(0.0f64, f64::max);
    if rt.world().rank() == 0 {
        println!(
            "pressed pad: {} CEA modes, off the real modes by {worst:.1e}",
            a.len()
        );
    }
    if a.len() != b.len() || worst > 1e-8 {
        return Err(format!("CEA {a:?} vs real modes {b:?}"));
    }
    let mut out = vec![reaction, contact];
    out.extend(a);
    Ok(out)
}

// --- tied pads -----------------------------------------------------------------------------

/// tests/data/tied_pads_clamped.inp (two pads tied by `*TIE` to a plate held at its end,
/// non-matching meshes) with forces on the pads' top nodes: pad 1 pushed down and along x,
/// pad 2 along y. A pad is held by nothing but its tie, so the forces the tie applies on
/// its nodes must cancel its load, force and moment (its elastic forces sum to zero for
/// any displacement: K annihilates rigid motions), and the plate's master nodes must receive
/// the opposite. Asked 1e-8 of the load (the static's linear solve leaves ~1e-12).
fn tied_pads_loaded(rt: &Runtime) -> Result<Vec<f64>, String> {
    let mut model = deck("tied_pads_clamped.inp")?;
    let labels = &model.mesh.node_labels;
    let pad_of = |n: usize| match labels[n] {
        1000..=1999 => Some(0),
        2000..=2999 => Some(1),
        _ => None,
    };
    let loads = [[0.5, 0.0, -1.0], [0.0, 1.0, 0.0]];
    let top = model
        .mesh
        .nodes
        .iter()
        .enumerate()
        .filter(|(_, x)| (x[2] - 0.010).abs() < 1e-12)
        .map(|(n, _)| n)
        .collect::<Vec<_>>();
    let mut applied = [[0.0; 6]; 2];
    for &n in &top {
        let Some(p) = pad_of(n) else { continue };
        let x = model.mesh.nodes[n];
        let f = loads[p];
        model
            .forces
            .extend(f.iter().enumerate().map(|(c, &fc)| (n, c, fc)));
        let m = squeal::vector3::cross(x, f);
        for c in 0..3 {
            applied[p][c] += f[c];
            applied[p][3 + c] += m[c];
        }
    }
    let (_, forces) = solve_static(rt, &model)?;
    // Net force and moment (about the origin) of the constraint forces on each pad, and on
    // the plate's top-face nodes.
    let mut on_pad = [[0.0; 6]; 2];
    let mut on_plate = [0.0; 6];
    for (n, f) in forces.iter().enumerate() {
        let x = model.mesh.nodes[n];
        let m = squeal::vector3::cross(x, *f);
        let sums = match pad_of(n) {
            Some(p) => &mut on_pad[p],
            None if (x[2] - 0.005).abs() < 1e-12 => &mut on_plate,
            None => continue,
        };
        for c in 0..3 {
            sums[c] += f[c];
            sums[3 + c] += m[c];
        }
    }
    // Loads of about 1 N per node, moments of about 0.06 N m per node.
    let scale = top.len() as f64;
    let mut worst: f64 = 0.0;
    for p in 0..2 {
        for k in 0..6 {
            let gap = on_pad[p][k] + applied[p][k];
            let opposite = on_plate[k] - applied[0][k] - applied[1][k];
            worst = worst.max(gap.abs().max(opposite.abs()) / scale);
            if gap.abs() > 1e-8 * scale || opposite.abs() > 1e-8 * scale {
                return Err(format!(
                    "pad {}: the tie's resultant {:?} does not cancel the load {:?}, or the \
                     plate's {:?} is not their opposite (component {k})",
                    p + 1,
                    on_pad[p],
                    applied[p],
                    on_plate
                ));
            }
        }
    }
    if rt.world().rank() == 0 {
        println!(
            "tied pads: tie force on pad 1 {:?} N, pad 2 {:?} N, plate {:?} N; largest \
             imbalance {worst:.1e} of the load",
            &on_pad[0][..3],
            &on_pad[1][..3],
            &on_plate[..3]
        );
    }
    Ok(on_pad.iter().flatten().copied().collect())
}
