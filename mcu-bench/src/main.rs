//! `mcu-bench`: instructions per call of softfinger-core's kernels on an emulated Cortex-M4F.
//!
//! Runs on QEMU `mps2-an386` with `-icount shift=0` (see `.cargo/config.toml`); prints one
//! `BENCH <name> <backend> <instructions>` line per result through semihosting and exits with
//! failure if a sanity check or a measurement fails. `scripts/mcu-bench` builds, runs and parses it.
//!
//! To add a benchmark, add one `bench!` line below (see [`softfinger_mcu_bench::bench!`]).
#![no_std]
#![no_main]

use cortex_m_rt::entry;
use cortex_m_semihosting::hprintln;
use softfinger_core::contact::decompose::{decompose, Method};
use softfinger_core::contact::params::ContactParams;
use softfinger_core::contact::rolling::Rolling;
use softfinger_core::contact::spin::{torsion_limit, SpinSpring};
use softfinger_core::contact::state::{next_state, ContactState, StateInputs};
use softfinger_core::contact::surface::{Bowl, Cylinder, Plane, Sphere, Surface};
use softfinger_core::contact::{
    ContactInput, ContactModel, Full, Parts, PointFriction, RollingOnly, WithRolling, WithSpin,
};
use softfinger_core::control::controller::passivity::{Passivity, PassivityConfig};
use softfinger_core::control::controller::{
    Controller, ControllerConfig, Environment, TickInput, WithParts,
};
use softfinger_core::device::DeviceParams;
use softfinger_core::{Fast, Libm, Math, Micromath, Quat, Rot3, Vec3};
use softfinger_mcu_bench::bench::Bencher;
use softfinger_mcu_bench::counter::Counter;
use softfinger_mcu_bench::{bb, bench, exit::exit, install_fault_handler};

mod grasp_bench;
mod link_bench;

install_fault_handler!();

#[entry]
fn main() -> ! {
    let Some(peripherals) = cortex_m::Peripherals::take() else {
        exit(false)
    };
    let mut b = Bencher::new(Counter::new(peripherals.SYST));

    sanity_checks(&mut b);
    math_kernels(&mut b);
    rotations(&mut b);
    pipeline(&mut b);
    link_bench::benches(&mut b);
    grasp_bench::benches(&mut b);

    exit(b.ok())
}

// The instruction sequences are written out, not `.rept`: LLVM sizes inline assembly by its lines
// when it places literal pools, and a `.rept` line would be sized as one instruction.
macro_rules! x5 {
    ($i:expr) => {
        concat!($i, "\n", $i, "\n", $i, "\n", $i, "\n", $i, "\n")
    };
}
macro_rules! x10 {
    ($i:expr) => {
        concat!(x5!($i), x5!($i))
    };
}
macro_rules! x100 {
    ($i:expr) => {
        x10!(x10!($i))
    };
}

/// Sequences of known length: the method must report exactly their instruction count. The FP one
/// also proves the FPU is enabled (with CP10/CP11 off, VADD raises a usage fault → HardFault → the
/// handler reports it and exits with failure).
fn sanity_checks(b: &mut Bencher) {
    b.sanity("nop_x100", 100, || {
        // SAFETY: NOPs only; no memory, stack or flags touched.
        unsafe { core::arch::asm!(x100!("nop"), options(nomem, nostack, preserves_flags)) }
    });
    b.sanity("vadd_f32_x50", 50, || {
        // SAFETY: touches only s0, which is declared clobbered.
        unsafe {
            core::arch::asm!(
                x10!(x5!("vadd.f32 s0, s0, s0")),
                out("s0") _,
                options(nomem, nostack, preserves_flags)
            )
        }
    });
}

