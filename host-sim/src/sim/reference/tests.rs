//! Cross-checks of the two reference methods (closed form vs Montana + RK45) on the paper's §3.1 scene and
//! on the same motion sampled at other rates. Each test prints its figures; reproduce them with
//! `cargo test -p host-sim reference::tests -- --nocapture`.

use super::montana_paths::{self, MontanaOptions};
use super::scene::{paper_scene, paper_scene_at_rate};
use super::*;

fn paths(method: ReferenceMethod, rate: f64) -> ReferencePaths {
    let s = paper_scene_at_rate(rate);
    reference_paths(method, &s.samples, s.dt, s.radius).unwrap()
}

/// Prints and returns (plane, sphere) max distances to the closed form, in m.
fn compare(label: &str, r: &ReferencePaths, exact: &ReferencePaths) -> (f64, f64) {
    let (dp, ds) = (
        max_distance(&r.plane, &exact.plane),
        max_distance(&r.sphere, &exact.sphere),
    );
    let mm = |v: [f64; 3]| v.map(|x| format!("{:.3e}", x * 1e3)).join(", ");
    eprintln!(
        "{label}: plane max |Δ| {:.3e} mm (per axis {} mm), sphere max |Δ| {:.3e} mm (per axis {} mm), \
         steps {}, rejected {}, f-evals {}, intervals {}, recharts {}",
        dp * 1e3,
        mm(max_abs_diff_per_axis(&r.plane, &exact.plane)),
        ds * 1e3,
        mm(max_abs_diff_per_axis(&r.sphere, &exact.sphere)),
        r.stats.steps,
        r.stats.rejected,
        r.stats.f_evals,
        r.stats.intervals,
        r.stats.recharts
    );
    (dp, ds)
}

