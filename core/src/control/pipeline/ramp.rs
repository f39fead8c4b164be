//! The arming ramp: after `Arm` the rendered force is scaled by a gain rising linearly from 0 to 1
//! over the configured time, so arming while pressing a surface gives no force step.

/// Linear 0 → 1 gain over a number of ticks.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ArmRamp {
    ticks: u32,
    done: u32,
}

impl ArmRamp {
    /// A ramp over `ticks` ticks (0: no ramp, full gain at once), starting at gain 0.
    pub const fn new(ticks: u32) -> Self {
        ArmRamp { ticks, done: 0 }
    }

    /// Start again from gain 0.
    pub fn restart(&mut self) {
        self.done = 0;
    }

    /// Advance one tick and return the gain to apply this tick, in (0, 1]: `k / ticks` on the
    /// k-th tick after a restart (k = 1, 2, …), 1 from then on.
    pub fn next_gain(&mut self) -> f32 {
        if self.done < self.ticks {
            self.done += 1;
            self.done as f32 / self.ticks as f32
        } else {
            1.0
        }
    }

    /// True once the gain has reached 1.
    pub const fn complete(&self) -> bool {
        self.done >= self.ticks
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rises_linearly_then_stays_at_one() {
        let mut r = ArmRamp::new(4);
        let g: [f32; 6] = core::array::from_fn(|_| r.next_gain());
        assert_eq!(g, [0.25, 0.5, 0.75, 1.0, 1.0, 1.0]);
        assert!(r.complete());
        r.restart();
        assert!(!r.complete());
        assert_eq!(r.next_gain(), 0.25);
    }

    #[test]
    fn zero_ticks_is_full_gain_at_once() {
        let mut r = ArmRamp::new(0);
        assert!(r.complete());
        assert_eq!(r.next_gain(), 1.0);
    }

    #[test]
    fn largest_step_is_one_over_ticks() {
        let mut r = ArmRamp::new(5000);
        let mut prev = 0.0f32;
        for _ in 0..6000 {
            let g = r.next_gain();
            assert!(g - prev <= 1.0 / 5000.0 + 1e-6 && g >= prev);
            prev = g;
        }
    }
}
