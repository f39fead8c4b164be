//! Named device definitions: everything a build needs to know about one device — its hardware
//! ([`DeviceParams`]), limits and fault thresholds ([`Limits`], physical units), homing
//! procedure, driver wake time and arming ramp. The firmware and host-sim name one of these
//! explicitly; nothing picks a device by default.

use crate::controller::Limits;
use crate::device::DeviceParams;
use crate::params::{positive, ParamError};
use crate::pipeline::homing::HomingSpec;

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

/// The Omega.6-like device (see [`DeviceParams::OMEGA_LIKE`] and [`Limits::OMEGA_LIKE`]).
///
/// Homing: up (θ decreasing) at 1 rad/s and at most 0.15 N·m to the upper stops at −40°, stall
/// 2 counts for 0.1 s after 0.05 rad of travel, park at 0 rad within 0.03 rad, timeout 5 s.
/// Driver wake 1 ms; arming ramp 0.5 s. Derivation: docs/design.md#homing-limits.
pub const OMEGA_LIKE: DeviceDefinition = DeviceDefinition {
    name: "omega-like",
    params: DeviceParams::OMEGA_LIKE,
    limits: Limits::OMEGA_LIKE,
    homing: HomingSpec {
        speed_rad_s: -1.0,
        max_torque_nm: 0.15,
        velocity_gain_nm_s_per_rad: 0.5,
        stall_s: 0.1,
        stall_window_counts: 2,
        min_travel_rad: 0.05,
        timeout_s: 5.0,
        stop_angle_rad: -40.0 * core::f32::consts::PI / 180.0,
        park_angle_rad: 0.0,
        park_tolerance_rad: 0.03,
    },
    driver_wake_s: 1.0e-3,
    arm_ramp_s: 0.5,
};

#[cfg(test)]
mod tests {
    use super::*;

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
