//! The friction values a sweep has finished, kept by key so that a sweep stopped part-way
//! (Ctrl-C, SIGTERM, a crash) or rerun with more friction values computes only the points it
//! has not got (`squeal study`).
//!
//! A point's result depends on the model and on the path that led to it: its equilibrium is
//! warm-started from the previous point's and Coulomb pairs carry their slip history from
//! one friction value to the next. Its key is therefore a hash of the model's key (everything
//! the sweep depends on but its friction list) and of the friction values swept up to and
//! including it, in order. Extending the list reuses every point before the first change; a
//! changed or inserted value recomputes from there on.
//!
//! Each entry is a folder `<key>/`: the point's files as the sweep wrote them (`files/`,
//! hard links when the file system allows, copies otherwise), `point.json` (the report,
//! the eigenvalues to the bit, the tracked shapes and the [`ModelCheckpoint`] the next point
//! starts from) and `entry.json`, what the entry held when it was made: its key, its mu,
//! and the length and hash of `point.json` and of every file ([`Manifest`]). An entry is
//! used only when all of it checks out; an edited, truncated, exchanged or incomplete one
//! is recomputed with a warning saying why (the published files are hard links to the
//! entry's, so an edit of a result in place is an edit of the cache). An entry is made under
//! a temporary name and renamed into place whole, so an entry that exists is complete;
//! temporaries an interruption left are removed by the next [`PointCache::prune`].

use super::ModelCheckpoint;
use crate::mesh::hash::{bytes_hash, text_hash};
use crate::results::SweepPointReport;
use crate::study::manifest::Manifest;
use crate::study::StudyError;
use num_complex::Complex64;
use std::path::{Path, PathBuf};

/// Where a sweep keeps its finished points, and the key of the model they belong to.
#[derive(Clone, Debug)]
pub struct PointCache {
    dir: PathBuf,
    model_key: String,
}

/// One finished point as the cache keeps it.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct CachedPoint {
    pub mu: f64,
    pub report: SweepPointReport,
    /// Each mode's eigenvalue (re, im): the report's modes do not carry it.
    pub lambdas: Vec<[f64; 2]>,
    /// Each mode's shape on the tracked DOFs, (re, im) per DOF.
    pub shapes: Vec<Vec<[f64; 2]>>,
    pub checkpoint: ModelCheckpoint,
}

impl CachedPoint {
    pub fn new(
        mu: f64,
        report: &SweepPointReport,
        shapes: &[Vec<Complex64>],
        checkpoint: ModelCheckpoint,
    ) -> Self {
        CachedPoint {
            mu,
            report: report.clone(),
            lambdas: report
                .eigenvalues
                .iter()
                .map(|m| [m.lambda.re, m.lambda.im])
                .collect(),
            shapes: shapes
                .iter()
                .map(|s| s.iter().map(|z| [z.re, z.im]).collect())
                .collect(),
            checkpoint,
        }
    }

    /// The report with its eigenvalues restored, and the shapes as complex vectors.
    pub fn into_parts(self) -> (SweepPointReport, Vec<Vec<Complex64>>, ModelCheckpoint) {
        let mut report = self.report;
        for (mode, l) in report.eigenvalues.iter_mut().zip(&self.lambdas) {
            mode.lambda = Complex64::new(l[0], l[1]);
        }
        let shapes = self
            .shapes
            .into_iter()
            .map(|s| s.into_iter().map(|z| Complex64::new(z[0], z[1])).collect())
            .collect();
        (report, shapes, self.checkpoint)
    }
}

/// What an entry held when it was made (`entry.json`).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
struct Entry {
    key: String,
    /// The friction value, to the bit.
    mu: f64,
    /// Length and hash of `point.json`.
    point: (u64, String),
    /// The files under `files/`.
    files: Manifest,
}

const POINT: &str = "point.json";
const ENTRY: &str = "entry.json";
const FILES: &str = "files";
const UNFINISHED: &str = ".unfinished-";

