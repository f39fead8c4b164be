//! Part 3, continued: the largest passive wall at the firmware's output timing, and what the
//! passivity controller buys beyond it (sampled-wall model of [`super::haptic`]).
//!
//! **Firmware timing** per control rate: the board timing the firmware runs
//! ([`crate::sim::closed_loop::board_timing`], from `BoardTiming::STM32G474_10KHZ`, the constant
//! `firmware/src/config.rs` asserts on) with the output timing of
//! [`softfinger_core::control::pipeline::output_timing`] — 40 kHz PWM (an integer multiple of every rate
//! here), the tick starting on a PWM period boundary, the encoders sampled at the interrupt's start
//! and the compare written as soon as the force is known; the compare takes effect at the next PWM
//! period start. The compute time is the planned pipeline tick
//! ([`PIPELINE_TICK_INSTRUCTIONS`] instructions at [`CCM_CYCLES_PER_INSTRUCTION`] cycles each,
//! 170 MHz), a parameter of [`firmware_delay_ticks`].
//!
//! **Passivity at 3×**: the wall set to three times the largest passive stiffness of the
//! firmware timing, with the core's passivity stage on. "Bounded" means the run's verdict is
//! stable (the oscillation decays, the criterion of [`super::haptic`]) and the oscillation energy
//! never exceeds [`BOUNDED_ENERGY_FACTOR`] times the hit's.

use super::haptic::{self, Device, Loop, Outcome};
use softfinger_core::control::controller::passivity::PassivityConfig;
use softfinger_core::control::pipeline::output_timing::{
    OutputTiming, CCM_CYCLES_PER_INSTRUCTION, PIPELINE_TICK_INSTRUCTIONS,
};

/// A passivity run is bounded when its oscillation energy stays below this multiple of the hit's.
pub const BOUNDED_ENERGY_FACTOR: f64 = 2.0;
/// Stiffness multiple of the largest passive wall for the passivity test.
pub const PASSIVITY_MULTIPLE: f64 = 3.0;

/// The firmware's sample-to-output delay at `rate_hz`, in ticks, for a tick of `instructions`
/// instructions at `cpi` cycles each. `None` when the rate gives no valid board timing.
pub fn firmware_delay_ticks(rate_hz: f64, instructions: u32, cpi: f32) -> Option<f64> {
    let board = crate::sim::closed_loop::board_timing(rate_hz).ok()?;
    Some(OutputTiming::from_instructions(&board, instructions, cpi).delay_ticks() as f64)
}

/// One rate's figures.
#[derive(Clone, Debug)]
pub struct TimingRow {
    pub rate_hz: f64,
    /// Colgate's bound 2b/T, N/m.
    pub bound: f64,
    /// The firmware's sample-to-output delay, ticks.
    pub delay_ticks: f64,
    /// Eigenvalue limit and measured K_max at the firmware timing, N/m.
    pub eigen_firmware: Option<f64>,
    pub measured_firmware: Option<f64>,
    /// Measured K_max with one full tick of delay, N/m.
    pub measured_one_tick: Option<f64>,
    /// Measured K_max at the firmware timing with the passivity stage (None: no unstable K in
    /// the sweep up to its top), N/m.
    pub measured_passivity: Option<f64>,
    /// The wall at [`PASSIVITY_MULTIPLE`] × `measured_firmware`: without and with passivity.
    pub at_multiple: Option<(f64, Outcome, Outcome)>,
}

impl TimingRow {
    /// K_max at the firmware timing over 2b/T.
    pub fn ratio_firmware(&self) -> Option<f64> {
        self.measured_firmware.map(|k| k / self.bound)
    }

    /// True when the 3× wall with passivity is bounded (see the module doc).
    pub fn passivity_bounded(&self) -> Option<bool> {
        self.at_multiple
            .as_ref()
            .map(|(_, _, with)| with.stable && with.peak_j <= BOUNDED_ENERGY_FACTOR * with.hit_j)
    }
}

/// The firmware-timing loop at `rate_hz`.
pub fn firmware_loop(device: &Device, rate_hz: f64, delay_ticks: f64, pc: bool) -> Loop {
    Loop {
        passivity: pc.then_some(PassivityConfig::DEFAULT),
        ..Loop::wall(*device, rate_hz, delay_ticks, 0.0)
    }
}

