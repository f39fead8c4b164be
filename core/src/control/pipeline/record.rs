//! The compact telemetry record the pipeline emits on decimated ticks (46 bytes of payload, a
//! fraction of the full [`crate::control::telemetry::TelemetryRecord`]), so a non-blocking log transport
//! can keep up and drop rather than wait.

use crate::contact::state::ContactState;
use crate::flags::Flags;
use crate::math::vec3::Vec3;

use super::mode::Mode;

/// One decimated tick. Fixed-point fields saturate at their range.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PipelineRecord {
    /// Tick index since start-up (wrapping).
    pub tick: u32,
    /// Operating mode.
    pub mode: Mode,
    /// Contact state.
    pub state: ContactState,
    /// Flags of the tick, latched faults included.
    pub flags: Flags,
    /// Homed motor counts (0 ↔ the device's zero-count arm angle; raw extended counts before
    /// homing).
    pub motor_counts: [i32; 3],
    /// Wrist counts from the calibration pose (wrapping to 16 bits: ±8 joint turns at 4096
    /// counts per turn).
    pub wrist_counts: [i16; 3],
    /// Rendered force, base frame, mN.
    pub force_mn: [i16; 3],
    /// Signed compare values written (sign = phase).
    pub compare: [i16; 3],
    /// This tick's start latency, timer counts (saturating).
    pub latency_counts: u16,
    /// The previous tick's write time, timer counts (saturating).
    pub write_counts: u16,
    /// Records dropped since the previous record that got through (saturating).
    pub dropped_before: u16,
}

/// `x` to a saturated i16 (NaN → 0).
#[inline]
pub fn sat_i16(x: f32) -> i16 {
    // Half away from zero first; then `as i32` saturates, rounds toward zero and takes NaN to 0
    // (one VCVT on the M4F, where `as i16` adds its own range and NaN checks), and the clamp
    // saturates to i16 (one SSAT).
    let rounded = (x + 0.5f32.copysign(x)) as i32;
    rounded.clamp(i32::from(i16::MIN), i32::from(i16::MAX)) as i16
}

/// `x` to a saturated u16.
#[inline]
pub fn sat_u16(x: u32) -> u16 {
    x.min(u32::from(u16::MAX)) as u16
}

/// Force vector to mN fields.
#[inline]
pub fn force_mn(f: Vec3) -> [i16; 3] {
    [
        sat_i16(f.x * 1000.0),
        sat_i16(f.y * 1000.0),
        sat_i16(f.z * 1000.0),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fixed_point_saturates_and_rounds() {
        assert_eq!(
            force_mn(Vec3::new(1.2344, -0.0005, 40.0)),
            [1234, -1, i16::MAX]
        );
        assert_eq!(force_mn(Vec3::new(f32::NAN, -40.0, 0.0)), [0, i16::MIN, 0]);
        // Just inside and just outside the i16 range, both signs; infinities saturate.
        assert_eq!(sat_i16(32_766.4), 32_766);
        assert_eq!(sat_i16(32_766.6), i16::MAX);
        assert_eq!(sat_i16(40_000.0), i16::MAX);
        assert_eq!(sat_i16(-32_767.4), -32_767);
        assert_eq!(sat_i16(-32_767.6), i16::MIN);
        assert_eq!(sat_i16(-32_769.0), i16::MIN);
        assert_eq!(sat_i16(f32::INFINITY), i16::MAX);
        assert_eq!(sat_i16(f32::NEG_INFINITY), i16::MIN);
        assert_eq!((sat_i16(0.49), sat_i16(-0.5), sat_i16(2.5)), (0, -1, 3));
        assert_eq!(sat_u16(70_000), u16::MAX);
        assert_eq!(sat_u16(65_535), 65_535);
        assert!(core::mem::size_of::<PipelineRecord>() <= 48);
    }
}
