//! The speed–accuracy chart: time per step against the largest contact-path error, log–log, one panel
//! per sampling rate (like compared with like: every method and the classical RK45 on the same scene),
//! each point with its timing spread over the rounds, and the Pareto front where the spread separates
//! the points.

use crate::error::ChartError;
use plotters::coord::combinators::LogCoord;
use plotters::prelude::*;

use super::pareto;
use super::points::{Point, Series};
use crate::chart::style::{
    backend_shape, draw_axes, draw_line, draw_side_legend, drawing_err, log_range, svg_string,
    variant_color, Entry, Key, Shape, ERROR_FLOOR_MM, FONT, FRONT_COLOR, RK45_COLORS,
};
use crate::experiments::validate::classical::Rk45Call;
use crate::experiments::validate::ours::Variant;

/// Errors above this (mm) are off the chart's scale (the paper-verbatim decomposition's 1e2–1e5 mm
/// on a 10 mm fingertip): drawn at it as hollow markers and named in the panel.
pub const ERROR_CLIP_MM: f64 = 100.0;

/// `(ns per step, error in mm clamped to the floor and the clip)` of a point.
pub fn xy(p: &Point) -> (f64, f64) {
    (
        p.ns_per_step,
        p.error_mm.clamp(ERROR_FLOOR_MM, ERROR_CLIP_MM),
    )
}

/// Whether `a` dominates `b` when only timing differences the rounds separate count: `a` is at most
/// as wrong and not clearly slower (its lower quartile at most `b`'s upper one), and either more
/// accurate or clearly faster (its upper quartile below `b`'s lower one).
pub fn dominates(a: &Point, b: &Point) -> bool {
    let (a_lo, a_hi) = a.ns_quartiles;
    let (b_lo, b_hi) = b.ns_quartiles;
    let no_worse = a.error_mm <= b.error_mm && a_lo <= b_hi;
    no_worse && (a.error_mm < b.error_mm || a_hi < b_lo)
}

/// Indices of the points no other point of the same rate [`dominates`], by rate and then by
/// increasing median time. Points within each other's timing spread and of equal error are both
/// on the front: noise does not decide. Points with a NaN time or error are left out.
pub fn front(points: &[Point]) -> Vec<usize> {
    let ok = |p: &Point| {
        !(p.ns_per_step.is_nan()
            || p.error_mm.is_nan()
            || p.ns_quartiles.0.is_nan()
            || p.ns_quartiles.1.is_nan())
    };
    let mut out: Vec<usize> = (0..points.len())
        .filter(|&i| ok(&points[i]))
        .filter(|&i| {
            let b = &points[i];
            !points
                .iter()
                .enumerate()
                .any(|(j, a)| j != i && ok(a) && a.rate_hz == b.rate_hz && dominates(a, b))
        })
        .collect();
    out.sort_by(|&a, &b| {
        let (pa, pb) = (&points[a], &points[b]);
        pa.rate_hz
            .total_cmp(&pb.rate_hz)
            .then(pa.ns_per_step.total_cmp(&pb.ns_per_step))
    });
    out
}

/// Short rate label: `100 Hz`, `4 kHz`.
pub fn rate_label(hz: f64) -> String {
    if hz >= 1000.0 {
        format!("{} kHz", hz / 1000.0)
    } else {
        format!("{hz} Hz")
    }
}

/// A panel: log time against log error.
type LogLog<'a, 'b> = ChartContext<'a, SVGBackend<'b>, Cartesian2d<LogCoord<f64>, LogCoord<f64>>>;

/// The rates of `points`, increasing.
fn rates(points: &[Point]) -> Vec<f64> {
    let mut r: Vec<f64> = points.iter().map(|p| p.rate_hz).collect();
    r.sort_by(f64::total_cmp);
    r.dedup();
    r
}

