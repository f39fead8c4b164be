//! softfinger firmware for the NUCLEO-G474RE (STM32G474RE, Cortex-M4F at 170 MHz): the one image
//! users flash, with the USB host link, the application's local model (the default scene's plane
//! until an application sends one) and the button bench.
//!
//! The app is the board-independent library `softfinger-app` (`firmware/app`): the control tick,
//! the host link, the logger, supervisor and operator tasks. This binary adds the board:
//!
//! - `board::stm32g474`: clocks, pins, timers, the tick interrupt, the emergency stop.
//! - `ccm`: the tick's code copied to CCM SRAM at start-up.
//! - `usb_link`: the host link's transport (USB CDC-ACM).
//!
//! The control logic itself is `softfinger-core`, tested on the host.
#![no_std]
#![no_main]
#![deny(unsafe_code)]

mod board;
#[allow(unsafe_code)] // the copy of the CCM code image; justified in place
mod ccm;
mod usb_link;

// The critical section (BASEPRI, never masking the tick) and the fail-safe handlers (panic,
// HardFault, default handler: bridges off first), with this board's mask and emergency stop.
critical_section::set_impl!(
    softfinger_app::critical_section_basepri::BasepriCriticalSection<{ board::BASEPRI_BELOW_TICK }>
);
softfinger_app::install_fail_safe!(board::emergency_stop);

use board::stm32g474::{self as bsp, Board};
use defmt::{error, info};
use defmt_rtt as _;
use embassy_executor::{Executor, Spawner};
use heapless::spsc::Queue;
use heapless::spsc::{Consumer, Producer};
use softfinger_app::persist::DeviceStore;
use softfinger_app::reset_cause::ResetCause;
use softfinger_app::tap::Tap;
use softfinger_app::tick::{self, CommandOutcome, ControlLoop};
use softfinger_app::{config, failsafe, link, logger, operator, queues, stream, supervisor};
use softfinger_core::control::pipeline::CheckedCommand;
use softfinger_update::layout::G474;
use softfinger_update::{BootState, SelfTest};

/// The operator's end of the tick's command queue (the link has a queue of its own).
pub type CommandTx = Producer<'static, CheckedCommand>;

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

/// The device's flash: the settings store and the update's slots.
type Store = DeviceStore<bsp::BoardFlash>;

/// The USB device and the link tasks, the link sending to the tick's link command queue
/// (`link_commands`) and answering settings and update requests from `store`; returns the queue
/// the supervisor forwards to and the tick's end of the stream queue.
fn start_usb_link(
    spawner: &Spawner,
    usb: bsp::UsbParts,
    link_commands: Producer<'static, CheckedCommand>,
    store: Store,
    reset_cause: ResetCause,
) -> Option<(OutcomeTap, bsp::StreamTx)> {
    let link_stream = cortex_m::singleton!(
        : Queue<stream::StreamPoint, {stream::QUEUE_LEN}> = Queue::new()
    )?;
    let link_outcomes =
        cortex_m::singleton!(: Queue<CommandOutcome, {usb_link::LINK_QUEUE_LEN}> = Queue::new())?;
    let (stream_tx, stream) = link_stream.split();
    let (outcomes_tx, outcomes) = link_outcomes.split();
    let (device, class) = usb_link::build(usb.driver())?;
    match usb_device_task(device) {
        Ok(t) => spawner.spawn(t),
        Err(e) => error!("USB task not spawned: {}", e),
    }
    match usb_link_task(
        class,
        link_commands,
        link::task::LinkQueues { outcomes, stream },
        store,
        reset_cause,
    ) {
        Ok(t) => spawner.spawn(t),
        Err(e) => error!("USB link task not spawned: {}", e),
    }
    Some((outcomes_tx, stream_tx))
}

#[embassy_executor::task]
async fn usb_device_task(mut device: embassy_usb::UsbDevice<'static, usb_link::UsbDriver>) {
    device.run().await
}

