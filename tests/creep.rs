//! No creep at rest in closed loop: the core's controller against the plant, a hand pressing 1 mm
//! with the wrist tilted and twisted, then holding still. Self-contained (it builds its own hand
//! script and runs `host_sim::sim::closed_loop::simulate` through `host_sim::experiments::creep`), so it ports to any
//! loop that exposes the contact model's anchor.

use host_sim::experiments::creep::closed_loop_hold;
use softfinger_core::contact::decompose::Method;
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
        // One encoder count of displacement: K_t × 12.7 µm (the Omega-like delta at the centre):
        // measured 2.2e-6 N off the quoted 0.01274 N; bound 3×.
        assert!((h.one_count_n - 0.01274).abs() < 6.6e-6, "{h:?}");
    }
    let h = closed_loop_hold::<Libm>(Method::Exact, 3.0).unwrap();
    assert_eq!(h.still_anchor_walk_n, 0.0, "libm: {h:?}");
}

/// Issue 12's closed-loop criterion: a hand pressing and holding still, the rendered tangential
/// force stays below the force of one encoder count of displacement (K_t × 12.7 µm = 0.0127 N),
/// with the shipped pipeline (passivity on), the exact method, every backend, over a 20 s hold
/// (`host-sim creep --seconds 0.001 --held-ticks 1 --hold-s 60` prints the 60 s for every
/// backend).
///
/// The motor counts under the hand dither (thousands of count changes in 20 s), and where a
/// dithering count moves the probe sideways, its one-count step is rendered: the tangential spring
/// on the probe's offset from the anchor (elastic part, at most one count's force) plus the
/// tangential damping on the filtered velocity of that step, which decays within a few ticks.
/// Which counts dither depends on where the equilibrium falls on the encoder grid, so it differs
/// between backends: with libm only normal ones do (largest force 5.3e-5 N), with micromath and
/// Fast sideways ones do too (largest 0.027 / 0.043 N, of which 0.0104 / 0.0103 N elastic).
/// Creep would show as the anchor walking and the elastic force and its mean growing; asserted,
/// per backend:
/// - the anchor does not walk;
/// - the elastic part stays below one count's force (the criterion; the quantisation
///   transients of the damping term are the encoder's, not the contact model's);
/// - both window means stay below one count's force, and their change below 3x the measured
///   change for that backend (named next to each bound below).
///
/// With the hand's reference drifting along x (a test hook in `host_sim::experiments::creep::hold_scene`, the
/// probe walking relative to the anchor as creep would make it) the change is 3.2e-3 N at issue
/// 12's 0.65 µm/s and 4.7e-4 N at 0.05 µm/s (libm, measured over 20 s): both caught.
#[test]
fn a_held_finger_renders_no_mean_tangential_force_growth() {
    use host_sim::experiments::creep::hold_quantisation::{measure, HoldSetup};
    use host_sim::sim::backend::Backend;
    use softfinger_core::Micromath;
    const ONE_COUNT_N: f64 = 0.01274;
    let setup = |drift| HoldSetup {
        hold_s: 20.0,
        passivity: true,
        drift_m_per_s: drift,
        window_s: 5.0,
    };
    // Change bounds: 3x the change measured with this setup (20 s, 5 s windows): libm 5.29e-5 N,
    // micromath 2.48e-6 N, Fast 2.63e-5 N. The slowest drift below makes 4.7e-4 N, above all three.
    // (libm measured 1.74e-9 N while the hold armed 2 mm above the plane; the device now refuses
    // that Arm as inside the surface, so the hold arms 20 mm above and approaches, and libm's
    // sideways counts dither as the other backends' do.)
    let libm = measure::<Libm>(setup(0.0)).unwrap();
    for (name, still, change_bound_n) in [
        (Backend::Libm, libm, 1.6e-4),
        (
            Backend::Micromath,
            measure::<Micromath>(setup(0.0)).unwrap(),
            7.4e-6,
        ),
        (Backend::Fast, measure::<Fast>(setup(0.0)).unwrap(), 7.9e-5),
    ] {
        eprintln!("{name} still: {still:?}");
        assert_eq!(still.anchor_walk_m, 0.0, "{name}: {still:?}");
        assert!(
            still.count_changes > 1000,
            "{name}: the counts dither: {still:?}"
        );
        assert!(still.max_elastic_n < ONE_COUNT_N, "{name}: {still:?}");
        assert!(
            still.max_elastic_n <= still.max_n + 1e-12,
            "{name}: {still:?}"
        );
        assert!(
            still.first_mean_n < ONE_COUNT_N && still.last_mean_n < ONE_COUNT_N,
            "{name}: {still:?}"
        );
        assert!(still.mean_change_n < change_bound_n, "{name}: {still:?}");
    }
    // The whole force with libm stays within 0.13 N, 3x the measured 0.043 N (the sideways
    // dither; its mean stays below one count's force, checked above).
    assert!(libm.max_n < 0.13, "{libm:?}");
    for drift in [0.05e-6, 0.65e-6] {
        let d = measure::<Libm>(setup(drift)).unwrap();
        eprintln!("drift {drift:e} m/s: {d:?}");
        assert_eq!(d.anchor_walk_m, 0.0, "{d:?}");
        assert!(
            d.mean_change_n > 1.6e-4,
            "{drift:e}: caught by every backend's bound: {d:?}"
        );
    }
}
