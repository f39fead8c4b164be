//! Charts of part 3 (haptic stability of the virtual wall): K_max against the control rate,
//! the energy ratio over the stiffness sweep, K_max against the delay and the impact trace.

use super::haptic::TraceSample;
use super::haptic::{self, Device, RateRow};
use super::haptic_timing::{Impact, TimingRow, IMPACT_SPEED};
use crate::chart::lines::{line_chart, Axes, Series, Style};
use crate::chart::style::PALETTE;
use crate::error::ChartError;
use plotters::style::RGBColor;
use std::path::Path;

pub fn haptic_charts(out: &Path, d: &Device, rows: &[RateRow]) -> Result<(), ChartError> {
    kmax_chart(out, d, rows)?;
    energy_chart(out, rows)
}

/// haptic_kmax.svg: K_max against the control rate, the bounds and eigenvalue limits as lines and
/// the simulated values as markers, without and with one tick of delay.
fn kmax_chart(out: &Path, d: &Device, rows: &[RateRow]) -> Result<(), ChartError> {
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
    let title = format!(
        "How stiff can a sampled wall be? K_max vs control rate (m = {} kg, b = {} N s/m, B = 0)",
        d.mass_kg, d.damping
    );
    let axes = rate_axes(
        title,
        "largest stable wall stiffness K_max (N/m)",
        (1e3, 2e5),
    );
    line_chart(&out.join("haptic_kmax.svg"), 1000, 640, &[(axes, series)])
}

/// The log-log axes of a K_max chart against the control rate (0.9 to 22 kHz).
fn rate_axes(title: String, y_label: &str, y: (f64, f64)) -> Axes {
    Axes {
        title,
        x_label: "control rate 1/T (Hz)".into(),
        y_label: y_label.into(),
        x: (900.0, 22_000.0),
        y,
        x_log: true,
        y_log: true,
        ..Axes::default()
    }
}

/// haptic_energy.svg: energy ratio late/early over the K sweep, per rate, both delays.
fn energy_chart(out: &Path, rows: &[RateRow]) -> Result<(), ChartError> {
    line_chart(
        &out.join("haptic_energy.svg"),
        700,
        560,
        &[energy_panel(rows, 0), energy_panel(rows, 1)],
    )
}

/// One panel of haptic_energy.svg; `delay`: 0 no delay, 1 one tick.
fn energy_panel(rows: &[RateRow], delay: usize) -> (Axes, Vec<Series>) {
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
                "Does a wall hit gain energy? Late / early energy, {}",
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
            ..Axes::default()
        },
        s,
    )
}

/// K_max over 2b/T against the control rate: one tick of delay, the firmware's timing, with the
/// passivity stage (measured markers; eigenvalue lines where they exist).
pub fn timing_chart(out: &Path, d: &Device, rows: &[TimingRow]) -> Result<(), ChartError> {
    let pts = |label: &str, color, style, get: &dyn Fn(&TimingRow) -> Option<f64>| Series {
        label: label.into(),
        color,
        style,
        points: rows
            .iter()
            .filter_map(|r| get(r).map(|k| (r.rate_hz, k / r.bound)))
            .collect(),
    };
    let (blue, red, green) = (PALETTE[0], PALETTE[3], PALETTE[2]);
    type Get = fn(&TimingRow) -> Option<f64>;
    let table: [(&str, RGBColor, Style, Get); 4] = [
        (
            "one tick of delay (measured)",
            red,
            Style::LineMarkers,
            |r| r.measured_one_tick,
        ),
        (
            "firmware timing, 40 kHz PWM (measured)",
            blue,
            Style::LineMarkers,
            |r| r.measured_firmware,
        ),
        (
            "firmware timing (eigenvalue limit)",
            blue,
            Style::Dashed,
            |r| r.eigen_firmware,
        ),
        (
            "firmware timing + passivity controller (measured; none = stable to 1e6 N/m)",
            green,
            Style::LineMarkers,
            |r| r.measured_passivity,
        ),
    ];
    let mut series: Vec<Series> = table
        .iter()
        .map(|&(label, color, style, get)| pts(label, color, style, &get))
        .collect();
    series.push(Series {
        label: "1/3: the estimate 2b/(3T) with one tick of delay".into(),
        color: RGBColor(0, 0, 0),
        style: Style::Dotted,
        points: vec![(900.0, 1.0 / 3.0), (22_000.0, 1.0 / 3.0)],
    });
    let title = format!(
        "How stiff a wall stays passive at the firmware's timing? K_max / (2b/T) vs control rate (m = {} kg, b = {} N s/m)",
        d.mass_kg, d.damping
    );
    // Sized to the data (a decade-only log axis would have no tick between 0.1 and 1).
    let ys = series.iter().flat_map(|s| s.points.iter().map(|p| p.1));
    let (lo, hi) = ys
        .filter(|v| v.is_finite() && *v > 0.0)
        .fold((f64::INFINITY, 0.0f64), |(a, b), v| (a.min(v), b.max(v)));
    let y = if lo <= hi {
        (lo / 1.4, hi * 1.4)
    } else {
        (0.1, 10.0)
    };
    let mut axes = rate_axes(title, "K_max / (2b/T)", y);
    axes.y_ticks = [0.2, 1.0 / 3.0, 0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 50.0]
        .into_iter()
        .filter(|t| *t >= y.0 && *t <= y.1)
        .collect();
    line_chart(
        &out.join("haptic_kmax_timing.svg"),
        1000,
        640,
        &[(axes, series)],
    )
}

