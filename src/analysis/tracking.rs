//! Mode tracking across a friction sweep, and the instabilities it reveals.
//!
//! A CEA at each friction coefficient mu returns its modes sorted by frequency, but the order
//! means nothing from one mu to the next: two modes whose frequencies cross swap indices, and
//! the two modes of a coupling pair approach each other until they merge. Tracking therefore
//! follows shapes: neighbouring sweep points are linked by the complex MAC and an optimal
//! one-to-one assignment (Hungarian algorithm), so a mode keeps its identity however the
//! spectrum reorders.
//!
//! What is compared (issue 36). The caller gives each shape on a common set of DOFs, scaled
//! so that the plain inner product is the one it wants: a full-size model's shapes on the
//! mesh's mass sample, scaled by the square root of each node's mass
//! ([`crate::fem::mass_sample`]), so the MAC is the kinetic-energy one over every body; a
//! super-element model's expanded (u = T q) onto the same sample, whichever super-element
//! each point stands on. Measured on small-caliper (0-10 kHz, mu 0.1 to 0.9, 56 modes a
//! point): compared on the disc/pad faces' DOFs alone, 36 of 380 links changed frequency by
//! more than 5 %, up to 67 %, with MACs of 0.54-0.79; mass-weighted over the whole model, 14
//! of 366, up to 18 % (each of those 14 the only acceptable link of its mode, regret above
//! 1.1: a mode that changed, or a link to settle by a finer step). A single super-element of
//! tiny-caliper (every pair reduced, 22 nodes per pad, same band and mu): on its boundary
//! coordinates 27 of 363 links jumped by more than 5 % (up to 77 %) and 56 were uncertain;
//! expanded onto the sample, 7 of 368 (up to 9.8 %) and 17.
//!
//! How sure a link is: its regret ([`Track::link_regret`]), what the total link cost rises
//! by when the link is forbidden and the rest re-assigned at their best. A high MAC is no
//! proof (two modes with the same MAC to a mode of the point before are a tie); a regret
//! near 0 is. Links below [`TRUSTED_REGRET`] are uncertain, and an instability that stands on
//! one says so ([`Instability::uncertain_links`]). Where links are uncertain or jump, a sweep
//! can insert friction values between the two points (`analysis.refine_points`, the sweep's
//! `refine` module) until they are sure or the step is an eighth of the asked one.
//!
//! An instability in the sense of mode coupling (METHOD.md section 4, Fazio et al. 2015) is
//! a track whose real part becomes positive after its frequency has merged with another
//! track's; past the merge the pair's real parts split to +a and -a. [`instabilities`]
//! reports each such event with its partner, where it starts and how strong it gets.

use num_complex::Complex64;
use std::f64::consts::PI;

/// The modes of one sweep point.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepPoint {
    /// Friction coefficient of this point.
    pub mu: f64,
    /// lambda = a + i b, one per conjugate pair: the one with b >= 0. Frequency b / 2 pi (Hz),
    /// a > 0 grows.
    pub eigenvalues: Vec<Complex64>,
    /// The complex shape of each eigenvalue, restricted to a set of DOFs common to all points
    /// (so every shape of the sweep has the same length). Any complex scaling is fine.
    pub shapes: Vec<Vec<Complex64>>,
}

/// How neighbouring sweep points are linked.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct TrackingOptions {
    /// Two modes whose complex MAC is below this are never linked: the track ends and a new
    /// one starts. In [0, 1].
    pub min_mac: f64,
    /// Weight of the relative frequency distance |f_i - f_j| / max(f_i, f_j) added to the
    /// link cost 1 - MAC. Small: it breaks near-ties in MAC (coupled modes near their merge
    /// have similar shapes), it must not overrule clear shape evidence. >= 0.
    pub frequency_weight: f64,
}

impl Default for TrackingOptions {
    fn default() -> Self {
        TrackingOptions {
            min_mac: 0.5,
            frequency_weight: 0.1,
        }
    }
}

/// One mode followed across the sweep.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Track {
    /// Index of the track in the list [`track`] returns.
    pub id: usize,
    /// The track's mode index at each sweep point; `None` before the track starts and after
    /// it ends. The `Some` entries are contiguous.
    pub members: Vec<Option<usize>>,
    /// The complex MAC of the link reaching each point from the previous one; `None` at the
    /// track's first point and wherever the track is absent. A low value flags a doubtful link.
    pub link_mac: Vec<Option<f64>>,
    /// The regret of the link reaching each point: how much the total link cost of the two
    /// points rises when this link is forbidden and every other mode is linked again at its
    /// best ([`link`]). Near 0, another assignment explains the two points almost as well:
    /// the link is ambiguous, however high its MAC. `None` where `link_mac` is. (Not written
    /// by earlier versions: read as absent.)
    #[serde(default)]
    pub link_regret: Vec<Option<f64>>,
}

/// How instabilities are recognised.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct InstabilityOptions {
    /// A mode is unstable when its real part exceeds this fraction of |lambda|: above the
    /// round-off of a non-symmetric solve (~1e-10), below any physical growth rate. >= 0.
    pub real_part_tolerance: f64,
    /// Two frequencies have merged when they differ by at most this fraction of the larger.
    /// Undamped coupled pairs share their frequency to round-off; non-proportional damping
    /// leaves a small gap. >= 0.
    pub frequency_tolerance: f64,
    /// A link whose regret ([`Track::link_regret`]) is below this is uncertain: an
    /// instability that stands on one says so ([`Instability::uncertain_links`]). >= 0.
    pub trusted_regret: f64,
}

/// See [`InstabilityOptions::trusted_regret`]. Chosen in the gap of the measured links'
/// regrets: on small-caliper (0-10 kHz, mu 0.1 to 0.9, mass-weighted shapes) 9 of 366 links
/// lie between 0.03 and 0.20, all among near-degenerate modes (the 3027/3045/3048 Hz
/// cluster, a 6692 Hz doublet, the coupled pairs of the 8.4 kHz cluster), and the other 357
/// at 0.56 and above (their 5 % quantile). In MAC terms: some other assignment explains the
/// two points within a quarter of one link's similarity.
pub const TRUSTED_REGRET: f64 = 0.25;

impl Default for InstabilityOptions {
    fn default() -> Self {
        InstabilityOptions {
            real_part_tolerance: crate::analysis::cea::DEFAULT_UNSTABLE_THRESHOLD,
            frequency_tolerance: 1e-2,
            trusted_regret: TRUSTED_REGRET,
        }
    }
}

/// A link an instability stands on that another assignment explains almost as well.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct UncertainLink {
    /// The track (the unstable one or its partner) and the friction values it links.
    pub track: usize,
    pub from_mu: f64,
    pub to_mu: f64,
    pub mac: f64,
    pub regret: f64,
    /// The relative change of frequency across the link.
    pub frequency_change: f64,
    /// Whether some contact pair's counts of open, sticking and slipping points differ
    /// between the two friction values (filled by the sweep, which has the contact states).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub contact_changed: bool,
}

/// One interval of mu over which a track is unstable.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Instability {
    /// The unstable track's id.
    pub track: usize,
    /// The track it coupled with: present at the first unstable point (or a later one of the
    /// interval) with a frequency merged with this track's and a negative real part; the
    /// closest in frequency when several qualify.
    pub partner: Option<usize>,
    /// Where the real part crosses zero: linear interpolation between the last stable point
    /// and the first unstable one. Undamped, the real part is exactly zero up to the merge and
    /// grows like sqrt(mu - mu_c) after, so this lands on the last stable point: see
    /// `coalescence_mu` for a sharper estimate. When the track is unstable from its first
    /// point, that point's mu (see `onset_bracketed`).
    pub onset_mu: f64,
    /// False when the track is already unstable at its first point, so `onset_mu` is only
    /// a bound.
    pub onset_bracketed: bool,
    /// Where the pair's eigenvalues meet. Near the merge (an exceptional point)
    /// lambda_track, lambda_partner = lambda_0 +/- sqrt(c (mu - mu_c)), so
    /// q = Re(((lambda_track - lambda_partner) / 2)^2) is -(half the frequency gap)^2 before
    /// and +a^2 after, linear in mu to first order; this is the zero of q interpolated
    /// linearly between the two points that bracket its sign change just before the onset.
    /// `None` without a partner or without such a bracket.
    pub coalescence_mu: Option<f64>,
    /// Frequency at `onset_mu`, interpolated linearly like it.
    pub frequency_hz_at_onset: f64,
    /// The first friction value where the track is unstable, and its frequency there: what
    /// "unstable from" means to a reader (`onset_mu` lies at or before it).
    pub first_unstable_mu: f64,
    pub frequency_hz_at_first_unstable: f64,
    /// The largest real part (1/s) over the interval.
    pub max_real_part: f64,
    /// (Not written by the oldest versions: read as 0.)
    #[serde(default)]
    pub mu_at_max: f64,
    pub frequency_hz_at_max: f64,
    /// Where the real part crosses zero again (linear interpolation), `None` when the track
    /// is still unstable at its last point.
    pub restabilisation_mu: Option<f64>,
    /// The uncertain links of the track and its partner from the last stable point before
    /// the interval to its last unstable one: where this instability's onset, partner or
    /// largest real part may belong to another mode. Empty when every one is trusted (and
    /// in files of earlier versions, which did not weigh links).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub uncertain_links: Vec<UncertainLink>,
}

