//! The charts of `host-sim run`, made to be read at a glance:
//!
//! - `forces.svg`: the rendered force (base frame, N) and, below on its own axis, the spin torque
//!   (mN·m) against time, with the contact state as coloured bands behind both (no contact yet,
//!   rolling, sliding, broken after a release) and a legend naming them;
//! - `contact_path.svg`: the contact point's path on the object (object frame) and on the fingertip
//!   (fingertip frame) in two panels, x-y, each with equal axes (1 mm is as long on x as on y), the
//!   path coloured by the state it was traced in and its start marked.

use super::result::{Row, RunResult};
use crate::chart::lines::{line_chart, phase_bands, stacked_chart, Axes, Mark, Series, Style};
use crate::chart::style::{linear_range, state_color, ContactPhase, PALETTE};
use crate::error::ChartError;
use plotters::style::BLACK;
use softfinger_core::contact::state::ContactState;
use std::path::{Path, PathBuf};

/// At most about this many points per drawn line (every k-th tick; the CSV has them all).
const MAX_POINTS: usize = 4000;

/// Writes the run's charts into `dir`; returns their paths.
pub fn write(dir: &Path, res: &RunResult) -> Result<Vec<PathBuf>, ChartError> {
    let paths = dir.join("contact_path.svg");
    path_chart(&paths, res)?;
    let forces = dir.join("forces.svg");
    force_chart(&forces, res)?;
    Ok(vec![forces, paths])
}

/// Every k-th row, k such that at most about [`MAX_POINTS`] are kept.
fn thinned(rows: &[Row]) -> impl Iterator<Item = &Row> {
    rows.iter().step_by((rows.len() / MAX_POINTS).max(1))
}

/// Force and spin torque against time over the state bands.
fn force_chart(file: &Path, res: &RunResult) -> Result<(), ChartError> {
    let rows = &res.rows;
    let bands = phase_bands(
        rows.iter().map(|r| (r.t_s, r.state)),
        1.0 / res.scene.rate_hz,
    );
    let series = |label: &str, color, get: &dyn Fn(&Row) -> f64| Series {
        label: label.into(),
        color,
        style: Style::Line,
        points: thinned(rows).map(|r| (r.t_s, get(r))).collect(),
    };
    let force = vec![
        series("Fx", PALETTE[0], &|r| f64::from(r.force_n[0])),
        series("Fy", PALETTE[4], &|r| f64::from(r.force_n[1])),
        series("Fz", BLACK, &|r| f64::from(r.force_n[2])),
    ];
    let marks = phase_marks(rows, 1.0 / res.scene.rate_hz);
    let torque = vec![series("τn", PALETTE[5], &|r| f64::from(r.tau_n_nm) * 1e3)];
    let t = (
        rows.first()
            .map_or(0.0, |r| r.t_s - 1.0 / res.scene.rate_hz),
        rows.last().map_or(1.0, |r| r.t_s),
    );
    let axes = |title: String, y_label: &str, s: &[Series]| Axes {
        title,
        x_label: "time since arming (s)".into(),
        y_label: y_label.into(),
        x: t,
        // Room on top for the phase names.
        y: linear_range(
            s.iter().flat_map(|s| s.points.iter().map(|p| p.1)),
            0.1,
            0.2,
        ),
        bands: bands.clone(),
        marks: marks.clone(),
        ..Axes::default()
    };
    let name = &res.scene.name;
    stacked_chart(
        file,
        1100,
        380,
        &[
            (
                axes(
                    format!(
                        "{name}: what force was rendered in each script phase (dashed) and contact state (colour)?"
                    ),
                    "force (N)",
                    &force,
                ),
                force,
            ),
            (
                axes(
                    format!("{name}: spin torque about the contact normal, same phases and states"),
                    "spin torque τn (mN·m)",
                    &torque,
                ),
                torque,
            ),
        ],
    )
}

/// Where each phase of the scene's script begins: the start of its first tick (`dt` long).
fn phase_marks(rows: &[Row], dt: f64) -> Vec<Mark> {
    let mut out: Vec<Mark> = Vec::new();
    let mut last: Option<&str> = None;
    for r in rows {
        if last != Some(r.phase) {
            out.push(Mark {
                x: r.t_s - dt,
                label: r.phase.to_string(),
            });
            last = Some(r.phase);
        }
    }
    out
}

