//! softfinger firmware on the emulated board: QEMU mps2-an386 (Cortex-M4F), processor in the loop
//! with host-sim's plant (`scripts/pil`, `host-sim pil`).
//!
//! The same control code, configuration and logger task as the STM32G474 build; only the board
//! layer differs: CMSDK timers instead of TIM6/TIM15, the CMSDK watchdog (NMI, then reset) instead
//! of the IWDG, the plant link ([`link`]: semihosting, lock step) instead of the encoder timers and
//! TIM1, and a non-blocking defmt ring drained to a host file instead of RTT.
#![no_std]
#![no_main]
#![deny(unsafe_code)]

mod app;
mod cmsdk;
#[allow(dead_code)] // the STM32 build's configuration; not every item applies to this board
#[path = "../../config.rs"]
mod config;
mod control;
mod defmt_sink;
mod faults;
mod link;
#[path = "../../logger.rs"]
mod logger;
mod supervisor;
mod time_driver;
mod vectors;

use defmt::{error, info, warn};
use embassy_executor::Spawner;
use embassy_time::Timer;
use heapless::spsc::Queue;
use softfinger_core::controller::{Controller, ControllerConfig};
use softfinger_core::device::DeviceParams;
use softfinger_core::encoder::EncoderBank;
use softfinger_core::output_guard::OutputGuard;
use softfinger_core::telemetry::{Decimator, TelemetryRecord, TickStats, TickSummary};

use cmsdk::{FreeRunning, Irq, PCLK_HZ};
use control::{Injected, INSTRUCTIONS_PER_COUNT};

/// Watchdog timeout in 25 MHz counts (the STM32 build's timeout).
const WATCHDOG_COUNTS: u32 = config::WATCHDOG_TIMEOUT_US * (PCLK_HZ / 1_000_000);

/// End the emulation (semihosting exit), after writing out the log.
fn exit(success: bool) -> ! {
    defmt_sink::drain();
    cortex_m_semihosting::debug::exit(if success {
        cortex_m_semihosting::debug::EXIT_SUCCESS
    } else {
        cortex_m_semihosting::debug::EXIT_FAILURE
    });
    loop {
        cortex_m::asm::wfi();
    }
}

/// Report the run's figures to the plant, then end the emulation.
async fn finish() -> ! {
    // Let the logger task empty the queues and the reader drain the ring.
    Timer::after_millis(3 * config::LOGGER_POLL_MS).await;
    let (frames, drops) = defmt_sink::counters();
    use core::sync::atomic::Ordering::Relaxed;
    let figures = [
        control::TICKS.load(Relaxed),
        control::OVERRUNS.load(Relaxed),
        control::MAX_LATENCY.load(Relaxed),
        control::MAX_DURATION.load(Relaxed),
        frames,
        drops,
        control::telemetry_drops(),
    ];
    for (key, value) in figures.into_iter().enumerate() {
        link::report(key as u16 + 1, value);
    }
    link::send(link::Kind::Done, 0, 0, [0; 3], [0; 3]);
    exit(true)
}

#[embassy_executor::main]
async fn main(spawner: Spawner) {
    let reset_cause = faults::take_reset_cause();
    FreeRunning::start();
    defmt_sink::open();
    time_driver::start();
    // SAFETY: the time base's state is behind critical sections.
    #[allow(unsafe_code)]
    unsafe {
        cortex_m::peripheral::NVIC::unmask(Irq::Timer1);
    }
    if !link::open_link() {
        error!("no plant link (run under scripts/pil)");
        exit(false);
    }
    let boot = link::BootInfo {
        reset_cause,
        full_scale: DeviceParams::OMEGA_LIKE.pwm_period_counts as u16,
        max_duty: config::GUARD.max_duty,
        max_overrun_streak: config::GUARD.max_overrun_streak,
        max_counts_per_tick: config::MAX_COUNTS_PER_TICK,
    };
    let Some((rate_hz, fault_code, fault_tick)) = link::hello(&boot) else {
        exit(false);
    };
    if reset_cause != faults::CAUSE_POWER_ON {
        warn!("reset by the watchdog (cause {=u32})", reset_cause);
    }
    if !(1_000..=20_000).contains(&rate_hz) || PCLK_HZ % rate_hz != 0 {
        error!("control rate {=u32} Hz not supported", rate_hz);
        exit(false);
    }
    let period_instructions = PCLK_HZ / rate_hz * INSTRUCTIONS_PER_COUNT;
    info!(
        "softfinger PIL board: control {=u32} Hz ({=u32} instructions per period), telemetry {=u32} Hz",
        rate_hz, period_instructions, config::LOG_RATE_HZ
    );

    let controller_config = ControllerConfig {
        rate_hz: rate_hz as f32,
        ..ControllerConfig::default()
    };
    let (Ok(controller), Ok(guard)) = (
        Controller::new(controller_config),
        OutputGuard::new(config::GUARD),
    ) else {
        error!("configuration rejected; control loop not started");
        exit(false);
    };
    let Some(records) = cortex_m::singleton!(: Queue<TelemetryRecord, {config::TELEMETRY_QUEUE_LEN}> = Queue::new())
    else {
        exit(false);
    };
    let Some(summaries) =
        cortex_m::singleton!(: Queue<TickSummary, {config::SUMMARY_QUEUE_LEN}> = Queue::new())
    else {
        exit(false);
    };
    let (record_tx, record_rx) = records.split();
    let (summary_tx, summary_rx) = summaries.split();
    match logger::logger(record_rx, summary_rx) {
        Ok(t) => spawner.spawn(t),
        Err(e) => error!("logger task not spawned: {}", e),
    }
    match supervisor::supervisor() {
        Ok(t) => spawner.spawn(t),
        Err(e) => error!("supervisor task not spawned: {}", e),
    }

    let Some(first) = link::sense() else {
        exit(false);
    };
    let app = app::App::new(
        controller,
        guard,
        EncoderBank::new(first.counts, config::MAX_COUNTS_PER_TICK),
        record_tx,
        summary_tx,
        Decimator::new(rate_hz, config::LOG_RATE_HZ),
        TickStats::new(period_instructions),
        DeviceParams::OMEGA_LIKE.pwm_period_counts,
        rate_hz,
    );
    faults::set_watchdog_counts(WATCHDOG_COUNTS);
    let fault = Injected::from_code(fault_code);
    if fault != Injected::None {
        warn!("fault injection: {} at tick {=u32}", fault, fault_tick);
    }
    control::start(app, rate_hz, WATCHDOG_COUNTS, fault, fault_tick);
    info!("control loop running");
    loop {
        Timer::after_millis(config::LOGGER_POLL_MS).await;
        if control::STOPPED.load(core::sync::atomic::Ordering::Acquire) {
            finish().await;
        }
    }
}
