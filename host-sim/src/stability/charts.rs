//! SVG charts (plotters, SVG backend only: text is left to the browser's fonts).
//!
//! Three kinds: line charts with one or more panels ([`line_chart`]), heatmaps with a colour bar
//! ([`heatmap`]) and grouped bar charts ([`super::bar_chart`]). Log axes cannot show zero or negative
//! values: callers clamp to a stated floor.

use plotters::coord::ranged1d::{AsRangedCoord, ValueFormatter};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

type Area<'a> = DrawingArea<SVGBackend<'a>, Shift>;

pub(super) fn err<E: std::fmt::Debug>(path: &Path) -> impl Fn(E) -> String + '_ {
    move |e| format!("{}: drawing failed: {e:?}", path.display())
}

pub(super) const FONT: &str = "sans-serif";

/// How a series is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Style {
    Line,
    Dashed,
    Dotted,
    Markers,
    LineMarkers,
}

/// One series of (x, y) points.
#[derive(Clone, Debug)]
pub struct Series {
    pub label: String,
    pub color: RGBColor,
    pub style: Style,
    pub points: Vec<(f64, f64)>,
}

/// Axes of one panel. Ranges are (min, max); log axes need min > 0.
#[derive(Clone, Debug)]
pub struct Axes {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub x: (f64, f64),
    pub y: (f64, f64),
    pub x_log: bool,
    pub y_log: bool,
}

/// Tick label for a log axis: powers of ten as 1e-7, others in short form.
pub fn fmt_num(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    let a = v.abs();
    if (1e-2..1e4).contains(&a) {
        let s = format!("{v:.3}");
        let s = s.trim_end_matches('0').trim_end_matches('.');
        s.to_string()
    } else {
        let s = format!("{v:.1e}");
        s.replace(".0e", "e")
    }
}

fn draw_panel<X, Y>(area: &Area, axes: &Axes, series: &[Series], x: X, y: Y) -> Result<(), String>
where
    X: AsRangedCoord<Value = f64>,
    Y: AsRangedCoord<Value = f64>,
    X::CoordDescType: ValueFormatter<f64>,
    Y::CoordDescType: ValueFormatter<f64>,
{
    let e = |e: DrawingAreaErrorKind<std::io::Error>| format!("drawing failed: {e:?}");
    let mut chart = ChartBuilder::on(area)
        .caption(&axes.title, (FONT, 20))
        .margin(12)
        .x_label_area_size(48)
        .y_label_area_size(78)
        .build_cartesian_2d(x, y)
        .map_err(e)?;
    chart
        .configure_mesh()
        .x_desc(axes.x_label.as_str())
        .y_desc(axes.y_label.as_str())
        .x_label_formatter(&|v| fmt_num(*v))
        .y_label_formatter(&|v| fmt_num(*v))
        .label_style((FONT, 13))
        .axis_desc_style((FONT, 15))
        .light_line_style(RGBColor(235, 235, 235))
        .draw()
        .map_err(e)?;
    let (xlo, xhi) = axes.x;
    let (ylo, yhi) = axes.y;
    let inside = |&(px, py): &(f64, f64)| {
        px.is_finite() && py.is_finite() && px >= xlo && px <= xhi && py >= ylo && py <= yhi
    };
    for s in series {
        let pts: Vec<(f64, f64)> = s.points.iter().copied().filter(inside).collect();
        let c = s.color;
        let line = ShapeStyle::from(&c).stroke_width(2);
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
        let style = s.style;
        anno.label(s.label.as_str()).legend(move |(lx, ly)| {
            // One element type for every style: a dot (invisible unless markers) and two strokes
            // (joined for a solid line, apart for dashes, absent for markers).
            let l = ShapeStyle::from(&c).stroke_width(2);
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
                + PathElement::new(a, l)
                + PathElement::new(b, l)
                + PathElement::new(d, l)
        });
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font((FONT, 12))
        .position(SeriesLabelPosition::UpperLeft)
        .draw()
        .map_err(e)?;
    Ok(())
}

fn panel(area: &Area, axes: &Axes, series: &[Series]) -> Result<(), String> {
    let (x0, x1) = axes.x;
    let (y0, y1) = axes.y;
    match (axes.x_log, axes.y_log) {
        (true, true) => draw_panel(
            area,
            axes,
            series,
            (x0..x1).log_scale(),
            (y0..y1).log_scale(),
        ),
        (false, true) => draw_panel(area, axes, series, x0..x1, (y0..y1).log_scale()),
        (true, false) => draw_panel(area, axes, series, (x0..x1).log_scale(), y0..y1),
        (false, false) => draw_panel(area, axes, series, x0..x1, y0..y1),
    }
}

/// Line chart(s): panels side by side, each `panel_w` × `h` pixels.
pub fn line_chart(
    path: &Path,
    panel_w: u32,
    h: u32,
    panels: &[(Axes, Vec<Series>)],
) -> Result<(), String> {
    let n = panels.len().max(1);
    let root = SVGBackend::new(path, (panel_w * n as u32, h)).into_drawing_area();
    root.fill(&WHITE).map_err(err(path))?;
    let areas = root.split_evenly((1, n));
    for (area, (axes, series)) in areas.iter().zip(panels) {
        panel(area, axes, series).map_err(|s| format!("{}: {s}", path.display()))?;
    }
    root.present().map_err(err(path))?;
    Ok(())
}

/// Viridis colour map, t in [0, 1] (5 anchors, linear in between).
pub fn viridis(t: f64) -> RGBColor {
    const A: [(u8, u8, u8); 5] = [
        (68, 1, 84),
        (59, 82, 139),
        (33, 145, 140),
        (94, 201, 98),
        (253, 231, 37),
    ];
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let s = t * 4.0;
    let i = (s.floor() as usize).min(3);
    let f = s - i as f64;
    let mix = |a: u8, b: u8| (a as f64 + (b as f64 - a as f64) * f).round() as u8;
    RGBColor(
        mix(A[i].0, A[i + 1].0),
        mix(A[i].1, A[i + 1].1),
        mix(A[i].2, A[i + 1].2),
    )
}

/// Colour of flagged (failed) cells.
pub const FAIL_COLOR: RGBColor = RGBColor(255, 0, 160);

/// One heatmap panel: x log-spaced centres, y linear centres, `value[iy][ix]` mapped through
/// viridis over [vmin, vmax]; cells with `failed[iy][ix]` drawn in [`FAIL_COLOR`] with a marker.
pub struct HeatPanel<'a> {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub x: &'a [f64],
    pub y: &'a [f64],
    pub value: Vec<Vec<f64>>,
    pub failed: Vec<Vec<bool>>,
}

