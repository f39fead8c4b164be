//! Time-domain passivity: an observer of the energy the rendered force puts into the user, and a
//! variable damper that removes it (Hannaford & Ryu, "Time-domain passivity control of haptic
//! interfaces", IEEE T-RA 18(1), 2002; Ryu, Kim & Hannaford, "Sampled- and continuous-time
//! passivity and stability of virtual environments", IEEE T-RO 20(4), 2004).
//!
//! Conventions: `force` is the force the device applies to the user (base frame, N), `position`
//! the probe position (base frame, m). Energy into the user over one tick interval is the force
//! that *acted* during it times the displacement over it. With an output delay of `d` ticks
//! (0 ≤ d ≤ 1, see [`crate::control::pipeline::output_timing`]) the force computed at tick j acts from j + d to
//! j + 1 + d, so over the interval [k−1, k] the acting force is `d·F[k−2] + (1−d)·F[k−1]`:
//!
//! ```text
//! W[k] = W[k−1] + (d·F[k−2] + (1−d)·F[k−1]) · (p[k] − p[k−1])      (J, into the user)
//! ```
//!
//! A passive rendering keeps W ≤ 0 (it can only return what the user put in). When W > 0 the
//! controller adds a damper −α·v, v the probe velocity the caller hands in (the controller's
//! filtered velocity: a raw one-count difference would turn encoder quantisation into force
//! steps), with α = W/(T·|v|²) (the damping that dissipates W over one tick at that speed),
//! limited to `max_damping_n_s_per_m`; the damper's own work enters W when it acts. The observer restarts (W = 0) when the environment
//! force and the forces still acting are all zero: out of contact, nothing is stored.
//!
//! When W ≤ 0 the force passes through unchanged (bit for bit), so a passive setting renders
//! exactly as without the controller.
//!
//! Encoder quantisation: with E_q = |F|₁·`position_quantum_m` (J; |F|₁ = |Fx| + |Fy| + |Fz|), a
//! positive W drains by E_q per [`LEAK_S`] and the damper acts only when W > E_q; a quantum of 0
//! gives the textbook stage. Why: docs/design.md#passivity-under-encoder-quantisation.

use crate::math::vec3::Vec3;
use crate::validate::{non_negative, positive, ParamError};

/// Time over which the energy of one count of dither drains from a positive W, s: a held probe (2 N, 12.8 µm counts) drains 2.6e-4 W, five times the
/// 4.6e-5 W its count dither feeds the observer (measured over a 60 s hold, see the module doc).
pub const LEAK_S: f32 = 0.1;

/// Parameters of the passivity stage.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PassivityConfig {
    /// Add the damper when the observed energy is positive (false: observe only).
    pub enabled: bool,
    /// Largest damping the controller adds at the probe, N·s/m.
    pub max_damping_n_s_per_m: f32,
    /// Sample-to-output delay in ticks, [0, 1] (see [`crate::control::pipeline::output_timing::OutputTiming`]).
    pub output_delay_ticks: f32,
    /// Probe displacement of one position-sensor count, m (≥ 0; 0: an ideal sensor). The damper
    /// leaves alone the energy |F|·quantum that one count of dither can fake.
    pub position_quantum_m: f32,
}

impl PassivityConfig {
    /// On, with at most 50 N·s/m (the largest damper the Omega-like device renders with its
    /// filtered velocity at 10 kHz without ringing is far above this; 50 N·s/m at the 0.2 m/s of a
    /// fast tap is 10 N, within the device's force range), and one tick of output delay (the host
    /// plant's output latch; the pipeline sets its board's figure).
    pub const DEFAULT: PassivityConfig = PassivityConfig {
        enabled: true,
        max_damping_n_s_per_m: 50.0,
        output_delay_ticks: 1.0,
        position_quantum_m: 0.0,
    };

    /// Check every field.
    pub fn validate(&self) -> Result<(), ParamError> {
        positive("max_damping_n_s_per_m", self.max_damping_n_s_per_m)?;
        non_negative("output_delay_ticks", self.output_delay_ticks)?;
        non_negative("position_quantum_m", self.position_quantum_m)?;
        if self.output_delay_ticks > 1.0 {
            return Err(ParamError::OutOfRange("output_delay_ticks"));
        }
        Ok(())
    }
}

/// What one tick of the stage did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PassivityStep {
    /// Force to render, N.
    pub force_n: Vec3,
    /// Damping added this tick, N·s/m (0 when passive).
    pub damping_n_s_per_m: f32,
    /// Observed energy into the user since the contact began, J.
    pub energy_j: f32,
}

