//! Tables and charts of the four experiments.

use super::chatter::{self, ChatterRun};
use super::decomp_map::{self, Grid, MethodMap};
use super::drift::DriftRun;
use super::table::{sci, Table};
use crate::chart::bars::BarChart;
use crate::chart::heatmap::{heatmap, HeatPanel};
use crate::chart::lines::{line_chart, Axes, Series, Style};
use crate::chart::style::{method_color, PALETTE};
use crate::error::ChartError;
use crate::sim::backend::Backend;
use plotters::style::RGBColor;
use softfinger_core::contact::decompose::Method;
use std::path::Path;

/// Floor of the log error axes, rad (errors are clamped to it for display only).
pub const ERR_FLOOR: f64 = 1e-16;

fn backend_style(b: Backend) -> Style {
    match b {
        Backend::Libm => Style::Line,
        Backend::Fast => Style::Dashed,
        Backend::Micromath => Style::Dotted,
    }
}

// ---------------------------------------------------------------- part 1

/// `decomp_map.svg`, one panel per method (the worst of its math backends in each cell), and the
/// worst-error line chart.
pub fn decomp_charts(out: &Path, grid: &Grid, maps: &[MethodMap]) -> Result<(), ChartError> {
    let mags = grid.magnitudes();
    let tilts_deg: Vec<f64> = grid.tilts().iter().map(|t| t.to_degrees()).collect();
    let mut vmax = f64::NEG_INFINITY;
    let mut panels: Vec<HeatPanel> = Vec::new();
    for m in Method::ALL {
        let of_m: Vec<&MethodMap> = maps.iter().filter(|mm| mm.method == m).collect();
        let Some(first) = of_m.first() else {
            continue;
        };
        let cell = |iy: usize, ix: usize| {
            of_m.iter().fold((0.0f64, false), |(e, f), mm| {
                let c = &mm.cells[iy][ix];
                (e.max(c.worst_err), f || c.fail_frac > 0.0)
            })
        };
        let (ny, nx) = (first.cells.len(), first.cells.first().map_or(0, Vec::len));
        let value: Vec<Vec<f64>> = (0..ny)
            .map(|iy| {
                (0..nx)
                    .map(|ix| cell(iy, ix).0.max(ERR_FLOOR).log10())
                    .collect()
            })
            .collect();
        vmax = value.iter().flatten().copied().fold(vmax, f64::max);
        let backends: Vec<String> = of_m.iter().map(|mm| mm.backend.to_string()).collect();
        panels.push(HeatPanel {
            title: format!("{}: worst of {}", m.name(), backends.join(", ")),
            x_label: "rotation magnitude |w| (rad)".into(),
            y_label: "axis angle from the normal z (deg)".into(),
            x: &mags,
            y: &tilts_deg,
            value,
            failed: (0..ny)
                .map(|iy| (0..nx).map(|ix| cell(iy, ix).1).collect())
                .collect(),
        });
    }
    heatmap(
        &out.join("decomp_map.svg"),
        "Where does each decomposition fail? Worst error over the axis azimuths and math backends",
        &panels,
        ERR_FLOOR.log10(),
        if vmax.is_finite() { vmax } else { 0.0 },
        "error |angles - w|",
    )?;
    let mut series: Vec<Series> = maps
        .iter()
        .map(|mm| Series {
            label: format!("{} / {}", mm.method.name(), mm.backend),
            color: method_color(mm.method),
            style: backend_style(mm.backend),
            points: mags
                .iter()
                .zip(mm.worst_per_magnitude())
                .map(|(&x, e)| (x, e.max(ERR_FLOOR)))
                .collect(),
        })
        .collect();
    series.push(Series {
        label: "|w| (the error of skipping the step)".into(),
        color: RGBColor(120, 120, 120),
        style: Style::Dotted,
        points: mags.iter().map(|&x| (x, x)).collect(),
    });
    line_chart(
        &out.join("decomp_worst_error.svg"),
        1000,
        620,
        &[(
            Axes {
                title: "How large can each decomposition's error get? Worst over all axes (f32 vs nalgebra f64)".into(),
                x_label: "rotation magnitude |w| (rad)".into(),
                y_label: "worst error |(dpsi, dtheta, dphi) - w| (rad)".into(),
                x: (decomp_map::MAG_MIN, std::f64::consts::PI),
                y: crate::chart::style::log_range(
                    series.iter().flat_map(|s| s.points.iter().map(|p| p.1)),
                ),
                x_log: true,
                y_log: true,
                ..Axes::default()
            },
            series,
        )],
    )
}

