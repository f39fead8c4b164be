//! Tables, notes and the JSON figures of part 3 (haptic stability of the virtual wall); its charts
//! are in `haptic_charts`.

use super::haptic::{self, Device, RateRow};
use super::haptic_device::DeviceRow;
use super::haptic_timing::{Impact, TimingRow, IMPACT_SECONDS, IMPACT_SPEED};
use super::table::Table;

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
    /// The 3x wall with passivity is bounded at every rate in the sampled-wall model and at every
    /// rate of `device_plant` in closed loop with the device plant
    /// (`device_plant[i].passivity_3x_bounded`: within the encoder quantisation's floor).
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
            && rows.iter().all(|r| r.passivity_bounded() == Some(true))
            && device_plant
                .iter()
                .all(|r| r.passivity_3x_bounded == Some(true)),
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
            "late 1 s p-p max: 1x without / 3x with passivity / one cell (um)",
            "force std: 1x without / 3x with / 3x bound K*cell/2 (N)",
            "3x bounded (within the quantisation floor)",
            "L ~ 0: K_max one tick / firmware (N/m)",
            "L ~ 0: 3x settled with passivity",
        ],
    );
    let k = |v: Option<f64>| v.map_or("-".to_string(), |k| format!("{k:.0}"));
    let um = |v: Option<f64>| v.map_or("-".to_string(), |a| format!("{:.1}", a * 1e6));
    let n = |v: Option<f64>| v.map_or("-".to_string(), |f| format!("{f:.2}"));
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
                "{} / {} / {}",
                um(r.passive_1x_late_amp_m),
                um(r.passivity_3x_verdict.map(|v| v.late_amp_max_m)),
                um(r.encoder_cell_normal_m)
            ),
            format!(
                "{} / {} / {}",
                n(r.passive_1x_force_z_std_n),
                n(r.passivity_3x_verdict.map(|v| v.force_z_std_n)),
                n(r.passivity_3x_verdict.map(|v| v.force_z_std_bound_n))
            ),
            r.passivity_3x_bounded.map_or("-".into(), |s| s.to_string()),
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
