//! `squeal cea` on matrix files and `squeal sweep` on the built-in brake, run as a user runs
//! them (under mpirun), with closed-form checks and bad input.

use crate::common;

use num_complex::Complex64;
use std::path::{Path, PathBuf};

fn squeal() -> &'static Path {
    Path::new(env!("CARGO_BIN_EXE_squeal"))
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("squeal-sweep-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn write_mtx(path: &Path, entries: &[(usize, usize, f64)]) {
    // 2 x 2, or larger when an entry says so.
    let n = entries.iter().map(|e| e.0.max(e.1) + 1).fold(2, usize::max);
    let mut s = format!(
        "%%MatrixMarket matrix coordinate real general\n{n} {n} {}\n",
        entries.len()
    );
    for (i, j, v) in entries {
        s.push_str(&format!("{} {} {v:e}\n", i + 1, j + 1));
    }
    std::fs::write(path, s).unwrap();
}

fn eigenvalues(dir: &Path) -> Vec<(f64, f64, bool)> {
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("cea.json")).unwrap()).unwrap();
    common::eigenvalues_of(&json)
}

/// The mode-coupling model as Matrix Market files: M = I, K = [[2, 1 - D], [1, 2]].
/// For D > 1, lambda = +/- sqrt(-2 +/- i sqrt(D - 1)): the pair with non-negative frequency
/// must come out to 1e-10, one of them unstable.
#[test]
fn cea_on_matrix_market_files_matches_the_closed_form() {
    let dir = scratch("mtx");
    for d in [0.5, 1.5, 4.0] {
        write_mtx(
            &dir.join("K.mtx"),
            &[(0, 0, 2.0), (0, 1, 1.0 - d), (1, 0, 1.0), (1, 1, 2.0)],
        );
        write_mtx(&dir.join("M.mtx"), &[(0, 0, 1.0), (1, 1, 1.0)]);
        let out = dir.join(format!("out{d}"));
        cea_on(&dir, "1", &out, &[]);
        let found = eigenvalues(&out);
        assert_eq!(found.len(), 2, "{found:?}");
        let disc = Complex64::new(1.0 - d, 0.0).sqrt();
        for w2 in [2.0 + disc, 2.0 - disc] {
            // lambda^2 = -omega^2, the root with non-negative imaginary part.
            let mut lambda = (-w2).sqrt();
            if lambda.im < 0.0 {
                lambda = -lambda;
            }
            let f = lambda.im / (2.0 * std::f64::consts::PI);
            let hit = found.iter().any(|&(ff, a, _)| {
                (Complex64::new(a, 2.0 * std::f64::consts::PI * ff) - lambda).norm()
                    < 1e-10 * lambda.norm()
            });
            assert!(hit, "D = {d}: lambda {lambda} ({f} Hz) not in {found:?}");
        }
        let unstable = found.iter().filter(|m| m.2).count();
        assert_eq!(unstable, usize::from(d > 1.0), "D = {d}: {found:?}");
    }
}

#[test]
fn sweep_of_the_builtin_brake_writes_a_complete_study() {
    let dir = scratch("sweep");
    let run = success(
        2,
        &[
            "sweep",
            "--preset",
            "tiny",
            "--friction",
            "0.2,0.6",
            "--fmax",
            "6000",
            "-o",
            dir.to_str().unwrap(),
        ],
    );
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(stdout.contains("instabilities"), "{stdout}");
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("sweep.json")).unwrap()).unwrap();
    let points = json["points"].as_array().unwrap();
    assert_eq!(points.len(), 2);
    for p in points {
        // The pads carry the whole brake load (the springs act in the disc plane only).
        let balance = p["balance_ratio"].as_f64().unwrap();
        assert!((balance - 1.0).abs() < 1e-8, "balance {balance}");
        for pair in p["contact"].as_array().unwrap() {
            // Every closed point slides along the disc's motion, perpendicular to the
            // radius: the braking torque is mu N times a radius within the pad's.
            let r = pair["effective_radius"].as_f64().unwrap();
            assert!((0.09..=0.135).contains(&r), "{pair}");
        }
        assert!(!p["eigenvalues"].as_array().unwrap().is_empty());
    }
    // Every link says how sure it is (its regret, >= 0) where it says its MAC; the log
    // counts them.
    let tracks = json["tracks"].as_array().unwrap();
    let mut links = 0;
    for t in tracks {
        for (mac, regret) in t["link_mac"]
            .as_array()
            .unwrap()
            .iter()
            .zip(t["link_regret"].as_array().unwrap())
        {
            assert_eq!(mac.is_null(), regret.is_null(), "{t}");
            links += usize::from(!mac.is_null());
            assert!(regret.is_null() || regret.as_f64().unwrap() >= 0.0, "{t}");
        }
    }
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(
        stderr.contains(&format!("tracking: {} tracks, {links} links", tracks.len())),
        "{stderr}"
    );
    assert!(json["instabilities"].as_array().is_some());
    for f in [
        "stability_map.svg",
        "friction_sweep.svg",
        "mu_0.200/cea.json",
        "mu_0.600/cea.vtu",
    ] {
        assert!(dir.join(f).is_file(), "{f} missing");
    }
}

/// The CEA's two window solvers on the spring-held brake at mu 0.6 (2 ranks): block
/// Krylov-Schur (the default, its windows said on the log) and SLEPc's Krylov-Schur
/// (`--cea-solver krylov-schur`) give the same modes, each eigenvalue to 1e-8 of its modulus
/// (both converge the shift-and-invert problem to 1e-10), the same unstable flags, and the
/// unstable modes' friction sensitivities, made of left vectors each solver finds its own
/// way, to 1e-6 of their modulus (first-order quantities over y^H M x). With
/// `-st_matmode inplace` in the PETSc options the default is SLEPc's, with the same results.
#[test]
fn both_cea_solvers_give_the_same_modes_and_sensitivities() {
    let run = |name: &str, extra: &[&str]| {
        let dir = scratch(&format!("solver-{name}"));
        let mut args = vec![
            "sweep",
            "--preset",
            "tiny",
            "--friction",
            "0.6",
            "--fmax",
            "6000",
            "-v",
            "-o",
        ];
        args.push(dir.to_str().unwrap());
        args.extend_from_slice(extra);
        let out = success(2, &args);
        let json: serde_json::Value =
            serde_json::from_slice(&std::fs::read(dir.join("sweep.json")).unwrap()).unwrap();
        (String::from_utf8_lossy(&out.stderr).to_string(), json)
    };
    let (log, block) = run("default", &[]);
    assert!(log.contains("block Krylov-Schur"), "{log}");
    let (log, slepc) = run("krylov-schur", &["--cea-solver", "krylov-schur"]);
    assert!(!log.contains("block Krylov-Schur"), "{log}");
    // Asking SLEPc to shift the tangent in place (README: where memory is tight) is a request
    // for SLEPc's solver, which the default then follows.
    let (log, in_place) = run("in-place", &["--petsc-options", "-st_matmode inplace"]);
    assert!(
        !log.contains("block Krylov-Schur") && log.contains("-st_matmode inplace, so SLEPc's"),
        "{log}"
    );
    for other in [&slepc, &in_place] {
        let (a, b) = (&block["points"][0], &other["points"][0]);
        let (ea, eb) = (common::eigenvalues_of(a), common::eigenvalues_of(b));
        assert_eq!(ea.len(), eb.len(), "{ea:?}\n{eb:?}");
        for (x, y) in ea.iter().zip(&eb) {
            let size = x.1.hypot(2.0 * std::f64::consts::PI * x.0);
            let gap = (x.1 - y.1).hypot(2.0 * std::f64::consts::PI * (x.0 - y.0));
            assert!(gap <= 1e-8 * size && x.2 == y.2, "{x:?} against {y:?}");
        }
        let (ua, ub) = (common::unstable_modes(a), common::unstable_modes(b));
        assert!(!ua.is_empty());
        assert_eq!(ua.len(), ub.len());
        for (x, y) in ua.iter().zip(&ub) {
            for key in ["d_real_part_d_mu", "d_frequency_hz_d_mu"] {
                let (p, q) = (
                    x["sensitivity"][key].as_f64().unwrap(),
                    y["sensitivity"][key].as_f64().unwrap(),
                );
                assert!(
                    (p - q).abs() <= 1e-6 * p.abs().max(q.abs()),
                    "{key}: {p} against {q}"
                );
            }
        }
    }
}