/// The scalar kernels of each math backend, at a mid-range input (1 rad: away from each backend's
/// small-argument fast path; libm's sinf/cosf reduce 1 rad against π/2 in f64).
fn math_kernels(b: &mut Bencher) {
    bench!(b, "sin", for M in [Libm, Micromath, Fast], || M::sin(bb(1.0f32)));
    bench!(b, "cos", for M in [Libm, Micromath, Fast], || M::cos(bb(1.0f32)));
    bench!(b, "sin_cos", for M in [Libm, Micromath, Fast], || M::sin_cos(bb(1.0f32)));
    bench!(b, "atan2", for M in [Libm, Micromath, Fast], || M::atan2(bb(0.3f32), bb(-0.8f32)));
    bench!(b, "sqrt", for M in [Libm, Micromath, Fast], || M::sqrt(bb(2.5f32)));
}

/// Rodrigues (eq. 4) and the quaternion log map.
fn rotations(b: &mut Bencher) {
    // A unit axis (1, 2, 3)/√14 and 1 rad; the axis is re-normalised inside (one sqrt).
    let axis = Vec3::new(0.267_261_24, 0.534_522_5, 0.801_783_7);
    bench!(b, "rot3_from_axis_angle", for M in [Libm, Micromath, Fast], || {
        Rot3::from_axis_angle::<M>(bb(axis), bb(1.0f32))
    });
    // The same rotation as a unit quaternion (cos 0.5, axis · sin 0.5).
    let q = Quat::new(0.877_582_56, 0.128_129_8, 0.256_259_6, 0.384_389_4);
    bench!(b, "quat_to_rotation_vector", for M in [Libm, Micromath, Fast], || {
        bb(q).to_rotation_vector::<M>()
    });
}

/// The paper scene's rotation increment per 10 ms step: δψ = 0.03 rad about x, δθ = 0.02 rad about y,
/// δφ = 0.05 rad about z (the contact normal), as a rotation vector (x, y, z).
const SCENE_STEP: Vec3 = Vec3::new(0.03, 0.02, 0.05);

/// The contact pipeline, stage by stage.
fn pipeline(b: &mut Bencher) {
    let (dq, _) = Quat::from_rotation_vector::<Libm>(SCENE_STEP);
    bench!(b, "decompose_paper", for M in [Libm, Micromath, Fast], || {
        decompose::<M>(Method::PaperVerbatim, bb(dq))
    });
    bench!(b, "decompose_rpy", for M in [Libm, Micromath, Fast], || {
        decompose::<M>(Method::Rpy, bb(dq))
    });
    bench!(b, "decompose_exact", for M in [Libm, Micromath, Fast], || {
        decompose::<M>(Method::Exact, bb(dq))
    });

    // Rolling update (Algorithm 1): one orientation sample in, the contact points move. The samples
    // alternate between q0 and q0·dq, so every step rolls by the scene increment, forwards then back
    // (the alternation costs about two instructions per call).
    let q0 = Quat::new(0.877_582_56, 0.128_129_8, 0.256_259_6, 0.384_389_4);
    let samples = [q0 * dq, q0];
    macro_rules! rolling {
        ($name:literal, $surface:expr, $method:expr) => {
            bench!(b, $name, for M in [Libm, Micromath, Fast], {
                let mut r = Rolling::new($surface, 0.01, q0, $method);
                let mut k = 0;
                move || {
                    let q = samples[k];
                    k ^= 1;
                    r.step::<M>(bb(q))
                }
            });
        };
    }
    rolling!(
        "rolling_plane_paper",
        Plane::default(),
        Method::PaperVerbatim
    );
    rolling!("rolling_plane_rpy", Plane::default(), Method::Rpy);
    rolling!("rolling_plane_exact", Plane::default(), Method::Exact);
    rolling!("rolling_sphere_exact", Sphere::new(0.05), Method::Exact);

    state_machine(b);
    spin_torque(b);
    passivity_step(b);
    let plane = Plane::default();
    contact_step::<Libm, _>(b, "contact_step", Method::Exact, plane);
    contact_step::<Micromath, _>(b, "contact_step", Method::Exact, plane);
    contact_step::<Fast, _>(b, "contact_step", Method::Exact, plane);
    contact_step::<Libm, _>(b, "contact_step_rpy", Method::Rpy, plane);
    contact_step::<Micromath, _>(b, "contact_step_rpy", Method::Rpy, plane);
    contact_step::<Fast, _>(b, "contact_step_rpy", Method::Rpy, plane);
    // Curved objects of radius 5 cm, the contact at the top (bottom for the bowl).
    let sphere = Sphere::new(0.05);
    let bowl = Bowl::new(0.05);
    let cylinder = Cylinder::new(0.05);
    contact_step::<Libm, _>(b, "contact_step_sphere", Method::Exact, sphere);
    contact_step::<Micromath, _>(b, "contact_step_sphere", Method::Exact, sphere);
    contact_step::<Fast, _>(b, "contact_step_sphere", Method::Exact, sphere);
    contact_step::<Libm, _>(b, "contact_step_bowl", Method::Exact, bowl);
    contact_step::<Micromath, _>(b, "contact_step_bowl", Method::Exact, bowl);
    contact_step::<Fast, _>(b, "contact_step_bowl", Method::Exact, bowl);
    contact_step::<Libm, _>(b, "contact_step_cylinder", Method::Exact, cylinder);
    contact_step::<Micromath, _>(b, "contact_step_cylinder", Method::Exact, cylinder);
    contact_step::<Fast, _>(b, "contact_step_cylinder", Method::Exact, cylinder);

    model_rows(b);

    device_kinematics(b);
    control_tick::<Libm>(b);
    control_tick::<Micromath>(b);
    control_tick::<Fast>(b);
    control_tick_rolling(b);
    pipeline_tick(b);
}

