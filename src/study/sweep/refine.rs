//! Friction values inserted where tracking is unsure (issue 36, item 2;
//! `analysis.refine_points`).
//!
//! After the asked values, each pair of neighbouring points is judged by its links
//! ([`tracking::link`]): a link of regret below [`tracking::TRUSTED_REGRET`] (another
//! assignment explains the two spectra almost as well) or one that moves its mode's frequency
//! by more than [`LinkSummary::JUMP`] makes the interval doubtful. Doubtful intervals are
//! halved level by level (every asked one before any half, the most doubtful first within a
//! level): the value between is solved from the lower point's equilibrium and Coulomb
//! history (the model restored from that point's checkpoint), exactly as a sweep that went
//! there next would have, and the two halves are judged again. It stops when no interval is
//! doubtful, when the budget of points is spent, or when the doubtful ones are down to an
//! eighth of the asked step ([`MAX_DEPTH`]).
//!
//! The asked points are not solved again: each keeps the path (and so the numbers) of the
//! sweep without refinement, and an inserted point's path is its lower neighbour's and then
//! itself. A doubt that halving does not remove is often a real change of the modes: a
//! contact point that sticks or opens between the two values changes the stiffness at once,
//! and the log says which doubtful intervals change the contact state.

use super::swept::{self, Swept};
use super::{restore_from_root, FrictionModel, SweepPlan};
use crate::analysis::tracking::{self, LinkSummary, SweepPoint, TrackingOptions};
use crate::petsc::Comm;
use crate::results::{friction_text, ModelInfo, SweepPointReport};
use crate::study::progress::Progress;
use crate::study::report::collective;
use crate::study::{interrupt, StudyError};
use std::time::Instant;

/// An interval between two asked values is halved at most this many times: inserted steps
/// go down to 1/8 of the asked one. Past that, a doubt is a change of the modes that a finer
/// step would show as sudden too (measured on small-caliper: see the README's tracking
/// figures).
pub const MAX_DEPTH: u32 = 3;

/// What makes the links between two neighbouring points doubtful.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Doubt {
    /// Links of regret below [`tracking::TRUSTED_REGRET`].
    pub uncertain: usize,
    /// Links that change their mode's frequency by more than [`LinkSummary::JUMP`].
    pub jumps: usize,
}

impl Doubt {
    /// The doubt of the links from `from` to `to`, by the tracking's own assignment.
    pub fn of(from: &SweepPoint, to: &SweepPoint) -> Result<Doubt, tracking::TrackingError> {
        let links = tracking::link(from, to, &TrackingOptions::default())?;
        let mut d = Doubt::default();
        for (i, link) in links.iter().enumerate() {
            let Some(l) = link else { continue };
            d.uncertain += usize::from(l.regret < tracking::TRUSTED_REGRET);
            let change =
                tracking::relative_frequency_distance(from.eigenvalues[i], to.eigenvalues[l.to]);
            d.jumps += usize::from(change > LinkSummary::JUMP);
        }
        Ok(d)
    }

    /// Doubtful links (a link both uncertain and a jump counts twice: it is worse).
    pub fn count(&self) -> usize {
        self.uncertain + self.jumps
    }
}

/// The value inserted between `a` < `b`: their midpoint rounded to the fewest decimals (three
/// at least) that keep it strictly between, so folders and tables name it exactly; `None`
/// when nine decimals cannot.
pub fn midpoint(a: f64, b: f64) -> Option<f64> {
    (3..=9).find_map(|d| {
        let scale = 10f64.powi(d);
        // An integer over a power of ten: the double nearest the decimal, as parsing it gives.
        let m = (0.5 * (a + b) * scale).round() / scale;
        (a < m && m < b).then_some(m)
    })
}

/// The interval to halve next, as (index of its lower point, value inserted): level by
/// level, so that every doubtful asked interval is halved before any half is halved again
/// (a budget spent deep in one region would leave the others as coarse as asked); within a
/// level the most doubtful first, then the wider, then the lower. `None` when no doubtful
/// interval may be halved.
fn choose(friction: &[f64], depths: &[u32], doubts: &[Doubt]) -> Option<(usize, f64)> {
    let depth = |k: usize| depths[k].max(depths[k + 1]);
    (0..doubts.len())
        .filter(|&k| doubts[k].count() > 0 && depth(k) < MAX_DEPTH)
        .filter_map(|k| midpoint(friction[k], friction[k + 1]).map(|m| (k, m)))
        .max_by(|&(x, _), &(y, _)| {
            depth(y)
                .cmp(&depth(x))
                .then(doubts[x].count().cmp(&doubts[y].count()))
                .then((friction[x + 1] - friction[x]).total_cmp(&(friction[y + 1] - friction[y])))
                .then(y.cmp(&x))
        })
}