/// Per method × backend and magnitude decade: worst error and failure fraction.
pub fn decomp_table(grid: &Grid, maps: &[MethodMap]) -> Table {
    let mags = grid.magnitudes();
    let dec = decomp_map::decades();
    let mut header = vec!["method / backend".to_string()];
    header.extend(dec.iter().map(|d| format!("|w| {}", d.2)));
    let mut t = Table {
        title: format!(
            "Part 1. Decomposition: worst error (rad) / fraction flagged, per |w| decade \
             ({} magnitudes incl. pi/2 x {} axis tilts x {} azimuths)",
            mags.len(),
            grid.n_tilt,
            grid.n_az
        ),
        header,
        rows: Vec::new(),
    };
    for mm in maps {
        let mut row = vec![format!("{} / {}", mm.method.name(), mm.backend)];
        for (lo, hi, _) in &dec {
            row.push(match mm.summary(&mags, *lo, *hi) {
                Some((w, f)) => format!("{} / {:.0}%", sci(w), 100.0 * f),
                None => "-".into(),
            });
        }
        t.row(row);
    }
    t
}

/// Where each method × backend is flagged, and its largest error.
pub fn decomp_failures(grid: &Grid, maps: &[MethodMap]) -> String {
    let mags = grid.magnitudes();
    let tilts = grid.tilts();
    let mut s = String::from("Where each method fails (flagged cells; worst error and where):\n");
    for mm in maps {
        let mut flagged = 0usize;
        let (mut mlo, mut mhi) = (f64::INFINITY, 0.0f64);
        let mut tilt_set: Vec<f64> = Vec::new();
        let (mut worst, mut at) = (0.0f64, (0.0, 0.0));
        let mut small_tilt_all = true;
        for (i, row) in mm.cells.iter().enumerate() {
            for (j, c) in row.iter().enumerate() {
                if c.fail_frac > 0.0 {
                    flagged += 1;
                    mlo = mlo.min(mags[j]);
                    mhi = mhi.max(mags[j]);
                    let d = tilts[i].to_degrees().round();
                    if !tilt_set.contains(&d) {
                        tilt_set.push(d);
                    }
                }
                if c.worst_err > worst {
                    worst = c.worst_err;
                    at = (mags[j], tilts[i].to_degrees());
                }
            }
            if row[0].fail_frac < 1.0 {
                small_tilt_all = false;
            }
        }
        let total = mm.cells.len() * mags.len();
        s += &format!(
            "  {:>14} / {:<9}: {:>4}/{} cells flagged",
            mm.method.name(),
            mm.backend,
            flagged,
            total
        );
        if flagged > 0 {
            tilt_set.sort_by(f64::total_cmp);
            let tl = if tilt_set.len() > 6 {
                format!(
                    "{} tilts from {}° to {}°",
                    tilt_set.len(),
                    tilt_set[0],
                    tilt_set[tilt_set.len() - 1]
                )
            } else {
                format!("tilts {:?}°", tilt_set)
            };
            s += &format!(" (|w| {} .. {}, {tl}", sci(mlo), sci(mhi));
            if small_tilt_all {
                s += "; every axis at |w| = 1e-7";
            }
            s += ")";
        }
        s += &format!(
            "; worst error {} rad at |w| = {}, tilt {:.0}°\n",
            sci(worst),
            sci(at.0),
            at.1
        );
    }
    s
}

// ---------------------------------------------------------------- part 2