/// The contact state machine on its common path: rolling, kept (inside the friction cone, below the
/// twist threshold). Backend-independent (no math kernels).
fn state_machine(b: &mut Bencher) {
    let params = ContactParams::DEFAULT.state_params();
    let inputs = StateInputs {
        normal_force_n: 2.0,
        gap_m: -0.001,
        normal_accel: 0.0,
        tangential_force_n: Vec3::new(0.1, -0.05, 0.0),
        tangential_accel: Vec3::new(0.01, 0.0, 0.0),
        tangential_velocity: Vec3::new(0.0005, 0.0, 0.0),
        roll_disp_m: Vec3::new(2.0e-6, -3.0e-6, 0.0),
        tilt_rate_sq: 0.36 * 0.36,
        time_in_state_s: 1.0,
        spin_torque_nm: 5.0e-4,
        torsion_limit_nm: 4.7e-3,
    };
    let (state, _) = next_state(ContactState::Rolling, &inputs, &params);
    if state != ContactState::Rolling {
        hprintln!("ERROR state_machine bench: inputs do not keep rolling");
        b.fail();
    }
    bench!(b, "state_machine", _, || {
        next_state(bb(ContactState::Rolling), &bb(inputs), &params)
    });
}

/// Spin torque, eq. (1) with the torsional friction limit: wind the spring by δφ (alternating
/// ±0.5 mrad so it stays elastic) and return τn. Backend-independent.
fn spin_torque(b: &mut Bencher) {
    let p = ContactParams::DEFAULT;
    let mut spring = SpinSpring::default();
    let mut dphi = 5.0e-4f32;
    bench!(b, "spin_torque", _, || {
        dphi = -dphi;
        let tau_max = torsion_limit(p.mu_s, bb(2.0f32), p.patch_radius_m);
        spring.update(bb(dphi), p.spin_stiffness, tau_max)
    });
}

