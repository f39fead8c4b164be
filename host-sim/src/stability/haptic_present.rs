//! Tables, charts and the JSON figures of part 3 (haptic stability of the virtual wall).

use super::charts::{self, Axes, Series, Style};
use super::haptic::TraceSample;
use super::haptic::{self, Device, RateRow};
use super::haptic_device::DeviceRow;
use super::haptic_timing::{Impact, TimingRow, IMPACT_SECONDS, IMPACT_SPEED};
use super::present::PALETTE;
use super::table::Table;
use plotters::style::RGBColor;
use std::path::Path;

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

/// K_max over 2b/T against the control rate: one tick of delay, the firmware's timing, with the
/// passivity stage (measured markers; eigenvalue lines where they exist).
pub fn timing_chart(out: &Path, d: &Device, rows: &[TimingRow]) -> Result<(), String> {
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
    let series = vec![
        pts(
            "one tick of delay (measured)",
            red,
            Style::LineMarkers,
            &|r| r.measured_one_tick,
        ),
        pts(
            "firmware timing, 40 kHz PWM (measured)",
            blue,
            Style::LineMarkers,
            &|r| r.measured_firmware,
        ),
        pts(
            "firmware timing (eigenvalue limit)",
            blue,
            Style::Dashed,
            &|r| r.eigen_firmware,
        ),
        pts(
            "firmware timing + passivity controller (measured; none = stable to 1e6 N/m)",
            green,
            Style::LineMarkers,
            &|r| r.measured_passivity,
        ),
    ];
    charts::line_chart(
        &out.join("haptic_kmax_timing.svg"),
        1000,
        640,
        &[(
            Axes {
                title: format!(
                    "Largest passive wall / (2b/T) vs control rate (m = {} kg, b = {} N s/m)",
                    d.mass_kg, d.damping
                ),
                x_label: "control rate 1/T (Hz)".into(),
                y_label: "K_max / (2b/T)".into(),
                x: (900.0, 22_000.0),
                y: (0.1, 100.0),
                x_log: true,
                y_log: true,
            },
            series,
        )],
    )
}

/// Position and force against time for the fast impact, without and with passivity.
pub fn impact_chart(out: &Path, imp: &Impact) -> Result<(), String> {
    let (red, green) = (PALETTE[3], PALETTE[2]);
    let s = |label: &str, color, tr: &[TraceSample], get: &dyn Fn(&TraceSample) -> f64| Series {
        label: label.into(),
        color,
        style: Style::Line,
        points: tr.iter().map(|p| (p.time_s * 1e3, get(p))).collect(),
    };
    let clamp = |v: f64, lim: f64| v.clamp(-lim, lim);
    let x_lim = 4.0 * imp.ideal_peak_n / imp.stiffness * 1e3;
    let f_lim = 4.0 * imp.ideal_peak_n;
    let title = |what: &str| {
        format!(
            "{what}: wall {:.0} N/mm hit at {} m/s, {} kHz, delay {:.2} tick",
            imp.stiffness / 1e3,
            IMPACT_SPEED,
            imp.rate_hz / 1e3,
            imp.delay_ticks
        )
    };
    let pos = |p: &TraceSample| clamp(p.x_m * 1e3, x_lim);
    let force = |p: &TraceSample| clamp(-p.force_n, f_lim);
    let ms = (0.0, IMPACT_SECONDS * 1e3);
    charts::line_chart(
        &out.join("haptic_impact.svg"),
        800,
        560,
        &[
            (
                Axes {
                    title: title("Penetration"),
                    x_label: "time (ms)".into(),
                    y_label: format!("penetration x (mm, clipped at ±{x_lim:.2})"),
                    x: ms,
                    y: (-x_lim, x_lim),
                    x_log: false,
                    y_log: false,
                },
                vec![
                    s("without passivity", red, &imp.without, &pos),
                    s("with passivity", green, &imp.with, &pos),
                ],
            ),
            (
                Axes {
                    title: title("Wall force"),
                    x_label: "time (ms)".into(),
                    y_label: format!(
                        "force on the probe, out of the wall (N, clipped at ±{f_lim:.1})"
                    ),
                    x: ms,
                    y: (-f_lim, f_lim),
                    x_log: false,
                    y_log: false,
                },
                vec![
                    s("without passivity", red, &imp.without, &force),
                    s("with passivity", green, &imp.with, &force),
                ],
            ),
        ],
    )
}

