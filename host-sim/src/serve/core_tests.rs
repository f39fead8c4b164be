use super::*;
use crate::scene::Scene;
use softfinger_core::local_model::ModelPose;

const RATE: f32 = 10_000.0;

/// A core whose plane sits 2 mm into the fingertip held at the plant's start position (4 N at
/// 2 N/mm), and those counts.
fn pressed() -> (LocalModelCore, [i32; 6]) {
    let scene = Scene::default_scene();
    let (contact, _) = scene_model(&scene).unwrap();
    let plant = crate::closed_loop::plant(&scene, &contact).unwrap();
    let counts = plant.counts();
    let probe = Vec3::from_array(plant.effector_position_m().map(|v| v as f32));
    let model = LocalModelSpec::plane(
        1,
        ModelPose::at(Vec3::new(0.0, 0.0, probe.z - 0.008)),
        &contact,
    );
    let core = LocalModelCore::new(
        softfinger_core::devices::OMEGA_LIKE.params,
        RATE,
        contact,
        model,
        0.002,
    )
    .unwrap();
    (core, counts)
}

fn ticks(core: &mut LocalModelCore, counts: [i32; 6], n: u32) -> CoreOutput {
    let mut out = CoreOutput::default();
    for _ in 0..n {
        out = core.tick(counts);
    }
    out
}

/// Unhomed: no force, arming refused. Homing takes 50 ms (500 ticks: not done at 499). Armed: the
/// force ramps in over 0.1 s (1000 ticks) to the 4 N spring, never stepping by more than 4 N/1000
/// (+1 %).
#[test]
fn no_force_before_homing_and_arming_then_a_ramp() {
    let (mut core, counts) = pressed();
    let out = ticks(&mut core, counts, 10);
    assert_eq!(
        (out.mode, out.force_n, out.enable),
        (Mode::Unhomed, Vec3::ZERO, false)
    );
    assert_eq!(
        core.request(CoreRequest::Arm),
        AckResult::Err(ErrorCode::WrongMode)
    );
    assert_eq!(core.request(CoreRequest::Home), AckResult::Ok);
    assert_eq!(ticks(&mut core, counts, 499).mode, Mode::Homing);
    assert_eq!(
        core.request(CoreRequest::Arm),
        AckResult::Err(ErrorCode::WrongMode)
    );
    assert_eq!(ticks(&mut core, counts, 1).mode, Mode::Disarmed);
    assert_eq!(core.request(CoreRequest::Arm), AckResult::Ok);
    let mut prev = 0.0f32;
    let mut max_step = 0.0f32;
    for _ in 0..1100 {
        let out = core.tick(counts);
        let f = out.force_n.norm::<Fast>();
        max_step = max_step.max((f - prev).abs());
        prev = f;
        assert!(out.enable && out.mode == Mode::Armed);
    }
    assert!((prev - 4.0).abs() < 0.01, "{prev}");
    assert!(max_step <= 4.0 / 1000.0 * 1.01, "{max_step}");
    assert!(core.tick(counts).duties.iter().any(|d| d.abs() > 0.0));
    // Parameters do not change under force.
    let p = core.contact_params();
    assert_eq!(
        core.request(CoreRequest::SetContactParams(p)),
        AckResult::Err(ErrorCode::WrongMode)
    );
    assert_eq!(core.request(CoreRequest::Disarm), AckResult::Ok);
    let out = core.tick(counts);
    assert_eq!(
        (out.force_n, out.enable, out.duties),
        (Vec3::ZERO, false, [0.0; 3])
    );
}

fn armed() -> (LocalModelCore, [i32; 6]) {
    let (mut core, counts) = pressed();
    core.request(CoreRequest::Home);
    ticks(&mut core, counts, 500);
    core.request(CoreRequest::Arm);
    ticks(&mut core, counts, 1100);
    (core, counts)
}

