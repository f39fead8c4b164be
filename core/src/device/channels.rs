//! The device's six encoder channels by name: three motors (the delta's arms, motor `i` at
//! azimuth 120°·i, see [`crate::device::delta`]) and three wrist joints (joint 0 next to the
//! effector platform, see [`crate::device::hardware`]). Every count array of the crate holds them
//! in one order, motors first: raw 16-bit readings (`[u16; 6]`) and extended positions
//! (`[i32; 6]`) at the boundary with the firmware and the plant; [`EncoderCounts`] names them
//! inside.

/// Number of encoder channels (motors, then wrist joints).
pub const CHANNELS: usize = 6;
/// Index of motor `i`'s channel in a count array is `MOTOR[i]`.
pub const MOTOR: [usize; 3] = [0, 1, 2];
/// Index of wrist joint `i`'s channel in a count array is `WRIST[i]`.
pub const WRIST: [usize; 3] = [3, 4, 5];

/// Six extended encoder positions by name, counts.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct EncoderCounts {
    /// Motor `i`'s position (the arm encoders), counts.
    pub motor: [i32; 3],
    /// Wrist joint `i`'s position, counts.
    pub wrist: [i32; 3],
}

impl From<[i32; CHANNELS]> for EncoderCounts {
    /// The channels of a count array in the crate's order (motors, then wrist joints).
    #[inline]
    fn from(c: [i32; CHANNELS]) -> Self {
        EncoderCounts {
            motor: MOTOR.map(|i| c[i]),
            wrist: WRIST.map(|i| c[i]),
        }
    }
}

impl From<EncoderCounts> for [i32; CHANNELS] {
    /// The count array in the crate's order (motors, then wrist joints).
    #[inline]
    fn from(c: EncoderCounts) -> Self {
        let mut a = [0; CHANNELS];
        for (k, i) in MOTOR.into_iter().enumerate() {
            a[i] = c.motor[k];
        }
        for (k, i) in WRIST.into_iter().enumerate() {
            a[i] = c.wrist[k];
        }
        a
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Motors first, then the wrist, and the array comes back unchanged.
    #[test]
    fn channels_are_named_in_array_order() {
        let a = [10, 11, 12, -3, -4, -5];
        let c = EncoderCounts::from(a);
        assert_eq!(c.motor, [10, 11, 12]);
        assert_eq!(c.wrist, [-3, -4, -5]);
        assert_eq!(<[i32; CHANNELS]>::from(c), a);
    }

    /// Every index appears once.
    #[test]
    fn the_indices_cover_every_channel_once() {
        let mut seen = [0u8; CHANNELS];
        for i in MOTOR.into_iter().chain(WRIST) {
            seen[i] += 1;
        }
        assert_eq!(seen, [1; CHANNELS]);
    }
}
