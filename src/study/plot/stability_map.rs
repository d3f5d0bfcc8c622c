//! The stability map: every mode of every friction coefficient of a sweep as frequency (x)
//! against real part (y), coloured by mu (colour bar), y = 0 emphasised, the modes the CEA
//! flagged unstable drawn larger, outlined in black, on top.

use super::style::{self, Entry, Look, Marker, MUTED, UNSTABLE_OUTLINE};
use super::{MapPoint, PlotError};

const WIDTH: u32 = 900;
const HEIGHT: u32 = 560;
/// Legend and colour bar, right of the plot.
const SIDE: u32 = 190;

const STABLE: Look = Look {
    marker: Marker::Circle,
    size: 3,
    fill: MUTED,
    outline: None,
};
const UNSTABLE: Look = Look {
    marker: Marker::Circle,
    size: 5,
    fill: MUTED,
    outline: Some(UNSTABLE_OUTLINE),
};

/// The map's SVG. Which modes are unstable is the caller's decision ([`MapPoint::unstable`]).
pub fn stability_map(points: &[MapPoint], title: &str) -> Result<String, PlotError> {
    let drawable: Vec<&MapPoint> = points
        .iter()
        .filter(|p| style::plottable(p.frequency_hz) && style::plottable(p.real_part))
        .collect();
    style::render(WIDTH, HEIGHT, title, |body| {
        if drawable.is_empty() {
            return style::no_data(
                body,
                "no data: no mode with a finite frequency and real part",
            );
        }
        let (main, side) = body.split_horizontally(WIDTH - SIDE);
        let x = style::axis_range(
            style::extent(drawable.iter().map(|p| p.frequency_hz)),
            false,
        );
        let y = style::axis_range(style::extent(drawable.iter().map(|p| p.real_part)), true);
        let plot = style::panel(
            &main,
            &style::Axes {
                caption: "",
                x_label: style::FREQUENCY_LABEL,
                y_label: style::REAL_PART_LABEL,
                x,
                y,
                x_ticks: true,
                zero_line: true,
            },
        )?;
        let mu = style::extent(drawable.iter().map(|p| p.mu)).unwrap_or((0.0, 1.0));
        // Stable modes first, so the unstable ones are drawn over them.
        for unstable in [false, true] {
            let look = if unstable { UNSTABLE } else { STABLE };
            for p in drawable.iter().filter(|p| p.unstable == unstable) {
                let fill = style::viridis(p.mu, mu);
                style::draw_marker(&plot, (p.frequency_hz, p.real_part), Look { fill, ..look })?;
            }
        }
        let (legend, bar) = side.split_vertically(70);
        style::draw_legend(
            &legend.margin(12, 0, 4, 0),
            &[
                Entry {
                    name: "stable mode".into(),
                    line: None,
                    look: Some(STABLE),
                },
                Entry {
                    name: "unstable mode".into(),
                    line: None,
                    look: Some(UNSTABLE),
                },
            ],
        )?;
        style::draw_colour_bar(&bar.margin(0, 0, 50, 40), style::FRICTION_LABEL, mu)
    })
}

#[cfg(test)]
mod tests {
    use super::super::svg_check::{check_xml, circles, unstable_markers, Lcg};
    use super::*;

    fn sweep_points(seed: u64, count: usize) -> Vec<MapPoint> {
        let mut rng = Lcg(seed);
        (0..count)
            .map(|i| {
                let mu = 0.1 * (1 + i % 9) as f64;
                let f = 500.0 + 6000.0 * rng.next();
                let a = 400.0 * (rng.next() - 0.8);
                let (mu, f, a) = match i % 23 {
                    5 => (mu, f64::NAN, a),
                    11 => (mu, f, f64::INFINITY),
                    17 => (f64::NAN, f, a), // no mu: still drawn, in grey
                    19 => (mu, f, 1e301),   // beyond the plot limit
                    _ => (mu, f, a),
                };
                // The classification is the caller's, not the sign: here real parts above
                // 10 only, so a plot that decided by itself (a > 0) would count more.
                MapPoint {
                    mu,
                    frequency_hz: f,
                    real_part: a,
                    unstable: a > 10.0,
                }
            })
            .collect()
    }

