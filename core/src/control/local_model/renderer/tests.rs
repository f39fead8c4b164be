use super::*;
use crate::control::local_model::spec::ModelKind;
use crate::math::Libm;

const RATE: f32 = 10_000.0;
/// Default stiffness, N/m.
const K: f32 = 2000.0;

fn config(blend_s: f32) -> RendererConfig {
    RendererConfig {
        rate_hz: RATE,
        blend_s,
        stale_fade_s: 0.020,
    }
}

fn plane_at(seq: u32, z: f32) -> LocalModelSpec {
    LocalModelSpec::plane(
        seq,
        ModelPose::at(Vec3::new(0.0, 0.0, z)),
        &ContactParams::DEFAULT,
    )
}

/// The probe held still with its centre 8 mm above the base origin: a 10 mm fingertip on the
/// plane z = 0 penetrates 2 mm, 4 N at 2 N/mm.
fn held() -> ProbeSample {
    ProbeSample {
        q: Quat::IDENTITY,
        probe_m: Vec3::new(0.0, 0.0, 0.008),
        probe_vel: Vec3::ZERO,
    }
}

fn renderer(blend_s: f32, initial: LocalModelSpec) -> LocalModelRenderer<Libm> {
    LocalModelRenderer::new(config(blend_s), ContactParams::DEFAULT, initial).unwrap()
}

/// Settle on the initial model; returns the last output.
fn settle(r: &mut LocalModelRenderer<Libm>, ticks: u32) -> RenderOutput {
    let mut out = RenderOutput::default();
    for _ in 0..ticks {
        out = r.step(&held());
    }
    out
}

/// Run `ticks` ticks; the largest per-tick change of |F| and whether the state ever left
/// `Rolling`.
fn run(r: &mut LocalModelRenderer<Libm>, mut prev: Vec3, ticks: u32) -> (f32, bool, RenderOutput) {
    let mut max_step = 0.0f32;
    let mut always_rolling = true;
    let mut out = RenderOutput::default();
    for _ in 0..ticks {
        out = r.step(&held());
        max_step = max_step.max((out.force_n - prev).norm::<Libm>());
        always_rolling &= out.state == ContactState::Rolling;
        prev = out.force_n;
    }
    (max_step, always_rolling, out)
}

#[test]
fn a_pressed_plane_renders_its_spring() {
    let mut r = renderer(0.002, plane_at(1, 0.0));
    let out = settle(&mut r, 100);
    assert_eq!(out.state, ContactState::Rolling);
    // Measured 1.19e-6 N; bound 3x.
    assert!((out.force_n.z - 4.0).abs() < 3.6e-6, "{:?}", out.force_n);
}

/// Raising the plane 1 mm under a held probe adds 2 N. Blended over 10 ms (100 ticks) the force
/// changes by 2 N / 100 = 0.02 N per tick at most (measured 0.0200 N); in one tick (blend 0) it
/// steps by the whole 2 N. The contact stays rolling throughout. The settled force measured 9.5e-7
/// N off 6 N and the unblended step 2.4e-7 N off 2 N; bounds 3x.
#[test]
fn a_pose_switch_is_slewed_without_a_force_step() {
    let mut r = renderer(0.010, plane_at(1, 0.0));
    let before = settle(&mut r, 100);
    r.accept(plane_at(2, 0.001)).unwrap();
    let (max_step, rolling, after) = run(&mut r, before.force_n, 300);
    assert!(rolling);
    assert!(
        (after.force_n.z - 6.0).abs() < 2.9e-6,
        "{:?}",
        after.force_n
    );
    assert!(max_step <= 0.0201 && max_step > 0.0199, "{max_step}");
    assert_eq!(after.model_seq, 2);

    let mut r = renderer(0.0, plane_at(1, 0.0));
    let before = settle(&mut r, 100);
    r.accept(plane_at(2, 0.001)).unwrap();
    let (max_step, _, _) = run(&mut r, before.force_n, 10);
    assert!(
        (max_step - 2.0).abs() < 7.2e-7,
        "no blend: a 2 N step, got {max_step}"
    );
}

