//! How much the full model's modes depend on the edge of its disc/pad contact zone: the
//! modes about the sliding equilibrium, then again with the r closed points of smallest
//! normal force opened, and with the r open points of smallest gap closed (r = 1, 2, 4, 8,
//! 16), nothing else changed. Run it with
//!
//!     cargo run --release --example contact_edge -- [PRESET] [MU] [FMAX]
//!     mpirun -n 2 target/release/examples/contact_edge small-caliper 0 3000
//!
//! (defaults: small-caliper, mu = 0, 3 kHz).
//!
//! Why. A penalty contact's tangent holds k_n a_i on a closed node whatever its force, and
//! nothing on an open one, so a node at the edge of the contact zone with a force of a
//! newton or two holds the pad as firmly as one in the middle. A mode whose frequency moves
//! by more than a reduced interface's error when one such node changes state cannot be
//! matched by any interface to better than that: the full model's own mesh decides it
//! (issue 29: small-caliper's 2272.9 Hz pad mode).
//!
//! How: [`squeal::analysis::contact_edge::moved_edge`] (the points' slave nodes moved along
//! the normal until their gaps change sign, in the displacement the tangent is taken at
//! alone), which `--contact-edge-points` uses at every point of a sweep.
//!
//! What it checks (at mu = 0, where the tangent is symmetric): closing r points adds r
//! rank-one stiffnesses, so the eigenvalues omega_i^2 interlace, omega_i^2 <= omega'_i^2 <=
//! omega_{i+r}^2, and opening r points the other way, omega_{i-r}^2 <= omega'_i^2 <=
//! omega_i^2 (Weyl). The contact tangent's geometric part (the force times the rotation of
//! the master face's normal, about p / h, a few 1e3 N/m here, against k_n a_i of 1e8 and
//! more) is not rank-one; 1e-4 of omega_i^2 covers it. It exits with failure otherwise.

use squeal::analysis::cea::{self, CeaOptions, ComplexMode};
use squeal::analysis::contact_edge::{moved_edge, EdgeMove};
use squeal::analysis::restraint;
use squeal::analysis::statics::{self, StaticOptions, StaticProblem};
use squeal::contact::SlipHistory;
use squeal::fem::element::MassRule;
use squeal::model::{self, Model, Operators};
use squeal::petsc::{Runtime, RuntimeOptions};
use squeal::study::config::Study;
use std::process::ExitCode;

/// Interlacing holds to this fraction of omega_i^2 (the geometric part; see the module doc).
const INTERLACING: f64 = 1e-4;

fn omega2(m: &ComplexMode) -> f64 {
    (2.0 * std::f64::consts::PI * m.frequency_hz).powi(2)
}