/// Legend entries: every method × backend, the two RK45 calls, the spread, the front, off scale.
fn legend() -> Vec<Entry> {
    let mut e: Vec<Entry> = Variant::all()
        .into_iter()
        .map(|v| Entry {
            label: format!("ours: {} (f32)", v.name()),
            key: Key::Marker(variant_color(v.method, v.backend), backend_shape(v.backend)),
        })
        .collect();
    for (call, color) in [Rk45Call::Restart, Rk45Call::SingleCall]
        .into_iter()
        .zip(RK45_COLORS)
    {
        e.push(Entry {
            label: format!("RK45 (f64), {}", call.name()),
            key: Key::LineMarker(color, Shape::Diamond),
        });
    }
    e.push(Entry {
        label: "timing spread: quartiles over the rounds".into(),
        key: Key::Line(RGBColor(90, 90, 90), None),
    });
    e.push(Entry {
        label: "Pareto front (medians; ties where spreads overlap)".into(),
        key: Key::Line(FRONT_COLOR, None),
    });
    e
}

/// Renders the chart as SVG: a panel per rate on a grid of three columns, the legend and notes in
/// the last cell.
pub fn svg(points: &[Point]) -> Result<String, ChartError> {
    let rates = rates(points);
    let cols = 3usize;
    let rows = (rates.len() + 1).div_ceil(cols).max(1);
    let (pw, ph) = (620u32, 520u32);
    let title_h = 64u32;
    svg_string((pw * cols as u32, ph * rows as u32 + title_h), |root| {
        let (top, grid) = root.split_vertically(title_h);
        top.draw(&Text::new(
            "Which contact step gives the most accuracy per nanosecond? Time per step against the largest \
             contact-path error, one panel per sampling rate",
            (16, 10),
            (FONT, 19).into_font(),
        ))
        .map_err(drawing_err)?;
        top.draw(&Text::new(
            format!(
                "paper §3.1 motion, sphere 10 mm on a plane, 1 s; errors < {ERROR_FLOOR_MM:.0e} mm drawn at \
                 {ERROR_FLOOR_MM:.0e}, > {ERROR_CLIP_MM:.0} mm clipped at {ERROR_CLIP_MM:.0} (hollow ▲, value named); \
                 host CPU, median of interleaved timing rounds"
            ),
            (16, 38),
            (FONT, 14).into_font().color(&RGBColor(70, 70, 70)),
        ))
        .map_err(drawing_err)?;
        let (x0, x1) = log_range(
            points
                .iter()
                .flat_map(|p| [p.ns_quartiles.0, p.ns_quartiles.1]),
        );
        let (y0, _) = log_range(points.iter().map(|p| xy(p).1));
        let y1 = ERROR_CLIP_MM * 10.0;
        let cells = grid.split_evenly((rows, cols));
        let front = front(points);
        for (cell, &rate) in cells.iter().zip(&rates) {
            panel(cell, points, &front, rate, (x0, x1), (y0, y1))?;
        }
        if let Some(cell) = cells.get(rates.len()) {
            let area = cell.margin(40, 10, 20, 10);
            let h = draw_side_legend(&area, &legend(), 13)?;
            plateau_note(&area, points, h + 16)?;
        }
        Ok(())
    })
}

/// The rk45/restart plateau explained below the legend: per rate, the tolerances at which every
/// sample was one RK45 step (taken from the points' step counts; re-centrings add a few).
fn plateau_note(
    area: &crate::chart::style::Area,
    points: &[Point],
    y: i32,
) -> Result<(), ChartError> {
    let mut lines = vec![
        "Why rk45/restart is flat: each sample restarts the integrator,".to_string(),
        "and its first step spans the whole sample and passes the error".to_string(),
        "test, so every such rtol takes the same steps and gives the same".to_string(),
        "error (one step's). Tighter rtol splits steps; the error falls.".to_string(),
        "One step per sample at:".to_string(),
    ];
    for rate in rates(points) {
        let one_step: Vec<f64> = points
            .iter()
            .filter(|p| p.series == Series::Rk45(Rk45Call::Restart) && p.rate_hz == rate)
            .filter(|p| p.steps_per_sample.is_some_and(|s| s < 1.1))
            .filter_map(|p| p.rtol)
            .collect();
        if let (Some(lo), Some(hi)) = (
            one_step.iter().copied().reduce(f64::min),
            one_step.iter().copied().reduce(f64::max),
        ) {
            lines.push(format!("  {}: rtol {hi:.0e} … {lo:.0e}", rate_label(rate)));
        }
    }
    if lines.len() == 5 {
        return Ok(());
    }
    for (k, l) in lines.iter().enumerate() {
        area.draw(&Text::new(
            l.clone(),
            (8, y + 17 * k as i32),
            (FONT, 13).into_font(),
        ))
        .map_err(drawing_err)?;
    }
    Ok(())
}