/// The passivity stage on its active path (the worst case): the probe moves 1 µm per tick along a
/// 2 N force, so the observed energy grows every tick and the damper is computed and applied
/// every tick (checked after the measurement). Backend-independent (one `sqrtf` only when the
/// force limit binds, which it does not here).
fn passivity_step(b: &mut Bencher) {
    let Ok(mut p) = Passivity::new(PassivityConfig::DEFAULT, 1.0e-4, 2_000.0, 12.0) else {
        hprintln!("ERROR passivity_step: the default configuration was rejected");
        b.fail();
        return;
    };
    let _ = p.step(Vec3::ZERO, Vec3::ZERO, Vec3::ZERO);
    let mut x = 0.0f32;
    let force = Vec3::new(2.0, 0.0, 0.0);
    let v = Vec3::new(0.01, 0.0, 0.0);
    bench!(b, "passivity_step", _, || {
        x += 1.0e-6;
        p.step(bb(force), bb(Vec3::new(x, 0.0, 0.0)), bb(v))
    });
    let s = p.step(force, Vec3::new(x + 1.0e-6, 0.0, 0.0), v);
    if !(s.energy_j > 0.0 && s.damping_n_s_per_m > 0.0) {
        hprintln!(
            "ERROR passivity_step: expected the active path; energy {} J, damping {}",
            s.energy_j,
            s.damping_n_s_per_m
        );
        b.fail();
    }
}

/// The full contact step (`ContactModel::contact_step`) at 10 kHz: orientation and probe sample in;
/// force, contact points, spin torque and state out. The probe presses 1 mm into the surface
/// (f_N = 2 N) and holds still while the orientation alternates between q0 and q0·dq, dq = the
/// paper scene's increment / 100 (rolling at 3.6 rad/s: δ ≈ 0.6 mrad per tick), so every step rolls
/// and the model stays in the rolling state (checked after the measurement). Every surface starts
/// with the normal +z at its contact point, so the pressed probe is 1 mm less than the fingertip
/// radius above it.
fn contact_step<M: Math, S: Surface>(b: &mut Bencher, name: &str, method: Method, surface: S) {
    contact_step_parts::<M, S, Full>(b, name, method, surface);
}

/// The contact models a scene can name ([`softfinger_core::contact::parts`]), on each surface, with
/// the fast backend: one row `contact_step_<surface>_<model>` each, measured as
/// [`contact_step`] is (the `full` rows repeat `contact_step`, `contact_step_sphere`, ... under
/// the names `host-sim model` reads).
fn model_rows(b: &mut Bencher) {
    fn rows<S: Surface>(b: &mut Bencher, surface_name: &str, surface: S) {
        fn one<S: Surface, P: Parts>(b: &mut Bencher, surface_name: &str, surface: S) {
            let mut name: heapless::String<64> = heapless::String::new();
            let _ = core::fmt::Write::write_fmt(
                &mut name,
                format_args!("contact_step_{}_{}", surface_name, P::NAME),
            );
            contact_step_parts::<Fast, S, P>(b, &name, Method::Exact, surface);
        }
        one::<S, PointFriction>(b, surface_name, surface);
        one::<S, RollingOnly>(b, surface_name, surface);
        one::<S, WithSpin>(b, surface_name, surface);
        one::<S, WithRolling>(b, surface_name, surface);
        one::<S, Full>(b, surface_name, surface);
    }
    rows(b, "plane", Plane::default());
    rows(b, "sphere", Sphere::new(0.05));
    rows(b, "bowl", Bowl::new(0.05));
    rows(b, "cylinder", Cylinder::new(0.05));
}

