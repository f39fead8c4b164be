//! The emulated board's hardware layer for the app: [`Mps2Control`] implements `ControlHw` (the
//! tick timer, the plant link's encoder counts, nFAULT and bridges, the watchdog), [`Led`] the
//! status LED, and the tick interrupt runs the app's `ControlLoop` at the highest priority.
//!
//! Timing: under `-icount shift=3` one instruction is 8 ns of virtual time (125 M instructions/s,
//! standing for the STM32G474's 170 MHz at 1.36 cycles per instruction; mcu-bench/README.md plans
//! with 1.1-1.5). The CMSDK timers count at 25 MHz (5 instructions per count); the app and the
//! pipeline get counts of the STM32's 170 MHz timer clock, scaled by 6.8 (34/5), so the pipeline's
//! timing figures mean the same on both boards.
#![allow(unsafe_code)]

use core::sync::atomic::{AtomicBool, AtomicU32, Ordering};

use cortex_m::peripheral::NVIC;
use heapless::spsc::Consumer;
use softfinger_core::control::pipeline::{BridgeCommands, CheckedCommand};

use super::cmsdk::{FreeRunning, Irq, Watchdog, PCLK_HZ, TICK_TIMER};
use super::defmt_sink::READER_STALLED;
use super::link::{self, CONTROL_INJECT, CONTROL_LOG_STALL, CONTROL_STOP};
use softfinger_app::board::{CommandSource, ControlHw, Indicator, RawSample};
use softfinger_app::isr_cell::IsrCell;
use softfinger_app::tick::{ControlLoop, STATUS};

/// The critical section's BASEPRI: masks everything below the tick (priority 0x00).
pub const BASEPRI_BELOW_TICK: u8 = 0x20;
/// Priority of the embassy-time base interrupt (below the tick, above thread mode).
pub const TIME_BASE_PRIORITY: u8 = 0x80;
/// Instructions per 25 MHz timer count at `-icount shift=3`.
pub const INSTRUCTIONS_PER_COUNT: u32 = 5;

/// A 25 MHz count in 170 MHz timer counts (×6.8).
#[inline(always)]
fn timer_counts(c25: u32) -> u32 {
    c25 * 34 / 5
}

/// Bridges off, from any context (panic, HardFault, NMI).
pub fn emergency_stop() {
    link::drive(&BridgeCommands::OFF);
}

/// A fault the test hook injects in the tick when the plant asks (emulated board only).
#[derive(Clone, Copy, Debug, PartialEq, Eq, defmt::Format)]
pub enum Injected {
    None,
    /// `panic!` inside the tick.
    Panic,
    /// The tick never returns (the watchdog must reset the MCU).
    Hang,
}

impl Injected {
    /// From the `Hello` reply's code (1 panic, 2 hang; others are the plant's to make).
    pub fn from_code(code: u32) -> Injected {
        match code {
            1 => Injected::Panic,
            2 => Injected::Hang,
            _ => Injected::None,
        }
    }
}

/// The run is over (or the host went away): the tick stops after this one.
static STOP_REQUESTED: AtomicBool = AtomicBool::new(false);
/// The tick is stopped.
pub static STOPPED: AtomicBool = AtomicBool::new(false);
/// Largest start latency (timer event to the interrupt's first timer read), instructions.
pub static MAX_LATENCY: AtomicU32 = AtomicU32::new(0);
/// Largest whole interrupt (timer event to its last timer read), instructions.
pub static MAX_TICK: AtomicU32 = AtomicU32::new(0);
/// Ticks run, and ticks that ran into the next period.
pub static TICKS: AtomicU32 = AtomicU32::new(0);
pub static OVERRUNS: AtomicU32 = AtomicU32::new(0);

/// The scripted application's updates on their way to the tick: prepared and checked in thread
/// mode (the application's side, as a host link checks a request where it arrives), applied
/// where they wait on the plant's [`link::APP_STEP`] (as a host link's request arrives: served at
/// the end of that tick).
pub struct AppFeed {
    pub ready: Consumer<'static, CheckedCommand>,
}

