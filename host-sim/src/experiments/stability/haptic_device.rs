//! Part 3, device plant: the largest passive wall in closed loop with the Omega-like plant
//! (3-DoF linkage, motors with winding inductance and current limit, friction, the hand), the
//! core's controller rendering the plane, for one tick of output delay, the firmware's timing
//! ([`crate::sim::plant::Plant::step_with_output_delay`]) and with the passivity stage.
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
//! oscillation.) K_max: log sweep, then bisection to 2 %. The 3x wall with passivity is judged
//! over the last second of a 2 s run against the encoder quantisation's floor
//! ([`super::encoder_cell`]): one cell along the normal in position, K·cell/2 in the rendered
//! force's standard deviation, where the largest passive wall without the stage sits.
//!
//! **Diagnostic.** Every figure is also computed with the winding inductance made negligible
//! ([`NEGLIGIBLE_INDUCTANCE_H`]): the current then follows the duty at once, and what remains is
//! the sampled loop of the model in [`super::haptic`]. The 3x wall is also run at the same K with
//! the negligible winding and with a [`FINE_ENCODER_FACTOR`]× finer motor encoder (controller and
//! plant), separating the winding lag from the encoder's quantisation.

use super::encoder_cell;
use crate::sim::closed_loop;
use crate::sim::plant::{HandScript, Phase, Plant, PlantParams, Waypoint};
use softfinger_core::contact::params::ContactParams;
use softfinger_core::control::controller::passivity::PassivityConfig;
use softfinger_core::control::controller::{Controller, ControllerConfig, TickInput};
use softfinger_core::device::DeviceParams;
use softfinger_core::math::vec3::Vec3;
use softfinger_core::math::Fast;

/// Why a device-plant wall run could not be set up.
#[derive(Debug, thiserror::Error)]
pub enum DeviceWallError {
    /// The controller rejected the wall (stiffness K, N/m).
    #[error("device wall K = {0}: {1}")]
    Controller(f64, softfinger_core::contact::params::ParamError),
    /// The passivity stage rejected its configuration.
    #[error("passivity: {0}")]
    Passivity(softfinger_core::contact::params::ParamError),
    /// The plant rejected the run.
    #[error("plant: {0}")]
    Plant(crate::sim::plant::PlantError),
}

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
    /// The passivity stage's damper limit, N·s/m (the default's, unless an experiment varies it).
    pub damper_limit_n_s_per_m: f32,
}

impl DeviceLoop {
    /// The Omega-like device as built: the plant's winding, the device's motor encoder and the
    /// passivity stage's default damper limit, at `rate_hz` with `delay_ticks` of output delay.
    pub fn omega_like(rate_hz: f64, delay_ticks: f64, passivity: bool) -> DeviceLoop {
        DeviceLoop {
            rate_hz,
            delay_ticks,
            passivity,
            inductance_h: PlantParams::OMEGA_LIKE.motor_inductance_h,
            motor_counts_per_rev: DeviceParams::OMEGA_LIKE.motor_encoder_counts_per_rev,
            damper_limit_n_s_per_m: PassivityConfig::DEFAULT.max_damping_n_s_per_m,
        }
    }
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

/// One tick of a wall run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    /// Time after the tick, s.
    pub t_s: f64,
    /// Effector height, plant truth, m.
    pub z_m: f64,
    /// The controller's probe height (from the encoder counts) over the height at which the
    /// fingertip touches the plane, m.
    pub probe_height_m: f64,
    /// Rendered force along z (up: the wall pushing), N, and its magnitude, N.
    pub force_z_n: f64,
    pub force_n: f64,
    /// The passivity observer's energy after the tick, J.
    pub energy_j: f64,
}

