//! Part 4: chatter of the contact state machine on the friction-cone boundary.
//!
//! The state machine ([`next_state`]) is driven directly, at [`RATE_HZ`], with the inputs of a
//! hand holding the fingertip still on the surface while pushing tangentially exactly at the
//! static cone, f_T = μ_s·f_N, plus noise:
//!
//! - f_N = 2 N, steady (a_N = 0), 1 mm of penetration;
//! - f_T = μ_s·f_N·(1 + a·u), u uniform in [−1, 1] drawn each step: a is the noise amplitude as a
//!   fraction of the cone (a force sensor or a jittery hand; 0.01 = ±1 %);
//! - a_T = 0.5 m/s² (tremor: always above ε_a, so the "relative motion" condition never blocks a
//!   slide: the worst case for chatter);
//! - v_T = 0 (held still: below v_stick, so a slide ends as soon as f_T ≤ μ_k·f_N);
//! - no rolling this step (the haptic direction rule never blocks) and no twist.
//!
//! A transition is any step whose [`Reason`] is not `Kept`. Two friction settings: the model's
//! defaults (μ_k = 0.6 < μ_s = 0.8: the kinetic gap is itself a 25 % hysteresis), and
//! μ_k = μ_s = 0.8 (a single friction coefficient), where only the cone hysteresis h separates the
//! two thresholds.

use crate::sim::rng::SplitMix64;
use softfinger_core::contact::params::ContactParams;
use softfinger_core::contact::state::{next_state, ContactState, Reason, StateInputs};
use softfinger_core::Vec3;

/// Step rate of the state machine, Hz.
pub const RATE_HZ: f64 = 10_000.0;
/// Length of each run, s.
pub const DURATION_S: f64 = 10.0;
/// Noise amplitudes a (fraction of μ_s·f_N), uniform ±a.
pub const NOISE_LEVELS: [f64; 7] = [0.0, 0.01, 0.02, 0.04, 0.08, 0.16, 0.32];
/// Hysteresis values compared.
pub const HYSTERESES: [f32; 2] = [0.0, 0.05];
/// Normal force, N.
pub const NORMAL_FORCE_N: f32 = 2.0;

/// One configuration's result.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChatterRun {
    /// Friction: true for μ_k = μ_s, false for the defaults.
    pub single_mu: bool,
    pub hysteresis: f32,
    pub noise: f64,
    /// Number of state changes.
    pub transitions: u64,
    /// Transitions per second.
    pub per_s: f64,
    /// Fraction of the steps spent sliding.
    pub sliding_frac: f64,
}

/// Run one configuration for `steps` steps (seeded: the same seed gives the same count).
pub fn run(single_mu: bool, hysteresis: f32, noise: f64, steps: u64, seed: u64) -> ChatterRun {
    let mut params = ContactParams::DEFAULT;
    params.tolerances.hysteresis = hysteresis;
    if single_mu {
        params.mu_k = params.mu_s;
    }
    let sp = params.state_params();
    let mut rng = SplitMix64::new(seed);
    let mut state = ContactState::Rolling;
    let (mut transitions, mut sliding) = (0u64, 0u64);
    // Time in the current state, advanced at the 10 kHz tick (the state machine's dwell times).
    let mut time_in_state_s = 0.0f32;
    let boundary = params.mu_s * NORMAL_FORCE_N;
    for _ in 0..steps {
        let u = rng.uniform_pm1();
        let ft = boundary * (1.0 + (noise * u) as f32);
        let inputs = StateInputs {
            normal_force_n: NORMAL_FORCE_N,
            gap_m: -0.001,
            normal_accel: 0.0,
            tangential_force_n: Vec3::new(ft, 0.0, 0.0),
            tangential_accel: Vec3::new(0.5, 0.0, 0.0),
            tangential_velocity: Vec3::ZERO,
            roll_disp_m: Vec3::ZERO,
            tilt_rate_sq: 0.0,
            time_in_state_s,
            ..StateInputs::default()
        };
        let (s, r) = next_state(state, &inputs, &sp);
        time_in_state_s = if s == state {
            time_in_state_s + (1.0 / RATE_HZ) as f32
        } else {
            0.0
        };
        if r != Reason::Kept {
            transitions += 1;
        }
        if s == ContactState::Sliding {
            sliding += 1;
        }
        state = s;
    }
    let secs = steps as f64 / RATE_HZ;
    ChatterRun {
        single_mu,
        hysteresis,
        noise,
        transitions,
        per_s: transitions as f64 / secs,
        sliding_frac: sliding as f64 / steps.max(1) as f64,
    }
}

/// Every friction setting × hysteresis × noise level.
pub fn run_all(steps: u64) -> Vec<ChatterRun> {
    let mut out = Vec::new();
    for single_mu in [false, true] {
        for h in HYSTERESES {
            for (i, &a) in NOISE_LEVELS.iter().enumerate() {
                out.push(run(single_mu, h, a, steps, 0x5eed + i as u64));
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    const STEPS: u64 = 100_000;

    /// With h = 0.05 a slide needs f_T > 1.05·μ_s·f_N: noise of ±4 % (below the band) never
    /// reaches it, for either friction setting. Exact count: 0.
    #[test]
    fn no_chatter_with_the_default_hysteresis_below_the_band() {
        for single_mu in [false, true] {
            for a in [0.0, 0.01, 0.02, 0.04] {
                let r = run(single_mu, 0.05, a, STEPS, 1);
                assert_eq!(r.transitions, 0, "single_mu {single_mu}, noise {a}");
            }
        }
    }

    /// Without hysteresis and with μ_k = μ_s, any noise makes it chatter: each step the force is
    /// above the cone with probability ½. The 20 ms minimum slide dwell (ContactParams::min_slide_s)
    /// then bounds it: at most one slide per dwell plus the stick that ends it, ≤ 2/0.02 s = 100
    /// transitions per second; it hits that bound (each stick is followed by a slide within a few
    /// steps). Above the band, h = 0.05 chatters too.
    #[test]
    fn h_zero_chatters_and_noise_above_the_band_defeats_h() {
        let r = run(true, 0.0, 0.01, STEPS, 2);
        assert!(r.per_s > 80.0 && r.per_s <= 101.0, "{}", r.per_s);
        let r = run(true, 0.05, 0.16, STEPS, 3);
        assert!(r.transitions > 100, "{}", r.transitions);
    }

    /// With the default μ_k = 0.6 the first slide latches (f_T never falls to 0.6/0.8 = 75 % of
    /// the cone with ±16 % noise): exactly one transition, then sliding.
    #[test]
    fn the_kinetic_gap_latches_the_slide() {
        let r = run(false, 0.0, 0.16, STEPS, 4);
        assert_eq!(r.transitions, 1);
        assert!(r.sliding_frac > 0.99);
    }
}
