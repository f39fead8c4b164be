//! The PWM output stage: duty quantisation to the timer resolution, and the one-tick output
//! delay.
//!
//! Duties are quantised exactly as the firmware writes them, through
//! `DeviceParams::duty_to_pwm_counts` (round(|duty|·period), sign = direction), and the plant
//! applies counts/period.
//!
//! **The one-tick delay lives here.** In a closed loop the host runs, per tick k:
//! `counts = plant.counts()` (sampled at t_k) → `duties = controller.tick(counts)` →
//! `plant.step(duties, dt)`. `step` pushes the new command into [`OutputLatch`] and integrates
//! [t_k, t_k+1) with the command the latch held, the one computed at tick k−1: a command
//! computed from the counts of tick k acts during tick k+1, as on the MCU where the compare
//! registers are written at the end of a tick's computation and take effect on the next period.

use softfinger_core::device::DeviceParams;

/// One motor command as the drive sees it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DriveCommand {
    /// Averaged duties after quantisation, in [-1, 1].
    pub duties: [f64; 3],
    /// H-bridge enable (false: outputs off, windings open).
    pub enable: bool,
}

impl DriveCommand {
    /// Bridge enabled, zero duty (the state at power-up of the plant).
    pub const IDLE: DriveCommand = DriveCommand {
        duties: [0.0; 3],
        enable: true,
    };

    /// Quantise controller duties to the PWM timer, as the firmware does.
    pub fn quantized(device: &DeviceParams, duties: [f32; 3], enable: bool) -> DriveCommand {
        let period = device.pwm_period_counts as f64;
        DriveCommand {
            duties: duties.map(|d| device.duty_to_pwm_counts(d) as f64 / period),
            enable,
        }
    }
}

/// Holds the command computed at tick k until it is applied during tick k+1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OutputLatch {
    pending: DriveCommand,
}

impl Default for OutputLatch {
    fn default() -> Self {
        OutputLatch::new()
    }
}

impl OutputLatch {
    pub fn new() -> OutputLatch {
        OutputLatch {
            pending: DriveCommand::IDLE,
        }
    }

    /// Store the new command and return the one to apply during this tick (the previous one).
    pub fn shift(&mut self, new: DriveCommand) -> DriveCommand {
        std::mem::replace(&mut self.pending, new)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn duties_are_quantised_to_the_timer_and_delayed_by_one_tick() {
        let d = DeviceParams::OMEGA_LIKE;
        // 8500 counts per period: 0.1 + 0.4 count rounds down to 850/8500 exactly,
        // -0.3 - 0.6 count rounds to -2551/8500, 2.0 saturates.
        let cmd = DriveCommand::quantized(&d, [0.1 + 0.4 / 8500.0, -0.3 - 0.6 / 8500.0, 2.0], true);
        assert_eq!(cmd.duties, [850.0 / 8500.0, -2551.0 / 8500.0, 1.0]);
        let mut latch = OutputLatch::new();
        assert_eq!(latch.shift(cmd), DriveCommand::IDLE);
        let next = DriveCommand::quantized(&d, [0.0; 3], false);
        assert_eq!(latch.shift(next), cmd);
        assert_eq!(latch.shift(DriveCommand::IDLE), next);
    }
}
