//! The grasp's charts, in the project's one chart style ([`crate::chart::lines`],
//! [`crate::chart::style`]): the object's pose over time, each contact's forces, spin torque and
//! state over time, each contact's load path against its limit surface, and the twist sweep
//! (turn against external torque, torsion on and off).

use super::simulate::{GraspRun, Sample};
use super::sweep::SweepPoint;
use super::verdict::{twist_about, ROTATION_LIMIT_RAD};
use crate::chart::lines::{line_chart, phase_bands, stacked_chart, Axes, Series, Style};
use crate::chart::style::{linear_range, PALETTE};
use crate::error::ChartError;
use nalgebra::{Quaternion, UnitQuaternion, Vector3};
use std::path::{Path, PathBuf};

fn series(label: &str, color: usize, style: Style, points: Vec<(f64, f64)>) -> Series {
    Series {
        label: label.into(),
        color: PALETTE[color],
        style,
        points,
    }
}

fn axes(title: &str, x: &str, y: &str, xr: (f64, f64), ys: &[&Series]) -> Axes {
    Axes {
        title: title.into(),
        x_label: x.into(),
        y_label: y.into(),
        x: xr,
        y: linear_range(
            ys.iter().flat_map(|s| s.points.iter().map(|p| p.1)),
            1e-6,
            0.25,
        ),
        ..Axes::default()
    }
}

/// Every tick is too many points for an SVG: about 2 000 per series.
fn stride(n: usize) -> usize {
    (n / 2000).max(1)
}

fn pick(s: &[Sample]) -> impl Iterator<Item = &Sample> {
    s.iter().step_by(stride(s.len()))
}

/// `pose.svg`: the object's centre (mm) and its turn about the grasp axis (rad) over time.
pub fn pose(path: &Path, run: &GraspRun) -> Result<(), ChartError> {
    let s = &run.samples;
    let t_end = s.last().map_or(1.0, |x| x.t_s);
    let q0 = UnitQuaternion::from_quaternion(Quaternion::new(
        run.samples[0].q[0],
        run.samples[0].q[1],
        run.samples[0].q[2],
        run.samples[0].q[3],
    ));
    let pos: Vec<Series> = ["x", "y", "z"]
        .iter()
        .enumerate()
        .map(|(i, n)| {
            series(
                &format!("object {n}"),
                i,
                Style::Line,
                pick(s).map(|x| (x.t_s, x.pos_m[i] * 1e3)).collect(),
            )
        })
        .collect();
    let turn = vec![series(
        "turn about the grasp axis",
        3,
        Style::Line,
        pick(s)
            .map(|x| {
                let q = UnitQuaternion::from_quaternion(Quaternion::new(
                    x.q[0], x.q[1], x.q[2], x.q[3],
                ));
                (x.t_s, twist_about(&q0, &q, &Vector3::x()))
            })
            .collect(),
    )];
    let a1 = axes(
        "Object position",
        "t (s)",
        "mm",
        (0.0, t_end),
        &pos.iter().collect::<Vec<_>>(),
    );
    let a2 = axes(
        "Object turn about the grasp axis (x)",
        "t (s)",
        "rad",
        (0.0, t_end),
        &turn.iter().collect::<Vec<_>>(),
    );
    stacked_chart(path, 900, 300, &[(a1, pos), (a2, turn)])
}

/// `contacts.svg`: per contact, normal and tangential force with μ_s·f_N, over the state bands;
/// then both spin torques with their limits.
pub fn contacts(path: &Path, run: &GraspRun) -> Result<(), ChartError> {
    let s = &run.samples;
    let dt = 1.0 / run.config.rate_hz;
    let t_end = s.last().map_or(1.0, |x| x.t_s);
    let mut panels = Vec::new();
    for c in 0..2 {
        let f = vec![
            series(
                "f_N",
                0,
                Style::Line,
                pick(s).map(|x| (x.t_s, x.f_n[c])).collect(),
            ),
            series(
                "|f_t|",
                1,
                Style::Line,
                pick(s).map(|x| (x.t_s, x.f_t[c])).collect(),
            ),
            series(
                "mu_s f_N",
                1,
                Style::Dashed,
                pick(s).map(|x| (x.t_s, x.limits[c].0)).collect(),
            ),
        ];
        let mut a = axes(
            &format!("Contact {c}: forces over the contact state"),
            "t (s)",
            "N",
            (0.0, t_end),
            &f.iter().collect::<Vec<_>>(),
        );
        a.bands = phase_bands(s.iter().map(|x| (x.t_s, x.state[c])), dt);
        panels.push((a, f));
    }
    let mut tau = Vec::new();
    for c in 0..2 {
        tau.push(series(
            &format!("tau_n contact {c}"),
            2 + 2 * c,
            Style::Line,
            pick(s).map(|x| (x.t_s, x.tau_n[c] * 1e3)).collect(),
        ));
        tau.push(series(
            &format!("±tau_max contact {c}"),
            2 + 2 * c,
            Style::Dashed,
            pick(s).map(|x| (x.t_s, -x.limits[c].1 * 1e3)).collect(),
        ));
    }
    let mut a = axes(
        "Spin torques",
        "t (s)",
        "mN·m",
        (0.0, t_end),
        &tau.iter().collect::<Vec<_>>(),
    );
    a.y.1 = a.y.1.max(0.0);
    panels.push((a, tau));
    stacked_chart(path, 900, 280, &panels)
}

