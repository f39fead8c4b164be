//! The device plant's verdict on the 3x wall with passivity: its late cycle within one encoder
//! cell along the wall's normal.
//!
//! **Why one cell.** The controller sees the probe only on the lattice of motor-encoder counts.
//! Near the workspace axis the three motors' counts change at about the same height, so along the
//! plane's normal (z) the wall sees cells of [`normal_cell_m`] (22.6 µm for the Omega-like device
//! at the scene's touching pose) and renders one force per cell. Once the spring's step over one
//! cell exceeds the load the wall holds (2.6 N here), no cell gives an equilibrium and any
//! controller on these encoders keeps the probe crossing one cell edge: a cycle that the
//! controller cannot tell from rest until it spans more than one cell. A passive wall shows it
//! too: the largest passive wall, without the stage, cycles 12.4-14.2 µm at 10 kHz and 12.6 µm at
//! 20 kHz (`device_plant[i].passive_1x_late_amp_m`). A cycle larger than one cell is one the
//! controller sees and sustains: an instability. So the 3x wall is bounded at a rate when the
//! effector's peak-to-peak height in every 0.1 s window of the last second of a 2 s run is at
//! most one cell.

use crate::closed_loop;
use softfinger_core::device::DeviceParams;
use softfinger_core::math::Fast;
use softfinger_core::params::ContactParams;
use softfinger_core::vec3::Vec3;

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

/// Bounded: every late window within one cell (a non-finite amplitude is not bounded).
pub fn bounded(envelope: &[f64], cell_m: f64) -> Option<bool> {
    late_max_m(envelope).map(|a| a.is_finite() && a <= cell_m)
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

    /// The verdict reads only the last ten windows, and is bounded at exactly one cell and not
    /// just above it.
    #[test]
    fn bounded_reads_the_last_second() {
        let mut env = vec![1.0; 5];
        env.extend([1e-6; LATE_WINDOWS]);
        assert_eq!(late_max_m(&env), Some(1e-6));
        assert_eq!(bounded(&env, 1e-6), Some(true));
        assert_eq!(bounded(&env, 0.999e-6), Some(false));
        env[5] = f64::NAN;
        assert_eq!(bounded(&env, 1.0), Some(false));
        assert_eq!(bounded(&[1e-6; LATE_WINDOWS - 1], 1.0), None);
    }
}
