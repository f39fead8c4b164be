//! The Omega.6-like device: the one device instance this project ships. Its geometry, motors,
//! limits and homing live here, in one place; generic types carry no device's numbers.

use crate::contact::params::ContactParams;
use crate::contact::surface::Plane;
use crate::control::controller::{ControllerConfig, Limits};
use crate::control::pipeline::homing::HomingSpec;
use crate::control::pipeline::BoardTiming;
use crate::device::delta::DeltaGeometry;
use crate::device::hardware::MotorParams;
use crate::device::{DeviceDefinition, DeviceParams};
use crate::math::Vec3;

/// The Omega.6-like device (see [`DeviceParams::OMEGA_LIKE`] and [`Limits::OMEGA_LIKE`]).
///
/// Homing drives the arms up (θ decreasing) to their upper stops at −40° (the mechanical stop of
/// the linkage, as in host-sim's plant) at 1 rad/s, with at most 0.15 N·m: twice the largest
/// holding torque the arm needs against gravity and friction (0.15 kg effector shared by three
/// arms at ~0.1 m, 1.5e-3 kg·m arm mass moment, 0.01 N·m Coulomb friction: about 0.075 N·m),
/// and 13 % of the amplifier's 1.12 N·m. Stall: no more than 2 counts of motion for 0.1 s, after
/// at least 0.05 rad of travel. Then the arms park at 0 rad (arms horizontal, 0.7 rad from the
/// stops, inside the linkage's dead centres) within 0.03 rad: the park loop commands 10 rad/s
/// per rad of error, and the 0.06 N·m gravity share leaves about 0.012 rad of error. Timeout 5 s
/// (the full 145° range takes 2.5 s at 1 rad/s, the park 0.7 s).
///
/// Driver wake 1 ms: the order of a DRV887x's wake-up time (check the fitted part's datasheet).
/// Arming ramp 0.5 s: slow enough that the largest force (12 N) rises at 24 N/s, i.e. 2.4 mN per
/// 10 kHz tick.
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

impl DeltaGeometry {
    /// Our geometry for an Omega.6-like device. Force Dimension does not publish the linkage
    /// dimensions; these values are ours, chosen so that the Omega.6's translational workspace
    /// (datasheet: ∅160 × 110 mm) fits inside the well-conditioned part of the reachable volume:
    /// over the cylinder ∅160 × 110 mm centred at [`Self::OMEGA_LIKE_WORKSPACE_CENTRE_M`], the arm
    /// angles stay within about −31° … 94°, the forearm volume (see [`MIN_FOREARM_VOLUME`]) stays
    /// above 0.6, and no arm needs more than 0.115 N·m of torque per newton of effector force in
    /// any direction (so the 1.12 N·m arm torque of [`crate::device::DeviceParams::OMEGA_LIKE`]
    /// renders at least 9.8 N in every direction). A cylinder 15 % larger in both dimensions is
    /// still reachable. The test
    /// `omega_like_workspace_covers_the_datasheet_cylinder` checks these figures on a grid.
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
    /// - motors: a maxon RE 25-class brushed DC motor (Ø25 mm, 20 W, graphite brushes, 24 V
    ///   winding), figures as in maxon's catalogue for that class, rounded: k_t = 23.4 mN·m/A,
    ///   speed constant 408 rpm/V (k_e = 60/(2π·408) = 0.0234 V·s/rad), terminal resistance
    ///   2.18 Ω (also: inductance 0.24 mH, rotor inertia 10.8 g·cm², which the plant uses). They
    ///   are self-consistent: R·J/k² = 4.3 ms, the catalogue's mechanical time constant. Check a
    ///   current datasheet before using them on hardware;
    /// - capstan reduction 12:1 (ours: a 5 mm drive pulley on a 60 mm arm sector);
    /// - amplifier limit 4 A: a short-term peak (the RE 25's continuous current is about 1.5 A),
    ///   giving 12 × 0.0234 × 4 = 1.12 N·m per arm;
    /// - 24 V supply; PWM 40 kHz from a 170 MHz timer clock, 4250 counts per period (from
    ///   [`BoardTiming::STM32G474_10KHZ`]);
    /// - motor encoders 1024 lines (4096 quadrature counts per motor turn): 2π/(4096·12) =
    ///   0.128 mrad per count at the arm, ~13 µm at the effector;
    /// - wrist encoders 4096 counts per joint turn (0.088° per count);
    /// - counts referenced to the arms-horizontal pose (θ = 0).
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
    /// The Omega-like device's limits (named by [`crate::device::OMEGA_LIKE`]).
    ///
    /// - duty ≤ 0.9: leaves bootstrap and current-sense margin on the bridge;
    /// - glitch: 2 M counts/s, three times the motor's no-load speed at 24 V (24 V / k_e =
    ///   1026 rad/s = 669 k counts/s with 4096 counts per turn): 200 counts per tick at 10 kHz,
    ///   100 at 20 kHz;
    /// - overrun streak: 1 ms (10 ticks at 10 kHz, 20 at 20 kHz);
    /// - stuck: 20 % duty for 0.2 s without a single count: a hand holding the handle still
    ///   against that drive still moves it by more than a count (physiological tremor). The duty
    ///   threshold must lie below the largest duty at stall, R·i_max/V = 2.18·4/24 = 0.363: a
    ///   frozen encoder reads zero velocity, so its motor gets no back-EMF feed-forward and its
    ///   duty never exceeds that. At the 12 N force limit the duties of the touch scene reach
    ///   about 0.24.
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
    /// default scene: a plane 10 mm below the centre of the device's workspace, so the 10 mm
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
