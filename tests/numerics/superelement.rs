//! The Craig-Bampton super-element (METHOD.md section 6) checked against independent answers
//! on the tiny built-in brake reduced to 6 contact nodes per pad, on 1 and 2 ranks (see
//! `common/harness.rs`): its eigenvalues against the real modes of the whole model without
//! the swept contact, their convergence with the cut-off, and its equilibrium.

use crate::common;

use common::harness::Check;
use faer::{Mat, Side};
use squeal::analysis::modes::{real_modes, ModeBand, ModesOptions};
use squeal::analysis::restraint;
use squeal::analysis::statics::{self, StaticOptions, StaticProblem};
use squeal::fem::element::MassRule;
use squeal::model::{self, Model, Operators};
use squeal::petsc::{DenseMatrix, Runtime};
use squeal::reduce::{
    build_with_basis, reduce_interface, BuildSettings, CraigBampton, DiscCoupling, GridSize,
    InterfaceSettings, PadCoupling, ReducedInterface, SuperElementError,
};
use squeal::study::config::Study;
use std::f64::consts::PI;

pub const CHECKS: &[Check] = &[
    Check {
        name: "superelement_reproduces_its_equilibrium",
        run: equilibrium,
        ranks: &[1, 2],
        agreement: 1e-8,
    },
    Check {
        name: "superelement_with_a_kept_frictional_pair_reproduces_its_equilibrium",
        run: equilibrium_kept_pair,
        ranks: &[1, 2],
        agreement: 1e-8,
    },
    Check {
        name: "superelement_modes_converge_with_the_cutoff",
        run: convergence,
        ranks: &[1, 2],
        agreement: 1e-8,
    },
    Check {
        name: "superelement_assembly_sits_at_its_equilibrium_and_matches_the_cea",
        run: assembly_matches_the_reduced_interface,
        ranks: &[1, 2],
        agreement: 1e-8,
    },
    Check {
        name: "superelement_of_patch_laws_sits_at_its_equilibrium_and_matches_the_cea",
        run: patch_law_assembly_matches_the_reduced_interface,
        ranks: &[1, 2],
        agreement: 1e-8,
    },
    Check {
        name: "superelement_of_share_couplings_sits_at_its_equilibrium_and_matches_the_cea",
        run: share_coupled_assembly_matches_the_reduced_interface,
        ranks: &[1, 2],
        agreement: 1e-8,
    },
];

fn e(err: impl std::fmt::Display) -> String {
    err.to_string()
}

const FRICTION: f64 = 0.5;

/// The tiny brake at mu 0.5, 6 reduced contact nodes per pad, assembled and solved.
struct Setup<'rt> {
    reduced: ReducedInterface,
    operators: Operators<'rt>,
    displacement: Vec<[f64; 3]>,
    slip: squeal::contact::SlipHistory,
    swept: Vec<usize>,
}

impl Setup<'_> {
    fn configuration(&self) -> statics::Configuration<'_> {
        statics::Configuration {
            displacement: &self.displacement,
            slip: &self.slip,
        }
    }
}

fn setup(rt: &Runtime) -> Result<Setup<'_>, String> {
    setup_with(rt, false, false, 6)
}

/// [`setup`], the reduced contacts with patch laws (`tilt`) or point contacts, tied by the
/// paper's couplings or by share couplings on both sides (`shares`), `count` reduced contact
/// nodes per pad.
fn setup_with(rt: &Runtime, tilt: bool, shares: bool, count: usize) -> Result<Setup<'_>, String> {
    let comm = rt.world();
    let mut study = Study::builtin("tiny");
    for c in &mut study.contacts {
        c.friction = FRICTION;
    }
    let full = Model::from_spec(&study.model_spec()).map_err(e)?;
    let mut settings = InterfaceSettings {
        tilt: Some(tilt),
        ..InterfaceSettings::paper(GridSize::Count(count))
    };
    if shares {
        settings.pad_coupling = PadCoupling::Share;
        settings.disc_coupling = DiscCoupling::Share;
    }
    let reduced = reduce_interface(&full, &settings).map_err(e)?;
    let model = &reduced.model;
    let operators = model::assemble(comm, model, MassRule::Exact).map_err(e)?;
    let problem = StaticProblem {
        dofs: &operators.dofs,
        stiffness: &operators.stiffness,
        load: &operators.load,
        pairs: &model.pairs,
        slip: &squeal::contact::SlipHistory::default(),
        bodies: &restraint::bodies(&model.mesh),
        constraints: None,
    };
    let solution = statics::solve(comm, &problem, None, &StaticOptions::default()).map_err(e)?;
    let swept = (0..model.pairs.len()).filter(|&i| model.swept[i]).collect();
    Ok(Setup {
        reduced,
        operators,
        displacement: solution.displacement,
        slip: solution.slip_before,
        swept,
    })
}

