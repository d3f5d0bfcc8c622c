//! The unstable modes friction value by friction value, apart from tracking: at each friction
//! value both sweeps computed, does every unstable mode of the reference have an unstable mode
//! of the other model within [`UNSTABLE_MODE_TOLERANCE`] in frequency (issue 29's second
//! criterion)? Tracks join modes across friction values and can join them wrongly on a dense
//! spectrum; this count reads each point's eigenvalues alone, so a miss here is a miss of the
//! model, not of the tracking.

use super::Sweep;
use crate::analysis::cea::ComplexMode;
use crate::results::EdgeCheck;

/// The paper's tolerance on a reduced model's frequencies (its Tables 4-7 stay within it).
pub const UNSTABLE_MODE_TOLERANCE: f64 = 0.01;

/// One model's unstable modes against the reference's at one friction value.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct UnstableModesAt {
    pub model: String,
    pub friction: f64,
    /// The reference's unstable modes at this friction value, and the model's.
    pub reference: usize,
    pub model_unstable: usize,
    /// The reference's unstable modes paired with one of the model's within the tolerance
    /// (one to one, nearest first).
    pub matched: usize,
    /// The reference's unstable modes left without one.
    pub unmatched: Vec<UnmatchedMode>,
    /// Whether the reference checked its contact edge at this point.
    #[serde(default)]
    pub edge_checked: bool,
}

/// A reference unstable mode without an unstable mode of the model within the tolerance.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct UnmatchedMode {
    pub frequency_hz: f64,
    pub real_part: f64,
    /// The relative frequency distance to the model's nearest unstable mode left unpaired,
    /// if it has one.
    pub nearest_unstable: Option<f64>,
    /// The model's two uncoupled modes nearest in frequency (neither unstable nor the stable
    /// twin of an unstable one), when both are within the tolerance: the pair a mode-coupling
    /// instability is made of is there, not coupled. In the two-mode model of mode coupling,
    /// omega^2 = m +/- sqrt(D), their relative gap is sqrt(D) / omega^2 and the reference's
    /// 2 a / omega is sqrt(-D) / omega^2: how far each sits from coalescence (D = 0), on
    /// either side of it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub model_pair_hz: Option<[f64; 2]>,
    /// Where the reference checked its contact edge: whether this mode is stable, or moves
    /// by the tolerance or more, with the edge moved (the full mesh does not resolve it to
    /// the tolerance).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub on_edge: Option<bool>,
}

impl UnstableModesAt {
    /// The unmatched modes the reference resolves: not decided by its own contact edge.
    pub fn unmatched_off_edge(&self) -> usize {
        self.unmatched
            .iter()
            .filter(|m| m.on_edge != Some(true))
            .count()
    }
}

/// One model's counts over every shared friction value.
#[derive(Clone, Debug, PartialEq)]
pub struct UnstableModeTotals {
    pub model: String,
    /// The reference's unstable modes, summed over the friction values.
    pub reference: usize,
    pub matched: usize,
    /// Of the unmatched, those decided by the reference's contact edge; `None` where it did
    /// not check.
    pub on_edge: Option<usize>,
}

impl UnstableModeTotals {
    pub fn unmatched(&self) -> usize {
        self.reference - self.matched
    }
}

/// The totals per model, in the order the models first appear.
pub fn totals(all: &[UnstableModesAt]) -> Vec<UnstableModeTotals> {
    let mut out: Vec<UnstableModeTotals> = Vec::new();
    for u in all {
        let edge_known = u.edge_checked;
        let on_edge = u.unmatched.len() - u.unmatched_off_edge();
        match out.iter_mut().find(|t| t.model == u.model) {
            Some(t) => {
                t.reference += u.reference;
                t.matched += u.matched;
                t.on_edge = match (t.on_edge, edge_known) {
                    (Some(n), _) => Some(n + on_edge),
                    (None, true) => Some(on_edge),
                    (None, false) => None,
                };
            }
            None => out.push(UnstableModeTotals {
                model: u.model.clone(),
                reference: u.reference,
                matched: u.matched,
                on_edge: edge_known.then_some(on_edge),
            }),
        }
    }
    out
}

