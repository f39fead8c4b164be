//! Driver power for DRV887x-class bridges: sleep only on faults (and at power-up), and the nFAULT
//! line masked while the driver sleeps and during its wake-up time.
//!
//! Such drivers assert nFAULT during sleep and while waking (under-voltage lockout of the charge
//! pump until it is up), so reading the line then would latch a fault that is not one. Zero
//! torque in normal operation goes through PWM/EN; sleeping is reserved for faults, because
//! sleeping also clears the driver's own fault latch and a wake costs the wake time.
//!
//! The wake time counts from the nSLEEP edge: a wake requested between ticks reaches the pin
//! with the next tick's writes, so that tick does not count (the DRV8876's t_WAKE is 1 ms; the
//! device definitions ask 2 ms, the margin the bring-up review asked for).

/// Sleep/wake state and the nFAULT mask.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct DriverPower {
    awake: bool,
    wake_ticks: u32,
    waking_left: u32,
    /// A wake was requested and nSLEEP has not been written high yet.
    edge_pending: bool,
}

impl DriverPower {
    /// Asleep (power-up). Waking takes `wake_ticks` ticks during which nFAULT is ignored and the
    /// bridges stay disabled.
    pub const fn new(wake_ticks: u32) -> Self {
        DriverPower {
            awake: false,
            wake_ticks,
            waking_left: 0,
            edge_pending: false,
        }
    }

    /// Start waking (no-op when already awake or waking).
    pub fn wake(&mut self) {
        if !self.awake {
            self.awake = true;
            self.waking_left = self.wake_ticks;
            self.edge_pending = self.wake_ticks > 0;
        }
    }

    /// Go to sleep at once.
    pub fn sleep(&mut self) {
        self.awake = false;
        self.waking_left = 0;
        self.edge_pending = false;
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
    /// as a driver fault: only when the driver was already ready at the start of this tick. The
    /// tick that first writes nSLEEP high (the edge) does not count towards the wake time.
    pub fn tick(&mut self, fault_line: bool) -> bool {
        let counts = self.ready() && fault_line;
        if self.edge_pending {
            self.edge_pending = false;
        } else if self.awake && self.waking_left > 0 {
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
        // The edge tick (nSLEEP written high) and the 3 ticks after it: masked.
        for k in 0..4 {
            assert!(!d.ready(), "tick {k}");
            assert!(!d.tick(true), "tick {k}");
        }
        // Tick 5: ready (3 full periods after the edge), and the line counts.
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
        assert!(!d.ready(), "the edge tick does not count");
        let _ = d.tick(false);
        assert!(d.ready());
        d.wake();
        assert!(d.ready());
    }
}
