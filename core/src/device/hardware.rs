//! The hardware description the controller and the host plant model must agree on: linkage
//! geometry, motors and capstan drives, H-bridge supply and PWM timer, encoders, and the wrist
//! gimbal convention. Values only the plant needs (inertias, friction, inductance) live in the
//! plant, not here.
//!
//! # Sign conventions (the firmware's pin and counter set-up must honour them)
//!
//! - A positive duty drives a positive motor current, which gives a positive arm torque (towards
//!   increasing arm angle θ, i.e. arm down; see [`crate::device::delta`]).
//! - Motor encoder counts increase with θ. Counts are *extended* 32-bit positions referenced to
//!   the calibration pose: 0 counts ↔ θ = [`DeviceParams::arm_angle_at_zero_count_rad`].
//! - Wrist encoder counts increase with right-handed rotation about the joint's axis; 0 counts is
//!   the wrist's zero pose.
//!
//! # Wrist gimbal
//!
//! Three passive revolute joints carry the handle. Joint 0 (next to the effector platform) turns
//! about the platform's z axis, joint 1 about the y axis after joint 0, joint 2 (in the handle)
//! about the x axis after joints 0 and 1: intrinsic z-y'-x'', so the handle orientation, mapping
//! handle-frame vectors to the base frame `B`, is
//!
//! q = Rz(a₀) · Ry(a₁) · Rx(a₂)
//!
//! (the delta keeps the platform parallel to `B`). Zero pose: all three angles 0, handle frame
//! aligned with `B`. This is the same matrix as nalgebra's `Rotation3::from_euler_angles(a₂, a₁,
//! a₀)` (roll a₂, pitch a₁, yaw a₀).

use crate::device::channels::{EncoderCounts, CHANNELS};
use crate::device::delta::DeltaGeometry;
use crate::flags::{all_finite, Flags};
use crate::math::quat::Quat;
use crate::math::vec3::Vec3;
use crate::math::{Fast, Math};
use core::f32::consts::TAU;

/// One motor with its capstan drive. The three axes use identical drives.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct MotorParams {
    /// Torque constant k_t, N·m/A (motor shaft).
    pub torque_constant_nm_per_a: f32,
    /// Winding (terminal) resistance, Ω.
    pub resistance_ohm: f32,
    /// Back-EMF constant k_e, V·s/rad (motor shaft). Equal to k_t in SI for an ideal DC motor;
    /// kept separate because datasheets give both, rounded differently.
    pub back_emf_v_s_per_rad: f32,
    /// Capstan reduction: motor turns per arm turn (> 1).
    pub capstan_ratio: f32,
    /// Amplifier current limit, A (peak, both directions).
    pub max_current_a: f32,
}

/// Everything about the hardware that the controller and the plant model share.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct DeviceParams {
    /// Delta linkage geometry.
    pub delta: DeltaGeometry,
    /// The (identical) motor and capstan drive of each axis.
    pub motor: MotorParams,
    /// H-bridge supply voltage, V.
    pub supply_v: f32,
    /// PWM timer counts per PWM period (duty resolution), e.g. 4250 = 170 MHz / 40 kHz. The
    /// pipeline and the plant's bridge path take it from the board timing
    /// ([`crate::control::pipeline::BoardTiming`]); the named devices set this field from the same constant.
    pub pwm_period_counts: u32,
    /// Motor encoder quadrature counts per motor-shaft revolution (4 × lines).
    pub motor_encoder_counts_per_rev: u32,
    /// Wrist encoder quadrature counts per joint revolution (encoders sit on the joints).
    pub wrist_encoder_counts_per_rev: u32,
    /// Arm angle θ (rad) at which a motor's extended count is 0 (the calibration pose).
    pub arm_angle_at_zero_count_rad: f32,
}

