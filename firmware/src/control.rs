//! The control tick: TIM6's update interrupt at the highest priority runs one complete tick.
//!
//! Why a plain timer interrupt rather than an embassy `InterruptExecutor` task: the tick is a
//! bounded, synchronous computation, so an executor adds nothing but latency and jitter (waking a
//! task, polling a future) to the one path that must be deterministic. Here the hardware timer is
//! the clock, the handler is the tick, and nothing can preempt it.
//!
//! Ownership: [`ControlLoop`] (every peripheral the tick touches, the controller, the guard, the
//! telemetry producers) is moved into [`CONTROL`] once at start-up and afterwards touched only by
//! the interrupt. Tasks talk to it through atomics: [`CLEAR_REQUEST`] in, [`LATCHED`] out.

use core::cell::{Cell, RefCell};
use core::sync::atomic::{AtomicBool, AtomicU32, Ordering};

use cortex_m::peripheral::DWT;
use critical_section::Mutex;
use embassy_stm32::interrupt;
use embassy_stm32::peripherals::{IWDG, TIM6};
use embassy_stm32::timer::low_level::Timer;
use embassy_stm32::wdg::IndependentWatchdog;
use heapless::spsc::Producer;
use softfinger_core::controller::{Controller, TickInput};
use softfinger_core::encoder::EncoderBank;
use softfinger_core::output_guard::OutputGuard;
use softfinger_core::params::ContactParams;
use softfinger_core::telemetry::{Decimator, DropCounter, TelemetryRecord, TickStats, TickSummary};
use softfinger_core::{Fast, Flags};

use crate::board::{Encoders, Motors};
use crate::config;

/// Set by a task to ask the next tick to clear latched faults (controller and guard).
pub static CLEAR_REQUEST: AtomicBool = AtomicBool::new(false);

/// Contact parameters waiting to be applied by the next control tick (set by a low-priority task).
/// The controller validates them: an invalid set is rejected and the old one stays in force.
pub static PARAM_REQUEST: Mutex<Cell<Option<ContactParams>>> = Mutex::new(Cell::new(None));

/// Outcome of the last parameter request, for the supervisor to log: 0 none yet, then
/// `PARAM_APPLIED` or `PARAM_REJECTED` in the low bits and a sequence number above them.
pub static PARAM_RESULT: AtomicU32 = AtomicU32::new(0);
/// [`PARAM_RESULT`] low bits: the request was applied.
pub const PARAM_APPLIED: u32 = 1;
/// [`PARAM_RESULT`] low bits: the request was rejected.
pub const PARAM_REJECTED: u32 = 2;

/// The guard's latched faults as of the last tick ([`Flags`] bits), for the supervisor task.
pub static LATCHED: AtomicU32 = AtomicU32::new(0);

/// The control loop's state, owned by the TIM6 interrupt once installed.
pub static CONTROL: Mutex<RefCell<Option<ControlLoop>>> = Mutex::new(RefCell::new(None));

/// Everything one tick reads and writes.
pub struct ControlLoop {
    pub encoders: Encoders,
    pub motors: Motors,
    pub tick_timer: Timer<'static, TIM6>,
    pub watchdog: IndependentWatchdog<'static, IWDG>,
    pub controller: Controller<Fast>,
    pub guard: OutputGuard,
    pub bank: EncoderBank<6>,
    pub records: Producer<'static, TelemetryRecord>,
    pub summaries: Producer<'static, TickSummary>,
    pub decimator: Decimator,
    pub drops: DropCounter,
    pub stats: TickStats,
    /// Ticks since start-up (wrapping).
    pub tick: u32,
    /// DWT cycle count at the previous tick's entry.
    pub last_entry: u32,
    /// The previous tick overran (fed to the controller as `TickInput::overrun`).
    pub overran: bool,
}

