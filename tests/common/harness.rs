//! The harness for tests that need PETSc. PETSc can be initialised once per process and is
//! not thread-safe, so every check runs in its own `mpirun` job: the test binary using this
//! (`tests/numerics/`) is both the libtest-mimic harness (parent: one trial per check, never touching MPI itself)
//! and the program those jobs run (`--child NAME`). The parent runs each check on every
//! rank count it lists and compares the numbers the runs printed.

use libtest_mimic::{Arguments, Failed, Trial};
use squeal::petsc::{Runtime, RuntimeOptions};

/// A check: computes on the runtime, verifies against an independent answer, and returns
/// the numbers that must not depend on the rank count.
pub type CheckFn = fn(&Runtime) -> Result<Vec<f64>, String>;

pub struct Check {
    pub name: &'static str,
    pub run: CheckFn,
    pub ranks: &'static [usize],
    /// Largest difference between rank counts, relative to the largest number.
    pub agreement: f64,
}

/// The harness over the checks of each file: `(file, checks)`, each check a trial named
/// `file::check`.
pub fn main(files: &[(&'static str, &'static [Check])]) {
    let named = || {
        files.iter().flat_map(|&(file, checks)| {
            checks
                .iter()
                .map(move |c| (format!("{file}::{}", c.name), c))
        })
    };
    let args: Vec<String> = std::env::args().collect();
    if args.len() >= 3 && args[1] == "--child" {
        let found = named().find(|(name, _)| *name == args[2]);
        std::process::exit(match found {
            Some((name, check)) => child(check, &name),
            None => {
                eprintln!("no check named {}", args[2]);
                2
            }
        });
    }
    let arguments = Arguments::from_args();
    let exe = std::env::current_exe().expect("own path");
    let only = only();
    let trials = named()
        .filter(|(name, _)| {
            only.as_ref()
                .is_none_or(|o| o.iter().any(|w| selects(w, name)))
        })
        .map(|(name, c)| {
            let exe = exe.clone();
            let trial_name = name.clone();
            Trial::test(trial_name, move || parent(&exe, &name, c))
        })
        .collect();
    libtest_mimic::run(&arguments, trials).exit();
}

/// The checks `SQUEAL_TEST_ONLY` (a comma-separated list) names, when it is set: libtest-mimic
/// takes one filter on its command line, and `ci/test` reruns a list of checks under each
/// other BLAS kernel in one run of the binary, so that they share the cores.
fn only() -> Option<Vec<String>> {
    let list = std::env::var("SQUEAL_TEST_ONLY").ok()?;
    Some(list.split(',').map(|s| s.trim().to_string()).collect())
}

/// Whether an entry of `SQUEAL_TEST_ONLY` selects the check `name`: its whole name, or, for
/// an entry ending in `::`, every check of that file.
fn selects(entry: &str, name: &str) -> bool {
    if entry.ends_with("::") {
        name.starts_with(entry)
    } else {
        entry == name
    }
}

/// The rank counts to run `check` on: all it lists, or, with `SQUEAL_TEST_RANKS=2` (a
/// comma-separated list) in the environment, those of them that are listed there (its
/// largest when none is). `ci/test` sets it for the reruns under other BLAS kernels, which
/// check decisions, not the agreement between rank counts that the first run checked.
fn rank_counts(check: &Check) -> Vec<usize> {
    let Ok(wanted) = std::env::var("SQUEAL_TEST_RANKS") else {
        return check.ranks.to_vec();
    };
    let wanted: Vec<usize> = wanted
        .split(',')
        .map(|n| {
            n.trim()
                .parse()
                .expect("SQUEAL_TEST_RANKS: a list of rank counts")
        })
        .collect();
    let kept: Vec<usize> = check
        .ranks
        .iter()
        .copied()
        .filter(|n| wanted.contains(n))
        .collect();
    if kept.is_empty() {
        check.ranks.iter().copied().max().into_iter().collect()
    } else {
        kept
    }
}

fn parent(exe: &std::path::Path, name: &str, check: &Check) -> Result<(), Failed> {
    let mut results: Vec<(usize, Vec<f64>)> = Vec::new();
    for n in rank_counts(check) {
        let out = super::mpirun(n, exe, &["--child", name]);
        if super::hung(&out) {
            return Err(format!("{name} hung on {n} ranks\n{}", super::text(&out)).into());
        }
        if !out.status.success() {
            return Err(format!("{name} failed on {n} ranks\n{}", super::text(&out)).into());
        }
        let stdout = String::from_utf8_lossy(&out.stdout);
        let line = stdout
            .lines()
            .find_map(|l| l.strip_prefix("RESULT "))
            .ok_or_else(|| format!("{name}: no RESULT line\n{}", super::text(&out)))?;
        let numbers: Vec<f64> = serde_json::from_str(line).map_err(|e| e.to_string())?;
        results.push((n, numbers));
    }
    let (n0, first) = &results[0];
    let scale = first.iter().fold(1e-300f64, |m, v| m.max(v.abs()));
    for (n, other) in &results[1..] {
        if other.len() != first.len() {
            return Err(format!(
                "{name}: {} numbers on {n0} ranks, {} on {n}",
                first.len(),
                other.len()
            )
            .into());
        }
        for (i, (a, b)) in first.iter().zip(other).enumerate() {
            if (a - b).abs() > check.agreement * scale {
                return Err(format!("{name}: value {i}: {a} on {n0} ranks, {b} on {n}").into());
            }
        }
    }
    Ok(())
}

fn child(check: &Check, name: &str) -> i32 {
    let rt = Runtime::init(&RuntimeOptions::default()).expect("PETSc initialises");
    let rank = rt.world().rank();
    let code = match (check.run)(&rt) {
        Ok(numbers) => {
            if rank == 0 {
                println!("RESULT {}", serde_json::to_string(&numbers).unwrap());
            }
            0
        }
        Err(why) => {
            eprintln!("rank {rank}: {name}: {why}");
            1
        }
    };
    drop(rt);
    code
}
