//! The host link's state stream, taken by the tick itself: every `divisor` ticks (set by the
//! link from the host's `SetStream`), the tick copies what it rendered into a [`StreamPoint`] and
//! queues it for the link task, which turns it into a protocol `StateSample`. The tick never
//! waits: a full queue drops the point (the link counts it).
//!
//! A build without a host link streams nothing ([`NoStream`]): the tick's code for it is removed
//! at compile time.

use core::sync::atomic::{AtomicU16, Ordering};

use heapless::spsc::Producer;

pub use crate::stream_point::StreamPoint;

/// The fastest state stream the firmware sends, Hz. A state frame is at most
/// `softfinger_protocol::MAX_FRAME_LEN` bytes and about 80 in practice: 2 kHz is about 160 kB/s, an
/// eighth of full-speed USB's bulk bandwidth (19 packets of 64 bytes per 1 ms frame).
pub const MAX_STREAM_HZ: u32 = 2_000;

/// The smallest stream divisor at `control_rate_hz`: the one that keeps the stream at or below
/// [`MAX_STREAM_HZ`]. At least 1.
#[allow(dead_code)] // a build without a host link never streams
pub const fn min_stream_divisor(control_rate_hz: u32) -> u16 {
    let d = control_rate_hz.div_ceil(MAX_STREAM_HZ);
    if d < 1 {
        1
    } else if d > u16::MAX as u32 {
        u16::MAX
    } else {
        d as u16
    }
}

/// Stream points queued for the host link: 8 ms at the fastest stream (2 kHz), four times the
/// link's 1 ms poll.
#[allow(dead_code)] // a build without a host link never streams
pub const QUEUE_LEN: usize = 16;

/// The stream divisor in force (0: no stream), written by the link task, read by the tick.
static DIVISOR: AtomicU16 = AtomicU16::new(0);

/// Stream every `divisor` ticks from the next tick on (0: stop). Any task; never waits.
#[allow(dead_code)] // a build without a host link never streams
pub fn set_divisor(divisor: u16) {
    DIVISOR.store(divisor, Ordering::Relaxed);
}

/// Where the tick's stream points go.
pub trait StreamSink {
    /// False: this build has no stream (the tick skips all of it).
    const ENABLED: bool;
    /// Queue `point`; false when the queue is full (the point is lost: the link sees the gap in
    /// the tick indices and counts it).
    fn push(&mut self, point: StreamPoint) -> bool;
}

impl StreamSink for Producer<'static, StreamPoint> {
    const ENABLED: bool = true;
    fn push(&mut self, point: StreamPoint) -> bool {
        self.enqueue(point).is_ok()
    }
}

/// No host link: no stream.
#[allow(dead_code)] // the emulated board always has its link
#[derive(Clone, Copy, Debug)]
pub struct NoStream;

impl StreamSink for NoStream {
    const ENABLED: bool = false;
    fn push(&mut self, _point: StreamPoint) -> bool {
        false
    }
}

/// The tick's side of the stream: the tick index and the timing accumulated since the previous
/// point.
#[derive(Clone, Copy, Debug, Default)]
pub struct StreamTap {
    tick: u32,
    max_counts: u32,
    sum_counts: u32,
    ticks: u32,
    overruns: u32,
}

impl StreamTap {
    /// Whether this tick is streamed: its index is a multiple of the divisor in force, as the
    /// virtual device streams (call once per tick, before [`Self::stamp`]).
    #[inline(always)]
    pub fn due(&mut self) -> bool {
        let tick = self.tick;
        self.tick = tick.wrapping_add(1);
        let divisor = u32::from(DIVISOR.load(Ordering::Relaxed));
        divisor != 0 && tick.is_multiple_of(divisor)
    }

    /// The point's tick index and timing fields, filled in `point`; the timing restarts.
    #[inline(always)]
    pub fn stamp(&mut self, point: &mut StreamPoint) {
        point.tick = self.tick.wrapping_sub(1);
        point.max_tick_counts = self.max_counts;
        point.sum_tick_counts = self.sum_counts;
        point.ticks = self.ticks;
        point.overruns = self.overruns;
        self.max_counts = 0;
        self.sum_counts = 0;
        self.ticks = 0;
    }

    /// One tick's duration (`end` timer counts after its event; `overrun`: it ended after the
    /// next event).
    #[inline(always)]
    pub fn account(&mut self, end: u32, overrun: bool) {
        self.max_counts = self.max_counts.max(end);
        self.sum_counts = self.sum_counts.saturating_add(end);
        self.ticks += 1;
        self.overruns += u32::from(overrun);
    }
}
