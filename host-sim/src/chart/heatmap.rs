//! Heatmaps with a colour bar (plotters, SVG backend): log-spaced x cells, linear y cells, values
//! through the viridis colour map, flagged cells in [`FAIL_COLOR`] with a marker.

use super::style::{self, fmt_num, render_svg, Area, FONT};
use crate::error::ChartError;
use plotters::prelude::*;
use std::path::Path;

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

/// Heatmaps side by side under the figure's `title`, plus a colour bar labelled `bar_label` over
/// [vmin, vmax] (log10 of the value), written atomically to `path`.
pub fn heatmap(
    path: &Path,
    title: &str,
    panels: &[HeatPanel],
    vmin: f64,
    vmax: f64,
    bar_label: &str,
) -> Result<(), ChartError> {
    let n = panels.len().max(1) as u32;
    let (pw, h, bar_w, title_h) = (520u32, 520u32, 190u32, 40u32);
    render_svg(path, (pw * n + bar_w, h + title_h), |root| {
        let root = root.titled(title, (FONT, 21)).map_err(style::drawing_err)?;
        let (maps, bar) = root.split_horizontally(pw * n);
        for (area, p) in maps.split_evenly((1, n as usize)).iter().zip(panels) {
            heat_panel(area, p, vmin, vmax)?;
        }
        colour_bar(&bar, vmin, vmax, bar_label)
    })
}

/// One heatmap: cells coloured by value over [vmin, vmax], flagged cells in the failure colour
/// with a marker.
fn heat_panel(area: &Area, p: &HeatPanel, vmin: f64, vmax: f64) -> Result<(), ChartError> {
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
        .map_err(style::drawing_err)?;
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
        .map_err(style::drawing_err)?;
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
            // Filled and outlined in its own colour: neighbours overlap by the outline, so no
            // background shows between cells (seams) when the viewer antialiases their edges.
            let corners = [(xe[ix], ye[iy]), (xe[ix + 1], ye[iy + 1])];
            cells.push(Rectangle::new(corners, color.filled()));
            cells.push(Rectangle::new(corners, color.stroke_width(1)));
            if failed {
                marks.push((p.x[ix], p.y[iy]));
            }
        }
    }
    chart.draw_series(cells).map_err(style::drawing_err)?;
    // Markers keep narrow failed columns (the inserted π/2) visible.
    chart
        .draw_series(
            marks
                .iter()
                .map(|&c| Circle::new(c, 3, ShapeStyle::from(&FAIL_COLOR).filled())),
        )
        .map_err(style::drawing_err)?;
    Ok(())
}

/// The colour bar over [vmin, vmax] (log10 of the value) labelled `bar_label` above it, ticks
/// written as the value itself, with the failure colour's key below.
fn colour_bar(bar: &Area, vmin: f64, vmax: f64, bar_label: &str) -> Result<(), ChartError> {
    // The label horizontal above the bar (a rotated one is tiny and hard to read).
    bar.draw(&Text::new(bar_label, (4, 8), (FONT, 14).into_font()))
        .map_err(style::drawing_err)?;
    let mut cb = ChartBuilder::on(bar)
        .margin_top(40)
        .margin_bottom(60)
        .margin_left(10)
        .margin_right(10)
        .y_label_area_size(0)
        .right_y_label_area_size(90)
        .build_cartesian_2d(0.0..1.0, vmin..vmax)
        .map_err(style::drawing_err)?;
    cb.configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .y_label_formatter(&|v| format!("{} rad", fmt_num(10f64.powf(*v))))
        .label_style((FONT, 12))
        .axis_desc_style((FONT, 13))
        .draw()
        .map_err(style::drawing_err)?;
    let steps = 100;
    cb.draw_series((0..steps).map(|i| {
        let a = vmin + (vmax - vmin) * i as f64 / steps as f64;
        let b = vmin + (vmax - vmin) * (i + 1) as f64 / steps as f64;
        Rectangle::new(
            [(0.0, a), (1.0, b)],
            viridis(i as f64 / (steps - 1) as f64).filled(),
        )
    }))
    .map_err(style::drawing_err)?;
    // The top of the scale is the data's largest value: name it at the bar's top.
    bar.draw(&Text::new(
        format!("top: {} rad (largest)", fmt_num(10f64.powf(vmax))),
        (4, 24),
        (FONT, 12).into_font(),
    ))
    .map_err(style::drawing_err)?;
    let (_, bh) = bar.dim_in_pixel();
    bar.draw(&Rectangle::new(
        [(10, bh as i32 - 40), (26, bh as i32 - 24)],
        FAIL_COLOR.filled(),
    ))
    .map_err(style::drawing_err)?;
    bar.draw(&Text::new(
        "flagged",
        (32, bh as i32 - 38),
        (FONT, 13).into_font(),
    ))
    .map_err(style::drawing_err)?;
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
}
