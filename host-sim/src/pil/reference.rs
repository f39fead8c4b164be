//! The in-process reference: the same pipeline as the board's tick (`Pipeline::<Fast, S>` on the
//! board's scene: the fixed plane of the default build, or the local model, [`firmware_config`]), the same plant, the same operator session and the same plant-side
//! faults, tick by tick. The f32 operations are the same on both sides (Rust never contracts
//! a·b+c into an FMA unless asked), so the bridge commands should agree to the bit.
//!
//! Output timing: the compares load at the PWM boundary the firmware's planned tick reaches
//! (`OutputTiming::planned`: the first boundary after the tick event), which is where the board's
//! do load as long as its writes land in the first PWM period (`pil --check` holds it to that).

use super::operator::Operator;
use super::session::Settings;
use super::PilError;
use crate::sim::plant::Plant;
use softfinger_app::scripted_app::ScriptedApp;
use softfinger_core::contact::params::ContactParams;
use softfinger_core::contact::state::ContactState;
use softfinger_core::contact::RollingOnly;
use softfinger_core::control::controller::Environment;
use softfinger_core::control::local_model::{LocalModelEnvironment, LocalModelSpec, ModelPose};
use softfinger_core::control::pipeline::output_timing::OutputTiming;
use softfinger_core::control::pipeline::{
    BridgeCommands, Mode, Pipeline, PipelineConfig, RawInput,
};
use softfinger_core::device::delta::DeltaGeometry;
use softfinger_core::{Fast, Vec3};

/// One reference tick.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RefTick {
    pub bridges: BridgeCommands,
    pub state: ContactState,
    pub mode: Mode,
}

/// The reference run: every tick, and the tick the scene started at.
pub struct RefRun {
    pub ticks: Vec<RefTick>,
    pub scene_start: Option<u64>,
}

/// The firmware's scene (`firmware/app/src/config.rs`, `TickEnvironment`): the application's local
/// model with the contact model the default scene names (`rolling`: the device displays no
/// torque about the normal, so the firmware compiles no spin torque and no limit surface).
pub type FirmwareEnvironment = LocalModelEnvironment<RollingOnly>;

/// The firmware's pipeline configuration (`firmware/src/config.rs`, `pipeline_config`) on
/// `timing`: the local-model scene whose initial model is the plane 10 mm below the workspace
/// centre with `contact`'s material, watchdog off, poses in the base frame. The plane's height
/// is computed as the firmware computes it (in f32), so both sides render the same bits.
pub fn firmware_config(
    timing: softfinger_core::control::pipeline::BoardTiming,
    contact: ContactParams,
) -> PipelineConfig<FirmwareEnvironment> {
    let top = Vec3::new(
        0.0,
        0.0,
        DeltaGeometry::OMEGA_LIKE_WORKSPACE_CENTRE_M.z - 0.010,
    );
    let initial = LocalModelSpec::plane(0, ModelPose::at(top), &contact);
    PipelineConfig {
        device: softfinger_core::omega_like::OMEGA_LIKE,
        timing,
        contact,
        surface: LocalModelEnvironment::with_parts(initial),
        object_origin_m: Vec3::ZERO,
        log_rate_hz: softfinger_core::control::telemetry::DEFAULT_LOG_RATE_HZ,
    }
}

/// Run until the scene's end. Mirrors the session's timing: one idle period, then tick k.
/// `prev_write_done` (index = tick, as the board's trace records it): the previous tick's write
/// time each of the board's ticks was told, given to the same tick here, so that a write the
/// board finished late (in emulated time) has the same effect on both (a direction reversal held
/// one tick longer); ticks beyond it are told 0, on time.
pub fn run<S: Environment>(
    plant: &Plant,
    config: PipelineConfig<S>,
    s: &Settings,
    prev_write_done: &[u32],
) -> Result<RefRun, PilError> {
    let mut plant = plant.clone();
    let timing = config.timing;
    let config_contact = config.contact;
    let planned = OutputTiming::planned(&timing);
    let load_after = planned.effect_counts / planned.pwm_counts.max(1);
    let mut pipe = Pipeline::<Fast, S>::new(config)?;
    plant.step_bridges(&BridgeCommands::OFF, &timing);
    let mut op = Operator::for_settings(s);
    let mut app = ScriptedApp::new(config_contact);
    let mut prev_mode = Mode::Unhomed;
    let mut ticks = Vec::new();
    for k in 0.. {
        if s.finished(k, op.scene_start()) {
            break;
        }
        if op.homing_timed_out(k) {
            return Err(PilError::ReferenceNotHomed);
        }
        let command = op.before_sample(k, prev_mode, &mut plant);
        let mut raw = RawInput {
            counts: plant.raw_counts(),
            prev_write_done_counts: usize::try_from(k)
                .ok()
                .and_then(|i| prev_write_done.get(i))
                .copied()
                .unwrap_or(0),
            ..RawInput::default()
        };
        if s.fault.mirrored_in_reference() {
            s.fault
                .edit_sample(k, s.fault_tick(op.scene_start()), &mut raw);
        }
        let out = pipe.tick(&raw);
        plant.step_bridges_loading_after(&out.bridges, &timing, load_after);
        if let Some(c) = command {
            // A refusal is the pipeline's answer, as on the board.
            let _ = pipe.command(c);
        } else if op.app_step(k) {
            // After the operator's queue, as the board's tick serves its link queue.
            let _ = pipe.link_command(app.next_command());
        }
        prev_mode = out.mode;
        ticks.push(RefTick {
            bridges: out.bridges,
            state: out.control.state,
            mode: out.mode,
        });
    }
    Ok(RefRun {
        ticks,
        scene_start: op.scene_start(),
    })
}
