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
#[allow(dead_code)] // items for the emulated board's UART transport and the host tests
#[cfg(feature = "usb")]
mod link;
mod logger;
mod operator;
mod queues;
mod stream;
mod stream_point;
mod supervisor;
mod tap;
mod tick;
#[cfg(feature = "usb")]
mod usb_link;

use board::stm32g474::{self as bsp, Board};
use defmt::{error, info};
use defmt_rtt as _;
use embassy_executor::{Executor, Spawner};
#[cfg(feature = "usb")]
use heapless::spsc::Queue;
use heapless::spsc::{Consumer, Producer};
use softfinger_core::control::pipeline::Command;
use tap::Tap;
use tick::{CommandOutcome, ControlLoop};

/// The operator's end of the tick's command queue (shared with the USB link when there is one).
#[cfg(not(feature = "usb"))]
pub type CommandTx = Producer<'static, Command>;
/// The operator's end of the tick's command queue (shared with the USB link when there is one).
#[cfg(feature = "usb")]
pub type CommandTx = usb_link::SharedCommands;

/// Where the supervisor forwards command outcomes (`NoTap`: nowhere; with USB: the link's queue).
#[cfg(not(feature = "usb"))]
type OutcomeTap = tap::NoTap;
#[cfg(feature = "usb")]
type OutcomeTap = Producer<'static, CommandOutcome>;

#[embassy_executor::task]
async fn supervisor_task(
    led: bsp::Led,
    outcomes: Consumer<'static, CommandOutcome>,
    mut tap: OutcomeTap,
) {
    supervisor::run(led, outcomes, |o| tap.forward(o)).await
}

#[embassy_executor::task]
async fn operator_task(button: bsp::Button, commands: CommandTx) {
    operator::run(button, commands).await
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

/// The USB device and the link tasks; returns the queue the supervisor forwards to, the tick's
/// end of the stream queue, and the operator's share of the command queue.
#[cfg(feature = "usb")]
fn start_usb_link(
    spawner: &Spawner,
    usb: bsp::UsbParts,
    commands: Producer<'static, Command>,
) -> Option<(OutcomeTap, bsp::StreamTx, CommandTx)> {
    let link_stream = cortex_m::singleton!(
        : Queue<stream::StreamPoint, {stream::QUEUE_LEN}> = Queue::new()
    )?;
    let link_outcomes =
        cortex_m::singleton!(: Queue<CommandOutcome, {usb_link::LINK_QUEUE_LEN}> = Queue::new())?;
    let (stream_tx, stream) = link_stream.split();
    let (outcomes_tx, outcomes) = link_outcomes.split();
    let (operator, link) = usb_link::SharedCommands::new(commands)?;
    let (device, class) = usb_link::build(usb.driver())?;
    match usb_device_task(device) {
        Ok(t) => spawner.spawn(t),
        Err(e) => error!("USB task not spawned: {}", e),
    }
    match usb_link_task(class, link, link::task::LinkQueues { outcomes, stream }) {
        Ok(t) => spawner.spawn(t),
        Err(e) => error!("USB link task not spawned: {}", e),
    }
    Some((outcomes_tx, stream_tx, operator))
}

#[cfg(feature = "usb")]
#[embassy_executor::task]
async fn usb_device_task(mut device: embassy_usb::UsbDevice<'static, usb_link::UsbDriver>) {
    device.run().await
}

#[cfg(feature = "usb")]
#[embassy_executor::task]
async fn usb_link_task(
    class: embassy_usb::class::cdc_acm::CdcAcmClass<'static, usb_link::UsbDriver>,
    commands: usb_link::SharedCommands,
    queues: link::task::LinkQueues,
) {
    let pipeline = config::pipeline_config();
    let session = link::session::LinkSession::<{ usb_link::LINK_TX_BYTES }>::new(
        &link::session::LinkConfig {
            info: link::info::InfoSource {
                name: config::DEVICE.name,
                firmware_version: env!("CARGO_PKG_VERSION"),
                control_rate_hz: config::CONTROL_RATE_HZ,
                max_force_n: pipeline.contact.max_force_n,
                min_stream_divisor: link::info::min_stream_divisor(config::CONTROL_RATE_HZ),
                watchdog_ms: config::BENCH_WATCHDOG_MS,
            },
            timer_clock_hz: config::SYSCLK_HZ,
            contact: pipeline.contact,
        },
    );
    usb_link::run(class, session, commands, queues).await
}

/// Start-up, as the first task: validate, configure, spawn the tasks, start the tick.
#[embassy_executor::task]
async fn start(spawner: Spawner) {
    info!(
        "softfinger firmware: control {=u32} Hz, PWM {=u32} Hz ({=u16} counts), telemetry {=u32} Hz",
        config::CONTROL_RATE_HZ,
        config::PWM_FREQ_HZ,
        config::PWM_FULL_SCALE,
        config::LOG_RATE_HZ
    );
    // The whole configuration is validated (the pipeline built) before the peripherals are taken.
    let pipeline = tick::TickPipeline::new(config::pipeline_config());
    let periph = embassy_stm32::init(bsp::hal_config());
    bsp::after_hal_init();
    let pipeline = match pipeline {
        Ok(p) => p,
        Err(e) => {
            error!("configuration rejected: {}; control loop not started", e);
            Board::hold_safe(periph);
            return;
        }
    };
    info!("device {=str}; pipeline built", config::DEVICE.name);
    let Some((tick_ends, tasks)) = queues::take() else {
        return;
    };

    let Board {
        control,
        led,
        button,
        #[cfg(feature = "usb")]
        usb,
    } = Board::new(periph);
    #[cfg(not(feature = "usb"))]
    let (outcome_tap, stream_tx, command_tx): (OutcomeTap, bsp::StreamTx, CommandTx) =
        (tap::NoTap, stream::NoStream, tasks.commands);
    #[cfg(feature = "usb")]
    let Some((outcome_tap, stream_tx, command_tx)) = start_usb_link(&spawner, usb, tasks.commands) else {
        return;
    };
    match logger::task(tasks.records, tasks.summaries) {
        Ok(t) => spawner.spawn(t),
        Err(e) => error!("logger task not spawned: {}", e),
    }
    match supervisor_task(led, tasks.outcomes, outcome_tap) {
        Ok(t) => spawner.spawn(t),
        Err(e) => error!("supervisor task not spawned: {}", e),
    }
    match operator_task(button, command_tx) {
        Ok(t) => spawner.spawn(t),
        Err(e) => error!("operator task not spawned: {}", e),
    }

    let queues = tick_ends.with_stream(stream_tx);
    match bsp::start_tick(ControlLoop::new(control, pipeline, queues)) {
        Ok(skew) => info!(
            "control loop running: tick period {=u32} counts, PWM period {=u16} counts, tick timer {=i32} counts after the PWM timer; watchdog {=u32} us; drivers asleep until homed (hold B1 1 s)",
            config::TICK_PERIOD_COUNTS,
            config::PWM_FULL_SCALE,
            skew,
            config::WATCHDOG_TIMEOUT_US
        ),
        Err(e) => error!("control loop not started: {}", e),
    }
}
