//! Driver power for DRV887x-class bridges: sleep only on faults (and at power-up), and the nFAULT
//! line masked while the driver sleeps and during its wake-up time.
//!
//! Such drivers assert nFAULT during sleep and while waking (under-voltage lockout of the charge
//! pump until it is up), so reading the line then would latch a fault that is not one. Zero
//! torque in normal operation goes through PWM/EN; sleeping is reserved for faults, because
//! sleeping also clears the driver's own fault latch and a wake costs the wake time.

/// Sleep/wake state and the nFAULT mask.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct DriverPower {
    awake: bool,
    wake_ticks: u32,
    waking_left: u32,
}

impl DriverPower {
    /// Asleep (power-up). Waking takes `wake_ticks` ticks during which nFAULT is ignored and the
    /// bridges stay disabled.
    pub const fn new(wake_ticks: u32) -> Self {
        DriverPower {
            awake: false,
            wake_ticks,
            waking_left: 0,
        }
    }

    /// Start waking (no-op when already awake or waking).
    pub fn wake(&mut self) {
        if !self.awake {
            self.awake = true;
            self.waking_left = self.wake_ticks;
        }
    }

    /// Go to sleep at once.
    pub fn sleep(&mut self) {
        self.awake = false;
        self.waking_left = 0;
    }

    /// nSLEEP level to write (true: awake or waking).
    pub const fn awake(&self) -> bool {
        self.awake
    }

    /// Awake and past the wake time: the bridges may be enabled and nFAULT is meaningful.
    pub const fn ready(&self) -> bool {
        self.awake && self.waking_left == 0
    }

    /// Advance one tick with the nFAULT level as read (`true`: asserted). Returns whether it counts
    /// as a driver fault: only when the driver was already ready at the start of this tick.
    pub fn tick(&mut self, fault_line: bool) -> bool {
        let counts = self.ready() && fault_line;
        if self.awake && self.waking_left > 0 {
            self.waking_left -= 1;
        }
        counts
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fault_line_is_ignored_asleep_and_for_exactly_the_wake_time() {
        let mut d = DriverPower::new(3);
        for _ in 0..10 {
            assert!(!d.tick(true), "asleep: masked");
        }
        d.wake();
        assert!(d.awake() && !d.ready());
        // Ticks 1..=3 after the wake: masked.
        for k in 0..3 {
            assert!(!d.ready(), "tick {k}");
            assert!(!d.tick(true), "tick {k}");
        }
        // Tick 4: ready, and the line counts.
        assert!(d.ready());
        assert!(d.tick(true));
        assert!(!d.tick(false));
        d.sleep();
        assert!(!d.awake() && !d.tick(true));
    }

    #[test]
    fn zero_wake_time_is_ready_at_once() {
        let mut d = DriverPower::new(0);
        d.wake();
        assert!(d.ready());
        assert!(d.tick(true));
    }

    #[test]
    fn wake_while_awake_does_not_restart_the_mask() {
        let mut d = DriverPower::new(2);
        d.wake();
        let _ = d.tick(false);
        let _ = d.tick(false);
        assert!(d.ready());
        d.wake();
        assert!(d.ready());
    }
}
