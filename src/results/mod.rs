//! The typed schema of a sweep folder: `sweep.json` ([`SweepDocument`]: the model, its points,
//! tracks and instabilities) and `contact.json` ([`ContactMap`]), each one set of types that
//! the sweep writes ([`crate::study::sweep::output::write_sweep`]) and that `squeal compare`
//! and the study report read. Before, the writer had its own borrowed struct, compare its own private
//! copies of some fields and the report some 40 string lookups into untyped JSON: a field
//! renamed in the writer turned the report's cell into "-" without a word (issue 31). Now a
//! rename is a compile error in every reader.
//!
//! Folders of older squeal versions are read as they always were: a missing eigenvalue flag
//! `unstable` is the CEA's own decision with the default threshold (not `real part > 0`,
//! which counts round-off as growth), and a missing `seconds`, `model.nodes` or
//! `mu_at_max` reads as 0 (unknown). Anything else missing is refused by name.

mod cea_json;
mod contact_map;
mod model;
mod point;

pub use cea_json::{CeaDocument, DeckStep, FrictionPoint, MatrixFiles};
pub use contact_map::{ContactMap, ContactMapPoint, SurfacePressure, SurfaceShape};
pub use model::ModelInfo;
pub use point::{EdgeCheck, PairReport, SuperElementInfo, SuperElementPoint, SweepPointReport};

use crate::analysis::cea;
use crate::analysis::tracking::{Instability, Track};
use num_complex::Complex64;
use std::path::{Path, PathBuf};

/// Everything a sweep folder's sweep.json holds.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct SweepDocument {
    pub model: ModelInfo,
    pub points: Vec<SweepPointReport>,
    pub tracks: Vec<Track>,
    pub instabilities: Vec<Instability>,
}

/// Why a result file (sweep.json, compare.json) could not be read.
#[derive(Debug, thiserror::Error)]
pub enum DocumentError {
    #[error("reading {}: {source}", file.display())]
    Read {
        file: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error(
        "{}: not a squeal {}: {message}",
        file.display(),
        file.file_name().map_or(String::new(), |n| n.to_string_lossy().into_owned())
    )]
    Format { file: PathBuf, message: String },
}

/// A result file's JSON as `T`: the file named in either error.
pub fn read_document<T: serde::de::DeserializeOwned>(file: &Path) -> Result<T, DocumentError> {
    let bytes = std::fs::read(file).map_err(|source| DocumentError::Read {
        file: file.to_path_buf(),
        source,
    })?;
    serde_json::from_slice(&bytes).map_err(|e| DocumentError::Format {
        file: file.to_path_buf(),
        message: e.to_string(),
    })
}

impl SweepDocument {
    /// The file's name in a sweep folder.
    pub const FILE: &'static str = "sweep.json";

    /// Reads `dir`/sweep.json, fills what older versions did not write (see the module
    /// doc), and refuses what no sweep squeal wrote holds ([`SweepDocument::check`]).
    pub fn read(dir: &Path) -> Result<SweepDocument, DocumentError> {
        let file = dir.join(Self::FILE);
        let format = |message: String| DocumentError::Format {
            file: file.clone(),
            message,
        };
        let mut value: serde_json::Value = read_document(&file)?;
        migrate(&mut value);
        let mut doc: SweepDocument =
            serde_json::from_value(value).map_err(|e| format(e.to_string()))?;
        doc.check().map_err(format)?;
        // lambda is not written (the frequency and real part are): put it back.
        for mode in doc.points.iter_mut().flat_map(|p| &mut p.eigenvalues) {
            mode.lambda = Complex64::new(
                mode.real_part,
                2.0 * std::f64::consts::PI * mode.frequency_hz,
            );
        }
        Ok(doc)
    }