#[test]
fn closed_form_paths_have_one_row_per_sample() {
    let r = paths(ReferenceMethod::ClosedForm, 100.0);
    assert_eq!(r.plane.len(), 101);
    assert_eq!(r.sphere.len(), 101);
    assert_eq!(r.stats, ReferenceStats::default());
    assert_eq!(r.plane[0], [0.0, 0.0, 0.0]);
    assert_eq!(r.sphere[0], [0.0, 0.0, -0.01]);
    assert!(r.plane.iter().all(|p| p[2] == 0.0));
    // Every sphere contact lies on the sphere (round-off only: measured 3.5e-18 m, 2 ulp of 0.01 m;
    // bound 1e-17 m, 2.9×).
    assert!(r
        .sphere
        .iter()
        .all(|p| ((p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt() - 0.01).abs() < 1e-17));
}

/// The paper scene (100 Hz) through the restarting RK45 at (`rtol`, `atol`): the paths and their
/// largest distances (m) from the closed form on the plane and on the sphere.
fn rk45_on_paper_scene(rtol: f64, atol: f64) -> (ReferencePaths, f64, f64) {
    let exact = paths(ReferenceMethod::ClosedForm, 100.0);
    let r = paths(ReferenceMethod::Rk45 { rtol, atol }, 100.0);
    let (dp, ds) = compare(
        &format!("paper scene, rtol {rtol:e} atol {atol:e}"),
        &r,
        &exact,
    );
    (r, dp, ds)
}

#[test]
fn rk45_tight_tolerance_matches_closed_form_on_paper_scene() {
    // rtol 1e-12, atol 1e-14 on states of size ≤ ~1 rad and ≤ ~1e-2 m. The RK45 tests show global errors of
    // ~0.2–9·tol per unit of motion, so ~1e-14 m is expected here (measured 6.3e-15 m on the plane,
    // 2.1e-15 m on the sphere). Bounds 3×: 1.9e-14 m and 6.4e-15 m.
    let (r, dp, ds) = rk45_on_paper_scene(1e-12, 1e-14);
    assert!(dp < 1.9e-14 && ds < 6.4e-15);
    assert_eq!(r.plane.len(), 101);
    assert!(r.plane.iter().all(|p| p[2] == 0.0));
    assert_eq!(r.stats.intervals, 100);
}

#[test]
fn rk45_matlab_default_tolerance_on_paper_scene() {
    // rtol 1e-3, atol 1e-6 (Matlab's defaults). Restarting at every 10 ms sample, one Dormand–Prince step
    // spans a whole interval (a rotation of ~0.06 rad): its estimated local error, ~ρ·(0.06)^6 ~ 5e-10 m,
    // is far below the tolerance, so the step is limited by the interval, not by the tolerance, and the
    // result is the one-step-per-interval solution. Expected error: ~100 steps × ≲1e-11 m
    // (measured 6.3e-12 m plane, 2.5e-12 m sphere, i.e. ~6e-9 mm). Bounds 3×: 1.9e-11 m and 7.6e-12 m;
    // and at most 10 steps more than intervals (the first interval's starting step is smaller;
    // measured 104 steps for 100 intervals).
    let (r, dp, ds) = rk45_on_paper_scene(1e-3, 1e-6);
    assert!(dp < 1.9e-11 && ds < 7.6e-12);
    assert!(r.stats.steps <= r.stats.intervals + 10, "{:?}", r.stats);
}

#[test]
fn matlab_ode45_emulations_on_paper_scene() {
    // How the paper's ODE45 figure depends on how ode45 is called, at Matlab's default tolerances.
    let exact = paths(ReferenceMethod::ClosedForm, 100.0);
    let s = paper_scene();

    // (a) `ode45(f, 0:dt:1, y0)`: one call, outputs interpolated at the samples. Error bound argued in
    // `montana_paths::tests::single_call_emulation` (measured 5.45e-5 m plane, 3.12e-5 m sphere; bounds
    // 3×).
    let one = paths(
        ReferenceMethod::MatlabOde45 {
            rtol: 1e-3,
            atol: 1e-6,
        },
        100.0,
    );
    let (dp, ds) = compare(
        "paper scene, ode45-like single call, rtol 1e-3 atol 1e-6",
        &one,
        &exact,
    );
    assert!(dp < 1.6e-4 && ds < 9.3e-5);
    assert_eq!(one.stats.intervals, 1);
    assert_eq!(one.plane.len(), 101);

    // (b) `ode45(f, [t_k, t_k+dt], y_k)` once per sample: MaxStep = dt/10 forces ≥ 10 steps of ≤ 6 mrad
    // per sample, so the error is at round-off level whatever the tolerance (measured 3.7e-16 m plane,
    // 2.9e-17 m sphere; bounds 3×: 1.1e-15 m and 8.7e-17 m), and ≥ 1000 steps (measured 1004).
    let run = montana_paths::integrate(
        s.radius,
        surface::Surface::Plane,
        [0.0, 0.0],
        &s.samples,
        s.dt,
        &MontanaOptions::matlab_like_per_interval(1e-3, 1e-6, s.dt),
    )
    .unwrap();
    let per = ReferencePaths::from_run(&run);
    let (dp, ds) = compare(
        "paper scene, ode45-like call per sample, rtol 1e-3 atol 1e-6",
        &per,
        &exact,
    );
    assert!(dp < 1.1e-15 && ds < 8.7e-17);
    assert!(per.stats.steps >= 1000);
}

#[test]
fn rk45_tight_tolerance_matches_closed_form_at_higher_rates() {
    // The same motion sampled at 1 kHz and 20 kHz: each sample interval is one step; the error grows with
    // the number of steps through round-off (~ε·1e-2 m per step). Measured: plane 1.7e-16 m at 1 kHz,
    // 1.7e-15 m at 20 kHz; sphere 6.2e-17 m and 2.2e-16 m. Bounds 3× each.
    for (rate, bound_plane, bound_sphere) in
        [(1000.0, 5e-16, 1.9e-16), (20_000.0, 5.1e-15, 6.6e-16)]
    {
        let exact = paths(ReferenceMethod::ClosedForm, rate);
        let r = paths(
            ReferenceMethod::Rk45 {
                rtol: 1e-12,
                atol: 1e-14,
            },
            rate,
        );
        let (dp, ds) = compare(&format!("{rate} Hz, rtol 1e-12 atol 1e-14"), &r, &exact);
        assert!(dp < bound_plane && ds < bound_sphere, "{rate} Hz");
        assert_eq!(r.plane.len(), rate as usize + 1);
    }
}

#[test]
fn rk45_on_a_sphere_ground_matches_closed_form() {
    // Fingertip (10 mm) on a 50 mm sphere, the paper's motion, rtol 1e-12: measured 1.57e-15 m on the
    // ground sphere, 5.3e-16 m on the fingertip; bounds 3×.
    let s = paper_scene();
    let ground = Ground::Sphere { radius: 0.05 };
    let exact = reference_paths_on(
        ground,
        ReferenceMethod::ClosedForm,
        &s.samples,
        s.dt,
        s.radius,
    )
    .unwrap();
    let r = reference_paths_on(
        ground,
        ReferenceMethod::Rk45 {
            rtol: 1e-12,
            atol: 1e-14,
        },
        &s.samples,
        s.dt,
        s.radius,
    )
    .unwrap();
    let (dp, ds) = compare("sphere ground R 50 mm, rtol 1e-12", &r, &exact);
    assert!(dp < 4.7e-15 && ds < 1.6e-15);
    assert_eq!(exact.plane[0], [0.0, 0.0, 0.05]);
}

#[test]
fn invalid_inputs_are_reported() {
    let s = paper_scene();
    let bad =
        |dt: f64, radius: f64| reference_paths(ReferenceMethod::ClosedForm, &s.samples, dt, radius);
    assert_eq!(bad(0.0, 0.01), Err(ReferenceError::InvalidInput));
    assert_eq!(bad(0.01, -1.0), Err(ReferenceError::InvalidInput));
    assert_eq!(bad(f64::NAN, 0.01), Err(ReferenceError::InvalidInput));
    assert_eq!(
        reference_paths_on(
            Ground::Sphere { radius: 0.0 },
            ReferenceMethod::ClosedForm,
            &s.samples,
            0.01,
            0.01
        ),
        Err(ReferenceError::InvalidInput)
    );
    assert_eq!(
        reference_paths(
            ReferenceMethod::Rk45 {
                rtol: 0.0,
                atol: 1e-6
            },
            &s.samples,
            0.01,
            0.01
        ),
        Err(ReferenceError::Integration(rk45::Rk45Error::InvalidOptions))
    );
    let empty = reference_paths(
        ReferenceMethod::Rk45 {
            rtol: 1e-3,
            atol: 1e-6,
        },
        &[],
        0.01,
        0.01,
    )
    .unwrap();
    assert!(empty.plane.is_empty() && empty.sphere.is_empty());
}

#[test]
fn path_difference_helpers() {
    let a = [[0.0, 1.0, 2.0], [1.0, 1.0, 1.0]];
    let b = [[0.5, 1.0, 2.0], [1.0, -1.0, 1.0]];
    assert_eq!(max_abs_diff_per_axis(&a, &b), [0.5, 2.0, 0.0]);
    assert_eq!(max_distance(&a, &b), 2.0);
}