/// The parameter a [`DeviceParamError`] refers to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum DeviceParamField {
    /// `delta.base_radius_m`.
    BaseRadius,
    /// `delta.effector_radius_m`.
    EffectorRadius,
    /// `delta.upper_arm_m`.
    UpperArm,
    /// `delta.forearm_m`.
    Forearm,
    /// `motor.torque_constant_nm_per_a`.
    TorqueConstant,
    /// `motor.resistance_ohm`.
    Resistance,
    /// `motor.back_emf_v_s_per_rad`.
    BackEmfConstant,
    /// `motor.capstan_ratio`.
    CapstanRatio,
    /// `motor.max_current_a`.
    MaxCurrent,
    /// `supply_v`.
    SupplyVoltage,
    /// `pwm_period_counts`.
    PwmPeriodCounts,
    /// `motor_encoder_counts_per_rev`.
    MotorEncoderCountsPerRev,
    /// `wrist_encoder_counts_per_rev`.
    WristEncoderCountsPerRev,
    /// `arm_angle_at_zero_count_rad`.
    ArmAngleAtZeroCount,
}

impl DeviceParamField {
    /// The field's path in [`DeviceParams`], e.g. `"motor.capstan_ratio"`.
    pub const fn name(self) -> &'static str {
        match self {
            DeviceParamField::BaseRadius => "delta.base_radius_m",
            DeviceParamField::EffectorRadius => "delta.effector_radius_m",
            DeviceParamField::UpperArm => "delta.upper_arm_m",
            DeviceParamField::Forearm => "delta.forearm_m",
            DeviceParamField::TorqueConstant => "motor.torque_constant_nm_per_a",
            DeviceParamField::Resistance => "motor.resistance_ohm",
            DeviceParamField::BackEmfConstant => "motor.back_emf_v_s_per_rad",
            DeviceParamField::CapstanRatio => "motor.capstan_ratio",
            DeviceParamField::MaxCurrent => "motor.max_current_a",
            DeviceParamField::SupplyVoltage => "supply_v",
            DeviceParamField::PwmPeriodCounts => "pwm_period_counts",
            DeviceParamField::MotorEncoderCountsPerRev => "motor_encoder_counts_per_rev",
            DeviceParamField::WristEncoderCountsPerRev => "wrist_encoder_counts_per_rev",
            DeviceParamField::ArmAngleAtZeroCount => "arm_angle_at_zero_count_rad",
        }
    }
}

impl core::fmt::Display for DeviceParamField {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.name())
    }
}

/// Why [`DeviceParams::validate`] rejected a parameter set. Nothing is clamped silently.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum DeviceParamError {
    /// The field is NaN or ±inf.
    NonFinite(DeviceParamField),
    /// The field is zero or negative but must be positive.
    NotPositive(DeviceParamField),
    /// The linkage cannot be assembled (or is singular) at the calibration pose.
    CalibrationPoseUnreachable,
}

impl core::fmt::Display for DeviceParamError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            DeviceParamError::NonFinite(field) => write!(f, "{field} is not finite"),
            DeviceParamError::NotPositive(field) => write!(f, "{field} must be > 0"),
            DeviceParamError::CalibrationPoseUnreachable => {
                f.write_str("the linkage cannot be assembled at the calibration pose")
            }
        }
    }
}

impl core::error::Error for DeviceParamError {}

impl DeviceParams {
    /// Check every field; the first problem found is returned, naming the field.
    pub fn validate(&self) -> Result<(), DeviceParamError> {
        use DeviceParamField as F;
        let positive = [
            (self.delta.base_radius_m, F::BaseRadius),
            (self.delta.effector_radius_m, F::EffectorRadius),
            (self.delta.upper_arm_m, F::UpperArm),
            (self.delta.forearm_m, F::Forearm),
            (self.motor.torque_constant_nm_per_a, F::TorqueConstant),
            (self.motor.resistance_ohm, F::Resistance),
            (self.motor.back_emf_v_s_per_rad, F::BackEmfConstant),
            (self.motor.capstan_ratio, F::CapstanRatio),
            (self.motor.max_current_a, F::MaxCurrent),
            (self.supply_v, F::SupplyVoltage),
        ];
        for (value, field) in positive {
            if !value.is_finite() {
                return Err(DeviceParamError::NonFinite(field));
            }
            if value <= 0.0 {
                return Err(DeviceParamError::NotPositive(field));
            }
        }
        let counts = [
            (self.pwm_period_counts, F::PwmPeriodCounts),
            (
                self.motor_encoder_counts_per_rev,
                F::MotorEncoderCountsPerRev,
            ),
            (
                self.wrist_encoder_counts_per_rev,
                F::WristEncoderCountsPerRev,
            ),
        ];
        for (value, field) in counts {
            if value == 0 {
                return Err(DeviceParamError::NotPositive(field));
            }
        }
        if !self.arm_angle_at_zero_count_rad.is_finite() {
            return Err(DeviceParamError::NonFinite(F::ArmAngleAtZeroCount));
        }
        let theta = [self.arm_angle_at_zero_count_rad; 3];
        // Fast, not Libm: validation runs on the MCU too, and libm's sincosf would add ~7 KB.
        let (p, flags) = self.delta.forward::<Fast>(theta);
        let (_, jflags) = self.delta.jacobian::<Fast>(theta, p);
        if !flags.is_empty() || !jflags.is_empty() {
            return Err(DeviceParamError::CalibrationPoseUnreachable);
        }
        Ok(())
    }

