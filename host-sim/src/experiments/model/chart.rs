//! The contact-model ablation of one scene (`host-sim model --svg`): each model choice's cost
//! (instructions per contact step on the emulated Cortex-M4F) against its largest difference from
//! the full model in units of the perceptual yardstick (the worst of force and contact path, and
//! spin torque where the device displays it; 1 = just noticeable), the same with the torque
//! counted (a device that displayed it), the yardstick drawn at 1, and the scene's named model
//! marked.

use crate::chart::style::{
    draw_axes, draw_line, draw_markers, draw_side_legend, drawing_err, linear_range, render_svg,
    split_for_legend, Entry, Key, Shape, FONT, PALETTE,
};
use crate::error::ChartError;
use crate::experiments::model::Report;
use plotters::prelude::*;
use std::path::Path;

/// Ratios below this are drawn at it (the full model's own row is 0).
pub const RATIO_FLOOR: f64 = 1e-3;

/// The worst of a row's yardstick ratios (the torque's only when `torque_displayed`), floored at
/// [`RATIO_FLOOR`].
pub fn worst_ratio(r: &crate::experiments::model::Row, torque_displayed: bool) -> f64 {
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
    write_for(
        path,
        report,
        "instructions per contact step (emulated Cortex-M4F, fast backend)",
        &[],
    )
}

/// [`write`] with the x axis described by `x_desc`, and the choices named in `dropped` labelled
/// as dropping the held object (the grasp: a failure the force and path yardstick does not show).
pub fn write_for(
    path: &Path,
    report: &Report,
    x_desc: &str,
    dropped: &[&str],
) -> Result<(), ChartError> {
    let device = crate::experiments::model::yardstick::DEVICE_DISPLAYS_TORQUE;
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
    let y_hi = with_torque.iter().map(|p| p.1).fold(10.0f64, f64::max) * 4.0;
    let labels = label_positions(&pts, x_hi - x_lo);
    let choice = if device {
        "model choice"
    } else {
        "model choice (force, path: this device shows no torque)"
    };
    let mut entries = vec![
        Entry {
            label: "yardstick (just noticeable)".into(),
            key: Key::Line(RED, None),
        },
        Entry {
            label: choice.into(),
            key: Key::Marker(PALETTE[0], Shape::Circle),
        },
    ];
    if !device {
        entries.push(Entry {
            label: "the same if the spin torque were displayed".into(),
            key: Key::Marker(PALETTE[1], Shape::Triangle),
        });
    }
    entries.push(Entry {
        label: "named in the scene file (ringed)".into(),
        key: Key::Marker(BLACK, Shape::Circle),
    });
    render_svg(path, (900, 480), |root| {
        let root = root
            .titled(
                &format!(
                    "{}: which contact model does this scene need? Cost against difference \
                     (least: {}, named: {})",
                    report.scene, report.least_model, report.named_model
                ),
                (FONT, 16),
            )
            .map_err(drawing_err)?;
        let (plot, legend) = split_for_legend(&root, &entries, 12);
        if let Some(l) = &legend {
            draw_side_legend(&l.margin(10, 0, 0, 0), &entries, 12)?;
        }
        let mut chart = ChartBuilder::on(&plot)
            .margin(12)
            .x_label_area_size(44)
            .y_label_area_size(64)
            .build_cartesian_2d(x_lo..x_hi, (RATIO_FLOOR / 5.0..y_hi).log_scale())
            .map_err(drawing_err)?;
        draw_axes(&mut chart, x_desc, "worst difference / yardstick")?;
        draw_line(
            &mut chart,
            &[(x_lo, 1.0), (x_hi, 1.0)],
            ShapeStyle::from(&RED).stroke_width(2),
            None,
        )?;
        let all: Vec<(f64, f64)> = pts.iter().map(|p| (p.0, p.1)).collect();
        draw_markers(&mut chart, &all, Shape::Circle, PALETTE[0].filled(), None)?;
        if !device {
            draw_markers(
                &mut chart,
                &with_torque,
                Shape::Triangle,
                PALETTE[1].stroke_width(2),
                None,
            )?;
        }
        if let Some(&(x, y, _)) = pts.iter().find(|p| p.2 == report.named_model) {
            chart
                .draw_series(std::iter::once(Circle::new(
                    (x, y),
                    9,
                    ShapeStyle::from(&BLACK).stroke_width(2),
                )))
                .map_err(drawing_err)?;
        }
        chart
            .draw_series(pts.iter().zip(&labels).map(|(&(_, _, name), &at)| {
                let label = if dropped.contains(&name) {
                    format!("{name} (drops the object)")
                } else {
                    name.to_string()
                };
                Text::new(label, at, (FONT, 13).into_font())
            }))
            .map_err(drawing_err)?;
        Ok(())
    })
}

/// Where each point's label goes, in data coordinates: right of the point (clear of the ring),
/// above it; a point whose label would meet an earlier one's (closer than 12 % of the x span and
/// within a factor 4 in y) takes the next slot below instead, so no two labels overlap.
fn label_positions(pts: &[(f64, f64, &str)], x_span: f64) -> Vec<(f64, f64)> {
    let dx = 0.015 * x_span;
    let mut placed: Vec<(f64, f64, usize)> = Vec::new();
    pts.iter()
        .map(|&(x, y, _)| {
            let near = placed
                .iter()
                .filter(|&&(px, py, _)| {
                    (px - x).abs() < 0.12 * x_span && (py / y).ln().abs() < 4f64.ln()
                })
                .map(|&(_, _, slot)| slot + 1)
                .max()
                .unwrap_or(0);
            placed.push((x, y, near));
            // Slot 0 above the point, then each further slot a factor 3 lower.
            (x + dx, y * 1.4 / 3f64.powi(near as i32))
        })
        .collect()
}

#[cfg(test)]
mod label_tests {
    use super::label_positions;

    #[test]
    fn labels_of_nearby_points_take_different_slots() {
        // spin-rolling and full: 5 instructions apart at the same ratio (finger-on-plane).
        let pts = [(256.0, 8.0, "a"), (435.0, 1e-3, "b"), (440.0, 1e-3, "c")];
        let l = label_positions(&pts, 200.0);
        assert_eq!(l[0].1, 8.0 * 1.4);
        assert_eq!(l[1].1, 1e-3 * 1.4);
        assert!((l[2].1 - 1e-3 * 1.4 / 3.0).abs() < 1e-12, "{l:?}");
        // Far apart in x: both above their points.
        let l = label_positions(&[(256.0, 1.0, "a"), (440.0, 1.0, "b")], 200.0);
        assert_eq!(l[0].1, l[1].1);
    }
}
