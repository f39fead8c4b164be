//! Tests of the RK45 integrator (the sibling `rk45.rs`).

use super::*;

/// y' = −λ y, λ = 2: y(t) = y0·exp(−λ t).
fn decay(_t: f64, y: &[f64; 1]) -> [f64; 1] {
    [-2.0 * y[0]]
}

/// Harmonic oscillator y0' = y1, y1' = −y0: (cos t, −sin t) from (1, 0).
fn oscillator(_t: f64, y: &[f64; 2]) -> [f64; 2] {
    [y[1], -y[0]]
}

fn osc_error(y: &[f64; 2], t: f64) -> f64 {
    (y[0] - t.cos()).abs().max((y[1] + t.sin()).abs())
}

#[test]
fn decay_global_error_follows_tolerance() {
    // y(5) = exp(−10) ≈ 4.5e-5 from y(0) = 1. With rtol = atol = tol each local error is at most about
    // tol·(1 + |y|) and the decay damps earlier ones, so the global error is a fraction of tol.
    // Measured err/tol per tolerance: 0.028, 0.12, 0.13, 0.18, 0.19 (2.8e-5 at 1e-3 .. 1.9e-12 at
    // 1e-11). Asserted: the specification err ≤ tol, and each tolerance's own measured ratio, bound
    // 3×. The error tracks the tolerance: measured 23×, 89×, 75×, 95× smaller per two decades of
    // tolerance; asserted at least 10× (2.3× below the worst, the 1e-3 → 1e-5 drop, where the
    // 1e-3 run is not yet asymptotic).
    let exact = (-10.0f64).exp();
    let mut prev = f64::INFINITY;
    for (tol, measured) in [
        (1e-3, 0.028),
        (1e-5, 0.12),
        (1e-7, 0.13),
        (1e-9, 0.18),
        (1e-11, 0.19),
    ] {
        let mut rk = Rk45::new(Options::<1>::uniform(tol, tol)).unwrap();
        let mut y = [1.0];
        rk.integrate(decay, 0.0, 5.0, &mut y).unwrap();
        let err = (y[0] - exact).abs();
        assert!(err <= tol, "tol {tol}: err {err}");
        assert!(err <= 3.0 * measured * tol, "tol {tol}: err {err}");
        assert!(
            err < prev / 10.0,
            "tol {tol}: err {err} did not drop from {prev}"
        );
        prev = err;
    }
}

#[test]
fn oscillator_global_error_follows_tolerance() {
    // Over t ∈ [0, 20] (about 3 periods) the oscillator neither damps nor amplifies errors, so the
    // global error accumulates the local ones; with local extrapolation the error per unit time is
    // proportional to tol, so err/tol stays roughly constant. Measured err/tol per tolerance: 8.6,
    // 5.4, 5.4, 5.7, 5.8 (8.6e-4 at 1e-4 .. 5.8e-12 at 1e-12); asserted: each tolerance's own ratio,
    // bound 3×. Measured 160×, 99×, 96×, 98× less error per two decades of tolerance; asserted at
    // least 30× (3.2× below the worst, 96×).
    let t_end = 20.0;
    let mut prev = f64::INFINITY;
    let mut prev_steps = 0;
    for (tol, measured) in [
        (1e-4, 8.6),
        (1e-6, 5.4),
        (1e-8, 5.4),
        (1e-10, 5.7),
        (1e-12, 5.8),
    ] {
        let mut rk = Rk45::new(Options::<2>::uniform(tol, tol)).unwrap();
        let mut y = [1.0, 0.0];
        rk.integrate(oscillator, 0.0, t_end, &mut y).unwrap();
        let err = osc_error(&y, t_end);
        assert!(err <= 3.0 * measured * tol, "tol {tol}: err {err}");
        assert!(
            err < prev / 30.0,
            "tol {tol}: err {err} did not drop from {prev}"
        );
        // A 5th-order method needs ~100^(1/5) ≈ 2.5× more steps per two decades of tolerance.
        let steps = rk.stats().accepted;
        assert!(steps > prev_steps, "steps must grow as tol shrinks");
        prev = err;
        prev_steps = steps;
    }
}

