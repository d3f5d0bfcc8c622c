//! `squeal compare REFERENCE OTHER...`: how far other models of a brake (reduced-interface
//! models, super-element assemblies) stand in for a reference, from the folders their sweeps
//! wrote (METHOD.md section 8; the paper's eqs. 12-14, Tables 4-7).
//!
//! Each instability of the reference (an unstable track and the partner it coupled with) is
//! paired with one of the other model's instabilities within [`MATCH_TOLERANCE`] in
//! frequency, preferring those unstable at the same friction values (see
//! [`match_instabilities`]). For a paired instability and each friction value mu_j both
//! sweeps share, the two modes of each pair are matched lower to lower and the error is
//! e_j = sum_i |f_other(j, i) - f_ref(j, i)| / f_ref(j, i) (eq. 12's summand); the mean over
//! the M shared values is eq. 12, the smallest and largest are eqs. 13-14. The real parts
//! are compared as the largest |a_other - a_ref| over the mu values, relative to the
//! reference's largest real part. Instabilities one model has and the other has not are
//! listed both ways. Errors are fractions (0.01 is 1 %).
//!
//! Among the other model's instabilities within [`MATCH_TOLERANCE`] in frequency and unstable
//! at the nearest friction values, the one whose unstable mode shape is most alike (complex
//! MAC on the pad surface nodes both models share, at the reference's mu of largest real
//! part, from the folders' contact.json) is taken; without shapes, the nearest in frequency.

mod edge;
pub mod error;
mod matching;
mod output;
mod statics;
mod unstable_modes;

pub use edge::{EdgeSensitiveMode, EDGE_NOTED};
pub use error::CompareError;
pub use matching::MATCH_TOLERANCE;
pub use statics::{patch_pressure_l2, StaticComparison, ZoneComparison};
pub use unstable_modes::{
    totals as unstable_mode_totals, UnmatchedMode, UnstableModeTotals, UnstableModesAt,
    UNSTABLE_MODE_TOLERANCE,
};

use crate::analysis::spectrum_match::{match_spectra, SpectrumMatch};
use crate::results::SweepDocument as Sweep;
use crate::results::{SuperElementPoint as SuperElementRecord, SweepPointReport as Point};
use matching::{
    match_instabilities, nearest_modes, pair_indices, pair_modes, reference_curves, relative,
};
use statics::{compare_statics, compare_zones};
use std::path::{Path, PathBuf};

/// One model's errors on one reference instability.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct InstabilityComparison {
    pub reference_frequency_hz: f64,
    pub reference_onset_mu: f64,
    pub reference_max_real_part: f64,
    /// The other model's folder.
    pub model: String,
    pub matched: bool,
    /// The complex MAC between the two instabilities' unstable mode shapes on the pad
    /// surface nodes, at the reference's largest real part (when both folders hold shapes).
    pub mac: Option<f64>,
    /// The other model's instability: its frequency and onset.
    pub model_frequency_hz: Option<f64>,
    pub model_onset_mu: Option<f64>,
    /// Eqs. 12-14 over the shared friction values (fractions); `None` when not matched.
    pub mean_error: Option<f64>,
    pub min_error: Option<f64>,
    pub max_error: Option<f64>,
    /// max_j |a_model - a_ref| / max_j a_ref (the pair's larger real part at each mu).
    pub real_part_max_error: Option<f64>,
    /// e_j per shared mu: (mu, e_j). At each mu the other model's modes are those nearest
    /// in eigenvalue to the reference's (see [`nearest_modes`]), not its tracks' members.
    pub per_friction: Vec<(f64, f64)>,
    /// The friction values where those nearest modes are not the members of the other
    /// model's own tracks of this instability: where the two trackings paired close modes
    /// differently (or the other model's mode moved past a neighbour).
    pub track_disagreements: Vec<f64>,
    /// Where the reference checked its own contact edge (`--contact-edge-points`): the
    /// friction values at which this instability is stable with the edge moved; `None`
    /// where it did not check.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reference_on_edge: Option<Vec<f64>>,
    /// Which reference instability this is (its index), for grouping the plots.
    #[serde(skip)]
    pub reference_index: usize,
    /// The curves (mu, frequency, real part) of the pair's modes: the reference's, then
    /// this model's, for the plots.
    #[serde(skip)]
    pub curves: Vec<crate::study::plot::Track>,
}

/// An instability of another model that matches none of the reference's.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct ExtraInstability {
    pub model: String,
    pub frequency_hz: f64,
    pub onset_mu: f64,
    pub max_real_part: f64,
}

#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct ModelEntry {
    pub folder: String,
    pub source: String,
    pub equations: usize,
    pub instabilities: usize,
    /// Median wall time of a friction value (static + CEA), s.
    pub seconds_per_friction: f64,
    /// A super-element assembly: its largest reduced size, the super-elements it built and
    /// the median time of its dense static + CEA per friction value (s).
    pub superelement: Option<SuperElementSummary>,
}

#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct SuperElementSummary {
    pub size: usize,
    pub built: usize,
    pub dense_seconds_per_friction: f64,
}

