//! Telemetry bookkeeping for the firmware's defmt log: record decimation, drop counting and
//! tick-cost statistics. Pure logic, so the host tests exercise exactly what runs on the MCU.
//!
//! The firmware's control interrupt fills a [`TelemetryRecord`] on the ticks a [`Decimator`]
//! selects and pushes it into a bounded queue; a failed push is counted by a [`DropCounter`] and
//! never waits. Every tick's cost (CPU cycles) goes into [`TickStats`], which yields a
//! [`TickSummary`] once per reporting window (one second).

use crate::contact::state::ContactState;
use crate::control::controller::{TickInput, TickOutput};
use crate::device::channels::CHANNELS;
use crate::flags::Flags;
use crate::math::vec3::Vec3;

/// Default rate at which telemetry records are logged, Hz.
pub const DEFAULT_LOG_RATE_HZ: u32 = 100;

/// Selects every `period`-th tick: turns a control rate into a lower logging rate.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Decimator {
    /// Ticks between two selected ticks; 0 means never select.
    period: u32,
    /// Ticks since the last selected one.
    count: u32,
}

impl Decimator {
    /// Select `log_rate_hz` ticks per second out of `tick_rate_hz`.
    ///
    /// The period is `tick_rate_hz / log_rate_hz` rounded to the nearest integer, at least 1 (a log
    /// rate at or above the tick rate selects every tick). `log_rate_hz = 0` or `tick_rate_hz = 0`
    /// disables logging. The first selected tick is the `period`-th call of [`Decimator::tick`].
    pub const fn new(tick_rate_hz: u32, log_rate_hz: u32) -> Self {
        let period = if log_rate_hz == 0 || tick_rate_hz == 0 {
            0
        } else {
            // Round to nearest in u64 so large rates cannot overflow.
            let p = (tick_rate_hz as u64 + log_rate_hz as u64 / 2) / log_rate_hz as u64;
            if p == 0 {
                1
            } else if p > u32::MAX as u64 {
                u32::MAX
            } else {
                p as u32
            }
        };
        Decimator { period, count: 0 }
    }

    /// Ticks between two selected ticks (0: disabled).
    pub const fn period(&self) -> u32 {
        self.period
    }

    /// Advance one tick; true when this tick is selected.
    #[inline]
    pub fn tick(&mut self) -> bool {
        if self.period == 0 {
            return false;
        }
        self.count += 1;
        if self.count >= self.period {
            self.count = 0;
            true
        } else {
            false
        }
    }
}

/// Counts records that could not be queued (queue full). Saturates instead of wrapping.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct DropCounter {
    total: u32,
    unreported: u32,
}

impl DropCounter {
    /// A counter with nothing dropped.
    pub const fn new() -> Self {
        DropCounter {
            total: 0,
            unreported: 0,
        }
    }

    /// Note the outcome of one push attempt: `queued = false` counts a drop.
    #[inline]
    pub fn note(&mut self, queued: bool) {
        if !queued {
            self.total = self.total.saturating_add(1);
            self.unreported = self.unreported.saturating_add(1);
        }
    }

    /// Drops not yet reported, without resetting (to attach to a record before trying to queue it).
    pub const fn unreported(&self) -> u32 {
        self.unreported
    }

    /// Drops since the previous call (then reset to 0), for attaching to the next report.
    #[inline]
    pub fn take_unreported(&mut self) -> u32 {
        core::mem::take(&mut self.unreported)
    }

    /// Offer one record to a bounded queue without waiting.
    ///
    /// `try_push` receives the number of drops not yet reported (to store in the record) and
    /// returns whether the record was queued. On success those drops count as reported; on failure
    /// this record is one more drop. Returns whether the record was queued.
    #[inline]
    pub fn offer(&mut self, try_push: impl FnOnce(u32) -> bool) -> bool {
        let queued = try_push(self.unreported);
        if queued {
            self.unreported = 0;
        }
        self.note(queued);
        queued
    }

    /// Drops since start-up (saturating).
    pub const fn total(&self) -> u32 {
        self.total
    }
}

