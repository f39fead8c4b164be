//! The core's rolling (`Rolling<Plane>`, `<Sphere>`, `<Bowl>`, `<Cylinder>`, exact method) against
//! host-sim's independent reference: Montana's contact equations integrated by RK45 at rtol 1e-12
//! (which imports nothing from the core). Many rotation axes, fixed and wandering, on the plane, a
//! sphere, a bowl and a cylinder, each math backend with its own bound.
//!
//! Step sizes: 0.02 rad per sample takes the log map's series branch (angles up to 0.39 rad, no
//! backend function called); 0.6, 1.4 and 2.6 rad take the backend's sqrt and atan2, on both sides
//! of the atan2 octant split at π/2 (|v| < |w| and |v| > |w|), and the sphere's exp map calls its
//! sin/cos. So each backend's own code path is exercised, not three copies of the series.
//!
//! Bounds: about 3x the worst error measured by this test (run with `-- --nocapture` to print it),
//! per backend and branch; the measurement is named on each constant.

use host_sim::sim::backend::Backend;
use host_sim::sim::reference::motions::{cube_axes, motion};
use host_sim::sim::reference::{reference_paths_on, Ground, ReferenceMethod};
use nalgebra::UnitQuaternion;
use softfinger_core::contact::decompose::Method;
use softfinger_core::contact::rolling::Rolling;
use softfinger_core::contact::surface::{Bowl, Cylinder, Plane, Sphere, Surface};
use softfinger_core::{Fast, Libm, Math, Micromath, Quat};

/// Fingertip radius, m.
const RHO: f64 = 0.01;
/// Object sphere radius, m.
const BIG: f64 = 0.05;
/// Samples per run: 40 small steps, 16 large ones (the RK45 reference's cost grows with the
/// total rotation).
fn samples(step: f64) -> usize {
    if step < 0.39 {
        40
    } else {
        16
    }
}

/// Bounds (m) on the largest per-axis error of either contact point, per backend, for the series
/// branch (0.02 rad steps) and for each large step (0.6, 1.4, 2.6 rad): 3x the worst error this
/// test measured (`cargo test -p softfinger-tests --test rolling_reference -- --nocapture`, worst
/// over the 26 axes x 2 motions x 2 grounds, every case against the RK45 reference), named on each.
#[derive(Clone, Copy)]
struct Bounds {
    small: f64,
    /// At 0.6, 1.4 and 2.6 rad per step.
    large: [f64; 3],
}
/// The large steps, rad.
const LARGE_STEPS: [f64; 3] = [0.6, 1.4, 2.6];

const fn bounds(small: f64, large: [f64; 3]) -> Bounds {
    Bounds { small, large }
}

/// `BOUNDS[grounds][backend]`: grounds 0 the plane and the sphere, 1 the bowl and the cylinder (their
/// own worst); backends in [`Backend::ALL`] order. Measured at 0.02 rad, then 0.6, 1.4, 2.6 rad:
const BOUNDS: [[Bounds; 3]; 2] = [
    [
        // libm: 3.69e-9 m; 2.12e-8, 3.25e-8, 3.27e-8 m.
        bounds(1.1e-8, [6.4e-8, 9.8e-8, 9.8e-8]),
        // fast: 3.69e-9 m; 2.12e-8, 2.82e-8, 3.18e-8 m.
        bounds(1.1e-8, [6.4e-8, 8.5e-8, 9.5e-8]),
        // micromath: 8.53e-5 m (its sqrt, 6 % off, normalises the samples and the sphere's exp
        // map); 7.39e-4, 2.67e-3, 1.61e-3 m (its atan2, 2.8e-3 rad, and sqrt in the log map).
        bounds(2.6e-4, [2.2e-3, 8.0e-3, 4.8e-3]),
    ],
    [
        // libm: 6.63e-9 m; 2.46e-8, 3.77e-8, 5.94e-8 m.
        bounds(2.0e-8, [7.4e-8, 1.1e-7, 1.8e-7]),
        // fast: 6.63e-9 m; 2.46e-8, 3.10e-8, 5.94e-8 m.
        bounds(2.0e-8, [7.4e-8, 9.3e-8, 1.8e-7]),
        // micromath: 1.25e-4 m; 8.22e-4, 3.37e-3, 3.62e-3 m.
        bounds(3.8e-4, [2.5e-3, 1.0e-2, 1.1e-2]),
    ],
];

/// The grounds' names in messages, by `BOUNDS`' first index.
const GROUNDS: [&str; 2] = ["plane, sphere", "bowl, cylinder"];

fn to_q(q: &UnitQuaternion<f64>) -> Quat {
    Quat::new(q.w as f32, q.i as f32, q.j as f32, q.k as f32)
}