#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TrackingError {
    #[error("complex MAC of two shapes of different lengths ({left} and {right} DOFs)")]
    ShapeLengths { left: usize, right: usize },
    #[error("sweep point {point} (mu = {mu}): {eigenvalues} eigenvalues but {shapes} shapes")]
    ShapeCount {
        point: usize,
        mu: f64,
        eigenvalues: usize,
        shapes: usize,
    },
    #[error("sweep point {point} (mu = {mu}), mode {mode}: the shape has {len} DOFs, the sweep's first shape has {expected} (shapes must be restricted to one common DOF set)")]
    ShapeLength {
        point: usize,
        mu: f64,
        mode: usize,
        len: usize,
        expected: usize,
    },
    #[error("sweep point {point} (mu = {mu}), mode {mode}: the shape is zero")]
    ZeroShape { point: usize, mu: f64, mode: usize },
    #[error("sweep point {point}: mu = {mu} is not finite")]
    MuNotFinite { point: usize, mu: f64 },
    #[error("sweep point {point} (mu = {mu}), mode {mode}: {what} is not finite")]
    NotFinite {
        point: usize,
        mu: f64,
        mode: usize,
        what: &'static str,
    },
    #[error("sweep point {point} (mu = {mu}), mode {mode}: eigenvalue {re} + {im} i has a negative frequency; give the member of each conjugate pair with Im(lambda) >= 0")]
    NegativeFrequency {
        point: usize,
        mu: f64,
        mode: usize,
        re: f64,
        im: f64,
    },
    #[error("the friction coefficients must be strictly increasing or strictly decreasing: point {point} has mu = {mu} after {previous}")]
    NotMonotonic {
        point: usize,
        mu: f64,
        previous: f64,
    },
    #[error("option {name} = {value}: must be {requirement}")]
    BadOption {
        name: &'static str,
        value: f64,
        requirement: &'static str,
    },
    #[error("cost matrix row {row} has {len} entries, row 0 has {expected}")]
    RaggedCost {
        row: usize,
        len: usize,
        expected: usize,
    },
    #[error("cost matrix entry ({row}, {column}) = {value} is not finite")]
    CostNotFinite {
        row: usize,
        column: usize,
        value: f64,
    },
    #[error("track {track} has {len} members but the sweep has {points} points")]
    TrackLength {
        track: usize,
        len: usize,
        points: usize,
    },
    #[error("track {track} refers to mode {mode} of sweep point {point}, which has {count} modes")]
    TrackMember {
        track: usize,
        point: usize,
        mode: usize,
        count: usize,
    },
    #[error("track {track}: its modes are not contiguous (absent at point {point} between two present ones)")]
    TrackGap { track: usize, point: usize },
}

/// Frequency in Hz of lambda = a + i b: b / 2 pi.
pub fn frequency_hz(lambda: Complex64) -> f64 {
    lambda.im / (2.0 * PI)
}

/// The complex modal assurance criterion |a^H b|^2 / ((a^H a)(b^H b)), in [0, 1]: 1 when
/// the shapes are parallel (by any complex factor), 0 when orthogonal; 0 when either is
/// the zero vector.
pub fn complex_mac(a: &[Complex64], b: &[Complex64]) -> Result<f64, TrackingError> {
    if a.len() != b.len() {
        return Err(TrackingError::ShapeLengths {
            left: a.len(),
            right: b.len(),
        });
    }
    Ok(mac_of(inner(a, b), norm_sqr(a), norm_sqr(b)))
}

/// a^H b.
fn inner(a: &[Complex64], b: &[Complex64]) -> Complex64 {
    a.iter().zip(b).map(|(x, y)| x.conj() * y).sum()
}

fn norm_sqr(a: &[Complex64]) -> f64 {
    a.iter().map(|x| x.norm_sqr()).sum()
}

fn mac_of(ab: Complex64, aa: f64, bb: f64) -> f64 {
    if aa == 0.0 || bb == 0.0 {
        return 0.0;
    }
    // Cauchy-Schwarz bounds the exact value by 1; rounding may exceed it by a few ulps.
    (ab.norm_sqr() / (aa * bb)).clamp(0.0, 1.0)
}

/// Optimal one-to-one assignment: the rows' columns minimising the total cost, each column
/// used at most once. Rectangular matrices are fine: with more rows than columns the surplus
/// rows get `None`, otherwise every row gets a column. Hungarian algorithm with potentials
/// (shortest augmenting paths, as in Jonker-Volgenant), O(n^2 m) for n <= m.
pub fn assign(cost: &[Vec<f64>]) -> Result<Vec<Option<usize>>, TrackingError> {
    let rows = cost.len();
    let columns = cost.first().map_or(0, Vec::len);
    for (row, entries) in cost.iter().enumerate() {
        if entries.len() != columns {
            return Err(TrackingError::RaggedCost {
                row,
                len: entries.len(),
                expected: columns,
            });
        }
        if let Some((column, &value)) = entries.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(TrackingError::CostNotFinite { row, column, value });
        }
    }
    if rows == 0 || columns == 0 {
        return Ok(vec![None; rows]);
    }
    if rows <= columns {
        Ok(hungarian(rows, columns, |i, j| cost[i][j])
            .into_iter()
            .map(Some)
            .collect())
    } else {
        // Assign the columns to rows instead, then invert.
        let of_column = hungarian(columns, rows, |i, j| cost[j][i]);
        let mut of_row = vec![None; rows];
        for (column, &row) in of_column.iter().enumerate() {
            of_row[row] = Some(column);
        }
        Ok(of_row)
    }
}

/// Hungarian algorithm for n <= m with finite costs: for each row, its column. Rows and
/// columns are 1-based inside, index 0 being the virtual start of each augmenting path.
fn hungarian(n: usize, m: usize, cost: impl Fn(usize, usize) -> f64) -> Vec<usize> {
    let mut u = vec![0.0; n + 1];
    let mut v = vec![0.0; m + 1];
    // row_of[j]: the row holding column j, 0 when free.
    let mut row_of = vec![0usize; m + 1];
    let mut way = vec![0usize; m + 1];
    for i in 1..=n {
        row_of[0] = i;
        let mut j0 = 0;
        let mut min_slack = vec![f64::INFINITY; m + 1];
        let mut used = vec![false; m + 1];
        loop {
            used[j0] = true;
            let i0 = row_of[j0];
            let mut delta = f64::INFINITY;
            let mut j1 = 0;
            for j in 1..=m {
                if !used[j] {
                    let slack = cost(i0 - 1, j - 1) - u[i0] - v[j];
                    if slack < min_slack[j] {
                        min_slack[j] = slack;
                        way[j] = j0;
                    }
                    if min_slack[j] < delta {
                        delta = min_slack[j];
                        j1 = j;
                    }
                }
            }
            // With n <= m a free column always remains, and costs are finite, so j1 != 0.
            for j in 0..=m {
                if used[j] {
                    u[row_of[j]] += delta;
                    v[j] -= delta;
                } else {
                    min_slack[j] -= delta;
                }
            }
            j0 = j1;
            if row_of[j0] == 0 {
                break;
            }
        }
        // Flip the augmenting path back to its start.
        while j0 != 0 {
            let j1 = way[j0];
            row_of[j0] = row_of[j1];
            j0 = j1;
        }
    }
    let mut column_of = vec![0; n];
    for j in 1..=m {
        if row_of[j] != 0 {
            column_of[row_of[j] - 1] = j - 1;
        }
    }
    column_of
}

fn check_options(options: &TrackingOptions) -> Result<(), TrackingError> {
    if !(0.0..=1.0).contains(&options.min_mac) {
        return Err(TrackingError::BadOption {
            name: "min_mac",
            value: options.min_mac,
            requirement: "in [0, 1]",
        });
    }
    if !(options.frequency_weight.is_finite() && options.frequency_weight >= 0.0) {
        return Err(TrackingError::BadOption {
            name: "frequency_weight",
            value: options.frequency_weight,
            requirement: "finite and >= 0",
        });
    }
    Ok(())
}