    /// Arm angle per motor encoder count, rad: 2π / (counts per rev · capstan ratio).
    #[inline]
    pub fn arm_rad_per_motor_count(&self) -> f32 {
        TAU / (self.motor_encoder_counts_per_rev as f32 * self.motor.capstan_ratio)
    }

    /// Probe displacement of one motor encoder count at the upper arm's tip, m: the arm angle per
    /// count times the upper arm's length (the probe moves by about this much when one motor's
    /// count changes; 12.8 µm on the Omega-like device).
    #[inline]
    pub fn probe_m_per_motor_count(&self) -> f32 {
        self.arm_rad_per_motor_count() * self.delta.upper_arm_m
    }

    /// Wrist joint angle per wrist encoder count, rad: 2π / counts per rev.
    #[inline]
    pub fn wrist_rad_per_count(&self) -> f32 {
        TAU / self.wrist_encoder_counts_per_rev as f32
    }

    /// Arm angle θ (rad) from an extended motor encoder count.
    #[inline]
    pub fn motor_counts_to_arm_angle_rad(&self, counts: i32) -> f32 {
        self.arm_angle_at_zero_count_rad + counts as f32 * self.arm_rad_per_motor_count()
    }

    /// The extended motor count nearest to arm angle θ (rad): the inverse of
    /// [`Self::motor_counts_to_arm_angle_rad`], rounded to nearest. Saturates at the `i32` range;
    /// a NaN angle gives 0.
    #[inline]
    #[must_use]
    pub fn arm_angle_to_motor_counts(&self, angle_rad: f32) -> i32 {
        libm::roundf(
            (angle_rad - self.arm_angle_at_zero_count_rad) / self.arm_rad_per_motor_count(),
        ) as i32
    }

    /// Encoder counts `[motor0, motor1, motor2, wrist0, wrist1, wrist2]` that put the probe
    /// (fingertip centre) at `p` (base frame `B`, m), with the wrist at `wrist` counts: the delta's
    /// inverse kinematics, each arm angle rounded to its nearest count. `None` where `p` is out of
    /// reach. For the tests, benches and simulators that drive the controller from a probe position.
    #[must_use]
    pub fn counts_at<M: Math>(&self, p: Vec3, wrist: [i32; 3]) -> Option<[i32; CHANNELS]> {
        let (angles, flags) = self.delta.inverse::<M>(p);
        if !flags.is_empty() {
            return None;
        }
        let motor = angles.map(|a| self.arm_angle_to_motor_counts(a));
        Some(EncoderCounts { motor, wrist }.into())
    }

    /// Wrist joint angle (rad) from an extended wrist encoder count.
    #[inline]
    pub fn wrist_counts_to_angle_rad(&self, counts: i32) -> f32 {
        counts as f32 * self.wrist_rad_per_count()
    }

    /// Largest arm torque the amplifier's current limit allows, N·m: ratio · k_t · i_max.
    #[inline]
    pub fn max_arm_torque_nm(&self) -> f32 {
        self.motor.capstan_ratio * self.motor.torque_constant_nm_per_a * self.motor.max_current_a
    }

