//! The speed–accuracy chart: time per step against the largest contact-path error, log–log, with the
//! Pareto front.

use crate::error::ChartError;
use plotters::coord::combinators::LogCoord;
use plotters::prelude::*;

use super::pareto;
use super::points::{Point, Series};
use super::style::{
    backend_shape, draw_axes, draw_legend, draw_line, draw_markers, drawing_err, log_range,
    svg_string, variant_color, Shape, ERROR_FLOOR_MM, FONT, FRONT_COLOR, RK45_COLORS,
};
use crate::validate::classical::Rk45Call;
use crate::validate::ours::Variant;

/// `(ns per step, error in mm clamped to the floor)` of a point.
pub fn xy(p: &Point) -> (f64, f64) {
    (p.ns_per_step, p.error_mm.max(ERROR_FLOOR_MM))
}

/// Indices of the Pareto-front points of `points`, by increasing time.
pub fn front(points: &[Point]) -> Vec<usize> {
    let xy: Vec<(f64, f64)> = points.iter().map(xy).collect();
    pareto::front(&xy)
}

/// Short rate label: `100 Hz`, `4 kHz`.
pub fn rate_label(hz: f64) -> String {
    if hz >= 1000.0 {
        format!("{} kHz", hz / 1000.0)
    } else {
        format!("{hz} Hz")
    }
}

/// The chart: log time against log error.
type LogLog<'a, 'b> = ChartContext<'a, SVGBackend<'b>, Cartesian2d<LogCoord<f64>, LogCoord<f64>>>;

/// Renders the chart as SVG.
pub fn svg(points: &[Point]) -> Result<String, ChartError> {
    svg_string((1200, 860), |root| {
        let (x0, x1) = log_range(points.iter().map(|p| p.ns_per_step));
        let (y0, y1) = log_range(points.iter().map(|p| xy(p).1));
        let mut chart = ChartBuilder::on(root)
            .caption(
                format!(
                    "Rolling contact step: speed vs accuracy (paper §3.1 motion, sphere 10 mm on a plane, 1 s); \
                     errors < {ERROR_FLOOR_MM:.0e} mm drawn at {ERROR_FLOOR_MM:.0e} mm"
                ),
                (FONT, 17),
            )
            .margin(16)
            .x_label_area_size(50)
            .y_label_area_size(80)
            .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
            .map_err(drawing_err)?;
        draw_axes(
            &mut chart,
            "time per step (ns, log; host CPU, median of interleaved batches)",
            "max contact-path error, plane or sphere, any axis (mm, log)",
        )?;

        draw_front(&mut chart, points, x1)?;
        draw_ours(&mut chart, points)?;
        draw_rk45(&mut chart, points)?;
        draw_legend(&mut chart, SeriesLabelPosition::UpperRight, 13)?;
        Ok(())
    })
}

/// The Pareto front, drawn first, wide and pale, so the points stay visible on it; `x1`: the
/// x axis end the staircase runs to.
fn draw_front<'a, 'b: 'a>(
    chart: &mut LogLog<'a, 'b>,
    points: &[Point],
    x1: f64,
) -> Result<(), ChartError> {
    let idx = front(points);
    let front_xy: Vec<(f64, f64)> = idx.iter().map(|&i| xy(&points[i])).collect();
    draw_line(
        chart,
        &pareto::staircase(&front_xy, x1),
        FRONT_COLOR.mix(0.45).stroke_width(9),
        Some("Pareto front (no other point is both faster and more accurate)"),
    )?;
    Ok(())
}

/// Our variants: one line and marker set per method x backend over the rates, the recommended
/// variant's points labelled with their rate.
fn draw_ours<'a, 'b: 'a>(chart: &mut LogLog<'a, 'b>, points: &[Point]) -> Result<(), ChartError> {
    for v in Variant::all() {
        let mut pts: Vec<&Point> = points
            .iter()
            .filter(|p| p.series == Series::Ours(v))
            .collect();
        pts.sort_by(|a, b| a.rate_hz.total_cmp(&b.rate_hz));
        let line: Vec<(f64, f64)> = pts.iter().map(|p| xy(p)).collect();
        let color = variant_color(v.method, v.backend);
        draw_line(chart, &line, color.mix(0.5).stroke_width(1), None)?;
        let rates = match (pts.first(), pts.last()) {
            (Some(a), Some(b)) if pts.len() > 1 => {
                format!(" ({} … {})", rate_label(a.rate_hz), rate_label(b.rate_hz))
            }
            (Some(a), _) => format!(" ({})", rate_label(a.rate_hz)),
            _ => String::new(),
        };
        draw_markers(
            chart,
            &line,
            backend_shape(v.backend),
            color.filled(),
            Some(&format!("{}{rates}", v.name())),
        )?;
        // Rates written next to the recommended variant's points.
        if v.method == softfinger_core::contact::decompose::Method::Exact
            && v.backend == crate::validate::ours::Backend::Libm
        {
            chart
                .draw_series(pts.iter().map(|p| {
                    Text::new(
                        rate_label(p.rate_hz),
                        xy(p),
                        (FONT, 12).into_font().color(&color),
                    )
                }))
                .map_err(drawing_err)?;
        }
    }
    Ok(())
}

/// The classical RK45 runs: one line per call style over the tolerances, points labelled with
/// their rtol.
fn draw_rk45<'a, 'b: 'a>(chart: &mut LogLog<'a, 'b>, points: &[Point]) -> Result<(), ChartError> {
    for (call, color) in [Rk45Call::Restart, Rk45Call::SingleCall]
        .into_iter()
        .zip(RK45_COLORS)
    {
        let pts: Vec<&Point> = points
            .iter()
            .filter(|p| p.series == Series::Rk45(call))
            .collect();
        let line: Vec<(f64, f64)> = pts.iter().map(|p| xy(p)).collect();
        draw_line(chart, &line, color.stroke_width(2), None)?;
        let rate = pts.first().map_or(String::new(), |p| rate_label(p.rate_hz));
        draw_markers(
            chart,
            &line,
            Shape::Diamond,
            color.filled(),
            Some(&format!(
                "classical RK45 (f64), {}, {rate}, rtol 1e-3 … 1e-12",
                call.describe()
            )),
        )?;
        // rtol written next to the points, skipping points that sit on the last labelled one.
        let mut last: Option<(f64, f64)> = None;
        let mut labels = Vec::new();
        for p in &pts {
            let (x, y) = xy(p);
            let apart = last.is_none_or(|(lx, ly)| {
                (x / lx).log10().abs() > 0.08 || (y / ly).log10().abs() > 0.3
            });
            if let (Some(r), true) = (p.rtol, apart) {
                labels.push(Text::new(
                    format!("{r:.0e}"),
                    (x, y),
                    (FONT, 11).into_font().color(&color),
                ));
                last = Some((x, y));
            }
        }
        chart.draw_series(labels).map_err(drawing_err)?;
    }
    Ok(())
}