    /// What no sweep squeal wrote holds: an equation count beyond three per node, a
    /// negative or non-finite friction value, a non-finite eigenvalue, a track whose
    /// members point past its point's eigenvalues. (An edited file was compared without a
    /// word.)
    pub fn check(&self) -> Result<(), String> {
        let m = &self.model;
        if m.equations == 0 || (m.nodes > 0 && m.equations > 3 * m.nodes) {
            return Err(format!(
                "model.equations = {} for {} nodes: at most three per node",
                m.equations,
                if m.nodes > 0 {
                    m.nodes.to_string()
                } else {
                    "?".into()
                }
            ));
        }
        for p in &self.points {
            if !(p.friction.is_finite() && p.friction >= 0.0) {
                return Err(format!("a point's friction is {}", p.friction));
            }
            if let Some(e) = p
                .eigenvalues
                .iter()
                .find(|e| !(e.frequency_hz.is_finite() && e.real_part.is_finite()))
            {
                return Err(format!(
                    "at mu {} an eigenvalue is {} Hz, {} 1/s",
                    p.friction, e.frequency_hz, e.real_part
                ));
            }
        }
        for t in &self.tracks {
            if t.members.len() != self.points.len() {
                return Err(format!(
                    "track {} has {} members for {} points",
                    t.id,
                    t.members.len(),
                    self.points.len()
                ));
            }
            for (k, n) in t.members.iter().enumerate() {
                if let Some(n) = *n {
                    if n >= self.points[k].eigenvalues.len() {
                        return Err(format!(
                            "track {} names mode {n} at mu {}, which has {} modes",
                            t.id,
                            self.points[k].friction,
                            self.points[k].eigenvalues.len()
                        ));
                    }
                }
            }
        }
        Ok(())
    }

    /// The point at friction `mu` (to 1e-9 relative).
    pub fn point_at(&self, mu: f64) -> Option<usize> {
        self.points
            .iter()
            .position(|p| (p.friction - mu).abs() <= 1e-9 * mu.abs().max(1.0))
    }
}

/// An instability's unstable mode where its real part is largest: at the point of
/// `mu_at_max`, the unstable eigenvalue nearest to (`frequency_hz_at_max`, `max_real_part`).
pub fn mode_at_max<'a>(
    points: &'a [SweepPointReport],
    i: &crate::analysis::tracking::Instability,
) -> Option<&'a crate::analysis::cea::ComplexMode> {
    let point = points
        .iter()
        .find(|p| (p.friction - i.mu_at_max).abs() <= 1e-9 * i.mu_at_max.abs().max(1.0))?;
    let distance = |m: &crate::analysis::cea::ComplexMode| {
        (2.0 * std::f64::consts::PI * (m.frequency_hz - i.frequency_hz_at_max))
            .hypot(m.real_part - i.max_real_part)
    };
    point
        .eigenvalues
        .iter()
        .filter(|m| m.unstable)
        .min_by(|a, b| distance(a).total_cmp(&distance(b)))
}

/// "mu 0.30-0.40 (regret 0.031, frequency -4.1 %), ...": the uncertain links an instability
/// stands on, or `None` when it stands on trusted ones only.
pub fn uncertain_links(i: &crate::analysis::tracking::Instability) -> Option<String> {
    (!i.uncertain_links.is_empty()).then(|| {
        i.uncertain_links
            .iter()
            .map(|u| {
                format!(
                    "track {} mu {}-{} (regret {:.3}, frequency {:+.1} %{})",
                    u.track,
                    friction_text(u.from_mu),
                    friction_text(u.to_mu),
                    u.regret,
                    100.0 * u.frequency_change,
                    if u.contact_changed {
                        ", the contact state changes"
                    } else {
                        ""
                    }
                )
            })
            .collect::<Vec<_>>()
            .join(", ")
    })
}

/// A friction value as folders and tables show it: three decimals ("0.300"), or as many
/// more as it needs to read back as itself (an inserted 0.1125), at most nine.
pub fn friction_text(mu: f64) -> String {
    (3..=9)
        .map(|d| format!("{mu:.d$}"))
        .find(|t| t.parse::<f64>() == Ok(mu))
        .unwrap_or_else(|| format!("{mu:.9}"))
}

