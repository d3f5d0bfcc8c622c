//! The built-in floating-caliper study (`Study::builtin("tiny-caliper")`): its static
//! equilibrium carries the hydraulic force from the piston through both pads to the disc and
//! back through the caliper, on 1 and 2 ranks (see `common/harness.rs`).
//!
//! The pads' abutment clips (radial springs on `pad_*_guides`) are part of the study: without
//! them, once the pads slip on the piston and the fingers, nothing holds them radially, and
//! the solve must fail cleanly.

use crate::common;

use common::harness::Check;
use squeal::analysis::cea::{self, CeaOptions};
use squeal::analysis::restraint;
use squeal::analysis::statics::{self, StaticOptions, StaticProblem};
use squeal::contact;
use squeal::fem::element::MassRule;
use squeal::fem::loads::pressure_resultant;
use squeal::model::{self, Model, Operators};
use squeal::petsc::Runtime;
use squeal::study::config::Study;

pub const CHECKS: &[Check] = &[
    Check {
        name: "floating_caliper_static_balance_and_cea",
        run: balance,
        ranks: &[1, 2],
        // The 1e-8: Newton stops at |R| < 1e-10 |R0|, the forces and frequencies
        // then agree to ~1e-10 of the hydraulic force.
        agreement: 1e-8,
    },
    Check {
        name: "floating_caliper_restraint_and_a_removed_guide_pin",
        run: restraint_check,
        ranks: &[1, 2],
        agreement: 0.0,
    },
    Check {
        name: "floating_caliper_without_guides_fails_cleanly",
        run: free_pads,
        ranks: &[1, 2],
        agreement: 0.0,
    },
];

fn e<E: std::fmt::Display>(err: E) -> String {
    err.to_string()
}

/// The static solution of the tiny floating-caliper study, pads guided radially or not.
type Solved<'rt> = (
    Model,
    Operators<'rt>,
    Result<statics::StaticSolution, String>,
);

fn solve(rt: &Runtime, guided: bool) -> Result<Solved<'_>, String> {
    let comm = rt.world();
    let mut study = Study::builtin("tiny-caliper");
    if !guided {
        study.springs.retain(|s| !s.set.ends_with("_guides"));
    }
    let model = Model::from_spec(&study.model_spec()).map_err(e)?;
    let operators = model::assemble(comm, &model, MassRule::Exact).map_err(e)?;
    let problem = StaticProblem {
        dofs: &operators.dofs,
        stiffness: &operators.stiffness,
        load: &operators.load,
        pairs: &model.pairs,
        slip: &contact::SlipHistory::default(),
        bodies: &restraint::bodies(&model.mesh),
        constraints: None,
    };
    // Unguided, every cut-back and the fallback line search fail alike, and so does every
    // Newton iteration past the first few once the pads slip: one increment of 12 iterations
    // shows it (the defaults took 46 s per rank count to say the same).
    let options = if guided {
        StaticOptions::default()
    } else {
        let mut o = StaticOptions {
            max_cutbacks: 0,
            fallback_line_search: None,
            ..StaticOptions::default()
        };
        o.newton.max_iterations = 12;
        o
    };
    let solution = statics::solve(comm, &problem, None, &options).map_err(e);
    Ok((model, operators, solution))
}

