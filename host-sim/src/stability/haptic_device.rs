//! Part 3, device plant: the largest passive wall in closed loop with the Omega-like plant
//! (3-DoF linkage, motors with winding inductance and current limit, friction, the hand), the
//! core's controller rendering the plane, for one tick of output delay, the firmware's timing
//! ([`crate::plant::Plant::step_with_output_delay`]) and with the passivity stage.
//!
//! **Scene.** The plane 10 mm below the workspace centre ([`closed_loop::surface_top_z_m`]), the
//! contact's virtual damping set to 0 (a pure spring wall K, as in the sampled-wall model). The
//! hand starts with the fingertip 1 mm above the surface, moves (minimum jerk, 0.2 s) to 3 mm
//! below touching and holds there: through the 300 N/m grasp it pushes about 1 N into the wall.
//!
//! **Verdict.** The effector's height (plant truth, no quantisation) is recorded; the wall is
//! stable when its peak-to-peak amplitude over the last 0.1 s of a 0.6 s run is below
//! [`SETTLED_AMPLITUDE_M`], one motor-encoder count at the tip (about 13 µm): the loop has
//! settled to its resolution, where only a sub-count limit cycle of the quantised loop remains.
//! (The amplitude over [0.35, 0.45) s is reported beside it: equal amplitudes are a sustained
//! oscillation.) K_max: log sweep, then bisection to 2 %.
//!
//! **Diagnostic.** Every figure is also computed with the winding inductance made negligible
//! ([`NEGLIGIBLE_INDUCTANCE_H`]): the current then follows the duty at once, and what remains is
//! the sampled loop of the model in [`super::haptic`]. The 3x wall is also run at the same K with
//! the negligible winding and with a [`FINE_ENCODER_FACTOR`]× finer motor encoder (controller and
//! plant), separating the winding lag from the encoder's quantisation.

use crate::closed_loop;
use crate::plant::{HandScript, Phase, Plant, PlantParams, Waypoint};
use softfinger_core::controller::{Controller, ControllerConfig, TickInput};
use softfinger_core::device::DeviceParams;
use softfinger_core::math::Fast;
use softfinger_core::params::ContactParams;
use softfinger_core::pipeline::passivity::PassivityConfig;
use softfinger_core::vec3::Vec3;

/// Run length, s.
pub const RUN_S: f64 = 0.6;
/// A late peak-to-peak amplitude below this is settled, m.
pub const SETTLED_AMPLITUDE_M: f64 = 13e-6;
/// Relative width of the bisection bracket.
pub const BISECT_REL: f64 = 0.02;
/// The sweep: log-spaced over [1e4, 1e6] N/m.
pub const K_SWEEP: (f64, f64, usize) = (1e4, 1e6, 21);

/// One closed-loop wall run's figures.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DeviceOutcome {
    /// Peak-to-peak effector height over [0.2, 0.3) s and over the last 0.1 s, m.
    pub early_amp_m: f64,
    pub late_amp_m: f64,
    /// Largest |rendered force|, N.
    pub peak_force_n: f64,
    /// Ticks in which the passivity stage added damping.
    pub damped_ticks: u64,
    pub stable: bool,
}

/// The loop's timing and stage.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DeviceLoop {
    pub rate_hz: f64,
    /// Sample-to-output delay, ticks in [0, 1].
    pub delay_ticks: f64,
    pub passivity: bool,
    /// Motor winding inductance, H (the plant's 0.24 mH; a near-zero value isolates the
    /// electrical lag).
    pub inductance_h: f64,
    /// Motor encoder counts per motor turn, controller and plant (the device's 4096; a finer
    /// encoder isolates the quantisation).
    pub motor_counts_per_rev: u32,
}

fn script() -> HandScript {
    let touch_z = closed_loop::surface_top_z_m() + 0.010;
    HandScript::hold([0.0, 0.0, touch_z + 0.001]).then(
        Phase::Press,
        0.2,
        Waypoint {
            position_m: [0.0, 0.0, touch_z - 0.003],
            wrist_rad: [0.0; 3],
        },
    )
}

