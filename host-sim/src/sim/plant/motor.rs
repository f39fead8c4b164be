//! One brushed DC motor on a voltage-mode H-bridge, its capstan reduction and the drive-train
//! friction, all referred to the arm where that is stated.
//!
//! Electrical model: L·di/dt = V − R·i − k_e·ω_motor, with the current's own dynamics kept. The
//! RE 25-class winding has τ_e = L/R = 0.24 mH / 2.18 Ω = 110 µs, the same order as a 10 kHz
//! control period, so a quasi-static i = (V − k_e·ω)/R would advance the torque by about one
//! tick and hide exactly the lag a haptic loop has to live with. Over a plant sub-step (10 µs)
//! ω is held and the linear ODE is solved exactly, i ← i_ss + (i − i_ss)·e^(−R·h/L), which is
//! stable for any step. The PWM is state-space averaged (terminal voltage = duty·V_supply); the
//! 20 kHz current ripple (±0.6 A at 50 % duty) averages out of the torque and is not modelled.
//! The bridge is assumed to recirculate actively (drive/brake), so the averaged voltage holds
//! in all four quadrants; with the bridge disabled the winding is open and the current is zero
//! (body-diode conduction above the supply voltage is ignored).
//!
//! Amplifier current limit: |i| is clamped at `max_current_a` after each sub-step (a
//! cycle-by-cycle limiter, seen from the averaged model).

use softfinger_core::device::DeviceParams;

use super::params::PlantParams;

/// Motor, drive and friction constants in f64.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Motor {
    resistance_ohm: f64,
    inductance_h: f64,
    torque_constant_nm_per_a: f64,
    back_emf_v_s_per_rad: f64,
    ratio: f64,
    max_current_a: f64,
    supply_v: f64,
    coulomb_nm: f64,
    viscous_nm_s_per_rad: f64,
    smoothing_rad_s: f64,
}

impl Motor {
    pub fn new(device: &DeviceParams, plant: &PlantParams) -> Motor {
        let m = &device.motor;
        Motor {
            resistance_ohm: m.resistance_ohm as f64,
            inductance_h: plant.motor_inductance_h,
            torque_constant_nm_per_a: m.torque_constant_nm_per_a as f64,
            back_emf_v_s_per_rad: m.back_emf_v_s_per_rad as f64,
            ratio: m.capstan_ratio as f64,
            max_current_a: m.max_current_a as f64,
            supply_v: device.supply_v as f64,
            coulomb_nm: plant.coulomb_friction_nm,
            viscous_nm_s_per_rad: plant.viscous_friction_nm_s_per_rad,
            smoothing_rad_s: plant.friction_smoothing_rad_s,
        }
    }

    /// Capstan ratio (motor turns per arm turn).
    pub fn ratio(&self) -> f64 {
        self.ratio
    }

    /// Current (A) after a sub-step of `h` seconds at averaged duty `duty` (already quantised,
    /// in [-1, 1]) with the arm turning at `arm_omega` rad/s. `enabled = false` opens the bridge.
    pub fn current_step(
        &self,
        current: f64,
        duty: f64,
        enabled: bool,
        arm_omega: f64,
        h: f64,
    ) -> f64 {
        if !enabled {
            return 0.0;
        }
        let volts = duty * self.supply_v;
        let emf = self.back_emf_v_s_per_rad * self.ratio * arm_omega;
        let steady = (volts - emf) / self.resistance_ohm;
        let decay = (-self.resistance_ohm * h / self.inductance_h).exp();
        let i = steady + (current - steady) * decay;
        i.clamp(-self.max_current_a, self.max_current_a)
    }

    /// Arm-side torque of a motor current, N·m: ratio · k_t · i.
    pub fn arm_torque(&self, current: f64) -> f64 {
        self.ratio * self.torque_constant_nm_per_a * current
    }

    /// Drive-train friction torque opposing the arm velocity, N·m (arm side): viscous plus a
    /// Coulomb term smoothed by tanh(ω/ω_s), so it is continuous through zero velocity (a
    /// regularised stick-slip: below ω_s it acts as a steep viscous term).
    pub fn friction_torque(&self, arm_omega: f64) -> f64 {
        self.viscous_nm_s_per_rad * arm_omega
            + self.coulomb_nm * (arm_omega / self.smoothing_rad_s).tanh()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn motor() -> Motor {
        Motor::new(&DeviceParams::OMEGA_LIKE, &PlantParams::OMEGA_LIKE)
    }

    #[test]
    fn current_follows_the_rl_step_response_at_locked_rotor() {
        // Locked rotor, 10 % duty = 2.4 V: i(t) = V/R·(1 − e^(−t·R/L)). Exact exponential
        // sub-steps compose to the closed form up to rounding: measured 4.4e-16 A at worst over the
        // 100 steps; bound 3×.
        let m = motor();
        let r = DeviceParams::OMEGA_LIKE.motor.resistance_ohm as f64;
        let l = PlantParams::OMEGA_LIKE.motor_inductance_h;
        let h = 1e-5;
        let mut i = 0.0;
        for k in 1..=100 {
            i = m.current_step(i, 0.1, true, 0.0, h);
            let t = k as f64 * h;
            let expected = 2.4 / r * (1.0 - (-t * r / l).exp());
            assert!((i - expected).abs() < 1.3e-15, "t {t}: {i} vs {expected}");
        }
    }

    #[test]
    fn current_saturates_at_the_amplifier_limit_and_is_zero_when_disabled() {
        let m = motor();
        let mut i = 0.0;
        for _ in 0..1000 {
            i = m.current_step(i, 1.0, true, 0.0, 1e-5);
        }
        // 24 V / 2.18 Ω = 11 A would flow; the limit is 4 A.
        assert_eq!(i, 4.0);
        assert_eq!(m.current_step(3.0, 1.0, false, 0.0, 1e-5), 0.0);
    }

    #[test]
    fn friction_is_odd_continuous_and_tends_to_coulomb_plus_viscous() {
        let m = motor();
        let p = PlantParams::OMEGA_LIKE;
        assert_eq!(m.friction_torque(0.0), 0.0);
        for w in [1e-4, 0.01, 1.0, 10.0] {
            assert_eq!(m.friction_torque(-w), -m.friction_torque(w));
        }
        // Far above ω_s, tanh rounds to exactly 1: measured equal.
        let w = 10.0;
        let expected = p.coulomb_friction_nm + p.viscous_friction_nm_s_per_rad * w;
        assert_eq!(m.friction_torque(w), expected);
    }
}
