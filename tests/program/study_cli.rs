//! `squeal study` under `mpirun -n 2`: every stage runs, the report carries the comparison's
//! numbers, a rerun reuses every stage, a changed key recomputes only what depends on it, a
//! run interrupted in the middle of a sweep resumes after its last finished point with the
//! same numbers, and a longer friction list computes only its new points.

use crate::common;

use common::{scratch, squeal};
use serde_json::Value;
use std::path::{Path, PathBuf};

fn success(args: &[&str]) -> String {
    success_with_log(args).0
}

/// A successful run's standard output and its log (standard error).
fn success_with_log(args: &[&str]) -> (String, String) {
    let run = common::mpirun(2, squeal(), args);
    assert!(run.status.success(), "{}", common::text(&run));
    (
        String::from_utf8_lossy(&run.stdout).into_owned(),
        String::from_utf8_lossy(&run.stderr).into_owned(),
    )
}

/// Friction values a run's log says it took from the point cache, and computed.
fn points(log: &str) -> (usize, usize) {
    let reused = log.matches("): from the point cache (key ").count();
    let computed = log
        .lines()
        .filter(|l| l.contains(" INFO mu ") && l.contains("): static "))
        .count();
    (reused, computed)
}

/// The entries of a sweep stage's point cache.
fn kept_points(out: &Path, stage: &str) -> usize {
    // A kept point is a finished entry: one being stored sits in a ".unfinished-" folder
    // until its entry.json (written last) and the rename make it whole; a crash there once
    // counted it, and the resume then rightly recomputed it.
    std::fs::read_dir(out.join("points").join(stage))
        .map(|d| {
            d.flatten()
                .filter(|e| {
                    !e.file_name().to_string_lossy().starts_with(".unfinished-")
                        && e.path().join("entry.json").is_file()
                })
                .count()
        })
        .unwrap_or(0)
}

/// The example study of the tiny brake (examples/tiny-study.toml: two friction values, one
/// reduced interface of 22 nodes per pad, which finds the full model's two instabilities, and
/// one super-element strategy), with the super-element made at `mu_se`.
fn write_study(dir: &Path, mu_se: f64) -> PathBuf {
    let example = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/tiny-study.toml");
    let text = std::fs::read_to_string(&example).unwrap();
    let line = "superelement_friction = 0.5\n";
    assert!(text.contains(line), "{}", example.display());
    let file = dir.join("study.toml");
    std::fs::write(
        &file,
        text.replace(line, &format!("superelement_friction = {mu_se}\n")),
    )
    .unwrap();
    file
}

