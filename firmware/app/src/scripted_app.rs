//! The scripted application session of the processor-in-the-loop run (`scripts/pil
//! --app-session`): what an application does to the device once it is armed, played by the
//! emulated board and by host-sim's in-process reference from this one code, so both apply the
//! same commands at the same ticks (the reference through `Pipeline::link_command`, the board
//! through the tick's link command queue, as the host link's commands arrive).
//!
//! - a state stream at [`STREAM_HZ`] from power-up;
//! - a local model every 1 / [`UPDATE_HZ`] s once armed: the firmware's initial plane
//!   ([`config::INITIAL_PLANE_TOP_M`]) moving up and down in a triangle wave of
//!   ± [`AMPLITUDE_M`] over [`WAVE_UPDATES`] updates, each with the next sequence number;
//! - every [`PARAMS_EVERY`]-th update a contact-parameter change instead: the normal stiffness
//!   alternating between the default's and [`SOFT_STIFFNESS_FRACTION`] of it.
//!
//! Integer steps and f32 arithmetic only (no transcendental functions), so the board and the host
//! compute the same bits.

use softfinger_core::contact::params::ContactParams;
use softfinger_core::control::local_model::{LocalModelSpec, ModelPose};
use softfinger_core::control::pipeline::Command;
use softfinger_core::Vec3;

use crate::config;

/// Local-model updates per second.
pub const UPDATE_HZ: u32 = 1_000;
/// State samples streamed per second.
pub const STREAM_HZ: u32 = 2_000;
/// Every this many updates, a contact-parameter change instead of a model.
pub const PARAMS_EVERY: u32 = 100;
/// The plane's travel each side of its initial height, m.
pub const AMPLITUDE_M: f32 = 0.5e-3;
/// Updates per period of the plane's triangle wave (0.4 s at [`UPDATE_HZ`]).
pub const WAVE_UPDATES: u32 = 400;
/// The softer stiffness, as a fraction of the default's.
pub const SOFT_STIFFNESS_FRACTION: f32 = 0.8;

/// The session's state: how many updates it has given.
#[derive(Clone, Debug)]
pub struct ScriptedApp {
    updates: u32,
    contact: ContactParams,
}

impl ScriptedApp {
    /// The session on the firmware's default contact parameters `contact`.
    pub fn new(contact: ContactParams) -> ScriptedApp {
        ScriptedApp {
            updates: 0,
            contact,
        }
    }

    /// Control ticks between two updates at `rate_hz` (at least 1).
    pub fn update_period_ticks(rate_hz: u32) -> u32 {
        (rate_hz / UPDATE_HZ).max(1)
    }

    /// The stream divisor at `rate_hz` (at least 1).
    pub fn stream_divisor(rate_hz: u32) -> u16 {
        (rate_hz / STREAM_HZ).clamp(1, u32::from(u16::MAX)) as u16
    }

    /// The next update.
    pub fn next_command(&mut self) -> Command {
        self.updates = self.updates.wrapping_add(1);
        let n = self.updates;
        if n % PARAMS_EVERY == 0 {
            let soft = (n / PARAMS_EVERY) % 2 == 1;
            let base = self.contact;
            let stiffness = if soft {
                base.normal_stiffness * SOFT_STIFFNESS_FRACTION
            } else {
                base.normal_stiffness
            };
            return Command::SetContactParams(ContactParams {
                normal_stiffness: stiffness,
                ..base
            });
        }
        let phase = n % WAVE_UPDATES;
        let half = WAVE_UPDATES / 2;
        let up = if phase < half {
            phase
        } else {
            WAVE_UPDATES - phase
        };
        // -1 ..= 1 over the wave.
        let wave = up as f32 / half as f32 * 2.0 - 1.0;
        let top = config::INITIAL_PLANE_TOP_M + Vec3::new(0.0, 0.0, wave * AMPLITUDE_M);
        Command::SetLocalModel(LocalModelSpec::plane(n, ModelPose::at(top), &self.contact))
    }
}
