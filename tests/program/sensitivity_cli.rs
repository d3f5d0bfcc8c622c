//! The unstable modes' friction sensitivities in `sweep.json`, against the sweep's own
//! central differences, on 1 and 2 ranks (issue 33).

use crate::common;

use std::path::{Path, PathBuf};

fn squeal() -> &'static Path {
    Path::new(env!("CARGO_BIN_EXE_squeal"))
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("squeal-sens-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The sweep of `preset` at mu 0.6 - h, 0.6, 0.6 + h (0-6 kHz) on `ranks` ranks.
fn sweep(dir: &Path, ranks: usize, h: f64, extra: &[&str]) -> serde_json::Value {
    let friction = format!("{},0.6,{}", 0.6 - h, 0.6 + h);
    let mut args = vec![
        "sweep",
        "--friction",
        friction.as_str(),
        "--fmax",
        "6000",
        "-q",
        "-o",
        dir.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let run = common::mpirun(ranks, squeal(), &args);
    assert!(run.status.success(), "{}", common::text(&run));
    serde_json::from_slice(&std::fs::read(dir.join("sweep.json")).unwrap()).unwrap()
}

/// Each unstable mode at mu 0.6: (frequency, d Re/dmu, d f/dmu, the central differences of
/// the neighbouring points' nearest unstable modes).
fn checked(json: &serde_json::Value, h: f64) -> Vec<[f64; 5]> {
    let points = json["points"].as_array().unwrap();
    let nearest = |k: usize, f: f64| {
        common::unstable_modes(&points[k])
            .into_iter()
            .min_by(|a, b| {
                let d = |m: &serde_json::Value| (m["frequency_hz"].as_f64().unwrap() - f).abs();
                d(a).total_cmp(&d(b))
            })
            .unwrap()
    };
    let mut out = Vec::new();
    for m in &common::unstable_modes(&points[1]) {
        let f = m["frequency_hz"].as_f64().unwrap();
        let s = &m["sensitivity"];
        assert!(s.is_object(), "{f} Hz has no sensitivity: {m}");
        assert_eq!(s["one_sided"], false, "{f} Hz: {s}");
        let left = m["left_residual"].as_f64().unwrap();
        assert!(
            left < 1e-6,
            "{f} Hz: left eigenvector's backward error {left:e}"
        );
        for key in ["pair_shares", "body_shares"] {
            let sum: f64 = m[key]
                .as_object()
                .unwrap()
                .values()
                .map(|v| v.as_f64().unwrap())
                .sum();
            assert!((sum - 1.0).abs() < 1e-9, "{f} Hz: {key} sum to {sum}");
        }
        let (a, b) = (nearest(0, f), nearest(2, f));
        let difference =
            |key: &str| (b[key].as_f64().unwrap() - a[key].as_f64().unwrap()) / (2.0 * h);
        out.push([
            f,
            s["d_real_part_d_mu"].as_f64().unwrap(),
            s["d_frequency_hz_d_mu"].as_f64().unwrap(),
            difference("real_part"),
            difference("frequency_hz"),
        ]);
    }
    out
}

/// [`checked`]'s rows, each derivative within 1e-3 of its modulus of the central
/// differences (d lambda/dmu as a complex number: the real part's and 2 pi times the
/// frequency's).
fn agreeing(json: &serde_json::Value, h: f64) -> Vec<[f64; 5]> {
    let rows = checked(json, h);
    assert!(rows.len() >= 2, "{rows:?}");
    for [f, d_re, d_f, cd_re, cd_f] in &rows {
        let scale = d_re.hypot(2.0 * std::f64::consts::PI * d_f);
        assert!(
            (d_re - cd_re).abs() < 1e-3 * scale,
            "{f} Hz: {d_re} against {cd_re}"
        );
        let df = 2.0 * std::f64::consts::PI * (d_f - cd_f);
        assert!(df.abs() < 1e-3 * scale, "{f} Hz: {d_f} against {cd_f}");
    }
    rows
}

/// The spring-held brake (every contact swept; linear penalty, steady sliding: the tangent
/// is affine in mu between state changes), mu 0.599/0.6/0.601: each unstable mode's
/// d Re(lambda)/dmu and d f/dmu against the central difference of the neighbouring points.
/// Measured: 606.322 against 606.337 1/s and 30.9392 against 30.9392 Hz (3101.8 Hz), 909.779
/// against 909.779 (5159.8 Hz): the central difference's own error, h^2 lambda'''/6, is the
/// 2.5e-5; 1e-3 of the derivative's modulus leaves it room and still fails a derivative that
/// misses a term (the equilibrium's, the left vector's conjugate: tens of per cent). One
/// and two ranks agree to 3e-8 (MUMPS's orderings differ): 1e-6.
#[test]
fn sensitivities_match_the_sweeps_central_differences_on_one_and_two_ranks() {
    let h = 1e-3;
    let mut by_ranks = Vec::new();
    for ranks in [2, 1] {
        let dir = scratch(&format!("tiny-{ranks}"));
        let json = sweep(&dir, ranks, h, &["--preset", "tiny"]);
        let rows = agreeing(&json, h);
        by_ranks.push(rows);
        let _ = std::fs::remove_dir_all(&dir);
    }
    for (a, b) in by_ranks[0].iter().zip(&by_ranks[1]) {
        for k in 1..3 {
            assert!(
                (a[k] - b[k]).abs() <= 1e-6 * a[k].abs(),
                "{a:?} against {b:?}"
            );
        }
    }
}

/// A reduced interface's patch laws are piecewise linear (each share's quadrature points
/// open and close one by one), so the sweep's differences over 1e-3 or 1e-4 straddle their
/// kinks (5160 Hz: d f/dmu 27.14 Hz, differences -7.5 and -80 Hz); over 1e-5 none is
/// crossed and they agree to 1e-5 (504.541 against 504.543 1/s, 27.1409 against 27.1409
/// Hz). The floating caliper's kept pairs slip, and it gets no sensitivity at all
/// (`analysis::sensitivity`: its eigenvalues follow the slip directions).
#[test]
fn a_reduced_interface_matches_over_a_step_without_kinks_and_the_caliper_has_none() {
    let h = 1e-5;
    let dir = scratch("tiny-22");
    let json = sweep(
        &dir,
        2,
        h,
        &["--preset", "tiny", "--contact-nodes-per-pad", "22"],
    );
    agreeing(&json, h);
    // The reduction's stiffnesses follow the lining's modulus unseen: no moduli's
    // sensitivities there (the lining's was 10-20 % off the central difference).
    for m in json["points"][1]["eigenvalues"].as_array().unwrap() {
        assert!(m.get("modulus_sensitivity").is_none(), "{m}");
    }
    let _ = std::fs::remove_dir_all(&dir);

    let dir = scratch("caliper");
    let friction = "0.6";
    let run = common::mpirun(
        2,
        squeal(),
        &[
            "sweep",
            "--preset",
            "tiny-caliper",
            "--friction",
            friction,
            "--fmax",
            "1000",
            "-q",
            "-o",
            dir.to_str().unwrap(),
        ],
    );
    assert!(run.status.success(), "{}", common::text(&run));
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("sweep.json")).unwrap()).unwrap();
    let modes = json["points"][0]["eigenvalues"].as_array().unwrap();
    assert!(modes.iter().any(|m| m["unstable"].as_bool().unwrap()));
    for m in modes {
        assert!(
            m.get("sensitivity").is_none()
                && m.get("left_residual").is_none()
                && m.get("modulus_sensitivity").is_none(),
            "{m}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// examples/tiny-study.toml (the spring-held `tiny` brake) without its comparison plan and
/// reduction, writing to `out`, with `part`'s Young's modulus `young` (its preset material's
/// Poisson's ratio and density kept).
fn tiny_study_with(out: &Path, part: &str, young: f64, poisson: f64, density: f64) -> String {
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/tiny-study.toml"),
    )
    .unwrap();
    let mut kept = Vec::new();
    let mut skipping = false;
    for line in text.lines() {
        if line.starts_with('[') {
            skipping = matches!(line.trim(), "[comparison]" | "[reduction]");
        }
        if skipping || line.starts_with("materials = []") || line.starts_with("output =") {
            continue;
        }
        kept.push(line);
    }
    format!(
        "output = {out:?}\n{}\n[[materials]]\npart = \"{part}\"\nyoung = {young:?}\n\
         poisson = {poisson:?}\ndensity = {density:?}\n",
        kept.join("\n")
    )
}

/// The unstable modes of the one point of a sweep of `study` at mu 0.6, 0-6 kHz.
fn unstable_at_06(dir: &Path, name: &str, study: &str, ranks: usize) -> Vec<serde_json::Value> {
    let file = dir.join(format!("{name}.toml"));
    std::fs::write(&file, study).unwrap();
    let args = [
        "sweep",
        file.to_str().unwrap(),
        "--friction",
        "0.6",
        "--fmax",
        "6000",
        "-q",
    ];
    let run = common::mpirun(ranks, squeal(), &args);
    assert!(run.status.success(), "{}", common::text(&run));
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join(name).join("sweep.json")).unwrap()).unwrap();
    common::unstable_modes(&json["points"][0])
}