#[test]
fn fsal_evaluation_count() {
    // Each attempt costs 6 evaluations, plus 1 for the first stage and 1 for the starting step.
    let mut rk = Rk45::new(Options::<2>::uniform(1e-8, 1e-8)).unwrap();
    let mut y = [1.0, 0.0];
    rk.integrate(oscillator, 0.0, 3.0, &mut y).unwrap();
    let s = rk.stats();
    assert!(s.accepted > 0);
    assert_eq!(s.f_evals, 6 * (s.accepted + s.rejected) + 2);
    assert_eq!(s.intervals, 1);
}

#[test]
fn fifth_order_convergence_fixed_step() {
    // Global error of the fixed-step 5th-order solution ~ C·h^5: halving h divides it by ~32.
    // Observed order from three step sizes on the oscillator over [0, 2]: measured 5.056 (h = 1/4 →
    // 1/8) and 5.048 (1/8 → 1/16), i.e. 0.056 off the theoretical 5 at worst (the asymptotic regime
    // is reached at these step sizes and the smallest error, ≈ 5e-10, is far above round-off).
    // Asserted: within ±0.17 of 5, 3× the measured deviation.
    let t_end = 2.0;
    let errs: Vec<f64> = [8u32, 16, 32]
        .iter()
        .map(|&n| {
            osc_error(
                &integrate_fixed(oscillator, 0.0, t_end, n, [1.0, 0.0]),
                t_end,
            )
        })
        .collect();
    for w in errs.windows(2) {
        let order = (w[0] / w[1]).log2();
        assert!(
            (order - 5.0).abs() < 0.17,
            "observed order {order}, errors {errs:?}"
        );
    }
}

#[test]
fn embedded_error_estimate_is_fourth_order_local() {
    // The error estimate is the difference to the 4th-order solution, whose local error is O(h^5):
    // halving h divides the estimate by ~32 (measured log2 ratio 4.9978, 0.0022 off 5; asserted
    // within ±0.007 of 5, 3× the measured deviation).
    let mut f = oscillator;
    let y = [1.0, 0.0];
    let k1 = f(0.0, &y);
    let e1 = dopri5_step(&mut f, 0.0, &y, 0.2, &k1).err;
    let e2 = dopri5_step(&mut f, 0.0, &y, 0.1, &k1).err;
    let (e1, e2) = (e1[0].abs().max(e1[1].abs()), e2[0].abs().max(e2[1].abs()));
    let order = (e1 / e2).log2();
    assert!((order - 5.0).abs() < 0.007, "estimate order {order}");
}

#[test]
fn continuous_extension_is_consistent_and_fourth_order() {
    // s = 0 gives y, s = 1 gives the 5th-order solution (each BI row sums to b_j; the sums are formed
    // differently: measured 1.1e-16 and 3.9e-16 (1 and 3.5 ulp of the O(1) values), bounds 3×).
    // In between the extension is 4th order: its local error at s = 1/2 is O(h^5), so halving h divides
    // it by ~32 (measured log2 ratio 4.983, 0.017 off 5; asserted within ±0.05 of 5, 3×).
    let mut f = oscillator;
    let y = [1.0, 0.0];
    let k1 = f(0.0, &y);
    let step = dopri5_step(&mut f, 0.0, &y, 0.3, &k1);
    assert_eq!(interpolate(&y, 0.3, &step, 0.0), y);
    let end = interpolate(&y, 0.3, &step, 1.0);
    assert!((end[0] - step.y_new[0]).abs() < 3.3e-16);
    assert!((end[1] - step.y_new[1]).abs() < 1.2e-15);
    let mut mid_err = |h: f64| {
        let step = dopri5_step(&mut f, 0.0, &y, h, &k1);
        osc_error(&interpolate(&y, h, &step, 0.5), h / 2.0)
    };
    let (e1, e2) = (mid_err(0.4), mid_err(0.2));
    let order = (e1 / e2).log2();
    eprintln!("interpolant local error order {order} ({e1:e}, {e2:e})");
    assert!((order - 5.0).abs() < 0.05, "{order}");
}