/// Checks the sweep's consistency: finite data, shapes of one common length, non-zero,
/// eigenvalues with b >= 0, mu strictly monotonic.
fn check_points(points: &[SweepPoint]) -> Result<(), TrackingError> {
    let expected = points
        .iter()
        .find_map(|p| p.shapes.first())
        .map_or(0, Vec::len);
    let mut direction = 0.0;
    for (point, p) in points.iter().enumerate() {
        let mu = p.mu;
        if !mu.is_finite() {
            return Err(TrackingError::MuNotFinite { point, mu });
        }
        if point > 0 {
            let previous = points[point - 1].mu;
            let step = mu - previous;
            if step == 0.0 || step * direction < 0.0 {
                return Err(TrackingError::NotMonotonic {
                    point,
                    mu,
                    previous,
                });
            }
            direction = step.signum();
        }
        if p.eigenvalues.len() != p.shapes.len() {
            return Err(TrackingError::ShapeCount {
                point,
                mu,
                eigenvalues: p.eigenvalues.len(),
                shapes: p.shapes.len(),
            });
        }
        for (mode, (lambda, shape)) in p.eigenvalues.iter().zip(&p.shapes).enumerate() {
            if !(lambda.re.is_finite() && lambda.im.is_finite()) {
                return Err(TrackingError::NotFinite {
                    point,
                    mu,
                    mode,
                    what: "the eigenvalue",
                });
            }
            if lambda.im < 0.0 {
                return Err(TrackingError::NegativeFrequency {
                    point,
                    mu,
                    mode,
                    re: lambda.re,
                    im: lambda.im,
                });
            }
            if shape.len() != expected {
                return Err(TrackingError::ShapeLength {
                    point,
                    mu,
                    mode,
                    len: shape.len(),
                    expected,
                });
            }
            if shape
                .iter()
                .any(|x| !(x.re.is_finite() && x.im.is_finite()))
            {
                return Err(TrackingError::NotFinite {
                    point,
                    mu,
                    mode,
                    what: "the shape",
                });
            }
            if shape.iter().all(|x| *x == Complex64::new(0.0, 0.0)) {
                return Err(TrackingError::ZeroShape { point, mu, mode });
            }
        }
    }
    Ok(())
}

/// |f_i - f_j| / max(f_i, f_j), 0 when both are 0 Hz (rigid-body modes).
pub fn relative_frequency_distance(a: Complex64, b: Complex64) -> f64 {
    let (fa, fb) = (a.im, b.im);
    let larger = fa.max(fb);
    if larger > 0.0 {
        (fa - fb).abs() / larger
    } else {
        0.0
    }
}

/// Follows the modes across the sweep by shape.
///
/// Between neighbouring points, the link cost of modes i and j is
/// 1 - MAC(i, j) + frequency_weight * |f_i - f_j| / max(f_i, f_j), and links with a MAC
/// below `min_mac` are forbidden. The links minimise the total cost plus, for each mode of
/// the earlier point left unlinked, a penalty of one more than the worst acceptable link:
/// every mode that has an acceptable partner keeps its track unless that partner is better
/// used by another mode. An unlinked mode ends its track; an unlinked mode of the later
/// point starts a new one. Tracks are numbered by their first point, then by mode index.
pub fn track(
    points: &[SweepPoint],
    options: &TrackingOptions,
) -> Result<Vec<Track>, TrackingError> {
    check_options(options)?;
    check_points(points)?;
    let count = points.len();
    let mut tracks: Vec<Track> = Vec::new();
    // The track of each mode of the current point.
    let mut open: Vec<usize> = Vec::new();
    for (k, point) in points.iter().enumerate() {
        let modes = point.eigenvalues.len();
        let mut next = vec![usize::MAX; modes];
        if k > 0 {
            let previous = &points[k - 1];
            let links = link(previous, point, options)?;
            for (i, found) in links.into_iter().enumerate() {
                if let Some(Link { to, mac, regret }) = found {
                    let id = open[i];
                    tracks[id].members[k] = Some(to);
                    tracks[id].link_mac[k] = Some(mac);
                    tracks[id].link_regret[k] = Some(regret);
                    next[to] = id;
                }
            }
        }
        for (j, id) in next.iter_mut().enumerate() {
            if *id == usize::MAX {
                *id = tracks.len();
                let mut members = vec![None; count];
                members[k] = Some(j);
                tracks.push(Track {
                    id: *id,
                    members,
                    link_mac: vec![None; count],
                    link_regret: vec![None; count],
                });
            }
        }
        open = next;
    }
    Ok(tracks)
}

/// A mode's link to the next point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Link {
    /// The linked mode of the next point.
    pub to: usize,
    pub mac: f64,
    /// See [`Track::link_regret`].
    pub regret: f64,
}

/// For each mode of `from`, its link to a mode of `to`.
///
/// The regret of a link (i, j): the optimal total cost with (i, j) forbidden, less the
/// optimum. One more assignment per link (n^3 each: 60 modes take milliseconds), and exact:
/// it sees the swaps of three or more modes that comparing a row's best and second-best
/// entries would not.
pub fn link(
    from: &SweepPoint,
    to: &SweepPoint,
    options: &TrackingOptions,
) -> Result<Vec<Option<Link>>, TrackingError> {
    let (n, m) = (from.shapes.len(), to.shapes.len());
    let from_norms: Vec<f64> = from.shapes.iter().map(|s| norm_sqr(s)).collect();
    let to_norms: Vec<f64> = to.shapes.iter().map(|s| norm_sqr(s)).collect();
    let mac: Vec<Vec<f64>> = (0..n)
        .map(|i| {
            (0..m)
                .map(|j| {
                    mac_of(
                        inner(&from.shapes[i], &to.shapes[j]),
                        from_norms[i],
                        to_norms[j],
                    )
                })
                .collect()
        })
        .collect();
    // Relative frequency distances are at most 1, so no acceptable link costs more than
    // `worst`; leaving a mode unlinked costs more than any acceptable link, and a forbidden
    // link more than leaving the mode unlinked (each row has its own "unlinked" column, so
    // an optimum never uses a forbidden link).
    let worst = 1.0 - options.min_mac + options.frequency_weight;
    let unlinked = worst + 1.0;
    let forbidden = 2.0 * unlinked + 1.0;
    let cost: Vec<Vec<f64>> = (0..n)
        .map(|i| {
            let mut row: Vec<f64> = (0..m)
                .map(|j| {
                    if mac[i][j] >= options.min_mac {
                        1.0 - mac[i][j]
                            + options.frequency_weight
                                * relative_frequency_distance(
                                    from.eigenvalues[i],
                                    to.eigenvalues[j],
                                )
                    } else {
                        forbidden
                    }
                })
                .collect();
            row.extend((0..n).map(|d| if d == i { unlinked } else { forbidden }));
            row
        })
        .collect();
    let total = |cost: &[Vec<f64>], columns: &[Option<usize>]| -> f64 {
        columns
            .iter()
            .enumerate()
            .filter_map(|(i, c)| c.map(|j| cost[i][j]))
            .sum()
    };
    let best = assign(&cost)?;
    let optimum = total(&cost, &best);
    let (from_twins, to_twins) = (twins(&from.eigenvalues), twins(&to.eigenvalues));
    let mut links = Vec::with_capacity(n);
    for (i, column) in best.iter().enumerate() {
        links.push(match *column {
            Some(j) if j < m && mac[i][j] >= options.min_mac => {
                let mut without = cost.clone();
                for &a in group_of(&from_twins, &i) {
                    for &b in group_of(&to_twins, &j) {
                        without[a][b] = forbidden;
                    }
                }
                let other = assign(&without)?;
                Some(Link {
                    to: j,
                    mac: mac[i][j],
                    regret: (total(&without, &other) - optimum).max(0.0),
                })
            }
            _ => None,
        });
    }
    Ok(links)
}

/// What the links of a sweep's tracks look like, for the log: how many, how many uncertain,
/// how many change frequency by more than [`LinkSummary::JUMP`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LinkSummary {
    pub links: usize,
    pub uncertain: usize,
    pub jumps: usize,
    /// The largest relative change of frequency across a link.
    pub largest_jump: f64,
}

impl LinkSummary {
    /// A link that changes its mode's frequency by more than this is a jump: friction moves
    /// a mode by a few percent over a step of 0.1; more says the link may join two modes.
    pub const JUMP: f64 = 0.05;

    pub fn of(points: &[SweepPoint], tracks: &[Track], trusted_regret: f64) -> Self {
        let mut s = LinkSummary::default();
        for t in tracks {
            for k in 1..points.len().min(t.members.len()) {
                let (Some(a), Some(b)) = (t.members[k - 1], t.members[k]) else {
                    continue;
                };
                let (Some(la), Some(lb)) = (
                    points[k - 1].eigenvalues.get(a),
                    points[k].eigenvalues.get(b),
                ) else {
                    continue;
                };
                let change = relative_frequency_distance(*la, *lb);
                s.links += 1;
                s.jumps += usize::from(change > Self::JUMP);
                s.largest_jump = s.largest_jump.max(change);
                let regret = t.link_regret.get(k).copied().flatten();
                s.uncertain += usize::from(regret.is_some_and(|r| r < trusted_regret));
            }
        }
        s
    }
}