/// Every rate of [`haptic::RATES_HZ`].
pub fn run_all(device: &Device, duration_s: f64) -> Vec<TimingRow> {
    haptic::RATES_HZ
        .iter()
        .map(|&rate| {
            let delay =
                firmware_delay_ticks(rate, PIPELINE_TICK_INSTRUCTIONS, CCM_CYCLES_PER_INSTRUCTION)
                    .unwrap_or(1.0);
            let fw = firmware_loop(device, rate, delay, false);
            let with_pc = firmware_loop(device, rate, delay, true);
            let (measured_firmware, _) = haptic::measured_kmax(&fw, duration_s);
            let (measured_one_tick, _) =
                haptic::measured_kmax(&Loop::wall(*device, rate, 1.0, 0.0), duration_s);
            let (measured_passivity, _) = haptic::measured_kmax(&with_pc, duration_s);
            let at_multiple = measured_firmware.map(|k| {
                let k3 = PASSIVITY_MULTIPLE * k;
                let without = haptic::simulate(&fw, k3, duration_s);
                let with = haptic::simulate(&with_pc, k3, duration_s);
                (k3, without, with)
            });
            TimingRow {
                rate_hz: rate,
                bound: haptic::colgate_kmax(device.damping, 0.0, 1.0 / rate),
                delay_ticks: delay,
                eigen_firmware: haptic::eigen_kmax(&fw),
                measured_firmware,
                measured_one_tick,
                measured_passivity,
                at_multiple,
            }
        })
        .collect()
}

/// Speed of the fast impact, m/s (a quick tap on a desktop device).
pub const IMPACT_SPEED: f64 = 0.2;
/// Duration of the impact traces, s.
pub const IMPACT_SECONDS: f64 = 0.1;

/// A fast impact on the wall at one stiffness, without and with the passivity stage.
#[derive(Clone, Debug)]
pub struct Impact {
    pub rate_hz: f64,
    pub delay_ticks: f64,
    pub stiffness: f64,
    pub without: Vec<haptic::TraceSample>,
    pub with: Vec<haptic::TraceSample>,
    /// Peak force of an ideal continuous spring of this stiffness hit at the same speed with the
    /// same push (no damping): F_h + sqrt(F_h² + K·m·v₀²), N.
    pub ideal_peak_n: f64,
}

impl Impact {
    /// Largest |force| of a trace, N.
    pub fn peak_n(trace: &[haptic::TraceSample]) -> f64 {
        trace.iter().map(|s| s.force_n.abs()).fold(0.0, f64::max)
    }

    /// Peak force with passivity over the ideal spring's, minus one.
    pub fn overshoot_with(&self) -> f64 {
        Self::peak_n(&self.with) / self.ideal_peak_n - 1.0
    }
}

/// The fast impact at `rate_hz` on a wall of `stiffness` N/m at the firmware timing.
pub fn impact(device: &Device, rate_hz: f64, delay_ticks: f64, stiffness: f64) -> Impact {
    let trace = |pc| {
        let mut v = Vec::new();
        let l = firmware_loop(device, rate_hz, delay_ticks, pc);
        haptic::run_wall(&l, stiffness, IMPACT_SPEED, IMPACT_SECONDS, |s| v.push(s));
        v
    };
    let f = device.user_force_n;
    Impact {
        rate_hz,
        delay_ticks,
        stiffness,
        without: trace(false),
        with: trace(true),
        ideal_peak_n: f + (f * f + stiffness * device.mass_kg * IMPACT_SPEED.powi(2)).sqrt(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 40 kHz PWM: a compute time under one PWM period (25 µs) gives a quarter tick at 10 kHz and
    /// half a tick at 20 kHz, less the sample instant (51 counts of 17 000 / 8 500).
    #[test]
    fn firmware_delays() {
        let d10 = firmware_delay_ticks(10_000.0, 2_500, 1.25).unwrap();
        assert!((d10 - (4_250.0 - 51.0) / 17_000.0).abs() < 1e-6, "{d10}");
        let d20 = firmware_delay_ticks(20_000.0, 2_500, 1.25).unwrap();
        assert!((d20 - (4_250.0 - 51.0) / 8_500.0).abs() < 1e-6, "{d20}");
        // 3 400 instructions at 1.25 miss the first PWM period: half a tick at 10 kHz.
        let d = firmware_delay_ticks(10_000.0, 3_400, 1.25).unwrap();
        assert!((d - (8_500.0 - 51.0) / 17_000.0).abs() < 1e-6, "{d}");
        // 30 kHz control is not a divisor of 40 kHz PWM, and 30 kHz PWM has no integer period
        // at 170 MHz.
        assert!(firmware_delay_ticks(30_000.0, 2_500, 1.25).is_none());
        // Every rate of the experiment has a board timing.
        for rate in haptic::RATES_HZ {
            assert!(firmware_delay_ticks(rate, 2_500, 1.25).is_some(), "{rate}");
        }
    }
}