fn edges(c: &[f64], log: bool) -> Vec<f64> {
    let n = c.len();
    let mid = |a: f64, b: f64| if log { (a * b).sqrt() } else { 0.5 * (a + b) };
    let mut e = Vec::with_capacity(n + 1);
    if n == 1 {
        return vec![c[0] * 0.9, c[0] * 1.1];
    }
    e.push(if log {
        c[0] * c[0] / mid(c[0], c[1])
    } else {
        2.0 * c[0] - mid(c[0], c[1])
    });
    for i in 0..n - 1 {
        e.push(mid(c[i], c[i + 1]));
    }
    e.push(if log {
        c[n - 1] * c[n - 1] / mid(c[n - 2], c[n - 1])
    } else {
        2.0 * c[n - 1] - mid(c[n - 2], c[n - 1])
    });
    e
}

/// Heatmaps side by side plus a colour bar labelled `bar_label` over [vmin, vmax].
pub fn heatmap(
    path: &Path,
    panels: &[HeatPanel],
    vmin: f64,
    vmax: f64,
    bar_label: &str,
) -> Result<(), String> {
    let n = panels.len().max(1) as u32;
    let (pw, h, bar_w) = (520u32, 520u32, 150u32);
    let root = SVGBackend::new(path, (pw * n + bar_w, h)).into_drawing_area();
    root.fill(&WHITE).map_err(err(path))?;
    let (maps, bar) = root.split_horizontally(pw * n);
    for (area, p) in maps.split_evenly((1, n as usize)).iter().zip(panels) {
        heat_panel(path, area, p, vmin, vmax)?;
    }
    colour_bar(path, &bar, vmin, vmax, bar_label)?;
    root.present().map_err(err(path))?;
    Ok(())
}