fn run(rt: &Runtime) -> Result<Vec<String>, String> {
    let comm = rt.world();
    let root = comm.rank() == 0;
    let args: Vec<String> = std::env::args().skip(1).collect();
    let preset = args.first().map_or("small-caliper", String::as_str);
    let mu: f64 = match args.get(1) {
        Some(m) => m.parse().map_err(|_| format!("MU: a number, got {m}"))?,
        None => 0.0,
    };
    let fmax: f64 = match args.get(2) {
        Some(f) => f
            .parse()
            .map_err(|_| format!("FMAX: a frequency, got {f}"))?,
        None => 3000.0,
    };
    let mut study = Study::builtin(preset);
    for c in study.contacts.iter_mut().filter(|c| c.sweep) {
        c.friction = mu;
    }
    let model = Model::from_spec(&study.model_spec()).map_err(|e| e.to_string())?;
    let Operators {
        dofs,
        stiffness,
        mass,
        load,
        ..
    } = model::assemble(comm, &model, MassRule::Exact).map_err(|e| e.to_string())?;
    let bodies = restraint::bodies(&model.mesh);
    let problem = StaticProblem {
        dofs: &dofs,
        stiffness: &stiffness,
        load: &load,
        pairs: &model.pairs,
        slip: &SlipHistory::default(),
        bodies: &bodies,
        constraints: None,
    };
    let eq = statics::solve(comm, &problem, None, &StaticOptions::default())
        .map_err(|e| e.to_string())?;
    let swept_states = || {
        model
            .pairs
            .iter()
            .zip(&eq.contact)
            .zip(&model.swept)
            .filter(|&(_, &swept)| swept)
            .flat_map(|((_, states), _)| states.iter())
    };
    let closed = swept_states().filter(|s| s.closed).count();
    let weakest = swept_states()
        .filter(|s| s.closed)
        .map(|s| s.normal_force)
        .fold(f64::INFINITY, f64::min);
    let nearest = swept_states()
        .filter(|s| !s.closed)
        .map(|s| s.gap)
        .fold(f64::INFINITY, f64::min);
    let total = swept_states().count();
    let options = CeaOptions {
        max_frequency_hz: fmax,
        expected_rigid_modes: Some(0),
        ..Default::default()
    };
    // The modes with r points moved across the edge, and how many moved.
    let modes_with = |r: usize, direction: EdgeMove| -> Result<(Vec<ComplexMode>, usize), String> {
        let (u, moved) = moved_edge(
            &model.pairs,
            &model.swept,
            &eq.contact,
            &eq.displacement,
            r,
            direction,
        );
        let kt = statics::tangent(comm, &stiffness, &dofs, &model.pairs, &eq.slip_before, &u)
            .map_err(|e| e.to_string())?;
        let res = cea::undamped(comm, &kt, &mass, &options).map_err(|e| e.to_string())?;
        Ok((res.modes, moved))
    };
    let (base, _) = modes_with(0, EdgeMove::Open)?;
    if root {
        println!(
            "{preset}, mu {mu}: {} swept contact points, {} closed (forces from {:.3} N), {} \
             open (gaps from {:.3e} m); {} modes to {fmax} Hz",
            total,
            closed,
            weakest,
            total - closed,
            nearest,
            base.len()
        );
    }
    let mut failures = Vec::new();
    let mut rows: Vec<Vec<String>> = base
        .iter()
        .map(|m| vec![format!("{:9.1}", m.frequency_hz)])
        .collect();
    let mut header = vec!["  f (Hz) ".to_string()];
    for (action, direction) in [("open", EdgeMove::Open), ("close", EdgeMove::Close)] {
        for r in [1usize, 2, 4, 8, 16] {
            let (changed, moved) = modes_with(r, direction)?;
            if moved < r {
                continue;
            }
            header.push(format!("{action} {r:2}"));
            for (i, row) in rows.iter_mut().enumerate() {
                let cell = changed.get(i).map_or("      -".to_string(), |m| {
                    format!(
                        "{:+6.2}%",
                        100.0 * (m.frequency_hz / base[i].frequency_hz - 1.0)
                    )
                });
                row.push(cell);
            }
            if mu == 0.0 {
                for (i, m) in changed.iter().enumerate().take(base.len()) {
                    let w = omega2(m);
                    let slack = INTERLACING * omega2(&base[i]);
                    // Opening lowers every eigenvalue by at most r places, closing raises it.
                    let (low, high) = if direction == EdgeMove::Open {
                        (
                            i.checked_sub(r).map(|k| omega2(&base[k])),
                            Some(omega2(&base[i])),
                        )
                    } else {
                        (Some(omega2(&base[i])), base.get(i + r).map(omega2))
                    };
                    if low.is_some_and(|l| w < l - slack) || high.is_some_and(|h| w > h + slack) {
                        failures.push(format!(
                            "{action} {r}: mode {i} at {:.2} Hz breaks the interlacing with the \
                             unchanged model's ({:.2} Hz)",
                            m.frequency_hz, base[i].frequency_hz
                        ));
                    }
                }
            }
            if mu > 0.0 && root {
                let unstable: Vec<String> = changed
                    .iter()
                    .filter(|m| m.unstable)
                    .map(|m| format!("{:.1} Hz ({:+.1} 1/s)", m.frequency_hz, m.real_part))
                    .collect();
                println!("{action} {r:2}: unstable {}", unstable.join(", "));
            }
        }
    }
    if root {
        if mu > 0.0 {
            let unstable: Vec<String> = base
                .iter()
                .filter(|m| m.unstable)
                .map(|m| format!("{:.1} Hz ({:+.1} 1/s)", m.frequency_hz, m.real_part))
                .collect();
            println!("as solved: unstable {}", unstable.join(", "));
        }
        println!("frequency of the i-th mode, change with r points opened (weakest first) or closed (nearest first):");
        println!("{}", header.join(" | "));
        for row in &rows {
            println!("{}", row.join(" |  "));
        }
    }
    Ok(failures)
}

fn main() -> ExitCode {
    let rt = match Runtime::init(&RuntimeOptions::default()) {
        Ok(rt) => rt,
        Err(e) => {
            eprintln!("contact_edge: PETSc did not start: {e}");
            return ExitCode::FAILURE;
        }
    };
    let root = rt.world().rank() == 0;
    match run(&rt) {
        Ok(failures) if failures.is_empty() => ExitCode::SUCCESS,
        Ok(failures) => {
            if root {
                eprintln!("contact_edge: FAILED: {}", failures.join("; "));
            }
            ExitCode::FAILURE
        }
        Err(e) => {
            if root {
                eprintln!("contact_edge: {e}");
            }
            ExitCode::FAILURE
        }
    }
}