/// Run the wall of stiffness `k` (N/m) for `seconds`, calling `each(t, z, |force|)` after every
/// tick with the effector height z (plant truth, m) and the rendered force (N).
fn simulate(
    l: &DeviceLoop,
    k: f64,
    seconds: f64,
    mut each: impl FnMut(f64, f64, f64),
) -> Result<u64, String> {
    let contact = ContactParams {
        normal_stiffness: k as f32,
        normal_damping: 0.0,
        ..ContactParams::DEFAULT
    };
    // Controller and plant read the same (possibly finer) motor encoder.
    let mut device = DeviceParams::OMEGA_LIKE;
    device.motor_encoder_counts_per_rev = l.motor_counts_per_rev;
    let config = ControllerConfig {
        rate_hz: l.rate_hz as f32,
        device,
        contact,
        object_origin_m: Vec3::new(0.0, 0.0, closed_loop::surface_top_z_m() as f32),
        ..ControllerConfig::default_plane()
    };
    let mut ctrl: Controller<Fast> =
        Controller::new(config).map_err(|e| format!("device wall K = {k}: {e}"))?;
    ctrl.set_passivity(PassivityConfig {
        enabled: l.passivity,
        output_delay_ticks: l.delay_ticks.clamp(0.0, 1.0) as f32,
        ..PassivityConfig::DEFAULT
    })
    .map_err(|e| format!("passivity: {e}"))?;
    let params = PlantParams {
        motor_inductance_h: l.inductance_h,
        ..PlantParams::OMEGA_LIKE
    };
    let mut plant = Plant::new(device, params, script()).map_err(|e| format!("plant: {e:?}"))?;
    let dt = 1.0 / l.rate_hz;
    let ticks = (seconds * l.rate_hz).round() as u64;
    let mut damped = 0u64;
    for i in 0..ticks {
        let out = ctrl.tick(&TickInput {
            counts: plant.counts(),
            ..TickInput::default()
        });
        if ctrl.passivity().energy_j() > 0.0 && l.passivity {
            damped += 1;
        }
        plant.step_with_output_delay(out.duties, out.enable, dt, l.delay_ticks);
        let force = f64::from(out.force_n.norm_squared()).sqrt();
        each((i + 1) as f64 * dt, plant.effector_position_m()[2], force);
    }
    Ok(damped)
}

/// One run with wall stiffness `k` (N/m).
pub fn run(l: &DeviceLoop, k: f64) -> Result<DeviceOutcome, String> {
    let (mut early, mut late) = ((f64::MAX, f64::MIN), (f64::MAX, f64::MIN));
    let mut peak = 0.0f64;
    let damped = simulate(l, k, RUN_S, |t, z, force| {
        let win = if (0.35..0.45).contains(&t) {
            Some(&mut early)
        } else if t >= RUN_S - 0.1 {
            Some(&mut late)
        } else {
            None
        };
        if let Some(w) = win {
            *w = (w.0.min(z), w.1.max(z));
        }
        peak = peak.max(force);
    })?;
    let (ea, la) = (early.1 - early.0, late.1 - late.0);
    Ok(DeviceOutcome {
        early_amp_m: ea,
        late_amp_m: la,
        peak_force_n: peak,
        damped_ticks: damped,
        stable: la.is_finite() && la < SETTLED_AMPLITUDE_M,
    })
}

/// Length of the envelope run, s, and of its windows, s.
pub const ENVELOPE_S: (f64, f64) = (2.0, 0.1);

/// Peak-to-peak effector height (m) in each [`ENVELOPE_S`] window of a 2 s run of the wall of
/// stiffness `k` after the press (from 0.3 s): equal values are a sustained oscillation, falling
/// ones a decaying one.
pub fn envelope(l: &DeviceLoop, k: f64) -> Result<Vec<f64>, String> {
    let (seconds, window) = ENVELOPE_S;
    let start = 0.3;
    let n = ((seconds - start) / window).round() as usize;
    let mut w = vec![(f64::MAX, f64::MIN); n];
    simulate(l, k, seconds, |t, z, _| {
        if t >= start {
            let i = (((t - start) / window) as usize).min(n - 1);
            w[i] = (w[i].0.min(z), w[i].1.max(z));
        }
    })?;
    Ok(w.into_iter().map(|(lo, hi)| hi - lo).collect())
}

/// K_max: the sweep's first unstable K bisected against the last stable one (`None`: nothing in
/// the sweep is unstable, or the first K already is).
pub fn kmax(l: &DeviceLoop) -> Result<Option<f64>, String> {
    let (lo, hi, n) = K_SWEEP;
    let mut last_stable = None;
    for i in 0..n {
        let k = lo * (hi / lo).powf(i as f64 / (n - 1) as f64);
        if run(l, k)?.stable {
            last_stable = Some(k);
            continue;
        }
        let Some(mut a) = last_stable else {
            return Ok(None);
        };
        let mut b = k;
        while b / a > 1.0 + BISECT_REL {
            let mid = (a * b).sqrt();
            if run(l, mid)?.stable {
                a = mid;
            } else {
                b = mid;
            }
        }
        return Ok(Some((a * b).sqrt()));
    }
    Ok(None)
}

