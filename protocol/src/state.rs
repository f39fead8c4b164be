//! The state stream: one [`StateSample`] every `divisor` control ticks.

use serde::{Deserialize, Serialize};

/// The device's operating mode: the pipeline's own `Mode`, encoded as its variant index (the
/// recorded frames of the protocol's tests pin it).
pub use softfinger_core::control::pipeline::Mode;

/// The contact state: the core's own type, encoded as its variant index.
pub use softfinger_core::contact::state::ContactState;

/// Control-tick timing since the previous sample.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct TickStatsWire {
    /// Longest tick, ns.
    pub max_duration_ns: u32,
    /// Mean tick, ns.
    pub mean_duration_ns: u32,
    /// Ticks that started late or overran their period, since the device started.
    pub overruns: u32,
}

/// One sample of the device state. Vectors in the device base frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct StateSample {
    /// Control tick of this sample since the device started; time = tick / control rate.
    pub tick: u64,
    /// Probe (fingertip centre) position, m.
    pub probe_m: [f32; 3],
    /// Probe velocity, m/s.
    pub probe_vel_m_s: [f32; 3],
    /// Force rendered on the user, N.
    pub force_n: [f32; 3],
    /// Spin torque about the contact normal, N·m.
    pub spin_torque_nm: f32,
    /// Contact state.
    pub contact: ContactState,
    /// Contact point on the object, base frame, m.
    pub contact_point_m: [f32; 3],
    /// `softfinger_core::Flags` bits raised this tick (latched ones included).
    pub flags: u32,
    /// Operating mode.
    pub mode: Mode,
    /// Sequence number of the local model in force.
    pub model_seq: u32,
    /// Tick timing.
    pub tick_stats: TickStatsWire,
    /// Samples this connection could not be sent since the device started (queue full).
    pub dropped: u32,
}