/// [`contact_step`] for the model of parts `P`.
fn contact_step_parts<M: Math, S: Surface, P: Parts>(
    b: &mut Bencher,
    name: &str,
    method: Method,
    surface: S,
) {
    let dt_s = 1.0e-4;
    let params = ContactParams {
        method,
        ..ContactParams::DEFAULT
    };
    let q0 = Quat::IDENTITY;
    let (dq, _) = Quat::from_rotation_vector::<Libm>(SCENE_STEP * 0.01);
    let Ok(mut model) = ContactModel::<M, S, P>::with_parts(params, surface, q0, dt_s) else {
        hprintln!(
            "ERROR {}: ContactModel::new rejected the default parameters",
            name
        );
        return;
    };
    let top = surface.contact_point().z;
    let probe_m = Vec3::new(0.0, 0.0, top + params.fingertip_radius_m - 0.001);
    let inputs = [
        ContactInput {
            q: q0 * dq,
            probe_m,
            probe_vel: Vec3::ZERO,
        },
        ContactInput {
            q: q0,
            probe_m,
            probe_vel: Vec3::ZERO,
        },
    ];
    // Make contact first (broken → rolling), so the measurement is of the rolling path.
    for _ in 0..4 {
        model.contact_step(&inputs[1]);
    }
    let mut k = 0;
    bench!(b, name, M, || {
        let out = model.contact_step(&bb(inputs[k]));
        k ^= 1;
        out
    });
    let out = model.contact_step(&inputs[k]);
    if out.state != ContactState::Rolling || !out.flags.is_empty() {
        hprintln!(
            "ERROR {} [{}]: expected to stay rolling without flags, got {:?} {:?}",
            name,
            M::NAME,
            out.state,
            out.flags
        );
        b.fail();
    }
}

/// The full controller tick (`Controller::tick`): six encoder counts in, three duties out, through
/// forward kinematics, the wrist orientation, the contact step and Jᵀ·F torques, at 10 kHz on the
/// default plane scene. The probe presses 1 mm into the plane (f_N ≈ 2 N) and the wrist's middle
/// joint alternates between 0 and 1 count (1.5 mrad per tick, 15 rad/s: below the twist threshold
/// of 40 rad/s), so every tick rolls when the kinematics are accurate. Afterwards the drivers must be
/// enabled with no latched fault; the contact state reached is printed as a `NOTE`.
fn control_tick<M: Math>(b: &mut Bencher) {
    control_tick_on::<M, Plane>(b, "control_tick", ControllerConfig::default_plane());
}

/// [`control_tick`] (fast backend) with the contact model the firmware compiles for the default
/// scene (`rolling`, `firmware/app/src/config.rs`): the same plane, inputs and checks.
fn control_tick_rolling(b: &mut Bencher) {
    let c = ControllerConfig::default_plane();
    let config = ControllerConfig {
        rate_hz: c.rate_hz,
        device: c.device,
        contact: c.contact,
        surface: WithParts::<Plane, RollingOnly>::new(c.surface),
        object_origin_m: c.object_origin_m,
        limits: c.limits,
    };
    control_tick_on::<Fast, _>(b, "control_tick_rolling", config);
}

fn control_tick_on<M: Math, S: Environment>(
    b: &mut Bencher,
    name: &'static str,
    config: ControllerConfig<S>,
) {
    let Ok(mut ctrl) = Controller::<M, S>::new(config) else {
        hprintln!(
            "ERROR {} [{}]: the default configuration was rejected",
            name,
            M::NAME
        );
        b.fail();
        return;
    };
    let touching =
        config.object_origin_m + Vec3::new(0.0, 0.0, config.contact.fingertip_radius_m - 0.001);
    let (Some(a), Some(b1)) = (
        config.device.counts_at::<Libm>(touching, [0, 0, 0]),
        config.device.counts_at::<Libm>(touching, [0, 1, 0]),
    ) else {
        hprintln!("ERROR {}: the pressing position is out of reach", name);
        b.fail();
        return;
    };
    let inputs = [
        TickInput {
            counts: a,
            ..TickInput::default()
        },
        TickInput {
            counts: b1,
            ..TickInput::default()
        },
    ];
    for _ in 0..8 {
        ctrl.tick(&inputs[0]);
    }
    let mut k = 0;
    bench!(b, name, M, || {
        let out = ctrl.tick(&bb(inputs[k]));
        k ^= 1;
        out
    });
    // Which path was measured depends on the backend's accuracy (the kinematics run on it), so a
    // different end state is reported, not failed; a latched fault or disabled drivers fail.
    let out = ctrl.tick(&inputs[k]);
    hprintln!(
        "NOTE {} [{}]: ends {} with probe {:?} m, force {:?} N",
        name,
        M::NAME,
        out.state.name(),
        out.probe_m.to_array(),
        out.force_n.to_array()
    );
    if !out.enable || !ctrl.latched_faults().is_empty() {
        hprintln!(
            "ERROR {} [{}]: expected enabled drivers and no latched fault; got enable {}, flags {:?}",
            name,
            M::NAME,
            out.enable,
            out.flags
        );
        b.fail();
    }
}

