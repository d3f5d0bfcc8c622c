//! The closed contact zone's normal stiffness and its moments: what holds a pad against the
//! disc along the normal (the total, `sum k`) and against rocking (the second moments about a
//! centre, `sum k (x - c)(x - c)^T`). A reduced interface that stands for the full one must
//! keep both (issue 29 found the reduced zone of the floating-caliper brake 7-19 % smaller,
//! and its pads' rocking modes 2-3 % softer).
//!
//! `k` is the slope of the normal force with the overclosure at each closed point: `k_n A`
//! for squeal's penalty law, the smoothed law's slope for CalculiX's, and for a patch law
//! ([`super::Tilt`]) `k_n a_j` at each closed quadrature point of its share, at the share's own
//! position ([`super::penalty::zone_stiffness`] sums a pair's states).

/// `sum k`, `sum k x` and `sum k x x^T` over a zone's closed points (global coordinates).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ZoneStiffness {
    /// N/m.
    pub total: f64,
    /// N.
    pub first: [f64; 3],
    /// N m.
    pub second: [[f64; 3]; 3],
}

impl ZoneStiffness {
    pub fn add(&mut self, k: f64, at: [f64; 3]) {
        self.total += k;
        for a in 0..3 {
            self.first[a] += k * at[a];
            for b in 0..3 {
                self.second[a][b] += k * at[a] * at[b];
            }
        }
    }

    /// Where the zone holds on average; `None` when nothing is closed.
    pub fn centroid(&self) -> Option<[f64; 3]> {
        (self.total > 0.0).then(|| self.first.map(|f| f / self.total))
    }

    /// The second moments about `c`: `sum k (x - c)(x - c)^T`.
    pub fn about(&self, c: [f64; 3]) -> [[f64; 3]; 3] {
        let mut m = [[0.0; 3]; 3];
        for a in 0..3 {
            for b in 0..3 {
                m[a][b] = self.second[a][b] - c[a] * self.first[b] - c[b] * self.first[a]
                    + self.total * c[a] * c[b];
            }
        }
        m
    }
}

/// A zone against a reference zone of the same pair.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ZoneRatios {
    /// `sum k` over the reference's.
    pub total: f64,
    /// How far the centroid moved, m.
    pub centroid_offset: f64,
    /// The second moments about the reference's centroid, along the reference's two principal
    /// axes of largest moment (in the contact plane: the third is the normal, where a flat
    /// zone has none), each over the reference's: the stiffness against rocking about the
    /// axis of least and of most resistance, in that order. `None` about an axis the
    /// reference's zone has no extent across (its closed points on one line, or one point).
    pub rocking: [Option<f64>; 2],
}

impl ZoneRatios {
    /// The rocking ratios as a person reads them: "0.949, 0.843", "-" where there is none.
    pub fn rocking_text(&self) -> String {
        let show = |r: Option<f64>| r.map_or("-".to_string(), |r| format!("{r:.3}"));
        format!("{}, {}", show(self.rocking[0]), show(self.rocking[1]))
    }
}

