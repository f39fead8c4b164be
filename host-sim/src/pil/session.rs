//! The lock-step session: the plant advanced in control periods by the board's own clock, the
//! board's inputs sampled and its outputs applied exactly when its messages say.
//!
//! Plant time: every message carries the board time; the host steps the plant, one control period
//! at a time, up to the period that time falls in, each step with the bridge commands held at the
//! end of that period (the PWM keeps running on its last commands). So a tick that runs late or
//! not at all, a panic, and a watchdog reset all act on the plant when they act in virtual time.
//! Step j (period j to j+1) is `Plant::step_bridges` with the commands of period j, which is what
//! the in-process loop does after tick j−1.
//!
//! Ticks: the tick timer's first event ends period 0; tick k samples in period k+1. The operator
//! ([`Operator`]) acts before each sample; the run stops `scene_ticks` after the scene starts.
//!
//! Output timing: the compares a tick writes load at the first PWM period boundary after the
//! write (`softfinger_core::control::pipeline::output_timing`). The write instant is the `Drive` message's
//! offset from the tick event (the period start), in instructions (5 per 25 MHz count under
//! `-icount shift=3`) at [`CCM_CYCLES_PER_INSTRUCTION`] cycles each of the 170 MHz timer clock;
//! the sample instant is the `Sense` message's. Each tick's [`OutputTiming`] is kept.

use super::faults::Fault;
use super::operator::{command_code, Operator};
use super::qemu::Emulator;
use super::wire::{self, Message};
use super::PilError;
use crate::sim::plant::Plant;
use softfinger_core::control::pipeline::output_timing::{OutputTiming, CCM_CYCLES_PER_INSTRUCTION};
use softfinger_core::control::pipeline::{BoardTiming, BridgeCommands, Mode, RawInput};
use std::collections::BTreeMap;
use std::sync::atomic::{AtomicBool, Ordering};

/// What the plant saw over the run.
#[derive(Clone, Debug, Default)]
pub struct Trace {
    /// The bridge commands held at the end of each period, index = period.
    pub pins: Vec<BridgeCommands>,
    /// Boots after the first, by reset cause.
    pub resets: Vec<u32>,
    /// `ResetPending` messages (watchdog NMI).
    pub watchdog_nmis: u32,
    /// End-of-run figures by key.
    pub reports: BTreeMap<u16, u32>,
    /// The board said `Done`.
    pub done: bool,
    /// Samples served.
    pub samples: u64,
    /// The tick the scene started at (armed).
    pub scene_start: Option<u64>,
    /// Homing did not finish in time.
    pub homing_timed_out: bool,
    /// Per tick that sampled and wrote in the same period: its sample-to-output timing, in
    /// 170 MHz timer counts from the tick event.
    pub output: Vec<OutputTiming>,
    /// Largest sample and write instants, instructions after the tick event.
    pub max_sample_instructions: u64,
    pub max_write_instructions: u64,
    /// Per tick (index = tick): the previous tick's write time as the board's pipeline got it
    /// (`RawInput::prev_write_done_counts`, 170 MHz counts; `u32::MAX`: ran into the next
    /// period). The in-process reference is fed the same.
    pub prev_write_done: Vec<u32>,
}

impl Trace {
    /// Ticks whose pipeline was told the previous tick's writes finished after its first PWM
    /// period (`pwm_counts`, 170 MHz timer counts): in emulated time, the board's late writes.
    pub fn late_writes_seen(&self, pwm_counts: u32) -> usize {
        self.prev_write_done
            .iter()
            .filter(|&&c| c >= pwm_counts)
            .count()
    }
}

/// The run's settings.
#[derive(Clone, Copy, Debug)]
pub struct Settings {
    pub timing: BoardTiming,
    /// Ticks of the scene after arming.
    pub scene_ticks: u64,
    pub fault: Fault,
    /// Ticks from the scene's start to the fault.
    pub fault_offset: u64,
    /// The scripted application session runs (`softfinger_app::scripted_app`).
    pub app_session: bool,
}

