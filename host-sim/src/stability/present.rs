//! Tables and charts of the four experiments.

use super::charts::{self, Axes, HeatPanel, Series, Style};
use super::chatter::{self, ChatterRun};
use super::decomp_map::{self, Grid, MethodMap};
use super::drift::DriftRun;
use super::haptic::{self, Device, RateRow};
use super::table::{sci, Table};
use plotters::style::RGBColor;
use softfinger_core::decompose::Method;
use std::path::Path;

/// Floor of the log error axes, rad (errors are clamped to it for display only).
pub const ERR_FLOOR: f64 = 1e-16;

fn method_color(m: Method) -> RGBColor {
    match m {
        Method::PaperVerbatim => RGBColor(214, 39, 40),
        Method::Rpy => RGBColor(31, 119, 180),
        Method::Exact => RGBColor(44, 160, 44),
    }
}

fn backend_style(b: &str) -> Style {
    match b {
        "libm" => Style::Line,
        "fast" => Style::Dashed,
        _ => Style::Dotted,
    }
}

const PALETTE: [RGBColor; 5] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
];

// ---------------------------------------------------------------- part 1

/// One heatmap SVG per method (a panel per backend) and the worst-error line chart.
pub fn decomp_charts(out: &Path, grid: &Grid, maps: &[MethodMap]) -> Result<(), String> {
    let mags = grid.magnitudes();
    let tilts_deg: Vec<f64> = grid.tilts().iter().map(|t| t.to_degrees()).collect();
    for m in Method::ALL {
        let panels: Vec<HeatPanel> = maps
            .iter()
            .filter(|mm| mm.method == m)
            .map(|mm| HeatPanel {
                title: format!("{} / {}: worst over azimuths", m.name(), mm.backend),
                x_label: "rotation magnitude |w| (rad)".into(),
                y_label: "axis angle from the normal z (deg)".into(),
                x: &mags,
                y: &tilts_deg,
                value: mm
                    .cells
                    .iter()
                    .map(|r| {
                        r.iter()
                            .map(|c| c.worst_err.max(ERR_FLOOR).log10())
                            .collect()
                    })
                    .collect(),
                failed: mm
                    .cells
                    .iter()
                    .map(|r| r.iter().map(|c| c.fail_frac > 0.0).collect())
                    .collect(),
            })
            .collect();
        charts::heatmap(
            &out.join(format!("decomp_map_{}.svg", m.name())),
            &panels,
            ERR_FLOOR.log10(),
            1.0,
            "log10 error |angles - w| (rad)",
        )?;
    }
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
    charts::line_chart(
        &out.join("decomp_worst_error.svg"),
        1000,
        620,
        &[(
            Axes {
                title: "Worst decomposition error over all axes (f32 vs nalgebra f64)".into(),
                x_label: "rotation magnitude |w| (rad)".into(),
                y_label: "worst error |(dpsi, dtheta, dphi) - w| (rad)".into(),
                x: (decomp_map::MAG_MIN, std::f64::consts::PI),
                y: (ERR_FLOOR, 100.0),
                x_log: true,
                y_log: true,
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

pub fn drift_charts(out: &Path, runs: &[DriftRun]) -> Result<(), String> {
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
        x_log: false,
        y_log: true,
    };
    charts::line_chart(
        &out.join("drift.svg"),
        760,
        560,
        &[
            (axes("Plane contact point drift (f32)"), mk(false)),
            (axes("Fingertip contact point drift (f32)"), mk(true)),
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

// ---------------------------------------------------------------- part 3

pub fn haptic_charts(out: &Path, d: &Device, rows: &[RateRow]) -> Result<(), String> {
    let fine: Vec<f64> = (0..=40)
        .map(|i| 1_000.0 * 20f64.powf(i as f64 / 40.0))
        .collect();
    let line = |label: &str, color, style, f: &dyn Fn(f64) -> f64| Series {
        label: label.into(),
        color,
        style,
        points: fine.iter().map(|&r| (r, f(1.0 / r))).collect(),
    };
    let pts = |label: &str, color, get: &dyn Fn(&RateRow) -> Option<f64>| Series {
        label: label.into(),
        color,
        style: Style::Markers,
        points: rows
            .iter()
            .filter_map(|r| get(r).map(|k| (r.rate_hz, k)))
            .collect(),
    };
    let b = d.damping;
    let black = RGBColor(0, 0, 0);
    let (blue, red) = (PALETTE[0], PALETTE[3]);
    let eig = |delay: f64| {
        move |t: f64| {
            haptic::eigen_kmax(&haptic::Loop::wall(*d, 1.0 / t, delay, 0.0)).unwrap_or(f64::NAN)
        }
    };
    let series = vec![
        line(
            "Colgate-Schenkel passivity bound 2b/T",
            black,
            Style::Line,
            &|t| haptic::colgate_kmax(b, 0.0, t),
        ),
        line("eigenvalue limit, no delay", blue, Style::Dashed, &eig(0.0)),
        pts("measured (simulation), no delay", blue, &|r| {
            r.measured_no_delay
        }),
        line(
            "estimate 2b/(3T) with one tick delay",
            black,
            Style::Dotted,
            &|t| haptic::delayed_estimate_kmax(b, 0.0, t, t),
        ),
        line(
            "eigenvalue limit, one tick delay",
            red,
            Style::Dashed,
            &eig(1.0),
        ),
        pts("measured (simulation), one tick delay", red, &|r| {
            r.measured_delay
        }),
    ];
    charts::line_chart(
        &out.join("haptic_kmax.svg"),
        1000,
        640,
        &[(
            Axes {
                title: format!(
                    "Virtual wall K_max vs control rate (m = {} kg, b = {} N s/m, B = 0)",
                    d.mass_kg, d.damping
                ),
                x_label: "control rate 1/T (Hz)".into(),
                y_label: "largest stable wall stiffness K_max (N/m)".into(),
                x: (900.0, 22_000.0),
                y: (1e3, 2e5),
                x_log: true,
                y_log: true,
            },
            series,
        )],
    )?;
    // Energy ratio late/early over the K sweep, per rate, both delays.
    let panel = |delay: usize| {
        let s: Vec<Series> = rows
            .iter()
            .enumerate()
            .map(|(i, r)| Series {
                label: format!("{} kHz", r.rate_hz / 1e3),
                color: PALETTE[i % PALETTE.len()],
                style: Style::LineMarkers,
                points: r.sweeps[delay]
                    .iter()
                    .map(|(k, o)| {
                        // Decayed to rounding (both windows may then hold noise): the floor.
                        let ratio = if o.late_j < haptic::ENERGY_FLOOR * o.hit_j {
                            1e-12
                        } else if o.early_j > 0.0 {
                            o.late_j / o.early_j
                        } else {
                            f64::NAN
                        };
                        (*k, ratio.clamp(1e-12, 1e6))
                    })
                    .collect(),
            })
            .collect();
        (
            Axes {
                title: format!(
                    "Energy late / early after a wall hit, {}",
                    if delay == 0 {
                        "no delay"
                    } else {
                        "one tick delay"
                    }
                ),
                x_label: "wall stiffness K (N/m)".into(),
                y_label: "energy ratio late/early (< 0.5 stable; 1e-12: decayed)".into(),
                x: (haptic::K_SWEEP.0, haptic::K_SWEEP.1),
                y: (1e-12, 1e6),
                x_log: true,
                y_log: true,
            },
            s,
        )
    };
    charts::line_chart(
        &out.join("haptic_energy.svg"),
        700,
        560,
        &[panel(0), panel(1)],
    )
}

pub fn haptic_table(d: &Device, rows: &[RateRow], duration_s: f64) -> Table {
    let mut t = Table::new(
        &format!(
            "Part 3. Virtual wall K_max (N/m): m = {} kg, b = {} N s/m, B = 0, user push {} N, hit at {} m/s, {} s per run",
            d.mass_kg, d.damping, d.user_force_n, d.hit_speed, duration_s
        ),
        &[
            "rate (kHz)",
            "Colgate 2b/T",
            "eigen, no delay",
            "measured, no delay",
            "meas/Colgate",
            "eigen, 1 tick",
            "measured, 1 tick",
            "2b/(3T)",
            "meas 1 tick/Colgate",
        ],
    );
    let o = |v: Option<f64>| v.map_or("none".to_string(), |k| format!("{k:.0}"));
    for r in rows {
        let ratio = |v: Option<f64>| v.map_or("-".to_string(), |k| format!("{:.3}", k / r.colgate));
        t.row(vec![
            format!("{}", r.rate_hz / 1e3),
            format!("{:.0}", r.colgate),
            o(r.eigen_no_delay),
            o(r.measured_no_delay),
            ratio(r.measured_no_delay),
            o(r.eigen_delay),
            o(r.measured_delay),
            format!("{:.0}", r.estimate_delay),
            ratio(r.measured_delay),
        ]);
    }
    t
}

/// The detection's resolution, in words and numbers.
pub fn haptic_notes(d: &Device, duration_s: f64) -> String {
    let mut s = String::from(
        "Detection: stable when the oscillation energy over the last 10 % of the run is below half its \
         maximum over [40 %, 50 %) (or below 1e-12 of the hit's energy); K_max by a 81-point log sweep over 1e2..1e6 N/m then bisection to \
         0.5 %. Criterion threshold vs the exact eigenvalue limit (linear regime), per rate:\n",
    );
    for rate in haptic::RATES_HZ {
        for delay in [0.0, 1.0] {
            let l = haptic::Loop::wall(*d, rate, delay, 0.0);
            if let (Some(e), Some(c)) = (
                haptic::eigen_kmax(&l),
                haptic::criterion_kmax(&l, duration_s),
            ) {
                s += &format!(
                    "  {:>4} kHz, delay {}: criterion switches at {:.0} N/m, {:.3} % below the limit {:.0}\n",
                    rate / 1e3,
                    delay,
                    c,
                    100.0 * (1.0 - c / e),
                    e
                );
            }
        }
    }
    s
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

pub fn chatter_chart(out: &Path, runs: &[ChatterRun]) -> Result<(), String> {
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
    charts::bar_chart(
        &out.join("chatter.svg"),
        "State-machine transitions with f_T held on the static cone (10 kHz)",
        "noise amplitude on f_T (uniform, fraction of mu_s f_N)",
        "transitions per second",
        &cats,
        &groups,
        &values,
        (0.05, 1e6),
    )
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
