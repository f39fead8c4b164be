//! Names of the flag bits in a state sample (`softfinger_core::Flags`).

use softfinger_core::Flags;

/// Every named flag, in bit order.
pub const NAMES: [(Flags, &str); 20] = [
    (Flags::NON_FINITE_INPUT, "non-finite-input"),
    (Flags::ZERO_AXIS, "zero-axis"),
    (Flags::NON_UNIT_QUAT, "non-unit-quat"),
    (Flags::SINGULAR, "singular"),
    (Flags::GIMBAL_LOCK, "gimbal-lock"),
    (Flags::OUT_OF_RANGE, "out-of-range"),
    (Flags::SPIN_SATURATED, "spin-saturated"),
    (Flags::KINEMATICS_SINGULAR, "kinematics-singular"),
    (Flags::ENCODER_GLITCH, "encoder-glitch"),
    (Flags::OUTPUT_LIMITED, "output-limited"),
    (Flags::DRIVER_FAULT, "driver-fault"),
    (Flags::OVERRUN, "overrun"),
    (Flags::NON_FINITE_OUTPUT, "non-finite-output"),
    (Flags::ENCODER_STUCK, "encoder-stuck"),
    (Flags::PARAM_REJECTED, "param-rejected"),
    (Flags::HOMING_FAILED, "homing-failed"),
    (Flags::THREAD_STALLED, "thread-stalled"),
    (Flags::COMM_TIMEOUT, "comm-timeout"),
    (Flags::MODEL_STALE, "model-stale"),
    (Flags::MODEL_REJECTED, "model-rejected"),
];

/// The names of the raised bits, joined by `|`; unnamed bits as `bitN`; empty for none.
pub fn describe(bits: u32) -> String {
    let mut parts: Vec<String> = NAMES
        .iter()
        .filter(|(f, _)| bits & f.0 != 0)
        .map(|(_, n)| n.to_string())
        .collect();
    let named = NAMES.iter().fold(0, |acc, (f, _)| acc | f.0);
    for b in 0..32 {
        if bits & !named & (1 << b) != 0 {
            parts.push(format!("bit{b}"));
        }
    }
    parts.join("|")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_and_unknown_bits() {
        assert_eq!(describe(0), "");
        assert_eq!(
            describe((Flags::COMM_TIMEOUT | Flags::ZERO_AXIS).0),
            "zero-axis|comm-timeout"
        );
        assert_eq!(describe(1 << 31), "bit31");
    }
}
