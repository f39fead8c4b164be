//! The board-independent part of one control tick, as the STM32 build's `control.rs` runs it:
//! count extension and glitch checks, the controller, the output guard, the phase/enable mapping,
//! telemetry decimation with drop counting, and the tick statistics.
//!
//! Interim: this is the sequence of `ControlLoop::run` in `firmware/src/control.rs` with the
//! STM32 register accesses taken out. When `softfinger_core::pipeline::Pipeline` lands, `App::tick`
//! becomes one `Pipeline::tick(&RawInput)` call and this file goes away; host-sim's in-process
//! reference (`host-sim/src/pil/reference.rs`) changes with it.

use core::sync::atomic::Ordering;

use heapless::spsc::Producer;
use softfinger_core::controller::{Controller, TickInput};
use softfinger_core::encoder::EncoderBank;
use softfinger_core::output_guard::{phase_enable, OutputGuard};
use softfinger_core::telemetry::{Decimator, DropCounter, TelemetryRecord, TickStats, TickSummary};
use softfinger_core::{Fast, Flags};

use super::control::{CLEAR_REQUEST, LATCHED};
use super::link::Pins;

/// What the hardware layer read this tick.
#[derive(Clone, Copy, Debug, Default)]
pub struct RawInput {
    /// Raw 16-bit encoder timer counts: motor0..2, wrist0..2.
    pub counts: [u16; 6],
    /// nFAULT asserted, as read.
    pub driver_fault: bool,
}

/// The control state the tick interrupt owns.
pub struct App {
    pub controller: Controller<Fast>,
    pub guard: OutputGuard,
    pub bank: EncoderBank<6>,
    pub records: Producer<'static, TelemetryRecord>,
    pub summaries: Producer<'static, TickSummary>,
    pub decimator: Decimator,
    pub drops: DropCounter,
    pub stats: TickStats,
    /// PWM compare value for 100 % duty.
    pub full_scale: u32,
    /// Ticks in a statistics window (one second).
    pub window_ticks: u32,
    /// Ticks since start-up (wrapping).
    pub tick: u32,
    /// The previous tick overran.
    pub overran: bool,
    /// The last tick's input, output and guarded output, for its telemetry record.
    last: Option<TelemetryRecord>,
}

impl App {
    /// Assemble the state; `tick` starts at 0.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        controller: Controller<Fast>,
        guard: OutputGuard,
        bank: EncoderBank<6>,
        records: Producer<'static, TelemetryRecord>,
        summaries: Producer<'static, TickSummary>,
        decimator: Decimator,
        stats: TickStats,
        full_scale: u32,
        window_ticks: u32,
    ) -> App {
        App {
            controller,
            guard,
            bank,
            records,
            summaries,
            decimator,
            drops: DropCounter::new(),
            stats,
            full_scale,
            window_ticks,
            tick: 0,
            overran: false,
            last: None,
        }
    }

    /// Inputs to bridge commands. Never blocks, never panics.
    #[inline]
    pub fn tick(&mut self, raw: &RawInput) -> Pins {
        let (counts, encoder_flags) = self.bank.update(raw.counts);
        let input = TickInput {
            counts,
            driver_fault: raw.driver_fault,
            overrun: self.overran,
        };
        if CLEAR_REQUEST.swap(false, Ordering::Relaxed) {
            self.controller.clear_faults();
            self.guard.clear();
        }
        let output = self.controller.tick(&input);
        let mut events = encoder_flags;
        if raw.driver_fault {
            events |= Flags::DRIVER_FAULT;
        }
        let guarded = self.guard.apply(&output, events, self.stats.streak());
        LATCHED.store(self.guard.latched().0, Ordering::Relaxed);
        self.last = Some(TelemetryRecord::new(
            self.tick,
            &input,
            &output,
            (guarded.duties, guarded.enable, guarded.flags),
            0,
        ));
        let mut pins = Pins {
            pwm_enable: guarded.enable,
            driver_awake: guarded.enable,
            ..Pins::OFF
        };
        for (i, duty) in guarded.duties.iter().enumerate() {
            let cmd = phase_enable(if guarded.enable { *duty } else { 0.0 }, self.full_scale);
            pins.phase_forward[i] = cmd.forward;
            pins.compare[i] = cmd.compare.min(u32::from(u16::MAX)) as u16;
        }
        pins
    }

    /// After the outputs are written: telemetry (never waits) and the tick statistics.
    /// `control_cost` is the cost of the tick so far, `total_cost` the whole interrupt's, both in
    /// the unit of the statistics' budget; `late` marks an overrun seen by the hardware layer.
    #[inline]
    pub fn finish(&mut self, control_cost: u32, total_cost: u32, late: bool) {
        if self.decimator.tick() {
            if let Some(record) = self.last.take() {
                let records = &mut self.records;
                self.drops.offer(|dropped_before| {
                    records
                        .enqueue(TelemetryRecord {
                            dropped_before,
                            cycles: control_cost,
                            ..record
                        })
                        .is_ok()
                });
            }
        }
        self.overran = self.stats.record(total_cost, late);
        if self.stats.ticks() >= self.window_ticks {
            let _ = self
                .summaries
                .enqueue(self.stats.take_summary(self.drops.total()));
        }
        self.tick = self.tick.wrapping_add(1);
    }
}
