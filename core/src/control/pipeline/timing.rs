//! Tick timing statistics from timer counts: the start latency (timer event → first instruction of
//! the tick), the write time (timer event → last hardware write of the tick), overruns, and a
//! summary per reporting window.
//!
//! Definitions, all in counts of the board's timer clock (see [`super::board`]):
//! - an **overrun** is a tick whose writes finished at or after the next tick's timer event
//!   (`write_done ≥ tick period`), or a tick that started a full period late;
//! - a **late write** finished at or after the end of the tick's first PWM period, so its compare
//!   values were loaded one PWM period later than planned (the bridge mapper then holds
//!   reversals one more tick).

/// One window's figures. The means are computed where the summary is read
/// ([`TimingSummary::mean_latency_counts`]), not in the tick that closes the window: a 64-bit
/// division costs the M4F's tick about 80 instructions.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct TimingSummary {
    /// Ticks in the window.
    pub ticks: u32,
    /// Largest start latency, timer counts.
    pub max_latency_counts: u32,
    /// Sum of the window's start latencies, timer counts.
    pub sum_latency_counts: u64,
    /// Largest write time (timer event → writes done), timer counts.
    pub max_write_counts: u32,
    /// Sum of the window's write times (timer event → writes done), timer counts.
    pub sum_write_counts: u64,
    /// Overrun ticks in the window.
    pub overruns: u32,
    /// Late writes in the window.
    pub late_writes: u32,
    /// Longest run of consecutive overruns in the window (a run carries over windows).
    pub longest_overrun_streak: u32,
    /// Telemetry records dropped since start-up.
    pub dropped_total: u32,
}

impl TimingSummary {
    /// Mean start latency over the window, timer counts (0 for an empty window).
    pub fn mean_latency_counts(&self) -> u32 {
        mean(self.sum_latency_counts, self.ticks)
    }

    /// Mean write time over the window, timer counts (0 for an empty window).
    pub fn mean_write_counts(&self) -> u32 {
        mean(self.sum_write_counts, self.ticks)
    }
}

/// `sum / n`, rounded down; 0 when `n` is 0. Sums of u32 samples, so the mean fits a u32.
fn mean(sum: u64, n: u32) -> u32 {
    if n == 0 {
        0
    } else {
        (sum / u64::from(n)) as u32
    }
}

/// What one tick's timing means for the pipeline.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TimingVerdict {
    /// The previous tick overran, or this one started a period late.
    pub overrun: bool,
    /// The previous tick's writes missed its first PWM period.
    pub late_write: bool,
    /// Consecutive overruns up to this tick.
    pub streak: u32,
}

/// Accumulates one window at a time.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct TickTiming {
    tick_counts: u32,
    pwm_counts: u32,
    window_ticks: u32,
    ticks: u32,
    sum_latency: u64,
    max_latency: u32,
    sum_write: u64,
    max_write: u32,
    overruns: u32,
    late_writes: u32,
    streak: u32,
    longest: u32,
    started: bool,
}

impl TickTiming {
    /// Periods in timer counts; a summary closes every `window_ticks` ticks (0: never).
    pub const fn new(tick_counts: u32, pwm_counts: u32, window_ticks: u32) -> Self {
        TickTiming {
            tick_counts,
            pwm_counts,
            window_ticks,
            ticks: 0,
            sum_latency: 0,
            max_latency: 0,
            sum_write: 0,
            max_write: 0,
            overruns: 0,
            late_writes: 0,
            streak: 0,
            longest: 0,
            started: false,
        }
    }

