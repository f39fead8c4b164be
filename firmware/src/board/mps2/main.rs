//! softfinger firmware on the emulated board: QEMU mps2-an386 (Cortex-M4F), processor in the loop
//! with host-sim's plant (`scripts/pil`, `host-sim pil`).
//!
//! The app is the STM32G474 binary's: the library `softfinger-app` (`firmware/app`: `tick`,
//! `logger`, `supervisor`, `failsafe`, `isr_cell`, `critical_section_basepri`, `config`, `link`, the
//! board traits); only the board differs:
//! CMSDK timers instead of TIM6/TIM15, the CMSDK watchdog (NMI, then reset) instead of the IWDG,
//! the plant link ([`link`]: semihosting, lock step) instead of the encoder timers, nFAULT and
//! TIM1, a non-blocking defmt ring drained to a host file instead of RTT, and the operator's
//! commands from the plant's operator instead of the B1 button (`operator` is not run).
//! The control rate comes from the host at boot; everything else is the firmware's `config`.
#![no_std]
#![no_main]
#![deny(unsafe_code)]

mod cmsdk;
mod defmt_sink;
mod faults;
mod hw;
mod link;
mod ram_flash;
mod time_driver;
mod uart;
mod vectors;

// The app's critical section (BASEPRI, never masking the tick) and fail-safe handlers (panic,
// HardFault, default handler: bridges off first), with this board's mask and emergency stop.
critical_section::set_impl!(
    softfinger_app::critical_section_basepri::BasepriCriticalSection<{ hw::BASEPRI_BELOW_TICK }>
);
softfinger_app::install_fail_safe!(hw::emergency_stop);

use defmt::{error, info, warn};
use embassy_executor::Spawner;
use embassy_time::Timer;
use heapless::spsc::{Consumer, Producer, Queue};
use softfinger_core::control::pipeline::{BoardTiming, CheckedCommand, PipelineConfig};

use cmsdk::{FreeRunning, Irq, PCLK_HZ};
use softfinger_app::link::info::{min_stream_divisor, InfoSource};
use softfinger_app::link::session::{LinkConfig, LinkSession};
use softfinger_app::link::task::LinkQueues;
use softfinger_app::persist::{DeviceStore, PacedFlash};
use softfinger_app::scripted_app::ScriptedApp;
use softfinger_app::tick::{self, CommandOutcome, ControlLoop};
use softfinger_app::{config, logger, queues, stream, supervisor};

/// Watchdog timeout in 25 MHz counts (the STM32 build's timeout).
const WATCHDOG_COUNTS: u32 = config::WATCHDOG_TIMEOUT_US * (PCLK_HZ / 1_000_000);

/// End-of-run figure keys (the host's `report::REPORT_KEYS`, in order from 1).
const FIGURES: usize = 6;

#[embassy_executor::task]
async fn supervisor_task(outcomes: Consumer<'static, CommandOutcome>) {
    supervisor::run(hw::Led, outcomes, |_| {}).await
}

/// Bytes of frames the host link holds for UART0 (about 20 state frames).
const LINK_TX_BYTES: usize = 2048;

/// How often the host link polls UART0 and the tick's queues, µs.
const LINK_POLL_US: u64 = 200;

#[embassy_executor::task]
async fn host_link_task(
    config: LinkConfig,
    commands: Producer<'static, CheckedCommand>,
    queues: LinkQueues,
) {
    // The settings store and the update's slots on the emulated flash, as the STM32 build has
    // them on its own (softfinger-update's layout::G474).
    let store = DeviceStore::boot(
        PacedFlash(ram_flash::RamFlash::erased()),
        softfinger_update::layout::G474,
        env!("CARGO_PKG_VERSION"),
    );
    info!("{=str}", store.boot_load().notice());
    let session = LinkSession::<LINK_TX_BYTES, _>::with_store(&config, store);
    softfinger_app::link::task::run(uart::Uart0::open(), session, commands, queues, LINK_POLL_US)
        .await
}

/// Updates the scripted application prepares ahead of the tick.
const APP_READY_LEN: usize = 4;

