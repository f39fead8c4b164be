//! The in-process reference: the same control sequence as the board's tick, on the host, against
//! the same plant and the same plant-side faults, tick by tick.
//!
//! Interim, like `firmware/src/board/mps2/app.rs`: count extension, controller, output guard and
//! phase/enable mapping in the firmware's order. When `softfinger_core::pipeline::Pipeline` lands,
//! both become one `Pipeline::tick` call. The f32 operations are the same on both sides (no FMA
//! contraction: Rust never fuses without being asked), so the outputs should agree to the bit.

use super::session::Settings;
use super::wire::{BoardConfig, Pins};
use crate::plant::Plant;
use softfinger_core::contact_state::ContactState;
use softfinger_core::controller::{Controller, ControllerConfig, TickInput};
use softfinger_core::encoder::EncoderBank;
use softfinger_core::output_guard::{phase_enable, GuardConfig, OutputGuard};
use softfinger_core::{Fast, Flags};

/// One reference tick: the outputs it writes and the contact state after it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RefTick {
    pub pins: Pins,
    pub state: ContactState,
}

/// Run `s.ticks` ticks with the board's configuration `cfg`. Mirrors the session's timing: one
/// boot sample in period 0, one idle period, then tick k samples in period k+1.
pub fn run(plant: &Plant, cfg: &BoardConfig, s: &Settings) -> Result<Vec<RefTick>, String> {
    let mut plant = plant.clone();
    let config = ControllerConfig {
        rate_hz: s.rate_hz as f32,
        ..ControllerConfig::default()
    };
    let mut ctrl = Controller::<Fast>::new(config).map_err(|e| format!("controller: {e:?}"))?;
    let mut guard = OutputGuard::new(GuardConfig {
        max_duty: cfg.max_duty,
        max_overrun_streak: cfg.max_overrun_streak,
    })
    .map_err(|e| format!("output guard: {e:?}"))?;
    let raw = |p: &Plant| p.counts().map(|c| c as u16);
    let mut bank = EncoderBank::new(raw(&plant), cfg.max_counts_per_tick);
    let dt = 1.0 / f64::from(s.rate_hz);
    plant.step_with_enable(Pins::OFF.duties(cfg.full_scale), false, dt);
    let mut out = Vec::with_capacity(s.ticks as usize);
    for k in 0..s.ticks {
        let mut counts = raw(&plant);
        let mut n_fault = false;
        if s.fault.mirrored_in_reference() {
            s.fault
                .edit_sample(k, s.fault_tick, &mut counts, &mut n_fault);
        }
        let (extended, encoder_flags) = bank.update(counts);
        let input = TickInput {
            counts: extended,
            driver_fault: n_fault,
            overrun: false,
        };
        let output = ctrl.tick(&input);
        let mut events = encoder_flags;
        if n_fault {
            events |= Flags::DRIVER_FAULT;
        }
        let guarded = guard.apply(&output, events, 0);
        let mut pins = Pins {
            pwm_enable: guarded.enable,
            driver_awake: guarded.enable,
            ..Pins::OFF
        };
        for (i, duty) in guarded.duties.iter().enumerate() {
            let cmd = phase_enable(if guarded.enable { *duty } else { 0.0 }, cfg.full_scale);
            pins.phase_forward[i] = cmd.forward;
            pins.compare[i] = cmd.compare.min(u32::from(u16::MAX)) as u16;
        }
        plant.step_with_enable(pins.duties(cfg.full_scale), pins.enabled(), dt);
        out.push(RefTick {
            pins,
            state: output.state,
        });
    }
    Ok(out)
}