    /// Duty (in [-1, 1]) that makes a voltage-mode H-bridge deliver `arm_torque_nm` at arm
    /// velocity `arm_velocity_rad_s`. See [`Self::arm_torque_to_duty_checked`]; this drops the
    /// flags.
    #[inline]
    pub fn arm_torque_to_duty(&self, arm_torque_nm: f32, arm_velocity_rad_s: f32) -> f32 {
        self.arm_torque_to_duty_checked(arm_torque_nm, arm_velocity_rad_s)
            .0
    }

    /// Duty for an arm torque, with flags.
    ///
    /// Quasi-static DC motor model: current i = τ_arm / (ratio · k_t), limited to ±i_max; motor
    /// voltage V = R·i + k_e·ω_motor with ω_motor = ratio · ω_arm (the back-EMF feed-forward;
    /// pass `arm_velocity_rad_s = 0` to leave it out); duty = V / V_supply limited to [-1, 1].
    /// Either limit raises [`Flags::OUTPUT_LIMITED`]. Non-finite input gives duty 0 and
    /// [`Flags::NON_FINITE_INPUT`].
    #[must_use]
    pub fn arm_torque_to_duty_checked(
        &self,
        arm_torque_nm: f32,
        arm_velocity_rad_s: f32,
    ) -> (f32, Flags) {
        if !all_finite(&[arm_torque_nm, arm_velocity_rad_s]) {
            return (0.0, Flags::NON_FINITE_INPUT);
        }
        let m = &self.motor;
        let mut flags = Flags::NONE;
        let mut current = arm_torque_nm / (m.capstan_ratio * m.torque_constant_nm_per_a);
        if current.abs() > m.max_current_a {
            current = m.max_current_a.copysign(current);
            flags.insert(Flags::OUTPUT_LIMITED);
        }
        let volts = m.resistance_ohm * current
            + m.back_emf_v_s_per_rad * m.capstan_ratio * arm_velocity_rad_s;
        let mut duty = volts / self.supply_v;
        if !duty.is_finite() {
            // Only with unvalidated parameters (zero supply, ...) or huge velocities.
            return (0.0, flags | Flags::OUT_OF_RANGE);
        }
        if duty.abs() > 1.0 {
            duty = 1.0f32.copysign(duty);
            flags.insert(Flags::OUTPUT_LIMITED);
        }
        (duty, flags)
    }

    /// The PWM compare value for a signed duty, as the firmware writes it: round(|duty| · period)
    /// with the duty's sign (the sign selects the H-bridge direction). Duties beyond ±1 saturate
    /// at ±period; NaN gives 0.
    pub fn duty_to_pwm_counts(&self, duty: f32) -> i32 {
        if duty.is_nan() {
            return 0;
        }
        let period = self.pwm_period_counts as f32;
        let magnitude = duty.abs().min(1.0) * period;
        // magnitude is in [0, period] here, so the cast cannot saturate.
        let counts = (magnitude + 0.5) as i32;
        if duty < 0.0 {
            -counts
        } else {
            counts
        }
    }

    /// Handle orientation from the three wrist joint angles (rad): q = Rz(a₀)·Ry(a₁)·Rx(a₂), maps
    /// handle-frame vectors to the base frame (see the module doc). Non-finite angles give the
    /// identity (wrist angles come from integer counts, so this only guards misuse).
    pub fn wrist_orientation<M: Math>(angles_rad: [f32; 3]) -> Quat {
        if !all_finite(&angles_rad) {
            return Quat::IDENTITY;
        }
        let [a0, a1, a2] = angles_rad;
        // Rz(a₀)·Ry(a₁)·Rx(a₂) multiplied out with half-angle sines and cosines (the general
        // products would spend 32 multiplications on terms that are zero).
        let (s0, c0) = M::sin_cos(0.5 * a0);
        let (s1, c1) = M::sin_cos(0.5 * a1);
        let (s2, c2) = M::sin_cos(0.5 * a2);
        let (cc, ss, cs, sc) = (c0 * c1, s0 * s1, c0 * s1, s0 * c1);
        Quat::new(
            cc * c2 + ss * s2,
            cc * s2 - ss * c2,
            cs * c2 + sc * s2,
            sc * c2 - cs * s2,
        )
    }
}

#[cfg(test)]
mod tests;
