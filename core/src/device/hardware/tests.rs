//! Tests of the device parameters: validation, conversions on known values, the wrist convention
//! against nalgebra's f64 rotations.

use super::*;
use crate::math::vec3::Vec3;
use crate::math::{Fast, Libm};
use nalgebra::{Rotation3, UnitQuaternion, Vector3};

const D: DeviceParams = DeviceParams::OMEGA_LIKE;

#[test]
fn omega_like_is_valid() {
    assert_eq!(D.validate(), Ok(()));
}

#[test]
fn validate_rejects_each_bad_float_field_by_name() {
    use DeviceParamField as F;
    type Setter = fn(&mut DeviceParams, f32);
    let fields: [(Setter, DeviceParamField); 10] = [
        (|d, v| d.delta.base_radius_m = v, F::BaseRadius),
        (|d, v| d.delta.effector_radius_m = v, F::EffectorRadius),
        (|d, v| d.delta.upper_arm_m = v, F::UpperArm),
        (|d, v| d.delta.forearm_m = v, F::Forearm),
        (
            |d, v| d.motor.torque_constant_nm_per_a = v,
            F::TorqueConstant,
        ),
        (|d, v| d.motor.resistance_ohm = v, F::Resistance),
        (|d, v| d.motor.back_emf_v_s_per_rad = v, F::BackEmfConstant),
        (|d, v| d.motor.capstan_ratio = v, F::CapstanRatio),
        (|d, v| d.motor.max_current_a = v, F::MaxCurrent),
        (|d, v| d.supply_v = v, F::SupplyVoltage),
    ];
    for (set, field) in fields {
        for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
            let mut d = D;
            set(&mut d, bad);
            assert_eq!(d.validate(), Err(DeviceParamError::NonFinite(field)));
        }
        for bad in [0.0, -0.0, -1.0e-9, -3.0] {
            let mut d = D;
            set(&mut d, bad);
            assert_eq!(d.validate(), Err(DeviceParamError::NotPositive(field)));
        }
    }
}

#[test]
fn validate_rejects_zero_counts_and_a_non_finite_calibration_angle() {
    use DeviceParamField as F;
    let mut d = D;
    d.pwm_period_counts = 0;
    assert_eq!(
        d.validate(),
        Err(DeviceParamError::NotPositive(F::PwmPeriodCounts))
    );
    let mut d = D;
    d.motor_encoder_counts_per_rev = 0;
    assert_eq!(
        d.validate(),
        Err(DeviceParamError::NotPositive(F::MotorEncoderCountsPerRev))
    );
    let mut d = D;
    d.wrist_encoder_counts_per_rev = 0;
    assert_eq!(
        d.validate(),
        Err(DeviceParamError::NotPositive(F::WristEncoderCountsPerRev))
    );
    let mut d = D;
    d.arm_angle_at_zero_count_rad = f32::NAN;
    assert_eq!(
        d.validate(),
        Err(DeviceParamError::NonFinite(F::ArmAngleAtZeroCount))
    );
    // A negative calibration angle is legitimate (arm above horizontal).
    let mut d = D;
    d.arm_angle_at_zero_count_rad = -0.2;
    assert_eq!(d.validate(), Ok(()));
}

#[test]
fn validate_rejects_a_linkage_that_cannot_assemble_at_the_calibration_pose() {
    let mut d = D;
    d.delta.forearm_m = 0.05; // the arms-horizontal elbows are 0.17 m from the axis
    assert_eq!(
        d.validate(),
        Err(DeviceParamError::CalibrationPoseUnreachable)
    );
}