/// One heatmap: cells coloured by value over [vmin, vmax], flagged cells in the failure colour
/// with a marker.
fn heat_panel(path: &Path, area: &Area, p: &HeatPanel, vmin: f64, vmax: f64) -> Result<(), String> {
    let e = err(path);
    let xe = edges(p.x, true);
    let ye = edges(p.y, false);
    let mut chart = ChartBuilder::on(area)
        .caption(&p.title, (FONT, 18))
        .margin(12)
        .x_label_area_size(48)
        .y_label_area_size(60)
        .build_cartesian_2d(
            (xe[0]..xe[xe.len() - 1]).log_scale(),
            ye[0]..ye[ye.len() - 1],
        )
        .map_err(&e)?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc(p.x_label.as_str())
        .y_desc(p.y_label.as_str())
        .x_label_formatter(&|v| fmt_num(*v))
        .y_label_formatter(&|v| format!("{v:.0}"))
        .label_style((FONT, 13))
        .axis_desc_style((FONT, 15))
        .draw()
        .map_err(&e)?;
    let mut cells = Vec::new();
    let mut marks = Vec::new();
    for (iy, row) in p.value.iter().enumerate() {
        for (ix, &v) in row.iter().enumerate() {
            let failed = p.failed[iy][ix];
            let color = if failed {
                FAIL_COLOR
            } else {
                viridis((v - vmin) / (vmax - vmin))
            };
            cells.push(Rectangle::new(
                [(xe[ix], ye[iy]), (xe[ix + 1], ye[iy + 1])],
                color.filled(),
            ));
            if failed {
                marks.push((p.x[ix], p.y[iy]));
            }
        }
    }
    chart.draw_series(cells).map_err(&e)?;
    // Markers keep narrow failed columns (the inserted π/2) visible.
    chart
        .draw_series(
            marks
                .iter()
                .map(|&c| Circle::new(c, 3, ShapeStyle::from(&FAIL_COLOR).filled())),
        )
        .map_err(&e)?;
    Ok(())
}

/// The colour bar over [vmin, vmax] labelled `bar_label`, with the failure colour's key below.
fn colour_bar(
    path: &Path,
    bar: &Area,
    vmin: f64,
    vmax: f64,
    bar_label: &str,
) -> Result<(), String> {
    let e = err(path);
    let mut cb = ChartBuilder::on(bar)
        .margin_top(40)
        .margin_bottom(60)
        .margin_left(10)
        .margin_right(10)
        .y_label_area_size(0)
        .right_y_label_area_size(90)
        .build_cartesian_2d(0.0..1.0, vmin..vmax)
        .map_err(&e)?;
    cb.configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .y_desc(bar_label)
        .label_style((FONT, 12))
        .axis_desc_style((FONT, 13))
        .draw()
        .map_err(&e)?;
    let steps = 100;
    cb.draw_series((0..steps).map(|i| {
        let a = vmin + (vmax - vmin) * i as f64 / steps as f64;
        let b = vmin + (vmax - vmin) * (i + 1) as f64 / steps as f64;
        Rectangle::new(
            [(0.0, a), (1.0, b)],
            viridis(i as f64 / (steps - 1) as f64).filled(),
        )
    }))
    .map_err(&e)?;
    let (_, bh) = bar.dim_in_pixel();
    bar.draw(&Rectangle::new(
        [(10, bh as i32 - 40), (26, bh as i32 - 24)],
        FAIL_COLOR.filled(),
    ))
    .map_err(&e)?;
    bar.draw(&Text::new(
        "flagged",
        (32, bh as i32 - 38),
        (FONT, 13).into_font(),
    ))
    .map_err(&e)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn viridis_ends_and_clamps() {
        assert_eq!(viridis(0.0), RGBColor(68, 1, 84));
        assert_eq!(viridis(1.0), RGBColor(253, 231, 37));
        assert_eq!(viridis(-3.0), viridis(0.0));
        assert_eq!(viridis(f64::NAN), viridis(0.0));
    }

    #[test]
    fn edges_bracket_the_centres() {
        let c = [1.0, 10.0, 100.0];
        let e = edges(&c, true);
        assert_eq!(e.len(), 4);
        for i in 0..3 {
            assert!(e[i] < c[i] && c[i] < e[i + 1]);
        }
        // The geometric mean √(1·10): sqrt is correctly rounded, so exactly √10 (measured equal).
        assert_eq!(e[1], 10f64.sqrt());
    }

    #[test]
    fn numbers_are_short() {
        assert_eq!(fmt_num(1e-7), "1e-7");
        assert_eq!(fmt_num(0.5), "0.5");
        assert_eq!(fmt_num(2000.0), "2000");
        assert_eq!(fmt_num(0.0), "0");
    }
}
