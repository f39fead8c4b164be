//! Line charts in panels (side by side or stacked), on linear or log axes, in the style of
//! [`super::style`]: the one series type ([`Series`]) and the one axis and legend code path of every
//! line chart host-sim writes. A panel can carry coloured bands behind its series (the contact
//! state over time, [`phase_bands`]) and can draw its two axes at the same scale (paths: 1 mm is
//! as long on x as on y). Log axes cannot show zero or negative values: callers clamp to a stated
//! floor.

use super::style::{
    draw_axes, draw_legend, draw_side_legend, drawing_err, render_svg, split_for_legend, Area,
    ContactPhase, Entry, Key, Shape, FONT,
};
use crate::error::ChartError;
use plotters::coord::ranged1d::{AsRangedCoord, ValueFormatter};
use plotters::prelude::*;
use softfinger_core::contact::state::ContactState;
use std::path::Path;

/// Margin around each panel, px.
const MARGIN: u32 = 12;
/// Height of the x tick labels and axis name, px.
const X_LABEL_AREA: u32 = 48;
/// Width of the y tick labels and axis name, px.
const Y_LABEL_AREA: u32 = 78;

/// How a series is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Style {
    Line,
    Dashed,
    Dotted,
    Markers,
    LineMarkers,
}

/// One series of (x, y) points. An empty label draws no legend entry (for a series continuing
/// one already in the legend).
#[derive(Clone, Debug)]
pub struct Series {
    pub label: String,
    pub color: RGBColor,
    pub style: Style,
    pub points: Vec<(f64, f64)>,
}

/// A coloured stretch of x behind a panel's series, e.g. a contact state over time. Bands with
/// the same label share one legend entry.
#[derive(Clone, Debug, PartialEq)]
pub struct Band {
    /// From, to (x units).
    pub x: (f64, f64),
    pub color: RGBColor,
    pub label: String,
}

/// A labelled vertical line at `x` (x units), e.g. the start of a script phase.
#[derive(Clone, Debug, PartialEq)]
pub struct Mark {
    pub x: f64,
    pub label: String,
}

/// Axes of one panel. Ranges are (min, max); log axes need min > 0.
#[derive(Clone, Debug, Default)]
pub struct Axes {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub x: (f64, f64),
    pub y: (f64, f64),
    pub x_log: bool,
    pub y_log: bool,
    /// Ticks of a log y axis (empty: the decades plotters picks; give them when the axis spans
    /// more than a decade but the data need labels between decades).
    pub y_ticks: Vec<f64>,
    /// Drawn pale behind the series, with legend entries before theirs.
    pub bands: Vec<Band>,
    /// Vertical marks across the plot, each labelled at its top (e.g. where a script phase
    /// begins).
    pub marks: Vec<Mark>,
    /// Widen the shorter range so one unit is as long on x as on y (linear axes only).
    pub equal_scale: bool,
    /// Where the legend goes: `None` (the default) beside the plot, off the data; `Some` inside
    /// the plot at that corner (only for a corner the data leave empty).
    pub legend_at: Option<SeriesLabelPosition>,
}

/// Line chart(s): panels side by side, each `panel_w` × `h` px, written atomically to `path`.
pub fn line_chart(
    path: &Path,
    panel_w: u32,
    h: u32,
    panels: &[(Axes, Vec<Series>)],
) -> Result<(), ChartError> {
    grid_chart(path, (1, panels.len().max(1)), (panel_w, h), panels)
}

/// Line charts stacked top to bottom, each `w` × `panel_h` px, written atomically to `path`.
pub fn stacked_chart(
    path: &Path,
    w: u32,
    panel_h: u32,
    panels: &[(Axes, Vec<Series>)],
) -> Result<(), ChartError> {
    grid_chart(path, (panels.len().max(1), 1), (w, panel_h), panels)
}

/// `panels` on a grid of (rows, columns), row by row, each `panel_px` (w, h).
fn grid_chart(
    path: &Path,
    (rows, cols): (usize, usize),
    panel_px: (u32, u32),
    panels: &[(Axes, Vec<Series>)],
) -> Result<(), ChartError> {
    let size = (panel_px.0 * cols as u32, panel_px.1 * rows as u32);
    render_svg(path, size, |root| {
        draw_panels(&root.split_evenly((rows, cols)), panels)
    })
}

fn draw_panels(areas: &[Area], panels: &[(Axes, Vec<Series>)]) -> Result<(), ChartError> {
    for (area, (axes, series)) in areas.iter().zip(panels) {
        panel(area, axes, series)?;
    }
    Ok(())
}

