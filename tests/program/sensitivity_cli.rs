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
    let modes = |k: usize| points[k]["eigenvalues"].as_array().unwrap().clone();
    let nearest = |k: usize, f: f64| {
        modes(k)
            .into_iter()
            .filter(|m| m["unstable"].as_bool().unwrap())
            .min_by(|a, b| {
                let d = |m: &serde_json::Value| (m["frequency_hz"].as_f64().unwrap() - f).abs();
                d(a).total_cmp(&d(b))
            })
            .unwrap()
    };
    let mut out = Vec::new();
    for m in modes(1).iter().filter(|m| m["unstable"].as_bool().unwrap()) {
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
            m.get("sensitivity").is_none() && m.get("left_residual").is_none(),
            "{m}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}