/// The doubt of every interval of `points` (rank 0).
fn doubts_of(points: &[SweepPoint]) -> Result<Vec<Doubt>, StudyError> {
    points
        .windows(2)
        .map(|w| Doubt::of(&w[0], &w[1]).map_err(StudyError::from))
        .collect()
}

/// Inserts up to `plan.refine_points` friction values into `swept` where its links are
/// doubtful (see the module's doc). Collective: rank 0 judges and every rank follows.
pub(super) fn refine<'rt>(
    comm: Comm<'rt>,
    model: &mut dyn FrictionModel<'rt>,
    plan: &SweepPlan,
    info: &ModelInfo,
    swept: &mut Swept,
    bar: &Progress,
) -> Result<(), StudyError> {
    if plan.refine_points == 0 {
        return Ok(());
    }
    let root = comm.rank() == 0;
    let started = Instant::now();
    let doubts = if root {
        doubts_of(&swept.points)
    } else {
        Ok(Vec::new())
    };
    let mut doubts = collective(comm, doubts)?;
    let mut inserted = Vec::new();
    while inserted.len() < plan.refine_points {
        let mut choice = vec![-1.0, 0.0];
        let friction: Vec<f64> = swept.reports.iter().map(|r| r.friction).collect();
        if let Some((k, mu)) = root
            .then(|| choose(&friction, &swept.depths, &doubts))
            .flatten()
        {
            choice = vec![k as f64, mu];
        }
        comm.broadcast_from_root(&mut choice);
        if choice[0] < 0.0 {
            break;
        }
        let (k, mu) = (choice[0] as usize, choice[1]);
        inserted.push(mu);
        bar.grow(1);
        bar.message(format!("mu {} (inserted)", friction_text(mu)));
        interrupt::progress(format!(
            " at mu {} (inserted where tracking is unsure, {} of at most {}); the asked \
             points are whole in {}",
            friction_text(mu),
            inserted.len(),
            plan.refine_points,
            plan.output.display()
        ));
        let (path, depth) = if root {
            let mut path = swept.paths[k].clone();
            path.push(mu);
            (path, swept.depths[k].max(swept.depths[k + 1]) + 1)
        } else {
            (Vec::new(), 0)
        };
        let cached = match (root, &plan.cache) {
            (true, Some(cache)) => swept::from_cache(cache, &plan.output, &path, depth),
            _ => Ok(None),
        };
        let mut cached = collective(comm, cached)?;
        let mut found = vec![f64::from(u8::from(cached.is_some()))];
        comm.broadcast_from_root(&mut found);
        if found[0] == 0.0 {
            let from = swept.checkpoints.get(k).and_then(Option::as_ref);
            restore_from_root(comm, model, from, &plan.output)?;
            let mut outcome = model.solve_point(comm, mu)?;
            outcome.report.inserted = true;
            outcome.report.path.clone_from(&path);
            if root {
                tracing::info!(
                    "mu {} (inserted {} of at most {}, from mu {}): {}",
                    friction_text(mu),
                    inserted.len(),
                    plan.refine_points,
                    friction_text(swept.reports[k].friction),
                    outcome.report.log_line()
                );
                cached = Some(swept::keep_solved(model, plan, info, outcome, path, depth)?);
            }
        } else if root {
            tracing::info!(
                "mu {} (inserted {} of at most {}): from the point cache",
                friction_text(mu),
                inserted.len(),
                plan.refine_points
            );
        }
        if let (true, Some(point)) = (root, cached) {
            swept.insert(k + 1, point);
            let local = (|| -> Result<(), StudyError> {
                let lower = Doubt::of(&swept.points[k], &swept.points[k + 1])?;
                let upper = Doubt::of(&swept.points[k + 1], &swept.points[k + 2])?;
                doubts.splice(k..=k, [lower, upper]);
                Ok(())
            })();
            collective(comm, local)?;
        } else {
            collective::<(), StudyError>(comm, Ok(()))?;
        }
        bar.step();
    }
    if root {
        tracing::info!(
            "{}",
            summary(&inserted, swept, &doubts, plan.refine_points, started)
        );
    }
    Ok(())
}