/// Whether the reference's eigenvalue `n` at a point with this edge check is decided by the
/// edge: stable with it moved, or moved by the tolerance or more.
fn edge_decides(edge: &EdgeCheck, n: usize, mode: &ComplexMode) -> bool {
    edge.loses_instability(n) || edge.frequency_change(n, mode) >= UNSTABLE_MODE_TOLERANCE
}

/// The two uncoupled modes of `modes` nearest to `f`, in ascending frequency, when both are
/// within the tolerance of it: not unstable, and not at the frequency of an unstable one (its
/// stable twin, lambda's conjugate pair -a + i b).
fn uncoupled_pair(modes: &[ComplexMode], f: f64) -> Option<[f64; 2]> {
    let coupled = |g: f64| {
        modes
            .iter()
            .any(|m| m.unstable && (m.frequency_hz - g).abs() <= 1e-9 * g)
    };
    let mut near: Vec<f64> = modes
        .iter()
        .map(|m| m.frequency_hz)
        .filter(|&g| (g / f - 1.0).abs() <= UNSTABLE_MODE_TOLERANCE && !coupled(g))
        .collect();
    near.sort_by(|x, y| (x / f - 1.0).abs().total_cmp(&(y / f - 1.0).abs()));
    let mut two = [*near.first()?, *near.get(1)?];
    two.sort_by(f64::total_cmp);
    Some(two)
}

/// Pairs the reference's unstable modes with the model's one to one, the closest pairs in
/// relative frequency first, and keeps those within the tolerance.
pub fn unstable_modes_at(
    model: &str,
    reference: &crate::results::SweepPointReport,
    other: &crate::results::SweepPointReport,
) -> UnstableModesAt {
    let unstable = |modes: &[ComplexMode]| -> Vec<usize> {
        (0..modes.len()).filter(|&n| modes[n].unstable).collect()
    };
    let (r, o) = (&reference.eigenvalues, &other.eigenvalues);
    let (ru, ou) = (unstable(r), unstable(o));
    let distance = |a: usize, b: usize| (o[b].frequency_hz / r[a].frequency_hz - 1.0).abs();
    let mut candidates: Vec<(f64, usize, usize)> = ru
        .iter()
        .flat_map(|&a| ou.iter().map(move |&b| (a, b)))
        .map(|(a, b)| (distance(a, b), a, b))
        .collect();
    candidates.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)).then(x.2.cmp(&y.2)));
    let (mut r_used, mut o_used) = (vec![false; r.len()], vec![false; o.len()]);
    let mut matched = 0;
    for &(d, a, b) in &candidates {
        if d > UNSTABLE_MODE_TOLERANCE {
            break;
        }
        if !r_used[a] && !o_used[b] {
            r_used[a] = true;
            o_used[b] = true;
            matched += 1;
        }
    }
    let unmatched = ru
        .iter()
        .filter(|&&a| !r_used[a])
        .map(|&a| UnmatchedMode {
            frequency_hz: r[a].frequency_hz,
            real_part: r[a].real_part,
            nearest_unstable: ou
                .iter()
                .filter(|&&b| !o_used[b])
                .map(|&b| distance(a, b))
                .min_by(f64::total_cmp),
            model_pair_hz: uncoupled_pair(o, r[a].frequency_hz),
            on_edge: reference
                .contact_edge
                .as_ref()
                .map(|e| edge_decides(e, a, &r[a])),
        })
        .collect();
    UnstableModesAt {
        model: model.to_string(),
        friction: reference.friction,
        reference: ru.len(),
        model_unstable: ou.len(),
        matched,
        unmatched,
        edge_checked: reference.contact_edge.is_some(),
    }
}

