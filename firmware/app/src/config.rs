//! Compile-time configuration of the firmware: the device, the board timing, queue sizes and task
//! periods. Safety limits and fault thresholds are the device definition's (softfinger-core,
//! physical units, derived for the control rate by the pipeline).

use softfinger_core::contact::params::ContactParams;
use softfinger_core::contact::RollingOnly;
use softfinger_core::control::device_definition::DeviceDefinition;
use softfinger_core::control::local_model::{LocalModelEnvironment, LocalModelSpec, ModelPose};
use softfinger_core::control::operator::ButtonTiming;
use softfinger_core::control::pipeline::{BoardTiming, PipelineConfig};
use softfinger_core::device::delta::DeltaGeometry;
use softfinger_core::omega_like::OMEGA_LIKE;
use softfinger_core::Vec3;

/// The device this firmware drives.
pub const DEVICE: DeviceDefinition = OMEGA_LIKE;

/// Timer clock, PWM and control rates, shared with host-sim's plant: 170 MHz, 40 kHz PWM
/// (4250 counts), 10 kHz control (four PWM periods per tick). The low-latency output: a compare
/// written in the tick's first PWM period acts from its second, a quarter tick after the tick's
/// event (`softfinger_core::control::pipeline::output_timing`).
pub const TIMING: BoardTiming = BoardTiming::STM32G474_10KHZ;
const _: () = assert!(TIMING.is_valid());
// Four PWM periods per tick: the delay the stability experiment and the passivity stage assume.
const _: () = assert!(TIMING.pwm_periods_per_tick() == 4);
// The device model's PWM period (duty -> voltage) is the one this board runs.
const _: () = assert!(DEVICE.params.pwm_period_counts == TIMING.pwm_period_counts());

/// The board's crystal (NUCLEO-G474RE X3), Hz.
pub const HSE_HZ: u32 = 24_000_000;

/// System clock, Hz: HSE 24 MHz / 6 × 85 / 2. TIM1 and TIM6 run at this clock (APB prescalers
/// 1, timer prescalers 1), which must be the shared timing's timer clock.
pub const SYSCLK_HZ: u32 = 170_000_000;
const _: () = assert!(HSE_HZ / 6 * 85 / 2 == SYSCLK_HZ);
const _: () = assert!(TIMING.timer_clock_hz == SYSCLK_HZ);

/// Control loop rate, Hz.
pub const CONTROL_RATE_HZ: u32 = TIMING.control_hz;

/// Tick-timer (TIM6) counts per control period; equal to CPU cycles per tick.
pub const TICK_PERIOD_COUNTS: u32 = TIMING.tick_period_counts();
// TIM6 is a 16-bit counter with ARR = period - 1.
const _: () = assert!(TICK_PERIOD_COUNTS <= 1 << 16);

/// Motor PWM frequency, Hz.
pub const PWM_FREQ_HZ: u32 = TIMING.pwm_hz;

/// TIM1 compare for 100 % duty (ARR + 1): the PWM period in timer counts.
pub const PWM_FULL_SCALE: u16 = TIMING.pwm_period_counts() as u16;
const _: () = assert!(TIMING.pwm_period_counts() <= u16::MAX as u32);

/// Top of the plane rendered at power-up, base frame, m: 10 mm below the centre of the
/// workspace (the default scene's plane).
pub const INITIAL_PLANE_TOP_M: Vec3 = Vec3::new(
    0.0,
    0.0,
    DeltaGeometry::OMEGA_LIKE_WORKSPACE_CENTRE_M.z - 0.010,
);
const _: () = assert!(
    DeltaGeometry::OMEGA_LIKE_WORKSPACE_CENTRE_M.x == 0.0
        && DeltaGeometry::OMEGA_LIKE_WORKSPACE_CENTRE_M.y == 0.0
);

/// The communication watchdog's timeout at power-up, ms: off. The button-only bench mode has no
/// application to feed it; an application turns it on with `SetWatchdog`.
pub const BENCH_WATCHDOG_MS: u16 = 0;

/// The scene the tick renders: the application's local model, initially the default scene's
/// plane (what a device nobody talks to renders).
pub type TickEnvironment = LocalModelEnvironment<RollingOnly>;

/// The local model until an application sends one: the default scene's plane (top at
/// [`INITIAL_PLANE_TOP_M`], the default contact material, never stale), the watchdog off
/// ([`BENCH_WATCHDOG_MS`]). Model poses are in the base frame (object origin zero), as the
/// host-link protocol sends them.
fn scene(contact: &ContactParams) -> (TickEnvironment, Vec3) {
    let initial = LocalModelSpec::plane(0, ModelPose::at(INITIAL_PLANE_TOP_M), contact);
    let scene = LocalModelEnvironment {
        watchdog_timeout_s: f32::from(BENCH_WATCHDOG_MS) * 1e-3,
        ..LocalModelEnvironment::with_parts(initial)
    };
    (scene, Vec3::ZERO)
}

/// The pipeline's configuration: the device on this board's timing, the default contact
/// parameters, the scene above.
pub fn pipeline_config() -> PipelineConfig<TickEnvironment> {
    let contact = ContactParams::DEFAULT;
    let (surface, object_origin_m) = scene(&contact);
    PipelineConfig {
        device: DEVICE,
        timing: TIMING,
        contact,
        surface,
        object_origin_m,
        log_rate_hz: LOG_RATE_HZ,
    }
}

/// Telemetry records logged per second (decimated from the control rate).
pub const LOG_RATE_HZ: u32 = softfinger_core::control::telemetry::DEFAULT_LOG_RATE_HZ;

/// Telemetry queue capacity, records. At 100 Hz this is 320 ms of headroom for a stalled logger.
pub const TELEMETRY_QUEUE_LEN: usize = 32;

/// Tick-summary queue capacity (one summary per second).
pub const SUMMARY_QUEUE_LEN: usize = 4;

/// Operator commands waiting for the tick, and their outcomes waiting for the supervisor.
pub const COMMAND_QUEUE_LEN: usize = 4;

/// How often the logger task drains the queues, ms.
pub const LOGGER_POLL_MS: u64 = 5;

/// How often the supervisor task checks the tick's status and updates the LED, ms.
pub const SUPERVISOR_POLL_MS: u64 = 10;

/// Independent watchdog timeout, µs. Fed by the control tick only, so it bites when the loop stops
/// for 5 ms (50 ticks at 10 kHz).
pub const WATCHDOG_TIMEOUT_US: u32 = 5_000;

/// The operator button's timing (softfinger-core's default, the one host-sim's fault campaign
/// uses): 20 ms debounce, 1 s long press, 3 s very long press.
pub const BUTTON_TIMING: ButtonTiming = ButtonTiming::DEFAULT;

/// How often the button task samples the button while a press is in progress, ms (it waits for
/// the button's edge otherwise). The debounce is then 4 samples.
pub const BUTTON_SAMPLE_MS: u64 = 5;