#[test]
fn count_conversions_are_exact_on_known_values() {
    // 4096 counts/rev × 12 = 49152 motor counts per arm turn; a quarter turn is 12288 counts.
    assert_eq!(D.motor_counts_to_arm_angle_rad(0), 0.0);
    let quarter = D.motor_counts_to_arm_angle_rad(12288);
    // 12288 and 49152 are exact in f32; the only rounding is TAU/49152 and one product: ≤ 1 ulp
    // of π/2 each (1.2e-7 rad). Measured 0: the bound is this ulp argument.
    assert!(
        (quarter - core::f32::consts::FRAC_PI_2).abs() <= 2.4e-7,
        "{quarter}"
    );
    assert_eq!(
        D.motor_counts_to_arm_angle_rad(-12288),
        -D.motor_counts_to_arm_angle_rad(12288)
    );
    // With a calibration offset the offset is added exactly at count 0.
    let mut d = D;
    d.arm_angle_at_zero_count_rad = 0.5;
    assert_eq!(d.motor_counts_to_arm_angle_rad(0), 0.5);
    // One count at the arm: 2π/49152 = 1.2783e-4 rad (f64 reference, 1e-7 relative bound).
    // Measured 3.56e-12 rad (half an ulp); the bound is 3.7x.
    let one = D.motor_counts_to_arm_angle_rad(1) as f64;
    assert!((one - 2.0 * core::f64::consts::PI / 49152.0).abs() < 1.3e-11);
    // Wrist: 4096 counts per joint turn, so 1024 counts is π/2 and -2048 is -π. Measured 0 for
    // both: the bounds are 1 and 2 ulp of the result, an ulp argument.
    let w = D.wrist_counts_to_angle_rad(1024);
    assert!((w - core::f32::consts::FRAC_PI_2).abs() <= 1.2e-7, "{w}");
    let w = D.wrist_counts_to_angle_rad(-2048);
    assert!((w + core::f32::consts::PI).abs() <= 2.4e-7, "{w}");
    // Extreme counts stay finite.
    assert!(D.motor_counts_to_arm_angle_rad(i32::MIN).is_finite());
    assert!(D.wrist_counts_to_angle_rad(i32::MAX).is_finite());
}

/// Angle to count rounds to nearest: a hair below the midpoint between counts k and k + 1 gives
/// k, a hair above gives k + 1; out-of-range angles saturate and NaN gives 0.
#[test]
fn arm_angle_to_motor_counts_rounds_at_the_midpoint() {
    let step = D.arm_rad_per_motor_count();
    for k in [-300, 0, 41] {
        let mid = (k as f32 + 0.5) * step;
        assert_eq!(D.arm_angle_to_motor_counts(mid - 1e-3 * step), k, "k {k}");
        assert_eq!(
            D.arm_angle_to_motor_counts(mid + 1e-3 * step),
            k + 1,
            "k {k}"
        );
        assert_eq!(
            D.arm_angle_to_motor_counts(D.motor_counts_to_arm_angle_rad(k)),
            k
        );
    }
    assert_eq!(D.arm_angle_to_motor_counts(1e30), i32::MAX);
    assert_eq!(D.arm_angle_to_motor_counts(-1e30), i32::MIN);
    assert_eq!(D.arm_angle_to_motor_counts(f32::NAN), 0);
}

/// `counts_at` inverts the kinematics to the nearest counts: the forward kinematics of its counts
/// is within the quantisation of the target (each arm at most half a count off, so the probe at
/// most 3 · ½ · 12.8 µm = 19 µm; measured 7.6 µm at worst on these points), the wrist counts pass
/// through, and an unreachable point gives `None`.
#[test]
fn counts_at_puts_the_probe_within_the_count_quantisation() {
    let centre = crate::device::delta::DeltaGeometry::OMEGA_LIKE_WORKSPACE_CENTRE_M;
    let half_count_reach = 1.5 * D.probe_m_per_motor_count();
    for off in [
        Vec3::ZERO,
        Vec3::new(0.03, -0.02, 0.01),
        Vec3::new(-0.05, 0.04, -0.04),
    ] {
        let p = centre + off;
        let c = D.counts_at::<Libm>(p, [1, -2, 3]).expect("reachable");
        assert_eq!(&c[3..], &[1, -2, 3]);
        let angles = [0, 1, 2].map(|i| D.motor_counts_to_arm_angle_rad(c[i]));
        let (q, f) = D.delta.forward::<Libm>(angles);
        assert!(f.is_empty());
        let err = (q - p).norm::<Libm>();
        assert!(err <= half_count_reach, "{p:?}: {:?}", q - p);
    }
    assert_eq!(D.counts_at::<Libm>(Vec3::new(0.0, 0.0, 1.0), [0; 3]), None);
}