impl PointCache {
    /// The cache in `dir` of the model whose key (its study without the friction list, the
    /// mesh, squeal's version) is `model_key`.
    pub fn new(dir: impl Into<PathBuf>, model_key: impl Into<String>) -> Self {
        PointCache {
            dir: dir.into(),
            model_key: model_key.into(),
        }
    }

    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// The key of the point reached by sweeping `path` (every friction value so far, in
    /// order, the point's own last).
    pub fn key(&self, path: &[f64]) -> String {
        let bits: Vec<String> = path
            .iter()
            .map(|m| format!("{:016x}", m.to_bits()))
            .collect();
        text_hash(&format!(
            "{}\nfriction path {}",
            self.model_key,
            bits.join(" ")
        ))
    }

    /// The entry of `key` for friction value `mu`, if there is one that holds what it held
    /// when it was made (rank 0). An entry that is there but fails its check is said on the
    /// log, with why.
    pub fn load(&self, key: &str, mu: f64) -> Option<CachedPoint> {
        let dir = self.dir.join(key);
        if !dir.exists() {
            return None;
        }
        match self.checked(&dir, key, mu) {
            Ok(p) => Some(p),
            Err(why) => {
                tracing::warn!(
                    "point cache entry {key} (mu {mu}) is not used: {why}; the point is recomputed"
                );
                None
            }
        }
    }

    fn checked(&self, dir: &Path, key: &str, mu: f64) -> Result<CachedPoint, String> {
        let entry: Entry = std::fs::read(dir.join(ENTRY))
            .map_err(|e| format!("its {ENTRY} cannot be read ({e})"))
            .and_then(|b| {
                serde_json::from_slice(&b).map_err(|e| format!("its {ENTRY} does not read ({e})"))
            })?;
        if entry.key != key {
            return Err(format!("it was made as entry {}", entry.key));
        }
        if entry.mu.to_bits() != mu.to_bits() {
            return Err(format!("it was made at mu {}", entry.mu));
        }
        let bytes = std::fs::read(dir.join(POINT)).map_err(|e| format!("{POINT}: {e}"))?;
        if (bytes.len() as u64, bytes_hash(&bytes)) != entry.point {
            return Err(format!("{POINT} changed since it was made"));
        }
        if let Some(why) = entry.files.check(&dir.join(FILES)) {
            return Err(why);
        }
        let point: CachedPoint =
            serde_json::from_slice(&bytes).map_err(|e| format!("{POINT} does not read ({e})"))?;
        if point.mu.to_bits() != mu.to_bits() {
            return Err(format!("its {POINT} is mu {}", point.mu));
        }
        Ok(point)
    }

    /// Puts the files of entry `key` in `point_dir` (rank 0), as the sweep would have
    /// written them.
    pub fn publish(&self, key: &str, point_dir: &Path) -> Result<(), StudyError> {
        link_tree(&self.dir.join(key).join(FILES), point_dir)
    }

    /// Keeps `point` and the files the sweep wrote for it in `point_dir` under `key`
    /// (rank 0). Made under a temporary name and renamed whole into place.
    pub fn store(
        &self,
        key: &str,
        point_dir: &Path,
        point: &CachedPoint,
    ) -> Result<(), StudyError> {
        std::fs::create_dir_all(&self.dir).map_err(|e| StudyError::create_dir(&self.dir, e))?;
        let temp = self.dir.join(format!("{UNFINISHED}{key}"));
        let fin = self.dir.join(key);
        remove_dir(&temp)?;
        link_tree(point_dir, &temp.join(FILES))?;
        let json = serde_json::to_vec(point).map_err(|source| StudyError::JsonFile {
            path: temp.join(POINT),
            source,
        })?;
        crate::study::report::write_file(&temp.join(POINT), &json)?;
        let files = Manifest::of(&temp.join(FILES)).map_err(|source| StudyError::Read {
            path: temp.join(FILES),
            source,
        })?;
        let entry = Entry {
            key: key.to_string(),
            mu: point.mu,
            point: (json.len() as u64, bytes_hash(&json)),
            files,
        };
        let entry_path = temp.join(ENTRY);
        crate::study::report::write_file(
            &entry_path,
            &crate::study::report::json_for(&entry_path, &entry)?,
        )?;
        remove_dir(&fin)?;
        std::fs::rename(&temp, &fin).map_err(|e| StudyError::Write {
            path: fin.clone(),
            source: e,
        })
    }