/// One path (mm, x-y) split where the state changes or the contact breaks, each piece in its
/// state's colour, the first piece of each state in the legend; the start marked.
fn path_series(rows: &[Row], point: impl Fn(&Row) -> [f32; 3]) -> Vec<Series> {
    let mm = |r: &Row| {
        let p = point(r);
        (f64::from(p[0]) * 1e3, f64::from(p[1]) * 1e3)
    };
    let mut out: Vec<Series> = Vec::new();
    let mut prev: Option<ContactState> = None;
    for r in thinned(rows) {
        if r.state == ContactState::Broken {
            prev = None;
            continue;
        }
        if prev != Some(r.state) {
            // Continue from the previous piece's end so the path has no gap at a state change
            // (`prev` is None after a break: no joint across it).
            let joint = prev.and(out.last().and_then(|s| s.points.last().copied()));
            let color = state_color(r.state);
            let named = out.iter().any(|s| s.color == color);
            out.push(Series {
                label: if named {
                    ""
                } else {
                    ContactPhase::of(r.state, true).label()
                }
                .to_string(),
                color,
                style: Style::Line,
                points: joint.into_iter().collect(),
            });
        }
        if let Some(s) = out.last_mut() {
            s.points.push(mm(r));
        }
        prev = Some(r.state);
    }
    if let Some(&start) = out.first().and_then(|s| s.points.first()) {
        out.push(Series {
            label: "start".into(),
            color: BLACK,
            style: Style::Markers,
            points: vec![start],
        });
    }
    out
}

/// The contact paths on the object and on the fingertip, side by side, equal axes.
fn path_chart(file: &Path, res: &RunResult) -> Result<(), ChartError> {
    let name = &res.scene.name;
    let panel = |title: String, series: Vec<Series>| {
        let xs = series.iter().flat_map(|s| s.points.iter().map(|p| p.0));
        let ys = series.iter().flat_map(|s| s.points.iter().map(|p| p.1));
        let axes = Axes {
            title,
            x_label: "x (mm)".into(),
            y_label: "y (mm)".into(),
            x: linear_range(xs, 0.5, 0.0),
            y: linear_range(ys, 0.5, 0.0),
            equal_scale: true,
            ..Axes::default()
        };
        (axes, series)
    };
    line_chart(
        file,
        640,
        620,
        &[
            panel(
                format!("{name}: where did the contact travel on the object? (object frame)"),
                path_series(&res.rows, |r| r.object_point_m),
            ),
            panel(
                format!("{name}: and on the fingertip? (fingertip frame)"),
                path_series(&res.rows, |r| r.finger_point_m),
            ),
        ],
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(t_s: f64, state: ContactState, x_mm: f32) -> Row {
        Row {
            t_s,
            phase: "roll",
            state,
            flags: softfinger_core::Flags::NONE,
            probe_m: [0.0; 3],
            force_n: [0.0; 3],
            tau_n_nm: 0.0,
            spin_rad: 0.0,
            object_point_m: [x_mm * 1e-3, 0.0, 0.0],
            finger_point_m: [0.0; 3],
            normal: [0.0, 0.0, 1.0],
            duties: [0.0; 3],
            hand_force_n: [0.0; 3],
        }
    }

    /// A mark where each script phase begins, at the start of its first tick.
    #[test]
    fn phases_are_marked_where_they_begin() {
        let mut rows: Vec<Row> = (1..=5)
            .map(|k| row(0.1 * k as f64, ContactState::Rolling, 0.0))
            .collect();
        rows[2].phase = "slide";
        rows[3].phase = "slide";
        rows[4].phase = "lift-off";
        let m = phase_marks(&rows, 0.1);
        let got: Vec<(i64, &str)> = m
            .iter()
            .map(|m| ((m.x * 10.0).round() as i64, m.label.as_str()))
            .collect();
        assert_eq!(got, vec![(0, "roll"), (2, "slide"), (4, "lift-off")]);
    }

    /// Pieces per state run, joined at state changes, broken ticks left out, each state named
    /// once in the legend, the start marked.
    #[test]
    fn the_path_is_split_by_state() {
        use ContactState::{Broken, Rolling, Sliding};
        let rows = [
            row(0.1, Broken, 9.0),
            row(0.2, Rolling, 1.0),
            row(0.3, Rolling, 2.0),
            row(0.4, Sliding, 3.0),
            row(0.5, Broken, 9.0),
            row(0.6, Rolling, 5.0),
        ];
        let s = path_series(&rows, |r| r.object_point_m);
        let xs: Vec<Vec<f64>> = s
            .iter()
            .map(|s| s.points.iter().map(|p| (p.0 * 1e3).round() / 1e3).collect())
            .collect();
        assert_eq!(
            xs,
            vec![vec![1.0, 2.0], vec![2.0, 3.0], vec![5.0], vec![1.0]]
        );
        let labels: Vec<&str> = s.iter().map(|s| s.label.as_str()).collect();
        assert_eq!(labels, ["rolling", "sliding", "", "start"]);
        assert_eq!(s[2].color, state_color(Rolling));
    }
}
