use super::*;
use crate::frame::tests::model;
use crate::model::{ContactParamsWire, SurfaceKind, SurfaceShape};
use softfinger_core::contact::params::ParamError;

/// Every field arrives where it belongs: the quaternion not the identity (a swapped component
/// shows), each material value different, the age in s.
#[test]
fn a_model_of_every_shape_keeps_its_fields() {
    for shape in [
        SurfaceShape::Plane,
        SurfaceShape::Sphere { radius_m: 0.02 },
        SurfaceShape::Bowl { radius_m: 0.05 },
        SurfaceShape::Cylinder { radius_m: 0.015 },
    ] {
        let m = LocalModel {
            shape,
            orientation: [0.5, -0.5, 0.5, 0.5],
            max_age_ms: 250,
            ..model(9)
        };
        let s = m.spec();
        assert_eq!(s.kind, shape);
        assert_eq!(s.pose.orientation, Quat::new(0.5, -0.5, 0.5, 0.5));
        assert_eq!(s.pose.position_m, Vec3::new(0.0, 0.01, -0.02));
        let material = (s.stiffness_n_per_m, s.damping_n_s_per_m, s.mu_s, s.mu_k);
        assert_eq!(material, (2000.0, 2.0, 0.8, 0.6));
        assert_eq!((s.seq, s.spin_stiffness_nm_per_rad), (9, 0.01));
        assert!((s.max_age_s - 0.25).abs() < 1e-7, "{}", s.max_age_s);
    }
    // The longest age the wire carries, 65.535 s (the renderer refuses more than 60 s).
    let oldest = LocalModel {
        max_age_ms: u16::MAX,
        ..model(1)
    };
    assert!((oldest.spec().max_age_s - 65.535).abs() < 1e-5);
}

/// The wire's fields replace the base's; the others stay the base's.
#[test]
fn contact_params_round_trip_through_the_wire_over_their_base() {
    let base = ContactParams::DEFAULT;
    let p = ContactParams {
        normal_stiffness: 1234.0,
        mu_k: 0.5,
        max_force_n: 7.0,
        ..base
    };
    assert_eq!(ContactParamsWire::of(&p).over(&base), p);
    let other_base = ContactParams {
        patch_radius_m: 0.004,
        k_tau: 3.0,
        ..base
    };
    let q = ContactParamsWire::of(&p).over(&other_base);
    assert_eq!((q.patch_radius_m, q.k_tau), (0.004, 3.0));
    assert_eq!(
        (q.normal_stiffness, q.mu_k, q.max_force_n),
        (1234.0, 0.5, 7.0)
    );
}

#[test]
fn each_request_is_its_command_or_none() {
    let base = ContactParams::DEFAULT;
    let cmd = |r: Request| r.command(&base);
    assert_eq!(cmd(Request::Home), Some(Command::Home));
    assert_eq!(cmd(Request::Arm), Some(Command::Arm));
    assert_eq!(cmd(Request::Disarm), Some(Command::Disarm));
    assert_eq!(cmd(Request::ClearFaults), Some(Command::ClearFaults));
    assert_eq!(
        cmd(Request::SetWatchdog { timeout_ms: 150 }),
        Some(Command::SetWatchdog { timeout_s: 0.15 })
    );
    let m = model(4);
    assert_eq!(
        cmd(Request::SetLocalModel(m)),
        Some(Command::SetLocalModel(m.spec()))
    );
    let w = ContactParamsWire::of(&ContactParams { mu_s: 0.95, ..base });
    assert_eq!(
        cmd(Request::SetContactParams(w)),
        Some(Command::SetContactParams(w.over(&base)))
    );
    for r in [
        Request::GetInfo,
        Request::GetCounters,
        Request::GetContactParams,
        Request::Ping,
        Request::SetStream { divisor: 5 },
        Request::ReleaseHand,
    ] {
        assert_eq!(cmd(r.clone()), None, "{r:?}");
    }
}

#[test]
fn each_refusal_of_the_pipeline_has_its_error_code() {
    let code = ErrorCode::from;
    assert_eq!(code(CommandError::NotHomed), ErrorCode::WrongMode);
    assert_eq!(code(CommandError::Armed), ErrorCode::WrongMode);
    assert_eq!(code(CommandError::Homing), ErrorCode::WrongMode);
    assert_eq!(code(CommandError::Faulted), ErrorCode::Faulted);
    let bad = CommandError::InvalidParams(ParamError::NotFinite("normal_stiffness"));
    assert_eq!(code(bad), ErrorCode::InvalidValue);
    let stale = CommandError::InvalidModel(ModelError::StaleSequence);
    assert_eq!(code(stale), ErrorCode::StaleSequence);
    let bad_pose = CommandError::InvalidModel(ModelError::BadPose);
    assert_eq!(code(bad_pose), ErrorCode::InvalidValue);
    assert_eq!(code(CommandError::Unsupported), ErrorCode::Unsupported);
    assert_eq!(AckResult::from(Ok(())), AckResult::Ok);
    assert_eq!(
        AckResult::from(Err(CommandError::Faulted)),
        AckResult::Err(ErrorCode::Faulted)
    );
}

