//! A gain in [0, 1] that moves towards its target by a fixed step per tick: every fade and blend
//! of the local model. Moving linearly, it reaches any target within `ceil(duration / dt)` ticks,
//! and changes by at most `dt / duration` per tick.

/// A linear ramp between 0 and 1.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Ramp {
    value: f32,
    step: f32,
}

impl Ramp {
    /// A ramp at `value` (clamped to [0, 1]) taking `duration_s` for a full 0 → 1 swing at
    /// `rate_hz` ticks per second. A duration shorter than one tick (or not finite and positive)
    /// jumps in one tick.
    pub fn new(value: f32, duration_s: f32, rate_hz: f32) -> Ramp {
        let ticks = duration_s * rate_hz;
        let step = if ticks.is_finite() && ticks > 1.0 {
            1.0 / ticks
        } else {
            1.0
        };
        Ramp {
            value: clamp01(value),
            step,
        }
    }

    /// The gain now.
    #[inline]
    pub fn value(&self) -> f32 {
        self.value
    }

    /// The largest change per tick.
    #[inline]
    pub fn step_size(&self) -> f32 {
        self.step
    }

    /// Move one tick towards `target` (clamped to [0, 1]); returns the new gain.
    #[inline]
    pub fn advance(&mut self, target: f32) -> f32 {
        let t = clamp01(target);
        let d = t - self.value;
        // Within a step (plus the rounding of the steps summed so far): arrive exactly.
        self.value = if d.abs() <= self.step * 1.001 {
            t
        } else if d > 0.0 {
            self.value + self.step
        } else {
            self.value - self.step
        };
        self.value
    }

    /// Jump to `value` (clamped to [0, 1]).
    #[inline]
    pub fn set(&mut self, value: f32) {
        self.value = clamp01(value);
    }
}

/// `v` clamped to [0, 1]; NaN gives 0.
#[inline]
fn clamp01(v: f32) -> f32 {
    if v >= 1.0 {
        1.0
    } else if v > 0.0 {
        v
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 10 ms at 10 kHz: 100 ticks from 1 to 0, never more than 0.01 a tick; at 99 ticks not
    /// yet there, at 100 there.
    #[test]
    fn reaches_its_target_in_duration_over_dt_ticks() {
        let mut r = Ramp::new(1.0, 0.010, 10_000.0);
        let mut prev = r.value();
        for k in 1..=100 {
            let v = r.advance(0.0);
            assert!((prev - v) <= 0.01 + 1e-6, "tick {k}: step {}", prev - v);
            prev = v;
            if k == 99 {
                assert!(v > 0.0, "not there at 99 ticks: {v}");
            }
        }
        assert_eq!(r.value(), 0.0);
        assert_eq!(r.advance(0.0), 0.0);
    }

    #[test]
    fn bad_durations_and_targets_are_safe() {
        let mut r = Ramp::new(f32::NAN, f32::NAN, 10_000.0);
        assert_eq!(r.value(), 0.0);
        assert_eq!(r.advance(f32::NAN), 0.0);
        assert_eq!(
            r.advance(5.0),
            1.0,
            "a non-positive duration jumps in one tick"
        );
        let mut r = Ramp::new(0.5, 0.0, 10_000.0);
        assert_eq!(r.advance(-3.0), 0.0);
    }
}
