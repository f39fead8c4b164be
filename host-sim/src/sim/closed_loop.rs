//! The closed loop: the core's control pipeline (the firmware's interrupt, minus the hardware
//! access) against the plant, coupled only by wrapping 16-bit timer counts in and bridge commands
//! (phase, compare, enable, sleep) out, with the board timing the firmware uses.
//!
//! Each tick: `raw = plant.raw_counts()`, an optional injection hook edits the raw input (faults,
//! noise, timing), `out = pipeline.tick(raw)`, then `plant.step_bridges(out.bridges, timing)`.
//! Before a scene, [`prepare`] plays the operator's session: power-up, `Home` with the handle let
//! go (the arms find their stops), the hand takes the handle, `Arm`; the scene's script starts then.

use crate::sim::plant::{HandScript, Plant, PlantError, PlantParams, TouchScript};
use crate::sim::scene::{Scene, SceneProblem, SurfaceSpec};
use softfinger_core::contact::params::{ContactParams, ParamError};
use softfinger_core::contact::surface::{Bowl, Cylinder, Plane, Sphere, Surface};
use softfinger_core::control::controller::Environment;
use softfinger_core::control::pipeline::{
    BoardTiming, Command, CommandError, Mode, Pipeline, PipelineConfig, PipelineError,
    PipelineOutput, RawInput, TimingError,
};
use softfinger_core::omega_like::OMEGA_LIKE;
use softfinger_core::{Math, Vec3};
use softfinger_scene::model::ModelError;
use std::time::{Duration, Instant};