/// The observer and controller with their state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Passivity {
    config: PassivityConfig,
    dt_s: f32,
    started: bool,
    prev_position: Vec3,
    /// Forces output at k−1 and k−2.
    out: [Vec3; 2],
    energy_j: f32,
    /// Ticks per leak time, T/[`LEAK_S`].
    leak_per_tick: f32,
    /// Spring stiffness for the energy stored at a (re)start, N/m.
    spring_n_per_m: f32,
    /// Largest force magnitude rendered, damper included, N.
    max_force_n: f32,
}

impl Passivity {
    /// A stage for ticks of `dt_s` seconds rendering a contact whose stiffest spring is
    /// `spring_n_per_m` and whose force is limited to `max_force_n` (the damper never takes the
    /// force beyond it); invalid parameters are rejected.
    pub fn new(
        config: PassivityConfig,
        dt_s: f32,
        spring_n_per_m: f32,
        max_force_n: f32,
    ) -> Result<Self, ParamError> {
        config.validate()?;
        positive("dt_s", dt_s)?;
        positive("spring_n_per_m", spring_n_per_m)?;
        positive("max_force_n", max_force_n)?;
        Ok(Passivity {
            leak_per_tick: dt_s / LEAK_S,
            spring_n_per_m,
            max_force_n,
            config,
            dt_s,
            started: false,
            prev_position: Vec3::ZERO,
            out: [Vec3::ZERO; 2],
            energy_j: 0.0,
        })
    }

    /// The parameters in force.
    pub fn config(&self) -> &PassivityConfig {
        &self.config
    }

    /// Observed energy into the user since the contact began, J.
    pub fn energy_j(&self) -> f32 {
        self.energy_j
    }

    /// The rendered contact changed: its stiffest spring, N/m, and its force limit, N (each
    /// ignored unless finite and > 0).
    pub fn set_contact(&mut self, spring_n_per_m: f32, max_force_n: f32) {
        if spring_n_per_m.is_finite() && spring_n_per_m > 0.0 {
            self.spring_n_per_m = spring_n_per_m;
        }
        if max_force_n.is_finite() && max_force_n > 0.0 {
            self.max_force_n = max_force_n;
        }
    }

    /// Forget the history (after a restart of the controller or untrusted kinematics).
    pub fn restart(&mut self) {
        self.started = false;
        self.out = [Vec3::ZERO; 2];
        self.energy_j = 0.0;
    }

    /// One tick: observe the last interval's energy, then pass `force` through or damp it with
    /// a damper on `velocity` (m/s).
    pub fn step(&mut self, force: Vec3, position: Vec3, velocity: Vec3) -> PassivityStep {
        if !self.started {
            self.started = true;
            self.prev_position = position;
            self.out = [force; 2];
            self.energy_j = -0.5 * force.norm_squared() / self.spring_n_per_m;
        }
        let dp = position - self.prev_position;
        self.prev_position = position;
        let d = self.config.output_delay_ticks;
        let acting = self.out[1] * d + self.out[0] * (1.0 - d);
        let mut energy = self.energy_j + acting.dot(dp);
        let e_q = (force.x.abs() + force.y.abs() + force.z.abs()) * self.config.position_quantum_m;
        if energy > 0.0 {
            energy -= e_q * self.leak_per_tick;
            if energy < 0.0 {
                energy = 0.0;
            }
        }
        let idle = force == Vec3::ZERO && self.out[0] == Vec3::ZERO && self.out[1] == Vec3::ZERO;
        if idle || !energy.is_finite() {
            energy = 0.0;
        }
        self.energy_j = energy;
        // |v|² only when it decides (most ticks store no energy above the quantum).
        let damps = self.config.enabled && energy > e_q;
        let v2 = if damps { velocity.norm_squared() } else { 0.0 };
        let (out, alpha) = if damps && v2 > 0.0 {
            let alpha = (energy / (self.dt_s * v2)).min(self.config.max_damping_n_s_per_m);
            let damped = self.limited(force - velocity * alpha);
            if damped.is_finite() {
                (damped, alpha)
            } else {
                (force, 0.0)
            }
        } else {
            (force, 0.0)
        };
        self.out = [out, self.out[0]];
        PassivityStep {
            force_n: out,
            damping_n_s_per_m: alpha,
            energy_j: energy,
        }
    }
}

impl Passivity {
    /// `f` scaled down to the force limit when above it (never above the larger of the limit).
    fn limited(&self, f: Vec3) -> Vec3 {
        let n2 = f.norm_squared();
        let m = self.max_force_n;
        if n2 > m * m {
            f * (m / libm::sqrtf(n2))
        } else {
            f
        }
    }
}

#[cfg(test)]
mod tests;
