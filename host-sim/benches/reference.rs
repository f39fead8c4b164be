//! The paper's speed comparison, in one run: the classical method (Montana's equations integrated by our
//! f64 RK45) on the paper's §3.1 scene at Matlab's `ode45` defaults and at the tolerance that matches our
//! exact method's accuracy, against our exact rolling step (Libm and Fast) over the same 100 steps.
//!
//! `cargo bench -p host-sim --bench reference`. Each case is one whole pass over the 100 samples
//! (throughput in elements = steps); our pass computes both contact points each step, as the RK45
//! cases compute both paths. After criterion, the ratios are printed from one interleaved
//! measurement (the same one `host-sim validate` uses), round by round with their spread.

use criterion::{BenchmarkId, Criterion, Throughput};
use softfinger_core::contact::decompose::Method;
use softfinger_core::contact::rolling::Rolling;
use softfinger_core::contact::surface::Plane;
use softfinger_core::{Fast, Libm, Math, Quat};
use std::hint::black_box;
use std::time::Duration;

use host_sim::experiments::validate::classical::{
    self, Rk45Call, Rk45Run, SceneRef, ODE45_DEFAULTS,
};
use host_sim::experiments::validate::ours::{self, Backend, Variant};
use host_sim::experiments::validate::timing::{self, Timing};
use host_sim::experiments::validate::{closed_form, reference_for, run_ours};
use host_sim::sim::reference::scene::{paper_scene, Scene};

/// One pass: every step and both contact points after it, as the RK45 cases compute both paths.
fn pass<M: Math>(start: Rolling<Plane>, samples: &[Quat]) -> Rolling<Plane> {
    let mut r = start;
    for &q in &samples[1..] {
        black_box(r.step::<M>(black_box(q)));
        black_box((r.surface().point, r.finger_point()));
    }
    r
}

fn main() {
    let scene = paper_scene();
    let closed = closed_form(&scene).expect("closed form");
    let reference = reference_for(&scene, &closed).expect("reference").paths;
    let sref = SceneRef {
        samples: &scene.samples,
        dt: scene.dt,
        radius: scene.radius,
        closed: &closed,
    };
    let exact = Variant {
        method: Method::Exact,
        backend: Backend::Libm,
    };
    let target = run_ours(exact, &scene, &reference).errors.max_mm();
    let runs = classical_runs(sref, target);
    let samples = ours::to_f32(&scene.samples);
    let start = Rolling::new(
        Plane::default(),
        scene.radius as f32,
        samples[0],
        Method::Exact,
    );
    criterion_group(&scene, &runs, start, &samples);
    print_ratios(&runs, sref, &samples, scene.radius as f32);
}

/// The classical runs at ode45's defaults and at the tolerance matching `target` (mm), per call
/// style, each with its error printed.
fn classical_runs(sref: SceneRef<'_>, target: f64) -> Vec<(String, Rk45Run)> {
    let (rtol, atol) = ODE45_DEFAULTS;
    let mut runs: Vec<(String, Rk45Run)> = Vec::new();
    for call in [Rk45Call::Restart, Rk45Call::SingleCall] {
        let d = classical::run(sref, call, rtol, atol).expect("ode45 defaults");
        runs.push((format!("ode45-defaults/{}", call.name()), d));
        if let Some(m) = classical::matched(sref, call, target).expect("matched") {
            runs.push((format!("matched/{}", call.name()), m));
        }
    }
    eprintln!("exact/libm max error on the paper scene: {target:.2e} mm; classical runs:");
    for (name, r) in &runs {
        eprintln!(
            "  {name}: rtol {:.1e}, atol {:.1e}, max error vs closed form {:.2e} mm",
            r.rtol,
            r.atol,
            r.errors.max_mm()
        );
    }
    runs
}

/// Criterion: each classical run and our exact step (Libm, Fast), one whole pass each.
fn criterion_group(
    scene: &Scene,
    runs: &[(String, Rk45Run)],
    start: Rolling<Plane>,
    samples: &[Quat],
) {
    let mut c = Criterion::default()
        .measurement_time(Duration::from_secs(2))
        .warm_up_time(Duration::from_millis(500))
        .configure_from_args();
    {
        let mut g = c.benchmark_group("paper_scene_100_steps");
        g.throughput(Throughput::Elements((scene.samples.len() - 1) as u64));
        for (name, r) in runs {
            let (call, rtol, atol) = (r.call, r.rtol, r.atol);
            g.bench_function(BenchmarkId::new("rk45", name), |b| {
                b.iter(|| {
                    call.paths(
                        black_box(&scene.samples),
                        scene.dt,
                        scene.radius,
                        rtol,
                        atol,
                    )
                })
            });
        }
        g.bench_function(BenchmarkId::new("ours", "exact/libm"), |b| {
            b.iter(|| pass::<Libm>(black_box(start), samples))
        });
        g.bench_function(BenchmarkId::new("ours", "exact/fast"), |b| {
            b.iter(|| pass::<Fast>(black_box(start), samples))
        });
        g.finish();
    }
    c.final_summary();
}

/// The ratios from one interleaved measurement (the one `host-sim validate` uses), round by round.
fn print_ratios(runs: &[(String, Rk45Run)], sref: SceneRef<'_>, samples: &[Quat], radius: f32) {
    // Ratios from one interleaved measurement (median of 41 rounds).
    let mut cases: Vec<timing::Case<'_>> = runs.iter().map(|(_, r)| r.case(sref)).collect();
    for backend in [Backend::Libm, Backend::Fast] {
        cases.push(
            Variant {
                method: Method::Exact,
                backend,
            }
            .case(samples, radius),
        );
    }
    let rounds = timing::measure_rounds(&mut cases, Timing::STANDARD);
    let median = |v: &[f64]| {
        let mut v = v.to_vec();
        v.sort_by(f64::total_cmp);
        timing::median(&v)
    };
    let (ours, rk) = (&rounds[runs.len()..], &rounds[..runs.len()]);
    println!(
        "\nns per step (interleaved median of {} rounds, both contact points each step): \
         exact/libm {:.1}, exact/fast {:.1}",
        ours[0].len(),
        median(&ours[0]),
        median(&ours[1])
    );
    for ((name, _), t) in runs.iter().zip(rk) {
        let spread = |o: &[f64]| match timing::ratio_spread(t, o) {
            Some(s) => format!(
                "{:.1}x (quartiles {:.1}-{:.1}x, range {:.1}-{:.1}x)",
                s.median, s.q1, s.q3, s.min, s.max
            ),
            None => "n/a".to_string(),
        };
        println!(
            "  rk45 {name}: {:.0} ns per step; per round: {} exact/libm, {} exact/fast",
            median(t),
            spread(&ours[0]),
            spread(&ours[1])
        );
    }
}
