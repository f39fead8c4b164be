//! The hardware-independent controller tick: six encoder counts in, three motor duties out.
//! STUB: types final, tick body pending.

use crate::flags::Flags;
use crate::math::Math;
use crate::vec3::Vec3;
use core::marker::PhantomData;

/// What the firmware (or the host plant) hands the controller each tick.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct TickInput {
    /// Extended 32-bit encoder positions, counts: `[motor0, motor1, motor2, wrist0, wrist1, wrist2]`.
    pub counts: [i32; 6],
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
    /// Flags raised this tick (including the latched fault flags).
    pub flags: Flags,
    /// Probe (fingertip centre) position in the device base frame, m.
    pub probe_m: Vec3,
    /// Force rendered on the user, base frame, N.
    pub force_n: Vec3,
    /// Spin torque about the contact normal, N·m (not displayed by a 3-DoF device; reported).
    pub tau_n_nm: f32,
}

/// Everything the controller needs to know about the device and the scene. STUB: fields pending.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ControllerConfig {
    /// Control rate, Hz.
    pub rate_hz: f32,
}

/// A rejected parameter set. STUB: variants pending.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum ParamError {
    /// A value is outside its valid range.
    OutOfRange,
}

/// The controller with its state. Generic over the math backend.
#[derive(Debug)]
pub struct Controller<M: Math> {
    _m: PhantomData<M>,
}

impl<M: Math> Controller<M> {
    /// Build a controller; an invalid configuration is rejected, never clamped.
    pub fn new(_config: ControllerConfig) -> Result<Self, ParamError> {
        Ok(Controller { _m: PhantomData })
    }
    /// One control tick. Never panics; any fault gives zero duties and `enable = false`.
    pub fn tick(&mut self, _input: &TickInput) -> TickOutput {
        TickOutput::default()
    }
    /// Clear latched faults (an explicit operator action).
    pub fn clear_faults(&mut self) {}
}