fn superelement_summary(s: &Sweep) -> Option<SuperElementSummary> {
    let records: Vec<&SuperElementRecord> = s
        .points
        .iter()
        .filter_map(|p| p.superelement.as_ref())
        .collect();
    if records.is_empty() {
        return None;
    }
    let mut t: Vec<f64> = records
        .iter()
        .map(|r| r.dense_static_seconds + r.dense_cea_seconds)
        .collect();
    t.sort_by(f64::total_cmp);
    Some(SuperElementSummary {
        size: records.iter().map(|r| r.size).max().unwrap_or(0),
        built: records.iter().filter(|r| r.rebuilt).count(),
        dense_seconds_per_friction: t[t.len() / 2],
    })
}

fn median_seconds(s: &Sweep) -> f64 {
    let mut t: Vec<f64> = s.points.iter().map(|p| p.seconds).collect();
    t.sort_by(f64::total_cmp);
    t.get(t.len() / 2).copied().unwrap_or(0.0)
}

/// The comparison, as written to compare.json.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct Comparison {
    /// The reference first.
    pub models: Vec<ModelEntry>,
    pub instabilities: Vec<InstabilityComparison>,
    /// Instabilities found in another model but not in the reference.
    pub extra: Vec<ExtraInstability>,
    /// Contact states and pressures, per model and shared friction value (where both sweeps
    /// wrote contact.json).
    pub statics: Vec<StaticComparison>,
    /// Every mode of the band, per model and shared friction value, paired by frequency
    /// with the reference's ([`match_spectra`]): how far the whole spectrum moved, stable
    /// modes included (at mu = 0 the interface's stiffness alone).
    pub spectra: Vec<SpectrumComparison>,
    /// Each pair's closed zone against the reference's, per model and shared friction value
    /// where both sweeps wrote it: what holds the pads, before any mode is computed.
    #[serde(default)]
    pub zones: Vec<ZoneComparison>,
    /// The reference's modes its own contact edge moves by 1 % or more, where it checked
    /// (`--contact-edge-points`).
    #[serde(default)]
    pub reference_edge: Vec<EdgeSensitiveMode>,
    /// Per model and shared friction value, the reference's unstable modes with and without
    /// an unstable mode of the model within 1 %, read from each point's eigenvalues apart
    /// from tracking.
    #[serde(default)]
    pub unstable_modes: Vec<UnstableModesAt>,
    /// What the comparison should be read with (models of other brakes).
    pub warnings: Vec<String>,
}

/// One model's spectrum against the reference's at one friction value.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct SpectrumComparison {
    pub model: String,
    pub friction: f64,
    #[serde(flatten)]
    pub spectrum: SpectrumMatch,
}