#[test]
fn dense_output_at_requested_times() {
    // Matlab-style tspan: outputs at 0, 0.1, …, 5 from one call. The interpolant is 4th order while the
    // steps are 5th order, so between steps the error may exceed the step-end error; at
    // rtol = atol = 1e-8 it must still be ~tol: measured 4.4e-9 at worst over the 51 outputs;
    // bound 3×: 1.3e-8.
    let times: Vec<f64> = (0..=50).map(|i| f64::from(i) * 0.1).collect();
    let mut rk = Rk45::new(Options::<1>::uniform(1e-8, 1e-8)).unwrap();
    let mut y = [1.0];
    let mut out = Vec::new();
    // Out-of-range times are skipped.
    let mut requested = vec![-1.0];
    requested.extend(&times);
    requested.push(7.0);
    rk.integrate_dense(decay, 0.0, 5.0, &mut y, &requested, &mut out)
        .unwrap();
    assert_eq!(out.len(), times.len());
    assert_eq!(out[0], [1.0]);
    assert_eq!(out.last().copied(), Some(y));
    for (t, v) in times.iter().zip(&out) {
        assert!((v[0] - (-2.0 * t).exp()).abs() < 1.3e-8, "t {t}");
    }
    // Far fewer steps than outputs: the outputs do not restart the integration.
    assert!(rk.stats().accepted < 50, "{:?}", rk.stats());
}

#[test]
fn piecewise_constant_input_hits_sample_times() {
    // y' = u_k − y on [k·dt, (k+1)·dt] with u_k piecewise constant has the exact update
    // y_{k+1} = u_k + (y_k − u_k)·exp(−dt). 50 intervals at rtol = atol = 1e-12: the exact solution is a
    // contraction, so the accumulated error stays within ~10·tol per interval at most. Measured
    // 3.4e-14 at worst over the 50 intervals; bound 3×: 1e-13.
    let dt = 0.05;
    let mut rk = Rk45::new(Options::<1>::uniform(1e-12, 1e-12)).unwrap();
    let mut y = [0.3];
    let mut exact = 0.3;
    for k in 0..50 {
        let u = (k as f64 * 0.7).sin() * 2.0;
        let t0 = k as f64 * dt;
        rk.integrate(|_t, y: &[f64; 1]| [u - y[0]], t0, t0 + dt, &mut y)
            .unwrap();
        exact = u + (exact - u) * (-dt).exp();
        assert!((y[0] - exact).abs() < 1e-13, "interval {k}");
    }
    let s = rk.stats();
    assert_eq!(s.intervals, 50);
    // One fresh first stage per interval plus one starting-step evaluation (first interval only).
    assert_eq!(s.f_evals, 6 * (s.accepted + s.rejected) + 50 + 1);
}

#[test]
fn fresh_start_on_every_interval_costs_one_more_evaluation_each() {
    let mut opts = Options::<1>::uniform(1e-9, 1e-9);
    opts.reuse_step = false;
    let mut rk = Rk45::new(opts).unwrap();
    let mut y = [1.0];
    for k in 0..10 {
        let t0 = f64::from(k) * 0.1;
        rk.integrate(decay, t0, t0 + 0.1, &mut y).unwrap();
    }
    let s = rk.stats();
    assert_eq!(s.f_evals, 6 * (s.accepted + s.rejected) + 2 * 10);
    // Measured 1.3e-10 off exp(−2) at rtol = atol = 1e-9; bound 3×.
    assert!((y[0] - (-2.0f64).exp()).abs() < 4e-10);
}

#[test]
fn h_max_limits_the_step() {
    // With h_max = span/10 (Matlab's default) an interval takes at least 10 steps.
    let mut opts = Options::<1>::uniform(1e-3, 1e-6);
    opts.h_max = 0.1;
    let mut rk = Rk45::new(opts).unwrap();
    let mut y = [1.0];
    rk.integrate(decay, 0.0, 1.0, &mut y).unwrap();
    assert!(rk.stats().accepted >= 10);
}