    /// Removes every entry not in `keep`, and what an interruption left unfinished (rank 0).
    pub fn prune(&self, keep: &[String]) -> Result<(), StudyError> {
        let Ok(entries) = std::fs::read_dir(&self.dir) else {
            return Ok(());
        };
        for entry in entries.flatten() {
            let name = entry.file_name().to_string_lossy().into_owned();
            if !keep.contains(&name) {
                remove_dir(&entry.path())?;
            }
        }
        Ok(())
    }
}

/// Removes the folder `path` and what it holds, if it exists.
fn remove_dir(path: &Path) -> Result<(), StudyError> {
    match std::fs::remove_dir_all(path) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => Err(StudyError::Write {
            path: path.to_path_buf(),
            source: e,
        }),
        _ => Ok(()),
    }
}

/// `to` made as a copy of the folder `from`: each file hard-linked (its results are never
/// rewritten in place: every writer replaces a file by renaming a new one over it), or
/// copied where links cannot be made.
fn link_tree(from: &Path, to: &Path) -> Result<(), StudyError> {
    let write_error = |path: &Path, source| StudyError::Write {
        path: path.to_path_buf(),
        source,
    };
    std::fs::create_dir_all(to).map_err(|e| StudyError::create_dir(to, e))?;
    for entry in std::fs::read_dir(from).map_err(|e| write_error(from, e))? {
        let entry = entry.map_err(|e| write_error(from, e))?;
        let (source, target) = (entry.path(), to.join(entry.file_name()));
        if entry
            .file_type()
            .map_err(|e| write_error(&source, e))?
            .is_dir()
        {
            link_tree(&source, &target)?;
            continue;
        }
        if std::fs::hard_link(&source, &target).is_err() {
            std::fs::copy(&source, &target).map_err(|e| write_error(&target, e))?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_point_is_keyed_by_the_model_and_the_friction_path_that_led_to_it() {
        let cache = PointCache::new("x", "model a");
        let k = cache.key(&[0.1, 0.3]);
        assert_eq!(k, cache.key(&[0.1, 0.3]));
        // Another path to the same friction value is another point (Coulomb history).
        assert_ne!(k, cache.key(&[0.2, 0.3]));
        assert_ne!(k, cache.key(&[0.3]));
        // The same path on another model.
        assert_ne!(k, PointCache::new("x", "model b").key(&[0.1, 0.3]));
        // One ulp apart: another friction value.
        assert_ne!(k, cache.key(&[0.1, f64::from_bits(0.3f64.to_bits() + 1)]));
    }

    #[test]
    fn an_entry_is_stored_whole_reads_back_to_the_bit_and_is_pruned_when_not_kept() {
        let root = tempfile::tempdir().unwrap();
        let point_dir = root.path().join("mu_0.300");
        std::fs::create_dir_all(&point_dir).unwrap();
        std::fs::write(point_dir.join("cea.json"), b"{}").unwrap();
        let cache = PointCache::new(root.path().join("cache"), "m");
        let report: SweepPointReport = serde_json::from_str(
            r#"{"friction":0.3,"static_iterations":2,"static_factorizations":2,
            "static_residuals":[1.0,1e-9],"cutbacks":0,"contact":[],"balance_ratio":1.0,
            "eigenvalues":[{"frequency_hz":1000.1,"real_part":0.5,"damping_ratio":-1e-4,
            "unstable":true,"rigid_body":false,"residual":1e-12}],
            "static_seconds":1.0,"cea_seconds":1.0,"cea_shifts":1,"seconds":2.0,
            "peak_rss_mib_max_rank":1.0,"peak_rss_mib_all_ranks":2.0}"#,
        )
        .unwrap();
        let mut report = report;
        let lambda = Complex64::new(0.1 + 0.2, 2.0 * std::f64::consts::PI * 1000.1);
        report.eigenvalues[0].lambda = lambda;
        let shape = vec![vec![Complex64::new(1.0 / 3.0, -2.0 / 7.0)]];
        let checkpoint = ModelCheckpoint {
            previous: Some(super::super::EquilibriumState {
                mu: 0.3,
                displacement: vec![[1e-7 / 3.0, 0.1 + 0.2, -5e-300]],
                slip: vec![vec![[1.0 / 7.0, 0.0, 0.0]]],
            }),
            earlier: Some(super::super::PathPoint {
                mu: 0.2,
                displacement: vec![[1e-7 / 7.0, 0.1 + 0.7, 5e-300]],
            }),
            superelement: None,
        };
        let key = cache.key(&[0.3]);
        assert!(cache.load(&key, 0.3).is_none());
        cache
            .store(
                &key,
                &point_dir,
                &CachedPoint::new(0.3, &report, &shape, checkpoint.clone()),
            )
            .unwrap();
        let (back, shapes, cp) = cache.load(&key, 0.3).unwrap().into_parts();
        assert_eq!(back.eigenvalues[0].lambda, lambda);
        assert_eq!(shapes, shape);
        let (a, b) = (cp.previous.unwrap(), checkpoint.previous.unwrap());
        assert_eq!(a.displacement, b.displacement);
        assert_eq!(a.slip, b.slip);
        assert_eq!(cp.earlier, checkpoint.earlier);
        let out = root.path().join("published");
        cache.publish(&key, &out).unwrap();
        assert_eq!(std::fs::read(out.join("cea.json")).unwrap(), b"{}");
        // Asked for another mu, or damaged in any part: not used.
        assert!(cache.load(&key, 0.6).is_none());
        let entry = cache.dir().join(&key);
        let damage = |path: &Path, bytes: &[u8]| {
            let was = std::fs::read(path).unwrap();
            std::fs::remove_file(path).unwrap();
            std::fs::write(path, bytes).unwrap();
            assert!(cache.load(&key, 0.3).is_none(), "{}", path.display());
            std::fs::remove_file(path).unwrap();
            std::fs::write(path, was).unwrap();
            assert!(cache.load(&key, 0.3).is_some());
        };
        damage(&entry.join(FILES).join("cea.json"), b"[]");
        let point = std::fs::read(entry.join(POINT)).unwrap();
        let edited = String::from_utf8(point.clone())
            .unwrap()
            .replacen("1000.1", "1000.2", 1);
        damage(&entry.join(POINT), edited.as_bytes());
        damage(&entry.join(POINT), &point[..point.len() / 2]);
        damage(&entry.join(ENTRY), b"{");
        // Another point's entry put in its place.
        let other = cache.key(&[0.6]);
        std::fs::rename(&entry, cache.dir().join(&other)).unwrap();
        assert!(cache.load(&other, 0.6).is_none());
        std::fs::rename(cache.dir().join(&other), &entry).unwrap();
        // An unfinished entry (an interruption) and an entry of another plan go; the kept stays.
        std::fs::create_dir_all(cache.dir().join(format!("{UNFINISHED}abc"))).unwrap();
        std::fs::create_dir_all(cache.dir().join("0123456789abcdef")).unwrap();
        cache.prune(std::slice::from_ref(&key)).unwrap();
        let left: Vec<_> = std::fs::read_dir(cache.dir())
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        assert_eq!(left, [key]);
    }
}
