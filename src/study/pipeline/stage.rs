//! The stages of `squeal study`, in the order they run: the full model and each reduced
//! interface without friction and their comparison (unless `[comparison] frictionless =
//! false`), the full model's friction sweep, a
//! reduced-interface sweep per grid size, a super-element sweep per strategy, then the two
//! comparisons (reduced interfaces against the full model, the paper's Tables 4-5;
//! super-elements against the reduced interface they were built on, Tables 6-7).
//!
//! Each stage has a key: a hash of everything its result depends on (squeal's version and
//! build, the study it sweeps as TOML with the output folder left out, the bytes of the mesh
//! file and of the files it includes; for a comparison, its inputs' keys). A stage whose key matches the
//! one recorded beside its folder is not run again.

use crate::mesh::hash::{bytes_hash, text_hash};
use crate::study::config::{ReductionSpec, Study};
use crate::study::sweep::SweepSettings;

/// What a stage computes.
#[derive(Clone, Debug, PartialEq)]
pub enum Work {
    /// A friction sweep of this study (its `output` is the stage's folder).
    Sweep(Box<Study>),
    /// `squeal compare` of the stages named: the first is the reference.
    Compare(Vec<String>),
}

/// One stage of the study.
#[derive(Clone, Debug, PartialEq)]
pub struct Stage {
    /// The folder name under the study's output, e.g. `reduced-52`.
    pub name: String,
    /// What a person reads, e.g. "reduced interface, 52 nodes per pad".
    pub title: String,
    pub work: Work,
    pub key: String,
    /// A sweep's key without its friction list: what its finished points are kept under
    /// ([`crate::study::sweep::point_cache`]); empty for a comparison.
    pub point_key: String,
}

/// The prefix of the stages without friction (their folders and their comparison's).
pub const FRICTIONLESS: &str = "frictionless-";
/// The comparison of the reduced interfaces against the full model without friction.
pub const COMPARE_FRICTIONLESS: &str = "compare-frictionless";

/// squeal's version, as the report and the stage records say it.
pub fn version() -> String {
    format!("squeal {}", env!("CARGO_PKG_VERSION"))
}

/// What goes into every key: the version and the build, so that results of another squeal,
/// or of another build of this one, are not reused.
///
/// Why the build. With the version alone, a squeal rebuilt from changed numerics took the
/// stages and cached points of the build before it as its own (the crate's version does not
/// change from one commit to the next); a rebuild of the same code costs only a cache miss.
/// The build is known by a hash of the running executable's bytes (about 0.1 s, once). The
/// decisions to reuse are taken on rank 0 alone and broadcast, so ranks that read different
/// files (or none) cannot disagree.
fn key_version() -> &'static str {
    static KEY: std::sync::OnceLock<String> = std::sync::OnceLock::new();
    KEY.get_or_init(|| {
        let build = std::env::current_exe()
            .and_then(std::fs::read)
            .map(|bytes| bytes_hash(&bytes))
            .unwrap_or_else(|_| "unreadable".into());
        format!("{} build {build}", version())
    })
}

/// The study of a sweep stage as hashed: what its models are made from
/// ([`SweepSettings`]), not the output folder (where the result goes, not what it is) nor
/// the comparison plan.
fn sweep_key(study: &Study, mesh_bytes: &str) -> String {
    text_hash(&format!(
        "{}\n{}\nmesh file {mesh_bytes}",
        key_version(),
        SweepSettings::of(study, "").hash()
    ))
}

/// The `[reduction]` of a reduced-interface stage: the study's own settings (weighting,
/// radius, springs...) at `nodes` per pad, without the super-element settings, so that
/// changing those does not recompute the reduced interfaces.
fn reduced_interface(base: Option<&ReductionSpec>, nodes: usize) -> ReductionSpec {
    let mut r = base
        .cloned()
        .unwrap_or_else(|| ReductionSpec::with_count(nodes));
    r.contact_nodes_per_pad = Some(nodes);
    r.spacing = None;
    // The cubic law of the super-elements asks for point contacts: their reference
    // reduced interface must have them too, with the law's settings left out of its key.
    if r.tilt.is_none() && r.cubic_law() {
        r.tilt = Some(false);
    }
    r.superelements = None;
    r.superelement_friction = None;
    r.cutoff_frequency_hz = None;
    r.k_linear = None;
    r.k_cubic = None;
    r
}

