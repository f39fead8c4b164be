//! The controller's configuration: the device, the contact model, the environment and the limits and
//! fault thresholds (in physical units; [`Limits::per_tick`] converts them for a control rate).

use super::stage::Environment;
use crate::contact::params::ContactParams;
use crate::contact::surface::Plane;
use crate::device::DeviceParams;
use crate::math::vec3::Vec3;
use crate::validate::{positive, ParamError};

/// Limits and fault thresholds, in physical units so that changing the control rate changes no
/// behaviour; [`Limits::per_tick`] converts them for a rate.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Limits {
    /// Largest |duty| ever output, (0, 1].
    pub max_duty: f32,
    /// Largest motor-side arm torque requested, N·m.
    pub max_arm_torque_nm: f32,
    /// An encoder moving faster than this between two ticks is a glitch, counts/s.
    pub glitch_counts_per_s: f32,
    /// Overrunning ticks for this long in a row latch a fault, s.
    pub overrun_streak_s: f32,
    /// |duty| at or above this, with no count change for `stuck_s`, latches ENCODER_STUCK.
    pub stuck_duty: f32,
    /// Time of drive without motion before ENCODER_STUCK, s.
    pub stuck_s: f32,
    /// Cut-off of the first-order low-pass on the finite-difference velocities, Hz.
    pub velocity_cutoff_hz: f32,
    /// Arm angles outside [min, max] (rad) cannot be reached by the mechanism: the encoders or
    /// their calibration are wrong, so no force is rendered ([`Flags::OUT_OF_RANGE`](crate::Flags::OUT_OF_RANGE)).
    pub arm_angle_range_rad: [f32; 2],
}

/// [`Limits`] converted for one control rate.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct TickLimits {
    /// A count change larger than this in one tick is a glitch: round(glitch_counts_per_s / rate),
    /// at least 1, at most 32 767 (beyond that a 16-bit wrapping difference cannot tell).
    pub max_counts_per_tick: u16,
    /// Consecutive overrun ticks that latch OVERRUN: round(overrun_streak_s · rate), at least 1.
    pub overrun_streak: u32,
    /// Ticks of drive without motion before ENCODER_STUCK: round(stuck_s · rate), at least 1.
    pub stuck_ticks: u32,
}

impl Limits {
    /// Check every field.
    pub fn validate(&self) -> Result<(), ParamError> {
        positive("max_duty", self.max_duty)?;
        if self.max_duty > 1.0 {
            return Err(ParamError::OutOfRange("max_duty"));
        }
        positive("max_arm_torque_nm", self.max_arm_torque_nm)?;
        positive("glitch_counts_per_s", self.glitch_counts_per_s)?;
        positive("overrun_streak_s", self.overrun_streak_s)?;
        positive("stuck_duty", self.stuck_duty)?;
        positive("stuck_s", self.stuck_s)?;
        positive("velocity_cutoff_hz", self.velocity_cutoff_hz)?;
        let [lo, hi] = self.arm_angle_range_rad;
        if !lo.is_finite() || !hi.is_finite() {
            return Err(ParamError::NotFinite("arm_angle_range_rad"));
        }
        if lo >= hi {
            return Err(ParamError::OutOfRange("arm_angle_range_rad"));
        }
        Ok(())
    }

    /// The thresholds in ticks at `rate_hz` (see [`TickLimits`] for the rounding).
    pub fn per_tick(&self, rate_hz: f32) -> TickLimits {
        let glitch = round_at_least_one(self.glitch_counts_per_s / rate_hz).min(32_767);
        TickLimits {
            max_counts_per_tick: glitch as u16,
            overrun_streak: round_at_least_one(self.overrun_streak_s * rate_hz),
            stuck_ticks: round_at_least_one(self.stuck_s * rate_hz),
        }
    }
}

/// Round a non-negative value to the nearest integer, at least 1, saturating; NaN → 1.
fn round_at_least_one(x: f32) -> u32 {
    let r = x + 0.5;
    if r.is_nan() || r < 1.0 {
        1
    } else if r >= u32::MAX as f32 {
        u32::MAX
    } else {
        r as u32
    }
}

/// Everything the controller needs to know about the device and the environment.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ControllerConfig<S: Environment = Plane> {
    /// Control rate, Hz (1 kHz to 40 kHz).
    pub rate_hz: f32,
    /// The device: kinematics, motors, encoders.
    pub device: DeviceParams,
    /// The contact model.
    pub contact: ContactParams,
    /// The environment: a fixed surface, or the local model (see [`super::stage`]).
    pub surface: S,
    /// Origin of the object frame in the device base frame, m.
    pub object_origin_m: Vec3,
    /// Limits and fault thresholds.
    pub limits: Limits,
}

impl<S: Environment> ControllerConfig<S> {
    /// Check every part.
    pub fn validate(&self) -> Result<(), ParamError> {
        positive("rate_hz", self.rate_hz)?;
        if !(1_000.0..=40_000.0).contains(&self.rate_hz) {
            return Err(ParamError::OutOfRange("rate_hz"));
        }
        self.device.validate().map_err(ParamError::Device)?;
        self.contact.validate()?;
        self.limits.validate()?;
        if !self.object_origin_m.is_finite() {
            return Err(ParamError::NotFinite("object_origin_m"));
        }
        Ok(())
    }
}
