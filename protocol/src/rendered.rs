//! What the pipeline rendered on one tick, as the state stream reports it, and the one place a
//! [`StateSample`] is assembled from it: the virtual device (`host-sim serve`) builds its samples
//! here, and the firmware's link can, so both sides of the stream carry the same fields the same
//! way.
//!
//! Vectors in the device base frame; SI units (m, m/s, N, N·m).

use crate::state::{ContactState, Mode, StateSample, TickStatsWire};
use softfinger_core::control::controller::{ContactStage, Environment};
use softfinger_core::control::pipeline::{Pipeline, PipelineOutput};
use softfinger_core::{Flags, Math, Vec3};

/// One tick of the pipeline, the fields a state sample carries from it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RenderedTick {
    /// Mode after the tick.
    pub mode: Mode,
    /// Contact state after the tick.
    pub contact: ContactState,
    /// Flags of the tick, latched faults included.
    pub flags: Flags,
    /// Probe (fingertip centre) position, base frame, m.
    pub probe_m: Vec3,
    /// The controller's filtered probe velocity, base frame, m/s.
    pub probe_vel_m_s: Vec3,
    /// Force rendered on the user, base frame, N (0 unless armed).
    pub force_n: Vec3,
    /// Spin torque about the contact normal, N·m.
    pub spin_torque_nm: f32,
    /// Contact point on the object, base frame, m.
    pub contact_point_m: Vec3,
    /// Sequence number of the local model in force (0 on a fixed scene).
    pub model_seq: u32,
}

impl RenderedTick {
    /// What `pipeline` rendered on the tick that returned `out` (read right after that tick:
    /// the filtered velocity, the contact point and the model sequence are the controller's
    /// state after it).
    pub fn of<M: Math, S: Environment>(pipeline: &Pipeline<M, S>, out: &PipelineOutput) -> Self {
        let c = pipeline.controller();
        RenderedTick {
            mode: out.mode,
            contact: out.control.state,
            flags: out.flags,
            probe_m: out.control.probe_m,
            probe_vel_m_s: c.probe_velocity(),
            force_n: out.control.force_n,
            spin_torque_nm: out.control.tau_n_nm,
            contact_point_m: c.contact_point_m(),
            model_seq: c.contact().model_seq(),
        }
    }
}

impl StateSample {
    /// The sample of control tick `tick` that rendered `r`, with the tick timing `tick_stats`;
    /// `dropped` is 0, the connection's to fill ([`crate::DeviceEndpoint::offer_state`]).
    pub fn rendered(tick: u64, r: &RenderedTick, tick_stats: TickStatsWire) -> StateSample {
        StateSample {
            tick,
            probe_m: r.probe_m.to_array(),
            probe_vel_m_s: r.probe_vel_m_s.to_array(),
            force_n: r.force_n.to_array(),
            spin_torque_nm: r.spin_torque_nm,
            contact: r.contact,
            contact_point_m: r.contact_point_m.to_array(),
            flags: r.flags.0,
            mode: r.mode,
            model_seq: r.model_seq,
            tick_stats,
            dropped: 0,
        }
    }
}

#[cfg(test)]
mod tests;
