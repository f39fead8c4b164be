//! No creep at rest in closed loop: the core's controller against the plant, a hand pressing 1 mm
//! with the wrist tilted and twisted, then holding still. Self-contained (it builds its own hand
//! script and runs `host_sim::closed_loop::simulate` through `host_sim::creep`), so it ports to any
//! loop that exposes the contact model's anchor.

use host_sim::creep::closed_loop_hold;
use softfinger_core::decompose::Method;
use softfinger_core::{Fast, Libm};

/// 3 s of hold (`host-sim creep --hold-s 60` runs the 60 s): the rolling anchor does not
/// move at all with the wrist still (before the fix it walked 33 µm, 0.033 N of phantom force, in
/// 60 s; see `host-sim creep`); with one wrist count dithering every tick it only alternates
/// between its two positions one roll step apart, ρ·(2π/4096) = 15.3 µm, i.e. K_t·15.3 µm =
/// 0.0153 N (measured 0.01534 N; the bound 1.01x that step would fail on any walk beyond it).
#[test]
fn a_held_finger_does_not_creep_in_closed_loop() {
    for method in [Method::Exact, Method::Rpy] {
        let h = closed_loop_hold::<Fast>(method, 3.0).unwrap();
        assert_eq!(h.still_anchor_walk_n, 0.0, "{method:?} still: {h:?}");
        let step_n = 1000.0 * 0.01 * std::f64::consts::TAU / 4096.0;
        assert!(
            h.dither_anchor_walk_n <= 1.01 * step_n,
            "{method:?} dither: {h:?}"
        );
        assert!(
            h.dither_anchor_walk_n >= 0.99 * step_n,
            "{method:?} the dither rolls: {h:?}"
        );
        // One encoder count of displacement: K_t × 12.7 µm (the Omega-like delta at the centre).
        assert!((h.one_count_n - 0.01274).abs() < 1e-4, "{h:?}");
    }
    let h = closed_loop_hold::<Libm>(Method::Exact, 3.0).unwrap();
    assert_eq!(h.still_anchor_walk_n, 0.0, "libm: {h:?}");
}

/// Issue 12's closed-loop criterion: a hand pressing and holding still, the rendered tangential
/// force stays below the force of one encoder count of displacement (0.0127 N), with the shipped
/// pipeline (passivity on), libm, exact method, over a 20 s hold (`host-sim creep --seconds 0.001
/// --held-ticks 1 --hold-s 20` prints the same run; `--hold-s 60` the 60 s: max 5.34e-5 N,
/// mean change 4.1e-9 N). The motor counts under the hand still dither (2 206 count changes in
/// 20 s); before the passivity observer forgave one count of dither (see
/// `softfinger_core::pipeline::passivity`) its damper fired on every flip, 1.3 N. Asserted:
/// - the anchor does not walk;
/// - the largest tangential force stays below one count's force, and below 1.6e-4 N: 3x the
///   measured 5.34e-5 N;
/// - the change between the mean force over the first and the last 5 s stays below 5.2e-9 N: 3x
///   the measured 1.74e-9 N.
///
/// With the hand's reference drifting along x (a test hook in `host_sim::creep::hold_scene`, the
/// probe walking relative to the anchor as creep would make it) the change is 3.2e-3 N at issue
/// 12's 0.65 µm/s and 4.7e-4 N at 0.05 µm/s (measured over 20 s): both caught.
#[test]
fn a_held_finger_renders_no_mean_tangential_force_growth() {
    use host_sim::hold_quantisation::{measure, HoldSetup};
    const ONE_COUNT_N: f64 = 0.01274;
    const MAX_BOUND_N: f64 = 1.6e-4;
    const CHANGE_BOUND_N: f64 = 5.2e-9;
    let setup = |drift| HoldSetup {
        hold_s: 20.0,
        passivity: true,
        drift_m_per_s: drift,
        window_s: 5.0,
    };
    let still = measure::<Libm>(setup(0.0)).unwrap();
    eprintln!("still: {still:?}");
    assert_eq!(still.anchor_walk_m, 0.0, "{still:?}");
    assert!(still.count_changes > 1000, "the counts dither: {still:?}");
    // The derived bound is the tighter of the two (one count: 0.0127 N).
    const _: () = assert!(MAX_BOUND_N < ONE_COUNT_N);
    assert!(
        still.max_n < MAX_BOUND_N,
        "tangential force during the hold: {still:?}"
    );
    assert!(still.first_mean_n < ONE_COUNT_N && still.last_mean_n < ONE_COUNT_N);
    assert!(still.mean_change_n < CHANGE_BOUND_N, "{still:?}");
    for drift in [0.05e-6, 0.65e-6] {
        let d = measure::<Libm>(setup(drift)).unwrap();
        eprintln!("drift {drift:e} m/s: {d:?}");
        assert_eq!(d.anchor_walk_m, 0.0, "{d:?}");
        assert!(d.mean_change_n > CHANGE_BOUND_N, "{drift:e}: {d:?}");
    }
}