fn build<'rt>(s: &Setup<'rt>, rt: &'rt Runtime, cutoff: f64) -> Result<CraigBampton<'rt>, String> {
    let start = std::time::Instant::now();
    let cb = build_with_basis(
        rt.world(),
        &s.reduced,
        &s.operators,
        s.configuration(),
        &s.swept,
        &BuildSettings {
            friction: FRICTION,
            cutoff_hz: cutoff,
            interior_modes_hint: None,
            residual_vectors: false,
        },
    )
    .map_err(e)?;
    if rt.world().rank() == 0 {
        let h = &cb.superelement.header;
        eprintln!(
            "cut-off {cutoff} Hz: {} equations, {} boundary pairs, {} modes, size {}, built \
             in {:.2} s",
            s.operators.dofs.equations(),
            h.boundary.len(),
            h.modes,
            h.size,
            start.elapsed().as_secs_f64()
        );
    }
    Ok(cb)
}

/// Eigenvalues (omega^2) of the dense pencil (K, M), M symmetric positive definite: those of
/// L^-1 K L^-T with M = L L^T, K symmetrised (T^T K T is symmetric to round-off only).
fn dense_eigenvalues(k: &Mat<f64>, m: &Mat<f64>) -> Result<Vec<f64>, String> {
    let n = k.nrows();
    let l = m
        .llt(Side::Lower)
        .map_err(|x| format!("{x:?}"))?
        .L()
        .to_owned();
    let ks = Mat::from_fn(n, n, |i, j| 0.5 * (k[(i, j)] + k[(j, i)]));
    // X = L^-1 K_s, then A = (L^-1 X^T) = L^-1 K_s L^-T.
    let solve_lower = |b: &Mat<f64>| {
        let mut x = b.clone();
        faer::linalg::triangular_solve::solve_lower_triangular_in_place(
            l.as_ref(),
            x.as_mut(),
            faer::Par::Seq,
        );
        x
    };
    let x = solve_lower(&ks);
    let a = solve_lower(&x.transpose().to_owned());
    let a = Mat::from_fn(n, n, |i, j| 0.5 * (a[(i, j)] + a[(j, i)]));
    let values = a
        .self_adjoint_eigenvalues(Side::Lower)
        .map_err(|x| format!("{x:?}"))?;
    Ok(values)
}

fn hz(omega2: f64) -> f64 {
    omega2.max(0.0).sqrt() / (2.0 * PI)
}

