//! Low-priority telemetry logger: drains the queues the control tick fills.
//!
//! Records (decimated to `config::LOG_RATE_HZ`, compact `PipelineRecord`s) are logged at debug
//! level, drops at warn, and the once-a-second timing summary at info: start latency and write
//! time (timer event -> last hardware write) from the pipeline, and the longest whole tick. The
//! log goes out through defmt-rtt in non-blocking, drop-on-contention mode: a host that stops
//! reading loses frames, it never stalls this task, and no log call ever masks the tick.

use core::sync::atomic::Ordering;

use defmt::{debug, info, warn};
use embassy_time::{Duration, Ticker};
use heapless::spsc::Consumer;
use softfinger_core::control::pipeline::{PipelineRecord, TimingSummary};

use crate::config;
use crate::tick::STATUS;

/// Timer counts to ns at the timer clock, in integers.
fn ns(counts: u32) -> u32 {
    (u64::from(counts) * 1_000_000_000 / u64::from(config::TIMING.timer_clock_hz)) as u32
}

/// Drain the queues forever: the logger task every board binary spawns.
#[embassy_executor::task]
pub async fn task(
    mut records: Consumer<'static, PipelineRecord>,
    mut summaries: Consumer<'static, TimingSummary>,
) {
    let mut ticker = Ticker::every(Duration::from_millis(config::LOGGER_POLL_MS));
    loop {
        // Proof of life for the watchdog (`tick::THREAD_HEARTBEAT`): this loop runs only while
        // the cooperative executor does, so a task that hangs stops it.
        crate::tick::thread_heartbeat();
        while let Some(r) = records.dequeue() {
            if r.dropped_before > 0 {
                warn!(
                    "telemetry: {=u16} records dropped before tick {=u32}",
                    r.dropped_before, r.tick
                );
            }
            debug!("{}", r);
        }
        while let Some(s) = summaries.dequeue() {
            let max_tick = STATUS.max_tick_counts.swap(0, Ordering::Relaxed);
            info!(
                "tick timing over {=u32} ticks (counts at {=u32} Hz; period {=u32}): latency mean {=u32} max {=u32} ({=u32} ns); writes done mean {=u32} max {=u32} ({=u32} ns); whole tick max {=u32} ({=u32} ns); overruns {=u32} (longest streak {=u32}), late writes {=u32}; telemetry dropped {=u32} total",
                s.ticks,
                config::TIMING.timer_clock_hz,
                config::TICK_PERIOD_COUNTS,
                s.mean_latency_counts(),
                s.max_latency_counts,
                ns(s.max_latency_counts),
                s.mean_write_counts(),
                s.max_write_counts,
                ns(s.max_write_counts),
                max_tick,
                ns(max_tick),
                s.overruns,
                s.longest_overrun_streak,
                s.late_writes,
                s.dropped_total
            );
            if s.overruns > 0 || s.late_writes > 0 {
                warn!(
                    "{=u32} overruns and {=u32} late writes in the last second",
                    s.overruns, s.late_writes
                );
            }
        }
        ticker.next().await;
    }
}