impl ControlLoop {
    /// One control tick. Never blocks, never panics.
    #[inline]
    fn run(&mut self) {
        let entry = DWT::cycle_count();
        self.tick_timer.clear_update_interrupt();
        // A tick that starts more than half a period late (delayed by a critical section in
        // thread mode, e.g. a log write) counts as an overrun as well.
        let period = config::TICK_BUDGET_CYCLES;
        let started_late =
            self.tick != 0 && entry.wrapping_sub(self.last_entry) > period + period / 2;
        self.last_entry = entry;

        // Inputs.
        let raw = self.encoders.read();
        let driver_fault = self.motors.fault();
        let (counts, encoder_flags) = self.bank.update(raw);
        let input = TickInput {
            counts,
            driver_fault,
            overrun: self.overran,
        };

        if let Some(params) = critical_section::with(|cs| PARAM_REQUEST.borrow(cs).take()) {
            let outcome = match self.controller.set_contact_params(params) {
                Ok(()) => PARAM_APPLIED,
                Err(_) => PARAM_REJECTED,
            };
            let seq = (PARAM_RESULT.load(Ordering::Relaxed) >> 2).wrapping_add(1);
            PARAM_RESULT.store(seq << 2 | outcome, Ordering::Relaxed);
        }

        if CLEAR_REQUEST.swap(false, Ordering::Relaxed) {
            self.controller.clear_faults();
            self.guard.clear();
        }

        // Controller, then the independent guard.
        let output = self.controller.tick(&input);
        let mut events = encoder_flags;
        if driver_fault {
            events |= Flags::DRIVER_FAULT;
        }
        let guarded = self.guard.apply(&output, events, self.stats.streak());

        // Outputs, then proof of life.
        self.motors.write(&guarded);
        self.watchdog.pet();
        LATCHED.store(self.guard.latched().0, Ordering::Relaxed);
        let control_cycles = DWT::cycle_count().wrapping_sub(entry);

        // Telemetry: never waits; a full queue drops the record and counts it.
        if self.decimator.tick() {
            let record = TelemetryRecord::new(
                self.tick,
                &input,
                &output,
                (guarded.duties, guarded.enable, guarded.flags),
                control_cycles,
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

        // Cost of the whole tick; `late` also catches a tick that ran into the next period.
        let total_cycles = DWT::cycle_count().wrapping_sub(entry);
        let ran_over = self.tick_timer.regs_core().sr().read().uif();
        self.overran = self.stats.record(total_cycles, started_late || ran_over);
        if self.stats.ticks() >= config::CONTROL_RATE_HZ {
            // A lost summary (logger stalled for seconds) is not worth more than its absence.
            let _ = self
                .summaries
                .enqueue(self.stats.take_summary(self.drops.total()));
        }
        self.tick = self.tick.wrapping_add(1);
    }
}

/// Hand the loop to the interrupt. Call before [`start`].
pub fn install(control: ControlLoop) {
    critical_section::with(|cs| {
        if let Ok(mut slot) = CONTROL.borrow(cs).try_borrow_mut() {
            slot.replace(control);
        }
    });
}

/// Start the tick: highest interrupt priority, then the watchdog, then the timer.
pub fn start() {
    use embassy_stm32::interrupt::{InterruptExt, Priority};
    interrupt::TIM6_DAC.set_priority(Priority::P0);
    interrupt::TIM6_DAC.unpend();
    critical_section::with(|cs| {
        if let Ok(mut slot) = CONTROL.borrow(cs).try_borrow_mut() {
            if let Some(c) = slot.as_mut() {
                c.watchdog.unleash();
                c.tick_timer.start();
            }
        }
    });
    // SAFETY: unmasking an interrupt is unsafe because it could break a critical section that
    // relies on that interrupt staying masked. Nothing here does: all state shared with this
    // handler is behind `critical_section::Mutex` (PRIMASK-based on this single-core part) or
    // atomics.
    #[allow(unsafe_code)]
    unsafe {
        interrupt::TIM6_DAC.enable();
    }
}

#[interrupt]
fn TIM6_DAC() {
    critical_section::with(|cs| {
        // Borrowing cannot fail here (nothing else holds it inside a critical section), but a
        // failed borrow must not panic: the tick is skipped and the watchdog notices.
        if let Ok(mut slot) = CONTROL.borrow(cs).try_borrow_mut() {
            if let Some(control) = slot.as_mut() {
                control.run();
            }
        }
    });
}
