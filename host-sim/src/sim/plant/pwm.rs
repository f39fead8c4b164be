//! The PWM output stage, two ways in:
//!
//! - **bridge commands** ([`BridgeStage`]), as the control pipeline writes them to the firmware's
//!   timer and pins: the phase pins and the enable act when written, a compare value is preloaded
//!   and acts from the next PWM period boundary (the board timing is the core's
//!   [`BoardTiming`](softfinger_core::control::pipeline::BoardTiming), the same the firmware uses). This is
//!   the path of every closed loop of the simulator;
//! - plain duties (the plant's own unit tests), through the one-tick latch below.
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

use softfinger_core::control::pipeline::BridgeCommands;
use softfinger_core::device::DeviceParams;

// The plant's duty path quantises with the device's PWM period: it must be the board's.
const _: () = assert!(
    softfinger_core::device::DeviceParams::OMEGA_LIKE.pwm_period_counts
        == softfinger_core::control::pipeline::BoardTiming::STM32G474_10KHZ.pwm_period_counts()
);

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

/// The bridges' state as the hardware holds it between writes.
///
/// Per tick the host writes the pipeline's commands at the tick's start (the earliest a firmware
/// could, which makes the window between a phase change and the next compare load the longest:
/// the worst case for wrong-direction drive), then [`BridgeStage::load`] runs at the first PWM
/// period boundary of the tick.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BridgeStage {
    phase: [bool; 3],
    active: [u16; 3],
    active_phase: [bool; 3],
    pending: [u16; 3],
    pending_phase: [bool; 3],
    enable: bool,
    awake: bool,
    /// Time each bridge drove a non-zero compare with the phase pin opposite to the phase the
    /// compare was written with (wrong-direction drive), s.
    pub wrong_direction_s: [f64; 3],
    /// Phase pin changes while the bridge was enabled.
    pub reversals: u64,
}

impl BridgeStage {
    /// Write one tick's commands: phase, enable and sleep now, compares pending.
    pub fn write(&mut self, b: &BridgeCommands) {
        for i in 0..3 {
            if self.phase[i] != b.phase_forward[i] && self.enable && b.pwm_enable {
                self.reversals += 1;
            }
        }
        self.phase = b.phase_forward;
        self.pending = b.compare;
        self.pending_phase = b.phase_forward;
        self.enable = b.pwm_enable;
        self.awake = b.driver_awake;
    }

    /// A PWM period boundary: the pending compares take effect.
    pub fn load(&mut self) {
        self.active = self.pending;
        self.active_phase = self.pending_phase;
    }

    /// What the bridges drive now (averaged over a PWM period), for a `full_scale` compare.
    pub fn applied(&self, full_scale: u16) -> DriveCommand {
        let on = self.enable && self.awake;
        let fs = f64::from(full_scale.max(1));
        DriveCommand {
            duties: std::array::from_fn(|i| {
                let m = if on {
                    f64::from(self.active[i]) / fs
                } else {
                    0.0
                };
                if self.phase[i] {
                    m
                } else {
                    -m
                }
            }),
            enable: on,
        }
    }

    /// Account `h` seconds of drive in the current state.
    pub fn note(&mut self, h: f64) {
        if !(self.enable && self.awake) {
            return;
        }
        for i in 0..3 {
            if self.active[i] > 0 && self.phase[i] != self.active_phase[i] {
                self.wrong_direction_s[i] += h;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cmd(phase: bool, compare: u16) -> BridgeCommands {
        BridgeCommands {
            phase_forward: [phase, true, true],
            compare: [compare, 0, 0],
            pwm_enable: true,
            driver_awake: true,
        }
    }

    #[test]
    fn compare_waits_for_the_boundary_phase_does_not() {
        let mut b = BridgeStage::default();
        b.write(&cmd(true, 4250));
        assert_eq!(b.applied(8500).duties[0], 0.0, "preloaded: not yet");
        b.load();
        assert_eq!(b.applied(8500).duties[0], 0.5);
        // Flipping the phase with a new compare: the old magnitude drives the new direction until
        // the boundary. That is wrong-direction drive, and it is measured.
        b.write(&cmd(false, 850));
        assert_eq!(b.applied(8500).duties[0], -0.5);
        b.note(25e-6);
        assert_eq!(b.wrong_direction_s[0], 25e-6);
        assert_eq!(b.reversals, 1);
        b.load();
        assert_eq!(b.applied(8500).duties[0], -0.1);
        b.note(25e-6);
        assert_eq!(
            b.wrong_direction_s[0], 25e-6,
            "correct direction after the load"
        );
    }

    #[test]
    fn zero_compare_then_flip_never_drives_the_wrong_way() {
        let mut b = BridgeStage::default();
        b.write(&cmd(true, 4250));
        b.load();
        b.write(&cmd(true, 0));
        b.note(1e-5);
        b.load();
        b.write(&cmd(false, 850));
        b.note(1e-5);
        b.load();
        b.note(1e-5);
        assert_eq!(b.wrong_direction_s, [0.0; 3]);
        assert_eq!(b.reversals, 1);
    }

    #[test]
    fn disabled_or_asleep_drives_nothing() {
        let mut b = BridgeStage::default();
        b.write(&BridgeCommands {
            pwm_enable: false,
            ..cmd(true, 4250)
        });
        b.load();
        assert_eq!(b.applied(8500).duties, [0.0; 3]);
        assert!(!b.applied(8500).enable);
        b.write(&BridgeCommands {
            driver_awake: false,
            ..cmd(true, 4250)
        });
        b.load();
        assert!(!b.applied(8500).enable);
    }

    #[test]
    fn duties_are_quantised_to_the_timer_and_delayed_by_one_tick() {
        let d = DeviceParams::OMEGA_LIKE;
        // 4250 counts per period (40 kHz): 0.1 + 0.4 count rounds down to 425/4250 exactly,
        // -0.3 - 0.6 count rounds to -1276/4250, 2.0 saturates.
        assert_eq!(d.pwm_period_counts, 4250);
        let cmd = DriveCommand::quantized(&d, [0.1 + 0.4 / 4250.0, -0.3 - 0.6 / 4250.0, 2.0], true);
        assert_eq!(cmd.duties, [425.0 / 4250.0, -1276.0 / 4250.0, 1.0]);
        let mut latch = OutputLatch::new();
        assert_eq!(latch.shift(cmd), DriveCommand::IDLE);
        let next = DriveCommand::quantized(&d, [0.0; 3], false);
        assert_eq!(latch.shift(next), cmd);
        assert_eq!(latch.shift(DriveCommand::IDLE), next);
    }
}
