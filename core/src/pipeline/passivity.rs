//! Time-domain passivity: an observer of the energy the rendered force puts into the user, and a
//! variable damper that removes it (Hannaford & Ryu, "Time-domain passivity control of haptic
//! interfaces", IEEE T-RA 18(1), 2002; Ryu, Kim & Hannaford, "Sampled- and continuous-time
//! passivity and stability of virtual environments", IEEE T-RO 20(4), 2004).
//!
//! Conventions: `force` is the force the device applies to the user (base frame, N), `position`
//! the probe position (base frame, m). Energy into the user over one tick interval is the force
//! that *acted* during it times the displacement over it. With an output delay of `d` ticks
//! (0 ≤ d ≤ 1, see [`super::output_timing`]) the force computed at tick j acts from j + d to
//! j + 1 + d, so over the interval [k−1, k] the acting force is `d·F[k−2] + (1−d)·F[k−1]`:
//!
//! ```text
//! W[k] = W[k−1] + (d·F[k−2] + (1−d)·F[k−1]) · (p[k] − p[k−1])      (J, into the user)
//! ```
//!
//! The force acting is the *applied* one: the motor current follows the output as a first-order
//! lag with the winding's time constant τ = L/R (`winding_lag_s`, from the device's
//! [`crate::device::MotorParams::electrical_time_constant_s`]). The observer propagates that lag
//! exactly over the two piecewise-constant segments of each interval (length d·T with F[k−2], then
//! (1−d)·T with F[k−1]; a₁ = e^{−dT/τ}, a₂ = e^{−(1−d)T/τ}) and uses the lag's own integral
//! (τ·ḟ = u − f ⇒ ∫f = ∫u − τ·(f_end − f_start)):
//!
//! ```text
//! f[k]   = a₁a₂·f[k−1] + (1−a₁)a₂·F[k−2] + (1−a₂)·F[k−1]          (applied force at tick k)
//! W[k]   = W[k−1] + (d·F[k−2] + (1−d)·F[k−1] + τ/T·(f[k−1] − f[k])) · (p[k] − p[k−1])
//! ```
//!
//! (a zero-order hold with a delay, then a lag: the sampled-system treatment of Ryu, Kim &
//! Hannaford with the actuator's dynamics in the path). With τ = 0 it is the line above, bit for
//! bit. A passive rendering keeps W ≤ 0 (it can only return what the user put in). When W > 0 the
//! controller adds a damper −α·v, v the probe velocity the caller hands in (the controller's
//! filtered velocity: a raw one-count difference would turn encoder quantisation into force
//! steps), with α = W/(T·|v|²) (the damping that dissipates W over one tick at that speed),
//! limited to `max_damping_n_s_per_m`; the damper's own work enters W when it acts. The observer restarts (W = 0) when the environment
//! force and the forces still acting are all zero: out of contact, nothing is stored.
//!
//! When W ≤ 0 the force passes through unchanged (bit for bit), so a passive setting renders
//! exactly as without the controller.

use crate::params::{non_negative, positive, ParamError};
use crate::vec3::Vec3;