/// One rate's panel: our variants, both RK45 ladders, the spreads, the front, off-scale notes.
fn panel(
    area: &crate::chart::style::Area,
    points: &[Point],
    front: &[usize],
    rate: f64,
    (x0, x1): (f64, f64),
    (y0, y1): (f64, f64),
) -> Result<(), ChartError> {
    let mut chart = ChartBuilder::on(area)
        .caption(format!("sampling at {}", rate_label(rate)), (FONT, 17))
        .margin(10)
        .x_label_area_size(46)
        .y_label_area_size(70)
        .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
        .map_err(drawing_err)?;
    draw_axes(
        &mut chart,
        "time per step (ns, log)",
        "max path error (mm, log)",
    )?;
    // The clip line.
    draw_line(
        &mut chart,
        &[(x0, ERROR_CLIP_MM), (x1, ERROR_CLIP_MM)],
        RGBColor(200, 120, 120).stroke_width(1),
        None,
    )?;
    let at: Vec<(usize, &Point)> = points
        .iter()
        .enumerate()
        .filter(|(_, p)| p.rate_hz == rate)
        .collect();
    let front_xy: Vec<(f64, f64)> = front
        .iter()
        .filter(|&&i| points[i].rate_hz == rate)
        .map(|&i| xy(&points[i]))
        .collect();
    draw_line(
        &mut chart,
        &pareto::staircase(&front_xy, x1),
        FRONT_COLOR.mix(0.45).stroke_width(8),
        None,
    )?;
    // Timing spreads.
    for (_, p) in &at {
        let y = xy(p).1;
        draw_line(
            &mut chart,
            &[(p.ns_quartiles.0, y), (p.ns_quartiles.1, y)],
            RGBColor(90, 90, 90).stroke_width(1),
            None,
        )?;
    }
    draw_rk45(&mut chart, &at)?;
    let mut clipped: Vec<String> = Vec::new();
    for v in Variant::all() {
        let Some((_, p)) = at.iter().find(|(_, p)| p.series == Series::Ours(v)) else {
            continue;
        };
        let color = variant_color(v.method, v.backend);
        let shape = backend_shape(v.backend);
        let (x, y) = xy(p);
        let style = if p.error_mm > ERROR_CLIP_MM {
            clipped.push(format!("{} {:.1e} mm", v.name(), p.error_mm));
            color.stroke_width(2)
        } else {
            color.filled()
        };
        chart
            .draw_series(std::iter::once(
                EmptyElement::at((x, y)) + Polygon::new(shape.offsets(5), style),
            ))
            .map_err(drawing_err)?;
    }
    // Off-scale values named under the clip line, one per row.
    for (k, t) in clipped.iter().enumerate() {
        chart
            .plotting_area()
            .draw(
                &(EmptyElement::at((x0, ERROR_CLIP_MM))
                    + Text::new(
                        format!("▲ off scale: {t}"),
                        (6, 4 + 14 * k as i32),
                        (FONT, 11).into_font().color(&RGBColor(150, 30, 30)),
                    )),
            )
            .map_err(drawing_err)?;
    }
    Ok(())
}