/// The bands of a contact-state timeline: `ticks` gives each tick's end time and state, a tick
/// lasting `dt`; consecutive ticks of the same [`ContactPhase`] make one band.
pub fn phase_bands(ticks: impl IntoIterator<Item = (f64, ContactState)>, dt: f64) -> Vec<Band> {
    let mut bands: Vec<Band> = Vec::new();
    let mut touched = false;
    let mut last: Option<ContactPhase> = None;
    for (t, state) in ticks {
        let phase = ContactPhase::of(state, touched);
        touched |= state != ContactState::Broken;
        match bands.last_mut() {
            Some(b) if last == Some(phase) => b.x.1 = t,
            _ => bands.push(Band {
                x: (t - dt, t),
                color: phase.color(),
                label: phase.label().to_string(),
            }),
        }
        last = Some(phase);
    }
    bands
}

/// `(x, y)` widened about their centres so that x spans `plot_px.0` pixels and y spans
/// `plot_px.1` at the same units per pixel.
pub fn equal_ranges(x: (f64, f64), y: (f64, f64), plot_px: (u32, u32)) -> ((f64, f64), (f64, f64)) {
    let (w, h) = (f64::from(plot_px.0.max(1)), f64::from(plot_px.1.max(1)));
    let per_px = ((x.1 - x.0) / w).max((y.1 - y.0) / h);
    let widen = |(a, b): (f64, f64), px: f64| {
        let c = 0.5 * (a + b);
        (c - 0.5 * per_px * px, c + 0.5 * per_px * px)
    };
    (widen(x, w), widen(y, h))
}

/// One panel: the title, then the axes at the requested scales.
fn panel(area: &Area, axes: &Axes, series: &[Series]) -> Result<(), ChartError> {
    let inner = area
        .margin(MARGIN, MARGIN, MARGIN, MARGIN)
        .titled(&axes.title, (FONT, 20))
        .map_err(drawing_err)?;
    let (mut x, mut y) = (axes.x, axes.y);
    let entries = if axes.legend_at.is_none() {
        legend_entries(axes, series)
    } else {
        Vec::new()
    };
    let (inner, legend) = split_for_legend(&inner, &entries, LEGEND_FONT);
    if let Some(l) = &legend {
        draw_side_legend(l, &entries, LEGEND_FONT)?;
    }
    if axes.equal_scale && !axes.x_log && !axes.y_log {
        let (w, h) = inner.dim_in_pixel();
        let plot = (
            w.saturating_sub(Y_LABEL_AREA),
            h.saturating_sub(X_LABEL_AREA),
        );
        (x, y) = equal_ranges(x, y, plot);
    }
    let r = (x, y);
    let ticks = axes.y_ticks.clone();
    match (axes.x_log, axes.y_log) {
        (true, true) if !ticks.is_empty() => draw_panel(
            &inner,
            axes,
            r,
            series,
            (x.0..x.1).log_scale(),
            (y.0..y.1).log_scale().with_key_points(ticks),
        ),
        (false, true) if !ticks.is_empty() => draw_panel(
            &inner,
            axes,
            r,
            series,
            x.0..x.1,
            (y.0..y.1).log_scale().with_key_points(ticks),
        ),
        (true, true) => draw_panel(
            &inner,
            axes,
            r,
            series,
            (x.0..x.1).log_scale(),
            (y.0..y.1).log_scale(),
        ),
        (false, true) => draw_panel(&inner, axes, r, series, x.0..x.1, (y.0..y.1).log_scale()),
        (true, false) => draw_panel(&inner, axes, r, series, (x.0..x.1).log_scale(), y.0..y.1),
        (false, false) => draw_panel(&inner, axes, r, series, x.0..x.1, y.0..y.1),
    }
}

type Ranges = ((f64, f64), (f64, f64));

/// Font size of the legends, px.
const LEGEND_FONT: u32 = 12;

/// The legend beside a panel: each band label once, then each labelled series.
fn legend_entries(axes: &Axes, series: &[Series]) -> Vec<Entry> {
    let mut out: Vec<Entry> = Vec::new();
    for b in &axes.bands {
        if !out.iter().any(|e| e.label == b.label) {
            out.push(Entry {
                label: b.label.clone(),
                key: Key::Band(b.color),
            });
        }
    }
    for s in series.iter().filter(|s| !s.label.is_empty()) {
        let c = s.color;
        let key = match s.style {
            Style::Line => Key::Line(c, None),
            Style::Dashed => Key::Line(c, Some((6, 4))),
            Style::Dotted => Key::Line(c, Some((2, 3))),
            Style::Markers => Key::Marker(c, Shape::Circle),
            Style::LineMarkers => Key::LineMarker(c, Shape::Circle),
        };
        out.push(Entry {
            label: s.label.clone(),
            key,
        });
    }
    out
}

