//! What the tick hands the host link on a streamed tick (see `crate::stream`). Plain data, no
//! HAL or executor type, so the link's host tests use it too.

use softfinger_protocol::RenderedTick;

/// One streamed tick: what the pipeline rendered (the protocol's [`RenderedTick`], device base
/// frame, the one shape the virtual device streams too) and the tick timing since the previous
/// point.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StreamPoint {
    /// Tick index since start-up (wrapping).
    pub tick: u32,
    /// What the pipeline rendered on this tick.
    pub rendered: RenderedTick,
    /// Longest tick since the previous point (timer event to the end of the tick's work), timer
    /// counts.
    pub max_tick_counts: u32,
    /// Sum of the tick durations since the previous point, timer counts.
    pub sum_tick_counts: u32,
    /// Ticks since the previous point.
    pub ticks: u32,
    /// Ticks that ended after the next tick's event, since start-up.
    pub overruns: u32,
}