/// The firmware-timing table.
pub fn timing_table(d: &Device, rows: &[TimingRow], duration_s: f64) -> Table {
    let mut t = Table::new(
        &format!(
            "Part 3b. Largest passive wall at the firmware timing (40 kHz PWM, compare written at once), m = {} kg, b = {} N s/m, {} s per run; x = K_max / (2b/T)",
            d.mass_kg, d.damping, duration_s
        ),
        &[
            "rate (kHz)",
            "delay (ticks)",
            "x one tick",
            "x firmware",
            "x eigen firmware",
            "x with passivity",
            "3x wall: without",
            "3x wall: with passivity (peak E / hit E)",
        ],
    );
    let x = |v: Option<f64>, b: f64| v.map_or("-".to_string(), |k| format!("{:.3}", k / b));
    for r in rows {
        let (without, with) = match &r.at_multiple {
            Some((_, a, b)) => (
                if a.stable { "stable" } else { "unstable" }.to_string(),
                format!(
                    "{} ({:.2})",
                    if r.passivity_bounded() == Some(true) {
                        "bounded"
                    } else {
                        "NOT bounded"
                    },
                    b.peak_j / b.hit_j
                ),
            ),
            None => ("-".into(), "-".into()),
        };
        t.row(vec![
            format!("{}", r.rate_hz / 1e3),
            format!("{:.3}", r.delay_ticks),
            x(r.measured_one_tick, r.bound),
            x(r.measured_firmware, r.bound),
            x(r.eigen_firmware, r.bound),
            r.measured_passivity
                .map_or("> 1e6 N/m".to_string(), |k| format!("{:.1}", k / r.bound)),
            without,
            with,
        ]);
    }
    t
}

/// The impact's figures in words.
pub fn impact_notes(imp: &Impact) -> String {
    format!(
        "Fast impact ({} m/s) on a {:.0} N/m wall (3x the largest passive one) at {} kHz: peak force {:.2} N with passivity, \
         {:.2} N without (unstable, {} ms shown), ideal continuous spring {:.2} N: overshoot {:+.1} % with passivity.\n",
        IMPACT_SPEED,
        imp.stiffness,
        imp.rate_hz / 1e3,
        Impact::peak_n(&imp.with),
        Impact::peak_n(&imp.without),
        IMPACT_SECONDS * 1e3,
        imp.ideal_peak_n,
        100.0 * imp.overshoot_with()
    )
}

/// The `haptic` member of `host-sim stability --json`.
#[derive(Clone, Debug, serde::Serialize)]
pub struct HapticJson {
    pub rates_hz: Vec<f64>,
    /// Sample-to-output delay of the firmware timing, ticks.
    pub firmware_delay_ticks: Vec<f64>,
    /// Measured largest passive wall over 2b/T, one tick of delay.
    pub kmax_over_bound_one_tick: Vec<Option<f64>>,
    /// Measured largest passive wall over 2b/T at the firmware timing.
    pub kmax_over_bound_firmware_timing: Vec<Option<f64>>,
    /// Measured largest stable wall over 2b/T with the passivity stage (null: stable to 1e6 N/m).
    pub kmax_over_bound_passivity: Vec<Option<f64>>,
    /// The 3x wall with passivity is bounded at every rate.
    pub passivity_3x_bounded: bool,
    /// Peak oscillation energy over the hit's, 3x wall with passivity, per rate.
    pub passivity_3x_peak_energy_over_hit: Vec<Option<f64>>,
    /// Fast impact at 10 kHz: peak force with passivity over the ideal spring's, minus one.
    pub impact_overshoot_with_passivity: f64,
    /// The same walls in closed loop with the device plant.
    pub device_plant: Vec<DeviceRow>,
    /// The default scene with the stage on vs observing only.
    pub default_scene: Option<super::passivity_scene::SceneDifference>,
}