fn json(path: &Path) -> Value {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_slice(&bytes).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The stages a run's output says it ran (not from the cache), by folder title.
fn running(stdout: &str) -> Vec<String> {
    stdout
        .lines()
        .filter(|l| {
            l.starts_with('[')
                && (l.contains(": running") || l.contains(": its cached result is not used"))
        })
        .map(|l| l.split(": ").next().unwrap().to_string())
        .collect()
}

fn cached(stdout: &str) -> usize {
    stdout
        .lines()
        .filter(|l| l.starts_with('[') && l.contains(": from the cache"))
        .count()
}

/// Every eigenvalue of every stage's sweep, in stage order: what must not change when a run
/// is interrupted and resumed.
fn all_eigenvalues(out: &Path) -> Vec<(f64, f64)> {
    let mut v = Vec::new();
    for stage in ["full", "reduced-22", "superelements-single-22"] {
        let s = json(&out.join(stage).join("sweep.json"));
        for p in s["points"].as_array().unwrap() {
            v.extend(
                common::eigenvalues_of(p)
                    .into_iter()
                    .map(|(f, a, _)| (f, a)),
            );
        }
    }
    v
}

/// Eigenvalues recomputed from the same state: equal to the round-off of the solves (a
/// rerun's MUMPS ordering may differ), far below any physical difference. Each eigenvalue
/// lambda = a + i 2 pi f (frequency f in Hz, real part a in 1/s) as a whole: a solve's
/// round-off moves it by a fraction of |lambda|, and its real part, often a thousandth of
/// it, by as much in absolute terms (a real part of -108.2 1/s came back 2.8e-7 off, 2.6e-9
/// of itself and some 1e-11 of |lambda|, when the real part was compared alone).
fn same_numbers(a: &[(f64, f64)], b: &[(f64, f64)]) {
    assert_eq!(a.len(), b.len());
    let omega = |f: f64| 2.0 * std::f64::consts::PI * f;
    for (&(fa, ra), &(fb, rb)) in a.iter().zip(b) {
        let size = ra.hypot(omega(fa)).max(1.0);
        let moved = (ra - rb).hypot(omega(fa) - omega(fb));
        assert!(
            moved <= 1e-9 * size,
            "recomputed {rb} 1/s, {fb} Hz against {ra} 1/s, {fa} Hz"
        );
    }
}

/// The example study's stages, in the order they run.
const STAGES: [&str; 8] = [
    "frictionless-full",
    "frictionless-reduced-22",
    "compare-frictionless",
    "full",
    "reduced-22",
    "superelements-single-22",
    "compare-reduced",
    "compare-superelements",
];

#[test]
fn a_study_runs_its_stages_reports_them_and_reruns_only_what_changed() {
    let dir = scratch("study", "stages");
    let file = write_study(&dir, 0.5);
    let out = dir.join("out");
    let (f, o) = (file.to_str().unwrap(), out.to_str().unwrap());
    let first = success(&["study", f, "-o", o]);
    assert_eq!(running(&first).len(), STAGES.len(), "{first}");
    assert_eq!(cached(&first), 0, "{first}");

    // The report's numbers are the comparison's: each row of compare.json, printed.
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    // The spring-held brake's instabilities have sensitivities (friction and moduli): their
    // table is in the report.
    assert!(report.contains("| d Re / d mu (1/s) |"), "{report}");
    let full = json(&out.join("full").join("sweep.json"));
    let with: Vec<&Value> = full["points"]
        .as_array()
        .unwrap()
        .iter()
        .flat_map(|p| p["eigenvalues"].as_array().unwrap())
        .filter(|m| m["sensitivity"].is_object())
        .collect();
    assert!(!with.is_empty());
    assert!(with
        .iter()
        .all(|m| m["modulus_sensitivity"]["disc"].is_object()));
    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    let mut rows = 0;
    for stage in ["compare-reduced", "compare-superelements"] {
        let c = json(&out.join(stage).join("compare.json"));
        for i in c["instabilities"].as_array().unwrap() {
            assert_eq!(i["matched"], Value::Bool(true), "{stage}: {i}");
            let row = format!(
                "| {:.1} Hz | `{}` | yes | {:.3} | {:.3} % | {:.3} % | {:.3} % | {:.3} % |",
                i["reference_frequency_hz"].as_f64().unwrap(),
                Path::new(i["model"].as_str().unwrap())
                    .file_name()
                    .unwrap()
                    .to_string_lossy(),
                i["mac"].as_f64().unwrap(),
                100.0 * i["mean_error"].as_f64().unwrap(),
                100.0 * i["min_error"].as_f64().unwrap(),
                100.0 * i["max_error"].as_f64().unwrap(),
                100.0 * i["real_part_max_error"].as_f64().unwrap(),
            );
            assert!(report.contains(&row), "{row}\nnot in\n{report}");
            rows += 1;
        }
    }
    // The tiny brake's two instabilities, in the reduced interface and the super-element.
    assert_eq!(rows, 4, "{report}");
    // And each comparison's whole-band row per friction value, printed from compare.json.
    for stage in ["compare-reduced", "compare-superelements"] {
        let c = json(&out.join(stage).join("compare.json"));
        let spectra = c["spectra"].as_array().unwrap();
        assert_eq!(spectra.len(), 2, "{stage}: one model, two friction values");
        for s in spectra {
            let row = format!(
                "| {:.2} | {} / {} | {:.2} % |",
                s["friction"].as_f64().unwrap(),
                s["reference_modes"],
                s["other_modes"],
                100.0 * s["mean_relative"].as_f64().unwrap()
            );
            assert!(report.contains(&row), "{row}\nnot in\n{report}");
        }
    }
    // Friction value by friction value: every unstable eigenvalue of the full sweep at the
    // shared values is counted once, and the report prints each model's count.
    let full = json(&out.join("full").join("sweep.json"));
    for stage in ["compare-reduced", "compare-superelements"] {
        let c = json(&out.join(stage).join("compare.json"));
        let at = c["unstable_modes"].as_array().unwrap();
        let count =
            |key: &str| -> usize { at.iter().map(|u| u[key].as_u64().unwrap() as usize).sum() };
        let unstable_in_full: usize = full["points"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|p| at.iter().any(|u| u["friction"] == p["friction"]))
            .map(|p| common::unstable_modes(p).len())
            .sum();
        assert_eq!(count("reference"), unstable_in_full, "{stage}");
        let unmatched: usize = at
            .iter()
            .map(|u| u["unmatched"].as_array().unwrap().len())
            .sum();
        assert_eq!(count("matched") + unmatched, count("reference"), "{stage}");
        let folder = Path::new(at[0]["model"].as_str().unwrap())
            .file_name()
            .unwrap()
            .to_string_lossy()
            .into_owned();
        let said = format!("`{folder}` {} of {}", count("matched"), count("reference"));
        assert!(report.contains(&said), "{said}\nnot in\n{report}");
    }
    for i in full["instabilities"].as_array().unwrap() {
        let line = format!("| {:.1} Hz |", i["frequency_hz_at_max"].as_f64().unwrap());
        assert!(report.contains(&line), "{line}\n{report}");
    }
    // Which body moves: each instability's mode at its largest real part, its bodies' shares
    // of kinetic energy as sweep.json has them, in one row of the report.
    assert!(
        report.contains("Which part moves: each instability's kinetic energy"),
        "{report}"
    );
    for i in full["instabilities"].as_array().unwrap() {
        let (mu, f, a) = (
            i["mu_at_max"].as_f64().unwrap(),
            i["frequency_hz_at_max"].as_f64().unwrap(),
            i["max_real_part"].as_f64().unwrap(),
        );
        let point = full["points"]
            .as_array()
            .unwrap()
            .iter()
            .find(|p| p["friction"].as_f64() == Some(mu))
            .unwrap();
        let mode = point["eigenvalues"]
            .as_array()
            .unwrap()
            .iter()
            .find(|m| m["frequency_hz"].as_f64() == Some(f) && m["real_part"].as_f64() == Some(a))
            .unwrap();
        // Which pair feeds it: the pairs' shares of its growth rate likewise.
        for key in ["body_shares", "pair_shares"] {
            let shares = mode[key].as_object().unwrap();
            let cells: Vec<String> = shares
                .values()
                .map(|v| format!("{:.1} %", 100.0 * v.as_f64().unwrap()))
                .collect();
            let row = format!("| {f:.1} Hz | {} |", cells.join(" | "));
            assert!(report.contains(&row), "{key}: {row}\nnot in\n{report}");
        }
    }
    // Without friction first: every pair's closed zone and the whole band, printed from
    // compare-frictionless/compare.json.
    let c = json(&out.join("compare-frictionless").join("compare.json"));
    assert!(report.contains("## The reduced interfaces without friction (mu = 0)"));
    let zones = c["zones"].as_array().unwrap();
    // The tiny brake's two disc/pad pairs (the other pairs' zones are not reduced, and
    // equal in both models; they are compared all the same).
    assert!(zones.len() >= 2, "{c}");
    for z in zones {
        let row = format!(
            "| `frictionless-reduced-22` | {} | {:.3} | {:.2} mm |",
            z["pair"].as_str().unwrap(),
            z["total"].as_f64().unwrap(),
            1e3 * z["centroid_offset"].as_f64().unwrap(),
        );
        assert!(report.contains(&row), "{row}\nnot in\n{report}");
    }
    let spectra = c["spectra"].as_array().unwrap();
    assert_eq!(spectra.len(), 1, "one model at mu = 0");
    assert_eq!(spectra[0]["friction"].as_f64(), Some(0.0));
    let row = format!(
        "| `frictionless-reduced-22` | {} / {} | {:.2} % |",
        spectra[0]["reference_modes"],
        spectra[0]["other_modes"],
        100.0 * spectra[0]["mean_relative"].as_f64().unwrap()
    );
    assert!(report.contains(&row), "{row}\nnot in\n{report}");
    // No mode is unstable without friction.
    for stage in ["frictionless-full", "frictionless-reduced-22"] {
        let sweep = json(&out.join(stage).join("sweep.json"));
        assert_eq!(
            sweep["instabilities"].as_array().unwrap().len(),
            0,
            "{stage}"
        );
    }

    // The page holds the same tables and its figures inline.
    assert_eq!(
        html.matches("<table>").count(),
        report.matches("\n|---|").count(),
        "{html}"
    );
    assert!(html.matches("<svg").count() >= 3, "figures inlined");
    assert!(
        !html.contains("<?xml"),
        "an XML declaration inside the page"
    );

    look_at_the_page_in_chromium(&out.join("report.html"));

    // Nothing changed: every stage from the cache.
    let again = success(&["study", f, "-o", o]);
    assert!(running(&again).is_empty(), "{again}");
    assert_eq!(cached(&again), STAGES.len(), "{again}");

    // A cached result is reused only if it holds what was computed (issue 30, class 2).
    // An eigenvalue edited in place (same length), and a cached point's file deleted: the
    // stage runs again, says why, and recomputes from that point on.
    let full_sweep = out.join("full").join("sweep.json");
    let before = all_eigenvalues(&out);
    let text = std::fs::read_to_string(&full_sweep).unwrap();
    let at = text.find("\"frequency_hz\": ").unwrap() + "\"frequency_hz\": ".len();
    let digit = text.as_bytes()[at];
    let other = if digit == b'1' { '2' } else { '1' };
    let mut edited = text.clone();
    edited.replace_range(at..at + 1, &other.to_string());
    std::fs::write(&full_sweep, &edited).unwrap();
    let first_point = std::fs::read_dir(out.join("points").join("full"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| json(&p.join("point.json"))["mu"].as_f64() == Some(0.3))
        .unwrap();
    std::fs::remove_file(first_point.join("files").join("cea.json")).unwrap();
    let (tampered, log) = success_with_log(&["study", f, "-o", o]);
    assert_eq!(running(&tampered).len(), 1, "{tampered}");
    assert!(
        tampered.contains("its cached result is not used (sweep.json changed since it was made)"),
        "{tampered}"
    );
    assert!(log.contains("is not used: cea.json is missing"), "{log}");
    assert_eq!(
        points(&log),
        (0, 2),
        "the first point recomputed, and the second after it (a sweep resumes from its \
         leading finished points only: each starts from the one before): {log}"
    );
    same_numbers(&before, &all_eigenvalues(&out));
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(
        report.contains("(recomputed: the cached result was not used, sweep.json changed"),
        "{report}"
    );
    // Truncated (it once failed every rerun with a bare JSON error).
    let reduced_sweep = out.join("reduced-22").join("sweep.json");
    let bytes = std::fs::read(&reduced_sweep).unwrap();
    std::fs::write(&reduced_sweep, &bytes[..bytes.len() / 2]).unwrap();
    let truncated = success(&["study", f, "-o", o]);
    assert_eq!(running(&truncated).len(), 1, "{truncated}");
    assert!(truncated.contains("sweep.json has"), "{truncated}");
    same_numbers(&before, &all_eigenvalues(&out));

    // mu_SE changed: the super-element and its comparison only.
    write_study(&dir, 0.3);
    let changed = success(&["study", f, "-o", o]);
    let ran = running(&changed);
    assert_eq!(ran.len(), 2, "{changed}");
    assert!(ran[0].contains("super-elements (single)"), "{changed}");
    assert!(ran[1].contains("super-elements against"), "{changed}");
    assert_eq!(cached(&changed), STAGES.len() - 2, "{changed}");

    // Crashed in the middle of the full model's sweep, once its first point is kept, a run
    // resumes after the finished points with the same numbers. (Ctrl-C and SIGTERM go
    // through the same folder states; sweep_cli checks their message.)
    write_study(&dir, 0.5);
    let resumed = dir.join("resumed");
    let r = resumed.to_str().unwrap();
    let (job, _session) = common::mpirun_spawn(2, squeal(), &["study", f, "-o", r]);
    let stopped = common::crash_when(job, "a kept point of the full model", || {
        kept_points(&resumed, "full") > 0
    });
    let stderr = String::from_utf8_lossy(&stopped.stderr);
    assert!(!stopped.status.success(), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    // Whatever is in the folder is whole: every JSON file parses.
    let mut files = vec![resumed.clone()];
    while let Some(p) = files.pop() {
        if p.is_dir() {
            files.extend(std::fs::read_dir(&p).unwrap().map(|e| e.unwrap().path()));
        } else if p.extension().is_some_and(|e| e == "json") {
            json(&p);
        }
    }
    assert!(!resumed.join("report.md").exists());
    let stages = STAGES;
    let done = |s: &str| resumed.join(format!("{s}.stage.json")).exists();
    let finished = stages.iter().filter(|s| done(s)).count();
    let unfinished_sweeps: Vec<&str> = stages
        .iter()
        .filter(|s| !s.starts_with("compare-") && !done(s))
        .copied()
        .collect();
    // Without friction, one point; the others sweep two.
    let sweep_points = |s: &str| if s.starts_with("frictionless-") { 1 } else { 2 };
    let kept: usize = unfinished_sweeps
        .iter()
        .map(|s| kept_points(&resumed, s))
        .sum();
    eprintln!(
        "interrupted with {finished} stage(s) finished and {kept} point(s) kept in the \
         unfinished sweeps {unfinished_sweeps:?}"
    );
    assert!(finished < stages.len());
    // Frozen within 20 ms of its first kept point, the full model cannot have finished its
    // second (a static and a CEA): the resume below is the middle-of-a-sweep kind.
    assert!(kept >= 1, "no kept point in an unfinished sweep");
    let (rest, log) = success_with_log(&["study", f, "-o", r]);
    assert_eq!(cached(&rest), finished, "{rest}");
    assert_eq!(running(&rest).len(), stages.len() - finished, "{rest}");
    // The finished points of the interrupted sweeps are reused, only the others computed
    // (two friction values per sweep, one without friction).
    assert_eq!(
        points(&log),
        (
            kept,
            unfinished_sweeps
                .iter()
                .map(|s| sweep_points(s))
                .sum::<usize>()
                - kept
        ),
        "{log}"
    );
    same_numbers(&all_eigenvalues(&out), &all_eigenvalues(&resumed));

    // One friction value more: each sweep computes it alone and reuses the two it has.
    let text = std::fs::read_to_string(&file).unwrap();
    let longer = "friction = [\n    0.3,\n    0.7,\n    0.9,\n]";
    std::fs::write(
        &file,
        text.replace("friction = [\n    0.3,\n    0.7,\n]", longer),
    )
    .unwrap();
    assert!(std::fs::read_to_string(&file).unwrap().contains(longer));
    let stages = ["full", "reduced-22", "superelements-single-22"];
    let sweep_points = |stage: &str| -> Vec<Value> {
        json(&resumed.join(stage).join("sweep.json"))["points"]
            .as_array()
            .unwrap()
            .clone()
    };
    let before: Vec<Vec<Value>> = stages.iter().map(|s| sweep_points(s)).collect();
    let (extended, log) = success_with_log(&["study", f, "-o", r]);
    assert_eq!(running(&extended).len(), 5, "{extended}");
    assert_eq!(points(&log), (6, 3), "{log}");
    for (stage, old) in stages.iter().zip(&before) {
        let new = sweep_points(stage);
        assert_eq!(new.len(), 3, "{stage}");
        // The reused points are the same points, to the bit.
        assert_eq!(new[..2], old[..], "{stage}");
        assert_eq!(kept_points(&resumed, stage), 3, "{stage}");
    }
}

/// Headless Chromium (Debian's, as ci/setup installs it), with the flags this closed
/// network needs.
fn chromium(args: &[&str]) -> std::process::Output {
    let profile = tempfile::tempdir().unwrap();
    std::process::Command::new("timeout")
        .args(["120", "chromium"])
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-quic",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
        ])
        .arg(format!("--user-data-dir={}", profile.path().display()))
        .args(args)
        .output()
        .expect("could not run chromium: install it (apt-get install chromium; ci/setup does)")
}

/// The report as a person sees it: Chromium lays the page out and takes a screenshot, which
/// must show a page (not blank, not an error page), and the DOM it built holds the tables.
fn look_at_the_page_in_chromium(page: &Path) {
    let url = format!("file://{}", page.canonicalize().unwrap().display());
    let shot = page.with_file_name("report-screenshot.png");
    let run = chromium(&[
        "--window-size=1200,1600",
        &format!("--screenshot={}", shot.display()),
        &url,
    ]);
    assert!(
        shot.is_file(),
        "no screenshot: {}",
        String::from_utf8_lossy(&run.stderr)
    );
    let image = resvg::tiny_skia::Pixmap::decode_png(&std::fs::read(&shot).unwrap()).unwrap();
    assert_eq!((image.width(), image.height()), (1200, 1600));
    // Text, table rules and the first figure: a laid-out report inks several per cent of
    // its first screen; a blank page or a one-line error page inks almost nothing.
    let inked = image
        .pixels()
        .iter()
        .filter(|p| p.red() < 200 || p.green() < 200 || p.blue() < 200)
        .count();
    let share = inked as f64 / (1200.0 * 1600.0);
    assert!(share > 0.02, "the screenshot is nearly blank ({share})");
    let dom = chromium(&["--dump-dom", &url]);
    let dom = String::from_utf8_lossy(&dom.stdout);
    assert!(dom.matches("<table>").count() >= 3, "{dom}");
    assert!(dom.contains("<svg"), "no figure in the DOM");
}

#[test]
fn a_bad_plan_is_refused_naming_the_key() {
    let dir = scratch("study", "bad-plan");
    let file = write_study(&dir, 0.5);
    let text = std::fs::read_to_string(&file).unwrap();
    for (plan, key) in [
        (
            "contact_nodes_per_pad = [22]",
            "contact_nodes_per_pad = [22, 22]",
        ),
        (
            "superelements = [\"single\"]",
            "superelements = [\"single\", \"single\"]",
        ),
        (
            "contact_nodes_per_pad = [22]",
            "contact_nodes_per_pad = [0]",
        ),
    ] {
        std::fs::write(&file, text.replace(plan, key)).unwrap();
        let run = common::mpirun(
            2,
            squeal(),
            &[
                "study",
                file.to_str().unwrap(),
                "-o",
                dir.join("out").to_str().unwrap(),
            ],
        );
        assert!(!run.status.success(), "{}", common::text(&run));
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert!(stderr.contains("comparison."), "{key}: {stderr}");
        assert_eq!(stderr.matches("squeal: error").count(), 1, "{stderr}");
        assert!(!dir.join("out").exists(), "{key}: something was written");
    }
}

/// examples/disc-and-pad-study.toml, a study of a mesh file (the tiny brake written out as
/// Gmsh, with materials, supports and contacts named by its physical groups), runs as its
/// header says and its full model is the built-in tiny brake's: the same eigenvalues.
#[test]
fn the_mesh_file_example_runs_and_its_model_is_the_built_in_one() {
    let dir = scratch("study", "mesh-file");
    let example = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/disc-and-pad-study.toml");
    let file = dir.join("disc-and-pad-study.toml");
    std::fs::copy(&example, &file).unwrap();
    let mesh = dir.join("tiny-brake.msh");
    let written = std::process::Command::new(squeal())
        .args(["mesh", "--preset", "tiny", "-o", mesh.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(written.status.success(), "{}", common::text(&written));
    let out = dir.join("out");
    let stdout = success(&[
        "study",
        file.to_str().unwrap(),
        "--friction",
        "0.7",
        "-o",
        out.to_str().unwrap(),
    ]);
    // Without friction (two sweeps and their comparison), then the five stages at 0.7.
    assert_eq!(running(&stdout).len(), 8, "{stdout}");
    assert!(out.join("report.html").is_file());
    let builtin = dir.join("builtin");
    success(&[
        "sweep",
        "--preset",
        "tiny",
        "--friction",
        "0.7",
        "--fmax",
        "4000",
        "-o",
        builtin.to_str().unwrap(),
    ]);
    let modes = |path: &Path| -> Vec<(f64, f64, bool)> {
        common::eigenvalues_of(&json(&path.join("sweep.json"))["points"][0])
    };
    let (from_file, from_preset) = (modes(&out.join("full")), modes(&builtin));
    assert_eq!(from_file.len(), from_preset.len());
    assert!(from_file.iter().any(|m| m.2), "no unstable mode at mu 0.7");
    for (a, b) in from_file.iter().zip(&from_preset) {
        assert!((a.0 - b.0).abs() <= 1e-8 * b.0, "{a:?} against {b:?}");
        // Real parts against |lambda| = 2 pi f: the eigenvalue's own scale.
        assert!(
            (a.1 - b.1).abs() <= 1e-8 * 2.0 * std::f64::consts::PI * b.0,
            "{a:?} against {b:?}"
        );
        assert_eq!(a.2, b.2);
    }
}

/// The quick study (no file, no preset) writes the interface choice it leaves to squeal
/// (`pad_coupling = "auto"`: share couplings and patch laws where the pad faces hold them)
/// and no `tilt`, which that choice makes; a `--preset` study has no `[reduction]` and gets
/// the same defaults.
#[test]
fn the_studies_write_that_the_interface_is_squeals_choice() {
    let dir = scratch("study", "quick-plan");
    let quick = dir.join("quick.toml");
    let preset = dir.join("preset.toml");
    success(&["study", "--write-study", quick.to_str().unwrap()]);
    let preset_args = [
        "study",
        "--preset",
        "tiny-caliper",
        "--write-study",
        preset.to_str().unwrap(),
    ];
    success(&preset_args);
    let read = |path: &Path| -> toml::Value {
        toml::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
    };
    let quick = read(&quick);
    let reduction = quick.get("reduction");
    assert_eq!(
        reduction.and_then(|r| r.get("pad_coupling")),
        Some(&toml::Value::String("auto".into())),
        "{quick}"
    );
    assert!(reduction.and_then(|r| r.get("tilt")).is_none(), "{quick}");
    let preset = read(&preset);
    assert!(preset.get("reduction").is_none(), "{preset}");
}
