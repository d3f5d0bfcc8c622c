//! Contact, sliding equilibrium and CEA of the full model, checked against conservation laws
//! and closed forms, on 1 and 2 ranks (see `common/harness.rs`).

use crate::common;

use common::harness::Check;
use common::meshes::merge;
use squeal::analysis::cea::{self, CeaOptions};
use squeal::analysis::restraint;
use squeal::analysis::statics::{self, StaticOptions, StaticProblem};
use squeal::contact::{self, PairSettings, SearchOptions, SlidingDirection};
use squeal::fem::element::MassRule;
use squeal::fem::springs::{add_ground_springs, GroundSpring};
use squeal::fem::{assemble, DofMap, StructureOptions, Support};
use squeal::mesh::{block::block, Material};
use squeal::model::{self, Model, Operators};
use squeal::petsc::Runtime;
use squeal::study::config::Study;

pub const CHECKS: &[Check] = &[
    Check {
        name: "block_on_block_balance_and_sliding_friction",
        run: block_on_block,
        ranks: &[1, 2],
        agreement: 1e-8,
    },
    Check {
        name: "brake_cea_same_on_one_and_two_ranks",
        run: brake_cea,
        ranks: &[1, 2],
        agreement: 1e-8,
    },
    Check {
        name: "frictionless_contact_gives_a_symmetric_tangent_and_real_eigenvalues",
        run: frictionless,
        ranks: &[1, 2],
        agreement: 1e-8,
    },
    Check {
        name: "unheld_pad_fails_cleanly_on_every_rank",
        run: unheld_pad,
        ranks: &[1, 2],
        agreement: 0.0,
    },
];

fn e<E: std::fmt::Display>(err: E) -> String {
    err.to_string()
}

/// A steel block (0.1 x 0.06 x 0.02) pressed by 1 MPa onto a larger base with a different
/// mesh, sliding along x with mu = 0.3: the sum of contact normal forces equals the applied
/// resultant to solver tolerance, and the friction force is exactly mu N (every closed point
/// slides). The contact pressure's spread is reported.
fn block_on_block(rt: &Runtime) -> Result<Vec<f64>, String> {
    let comm = rt.world();
    let steel = |name: &str| Material {
        name: name.into(),
        young: 210e9,
        poisson: 0.3,
        density: 7850.0,
    };
    let base = block(
        [-0.02, -0.02, -0.02],
        [0.14, 0.10, 0.02],
        [7, 5, 1],
        steel("base"),
    )
    .map_err(|e| e.to_string())?;
    let top = block([0.0, 0.0, 0.0], [0.1, 0.06, 0.02], [6, 4, 1], steel("top"))
        .map_err(|e| e.to_string())?;
    let mesh = merge(&base, "base_", &top, "top_");
    let settings = PairSettings {
        name: "top/base".into(),
        friction: 0.3,
        penalty: None,
        separation: true,
        sliding: SlidingDirection::Fixed([1.0, 0.0, 0.0]),
        law: squeal::contact::FrictionLaw::SteadySliding,
        calculix: None,
    };
    let pair = contact::node_to_surface(
        &mesh,
        &mesh.surfaces["top_z0"],
        &mesh.surfaces["base_z1"],
        settings,
        &SearchOptions::default(),
    )
    .map_err(e)?;
    let pairs = vec![pair];
    // The base is fixed at its bottom; the top block is held in x and y by soft springs on
    // its sides (the friction pushes it along x), in z only by the contact.
    let supports = vec![Support {
        name: "base_z0".into(),
        nodes: mesh.node_sets["base_z0"].clone(),
        components: [true; 3],
    }];
    let mut springs = Vec::new();
    for (set, d) in [("top_x1", [1.0, 0.0, 0.0]), ("top_y0", [0.0, 1.0, 0.0])] {
        let nodes = &mesh.node_sets[set];
        for &n in nodes {
            springs.push(GroundSpring {
                node: n,
                direction: d,
                stiffness: 1e9 / nodes.len() as f64,
            });
        }
    }
    let dofs = DofMap::new(mesh.nodes.len(), 0, &supports, comm.size(), comm.rank())
        .map_err(|e| e.to_string())?;
    let groups = squeal::contact::contact_groups(&pairs);
    let pattern = assemble::pattern(
        &dofs,
        mesh.elements
            .iter()
            .map(|c| &c[..])
            .chain(groups.iter().map(|g| &g[..])),
    );
    let (mut k, _m) =
        assemble::stiffness_and_mass(comm, &mesh, &dofs, &pattern, StructureOptions::default())
            .map_err(e)?;
    add_ground_springs(&mut k, &dofs, &springs).map_err(e)?;
    let pressure = 1e6;
    let faces: Vec<_> = mesh.surfaces["top_z1"]
        .faces
        .iter()
        .map(|f| (*f, pressure))
        .collect();
    let load = assemble::load_vector(comm, &mesh, &dofs, &faces, &[]).map_err(e)?;
    let problem = StaticProblem {
        dofs: &dofs,
        stiffness: &k,
        load: &load,
        pairs: &pairs,
        slip: &squeal::contact::SlipHistory::default(),
        bodies: &restraint::bodies(&mesh),
        constraints: None,
    };
    let solution = statics::solve(comm, &problem, None, &StaticOptions::default()).map_err(e)?;
    let summary = contact::summarize(&pairs[0], &[], &solution.displacement).map_err(e)?;
    let applied = pressure * 0.1 * 0.06;
    // Newton stops at |R| < 1e-10 |R0| (|R0| ~ the load): the balance holds to that.
    let balance = (summary.normal_force - applied).abs() / applied;
    if balance > 1e-8 {
        return Err(format!(
            "sum of normal forces {} vs applied {applied}",
            summary.normal_force
        ));
    }
    let friction = summary.friction_force;
    let ratio = friction[0] / (0.3 * summary.normal_force);
    if (ratio - 1.0).abs() > 1e-12 || friction[1].abs() > 1e-12 * summary.normal_force {
        return Err(format!(
            "friction {friction:?} vs mu N = {}",
            0.3 * summary.normal_force
        ));
    }
    let p = summary.pressure.ok_or("no closed point")?;
    eprintln!(
        "block on block: {} of {} points closed, pressure min {:.4e} mean {:.4e} max {:.4e} Pa (applied {pressure:.1e}), balance {balance:.1e}",
        summary.closed, summary.points, p.min, p.mean, p.max
    );
    if summary.closed != summary.points {
        return Err(format!(
            "{} of {} points closed",
            summary.closed, summary.points
        ));
    }
    Ok(vec![summary.normal_force, friction[0], p.min, p.max])
}

