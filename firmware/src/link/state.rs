//! State samples from the tick's telemetry records (`PipelineRecord`, one every
//! `control_rate / record_rate` ticks).
//!
//! What a record carries becomes the sample: tick, mode, contact state, flags, the rendered
//! force (mN in the record, N in the sample). The probe position is the forward kinematics of the
//! record's homed motor counts (the delta's effector, base frame; meaningless before homing, as
//! the mode says), its velocity the difference over the previous record (0 for the first record and when
//! the counts change frame at the end of homing). The record does not
//! carry the spin torque, the contact point or tick timing, so those fields are 0 in a sample
//! from the firmware; `model_seq` is 0 (the firmware renders its compiled-in plane).

use core::marker::PhantomData;
use softfinger_core::contact_state::ContactState;
use softfinger_core::device::DeviceParams;
use softfinger_core::pipeline::{Mode as CoreMode, PipelineRecord};
use softfinger_core::{Libm, Math};
use softfinger_protocol::{ContactStateWire, Mode, StateSample};

/// The wire mode.
pub fn mode(m: CoreMode) -> Mode {
    match m {
        CoreMode::Unhomed => Mode::Unhomed,
        CoreMode::Homing => Mode::Homing,
        CoreMode::Disarmed => Mode::Disarmed,
        CoreMode::Armed => Mode::Armed,
        CoreMode::Faulted => Mode::Faulted,
    }
}

/// The wire contact state.
pub fn contact_state(s: ContactState) -> ContactStateWire {
    match s {
        ContactState::Broken => ContactStateWire::Broken,
        ContactState::Rolling => ContactStateWire::Rolling,
        ContactState::Sliding => ContactStateWire::Sliding,
    }
}

/// A wrapping 32-bit tick index extended to 64 bits (records arrive in order, far less than 2³²
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

/// Builds samples from records. `M`: the math of the kinematics. The emulated board uses libm (a
/// separate instance of the kinematics, so the tick's measured code is not shared with the link);
/// the STM32 uses the tick's `Fast` math (libm's code would be placed in CCM SRAM with the tick's,
/// which has no room for it).
#[derive(Clone, Copy, Debug)]
pub struct StateBuilder<M: Math = Libm> {
    device: DeviceParams,
    rate_hz: f32,
    ticks: TickExtender,
    /// Tick, probe position and count frame (`true`: homed) of the previous record.
    previous: Option<(u64, [f32; 3], bool)>,
    math: PhantomData<M>,
}

/// The record's motor counts are homed (false: raw counts, before or during homing). A velocity
/// across a change of frame would be the homing offset, not a motion.
fn homed_counts(mode: CoreMode) -> bool {
    !matches!(mode, CoreMode::Unhomed | CoreMode::Homing)
}

impl<M: Math> StateBuilder<M> {
    /// For `device` at `control_rate_hz`.
    pub fn new(device: DeviceParams, control_rate_hz: u32) -> Self {
        StateBuilder {
            device,
            rate_hz: control_rate_hz as f32,
            ticks: TickExtender::default(),
            previous: None,
            math: PhantomData,
        }
    }

    /// The sample of `r` (its `dropped` field is the connection's to fill).
    pub fn sample(&mut self, r: &PipelineRecord) -> StateSample {
        let tick = self.ticks.extend(r.tick);
        let angles = r
            .motor_counts
            .map(|c| self.device.motor_counts_to_arm_angle_rad(c));
        // A singular or non-finite pose comes back as the origin with a flag: report the origin.
        let (probe, _flags) = self.device.delta.forward::<M>(angles);
        let probe = probe.to_array();
        let homed = homed_counts(r.mode);
        let velocity = match self.previous {
            Some((t0, p0, h0)) if tick > t0 && h0 == homed => {
                let dt = (tick - t0) as f32 / self.rate_hz;
                [0, 1, 2].map(|i| (probe[i] - p0[i]) / dt)
            }
            _ => [0.0; 3],
        };
        self.previous = Some((tick, probe, homed));
        StateSample {
            tick,
            probe_m: probe,
            probe_vel_m_s: velocity,
            force_n: r.force_mn.map(|f| f32::from(f) / 1000.0),
            spin_torque_nm: 0.0,
            contact: contact_state(r.state),
            contact_point_m: [0.0; 3],
            flags: r.flags.0,
            mode: mode(r.mode),
            model_seq: 0,
            tick_stats: Default::default(),
            dropped: 0,
        }
    }
}