/// The log's account of a refinement: what was inserted and what stays doubtful, and why.
fn summary(
    inserted: &[f64],
    swept: &Swept,
    doubts: &[Doubt],
    budget: usize,
    started: Instant,
) -> String {
    let mut values: Vec<f64> = inserted.to_vec();
    values.sort_by(f64::total_cmp);
    let listed: Vec<String> = values.iter().map(|&m| friction_text(m)).collect();
    let mut s = format!(
        "refinement: {} friction value(s) inserted{} in {:.1} s",
        inserted.len(),
        if listed.is_empty() {
            String::new()
        } else {
            format!(" ({})", listed.join(", "))
        },
        started.elapsed().as_secs_f64()
    );
    let left: Vec<String> = (0..doubts.len())
        .filter(|&k| doubts[k].count() > 0)
        .map(|k| {
            let (a, b) = (&swept.reports[k], &swept.reports[k + 1]);
            let why = if swept.depths[k].max(swept.depths[k + 1]) >= MAX_DEPTH {
                "step at its finest"
            } else {
                "budget spent"
            };
            format!(
                "mu {}-{}: {} uncertain, {} jump(s), {}, {why}",
                friction_text(a.friction),
                friction_text(b.friction),
                doubts[k].uncertain,
                doubts[k].jumps,
                contact_change_text(a, b)
            )
        })
        .collect();
    if left.is_empty() {
        s.push_str("; every link between neighbouring points is sure");
    } else {
        s.push_str(&format!(
            "; {} interval(s) still doubtful (budget {budget}): {}",
            left.len(),
            left.join("; ")
        ));
    }
    s
}

fn contact_change_text(a: &SweepPointReport, b: &SweepPointReport) -> &'static str {
    if a.contact_state_differs(b) {
        "the contact state changes"
    } else {
        "the same contact state"
    }
}

/// Says on each uncertain link of an instability whether the contact state changes across
/// it: a link joins neighbouring points, so that is the later point's own `contact_changed`
/// (its open, sticking and slipping counts against the point before), set before this runs.
pub(super) fn mark_contact_changes(
    instabilities: &mut [tracking::Instability],
    reports: &[SweepPointReport],
) {
    for link in instabilities
        .iter_mut()
        .flat_map(|i| i.uncertain_links.iter_mut())
    {
        link.contact_changed = reports
            .iter()
            .any(|r| r.friction == link.to_mu && r.contact_changed);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn doubt(count: usize) -> Doubt {
        Doubt {
            uncertain: count,
            jumps: 0,
        }
    }

    #[test]
    fn intervals_are_halved_level_by_level_most_doubtful_first() {
        let friction = [0.1, 0.15, 0.2, 0.3, 0.4];
        // 0.1-0.15 and 0.15-0.2 are halves already (depth 1): the asked 0.3-0.4 comes first
        // though less doubtful, then among equals the more doubtful, then the wider.
        let depths = [0, 1, 0, 0, 0];
        let d = [doubt(5), doubt(5), doubt(1), doubt(2)];
        assert_eq!(choose(&friction, &depths, &d), Some((3, 0.35)));
        let d = [doubt(5), doubt(5), doubt(1), doubt(0)];
        assert_eq!(choose(&friction, &depths, &d), Some((2, 0.25)));
        let d = [doubt(1), doubt(5), doubt(0), doubt(0)];
        assert_eq!(choose(&friction, &depths, &d), Some((1, 0.175)));
        // Sure links everywhere, or doubts only at the finest step: nothing to halve.
        assert_eq!(choose(&friction, &depths, &[doubt(0); 4]), None);
        let finest = [0, MAX_DEPTH, 0, 0, 0];
        let d = [doubt(3), doubt(3), doubt(0), doubt(0)];
        assert_eq!(choose(&friction, &finest, &d), None);
    }

    #[test]
    fn midpoints_are_short_decimals_strictly_between() {
        assert_eq!(midpoint(0.1, 0.2), Some(0.15));
        assert_eq!(midpoint(0.1, 0.15), Some(0.125));
        // 0.1125 rounds to 0.113 at three decimals, still between.
        assert_eq!(midpoint(0.1, 0.125), Some(0.113));
        assert_eq!(midpoint(0.3, 0.301), Some(0.3005));
        assert_eq!(midpoint(0.3, 0.3 + 1e-12), None);
    }
}