/// The tiny built-in brake at mu = 0.5: the eigenvalues of the CEA about the equilibrium.
fn brake_setup(mu: f64) -> Study {
    let mut study = Study::builtin("tiny");
    study.analysis.friction = vec![mu];
    for c in &mut study.contacts {
        c.friction = mu;
    }
    study
}

fn brake_modes(rt: &Runtime, mu: f64, symmetric_check: bool) -> Result<Vec<f64>, String> {
    let comm = rt.world();
    let study = brake_setup(mu);
    let model = Model::from_spec(&study.model_spec()).map_err(e)?;
    let Operators {
        dofs,
        stiffness: k,
        mass: m,
        load,
        ..
    } = model::assemble(comm, &model, MassRule::Exact).map_err(e)?;
    let problem = StaticProblem {
        dofs: &dofs,
        stiffness: &k,
        load: &load,
        pairs: &model.pairs,
        slip: &squeal::contact::SlipHistory::default(),
        bodies: &restraint::bodies(&model.mesh),
        constraints: None,
    };
    let solution = statics::solve(comm, &problem, None, &StaticOptions::default()).map_err(e)?;
    let kt = statics::tangent(
        comm,
        &k,
        &dofs,
        &model.pairs,
        &solution.slip_before,
        &solution.displacement,
    )
    .map_err(e)?;
    if symmetric_check {
        let norm = kt.norm_frobenius().map_err(e)?;
        if !kt.is_symmetric(1e-12 * norm).map_err(e)? {
            return Err("frictionless tangent is not symmetric".into());
        }
    }
    let result = cea::undamped(
        comm,
        &kt,
        &m,
        &CeaOptions {
            max_frequency_hz: 6000.0,
            ..Default::default()
        },
    )
    .map_err(e)?;
    let mut out = Vec::new();
    for mode in &result.modes {
        if symmetric_check {
            // K_t and M symmetric, M definite: omega^2 real, lambda on the imaginary axis;
            // a non-symmetric solver leaves round-off of order 1e-12 |lambda|.
            if mode.real_part.abs() > 1e-8 * mode.lambda.norm() || mode.unstable {
                return Err(format!("frictionless mode with real part: {mode:?}"));
            }
        }
        out.push(mode.frequency_hz);
        out.push(mode.real_part);
    }
    Ok(out)
}

fn brake_cea(rt: &Runtime) -> Result<Vec<f64>, String> {
    let out = brake_modes(rt, 0.5, false)?;
    // The real parts are compared too: the unstable ones are far from round-off.
    Ok(out)
}

/// Without friction the tangent is symmetric and every eigenvalue real: friction alone
/// couples modes into flutter.
fn frictionless(rt: &Runtime) -> Result<Vec<f64>, String> {
    let out = brake_modes(rt, 0.0, true)?;
    // Only frequencies are compared between rank counts (real parts are round-off).
    Ok(out.iter().step_by(2).copied().collect())
}

/// Pads pressed without abutments or guides are free to slide: the tangent is singular. The
/// static solve must fail with a message naming each pad and its free motion on every rank,
/// not hang or crash.
fn unheld_pad(rt: &Runtime) -> Result<Vec<f64>, String> {
    let comm = rt.world();
    let mut study = brake_setup(0.5);
    study.springs.clear();
    let model = Model::from_spec(&study.model_spec()).map_err(e)?;
    let Operators {
        dofs,
        stiffness: k,
        load,
        ..
    } = model::assemble(comm, &model, MassRule::Exact).map_err(e)?;
    let problem = StaticProblem {
        dofs: &dofs,
        stiffness: &k,
        load: &load,
        pairs: &model.pairs,
        slip: &squeal::contact::SlipHistory::default(),
        bodies: &restraint::bodies(&model.mesh),
        constraints: None,
    };
    let options = StaticOptions {
        max_cutbacks: 1,
        ..Default::default()
    };
    match statics::solve(comm, &problem, None, &options) {
        Ok(_) => Err("an unheld pad reached an equilibrium".into()),
        Err(err) => {
            let text = err.to_string();
            eprintln!("unheld pad: {text}");
            // Named before any factorisation: each pad (with its backplate) slides radially.
            let named = ["inboard", "outboard"]
                .iter()
                .all(|side| text.contains(&format!("pad_{side}")));
            if text.contains("singular") && text.contains("is free: translation along") && named {
                Ok(vec![])
            } else {
                Err(format!("unexpected error: {text}"))
            }
        }
    }
}