/// Runs squeal under mpirun and insists it succeeds.
/// `squeal cea` on dir/K.mtx and dir/M.mtx to `fmax` Hz into `out` on 2 ranks, with
/// `extra` flags; it must succeed.
fn cea_on(dir: &Path, fmax: &str, out: &Path, extra: &[&str]) -> std::process::Output {
    let (k, m) = (dir.join("K.mtx"), dir.join("M.mtx"));
    let mut args = vec![
        "cea",
        "--stiffness",
        k.to_str().unwrap(),
        "--mass",
        m.to_str().unwrap(),
        "--fmax",
        fmax,
        "-o",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    success(2, &args)
}

fn success(ranks: usize, args: &[&str]) -> std::process::Output {
    let run = common::mpirun(ranks, squeal(), args);
    assert!(run.status.success(), "{}", common::text(&run));
    run
}

fn failure(args: &[&str]) -> String {
    let run = common::mpirun(2, squeal(), args);
    assert!(!common::hung(&run), "{}", common::text(&run));
    assert!(!run.status.success(), "{}", common::text(&run));
    let stderr = String::from_utf8_lossy(&run.stderr).to_string();
    assert!(!stderr.contains("panicked"), "{stderr}");
    stderr
}

/// K negative definite, M = I: omega^2 = -4, -9, so lambda = +/- 2, +/- 3 (real). The
/// growing roots 2 and 3 are divergence instabilities: reported at 0 Hz and flagged.
#[test]
fn a_negative_stiffness_is_a_divergence_instability() {
    let dir = scratch("divergence");
    write_mtx(&dir.join("K.mtx"), &[(0, 0, -4.0), (1, 1, -9.0)]);
    write_mtx(&dir.join("M.mtx"), &[(0, 0, 1.0), (1, 1, 1.0)]);
    let out = dir.join("out");
    cea_on(&dir, "1", &out, &[]);
    let mut found = eigenvalues(&out);
    found.sort_by(|a, b| a.1.total_cmp(&b.1));
    assert_eq!(found.len(), 2, "{found:?}");
    for ((f, re, unstable), expected) in found.into_iter().zip([2.0, 3.0]) {
        assert!(f.abs() < 1e-12 && (re - expected).abs() < 1e-10 * expected && unstable);
    }
}

/// A very stiff spring raises the round-off level of the rigid-body check (1e-9 of the
/// largest K_ii / M_ii) into the band: K = diag(1e16, [[a, b], [-b, a]]), M = I. The block's
/// omega^2 = a +/- i b (a = 1e6, b = 1e5) lie below 1e7, so without a count its two modes
/// are taken as rigid, said on the log, and the unstable one is not flagged; with
/// `--rigid-body-modes 0` they are lambda = i sqrt(omega^2) exactly, one unstable.
#[test]
fn a_count_of_rigid_body_modes_keeps_modes_under_a_stiff_springs_level() {
    let dir = scratch("rigid-count");
    let (a, b) = (1e6, 1e5);
    write_mtx(
        &dir.join("K.mtx"),
        &[(0, 0, 1e16), (1, 1, a), (1, 2, b), (2, 1, -b), (2, 2, a)],
    );
    write_mtx(&dir.join("M.mtx"), &[(0, 0, 1.0), (1, 1, 1.0), (2, 2, 1.0)]);
    let run = |out: &Path, extra: &[&str]| common::text(&cea_on(&dir, "1000", out, extra));
    let unknown = dir.join("unknown");
    let log = run(&unknown, &[]);
    assert!(
        log.contains("2 mode(s) up to") && log.contains("--rigid-body-modes"),
        "{log}"
    );
    let found = eigenvalues(&unknown);
    assert_eq!(found.len(), 2, "{found:?}");
    assert!(found.iter().all(|m| !m.2), "{found:?}");

    let held = dir.join("held");
    let log = run(&held, &["--rigid-body-modes", "0"]);
    assert!(!log.contains("taken as rigid-body"), "{log}");
    let root = num_complex::Complex64::new(a, b).sqrt();
    let mut found = eigenvalues(&held);
    found.sort_by(|x, y| x.1.total_cmp(&y.1));
    assert_eq!(found.len(), 2, "{found:?}");
    let frequency = root.re / (2.0 * std::f64::consts::PI);
    for ((f, re, unstable), sign) in found.into_iter().zip([-1.0, 1.0]) {
        assert!(
            (f - frequency).abs() <= 1e-10 * frequency,
            "{f} vs {frequency}"
        );
        assert!(
            (re - sign * root.im).abs() <= 1e-8 * root.norm(),
            "{re} vs {}",
            root.im
        );
        assert_eq!(unstable, sign > 0.0);
    }
}

/// `squeal cea` refuses a band or a threshold that cannot mean anything before it reads a
/// matrix, once (not once per rank), naming the flag, and writes nothing.
#[test]
fn cea_flags_out_of_range_are_refused_up_front() {
    let dir = scratch("cea-flags");
    write_mtx(&dir.join("K.mtx"), &[(0, 0, 2.0), (1, 1, 2.0)]);
    write_mtx(&dir.join("M.mtx"), &[(0, 0, 1.0), (1, 1, 1.0)]);
    let out = dir.join("out");
    for (flag, value, words) in [
        // flag=value: a value that starts with '-' is not taken for a flag.
        ("--fmax", "1e300", "above"),
        ("--fmax", "inf", "finite"),
        // omega^2 underflows: was "0 modes" and success.
        ("--fmax", "1e-300", "below"),
        // Was refused as "--modes-per-target", a flag there is not.
        ("--window", "0", "at least 1"),
        ("--unstable-threshold", "-1", "[0, 1)"),
        ("--unstable-threshold", "nan", "[0, 1)"),
    ] {
        let e = failure(&[
            "cea",
            "--stiffness",
            dir.join("K.mtx").to_str().unwrap(),
            "--mass",
            dir.join("M.mtx").to_str().unwrap(),
            &format!("{flag}={value}"),
            "-o",
            out.to_str().unwrap(),
        ]);
        assert!(e.contains(flag) && e.contains(words), "{flag} {value}: {e}");
        assert_eq!(e.matches("squeal: error").count(), 1, "{e}");
        assert!(!out.exists(), "{flag} {value} wrote {}", out.display());
    }
}

/// Matrices that are no eigenproblem are refused before or after the solve, never reported:
/// a mass matrix that cannot be positive definite (negative, missing or all-zero mass, an
/// indefinite 2 x 2 block), a zero stiffness, and a result whose residuals are not small
/// (an entry of 1e308 made every residual NaN, once reported as 3 instabilities). Each
/// names the file or the residual, once, under `mpirun -n 2`, with nothing written.
#[test]
fn matrices_that_are_no_eigenproblem_are_refused() {
    let dir = scratch("pencil");
    let k = [(0, 0, 4e6), (0, 1, -1e5), (1, 0, -1e5), (1, 1, 9e6)];
    write_mtx(&dir.join("K.mtx"), &k);
    write_mtx(&dir.join("M.mtx"), &[(0, 0, 1.0), (1, 1, 1.0)]);
    // Six equations, one coupling of 1e308: the norms overflow, the residuals are NaN.
    let mut overflow: Vec<(usize, usize, f64)> =
        (0..6).map(|i| (i, i, (i + 1) as f64 * 1e6)).collect();
    overflow.push((0, 5, 1e308));
    write_mtx(&dir.join("Kbig.mtx"), &overflow);
    let unit: Vec<(usize, usize, f64)> = (0..6).map(|i| (i, i, 1.0)).collect();
    write_mtx(&dir.join("M6.mtx"), &unit);
    write_mtx(&dir.join("Kzero.mtx"), &[(0, 0, 0.0), (1, 1, 0.0)]);
    write_mtx(&dir.join("Mneg.mtx"), &[(0, 0, 1.0), (1, 1, -1.0)]);
    write_mtx(&dir.join("Mnone.mtx"), &[(0, 0, 1.0), (1, 1, 0.0)]);
    write_mtx(&dir.join("Mzero.mtx"), &[(0, 0, 0.0), (1, 1, 0.0)]);
    let coupled = [(0, 0, 1.0), (0, 1, 1.5), (1, 0, 1.5), (1, 1, 1.0)];
    write_mtx(&dir.join("Mind.mtx"), &coupled);
    let out = dir.join("out");
    for (stiffness, mass, words) in [
        ("K", "Mneg", "Mneg.mtx: the mass of equation 2 is -1e0"),
        ("K", "Mnone", "Mnone.mtx: 1 of 2 equations have no mass"),
        ("K", "Mzero", "Mzero.mtx: the mass matrix is zero"),
        (
            "K",
            "Mind",
            "the 2 x 2 block of the two is not positive definite",
        ),
        ("Kzero", "M", "Kzero.mtx: the stiffness matrix is zero"),
        // Once refused after the solve (its residuals overflowed), now before it.
        ("Kbig", "M6", "Kbig.mtx: its entries reach 1e308"),
    ] {
        let e = failure(&[
            "cea",
            "--stiffness",
            dir.join(format!("{stiffness}.mtx")).to_str().unwrap(),
            "--mass",
            dir.join(format!("{mass}.mtx")).to_str().unwrap(),
            "--fmax",
            "1000",
            "-o",
            out.to_str().unwrap(),
        ]);
        assert!(e.contains(words), "{stiffness} {mass}: {e}");
        assert_eq!(e.matches("squeal: error").count(), 1, "{e}");
        assert!(!out.exists(), "{stiffness} {mass} wrote {}", out.display());
    }
    // The same K with a good M is a result (the control: 318.3 and 477.5 Hz).
    success(
        2,
        &[
            "cea",
            "--stiffness",
            dir.join("K.mtx").to_str().unwrap(),
            "--mass",
            dir.join("M.mtx").to_str().unwrap(),
            "--fmax",
            "1000",
            "-o",
            out.to_str().unwrap(),
        ],
    );
    assert_eq!(eigenvalues(&out).len(), 2);
}

/// Results are whole or absent. A sweep writes into `<output>.partial` and replaces the
/// output only when done: interrupted by Ctrl-C to `mpirun` in its second friction value, it
/// says so (where, and what is left) within seconds on every rank, the previous results in
/// the output folder are untouched (before, new points were mixed with an old sweep.json),
/// and the finished point is whole in the partial folder. An output path that is a file is
/// refused before anything is computed.
#[test]
fn an_interrupted_sweep_leaves_the_previous_results_whole() {
    let dir = scratch("interrupt");
    let out = dir.join("out");
    let o = out.to_str().unwrap();
    success(
        2,
        &[
            "sweep",
            "--preset",
            "tiny",
            "--friction",
            "0.2",
            "--fmax",
            "2000",
            "-o",
            o,
        ],
    );
    let before = std::fs::read(out.join("sweep.json")).unwrap();
    let (job, _session) = common::mpirun_spawn(
        2,
        squeal(),
        &[
            "sweep",
            "--preset",
            "tiny-caliper",
            "--friction",
            "0.1,0.2,0.3",
            "--fmax",
            "3000",
            "-o",
            o,
        ],
    );
    let first = dir.join("out.partial/mu_0.100/cea.json");
    let output = common::interrupt_when(job, &first);
    let status = output.status;
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!status.success(), "{stderr}");
    assert!(stderr.contains("squeal: interrupted by SIG"), "{stderr}");
    assert!(stderr.contains("out is unchanged"), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert_eq!(std::fs::read(out.join("sweep.json")).unwrap(), before);
    assert!(
        !out.join("mu_0.100").exists(),
        "new points mixed with the old results"
    );
    let point: serde_json::Value = serde_json::from_slice(&std::fs::read(&first).unwrap()).unwrap();
    assert!(!point["eigenvalues"].as_array().unwrap().is_empty());

    let file = dir.join("a-file");
    std::fs::write(&file, b"keep me").unwrap();
    let e = failure(&[
        "sweep",
        "--preset",
        "tiny",
        "--friction",
        "0.2",
        "-o",
        file.to_str().unwrap(),
    ]);
    assert!(e.contains("is a file, not a folder"), "{e}");
    assert_eq!(std::fs::read(&file).unwrap(), b"keep me");
    assert!(!dir.join("a-file.partial").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// With no file and no preset, the study is the paper's floating-caliper brake: Table 1's
/// four interfaces (slave = pad side) with their friction and separation flags, the disc's
/// swept, the others Coulomb.
#[test]
fn the_builtin_study_is_the_floating_caliper_brake() {
    let dir = scratch("default-study");
    let file = dir.join("study.toml");
    success(1, &["sweep", "--write-study", file.to_str().unwrap()]);
    let study: toml::Value = toml::from_str(&std::fs::read_to_string(&file).unwrap()).unwrap();
    assert_eq!(study["mesh"]["preset"].as_str(), Some("small-caliper"));
    let contacts = study["contacts"].as_array().unwrap();
    // (name prefix, count, mu, separation, coulomb)
    let table1 = [
        ("disc/pad", 2, 0.5, true, false),
        ("piston/pad", 1, 0.15, false, true),
        ("bracket/pad", 4, 0.15, true, true),
        ("caliper/pad", 1, 0.15, false, true),
    ];
    for (prefix, count, mu, separation, coulomb) in table1 {
        let pairs: Vec<&toml::Value> = contacts
            .iter()
            .filter(|c| c["name"].as_str().unwrap().starts_with(prefix))
            .collect();
        assert_eq!(pairs.len(), count, "{prefix}: {contacts:?}");
        for c in pairs {
            assert_eq!(c["friction"].as_float(), Some(mu), "{c}");
            assert_eq!(c["separation"].as_bool(), Some(separation), "{c}");
            let law = c.get("friction_law").and_then(|l| l.as_str());
            assert_eq!(law == Some("coulomb"), coulomb, "{c}");
            // The disc/pad pairs are the swept ones.
            assert_eq!(c["sweep"].as_bool(), Some(!coulomb), "{c}");
            assert!(
                c["slave"].as_str().unwrap().starts_with("pad_")
                    || c["slave"].as_str().unwrap().starts_with("backplate_"),
                "{c}"
            );
        }
    }
    assert_eq!(contacts.len(), 8);
}

#[test]
fn bad_studies_name_the_file_and_the_key_and_write_nothing() {
    let dir = scratch("bad");
    let out = dir.join("out");
    let study = dir.join("study.toml");
    let builtin = dir.join("builtin.toml");
    success(
        1,
        &[
            "sweep",
            "--preset",
            "tiny",
            "--write-study",
            builtin.to_str().unwrap(),
        ],
    );
    let text = std::fs::read_to_string(&builtin).unwrap();
    // A pair naming a surface that does not exist.
    std::fs::write(
        &study,
        text.replace("pad_inboard_friction_face", "pad_left_face"),
    )
    .unwrap();
    let e = failure(&[
        "sweep",
        study.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(
        e.contains("study.toml") && e.contains("contacts[0].slave") && e.contains("pad_left_face"),
        "{e}"
    );
    // A negative friction coefficient.
    std::fs::write(&study, text.replace("friction = 0.5", "friction = -0.5")).unwrap();
    let e = failure(&[
        "sweep",
        study.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(e.contains("contacts[0].friction"), "{e}");
    // A band with no modes.
    let e = failure(&[
        "sweep",
        "--preset",
        "tiny",
        "--friction",
        "0.5",
        "--fmax",
        "10",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(e.contains("no mode in the band"), "{e}");
    // A solver option PETSc refuses is a set-up error: reported at once, not retried with
    // smaller load steps as if the equilibrium had diverged.
    let e = failure(&[
        "sweep",
        "--preset",
        "tiny",
        "--friction",
        "0.5",
        "-o",
        out.to_str().unwrap(),
        "--petsc-options",
        "-snes_lag_preconditioner -1",
    ]);
    assert!(
        e.contains("snes_lag_preconditioner") || e.contains("lag"),
        "{e}"
    );
    assert!(!e.contains("cutting back"), "{e}");
    assert!(!out.join("sweep.json").exists());
}

/// The modes the stability map outlines as unstable: its black-ringed circles, less the
/// legend's sample.
fn unstable_markers(svg: &str) -> usize {
    svg.split("<circle")
        .skip(1)
        .filter(|c| {
            c.split("/>")
                .next()
                .is_some_and(|c| c.contains("fill=\"none\" stroke=\"#000000\" stroke-width=\"2\""))
        })
        .count()
        .saturating_sub(1)
}

/// "Unstable" is decided once, by the CEA with the study's threshold: with a threshold
/// raised to 1e-2 (a mode must grow by more than 1 % of |lambda| per second), the map
/// outlines exactly the modes the table and sweep.json count, and fewer than at the default
/// 1e-6 (the tiny brake's 3.1 kHz instability at mu 0.6 grows by 0.4 %: unstable at 1e-6,
/// not at 1e-2).
#[test]
fn stability_map_and_table_agree_for_a_non_default_threshold() {
    let dir = scratch("threshold");
    let study = dir.join("study.toml");
    success(
        1,
        &[
            "sweep",
            "--preset",
            "tiny",
            "--write-study",
            study.to_str().unwrap(),
        ],
    );
    let text = std::fs::read_to_string(&study).unwrap();
    let mut counts = Vec::new();
    for threshold in ["0.000001", "0.01"] {
        std::fs::write(
            &study,
            text.replace(
                "unstable_threshold = 0.000001",
                &format!("unstable_threshold = {threshold}"),
            ),
        )
        .unwrap();
        let out = dir.join(format!("out-{threshold}"));
        let run = success(
            2,
            &[
                "sweep",
                study.to_str().unwrap(),
                "--friction",
                "0.6",
                "--fmax",
                "6000",
                "-o",
                out.to_str().unwrap(),
            ],
        );
        let json: serde_json::Value =
            serde_json::from_slice(&std::fs::read(out.join("sweep.json")).unwrap()).unwrap();
        let in_json = common::unstable_modes(&json["points"][0]).len();
        // The table's row for mu 0.60: mu, modes, unstable, ...
        let stdout = String::from_utf8_lossy(&run.stdout);
        let row = stdout
            .lines()
            .find(|l| l.trim_start().starts_with("0.60"))
            .unwrap_or_else(|| panic!("no table row for mu 0.60:\n{stdout}"));
        let in_table: usize = row.split_whitespace().nth(2).unwrap().parse().unwrap();
        let svg = std::fs::read_to_string(out.join("stability_map.svg")).unwrap();
        assert_eq!(in_json, in_table, "threshold {threshold}: {row}");
        assert_eq!(unstable_markers(&svg), in_json, "threshold {threshold}");
        counts.push(in_json);
    }
    assert!(counts[1] < counts[0] && counts[1] > 0, "{counts:?}");
}

/// A reduced interface that cannot be built says which key or node is at fault, on both
/// ranks' behalf once, and writes nothing.
#[test]
fn bad_reductions_name_the_key_or_the_node_and_write_nothing() {
    let dir = scratch("bad-reduction");
    let out = dir.join("out");
    let tiny = |extra: &[&str]| {
        let mut args = vec![
            "sweep",
            "--preset",
            "tiny",
            "--friction",
            "0.5",
            "--fmax",
            "6000",
            "-o",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        failure(&args)
    };
    let e = tiny(&["--contact-nodes-per-pad", "0"]);
    assert!(e.contains("reduction.contact_nodes_per_pad"), "{e}");
    // A radius of influence that catches no pad node (the paper's couplings have one).
    let e = tiny(&[
        "--contact-nodes-per-pad",
        "6",
        "--pad-coupling",
        "distributing",
        "--radius",
        "1e-6",
    ]);
    assert!(
        e.contains("reduced contact node") && e.contains("catches 0 surface node"),
        "{e}"
    );
    // A patch law's quadrature asked for where there is no patch law over a share.
    for other in [["--tilt", "false"], ["--pad-coupling", "distributing"]] {
        let e = tiny(&[
            "--contact-nodes-per-pad",
            "6",
            "--patch-quadrature",
            "area",
            other[0],
            other[1],
        ]);
        assert!(
            e.contains("--patch-quadrature") && e.contains(other[0]),
            "{other:?}: {e}"
        );
    }
    // A reduction with no swept pair to reduce.
    let study = dir.join("study.toml");
    success(
        1,
        &[
            "sweep",
            "--preset",
            "tiny",
            "--write-study",
            study.to_str().unwrap(),
        ],
    );
    let text = std::fs::read_to_string(&study)
        .unwrap()
        .replace("sweep = true", "sweep = false");
    std::fs::write(
        &study,
        format!("{text}\n[reduction]\ncontact_nodes_per_pad = 22\n"),
    )
    .unwrap();
    let e = failure(&[
        "sweep",
        study.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(
        e.contains("study.toml") && e.contains("reduction") && e.contains("sweep = true"),
        "{e}"
    );
    assert!(!out.join("sweep.json").exists());
}

/// `squeal compare` on real sweeps: the tiny brake's full model and its 22-node reduced
/// interface. A sweep compared with itself has no error at all (every instability matched,
/// eqs. 12-14 zero, every contact state agreeing, no pressure difference); the reduced model
/// finds the full model's 5.1 kHz instability within the paper's 2 % (Tables 4-5).
#[test]
fn compare_reads_sweep_folders_and_measures_the_reduced_model() {
    let dir = scratch("compare");
    let sweep = |name: &str, extra: &[&str]| {
        let out = dir.join(name);
        let mut args = vec![
            "sweep",
            "--preset",
            "tiny",
            "--friction",
            "0.3,0.6",
            "--fmax",
            "6000",
            "-o",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        success(2, &args);
        assert!(out.join("mu_0.300/contact.json").is_file());
        out
    };
    let full = sweep("full", &[]);
    let reduced = sweep("reduced", &["--contact-nodes-per-pad", "22"]);
    let out = dir.join("cmp");
    success(
        2,
        &[
            "compare",
            full.to_str().unwrap(),
            full.to_str().unwrap(),
            reduced.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ],
    );
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("compare.json")).unwrap()).unwrap();
    // The reference against itself, an identity check, is said as such.
    let md = std::fs::read_to_string(out.join("compare.md")).unwrap();
    assert!(md.contains("is given twice"), "{md}");
    let full_name = full.to_str().unwrap();
    for i in json["instabilities"].as_array().unwrap() {
        let max = i["max_error"].as_f64();
        if i["model"] == full_name {
            assert!(i["matched"].as_bool().unwrap() && max == Some(0.0), "{i}");
            // The same shapes: MAC 1 to round-off.
            assert!((i["mac"].as_f64().unwrap() - 1.0).abs() < 1e-12, "{i}");
        } else if (i["reference_frequency_hz"].as_f64().unwrap() - 5160.0).abs() < 100.0 {
            assert!(i["matched"].as_bool().unwrap(), "{i}");
            assert!(max.unwrap() < 0.02, "{i}");
        }
    }
    for s in json["statics"].as_array().unwrap() {
        if s["model"] == full_name {
            assert_eq!(s["state_agreement"].as_f64(), Some(1.0), "{s}");
            for (_, l2) in s["pressure_l2"]
                .as_array()
                .unwrap()
                .iter()
                .map(|p| (p[0].clone(), p[1].as_f64().unwrap()))
            {
                assert_eq!(l2, 0.0, "{s}");
            }
        }
    }
    // Every mode of the band paired by frequency: the reference against itself pairs every
    // mode with itself at zero shift; the reduced model's pairs are modes of both sweeps,
    // and its mean and largest shifts are those of its own pairs.
    let spectrum = |folder: &Path, k: usize| -> Vec<f64> {
        let sweep: serde_json::Value =
            serde_json::from_slice(&std::fs::read(folder.join("sweep.json")).unwrap()).unwrap();
        sweep["points"][k]["eigenvalues"]
            .as_array()
            .unwrap()
            .iter()
            .map(|m| m["frequency_hz"].as_f64().unwrap())
            .collect()
    };
    let spectra = json["spectra"].as_array().unwrap();
    assert_eq!(spectra.len(), 4, "two models at two friction values");
    for (n, s) in spectra.iter().enumerate() {
        let k = n % 2;
        let (reference, other) = (
            spectrum(&full, k),
            spectrum(if n < 2 { &full } else { &reduced }, k),
        );
        assert_eq!(s["friction"].as_f64(), Some([0.3, 0.6][k]), "{s}");
        assert_eq!(s["reference_modes"].as_u64(), Some(reference.len() as u64));
        assert_eq!(s["other_modes"].as_u64(), Some(other.len() as u64));
        let pairs: Vec<(f64, f64)> = s["pairs"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| {
                (
                    p["reference_hz"].as_f64().unwrap(),
                    p["other_hz"].as_f64().unwrap(),
                )
            })
            .collect();
        if n < 2 {
            assert_eq!(pairs.len(), reference.len());
            assert!(pairs.iter().all(|p| p.0 == p.1), "{s}");
            assert_eq!(s["mean_relative"].as_f64(), Some(0.0));
        } else {
            assert!(!pairs.is_empty());
            assert!(pairs
                .iter()
                .all(|p| reference.contains(&p.0) && other.contains(&p.1)));
            let shifts: Vec<f64> = pairs.iter().map(|p| ((p.1 - p.0) / p.0).abs()).collect();
            let mean = shifts.iter().sum::<f64>() / shifts.len() as f64;
            assert!(
                (s["mean_relative"].as_f64().unwrap() - mean).abs() < 1e-15,
                "{s}"
            );
            let worst = &s["worst"];
            let largest = shifts.iter().copied().fold(0.0, f64::max);
            let w = (worst["other_hz"].as_f64().unwrap() - worst["reference_hz"].as_f64().unwrap())
                / worst["reference_hz"].as_f64().unwrap();
            assert_eq!(w.abs(), largest, "{s}");
        }
    }
    let md = std::fs::read_to_string(out.join("compare.md")).unwrap();
    assert!(
        md.contains("eqs. 12-14")
            && md.contains("contact states agreeing")
            && md.contains("Every mode of the band"),
        "{md}"
    );
    let svgs = std::fs::read_dir(&out)
        .unwrap()
        .filter(|e| {
            e.as_ref()
                .unwrap()
                .path()
                .extension()
                .is_some_and(|x| x == "svg")
        })
        .count();
    assert!(svgs >= 2, "{svgs} plots");
}

/// The numbers of a sweep that must not depend on the rank count, each with the scale its
/// difference is measured against: every eigenvalue (frequency and real part against
/// |lambda|), and per contact pair the equilibrium's forces, torque, radius, pressures and
/// point counts, and the load balance.
fn rank_independent_numbers(sweep: &serde_json::Value) -> Vec<(String, f64, f64)> {
    let mut out = Vec::new();
    for p in sweep["points"].as_array().unwrap() {
        let mu = p["friction"].as_f64().unwrap();
        for (k, (f, re, _)) in common::eigenvalues_of(p).into_iter().enumerate() {
            let size = (2.0 * std::f64::consts::PI * f).hypot(re);
            out.push((format!("mu {mu}: mode {k} frequency"), f, size));
            out.push((format!("mu {mu}: mode {k} real part"), re, size));
        }
        // The unstable modes' bodies' shares of kinetic energy (fractions) and their pairs'
        // parts of the growth rate (1/s, against the mode's |lambda|).
        for (k, m) in p["eigenvalues"].as_array().unwrap().iter().enumerate() {
            for (body, share) in m["body_shares"].as_object().into_iter().flatten() {
                let v = share.as_f64().unwrap();
                out.push((format!("mu {mu}: mode {k} {body} share"), v, 1.0));
            }
            let size = (2.0 * std::f64::consts::PI * m["frequency_hz"].as_f64().unwrap())
                .hypot(m["real_part"].as_f64().unwrap());
            for (pair, rate) in m["pair_growth"].as_object().into_iter().flatten() {
                let v = rate.as_f64().unwrap();
                out.push((format!("mu {mu}: mode {k} {pair} growth"), v, size));
            }
        }
        for pair in p["contact"].as_array().unwrap() {
            for key in [
                "normal_force",
                "friction_force",
                "braking_torque",
                "effective_radius",
                "pressure_min",
                "pressure_max",
                "pressure_mean",
                "closed",
                "slip",
                "stick",
            ] {
                let v = pair[key].as_f64().unwrap();
                out.push((format!("mu {mu}: {} {key}", pair["name"]), v, v.abs()));
            }
        }
        let balance = p["balance_ratio"].as_f64().unwrap();
        out.push((format!("mu {mu}: balance_ratio"), balance, 1.0));
    }
    out
}

/// The same sweep of the tiny brake on 1, 2, 3 and 4 ranks (oversubscribed on 2 cores):
/// the node blocks, ownership ranges and reductions change with the rank count, the numbers
/// must not. Measured: 1.3e-12 at worst (a pad's smallest contact pressure, 3 ranks).
#[test]
fn a_sweep_gives_the_same_numbers_on_one_to_four_ranks() {
    let dir = scratch("ranks");
    let mut runs = Vec::new();
    for ranks in 1..=4 {
        let out = dir.join(format!("n{ranks}"));
        success(
            ranks,
            &[
                "sweep",
                "--preset",
                "tiny",
                "--friction",
                "0.2,0.6",
                "--fmax",
                "6000",
                "-o",
                out.to_str().unwrap(),
            ],
        );
        let json: serde_json::Value =
            serde_json::from_slice(&std::fs::read(out.join("sweep.json")).unwrap()).unwrap();
        runs.push((ranks, rank_independent_numbers(&json)));
    }
    let (_, one) = &runs[0];
    assert!(
        one.iter().any(|(what, _, _)| what.contains("mode")),
        "{one:?}"
    );
    // Every unstable mode says where its kinetic energy is: in every body of the brake (disc,
    // two pads' friction material and back plates), the shares summing to 1.
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("n1").join("sweep.json")).unwrap()).unwrap();
    let mut unstable = 0;
    for p in json["points"].as_array().unwrap() {
        // Where each is fed, drawn on the pad faces: one field per unstable mode.
        let vtu = dir
            .join("n1")
            .join(format!("mu_{:.3}", p["friction"].as_f64().unwrap()))
            .join("cea.vtu");
        let drawn = std::fs::read_to_string(&vtu)
            .unwrap()
            .matches("_feed\"")
            .count();
        let flagged = common::unstable_modes(p).len();
        assert_eq!(drawn, flagged, "{}", vtu.display());
        for m in p["eigenvalues"].as_array().unwrap() {
            if m["unstable"] != serde_json::Value::Bool(true) {
                assert!(m.get("body_shares").is_none(), "{m}");
                continue;
            }
            unstable += 1;
            let shares = m["body_shares"]
                .as_object()
                .expect("an unstable mode's body shares");
            assert!(shares.len() >= 3, "{m}");
            let sum: f64 = shares.values().map(|v| v.as_f64().unwrap()).sum();
            assert!((sum - 1.0).abs() <= 1e-9, "{m}: the shares sum to {sum}");
            assert!(shares.values().all(|v| v.as_f64().unwrap() >= 0.0), "{m}");
            // The pairs' parts of the growth rate add up to the CEA's real part: an identity
            // of the eigenpair (analysis/growth.rs), exact but for Im(x^H r) / (2 omega m),
            // r = K_t x - omega^2 M x the computed pair's residual vector. The CEA accepts a
            // pair at a relative residual up to 1e-6, so that is the level asserted, against
            // |lambda| (measured: 1e-11 of |lambda|, 1e-10 of a; reduced interfaces alike).
            let growth = m["pair_growth"]
                .as_object()
                .expect("the pairs' growth rates");
            let sum: f64 = growth.values().map(|v| v.as_f64().unwrap()).sum();
            let (f, a) = (
                m["frequency_hz"].as_f64().unwrap(),
                m["real_part"].as_f64().unwrap(),
            );
            let size = (2.0 * std::f64::consts::PI * f).hypot(a);
            assert!(
                (sum - a).abs() <= 1e-6 * size,
                "{m}: the pairs add up to {sum} 1/s"
            );
            let pair_shares = m["pair_shares"].as_object().unwrap();
            assert!(pair_shares.len() >= 2, "{m}");
            let total: f64 = pair_shares.values().map(|v| v.as_f64().unwrap()).sum();
            assert!(
                (total - 1.0).abs() <= 1e-9,
                "{m}: the pair shares sum to {total}"
            );
        }
    }
    assert!(unstable > 0, "no unstable mode to check");
    for (ranks, other) in &runs[1..] {
        let names = |r: &[(String, f64, f64)]| r.iter().map(|x| x.0.clone()).collect::<Vec<_>>();
        assert_eq!(names(one), names(other), "1 rank vs {ranks}");
        for ((what, a, scale), (_, b, _)) in one.iter().zip(other) {
            let relative = (a - b).abs() / scale.max(1e-300);
            assert!(
                relative <= 1e-8,
                "{what}: {a} on 1 rank, {b} on {ranks} ({relative:e})"
            );
        }
    }
}

/// A reduced interface's tie springs (1e12-1e13 N/m on mesh nodes of small consistent mass)
/// raise the largest K_ii / M_ii, and with it the round-off level under which eigenvalues
/// were called rigid, into the band: `small-caliper` with 22 nodes per pad had its 372 and
/// 519 Hz modes flagged rigid (medium-caliper with 52, 430-730 Hz, one pair growing at +150
/// to +394 1/s and not flagged unstable). Every body of a sweep's model is held (the static
/// proves it), so no mode is rigid, and each mode's flag is its real part's verdict.
/// A held model's modes in sweep.json: none called rigid, each `unstable` flag the verdict
/// of its own real part at the default threshold.
fn held_modes_flagged_by_their_real_parts(modes: &[serde_json::Value]) {
    for m in modes {
        let (f, re) = (
            m["frequency_hz"].as_f64().unwrap(),
            m["real_part"].as_f64().unwrap(),
        );
        assert_eq!(m["rigid_body"], false, "{f} Hz called rigid");
        let lambda = Complex64::new(re, 2.0 * std::f64::consts::PI * f);
        assert_eq!(
            m["unstable"].as_bool().unwrap(),
            squeal::analysis::cea::is_unstable(lambda, 1e-6),
            "{f} Hz, real part {re}"
        );
    }
}

#[test]
fn a_held_reduced_interface_model_has_no_rigid_modes() {
    let out = scratch("held-reduced");
    let dir = out.to_str().unwrap();
    success(
        2,
        &[
            "sweep",
            "--preset",
            "small-caliper",
            "--contact-nodes-per-pad",
            "22",
            "--friction",
            "0.5",
            // The modes once called rigid, and the pair that grows, lie below 2.5 kHz (15
            // modes; the default 10 kHz band doubled the test's time for no other check).
            "--fmax",
            "2500",
            "-o",
            dir,
            "-q",
        ],
    );
    let sweep: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("sweep.json")).unwrap()).unwrap();
    let modes = sweep["points"][0]["eigenvalues"].as_array().unwrap();
    assert!(modes.len() >= 15, "{} modes", modes.len());
    let frequency = |m: &serde_json::Value| m["frequency_hz"].as_f64().unwrap();
    // The two lowest: 372 and 519 Hz when the CEA's tangent was the first point's ramp's
    // (its last load increment's); 383 and 546 Hz from the committed slip history, as every
    // later point has them (contact::perturbation_history).
    for f in [383.0, 546.0] {
        assert!(
            modes.iter().any(|m| (frequency(m) - f).abs() < 10.0),
            "no mode near {f} Hz"
        );
    }
    held_modes_flagged_by_their_real_parts(modes);
    let _ = std::fs::remove_dir_all(&out);
}

/// Every pair of the floating caliper reduced (issue 32's first step): a full-size model like
/// the others that sweeps past mu 0.6, where ties 1000 times the kept pairs' steel contact
/// stiffness once stalled Newton on its round-off floor and left the CEA's residuals above
/// its bound. Each kept pair is reduced to its grid (the model names the counts), its
/// contact points are the reduced nodes, and each mode's flags are its real part's verdict.
#[test]
fn every_pair_reduced_is_a_model_that_sweeps_past_its_stiff_ties() {
    let out = scratch("every-pair-reduced");
    let dir = out.to_str().unwrap();
    success(
        2,
        &[
            "sweep",
            "--preset",
            "tiny-caliper",
            "--contact-nodes-per-pad",
            "22",
            "--reduce-pairs",
            "all",
            "--friction",
            "0.3,0.6",
            "--fmax",
            "3000",
            "-o",
            dir,
            "-q",
        ],
    );
    let sweep: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("sweep.json")).unwrap()).unwrap();
    let source = sweep["model"]["source"].as_str().unwrap();
    assert!(
        source.contains("22 nodes + 22 nodes + 2 nodes + 19 nodes + 3 nodes"),
        "{source}"
    );
    let points = sweep["points"].as_array().unwrap();
    assert_eq!(points.len(), 2);
    // From rest every gap is zero and the problem is positively homogeneous in the load
    // (the residuals of each cut-back were exactly half the last's), so a cut-back cannot
    // help: Newton must get there at the full load. It once did only by the round-off of
    // one BLAS kernel, when GMRES around a kept factorisation reaching its limit ended
    // Newton (2026-12-07).
    assert_eq!(points[0]["cutbacks"].as_u64(), Some(0), "{}", points[0]);
    for point in points {
        let modes = point["eigenvalues"].as_array().unwrap();
        assert!(modes.len() >= 15, "{} modes", modes.len());
        held_modes_flagged_by_their_real_parts(modes);
    }
    // Each pair's contact points are its reduced nodes, the kept ones' too.
    let counts: Vec<(String, u64)> = points[1]["contact"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| {
            (
                c["name"].as_str().unwrap().to_string(),
                c["points"].as_u64().unwrap(),
            )
        })
        .collect();
    let count = |name: &str| counts.iter().find(|(n, _)| n == name).map(|c| c.1);
    assert_eq!(count("disc/pad inboard"), Some(22), "{counts:?}");
    assert_eq!(count("piston/pad"), Some(2), "{counts:?}");
    assert_eq!(count("caliper/pad"), Some(19), "{counts:?}");
    assert_eq!(
        count("bracket/pad outboard trailing"),
        Some(3),
        "{counts:?}"
    );
    let _ = std::fs::remove_dir_all(&out);
}

/// `--contact-edge-points 4` on tiny-caliper without friction (0-1000 Hz: five modes, 7 % or
/// more apart): four of the full model's disc/pad points opened and four closed at the
/// point, each mode's nearest eigenvalue recorded. Closing points adds stiffness of rank one
/// each and opening takes it away, so (Weyl) every frequency rises or stays with the points
/// closed and falls or stays with them opened; the modes being further apart than any such
/// change, the nearest is the same mode. 1 and 2 ranks give the same eigenvalues.
#[test]
fn the_contact_edge_check_moves_each_mode_the_way_the_stiffness_goes() {
    let dir = scratch("contact-edge");
    let mut runs = Vec::new();
    for ranks in [1, 2].into_iter().filter(|&r| common::ranks_wanted(r)) {
        let out = dir.join(format!("ranks{ranks}"));
        let o = common::mpirun(
            ranks,
            squeal(),
            &[
                "-q",
                "sweep",
                "--preset",
                "tiny-caliper",
                "--friction",
                "0",
                "--fmax",
                "1000",
                "--contact-edge-points",
                "4",
                "-o",
                out.to_str().unwrap(),
            ],
        );
        assert!(o.status.success(), "{}", common::text(&o));
        let doc: squeal::results::SweepDocument =
            squeal::results::read_document(&out.join("sweep.json")).unwrap();
        runs.push(doc.points[0].clone());
    }
    for point in &runs {
        let edge = point
            .contact_edge
            .as_ref()
            .expect("the edge check was asked for");
        assert_eq!((edge.points, edge.opened, edge.closed), (4, 4, 4));
        assert_eq!(point.eigenvalues.len(), 5, "{:?}", point.eigenvalues);
        let mut moved = 0.0_f64;
        for (i, m) in point.eigenvalues.iter().enumerate() {
            let (open, shut) = (&edge.with_opened[i], &edge.with_closed[i]);
            // The geometric part of the contact tangent (force over face size) is not
            // rank-one: 1e-4 of omega^2, 5e-5 of the frequency, covers it.
            let slack = 5e-5 * m.frequency_hz;
            assert!(
                open.frequency_hz <= m.frequency_hz + slack,
                "{m:?} {open:?}"
            );
            assert!(
                shut.frequency_hz >= m.frequency_hz - slack,
                "{m:?} {shut:?}"
            );
            moved = moved.max(edge.frequency_change(i, m));
        }
        // Something moved: the check is not the unchanged model's CEA again.
        assert!(moved > 1e-4, "{moved}");
    }
    if let [one, two] = &runs[..] {
        let (a, b) = (
            one.contact_edge.as_ref().unwrap(),
            two.contact_edge.as_ref().unwrap(),
        );
        for (x, y) in a
            .with_opened
            .iter()
            .chain(&a.with_closed)
            .zip(b.with_opened.iter().chain(&b.with_closed))
        {
            assert!(
                (x.lambda - y.lambda).norm() <= 1e-9 * x.lambda.norm(),
                "{x:?} {y:?}"
            );
        }
    }
}

/// A sweep's first point (the load ramped from rest) and the next (a friction step from it)
/// stand on the same kind of tangent: the Coulomb pairs' points that slip are evaluated from
/// their committed slip history, with the full stick stiffness across their slip direction,
/// whatever the last increment was (`contact::perturbation_history`). From the last
/// increment's history instead, tiny-caliper at mu 0.599 (first, ramped) and 0.6 (a step of
/// 0.001) had their lowest modes at 376 and 393 Hz, and one instability at 665 Hz against
/// 707 Hz; now 394 and 393 Hz, 710 and 709 Hz. A friction step of 0.001 moves these modes
/// by about 0.1 %: every mode within 1 %, and the same flags.
#[test]
fn a_sweeps_first_point_agrees_with_the_next() {
    let out = scratch("first-point");
    let dir = out.to_str().unwrap();
    success(
        2,
        &[
            "sweep",
            "--preset",
            "tiny-caliper",
            "--friction",
            "0.599,0.6",
            "--fmax",
            "1000",
            "-o",
            dir,
            "-q",
        ],
    );
    let sweep: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("sweep.json")).unwrap()).unwrap();
    let points = sweep["points"].as_array().unwrap();
    let (first, next) = (
        common::eigenvalues_of(&points[0]),
        common::eigenvalues_of(&points[1]),
    );
    assert_eq!(first.len(), next.len(), "{first:?}\n{next:?}");
    assert!(first.len() >= 5, "{first:?}");
    for (a, b) in first.iter().zip(&next) {
        assert!((a.0 - b.0).abs() < 1e-2 * b.0, "{a:?} against {b:?}");
        assert_eq!(a.2, b.2, "{a:?} against {b:?}");
    }
    assert!(next.iter().any(|m| m.2), "the 709 Hz instability: {next:?}");
    let _ = std::fs::remove_dir_all(&out);
}

/// `--contributions-of-every-mode`: every mode of a full-size model carries its bodies'
/// shares (summing to 1) and its pairs' parts of the growth rate, which add up to its real
/// part (the identity of an eigenpair: measured 7e-16 of |lambda|, asked 1e-6, the CEA's
/// acceptance of a pair's relative residual); pair shares only where the real part is not
/// zero to the unstable threshold (an unstable mode and its coupled partner, whose parts
/// are the same with the sign turned). Without the flag, the stable modes carry none.
#[test]
fn contributions_of_every_mode_add_up_to_each_real_part() {
    let run = |extra: &[&str], name: &str| -> Vec<serde_json::Value> {
        let out = scratch(name);
        let mut args = vec![
            "sweep",
            "--preset",
            "tiny",
            "--friction",
            "0.6",
            "--fmax",
            "6000",
            "-q",
            "-o",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        success(2, &args);
        let json: serde_json::Value =
            serde_json::from_slice(&std::fs::read(out.join("sweep.json")).unwrap()).unwrap();
        json["points"][0]["eigenvalues"].as_array().unwrap().clone()
    };
    let every = run(&["--contributions-of-every-mode"], "every-mode");
    let mut partners = 0;
    for m in &every {
        let (f, re, lambda) = common::lambda_of(m);
        let bodies = common::sum_of(&m["body_shares"]);
        assert!(
            (bodies - 1.0).abs() < 1e-9,
            "{f} Hz: body shares sum to {bodies}"
        );
        let growth = common::sum_of(&m["pair_growth"]);
        assert!(
            (growth - re).abs() <= 1e-6 * lambda,
            "{f} Hz: parts {growth} against the real part {re}"
        );
        let coupled = re.abs() > 1e-6 * lambda;
        assert_eq!(m["pair_shares"].is_object(), coupled, "{f} Hz: {m}");
        partners += usize::from(coupled && !m["unstable"].as_bool().unwrap());
    }
    assert!(
        partners >= 2,
        "the coupled pairs' stable partners: {partners}"
    );
    let unstable_only = run(&[], "unstable-only");
    assert_eq!(unstable_only.len(), every.len());
    for m in &unstable_only {
        assert_eq!(
            m["body_shares"].is_object(),
            m["unstable"].as_bool().unwrap(),
            "{m}"
        );
    }
}

/// `-squeal_cea_count` other than 0 or 1 is refused by name with nothing written, on every
/// rank at once: given to both ranks, and given to rank 0 alone through its own
/// `PETSC_OPTIONS` (rank 0 reads the option, so rank 1 must fail too instead of waiting).
#[test]
fn a_band_count_switch_other_than_0_or_1_is_refused_on_every_rank() {
    let o = scratch("count-refused").join("out");
    let mut args = vec![
        "sweep",
        "--preset",
        "tiny",
        "--friction",
        "0.6",
        "--fmax",
        "6000",
    ];
    args.extend(["-o", o.to_str().unwrap()]);
    let mut asked = args.clone();
    asked.extend(["--petsc-options", "-squeal_cea_count yes"]);
    let e = failure(&asked);
    assert!(
        e.contains("-squeal_cea_count yes: 0 or 1 was expected"),
        "{e}"
    );
    assert!(!o.exists(), "a refused run wrote {}", o.display());
    let bad: &[(&str, &str)] = &[("PETSC_OPTIONS", "-squeal_cea_count yes")];
    let run = common::mpirun_per_rank(squeal(), &args, &[bad, &[]]);
    assert!(!common::hung(&run), "{}", common::text(&run));
    assert!(!run.status.success(), "{}", common::text(&run));
    assert!(common::text(&run).contains("-squeal_cea_count yes"));
    assert!(!o.exists(), "a refused run wrote {}", o.display());
}