/// Two modes of one point whose frequencies agree to this fraction are twins (see [`twins`]).
/// The two modes of a coupled pair of the undamped CEA share theirs to round-off (their
/// omega^2 are complex conjugates), a doublet of an axisymmetric disc nearly so.
pub const TWIN_TOLERANCE: f64 = 1e-6;

/// The groups of two or more modes of one point with one frequency (to [`TWIN_TOLERANCE`]).
///
/// Why they matter to a link's regret: past coalescence the pair's shapes are x and conj(x),
/// and a shape of the point before (nearly real there) has the same MAC with both. Linking
/// a mode into one twin rather than the other is a tie, regret 0, yet it changes nothing a
/// reader is told: the instability is the pair. So the regret of a link into (or out of) a
/// group forbids the whole group, and measures whether the mode belongs to the pair at all.
fn twins(eigenvalues: &[Complex64]) -> Vec<Vec<usize>> {
    let mut order: Vec<usize> = (0..eigenvalues.len()).collect();
    order.sort_by(|&a, &b| eigenvalues[a].im.total_cmp(&eigenvalues[b].im));
    let mut groups: Vec<Vec<usize>> = Vec::new();
    let mut current: Vec<usize> = Vec::new();
    for &k in &order {
        let joins = current.last().is_some_and(|&last| {
            relative_frequency_distance(eigenvalues[last], eigenvalues[k]) <= TWIN_TOLERANCE
        });
        if !joins {
            if current.len() > 1 {
                groups.push(std::mem::take(&mut current));
            }
            current.clear();
        }
        current.push(k);
    }
    if current.len() > 1 {
        groups.push(current);
    }
    groups
}

/// The twins of mode `k` with it, or `k` alone.
fn group_of<'a>(twins: &'a [Vec<usize>], k: &'a usize) -> &'a [usize] {
    twins
        .iter()
        .find(|g| g.contains(k))
        .map_or(std::slice::from_ref(k), Vec::as_slice)
}

fn check_tracks(points: &[SweepPoint], tracks: &[Track]) -> Result<(), TrackingError> {
    for (track, t) in tracks.iter().enumerate() {
        if t.members.len() != points.len() {
            return Err(TrackingError::TrackLength {
                track,
                len: t.members.len(),
                points: points.len(),
            });
        }
        let mut ended = false;
        let mut started = false;
        for (point, member) in t.members.iter().enumerate() {
            match member {
                Some(mode) => {
                    let count = points[point].eigenvalues.len();
                    if *mode >= count {
                        return Err(TrackingError::TrackMember {
                            track,
                            point,
                            mode: *mode,
                            count,
                        });
                    }
                    if ended {
                        return Err(TrackingError::TrackGap {
                            track,
                            point: point - 1,
                        });
                    }
                    started = true;
                }
                None => ended = started,
            }
        }
    }
    Ok(())
}

/// Linear interpolation of the zero of y between (x0, y0) and (x1, y1), kept in [x0, x1]
/// (y0 may be slightly positive within the stability tolerance).
fn zero_crossing(x0: f64, y0: f64, x1: f64, y1: f64) -> f64 {
    if y1 == y0 {
        return x0;
    }
    let t = (-y0 / (y1 - y0)).clamp(0.0, 1.0);
    x0 + t * (x1 - x0)
}

/// The unstable intervals of every track, with their partners.
///
/// A track is unstable at a point when its real part exceeds `real_part_tolerance * |lambda|`.
/// Each maximal run of unstable points of a track is one [`Instability`].
pub fn instabilities(
    points: &[SweepPoint],
    tracks: &[Track],
    options: &InstabilityOptions,
) -> Result<Vec<Instability>, TrackingError> {
    for (name, value) in [
        ("real_part_tolerance", options.real_part_tolerance),
        ("frequency_tolerance", options.frequency_tolerance),
        ("trusted_regret", options.trusted_regret),
    ] {
        if !(value.is_finite() && value >= 0.0) {
            return Err(TrackingError::BadOption {
                name,
                value,
                requirement: "finite and >= 0",
            });
        }
    }
    check_points(points)?;
    check_tracks(points, tracks)?;
    let lambda_of = |t: &Track, k: usize| t.members[k].map(|mode| points[k].eigenvalues[mode]);
    let unstable = |lambda: Complex64| super::cea::is_unstable(lambda, options.real_part_tolerance);

    let mut found = Vec::new();
    for (id, t) in tracks.iter().enumerate() {
        let mut k = 0;
        while k < points.len() {
            if !lambda_of(t, k).is_some_and(unstable) {
                k += 1;
                continue;
            }
            let first = k;
            while k < points.len() && lambda_of(t, k).is_some_and(unstable) {
                k += 1;
            }
            let last = k - 1;
            found.push(describe(points, tracks, id, first, last, options));
        }
    }
    Ok(found)
}