/// The whole control pipeline's tick (`Pipeline::tick`, the firmware's interrupt minus its
/// hardware reads and writes), armed and pressing 1 mm into the default plane after a scripted
/// homing (see [`softfinger_mcu_bench::rig`]): raw 16-bit counts in, count extension and glitch
/// check, nFAULT mask, the controller, the output guard, the bridge mapping, telemetry decimation
/// and tick statistics; the wrist's middle joint alternates between 0 and 1 count as in
/// [`control_tick`]. The fast backend (the firmware's). Afterwards the pipeline must still be armed
/// with the bridges enabled and no fault latched.
fn pipeline_tick(b: &mut Bencher) {
    use softfinger_core::control::pipeline::Mode;
    use softfinger_mcu_bench::rig::{pressing_counts, Rig};
    let (Some((mut rig, press)), Some(moved)) = (
        Rig::<Fast>::pressing(0.001),
        pressing_counts(0.001, [0, 1, 0]),
    ) else {
        hprintln!("ERROR pipeline_tick: could not home, arm and press");
        b.fail();
        return;
    };
    let inputs = [rig.raw(press), rig.raw(moved)];
    let mut k = 0;
    bench!(b, "pipeline_tick", Fast, || {
        let out = rig.pipe.tick(&bb(inputs[k]));
        k ^= 1;
        out
    });
    let out = rig.pipe.tick(&inputs[k]);
    hprintln!(
        "NOTE pipeline_tick [fast]: {} {}, force {:?} N, compare {:?}",
        out.mode.name(),
        out.control.state.name(),
        out.control.force_n.to_array(),
        out.bridges.compare
    );
    if out.mode != Mode::Armed || !out.bridges.pwm_enable || !out.latched.is_empty() {
        hprintln!(
            "ERROR pipeline_tick: expected armed, enabled, no fault; got {} flags {:?}",
            out.mode.name(),
            out.flags
        );
        b.fail();
    }
}

/// The device stages of the controller tick, at the pressing pose of [`control_tick`]: the delta's
/// forward kinematics, Jᵀ·F joint torques, and the wrist orientation from three joint angles.
fn device_kinematics(b: &mut Bencher) {
    let config = ControllerConfig::default_plane();
    let dev = config.device;
    let touching =
        config.object_origin_m + Vec3::new(0.0, 0.0, config.contact.fingertip_radius_m - 0.001);
    let (angles, _) = dev.delta.inverse::<Libm>(touching);
    let force = Vec3::new(0.17, 0.0, 2.0);
    bench!(b, "delta_forward", for M in [Libm, Micromath, Fast], || {
        dev.delta.forward::<M>(bb(angles))
    });
    bench!(b, "delta_joint_torques", for M in [Libm, Micromath, Fast], || {
        dev.delta.joint_torques::<M>(bb(angles), bb(touching), bb(force))
    });
    bench!(b, "wrist_orientation", for M in [Libm, Micromath, Fast], || {
        DeviceParams::wrist_orientation::<M>(bb([0.0, 0.0015, 0.0]))
    });
}
