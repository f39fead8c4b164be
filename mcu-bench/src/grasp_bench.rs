//! The grasp's cost per control tick on the target: one `Grasp::step` (both fingertips' contact
//! steps, the wrenches, the body's semi-implicit Euler step) at 10 kHz, a 0.1 kg object held by
//! two fingertips pressing with 5 N from ±x, its weight and a small torque about the grasp axis
//! acting, the fingertips' orientation alternating by the contact benches' increment (so both
//! contacts roll and spin every tick). Rows `grasp_tick_sphere` (30 mm sphere) and
//! `grasp_tick_cylinder` (25 mm cylinder, pinched across its axis), per backend.
//!
//! The rows `grasp_tick_sphere_<model>` (fast backend) are the sphere's tick with both contacts
//! of each contact model choice (`softfinger_core::contact::parts`, `Grasp::with_parts`), for
//! `host-sim model --scene grasp`; with no external torque, so that the choices without the spin
//! hold the body as well (the fingertips are fixed here, and 5 mN·m would spin a body that a
//! point contact cannot hold) and every row is of the same held grasp.
//!
//! After settling for 0.2 s and after the measurement, both contacts must still be rolling with no
//! flag, so a figure is never of a dropped or flagged grasp.

use cortex_m_semihosting::hprintln;
use softfinger_core::contact::params::ContactParams;
use softfinger_core::contact::state::ContactState;
use softfinger_core::contact::surface::{Cylinder, Sphere, Surface};
use softfinger_core::contact::{Full, Parts, PointFriction, RollingOnly, WithRolling, WithSpin};
use softfinger_core::grasp::{BodyParams, BodyState, Fingertip, Grasp, Wrench};
use softfinger_core::{Fast, Libm, Math, Micromath, Quat, Vec3};
use softfinger_mcu_bench::bench::Bencher;
use softfinger_mcu_bench::{bb, bench};

/// All grasp benchmarks.
pub fn benches(b: &mut Bencher) {
    let sphere = BodyParams::solid_sphere(0.1, 0.03);
    let cyl = BodyParams::solid_cylinder_x(0.1, 0.025, 0.08);
    grasp_tick::<Libm, _, Full>(
        b,
        "grasp_tick_sphere",
        sphere,
        Sphere::new(0.03),
        0.03,
        Quat::IDENTITY,
        0.005,
    );
    grasp_tick::<Micromath, _, Full>(
        b,
        "grasp_tick_sphere",
        sphere,
        Sphere::new(0.03),
        0.03,
        Quat::IDENTITY,
        0.005,
    );
    grasp_tick::<Fast, _, Full>(
        b,
        "grasp_tick_sphere",
        sphere,
        Sphere::new(0.03),
        0.03,
        Quat::IDENTITY,
        0.005,
    );
    // The cylinder's axis (body x) vertical: a turn of −90° about y.
    let q = Quat::from_axis_angle::<Libm>(Vec3::Y, -core::f32::consts::FRAC_PI_2);
    grasp_tick::<Libm, _, Full>(
        b,
        "grasp_tick_cylinder",
        cyl,
        Cylinder::new(0.025),
        0.025,
        q,
        0.005,
    );
    grasp_tick::<Micromath, _, Full>(
        b,
        "grasp_tick_cylinder",
        cyl,
        Cylinder::new(0.025),
        0.025,
        q,
        0.005,
    );
    grasp_tick::<Fast, _, Full>(
        b,
        "grasp_tick_cylinder",
        cyl,
        Cylinder::new(0.025),
        0.025,
        q,
        0.005,
    );
    grasp_model::<PointFriction>(b, "grasp_tick_sphere_point-friction", sphere);
    grasp_model::<RollingOnly>(b, "grasp_tick_sphere_rolling", sphere);
    grasp_model::<WithSpin>(b, "grasp_tick_sphere_spin", sphere);
    grasp_model::<WithRolling>(b, "grasp_tick_sphere_spin-rolling", sphere);
    grasp_model::<Full>(b, "grasp_tick_sphere_full", sphere);
}

/// The sphere's grasp tick with both contacts of parts `P`, no external torque (fast backend).
fn grasp_model<P: Parts>(b: &mut Bencher, name: &str, body: BodyParams) {
    grasp_tick::<Fast, _, P>(b, name, body, Sphere::new(0.03), 0.03, Quat::IDENTITY, 0.0);
}

/// `torque_nm`: the external torque about the grasp axis (world x), N·m.
fn grasp_tick<M: Math, S: Surface, P: Parts>(
    b: &mut Bencher,
    name: &str,
    body: BodyParams,
    surface: S,
    radius_m: f32,
    q0: Quat,
    torque_nm: f32,
) {
    let mut params = ContactParams::DEFAULT;
    params.spin_stiffness = 0.2;
    params.tangential_stiffness = 3000.0;
    params.tangential_damping = 10.0;
    let state = BodyState {
        q: q0,
        ..BodyState::default()
    };
    let Ok(mut grasp) = Grasp::<M, S, P>::with_parts(
        body,
        state,
        surface,
        [params; 2],
        Vec3::new(0.0, 0.0, -9.81),
        1.0e-4,
    ) else {
        hprintln!("ERROR {}: Grasp::new rejected the parameters", name);
        b.fail();
        return;
    };
    let d = radius_m + params.fingertip_radius_m - 0.0025;
    let (dq, _) = Quat::from_rotation_vector::<Libm>(Vec3::new(2.0e-4, 1.0e-4, 1.5e-4));
    let tip = |x: f32, q: Quat| {
        Some(Fingertip {
            pos_m: Vec3::new(x, 0.0, 0.0),
            vel_m_s: Vec3::ZERO,
            q,
        })
    };
    let inputs = [
        [tip(d, dq), tip(-d, dq)],
        [tip(d, Quat::IDENTITY), tip(-d, Quat::IDENTITY)],
    ];
    let ext = Wrench {
        force_n: Vec3::ZERO,
        torque_nm: Vec3::new(torque_nm, 0.0, 0.0),
    };
    let mut k = 0;
    for _ in 0..2000 {
        grasp.step(inputs[k], ext);
        k ^= 1;
    }
    let ok = |s: &softfinger_core::grasp::GraspStep| {
        s.contacts
            .iter()
            .all(|c| c.output.state == ContactState::Rolling && c.output.flags.is_empty())
    };
    let before = grasp.step(inputs[k], ext);
    k ^= 1;
    bench!(b, name, M, || {
        let out = grasp.step(bb(inputs[k]), bb(ext));
        k ^= 1;
        out
    });
    let after = grasp.step(inputs[k], ext);
    if !ok(&before) || !ok(&after) {
        hprintln!(
            "ERROR {} [{}]: expected both contacts rolling without flags, got {:?} {:?} / {:?} {:?}",
            name,
            M::NAME,
            after.contacts[0].output.state,
            after.contacts[0].output.flags,
            after.contacts[1].output.state,
            after.contacts[1].output.flags
        );
        b.fail();
    }
}
