//! The Omega.6-like device: the one device instance this project ships. Its geometry, motors,
//! limits and homing live here, in one place; generic types carry no device's numbers. The top
//! layer of the crate: an instance names values of every layer below it.

use crate::contact::params::ContactParams;
use crate::contact::surface::Plane;
use crate::control::controller::{ControllerConfig, Limits};
use crate::control::device_definition::DeviceDefinition;
use crate::control::pipeline::homing::HomingSpec;
use crate::control::pipeline::BoardTiming;
use crate::device::delta::DeltaGeometry;
use crate::device::hardware::DeviceParams;
use crate::device::hardware::MotorParams;
use crate::math::Vec3;

/// The Omega.6-like device (see [`DeviceParams::OMEGA_LIKE`] and [`Limits::OMEGA_LIKE`]).
///
/// Homing: down (θ increasing) at 1 rad/s and at most 0.15 N·m to the lower stops at 105°, then
/// up to the upper stops at −40°, the 145° between them checked within 0.02 rad (156 counts; the
/// stops yield 12 counts under the homing torque, measured in host-sim's session); stall 2
/// counts for 0.1 s, park at 0 rad within 0.03 rad, timeout 8 s (both legs and the park from
/// the worst start: 2.5 + 2.5 + 0.7 s plus three stall times).
/// Driver wake 2 ms from the nSLEEP edge (the DRV8876's t_WAKE is 1 ms: 2x margin); arming ramp 0.5 s. Derivation: docs/design.md#homing-limits.
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
        far_stop_angle_rad: 105.0 * core::f32::consts::PI / 180.0,
        range_tolerance_rad: 0.02,
        timeout_s: 8.0,
        stop_angle_rad: -40.0 * core::f32::consts::PI / 180.0,
        park_angle_rad: 0.0,
        park_tolerance_rad: 0.03,
    },
    driver_wake_s: 2.0e-3,
    arm_ramp_s: 0.5,
};

impl DeltaGeometry {
    /// Our geometry for an Omega.6-like device (m): the Omega.6's translational workspace
    /// (∅160 × 110 mm) centred at [`Self::OMEGA_LIKE_WORKSPACE_CENTRE_M`] lies in the
    /// well-conditioned part of the reachable volume, checked on a grid by
    /// `omega_like_workspace_covers_the_datasheet_cylinder`. Derivation:
    /// docs/design.md#delta-geometry.
    pub const OMEGA_LIKE: DeltaGeometry = DeltaGeometry {
        base_radius_m: 0.090,
        effector_radius_m: 0.025,
        upper_arm_m: 0.105,
        forearm_m: 0.180,
    };
    /// Centre of the ∅160 × 110 mm design cylinder of [`Self::OMEGA_LIKE`], frame `B`, m.
    pub const OMEGA_LIKE_WORKSPACE_CENTRE_M: Vec3 = Vec3::new(0.0, 0.0, -0.165);
    /// Radius of the design cylinder, m (datasheet diameter 160 mm).
    pub const OMEGA_LIKE_WORKSPACE_RADIUS_M: f32 = 0.080;
    /// Height of the design cylinder along z, m (datasheet 110 mm).
    pub const OMEGA_LIKE_WORKSPACE_HEIGHT_M: f32 = 0.110;
}

impl DeviceParams {
    /// An Omega.6-like device, our choice of values (Force Dimension does not publish them):
    ///
    /// - linkage: [`DeltaGeometry::OMEGA_LIKE`];
    /// - motors: maxon RE 25-class, k_t = 23.4 mN·m/A, k_e = 0.0234 V·s/rad, 2.18 Ω;
    /// - capstan reduction 12:1; amplifier limit 4 A (1.12 N·m per arm);
    /// - 24 V supply; PWM 40 kHz from a 170 MHz timer clock, 4250 counts per period (from
    ///   [`BoardTiming::STM32G474_10KHZ`]);
    /// - motor encoders 4096 counts per motor turn (0.128 mrad per count at the arm); wrist
    ///   encoders 4096 counts per joint turn;
    /// - counts referenced to the arms-horizontal pose (θ = 0).
    ///
    /// Where the values come from: docs/design.md#motors-reduction-encoders.
    pub const OMEGA_LIKE: DeviceParams = DeviceParams {
        delta: DeltaGeometry::OMEGA_LIKE,
        motor: MotorParams {
            torque_constant_nm_per_a: 0.0234,
            resistance_ohm: 2.18,
            back_emf_v_s_per_rad: 0.0234,
            capstan_ratio: 12.0,
            max_current_a: 4.0,
        },
        supply_v: 24.0,
        pwm_period_counts: BoardTiming::STM32G474_10KHZ.pwm_period_counts(),
        motor_encoder_counts_per_rev: 4096,
        wrist_encoder_counts_per_rev: 4096,
        arm_angle_at_zero_count_rad: 0.0,
    };
}

impl Limits {
    /// The Omega-like device's limits (named by [`OMEGA_LIKE`]).
    ///
    /// Duty ≤ 0.9; glitch 2 M counts/s; overrun streak 1 ms; stuck: 20 % duty for 0.2 s without a
    /// count. Derivation: docs/design.md#limits-and-fault-thresholds.
    pub const OMEGA_LIKE: Limits = Limits {
        max_duty: 0.9,
        max_arm_torque_nm: 2.0,
        glitch_counts_per_s: 2.0e6,
        overrun_streak_s: 1.0e-3,
        stuck_duty: 0.2,
        stuck_s: 0.2,
        velocity_cutoff_hz: 300.0,
        // The Omega-like linkage needs −31° … 94° over its workspace (see `crate::device::delta`); the
        // range allows margin for the workspace's edge.
        arm_angle_range_rad: [-1.05, 2.1],
    };
}

impl ControllerConfig<Plane> {
    /// The Omega-like device ([`DeviceParams::OMEGA_LIKE`], [`Limits::OMEGA_LIKE`]) with the
    /// default environment: a plane 10 mm below the centre of the device's workspace, so the 10 mm
    /// fingertip touches it with its centre at the workspace centre, at 10 kHz.
    pub fn default_plane() -> Self {
        ControllerConfig {
            rate_hz: 10_000.0,
            device: DeviceParams::OMEGA_LIKE,
            contact: ContactParams::DEFAULT,
            surface: Plane::default(),
            object_origin_m: DeltaGeometry::OMEGA_LIKE_WORKSPACE_CENTRE_M
                - Vec3::new(0.0, 0.0, 0.010),
            limits: Limits::OMEGA_LIKE,
        }
    }
}

/// The named device is a valid definition, and each part of a definition is validated (from it).
#[cfg(test)]
mod tests {
    use super::OMEGA_LIKE;
    use crate::validate::ParamError;

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