/// The scripted application (`softfinger_app::scripted_app`): its state stream on from the
/// start (drained here, as a host link would take it), its next updates kept ready for the tick
/// to apply on the plant's `APP_STEP`.
#[embassy_executor::task]
async fn scripted_app_task(
    rate_hz: u32,
    mut app: ScriptedApp,
    mut ready: Producer<'static, CheckedCommand>,
    mut stream: Consumer<'static, stream::StreamPoint>,
) {
    stream::set_divisor(ScriptedApp::stream_divisor(rate_hz));
    loop {
        while ready.ready() {
            // Checked here, as a host link checks a request where it arrives (the session's
            // commands are all valid: one refused would be missing, and the comparison with the
            // in-process run would show it).
            if let Ok(c) = app.next_command().check() {
                let _ = ready.enqueue(c);
            }
        }
        while stream.dequeue().is_some() {}
        Timer::after_micros(LINK_POLL_US).await;
    }
}

/// The host link's queues (command outcomes, stream points) and the tick's end of the stream;
/// `None` in a build without a stream (the fixed plane's).
fn link_queues(outcomes: Consumer<'static, CommandOutcome>) -> Option<(LinkQueues, hw::StreamTx)> {
    let q = cortex_m::singleton!(
        : Queue<stream::StreamPoint, { stream::QUEUE_LEN }> = Queue::new()
    )?;
    let (tx, rx) = q.split();
    Some((
        LinkQueues {
            outcomes,
            stream: rx,
        },
        tx,
    ))
}

/// What the host link says about this board at `rate_hz`.
fn host_link_config(
    rate_hz: u32,
    pipeline: &PipelineConfig<config::TickEnvironment>,
) -> LinkConfig {
    LinkConfig {
        info: InfoSource {
            name: config::DEVICE.name,
            firmware_version: env!("CARGO_PKG_VERSION"),
            control_rate_hz: rate_hz,
            max_force_n: pipeline.contact.max_force_n,
            min_stream_divisor: min_stream_divisor(rate_hz),
            watchdog_ms: config::BENCH_WATCHDOG_MS,
            // Every run of the emulator is a power-on.
            reset_cause: softfinger_app::reset_cause::ResetCause::PowerOn.name(),
        },
        // The board's tick-timer counts are scaled to the shared timing's 170 MHz clock.
        timer_clock_hz: pipeline.timing.timer_clock_hz,
        contact: pipeline.contact,
    }
}

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
    let figures: [u32; FIGURES] = [
        hw::TICKS.load(Relaxed),
        hw::OVERRUNS.load(Relaxed),
        hw::MAX_LATENCY.load(Relaxed),
        hw::MAX_TICK.load(Relaxed),
        frames,
        drops,
    ];
    for (key, value) in figures.into_iter().enumerate() {
        link::report(key as u16 + 1, value);
    }
    link::send(link::Kind::Done, 0, 0, [0; 3], [0; 3]);
    exit(true)
}

/// The firmware's pipeline configuration at `rate_hz` (the STM32 build's, rate aside).
fn pipeline_config(rate_hz: u32) -> PipelineConfig<config::TickEnvironment> {
    PipelineConfig {
        timing: BoardTiming {
            control_hz: rate_hz,
            pwm_hz: config::TIMING.pwm_hz.max(rate_hz),
            ..config::TIMING
        },
        ..config::pipeline_config()
    }
}

/// Bring up the board (interrupt priorities, the free-running counter, the log sink, the time
/// base, the plant link) and take the run's configuration from the plant; any failure ends the
/// emulation.
fn open_board(reset_cause: u32) -> link::RunConfig {
    let Some(mut core) = cortex_m::Peripherals::take() else {
        exit(false)
    };
    hw::set_priorities(&mut core.NVIC);
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
    let Some(run) = link::hello(reset_cause) else {
        exit(false)
    };
    if reset_cause != faults::CAUSE_POWER_ON {
        warn!("reset by the watchdog");
    }
    if !PCLK_HZ.is_multiple_of(run.rate_hz.max(1)) {
        error!("control rate {=u32} Hz does not divide 25 MHz", run.rate_hz);
        exit(false);
    }
    run
}

