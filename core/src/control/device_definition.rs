//! Device definitions: everything a build needs to know about one device — its hardware
//! ([`DeviceParams`]), limits and fault thresholds ([`Limits`], physical units), homing
//! procedure, driver wake time and arming ramp. Above the parts it configures (the controller's
//! limits, the homing procedure) and below the pipeline's configuration, which holds one. The
//! firmware and host-sim name one instance explicitly ([`crate::omega_like::OMEGA_LIKE`]);
//! nothing picks a device by default.

use crate::control::controller::Limits;
use crate::control::pipeline::homing::HomingSpec;
use crate::device::hardware::DeviceParams;
use crate::validate::{positive, ParamError};

/// One device, complete.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct DeviceDefinition {
    /// Name for logs and reports.
    pub name: &'static str,
    /// Kinematics, motors, encoders.
    pub params: DeviceParams,
    /// Limits and fault thresholds, physical units.
    pub limits: Limits,
    /// How the arms find their zero.
    pub homing: HomingSpec,
    /// Driver wake-up time after nSLEEP goes high, s: nFAULT is ignored and the bridges stay
    /// disabled for this long.
    pub driver_wake_s: f32,
    /// Time over which the force ramps in after arming, s.
    pub arm_ramp_s: f32,
}

impl DeviceDefinition {
    /// Check every part.
    pub fn validate(&self) -> Result<(), ParamError> {
        self.params.validate().map_err(ParamError::Device)?;
        self.limits.validate()?;
        self.homing.validate()?;
        positive("driver_wake_s", self.driver_wake_s)?;
        positive("arm_ramp_s", self.arm_ramp_s)?;
        Ok(())
    }
}