/// Run the wall of stiffness `k` (N/m) for `seconds`, calling `each` after every tick.
fn simulate(
    l: &DeviceLoop,
    k: f64,
    seconds: f64,
    mut each: impl FnMut(&Sample),
) -> Result<u64, DeviceWallError> {
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
        Controller::new(config).map_err(|e| DeviceWallError::Controller(k, e))?;
    // As the pipeline configures it for the firmware: the board's delay and the motor
    // encoders' resolution at the probe.
    ctrl.set_passivity(PassivityConfig {
        enabled: l.passivity,
        output_delay_ticks: l.delay_ticks.clamp(0.0, 1.0) as f32,
        position_quantum_m: device.probe_m_per_motor_count(),
        max_damping_n_s_per_m: l.damper_limit_n_s_per_m,
    })
    .map_err(DeviceWallError::Passivity)?;
    let params = PlantParams {
        motor_inductance_h: l.inductance_h,
        ..PlantParams::OMEGA_LIKE
    };
    let mut plant = Plant::new(device, params, script()).map_err(DeviceWallError::Plant)?;
    let dt = 1.0 / l.rate_hz;
    let ticks = (seconds * l.rate_hz).round() as u64;
    let mut damped = 0u64;
    let touch_z = closed_loop::surface_top_z_m() + f64::from(contact.fingertip_radius_m);
    for i in 0..ticks {
        let out = ctrl.tick(&TickInput {
            counts: plant.counts(),
            ..TickInput::default()
        });
        if ctrl.passivity().energy_j() > 0.0 && l.passivity {
            damped += 1;
        }
        plant.step_with_output_delay(out.duties, out.enable, dt, l.delay_ticks);
        each(&Sample {
            t_s: (i + 1) as f64 * dt,
            z_m: plant.effector_position_m()[2],
            probe_height_m: f64::from(out.probe_m.z) - touch_z,
            force_z_n: f64::from(out.force_n.z),
            force_n: f64::from(out.force_n.norm_squared()).sqrt(),
            energy_j: f64::from(ctrl.passivity().energy_j()),
        });
    }
    Ok(damped)
}

