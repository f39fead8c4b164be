//! State samples from the tick's stream points ([`StreamPoint`], one every `divisor` ticks, taken
//! by the tick itself).
//!
//! A point carries what the tick rendered (the protocol's `RenderedTick`: probe position and
//! filtered velocity, force, spin torque, contact state and point, flags, mode, the local model's
//! sequence number) and the tick timing since the previous point in timer counts, which the
//! sample reports in ns. The sample is assembled by `StateSample::rendered`, as the virtual
//! device's are.

use softfinger_protocol::{StateSample, TickStatsWire};

use crate::stream_point::StreamPoint;

/// A wrapping 32-bit tick index extended to 64 bits (points arrive in order, far less than 2³²
/// ticks apart).
#[derive(Clone, Copy, Debug, Default)]
pub struct TickExtender {
    high: u64,
    last: Option<u32>,
}

impl TickExtender {
    /// The 64-bit tick of `tick`.
    pub fn extend(&mut self, tick: u32) -> u64 {
        if self.last.is_some_and(|last| tick < last) {
            self.high += 1 << 32;
        }
        self.last = Some(tick);
        self.high | u64::from(tick)
    }
}

/// Builds samples from stream points.
#[derive(Clone, Copy, Debug)]
pub struct StateBuilder {
    /// Nanoseconds per tick-timer count.
    ns_per_count: f32,
    ticks: TickExtender,
}

impl StateBuilder {
    /// For a tick timer counting at `timer_clock_hz`.
    pub fn new(timer_clock_hz: u32) -> Self {
        StateBuilder {
            ns_per_count: 1e9 / timer_clock_hz.max(1) as f32,
            ticks: TickExtender::default(),
        }
    }

    /// The sample of `p` (its `dropped` field is the connection's to fill).
    pub fn sample(&mut self, p: &StreamPoint) -> StateSample {
        let ns = |counts: f32| (counts * self.ns_per_count) as u32;
        let mean = if p.ticks == 0 {
            0.0
        } else {
            p.sum_tick_counts as f32 / p.ticks as f32
        };
        StateSample::rendered(
            self.ticks.extend(p.tick),
            &p.rendered,
            TickStatsWire {
                max_duration_ns: ns(p.max_tick_counts as f32),
                mean_duration_ns: ns(mean),
                overruns: p.overruns,
            },
        )
    }
}
