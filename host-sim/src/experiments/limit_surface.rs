//! `host-sim limit-surface`: the ellipsoidal limit surface against the true limit surface of a
//! Hertzian patch (numerical integration in f64, [`crate::sim::reference::limit_surface`]): the curve,
//! the ellipse's radial error at each point, and the worst error; `--svg` charts both curves.

use crate::chart::style::{draw_axes, draw_legend, draw_line, drawing_err, render_svg, FONT};
use crate::error::{ChartError, JsonError};
use crate::sim::reference::limit_surface::{curve, ellipse_error_range, LimitPoint};
use plotters::prelude::*;
use std::path::{Path, PathBuf};

/// Why the limit-surface command failed.
#[derive(Debug, thiserror::Error)]
pub enum LimitSurfaceError {
    /// `--points` or `--cells` out of range.
    #[error("--points must be >= 2 and --cells between 10 and 5000")]
    Options,
    /// The chart could not be drawn or written.
    #[error(transparent)]
    Chart(#[from] ChartError),
    /// The JSON could not be serialised.
    #[error(transparent)]
    Json(#[from] JsonError),
}

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Points on the curve (instantaneous centres between 0.01 a and 100 a).
    #[arg(long, default_value_t = 60)]
    pub points: usize,
    /// Radial cells of the integration (the angular ones are twice as many).
    #[arg(long, default_value_t = 200)]
    pub cells: usize,
    /// Print JSON instead of the table.
    #[arg(long)]
    pub json: bool,
    /// Also draw the true limit curve and the ellipse (normalised) into this SVG file.
    #[arg(long)]
    pub svg: Option<PathBuf>,
}

/// The true curve and the ellipse, normalised by μ·f_N and τ_max, as an SVG chart.
pub fn chart(path: &Path, c: &[LimitPoint]) -> Result<(), ChartError> {
    render_svg(path, (640, 600), |root| {
        let mut ch = ChartBuilder::on(root)
            .caption(
                "Soft-finger limit surface: Hertzian patch vs ellipse",
                (FONT, 18),
            )
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(50)
            .build_cartesian_2d(0.0f64..1.1, 0.0f64..1.1)
            .map_err(drawing_err)?;
        draw_axes(&mut ch, "|f_t| / (mu f_N)", "tau_n / tau_max")?;
        let truth: Vec<(f64, f64)> = c.iter().map(|p| (p.x, p.y)).collect();
        let ellipse: Vec<(f64, f64)> = (0..=90)
            .map(|k| {
                let t = k as f64 / 90.0 * std::f64::consts::FRAC_PI_2;
                (t.cos(), t.sin())
            })
            .collect();
        draw_line(
            &mut ch,
            &truth,
            BLACK.stroke_width(2),
            Some("Hertzian patch (f64 integration)"),
        )?;
        draw_line(
            &mut ch,
            &ellipse,
            RED.stroke_width(2),
            Some("ellipse (rendered model)"),
        )?;
        draw_legend(&mut ch, SeriesLabelPosition::LowerLeft, 14)?;
        Ok(())
    })
}

/// The curve and the worst errors, rendered as the command prints them.
pub fn render(args: &Args) -> Result<String, LimitSurfaceError> {
    if args.points < 2 || args.cells < 10 || args.cells > 5000 {
        return Err(LimitSurfaceError::Options);
    }
    let c = curve(args.points, args.cells, 2 * args.cells);
    let (lo, hi) = ellipse_error_range(&c);
    if let Some(path) = &args.svg {
        chart(path, &c)?;
    }
    if args.json {
        let doc =
            serde_json::json!({ "curve": c, "ellipse_error_min": lo, "ellipse_error_max": hi });
        return Ok(serde_json::to_string_pretty(&doc).map_err(JsonError)?);
    }
    let mut out = String::from(
        "Hertzian limit surface (f64 integration) vs the ellipse (|f|/(mu fN))^2 + (tau/tau_max)^2 = 1\n\
         centre/a          |f|/(mu fN)   tau/tau_max   ellipse radial error\n",
    );
    for p in &c {
        out += &format!(
            "{:<16.4e} {:>12.6} {:>13.6} {:>14.4e}\n",
            p.centre_a,
            p.x,
            p.y,
            p.ellipse_error()
        );
    }
    out += &format!(
        "worst radial error of the ellipse: {lo:.4e} (over-estimate), {hi:.4e} (under-estimate)\n"
    );
    Ok(out)
}

pub fn main(args: &Args) -> Result<(), LimitSurfaceError> {
    println!("{}", render(args)?);
    Ok(())
}
