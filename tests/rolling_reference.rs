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

use host_sim::reference::{reference_paths_on, Ground, ReferenceMethod};
use nalgebra::{UnitQuaternion, Vector3};
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
struct Bounds {
    small: f64,
    /// At 0.6, 1.4 and 2.6 rad per step.
    large: [f64; 3],
}
/// The large steps, rad.
const LARGE_STEPS: [f64; 3] = [0.6, 1.4, 2.6];
/// libm: measured 3.69e-9 m (0.02 rad steps); 2.12e-8, 3.25e-8, 3.27e-8 m (0.6, 1.4, 2.6 rad).
const LIBM: Bounds = Bounds {
    small: 1.1e-8,
    large: [6.4e-8, 9.8e-8, 9.8e-8],
};
/// fast: measured 3.69e-9 m (0.02 rad steps); 2.12e-8, 2.82e-8, 3.18e-8 m (0.6, 1.4, 2.6 rad).
const FAST: Bounds = Bounds {
    small: 1.1e-8,
    large: [6.4e-8, 8.5e-8, 9.5e-8],
};
/// micromath: measured 8.53e-5 m (0.02 rad steps: its sqrt, 6 % off, normalises the samples and
/// the sphere's exp map); 7.39e-4, 2.67e-3, 1.61e-3 m (0.6, 1.4, 2.6 rad: its atan2, 2.8e-3 rad,
/// and sqrt in the log map).
const MICROMATH: Bounds = Bounds {
    small: 2.6e-4,
    large: [2.2e-3, 8.0e-3, 4.8e-3],
};
/// The bowl and the cylinder (same test, their own worst), libm: measured 6.63e-9 m (0.02 rad);
/// 2.46e-8, 3.77e-8, 5.94e-8 m (0.6, 1.4, 2.6 rad).
const CURVED_LIBM: Bounds = Bounds {
    small: 2.0e-8,
    large: [7.4e-8, 1.1e-7, 1.8e-7],
};
/// Bowl and cylinder, fast: measured 6.63e-9 m (0.02 rad); 2.46e-8, 3.10e-8, 5.94e-8 m.
const CURVED_FAST: Bounds = Bounds {
    small: 2.0e-8,
    large: [7.4e-8, 9.3e-8, 1.8e-7],
};
/// Bowl and cylinder, micromath: measured 1.25e-4 m (0.02 rad); 8.22e-4, 3.37e-3, 3.62e-3 m.
const CURVED_MICROMATH: Bounds = Bounds {
    small: 3.8e-4,
    large: [2.5e-3, 1.0e-2, 1.1e-2],
};

/// The 26 cube directions ([`Vec3::CUBE_DIRECTIONS`]), normalised in f64.
fn axes() -> Vec<Vector3<f64>> {
    let f = |d: softfinger_core::Vec3| Vector3::new(d.x as f64, d.y as f64, d.z as f64).normalize();
    softfinger_core::Vec3::CUBE_DIRECTIONS
        .iter()
        .map(|&d| f(d))
        .collect()
}

/// Orientation samples: from the identity (the reference starts its charts there), each step rotates by `step` rad about `axis` (fixed
/// in the object frame) or, when `wander`, about `axis` turned by a slowly changing offset.
fn motion(axis: &Vector3<f64>, step: f64, wander: bool) -> Vec<UnitQuaternion<f64>> {
    let mut q = UnitQuaternion::identity();
    let mut qs = vec![q];
    for k in 1..samples(step) {
        let t = k as f64;
        let a = if wander {
            (axis + Vector3::new((0.3 * t).sin(), (0.2 * t).cos(), 0.5 * (0.1 * t).sin()) * 0.6)
                .normalize()
        } else {
            *axis
        };
        q = UnitQuaternion::from_scaled_axis(a * step) * q;
        qs.push(q);
    }
    qs
}

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

/// Worst error per backend over every axis and motion for one step size: `[0]` over the plane
/// and the sphere, `[1]` over the bowl and the cylinder.
fn worst_for_step(step: f64) -> [[f64; 3]; 2] {
    let mut worst = [[0.0f64; 3]; 2];
    for axis in axes() {
        for wander in [false, true] {
            let qs = motion(&axis, step, wander);
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
                // (see `host_sim::reference::rk45`, `initial_step`).
                let reference = reference_paths_on(ground, method, &qs, 0.01, RHO)
                    .unwrap_or_else(|e| panic!("{axis:?} wander {wander} {ground:?}: {e:?}"));
                let (o, f) = (&reference.plane, &reference.sphere);
                let e = match ground {
                    Ground::Plane => [
                        core_error::<Libm, _>(Plane::default(), &qs, o, f),
                        core_error::<Fast, _>(Plane::default(), &qs, o, f),
                        core_error::<Micromath, _>(Plane::default(), &qs, o, f),
                    ],
                    Ground::Sphere { .. } => {
                        let s = Sphere::new(BIG as f32);
                        [
                            core_error::<Libm, _>(s, &qs, o, f),
                            core_error::<Fast, _>(s, &qs, o, f),
                            core_error::<Micromath, _>(s, &qs, o, f),
                        ]
                    }
                    Ground::Bowl { .. } => {
                        let s = Bowl::new(BIG as f32);
                        [
                            core_error::<Libm, _>(s, &qs, o, f),
                            core_error::<Fast, _>(s, &qs, o, f),
                            core_error::<Micromath, _>(s, &qs, o, f),
                        ]
                    }
                    Ground::Cylinder { .. } => {
                        let s = Cylinder::new(BIG as f32);
                        [
                            core_error::<Libm, _>(s, &qs, o, f),
                            core_error::<Fast, _>(s, &qs, o, f),
                            core_error::<Micromath, _>(s, &qs, o, f),
                        ]
                    }
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
    for (name, w) in [("plane, sphere", worst[0]), ("bowl, cylinder", worst[1])] {
        println!(
            "step {step} rad, {name}: worst error libm {:.2e} m, fast {:.2e} m, micromath {:.2e} m \
             (52 cases per ground, all against the RK45 reference)",
            w[0], w[1], w[2]
        );
    }
    worst
}

#[test]
fn small_steps_match_the_rk45_reference_on_every_axis() {
    let [flat, curved] = worst_for_step(0.02);
    for (name, e, b) in [
        ("libm", flat[0], LIBM.small),
        ("fast", flat[1], FAST.small),
        ("micromath", flat[2], MICROMATH.small),
        ("curved libm", curved[0], CURVED_LIBM.small),
        ("curved fast", curved[1], CURVED_FAST.small),
        ("curved micromath", curved[2], CURVED_MICROMATH.small),
    ] {
        assert!(e <= b, "{name}: {e:e} m > {b:e} m");
    }
}

#[test]
fn large_steps_match_the_rk45_reference_with_each_backends_bound() {
    for (s, step) in LARGE_STEPS.into_iter().enumerate() {
        let [flat, curved] = worst_for_step(step);
        for (name, e, b) in [
            ("libm", flat[0], LIBM.large[s]),
            ("fast", flat[1], FAST.large[s]),
            ("micromath", flat[2], MICROMATH.large[s]),
            ("curved libm", curved[0], CURVED_LIBM.large[s]),
            ("curved fast", curved[1], CURVED_FAST.large[s]),
            ("curved micromath", curved[2], CURVED_MICROMATH.large[s]),
        ] {
            assert!(e <= b, "step {step}, {name}: {e:e} m > {b:e} m");
        }
    }
}