/// Everything the control interrupt touches on this board.
pub struct Mps2Control {
    /// Tick period in 170 MHz timer counts.
    period_counts: u32,
    /// The plant's operator commands count (false while the host link owns the commands).
    plant_operator: bool,
    /// The plant operator's command that came with this tick's sample (unit variants only: set
    /// by a tag store, never a 92-byte copy).
    operator: Option<CheckedCommand>,
    fault: Injected,
    /// With the scripted application session.
    app: Option<AppFeed>,
    /// This tick's sample asked for the session's next update.
    app_step: bool,
    /// The previous tick's write time as the pipeline gets it, sent with the sample request.
    prev_write_done: u32,
}

impl Mps2Control {
    pub fn new(
        period_counts: u32,
        plant_operator: bool,
        fault: Injected,
        app: Option<AppFeed>,
    ) -> Self {
        Mps2Control {
            period_counts,
            plant_operator,
            operator: None,
            fault,
            app,
            app_step: false,
            prev_write_done: 0,
        }
    }

    /// Take the plant's operator command of a reply's byte 14 ([`link::HOME`] ..= [`link::CLEAR_FAULTS`]).
    #[inline(always)]
    fn take_operator_command(&mut self, code: u8) {
        self.operator = match code {
            link::HOME => Some(CheckedCommand::Home),
            link::ARM => Some(CheckedCommand::Arm),
            link::DISARM => Some(CheckedCommand::Disarm),
            link::CLEAR_FAULTS => Some(CheckedCommand::ClearFaults),
            _ => None,
        };
    }
}

impl ControlHw for Mps2Control {
    fn tick_period_counts(&self) -> u32 {
        self.period_counts
    }

    #[inline(always)]
    fn tick_timer_count(&self) -> u32 {
        timer_counts(TICK_TIMER.reload_value().wrapping_sub(TICK_TIMER.value()))
    }

    #[inline(always)]
    fn ack_tick(&mut self) {
        TICK_TIMER.clear();
    }

    #[inline(always)]
    fn tick_event_pending(&self) -> bool {
        TICK_TIMER.pending()
    }

    #[inline(always)]
    fn read_inputs(&mut self) -> RawSample {
        let Some(s) = link::sense(STATUS.mode.load(Ordering::Relaxed), self.prev_write_done) else {
            // The plant is gone: stop, and report a driver fault so this tick drives nothing.
            // The sampled command needs no clearing here: `sampled_command_done` cleared the
            // last one on the tick that applied it, and this tick is the run's last.
            STOP_REQUESTED.store(true, Ordering::Relaxed);
            return RawSample {
                counts: [0; 6],
                driver_fault: true,
            };
        };
        if s.control & CONTROL_STOP != 0 {
            STOP_REQUESTED.store(true, Ordering::Relaxed);
        }
        READER_STALLED.store(s.control & CONTROL_LOG_STALL != 0, Ordering::Relaxed);
        if s.control & CONTROL_INJECT != 0 {
            match self.fault {
                Injected::None => {}
                Injected::Panic => panic!("injected panic in the tick"),
                #[allow(clippy::empty_loop)]
                Injected::Hang => loop {},
            }
        }
        // Served at the end of this tick, in effect from the next (as a button press would be).
        self.app_step = s.command == link::APP_STEP && self.app.is_some();
        if self.plant_operator {
            self.take_operator_command(s.command);
        }
        RawSample {
            counts: s.counts,
            driver_fault: s.n_fault_asserted,
        }
    }

    #[inline(always)]
    fn write_bridges(&mut self, cmd: &BridgeCommands) {
        link::drive(cmd);
    }

    #[inline(always)]
    fn sampled_command(&self) -> Option<(CommandSource, &CheckedCommand)> {
        if let Some(c) = &self.operator {
            return Some((CommandSource::Operator, c));
        }
        if !self.app_step {
            return None;
        }
        // None ready (the application's task starved): the update is missed, and the
        // comparison with the in-process run shows it.
        let c = self.app.as_ref()?.ready.peek()?;
        Some((CommandSource::Host, c))
    }

    #[inline(always)]
    fn sampled_command_done(&mut self) {
        if self.operator.take().is_some() {
            return;
        }
        if core::mem::take(&mut self.app_step) {
            if let Some(app) = &mut self.app {
                let _ = app.ready.dequeue();
            }
        }
    }