/// The JSON figures of part 3.
pub fn haptic_json(rows: &[TimingRow], imp: &Impact, device_plant: Vec<DeviceRow>) -> HapticJson {
    let ratio = |f: &dyn Fn(&TimingRow) -> Option<f64>| {
        rows.iter().map(|r| f(r).map(|k| k / r.bound)).collect()
    };
    HapticJson {
        rates_hz: rows.iter().map(|r| r.rate_hz).collect(),
        firmware_delay_ticks: rows.iter().map(|r| r.delay_ticks).collect(),
        kmax_over_bound_one_tick: ratio(&|r| r.measured_one_tick),
        kmax_over_bound_firmware_timing: ratio(&|r| r.measured_firmware),
        kmax_over_bound_passivity: ratio(&|r| r.measured_passivity),
        passivity_3x_bounded: !rows.is_empty()
            && rows.iter().all(|r| r.passivity_bounded() == Some(true)),
        passivity_3x_peak_energy_over_hit: rows
            .iter()
            .map(|r| r.at_multiple.as_ref().map(|(_, _, b)| b.peak_j / b.hit_j))
            .collect(),
        impact_overshoot_with_passivity: imp.overshoot_with(),
        device_plant,
        default_scene: None,
    }
}

/// The device-plant table.
pub fn device_table(rows: &[DeviceRow]) -> Table {
    let mut t = Table::new(
        "Part 3c. Largest passive wall in closed loop with the device plant (plane, contact damping 0, ~1 N push; settled = last 0.1 s within one encoder count, 13 um)",
        &[
            "rate (kHz)",
            "delay (ticks)",
            "K_max one tick (N/m)",
            "K_max firmware (N/m)",
            "gain",
            "3x wall p-p without (um)",
            "3x wall p-p with passivity (um)",
            "settled with passivity",
            "3x with passivity, p-p first / last 0.1 s of 2 s (um)",
            "L ~ 0: K_max one tick / firmware (N/m)",
            "L ~ 0: 3x settled with passivity",
        ],
    );
    let k = |v: Option<f64>| v.map_or("-".to_string(), |k| format!("{k:.0}"));
    let um = |v: Option<f64>| v.map_or("-".to_string(), |a| format!("{:.1}", a * 1e6));
    for r in rows {
        let gain = match (r.kmax_firmware_timing, r.kmax_one_tick) {
            (Some(a), Some(b)) => format!("{:.2}", a / b),
            _ => "-".into(),
        };
        t.row(vec![
            format!("{}", r.rate_hz / 1e3),
            format!("{:.3}", r.firmware_delay_ticks),
            k(r.kmax_one_tick),
            k(r.kmax_firmware_timing),
            gain,
            um(r.passivity_3x_late_amp_without_m),
            um(r.passivity_3x_late_amp_with_m),
            r.passivity_3x_stable.map_or("-".into(), |s| s.to_string()),
            match r.passivity_3x_envelope_with_m.as_deref() {
                Some([first, .., last]) => format!("{} / {}", um(Some(*first)), um(Some(*last))),
                _ => "-".into(),
            },
            format!(
                "{} / {}",
                k(r.no_lag_kmax_one_tick),
                k(r.no_lag_kmax_firmware_timing)
            ),
            r.no_lag_passivity_3x_stable
                .map_or("-".into(), |s| s.to_string()),
        ]);
    }
    t
}
