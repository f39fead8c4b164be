//! The paper's Fig. 3 reproduced: contact trajectories on the plane and on the sphere, classical
//! (Montana + RK45) against ours (exact and rpy), as 2-D projections.

use crate::error::ChartError;
use plotters::prelude::*;
use plotters::style::full_palette::{BLUE_600, GREEN_700};

use crate::chart::style::{
    draw_axes, draw_legend, draw_line, draw_markers, drawing_err, linear_range, svg_string, Shape,
    FONT,
};

/// One run's paths, in metres, one row per sample.
#[derive(Clone, Debug)]
pub struct Run {
    /// Legend name.
    pub name: String,
    /// Contact on the plane, object frame.
    pub plane: Vec<[f64; 3]>,
    /// Contact on the sphere, fingertip frame.
    pub sphere: Vec<[f64; 3]>,
}

/// The runs to draw; the first is the classical reference.
#[derive(Clone, Debug)]
pub struct Trajectories {
    /// The runs.
    pub runs: Vec<Run>,
}

/// One panel: which path and which two axes.
struct Panel {
    title: &'static str,
    sphere: bool,
    axes: (usize, usize),
}

const PANELS: [Panel; 3] = [
    Panel {
        title: "(a) contact on the plane, plane frame: x-y",
        sphere: false,
        axes: (0, 1),
    },
    Panel {
        title: "(b) contact on the sphere, fingertip frame: x-y",
        sphere: true,
        axes: (0, 1),
    },
    Panel {
        title: "(c) contact on the sphere, fingertip frame: x-z",
        sphere: true,
        axes: (0, 2),
    },
];

const AXIS: [&str; 3] = ["x", "y", "z"];

/// Renders the three panels as one SVG.
pub fn svg(t: &Trajectories) -> Result<String, ChartError> {
    svg_string((1500, 560), |root| {
        let root = root
            .titled(
                "Paper Fig. 3 reproduced: contact trajectories, sphere R = 10 mm rolling on a plane \
                 (δφ, δθ, δψ = 0.05, 0.02, 0.03 rad per 10 ms, 1 s)",
                (FONT, 18),
            )
            .map_err(drawing_err)?;
        let areas = root.split_evenly((1, 3));
        let styles = [
            (BLACK.mix(0.35).stroke_width(6), None),
            (BLUE_600.filled(), Some(Shape::Circle)),
            (GREEN_700.stroke_width(2), Some(Shape::Triangle)),
        ];
        for (area, panel) in areas.iter().zip(&PANELS) {
            let (i, j) = panel.axes;
            let pick = |r: &Run| -> Vec<(f64, f64)> {
                let path = if panel.sphere { &r.sphere } else { &r.plane };
                path.iter().map(|p| (p[i] * 1e3, p[j] * 1e3)).collect()
            };
            let all: Vec<(f64, f64)> = t.runs.iter().flat_map(pick).collect();
            let (x0, x1) = linear_range(all.iter().map(|p| p.0), 1e-3, 0.0);
            // Room above the paths for the legend.
            let (y0, y1) = linear_range(all.iter().map(|p| p.1), 1e-3, 0.3);
            let mut chart = ChartBuilder::on(area)
                .caption(panel.title, (FONT, 15))
                .margin(12)
                .x_label_area_size(40)
                .y_label_area_size(55)
                .build_cartesian_2d(x0..x1, y0..y1)
                .map_err(drawing_err)?;
            draw_axes(
                &mut chart,
                &format!("{} (mm)", AXIS[i]),
                &format!("{} (mm)", AXIS[j]),
            )?;
            for (k, run) in t.runs.iter().enumerate() {
                let pts = pick(run);
                let (style, shape) = styles[k.min(styles.len() - 1)];
                match shape {
                    None => draw_line(&mut chart, &pts, style, Some(&run.name))?,
                    Some(shape) => {
                        if k > 1 {
                            draw_line(&mut chart, &pts, style, None)?;
                        }
                        // Every 4th sample marked, so the reference line stays visible underneath;
                        // each run starts at a different sample so coinciding runs stay visible.
                        let marked: Vec<(f64, f64)> =
                            pts.iter().copied().skip(2 * (k - 1)).step_by(4).collect();
                        draw_markers(
                            &mut chart,
                            &marked,
                            shape,
                            style.color.filled(),
                            Some(&run.name),
                        )?;
                    }
                }
            }
            draw_legend(&mut chart, SeriesLabelPosition::UpperLeft, 12)?;
        }
        Ok(())
    })
}
