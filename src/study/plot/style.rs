//! What the figures share: colours, markers, axis ranges and tick labels, one panel's axes,
//! lines broken at missing points, the legend, the colour bar, and the "no data" note.

use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::PlotError;

/// The whole figure, or a part of it, in pixels.
pub type Area<'a> = DrawingArea<SVGBackend<'a>, Shift>;
/// A panel's plot area, in data coordinates.
pub type Plot<'a> = DrawingArea<SVGBackend<'a>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;
pub type Drawn = Result<(), PlotError>;

pub const FRICTION_LABEL: &str = "Friction coefficient μ";
pub const FREQUENCY_LABEL: &str = "Frequency (Hz)";
pub const REAL_PART_LABEL: &str = "Real part (1/s)";

pub const FONT: &str = "sans-serif";
pub const TITLE_SIZE: f64 = 22.0;
pub const CAPTION_SIZE: f64 = 18.0;
pub const LABEL_SIZE: f64 = 16.0;
pub const TICK_SIZE: f64 = 14.0;

/// The Okabe-Ito colour-blind-safe palette (Okabe & Ito 2008), without its yellow, whose
/// contrast against white (1.2:1) is too low for thin lines.
pub const PALETTE: [RGBColor; 7] = [
    RGBColor(0x00, 0x72, 0xB2), // blue
    RGBColor(0xD5, 0x5E, 0x00), // vermillion
    RGBColor(0x00, 0x9E, 0x73), // bluish green
    RGBColor(0xCC, 0x79, 0xA7), // reddish purple
    RGBColor(0xE6, 0x9F, 0x00), // orange
    RGBColor(0x56, 0xB4, 0xE9), // sky blue
    RGBColor(0x00, 0x00, 0x00), // black
];
/// Series drawn as background (stable modes): light enough to recede, dark enough (2.5:1
/// on white) to be seen.
pub const MUTED: RGBColor = RGBColor(0x9A, 0x9A, 0x9A);
/// Grid lines.
const GRID: RGBColor = RGBColor(0xE4, 0xE4, 0xE4);
/// The y = 0 line of a real-part axis: the stability boundary.
const ZERO_LINE: RGBColor = RGBColor(0x44, 0x44, 0x44);
/// The outline that marks an unstable mode (drawn nowhere else, so it can be counted).
pub const UNSTABLE_OUTLINE: RGBColor = RGBColor(0x00, 0x00, 0x00);

/// Marker shapes, cycled with the colours (5 shapes, 7 colours: 35 distinct pairs), so
/// series stay apart in grey print and for readers who confuse colours.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Marker {
    Circle,
    Square,
    TriangleUp,
    Diamond,
    TriangleDown,
}

pub const MARKERS: [Marker; 5] = [
    Marker::Circle,
    Marker::Square,
    Marker::TriangleUp,
    Marker::Diamond,
    Marker::TriangleDown,
];

/// How a series' points look: a filled marker, optionally outlined.
#[derive(Debug, Clone, Copy)]
pub struct Look {
    pub marker: Marker,
    /// Half the marker's width, pixels.
    pub size: i32,
    pub fill: RGBColor,
    pub outline: Option<RGBColor>,
}

/// Values beyond this are not plottable: the span of two still fits in an f64.
const PLOT_LIMIT: f64 = 1e300;

pub fn plottable(v: f64) -> bool {
    v.is_finite() && v.abs() <= PLOT_LIMIT
}

pub fn point_plottable(p: &(f64, f64)) -> bool {
    plottable(p.0) && plottable(p.1)
}

/// The smallest and largest plottable value, if any.
pub fn extent(values: impl IntoIterator<Item = f64>) -> Option<(f64, f64)> {
    values
        .into_iter()
        .filter(|v| plottable(*v))
        .fold(None, |acc, v| match acc {
            None => Some((v, v)),
            Some((lo, hi)) => Some((lo.min(v), hi.max(v))),
        })
}

pub fn union(a: Option<(f64, f64)>, b: Option<(f64, f64)>) -> Option<(f64, f64)> {
    match (a, b) {
        (Some(a), Some(b)) => Some((a.0.min(b.0), a.1.max(b.1))),
        (a, None) => a,
        (None, b) => b,
    }
}

/// An axis range around the data: 4 % padding each side, zero kept in view if asked, a
/// single value widened by 10 % of itself (or to [-1, 1] at 0), no data: [0, 1].
pub fn axis_range(data: Option<(f64, f64)>, with_zero: bool) -> (f64, f64) {
    let Some((mut lo, mut hi)) = data else {
        return (0.0, 1.0);
    };
    if with_zero {
        lo = lo.min(0.0);
        hi = hi.max(0.0);
    }
    let span = hi - lo;
    if span <= 1e-9 * lo.abs().max(hi.abs()) || span == 0.0 {
        let half = if lo == 0.0 && hi == 0.0 {
            1.0
        } else {
            0.1 * lo.abs().max(hi.abs())
        };
        let mid = 0.5 * (lo + hi);
        return (mid - half, mid + half);
    }
    (lo - 0.04 * span, hi + 0.04 * span)
}