fn draw_panel<X, Y>(
    area: &Area,
    axes: &Axes,
    (xr, yr): Ranges,
    series: &[Series],
    x: X,
    y: Y,
) -> Result<(), ChartError>
where
    X: AsRangedCoord<Value = f64>,
    Y: AsRangedCoord<Value = f64>,
    X::CoordDescType: ValueFormatter<f64>,
    Y::CoordDescType: ValueFormatter<f64>,
{
    let mut chart = ChartBuilder::on(area)
        .x_label_area_size(X_LABEL_AREA)
        .y_label_area_size(Y_LABEL_AREA)
        .build_cartesian_2d(x, y)
        .map_err(drawing_err)?;
    draw_axes(&mut chart, &axes.x_label, &axes.y_label)?;
    draw_bands(&mut chart, &axes.bands, xr, yr)?;
    draw_marks(&mut chart, &axes.marks, xr, yr)?;
    let inside = |&(px, py): &(f64, f64)| {
        px.is_finite() && py.is_finite() && px >= xr.0 && px <= xr.1 && py >= yr.0 && py <= yr.1
    };
    for s in series {
        let pts: Vec<(f64, f64)> = s.points.iter().copied().filter(inside).collect();
        draw_series(&mut chart, s, pts)?;
    }
    match axes.legend_at.clone() {
        Some(at) => draw_legend(&mut chart, at, LEGEND_FONT),
        None => Ok(()),
    }
}

/// The bands, pale, clipped to the x range, each label once in the legend.
fn draw_bands<'a, 'b: 'a, X, Y>(
    chart: &mut ChartContext<'a, SVGBackend<'b>, Cartesian2d<X, Y>>,
    bands: &[Band],
    xr: (f64, f64),
    yr: (f64, f64),
) -> Result<(), ChartError>
where
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
    let mut seen: Vec<&str> = Vec::new();
    for b in bands {
        let (x0, x1) = (b.x.0.max(xr.0), b.x.1.min(xr.1));
        let fill = b.color.mix(0.22).filled();
        let rect = (x0 < x1).then(|| Rectangle::new([(x0, yr.0), (x1, yr.1)], fill));
        let anno = chart.draw_series(rect).map_err(drawing_err)?;
        if !seen.contains(&b.label.as_str()) {
            seen.push(&b.label);
            let key = b.color.mix(0.45).filled();
            anno.label(b.label.as_str())
                .legend(move |(lx, ly)| Rectangle::new([(lx, ly - 6), (lx + 16, ly + 6)], key));
        }
    }
    Ok(())
}

/// The marks: a dashed dark line each, its label at the plot's top just right of it; a label
/// that would run into the one before it goes one row lower (up to three rows).
fn draw_marks<'a, 'b: 'a, X, Y>(
    chart: &mut ChartContext<'a, SVGBackend<'b>, Cartesian2d<X, Y>>,
    marks: &[Mark],
    xr: (f64, f64),
    yr: (f64, f64),
) -> Result<(), ChartError>
where
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
    const ROW_PX: i32 = 15;
    let dark = RGBColor(60, 60, 60);
    let mut row_end: [i32; 3] = [i32::MIN; 3];
    // A mark in the last 1 % of the range would put its label past the plot's edge.
    let end = xr.1 - 0.01 * (xr.1 - xr.0);
    for m in marks.iter().filter(|m| m.x >= xr.0 && m.x < end) {
        chart
            .draw_series(DashedLineSeries::new(
                [(m.x, yr.0), (m.x, yr.1)],
                4,
                3,
                ShapeStyle::from(&dark).stroke_width(1),
            ))
            .map_err(drawing_err)?;
        let px = chart.backend_coord(&(m.x, yr.1)).0;
        let width = (m.label.chars().count() as f64 * 0.6 * 12.0).ceil() as i32 + 6;
        let row = (0..row_end.len())
            .find(|&r| row_end[r] < px)
            .unwrap_or(row_end.len() - 1);
        row_end[row] = px + width;
        chart
            .plotting_area()
            .draw(
                &(EmptyElement::at((m.x, yr.1))
                    + Text::new(
                        m.label.clone(),
                        (3, 3 + ROW_PX * row as i32),
                        (FONT, 12).into_font().color(&dark),
                    )),
            )
            .map_err(drawing_err)?;
    }
    Ok(())
}