/// The model's equation vector of a node displacement field.
fn equation_vector(s: &Setup, u: &[[f64; 3]]) -> Vec<f64> {
    let dofs = &s.operators.dofs;
    let mut out = vec![0.0; dofs.equations()];
    for (node, d) in u.iter().enumerate() {
        for (c, &v) in d.iter().enumerate() {
            if let Some(eq) = dofs.equation(node, c) {
                out[eq] = v;
            }
        }
    }
    out
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// (b) T q_s is the static displacement, and K_r q_s - T^T F is T^T (K u_s - F), which is
/// the swept contact force on each boundary node (the rest of K u_s - F is the statics'
/// residual): p (n + mu t) on c_k and its opposite on d_k, from the header's own data.
fn equilibrium(rt: &Runtime) -> Result<Vec<f64>, String> {
    equilibrium_case(rt, false)
}

/// (b) with only the first pad's pair swept: the other pad's reduced contact is kept,
/// linearised with its friction (K_t unsymmetric: the LU and the symmetrised modes' path),
/// and T^T (K_t u_s - F) is then the first pad's contact forces alone.
fn equilibrium_kept_pair(rt: &Runtime) -> Result<Vec<f64>, String> {
    equilibrium_case(rt, true)
}

fn equilibrium_case(rt: &Runtime, keep_second: bool) -> Result<Vec<f64>, String> {
    let comm = rt.world();
    faer::set_global_parallelism(faer::Par::Seq);
    let mut s = setup(rt)?;
    if keep_second {
        s.swept.truncate(1);
    }
    let cb = build(&s, rt, 8000.0)?;
    let se = &cb.superelement;
    if !keep_second {
        refuses_bad_input(rt, &s)?;
    }
    let q = &se.equilibrium;
    let n_b = se.boundary_size();

    // T q_s against u_s.
    let t = cb.basis.to_faer().map_err(e)?;
    let u = equation_vector(&s, &s.displacement);
    let tq: Vec<f64> = (0..t.nrows())
        .map(|i| (0..t.ncols()).map(|j| t[(i, j)] * q[j]).sum())
        .collect();
    let diff: Vec<f64> = tq.iter().zip(&u).map(|(a, b)| a - b).collect();
    let expansion_error = norm(&diff) / norm(&u);
    let alpha = q[q.len() - 1];
    let eta = norm(&q[n_b..q.len() - 1]);

    // K_t u_s - F, projected (K_t: K with the kept pairs' tangent; K itself when none).
    let kept: Vec<_> = s
        .reduced
        .model
        .pairs
        .iter()
        .enumerate()
        .filter(|(i, _)| !s.swept.contains(i))
        .map(|(_, p)| p.clone())
        .collect();
    if keep_second && (kept.len() != 1 || se.header.other_contacts.len() != 1) {
        return Err(format!("{} kept pairs", kept.len()));
    }
    let k_t = statics::tangent(
        comm,
        &s.operators.stiffness,
        &s.operators.dofs,
        &kept,
        &squeal::contact::SlipHistory::default(),
        &s.displacement,
    )
    .map_err(e)?;
    let k = &k_t;
    let (mut x, mut ku) = k.vectors().map_err(e)?;
    {
        let (lo, _) = x.ownership_range().map_err(e)?;
        let mut w = x.write().map_err(e)?;
        for (i, v) in w.iter_mut().enumerate() {
            *v = u[lo + i];
        }
    }
    k.mult(&x, &mut ku).map_err(e)?;
    ku.axpy(-1.0, &s.operators.load).map_err(e)?;
    let unbalance_full = ku.norm2().map_err(e)?;
    let load_norm = s.operators.load.norm2().map_err(e)?;
    let col = DenseMatrix::from_columns(comm, &[ku]).map_err(e)?;
    let projected = cb.basis.transpose_mult(&col).map_err(e)?;
    let reduced_unbalance: Vec<f64> = (0..se.header.size)
        .map(|i| {
            (0..se.header.size)
                .map(|j| se.stiffness[(i, j)] * q[j])
                .sum::<f64>()
                - se.load[i]
        })
        .collect();
    let scale = norm(&reduced_unbalance);
    let projection_error = (0..se.header.size)
        .map(|i| (reduced_unbalance[i] - projected[(i, 0)]).powi(2))
        .sum::<f64>()
        .sqrt()
        / scale;

    // The swept contact forces from the header.
    let mut expected = vec![0.0; se.header.size];
    for (k, b) in se.header.boundary.iter().enumerate() {
        let t = b.sliding.unwrap_or([0.0; 3]);
        for c in 0..3 {
            let f = b.normal_force * (b.normal[c] + FRICTION * t[c]);
            expected[6 * k + c] = f;
            expected[6 * k + 3 + c] = -f;
        }
    }
    let force_error = norm(
        &expected
            .iter()
            .zip(&reduced_unbalance)
            .map(|(a, b)| a - b)
            .collect::<Vec<_>>(),
    ) / norm(&expected);
    let total_normal: f64 = se.header.boundary.iter().map(|b| b.normal_force).sum();
    let closed = se
        .header
        .boundary
        .iter()
        .filter(|b| b.normal_force > 0.0)
        .count();
    if comm.rank() == 0 {
        eprintln!(
            "equilibrium: |T q_s - u_s| / |u_s| = {expansion_error:.3e} (alpha - 1 = {:.3e}, \
             |eta| = {eta:.3e}); |K u_s - F| / |F| = {:.3e}; |K_r q_s - l - T^T (K u_s - F)| \
             / |K_r q_s - l| = {projection_error:.3e}; against the swept contact forces \
             {force_error:.3e}; {closed} of {} points closed, normal force {total_normal:.6e} N",
            alpha - 1.0,
            unbalance_full / load_norm,
            se.header.boundary.len()
        );
    }
    // Tolerances: u_s leaves the span of T only by K_II^-1 times the statics' interior
    // residual (see src/reduce/craig_bampton.rs), which Newton brings below 1e-8 of the
    // initial residual at worst (its round-off floor, see StaticOptions); measured 1.3e-12.
    // K u_s - F is the contact force, |F| in size (5 |F| here), so the projections compare to
    // the solves' round-off: 1e-8 with a margin over the measured 2e-11.
    if expansion_error > 1e-8 {
        return Err(format!("T q_s differs from u_s by {expansion_error:e}"));
    }
    if projection_error > 1e-8 {
        return Err(format!(
            "K_r q_s - l differs from T^T (K u_s - F) by {projection_error:e}"
        ));
    }
    if force_error > 1e-8 {
        return Err(format!(
            "K_r q_s - l differs from the swept contact forces by {force_error:e}"
        ));
    }
    if closed == 0 {
        return Err("no swept contact point is closed".into());
    }
    // Rank-count invariants: the boundary blocks and the sizes (the modal columns' signs and
    // the bases of repeated eigenvalues are the eigensolver's choice), q_s on the boundary.
    let kmax = se.stiffness.norm_max();
    let mmax = se.mass.norm_max();
    let mut out = vec![se.header.modes as f64, se.header.size as f64];
    out.push(se.stiffness.norm_l2() / kmax);
    out.push(se.mass.norm_l2() / mmax);
    for i in 0..n_b {
        for j in 0..n_b {
            out.push(se.stiffness[(i, j)] / kmax);
            out.push(se.mass[(i, j)] / mmax);
        }
    }
    let umax = q[..n_b].iter().fold(0.0f64, |m, x| m.max(x.abs()));
    out.extend(q[..n_b].iter().map(|x| x / umax));
    out.push(alpha);
    out.push(total_normal / s.reduced.model.applied_load());
    Ok(out)
}

/// Typed errors for what the caller got wrong (decided before any collective call).
fn refuses_bad_input(rt: &Runtime, s: &Setup) -> Result<(), String> {
    let try_build = |swept: &[usize], cutoff: f64| {
        build_with_basis(
            rt.world(),
            &s.reduced,
            &s.operators,
            s.configuration(),
            swept,
            &BuildSettings {
                friction: FRICTION,
                cutoff_hz: cutoff,
                interior_modes_hint: None,
                residual_vectors: false,
            },
        )
        .err()
    };
    let pairs = s.reduced.model.pairs.len();
    match try_build(&[pairs], 8000.0) {
        Some(SuperElementError::PairIndex { index, .. }) if index == pairs => {}
        other => return Err(format!("pair out of range: {other:?}")),
    }
    match try_build(&[], 8000.0) {
        Some(SuperElementError::NoSweptPair) => {}
        other => return Err(format!("nothing swept: {other:?}")),
    }
    match try_build(&s.swept, -1.0) {
        Some(SuperElementError::Cutoff(_)) => {}
        other => return Err(format!("negative cut-off: {other:?}")),
    }
    Ok(())
}

/// (a) The super-element's eigenvalues below half the lowest cut-off match the real modes of
/// the whole reduced-interface model without the swept contact (K_t = K: the tiny brake has
/// no other pair), and come closer as the cut-off rises (Craig-Bampton's truncation error
/// falls with the first omitted fixed-interface mode).
fn convergence(rt: &Runtime) -> Result<Vec<f64>, String> {
    let comm = rt.world();
    faer::set_global_parallelism(faer::Par::Seq);
    let s = setup(rt)?;
    let compare_hz = 4000.0;
    let reference = real_modes(
        comm,
        &s.operators.stiffness,
        &s.operators.mass,
        &ModesOptions {
            band: ModeBand::Below {
                max_frequency_hz: compare_hz * 1.2,
            },
            ..Default::default()
        },
    )
    .map_err(e)?;
    let reference: Vec<f64> = reference.modes.iter().map(|m| m.frequency_hz).collect();
    let elastic: Vec<usize> = (0..reference.len())
        .filter(|&i| reference[i] > 1.0 && reference[i] < compare_hz)
        .collect();
    let mut out = Vec::new();
    let mut errors = Vec::new();
    for cutoff in [8000.0, 11000.0, 15000.0] {
        let cb = build(&s, rt, cutoff)?;
        let se = &cb.superelement;
        let values: Vec<f64> = dense_eigenvalues(&se.stiffness, &se.mass)?
            .into_iter()
            .map(hz)
            .collect();
        // The lowest modes one to one: the reduced model's eigenvalues lie above the full
        // model's (Rayleigh-Ritz), so the i-th with the i-th.
        let mut worst = 0.0f64;
        let mut per_mode = Vec::new();
        for &i in &elastic {
            let r = reference[i];
            let v = values[i];
            if v < r * (1.0 - 1e-9) {
                return Err(format!(
                    "cut-off {cutoff}: mode {i} at {v} Hz below the full model's {r} Hz"
                ));
            }
            worst = worst.max((v - r) / r);
            per_mode.push((r, (v - r) / r));
        }
        if comm.rank() == 0 {
            eprintln!(
                "cut-off {cutoff} Hz: {} modes kept; {} elastic modes below {compare_hz} Hz, \
                 largest relative frequency error {worst:.3e}",
                se.header.modes,
                elastic.len()
            );
            for (r, err) in &per_mode {
                eprintln!("  {r:9.2} Hz: {err:.3e}");
            }
        }
        errors.push(worst);
        out.push(se.header.modes as f64);
        out.extend(elastic.iter().map(|&i| values[i] / compare_hz));
    }
    // Measured: 5.1e-2, 5.7e-3, 4.4e-3 (and 5.5e-5 at 40 kHz, 6.4e-6 at 100 kHz with 960
    // modes: the reduction converges to the full model; slowly at low cut-offs, because the
    // stiff ties put much of the pads' interior flexibility in high fixed-interface modes).
    if errors[2] > 1e-2 || !(errors[1] < errors[0] && errors[2] < errors[1]) {
        return Err(format!("no convergence with the cut-off: {errors:?}"));
    }
    out.extend(elastic.iter().map(|&i| reference[i] / compare_hz));
    Ok(out)
}

/// A real super-element through the dense assembly. Eq. 5: at mu_SE, with the contact
/// forces matched (eq. 8), the reduced static residual at the super-element's own
/// equilibrium is round-off, for the linear law and for a cubic one, and Newton takes no
/// step. With k_nl = 0 and k_l = penalty x area (the reduced interface's own law), the dense
/// CEA of the linearised assembly equals the reduced-interface model's sparse CEA at the same
/// mu to within the Craig-Bampton truncation, measured by the modes test above (4.4e-3 at a
/// 15 kHz cut-off below 4 kHz).
fn assembly_matches_the_reduced_interface(rt: &Runtime) -> Result<Vec<f64>, String> {
    use squeal::reduce::assembly::{Assembly, CubicContact};
    let s = setup(rt)?;
    let cb = build(&s, rt, 15_000.0)?;
    let se = &cb.superelement;
    for k_cubic in [0.0, 1e17] {
        let contact = CubicContact {
            k_linear: None,
            k_cubic,
        };
        let assembly = Assembly::new(se, &contact).map_err(e)?;
        let residual = assembly.equilibrium_residual(FRICTION);
        // The super-element's projections are exact to ~1e-11 of the load (tests above);
        // the matched forces add round-off only.
        if residual > 1e-9 {
            return Err(format!(
                "eq. 5: |R(q_s)| / |load| = {residual:e} (k_nl {k_cubic:e})"
            ));
        }
        // Not compared between rank counts: round-off (see the patch-law check).
    }
    let assembly = Assembly::new(se, &CubicContact::default()).map_err(e)?;
    dense_against_sparse(rt, &s, &assembly)
}

/// The super-element of a reduced interface whose contacts carry patch laws (their tilt
/// nodes on the boundary, 12 coordinates per pair): the dense assembly evaluates the
/// reduced-interface model's own law, so R(q_s) is the projection's round-off with no force
/// matching; Newton from a start moved off q_s comes back to it (the 12 x 12 Jacobian is
/// the law's); and the dense CEA equals the reduced-interface model's sparse CEA to the
/// Craig-Bampton truncation, as for point contacts. A cubic law is refused with it.
fn patch_law_assembly_matches_the_reduced_interface(rt: &Runtime) -> Result<Vec<f64>, String> {
    patch_law_assembly(rt, false)
}

/// The same with share couplings on both sides (`pad_coupling` and `disc_coupling` =
/// share) at 22 nodes per pad, where some shares hold one row of face nodes and read their
/// nearest neighbour's tilt nodes (on the boundary once, with the neighbour): the couplings
/// change the boundary's ties, not what the super-element is, so the same checks hold. With
/// those shares reading their slopes from their neighbours' nodes instead, this
/// super-element's reduced mass was not positive definite.
fn share_coupled_assembly_matches_the_reduced_interface(rt: &Runtime) -> Result<Vec<f64>, String> {
    patch_law_assembly(rt, true)
}

fn patch_law_assembly(rt: &Runtime, shares: bool) -> Result<Vec<f64>, String> {
    use squeal::reduce::assembly::{Assembly, CubicContact, StaticOptions};
    let s = setup_with(rt, true, shares, if shares { 22 } else { 6 })?;
    let cb = build(&s, rt, 15_000.0)?;
    let se = &cb.superelement;
    let tilted = se.header.boundary.iter().all(|b| b.tilt.is_some());
    let owners = se
        .header
        .boundary
        .iter()
        .filter(|b| b.tilt.as_ref().is_some_and(|t| t.shared.is_none()))
        .count();
    let pairs = se.header.boundary.len();
    // Shares read their neighbours' tilt nodes on this grid, and only there.
    if !tilted || se.boundary_size() != 6 * pairs + 6 * owners || (owners < pairs) != shares {
        return Err(format!(
            "{pairs} boundary pairs, {owners} with tilt nodes of their own, {} coordinates: \
             every pair should carry a patch law, on tilt nodes held once",
            se.boundary_size()
        ));
    }
    let cubic = CubicContact {
        k_linear: None,
        k_cubic: 1e17,
    };
    match Assembly::new(se, &cubic) {
        Err(err) if err.to_string().contains("patch law") => {}
        other => return Err(format!("a cubic law with patch laws: {:?}", other.err())),
    }
    let assembly = Assembly::new(se, &CubicContact::default()).map_err(e)?;
    let residual = assembly.equilibrium_residual(FRICTION);
    if residual > 1e-9 {
        return Err(format!(
            "eq. 5 with patch laws: |R(q_s)| / |load| = {residual:e}"
        ));
    }
    let mismatch = assembly.force_mismatch();
    if mismatch > 1e-12 {
        return Err(format!(
            "patch forces at q_s off by {mismatch:e} (relative)"
        ));
    }
    // Closed pairs carry the load: some pair is partly or wholly closed.
    let states = assembly.pair_states(&se.equilibrium, se.header.friction);
    if !states.iter().any(|p| p.closed && p.force > 0.0) {
        return Err("no patch pair closed at the equilibrium".into());
    }
    // Newton back from a start with every tilt node moved: converges to q_s.
    let mut start = se.equilibrium.clone();
    let scale = start[..se.boundary_size()]
        .iter()
        .fold(0.0f64, |m, v| m.max(v.abs()));
    for (k, at) in se.header.tilt_offsets().into_iter().enumerate() {
        let Some(at) = at.filter(|_| se.header.boundary[k].width() == 12) else {
            continue;
        };
        for i in 0..6 {
            start[at + i] += 0.05 * scale * (((k * 12 + i + 6) % 7) as f64 - 3.0) / 3.0;
        }
    }
    let solved = assembly
        .solve_static_from(&start, FRICTION, &StaticOptions::default())
        .map_err(e)?;
    let moved = solved
        .q
        .iter()
        .zip(&se.equilibrium)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0f64, f64::max);
    if rt.world().rank() == 0 {
        eprintln!(
            "patch laws: |R(q_s)| / |load| = {residual:.2e}, force mismatch {mismatch:.2e}, \
             Newton back to q_s in {} steps, |q - q_s| = {moved:.2e} of {scale:.2e}",
            solved.iterations
        );
    }
    // The static is unique near q_s: back to it to the Newton tolerance's scale.
    if moved > 1e-6 * scale || solved.iterations == 0 {
        return Err(format!(
            "Newton from the moved start: {} steps, |q - q_s| = {moved:e} of {scale:e}",
            solved.iterations
        ));
    }
    // The ranks compare the dense frequencies only: the residual is round-off (3e-11 of the
    // load), checked above against 1e-9 on each rank count. Its rounded logarithm, compared
    // before, sat at -10.5 and flipped between -10 and -11 with the order MUMPS's messages
    // arrived in (under load, 2 runs in 3).
    dense_against_sparse(rt, &s, &assembly)
}