/// Why a scene could not be set up or its operator session failed.
#[derive(Debug, thiserror::Error)]
pub enum ClosedLoopError {
    /// The scene names an unknown method.
    #[error(transparent)]
    Scene(#[from] SceneProblem),
    /// The scene's contact parameters were rejected.
    #[error("scene '{scene}': contact parameters: {source}")]
    Contact {
        /// Scene name.
        scene: String,
        /// The rejected field.
        source: ParamError,
    },
    /// A control rate that is not an integer number of Hz in 1..=10⁶.
    #[error("rate_hz {0}: the board runs integer rates")]
    Rate(f64),
    /// No board timing with the PWM the rate needs.
    #[error("rate_hz {rate_hz}: no board timing with {pwm_hz} Hz PWM from a {timer_clock_hz} Hz timer clock ({source})")]
    Timing {
        /// Control rate, Hz.
        rate_hz: f64,
        /// PWM rate tried, Hz.
        pwm_hz: u32,
        /// Timer clock, Hz.
        timer_clock_hz: u32,
        /// The timing check's reason.
        source: TimingError,
    },
    /// A bowl no larger than the fingertip.
    #[error("scene '{scene}': a bowl of radius {radius_m} m cannot hold a fingertip of radius {fingertip_m} m")]
    BowlTooSmall {
        /// Scene name.
        scene: String,
        /// Bowl radius, m.
        radius_m: f64,
        /// Fingertip radius, m.
        fingertip_m: f64,
    },
    /// The pipeline faulted before the scene started (the latched flag bits).
    #[error("faulted during the session: latched flags {0:#010x}")]
    Faulted(u32),
    /// The pipeline refused an operator command.
    #[error("{command} refused: {source}")]
    Refused {
        /// The command's name.
        command: &'static str,
        /// The pipeline's reason.
        source: CommandError,
    },
    /// Homing did not finish in the given time, s.
    #[error("not homed after {0} s")]
    NotHomed(f64),
}

/// Why a closed loop (plant, pipeline, operator session) could not be set up.
#[derive(Debug, thiserror::Error)]
pub enum SetupError {
    /// The plant refused its parameters or script.
    #[error("plant: {0}")]
    Plant(#[from] PlantError),
    /// The pipeline refused its configuration.
    #[error("pipeline: {0}")]
    Pipeline(#[from] PipelineError),
    /// The passivity stage refused its configuration.
    #[error("passivity: {0}")]
    Passivity(ParamError),
    /// The scene's configuration or the operator's session failed.
    #[error(transparent)]
    Session(#[from] ClosedLoopError),
}

/// Height (base frame, m) of the first contact point in every built-in scene (the plane, the top
/// of the sphere or the cylinder, the bottom of the bowl): 10 mm below the workspace centre, so a
/// 10 mm fingertip touches with its centre there ([`softfinger_scene::model::surface_top_z_m`]).
pub fn surface_top_z_m() -> f64 {
    softfinger_scene::model::surface_top_z_m()
}

/// The scene's contact parameters: the defaults with the scene's overrides
/// ([`softfinger_scene::model::contact_params`]).
pub fn contact_params(scene: &Scene) -> Result<ContactParams, ClosedLoopError> {
    Ok(softfinger_scene::model::contact_params(scene)?)
}

impl From<ModelError> for ClosedLoopError {
    fn from(e: ModelError) -> Self {
        match e {
            ModelError::Scene(p) => ClosedLoopError::Scene(p),
            ModelError::Contact { scene, source } => ClosedLoopError::Contact { scene, source },
        }
    }
}

/// The hand script of a scene: the plant's touch script over the scene's surface.
pub fn touch_script(scene: &Scene, contact: &ContactParams) -> HandScript {
    let s = &scene.script;
    let d = TouchScript::default();
    TouchScript {
        surface_z_m: surface_top_z_m(),
        fingertip_radius_m: contact.fingertip_radius_m as f64,
        press_depth_m: s.press_depth_m.unwrap_or(d.press_depth_m),
        roll_rad: s.roll_rad.unwrap_or(d.roll_rad),
        twist_rad: s.twist_rad.unwrap_or(d.twist_rad),
        slide_m: s.slide_m.unwrap_or(d.slide_m),
        clearance_m: s.clearance_m.unwrap_or(d.clearance_m),
        heading_rad: s.heading_rad.unwrap_or(d.heading_rad),
        twist_while_sliding: s.twist_while_sliding.unwrap_or(d.twist_while_sliding),
        ..d
    }
    .script()
}

/// The plant for a scene (the Omega-like device, a hand following the scene's script).
pub fn plant(scene: &Scene, contact: &ContactParams) -> Result<Plant, PlantError> {
    Plant::new(
        OMEGA_LIKE.params,
        PlantParams::OMEGA_LIKE,
        touch_script(scene, contact),
    )
}

/// The board timing for a control rate: the firmware's (`BoardTiming::STM32G474_10KHZ`: 170 MHz
/// timer clock, 40 kHz PWM) at that rate, or PWM at the control rate above 40 kHz. Rates whose PWM
/// is not an integer multiple are refused.
pub fn board_timing(rate_hz: f64) -> Result<BoardTiming, ClosedLoopError> {
    let control = rate_hz.round();
    if !(control == rate_hz && (1.0..=1e6).contains(&control)) {
        return Err(ClosedLoopError::Rate(rate_hz));
    }
    let control = control as u32;
    let base = BoardTiming::STM32G474_10KHZ;
    let t = BoardTiming {
        control_hz: control,
        pwm_hz: base.pwm_hz.max(control),
        ..base
    };
    t.validate().map_err(|source| ClosedLoopError::Timing {
        rate_hz,
        pwm_hz: t.pwm_hz,
        timer_clock_hz: t.timer_clock_hz,
        source,
    })?;
    Ok(t)
}

fn config_for<S: Surface>(
    scene: &Scene,
    contact: ContactParams,
    surface: S,
    origin: Vec3,
) -> Result<PipelineConfig<S>, ClosedLoopError> {
    Ok(PipelineConfig {
        device: OMEGA_LIKE,
        timing: board_timing(scene.rate_hz)?,
        contact,
        surface,
        object_origin_m: origin,
        log_rate_hz: softfinger_core::control::telemetry::DEFAULT_LOG_RATE_HZ,
    })
}

/// The pipeline configuration for a plane scene.
pub fn plane_config(
    scene: &Scene,
    contact: ContactParams,
) -> Result<PipelineConfig<Plane>, ClosedLoopError> {
    let origin = Vec3::new(0.0, 0.0, surface_top_z_m() as f32);
    config_for(scene, contact, Plane::default(), origin)
}

/// The pipeline configuration for a sphere scene: the object frame's origin is the sphere's
/// centre, below the surface top.
pub fn sphere_config(
    scene: &Scene,
    contact: ContactParams,
    radius_m: f64,
) -> Result<PipelineConfig<Sphere>, ClosedLoopError> {
    let origin = Vec3::new(0.0, 0.0, (surface_top_z_m() - radius_m) as f32);
    config_for(scene, contact, Sphere::new(radius_m as f32), origin)
}

/// The pipeline configuration for a bowl scene: the object frame's origin is the bowl's centre,
/// above its bottom. The bowl must be larger than the fingertip.
pub fn bowl_config(
    scene: &Scene,
    contact: ContactParams,
    radius_m: f64,
) -> Result<PipelineConfig<Bowl>, ClosedLoopError> {
    let r = contact.fingertip_radius_m as f64;
    if radius_m <= r {
        return Err(ClosedLoopError::BowlTooSmall {
            scene: scene.name.clone(),
            radius_m,
            fingertip_m: r,
        });
    }
    let origin = Vec3::new(0.0, 0.0, (surface_top_z_m() + radius_m) as f32);
    config_for(scene, contact, Bowl::new(radius_m as f32), origin)
}

/// The pipeline configuration for a cylinder scene: the object frame's origin is on the
/// cylinder's axis (along the base x axis), below its top.
pub fn cylinder_config(
    scene: &Scene,
    contact: ContactParams,
    radius_m: f64,
) -> Result<PipelineConfig<Cylinder>, ClosedLoopError> {
    let origin = Vec3::new(0.0, 0.0, (surface_top_z_m() - radius_m) as f32);
    config_for(scene, contact, Cylinder::new(radius_m as f32), origin)
}

/// Which surface a scene needs, for dispatch to the monomorphised loop.
pub fn surface_of(scene: &Scene) -> SurfaceSpec {
    scene.surface
}

/// One closed-loop tick: sample the counters, `inject`, run the pipeline, drive the plant.
pub fn step<M: Math, S: Environment>(
    pipe: &mut Pipeline<M, S>,
    plant: &mut Plant,
    inject: impl FnOnce(&mut RawInput),
) -> (RawInput, PipelineOutput, Duration) {
    let mut raw = RawInput {
        counts: plant.raw_counts(),
        ..RawInput::default()
    };
    inject(&mut raw);
    let t0 = Instant::now();
    let out = pipe.tick(&raw);
    let spent = t0.elapsed();
    let timing = pipe.config().timing;
    plant.step_bridges(&out.bridges, &timing);
    (raw, out, spent)
}

/// What the operator's session before a scene took.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Prepared {
    /// Simulated time from power-up to the end of homing, s.
    pub homed_at_s: f64,
    /// Simulated time from power-up to `Arm`, s.
    pub armed_at_s: f64,
    /// Homed motor count minus the count of the plant's true arm angle, at the end of homing.
    pub homing_error_counts: [i64; 3],
}

/// Time the hand takes to bring the handle to the script's start after homing, s (the hand's
/// spring-damper settles in about 4/(ζ·ω) = 0.3 s with the plant's 300 N/m, 0.55 kg, ζ = 0.6).
pub const SETTLE_S: f64 = 0.5;
/// Power-up time before `Home`, s.
pub const POWER_UP_S: f64 = 0.01;

/// Longest homing the session waits for, s (the device's homing times out before this).
const HOMING_WAIT_S: f64 = 10.0;

/// Tick with the script held at its start for up to `n` ticks or until `done`; a fault is an
/// error. Returns the ticks run and the last output.
fn hold<M: Math, S: Environment>(
    pipe: &mut Pipeline<M, S>,
    plant: &mut Plant,
    n: u64,
    done: impl Fn(&PipelineOutput) -> bool,
) -> Result<(u64, Option<PipelineOutput>), ClosedLoopError> {
    let mut last = None;
    for k in 1..=n {
        plant.restart_script();
        let (_, out, _) = step(pipe, plant, |_| {});
        if out.mode == Mode::Faulted {
            return Err(ClosedLoopError::Faulted(out.latched.0));
        }
        last = Some(out);
        if done(&out) {
            return Ok((k, last));
        }
    }
    Ok((n, last))
}

/// The operator's session: power-up, `Home` with the handle let go (held in the wrist's
/// calibration pose: the script's start), the hand takes the handle and brings it to the script's
/// start, `Arm`. The script is held at its start throughout and restarts when armed.
pub fn prepare<M: Math, S: Environment>(
    pipe: &mut Pipeline<M, S>,
    plant: &mut Plant,
) -> Result<Prepared, ClosedLoopError> {
    let dt = 1.0 / f64::from(pipe.config().timing.control_hz);
    let ticks = |s: f64| (s / dt).round() as u64;
    plant.release_hand();
    let (powered, _) = hold(pipe, plant, ticks(POWER_UP_S), |_| false)?;
    pipe.command(Command::Home)
        .map_err(|source| ClosedLoopError::Refused {
            command: "Home",
            source,
        })?;
    let (homing, last) = hold(pipe, plant, ticks(HOMING_WAIT_S), |o| {
        o.mode == Mode::Disarmed
    })?;
    let out = match last {
        Some(o) if o.mode == Mode::Disarmed => o,
        _ => return Err(ClosedLoopError::NotHomed(HOMING_WAIT_S)),
    };
    let truth = plant.counts();
    let homing_error_counts =
        std::array::from_fn(|i| i64::from(out.counts[i]) - i64::from(truth[i]));
    plant.grasp_hand();
    let (settled, _) = hold(pipe, plant, ticks(SETTLE_S), |_| false)?;
    pipe.command(Command::Arm)
        .map_err(|source| ClosedLoopError::Refused {
            command: "Arm",
            source,
        })?;
    plant.restart_script();
    Ok(Prepared {
        homed_at_s: (powered + homing) as f64 * dt,
        armed_at_s: (powered + homing + settled) as f64 * dt,
        homing_error_counts,
    })
}

/// Run `ticks` closed-loop ticks. `inject(k, &mut raw)` may edit each tick's raw input;
/// `observe(k, &raw, &output, &pipeline, &plant)` sees every tick after the plant has stepped.
/// Returns the wall time spent inside `Pipeline::tick`.
pub fn simulate<M: Math, S: Environment>(
    pipe: &mut Pipeline<M, S>,
    plant: &mut Plant,
    ticks: u64,
    mut inject: impl FnMut(u64, &mut RawInput),
    mut observe: impl FnMut(u64, &RawInput, &PipelineOutput, &Pipeline<M, S>, &Plant),
) -> Duration {
    let mut in_pipeline = Duration::ZERO;
    for k in 0..ticks {
        let (raw, out, spent) = step(pipe, plant, |r| inject(k, r));
        in_pipeline += spent;
        observe(k, &raw, &out, pipe, plant);
    }
    in_pipeline
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A bowl must be larger than the fingertip (10 mm by default): refused at 10 mm, accepted
    /// just above.
    #[test]
    fn a_bowl_must_hold_the_fingertip() {
        let scene = Scene::load("finger-in-bowl").unwrap();
        let contact = contact_params(&scene).unwrap();
        let r = contact.fingertip_radius_m as f64;
        let e = bowl_config(&scene, contact, r).unwrap_err().to_string();
        assert!(e.contains("cannot hold"), "{e}");
        let ok = bowl_config(&scene, contact, r * 1.001).unwrap();
        // The bowl's centre is its radius above the first contact, up to the f32 rounding of the
        // origin: measured 1.1e-9 m (bowl) and 2.4e-9 m (cylinder); bounds 3×.
        let above = ok.object_origin_m.z as f64 - surface_top_z_m();
        assert!((above - r * 1.001).abs() < 3.3e-9, "{above}");
        let cyl = cylinder_config(&scene, contact, 0.05).unwrap();
        assert!((surface_top_z_m() - cyl.object_origin_m.z as f64 - 0.05).abs() < 7.2e-9);
    }
}