/// One series in its style, with its legend entry unless its label is empty.
fn draw_series<'a, 'b: 'a, X, Y>(
    chart: &mut ChartContext<'a, SVGBackend<'b>, Cartesian2d<X, Y>>,
    s: &Series,
    pts: Vec<(f64, f64)>,
) -> Result<(), ChartError>
where
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
    let c = s.color;
    let line = ShapeStyle::from(&c).stroke_width(2);
    let e = drawing_err;
    let anno = match s.style {
        Style::Line => chart.draw_series(LineSeries::new(pts, line)).map_err(e)?,
        Style::Dashed => chart
            .draw_series(DashedLineSeries::new(pts, 8, 5, line))
            .map_err(e)?,
        Style::Dotted => chart
            .draw_series(DashedLineSeries::new(pts, 2, 4, line))
            .map_err(e)?,
        Style::Markers => chart
            .draw_series(pts.iter().map(|&p| Circle::new(p, 4, c.filled())))
            .map_err(e)?,
        Style::LineMarkers => {
            chart
                .draw_series(LineSeries::new(pts.clone(), line))
                .map_err(e)?;
            chart
                .draw_series(pts.iter().map(|&p| Circle::new(p, 3, c.filled())))
                .map_err(e)?
        }
    };
    if s.label.is_empty() {
        return Ok(());
    }
    let style = s.style;
    anno.label(s.label.as_str()).legend(move |(lx, ly)| {
        // One element type for every style: a dot (invisible unless markers) and three strokes
        // (one for a solid line, two or three short ones for dashes and dots, none for markers).
        type Seg = Vec<(i32, i32)>;
        let (dot, a, b, d): (RGBAColor, Seg, Seg, Seg) = match style {
            Style::Markers => (c.to_rgba(), vec![], vec![], vec![]),
            Style::Dashed => (
                c.mix(0.0),
                vec![(0, 0), (6, 0)],
                vec![(10, 0), (16, 0)],
                vec![],
            ),
            Style::Dotted => (
                c.mix(0.0),
                vec![(0, 0), (2, 0)],
                vec![(7, 0), (9, 0)],
                vec![(14, 0), (16, 0)],
            ),
            Style::LineMarkers => (c.to_rgba(), vec![(0, 0), (16, 0)], vec![], vec![]),
            Style::Line => (c.mix(0.0), vec![(0, 0), (16, 0)], vec![], vec![]),
        };
        EmptyElement::at((lx, ly))
            + Circle::new((8, 0), 4, dot.filled())
            + PathElement::new(a, line)
            + PathElement::new(b, line)
            + PathElement::new(d, line)
    });
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equal_ranges_give_both_axes_one_scale() {
        // 10 mm × 2 mm of data on a 600 × 300 px plot: 10/600 mm/px wins, y widens to 5 mm.
        let (x, y) = equal_ranges((0.0, 10.0), (4.0, 6.0), (600, 300));
        assert_eq!(x, (0.0, 10.0));
        assert!(
            (y.0 - 2.5).abs() < 1e-12 && (y.1 - 7.5).abs() < 1e-12,
            "{y:?}"
        );
        // Tall data widens x instead.
        let (x, y) = equal_ranges((0.0, 1.0), (0.0, 3.0), (600, 300));
        assert_eq!(y, (0.0, 3.0));
        assert!(((x.1 - x.0) / 600.0 - 3.0 / 300.0).abs() < 1e-12, "{x:?}");
    }

    #[test]
    fn bands_follow_the_state_timeline() {
        use ContactState::{Broken, Rolling, Sliding};
        let states = [Broken, Broken, Rolling, Rolling, Sliding, Broken, Rolling];
        let ticks = states.iter().enumerate().map(|(k, &s)| ((k + 1) as f64, s));
        let b = phase_bands(ticks, 1.0);
        let got: Vec<(f64, f64, &str)> =
            b.iter().map(|b| (b.x.0, b.x.1, b.label.as_str())).collect();
        assert_eq!(
            got,
            vec![
                (0.0, 2.0, "no contact yet"),
                (2.0, 4.0, "rolling"),
                (4.0, 5.0, "sliding"),
                (5.0, 6.0, "broken (released)"),
                (6.0, 7.0, "rolling"),
            ]
        );
    }

    #[test]
    fn a_panel_has_its_band_legend_once_and_unlabelled_series_none() {
        let axes = Axes {
            title: "t".into(),
            x: (0.0, 3.0),
            y: (0.0, 1.0),
            bands: phase_bands(
                [
                    (1.0, ContactState::Rolling),
                    (2.0, ContactState::Sliding),
                    (3.0, ContactState::Rolling),
                ],
                1.0,
            ),
            ..Axes::default()
        };
        let s = |label: &str| Series {
            label: label.into(),
            color: super::super::style::PALETTE[0],
            style: Style::Line,
            points: vec![(0.0, 0.0), (3.0, 1.0)],
        };
        let svg = super::super::style::svg_string((400, 300), |root| {
            panel(root, &axes, &[s("force"), s("")])
        })
        .unwrap();
        // plotters writes each text on its own line between the tags.
        let texts = |t: &str| svg.lines().filter(|l| l.trim() == t).count();
        assert_eq!(texts("rolling"), 1, "{svg}");
        assert_eq!(texts("sliding"), 1);
        assert_eq!(texts("force"), 1);
        // Three bands, drawn pale (opacity 0.22).
        assert_eq!(svg.matches("opacity=\"0.22\"").count(), 3);
    }
}