pub fn drift_charts(out: &Path, runs: &[DriftRun]) -> Result<(), ChartError> {
    let floor = 1e-10; // mm
    let tmax = runs
        .iter()
        .flat_map(|r| r.series.last().map(|p| p.0))
        .fold(0.0, f64::max)
        .max(1e-3);
    let mk = |finger: bool| -> Vec<Series> {
        runs.iter()
            .map(|r| Series {
                label: format!("{} / {}", r.method.name(), r.backend),
                color: method_color(r.method),
                style: backend_style(r.backend),
                points: r
                    .series
                    .iter()
                    .map(|&(t, p, f)| (t, (if finger { f } else { p } * 1e3).max(floor)))
                    .collect(),
            })
            .collect()
    };
    let ymax = runs
        .iter()
        .map(|r| r.max_plane_m.max(r.max_finger_m) * 1e3)
        .fold(1e-6, f64::max)
        * 10.0;
    let axes = |title: &str| Axes {
        title: title.into(),
        x_label: "time (s), 10 kHz steps".into(),
        y_label: "error vs f64 closed form (mm), max per block".into(),
        x: (0.0, tmax),
        y: (floor, ymax),
        y_log: true,
        ..Axes::default()
    };
    line_chart(
        &out.join("drift.svg"),
        760,
        560,
        &[
            (
                axes("Does f32 drift over a long run? Plane contact point"),
                mk(false),
            ),
            (
                axes("Does f32 drift over a long run? Fingertip contact point"),
                mk(true),
            ),
        ],
    )
}

pub fn drift_table(runs: &[DriftRun]) -> Table {
    let steps = runs.first().map_or(0, |r| r.steps);
    let mut t = Table::new(
        &format!(
            "Part 2. Drift over {} steps at 10 kHz ({} s), rho = 10 mm, f32 core vs f64 closed form (mm)",
            steps,
            steps as f64 / super::drift::RATE_HZ
        ),
        &[
            "method / backend",
            "plane max",
            "plane final",
            "fingertip max",
            "fingertip final",
        ],
    );
    for r in runs {
        t.row(vec![
            format!("{} / {}", r.method.name(), r.backend),
            sci(r.max_plane_m * 1e3),
            sci(r.final_plane_m * 1e3),
            sci(r.max_finger_m * 1e3),
            sci(r.final_finger_m * 1e3),
        ]);
    }
    t
}

// ---------------------------------------------------------------- part 4

fn chatter_group(single_mu: bool, h: f32) -> String {
    format!(
        "h = {h}, {}",
        if single_mu {
            "mu_k = mu_s = 0.8"
        } else {
            "mu_k = 0.6, mu_s = 0.8"
        }
    )
}

pub fn chatter_chart(out: &Path, runs: &[ChatterRun]) -> Result<(), ChartError> {
    let cats: Vec<String> = chatter::NOISE_LEVELS
        .iter()
        .map(|a| format!("±{:.0}%", a * 100.0))
        .collect();
    let mut groups = Vec::new();
    let mut values = Vec::new();
    let mut i = 0;
    for single_mu in [false, true] {
        for h in chatter::HYSTERESES {
            groups.push((chatter_group(single_mu, h), PALETTE[i % PALETTE.len()]));
            values.push(
                chatter::NOISE_LEVELS
                    .iter()
                    .map(|&a| {
                        runs.iter()
                            .find(|r| r.single_mu == single_mu && r.hysteresis == h && r.noise == a)
                            .map_or(0.0, |r| r.per_s)
                    })
                    .collect(),
            );
            i += 1;
        }
    }
    // The log axis sized to the data: from the floor to the decade above the largest rate.
    let top = values.iter().flatten().copied().fold(1.0f64, f64::max);
    let y_top = 10f64.powf((top * 3.0).log10().ceil());
    BarChart {
        title: "Does the state machine chatter with f_T held on the static cone? Transitions per second (10 kHz)",
        x_label: "noise amplitude on f_T (uniform, fraction of mu_s f_N)",
        y_label: "transitions per second",
        categories: &cats,
        groups: &groups,
        values: &values,
        y_range: (0.05, y_top),
    }
    .write(&out.join("chatter.svg"))
}

pub fn chatter_table(runs: &[ChatterRun], steps: u64) -> Table {
    let mut t = Table::new(
        &format!(
            "Part 4. Chatter: f_T = mu_s f_N (1 + a u), u uniform in [-1, 1], f_N = 2 N, {} steps at 10 kHz ({} s)",
            steps,
            steps as f64 / chatter::RATE_HZ
        ),
        &["friction, hysteresis", "noise a", "transitions", "per s", "sliding"],
    );
    for r in runs {
        t.row(vec![
            chatter_group(r.single_mu, r.hysteresis),
            format!("±{:.0}%", r.noise * 100.0),
            format!("{}", r.transitions),
            format!("{:.1}", r.per_s),
            format!("{:.1}%", r.sliding_frac * 100.0),
        ]);
    }
    t
}
