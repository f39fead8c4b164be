//! Fault and status flags shared by every stage of the pipeline.
//!
//! Nothing in the core panics or returns NaN. When an input is bad (NaN, ±inf, a zero axis, a
//! non-unit quaternion, a singular decomposition, ...), the stage returns a defined safe value and
//! raises one of these flags so the caller can see what happened.

/// A small bit set of status flags. `Flags::NONE` means everything was nominal.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Flags(pub u32);

impl Flags {
    /// No flag raised.
    pub const NONE: Flags = Flags(0);
    /// An input contained NaN or ±inf; the output is the stage's safe default.
    pub const NON_FINITE_INPUT: Flags = Flags(1 << 0);
    /// A rotation axis or vector direction was zero (or too short to normalise).
    pub const ZERO_AXIS: Flags = Flags(1 << 1);
    /// A quaternion's norm was off unity by more than the tolerance; it was normalised.
    pub const NON_UNIT_QUAT: Flags = Flags(1 << 2);
    /// The paper-verbatim decomposition hit its singularity (sin δθ ≈ 0); outputs are zero.
    pub const SINGULAR: Flags = Flags(1 << 3);
    /// The roll-pitch-yaw decomposition is at or near its pole (|δθ| ≈ π/2).
    pub const GIMBAL_LOCK: Flags = Flags(1 << 4);
    /// A quantity was outside its valid range and the safe default was used.
    pub const OUT_OF_RANGE: Flags = Flags(1 << 5);
    /// The spin spring hit the torsional friction limit (it slips).
    pub const SPIN_SATURATED: Flags = Flags(1 << 6);
    /// The delta mechanism's kinematics are singular or unreachable here.
    pub const KINEMATICS_SINGULAR: Flags = Flags(1 << 7);
    /// An encoder jumped further in one tick than is physically possible.
    pub const ENCODER_GLITCH: Flags = Flags(1 << 8);
    /// An output had to be limited (force, torque or duty saturation).
    pub const OUTPUT_LIMITED: Flags = Flags(1 << 9);
    /// The motor driver reported a fault.
    pub const DRIVER_FAULT: Flags = Flags(1 << 10);
    /// Control ticks overran their period too many times in a row.
    pub const OVERRUN: Flags = Flags(1 << 11);
    /// A controller output was non-finite before limiting (replaced by zero).
    pub const NON_FINITE_OUTPUT: Flags = Flags(1 << 12);
    /// A motor encoder did not move while its motor was driven hard.
    pub const ENCODER_STUCK: Flags = Flags(1 << 13);
    /// A parameter update was rejected; the previous parameters stay in force.
    pub const PARAM_REJECTED: Flags = Flags(1 << 14);
    /// Homing failed (timeout, an arm stalled before travelling far enough, or the measured
    /// stop-to-stop range is not the mechanism's).
    pub const HOMING_FAILED: Flags = Flags(1 << 15);
    /// The thread-mode tasks stopped running (no heartbeat): outputs off, then the independent
    /// watchdog resets the MCU (`control::pipeline::liveness`).
    pub const THREAD_STALLED: Flags = Flags(1 << 16);

    /// True when no flag is raised.
    #[inline]
    pub const fn is_empty(self) -> bool {
        self.0 == 0
    }
    /// True when every flag in `other` is raised in `self`.
    #[inline]
    pub const fn contains(self, other: Flags) -> bool {
        self.0 & other.0 == other.0
    }
    /// True when any flag in `other` is raised in `self`.
    #[inline]
    pub const fn intersects(self, other: Flags) -> bool {
        self.0 & other.0 != 0
    }
    /// Raise the flags in `other`.
    #[inline]
    pub fn insert(&mut self, other: Flags) {
        self.0 |= other.0;
    }
}

impl core::ops::BitOr for Flags {
    type Output = Flags;
    #[inline]
    fn bitor(self, rhs: Flags) -> Flags {
        Flags(self.0 | rhs.0)
    }
}

impl core::ops::BitOrAssign for Flags {
    #[inline]
    fn bitor_assign(&mut self, rhs: Flags) {
        self.0 |= rhs.0;
    }
}

/// True when every value is finite (not NaN, not ±inf).
///
/// Branch-free: x·0 is ±0 for every finite x and NaN for NaN and ±inf, and a sum of signed zeros
/// is a zero, so Σ xᵢ·0 == 0 exactly when all xᵢ are finite. One multiply-add per value instead
/// of a bit test and a branch each (this runs on every input of every control tick).
#[inline]
pub fn all_finite(values: &[f32]) -> bool {
    values.iter().fold(0.0f32, |acc, v| acc + v * 0.0) == 0.0
}

impl core::ops::BitAnd for Flags {
    type Output = Flags;
    #[inline]
    fn bitand(self, rhs: Flags) -> Flags {
        Flags(self.0 & rhs.0)
    }
}

impl core::ops::Not for Flags {
    type Output = Flags;
    #[inline]
    fn not(self) -> Flags {
        Flags(!self.0)
    }
}

/// Flags of the host link and the local model (`crate::control::local_model`). High bits, apart from the
/// pipeline's, so the two sets grow without colliding.
impl Flags {
    /// The communication watchdog expired: the force faded to zero and stays there until re-armed.
    pub const COMM_TIMEOUT: Flags = Flags(1 << 24);
    /// The local model is older than its declared maximum age: its force fades to zero.
    pub const MODEL_STALE: Flags = Flags(1 << 25);
    /// A local model update was rejected; the model in force stays.
    pub const MODEL_REJECTED: Flags = Flags(1 << 26);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn all_finite_agrees_with_is_finite_on_every_class() {
        let classes = [
            0.0f32,
            -0.0,
            1.0,
            -1.0,
            f32::MIN_POSITIVE,
            1e-45,
            -1e-45,
            f32::MAX,
            f32::MIN,
            f32::NAN,
            -f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
        ];
        for &a in &classes {
            for &b in &classes {
                for &c in &classes {
                    let want = a.is_finite() && b.is_finite() && c.is_finite();
                    assert_eq!(all_finite(&[a, b, c]), want, "{a} {b} {c}");
                }
            }
        }
        assert!(all_finite(&[]));
    }
}
