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

/// A damping stage (T = 0.1 ms, K = 10 N/mm, 12 N limit, no delay) after an active start: out of
/// contact, then +2 N along the motion over 1 µm puts 2 µJ into the user; the third tick renders
/// `force` at that position with the probe moving at 0.01 m/s along x.
fn after_active_start(config: PassivityConfig, force: Vec3) -> PassivityStep {
    let config = PassivityConfig {
        enabled: true,
        output_delay_ticks: 0.0,
        ..config
    };
    let mut p = Passivity::new(config, 1e-4, 1e4, 12.0).unwrap();
    let _ = p.step(Vec3::ZERO, Vec3::ZERO, Vec3::ZERO);
    let _ = p.step(Vec3::new(2.0, 0.0, 0.0), Vec3::ZERO, Vec3::ZERO);
    p.step(force, Vec3::new(1e-6, 0.0, 0.0), Vec3::new(0.01, 0.0, 0.0))
}

/// Positive energy: the damper removes it at the current speed, up to its limit (bracketed).
#[test]
fn damper_removes_positive_energy_within_its_limit() {
    let mk = |max| {
        let c = PassivityConfig {
            max_damping_n_s_per_m: max,
            ..PassivityConfig::DEFAULT
        };
        after_active_start(c, Vec3::new(2.0, 0.0, 0.0))
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
    let c = PassivityConfig {
        max_damping_n_s_per_m: 1e3,
        ..PassivityConfig::DEFAULT
    };
    let s = after_active_start(c, Vec3::new(-12.0, 0.0, 0.0));
    assert!(s.damping_n_s_per_m > 100.0);
    assert!((s.force_n.x + 12.0).abs() < 1e-5, "{:?}", s.force_n);
    // Off: observe only.
    let dt = 1e-4f32;
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

/// A 10 kHz stage with sensor quantum `q` and no output delay.
fn stage(q: f32) -> Passivity {
    Passivity::new(
        PassivityConfig {
            output_delay_ticks: 0.0,
            position_quantum_m: q,
            ..PassivityConfig::DEFAULT
        },
        1e-4,
        1e4,
        12.0,
    )
    .unwrap()
}

/// An active +2 N push over 1 µm (2 µJ into the user), then one more tick at 0.01 m/s, on a
/// stage with sensor quantum `q` (no output delay).
fn pushed(q: f32) -> PassivityStep {
    let mut p = stage(q);
    let f = Vec3::new(2.0, 0.0, 0.0);
    let _ = p.step(Vec3::ZERO, Vec3::ZERO, Vec3::ZERO);
    let _ = p.step(f, Vec3::ZERO, Vec3::ZERO);
    p.step(f, Vec3::new(1e-6, 0.0, 0.0), Vec3::new(0.01, 0.0, 0.0))
}

/// The damper leaves alone the energy one sensor count can fake, |F|₁·q: W = 2 µJ is damped
/// with q at 0.99 of W/|F|₁ and left alone at 1.01 (the leak takes 0.1 % of W per tick here,
/// inside the bracket).
#[test]
fn damper_acts_only_above_one_counts_work() {
    let q_edge = 2e-6 / 2.0;
    let below = pushed(0.99 * q_edge);
    assert!(below.damping_n_s_per_m > 0.0, "{below:?}");
    let above = pushed(1.01 * q_edge);
    assert_eq!(above.damping_n_s_per_m, 0.0, "{above:?}");
    assert_eq!(above.force_n, Vec3::new(2.0, 0.0, 0.0));
    // An ideal sensor (q = 0) damps any positive energy.
    assert!(pushed(0.0).damping_n_s_per_m > 0.0);
}

/// Positive W drains by |F|₁·q per [`LEAK_S`] (here 2e-7 J per 0.1 s: 2e-10 J per tick) and
/// stops at zero; W ≤ 0 is never touched.
#[test]
fn positive_energy_leaks_one_counts_work_per_leak_time() {
    let q = 1e-7f32;
    let mut p = stage(q);
    let f = Vec3::new(2.0, 0.0, 0.0);
    let x = Vec3::new(1e-6, 0.0, 0.0);
    let _ = p.step(Vec3::ZERO, Vec3::ZERO, Vec3::ZERO);
    let _ = p.step(f, Vec3::ZERO, Vec3::ZERO);
    let w0 = p.step(f, x, Vec3::ZERO).energy_j; // 2e-6 J less one tick's leak
    let mut w = w0;
    for _ in 0..100 {
        w = p.step(f, x, Vec3::ZERO).energy_j;
    }
    let per_tick = 2.0 * q * 1e-4 / LEAK_S;
    // f32 rounding of 100 subtractions from 2e-6 J (ulp 2.3e-13 J): measured 9e-12 J off;
    // bound 3x.
    assert!((w0 - w - 100.0 * per_tick).abs() < 2.7e-11, "{w0} → {w}");
    for _ in 0..20_000 {
        w = p.step(f, x, Vec3::ZERO).energy_j;
    }
    assert_eq!(w, 0.0);
    // A passive (negative) energy keeps its value.
    let mut p = observer(0.0, 1e-4);
    let _ = p.step(f, Vec3::ZERO, Vec3::ZERO);
    let neg = p.step(f, -x, Vec3::ZERO).energy_j;
    assert!(neg < 0.0);
    assert_eq!(p.step(f, -x, Vec3::ZERO).energy_j, neg);
}

#[test]
fn quantum_is_validated() {
    let base = PassivityConfig::DEFAULT;
    let bad_q = PassivityConfig {
        position_quantum_m: -1e-9,
        ..base
    };
    assert_eq!(
        bad_q.validate(),
        Err(ParamError::Negative("position_quantum_m"))
    );
    assert_eq!(
        PassivityConfig {
            position_quantum_m: 1e-6,
            ..base
        }
        .validate(),
        Ok(())
    );
}