    #[test]
    fn one_marker_per_finite_point_and_the_flagged_ones_outlined() {
        let points = sweep_points(3, 400);
        let svg = stability_map(&points, "Stability map <disc & pads>").unwrap();
        check_xml(&svg).unwrap();
        let drawable: Vec<_> = points
            .iter()
            .filter(|p| style::plottable(p.frequency_hz) && style::plottable(p.real_part))
            .collect();
        // i % 23 == 5, 11, 19 are skipped: 18, 17 and 17 of i < 400.
        assert_eq!(drawable.len(), 400 - 18 - 17 - 17);
        let flagged = drawable.iter().filter(|p| p.unstable).count();
        let positive = drawable.iter().filter(|p| p.real_part > 0.0).count();
        assert!(flagged > 20 && positive > flagged, "{flagged} {positive}");
        // Filled markers: one per point, two in the legend.
        let filled = circles(&svg)
            .filter(|c| !c.contains("fill=\"none\""))
            .count();
        assert_eq!(filled, drawable.len() + 2);
        assert_eq!(unstable_markers(&svg), flagged);
        assert!(svg.contains("Stability map &lt;disc &amp; pads&gt;"));
        for text in [
            "Frequency (Hz)",
            "Real part (1/s)",
            "Friction coefficient μ",
        ] {
            assert!(svg.contains(text), "{text}");
        }
        assert!(svg.contains("unstable mode"));
    }

    /// Nothing is unstable: no outlined marker but the legend's.
    #[test]
    fn no_flag_no_outline() {
        let mut points = sweep_points(4, 100);
        for p in &mut points {
            p.unstable = false;
        }
        let svg = stability_map(&points, "map").unwrap();
        check_xml(&svg).unwrap();
        assert_eq!(unstable_markers(&svg), 0);
    }

    /// Markers sit where their data says: x grows with frequency, y falls with real part
    /// (SVG y points down), one affine map each, to the pixel rounding.
    #[test]
    fn coordinates_are_affine_and_monotone() {
        let points: Vec<MapPoint> = sweep_points(11, 300)
            .into_iter()
            .filter(|p| style::plottable(p.frequency_hz) && style::plottable(p.real_part))
            .map(|p| MapPoint {
                unstable: false,
                ..p
            })
            .collect();
        let svg = stability_map(&points, "map").unwrap();
        let centres: Vec<(f64, f64)> = circles(&svg)
            .map(|c| (attribute(c, "cx"), attribute(c, "cy")))
            .take(points.len())
            .collect();
        assert_eq!(centres.len(), points.len());
        for axis in 0..2 {
            let data = |k: usize| {
                if axis == 0 {
                    points[k].frequency_hz
                } else {
                    points[k].real_part
                }
            };
            let pixel = |k: usize| {
                if axis == 0 {
                    centres[k].0
                } else {
                    centres[k].1
                }
            };
            let order = |a: &usize, b: &usize| data(*a).total_cmp(&data(*b));
            let lo = (0..points.len()).min_by(order).unwrap();
            let hi = (0..points.len()).max_by(order).unwrap();
            let slope = (pixel(hi) - pixel(lo)) / (data(hi) - data(lo));
            assert!(if axis == 0 { slope > 0.0 } else { slope < 0.0 });
            for k in 0..points.len() {
                let predicted = pixel(lo) + slope * (data(k) - data(lo));
                assert!(
                    (pixel(k) - predicted).abs() <= 2.0,
                    "axis {axis}, point {k}"
                );
            }
        }
    }

    fn attribute(tag: &str, name: &str) -> f64 {
        let key = format!(" {name}=\"");
        let start = tag.find(&key).unwrap() + key.len();
        let len = tag[start..].find('"').unwrap();
        tag[start..start + len].parse().unwrap()
    }

    #[test]
    fn degenerate_inputs_give_valid_svg() {
        let nan = f64::NAN;
        let one = |mu, f, a, unstable| MapPoint {
            mu,
            frequency_hz: f,
            real_part: a,
            unstable,
        };
        for (points, markers, outlined) in [
            (vec![], 0, 0),
            (vec![one(0.5, 2500.0, 3.0, true)], 1, 1),
            (vec![one(nan, nan, nan, true)], 0, 0),
            (vec![one(nan, 1000.0, 0.0, false); 3], 3, 0),
            (
                vec![
                    one(0.1, 1e300, -1e300, true),
                    one(0.2, -1e300, 1e300, false),
                ],
                2,
                1,
            ),
        ] {
            let svg = stability_map(&points, "a < b \u{1}").unwrap();
            check_xml(&svg).unwrap_or_else(|e| panic!("{e}\n{svg}"));
            assert!(svg.contains("a &lt; b"));
            if markers == 0 {
                assert!(svg.contains("no data"), "{points:?}");
            } else {
                let filled = circles(&svg)
                    .filter(|c| !c.contains("fill=\"none\""))
                    .count();
                assert_eq!(filled, markers + 2, "{points:?}");
                assert_eq!(unstable_markers(&svg), outlined, "{points:?}");
            }
        }
    }
}