/// Tick labels for an axis over `range`: as many decimals as the tick step (at least a
/// tenth of the span) needs, trailing zeros dropped, a true minus; scientific notation for
/// magnitudes from 1e6 or below 1e-3.
pub fn tick_label(v: f64, range: (f64, f64)) -> String {
    let span = (range.1 - range.0).abs();
    let magnitude = range.0.abs().max(range.1.abs());
    if v.abs() < 1e-9 * span.max(f64::MIN_POSITIVE) {
        return "0".into();
    }
    let text = if !(1e-3..1e6).contains(&magnitude) {
        let digits = (magnitude.log10() - (span / 10.0).log10())
            .ceil()
            .clamp(0.0, 8.0) as usize;
        let s = format!("{v:.digits$e}");
        let (mantissa, exponent) = s.split_once('e').unwrap_or((&s, "0"));
        format!("{}e{exponent}", trim_zeros(mantissa))
    } else {
        let decimals = (-(span / 10.0).log10().floor()).clamp(0.0, 12.0) as usize;
        trim_zeros(&format!("{v:.decimals$}")).to_string()
    };
    match text.strip_prefix('-') {
        Some(magnitude) => format!("\u{2212}{magnitude}"),
        None => text,
    }
}

fn trim_zeros(s: &str) -> &str {
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.')
    } else {
        s
    }
}

/// Text as XML 1.0 allows it: control characters become spaces (the SVG backend escapes
/// the markup characters).
pub fn clean(text: &str) -> String {
    text.chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .collect()
}

/// At most `chars` characters, an ellipsis marking the cut.
pub fn truncate(text: &str, chars: usize) -> String {
    if text.chars().count() <= chars {
        text.to_string()
    } else {
        let mut s: String = text.chars().take(chars.saturating_sub(1)).collect();
        s.push('…');
        s
    }
}

pub fn font(size: f64) -> TextStyle<'static> {
    (FONT, size).into_font().color(&BLACK)
}

/// The SVG document of a `width` x `height` figure: white background, the title on top,
/// `draw` filling the rest.
pub fn render(
    width: u32,
    height: u32,
    title: &str,
    draw: impl FnOnce(&Area) -> Drawn,
) -> Result<String, PlotError> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (width, height)).into_drawing_area();
        root.fill(&WHITE)?;
        let title = clean(title);
        let body = if title.trim().is_empty() {
            root.margin(10, 0, 0, 0)
        } else {
            let chars = (f64::from(width) / (0.55 * TITLE_SIZE)) as usize;
            root.titled(&truncate(&title, chars), font(TITLE_SIZE))?
        };
        draw(&body)?;
        root.present()?;
    }
    Ok(svg)
}

/// "no data" in the middle of `area`.
pub fn no_data(area: &Area, note: &str) -> Drawn {
    let (w, h) = area.dim_in_pixel();
    let style = font(LABEL_SIZE)
        .color(&RGBColor(0x66, 0x66, 0x66))
        .pos(Pos::new(HPos::Center, VPos::Center));
    area.draw(&Text::new(clean(note), (w as i32 / 2, h as i32 / 2), style))?;
    Ok(())
}

/// One panel's axes.
pub struct Axes<'t> {
    /// Above the plot area ("" for none).
    pub caption: &'t str,
    pub x_label: &'t str,
    pub y_label: &'t str,
    pub x: (f64, f64),
    pub y: (f64, f64),
    /// Tick labels and label under the x axis (off for all but the bottom of panels that
    /// share it).
    pub x_ticks: bool,
    /// Emphasise y = 0 (the stability boundary of a real-part axis).
    pub zero_line: bool,
}