/// Parameters of the passivity stage.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PassivityConfig {
    /// Add the damper when the observed energy is positive (false: observe only).
    pub enabled: bool,
    /// Largest damping the controller adds at the probe, N·s/m.
    pub max_damping_n_s_per_m: f32,
    /// Sample-to-output delay in ticks, [0, 1] (see [`super::output_timing::OutputTiming`]).
    pub output_delay_ticks: f32,
    /// Time constant of the first-order lag of the applied force behind the output, s (≥ 0; the
    /// winding's L/R, [`crate::device::MotorParams::electrical_time_constant_s`]; 0: none).
    pub winding_lag_s: f32,
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
        winding_lag_s: 0.0,
    };

    /// [`Self::DEFAULT`] for a device whose output acts `output_delay_ticks` after the sample
    /// (clamped to [0, 1]) through the motors' winding lag.
    pub fn for_device(device: &crate::device::DeviceParams, output_delay_ticks: f32) -> Self {
        PassivityConfig {
            output_delay_ticks: output_delay_ticks.clamp(0.0, 1.0),
            winding_lag_s: device.motor.electrical_time_constant_s(),
            ..Self::DEFAULT
        }
    }

    /// Check every field.
    pub fn validate(&self) -> Result<(), ParamError> {
        positive("max_damping_n_s_per_m", self.max_damping_n_s_per_m)?;
        non_negative("output_delay_ticks", self.output_delay_ticks)?;
        if self.output_delay_ticks > 1.0 {
            return Err(ParamError::OutOfRange("output_delay_ticks"));
        }
        non_negative("winding_lag_s", self.winding_lag_s)?;
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
    /// Estimated applied force at the last tick (the winding lag's state), N.
    applied: Vec3,
    /// The lag over one interval: weights of f[k−1], F[k−2], F[k−1] in f[k], and of the same
    /// three in the mean force acting over the interval ([`lag_weights`]).
    lag: ([f32; 3], [f32; 3]),
    energy_j: f32,
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
            spring_n_per_m,
            max_force_n,
            config,
            dt_s,
            started: false,
            prev_position: Vec3::ZERO,
            out: [Vec3::ZERO; 2],
            applied: Vec3::ZERO,
            lag: lag_weights(config.output_delay_ticks, config.winding_lag_s, dt_s),
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
        self.applied = Vec3::ZERO;
        self.energy_j = 0.0;
    }

    /// One tick: observe the last interval's energy, then pass `force` through or damp it with
    /// a damper on `velocity` (m/s).
    pub fn step(&mut self, force: Vec3, position: Vec3, velocity: Vec3) -> PassivityStep {
        if !self.started {
            self.started = true;
            self.prev_position = position;
            self.out = [force; 2];
            self.applied = force;
            self.energy_j = -0.5 * force.norm_squared() / self.spring_n_per_m;
        }
        let dp = position - self.prev_position;
        self.prev_position = position;
        let ([a0, a1, a2], [m0, m1, m2]) = self.lag;
        let acting = self.out[1] * m1 + self.out[0] * m2 + self.applied * m0;
        self.applied = self.applied * a0 + self.out[1] * a1 + self.out[0] * a2;
        let mut energy = self.energy_j + acting.dot(dp);
        let idle = force == Vec3::ZERO && self.out[0] == Vec3::ZERO && self.out[1] == Vec3::ZERO;
        if idle || !energy.is_finite() {
            energy = 0.0;
            // A non-finite force reached the lag state (and so the energy): forget it.
            if !self.applied.is_finite() {
                self.applied = Vec3::ZERO;
            }
        }
        self.energy_j = energy;
        let v2 = velocity.norm_squared();
        let (out, alpha) = if self.config.enabled && energy > 0.0 && v2 > 0.0 {
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

/// The winding lag over one tick interval of `dt_s` with the output `delay` ticks late and time
/// constant `tau_s` (validated ≥ 0): the weights of (f[k−1], F[k−2], F[k−1]) in the applied force
/// f[k], `[a₁a₂, (1−a₁)a₂, 1−a₂]`, and in the mean force acting over the interval, `d·F[k−2] +
/// (1−d)·F[k−1] + τ/T·(f[k−1] − f[k])` (see the module text). τ = 0 gives `[0, 0, 1]` and
/// `[0, d, 1−d]`: the applied force is the output.
fn lag_weights(delay: f32, tau_s: f32, dt_s: f32) -> ([f32; 3], [f32; 3]) {
    if tau_s <= 0.0 {
        return ([0.0, 0.0, 1.0], [0.0, delay, 1.0 - delay]);
    }
    let a1 = libm::expf(-delay * dt_s / tau_s);
    let a2 = libm::expf(-(1.0 - delay) * dt_s / tau_s);
    let applied = [a1 * a2, (1.0 - a1) * a2, 1.0 - a2];
    let r = tau_s / dt_s;
    let acting = [
        r * (1.0 - applied[0]),
        delay - r * applied[1],
        (1.0 - delay) - r * applied[2],
    ];
    (applied, acting)
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
mod tests {
    use super::*;

    fn observer(d: f32, dt: f32) -> Passivity {
        Passivity::new(
            PassivityConfig {
                enabled: false,
                output_delay_ticks: d,
                ..PassivityConfig::DEFAULT
            },
            dt,
            1e4,
            12.0,
        )
        .unwrap()
    }

    /// A spring F = −K·x sampled every T against x = A·sin(ωt): over N ticks spanning whole
    /// periods the energy into the user is (closed form, f64)
    /// `−K/2·(x_end² − x_start²) + K·A²·N·sin²(ωT/2)·(1 + 2d·cos ωT)` for d ∈ {0, 1}
    /// (Σ Δx² = 2A²N·sin²(ωT/2), Σ Δx_k·Δx_{k−1} = 2A²N·sin²(ωT/2)·cos ωT) — the energy the
    /// sampled spring generates, three times larger with a tick of delay. Measured f32 error
    /// against it: < 2e-5 relative; bound 1e-4.
    #[test]
    fn observer_matches_the_closed_form_of_a_sampled_spring() {
        let (k, a, t) = (1.0e4f64, 1.0e-3f64, 1.0e-4f64);
        let w = 2.0 * core::f64::consts::PI * 100.0;
        let n = 1_000usize; // 10 periods of 100 ticks
        for d in [0.0f64, 1.0] {
            let mut p = observer(d as f32, t as f32);
            let x = |i: usize| a * (w * t * i as f64).sin();
            let mut at = |i: usize| {
                let xi = x(i);
                let f = Vec3::new((-k * xi) as f32, 0.0, 0.0);
                p.step(f, Vec3::new(xi as f32, 0.0, 0.0), Vec3::ZERO)
                    .energy_j as f64
            };
            // Ticks 0, 1: fill the history; the window is the intervals ending at 3..=n+2.
            let _ = (at(0), at(1));
            let start = at(2);
            let mut end = start;
            for i in 3..=n + 2 {
                end = at(i);
            }
            let s2 = (w * t / 2.0).sin().powi(2);
            let expected = -0.5 * k * (x(n + 2).powi(2) - x(2).powi(2))
                + k * a * a * n as f64 * s2 * (1.0 + 2.0 * d * (w * t).cos());
            let got = end - start;
            assert!(
                ((got - expected) / expected).abs() < 1e-4,
                "d {d}: {got} vs {expected}"
            );
            assert!(expected > 0.0);
        }
    }

    /// The winding lag: a force step F (from 0) at tick 1 with the output `d` ticks late, the
    /// probe moving at constant v. The applied force is F·(1 − e^{−(t − t₀)/τ}) from t₀ = (1 + d)·T
    /// on, so the energy into the user up to tick n is (closed form, f64)
    /// `F·v·(s − τ·(1 − e^{−s/τ}))`, s = nT − t₀. Measured f32 error against it: ≤ 4.2e-8
    /// relative (d = 0.247); bound 1.5e-7. An observer without the lag model (τ = 0) is off by
    /// the work the lag withholds, F·v·τ·(1 − e^{−s/τ}): 6.1–6.5 % of W here (checked > 5 %).
    #[test]
    fn observer_follows_the_winding_lag_in_closed_form() {
        let (t, f, v, tau) = (1.0e-4f64, 2.0f64, 0.01f64, 110e-6f64);
        let n = 20usize;
        let observed = |d: f64, lag: f64| {
            let mut p = Passivity::new(
                PassivityConfig {
                    enabled: false,
                    output_delay_ticks: d as f32,
                    winding_lag_s: lag as f32,
                    ..PassivityConfig::DEFAULT
                },
                t as f32,
                1e4,
                12.0,
            )
            .unwrap();
            let at = |i: usize| Vec3::new((v * t * i as f64) as f32, 0.0, 0.0);
            let _ = p.step(Vec3::ZERO, at(0), Vec3::ZERO);
            let force = Vec3::new(f as f32, 0.0, 0.0);
            let mut w = 0.0f64;
            for i in 1..=n {
                w = f64::from(p.step(force, at(i), Vec3::ZERO).energy_j);
            }
            w
        };
        for d in [0.0f64, 0.247, 1.0] {
            let s = (n as f64 - 1.0 - d) * t;
            let expected = f * v * (s - tau * (1.0 - (-s / tau).exp()));
            let rel = |w: f64| ((w - expected) / expected).abs();
            let w = observed(d, tau);
            assert!(rel(w) < 1.5e-7, "d {d}: {w} vs {expected} ({})", rel(w));
            assert!(rel(observed(d, 0.0)) > 0.05, "d {d}");
        }
    }

    /// A passive force (a damper) keeps W ≤ 0 and passes through bit for bit; the controller
    /// never acts.
    #[test]
    fn passive_force_passes_unchanged() {
        let mut p = Passivity::new(PassivityConfig::DEFAULT, 1e-4, 1e4, 12.0).unwrap();
        for i in 0..2_000 {
            let v = 0.05 * (i as f32 * 0.01).sin();
            let x = Vec3::new(0.0, 0.0, -0.05 * (i as f32 * 0.01).cos() / 100.0);
            let f = Vec3::new(0.0, 0.0, -20.0 * v);
            let s = p.step(f, x, Vec3::new(0.0, 0.0, v));
            assert_eq!(s.force_n, f);
            assert_eq!(s.damping_n_s_per_m, 0.0);
            assert!(s.energy_j <= 1e-9, "{}", s.energy_j);
        }
    }

    /// Positive energy: the damper removes it at the current speed, up to its limit (bracketed).
    #[test]
    fn damper_removes_positive_energy_within_its_limit() {
        let dt = 1e-4f32;
        let mk = |max| {
            let mut p = Passivity::new(
                PassivityConfig {
                    enabled: true,
                    max_damping_n_s_per_m: max,
                    output_delay_ticks: 0.0,
                    winding_lag_s: 0.0,
                },
                dt,
                1e4,
                12.0,
            )
            .unwrap();
            // Out of contact, then an active force: +2 N along the motion over 1 µm puts 2 µJ
            // into the user.
            let _ = p.step(Vec3::ZERO, Vec3::ZERO, Vec3::ZERO);
            let _ = p.step(Vec3::new(2.0, 0.0, 0.0), Vec3::ZERO, Vec3::ZERO);
            p.step(
                Vec3::new(2.0, 0.0, 0.0),
                Vec3::new(1e-6, 0.0, 0.0),
                Vec3::new(0.01, 0.0, 0.0),
            )
        };
        // α = W/(T·v²) = 2e-6/(1e-4·1e-4) = 200 N·s/m at v = 0.01 m/s: a limit of 200.5 lets
        // it through …
        let s = mk(200.5);
        assert!((s.energy_j - 2e-6).abs() < 1e-11);
        assert!((s.damping_n_s_per_m - 200.0).abs() < 1e-3);
        // … and the damper's force −α·v = −2 N over one tick at v removes W: 2 N · 1 µm.
        assert!((s.force_n.x - (2.0 - 2.0)).abs() < 1e-4, "{:?}", s.force_n);
        // A limit of 199.5 caps it.
        let s = mk(199.5);
        assert_eq!(s.damping_n_s_per_m, 199.5);
        assert!(
            (s.force_n.x - (2.0 - 1.995)).abs() < 1e-5,
            "{:?}",
            s.force_n
        );
        // The damper never takes the force beyond the contact's limit: a 12 N force moving at
        // 0.01 m/s against α = 200 would be 14 N; it is held at 12 N.
        let mut p = Passivity::new(
            PassivityConfig {
                max_damping_n_s_per_m: 1e3,
                output_delay_ticks: 0.0,
                ..PassivityConfig::DEFAULT
            },
            dt,
            1e4,
            12.0,
        )
        .unwrap();
        let _ = p.step(Vec3::ZERO, Vec3::ZERO, Vec3::ZERO);
        let _ = p.step(Vec3::new(2.0, 0.0, 0.0), Vec3::ZERO, Vec3::ZERO);
        let s = p.step(
            Vec3::new(-12.0, 0.0, 0.0),
            Vec3::new(1e-6, 0.0, 0.0),
            Vec3::new(0.01, 0.0, 0.0),
        );
        assert!(s.damping_n_s_per_m > 100.0);
        assert!((s.force_n.x + 12.0).abs() < 1e-5, "{:?}", s.force_n);
        // Off: observe only.
        let mut p = observer(0.0, dt);
        let _ = p.step(Vec3::ZERO, Vec3::ZERO, Vec3::ZERO);
        let _ = p.step(Vec3::new(2.0, 0.0, 0.0), Vec3::ZERO, Vec3::ZERO);
        let v = Vec3::new(0.01, 0.0, 0.0);
        let s = p.step(Vec3::new(2.0, 0.0, 0.0), Vec3::new(1e-6, 0.0, 0.0), v);
        assert!(s.energy_j > 0.0 && s.force_n.x == 2.0);
    }

    #[test]
    fn restarts_out_of_contact_and_rejects_bad_parameters() {
        let mut p = observer(0.0, 1e-4);
        let z = Vec3::ZERO;
        // Starting on a rendered 2 N: W starts at −|F|²/(2K) = −4/2e4 J.
        assert_eq!(p.step(Vec3::new(2.0, 0.0, 0.0), z, z).energy_j, -2e-4);
        p.restart();
        let _ = p.step(z, z, z);
        let _ = p.step(Vec3::new(2.0, 0.0, 0.0), z, z);
        let _ = p.step(z, Vec3::new(1e-6, 0.0, 0.0), z);
        assert!(p.energy_j() > 0.0);
        // Two more force-free ticks: nothing acts any more, W restarts.
        let _ = p.step(z, Vec3::new(2e-6, 0.0, 0.0), z);
        assert!(p.energy_j() > 0.0);
        let s = p.step(z, Vec3::new(3e-6, 0.0, 0.0), z);
        assert_eq!(s.energy_j, 0.0);
        let bad = |f: fn(&mut PassivityConfig)| {
            let mut c = PassivityConfig::DEFAULT;
            f(&mut c);
            Passivity::new(c, 1e-4, 1e4, 12.0).err()
        };
        assert_eq!(
            bad(|c| c.max_damping_n_s_per_m = 0.0),
            Some(ParamError::NotPositive("max_damping_n_s_per_m"))
        );
        assert_eq!(
            bad(|c| c.output_delay_ticks = 1.0 + f32::EPSILON),
            Some(ParamError::OutOfRange("output_delay_ticks"))
        );
        assert_eq!(bad(|c| c.output_delay_ticks = 1.0), None);
        assert_eq!(
            bad(|c| c.output_delay_ticks = -0.0001),
            Some(ParamError::Negative("output_delay_ticks"))
        );
        assert!(Passivity::new(PassivityConfig::DEFAULT, f32::NAN, 1e4, 12.0).is_err());
        assert!(Passivity::new(PassivityConfig::DEFAULT, 1e-4, 0.0, 12.0).is_err());
        assert!(Passivity::new(PassivityConfig::DEFAULT, 1e-4, 1e4, 0.0).is_err());
    }
}