#[test]
fn error_scale_forms() {
    // atol = 1e-6, rtol = 1e-3, |y| = 0.01, |y_new| = 0.02: sum 1e-6 + 2e-5, Matlab max(1e-6, 2e-5).
    let mut opts = Options::<1>::uniform(1e-3, 1e-6);
    let sum = Rk45::new(opts).unwrap().scale(0, 0.01, -0.02);
    opts.scale = ErrorScale::MatlabMax;
    let max = Rk45::new(opts).unwrap().scale(0, 0.01, -0.02);
    // The sum is one rounding away from the literal: measured 3.4e-21, 1 ulp of 2.1e-5; bound 3×.
    // The max is the product 1e-3·0.02, measured equal to the literal 2e-5.
    assert!((sum - 2.1e-5).abs() < 1e-20);
    assert_eq!(max, 2.0e-5);
}

#[test]
fn rejects_bad_options_and_intervals() {
    assert_eq!(
        Rk45::new(Options::<1>::uniform(0.0, 1e-6)).err(),
        Some(Rk45Error::InvalidOptions)
    );
    assert_eq!(
        Rk45::new(Options::<1>::uniform(1e-3, f64::NAN)).err(),
        Some(Rk45Error::InvalidOptions)
    );
    let mut rk = Rk45::new(Options::<1>::uniform(1e-3, 1e-6)).unwrap();
    let mut y = [1.0];
    assert_eq!(
        rk.integrate(decay, 1.0, 0.0, &mut y),
        Err(Rk45Error::InvalidInterval)
    );
    assert_eq!(
        rk.integrate(|_, _| [f64::NAN], 0.0, 1.0, &mut y),
        Err(Rk45Error::NonFinite { t: 0.0 })
    );
    // A zero-length interval is a no-op.
    rk.integrate(decay, 2.0, 2.0, &mut y).unwrap();
    assert_eq!(y, [1.0]);
}

#[test]
fn blow_up_reports_step_too_small() {
    // y' = y², y(0) = 1 blows up at t = 1: the integrator must stop with an error, not loop or lie.
    let mut rk = Rk45::new(Options::<1>::uniform(1e-8, 1e-8)).unwrap();
    let mut y = [1.0];
    let r = rk.integrate(|_, y: &[f64; 1]| [y[0] * y[0]], 0.0, 2.0, &mut y);
    assert!(
        matches!(r, Err(Rk45Error::StepTooSmall { t, .. }) if (t - 1.0).abs() < 1e-3)
            || matches!(r, Err(Rk45Error::TooManySteps { .. })),
        "{r:?}"
    );
}

#[test]
fn a_round_off_residue_state_still_starts() {
    // y' = 10, y(0) = 1e-16 (zero but for a round-off residue) at atol 1e-14: Hairer's probe
    // 0.01·‖y0‖/‖f0‖ = 0.01·1e-2/1e15 = 1e-19 s, capped start 100·h0 = 1e-17 s, below the round-off
    // limit 16·eps·0.01 = 3.6e-17 s: the old test ‖y0‖ < 1e-5 stopped here with `StepTooSmall`.
    // The solution is linear, so the 5th-order result is exact up to round-off: y(0.01) = 0.1 to
    // within a few ulps: measured 9.7e-17 (7 ulp of 0.1); bound 3×: 3e-16.
    let mut rk = Rk45::new(Options::<1>::uniform(1e-12, 1e-14)).unwrap();
    let mut y = [1e-16];
    rk.integrate(|_, _| [10.0], 0.0, 0.01, &mut y).unwrap();
    assert!((y[0] - 0.1).abs() < 3e-16, "{}", y[0]);
    // Exactly at the threshold and just above it (‖y0‖ = 1 and 1.5 in tolerance units) the probe is
    // Hairer's relative one; both start and reach the end, measured exactly at 0.1 + y0.
    for y0 in [1.0e-14, 1.5e-14] {
        let mut rk = Rk45::new(Options::<1>::uniform(1e-12, 1e-14)).unwrap();
        let mut y = [y0];
        rk.integrate(|_, _| [10.0], 0.0, 0.01, &mut y).unwrap();
        assert_eq!(y[0], 0.1 + y0, "{y0:e}");
    }
}