impl Settings {
    /// The control rate, Hz.
    pub fn rate_hz(&self) -> u32 {
        self.timing.control_hz
    }

    /// The fault's tick, once the scene has started.
    pub fn fault_tick(&self, scene_start: Option<u64>) -> Option<u64> {
        scene_start.map(|s| s + self.fault_offset)
    }

    /// Tick `k` is past the end of the run.
    pub fn finished(&self, k: u64, scene_start: Option<u64>) -> bool {
        scene_start.is_some_and(|s| k >= s + self.scene_ticks)
    }
}

/// 25 MHz board counts per control period.
fn period_counts(rate_hz: u32) -> u64 {
    25_000_000 / u64::from(rate_hz)
}

/// Guest instructions per 25 MHz board count (`-icount shift=3`: 8 ns per instruction).
pub const INSTRUCTIONS_PER_BOARD_COUNT: u64 = 5;

/// Instructions at [`CCM_CYCLES_PER_INSTRUCTION`] in 170 MHz timer counts (rounded up).
pub fn instructions_to_timer_counts(instructions: u64) -> u32 {
    let c = (instructions as f64 * f64::from(CCM_CYCLES_PER_INSTRUCTION)).ceil();
    c.min(f64::from(u32::MAX)) as u32
}

struct Lockstep<'a> {
    plant: Plant,
    s: &'a Settings,
    /// Set by another thread to end the run (the host-link check when it is done).
    stop: &'a AtomicBool,
    /// The host link owns the board's commands: the run ends on `stop` alone, never on the
    /// plant operator's scene length or homing wait (the host homes when its conversation gets
    /// there, and how much board time that takes depends on the host machine's speed).
    host_link: bool,
    op: Operator,
    /// Plant steps done = the current period.
    period: u64,
    /// The next tick the operator acts for.
    next_tick: u64,
    /// Board time of the current boot's origin, counts (moves at each reset).
    base: u64,
    /// When a reset is pending: the absolute time it happens.
    reset_at: Option<u64>,
    pins: BridgeCommands,
    /// PWM periods from the current period's start to the load of `pins`' compares.
    load_after: u32,
    /// This period's sample instant, instructions after the tick event: (period, instructions).
    sampled: Option<(u64, u64)>,
    trace: Trace,
}

impl Lockstep<'_> {
    fn advance_to(&mut self, target: u64) {
        while self.period < target {
            self.trace.pins.push(self.pins);
            self.plant
                .step_bridges_loading_after(&self.pins, &self.s.timing, self.load_after);
            // Loaded by the end of the step: a later period's step reloads the same values.
            self.load_after = 1;
            self.period += 1;
        }
    }

    /// (period, instructions after its tick event) of an absolute board time.
    fn instant(&self, absolute: u64) -> (u64, u64) {
        let per = period_counts(self.s.rate_hz());
        (
            absolute / per,
            absolute % per * INSTRUCTIONS_PER_BOARD_COUNT,
        )
    }

    /// New bridge commands at `absolute` board time: their compares load at the first PWM
    /// boundary after the write; a tick that sampled in this period gets its output timing.
    fn drive(&mut self, b: BridgeCommands, absolute: u64) {
        self.pins = b;
        let (period, write) = self.instant(absolute);
        // No sample in this period (a fault handler's write): timing from the event.
        let sampled = self.sampled.take().filter(|(p, _)| *p == period);
        let sample = sampled.map_or(0, |(_, i)| i);
        let t = OutputTiming::new(
            &self.s.timing,
            instructions_to_timer_counts(sample),
            instructions_to_timer_counts(write)
                .saturating_sub(instructions_to_timer_counts(sample)),
        );
        self.load_after = t.effect_counts / t.pwm_counts.max(1);
        if sampled.is_some() {
            self.trace.output.push(t);
            self.trace.max_sample_instructions = self.trace.max_sample_instructions.max(sample);
            self.trace.max_write_instructions = self.trace.max_write_instructions.max(write);
        }
    }

    fn sense_reply(&mut self, mode: Mode, prev_write_done: u32) -> [u8; wire::REPLY_LEN] {
        let k = self.period.saturating_sub(1);
        let at = k as usize;
        if at >= self.trace.prev_write_done.len() {
            self.trace.prev_write_done.resize(at + 1, 0);
        }
        self.trace.prev_write_done[at] = prev_write_done;
        let mut command = None;
        let mut app_step = false;
        if k >= self.next_tick {
            command = self.op.before_sample(k, mode, &mut self.plant);
            app_step = self.op.app_step(k);
            self.next_tick = k + 1;
        }
        let start = self.op.scene_start();
        self.trace.scene_start = start;
        let mut raw = RawInput {
            counts: self.plant.raw_counts(),
            ..RawInput::default()
        };
        let fault_tick = self.s.fault_tick(start);
        self.s.fault.edit_sample(k, fault_tick, &mut raw);
        let mut control = 0;
        let plant_ends =
            !self.host_link && (self.s.finished(k, start) || self.op.homing_timed_out(k));
        if plant_ends || self.stop.load(Ordering::Relaxed) {
            control |= wire::CONTROL_STOP;
            self.trace.homing_timed_out = !self.host_link && self.op.homing_timed_out(k);
        }
        if self.s.fault == Fault::LogStall && fault_tick.is_some_and(|f| k >= f) {
            control |= wire::CONTROL_LOG_STALL;
        }
        if self.s.fault.board_code() != 0 && fault_tick == Some(k) {
            control |= wire::CONTROL_INJECT;
        }
        self.trace.samples += 1;
        let code = if app_step && command.is_none() {
            wire::APP_STEP
        } else {
            command_code(command)
        };
        wire::sense_reply(raw.counts, raw.driver_fault, control, code)
    }
}