impl ZoneStiffness {
    /// This zone against `reference`; `None` when either has nothing closed.
    pub fn against(&self, reference: &ZoneStiffness) -> Option<ZoneRatios> {
        let (c_ref, c) = (reference.centroid()?, self.centroid()?);
        let (s_ref, s) = (reference.about(c_ref), self.about(c_ref));
        let evd = faer::Mat::<f64>::from_fn(3, 3, |i, j| s_ref[i][j])
            .self_adjoint_eigen(faer::Side::Lower)
            .ok()?;
        let (values, vectors) = (evd.S().column_vector(), evd.U());
        let mut order = [0, 1, 2];
        order.sort_by(|&i, &j| values[j].total_cmp(&values[i]));
        let along = |m: &[[f64; 3]; 3], k: usize| {
            let e = [0, 1, 2].map(|i| vectors[(i, k)]);
            (0..3)
                .map(|a| (0..3).map(|b| e[a] * m[a][b] * e[b]).sum::<f64>())
                .sum::<f64>()
        };
        // The in-plane axes, least resistance first. A zone on one line has round-off about
        // the other axis (1e-16 of the largest per term summed); a real zone of aspect ratio
        // a:b has (b/a)^2 there, 1e-2 at 10:1: 1e-9 tells the two apart by far.
        let largest = along(&s_ref, order[0]);
        let rocking = [order[1], order[0]].map(|k| {
            let m = along(&s_ref, k);
            (m > 1e-9 * largest && largest > 0.0).then(|| along(&s, k) / m)
        });
        let d = [0, 1, 2].map(|a| c[a] - c_ref[a]);
        Some(ZoneRatios {
            total: self.total / reference.total,
            centroid_offset: (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt(),
            rocking,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Moments about any centre follow from the sums (the parallel-axis theorem), and the
    /// centroid is where the first moment about it vanishes.
    #[test]
    fn moments_about_a_centre_are_the_parallel_axis_theorem() {
        let points = [
            (2.0, [0.1, 0.0, 0.3]),
            (1.0, [-0.2, 0.5, 0.3]),
            (3.0, [0.4, -0.1, 0.3]),
        ];
        let mut z = ZoneStiffness::default();
        for (k, x) in points {
            z.add(k, x);
        }
        let c = z.centroid().unwrap();
        let first: f64 = points.iter().map(|(k, x)| k * (x[0] - c[0])).sum();
        assert!(first.abs() < 1e-15);
        let about = [0.3, -0.7, 1.1];
        let m = z.about(about);
        for a in 0..3 {
            for b in 0..3 {
                let direct: f64 = points
                    .iter()
                    .map(|(k, x)| k * (x[a] - about[a]) * (x[b] - about[b]))
                    .sum();
                assert!((m[a][b] - direct).abs() < 1e-14, "{a}{b}");
            }
        }
        assert_eq!(ZoneStiffness::default().centroid(), None);
    }

    /// A rectangle of uniform stiffness against a part of it, on a midpoint grid whose sums
    /// have a closed form: over m cells of width h = L/m centred on 0, `sum h x^2 =
    /// L^3 (1 - 1/m^2) / 12`.
    #[test]
    fn parts_of_a_rectangle_have_the_closed_form_ratios() {
        // 0.2 x 0.1 m in the plane z = 0.05.
        let (lx, ly, n) = (0.2, 0.1, 200);
        let cell = |i: usize, l: f64| -l / 2.0 + (i as f64 + 0.5) * l / n as f64;
        let zone = |keep: &dyn Fn(f64) -> bool| {
            let mut z = ZoneStiffness::default();
            for i in 0..n {
                for j in 0..n {
                    let (x, y) = (cell(i, lx), cell(j, ly));
                    if keep(x) {
                        z.add(1.0 / (n * n) as f64, [x, y, 0.05]);
                    }
                }
            }
            z
        };
        let whole = zone(&|_| true);
        // The half x > 0: half of everything about the whole's centre, moved by lx / 4.
        let r = zone(&|x| x > 0.0).against(&whole).unwrap();
        assert!((r.total - 0.5).abs() < 1e-12);
        assert!((r.centroid_offset - lx / 4.0).abs() < 1e-12);
        assert!(
            r.rocking.iter().all(|x| (x.unwrap() - 0.5).abs() < 1e-12),
            "{r:?}"
        );
        // The middle strip |x| < lx / 4 (n / 2 cells): the same centroid, half the moment
        // about the long axis (y^2, least resistance), and about the short one
        // (lx/2)^3 (1 - 4/n^2) / (lx^3 (1 - 1/n^2)) of the whole's x^2.
        let r = zone(&|x| x.abs() < lx / 4.0).against(&whole).unwrap();
        let n2 = (n * n) as f64;
        let strip = (1.0 - 4.0 / n2) / (8.0 * (1.0 - 1.0 / n2));
        // (Round-off of 40,000 terms of 0.1 m.)
        assert!(r.centroid_offset < 1e-13, "{r:?}");
        assert!((r.rocking[0].unwrap() - 0.5).abs() < 1e-12, "{r:?}");
        assert!(
            (r.rocking[1].unwrap() - strip).abs() < 1e-12,
            "{r:?} against {strip}"
        );
        // A zone against itself.
        let same = whole.against(&whole).unwrap();
        assert!((same.total - 1.0).abs() < 1e-15 && same.centroid_offset < 1e-15);
        assert!(same
            .rocking
            .iter()
            .all(|x| (x.unwrap() - 1.0).abs() < 1e-12));
        // A zone on one line has one axis to rock about, a single point none.
        let mut line = ZoneStiffness::default();
        for x in [-0.1, 0.0, 0.1] {
            line.add(1.0, [x, 0.02, 0.05]);
        }
        let r = line.against(&line).unwrap();
        assert_eq!(r.rocking[0], None);
        assert!((r.rocking[1].unwrap() - 1.0).abs() < 1e-12);
        let mut point = ZoneStiffness::default();
        point.add(2.0, [0.1, 0.02, 0.05]);
        assert_eq!(point.against(&point).unwrap().rocking, [None, None]);
        assert!(whole.against(&ZoneStiffness::default()).is_none());
    }
}
