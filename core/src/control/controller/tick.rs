//! What the controller takes and gives each tick: [`TickInput`] (the encoder counts and the fault
//! inputs) and [`TickOutput`] (duties, enable, flags, probe, force). Below both the control law
//! ([`super::Controller`]) and the output guard ([`crate::control::output_guard`]), which checks
//! every output.

use crate::contact::state::ContactState;
use crate::device::channels::CHANNELS;
use crate::flags::Flags;
use crate::math::vec3::Vec3;

/// What the firmware (or the host plant) hands the controller each tick.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct TickInput {
    /// Extended 32-bit encoder positions, counts, in the channel order of
    /// [`crate::device::channels`] (motors 0-2, then wrist joints 0-2; named by
    /// [`EncoderCounts`](crate::device::channels::EncoderCounts)).
    pub counts: [i32; CHANNELS],
    /// The motor drivers' fault input is asserted.
    pub driver_fault: bool,
    /// The previous tick did not finish before this one started.
    pub overrun: bool,
}

/// What the controller hands back.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct TickOutput {
    /// Signed PWM duties in [-1, 1] per motor: sign is the direction pin, magnitude the duty.
    pub duties: [f32; 3],
    /// Drive the shared driver-enable pin. False in any fault: outputs at zero torque.
    pub enable: bool,
    /// Flags raised this tick, including the latched fault flags.
    pub flags: Flags,
    /// Probe (fingertip centre) position in the device base frame, m.
    pub probe_m: Vec3,
    /// Force rendered on the user, base frame, N.
    pub force_n: Vec3,
    /// Spin torque about the contact normal, N·m (not displayed by a 3-DoF device; reported).
    pub tau_n_nm: f32,
    /// Contact state after this tick.
    pub state: ContactState,
}