/// One rate's device figures.
#[derive(Clone, Debug, serde::Serialize)]
pub struct DeviceRow {
    pub rate_hz: f64,
    pub firmware_delay_ticks: f64,
    /// K_max with one tick of delay and at the firmware timing, N/m.
    pub kmax_one_tick: Option<f64>,
    pub kmax_firmware_timing: Option<f64>,
    /// The wall at 3 × `kmax_firmware_timing` with passivity: stable, and its largest force.
    pub passivity_3x_stable: Option<bool>,
    pub passivity_3x_without_stable: Option<bool>,
    pub passivity_3x_peak_force_n: Option<f64>,
    /// Late peak-to-peak amplitude of the 3x wall without and with passivity, m.
    pub passivity_3x_late_amp_without_m: Option<f64>,
    pub passivity_3x_late_amp_with_m: Option<f64>,
    /// Peak-to-peak per 0.1 s window of a 2 s run of the 3x wall with passivity, from 0.3 s, m
    /// ([`envelope`]).
    pub passivity_3x_envelope_with_m: Option<Vec<f64>>,
    /// The same with the winding inductance at [`NEGLIGIBLE_INDUCTANCE_H`]: K_max for one tick and
    /// the firmware timing, N/m, and whether the 3x wall with passivity settles.
    pub no_lag_kmax_one_tick: Option<f64>,
    pub no_lag_kmax_firmware_timing: Option<f64>,
    pub no_lag_passivity_3x_stable: Option<bool>,
    /// Late peak-to-peak amplitude of the same 3x wall (3 × `kmax_firmware_timing`) with passivity
    /// and the winding inductance at [`NEGLIGIBLE_INDUCTANCE_H`], and with the device's winding but
    /// a [`FINE_ENCODER_FACTOR`]× finer motor encoder, m: which of lag and quantisation sustains it.
    pub passivity_3x_late_amp_no_lag_m: Option<f64>,
    pub passivity_3x_late_amp_fine_encoder_m: Option<f64>,
}

/// The finer motor encoder of the quantisation diagnostic: this many times the device's counts.
pub const FINE_ENCODER_FACTOR: u32 = 16;

/// A winding inductance whose L/R (0.5 µs) is negligible against the tick, H.
pub const NEGLIGIBLE_INDUCTANCE_H: f64 = 1e-6;

/// K_max for one tick and for `delay_ticks`, and the 3x wall without and with passivity.
type Figures = (
    Option<f64>,
    Option<f64>,
    Option<DeviceOutcome>,
    Option<DeviceOutcome>,
);

fn figures(rate_hz: f64, delay_ticks: f64, inductance_h: f64) -> Result<Figures, String> {
    let mk = |delay_ticks, passivity| DeviceLoop {
        rate_hz,
        delay_ticks,
        passivity,
        inductance_h,
        motor_counts_per_rev: DeviceParams::OMEGA_LIKE.motor_encoder_counts_per_rev,
    };
    let one = kmax(&mk(1.0, false))?;
    let fw = kmax(&mk(delay_ticks, false))?;
    let (with, without) = match fw {
        Some(k) => (
            Some(run(&mk(delay_ticks, true), 3.0 * k)?),
            Some(run(&mk(delay_ticks, false), 3.0 * k)?),
        ),
        None => (None, None),
    };
    Ok((one, fw, with, without))
}

/// The device figures at `rate_hz` with the firmware's delay `delay_ticks`.
pub fn row(rate_hz: f64, delay_ticks: f64) -> Result<DeviceRow, String> {
    let l = PlantParams::OMEGA_LIKE.motor_inductance_h;
    let (one, fw, with, without) = figures(rate_hz, delay_ticks, l)?;
    let (n_one, n_fw, n_with, _) = figures(rate_hz, delay_ticks, NEGLIGIBLE_INDUCTANCE_H)?;
    let pc = DeviceLoop {
        rate_hz,
        delay_ticks,
        passivity: true,
        inductance_h: l,
        motor_counts_per_rev: DeviceParams::OMEGA_LIKE.motor_encoder_counts_per_rev,
    };
    let env = fw.map(|k| envelope(&pc, 3.0 * k)).transpose()?;
    let no_lag = DeviceLoop {
        inductance_h: NEGLIGIBLE_INDUCTANCE_H,
        ..pc
    };
    let fine = DeviceLoop {
        motor_counts_per_rev: pc.motor_counts_per_rev * FINE_ENCODER_FACTOR,
        ..pc
    };
    let late = |l: &DeviceLoop| {
        fw.map(|k| run(l, 3.0 * k).map(|o| o.late_amp_m))
            .transpose()
    };
    Ok(DeviceRow {
        rate_hz,
        firmware_delay_ticks: delay_ticks,
        kmax_one_tick: one,
        kmax_firmware_timing: fw,
        passivity_3x_stable: with.map(|o| o.stable),
        passivity_3x_without_stable: without.map(|o| o.stable),
        passivity_3x_peak_force_n: with.map(|o| o.peak_force_n),
        passivity_3x_late_amp_without_m: without.map(|o| o.late_amp_m),
        passivity_3x_late_amp_with_m: with.map(|o| o.late_amp_m),
        passivity_3x_envelope_with_m: env,
        no_lag_kmax_one_tick: n_one,
        no_lag_kmax_firmware_timing: n_fw,
        no_lag_passivity_3x_stable: n_with.map(|o| o.stable),
        passivity_3x_late_amp_no_lag_m: late(&no_lag)?,
        passivity_3x_late_amp_fine_encoder_m: late(&fine)?,
    })
}