/// Largest per-axis error (m) of the core's object and fingertip contact points against the
/// reference rows.
fn core_error<M: Math, S: Surface>(
    surface: S,
    qs: &[UnitQuaternion<f64>],
    object: &[[f64; 3]],
    finger: &[[f64; 3]],
) -> f64 {
    let mut r = Rolling::new(surface, RHO as f32, to_q(&qs[0]), Method::Exact);
    let mut worst = 0.0f64;
    for k in 0..qs.len() {
        if k > 0 {
            let s = r.step::<M>(to_q(&qs[k]));
            assert!(s.flags.is_empty(), "step {k}: {:?}", s.flags);
        }
        let (p, f) = (r.surface().contact_point(), r.finger_point());
        for (got, want) in [(p, object[k]), (f, finger[k])] {
            for (a, b) in [got.x, got.y, got.z].iter().zip(want) {
                worst = worst.max((*a as f64 - b).abs());
            }
        }
    }
    worst
}

/// [`core_error`] for each backend, in [`Backend::ALL`] order.
fn per_backend<S: Surface + Copy>(
    surface: S,
    qs: &[UnitQuaternion<f64>],
    object: &[[f64; 3]],
    finger: &[[f64; 3]],
) -> [f64; 3] {
    Backend::ALL.map(|b| match b {
        Backend::Libm => core_error::<Libm, _>(surface, qs, object, finger),
        Backend::Fast => core_error::<Fast, _>(surface, qs, object, finger),
        Backend::Micromath => core_error::<Micromath, _>(surface, qs, object, finger),
    })
}

/// Worst error per backend over every axis and motion for one step size: `[0]` over the plane
/// and the sphere, `[1]` over the bowl and the cylinder.
fn worst_for_step(step: f64) -> [[f64; 3]; 2] {
    let mut worst = [[0.0f64; 3]; 2];
    for axis in cube_axes() {
        for wander in [false, true] {
            let qs = motion(&axis, step, samples(step), wander);
            for ground in [
                Ground::Plane,
                Ground::Sphere { radius: BIG },
                Ground::Bowl { radius: BIG },
                Ground::Cylinder { radius: BIG },
            ] {
                let method = ReferenceMethod::Rk45 {
                    rtol: 1e-12,
                    atol: 1e-14,
                };
                // Every case integrates (no closed-form fallback): the reference's starting step
                // once fell below the round-off limit on a round-off residue of the contact angle
                // (see `host_sim::sim::reference::rk45`, `initial_step`).
                let reference = reference_paths_on(ground, method, &qs, 0.01, RHO)
                    .unwrap_or_else(|e| panic!("{axis:?} wander {wander} {ground:?}: {e:?}"));
                let (o, f) = (&reference.plane, &reference.sphere);
                let e = match ground {
                    Ground::Plane => per_backend(Plane::default(), &qs, o, f),
                    Ground::Sphere { .. } => per_backend(Sphere::new(BIG as f32), &qs, o, f),
                    Ground::Bowl { .. } => per_backend(Bowl::new(BIG as f32), &qs, o, f),
                    Ground::Cylinder { .. } => per_backend(Cylinder::new(BIG as f32), &qs, o, f),
                };
                let class = usize::from(matches!(
                    ground,
                    Ground::Bowl { .. } | Ground::Cylinder { .. }
                ));
                for i in 0..3 {
                    worst[class][i] = worst[class][i].max(e[i]);
                }
            }
        }
    }
    for (name, w) in GROUNDS.iter().zip(worst) {
        let each: Vec<String> = Backend::ALL
            .iter()
            .zip(w)
            .map(|(b, e)| format!("{b} {e:.2e} m"))
            .collect();
        println!(
            "step {step} rad, {name}: worst error {} (52 cases per ground, all against the RK45 reference)",
            each.join(", ")
        );
    }
    worst
}

/// Every backend's worst error on both ground classes within its bound (`bound` picks the step's).
fn check_step(step: f64, bound: impl Fn(&Bounds) -> f64) {
    let worst = worst_for_step(step);
    for (g, ground) in GROUNDS.iter().enumerate() {
        for (k, backend) in Backend::ALL.iter().enumerate() {
            let (e, b) = (worst[g][k], bound(&BOUNDS[g][k]));
            assert!(
                e <= b,
                "step {step}, {ground}, {backend}: {e:e} m > {b:e} m"
            );
        }
    }
}

#[test]
fn small_steps_match_the_rk45_reference_on_every_axis() {
    check_step(0.02, |b| b.small);
}

#[test]
fn large_steps_match_the_rk45_reference_with_each_backends_bound() {
    for (s, step) in LARGE_STEPS.into_iter().enumerate() {
        check_step(step, |b| b.large[s]);
    }
}
