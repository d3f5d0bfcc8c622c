//! Why each instability squeals, as bars: one row per instability, its bodies' shares of
//! kinetic energy on the left and its contact pairs' shares of the growth rate on the right
//! (at its largest real part; [`crate::fem::body_energy`], [`crate::analysis::growth`]). A
//! pair that takes energy out of the mode has a bar to the left of zero.

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::style::{self, Area, Drawn};
use super::PlotError;

const WIDTH: u32 = 1100;
const COLUMN: i32 = 550;
/// Names, left of the bars.
const NAMES: i32 = 240;
/// Room for the value right of the longest bar.
const VALUES: i32 = 70;
const ROW: i32 = 22;
const CAPTION: i32 = 30;
const GAP: i32 = 16;
/// The columns' headings.
const HEADER: i32 = 26;

/// One instability's bars: its caption and the (name, share) of its bodies and pairs.
#[derive(Clone, Debug, PartialEq)]
pub struct ContributionRow {
    pub caption: String,
    pub bodies: Vec<(String, f64)>,
    pub pairs: Vec<(String, f64)>,
}

fn rows_of(row: &ContributionRow) -> i32 {
    row.bodies.len().max(row.pairs.len()).max(1) as i32
}

/// The figure's SVG.
pub fn contributions(rows: &[ContributionRow], title: &str) -> Result<String, PlotError> {
    let height: i32 = 50
        + HEADER
        + rows
            .iter()
            .map(|r| CAPTION + ROW * rows_of(r) + GAP)
            .sum::<i32>()
            .max(60);
    style::render(WIDTH, height as u32, title, |body| {
        if rows.is_empty() {
            return style::no_data(body, "no data: no unstable mode with its shares");
        }
        let heading = style::font(style::LABEL_SIZE).pos(Pos::new(HPos::Left, VPos::Top));
        for (left, text) in [
            (0, "Kinetic energy by body (x^H M_b x / x^H M x)"),
            (COLUMN, "Growth rate by contact pair (a_p / a)"),
        ] {
            body.draw(&Text::new(text, (left + 8, 0), heading.clone()))?;
        }
        let mut top = HEADER;
        for row in rows {
            let caption = style::font(style::CAPTION_SIZE).pos(Pos::new(HPos::Left, VPos::Top));
            body.draw(&Text::new(style::clean(&row.caption), (8, top), caption))?;
            let y = top + CAPTION;
            bars(body, 0, y, "kinetic energy", &row.bodies, style::PALETTE[0])?;
            bars(
                body,
                COLUMN,
                y,
                "growth rate",
                &row.pairs,
                style::PALETTE[1],
            )?;
            top = y + ROW * rows_of(row) + GAP;
        }
        Ok(())
    })
}

/// One column of bars from pixel (`left`, `top`): a share s draws from 0 to s on a scale
/// that holds 0, 100 % and every share.
fn bars(
    area: &Area,
    left: i32,
    top: i32,
    what: &str,
    shares: &[(String, f64)],
    colour: RGBColor,
) -> Drawn {
    let finite: Vec<f64> = shares
        .iter()
        .map(|s| s.1)
        .filter(|v| v.is_finite())
        .collect();
    let lo = finite.iter().copied().fold(0.0f64, f64::min);
    let hi = finite.iter().copied().fold(1.0f64, f64::max);
    let (x0, x1) = (left + NAMES, left + COLUMN - VALUES);
    let at = |v: f64| x0 + (f64::from(x1 - x0) * (v - lo) / (hi - lo)).round() as i32;
    let zero = at(0.0);
    let grey = RGBColor(0x66, 0x66, 0x66);
    let names = style::font(style::TICK_SIZE).pos(Pos::new(HPos::Right, VPos::Center));
    let values = style::font(style::TICK_SIZE).pos(Pos::new(HPos::Left, VPos::Center));
    let chars = (f64::from(NAMES - 12) / (0.55 * style::TICK_SIZE)) as usize;
    if shares.is_empty() {
        let note = style::font(style::TICK_SIZE)
            .color(&grey)
            .pos(Pos::new(HPos::Left, VPos::Center));
        area.draw(&Text::new(
            format!("no {what} shares"),
            (x0, top + ROW / 2),
            note,
        ))?;
        return Ok(());
    }
    for (k, (name, share)) in shares.iter().enumerate() {
        let y = top + ROW * k as i32;
        let label = style::truncate(&style::clean(name), chars);
        area.draw(&Text::new(label, (x0 - 8, y + ROW / 2), names.clone()))?;
        if !share.is_finite() {
            continue;
        }
        let end = at(*share);
        let fill = if *share < 0.0 { grey } else { colour };
        // A share that rounds to no pixel gets no bar: a rectangle of zero width is invalid
        // SVG, and the PNG's renderer said so once per bar on every sweep's log.
        if end != zero {
            area.draw(&Rectangle::new(
                [(zero.min(end), y + 4), (zero.max(end), y + ROW - 4)],
                fill.filled(),
            ))?;
        }
        area.draw(&Text::new(
            format!("{:.1} %", 100.0 * share),
            (zero.max(end) + 6, y + ROW / 2),
            values.clone(),
        ))?;
    }
    // The zero line over the column's rows.
    let bottom = top + ROW * shares.len() as i32;
    area.draw(&PathElement::new(
        vec![(zero, top), (zero, bottom)],
        BLACK.stroke_width(1),
    ))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::super::svg_check::{check_xml, tags, texts};
    use super::*;

    /// Every body and pair is named with its value, one bar each (a negative share too),
    /// and the document is well-formed; no row says so.
    #[test]
    fn a_bar_per_share_named_with_its_value() {
        let rows = vec![ContributionRow {
            caption: "664.6 Hz, mu 0.60".into(),
            bodies: vec![("disc".into(), 0.25), ("pad <outboard>".into(), 0.75)],
            pairs: vec![
                ("disc/pad outboard".into(), 1.15),
                ("bracket/pad".into(), -0.15),
            ],
        }];
        let svg = contributions(&rows, "Why each instability squeals").unwrap();
        check_xml(&svg).unwrap();
        let t = texts(&svg);
        for s in [
            "25.0 %",
            "75.0 %",
            "115.0 %",
            "-15.0 %",
            "disc/pad outboard",
        ] {
            assert!(t.iter().any(|x| x.contains(s)), "{s} not in {t:?}");
        }
        // Four bars (and the background).
        assert_eq!(tags(&svg, "rect").count(), 5, "{svg}");
        // A share of no pixel is named but has no bar: a zero-width rectangle is invalid
        // SVG (the PNG's renderer warned once per bar).
        let rows = vec![ContributionRow {
            caption: "5891.8 Hz, mu 0.60".into(),
            bodies: vec![("bracket".into(), 1.0)],
            pairs: vec![("bracket/pad".into(), 1.0), ("leading".into(), 1e-6)],
        }];
        let svg = contributions(&rows, "zero").unwrap();
        assert!(texts(&svg).iter().any(|x| x.contains("0.0 %")), "{svg}");
        assert_eq!(tags(&svg, "rect").count(), 3, "{svg}");
        assert!(!svg.contains("width=\"0\""), "{svg}");
        let empty = contributions(&[], "none").unwrap();
        assert!(texts(&empty).iter().any(|x| x.contains("no data")));
    }
}