/// Length of the impact chart's traces, s: long enough for the run without the passivity stage
/// to show where it goes (the figures' traces, `haptic_timing::IMPACT_SECONDS`, are 0.1 s).
pub const IMPACT_CHART_SECONDS: f64 = 1.0;

/// Position and force against time for the fast impact, without and with passivity, over
/// [`IMPACT_CHART_SECONDS`] (the same runs as `imp`, continued), axes sized to the data.
pub fn impact_chart(out: &Path, d: &Device, imp: &Impact) -> Result<(), ChartError> {
    let trace = |pc| {
        let mut v = Vec::new();
        let l = super::haptic_timing::firmware_loop(d, imp.rate_hz, imp.delay_ticks, pc);
        haptic::run_wall(&l, imp.stiffness, IMPACT_SPEED, IMPACT_CHART_SECONDS, |s| {
            v.push(s)
        });
        v
    };
    let (without, with) = (trace(false), trace(true));
    let (red, green) = (PALETTE[3], PALETTE[2]);
    let s = |label: &str, color, tr: &[TraceSample], get: &dyn Fn(&TraceSample) -> f64| Series {
        label: label.into(),
        color,
        style: Style::Line,
        points: tr
            .iter()
            .step_by((tr.len() / 4000).max(1))
            .map(|p| (p.time_s * 1e3, get(p)))
            .collect(),
    };
    let title = |what: &str| {
        format!(
            "{what}: wall {:.0} N/mm hit at {} m/s, {} kHz, delay {:.2} tick",
            imp.stiffness / 1e3,
            IMPACT_SPEED,
            imp.rate_hz / 1e3,
            imp.delay_ticks
        )
    };
    let pos = |p: &TraceSample| p.x_m * 1e3;
    let force = |p: &TraceSample| -p.force_n;
    let panel = |what: &str, y_label: &str, get: &dyn Fn(&TraceSample) -> f64| {
        let series = vec![
            s("without passivity", red, &without, get),
            s("with passivity", green, &with, get),
        ];
        let axes = Axes {
            title: title(what),
            x_label: "time after the hit (ms)".into(),
            y_label: y_label.into(),
            x: (0.0, IMPACT_CHART_SECONDS * 1e3),
            y: crate::chart::style::linear_range(
                series.iter().flat_map(|s| s.points.iter().map(|p| p.1)),
                0.01,
                0.0,
            ),
            ..Axes::default()
        };
        (axes, series)
    };
    crate::chart::lines::stacked_chart(
        &out.join("haptic_impact.svg"),
        1100,
        380,
        &[
            panel(
                "Does the hit settle? Penetration",
                "x (mm; > 0 inside the wall, < 0 bounced off)",
                &pos,
            ),
            panel(
                "Wall force",
                "force on the probe, out of the wall (N)",
                &force,
            ),
        ],
    )
}
