//! The firmware's output timing in the plant: a command computed from the counts sampled at the
//! start of a tick takes effect a fraction of a tick later, not a whole tick.
//!
//! Timeline of one tick of `dt` seconds from the encoder sample (the plant's tick boundary is
//! the sample instant; the sample's offset from the timer event is the same every tick, so only
//! the sample-to-output delay matters, see `softfinger_core::control::pipeline::output_timing`):
//!
//! ```text
//! [0, d·dt)      the previous tick's command still acts (its compare is in the PWM registers)
//! [d·dt, dt)     the command computed from this tick's sample acts
//! ```
//!
//! `d = 1` is [`Plant::step_with_enable`] (the new command acts only during the next tick).
//! The enable pin is delayed with the duties (one drive command).

use super::pwm::DriveCommand;
use super::Plant;

impl Plant {
    /// Advance one tick of `dt_tick_s` seconds in which the command computed now takes effect
    /// `delay_ticks · dt_tick_s` after the tick's start (`delay_ticks` clamped to [0, 1]; NaN is
    /// taken as 1, the latest). Each piece is integrated with at least one sub-step and sub-steps
    /// no longer than the plant's `dt / substeps`.
    ///
    /// # Panics
    /// If `dt_tick_s` is not finite and positive (a bug in the caller, not a plant state).
    pub fn step_with_output_delay(
        &mut self,
        duties: [f32; 3],
        enable: bool,
        dt_tick_s: f64,
        delay_ticks: f64,
    ) {
        assert!(
            dt_tick_s.is_finite() && dt_tick_s > 0.0,
            "tick period must be finite and positive, got {dt_tick_s}"
        );
        let d = if delay_ticks.is_nan() {
            1.0
        } else {
            delay_ticks.clamp(0.0, 1.0)
        };
        self.non_finite_duties += duties.iter().filter(|d| !d.is_finite()).count() as u64;
        let command = DriveCommand::quantized(&self.device, duties, enable);
        let previous = self.latch.shift(command);
        let t0 = self.time_s;
        let n = f64::from(self.params.substeps);
        let mut t = t0;
        for (cmd, length) in [(previous, d * dt_tick_s), (command, (1.0 - d) * dt_tick_s)] {
            if length <= 0.0 {
                continue;
            }
            self.applied = cmd;
            let pieces = (length / dt_tick_s * n).ceil().max(1.0) as u32;
            let h = length / f64::from(pieces);
            for k in 0..pieces {
                self.time_s = t + f64::from(k) * h;
                self.substep(h);
            }
            t += length;
        }
        self.time_s = t0 + dt_tick_s;
        self.refresh_hand();
    }
}

#[cfg(test)]
mod tests {
    use crate::sim::plant::{HandScript, Plant, PlantParams};
    use softfinger_core::device::DeviceParams;

    fn plant() -> Plant {
        Plant::new(
            DeviceParams::OMEGA_LIKE,
            PlantParams::OMEGA_LIKE,
            HandScript::hold([0.0, 0.0, -0.165]),
        )
        .unwrap()
    }

    /// A delay of one tick is exactly the latched step; a delay of 0 applies the new duty at
    /// once (its current starts rising within the tick), and a fraction lies in between.
    #[test]
    fn delay_bounds_match_the_latch_and_the_immediate_output() {
        let dt = 1e-4;
        let duty = [0.2, -0.1, 0.05];
        let (mut a, mut b) = (plant(), plant());
        for _ in 0..3 {
            a.step_with_enable(duty, true, dt);
            b.step_with_output_delay(duty, true, dt, 1.0);
        }
        assert_eq!(a.truth(), b.truth());
        let current = |d: f64| {
            let mut p = plant();
            p.step_with_output_delay(duty, true, dt, d);
            p.truth().motor_currents_a[0]
        };
        // Against the latched case (the arms sag under gravity, so its current is the small
        // back-EMF current of that motion, the same in every case to first order).
        let i1 = current(1.0);
        let (i0, i25) = (current(0.0) - i1, current(0.25) - i1);
        // RL rise over 100 µs vs 75 µs with τ = L/R = 110 µs: 1 − e^(−0.91) = 0.60 vs
        // 1 − e^(−0.68) = 0.49 of the steady current. Measured 0.82780, 3.3e-5 off that closed
        // form (0.82777); bound 3×.
        let tau = PlantParams::OMEGA_LIKE.motor_inductance_h / 2.18;
        let ratio = (1.0 - (-75e-6 / tau).exp()) / (1.0 - (-100e-6 / tau).exp());
        assert!(i0 > i25 && i25 > 0.0, "{i0} {i25}");
        assert!((i25 / i0 - ratio).abs() < 1e-4, "{} vs {ratio}", i25 / i0);
    }
}
