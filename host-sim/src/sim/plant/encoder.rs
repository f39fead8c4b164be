//! Encoder quantisation: a joint angle to the extended 32-bit count the firmware would report.
//!
//! Motor encoders sit on the motor shafts, so one count is 2π/(counts per rev · capstan ratio)
//! of arm angle; wrist encoders sit on the joints. Counts are rounded to the nearest integer,
//! which is a floor-type quadrature counter whose edges sit half a count from the calibration
//! pose: the reading error is then within ±½ count and unbiased.

/// Extended count of `angle_rad` measured from the zero-count pose, with `rad_per_count` rad per
/// count. Saturates at the i32 range (which the linkage cannot reach: ±2³¹ counts is ±44 000
/// arm turns).
pub fn quantize(angle_from_zero_rad: f64, rad_per_count: f64) -> i32 {
    (angle_from_zero_rad / rad_per_count).round() as i32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rounds_to_the_nearest_count_symmetrically() {
        let step = 2.0 * std::f64::consts::PI / (4096.0 * 12.0);
        for k in [-5000i32, -1, 0, 1, 7, 12288] {
            let kf = k as f64;
            assert_eq!(quantize(kf * step, step), k);
            assert_eq!(quantize((kf + 0.49) * step, step), k);
            assert_eq!(quantize((kf - 0.49) * step, step), k);
            assert_eq!(quantize((kf + 0.51) * step, step), k + 1);
            assert_eq!(quantize((kf - 0.51) * step, step), k - 1);
        }
        assert_eq!(quantize(1e300, step), i32::MAX);
        assert_eq!(quantize(f64::NAN, step), 0);
    }
}