/// Draws a panel's frame, grid, ticks and labels into `area`, and returns its plot area.
pub fn panel<'a>(area: &Area<'a>, axes: &Axes) -> Result<Plot<'a>, PlotError> {
    let mut builder = ChartBuilder::on(area);
    builder
        .margin_top(8)
        .margin_right(16)
        .x_label_area_size(if axes.x_ticks { 48 } else { 8 })
        .y_label_area_size(78);
    let caption = clean(axes.caption);
    if !caption.trim().is_empty() {
        builder.caption(caption, font(CAPTION_SIZE));
    }
    let mut chart = builder.build_cartesian_2d(axes.x.0..axes.x.1, axes.y.0..axes.y.1)?;
    let (x, y) = (axes.x, axes.y);
    let x_format = move |v: &f64| tick_label(*v, x);
    let y_format = move |v: &f64| tick_label(*v, y);
    let hidden = |_: &f64| String::new();
    let mut mesh = chart.configure_mesh();
    mesh.bold_line_style(GRID)
        .light_line_style(TRANSPARENT)
        .axis_style(BLACK)
        .x_labels(8)
        .y_labels(7)
        .label_style(font(TICK_SIZE))
        .axis_desc_style(font(LABEL_SIZE))
        .y_desc(clean(axes.y_label))
        .y_label_formatter(&y_format);
    if axes.x_ticks {
        mesh.x_desc(clean(axes.x_label))
            .x_label_formatter(&x_format);
    } else {
        mesh.x_label_formatter(&hidden);
    }
    mesh.draw()?;
    let plot = chart.plotting_area().clone();
    if axes.zero_line && y.0.min(y.1) < 0.0 && y.0.max(y.1) > 0.0 {
        plot.draw(&PathElement::new(
            vec![(x.0, 0.0), (x.1, 0.0)],
            ZERO_LINE.stroke_width(1),
        ))?;
    }
    Ok(plot)
}

/// A line through the points in the order given, broken where a point is not plottable (a
/// failed solve shows as a gap, not as a line to nowhere).
pub fn draw_line(plot: &Plot, points: &[(f64, f64)], color: RGBColor, width: u32) -> Drawn {
    for piece in points.split(|p| !point_plottable(p)) {
        if piece.len() >= 2 {
            plot.draw(&PathElement::new(piece.to_vec(), color.stroke_width(width)))?;
        }
    }
    Ok(())
}

/// A marker at each plottable point.
pub fn draw_markers(plot: &Plot, points: &[(f64, f64)], look: Look) -> Drawn {
    for p in points.iter().filter(|p| point_plottable(p)) {
        draw_marker(plot, *p, look)?;
    }
    Ok(())
}

/// One marker at `at` (data coordinates of a plot, or pixels of an area).
pub fn draw_marker<CT: CoordTranslate>(
    area: &DrawingArea<SVGBackend, CT>,
    at: CT::From,
    look: Look,
) -> Drawn
where
    CT::From: Clone,
{
    let s = look.size;
    let fill = look.fill.filled();
    let shape: Vec<(i32, i32)> = match look.marker {
        Marker::Circle => {
            area.draw(&(EmptyElement::at(at.clone()) + Circle::new((0, 0), s, fill)))?;
            if let Some(outline) = look.outline {
                let stroke = outline.stroke_width(2);
                area.draw(&(EmptyElement::at(at) + Circle::new((0, 0), s, stroke)))?;
            }
            return Ok(());
        }
        Marker::Square => vec![(-s, -s), (s, -s), (s, s), (-s, s)],
        Marker::TriangleUp => vec![(0, -s - 1), (s + 1, s), (-s - 1, s)],
        Marker::TriangleDown => vec![(0, s + 1), (s + 1, -s), (-s - 1, -s)],
        Marker::Diamond => vec![(0, -s - 1), (s + 1, 0), (0, s + 1), (-s - 1, 0)],
    };
    area.draw(&(EmptyElement::at(at.clone()) + Polygon::new(shape.clone(), fill)))?;
    if let Some(outline) = look.outline {
        let mut closed = shape.clone();
        closed.push(shape[0]);
        let stroke = outline.stroke_width(1);
        area.draw(&(EmptyElement::at(at) + PathElement::new(closed, stroke)))?;
    }
    Ok(())
}

/// A legend entry: a line swatch, a marker, or both.
#[derive(Debug, Clone)]
pub struct Entry {
    pub name: String,
    pub line: Option<(RGBColor, u32)>,
    pub look: Option<Look>,
}

/// A legend row's height in pixels.
pub const LEGEND_ROW: i32 = 22;

