//! softfinger firmware for the NUCLEO-G474RE (STM32G474RE, Cortex-M4F at 170 MHz).
//!
//! - `board`: the hardware traits the app is written against, and `board::stm32g474`, this
//!   binary's board (clocks, pins, timers, the tick interrupt).
//! - `tick`: the board-independent control tick (read -> control -> write), run by the board's
//!   highest-priority timer interrupt; `isr_cell` hands it its state without a lock.
//! - `logger`, `supervisor`, `operator`: board-independent low-priority tasks (telemetry log,
//!   fault report and blink code, the operator's button).
//!
//! The control logic itself is `softfinger-core`, tested on the host.
#![no_std]
#![no_main]
#![deny(unsafe_code)]

mod board;
#[allow(unsafe_code)] // the copy of the CCM code image; justified in place
mod ccm;
mod config;
#[allow(unsafe_code)] // implementing `critical_section::Impl` is unsafe by definition
mod critical_section_basepri;
#[allow(unsafe_code)] // cortex-m-rt requires the HardFault handler to be an `unsafe fn`
mod failsafe;
#[allow(unsafe_code)] // the lock-free handoff to the interrupt; each block justified in place
mod isr_cell;
mod logger;
mod operator;
mod supervisor;
mod tick;

use board::stm32g474::{self as bsp, Board};
use defmt::{error, info};
use defmt_rtt as _;
use embassy_executor::{Executor, Spawner};
use heapless::spsc::{Consumer, Producer, Queue};
use softfinger_core::controller::{Controller, ControllerConfig};
use softfinger_core::encoder::EncoderBank;
use softfinger_core::output_guard::OutputGuard;
use softfinger_core::telemetry::{Decimator, DropCounter, TelemetryRecord, TickStats, TickSummary};
use softfinger_core::Fast;
use tick::{ControlLoop, OperatorCommand};

#[embassy_executor::task]
async fn logger_task(
    records: Consumer<'static, TelemetryRecord>,
    summaries: Consumer<'static, TickSummary>,
) {
    logger::run(records, summaries).await
}

#[embassy_executor::task]
async fn supervisor_task(led: bsp::Led) {
    supervisor::run(led).await
}

#[embassy_executor::task]
async fn operator_task(button: bsp::Button, commands: Producer<'static, OperatorCommand>) {
    operator::run(button, commands).await
}

/// The validated configuration: built before any peripheral is configured.
struct Validated {
    controller: Controller<Fast>,
    guard: OutputGuard,
}

fn validate() -> Result<Validated, softfinger_core::controller::ParamError> {
    let controller = Controller::new(ControllerConfig {
        rate_hz: config::CONTROL_RATE_HZ as f32,
        ..ControllerConfig::default()
    })?;
    let guard = OutputGuard::new(config::GUARD)?;
    Ok(Validated { controller, guard })
}

#[cortex_m_rt::entry]
fn main() -> ! {
    // First: the tick's code into CCM SRAM, before anything placed there can run.
    ccm::load();
    let Some(mut core) = cortex_m::Peripherals::take() else {
        failsafe::halt()
    };
    bsp::prepare_core(&mut core.NVIC);
    let Some(executor) = cortex_m::singleton!(: Executor = Executor::new()) else {
        failsafe::halt()
    };
    executor.run(|spawner| match start(spawner) {
        Ok(task) => spawner.spawn(task),
        Err(_) => failsafe::halt(),
    })
}

/// Start-up, as the first task: validate, configure, spawn the tasks, start the tick.
#[embassy_executor::task]
async fn start(spawner: Spawner) {
    let p = embassy_stm32::init(bsp::hal_config());
    bsp::after_hal_init();
    info!(
        "softfinger firmware: control {=u32} Hz, PWM {=u32} Hz ({=u16} counts), telemetry {=u32} Hz",
        config::CONTROL_RATE_HZ,
        config::PWM_FREQ_HZ,
        config::PWM_FULL_SCALE,
        config::LOG_RATE_HZ
    );

    let valid = match validate() {
        Ok(v) => v,
        Err(e) => {
            // No peripheral configured: every bridge pin is still in its reset state (analog,
            // undriven), so the drivers' nSLEEP/EN pull-downs hold them off.
            error!("configuration rejected: {}; control loop not started", e);
            return;
        }
    };
    let Some(commands) =
        cortex_m::singleton!(: Queue<OperatorCommand, {config::COMMAND_QUEUE_LEN}> = Queue::new())
    else {
        return;
    };
    let Some(records) = cortex_m::singleton!(: Queue<TelemetryRecord, {config::TELEMETRY_QUEUE_LEN}> = Queue::new())
    else {
        return;
    };
    let Some(summaries) =
        cortex_m::singleton!(: Queue<TickSummary, {config::SUMMARY_QUEUE_LEN}> = Queue::new())
    else {
        return;
    };
    let (command_tx, command_rx) = commands.split();
    let (record_tx, record_rx) = records.split();
    let (summary_tx, summary_rx) = summaries.split();

    let Board {
        mut control,
        led,
        button,
    } = Board::new(p);
    match logger_task(record_rx, summary_rx) {
        Ok(t) => spawner.spawn(t),
        Err(e) => error!("logger task not spawned: {}", e),
    }
    match supervisor_task(led) {
        Ok(t) => spawner.spawn(t),
        Err(e) => error!("supervisor task not spawned: {}", e),
    }
    match operator_task(button, command_tx) {
        Ok(t) => spawner.spawn(t),
        Err(e) => error!("operator task not spawned: {}", e),
    }

    use board::ControlHw;
    let bank = EncoderBank::new(control.read_inputs().counts, config::MAX_COUNTS_PER_TICK);
    let control_loop = ControlLoop {
        hw: control,
        controller: valid.controller,
        guard: valid.guard,
        bank,
        commands: command_rx,
        records: record_tx,
        summaries: summary_tx,
        decimator: Decimator::new(config::CONTROL_RATE_HZ, config::LOG_RATE_HZ),
        drops: DropCounter::new(),
        stats: TickStats::new(config::TICK_PERIOD_COUNTS),
        pwm_full_scale: config::PWM_FULL_SCALE,
        rate_hz: config::CONTROL_RATE_HZ,
        tick: 0,
        overran: false,
    };
    match bsp::start_tick(control_loop) {
        Ok(()) => info!(
            "control loop running; tick period {=u32} counts; watchdog {=u32} us",
            config::TICK_PERIOD_COUNTS,
            config::WATCHDOG_TIMEOUT_US
        ),
        Err(_) => error!("control loop already installed"),
    }
}