/// Compares sweeps: the first folder is the reference.
pub fn compare(reference: &Path, others: &[PathBuf]) -> Result<Comparison, CompareError> {
    let r = Sweep::read(reference)?;
    let mut models = vec![ModelEntry {
        folder: reference.display().to_string(),
        source: r.model.source.clone(),
        equations: r.model.equations,
        instabilities: r.instabilities.len(),
        seconds_per_friction: median_seconds(&r),
        superelement: superelement_summary(&r),
    }];
    let mut instabilities = Vec::new();
    let mut extra = Vec::new();
    let mut statics = Vec::new();
    let mut spectra = Vec::new();
    let mut zones = Vec::new();
    let mut unstable_modes = Vec::new();
    for dir in others {
        let o = Sweep::read(dir)?;
        let name = dir.display().to_string();
        models.push(ModelEntry {
            folder: name.clone(),
            source: o.model.source.clone(),
            equations: o.model.equations,
            instabilities: o.instabilities.len(),
            seconds_per_friction: median_seconds(&o),
            superelement: superelement_summary(&o),
        });
        let shared: Vec<(usize, usize)> = r
            .points
            .iter()
            .enumerate()
            .filter_map(|(k, p)| o.point_at(p.friction).map(|j| (k, j)))
            .collect();
        if shared.is_empty() {
            return Err(CompareError::NoCommonFriction {
                reference: reference.to_path_buf(),
                other: dir.clone(),
            });
        }
        for &(k, j) in &shared {
            statics.extend(compare_statics(reference, dir, r.points[k].friction));
            zones.extend(compare_zones(&name, &r.points[k], &o.points[j]));
            let frequencies =
                |p: &Point| -> Vec<f64> { p.eigenvalues.iter().map(|m| m.frequency_hz).collect() };
            spectra.push(SpectrumComparison {
                model: name.clone(),
                friction: r.points[k].friction,
                spectrum: match_spectra(&frequencies(&r.points[k]), &frequencies(&o.points[j])),
            });
        }
        unstable_modes.extend(unstable_modes::unstable_modes(&name, &r, &o, &shared));
        let matches = match_instabilities(reference, &r, dir, &o);
        let mut used = vec![false; o.instabilities.len()];
        for (ri, best) in r.instabilities.iter().zip(&matches) {
            let f_ref = ri.frequency_hz_at_max;
            let best = *best;
            let mut entry = InstabilityComparison {
                reference_frequency_hz: f_ref,
                reference_onset_mu: ri.onset_mu,
                reference_max_real_part: ri.max_real_part,
                model: name.clone(),
                matched: best.is_some(),
                mac: best.and_then(|b| b.2),
                model_frequency_hz: None,
                model_onset_mu: None,
                mean_error: None,
                min_error: None,
                max_error: None,
                real_part_max_error: None,
                per_friction: Vec::new(),
                track_disagreements: Vec::new(),
                reference_on_edge: edge::instability_on_edge(&r, ri),
                reference_index: instabilities
                    .iter()
                    .filter(|c: &&InstabilityComparison| c.model == name)
                    .count(),
                curves: reference_curves(&r, ri, &shared),
            };
            if let Some((n, _, _)) = best {
                used[n] = true;
                let oi = &o.instabilities[n];
                let label = dir
                    .file_name()
                    .map_or(name.clone(), |f| f.to_string_lossy().into_owned());
                entry.model_frequency_hz = Some(oi.frequency_hz_at_max);
                entry.model_onset_mu = Some(oi.onset_mu);
                let mut real_gap = 0.0f64;
                let mut real_ref = 0.0f64;
                let mut lines: Vec<crate::study::plot::Track> = vec![
                    (format!("{label} (lower)"), Vec::new(), true),
                    (format!("{label} (upper)"), Vec::new(), true),
                ];
                for &(k, j) in &shared {
                    let Some(a) = pair_modes(&r, ri, k) else {
                        continue;
                    };
                    let modes = &o.points[j].eigenvalues;
                    let Some(found) = nearest_modes(modes, &a) else {
                        continue;
                    };
                    let mut by_track = pair_indices(&o, oi, j).unwrap_or_default();
                    let mut sorted = found.clone();
                    by_track.sort_unstable();
                    sorted.sort_unstable();
                    if by_track != sorted {
                        entry.track_disagreements.push(r.points[k].friction);
                    }
                    let b: Vec<(f64, f64)> = found
                        .iter()
                        .map(|&n| (modes[n].frequency_hz, modes[n].real_part))
                        .collect();
                    let e: f64 = a.iter().zip(&b).map(|(x, y)| relative(y.0, x.0)).sum();
                    entry.per_friction.push((r.points[k].friction, e));
                    let mut drawn = b.clone();
                    drawn.sort_by(|x, y| x.0.total_cmp(&y.0));
                    for (line, m) in lines.iter_mut().zip(&drawn) {
                        line.1.push((o.points[j].friction, m.0, m.1));
                    }
                    let top = |m: &[(f64, f64)]| m.iter().map(|x| x.1).fold(f64::MIN, f64::max);
                    real_gap = real_gap.max((top(&b) - top(&a)).abs());
                    real_ref = real_ref.max(top(&a).abs());
                }
                if !entry.per_friction.is_empty() {
                    let es: Vec<f64> = entry.per_friction.iter().map(|p| p.1).collect();
                    entry.mean_error = Some(es.iter().sum::<f64>() / es.len() as f64);
                    entry.min_error = Some(es.iter().copied().fold(f64::INFINITY, f64::min));
                    entry.max_error = Some(es.iter().copied().fold(0.0, f64::max));
                    entry.real_part_max_error = (real_ref > 0.0).then(|| real_gap / real_ref);
                }
                lines.retain(|l| !l.1.is_empty());
                entry.curves.extend(lines);
            }
            instabilities.push(entry);
        }
        for (n, oi) in o.instabilities.iter().enumerate() {
            if !used[n] {
                extra.push(ExtraInstability {
                    model: name.clone(),
                    frequency_hz: oi.frequency_hz_at_max,
                    onset_mu: oi.onset_mu,
                    max_real_part: oi.max_real_part,
                });
            }
        }
    }
    let mut warnings = given_twice(reference, others);
    warnings.extend(other_brakes(&models));
    for w in &warnings {
        tracing::warn!("{w}");
    }
    Ok(Comparison {
        models,
        instabilities,
        extra,
        statics,
        spectra,
        zones,
        reference_edge: edge::sensitive_modes(&r),
        unstable_modes,
        warnings,
    })
}

/// The folders given twice (however spelt): allowed (a sweep against itself is an identity
/// check, every error 0), but said, where it was compared without a word.
fn given_twice(reference: &Path, others: &[PathBuf]) -> Vec<String> {
    let all: Vec<&Path> = std::iter::once(reference)
        .chain(others.iter().map(PathBuf::as_path))
        .collect();
    let key = |p: &Path| p.canonicalize().unwrap_or_else(|_| p.to_path_buf());
    let mut said = Vec::new();
    for (i, a) in all.iter().enumerate() {
        if let Some(b) = all[i + 1..].iter().find(|b| key(b) == key(a)) {
            said.push(format!(
                "{} is given twice (also as {}): compared with itself, its errors are 0 by \
                 construction",
                a.display(),
                b.display()
            ));
        }
    }
    said
}

/// The models that are another brake than the reference's (their source, less what a
/// reduction adds in parentheses, differs): allowed (two meshes of one brake are a mesh
/// study), but said, where they were compared without a word.
fn other_brakes(models: &[ModelEntry]) -> Vec<String> {
    let brake = |source: &str| source.split(" (").next().unwrap_or(source).to_string();
    let reference = brake(&models[0].source);
    models[1..]
        .iter()
        .filter(|m| brake(&m.source) != reference)
        .map(|m| {
            format!(
                "{} is a model of {}, the reference {} one of {}: the modes compared are \
                 another brake's",
                m.folder,
                brake(&m.source),
                models[0].folder,
                reference
            )
        })
        .collect()
}

