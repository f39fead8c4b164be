//! The contact-model ablation of one scene (`host-sim model --svg`): each model choice's cost
//! (instructions per contact step on the emulated Cortex-M4F) against its largest difference from
//! the full model in units of the perceptual yardstick (the worst of force and contact path, and
//! spin torque where the device displays it; 1 = just noticeable), the same with the torque
//! counted (a device that displayed it), the yardstick drawn at 1, and the scene's named model
//! marked.

use crate::chart::style::{
    draw_axes, draw_line, draw_markers, drawing_err, linear_range, render_svg, Shape, FONT, PALETTE,
};
use crate::error::ChartError;
use crate::model::Report;
use plotters::prelude::*;
use std::path::Path;

/// Ratios below this are drawn at it (the full model's own row is 0).
pub const RATIO_FLOOR: f64 = 1e-3;

/// The worst of a row's yardstick ratios (the torque's only when `torque_displayed`), floored at
/// [`RATIO_FLOOR`].
pub fn worst_ratio(r: &crate::model::Row, torque_displayed: bool) -> f64 {
    let t = if torque_displayed {
        r.diff.torque_ratio
    } else {
        0.0
    };
    r.diff
        .force_ratio
        .max(t)
        .max(r.diff.path_ratio)
        .max(RATIO_FLOOR)
}

/// Write the chart of `report` to `path` (SVG).
pub fn write(path: &Path, report: &Report) -> Result<(), ChartError> {
    let device = crate::model::yardstick::DEVICE_DISPLAYS_TORQUE;
    let pts: Vec<(f64, f64, &str)> = report
        .rows
        .iter()
        .filter_map(|r| {
            r.instructions
                .map(|n| (n as f64, worst_ratio(r, device), r.model))
        })
        .collect();
    let with_torque: Vec<(f64, f64)> = report
        .rows
        .iter()
        .filter_map(|r| r.instructions.map(|n| (n as f64, worst_ratio(r, true))))
        .collect();
    let (x_lo, x_hi) = linear_range(pts.iter().map(|p| p.0), 20.0, 0.0);
    let y_hi = with_torque.iter().map(|p| p.1).fold(10.0f64, f64::max) * 300.0; // room above the points for the legend
    render_svg(path, (760, 480), |root| {
        let mut chart = ChartBuilder::on(root)
            .caption(
                format!(
                    "{}: contact model cost against difference (least: {}, named: {})",
                    report.scene, report.least_model, report.named_model
                ),
                (FONT, 17),
            )
            .margin(12)
            .x_label_area_size(44)
            .y_label_area_size(64)
            .build_cartesian_2d(x_lo..x_hi, (RATIO_FLOOR / 2.0..y_hi).log_scale())
            .map_err(drawing_err)?;
        draw_axes(
            &mut chart,
            "instructions per contact step (emulated Cortex-M4F, fast backend)",
            "worst difference / yardstick",
        )?;
        draw_line(
            &mut chart,
            &[(x_lo, 1.0), (x_hi, 1.0)],
            ShapeStyle::from(&RED).stroke_width(2),
            Some("yardstick (just noticeable)"),
        )?;
        let all: Vec<(f64, f64)> = pts.iter().map(|p| (p.0, p.1)).collect();
        draw_markers(
            &mut chart,
            &all,
            Shape::Circle,
            PALETTE[0].filled(),
            Some(if device {
                "model choice"
            } else {
                "model choice (force, path: this device shows no torque)"
            }),
        )?;
        if !device {
            draw_markers(
                &mut chart,
                &with_torque,
                Shape::Triangle,
                PALETTE[1].stroke_width(2),
                Some("the same if the spin torque were displayed"),
            )?;
        }
        if let Some(&(x, y, _)) = pts.iter().find(|p| p.2 == report.named_model) {
            chart
                .draw_series(std::iter::once(Circle::new(
                    (x, y),
                    9,
                    ShapeStyle::from(&BLACK).stroke_width(2),
                )))
                .map_err(drawing_err)?
                .label("named in the scene file")
                .legend(|(x, y)| Circle::new((x, y), 6, ShapeStyle::from(&BLACK).stroke_width(2)));
        }
        chart
            .draw_series(pts.iter().map(|&(x, y, name)| {
                Text::new(name.to_string(), (x, y * 1.4), (FONT, 13).into_font())
            }))
            .map_err(drawing_err)?;
        crate::chart::style::draw_legend(&mut chart, SeriesLabelPosition::UpperRight, 13)
    })
}