/// `ALL` lists every kind once, in wire order, and each shape has its kind.
#[test]
fn every_surface_kind_once_each_shape_its_own() {
    let shapes = [
        SurfaceShape::Plane,
        SurfaceShape::Sphere { radius_m: 1.0 },
        SurfaceShape::Bowl { radius_m: 1.0 },
        SurfaceShape::Cylinder { radius_m: 1.0 },
    ];
    let kinds = shapes.map(|s| SurfaceKind::of(&s));
    assert_eq!(kinds, SurfaceKind::ALL);
}

/// The wire form of a spec is the inverse of `spec`.
#[test]
fn a_model_round_trips_through_its_spec() {
    let m = LocalModel {
        shape: SurfaceShape::Sphere { radius_m: 0.03 },
        orientation: [0.5, -0.5, 0.5, 0.5],
        max_age_ms: 250,
        ..model(7)
    };
    assert_eq!(LocalModel::of(&m.spec()), m);
}

/// Each wire field's range is the one `validate` applies: the ends are accepted, a value just
/// outside either end is refused with that field, and the error maps back to the range.
#[test]
fn every_field_range_is_the_one_validate_applies() {
    let base = ContactParams::DEFAULT;
    let limit = 12.0;
    type Set = fn(&mut ContactParams, f32);
    let fields: [(&str, Set); 9] = [
        ("fingertip_radius_m", |p, v| p.fingertip_radius_m = v),
        ("normal_stiffness", |p, v| p.normal_stiffness = v),
        ("normal_damping", |p, v| p.normal_damping = v),
        ("tangential_stiffness", |p, v| p.tangential_stiffness = v),
        ("tangential_damping", |p, v| p.tangential_damping = v),
        // μ_s above its range with μ_k kept: the first error is μ_s's own.
        ("mu_s", |p, v| {
            p.mu_s = v;
            p.mu_k = p.mu_k.min(v);
        }),
        ("mu_k", |p, v| p.mu_k = v),
        ("spin_stiffness", |p, v| p.spin_stiffness = v),
        ("max_force_n", |p, v| p.max_force_n = v),
    ];
    for (name, set) in fields {
        // Find the range from an error far above it.
        let mut p = base;
        set(&mut p, 1e30);
        let e = p.validate().expect_err(name);
        let r = FieldRange::of_param_error(&e, &p, 1e30).expect(name);
        assert_eq!(r.field.as_str(), name);
        let check = |v: f32, ok: bool| {
            let mut q = base;
            set(&mut q, v);
            let got = q.validate();
            assert_eq!(got.is_ok(), ok, "{name} = {v}: {got:?}");
            assert_eq!(r.contains(v), ok, "{name} = {v} against {r:?}");
            if let Err(e) = got {
                let again = FieldRange::of_param_error(&e, &q, 1e30).expect(name);
                assert_eq!(again, r, "{name} = {v}");
            }
        };
        let up = |v: f32| v * (1.0 + 1e-6) + 1e-30;
        check(r.max, true);
        check(up(r.max), false);
        if r.min_exclusive {
            check(r.min, false);
            check(up(r.min).max(1e-6), true);
        } else {
            check(r.min, true);
            check(r.min - r.min.abs().max(1e-6) * 1e-3, false);
        }
    }
    // The device's own force limit narrows the core's.
    let mut p = base;
    p.max_force_n = 1e30;
    let e = p.validate().unwrap_err();
    let r = FieldRange::of_param_error(&e, &p, limit).unwrap();
    assert_eq!((r.min, r.max), (ContactParams::MIN_MAX_FORCE_N, limit));
    // μ_k above μ_s: the range of μ_k ends at μ_s.
    p = base;
    p.mu_k = base.mu_s + 0.1;
    let r = FieldRange::of_param_error(&p.validate().unwrap_err(), &p, limit).unwrap();
    assert_eq!((r.field.as_str(), r.max), ("mu_k", base.mu_s));
    assert_eq!(
        FieldRange::of_param_error(&ParamError::NotFinite("bogus"), &p, limit),
        None
    );
}