/// The instability of track `id` unstable from point `first` to point `last` (inclusive).
/// `check_tracks` has made every member index valid.
fn describe(
    points: &[SweepPoint],
    tracks: &[Track],
    id: usize,
    first: usize,
    last: usize,
    options: &InstabilityOptions,
) -> Instability {
    let lambda_of = |t: usize, k: usize| -> Option<Complex64> {
        tracks[t].members[k].map(|mode| points[k].eigenvalues[mode])
    };
    // Members of the track in the interval are present by construction.
    let at = |k: usize| lambda_of(id, k).unwrap_or_default();

    let before = first
        .checked_sub(1)
        .and_then(|k| lambda_of(id, k).map(|l| (k, l)));
    let (onset_mu, frequency_hz_at_onset, onset_bracketed) = match before {
        Some((k0, l0)) => {
            let l1 = at(first);
            let mu = zero_crossing(points[k0].mu, l0.re, points[first].mu, l1.re);
            let t = (mu - points[k0].mu) / (points[first].mu - points[k0].mu);
            let f = frequency_hz(l0) + t * (frequency_hz(l1) - frequency_hz(l0));
            (mu, f, true)
        }
        None => (points[first].mu, frequency_hz(at(first)), false),
    };

    let (mut k_max, mut a_max) = (first, at(first).re);
    for k in first..=last {
        if at(k).re > a_max {
            (k_max, a_max) = (k, at(k).re);
        }
    }

    let after = (last + 1 < points.len())
        .then(|| lambda_of(id, last + 1))
        .flatten();
    let restabilisation_mu = after.map(|l1| {
        let l0 = at(last);
        zero_crossing(points[last].mu, l0.re, points[last + 1].mu, l1.re)
    });

    // The partner: at the first point of the interval where one qualifies, the track with
    // a negative real part whose frequency is merged with this one's, the closest.
    let partner = (first..=last).find_map(|k| {
        let mine = at(k);
        (0..tracks.len())
            .filter(|&t| t != id)
            .filter_map(|t| lambda_of(t, k).map(|l| (t, l)))
            .filter(|(_, l)| l.re < 0.0)
            .map(|(t, l)| (t, relative_frequency_distance(mine, l)))
            .filter(|&(_, d)| d <= options.frequency_tolerance)
            .min_by(|x, y| x.1.total_cmp(&y.1))
            .map(|(t, _)| t)
    });

    let coalescence_mu = partner.and_then(|p| {
        let q = |k: usize| -> Option<f64> {
            let (mine, theirs) = (lambda_of(id, k)?, lambda_of(p, k)?);
            let half = (mine - theirs) / 2.0;
            Some((half * half).re)
        };
        // The bracket nearest the onset, searching back from the first unstable point while
        // both tracks exist.
        let mut k = first;
        while k > 0 {
            let (q0, q1) = (q(k - 1)?, q(k)?);
            if q0 <= 0.0 && q1 > 0.0 {
                return Some(zero_crossing(points[k - 1].mu, q0, points[k].mu, q1));
            }
            k -= 1;
        }
        None
    });

    // The links reaching points `first..=last` (the first from the last stable point).
    let uncertain_links = std::iter::once(id)
        .chain(partner)
        .flat_map(|t| (first.max(1)..=last).map(move |k| (t, k)))
        .filter_map(|(t, k)| {
            let track = &tracks[t];
            let regret = track.link_regret.get(k).copied().flatten()?;
            let mac = track.link_mac.get(k).copied().flatten()?;
            let (l0, l1) = (lambda_of(t, k - 1)?, lambda_of(t, k)?);
            (regret < options.trusted_regret).then(|| UncertainLink {
                track: t,
                from_mu: points[k - 1].mu,
                to_mu: points[k].mu,
                mac,
                regret,
                frequency_change: relative_frequency_distance(l0, l1),
                contact_changed: false,
            })
        })
        .collect();

    Instability {
        track: id,
        partner,
        onset_mu,
        onset_bracketed,
        coalescence_mu,
        frequency_hz_at_onset,
        first_unstable_mu: points[first].mu,
        frequency_hz_at_first_unstable: frequency_hz(at(first)),
        max_real_part: a_max,
        mu_at_max: points[k_max].mu,
        frequency_hz_at_max: frequency_hz(at(k_max)),
        restabilisation_mu,
        uncertain_links,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn c(re: f64, im: f64) -> Complex64 {
        Complex64::new(re, im)
    }

    /// xorshift64*: reproducible pseudo-random numbers without a dependency.
    struct Rng(u64);
    impl Rng {
        fn uniform(&mut self) -> f64 {
            self.0 ^= self.0 >> 12;
            self.0 ^= self.0 << 25;
            self.0 ^= self.0 >> 27;
            (self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 / (1u64 << 53) as f64
        }
        fn complex(&mut self) -> Complex64 {
            c(2.0 * self.uniform() - 1.0, 2.0 * self.uniform() - 1.0)
        }
        fn vector(&mut self, n: usize) -> Vec<Complex64> {
            (0..n).map(|_| self.complex()).collect()
        }
    }

    fn mac(a: &[Complex64], b: &[Complex64]) -> f64 {
        complex_mac(a, b).unwrap()
    }

    fn scaled(v: &[Complex64], s: Complex64) -> Vec<Complex64> {
        v.iter().map(|x| s * x).collect()
    }

    #[test]
    fn complex_mac_properties() {
        let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
        for _ in 0..100 {
            let (a, b) = (rng.vector(7), rng.vector(7));
            let m = mac(&a, &b);
            assert!((0.0..=1.0).contains(&m));
            // b^H a is the exact conjugate of a^H b term by term in IEEE arithmetic.
            assert_eq!(m, mac(&b, &a));
            // Invariant under complex scaling of either shape: the factors cancel exactly in
            // exact arithmetic; a few roundings of O(eps) each remain.
            let (s, t) = (c(0.3, -1.7), c(-2.0, 0.5));
            assert!((mac(&scaled(&a, s), &scaled(&b, t)) - m).abs() < 1e-14);
            assert!((mac(&a, &scaled(&a, t)) - 1.0).abs() < 1e-14);
        }
        // (1, i) and (1, -i) are orthogonal under the Hermitian product, though not under the
        // plain one: the MAC must conjugate.
        assert_eq!(
            mac(&[c(1.0, 0.0), c(0.0, 1.0)], &[c(1.0, 0.0), c(0.0, -1.0)]),
            0.0
        );
        // Between the complex lines of e1 and (cos t, sin t e^{i p}): cos^2 t, whatever p.
        let (t, p) = (0.7_f64, 1.3_f64);
        let b = [c(t.cos(), 0.0), Complex64::from_polar(t.sin(), p)];
        let e1 = [c(1.0, 0.0), c(0.0, 0.0)];
        assert!((mac(&e1, &b) - t.cos().powi(2)).abs() < 1e-15);
        assert_eq!(mac(&e1, &[c(0.0, 0.0); 2]), 0.0);
        assert_eq!(
            complex_mac(&e1, &[c(1.0, 0.0)]),
            Err(TrackingError::ShapeLengths { left: 2, right: 1 })
        );
    }

    fn total(cost: &[Vec<f64>], assignment: &[Option<usize>]) -> f64 {
        assignment
            .iter()
            .enumerate()
            .filter_map(|(i, j)| j.map(|j| cost[i][j]))
            .sum()
    }

    /// Minimum over every injection of the smaller side into the larger one.
    fn brute_force(cost: &[Vec<f64>]) -> f64 {
        fn go(cost: &[Vec<f64>], row: usize, used: &mut Vec<bool>, skips: usize) -> f64 {
            if row == cost.len() {
                return 0.0;
            }
            let mut best = f64::INFINITY;
            if skips > 0 {
                best = go(cost, row + 1, used, skips - 1);
            }
            for j in 0..used.len() {
                if !used[j] {
                    used[j] = true;
                    best = best.min(cost[row][j] + go(cost, row + 1, used, skips));
                    used[j] = false;
                }
            }
            best
        }
        let columns = cost[0].len();
        let skips = cost.len().saturating_sub(columns);
        go(cost, 0, &mut vec![false; columns], skips)
    }

    fn check_assignment(cost: &[Vec<f64>]) {
        let result = assign(cost).unwrap();
        let columns = cost[0].len();
        let assigned: Vec<usize> = result.iter().flatten().copied().collect();
        assert_eq!(assigned.len(), cost.len().min(columns));
        let mut sorted = assigned.clone();
        sorted.sort();
        sorted.dedup();
        assert_eq!(sorted.len(), assigned.len(), "a column used twice");
        // Both are sums of at most 6 entries of order 1: they agree to a few ulps when the
        // assignment is optimal, and a suboptimal one would differ by a cost gap (random
        // entries: far above 1e-12).
        assert!((total(cost, &result) - brute_force(cost)).abs() < 1e-12);
    }

    #[test]
    fn assign_is_optimal_against_brute_force() {
        let mut rng = Rng(42);
        for (rows, columns) in [(6, 6), (4, 6), (6, 4), (1, 5), (5, 1)] {
            for trial in 0..200 {
                let cost: Vec<Vec<f64>> = (0..rows)
                    .map(|_| {
                        (0..columns)
                            .map(|_| {
                                // Every other trial in small integers: many ties.
                                if trial % 2 == 0 {
                                    10.0 * rng.uniform() - 3.0
                                } else {
                                    (3.0 * rng.uniform()).floor()
                                }
                            })
                            .collect()
                    })
                    .collect();
                check_assignment(&cost);
            }
        }
    }

    #[test]
    fn assign_rejects_bad_matrices() {
        assert_eq!(assign(&[]), Ok(vec![]));
        assert_eq!(assign(&[vec![], vec![]]), Ok(vec![None, None]));
        assert_eq!(
            assign(&[vec![1.0, 2.0], vec![3.0]]),
            Err(TrackingError::RaggedCost {
                row: 1,
                len: 1,
                expected: 2
            })
        );
        assert!(matches!(
            assign(&[vec![1.0, f64::NAN]]),
            Err(TrackingError::CostNotFinite {
                row: 0,
                column: 1,
                ..
            })
        ));
    }

    /// The 3-DOF mode-coupling model M = I,
    /// K = [[k1, mu c, 0], [-mu c, k2, 0], [0, 0, k3]]: the first two DOFs couple by friction,
    /// the third is a spectator. omega^2 = s +/- sqrt(D), s = (k1 + k2) / 2,
    /// D = ((k1 - k2) / 2)^2 - (mu c)^2: real and distinct below mu_c = |k1 - k2| / 2c, a
    /// conjugate pair above.
    struct Coupling {
        k1: f64,
        k2: f64,
        k3: f64,
        c: f64,
    }

    impl Coupling {
        fn new(mu_c: f64) -> Self {
            let (k1, k2) = ((2.0 * PI * 1000.0).powi(2), (2.0 * PI * 1100.0).powi(2));
            Coupling {
                k1,
                k2,
                k3: (2.0 * PI * 1500.0).powi(2),
                c: (k2 - k1).abs() / 2.0 / mu_c,
            }
        }
        fn s(&self) -> f64 {
            (self.k1 + self.k2) / 2.0
        }
        fn discriminant(&self, mu: f64) -> f64 {
            ((self.k1 - self.k2) / 2.0).powi(2) - (mu * self.c).powi(2)
        }
        /// The three (lambda, shape) pairs at mu, lambda = i sqrt(omega^2) (b >= 0).
        fn modes(&self, mu: f64) -> Vec<(Complex64, Vec<Complex64>)> {
            let root = Complex64::from(self.discriminant(mu)).sqrt();
            let mut modes: Vec<_> = [self.s() + root, self.s() - root]
                .into_iter()
                .map(|omega2| {
                    // Both rows of (K - omega^2) v = 0 give a null vector; take the larger
                    // (the other can vanish when mu c is small).
                    let from_row2 = vec![self.k2 - omega2, c(mu * self.c, 0.0), c(0.0, 0.0)];
                    let from_row1 = vec![c(mu * self.c, 0.0), omega2 - self.k1, c(0.0, 0.0)];
                    let v = if norm_sqr(&from_row2) >= norm_sqr(&from_row1) {
                        from_row2
                    } else {
                        from_row1
                    };
                    // Self-check: the residual of K v = omega^2 v, relative to |K| |v|.
                    let r1 = (self.k1 - omega2) * v[0] + mu * self.c * v[1];
                    let r2 = -mu * self.c * v[0] + (self.k2 - omega2) * v[1];
                    let scale = self.k2 * norm_sqr(&v).sqrt();
                    assert!((r1.norm() + r2.norm()) / scale < 1e-13);
                    (c(0.0, 1.0) * omega2.sqrt(), v)
                })
                .collect();
            let spectator = vec![c(0.0, 0.0), c(0.0, 0.0), c(1.0, 0.0)];
            modes.push((c(0.0, self.k3.sqrt()), spectator));
            modes
        }
        /// The growth rate a > 0 above mu_c, without cancellation: sqrt(s + i e) = x + i y
        /// with x = sqrt((|s + i e| + s) / 2) and y = e / 2x.
        fn growth_and_frequency(&self, mu: f64) -> (f64, f64) {
            let s = self.s();
            let e = (-self.discriminant(mu)).sqrt();
            let x = ((s.hypot(e) + s) / 2.0).sqrt();
            (e / (2.0 * x), x / (2.0 * PI))
        }
        /// Re(((lambda_1 - lambda_2) / 2)^2), the same closed form on both sides of mu_c:
        /// -D / (2 s + 2 sqrt(s^2 - D)).
        fn q(&self, mu: f64) -> f64 {
            let (s, d) = (self.s(), self.discriminant(mu));
            -d / (2.0 * s + 2.0 * (s * s - d).sqrt())
        }
    }

    /// The sweep 0.1, 0.2, ..., 0.9 of the coupling model, with the modes listed in a
    /// different order at each point and each shape scaled by an arbitrary complex factor.
    fn coupling_sweep(model: &Coupling) -> Vec<SweepPoint> {
        let mut rng = Rng(7);
        (1..=9)
            .map(|k| {
                let mu = 0.1 * k as f64;
                let mut modes = model.modes(mu);
                modes.rotate_left(k % 3);
                if k % 2 == 0 {
                    modes.swap(0, 1);
                }
                SweepPoint {
                    mu,
                    eigenvalues: modes.iter().map(|m| m.0).collect(),
                    shapes: modes
                        .iter()
                        .map(|m| scaled(&m.1, rng.complex() + 0.1))
                        .collect(),
                }
            })
            .collect()
    }

    #[test]
    fn coupling_pair_is_one_instability_with_its_partner() {
        let mu_c = 0.45;
        let model = Coupling::new(mu_c);
        let points = coupling_sweep(&model);
        let tracks = track(&points, &TrackingOptions::default()).unwrap();
        assert_eq!(tracks.len(), 3, "{tracks:?}");
        for t in &tracks {
            assert!(t.members.iter().all(Option::is_some), "{t:?}");
        }
        // The spectator keeps its own track (shape e3) across the reorderings.
        let spectator = tracks
            .iter()
            .find(|t| points[0].shapes[t.members[0].unwrap()][2].norm() > 0.0)
            .unwrap();
        for (k, member) in spectator.members.iter().enumerate() {
            assert!(points[k].shapes[member.unwrap()][2].norm() > 0.0);
        }

        let found = instabilities(&points, &tracks, &InstabilityOptions::default()).unwrap();
        assert_eq!(found.len(), 1, "{found:?}");
        let instability = &found[0];
        let last = points.len() - 1;
        // Past the merge the pair's shapes are x and conj(x), alike to any shape before it:
        // which of the two a mode is linked to is a tie, but whether it joins the pair is
        // not. Every link, the merge's included, is trusted: the spectator is orthogonal, so
        // the next best leaves modes unlinked (regret about 1.5 and more), except just before
        // the merge, where the two modes' shapes converge (an exceptional point has one
        // eigenvector) and swapping them costs less: 0.69 from mu 0.3 to 0.4.
        for t in &tracks {
            for k in 1..points.len() {
                let floor = if k == 3 { 0.5 } else { 1.4 };
                assert!(t.link_regret[k].unwrap() >= floor, "{k}: {t:?}");
            }
        }
        assert!(instability.uncertain_links.is_empty());
        let unstable = &tracks[instability.track];
        let partner = &tracks[instability.partner.expect("a partner")];
        assert_ne!(partner.id, spectator.id);
        assert_ne!(unstable.id, spectator.id);
        let lambda = |t: &Track, k: usize| points[k].eigenvalues[t.members[k].unwrap()];
        // Past the merge the pair is a +/- a with one frequency (conjugate omega^2).
        assert_eq!(lambda(partner, last).re, -lambda(unstable, last).re);

        // Onset: exactly the linear interpolation of the real parts at mu = 0.4 and 0.5; the
        // real part is exactly 0 below mu_c (i sqrt of a positive real), so that is 0.4, and
        // within one step of mu_c.
        let (mu0, mu1) = (points[3].mu, points[4].mu);
        let (a1, _) = model.growth_and_frequency(mu1);
        let expected = mu0 + (mu1 - mu0) * (0.0 - 0.0) / (a1 - 0.0);
        assert!(instability.onset_bracketed);
        assert!((instability.onset_mu - expected).abs() < 1e-15);
        assert!(mu0 <= mu_c && mu_c <= mu1);
        assert!((instability.onset_mu - mu_c).abs() <= mu1 - mu0);

        // The coalescence estimate: the zero of the linear interpolant of the closed-form q
        // (the tracker computes q from eigenvalue differences that cancel about 1.5 digits of
        // ~1e-16: 1e-12 is generous). q is (mu^2 c^2 - d^2) / 4s to within O(D / s^2) ~ 1%,
        // whose linear interpolant has its zero off by (mu_c - mu0)(mu1 - mu_c)/(mu0 + mu1):
        // allow 1.5 times that, ten times closer than the onset.
        let (q0, q1) = (model.q(mu0), model.q(mu1));
        let interpolated = mu0 - q0 * (mu1 - mu0) / (q1 - q0);
        let coalescence = instability.coalescence_mu.expect("a coalescence estimate");
        assert!((coalescence - interpolated).abs() < 1e-12);
        let bound = 1.5 * (mu_c - mu0) * (mu1 - mu_c) / (mu0 + mu1);
        assert!((coalescence - mu_c).abs() < bound, "{coalescence}");
        assert!((coalescence - mu_c).abs() < (instability.onset_mu - mu_c).abs() / 10.0);

        // The growth keeps increasing with mu, so the maximum is at the last point and equals
        // the closed form there (both to a few ulps; the tracker's lambda went through a
        // complex sqrt: relative 1e-13).
        let (a_max, f_max) = model.growth_and_frequency(points[last].mu);
        assert_eq!(instability.mu_at_max, points[last].mu);
        assert!((instability.max_real_part - a_max).abs() < 1e-13 * a_max);
        assert!((instability.frequency_hz_at_max - f_max).abs() < 1e-13 * f_max);
        // At the onset (mu = 0.4, the last stable point) the frequency is that of the track's
        // mode there.
        let f_onset = frequency_hz(lambda(unstable, 3));
        assert!((instability.frequency_hz_at_onset - f_onset).abs() < 1e-12 * f_onset);
        assert_eq!(instability.restabilisation_mu, None);
    }

    /// An orthonormal complex basis of C^n (Gram-Schmidt on random vectors).
    fn basis(rng: &mut Rng, n: usize) -> Vec<Vec<Complex64>> {
        let mut q: Vec<Vec<Complex64>> = Vec::new();
        for _ in 0..n {
            let mut v = rng.vector(n);
            for u in &q {
                let p = inner(u, &v);
                v.iter_mut().zip(u).for_each(|(x, y)| *x -= p * y);
            }
            let norm = norm_sqr(&v).sqrt();
            q.push(v.iter().map(|x| x / norm).collect());
        }
        q
    }

    #[test]
    fn crossing_modes_are_tracked_by_shape_not_index() {
        // Three orthogonal shapes; frequencies 100 -> 200 Hz, 200 -> 100 Hz and 300 Hz: the
        // first two cross at the middle point. Each point lists its modes by frequency, so
        // the first two swap indices across the crossing. Even a strong frequency weight
        // cannot link orthogonal shapes (MAC 0 < min_mac).
        let mut rng = Rng(3);
        let q = basis(&mut rng, 5);
        let steps = 7;
        let points: Vec<SweepPoint> = (0..steps)
            .map(|k| {
                let t = k as f64 / (steps - 1) as f64;
                let mut modes = [(100.0 + 100.0 * t, 0), (200.0 - 100.0 * t, 1), (300.0, 2)];
                modes.sort_by(|x, y| x.0.total_cmp(&y.0));
                SweepPoint {
                    mu: 0.1 + 0.1 * k as f64,
                    eigenvalues: modes
                        .iter()
                        .map(|&(f, _)| c(-0.01 * f, 2.0 * PI * f))
                        .collect(),
                    shapes: modes
                        .iter()
                        .map(|&(_, shape)| scaled(&q[shape], rng.complex() + 0.1))
                        .collect(),
                }
            })
            .collect();
        let options = TrackingOptions {
            min_mac: 0.5,
            frequency_weight: 10.0,
        };
        let tracks = track(&points, &options).unwrap();
        assert_eq!(tracks.len(), 3);
        for t in &tracks {
            let first = &points[0].shapes[t.members[0].unwrap()];
            for (k, member) in t.members.iter().enumerate() {
                let m = member.expect("a full track");
                // Same shape up to a complex factor: MAC 1 to rounding.
                assert!((mac(first, &points[k].shapes[m]) - 1.0).abs() < 1e-13);
                assert!((t.link_mac[k].unwrap_or(1.0) - 1.0).abs() < 1e-13);
            }
        }
        // The indices did swap: the track of the 100 Hz mode is index 0 first, 1 last.
        assert_eq!(tracks[0].members[0], Some(0));
        assert_eq!(tracks[0].members[steps - 1], Some(1));
        // No real part is positive: no instability.
        let found = instabilities(&points, &tracks, &InstabilityOptions::default()).unwrap();
        assert!(found.is_empty());
    }

    #[test]
    fn modes_leaving_and_entering_the_band_end_and_start_tracks() {
        // Shapes q0 (present throughout), q1 (leaves the band after point 2), q2 (enters at
        // point 3) and q3, whose shape turns by 60 degrees towards q4 between points 1 and 2:
        // MAC cos^2 60 = 0.25 < 0.5, so its only candidate is refused.
        let mut rng = Rng(11);
        let q = basis(&mut rng, 5);
        let turned: Vec<Complex64> = q[3]
            .iter()
            .zip(&q[4])
            .map(|(a, b)| a * (PI / 3.0).cos() + b * (PI / 3.0).sin())
            .collect();
        let mode = |f: f64, shape: &[Complex64]| (c(0.0, 2.0 * PI * f), shape.to_vec());
        let sets: Vec<Vec<(Complex64, Vec<Complex64>)>> = (0..5)
            .map(|k| {
                let mut set = vec![mode(100.0, &q[0])];
                if k <= 2 {
                    set.push(mode(990.0 + k as f64, &q[1]));
                } else {
                    set.push(mode(995.0, &q[2]));
                }
                set.push(mode(500.0, if k <= 1 { &q[3] } else { &turned }));
                set
            })
            .collect();
        let points: Vec<SweepPoint> = sets
            .iter()
            .enumerate()
            .map(|(k, set)| SweepPoint {
                mu: 0.1 * (k + 1) as f64,
                eigenvalues: set.iter().map(|m| m.0).collect(),
                shapes: set.iter().map(|m| m.1.clone()).collect(),
            })
            .collect();
        let tracks = track(&points, &TrackingOptions::default()).unwrap();
        let members: Vec<Vec<Option<usize>>> = tracks.iter().map(|t| t.members.clone()).collect();
        let (s, n) = (Some, None);
        assert_eq!(
            members,
            vec![
                vec![s(0), s(0), s(0), s(0), s(0)],
                vec![s(1), s(1), s(1), n, n],
                vec![s(2), s(2), n, n, n],
                vec![n, n, s(2), s(2), s(2)],
                vec![n, n, n, s(1), s(1)],
            ]
        );
        assert_eq!(
            tracks.iter().map(|t| t.id).collect::<Vec<_>>(),
            vec![0, 1, 2, 3, 4]
        );
        assert_eq!(tracks[3].link_mac[2], None);
        assert!((tracks[3].link_mac[3].unwrap() - 1.0).abs() < 1e-13);
    }

    #[test]
    fn frequency_breaks_ties_between_identical_shapes() {
        // Two modes with one shape (as at a merge): MAC 1 to both candidates, so only the
        // frequency term can choose. Listed in opposite orders, 100 -> 101 Hz and
        // 110 -> 111 Hz must still pair up.
        let shape = vec![c(1.0, 0.5), c(-0.3, 0.0)];
        let at = |f: f64| c(0.0, 2.0 * PI * f);
        let points = vec![
            SweepPoint {
                mu: 0.1,
                eigenvalues: vec![at(100.0), at(110.0)],
                shapes: vec![shape.clone(), shape.clone()],
            },
            SweepPoint {
                mu: 0.2,
                eigenvalues: vec![at(111.0), at(101.0)],
                shapes: vec![shape.clone(), shape.clone()],
            },
        ];
        let tracks = track(&points, &TrackingOptions::default()).unwrap();
        let members: Vec<_> = tracks.iter().map(|t| t.members.clone()).collect();
        assert_eq!(
            members,
            vec![vec![Some(0), Some(1)], vec![Some(1), Some(0)]]
        );
    }

    /// One track per (frequency, real parts) series, each mode with its own orthogonal shape.
    /// Two modes at 100 and 200 Hz whose shapes turn by theta from one point to the next:
    /// MAC cos^2 theta with their own, sin^2 theta with the other's.
    fn turned(theta: f64) -> Vec<SweepPoint> {
        let point = |mu: f64, t: f64| SweepPoint {
            mu,
            eigenvalues: vec![c(0.0, 2.0 * PI * 100.0), c(0.0, 2.0 * PI * 200.0)],
            shapes: vec![
                vec![c(t.cos(), 0.0), c(t.sin(), 0.0)],
                vec![c(-t.sin(), 0.0), c(t.cos(), 0.0)],
            ],
        };
        vec![point(0.1, 0.0), point(0.2, theta)]
    }

    #[test]
    fn a_link_s_regret_is_what_the_next_best_assignment_costs_more() {
        let theta = 40f64.to_radians();
        let (own, other) = (theta.cos().powi(2), theta.sin().powi(2));
        // Every link allowed, no frequency term: the swap costs 2 cos^2 theta against the
        // optimum's 2 sin^2 theta, so each link's regret is 2 cos 2 theta.
        let free = TrackingOptions {
            min_mac: 0.0,
            frequency_weight: 0.0,
        };
        let links = link(&turned(theta)[0], &turned(theta)[1], &free).unwrap();
        for (i, l) in links.iter().enumerate() {
            let l = l.unwrap();
            assert_eq!(l.to, i);
            assert!((l.mac - own).abs() < 1e-15);
            assert!(
                (l.regret - 2.0 * (2.0 * theta).cos()).abs() < 1e-14,
                "{l:?}"
            );
        }
        // With MAC sin^2 40 deg = 0.41 below min_mac, the swap is forbidden and the next best
        // leaves the mode unlinked: 1 + (1 - min_mac) more than its own link's 1 - cos^2.
        let strict = TrackingOptions {
            min_mac: 0.5,
            frequency_weight: 0.0,
        };
        let links = link(&turned(theta)[0], &turned(theta)[1], &strict).unwrap();
        for l in links {
            let l = l.unwrap();
            assert!((l.regret - (1.5 - other)).abs() < 1e-14, "{l:?}");
        }
        // Near 45 degrees the two assignments explain the points equally: regret -> 0.
        let links = link(
            &turned(44.9f64.to_radians())[0],
            &turned(44.9f64.to_radians())[1],
            &free,
        )
        .unwrap();
        assert!(links.iter().all(|l| l.unwrap().regret < 0.01));
    }

    #[test]
    fn an_instability_says_which_uncertain_links_it_stands_on() {
        // Track 0 (100 Hz) unstable at the second point with partner track 1 (100.5 Hz),
        // two modes whose shapes are 8 degrees apart at both points (MAC cos^2 8 deg = 0.98
        // between them): swapping them costs 2 sin^2 8 deg = 0.039 in MAC and 2 x 0.1 x
        // 0.005 in frequency, so both links are nearly a tie.
        let alike = |mu: f64, a: f64| {
            let d = 4f64.to_radians();
            let shape = |t: f64| vec![c(t.cos(), 0.0), c(t.sin(), 0.0)];
            SweepPoint {
                mu,
                eigenvalues: vec![c(a, 2.0 * PI * 100.0), c(-a, 2.0 * PI * 100.5)],
                shapes: vec![shape(PI / 4.0 - d), shape(PI / 4.0 + d)],
            }
        };
        let points = vec![alike(0.1, 0.0), alike(0.2, 5.0)];
        let tracks = track(&points, &TrackingOptions::default()).unwrap();
        let found = instabilities(&points, &tracks, &InstabilityOptions::default()).unwrap();
        assert_eq!(found.len(), 1);
        let i = &found[0];
        assert_eq!((i.track, i.partner), (0, Some(1)));
        let regret = tracks[0].link_regret[1].unwrap();
        let expected = 2.0 * 8f64.to_radians().sin().powi(2) + 0.2 * 0.5 / 100.5;
        assert!((regret - expected).abs() < 1e-14, "{regret} {expected}");
        assert!(regret < TRUSTED_REGRET);
        assert_eq!(i.uncertain_links.len(), 2, "{i:?}");
        for (u, track) in i.uncertain_links.iter().zip([0, 1]) {
            assert_eq!((u.track, u.from_mu, u.to_mu), (track, 0.1, 0.2));
            assert_eq!(u.regret, tracks[track].link_regret[1].unwrap());
            assert!(u.frequency_change.abs() < 1e-12);
        }
        // Trusting every link (regret >= 0) says nothing.
        let trusting = InstabilityOptions {
            trusted_regret: 0.0,
            ..InstabilityOptions::default()
        };
        let quiet = instabilities(&points, &tracks, &trusting).unwrap();
        assert!(quiet[0].uncertain_links.is_empty());
        // Shapes 90 degrees apart turned by 10 degrees, the links are sure.
        let mut sure = turned(10f64.to_radians());
        for (p, q) in sure.iter_mut().zip(&points) {
            p.eigenvalues.clone_from(&q.eigenvalues);
        }
        let tracks = track(&sure, &TrackingOptions::default()).unwrap();
        let found = instabilities(&sure, &tracks, &InstabilityOptions::default()).unwrap();
        assert!(found[0].uncertain_links.is_empty(), "{found:?}");
    }

    fn synthetic(series: &[(f64, Vec<f64>)]) -> Vec<SweepPoint> {
        let n = series[0].1.len();
        (0..n)
            .map(|k| SweepPoint {
                mu: 0.1 * (k + 1) as f64,
                eigenvalues: series.iter().map(|(f, a)| c(a[k], 2.0 * PI * f)).collect(),
                shapes: (0..series.len())
                    .map(|m| {
                        (0..series.len())
                            .map(|i| c(if i == m { 1.0 } else { 0.0 }, 0.0))
                            .collect()
                    })
                    .collect(),
            })
            .collect()
    }

    #[test]
    fn unstable_intervals_onsets_and_partners() {
        // Track 0 unstable at points 1-2 and 5; track 1 (0.5 % above in frequency, negative)
        // is its partner, track 2 (5 % above, also negative) is not merged; track 3 is
        // unstable from the first point.
        let points = synthetic(&[
            (1000.0, vec![-1.0, 2.0, 3.0, -1.0, -2.0, 4.0]),
            (1005.0, vec![-1.0, -2.0, -3.0, -1.0, -2.0, -4.0]),
            (1050.0, vec![-1.0, -2.0, -3.0, -1.0, -2.0, -4.0]),
            (2000.0, vec![5.0, 6.0, 7.0, 1.0, 0.0, 0.0]),
        ]);
        let tracks = track(&points, &TrackingOptions::default()).unwrap();
        assert_eq!(tracks.len(), 4);
        let found = instabilities(&points, &tracks, &InstabilityOptions::default()).unwrap();
        assert_eq!(found.len(), 3, "{found:?}");
        let mu = |k: usize| points[k].mu;
        let close = |x: f64, y: f64| (x - y).abs() < 1e-14;

        let first = &found[0];
        assert_eq!((first.track, first.partner), (0, Some(1)));
        // Zero of the real part between -1 at point 0 and 2 at point 1: a third of the step.
        assert!(close(first.onset_mu, mu(0) + (mu(1) - mu(0)) / 3.0));
        assert!(first.onset_bracketed);
        // 2 pi f / 2 pi: a couple of roundings.
        assert!((first.frequency_hz_at_onset - 1000.0).abs() < 1e-12);
        assert_eq!((first.max_real_part, first.mu_at_max), (3.0, mu(2)));
        // From 3 at point 2 to -1 at point 3: three quarters of the step.
        let back = first.restabilisation_mu.unwrap();
        assert!(close(back, mu(2) + 0.75 * (mu(3) - mu(2))));
        // q = Re(((lambda_0 - lambda_1) / 2)^2) = ((a0 - a1) / 2)^2 - (pi (f0 - f1))^2 is
        // -(5 pi)^2 at point 0 (equal real parts) and 4 - 25 pi^2 < 0 at point 1: no sign
        // change, the frequencies never merge exactly: no coalescence estimate.
        assert_eq!(first.coalescence_mu, None);

        let second = &found[1];
        assert_eq!((second.track, second.partner), (0, Some(1)));
        assert!(close(second.onset_mu, mu(4) + (mu(5) - mu(4)) / 3.0));
        assert_eq!((second.max_real_part, second.mu_at_max), (4.0, mu(5)));
        assert_eq!(second.restabilisation_mu, None);

        let third = &found[2];
        assert_eq!((third.track, third.partner), (3, None));
        assert!(!third.onset_bracketed);
        assert_eq!(third.onset_mu, mu(0));
        assert_eq!((third.max_real_part, third.mu_at_max), (7.0, mu(2)));
        // 1 at point 3 is unstable (above 1e-6 |lambda|), 0 at point 4 is not: the crossing
        // is exactly at point 4.
        assert!(close(third.restabilisation_mu.unwrap(), mu(4)));

        // Relative to |lambda| ~ 2 pi f, a tolerance of 3.6 / (2 pi 1000 Hz) keeps only the
        // real part 4 of track 0 at 1000 Hz: its 2 and 3 fall below, and so does track 3's
        // largest, 7 at 2000 Hz (3.5 / (2 pi 1000 Hz)).
        let lenient = InstabilityOptions {
            real_part_tolerance: 3.6 / (2.0 * PI * 1000.0),
            ..InstabilityOptions::default()
        };
        let strict = instabilities(&points, &tracks, &lenient).unwrap();
        assert_eq!(strict.len(), 1);
        assert_eq!((strict[0].track, strict[0].mu_at_max), (0, mu(5)));

        let json = serde_json::to_value(&found[0]).unwrap();
        assert_eq!(json["partner"], 1);
        let json = serde_json::to_value(&tracks[0]).unwrap();
        assert_eq!(json["members"][0], 0);
    }

    #[test]
    fn bad_input_is_named() {
        let good = || synthetic(&[(100.0, vec![0.0, 0.0]), (200.0, vec![0.0, 0.0])]);
        let options = TrackingOptions::default();

        let mut points = good();
        points[1].shapes.pop();
        assert!(matches!(
            track(&points, &options),
            Err(TrackingError::ShapeCount {
                point: 1,
                eigenvalues: 2,
                shapes: 1,
                ..
            })
        ));
        let mut points = good();
        points[1].shapes[0].push(c(1.0, 0.0));
        assert!(matches!(
            track(&points, &options),
            Err(TrackingError::ShapeLength {
                point: 1,
                mode: 0,
                len: 3,
                expected: 2,
                ..
            })
        ));
        let mut points = good();
        points[0].shapes[1] = vec![c(0.0, 0.0); 2];
        assert!(matches!(
            track(&points, &options),
            Err(TrackingError::ZeroShape {
                point: 0,
                mode: 1,
                ..
            })
        ));
        let mut points = good();
        points[1].shapes[1][0] = c(f64::NAN, 0.0);
        assert!(matches!(
            track(&points, &options),
            Err(TrackingError::NotFinite {
                point: 1,
                mode: 1,
                what: "the shape",
                ..
            })
        ));
        let mut points = good();
        points[0].eigenvalues[1] = c(0.0, -1.0);
        assert!(matches!(
            track(&points, &options),
            Err(TrackingError::NegativeFrequency {
                point: 0,
                mode: 1,
                ..
            })
        ));
        let mut points = good();
        points[1].mu = points[0].mu;
        assert!(matches!(
            track(&points, &options),
            Err(TrackingError::NotMonotonic { point: 1, .. })
        ));
        // Decreasing sweeps are fine.
        let mut points = good();
        points.reverse();
        assert_eq!(track(&points, &options).unwrap().len(), 2);
        let bad = TrackingOptions {
            min_mac: 1.5,
            ..options.clone()
        };
        assert!(matches!(
            track(&good(), &bad),
            Err(TrackingError::BadOption {
                name: "min_mac",
                ..
            })
        ));

        let points = good();
        let tracks = track(&points, &options).unwrap();
        let mut short = tracks.clone();
        short[1].members.pop();
        let defaults = InstabilityOptions::default();
        assert!(matches!(
            instabilities(&points, &short, &defaults),
            Err(TrackingError::TrackLength {
                track: 1,
                len: 1,
                points: 2
            })
        ));
        let mut wrong = tracks.clone();
        wrong[0].members[1] = Some(5);
        assert!(matches!(
            instabilities(&points, &wrong, &defaults),
            Err(TrackingError::TrackMember {
                track: 0,
                point: 1,
                mode: 5,
                count: 2
            })
        ));
        let negative = InstabilityOptions {
            frequency_tolerance: -1.0,
            ..defaults
        };
        assert!(matches!(
            instabilities(&points, &tracks, &negative),
            Err(TrackingError::BadOption {
                name: "frequency_tolerance",
                ..
            })
        ));
    }
}
