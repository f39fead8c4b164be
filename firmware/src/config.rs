//! Compile-time configuration of the firmware: rates, limits and sizes.

use softfinger_core::output_guard::GuardConfig;

/// The board's crystal (NUCLEO-G474RE X3), Hz.
pub const HSE_HZ: u32 = 24_000_000;

/// System clock, Hz: HSE 24 MHz / 6 × 85 / 2. TIM1 and TIM6 run at this clock (APB prescalers 1).
pub const SYSCLK_HZ: u32 = 170_000_000;
const _: () = assert!(HSE_HZ / 6 * 85 / 2 == SYSCLK_HZ);

/// Control loop rate, Hz: 10 kHz (20 kHz also fits the PWM and tick-timer constraints below).
pub const CONTROL_RATE_HZ: u32 = 10_000;

/// Tick-timer (TIM6, prescaler 1) counts per control period; equal to CPU cycles per tick.
pub const TICK_PERIOD_COUNTS: u32 = SYSCLK_HZ / CONTROL_RATE_HZ;
const _: () = assert!(TICK_PERIOD_COUNTS * CONTROL_RATE_HZ == SYSCLK_HZ);
const _: () = assert!(TICK_PERIOD_COUNTS <= 1 << 16);

/// Motor PWM frequency, Hz (at least 20 kHz: above hearing), an integer multiple of the control
/// rate so every tick sees the same PWM phase.
pub const PWM_FREQ_HZ: u32 = 20_000;
const _: () = assert!(PWM_FREQ_HZ >= 20_000 && PWM_FREQ_HZ.is_multiple_of(CONTROL_RATE_HZ));

/// TIM1 compare for 100 % duty (ARR + 1, prescaler 1): 8500 counts at 20 kHz.
pub const PWM_FULL_SCALE: u16 = (SYSCLK_HZ / PWM_FREQ_HZ) as u16;
const _: () = assert!(PWM_FULL_SCALE as u32 * PWM_FREQ_HZ == SYSCLK_HZ);

/// Telemetry records logged per second (decimated from the control rate).
pub const LOG_RATE_HZ: u32 = softfinger_core::telemetry::DEFAULT_LOG_RATE_HZ;

/// Telemetry queue capacity, records. At 100 Hz this is 320 ms of headroom for a stalled logger.
pub const TELEMETRY_QUEUE_LEN: usize = 32;

/// Tick-summary queue capacity (one summary per second).
pub const SUMMARY_QUEUE_LEN: usize = 4;

/// How often the logger task drains the queues, ms.
pub const LOGGER_POLL_MS: u64 = 5;

/// Operator commands waiting for the tick.
pub const COMMAND_QUEUE_LEN: usize = 4;

/// How often the supervisor task checks the fault latch, ms.
pub const SUPERVISOR_POLL_MS: u64 = 10;

/// Largest plausible encoder motion in one tick, counts. A 2000-line encoder (8000 counts/turn
/// with ×4 decoding) at 3000 rpm moves 400 000 counts/s = 40 counts per 10 kHz tick; 500 leaves a
/// wide margin at 20 kHz too while catching line noise and counter resets.
pub const MAX_COUNTS_PER_TICK: u16 = 500;

/// Limits enforced after the controller, independently of it.
pub const GUARD: GuardConfig = GuardConfig {
    // Never drive a bridge harder than 90 %: leaves bootstrap/current-sense margin.
    max_duty: 0.9,
    // 10 consecutive overruns (1 ms at 10 kHz) latch a fault.
    max_overrun_streak: 10,
};

/// Independent watchdog timeout, µs. Fed by the control tick only, so it bites when the loop stops
/// for 5 ms (50 ticks at 10 kHz).
pub const WATCHDOG_TIMEOUT_US: u32 = 5_000;

/// User-button debounce, ms.
pub const BUTTON_DEBOUNCE_MS: u64 = 30;

/// A press of B1 held at least this long is a long press (next stiffness preset), ms.
pub const LONG_PRESS_MS: u64 = 1_000;