/// A friction value in a table or a sentence: two decimals where they say it all ("0.30"),
/// else as [`friction_text`] (an inserted "0.125").
pub fn friction_label(mu: f64) -> String {
    let t = friction_text(mu);
    match t.strip_suffix('0') {
        Some(short) if t.len() == 5 => short.to_string(),
        _ => t,
    }
}

/// An instability whose frequency where it is first unstable and where it grows fastest
/// differ by more than this fraction gets a word on how it got there.
pub const DRIFT_SAID: f64 = 0.05;

/// "first unstable at mu 0.413 (709.6 Hz), 5.0 % from its frequency at the largest real
/// part (mu 0.90), along links that are all sure: ..." for an instability whose frequency
/// where it is first unstable differs from the one where it grows fastest by more than
/// [`DRIFT_SAID`] of the latter; `None` otherwise.
pub fn frequency_drift(i: &crate::analysis::tracking::Instability) -> Option<String> {
    let at_max = i.frequency_hz_at_max;
    let apart = (i.frequency_hz_at_first_unstable - at_max).abs() / at_max;
    (apart > DRIFT_SAID).then(|| {
        format!(
            "first unstable at mu {} ({:.1} Hz), {:.1} % from its frequency at the largest \
             real part (mu {}), {}",
            friction_label(i.first_unstable_mu),
            i.frequency_hz_at_first_unstable,
            100.0 * apart,
            friction_label(i.mu_at_max),
            if i.uncertain_links.is_empty() {
                "along links that are all sure: the coupled pair's frequency changes with \
                 friction"
            } else {
                "across the uncertain links said: the two ends may be two different modes"
            }
        )
    })
}