/// The blend time itself: 99 ticks into a 100-tick slew the force is not yet at its new value, at
/// 100 it is (measured 9.5e-7 N off 6 N; bound 3x).
#[test]
fn the_slew_takes_exactly_its_blend_time() {
    let mut r = renderer(0.010, plane_at(1, 0.0));
    settle(&mut r, 100);
    r.accept(plane_at(2, 0.001)).unwrap();
    let mut f = [0.0f32; 101];
    for v in f.iter_mut().skip(1) {
        *v = r.step(&held()).force_n.z;
    }
    assert!(f[99] < 6.0 - 0.015, "{}", f[99]);
    assert!((f[100] - 6.0).abs() < 2.9e-6, "{}", f[100]);
}

/// Doubling the stiffness (another material: a cross-fade between two contact models) under a
/// held probe: 4 N → 8 N over 10 ms, at most 4 N / 100 = 0.04 N per tick (measured 0.0400 N); the
/// reported contact state stays rolling on every tick. The settled force measured 2.4e-6 N off
/// 8 N; bound 3x.
#[test]
fn a_material_switch_is_cross_faded_and_the_state_stays() {
    let mut r = renderer(0.010, plane_at(1, 0.0));
    let before = settle(&mut r, 100);
    let stiffer = LocalModelSpec {
        stiffness_n_per_m: 2.0 * K,
        ..plane_at(2, 0.0)
    };
    r.accept(stiffer).unwrap();
    let (max_step, rolling, after) = run(&mut r, before.force_n, 300);
    assert!(rolling);
    assert!(
        (after.force_n.z - 8.0).abs() < 7.2e-6,
        "{:?}",
        after.force_n
    );
    assert!(max_step <= 0.0401 && max_step > 0.0399, "{max_step}");
}

/// Plane → sphere (another kind) whose top is 1 mm higher: cross-faded; the force goes from 4 N to
/// 6 N with no step above 2 N / 100 (+1 %). The settled force measured 2.9e-6 N off 6 N; bound
/// 3x.
#[test]
fn a_kind_switch_is_cross_faded() {
    let mut r = renderer(0.010, plane_at(1, 0.0));
    let before = settle(&mut r, 100);
    let ball = LocalModelSpec {
        kind: ModelKind::Sphere { radius_m: 0.05 },
        ..plane_at(2, 0.001 - 0.05)
    };
    r.accept(ball).unwrap();
    let (max_step, rolling, after) = run(&mut r, before.force_n, 300);
    assert!(rolling);
    assert!(
        (after.force_n.z - 6.0).abs() < 8.6e-6,
        "{:?}",
        after.force_n
    );
    assert!(max_step <= 0.0202, "{max_step}");
    assert_eq!(r.model().seq, 2);
}

/// A plane moving up and down 1 mm at 5 Hz, streamed at 1 kHz (every 10 ticks) with a 1 ms slew:
/// the force follows the continuous motion, whose largest change per tick is
/// K·A·2πf·dt = 2000·0.001·31.4·1e-4 = 6.3 mN; the slew spreads each 1 ms update over 10 ticks,
/// so no tick changes by more than that (measured 6.28 mN; bound 6.5 mN).
#[test]
fn a_1khz_stream_renders_without_steps() {
    let mut r = renderer(0.001, plane_at(1, 0.0));
    let mut prev = settle(&mut r, 100).force_n;
    let mut max_step = 0.0f32;
    for k in 0..10_000u32 {
        if k % 10 == 0 {
            let t = k as f32 / RATE;
            let z = 0.001 * libm::sinf(2.0 * core::f32::consts::PI * 5.0 * t);
            r.accept(plane_at(2 + k / 10, z)).unwrap();
        }
        let out = r.step(&held());
        assert_eq!(out.state, ContactState::Rolling);
        max_step = max_step.max((out.force_n - prev).norm::<Libm>());
        prev = out.force_n;
    }
    assert!(max_step < 0.0065 && max_step > 0.006, "{max_step}");
}