/// The stages of `study`, keyed. `mesh_hash`: a hash of the mesh file's bytes (and of the
/// files it includes) when the study reads one ("" for the built-in brake, whose parameters
/// are in the study itself).
pub fn plan(study: &Study, mesh_hash: &str) -> Vec<Stage> {
    let comparison = study.comparison.clone().unwrap_or_default();
    let derived = |name: &str, reduction: Option<ReductionSpec>| {
        let mut s = study.clone();
        s.reduction = reduction;
        s.comparison = None;
        s.output = study.output.join(name);
        s
    };
    let sweep_stage = |name: String, title: String, s: Study| Stage {
        key: sweep_key(&s, mesh_hash),
        point_key: {
            let mut model = s.clone();
            // A point's numbers depend on its friction path (in its own key), not on the
            // list asked or on how many points refinement may insert.
            model.analysis.friction = Vec::new();
            model.analysis.refine_points = 0;
            sweep_key(&model, mesh_hash)
        },
        name,
        title,
        work: Work::Sweep(Box::new(s)),
    };
    let compare_stage = |name: &str, title: String, inputs: Vec<String>, all: &[Stage]| {
        let keys: Vec<&str> = inputs
            .iter()
            .filter_map(|i| all.iter().find(|s| &s.name == i).map(|s| s.key.as_str()))
            .collect();
        Stage {
            name: name.into(),
            title,
            key: text_hash(&format!("{}\ncompare {inputs:?}\n{keys:?}", key_version())),
            point_key: String::new(),
            work: Work::Compare(inputs),
        }
    };
    let base = study.reduction.as_ref();
    let mut stages = Vec::new();
    // First, without friction: how well each reduced interface holds the pads (its closed
    // zone) and what that does to the real modes, before any friction value is run.
    if comparison.frictionless && !comparison.contact_nodes_per_pad.is_empty() {
        let frictionless = |name: &str, reduction: Option<ReductionSpec>| {
            let mut s = derived(name, reduction);
            s.analysis.friction = vec![0.0];
            s
        };
        let mut inputs = vec![format!("{FRICTIONLESS}full")];
        stages.push(sweep_stage(
            inputs[0].clone(),
            "full model without friction (mu = 0)".into(),
            frictionless(&inputs[0], None),
        ));
        for &n in &comparison.contact_nodes_per_pad {
            let name = format!("{FRICTIONLESS}reduced-{n}");
            let s = frictionless(&name, Some(reduced_interface(base, n)));
            stages.push(sweep_stage(
                name.clone(),
                format!("reduced interface, {n} nodes per pad, without friction"),
                s,
            ));
            inputs.push(name);
        }
        let c = compare_stage(
            COMPARE_FRICTIONLESS,
            "reduced interfaces against the full model without friction".into(),
            inputs,
            &stages,
        );
        stages.push(c);
    }
    stages.push(sweep_stage(
        "full".into(),
        "full model".into(),
        derived("full", None),
    ));
    let base = study.reduction.as_ref();
    for &n in &comparison.contact_nodes_per_pad {
        let name = format!("reduced-{n}");
        let s = derived(&name, Some(reduced_interface(base, n)));
        stages.push(sweep_stage(
            name,
            format!("reduced interface, {n} nodes per pad"),
            s,
        ));
    }
    let superelement_grid = comparison.superelement_grid();
    if let Some(n) = superelement_grid {
        // The reduced interface the super-elements stand for must be swept too: it is their
        // reference.
        if !comparison.contact_nodes_per_pad.contains(&n) {
            let name = format!("reduced-{n}");
            let s = derived(&name, Some(reduced_interface(base, n)));
            stages.push(sweep_stage(
                name,
                format!("reduced interface, {n} nodes per pad"),
                s,
            ));
        }
        for &strategy in &comparison.superelements {
            let name = format!("superelements-{}-{n}", strategy.name());
            let mut r = reduced_interface(base, n);
            if let Some(b) = base {
                // A new mu_SE recomputes only the strategies it changes.
                if strategy.depends_on_superelement_friction() {
                    r.superelement_friction = b.superelement_friction;
                }
                r.cutoff_frequency_hz = b.cutoff_frequency_hz;
                r.k_linear = b.k_linear;
                r.k_cubic = b.k_cubic;
            }
            r.superelements = Some(strategy);
            let s = derived(&name, Some(r));
            stages.push(sweep_stage(
                name,
                format!("super-elements ({}) on {n} nodes per pad", strategy.name()),
                s,
            ));
        }
    }
    let reduced: Vec<String> = stages
        .iter()
        .filter(|s| s.name.starts_with("reduced-"))
        .map(|s| s.name.clone())
        .collect();
    if !reduced.is_empty() {
        let mut inputs = vec!["full".to_string()];
        inputs.extend(reduced);
        let c = compare_stage(
            "compare-reduced",
            "reduced interfaces against the full model".into(),
            inputs,
            &stages,
        );
        stages.push(c);
    }
    if let Some(n) = superelement_grid {
        let mut inputs = vec![format!("reduced-{n}")];
        inputs.extend(
            stages
                .iter()
                .filter(|s| s.name.starts_with("superelements-"))
                .map(|s| s.name.clone()),
        );
        let c = compare_stage(
            "compare-superelements",
            format!("super-elements against the reduced interface of {n} nodes per pad"),
            inputs,
            &stages,
        );
        stages.push(c);
    }
    stages
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reduce::Strategy;
    use crate::study::config::ComparisonSpec;

    fn study() -> Study {
        let mut s = Study::builtin("tiny");
        s.comparison = Some(ComparisonSpec {
            contact_nodes_per_pad: vec![6, 22],
            superelements: vec![Strategy::Single, Strategy::Adaptive],
            superelement_contact_nodes_per_pad: None,
            frictionless: true,
        });
        s
    }

    fn keys(s: &Study) -> Vec<(String, String)> {
        plan(s, "").into_iter().map(|s| (s.name, s.key)).collect()
    }

    #[test]
    fn the_stages_run_frictionless_then_full_then_reduced_then_superelements_then_comparisons() {
        let names: Vec<String> = keys(&study()).into_iter().map(|k| k.0).collect();
        assert_eq!(
            names,
            [
                "frictionless-full",
                "frictionless-reduced-6",
                "frictionless-reduced-22",
                "compare-frictionless",
                "full",
                "reduced-6",
                "reduced-22",
                "superelements-single-22",
                "superelements-adaptive-22",
                "compare-reduced",
                "compare-superelements"
            ]
        );
        // A super-element grid not among the reduced interfaces is swept as their reference.
        let mut s = study();
        let c = s.comparison.as_mut().unwrap();
        c.contact_nodes_per_pad = vec![6];
        c.superelement_contact_nodes_per_pad = Some(52);
        let names: Vec<String> = keys(&s).into_iter().map(|k| k.0).collect();
        assert!(names.contains(&"reduced-52".to_string()), "{names:?}");
    }

    /// A change recomputes what depends on it and nothing else.
    #[test]
    fn a_changed_key_touches_only_the_stages_that_depend_on_it() {
        let before = keys(&study());
        let changed = |s: &Study| -> Vec<String> {
            keys(s)
                .into_iter()
                .zip(&before)
                .filter(|(a, b)| a.1 != b.1)
                .map(|(a, _)| a.0)
                .collect()
        };
        // The output folder and the comparison plan's own order are not results.
        let mut s = study();
        s.output = "elsewhere".into();
        assert!(changed(&s).is_empty());
        // mu_SE: only the single super-element and its comparison (the adaptive strategy
        // builds at the sweep's own friction values).
        let mut s = study();
        let mut r = ReductionSpec::with_count(52);
        r.superelement_friction = Some(0.3);
        s.reduction = Some(r);
        assert_eq!(
            changed(&s),
            ["superelements-single-22", "compare-superelements"]
        );
        // The friction values: everything but the stages without friction.
        let mut s = study();
        s.analysis.friction = vec![0.2, 0.4];
        let all: Vec<String> = before.iter().map(|b| b.0.clone()).collect();
        assert_eq!(changed(&s), all[4..]);
        // Without them, the rest keep their keys.
        let mut s = study();
        s.comparison.as_mut().unwrap().frictionless = false;
        let names: Vec<String> = keys(&s).into_iter().map(|k| k.0).collect();
        assert_eq!(names, all[4..]);
        assert!(keys(&s).iter().zip(&before[4..]).all(|(a, b)| a == b));
        // The band: everything.
        let mut s = study();
        s.analysis.max_frequency_hz = 5000.0;
        assert_eq!(changed(&s).len(), before.len());
        // Another mesh file's bytes: every sweep, and so every comparison.
        let other: Vec<String> = plan(&study(), "0123")
            .into_iter()
            .zip(&before)
            .filter(|(a, b)| a.key != b.1)
            .map(|(a, _)| a.name)
            .collect();
        assert_eq!(other.len(), before.len());
    }
}