/// "pad_outboard_backplate 50 %, pad_outboard_friction 24 %, caliper 17 %": the `count`
/// bodies with the largest shares, largest first.
pub fn largest_shares(shares: &std::collections::BTreeMap<String, f64>, count: usize) -> String {
    let mut by_size: Vec<(&String, &f64)> = shares.iter().collect();
    by_size.sort_by(|a, b| b.1.total_cmp(a.1).then(a.0.cmp(b.0)));
    by_size
        .iter()
        .take(count)
        .map(|(name, share)| format!("{name} {:.0} %", 100.0 * **share))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The `count` bodies whose modulus moves a mode's real part most, as "disc: Re -1.230 1/s,
/// f +0.41 Hz": a hundredth of the per-ln-E derivatives (1 % stiffer; first order, which
/// near a coalescence holds only for smaller changes), largest |Re| first.
pub fn stiffest_bodies(
    moduli: &std::collections::BTreeMap<String, crate::analysis::sensitivity::ModulusSensitivity>,
    count: usize,
) -> String {
    let mut rows: Vec<_> = moduli.iter().collect();
    rows.sort_by(|a, b| {
        b.1.d_real_part_d_ln_young
            .abs()
            .total_cmp(&a.1.d_real_part_d_ln_young.abs())
            .then(a.0.cmp(b.0))
    });
    rows.iter()
        .take(count)
        .map(|(body, s)| {
            format!(
                "{body}: Re {:+.3} 1/s, f {:+.2} Hz",
                0.01 * s.d_real_part_d_ln_young,
                0.01 * s.d_frequency_hz_d_ln_young
            )
        })
        .collect::<Vec<_>>()
        .join("; ")
}

/// Fills what older versions did not write: each eigenvalue's `unstable` flag, by the CEA's
/// own rule with the default threshold.
fn migrate(doc: &mut serde_json::Value) {
    let Some(points) = doc.get_mut("points").and_then(|p| p.as_array_mut()) else {
        return;
    };
    for point in points {
        let Some(modes) = point.get_mut("eigenvalues").and_then(|e| e.as_array_mut()) else {
            continue;
        };
        for mode in modes {
            let Some(object) = mode.as_object_mut() else {
                continue;
            };
            if object.contains_key("unstable") {
                continue;
            }
            let number = |key: &str| object.get(key).and_then(|v| v.as_f64());
            if let (Some(f), Some(a)) = (number("frequency_hz"), number("real_part")) {
                let lambda = Complex64::new(a, 2.0 * std::f64::consts::PI * f);
                let flag = cea::is_unstable(lambda, cea::DEFAULT_UNSTABLE_THRESHOLD);
                object.insert("unstable".into(), serde_json::Value::Bool(flag));
            }
        }
    }
}

/// Sweep documents for tests.
#[cfg(test)]
pub(crate) mod fixture {
    use serde_json::{json, Value};

    /// A sweep.json a test spelt out, completed with the schema's other fields (neutral
    /// values: no static iterations, no damping, the onset bracketed at the first unstable
    /// point), so that each test says only what it is about.
    pub fn complete(mut doc: Value) -> Value {
        fn fill(v: &mut Value, defaults: Value) {
            if let (Some(o), Value::Object(d)) = (v.as_object_mut(), defaults) {
                for (k, x) in d {
                    o.entry(k).or_insert(x);
                }
            }
        }
        fill(
            &mut doc["model"],
            json!({"elements": 0, "ranks": 1, "pairs": [], "max_frequency_hz": 1e4}),
        );
        for p in doc["points"].as_array_mut().into_iter().flatten() {
            fill(
                p,
                json!({"static_iterations": 0, "static_factorizations": 0,
                       "static_residuals": [], "cutbacks": 0, "contact": [],
                       "balance_ratio": 1.0, "static_seconds": 0.0, "cea_seconds": 0.0,
                       "cea_shifts": 0, "peak_rss_mib_max_rank": 0.0,
                       "peak_rss_mib_all_ranks": 0.0}),
            );
            for m in p["eigenvalues"].as_array_mut().into_iter().flatten() {
                fill(
                    m,
                    json!({"damping_ratio": 0.0, "rigid_body": false, "residual": 0.0}),
                );
            }
        }
        for t in doc["tracks"].as_array_mut().into_iter().flatten() {
            let n = t["members"].as_array().map_or(0, Vec::len);
            fill(t, json!({ "link_mac": vec![Value::Null; n] }));
        }
        for i in doc["instabilities"].as_array_mut().into_iter().flatten() {
            let (mu, f) = (i["onset_mu"].clone(), i["frequency_hz_at_max"].clone());
            fill(
                i,
                json!({"onset_bracketed": true, "frequency_hz_at_onset": f,
                       "first_unstable_mu": mu, "frequency_hz_at_first_unstable": f}),
            );
        }
        doc
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn a_frequency_that_moves_more_than_five_percent_is_explained() {
        use crate::analysis::tracking::{Instability, UncertainLink};
        let mut i = Instability {
            track: 0,
            partner: Some(1),
            onset_mu: 0.4,
            onset_bracketed: true,
            coalescence_mu: None,
            frequency_hz_at_onset: 710.0,
            first_unstable_mu: 0.413,
            frequency_hz_at_first_unstable: 709.6,
            max_real_part: 626.0,
            mu_at_max: 0.9,
            frequency_hz_at_max: 675.7,
            restabilisation_mu: None,
            uncertain_links: Vec::new(),
        };
        // 709.6 against 675.7 Hz: 5.02 % of the latter (4.78 % of the former).
        let said = super::frequency_drift(&i).expect("more than 5 %");
        assert!(
            said.starts_with(
                "first unstable at mu 0.413 (709.6 Hz), 5.0 % from its frequency at the largest \
                 real part (mu 0.90), along links that are all sure"
            ),
            "{said}"
        );
        i.uncertain_links.push(UncertainLink {
            track: 1,
            from_mu: 0.5,
            to_mu: 0.6,
            mac: 0.9,
            regret: 0.1,
            frequency_change: 0.01,
            contact_changed: true,
        });
        assert!(super::frequency_drift(&i)
            .unwrap()
            .contains("across the uncertain links"));
        i.frequency_hz_at_max = 676.0;
        assert_eq!(super::frequency_drift(&i), None);
    }

    #[test]
    fn friction_labels_keep_two_decimals_where_they_say_it_all() {
        assert_eq!(super::friction_label(0.3), "0.30");
        assert_eq!(super::friction_label(0.125), "0.125");
        assert_eq!(super::friction_label(0.1125), "0.1125");
        assert_eq!(super::friction_label(1.0), "1.00");
    }

    #[test]
    fn friction_values_read_back_as_themselves() {
        assert_eq!(super::friction_text(0.3), "0.300");
        assert_eq!(super::friction_text(0.35), "0.350");
        assert_eq!(super::friction_text(0.1125), "0.1125");
        assert_eq!(super::friction_text(113.0 / 1000.0), "0.113");
        assert_eq!(super::friction_text(0.1 + 0.2), "0.300000000");
    }

    use super::*;
    use serde_json::json;

    /// Two points, a coupled pair unstable at the second; the first point's modes carry no
    /// `unstable` flag (an older folder), with a real part of round-off at the first.
    fn doc() -> serde_json::Value {
        fixture::complete(json!({
            "model": {"source": "test", "equations": 12, "nodes": 4},
            "points": [
                {"friction": 0.1, "eigenvalues": [
                    {"frequency_hz": 1000.0, "real_part": 1e-9},
                    {"frequency_hz": 1100.0, "real_part": 0.0}]},
                {"friction": 0.2, "eigenvalues": [
                    {"frequency_hz": 1050.0, "real_part": -5.0, "unstable": false},
                    {"frequency_hz": 1050.0, "real_part": 5.0, "unstable": true}]}
            ],
            "tracks": [{"id": 0, "members": [0, 0]}, {"id": 1, "members": [1, 1]}],
            "instabilities": [{"track": 1, "partner": 0, "onset_mu": 0.15,
                               "max_real_part": 5.0, "frequency_hz_at_max": 1050.0,
                               "mu_at_max": 0.2}]
        }))
    }

    fn folder(doc: &serde_json::Value) -> tempfile::TempDir {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join(SweepDocument::FILE), doc.to_string()).unwrap();
        dir
    }

    #[test]
    fn what_is_written_is_what_is_read_and_older_flags_are_the_ceas_own() {
        let dir = folder(&doc());
        let read = SweepDocument::read(dir.path()).unwrap();
        // The missing flags: round-off (1e-9 of |lambda| ~ 6e3) is not growth.
        assert!(!read.points[0].eigenvalues[0].unstable);
        assert!(read.points[1].eigenvalues[1].unstable);
        // lambda comes back from what is written.
        let m = &read.points[1].eigenvalues[1];
        assert_eq!(
            m.lambda,
            Complex64::new(5.0, 2.0 * std::f64::consts::PI * 1050.0)
        );
        assert_eq!(read.point_at(0.2 + 1e-12), Some(1));
        // Written again and read back: the same document.
        let again = folder(&serde_json::to_value(&read).unwrap());
        let back = SweepDocument::read(again.path()).unwrap();
        assert_eq!(
            serde_json::to_value(&back).unwrap(),
            serde_json::to_value(&read).unwrap()
        );
        assert_eq!(back.instabilities, read.instabilities);
        assert_eq!(back.tracks, read.tracks);
    }

    #[test]
    fn a_missing_field_or_an_impossible_value_is_refused_by_name() {
        let mut d = doc();
        d["instabilities"][0]
            .as_object_mut()
            .unwrap()
            .remove("first_unstable_mu");
        let dir = folder(&d);
        let e = SweepDocument::read(dir.path()).unwrap_err().to_string();
        assert!(
            e.contains("sweep.json") && e.contains("first_unstable_mu"),
            "{e}"
        );
        let mut d = doc();
        d["tracks"][1]["members"] = json!([1, 2]);
        let dir = folder(&d);
        let e = SweepDocument::read(dir.path()).unwrap_err().to_string();
        assert!(e.contains("track 1 names mode 2"), "{e}");
        let mut d = doc();
        d["model"]["equations"] = json!(13);
        let dir = folder(&d);
        let e = SweepDocument::read(dir.path()).unwrap_err().to_string();
        assert!(e.contains("at most three per node"), "{e}");
    }
}