#[embassy_executor::task]
async fn usb_link_task(
    class: embassy_usb::class::cdc_acm::CdcAcmClass<'static, usb_link::UsbDriver>,
    commands: Producer<'static, CheckedCommand>,
    queues: link::task::LinkQueues,
    mut store: Store,
    reset_cause: ResetCause,
) {
    self_test_and_confirm(&mut store).await;
    let pipeline = config::pipeline_config();
    let session = link::session::LinkSession::<{ usb_link::LINK_TX_BYTES }, Store>::with_store(
        &link::session::LinkConfig {
            info: link::info::InfoSource {
                name: config::DEVICE.name,
                firmware_version: env!("CARGO_PKG_VERSION"),
                control_rate_hz: config::CONTROL_RATE_HZ,
                max_force_n: pipeline.contact.max_force_n,
                min_stream_divisor: link::info::min_stream_divisor(config::CONTROL_RATE_HZ),
                watchdog_ms: config::BENCH_WATCHDOG_MS,
                reset_cause: reset_cause.name(),
            },
            timer_clock_hz: config::SYSCLK_HZ,
            contact: pipeline.contact,
        },
        store,
    );
    usb_link::run(class, session, commands, queues).await
}

/// How long the self-test watches the tick, ms.
const SELF_TEST_MS: u64 = 200;

/// The running image's self-test (clock, encoders, the tick running without an overrun, the
/// store read), and on a trial boot (just swapped in by an update) its confirm: passed, the
/// image is kept; failed, the device resets and the bootloader swaps the previous image back.
async fn self_test_and_confirm(store: &mut Store) {
    // The tick publishes its longest run since the logger last took it: seen non-zero (running)
    // and never past the period (no overrun) over the window.
    let mut ran = false;
    let mut overran = false;
    for _ in 0..(SELF_TEST_MS / 10) {
        embassy_time::Timer::after_millis(10).await;
        let longest = tick::STATUS
            .max_tick_counts
            .load(core::sync::atomic::Ordering::Relaxed);
        ran |= longest != 0;
        overran |= longest >= config::TICK_PERIOD_COUNTS;
    }
    let test = SelfTest {
        clock: bsp::clock_ok(),
        encoders: bsp::encoders_ok(),
        tick: ran && !overran,
        store: store.status() != softfinger_store::LoadStatus::FlashError,
    };
    let trial = store.boot_state() == BootState::Trial;
    match store.confirm(&test) {
        Ok(true) if trial => info!("update: the new image passed its self-test: confirmed"),
        Ok(true) => {}
        Ok(false) => {
            error!(
                "update: the new image failed its self-test ({}): resetting, the bootloader restores the previous one",
                test
            );
            embassy_time::Timer::after_millis(50).await;
            bsp::emergency_stop();
            cortex_m::peripheral::SCB::sys_reset();
        }
        Err(e) => error!("update: confirm failed: {}", e),
    }
    if store.boot_state() == BootState::RolledBack {
        error!("update: the last update failed its trial: the previous image was restored");
    }
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
    let (ccm_start, ccm_end) = ccm::loaded_range();
    bsp::write_protect_ccm(ccm_start, ccm_end);
    let reset_cause = bsp::take_reset_cause();
    info!("reset cause: {=str}", reset_cause.name());
    let mut pipeline = match pipeline {
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
        usb,
        flash,
    } = Board::new(periph);
    let store = Store::boot(flash, G474, env!("CARGO_PKG_VERSION"));
    let load = store.boot_load();
    info!(
        "{=str} (flags {=u8:#x}, boot {})",
        load.notice(),
        load.flags(),
        store.boot_state()
    );
    if let Some(why) = store.arm_refusal() {
        error!("arming refused: {=str}", why);
    }
    // The stored watchdog and stream defaults, before the first tick (boot_defaults.rs).
    let defaults = store.boot_defaults();
    match defaults.apply(&mut pipeline) {
        Ok(()) => info!("boot defaults: {}", defaults),
        Err(e) => error!(
            "stored watchdog.timeout_ms refused ({}): the built-in host watchdog stays",
            e
        ),
    }
    let Some((outcome_tap, stream_tx)) =
        start_usb_link(&spawner, usb, tasks.link_commands, store, reset_cause)
    else {
        return;
    };
    let command_tx = tasks.commands;
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
