//! The lock-step session: the plant advanced in control periods by the board's own clock, the
//! board's inputs sampled and its outputs applied exactly when its messages say.
//!
//! Plant time: every message carries the board time; the host steps the plant, one control period
//! at a time, up to the period that time falls in, each step with the bridge outputs held at the
//! end of that period (the PWM keeps running on its last compare values). So a tick that runs late
//! or not at all, a panic, and a watchdog reset all act on the plant when they act in virtual time.
//! Step j (from period j to j+1) applies, through the plant's one-period output latch, the outputs
//! of period j−1, which is what the in-process loop does.
//!
//! Ticks: the board samples once at boot (period 0, to seed its count extension); tick k (0-based)
//! samples in period k+1. The run stops at the first sample in period `ticks + 1`.

use super::faults::Fault;
use super::qemu::Emulator;
use super::wire::{self, BoardConfig, Message, Pins};
use crate::plant::Plant;
use std::collections::BTreeMap;

/// What the plant saw over the run.
#[derive(Clone, Debug, Default)]
pub struct Trace {
    /// The outputs held at the end of each period, index = period (0 = boot).
    pub pins: Vec<Pins>,
    /// The board's configuration at its first boot.
    pub config: Option<BoardConfig>,
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
}

/// The run's settings.
pub struct Settings {
    pub rate_hz: u32,
    pub ticks: u64,
    pub fault: Fault,
    /// 0-based tick of the fault.
    pub fault_tick: u64,
}

/// 25 MHz board counts per control period.
fn period_counts(rate_hz: u32) -> u64 {
    25_000_000 / u64::from(rate_hz)
}

struct Lockstep<'a> {
    plant: Plant,
    s: &'a Settings,
    dt: f64,
    full_scale: u32,
    /// Plant steps done = the current period.
    period: u64,
    /// Board time of the current session's origin, counts (moves at each reset).
    base: u64,
    /// When a reset is pending: the absolute time it happens.
    reset_at: Option<u64>,
    pins: Pins,
    trace: Trace,
}

impl Lockstep<'_> {
    fn advance_to(&mut self, target: u64) {
        while self.period < target {
            self.trace.pins.push(self.pins);
            let duties = self.pins.duties(self.full_scale);
            self.plant
                .step_with_enable(duties, self.pins.enabled(), self.dt);
            self.period += 1;
        }
    }

    fn period_of(&self, time_counts: u64) -> u64 {
        (self.base + time_counts) / period_counts(self.s.rate_hz)
    }

    fn sense_reply(&mut self) -> [u8; wire::REPLY_LEN] {
        let tick = self.period.saturating_sub(1);
        let mut counts = self.plant.counts().map(|c| c as u16);
        let mut n_fault = false;
        self.s
            .fault
            .edit_sample(tick, self.s.fault_tick, &mut counts, &mut n_fault);
        let mut control = 0;
        if self.period > self.s.ticks {
            control |= wire::CONTROL_STOP;
        }
        if self.s.fault == Fault::LogStall && tick >= self.s.fault_tick {
            control |= wire::CONTROL_LOG_STALL;
        }
        self.trace.samples += 1;
        wire::sense_reply(counts, n_fault, control)
    }
}

/// Serve the board until it says `Done` (or QEMU exits). Returns the trace and the plant.
pub fn run(emu: &mut Emulator, plant: Plant, s: &Settings) -> Result<(Trace, Plant), String> {
    let mut l = Lockstep {
        plant,
        s,
        dt: 1.0 / f64::from(s.rate_hz),
        full_scale: 1,
        period: 0,
        base: 0,
        reset_at: None,
        pins: Pins::OFF,
        trace: Trace::default(),
    };
    let fault_code = s.fault.board_code();
    let fault_tick = u32::try_from(s.fault_tick).unwrap_or(u32::MAX);
    loop {
        let st = wire::decode(&emu.receive()?)?;
        if let Message::Hello(cfg) = st.message {
            if let Some(at) = l.reset_at.take() {
                l.base = at;
                l.trace.resets.push(cfg.reset_cause);
            } else if l.trace.config.is_some() {
                return Err("the board rebooted without a watchdog NMI".into());
            }
            l.full_scale = cfg.full_scale.max(1);
            l.trace.config.get_or_insert(cfg);
            // A reboot answers with no fault: it is injected once.
            let code = if l.trace.resets.is_empty() { fault_code } else { 0 };
            emu.reply(&wire::hello_reply(s.rate_hz, code, fault_tick))?;
            continue;
        }
        let target = l.period_of(st.time_counts);
        l.advance_to(target);
        match st.message {
            Message::Hello(_) => {}
            Message::Sense => {
                let r = l.sense_reply();
                emu.reply(&r)?;
            }
            Message::Drive(p) => l.pins = p,
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
    Ok((l.trace, l.plant))
}
