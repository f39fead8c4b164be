//! Low-priority telemetry logger: drains the queues the control interrupt fills.
//!
//! Records (decimated to `LOG_RATE_HZ`) are logged at debug level, drops at warn, and the
//! once-a-second tick-cost summary at info. Logging runs in thread mode; the only way it touches
//! the control loop is through the lock-free SPSC queues.

use defmt::{debug, info, warn};
use embassy_time::{Duration, Ticker};
use heapless::spsc::Consumer;
use softfinger_core::telemetry::{TelemetryRecord, TickSummary};

use crate::config;

/// Drain the queues forever (the board binary spawns this as a task).
pub async fn run(
    mut records: Consumer<'static, TelemetryRecord>,
    mut summaries: Consumer<'static, TickSummary>,
) {
    let mut ticker = Ticker::every(Duration::from_millis(config::LOGGER_POLL_MS));
    loop {
        while let Some(r) = records.dequeue() {
            if r.dropped_before > 0 {
                warn!(
                    "telemetry: {=u32} records dropped before tick {=u32}",
                    r.dropped_before, r.tick
                );
            }
            debug!("{}", r);
        }
        while let Some(s) = summaries.dequeue() {
            // Integer µs×100 from cycles at SYSCLK: cycles / 1.7 = ns; keep it in integers.
            let mean_ns = u64::from(s.mean_cycles) * 1_000_000_000 / u64::from(config::SYSCLK_HZ);
            let max_ns = u64::from(s.max_cycles) * 1_000_000_000 / u64::from(config::SYSCLK_HZ);
            info!(
                "tick cost over {=u32} ticks: mean {=u32} cycles ({=u64} ns), max {=u32} cycles ({=u64} ns), budget {=u32}; overruns {=u32} (longest streak {=u32}); telemetry dropped {=u32} total",
                s.ticks,
                s.mean_cycles,
                mean_ns,
                s.max_cycles,
                max_ns,
                config::TICK_PERIOD_COUNTS,
                s.overruns,
                s.longest_overrun_streak,
                s.dropped_total
            );
            if s.overruns > 0 {
                warn!(
                    "{=u32} control ticks overran in the last second",
                    s.overruns
                );
            }
        }
        ticker.next().await;
    }
}