/// Hydraulic force on the piston = piston/pad normal force + the seal's axial force on the
/// piston; caliper/pad normal force = the same hydraulic force less the pins' and the
/// seal's axial forces on the caliper; each pad in balance under the disc, the piston or the
/// fingers, the bracket abutments and the clips (at mu = 0.5, the study's).
fn balance(rt: &Runtime) -> Result<Vec<f64>, String> {
    let (model, operators, solution) = solve(rt, true)?;
    let solution = solution?;
    let u = &solution.displacement;
    let force = |name: &str| -> Result<contact::PairSummary, String> {
        let k = model
            .pairs
            .iter()
            .position(|p| p.settings.name == name)
            .ok_or(format!("no pair {name}"))?;
        Ok(contact::summarize_states(
            &model.pairs[k],
            &solution.contact[k],
        ))
    };
    let mesh = &model.mesh;
    let hydraulic = |surface: &str| {
        let p = model
            .pressures
            .iter()
            .find(|p| p.name == surface)
            .expect("pressure");
        pressure_resultant(mesh, &p.faces, p.value)[2]
    };
    let on_piston = hydraulic("piston_bottom");
    let on_caliper = hydraulic("caliper_bore_bottom");
    // The z force of the links starting on a node set: on that set's body.
    let link_force = |set: &str| -> f64 {
        let nodes = &mesh.node_sets[set];
        model
            .links
            .iter()
            .filter(|l| nodes.binary_search(&l.nodes[0]).is_ok())
            .map(|l| {
                let [a, b] = l.nodes;
                let d = l.direction;
                let stretch: f64 = (0..3).map(|c| d[c] * (u[a][c] - u[b][c])).sum();
                -l.stiffness * stretch * d[2]
            })
            .sum()
    };
    let seal_on_piston = link_force("piston_outer");
    let pins_on_caliper = link_force("caliper_pins");
    let piston_pad = force("piston/pad")?;
    let caliper_pad = force("caliper/pad")?;
    let disc_in = force("disc/pad inboard")?;
    let disc_out = force("disc/pad outboard")?;
    // Forces on the slaves (the pads): the piston pushes the inboard pad to -z, the
    // fingers the outboard one to +z.
    let (n_piston, n_fingers) = (-piston_pad.force_on_slave[2], caliper_pad.force_on_slave[2]);
    let applied = -on_piston;
    eprintln!(
        "hydraulic force {applied:.6} N (bore bottom {on_caliper:.6} N); piston/pad {n_piston:.6} N \
         ({} of {} points closed), caliper/pad {n_fingers:.6} N ({} of {}); seal on piston \
         {seal_on_piston:.6} N, pins on caliper {pins_on_caliper:.6} N; disc/pad inboard {:.6} N, \
         outboard {:.6} N",
        piston_pad.closed,
        piston_pad.points,
        caliper_pad.closed,
        caliper_pad.points,
        disc_in.normal_force,
        disc_out.normal_force
    );
    for name in [
        "bracket/pad inboard leading",
        "bracket/pad inboard trailing",
        "bracket/pad outboard leading",
        "bracket/pad outboard trailing",
    ] {
        let s = force(name)?;
        eprintln!(
            "{name}: {:.6} N, {} of {} points closed",
            s.normal_force, s.closed, s.points
        );
    }
    let close = |what: &str, a: f64, b: f64, tol: f64| {
        if (a - b).abs() <= tol * applied {
            Ok(())
        } else {
            Err(format!("{what}: {a} vs {b}"))
        }
    };
    // Equal and opposite hydraulic forces, to round-off.
    close("bore bottom vs piston bottom", on_caliper, applied, 1e-12)?;
    // Newton stops at |R| < 1e-10 |R0|: the balances hold to about that.
    close("piston", n_piston + seal_on_piston, applied, 1e-8)?;
    // The caliper: bore bottom (+z) = fingers (reaction -z) - pins - seal (its reaction).
    close(
        "caliper",
        n_fingers - pins_on_caliper + seal_on_piston,
        applied,
        1e-8,
    )?;
    // (Along z a pad also feels its abutments' friction, 0.15 of their normal force: its
    // balance is checked whole below.)
    // The springs take little: the piston and the fingers carry the hydraulic force.
    close("piston carries the load", n_piston, applied, 1e-2)?;
    close("fingers carry the load", n_fingers, applied, 1e-2)?;
    // Each pad is in balance as a whole, in every direction: the disc's normal force and
    // drag, the piston or the fingers (normal force and Coulomb friction), the bracket
    // abutments and the abutment clips. The drag the piston's or fingers' friction does not
    // take goes into the trailing abutment.
    for (side, pusher) in [("inboard", &piston_pad), ("outboard", &caliper_pad)] {
        let disc = force(&format!("disc/pad {side}"))?;
        let mut total = [0.0; 3];
        let mut abutments = [0.0; 3];
        for end in ["leading", "trailing"] {
            let s = force(&format!("bracket/pad {side} {end}"))?;
            (0..3).for_each(|c| abutments[c] += s.force_on_slave[c]);
        }
        let clips = &mesh.node_sets[&format!("pad_{side}_guides")];
        let mut springs = [0.0; 3];
        for g in model
            .springs
            .iter()
            .filter(|g| clips.binary_search(&g.node).is_ok())
        {
            let d = g.direction;
            let stretch: f64 = (0..3).map(|c| d[c] * u[g.node][c]).sum();
            (0..3).for_each(|c| springs[c] -= g.stiffness * stretch * d[c]);
        }
        for c in 0..3 {
            total[c] =
                disc.force_on_slave[c] + pusher.force_on_slave[c] + abutments[c] + springs[c];
        }
        let drag = disc.friction_force;
        let norm = |v: [f64; 3]| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        eprintln!(
            "{side} pad: disc drag {:.3} N, {} friction {:.3} N ({} stick, {} slip), \
             abutments {:.3} N, clips {:.3} N, braking torque {:.3} N m at radius {:.4} m; \
             unbalanced {:.2e} N",
            norm(drag),
            if side == "inboard" {
                "piston"
            } else {
                "finger"
            },
            norm(pusher.friction_force),
            pusher.stick,
            pusher.slip,
            norm(abutments),
            norm(springs),
            disc.braking_torque,
            disc.effective_radius,
            norm(total)
        );
        if norm(total) > 1e-8 * applied {
            return Err(format!("{side} pad: unbalanced force {total:?} N"));
        }
        // The friction acts, on average, between the pad's inner and outer radius (the
        // torque is the moment of mu N at the effective radius).
        if !(0.090..=0.135).contains(&disc.effective_radius) || disc.braking_torque == 0.0 {
            return Err(format!(
                "{side}: braking torque {} N m at effective radius {} m",
                disc.braking_torque, disc.effective_radius
            ));
        }
    }
    // The CEA at this equilibrium: every mode up to 3 kHz, the same on 1 and 2 ranks (its
    // frequencies, and the real parts of the unstable ones; a stable mode's real part is
    // round-off of the eigensolver).
    let comm = rt.world();
    let kt = statics::tangent(
        comm,
        &operators.stiffness,
        &operators.dofs,
        &model.pairs,
        &solution.slip_before,
        u,
    )
    .map_err(e)?;
    let modes = cea::undamped(
        comm,
        &kt,
        &operators.mass,
        &CeaOptions {
            max_frequency_hz: 3000.0,
            ..Default::default()
        },
    )
    .map_err(e)?
    .modes;
    let unstable: Vec<f64> = modes
        .iter()
        .filter(|m| m.unstable)
        .map(|m| m.real_part)
        .collect();
    eprintln!(
        "CEA to 3 kHz: {} modes, unstable real parts {unstable:?}",
        modes.len()
    );
    let mut out = vec![
        applied,
        n_piston,
        n_fingers,
        disc_in.normal_force,
        disc_out.normal_force,
        seal_on_piston,
        pins_on_caliper,
        modes.len() as f64,
    ];
    out.extend(modes.iter().map(|m| m.frequency_hz));
    out.extend(unstable);
    Ok(out)
}