#[test]
fn torque_to_duty_follows_the_dc_motor_closed_form() {
    // 0.1 N·m at rest: i = 0.1/(12·0.0234) = 0.356125 A, V = 2.18·i = 0.776353 V,
    // duty = V/24 = 0.0323480 (worked by hand from the datasheet values). Measured 5.59e-8 (the
    // hand value's rounding to 6 digits included); bound 3x.
    let (duty, flags) = D.arm_torque_to_duty_checked(0.1, 0.0);
    assert!(flags.is_empty());
    assert!((duty - 0.032_348).abs() < 1.7e-7, "{duty}");
    // Back-EMF: 2 rad/s at the arm is 24 rad/s at the motor, 0.5616 V, duty + 0.0234. Measured
    // 1.86e-9; bound 3x.
    let (duty_moving, _) = D.arm_torque_to_duty_checked(0.1, 2.0);
    assert!(
        (duty_moving - duty - 0.0234).abs() < 5.6e-9,
        "{duty_moving}"
    );
    // Odd in (torque, velocity).
    assert_eq!(D.arm_torque_to_duty(-0.1, -2.0), -duty_moving);
    // Current limit: a torque needing more than 4 A is delivered at 4 A: V = 8.72 V. Both measured
    // exact: bounds 1 ulp of the results (3e-8 of 0.363, 1.2e-7 of 1.12), an ulp argument.
    let (duty, flags) = D.arm_torque_to_duty_checked(5.0, 0.0);
    assert_eq!(flags, Flags::OUTPUT_LIMITED);
    assert!((duty - 2.18 * 4.0 / 24.0).abs() <= 3e-8, "{duty}");
    assert!((D.max_arm_torque_nm() - 12.0 * 0.0234 * 4.0).abs() <= 1.2e-7);
    // Duty limit: fast motion against the torque needs more than the supply.
    let (duty, flags) = D.arm_torque_to_duty_checked(0.5, 100.0);
    assert_eq!((duty, flags), (1.0, Flags::OUTPUT_LIMITED));
    let (duty, _) = D.arm_torque_to_duty_checked(-0.5, -100.0);
    assert_eq!(duty, -1.0);
    // Non-finite input.
    assert_eq!(
        D.arm_torque_to_duty_checked(f32::NAN, 0.0),
        (0.0, Flags::NON_FINITE_INPUT)
    );
    assert_eq!(
        D.arm_torque_to_duty_checked(0.1, f32::INFINITY),
        (0.0, Flags::NON_FINITE_INPUT)
    );
}

#[test]
fn duty_to_pwm_counts_rounds_and_saturates() {
    assert_eq!(D.duty_to_pwm_counts(0.0), 0);
    // The board's 40 kHz PWM: 4250 counts per period.
    assert_eq!(D.pwm_period_counts, 4250);
    assert_eq!(D.duty_to_pwm_counts(0.5), 2125);
    assert_eq!(D.duty_to_pwm_counts(-1.0), -4250);
    assert_eq!(D.duty_to_pwm_counts(1.7), 4250);
    assert_eq!(D.duty_to_pwm_counts(-f32::INFINITY), -4250);
    assert_eq!(D.duty_to_pwm_counts(f32::NAN), 0);
    // 1.4 counts rounds down, 1.6 up (1/4250 = 2.353e-4 per count).
    assert_eq!(D.duty_to_pwm_counts(1.4 / 4250.0), 1);
    assert_eq!(D.duty_to_pwm_counts(-1.6 / 4250.0), -2);
}

fn na_quat(q: Quat) -> UnitQuaternion<f64> {
    UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
        q.w as f64, q.x as f64, q.y as f64, q.z as f64,
    ))
}