/// One control tick as logged: what the controller saw and did, and what it cost.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct TelemetryRecord {
    /// Tick index since start-up (wraps after 2³² ticks: ~5 days at 10 kHz).
    pub tick: u32,
    /// Extended encoder positions, counts, in the channel order of [`crate::device::channels`]
    /// (motors 0-2, then wrist joints 0-2).
    pub counts: [i32; CHANNELS],
    /// Probe position, device base frame, m.
    pub probe_m: Vec3,
    /// Rendered force, base frame, N.
    pub force_n: Vec3,
    /// Spin torque about the contact normal, N·m.
    pub tau_n_nm: f32,
    /// Contact state after this tick.
    pub state: ContactState,
    /// Duties actually written to the drivers (after the output guard), in [-1, 1].
    pub duties: [f32; 3],
    /// Driver enable as written.
    pub enable: bool,
    /// Flags of this tick: controller flags, guard flags and latched faults.
    pub flags: Flags,
    /// CPU cycles this tick took (DWT cycle counter).
    pub cycles: u32,
    /// Records dropped (queue full) since the previous record that got through.
    pub dropped_before: u32,
}

impl TelemetryRecord {
    /// Assemble a record from one tick's input, the controller output, what was finally written
    /// (`duties`, `enable`, `flags` after the output guard) and the tick's cost.
    pub fn new(
        tick: u32,
        input: &TickInput,
        output: &TickOutput,
        written: ([f32; 3], bool, Flags),
        cycles: u32,
    ) -> Self {
        TelemetryRecord {
            tick,
            counts: input.counts,
            probe_m: output.probe_m,
            force_n: output.force_n,
            tau_n_nm: output.tau_n_nm,
            state: output.state,
            duties: written.0,
            enable: written.1,
            flags: written.2,
            cycles,
            dropped_before: 0,
        }
    }
}

/// Tick cost over one reporting window.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct TickSummary {
    /// Ticks in the window.
    pub ticks: u32,
    /// Mean cycles per tick, rounded down (0 for an empty window).
    pub mean_cycles: u32,
    /// Largest cycles of one tick.
    pub max_cycles: u32,
    /// Ticks that overran their period.
    pub overruns: u32,
    /// Longest run of consecutive overruns that ended in, or is still open at the end of, the window.
    pub longest_overrun_streak: u32,
    /// Telemetry records dropped since start-up.
    pub dropped_total: u32,
}

/// Accumulates tick cost; one window at a time.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct TickStats {
    budget_cycles: u32,
    ticks: u32,
    sum_cycles: u64,
    max_cycles: u32,
    overruns: u32,
    streak: u32,
    longest_streak: u32,
}

impl TickStats {
    /// A tick costing more than `budget_cycles` (the control period in CPU cycles) is an overrun.
    pub const fn new(budget_cycles: u32) -> Self {
        TickStats {
            budget_cycles,
            ticks: 0,
            sum_cycles: 0,
            max_cycles: 0,
            overruns: 0,
            streak: 0,
            longest_streak: 0,
        }
    }

    /// The overrun threshold, cycles.
    pub const fn budget_cycles(&self) -> u32 {
        self.budget_cycles
    }

    /// Record one tick that took `cycles` CPU cycles; returns true if it overran the budget.
    ///
    /// `late` additionally marks the tick as an overrun even within budget (e.g. the timer's update
    /// flag was already set again when the tick finished, or the tick started late).
    #[inline]
    pub fn record(&mut self, cycles: u32, late: bool) -> bool {
        self.ticks = self.ticks.saturating_add(1);
        self.sum_cycles = self.sum_cycles.saturating_add(u64::from(cycles));
        self.max_cycles = self.max_cycles.max(cycles);
        let overrun = late || cycles > self.budget_cycles;
        if overrun {
            self.overruns = self.overruns.saturating_add(1);
            self.streak = self.streak.saturating_add(1);
            self.longest_streak = self.longest_streak.max(self.streak);
        } else {
            self.streak = 0;
        }
        overrun
    }

    /// Consecutive overruns up to and including the last recorded tick.
    pub const fn streak(&self) -> u32 {
        self.streak
    }

    /// Ticks recorded in the current window.
    pub const fn ticks(&self) -> u32 {
        self.ticks
    }

    /// Close the window: return its summary and start a new one. The current overrun streak carries
    /// over (a streak does not end because a report was made).
    pub fn take_summary(&mut self, dropped_total: u32) -> TickSummary {
        let mean = match u64::from(self.ticks) {
            0 => 0,
            n => (self.sum_cycles / n) as u32,
        };
        let summary = TickSummary {
            ticks: self.ticks,
            mean_cycles: mean,
            max_cycles: self.max_cycles,
            overruns: self.overruns,
            longest_overrun_streak: self.longest_streak,
            dropped_total,
        };
        *self = TickStats {
            streak: self.streak,
            longest_streak: self.streak,
            ..TickStats::new(self.budget_cycles)
        };
        summary
    }
}

#[cfg(test)]
mod tests;