/// With the host link, its task takes the commands, their outcomes and the tick's stream
/// points; the plant's operator and the supervisor stand aside. Without it, nothing streams.
/// Returns the tick's stream and the scripted application's feed; any failure ends the
/// emulation.
fn spawn_command_side(
    spawner: Spawner,
    run: &link::RunConfig,
    config: &PipelineConfig<config::TickEnvironment>,
    link_command_tx: Producer<'static, CheckedCommand>,
    outcome_rx: Consumer<'static, CommandOutcome>,
) -> (hw::StreamTx, Option<hw::AppFeed>) {
    if run.host_link {
        let Some((queues, stream_tx)) = link_queues(outcome_rx) else {
            error!("the host link needs the local-model build (as the STM32's USB build)");
            exit(false)
        };
        match host_link_task(
            host_link_config(run.rate_hz, config),
            link_command_tx,
            queues,
        ) {
            Ok(t) => spawner.spawn(t),
            Err(e) => error!("host link task not spawned: {}", e),
        }
        return (stream_tx, None);
    }
    match supervisor_task(outcome_rx) {
        Ok(t) => spawner.spawn(t),
        Err(e) => error!("supervisor task not spawned: {}", e),
    }
    if !run.app_session {
        let Some(stream_tx) = hw::idle_stream() else {
            exit(false)
        };
        return (stream_tx, None);
    }
    let (Some(ready), Some(points)) = (
        cortex_m::singleton!(: Queue<CheckedCommand, APP_READY_LEN> = Queue::new()),
        cortex_m::singleton!(: Queue<stream::StreamPoint, { stream::QUEUE_LEN }> = Queue::new()),
    ) else {
        exit(false)
    };
    let (ready_tx, ready_rx) = ready.split();
    let (stream_tx, stream_rx) = points.split();
    let app = ScriptedApp::new(config.contact);
    match scripted_app_task(run.rate_hz, app, ready_tx, stream_rx) {
        Ok(t) => spawner.spawn(t),
        Err(e) => error!("scripted application task not spawned: {}", e),
    }
    (stream_tx, Some(hw::AppFeed { ready: ready_rx }))
}

#[embassy_executor::main]
async fn main(spawner: Spawner) {
    let reset_cause = faults::take_reset_cause();
    let run = open_board(reset_cause);
    let (rate_hz, fault_code) = (run.rate_hz, run.fault_code);
    let config = pipeline_config(rate_hz);
    let pipeline = match tick::TickPipeline::new(config) {
        Ok(p) => p,
        Err(e) => {
            error!("configuration rejected: {}; control loop not started", e);
            exit(false)
        }
    };
    info!(
        "softfinger PIL board: control {=u32} Hz, PWM {=u32} Hz, {=u32} instructions per period",
        rate_hz,
        config.timing.pwm_hz,
        PCLK_HZ / rate_hz * hw::INSTRUCTIONS_PER_COUNT
    );
    let Some((tick_ends, tasks)) = queues::take() else {
        exit(false)
    };
    match logger::task(tasks.records, tasks.summaries) {
        Ok(t) => spawner.spawn(t),
        Err(e) => error!("logger task not spawned: {}", e),
    }
    // No button task: the plant's operator gives its commands with the samples
    // (`hw::Mps2Control`), so the operator's queue stays empty.
    let (stream_tx, app) =
        spawn_command_side(spawner, &run, &config, tasks.link_commands, tasks.outcomes);
    let fault = hw::Injected::from_code(fault_code);
    if fault != hw::Injected::None {
        warn!("test hook armed: {}", fault);
    }
    if app.is_some() {
        info!("scripted application session: updates at 1 kHz once armed, stream at 2 kHz");
    }
    let control = hw::Mps2Control::new(
        config.timing.tick_period_counts(),
        !run.host_link,
        fault,
        app,
    );
    let queues = tick_ends.with_stream(stream_tx);
    faults::set_watchdog_counts(WATCHDOG_COUNTS);
    if !hw::start_tick(
        ControlLoop::new(control, pipeline, queues),
        rate_hz,
        WATCHDOG_COUNTS,
    ) {
        error!("control loop not started");
        exit(false);
    }
    info!("control loop running; drivers asleep until homed");
    loop {
        Timer::after_millis(config::LOGGER_POLL_MS).await;
        if hw::STOPPED.load(core::sync::atomic::Ordering::Acquire) {
            finish().await;
        }
    }
}
