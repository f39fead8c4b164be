//! Names and meanings of the flag bits a device reports (`softfinger_core::Flags`, in
//! [`crate::StateSample::flags`] and [`crate::DeviceStatus`]), for logs and user interfaces.

use softfinger_core::Flags;

/// Every named flag in bit order: the bit, its short name, what it means for the user.
pub const FLAGS: [(Flags, &str, &str); 20] = [
    (
        Flags::NON_FINITE_INPUT,
        "non-finite-input",
        "an input was NaN or infinite: safe output",
    ),
    (
        Flags::ZERO_AXIS,
        "zero-axis",
        "a rotation axis was too short to normalise",
    ),
    (
        Flags::NON_UNIT_QUAT,
        "non-unit-quat",
        "an orientation was renormalised",
    ),
    (
        Flags::SINGULAR,
        "singular",
        "the paper's decomposition is singular: zero output",
    ),
    (
        Flags::GIMBAL_LOCK,
        "gimbal-lock",
        "roll-pitch-yaw at its pole",
    ),
    (
        Flags::OUT_OF_RANGE,
        "out-of-range",
        "a value out of range: safe default used",
    ),
    (
        Flags::SPIN_SATURATED,
        "spin-saturated",
        "spin torque at the friction limit (slips)",
    ),
    (
        Flags::KINEMATICS_SINGULAR,
        "kinematics-singular",
        "arm pose singular or unreachable",
    ),
    (
        Flags::ENCODER_GLITCH,
        "encoder-glitch",
        "an encoder jumped impossibly far",
    ),
    (
        Flags::OUTPUT_LIMITED,
        "output-limited",
        "force, torque or duty was limited",
    ),
    (
        Flags::DRIVER_FAULT,
        "driver-fault",
        "the motor driver reported a fault",
    ),
    (
        Flags::OVERRUN,
        "overrun",
        "control ticks overran their period",
    ),
    (
        Flags::NON_FINITE_OUTPUT,
        "non-finite-output",
        "an output was non-finite: zeroed",
    ),
    (
        Flags::ENCODER_STUCK,
        "encoder-stuck",
        "an encoder did not move under drive",
    ),
    (
        Flags::PARAM_REJECTED,
        "param-rejected",
        "parameters refused: the old ones stay",
    ),
    (
        Flags::HOMING_FAILED,
        "homing-failed",
        "homing timed out, stalled early or measured a wrong range",
    ),
    (
        Flags::THREAD_STALLED,
        "thread-stalled",
        "thread-mode tasks stopped: outputs off, then a reset",
    ),
    (
        Flags::COMM_TIMEOUT,
        "comm-timeout",
        "no message in the watchdog time: force 0 until armed",
    ),
    (
        Flags::MODEL_STALE,
        "model-stale",
        "the local model is older than its maximum age: force fades",
    ),
    (
        Flags::MODEL_REJECTED,
        "model-rejected",
        "a local model was refused: the old one stays",
    ),
];

/// Flags that hold the rendered force at zero (or fading to it) while the mode stays armed.
pub const HOLD_FORCE_DOWN: Flags = Flags(Flags::COMM_TIMEOUT.0 | Flags::MODEL_STALE.0);

/// The name and meaning of each named flag raised in `bits`, in bit order (unnamed bits are
/// skipped; [`unnamed`] has them).
pub fn raised(bits: u32) -> impl Iterator<Item = (&'static str, &'static str)> {
    FLAGS
        .iter()
        .filter(move |(f, _, _)| bits & f.0 != 0)
        .map(|(_, n, m)| (*n, *m))
}

/// The raised bits of `bits` that have no name.
pub fn unnamed(bits: u32) -> u32 {
    bits & !FLAGS.iter().fold(0, |acc, (f, _, _)| acc | f.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_in_bit_order_and_unnamed_bits() {
        let got: std::vec::Vec<_> = raised((Flags::COMM_TIMEOUT | Flags::ZERO_AXIS).0)
            .map(|(n, _)| n)
            .collect();
        assert_eq!(got, ["zero-axis", "comm-timeout"]);
        assert_eq!(unnamed(1 << 31 | Flags::COMM_TIMEOUT.0), 1 << 31);
        for w in FLAGS.windows(2) {
            assert!(w[0].0 .0 < w[1].0 .0, "bit order");
        }
        // Every meaning fits beside its name on an 80-column line.
        for (_, n, m) in FLAGS {
            assert!(n.len() + m.len() + 4 <= 80, "{n}");
        }
    }
}
