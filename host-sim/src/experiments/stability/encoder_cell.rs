//! The device plant's verdict on the 3x wall with passivity: the cycle no larger than the encoder
//! quantisation's own, in position and in force.
//!
//! **The floor.** The controller sees the probe only on the lattice of motor-encoder counts.
//! Near the workspace axis the three motors' counts change at about the same height, so along the
//! plane's normal (z) the wall sees cells of [`normal_cell_m`] (22.6 µm for the Omega-like device
//! at the scene's touching pose) and renders one spring force per cell. Once the spring's step over
//! one cell, K·cell, exceeds the load the wall holds, no cell gives an equilibrium and the probe
//! keeps crossing a cell edge: a dither the controller cannot tell from rest until it spans more
//! than one cell, and in which the spring force takes two values K·cell apart, whose standard
//! deviation is at most K·cell/2 (a two-level signal of duty p: step·√(p(1−p))). The largest
//! passive wall without the stage sits on that floor: peak to peak 12.4-14.2 µm at 10 kHz and
//! 12.6 µm at 20 kHz, force standard deviation 1.30 N and 1.45 N against K·cell/2 = 1.35 N and
//! 1.45 N (`device_plant[i].passive_1x_*`).
//!
//! **The verdict.** The 3x wall is bounded at a rate when, over the last second of a 2 s run, the
//! effector's peak-to-peak height in every 0.1 s window is at most one cell *and* the rendered
//! force's standard deviation (the run's last 0.5 s) is at most K·cell/2. The force condition
//! matters: a damper strong enough to hold the position within one cell can do it by kicking the
//! force at every count edge (measured: a damper limit of K·1.6 ms holds 12-13 µm at 10 kHz with
//! a force standard deviation of 9.0 N against 4.1 N), which the user feels as a buzz.

use crate::sim::closed_loop;
use softfinger_core::contact::params::ContactParams;
use softfinger_core::device::DeviceParams;
use softfinger_core::math::vec3::Vec3;
use softfinger_core::math::Fast;

/// The windows of [`super::haptic_device::envelope`] the verdict reads: the last second.
pub const LATE_WINDOWS: usize = 10;

/// The z displacement of the probe when every motor advances one count from the encoder lattice
/// point nearest the touching pose of the device-plant scene (probe on the axis, fingertip on the
/// plane), m (`None`: the pose is outside the workspace).
pub fn normal_cell_m(device: &DeviceParams) -> Option<f64> {
    let touch_z =
        closed_loop::surface_top_z_m() + f64::from(ContactParams::DEFAULT.fingertip_radius_m);
    let (angles, flags) = device
        .delta
        .inverse::<Fast>(Vec3::new(0.0, 0.0, touch_z as f32));
    if !flags.is_empty() {
        return None;
    }
    let q = device.arm_rad_per_motor_count();
    let zero = device.arm_angle_at_zero_count_rad;
    let at = |extra: f32| {
        let lattice = angles.map(|a| zero + (((a - zero) / q).round() + extra) * q);
        let (p, f) = device.delta.forward::<Fast>(lattice);
        f.is_empty().then_some(f64::from(p.z))
    };
    Some((at(1.0)? - at(0.0)?).abs())
}

/// The largest of the last [`LATE_WINDOWS`] window amplitudes, m (`None`: fewer windows; NaN
/// when any of them is NaN).
pub fn late_max_m(envelope: &[f64]) -> Option<f64> {
    let late = envelope.get(envelope.len().checked_sub(LATE_WINDOWS)?..)?;
    late.iter().copied().reduce(|a, b| {
        if a.is_nan() || b.is_nan() {
            f64::NAN
        } else {
            a.max(b)
        }
    })
}

/// The verdict's figures for one wall.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct CellVerdict {
    /// Largest late window amplitude ([`late_max_m`]), m.
    pub late_amp_max_m: f64,
    /// The rendered force's standard deviation along z, N, and its bound K·cell/2, N.
    pub force_z_std_n: f64,
    pub force_z_std_bound_n: f64,
    /// Both within the floor (a non-finite figure is not).
    pub bounded: bool,
}

/// The verdict on a wall of stiffness `k_n_per_m` (N/m) with cell `cell_m` (m), from its
/// envelope and force standard deviation (`None`: fewer than [`LATE_WINDOWS`] windows).
pub fn verdict(
    envelope: &[f64],
    force_z_std_n: f64,
    k_n_per_m: f64,
    cell_m: f64,
) -> Option<CellVerdict> {
    let late = late_max_m(envelope)?;
    let bound = 0.5 * k_n_per_m * cell_m;
    Some(CellVerdict {
        late_amp_max_m: late,
        force_z_std_n,
        force_z_std_bound_n: bound,
        bounded: late.is_finite()
            && late <= cell_m
            && force_z_std_n.is_finite()
            && force_z_std_n <= bound,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The Omega-like device's cell along z at the touching pose: 22.6 µm, the spacing of the
    /// two probe heights the 3x wall's cycle visits (−7.58 and +15.01 µm in
    /// `device_plant[i].passivity_3x_cycle.levels`, 22.59 µm apart); three counts of the
    /// 7.5 µm single-motor levels. Bound ±0.3 µm (the levels' 0.1 µm rounding, the lattice's
    /// curvature). A finer encoder gives a proportionally finer cell.
    #[test]
    fn cell_of_the_omega_like_device() {
        let d = DeviceParams::OMEGA_LIKE;
        let cell = normal_cell_m(&d).unwrap();
        assert!((cell - 22.59e-6).abs() < 0.3e-6, "{cell}");
        let fine = DeviceParams {
            motor_encoder_counts_per_rev: 16 * d.motor_encoder_counts_per_rev,
            ..d
        };
        let f = normal_cell_m(&fine).unwrap();
        assert!((f * 16.0 - cell).abs() < 0.5e-6, "{f}");
    }

    /// The verdict reads only the last ten windows; it is bounded at exactly one cell and
    /// just below K·cell/2 and not just above either (K = 1e5 N/m, cell 1 µm: 0.05 N).
    #[test]
    fn verdict_reads_the_last_second_and_the_force() {
        let mut env = vec![1.0; 5];
        env.extend([1e-6; LATE_WINDOWS]);
        assert_eq!(late_max_m(&env), Some(1e-6));
        let at = |env: &[f64], std, cell| verdict(env, std, 1e5, cell).map(|v| v.bounded);
        assert_eq!(at(&env, 0.0499, 1e-6), Some(true));
        assert_eq!(at(&env, 0.0499, 0.999e-6), Some(false));
        assert_eq!(at(&env, 0.0501, 1e-6), Some(false));
        assert_eq!(at(&env, f64::NAN, 1e-6), Some(false));
        let v = verdict(&env, 0.01, 1e5, 1e-6).unwrap();
        assert!((v.force_z_std_bound_n - 0.05).abs() < 1e-12);
        env[5] = f64::NAN;
        assert_eq!(at(&env, 0.0, 1.0), Some(false));
        assert_eq!(at(&[1e-6; LATE_WINDOWS - 1], 0.0, 1.0), None);
    }
}