/// The dense CEA of `assembly` at its equilibrium against the reduced-interface model's
/// sparse CEA below 4 kHz: the same count, each sparse mode within 1 % (the truncation the
/// modes test measures: 4.4e-3 at a 15 kHz cut-off). Returns the dense frequencies.
fn dense_against_sparse(
    rt: &Runtime,
    s: &Setup,
    assembly: &squeal::reduce::assembly::Assembly,
) -> Result<Vec<f64>, String> {
    use squeal::analysis::cea::{self, CeaOptions};
    use squeal::reduce::assembly::DenseCeaOptions;
    let se = assembly.super_element();
    let band = 4000.0;
    let dense = assembly
        .cea(
            &se.equilibrium,
            FRICTION,
            &DenseCeaOptions {
                max_frequency_hz: band,
                ..Default::default()
            },
        )
        .map_err(e)?;
    // The reduced-interface model's own CEA at the same equilibrium.
    let comm = rt.world();
    let kt = statics::tangent(
        comm,
        &s.operators.stiffness,
        &s.operators.dofs,
        &s.reduced.model.pairs,
        &squeal::contact::SlipHistory::default(),
        &s.displacement,
    )
    .map_err(e)?;
    let sparse = cea::undamped(
        comm,
        &kt,
        &s.operators.mass,
        &CeaOptions {
            max_frequency_hz: band,
            ..Default::default()
        },
    )
    .map_err(e)?;
    let mut worst = 0.0f64;
    for m in &sparse.modes {
        let nearest = dense
            .modes
            .iter()
            .map(|d| (d.frequency_hz - m.frequency_hz).abs() / m.frequency_hz)
            .fold(f64::INFINITY, f64::min);
        worst = worst.max(nearest);
    }
    if rt.world().rank() == 0 {
        eprintln!(
            "dense assembly CEA: {} modes below {band} Hz against {} sparse; worst relative \
             frequency difference {worst:.3e}",
            dense.modes.len(),
            sparse.modes.len()
        );
    }
    if dense.modes.len() != sparse.modes.len() || worst > 1e-2 {
        return Err(format!(
            "dense CEA: {} modes vs {}, worst difference {worst:e}",
            dense.modes.len(),
            sparse.modes.len()
        ));
    }
    Ok(dense.modes.iter().map(|m| m.frequency_hz).collect())
}
