//! The control tick of the emulated board: APB timer 0's interrupt at the highest priority reads
//! the plant's inputs, runs [`App::tick`], writes the bridges, pets the watchdog and keeps the tick
//! statistics, as `firmware/src/control.rs` does with TIM6 on the STM32.
//!
//! Costs are in instructions: under `-icount shift=3` one instruction is 8 ns of virtual time and
//! the timers count at 25 MHz, so one timer count is [`INSTRUCTIONS_PER_COUNT`] instructions (the
//! resolution of every figure here). 125 M instructions/s stand for the STM32G474 at 170 MHz with
//! 1.36 cycles per instruction (mcu-bench/README.md plans with 1.1-1.5).

use core::cell::RefCell;
use core::sync::atomic::{AtomicBool, AtomicU32, Ordering};

use cortex_m::peripheral::NVIC;
use critical_section::Mutex;

use super::app::{App, RawInput};
use super::cmsdk::{FreeRunning, Irq, Watchdog, PCLK_HZ, TICK_TIMER};
use super::defmt_sink::READER_STALLED;
use super::link::{self, Pins, CONTROL_LOG_STALL, CONTROL_STOP};

/// Instructions per 25 MHz timer count at `-icount shift=3` (8 ns per instruction).
pub const INSTRUCTIONS_PER_COUNT: u32 = 5;

/// Set by a task to ask the next tick to clear latched faults.
pub static CLEAR_REQUEST: AtomicBool = AtomicBool::new(false);
/// The guard's latched faults as of the last tick ([`softfinger_core::Flags`] bits).
pub static LATCHED: AtomicU32 = AtomicU32::new(0);
/// The host ended the run (or went away): the tick is stopped.
pub static STOPPED: AtomicBool = AtomicBool::new(false);
/// Largest start latency (timer event to the interrupt's first read), instructions.
pub static MAX_LATENCY: AtomicU32 = AtomicU32::new(0);
/// Largest whole-interrupt duration (first read to last read), instructions.
pub static MAX_DURATION: AtomicU32 = AtomicU32::new(0);
/// Ticks run and ticks that overran.
pub static TICKS: AtomicU32 = AtomicU32::new(0);
pub static OVERRUNS: AtomicU32 = AtomicU32::new(0);

/// A fault the host asked the firmware to inject (board test hook, emulated board only).
#[derive(Clone, Copy, Debug, PartialEq, Eq, defmt::Format)]
pub enum Injected {
    None,
    /// `panic!` inside the tick.
    Panic,
    /// The tick never returns (the watchdog must reset the MCU).
    Hang,
}

impl Injected {
    /// From the wire code (1 panic, 2 hang; anything else is handled by the plant side).
    pub fn from_code(code: u32) -> Injected {
        match code {
            1 => Injected::Panic,
            2 => Injected::Hang,
            _ => Injected::None,
        }
    }
}

struct Tick {
    app: App,
    fault: Injected,
    fault_tick: u32,
}

static CONTROL: Mutex<RefCell<Option<Tick>>> = Mutex::new(RefCell::new(None));

/// Hand the loop to the interrupt and start it: highest priority, watchdog, then the timer.
pub fn start(app: App, rate_hz: u32, watchdog_counts: u32, fault: Injected, fault_tick: u32) {
    critical_section::with(|cs| {
        CONTROL.borrow(cs).replace(Some(Tick {
            app,
            fault,
            fault_tick,
        }));
    });
    TICK_TIMER.configure(PCLK_HZ / rate_hz);
    if let Some(mut cp) = cortex_m::Peripherals::take() {
        // SAFETY: priorities are set before the interrupts are unmasked; P0 (highest) for the tick,
        // 0x80 for the time base, thread mode below both.
        #[allow(unsafe_code)]
        unsafe {
            cp.NVIC.set_priority(Irq::Timer0, 0x00);
            cp.NVIC.set_priority(Irq::Timer1, 0x80);
        }
    }
    Watchdog::start(watchdog_counts);
    // Board time restarts with the tick timer: time 0 is the tick timer's start, so the plant's
    // control periods line up with the timer's.
    FreeRunning::start();
    TICK_TIMER.start();
    // SAFETY: state shared with the handler is behind critical-section mutexes or atomics.
    #[allow(unsafe_code)]
    unsafe {
        NVIC::unmask(Irq::Timer0);
    }
}

/// The run is over: tick and watchdog stopped, outputs off.
fn stop() {
    TICK_TIMER.stop();
    Watchdog::stop();
    NVIC::mask(Irq::Timer0);
    link::drive(&Pins::OFF);
    STOPPED.store(true, Ordering::Release);
}

/// One tick: inputs, app, outputs, proof of life, statistics.
#[inline(always)]
fn run(t: &mut Tick) {
    let entry = TICK_TIMER.value();
    TICK_TIMER.clear();
    let reload = TICK_TIMER.reload_value();
    let latency = reload.wrapping_sub(entry) * INSTRUCTIONS_PER_COUNT;

    let Some(sensed) = link::sense() else {
        stop();
        return;
    };
    if sensed.control & CONTROL_STOP != 0 {
        stop();
        return;
    }
    READER_STALLED.store(sensed.control & CONTROL_LOG_STALL != 0, Ordering::Relaxed);
    if t.app.tick == t.fault_tick {
        match t.fault {
            Injected::None => {}
            Injected::Panic => panic!("injected panic in tick {}", t.fault_tick),
            #[allow(clippy::empty_loop)]
            Injected::Hang => loop {},
        }
    }
    let pins = t.app.tick(&RawInput {
        counts: sensed.counts,
        driver_fault: sensed.n_fault_asserted,
    });
    link::drive(&pins);
    Watchdog::pet();
    let control = entry.wrapping_sub(TICK_TIMER.value()) * INSTRUCTIONS_PER_COUNT;
    t.app.finish(control, latency + control, false);

    let end = TICK_TIMER.value();
    let ran_over = TICK_TIMER.pending();
    let duration = entry.wrapping_sub(end) * INSTRUCTIONS_PER_COUNT;
    MAX_LATENCY.fetch_max(latency, Ordering::Relaxed);
    MAX_DURATION.fetch_max(duration, Ordering::Relaxed);
    TICKS.fetch_add(1, Ordering::Relaxed);
    if ran_over || latency + duration > (reload + 1) * INSTRUCTIONS_PER_COUNT {
        OVERRUNS.fetch_add(1, Ordering::Relaxed);
    }
}

/// APB timer 0: the control tick.
#[allow(unsafe_code)] // `no_mangle`: the vector table (vectors.rs) names it
#[no_mangle]
extern "C" fn TIMER0() {
    critical_section::with(|cs| {
        if let Ok(mut slot) = CONTROL.borrow(cs).try_borrow_mut() {
            if let Some(t) = slot.as_mut() {
                run(t);
            }
        }
    });
}

/// Telemetry records dropped so far (queue full), as the app counts them.
pub fn telemetry_drops() -> u32 {
    critical_section::with(|cs| {
        CONTROL
            .borrow(cs)
            .borrow()
            .as_ref()
            .map_or(0, |t| t.app.drops.total())
    })
}