    #[inline(always)]
    fn pet_watchdog(&mut self) {
        Watchdog::pet();
    }

    #[inline(always)]
    fn prev_write_done(&mut self, counts: u32) {
        self.prev_write_done = counts;
    }
}

/// The status LED: the FPGA's LED 0 (QEMU hw/misc/mps2-fpgaio.c).
pub struct Led;

impl Indicator for Led {
    fn set(&mut self, on: bool) {
        // SAFETY: the FPGAIO LED register of mps2-an386.
        unsafe { (0x4002_8000 as *mut u32).write_volatile(u32::from(on)) };
    }
}

/// Where the tick's state stream goes: the host link's queue in the local-model build (the
/// STM32's USB build), nowhere in the fixed plane's (the STM32's default build).
pub type StreamTx = heapless::spsc::Producer<'static, softfinger_app::stream::StreamPoint>;

/// The stream's end when no host link runs: a queue nobody reads (the tick's code stays the
/// linked run's; the divisor stays 0, so nothing is queued).
pub fn idle_stream() -> Option<StreamTx> {
    use heapless::spsc::Queue;
    let q = cortex_m::singleton!(: Queue<softfinger_app::stream::StreamPoint, 2> = Queue::new())?;
    Some(q.split().0)
}

static CONTROL: IsrCell<ControlLoop<Mps2Control, StreamTx>> = IsrCell::new();

/// Set the interrupt priorities: the tick highest, the time base below it.
pub fn set_priorities(nvic: &mut NVIC) {
    // SAFETY: done before either interrupt is unmasked.
    unsafe {
        nvic.set_priority(Irq::Timer0, 0x00);
        nvic.set_priority(Irq::Timer1, TIME_BASE_PRIORITY);
    }
}

/// Hand the loop to the interrupt and start it: watchdog, then the tick timer (board time 0).
pub fn start_tick(
    control: ControlLoop<Mps2Control, StreamTx>,
    rate_hz: u32,
    watchdog_counts: u32,
) -> bool {
    if CONTROL.install(control).is_err() {
        return false;
    }
    TICK_TIMER.configure(PCLK_HZ / rate_hz);
    Watchdog::start(watchdog_counts);
    // Board time restarts with the tick timer, so the plant's control periods line up with it.
    FreeRunning::start();
    TICK_TIMER.start();
    // SAFETY: the loop is installed; it is touched by this interrupt only from now on.
    unsafe { NVIC::unmask(Irq::Timer0) };
    true
}

/// The run is over: tick and watchdog stopped, bridges off.
fn stop() {
    TICK_TIMER.stop();
    NVIC::mask(Irq::Timer0);
    Watchdog::stop();
    emergency_stop();
    STOPPED.store(true, Ordering::Release);
}

/// APB timer 0: the control tick, and the board's measurement of it.
#[allow(unsafe_code)] // `no_mangle`: the vector table (vectors.rs) names it
#[no_mangle]
extern "C" fn TIMER0() {
    let reload = TICK_TIMER.reload_value();
    let entry = TICK_TIMER.value();
    let since_event = reload.wrapping_sub(entry);
    // SAFETY: after `start_tick` only this handler touches the loop, and it does not re-enter
    // (highest priority).
    if let Some(control) = unsafe { CONTROL.get_mut() } {
        control.run(timer_counts(since_event));
    }
    let end = TICK_TIMER.value();
    let ran_over = TICK_TIMER.pending();
    let latency = since_event * INSTRUCTIONS_PER_COUNT;
    let mut whole = reload.wrapping_sub(end);
    if ran_over {
        whole += reload + 1;
    }
    MAX_LATENCY.fetch_max(latency, Ordering::Relaxed);
    MAX_TICK.fetch_max(whole * INSTRUCTIONS_PER_COUNT, Ordering::Relaxed);
    TICKS.fetch_add(1, Ordering::Relaxed);
    if ran_over {
        OVERRUNS.fetch_add(1, Ordering::Relaxed);
    }
    if STOP_REQUESTED.load(Ordering::Relaxed) {
        stop();
    }
}