/// One run with wall stiffness `k` (N/m).
pub fn run(l: &DeviceLoop, k: f64) -> Result<DeviceOutcome, DeviceWallError> {
    let (mut early, mut late) = ((f64::MAX, f64::MIN), (f64::MAX, f64::MIN));
    let mut peak = 0.0f64;
    let damped = simulate(l, k, RUN_S, |x| {
        let (t, z, force) = (x.t_s, x.z_m, x.force_n);
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
/// ones a decaying one; with the same run's [`Cycle`].
pub fn envelope(l: &DeviceLoop, k: f64) -> Result<(Vec<f64>, Cycle), DeviceWallError> {
    let (seconds, window) = ENVELOPE_S;
    let start = 0.3;
    let n = ((seconds - start) / window).round() as usize;
    let mut w = vec![(f64::MAX, f64::MIN); n];
    let mut late = Vec::new();
    let mut energy_at_1s = 0.0;
    simulate(l, k, seconds, |x| {
        if x.t_s >= start {
            let i = (((x.t_s - start) / window) as usize).min(n - 1);
            w[i] = (w[i].0.min(x.z_m), w[i].1.max(x.z_m));
        }
        if x.t_s <= 1.0 {
            energy_at_1s = x.energy_j;
        }
        if x.t_s > seconds - CYCLE_S {
            late.push(*x);
        }
    })?;
    let n = late.len().max(1) as f64;
    let mean = late.iter().map(|x| x.force_z_n).sum::<f64>() / n;
    let var = late
        .iter()
        .map(|x| (x.force_z_n - mean).powi(2))
        .sum::<f64>()
        / n;
    let cycle = Cycle {
        levels: levels(&late),
        mean_force_z_n: mean,
        force_z_std_n: var.sqrt(),
        observed_energy_j: (energy_at_1s, late.last().map_or(0.0, |x| x.energy_j)),
        damped_fraction: late.iter().filter(|x| x.energy_j > 0.0).count() as f64 / n,
    };
    Ok((w.into_iter().map(|(lo, hi)| hi - lo).collect(), cycle))
}

/// The last part of the envelope run the [`Cycle`] figures describe, s.
pub const CYCLE_S: f64 = 0.5;

/// What sustains the 3x wall's cycle: the encoder lattice the controller sees along the wall's
/// normal, the force it renders there, and the passivity observer's view (the last [`CYCLE_S`]
/// of the envelope run).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Cycle {
    /// The probe heights the controller measured, lowest first.
    pub levels: Vec<Level>,
    /// Mean rendered force along z, N: the load (hand and gravity) the wall holds.
    pub mean_force_z_n: f64,
    /// Standard deviation of the rendered force along z about that mean, N: the force the
    /// cycle makes the user feel.
    pub force_z_std_n: f64,
    /// The observer's energy at 1 s and at the end (2 s), J.
    pub observed_energy_j: (f64, f64),
    /// Fraction of ticks with positive observed energy (the damper armed).
    pub damped_fraction: f64,
}

/// One measured probe height and what the loop did there.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Level {
    /// Probe height over the touching height, m (negative: into the wall).
    pub height_m: f64,
    /// Ticks at this height.
    pub ticks: u64,
    /// Mean rendered force along z at this height, N (the wall's spring, plus the damper).
    pub mean_force_z_n: f64,
}

/// The distinct measured probe heights of `samples` (rounded to 0.1 µm: one encoder lattice point;
/// each level's height is the first one seen), lowest first, with their tick counts and mean force.
pub fn levels(samples: &[Sample]) -> Vec<Level> {
    // (bin, first height seen in it, ticks, force sum)
    let mut out: Vec<(i64, f64, u64, f64)> = Vec::new();
    for x in samples {
        let key = (x.probe_height_m * 1e7).round() as i64;
        match out.iter_mut().find(|l| l.0 == key) {
            Some(l) => {
                l.2 += 1;
                l.3 += x.force_z_n;
            }
            None => out.push((key, x.probe_height_m, 1, x.force_z_n)),
        }
    }
    out.sort_by_key(|l| l.0);
    out.into_iter()
        .map(|(_, height_m, ticks, sum)| Level {
            height_m,
            ticks,
            mean_force_z_n: sum / ticks as f64,
        })
        .collect()
}

/// K_max: the sweep's first unstable K bisected against the last stable one (`None`: nothing in
/// the sweep is unstable, or the first K already is).
pub fn kmax(l: &DeviceLoop) -> Result<Option<f64>, DeviceWallError> {
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
    /// The same run's encoder levels, load and observer ([`Cycle`]).
    pub passivity_3x_cycle: Option<Cycle>,
    /// One motor-encoder cell along the wall's normal at the touching pose, m
    /// ([`encoder_cell::normal_cell_m`]).
    pub encoder_cell_normal_m: Option<f64>,
    /// The largest passive wall (1 × `kmax_firmware_timing`) without the stage, 2 s run: largest
    /// peak-to-peak per 0.1 s window over the last second, m, and the rendered force's standard
    /// deviation along z over the last [`CYCLE_S`], N.
    pub passive_1x_late_amp_m: Option<f64>,
    pub passive_1x_force_z_std_n: Option<f64>,
    /// The 3x wall with passivity within the encoder quantisation's floor in position and force
    /// ([`encoder_cell`]), and the figures it is judged on.
    pub passivity_3x_bounded: Option<bool>,
    pub passivity_3x_verdict: Option<encoder_cell::CellVerdict>,
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

fn figures(rate_hz: f64, delay_ticks: f64, inductance_h: f64) -> Result<Figures, DeviceWallError> {
    let mk = |delay_ticks, passivity| DeviceLoop {
        inductance_h,
        ..DeviceLoop::omega_like(rate_hz, delay_ticks, passivity)
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
pub fn row(rate_hz: f64, delay_ticks: f64) -> Result<DeviceRow, DeviceWallError> {
    let l = PlantParams::OMEGA_LIKE.motor_inductance_h;
    let (one, fw, with, without) = figures(rate_hz, delay_ticks, l)?;
    let (n_one, n_fw, n_with, _) = figures(rate_hz, delay_ticks, NEGLIGIBLE_INDUCTANCE_H)?;
    let pc = DeviceLoop::omega_like(rate_hz, delay_ticks, true);
    let (env, cycle) = match fw.map(|k| envelope(&pc, 3.0 * k)).transpose()? {
        Some((e, c)) => (Some(e), Some(c)),
        None => (None, None),
    };
    let passive_1x = fw.map(|k| {
        envelope(
            &DeviceLoop {
                passivity: false,
                ..pc
            },
            k,
        )
    });
    let passive_1x = passive_1x.transpose()?;
    let cell = encoder_cell::normal_cell_m(&DeviceParams::OMEGA_LIKE);
    let verdict = match (&env, &cycle, cell, fw) {
        (Some(e), Some(c), Some(cell), Some(k)) => {
            encoder_cell::verdict(e, c.force_z_std_n, 3.0 * k, cell)
        }
        _ => None,
    };
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
        passivity_3x_cycle: cycle,
        encoder_cell_normal_m: cell,
        passive_1x_force_z_std_n: passive_1x.as_ref().map(|(_, c)| c.force_z_std_n),
        passive_1x_late_amp_m: passive_1x.and_then(|(e, _)| encoder_cell::late_max_m(&e)),
        passivity_3x_bounded: verdict.map(|v| v.bounded),
        passivity_3x_verdict: verdict,
        no_lag_kmax_one_tick: n_one,
        no_lag_kmax_firmware_timing: n_fw,
        no_lag_passivity_3x_stable: n_with.map(|o| o.stable),
        passivity_3x_late_amp_no_lag_m: late(&no_lag)?,
        passivity_3x_late_amp_fine_encoder_m: late(&fine)?,
    })
}

#[cfg(test)]
mod tests;