/// The classical RK45 ladders of one rate: a line over the tolerances per call, the loosest and
/// the tightest rtol written beside their points.
fn draw_rk45<'a, 'b: 'a>(
    chart: &mut LogLog<'a, 'b>,
    at: &[(usize, &Point)],
) -> Result<(), ChartError> {
    for (call, color) in [Rk45Call::Restart, Rk45Call::SingleCall]
        .into_iter()
        .zip(RK45_COLORS)
    {
        let pts: Vec<&Point> = at
            .iter()
            .map(|(_, p)| *p)
            .filter(|p| p.series == Series::Rk45(call))
            .collect();
        let line: Vec<(f64, f64)> = pts.iter().map(|p| xy(p)).collect();
        draw_line(chart, &line, color.mix(0.7).stroke_width(1), None)?;
        chart
            .draw_series(line.iter().map(|&p| {
                EmptyElement::at(p) + Polygon::new(Shape::Diamond.offsets(4), color.filled())
            }))
            .map_err(drawing_err)?;
        // The loosest and tightest rtol beside their points; one label when they coincide.
        let (Some(first), Some(last)) = (pts.first(), pts.last()) else {
            continue;
        };
        let (a, b) = (xy(first), xy(last));
        let apart = (a.0 / b.0).log10().abs() > 0.15 || (a.1 / b.1).log10().abs() > 0.5;
        let rt = |p: &Point| p.rtol.map_or(String::new(), |r| format!("{r:.0e}"));
        // Restart's labels below its points, single-call's above, so the two never meet; the
        // loosest left of its point, the tightest right of it.
        let dy = if call == Rk45Call::Restart { 6 } else { -16 };
        let labels = if apart {
            vec![(a, rt(first), -34), (b, rt(last), 7)]
        } else {
            vec![(b, format!("{} … {}", rt(first), rt(last)), 7)]
        };
        for (p, t, dx) in labels {
            chart
                .draw_series(std::iter::once(
                    EmptyElement::at(p)
                        + Text::new(t, (dx, dy), (FONT, 11).into_font().color(&color)),
                ))
                .map_err(drawing_err)?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::experiments::validate::ours::Backend;
    use softfinger_core::contact::decompose::Method;

    fn pt(error_mm: f64, q: (f64, f64)) -> Point {
        Point {
            series: Series::Ours(Variant {
                method: Method::Exact,
                backend: Backend::Libm,
            }),
            rate_hz: 100.0,
            rtol: None,
            ns_per_step: 0.5 * (q.0 + q.1),
            ns_quartiles: q,
            steps_per_sample: None,
            error_mm,
        }
    }

    #[test]
    fn overlapping_spreads_of_equal_error_are_a_tie() {
        // Equal errors, quartiles overlapping by 1 ns: both on the front; 1 ns apart: the faster only.
        let tie = [pt(1e-5, (250.0, 260.0)), pt(1e-5, (259.0, 270.0))];
        assert_eq!(front(&tie), vec![0, 1]);
        let apart = [pt(1e-5, (250.0, 260.0)), pt(1e-5, (261.0, 270.0))];
        assert_eq!(front(&apart), vec![0]);
    }

    #[test]
    fn a_more_accurate_point_not_clearly_slower_dominates() {
        // b is faster by its median but within a's spread, and less accurate: a dominates it.
        let a = pt(1e-6, (250.0, 300.0));
        let b = pt(1e-5, (240.0, 260.0));
        assert!(dominates(&a, &b) && !dominates(&b, &a));
        // b clearly faster (upper quartile below a's lower): both on the front.
        let b = pt(1e-5, (200.0, 249.0));
        assert!(!dominates(&a, &b) && !dominates(&b, &a));
        // Another rate is not compared.
        let mut c = pt(1e-9, (1.0, 2.0));
        c.rate_hz = 1000.0;
        assert_eq!(front(&[a, c]), vec![0, 1]);
    }

    #[test]
    fn errors_above_the_clip_are_drawn_at_it() {
        assert_eq!(xy(&pt(6.2e2, (1.0, 1.0))).1, ERROR_CLIP_MM);
        assert_eq!(xy(&pt(99.0, (1.0, 1.0))).1, 99.0);
        assert_eq!(xy(&pt(0.0, (1.0, 1.0))).1, ERROR_FLOOR_MM);
    }
}