/// Every shared friction value of one model: `shared` holds (reference point, model point).
pub fn unstable_modes(
    model: &str,
    r: &Sweep,
    o: &Sweep,
    shared: &[(usize, usize)],
) -> Vec<UnstableModesAt> {
    shared
        .iter()
        .map(|&(k, j)| unstable_modes_at(model, &r.points[k], &o.points[j]))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::results::SweepPointReport;
    use serde_json::json;

    fn point(modes: &[(f64, f64)], edge: Option<serde_json::Value>) -> SweepPointReport {
        let m =
            |&(f, a): &(f64, f64)| json!({"frequency_hz": f, "real_part": a, "unstable": a > 0.0});
        let mut p =
            json!({"friction": 0.5, "eigenvalues": modes.iter().map(m).collect::<Vec<_>>()});
        if let Some(e) = edge {
            p["contact_edge"] = e;
        }
        let doc = crate::results::fixture::complete(json!({
            "model": {"source": "test", "equations": 10}, "points": [p], "tracks": [],
            "instabilities": []
        }));
        serde_json::from_value(doc["points"][0].clone()).unwrap()
    }

    /// Two reference modes 0.5 % apart and one model mode between them: it stands for one of
    /// them only (the nearer), so the other is unmatched though a model mode lies within 1 %;
    /// a mode 3.3 % off is unmatched and, as its edge moves it by 2 %, decided by the edge.
    #[test]
    fn unstable_modes_pair_one_to_one_and_say_the_edge() {
        let base = [
            (1000.0, 10.0),
            (1005.0, 5.0),
            (2000.0, -1.0),
            (3000.0, 20.0),
        ];
        let moved = |f: f64, a: f64| {
            json!({"frequency_hz": f, "real_part": a, "unstable": a > 0.0,
                   "damping_ratio": 0.0, "rigid_body": false, "residual": 0.0})
        };
        let same: Vec<_> = base.iter().map(|&(f, a)| moved(f, a)).collect();
        let mut opened = same.clone();
        opened[3] = moved(3060.0, 20.0);
        let edge = json!({"points": 4, "opened": 4, "closed": 4, "seconds": 0.0,
                          "with_opened": opened, "with_closed": same});
        let reference = point(&base, Some(edge));
        let other = point(&[(1004.0, 3.0), (2000.0, 1.0), (3100.0, 15.0)], None);
        let u = unstable_modes_at("m", &reference, &other);
        assert_eq!((u.reference, u.model_unstable, u.matched), (3, 3, 1));
        let close = |x: Option<f64>, y: f64| (x.unwrap() - y).abs() < 1e-12;
        assert_eq!(u.unmatched.len(), 2);
        let (a, b) = (&u.unmatched[0], &u.unmatched[1]);
        assert_eq!((a.frequency_hz, a.on_edge), (1000.0, Some(false)));
        assert!(close(a.nearest_unstable, 1.0), "{a:?}");
        assert_eq!((b.frequency_hz, b.on_edge), (3000.0, Some(true)));
        assert!(close(b.nearest_unstable, 100.0 / 3000.0), "{b:?}");
        assert_eq!(u.unmatched_off_edge(), 1);
        assert_eq!((a.model_pair_hz, b.model_pair_hz), (None, None));
        let twice = totals(&[u.clone(), u.clone()]);
        assert_eq!(twice.len(), 1);
        let t = &twice[0];
        assert_eq!(
            (t.reference, t.matched, t.unmatched(), t.on_edge),
            (6, 2, 4, Some(2))
        );

        // Without the reference's edge check nothing is said about the edge; a model with
        // every mode is matched in full.
        // The pair of a mode-coupling instability present, stable, 0.5 % apart.
        // (1004 Hz is unstable, its twin at -3 1/s coupled with it: neither is taken.)
        let uncoupled = point(
            &[
                (995.0, 0.0),
                (1002.0, 0.0),
                (1004.0, -3.0),
                (1004.0, 3.0),
                (1030.0, 0.0),
            ],
            None,
        );
        let u = unstable_modes_at("m", &reference, &uncoupled);
        let a = &u.unmatched[0];
        assert_eq!(a.frequency_hz, 1000.0);
        assert_eq!(a.model_pair_hz, Some([995.0, 1002.0]));

        let plain = point(&base, None);
        let u = unstable_modes_at("m", &plain, &other);
        assert!(u.unmatched.iter().all(|m| m.on_edge.is_none()));
        assert_eq!(totals(&[u])[0].on_edge, None);
        let u = unstable_modes_at("m", &plain, &plain);
        assert_eq!((u.matched, u.unmatched.len()), (3, 0));
    }
}