/// The entries top down from the area's top left; those that do not fit are counted in a
/// last row ("… and 12 more"), names too long for the width are shortened.
pub fn draw_legend(area: &Area, entries: &[Entry]) -> Drawn {
    let (width, height) = area.dim_in_pixel();
    let rows = (height as i32 / LEGEND_ROW).max(1) as usize;
    let shown = if entries.len() <= rows {
        entries.len()
    } else {
        rows - 1
    };
    let chars = ((f64::from(width) - 40.0) / (0.55 * TICK_SIZE)).max(4.0) as usize;
    let text = font(TICK_SIZE).pos(Pos::new(HPos::Left, VPos::Center));
    for (k, e) in entries[..shown].iter().enumerate() {
        let y = LEGEND_ROW * k as i32 + LEGEND_ROW / 2;
        if let Some((color, w)) = e.line {
            area.draw(&PathElement::new(
                vec![(4, y), (30, y)],
                color.stroke_width(w),
            ))?;
        }
        if let Some(look) = e.look {
            draw_marker(area, (17, y), look)?;
        }
        area.draw(&Text::new(
            truncate(&clean(&e.name), chars),
            (38, y),
            text.clone(),
        ))?;
    }
    if shown < entries.len() {
        let y = LEGEND_ROW * shown as i32 + LEGEND_ROW / 2;
        let more = format!("… and {} more", entries.len() - shown);
        let grey = text.color(&RGBColor(0x66, 0x66, 0x66));
        area.draw(&Text::new(more, (4, y), grey))?;
    }
    Ok(())
}

/// The viridis colour of `v` on the scale `range`; grey if `v` is not a number.
pub fn viridis(v: f64, range: (f64, f64)) -> RGBColor {
    if !v.is_finite() {
        return RGBColor(0xBD, 0xBD, 0xBD);
    }
    let (lo, hi) = range;
    let t = if hi > lo {
        ((v - lo) / (hi - lo)).clamp(0.0, 1.0)
    } else {
        0.5
    };
    ViridisRGB.get_color_normalized(t, 0.0, 1.0)
}

/// A vertical viridis colour bar over `range`, labelled, ticks on its right.
pub fn draw_colour_bar(area: &Area, label: &str, range: (f64, f64)) -> Drawn {
    let (lo, hi) = axis_range(Some(range), false);
    let mut chart = ChartBuilder::on(area)
        .margin_top(8)
        .margin_left(8)
        .x_label_area_size(48)
        .right_y_label_area_size(70)
        .build_cartesian_2d(0.0..1.0, lo..hi)?;
    let format = move |v: &f64| tick_label(*v, (lo, hi));
    chart
        .configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .y_labels(6)
        .label_style(font(TICK_SIZE))
        .axis_desc_style(font(LABEL_SIZE))
        .y_desc(clean(label))
        .y_label_formatter(&format)
        .draw()?;
    const STEPS: usize = 64;
    let plot = chart.plotting_area();
    for k in 0..STEPS {
        let a = lo + (hi - lo) * k as f64 / STEPS as f64;
        let b = lo + (hi - lo) * (k + 1) as f64 / STEPS as f64;
        let colour = viridis(0.5 * (a + b), range);
        plot.draw(&Rectangle::new([(0.0, a), (1.0, b)], colour.filled()))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tick_labels_without_round_off_noise() {
        let labels = |range: (f64, f64), values: &[f64]| -> Vec<String> {
            values.iter().map(|v| tick_label(*v, range)).collect()
        };
        // 0.1 + 0.2 = 0.30000000000000004 must not show.
        assert_eq!(
            labels((0.1, 0.9), &[0.1 + 0.2, 0.5, 0.0]),
            ["0.3", "0.5", "0"]
        );
        assert_eq!(labels((0.30, 0.35), &[0.325, 0.35]), ["0.325", "0.35"]);
        assert_eq!(labels((-37.2, 12.5), &[-30.0, 10.0]), ["−30", "10"]);
        assert_eq!(labels((0.0, 20_000.0), &[15_000.0]), ["15000"]);
        assert_eq!(labels((0.0, 3e6), &[1.5e6, 3e6]), ["1.5e6", "3e6"]);
        assert_eq!(labels((-4e-4, 4e-4), &[-2e-4, 0.0]), ["−2e-4", "0"]);
    }

    #[test]
    fn axis_ranges_hold_the_data_and_are_never_empty() {
        assert_eq!(axis_range(None, true), (0.0, 1.0));
        assert_eq!(axis_range(Some((0.0, 0.0)), false), (-1.0, 1.0));
        let (lo, hi) = axis_range(Some((2500.0, 2500.0)), false);
        assert!((lo - 2250.0).abs() < 1e-9 && (hi - 2750.0).abs() < 1e-9);
        let (lo, hi) = axis_range(Some((-1e300, 1e300)), true);
        assert!(lo.is_finite() && hi.is_finite() && lo < -1e300 && hi > 1e300);
        let (lo, hi) = axis_range(Some((5.0, 10.0)), true);
        assert!(lo < 0.0 && hi > 10.0);
        assert_eq!(
            extent([f64::NAN, 3.0, f64::INFINITY, -2.0, 1e301]),
            Some((-2.0, 3.0))
        );
        assert_eq!(clean("a\u{1}b\tc"), "a b c");
        assert_eq!(truncate("abcdef", 4), "abc…");
    }
}
