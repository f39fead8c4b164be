//! The control tick, board-independent: read the hardware -> run the control pipeline -> write the
//! hardware, then telemetry and tick statistics. Called by the board's tick interrupt, which runs
//! at the highest priority and owns a [`ControlLoop`] through `isr_cell::IsrCell`.
//!
//! The tick shares nothing with tasks except through atomics ([`STATUS`]) and lock-free SPSC
//! queues (commands in, telemetry and summaries out), so it never waits for a task.

use core::sync::atomic::{AtomicU32, Ordering};

use heapless::spsc::{Consumer, Producer};
use softfinger_core::controller::{Controller, TickInput};
use softfinger_core::encoder::EncoderBank;
use softfinger_core::output_guard::{phase_enable, Guarded, OutputGuard};
use softfinger_core::params::ContactParams;
use softfinger_core::telemetry::{Decimator, DropCounter, TelemetryRecord, TickStats, TickSummary};
use softfinger_core::{Fast, Flags};

use crate::board::{BridgeCommands, ControlHw};

/// An operator request, served at the start of the next tick.
#[derive(Clone, Copy, Debug)]
pub enum OperatorCommand {
    /// Clear latched faults (a condition still present latches again at once).
    ClearFaults,
    /// New contact parameters; the controller validates them.
    SetContactParams(ContactParams),
}

/// What the tick publishes for the tasks, one atomic per field.
pub struct TickStatus {
    /// Latched faults ([`Flags`] bits) as of the last tick.
    pub latched: AtomicU32,
    /// Commands served so far (wrapping): accepted in the low 16 bits, rejected in the high 16.
    pub command_results: AtomicU32,
}

/// The tick's published status.
pub static STATUS: TickStatus = TickStatus {
    latched: AtomicU32::new(0),
    command_results: AtomicU32::new(0),
};

/// Everything one tick reads and writes.
pub struct ControlLoop<H: ControlHw> {
    pub hw: H,
    pub controller: Controller<Fast>,
    pub guard: OutputGuard,
    pub bank: EncoderBank<6>,
    pub commands: Consumer<'static, OperatorCommand>,
    pub records: Producer<'static, TelemetryRecord>,
    pub summaries: Producer<'static, TickSummary>,
    pub decimator: Decimator,
    pub drops: DropCounter,
    pub stats: TickStats,
    /// PWM compare for 100 % duty, timer counts.
    pub pwm_full_scale: u16,
    /// Control rate, Hz (one tick-cost summary per second).
    pub rate_hz: u32,
    /// Ticks since start-up (wrapping).
    pub tick: u32,
    /// The previous tick overran (fed to the controller).
    pub overran: bool,
}

impl<H: ControlHw> ControlLoop<H> {
    /// One control tick. `entry_count` is the tick timer's count read as the interrupt's first
    /// action: the start latency, in timer counts. Never blocks, never panics.
    #[inline(always)]
    pub fn run(&mut self, entry_count: u32) {
        self.hw.ack_tick();
        let raw = self.hw.read_inputs();
        let (counts, encoder_flags) = self.bank.update(raw.counts);
        let input = TickInput {
            counts,
            driver_fault: raw.driver_fault,
            overrun: self.overran,
        };
        self.serve_commands();

        let output = self.controller.tick(&input);
        let mut events = encoder_flags;
        if raw.driver_fault {
            events |= Flags::DRIVER_FAULT;
        }
        let guarded = self.guard.apply(&output, events, self.stats.streak());
        self.hw.write_bridges(&self.bridge_commands(&guarded));
        self.hw.pet_watchdog();
        STATUS
            .latched
            .store(self.guard.latched().0, Ordering::Relaxed);

        let control_counts = self.hw.tick_timer_count().wrapping_sub(entry_count);
        if self.decimator.tick() {
            let record = TelemetryRecord::new(
                self.tick,
                &input,
                &output,
                (guarded.duties, guarded.enable, guarded.flags),
                control_counts,
            );
            let records = &mut self.records;
            self.drops.offer(|dropped_before| {
                records
                    .enqueue(TelemetryRecord {
                        dropped_before,
                        ..record
                    })
                    .is_ok()
            });
        }
        self.finish(entry_count);
    }

    /// Serve every queued operator command.
    fn serve_commands(&mut self) {
        while let Some(cmd) = self.commands.dequeue() {
            let accepted = match cmd {
                OperatorCommand::ClearFaults => {
                    self.controller.clear_faults();
                    self.guard.clear();
                    true
                }
                OperatorCommand::SetContactParams(p) => {
                    self.controller.set_contact_params(p).is_ok()
                }
            };
            let delta = if accepted { 1 } else { 1 << 16 };
            let sum = STATUS.command_results.load(Ordering::Relaxed);
            STATUS
                .command_results
                .store(sum.wrapping_add(delta), Ordering::Relaxed);
        }
    }

    /// Guarded duties -> bridge commands (zero torque via compare 0 and PWM disabled).
    fn bridge_commands(&self, g: &Guarded) -> BridgeCommands {
        let mut cmd = BridgeCommands {
            pwm_enable: g.enable,
            driver_awake: g.enable,
            ..BridgeCommands::OFF
        };
        if g.enable {
            for (i, duty) in g.duties.into_iter().enumerate() {
                let pe = phase_enable(duty, u32::from(self.pwm_full_scale));
                cmd.phase_forward[i] = pe.forward;
                cmd.compare[i] = pe.compare.min(u32::from(self.pwm_full_scale)) as u16;
            }
        }
        cmd
    }

    /// Tick statistics: duration from the timer event to now, overruns, the once-a-second summary.
    fn finish(&mut self, entry_count: u32) {
        let pending = self.hw.tick_event_pending();
        let now = self.hw.tick_timer_count();
        let total = if pending {
            // Ran into the next period: the counter restarted from 0 once.
            now + self.hw.tick_period_counts()
        } else {
            now
        };
        let duration = total.wrapping_sub(entry_count);
        // A tick starting more than half a period after its event is late, as is one that ran over.
        let late = pending || entry_count > self.hw.tick_period_counts() / 2;
        self.overran = self.stats.record(duration, late);
        if self.stats.ticks() >= self.rate_hz {
            // A lost summary (logger stalled for seconds) is not worth more than its absence.
            let _ = self
                .summaries
                .enqueue(self.stats.take_summary(self.drops.total()));
        }
        self.tick = self.tick.wrapping_add(1);
    }
}
