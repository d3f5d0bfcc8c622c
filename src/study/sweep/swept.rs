//! The points a sweep has finished, in friction order, as rank 0 keeps them, and how a
//! solved or cached point joins them: its folder, the point cache.

use super::output;
use super::point_cache::{CachedPoint, PointCache};
use super::{FrictionModel, ModelCheckpoint, PointOutcome, SweepPlan};
use crate::analysis::tracking::SweepPoint;
use crate::results::{ModelInfo, SweepPointReport};
use crate::study::StudyError;
use std::path::Path;

/// The finished points, sorted by friction (rank 0; empty elsewhere).
#[derive(Default)]
pub(super) struct Swept {
    pub reports: Vec<SweepPointReport>,
    pub points: Vec<SweepPoint>,
    /// Where the model stood after each point: an inserted point starts from its lower
    /// neighbour's. Kept only when the sweep may insert points (`None` otherwise).
    pub checkpoints: Vec<Option<ModelCheckpoint>>,
    /// Each point's friction path, the values solved on the way to it and then its own:
    /// what its results depend on, and its point-cache key.
    pub paths: Vec<Vec<f64>>,
    /// 0 for an asked value; an inserted one is one deeper than the deeper of the two it
    /// halves.
    pub depths: Vec<u32>,
}

/// A point to record, solved or read from the point cache.
pub(super) struct Finished {
    pub report: SweepPointReport,
    pub shapes: Vec<Vec<num_complex::Complex64>>,
    pub checkpoint: Option<ModelCheckpoint>,
    pub path: Vec<f64>,
    pub depth: u32,
}

impl Swept {
    pub fn len(&self) -> usize {
        self.reports.len()
    }

    /// Puts `point` at index `at` (the lists stay sorted by friction).
    pub fn insert(&mut self, at: usize, point: Finished) {
        let mu = point.report.friction;
        self.points.insert(
            at,
            SweepPoint {
                mu,
                eigenvalues: point.report.eigenvalues.iter().map(|m| m.lambda).collect(),
                shapes: point.shapes,
            },
        );
        self.reports.insert(at, point.report);
        self.checkpoints.insert(at, point.checkpoint);
        self.paths.insert(at, point.path);
        self.depths.insert(at, point.depth);
    }

    /// The point-cache keys of every point, for pruning the rest.
    pub fn keys(&self, cache: &PointCache) -> Vec<String> {
        self.paths.iter().map(|p| cache.key(p)).collect()
    }
}

/// Rank 0's part of a solved point: its folder, the point cache (a failure there costs
/// a later rerun time, not this one's results), and what [`Swept`] keeps of it.
pub(super) fn keep_solved(
    model: &dyn FrictionModel<'_>,
    plan: &SweepPlan,
    info: &ModelInfo,
    outcome: PointOutcome,
    path: Vec<f64>,
    depth: u32,
) -> Result<Finished, StudyError> {
    let report = outcome.report;
    let mu = report.friction;
    let dir = plan.output.join(super::point_folder(mu));
    output::write_point(&dir, model.mesh(), outcome.fields.as_ref(), &report, info)?;
    let checkpoint = (plan.cache.is_some() || plan.refine_points > 0).then(|| model.checkpoint());
    if let (Some(cache), Some(cp)) = (&plan.cache, &checkpoint) {
        let kept = CachedPoint::new(mu, &report, &outcome.tracking_shapes, cp.clone());
        let key = cache.key(&path);
        if let Err(e) = cache.store(&key, &dir, &kept) {
            tracing::warn!(
                "mu {mu:.3} is not kept in the point cache ({e}); a rerun recomputes it"
            );
        }
    }
    Ok(Finished {
        report,
        shapes: outcome.tracking_shapes,
        checkpoint: checkpoint.filter(|_| plan.refine_points > 0),
        path,
        depth,
    })
}

/// A point the cache holds for `path`, its files published into the output, with the
/// checkpoint the cache kept (rank 0).
pub(super) fn from_cache(
    cache: &PointCache,
    output: &Path,
    path: &[f64],
    depth: u32,
) -> Result<Option<Finished>, StudyError> {
    let mu = *path.last().expect("a friction path ends at its point");
    let key = cache.key(path);
    let Some(point) = cache.load(&key, mu) else {
        return Ok(None);
    };
    cache.publish(&key, &output.join(super::point_folder(mu)))?;
    let (report, shapes, cp) = point.into_parts();
    Ok(Some(Finished {
        report,
        shapes,
        checkpoint: Some(cp),
        path: path.to_vec(),
        depth,
    }))
}