/// Sequence numbers must increase; a refused model changes nothing and flags the next tick.
#[test]
fn old_sequences_and_bad_models_are_refused() {
    let mut r = renderer(0.002, plane_at(5, 0.0));
    settle(&mut r, 10);
    assert_eq!(r.accept(plane_at(5, 0.001)), Err(ModelError::StaleSequence));
    assert_eq!(r.accept(plane_at(4, 0.001)), Err(ModelError::StaleSequence));
    let bad = LocalModelSpec {
        stiffness_n_per_m: f32::NAN,
        ..plane_at(6, 0.0)
    };
    assert!(matches!(r.accept(bad), Err(ModelError::Params(_))));
    let out = r.step(&held());
    assert!(out.flags.contains(Flags::MODEL_REJECTED));
    assert_eq!(out.model_seq, 5);
    // Measured 1.19e-6 N; bound 3x.
    assert!((out.force_n.z - 4.0).abs() < 3.6e-6);
    assert!(!r.step(&held()).flags.contains(Flags::MODEL_REJECTED));
}

/// A model valid for 50 ms (500 ticks): not stale at 500 ticks, stale at 501; the force is zero
/// 200 ticks (the 20 ms fade) later and not at 199; a fresh model brings it back without a step.
#[test]
fn a_stale_model_fades_to_zero_and_a_fresh_one_restores_it() {
    let spec = |seq| LocalModelSpec {
        max_age_s: 0.050,
        ..plane_at(seq, 0.0)
    };
    let mut r = renderer(0.002, spec(1));
    for k in 1..=500 {
        let out = r.step(&held());
        assert!(!out.flags.contains(Flags::MODEL_STALE), "tick {k}");
    }
    let mut f = [0.0f32; 201];
    for (k, v) in f.iter_mut().enumerate().skip(1) {
        let out = r.step(&held());
        assert!(out.flags.contains(Flags::MODEL_STALE), "tick {}", 500 + k);
        *v = out.force_n.z;
    }
    assert!(f[199] > 0.0 && f[200] == 0.0, "{} {}", f[199], f[200]);
    r.accept(spec(2)).unwrap();
    let (max_step, rolling, after) = run(&mut r, Vec3::ZERO, 300);
    assert!(rolling);
    assert!(max_step <= 4.0 / 200.0 + 1e-4, "{max_step}");
    // Measured 1.19e-6 N; bound 3x.
    assert!((after.force_n.z - 4.0).abs() < 3.6e-6);
}

#[test]
fn non_finite_samples_give_a_finite_safe_output() {
    let mut r = renderer(0.002, plane_at(1, 0.0));
    settle(&mut r, 10);
    for bad in [f32::NAN, f32::INFINITY, 1e30] {
        let out = r.step(&ProbeSample {
            probe_m: Vec3::new(bad, 0.0, 0.008),
            ..held()
        });
        assert!(out.force_n.is_finite() && out.tau_n_nm.is_finite());
        assert_eq!(out.force_n, Vec3::ZERO);
        assert!(out
            .flags
            .intersects(Flags::NON_FINITE_INPUT | Flags::OUT_OF_RANGE));
    }
}

#[test]
fn bad_configurations_are_refused() {
    let ok = plane_at(1, 0.0);
    let b = ContactParams::DEFAULT;
    for (c, field) in [
        (
            RendererConfig {
                rate_hz: 999.0,
                ..config(0.0)
            },
            "rate_hz",
        ),
        (
            RendererConfig {
                blend_s: -1e-6,
                ..config(0.0)
            },
            "blend_s",
        ),
        (
            RendererConfig {
                blend_s: 1.001,
                ..config(0.0)
            },
            "blend_s",
        ),
        (
            RendererConfig {
                stale_fade_s: f32::NAN,
                ..config(0.0)
            },
            "stale_fade_s",
        ),
    ] {
        let e = LocalModelRenderer::<Libm>::new(c, b, ok).unwrap_err();
        let named = match e {
            ModelError::Params(ParamError::OutOfRange(n))
            | ModelError::Params(ParamError::Negative(n))
            | ModelError::Params(ParamError::NotFinite(n)) => n,
            other => panic!("{other:?}"),
        };
        assert_eq!(named, field);
    }
    assert!(LocalModelRenderer::<Libm>::new(
        RendererConfig {
            blend_s: 1.0,
            ..config(0.0)
        },
        b,
        ok
    )
    .is_ok());
}