/// Each unstable mode's sensitivity to a body's Young's modulus (per unit of ln E, in
/// sweep.json) against the central difference of sweeps with that body's E scaled by
/// 1 -/+ 1e-4 (the spring-held `tiny`, mu 0.6), for the disc and an inboard pad's lining.
/// Measured on the disc: 8422.76 against 8423.30 1/s and 750.7954 against 750.7958 Hz
/// (3101.8 Hz, whose pair is near coalescence: with steps of 1e-3 the difference is 8478.3,
/// its h^2 error); 579.52689 against 579.52689 (5159.8 Hz). On the lining -17.359215
/// against -17.359219 1/s and -103.21449 against -103.21449 (5159.8 Hz): the disc/pad
/// pair's default penalty is 10 E / h of the lining, so the lining's modulus moves the
/// contact stiffness too (without that term: -19.47 against -17.36). Asked 1e-3 of the
/// derivative's modulus; 1 and 2 ranks 1e-6.
#[test]
fn modulus_sensitivities_match_central_differences_of_the_bodies_moduli() {
    let h = 1e-4;
    let dir = scratch("modulus");
    // (part, E, nu, density) of the preset's materials.
    let bodies = [
        ("disc", 125e9, 0.25, 7200.0),
        ("pad_inboard_friction", 8e9, 0.25, 2500.0),
    ];
    let (part, e, nu, rho) = bodies[0];
    let base2 = unstable_at_06(
        &dir,
        "base2",
        &tiny_study_with(&dir.join("base2"), part, e, nu, rho),
        2,
    );
    let base1 = unstable_at_06(
        &dir,
        "base1",
        &tiny_study_with(&dir.join("base1"), part, e, nu, rho),
        1,
    );
    assert!(base2.len() >= 2, "{base2:?}");
    for (part, e, nu, rho) in bodies {
        let at = |sign: f64| {
            let name = format!("{part}-{}", if sign > 0.0 { "up" } else { "down" });
            let study = tiny_study_with(&dir.join(&name), part, e * (1.0 + sign * h), nu, rho);
            unstable_at_06(&dir, &name, &study, 2)
        };
        let (down, up) = (at(-1.0), at(1.0));
        for m in &base2 {
            let f = m["frequency_hz"].as_f64().unwrap();
            let nearest = |set: &[serde_json::Value]| {
                set.iter()
                    .min_by(|a, b| {
                        let d =
                            |x: &serde_json::Value| (x["frequency_hz"].as_f64().unwrap() - f).abs();
                        d(a).total_cmp(&d(b))
                    })
                    .unwrap()
                    .clone()
            };
            let (a, b) = (nearest(&down), nearest(&up));
            let difference =
                |key: &str| (b[key].as_f64().unwrap() - a[key].as_f64().unwrap()) / (2.0 * h);
            let s = &m["modulus_sensitivity"][part];
            assert!(s.is_object(), "{f} Hz: no sensitivity to {part}: {m}");
            assert_eq!(s["one_sided"], false, "{f} Hz: {s}");
            let d_re = s["d_real_part_d_ln_young"].as_f64().unwrap();
            let d_f = s["d_frequency_hz_d_ln_young"].as_f64().unwrap();
            let scale = d_re.hypot(2.0 * std::f64::consts::PI * d_f);
            let (cd_re, cd_f) = (difference("real_part"), difference("frequency_hz"));
            assert!(
                (d_re - cd_re).abs() < 1e-3 * scale,
                "{f} Hz, {part}: d Re {d_re} against {cd_re}"
            );
            assert!(
                (2.0 * std::f64::consts::PI * (d_f - cd_f)).abs() < 1e-3 * scale,
                "{f} Hz, {part}: d f {d_f} against {cd_f}"
            );
        }
    }
    // Every body has one, and 1 rank gives what 2 give.
    for (one, two) in base1.iter().zip(&base2) {
        let (a, b) = (&one["modulus_sensitivity"], &two["modulus_sensitivity"]);
        assert_eq!(a.as_object().unwrap().len(), 5, "{a}");
        for (body, sa) in a.as_object().unwrap() {
            for key in ["d_real_part_d_ln_young", "d_frequency_hz_d_ln_young"] {
                let (x, y) = (sa[key].as_f64().unwrap(), b[body][key].as_f64().unwrap());
                assert!(
                    (x - y).abs() <= 1e-6 * x.abs().max(1.0),
                    "{body} {key}: {x} {y}"
                );
            }
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}
