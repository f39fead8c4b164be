//! softfinger firmware for the NUCLEO-G474RE (STM32G474RE, Cortex-M4F at 170 MHz).
//!
//! - `board`: clocks, pins and peripherals (encoders, bridges, tick timer, watchdog, button).
//! - `control`: the control tick, run by TIM6's update interrupt at the highest priority.
//! - `logger`, `supervisor`: low-priority embassy tasks (telemetry log, fault reporting and clear).
//!
//! The control logic itself (controller, count extension, output guard, telemetry bookkeeping) is
//! `softfinger-core`, tested on the host.
#![no_std]
#![no_main]
#![deny(unsafe_code)]

mod board;
mod config;
mod control;
mod logger;
mod supervisor;

use defmt::{error, info};
use embassy_executor::Spawner;
use embassy_stm32::interrupt::{self, InterruptExt, Priority};
use heapless::spsc::Queue;
use softfinger_core::controller::{Controller, ControllerConfig};
use softfinger_core::encoder::EncoderBank;
use softfinger_core::output_guard::OutputGuard;
use softfinger_core::telemetry::{Decimator, DropCounter, TelemetryRecord, TickStats, TickSummary};
use {defmt_rtt as _, panic_probe as _};

#[embassy_executor::main]
async fn main(spawner: Spawner) {
    let p = embassy_stm32::init(board::hal_config());
    info!(
        "softfinger firmware: control {=u32} Hz, PWM {=u32} Hz, telemetry {=u32} Hz",
        config::CONTROL_RATE_HZ,
        config::PWM_FREQ_HZ,
        config::LOG_RATE_HZ
    );
    // Everything embassy uses runs below the control tick (P0).
    interrupt::TIM1_BRK_TIM15.set_priority(Priority::P2); // embassy-time driver (TIM15)
    interrupt::EXTI15_10.set_priority(Priority::P3); // user button

    let board = board::Board::new(p);

    // DWT cycle counter for the tick cost.
    let Some(mut core_peripherals) = cortex_m::Peripherals::take() else {
        error!("core peripherals already taken; control loop not started");
        return;
    };
    core_peripherals.DCB.enable_trace();
    core_peripherals.DWT.enable_cycle_counter();

    // The device and scene parameters are the core's defaults; only the rate is the firmware's.
    let controller_config = ControllerConfig {
        rate_hz: config::CONTROL_RATE_HZ as f32,
        ..ControllerConfig::default()
    };
    let controller = match Controller::new(controller_config) {
        Ok(c) => c,
        Err(e) => {
            error!(
                "controller configuration rejected: {}; control loop not started",
                e
            );
            return;
        }
    };
    let guard = match OutputGuard::new(config::GUARD) {
        Ok(g) => g,
        Err(e) => {
            error!(
                "output guard configuration rejected: {}; control loop not started",
                e
            );
            return;
        }
    };

    let Some(records) = cortex_m::singleton!(: Queue<TelemetryRecord, {config::TELEMETRY_QUEUE_LEN}> = Queue::new())
    else {
        error!("telemetry queue already taken; control loop not started");
        return;
    };
    let Some(summaries) =
        cortex_m::singleton!(: Queue<TickSummary, {config::SUMMARY_QUEUE_LEN}> = Queue::new())
    else {
        error!("summary queue already taken; control loop not started");
        return;
    };
    let (record_tx, record_rx) = records.split();
    let (summary_tx, summary_rx) = summaries.split();

    match logger::logger(record_rx, summary_rx) {
        Ok(t) => spawner.spawn(t),
        Err(e) => error!("logger task not spawned: {}", e),
    }
    let board::Board {
        encoders,
        motors,
        tick_timer,
        watchdog,
        button,
        led,
    } = board;
    match supervisor::supervisor(led) {
        Ok(t) => spawner.spawn(t),
        Err(e) => error!("supervisor task not spawned: {}", e),
    }
    match supervisor::clear_button(button) {
        Ok(t) => spawner.spawn(t),
        Err(e) => error!("button task not spawned: {}", e),
    }

    info!(
        "PWM full scale {=u32} counts; tick budget {=u32} cycles; watchdog {=u32} us",
        motors.full_scale(),
        config::TICK_BUDGET_CYCLES,
        config::WATCHDOG_TIMEOUT_US
    );
    let bank = EncoderBank::new(encoders.read(), config::MAX_COUNTS_PER_TICK);
    control::install(control::ControlLoop {
        encoders,
        motors,
        tick_timer,
        watchdog,
        controller,
        guard,
        bank,
        records: record_tx,
        summaries: summary_tx,
        decimator: Decimator::new(config::CONTROL_RATE_HZ, config::LOG_RATE_HZ),
        drops: DropCounter::new(),
        stats: TickStats::new(config::TICK_BUDGET_CYCLES),
        tick: 0,
        last_entry: 0,
        overran: false,
    });
    control::start();
    info!("control loop running");
}