/// `limit_surface.svg`: each contact's load (|f_t|/(μ_s f_N), |τn|/τ_max) per tick against the
/// static limit surface (the unit quarter ellipse) and its hysteresis margin.
pub fn limit_surface(path: &Path, run: &GraspRun, hysteresis: f64) -> Result<(), ChartError> {
    let ellipse = |k: f64| -> Vec<(f64, f64)> {
        (0..=90)
            .map(|i| {
                let a = f64::from(i) / 90.0 * std::f64::consts::FRAC_PI_2;
                (k * a.cos(), k * a.sin())
            })
            .collect()
    };
    let mut sr = vec![
        series("static limit surface", 5, Style::Line, ellipse(1.0)),
        series(
            "with the state machine's hysteresis",
            5,
            Style::Dotted,
            ellipse(1.0 + hysteresis),
        ),
    ];
    for c in 0..2 {
        let pts = pick(&run.samples)
            .filter(|x| x.limits[c].0 > 1e-6 && x.limits[c].1 > 1e-12)
            .map(|x| (x.f_t[c] / x.limits[c].0, x.tau_n[c].abs() / x.limits[c].1))
            .collect();
        sr.push(series(
            &format!("contact {c} load path"),
            c,
            Style::Markers,
            pts,
        ));
    }
    let a = Axes {
        title: "Each contact's load against its limit surface".into(),
        x_label: "|f_t| / (mu_s f_N)".into(),
        y_label: "|tau_n| / tau_max".into(),
        x: (0.0, 1.3),
        y: (0.0, 1.3),
        equal_scale: true,
        legend_at: Some(plotters::prelude::SeriesLabelPosition::UpperRight),
        ..Axes::default()
    };
    line_chart(path, 640, 600, &[(a, sr)])
}

/// `twist_sweep.svg`: the turn after settling against the external torque about the grasp axis,
/// torsion on and off, with the two contacts' combined torsional limit and the held line.
pub fn twist_sweep(
    path: &Path,
    on: &[SweepPoint],
    off: &[SweepPoint],
    combined_limit_nm: f64,
) -> Result<(), ChartError> {
    let floor = 1e-6;
    let to_pts = |v: &[SweepPoint]| {
        v.iter()
            .map(|p| (p.torque_nm * 1e3, p.rotation_rad.max(floor)))
            .collect()
    };
    let top = on
        .iter()
        .chain(off)
        .map(|p| p.rotation_rad)
        .fold(1.0, f64::max);
    let x_max = on
        .iter()
        .chain(off)
        .map(|p| p.torque_nm * 1e3)
        .fold(1.0, f64::max);
    let sr = vec![
        series(
            "torsion on (soft fingers)",
            0,
            Style::LineMarkers,
            to_pts(on),
        ),
        series(
            "torsion off (point contacts)",
            3,
            Style::LineMarkers,
            to_pts(off),
        ),
        series(
            "held below this turn",
            5,
            Style::Dotted,
            vec![(0.0, ROTATION_LIMIT_RAD), (x_max, ROTATION_LIMIT_RAD)],
        ),
        series(
            "2 tau_max (combined torsional limit)",
            2,
            Style::Dashed,
            vec![
                (combined_limit_nm * 1e3, floor),
                (combined_limit_nm * 1e3, top * 3.0),
            ],
        ),
    ];
    let a = Axes {
        title: "Torque about the grasp axis: soft fingers hold it up to their limit, point contacts never".into(),
        x_label: "external torque (mN·m)".into(),
        y_label: "turn after settling (rad, floor 1e-6)".into(),
        x: (0.0, x_max * 1.05),
        y: (floor * 0.5, top * 3.0),
        y_log: true,
        legend_at: Some(plotters::prelude::SeriesLabelPosition::LowerRight),
        ..Axes::default()
    };
    line_chart(path, 900, 560, &[(a, sr)])
}

/// The chart files of a run in `dir`.
pub fn write_all(dir: &Path, run: &GraspRun, hysteresis: f64) -> Result<Vec<PathBuf>, ChartError> {
    let files = [
        dir.join("pose.svg"),
        dir.join("contacts.svg"),
        dir.join("limit_surface.svg"),
    ];
    pose(&files[0], run)?;
    contacts(&files[1], run)?;
    limit_surface(&files[2], run, hysteresis)?;
    Ok(files.to_vec())
}