    /// Record one tick: its start latency and the previous tick's write time (ignored on the first
    /// tick, which has no predecessor).
    pub fn record(&mut self, latency_counts: u32, prev_write_done_counts: u32) -> TimingVerdict {
        let prev = if self.started {
            prev_write_done_counts
        } else {
            0
        };
        self.started = true;
        let overrun = prev >= self.tick_counts || latency_counts >= self.tick_counts;
        let late_write = prev >= self.pwm_counts;
        self.ticks = self.ticks.saturating_add(1);
        self.sum_latency = self.sum_latency.saturating_add(u64::from(latency_counts));
        self.max_latency = self.max_latency.max(latency_counts);
        self.sum_write = self.sum_write.saturating_add(u64::from(prev));
        self.max_write = self.max_write.max(prev);
        if overrun {
            self.overruns = self.overruns.saturating_add(1);
            self.streak = self.streak.saturating_add(1);
            self.longest = self.longest.max(self.streak);
        } else {
            self.streak = 0;
        }
        if late_write {
            self.late_writes = self.late_writes.saturating_add(1);
        }
        TimingVerdict {
            overrun,
            late_write,
            streak: self.streak,
        }
    }

    /// The window's summary once `window_ticks` ticks were recorded (then a new window starts).
    pub fn take_summary_if_due(&mut self, dropped_total: u32) -> Option<TimingSummary> {
        if self.window_ticks == 0 || self.ticks < self.window_ticks {
            return None;
        }
        let s = TimingSummary {
            ticks: self.ticks,
            max_latency_counts: self.max_latency,
            sum_latency_counts: self.sum_latency,
            max_write_counts: self.max_write,
            sum_write_counts: self.sum_write,
            overruns: self.overruns,
            late_writes: self.late_writes,
            longest_overrun_streak: self.longest,
            dropped_total,
        };
        *self = TickTiming {
            streak: self.streak,
            longest: self.streak,
            started: true,
            ..TickTiming::new(self.tick_counts, self.pwm_counts, self.window_ticks)
        };
        Some(s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn overrun_and_late_write_thresholds_are_exact() {
        let mut t = TickTiming::new(17_000, 8_500, 0);
        // First tick: no predecessor, whatever is passed.
        assert_eq!(t.record(10, u32::MAX), TimingVerdict::default());
        let v = t.record(10, 8_499);
        assert!(!v.overrun && !v.late_write);
        let v = t.record(10, 8_500);
        assert!(!v.overrun && v.late_write);
        let v = t.record(10, 16_999);
        assert!(!v.overrun && v.late_write);
        let v = t.record(10, 17_000);
        assert!(v.overrun && v.late_write && v.streak == 1);
        let v = t.record(16_999, 0);
        assert!(!v.overrun && v.streak == 0);
        let v = t.record(17_000, 0);
        assert!(v.overrun && v.streak == 1);
    }

    #[test]
    fn summary_every_window_with_streak_carried_over() {
        let mut t = TickTiming::new(100, 50, 4);
        let _ = t.record(1, 0);
        let _ = t.record(3, 20);
        let _ = t.record(5, 100);
        assert_eq!(t.take_summary_if_due(7), None);
        let _ = t.record(7, 100);
        let s = t.take_summary_if_due(7).unwrap_or_default();
        assert_eq!(
            s,
            TimingSummary {
                ticks: 4,
                max_latency_counts: 7,
                sum_latency_counts: 16,
                max_write_counts: 100,
                sum_write_counts: 220,
                overruns: 2,
                late_writes: 2,
                longest_overrun_streak: 2,
                dropped_total: 7,
            }
        );
        assert_eq!((s.mean_latency_counts(), s.mean_write_counts()), (4, 55));
        // The streak of 2 continues into the next window.
        assert_eq!(t.record(0, 100).streak, 3);
    }

    #[test]
    fn an_empty_window_has_zero_means() {
        let s = TimingSummary {
            sum_latency_counts: 9,
            sum_write_counts: 9,
            ..TimingSummary::default()
        };
        assert_eq!((s.mean_latency_counts(), s.mean_write_counts()), (0, 0));
        let one = TimingSummary { ticks: 1, ..s };
        assert_eq!((one.mean_latency_counts(), one.mean_write_counts()), (9, 9));
    }
}