/// Without the abutment clips the pads are held radially only by friction: the static solve
/// starts (the zero-gap contacts stick at the start, so the restraint check passes), and at
/// mu = 0.5 the disc's drag makes the pads slip on the piston and the fingers, where nothing
/// then holds them radially: the solve must fail with a message on every rank, not hang or
/// return an equilibrium.
fn free_pads(rt: &Runtime) -> Result<Vec<f64>, String> {
    let (_, _, solution) = solve(rt, false)?;
    match solution {
        Ok(_) => Err("the unguided pads were held".into()),
        Err(message) => {
            eprintln!("without guides: {message}");
            if message.contains("did not converge") || message.contains("singular") {
                Ok(vec![])
            } else {
                Err(format!("unexpected failure: {message}"))
            }
        }
    }
}

/// The restraint check on the floating-caliper brake, at rest: every body held (with and
/// without friction: pins, seal, clips, supports and normal contact hold it all). With the
/// guide pins removed, the caliper is held only by the stick of its fingers: the check
/// without friction names it, with the piston its seal ties it to, free to slide across
/// the disc axis (x and y) -- and nothing else.
fn restraint_check(rt: &Runtime) -> Result<Vec<f64>, String> {
    let comm = rt.world();
    let mut counts = Vec::new();
    // The third case: no pins and a piston 100 times softer than steel, so that its share of
    // the caliper's free motion, read off the stiffness-scaled null vectors, would be ~1e-4
    // (the rubber-on-steel case): it must still be named as moving with the caliper.
    for (pins, soft_piston) in [(true, false), (false, false), (false, true)] {
        let mut study = Study::builtin("tiny-caliper");
        if !pins {
            study.links.retain(|l| l.name != "guide pins");
        }
        if soft_piston {
            study.materials.push(squeal::model::spec::MaterialSpec {
                part: "piston".into(),
                young: 2.1e9,
                poisson: 0.3,
                density: 7850.0,
            });
        }
        let model = Model::from_spec(&study.model_spec()).map_err(e)?;
        let Operators {
            dofs,
            stiffness: k,
            load,
            ..
        } = model::assemble(comm, &model, MassRule::Exact).map_err(e)?;
        let bodies = restraint::bodies(&model.mesh);
        let names: Vec<String> = bodies.iter().map(|b| b.name()).collect();
        if bodies.len() != 6 {
            return Err(format!("expected 6 bodies, found {names:?}"));
        }
        let problem = StaticProblem {
            dofs: &dofs,
            stiffness: &k,
            load: &load,
            pairs: &model.pairs,
            slip: &contact::SlipHistory::default(),
            bodies: &bodies,
            constraints: None,
        };
        let rest = vec![[0.0; 3]; model.mesh.nodes.len()];
        let slip = contact::SlipHistory::default();
        let j = statics::tangent(comm, &k, &dofs, &model.pairs, &slip, &rest).map_err(e)?;
        let with_friction = restraint::free_bodies(comm, &j, &dofs, &bodies).map_err(e)?;
        if !with_friction.is_empty() {
            return Err(format!(
                "free with friction (pins {pins}): {with_friction:?}"
            ));
        }
        let free = statics::held_only_by_friction(comm, &problem, &rest).map_err(e)?;
        for f in &free {
            eprintln!("pins {pins}: {f}");
        }
        if pins {
            if !free.is_empty() {
                return Err(format!("held only by friction with the pins: {free:?}"));
            }
        } else {
            let [one] = &free[..] else {
                return Err(format!("expected one free group, found {free:?}"));
            };
            let mut moving = one.with.clone();
            moving.push(one.body.clone());
            moving.sort();
            if moving != ["caliper", "piston"] {
                return Err(format!("expected the caliper with the piston: {one}"));
            }
            // Two free motions, translations across the axis: no rotation, nothing along z.
            let inside =
                |axis: usize| -> f64 { one.motions.iter().map(|m| m[axis] * m[axis]).sum() };
            let text = one.to_string();
            if one.motions.len() != 2 || inside(0) < 0.99 || inside(1) < 0.99 {
                return Err(format!("expected x and y translations: {text}"));
            }
            if !text.contains("'piston'") || !text.contains("translation along x") {
                return Err(format!("message does not name the motion: {text}"));
            }
        }
        counts.push(free.len() as f64);
    }
    Ok(counts)
}