#[test]
fn wrist_orientation_matches_nalgebra_rotation_composition() {
    let angles = [-2.5f32, -1.2, -0.3, 0.0, 0.4, 1.5, 3.0];
    for &a0 in &angles {
        for &a1 in &angles {
            for &a2 in &angles {
                let q = DeviceParams::wrist_orientation::<Libm>([a0, a1, a2]);
                let (a0, a1, a2) = (a0 as f64, a1 as f64, a2 as f64);
                let r_ref = Rotation3::from_axis_angle(&Vector3::z_axis(), a0)
                    * Rotation3::from_axis_angle(&Vector3::y_axis(), a1)
                    * Rotation3::from_axis_angle(&Vector3::x_axis(), a2);
                // nalgebra's own roll-pitch-yaw constructor is the same matrix (documented).
                // Measured 0: bound 2 ulp of 1 in f64 (4.5e-16), an ulp argument.
                let r_euler = Rotation3::from_euler_angles(a2, a1, a0);
                assert!((r_ref.matrix() - r_euler.matrix()).abs().max() < 4.5e-16);
                let r = na_quat(q).to_rotation_matrix();
                // Three f32 quaternion products: ~5 roundings of 6e-8 each on unit-size entries.
                // Measured 2.01e-7 on any matrix entry over the 343 wrist poses; bound 3x, 6e-7.
                let err = (r.matrix() - r_ref.matrix()).abs().max();
                assert!(err < 6e-7, "{a0} {a1} {a2}: {err}");
                // Unit norm kept to f32 precision: measured 2.38e-7; bound 3x.
                assert!((q.norm_squared() - 1.0).abs() < 7.2e-7);
                // Same with the project's backend: measured 2.01e-7; bound 3x.
                let qf = DeviceParams::wrist_orientation::<Fast>([a0 as f32, a1 as f32, a2 as f32]);
                let rf = na_quat(qf).to_rotation_matrix();
                assert!((rf.matrix() - r_ref.matrix()).abs().max() < 6e-7);
            }
        }
    }
}

#[test]
fn wrist_joint_zero_is_identity_and_joint_two_turns_the_handle_x_axis() {
    assert_eq!(
        DeviceParams::wrist_orientation::<Libm>([0.0; 3]),
        Quat::IDENTITY
    );
    // Joint 0 at +90°: the handle's x axis points along the base y axis (right-hand about z).
    // Squared distances: measured 7.1e-15 here and 2.84e-14 for both axes below; bounds 3x.
    let q = DeviceParams::wrist_orientation::<Libm>([core::f32::consts::FRAC_PI_2, 0.0, 0.0]);
    assert!((q.rotate(Vec3::X) - Vec3::Y).norm_squared() < 2.1e-14);
    // Joints 0 and 2 at +90°: joint 2 turns about the handle x axis (now base y), taking the
    // handle's y axis (base −x after joint 0) to base +z.
    let q = DeviceParams::wrist_orientation::<Libm>([
        core::f32::consts::FRAC_PI_2,
        0.0,
        core::f32::consts::FRAC_PI_2,
    ]);
    assert!((q.rotate(Vec3::X) - Vec3::Y).norm_squared() < 8.5e-14);
    assert!((q.rotate(Vec3::Y) - Vec3::Z).norm_squared() < 8.5e-14);
    // Non-finite angles give the identity.
    assert_eq!(
        DeviceParams::wrist_orientation::<Libm>([f32::NAN, 0.0, 0.0]),
        Quat::IDENTITY
    );
}

/// One motor count at the probe: 2π/(counts per rev · capstan) · upper arm (f64 closed form); the
/// Omega-like device gives 12.8 µm, the size of the probe's count dither in a closed-loop hold.
/// Measured 3.2e-8 relative; bound 3x, 1e-7.
#[test]
fn probe_displacement_of_one_motor_count() {
    let p = DeviceParams::OMEGA_LIKE;
    let expected = std::f64::consts::TAU
        / (p.motor_encoder_counts_per_rev as f64 * p.motor.capstan_ratio as f64)
        * p.delta.upper_arm_m as f64;
    let got = p.probe_m_per_motor_count() as f64;
    assert!(
        (got - expected).abs() < 1e-7 * expected,
        "{got} vs {expected}"
    );
    assert!((12.0e-6..13.5e-6).contains(&got), "{got}");
}

/// The message names the field by its path in `DeviceParams`.
#[test]
fn display_names_the_field() {
    use std::string::ToString;
    let bad = DeviceParams {
        supply_v: f32::NAN,
        ..D
    };
    let e: &dyn core::error::Error = &bad.validate().unwrap_err();
    assert_eq!(e.to_string(), "supply_v is not finite");
    assert_eq!(
        DeviceParamError::NotPositive(DeviceParamField::UpperArm).to_string(),
        "delta.upper_arm_m must be > 0"
    );
}