/// Serve the board until it says `Done` (or QEMU exits). Returns the trace.
pub fn run(emu: &mut Emulator, plant: Plant, s: &Settings) -> Result<Trace, PilError> {
    run_with_link(emu, plant, s, false, &AtomicBool::new(false))
}

/// [`run`], with the board's host link on UART0 when `host_link` (it then owns the board's
/// command queue), ended early when `stop` is set.
pub fn run_with_link(
    emu: &mut Emulator,
    plant: Plant,
    s: &Settings,
    host_link: bool,
    stop: &AtomicBool,
) -> Result<Trace, PilError> {
    let mut l = Lockstep {
        plant,
        s,
        stop,
        host_link,
        op: Operator::for_settings(s),
        period: 0,
        next_tick: 0,
        base: 0,
        reset_at: None,
        pins: BridgeCommands::OFF,
        load_after: 1,
        sampled: None,
        trace: Trace::default(),
    };
    let mut booted = false;
    loop {
        let st = wire::decode(&emu.receive()?)?;
        if let Message::Hello { reset_cause } = st.message {
            if let Some(at) = l.reset_at.take() {
                l.base = at;
                l.trace.resets.push(reset_cause);
            } else if booted {
                return Err(PilError::Rebooted);
            }
            // A fault is injected once: a rebooted board's test hook stays disarmed.
            let code = if booted { 0 } else { s.fault.board_code() };
            booted = true;
            emu.reply(&wire::hello_reply(
                s.rate_hz(),
                code,
                host_link,
                s.app_session && !host_link,
            ))?;
            continue;
        }
        l.advance_to((l.base + st.time_counts) / period_counts(s.rate_hz()));
        match st.message {
            Message::Hello { .. } => {}
            Message::Sense {
                mode,
                prev_write_done,
            } => {
                l.sampled = Some(l.instant(l.base + st.time_counts));
                let r = l.sense_reply(mode, prev_write_done);
                emu.reply(&r)?;
            }
            Message::Drive(b) => l.drive(b, l.base + st.time_counts),
            Message::Report { key, value } => {
                l.trace.reports.insert(key, value);
            }
            Message::ResetPending { counts } => {
                l.trace.watchdog_nmis += 1;
                l.reset_at = Some(l.base + st.time_counts + u64::from(counts));
            }
            Message::Done => {
                l.trace.done = true;
                break;
            }
            Message::Exited => break,
        }
    }
    Ok(l.trace)
}
