//! The `squeal` binary run as a user runs it: under `mpirun -n 2`.

use crate::common;

use std::path::Path;

fn squeal() -> &'static Path {
    Path::new(env!("CARGO_BIN_EXE_squeal"))
}

#[test]
fn info_under_two_ranks_shows_both_ranks_and_the_solvers() {
    let out = common::mpirun(2, squeal(), &["info"]);
    assert!(out.status.success(), "{}", common::text(&out));
    let stdout = String::from_utf8_lossy(&out.stdout);
    // Rank 0 prints once, with each rank's own line.
    assert_eq!(stdout.matches("squeal ").count(), 1, "{stdout}");
    assert!(stdout.contains("MPI ranks    2"), "{stdout}");
    assert!(stdout.contains("rank 0 on "), "{stdout}");
    assert!(stdout.contains("rank 1 on "), "{stdout}");
    assert!(
        stdout.contains("PETSc        Petsc Release Version 3."),
        "{stdout}"
    );
    assert!(stdout.contains("mumps"), "{stdout}");
    assert!(stdout.contains("32-bit indices") || stdout.contains("64-bit indices"));
}

#[test]
fn info_json_is_valid() {
    let out = common::mpirun(1, squeal(), &["info", "--json"]);
    assert!(out.status.success(), "{}", common::text(&out));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    assert_eq!(v["ranks"], 1);
    assert_eq!(v["scalar"], "real double");
}

#[test]
fn petsc_options_reach_petsc_and_not_clap() {
    // -options_left makes PETSc report options nobody used: ours must arrive at PETSc.
    let out = common::mpirun(
        1,
        squeal(),
        &[
            "info",
            "--petsc-options",
            "-squeal_test_option 1 -options_left",
        ],
    );
    assert!(out.status.success(), "{}", common::text(&out));
    let all = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(all.contains("squeal_test_option"), "{all}");
}

#[test]
fn unknown_subcommand_is_a_clear_error_on_every_rank() {
    let out = common::mpirun(2, squeal(), &["no-such-command"]);
    assert!(!out.status.success());
    assert!(!common::hung(&out));
    assert!(String::from_utf8_lossy(&out.stderr).contains("unrecognized subcommand"));
}

#[test]
fn radius_runs_without_mpirun_and_prints_both_radii_per_degree() {
    // No mpirun and no runtime: the table is pure computation.
    let out = std::process::Command::new(squeal())
        .args(["radius", "--json"])
        .output()
        .expect("run squeal radius");
    assert!(out.status.success(), "{}", common::text(&out));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    let degrees = v["degrees"].as_array().expect("degrees");
    assert_eq!(degrees.len(), 3);
    for (d, paper) in degrees.iter().zip([0.9104, 0.7425, 0.9596]) {
        let r = d["paper_radius"].as_f64().unwrap();
        assert!((r - paper).abs() < 1e-3, "{d}");
        for key in ["paper_mean", "paper_std", "grid_radius", "grid_std"] {
            assert!(d[key].as_f64().is_some_and(f64::is_finite), "{key} in {d}");
        }
    }
    let text = std::process::Command::new(squeal())
        .arg("radius")
        .output()
        .expect("run squeal radius");
    assert!(String::from_utf8_lossy(&text.stdout).contains("whole grid"));
}