/// `squeal compare` (collective: every rank reads, rank 0 writes and prints).
pub fn run(
    rt: &crate::petsc::Runtime,
    reference: &Path,
    others: &[PathBuf],
    output: &Path,
) -> Result<(), super::StudyError> {
    let comm = rt.world();
    let comparison = crate::study::report::collective(comm, compare(reference, others))?;
    // Into `<output>.partial`, put in place when every file is written: a comparison that
    // fails half-way (a figure that cannot be drawn, a full disk) leaves the previous one
    // whole, not a new compare.json beside old figures.
    let claim = crate::study::staging::Claim::new(
        crate::study::ownership::Producer::Compare,
        std::iter::once(reference.to_path_buf()).chain(others.iter().cloned()),
    );
    crate::study::staging::staged(comm, output, &claim, |dir| {
        if comm.rank() == 0 {
            comparison.write(dir)?;
        }
        Ok(())
    })?;
    if comm.rank() == 0 {
        print!("{}", comparison.markdown());
        println!("\nresults in {}", output.display());
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::matching::{instability_mac, unstable_friction};
    use super::*;

    /// Writes a sweep.json a test spelt out, completed with the schema's other fields
    /// ([`crate::results::fixture::complete`]).
    fn store(dir: &Path, doc: serde_json::Value) {
        let doc = crate::results::fixture::complete(doc);
        std::fs::create_dir_all(dir).unwrap();
        std::fs::write(dir.join("sweep.json"), doc.to_string()).unwrap();
    }

    /// A sweep folder with one instability: tracks 0 and 1 at the given frequencies per mu,
    /// coupled (track 1 unstable, partner 0) with real part `a` at every point.
    fn write_sweep(dir: &Path, frequencies: &[(f64, f64)], a: f64) {
        let points: Vec<serde_json::Value> = frequencies
            .iter()
            .enumerate()
            .map(|(k, (f0, f1))| {
                serde_json::json!({
                    "friction": 0.1 * (k + 1) as f64,
                    "eigenvalues": [
                        {"frequency_hz": f0, "real_part": -a},
                        {"frequency_hz": f1, "real_part": a}
                    ]
                })
            })
            .collect();
        let n = frequencies.len();
        let doc = serde_json::json!({
            "model": {"source": dir.display().to_string(), "equations": 10},
            "points": points,
            "tracks": [
                {"id": 0, "members": vec![Some(0usize); n]},
                {"id": 1, "members": vec![Some(1usize); n]}
            ],
            "instabilities": [{
                "track": 1, "partner": 0, "onset_mu": 0.1, "max_real_part": a,
                "frequency_hz_at_max": frequencies[n - 1].1
            }]
        });
        std::fs::create_dir_all(dir).unwrap();
        store(dir, doc);
    }

    /// A reference that checked its contact edge: at mu 0.2 its instability's unstable mode
    /// is stable with the edge's points closed, and at mu 0.1 the stable mode moves by 2 %
    /// with them opened (listed), the unstable one by 0.5 % (not). Without a check, nothing
    /// is said.
    #[test]
    fn the_reference_s_own_contact_edge_is_read_from_its_points() {
        let dir = std::env::temp_dir().join(format!("squeal-compare-edge-{}", std::process::id()));
        let (r, o) = (dir.join("r"), dir.join("o"));
        write_sweep(&o, &[(1000.0, 1100.0), (1000.0, 1000.0)], 10.0);
        write_sweep(&r, &[(1000.0, 1100.0), (1000.0, 1000.0)], 10.0);
        let plain = compare(&r, std::slice::from_ref(&o)).unwrap();
        assert_eq!(plain.instabilities[0].reference_on_edge, None);
        assert!(plain.reference_edge.is_empty());

        let mode = |f: f64, a: f64, unstable: bool| {
            serde_json::json!({"frequency_hz": f, "real_part": a, "damping_ratio": 0.0,
                               "unstable": unstable, "rigid_body": false, "residual": 0.0})
        };
        let mut doc: serde_json::Value =
            serde_json::from_slice(&std::fs::read(r.join("sweep.json")).unwrap()).unwrap();
        doc["points"][0]["contact_edge"] = serde_json::json!({
            "points": 4, "opened": 4, "closed": 4, "seconds": 1.0,
            "with_opened": [mode(980.0, -10.0, false), mode(1105.5, 10.0, true)],
            "with_closed": [mode(1000.0, -10.0, false), mode(1100.0, 10.0, true)],
        });
        doc["points"][1]["contact_edge"] = serde_json::json!({
            "points": 4, "opened": 4, "closed": 4, "seconds": 1.0,
            "with_opened": [mode(1000.0, -10.0, false), mode(1000.0, 10.0, true)],
            "with_closed": [mode(1001.0, -1.0, false), mode(1001.0, -1.0, false)],
        });
        std::fs::write(r.join("sweep.json"), doc.to_string()).unwrap();
        let c = compare(&r, std::slice::from_ref(&o)).unwrap();
        assert_eq!(c.instabilities[0].reference_on_edge, Some(vec![0.2]));
        assert_eq!(c.reference_edge.len(), 1, "{:?}", c.reference_edge);
        let m = &c.reference_edge[0];
        assert_eq!(
            (m.friction, m.frequency_hz, m.opened_hz, m.points),
            (0.1, 1000.0, 980.0, 4)
        );
        let md = c.markdown();
        assert!(md.contains("## The reference's own contact edge"), "{md}");
        assert!(
            md.contains("**stable with the edge moved** at mu 0.20"),
            "{md}"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// Eqs. 12-14 by hand: per mu the two modes' relative errors add up.
    #[test]
    fn errors_are_the_papers_equations() {
        let root = tempfile::tempdir().unwrap();
        let (r, o) = (root.path().join("ref"), root.path().join("other"));
        write_sweep(&r, &[(1000.0, 1100.0), (1000.0, 1000.0)], 10.0);
        write_sweep(&o, &[(1010.0, 1100.0), (990.0, 1020.0)], 12.0);
        let c = compare(&r, std::slice::from_ref(&o)).unwrap();
        assert_eq!(c.instabilities.len(), 1);
        let i = &c.instabilities[0];
        assert!(i.matched);
        // mu 0.1: 10/1000 + 0 = 0.01; mu 0.2: 10/1000 + 20/1000 = 0.03.
        let close = |x: Option<f64>, y: f64| (x.unwrap() - y).abs() < 1e-15;
        assert!(close(i.mean_error, 0.02), "{i:?}");
        assert!(
            close(i.min_error, 0.01) && close(i.max_error, 0.03),
            "{i:?}"
        );
        // Real parts 12 against 10: 20 %.
        assert!(close(i.real_part_max_error, 0.2), "{i:?}");
        assert!(c.extra.is_empty());
    }

    /// Two instabilities 3 % apart whose tracks the other model pairs the other way round at
    /// mu 0.2: eq. 12 must measure the eigenvalues' error (0.1 % per mode), not the 3 % gap
    /// between the two physical modes, and the swap must be reported.
    #[test]
    fn swapped_tracks_of_close_instabilities_do_not_count_as_error() {
        let root = tempfile::tempdir().unwrap();
        let (r, o) = (root.path().join("ref"), root.path().join("other"));
        let sweep = |dir: &Path, scale: f64, swap: bool| {
            let modes = |mu: f64| {
                let m =
                    |f: f64, a: f64| serde_json::json!({"frequency_hz": f * scale, "real_part": a});
                serde_json::json!({
                    "friction": mu,
                    "eigenvalues": [m(1160.0, -20.0), m(1165.0, 20.0), m(1195.0, -40.0), m(1200.0, 40.0)]
                })
            };
            // At the second point the other model's tracking exchanges the two instabilities.
            let member = |own: usize, swapped: usize| {
                serde_json::json!([own, if swap { swapped } else { own }])
            };
            let doc = serde_json::json!({
                "model": {"source": "test", "equations": 10},
                "points": [modes(0.1), modes(0.2)],
                "tracks": [
                    {"id": 0, "members": member(0, 2)},
                    {"id": 1, "members": member(1, 3)},
                    {"id": 2, "members": member(2, 0)},
                    {"id": 3, "members": member(3, 1)}
                ],
                "instabilities": [
                    {"track": 1, "partner": 0, "onset_mu": 0.1, "max_real_part": 20.0,
                     "frequency_hz_at_max": 1165.0 * scale},
                    {"track": 3, "partner": 2, "onset_mu": 0.1, "max_real_part": 40.0,
                     "frequency_hz_at_max": 1200.0 * scale}
                ]
            });
            std::fs::create_dir_all(dir).unwrap();
            store(dir, doc);
        };
        sweep(&r, 1.0, false);
        sweep(&o, 1.001, true);
        let c = compare(&r, std::slice::from_ref(&o)).unwrap();
        assert_eq!(c.instabilities.len(), 2);
        for i in &c.instabilities {
            assert!(i.matched, "{i:?}");
            // Two modes, each 0.1 % off: e_j = 0.002 at both values.
            let max = i.max_error.unwrap();
            assert!((max - 0.002).abs() < 1e-12, "{i:?}");
            assert!((i.min_error.unwrap() - 0.002).abs() < 1e-12, "{i:?}");
            assert!(i.real_part_max_error.unwrap() < 1e-12, "{i:?}");
            assert_eq!(i.track_disagreements, vec![0.2], "{i:?}");
            // The drawn curves are the matched modes, not the swapped tracks.
            let model_upper = &i
                .curves
                .iter()
                .find(|t| t.0.ends_with("(upper)") && t.2)
                .unwrap()
                .1;
            assert!(
                (model_upper[1].1 - model_upper[0].1).abs() < 1e-9,
                "{model_upper:?}"
            );
        }
        assert!(c.markdown().contains("0.20"), "{}", c.markdown());
    }

    /// An instability 10 % away is another instability: missed in one model, extra in the
    /// other.
    #[test]
    fn far_instabilities_are_missed_and_extra() {
        let root = tempfile::tempdir().unwrap();
        let (r, o) = (root.path().join("ref"), root.path().join("other"));
        write_sweep(&r, &[(1000.0, 1000.0)], 10.0);
        write_sweep(&o, &[(1100.0, 1100.0)], 10.0);
        let c = compare(&r, std::slice::from_ref(&o)).unwrap();
        assert!(!c.instabilities[0].matched && c.instabilities[0].mean_error.is_none());
        assert_eq!(c.extra.len(), 1);
        assert!(c.markdown().contains("**missed**"));
    }

    /// The medium caliper's case: the reference has a 5377 Hz instability at mu 0.1 only and
    /// a 5236 Hz one at mu 0.2-0.3; the other model has one instability, at 5259 Hz and mu
    /// 0.2-0.3. Both reference instabilities are within the frequency tolerance of it, and
    /// the first in the reference's order is the 5377 Hz one: the match must go to the
    /// instability unstable at the same friction values, and the 5377 Hz one is missed.
    #[test]
    fn instabilities_are_matched_where_they_are_unstable() {
        let root = tempfile::tempdir().unwrap();
        let (r, o) = (root.path().join("ref"), root.path().join("other"));
        // Per mu, (frequency, real part) of four modes; tracks k = mode k at every point.
        let sweep = |dir: &Path, modes: [[(f64, f64); 4]; 3], instabilities: serde_json::Value| {
            let points: Vec<serde_json::Value> = modes
                .iter()
                .enumerate()
                .map(|(k, m)| {
                    let list: Vec<serde_json::Value> = m
                        .iter()
                        .map(|&(f, a)| {
                            serde_json::json!({"frequency_hz": f, "real_part": a, "unstable": a > 0.0})
                        })
                        .collect();
                    serde_json::json!({"friction": 0.1 * (k + 1) as f64, "eigenvalues": list})
                })
                .collect();
            let doc = serde_json::json!({
                "model": {"source": "test", "equations": 10},
                "points": points,
                "tracks": (0..4).map(|t| serde_json::json!({"id": t, "members": [t, t, t]})).collect::<Vec<_>>(),
                "instabilities": instabilities
            });
            std::fs::create_dir_all(dir).unwrap();
            store(dir, doc);
        };
        let record = |track: usize, f: f64, mu: f64| {
            serde_json::json!({"track": track, "partner": track - 1, "onset_mu": mu,
                "max_real_part": 50.0, "frequency_hz_at_max": f, "mu_at_max": mu})
        };
        sweep(
            &r,
            [
                [
                    (5200.0, -1.0),
                    (5220.0, -1.0),
                    (5377.0, -50.0),
                    (5377.0, 50.0),
                ],
                [
                    (5236.0, -40.0),
                    (5236.0, 40.0),
                    (5360.0, -1.0),
                    (5390.0, -1.0),
                ],
                [
                    (5236.0, -50.0),
                    (5236.0, 50.0),
                    (5350.0, -1.0),
                    (5400.0, -1.0),
                ],
            ],
            serde_json::json!([record(3, 5377.0, 0.1), record(1, 5236.0, 0.3)]),
        );
        sweep(
            &o,
            [
                [
                    (5215.0, -1.0),
                    (5240.0, -1.0),
                    (5480.0, -1.0),
                    (5500.0, -1.0),
                ],
                [
                    (5259.0, -40.0),
                    (5259.0, 40.0),
                    (5470.0, -1.0),
                    (5510.0, -1.0),
                ],
                [
                    (5259.0, -50.0),
                    (5259.0, 50.0),
                    (5460.0, -1.0),
                    (5520.0, -1.0),
                ],
            ],
            serde_json::json!([record(1, 5259.0, 0.3)]),
        );
        let c = compare(&r, std::slice::from_ref(&o)).unwrap();
        let by_frequency = |f: f64| {
            c.instabilities
                .iter()
                .find(|i| i.reference_frequency_hz == f)
                .unwrap()
        };
        assert!(!by_frequency(5377.0).matched, "{:?}", c.instabilities);
        let b = by_frequency(5236.0);
        assert!(b.matched && b.model_frequency_hz == Some(5259.0), "{b:?}");
        // At mu 0.2 and 0.3 the pair is 23 Hz off in each mode: e_j = 2 * 23 / 5236.
        let e = 2.0 * 23.0 / 5236.0;
        assert!((b.max_error.unwrap() - e).abs() < 1e-12, "{b:?}");
        assert!(c.extra.is_empty());
    }

    /// The patch L2: 0 for two fields with the same force on every patch however it is
    /// spread inside (a corner/mid-side oscillation against its mean), exactly the scale
    /// error for a field scaled by 1.1, and node by node when each node is its own patch.
    #[test]
    fn the_patch_pressure_difference_sees_patch_forces_only() {
        use crate::results::SurfacePressure;
        // A strip of 12 nodes, areas alternating 1 and 2, two patches of 6 around x = 2.5
        // and x = 8.5.
        let node = |i: usize, pressure: f64| SurfacePressure {
            pair: "p".into(),
            node: i,
            position: [i as f64, 0.0, 0.0],
            area: if i.is_multiple_of(2) { 1.0 } else { 2.0 },
            pressure,
        };
        let uniform: Vec<_> = (0..12).map(|i| node(i, 3.0)).collect();
        // Same force per patch: p A = 1.5 on area-1 nodes and 3.75 on area-2 nodes gives
        // (3 * 1.5 + 3 * 7.5) / 9 = 3 per patch.
        let oscillating: Vec<_> = (0..12)
            .map(|i| node(i, if i % 2 == 0 { 1.5 } else { 3.75 }))
            .collect();
        let points = [[2.5, 0.0, 0.0], [8.5, 0.0, 0.0]];
        let l2 = patch_pressure_l2(&uniform, &oscillating, &points).unwrap();
        assert!(l2 < 1e-15, "{l2}");
        let scaled: Vec<_> = (0..12).map(|i| node(i, 3.3)).collect();
        let l2 = patch_pressure_l2(&uniform, &scaled, &points).unwrap();
        assert!((l2 - 0.1).abs() < 1e-14, "{l2}");
        // Every node its own patch: the nodal L2 of the oscillation, errors 1.5 on the six
        // area-1 nodes and 0.75 on the six area-2 ones against 3 on area 18.
        let own: Vec<[f64; 3]> = (0..12).map(|i| [i as f64, 0.0, 0.0]).collect();
        let l2 = patch_pressure_l2(&uniform, &oscillating, &own).unwrap();
        let expect = ((6.0 * 1.5f64.powi(2) + 12.0 * 0.75f64.powi(2)) / (18.0 * 9.0)).sqrt();
        assert!((l2 - expect).abs() < 1e-14, "{l2} vs {expect}");
        assert!(patch_pressure_l2(&uniform, &oscillating, &[]).is_none());
    }

    /// An edited sweep.json (a negative friction, more equations than three per node, a
    /// NaN eigenvalue) is refused naming the file and what; a folder given twice and
    /// another brake's model are said.
    #[test]
    fn inputs_no_sweep_holds_are_refused_and_doubtful_ones_said() {
        let root = tempfile::tempdir().unwrap();
        let (r, o) = (root.path().join("ref"), root.path().join("other"));
        write_sweep(&r, &[(1000.0, 1100.0), (1000.0, 1000.0)], 10.0);
        write_sweep(&o, &[(1010.0, 1100.0), (990.0, 1020.0)], 12.0);
        let twice = |c: Comparison| {
            c.warnings
                .iter()
                .filter(|w| w.contains("is given twice"))
                .count()
        };
        assert_eq!(twice(compare(&r, std::slice::from_ref(&r)).unwrap()), 1);
        let spelt = root.path().join(".").join("other");
        assert_eq!(twice(compare(&r, &[o.clone(), spelt]).unwrap()), 1);
        assert_eq!(twice(compare(&r, std::slice::from_ref(&o)).unwrap()), 0);
        let edit = |what: &str, with: &str| {
            let file = o.join("sweep.json");
            let text = std::fs::read_to_string(&file).unwrap();
            assert!(text.contains(what), "{text}");
            std::fs::write(&file, text.replacen(what, with, 1)).unwrap();
            let e = compare(&r, std::slice::from_ref(&o))
                .unwrap_err()
                .to_string();
            std::fs::write(&file, text).unwrap();
            e
        };
        let e = edit("\"friction\":0.1", "\"friction\":-0.5");
        assert!(
            e.contains("other/sweep.json") && e.contains("friction is -0.5"),
            "{e}"
        );
        let e = edit(
            "\"equations\":10",
            "\"equations\":1000000000000,\"nodes\":100",
        );
        assert!(e.contains("at most three per node"), "{e}");
        let e = edit("\"frequency_hz\":1010.0", "\"frequency_hz\":1e999");
        assert!(
            e.contains("not a squeal sweep.json") || e.contains("Hz"),
            "{e}"
        );
        // The same brake (what a reduction adds in parentheses aside): nothing to say;
        // another brake: said.
        let source = |dir: &Path, text: &str| {
            let file = dir.join("sweep.json");
            let doc = std::fs::read_to_string(&file).unwrap();
            let before = format!(
                "\"source\":{}",
                serde_json::json!(dir.display().to_string())
            );
            assert!(doc.contains(&before), "{doc}");
            std::fs::write(
                &file,
                doc.replace(&before, &format!("\"source\":{}", serde_json::json!(text))),
            )
            .unwrap();
        };
        source(&r, "built-in brake 'tiny'");
        source(
            &o,
            "built-in brake 'tiny' (reduced interface: 22 nodes + 22 nodes)",
        );
        assert!(compare(&r, std::slice::from_ref(&o))
            .unwrap()
            .warnings
            .is_empty());
        let file = o.join("sweep.json");
        let doc = std::fs::read_to_string(&file).unwrap();
        std::fs::write(&file, doc.replace("'tiny'", "'small'")).unwrap();
        let c = compare(&r, std::slice::from_ref(&o)).unwrap();
        assert_eq!(c.warnings.len(), 1);
        assert!(
            c.warnings[0].contains("built-in brake 'small'"),
            "{:?}",
            c.warnings
        );
        assert!(c.markdown().contains("**Warning**"));
    }

    #[test]
    fn a_folder_without_a_sweep_is_named() {
        let root = tempfile::tempdir().unwrap();
        let e = compare(root.path(), &[root.path().join("other")]).unwrap_err();
        assert!(e.to_string().contains("sweep.json"), "{e}");
    }

    /// A growing pair whose partner track the reference's tracking lost after the first value
    /// (as medium-caliper's 645 Hz pair): without damping the partner is the growing mode's
    /// mirror (the same frequency, the opposite real part), so eq. 12 is read at every value;
    /// where no mode mirrors it (a damped model), the value is skipped, not guessed.
    #[test]
    fn a_lost_partner_is_the_growing_modes_mirror() {
        let root = tempfile::tempdir().unwrap();
        let sweep = |dir: &Path, scale: f64, mirrored: bool| {
            let m = |f: f64, a: f64| serde_json::json!({"frequency_hz": f * scale, "real_part": a});
            let b = if mirrored { -300.0 } else { -250.0 };
            let doc = serde_json::json!({
                "model": {"source": "test", "equations": 10},
                "points": [
                    {"friction": 0.3, "eigenvalues": [m(626.0, -150.0), m(626.0, 150.0), m(1000.0, 0.0)]},
                    {"friction": 0.4, "eigenvalues": [m(650.0, b), m(650.0, 300.0), m(1000.0, 0.0)]},
                    {"friction": 0.5, "eigenvalues": [m(645.0, 2.0 * b), m(645.0, 600.0), m(1000.0, 0.0)]}
                ],
                // The partner's track goes on to the 1000 Hz mode, then ends.
                "tracks": [
                    {"id": 0, "members": [0, 2, null]},
                    {"id": 1, "members": [1, 1, 1]}
                ],
                "instabilities": [{
                    "track": 1, "partner": 0, "onset_mu": 0.3, "max_real_part": 600.0,
                    "frequency_hz_at_max": 645.0 * scale, "mu_at_max": 0.5
                }]
            });
            std::fs::create_dir_all(dir).unwrap();
            store(dir, doc);
        };
        let (r, o, d) = (
            root.path().join("ref"),
            root.path().join("other"),
            root.path().join("damped"),
        );
        sweep(&r, 1.0, true);
        sweep(&o, 1.001, true);
        sweep(&d, 1.0, false);
        let r_sweep = Sweep::read(&r).unwrap();
        // At 0.4 the tracked partner is the 1000 Hz mode: kept (the tracking's word stands
        // where it has one); at 0.5 the mirror of the 645 Hz growing mode.
        assert_eq!(
            pair_indices(&r_sweep, &r_sweep.instabilities[0], 2),
            Some(vec![1, 0])
        );
        assert_eq!(
            unstable_friction(&r_sweep, &r_sweep.instabilities[0]),
            vec![0.3, 0.4, 0.5]
        );
        let c = compare(&r, std::slice::from_ref(&o)).unwrap();
        let mirrored = &c.instabilities[0];
        let values: Vec<f64> = mirrored.per_friction.iter().map(|p| p.0).collect();
        assert_eq!(values, vec![0.3, 0.4, 0.5], "{mirrored:?}");
        // Each of the two modes 0.1 % off; the other model's pair found the same way.
        assert!(
            (mirrored.per_friction[2].1 - 0.002).abs() < 1e-12,
            "{mirrored:?}"
        );
        assert!(mirrored.track_disagreements.is_empty(), "{mirrored:?}");
        // A damped reference: no mirror at 0.5, so that value is not read.
        let c = compare(&d, std::slice::from_ref(&o)).unwrap();
        let damped = &c.instabilities[0];
        let values: Vec<f64> = damped.per_friction.iter().map(|p| p.0).collect();
        assert_eq!(values, vec![0.3, 0.4], "{damped:?}");
    }

    /// The MAC pairs shapes of the same instability only: a folder with no unstable shape
    /// near the instability's frequency (its CEA called the mode stable or rigid) gives no
    /// MAC, not the MAC against another instability's shape.
    #[test]
    fn no_mac_from_another_instabilitys_shape() {
        let root = tempfile::tempdir().unwrap();
        let folder = |name: &str, shapes: &[(f64, [f64; 3])]| {
            let dir = root.path().join(name);
            write_sweep(&dir, &[(645.0, 645.0)], 500.0);
            let map = crate::results::ContactMap {
                shape_nodes: vec![7],
                unstable_shapes: shapes
                    .iter()
                    .map(|&(f, re)| crate::results::SurfaceShape {
                        frequency_hz: f,
                        real_part: 500.0,
                        re: vec![re],
                        im: vec![[0.0; 3]],
                    })
                    .collect(),
                ..Default::default()
            };
            let point = dir.join("mu_0.100");
            std::fs::create_dir_all(&point).unwrap();
            std::fs::write(
                point.join("contact.json"),
                serde_json::to_string(&map).unwrap(),
            )
            .unwrap();
            let mut sweep = Sweep::read(&dir).unwrap();
            // Its one point is mu 0.1, where the shapes are.
            sweep.instabilities[0].mu_at_max = 0.1;
            (dir.clone(), sweep)
        };
        let (a, sa) = folder("a", &[(645.0, [1.0, 0.0, 0.0]), (1207.0, [0.0, 1.0, 0.0])]);
        let (b, sb) = folder("b", &[(645.5, [2.0, 0.0, 0.0])]);
        let (c, sc) = folder("c", &[(1207.0, [0.0, 1.0, 0.0])]);
        let (ia, ib, ic) = (
            &sa.instabilities[0],
            &sb.instabilities[0],
            &sc.instabilities[0],
        );
        let mac = instability_mac(&a, ia, &b, ib).unwrap();
        assert!((mac - 1.0).abs() < 1e-15, "{mac}");
        assert_eq!(instability_mac(&a, ia, &c, ic), None);
        assert_eq!(instability_mac(&c, ic, &a, ia), None);
    }
}