/// An encoder jump beyond the device's glitch limit (2 M counts/s: 200 counts a tick at 10 kHz)
/// latches ENCODER_GLITCH: zero torque at once, drivers off; a jump of exactly the limit does not.
/// Clearing leads to Disarmed, never Armed.
#[test]
fn a_fault_cuts_the_force_at_once_and_latches() {
    let limit = softfinger_core::devices::OMEGA_LIKE
        .limits
        .per_tick(RATE)
        .max_counts_per_tick as i32;
    assert_eq!(limit, 200);
    let (mut core, mut counts) = armed();
    counts[0] += limit;
    let out = core.tick(counts);
    assert_eq!(out.mode, Mode::Armed, "the limit itself is not a glitch");
    counts[0] += limit + 1;
    let out = core.tick(counts);
    assert_eq!(out.mode, Mode::Faulted);
    assert!(out.flags.contains(Flags::ENCODER_GLITCH));
    assert_eq!(
        (out.force_n, out.enable, out.duties),
        (Vec3::ZERO, false, [0.0; 3])
    );
    assert_eq!(
        core.request(CoreRequest::Arm),
        AckResult::Err(ErrorCode::Faulted)
    );
    let out = ticks(&mut core, counts, 100);
    assert_eq!((out.mode, out.enable), (Mode::Faulted, false));
    assert_eq!(core.request(CoreRequest::ClearFaults), AckResult::Ok);
    let out = ticks(&mut core, counts, 10);
    assert_eq!((out.mode, out.enable), (Mode::Disarmed, false));
    assert!(!out.flags.contains(Flags::ENCODER_GLITCH));
}

/// Watchdog 10 ms: silent for 99 ticks nothing happens; at 100 COMM_TIMEOUT latches and the force
/// fades to zero over the 20 ms fade (200 ticks: not zero at 199); messages alone do not clear
/// it, arming does.
#[test]
fn the_watchdog_fades_and_latches_until_rearmed() {
    let (mut core, counts) = armed();
    assert_eq!(
        core.request(CoreRequest::SetWatchdog { timeout_s: 0.010 }),
        AckResult::Ok
    );
    let out = ticks(&mut core, counts, 99);
    assert!(!out.flags.contains(Flags::COMM_TIMEOUT));
    let out = core.tick(counts);
    assert!(out.flags.contains(Flags::COMM_TIMEOUT));
    let f0 = out.force_n.norm::<Fast>();
    assert!(f0 > 3.9 && f0 < 4.0, "{f0}");
    let out = ticks(&mut core, counts, 198);
    assert!(out.force_n.norm::<Fast>() > 0.0);
    let out = core.tick(counts);
    assert_eq!(out.force_n, Vec3::ZERO);
    core.message_received();
    assert!(core.tick(counts).flags.contains(Flags::COMM_TIMEOUT));
    assert_eq!(core.request(CoreRequest::Arm), AckResult::Ok);
    let out = ticks(&mut core, counts, 50);
    assert!(!out.flags.contains(Flags::COMM_TIMEOUT));
    assert!(out.force_n.norm::<Fast>() > 0.0);
    assert_eq!(
        core.request(CoreRequest::SetWatchdog { timeout_s: 60.01 }),
        AckResult::Err(ErrorCode::InvalidValue)
    );
}

/// A model with an old sequence number, or an invalid one, is refused with its code.
#[test]
fn models_are_refused_with_typed_codes() {
    let (mut core, _) = pressed();
    let (contact, spec) = scene_model(&Scene::default_scene()).unwrap();
    let old = LocalModelSpec { seq: 1, ..spec };
    assert_eq!(
        core.request(CoreRequest::SetLocalModel(old)),
        AckResult::Err(ErrorCode::StaleSequence)
    );
    let bad = LocalModelSpec {
        seq: 2,
        stiffness_n_per_m: -1.0,
        ..spec
    };
    assert_eq!(
        core.request(CoreRequest::SetLocalModel(bad)),
        AckResult::Err(ErrorCode::InvalidValue)
    );
    let good = LocalModelSpec { seq: 2, ..spec };
    assert_eq!(
        core.request(CoreRequest::SetLocalModel(good)),
        AckResult::Ok
    );
    assert_eq!(core.contact_params(), contact);
}

#[test]
fn bowl_and_cylinder_scenes_are_refused_with_their_kind() {
    for (name, kind) in [
        ("finger-in-bowl", "bowl"),
        ("finger-on-cylinder", "cylinder"),
    ] {
        let e = scene_model(&Scene::load(name).unwrap()).unwrap_err();
        assert!(e.contains(kind) && e.contains(name), "{e}");
    }
    assert!(scene_model(&Scene::load("finger-on-sphere").unwrap()).is_ok());
}
