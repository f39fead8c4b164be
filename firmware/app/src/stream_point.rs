//! What the tick hands the host link on a streamed tick (see `crate::stream`). Plain data, no
//! HAL or executor type, so the link's host tests use it too.

use softfinger_core::contact::state::ContactState;
use softfinger_core::control::pipeline::Mode;
use softfinger_core::Flags;

/// One streamed tick: what the pipeline rendered, in the device base frame, and the tick timing
/// since the previous point.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StreamPoint {
    /// Tick index since start-up (wrapping).
    pub tick: u32,
    /// Mode after the tick.
    pub mode: Mode,
    /// Contact state after the tick.
    pub state: ContactState,
    /// Flags of the tick, latched faults included.
    pub flags: Flags,
    /// Probe (fingertip centre) position, m.
    pub probe_m: [f32; 3],
    /// The controller's filtered probe velocity, m/s.
    pub probe_vel_m_s: [f32; 3],
    /// Force rendered on the user, N (0 unless armed).
    pub force_n: [f32; 3],
    /// Spin torque about the contact normal, N·m.
    pub spin_torque_nm: f32,
    /// Contact point on the object, m.
    pub contact_point_m: [f32; 3],
    /// Sequence number of the local model in force (0 on a fixed scene).
    pub model_seq: u32,
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
