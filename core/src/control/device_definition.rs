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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::omega_like::OMEGA_LIKE;

    #[test]
    fn omega_like_is_valid() {
        assert_eq!(OMEGA_LIKE.validate(), Ok(()));
    }

    #[test]
    fn each_part_is_validated() {
        let mut d = OMEGA_LIKE;
        d.driver_wake_s = 0.0;
        assert_eq!(d.validate(), Err(ParamError::NotPositive("driver_wake_s")));
        let mut d = OMEGA_LIKE;
        d.arm_ramp_s = f32::NAN;
        assert_eq!(d.validate(), Err(ParamError::NotFinite("arm_ramp_s")));
        let mut d = OMEGA_LIKE;
        d.homing.speed_rad_s = 0.0;
        assert!(d.validate().is_err());
        let mut d = OMEGA_LIKE;
        d.limits.stuck_s = -1.0;
        assert!(d.validate().is_err());
        let mut d = OMEGA_LIKE;
        d.params.supply_v = 0.0;
        assert!(d.validate().is_err());
    }
}
