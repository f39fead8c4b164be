//! The grasp body's integrator (core `grasp::body`, semi-implicit Euler with the exponential-map
//! quaternion update, f32) against an independent f64 reference of the same equations: classical
//! RK4 in nalgebra at 20 µs (its own error is below 1e-8 here, checked by halving the step).
//!
//! The motion: a body with three different principal moments tumbling (Euler's equations with the
//! gyroscopic term), under gravity, a constant world torque, and both dampers, for 1 s.

use nalgebra::{Quaternion, UnitQuaternion, Vector3};
use softfinger_core::grasp::{BodyParams, BodyState, RigidBody};
use softfinger_core::{Libm, Quat, Vec3};

const I: [f64; 3] = [1.0e-5, 2.0e-5, 2.5e-5];
const MASS: f64 = 0.1;
const C_V: f64 = 0.05;
const C_W: f64 = 1.0e-6;
const W0: [f64; 3] = [3.0, 0.5, -2.0];
const V0: [f64; 3] = [0.1, 0.0, 0.3];
const TORQUE: [f64; 3] = [0.0, 2.0e-5, 1.0e-5];
const G: f64 = -9.81;
/// The reference's step, s.
const REF_STEP_S: f64 = 2.0e-5;

#[derive(Clone, Copy)]
struct S {
    x: Vector3<f64>,
    v: Vector3<f64>,
    q: Quaternion<f64>,
    w: Vector3<f64>,
}

fn deriv(s: &S) -> S {
    let i = Vector3::from(I);
    let f = Vector3::new(0.0, 0.0, MASS * G) - s.v * C_V;
    let uq = UnitQuaternion::from_quaternion(s.q);
    let tau_b = uq.inverse() * Vector3::from(TORQUE);
    let iw = i.component_mul(&s.w);
    let wd = (tau_b - s.w.cross(&iw) - s.w * C_W).component_div(&i);
    let qd = s.q * Quaternion::from_imag(s.w) * 0.5;
    S {
        x: s.v,
        v: f / MASS,
        q: qd,
        w: wd,
    }
}

fn add(s: &S, d: &S, h: f64) -> S {
    S {
        x: s.x + d.x * h,
        v: s.v + d.v * h,
        q: s.q + d.q * h,
        w: s.w + d.w * h,
    }
}

fn rk4(t_end: f64, h: f64) -> S {
    let mut s = S {
        x: Vector3::zeros(),
        v: Vector3::from(V0),
        q: Quaternion::identity(),
        w: Vector3::from(W0),
    };
    let n = (t_end / h).round() as usize;
    for _ in 0..n {
        let k1 = deriv(&s);
        let k2 = deriv(&add(&s, &k1, h / 2.0));
        let k3 = deriv(&add(&s, &k2, h / 2.0));
        let k4 = deriv(&add(&s, &k3, h));
        let mut next = s;
        next.x += (k1.x + k2.x * 2.0 + k3.x * 2.0 + k4.x) * (h / 6.0);
        next.v += (k1.v + k2.v * 2.0 + k3.v * 2.0 + k4.v) * (h / 6.0);
        next.q += (k1.q + k2.q * 2.0 + k3.q * 2.0 + k4.q) * (h / 6.0);
        next.w += (k1.w + k2.w * 2.0 + k3.w * 2.0 + k4.w) * (h / 6.0);
        next.q = next.q.normalize();
        s = next;
    }
    s
}

fn core_run(t_end: f64, h: f64) -> BodyState {
    let p = BodyParams {
        mass_kg: MASS as f32,
        inertia_kg_m2: Vec3::new(I[0] as f32, I[1] as f32, I[2] as f32),
        linear_damping: C_V as f32,
        angular_damping: C_W as f32,
    };
    let s0 = BodyState {
        pos_m: Vec3::ZERO,
        vel_m_s: Vec3::new(V0[0] as f32, V0[1] as f32, V0[2] as f32),
        q: Quat::IDENTITY,
        omega_body: Vec3::new(W0[0] as f32, W0[1] as f32, W0[2] as f32),
    };
    let mut b = RigidBody::new(p, s0).unwrap();
    let n = (t_end / h).round() as usize;
    let g = Vec3::new(0.0, 0.0, (MASS * G) as f32);
    let tau = Vec3::new(TORQUE[0] as f32, TORQUE[1] as f32, TORQUE[2] as f32);
    for _ in 0..n {
        b.step::<Libm>(g, tau, h as f32);
    }
    b.state
}

/// (position error m, orientation error rad, angular velocity error rad/s) after 1 s.
fn errors(h: f64) -> (f64, f64, f64) {
    let r = rk4(1.0, REF_STEP_S);
    let c = core_run(1.0, h);
    let x = Vector3::new(
        f64::from(c.pos_m.x),
        f64::from(c.pos_m.y),
        f64::from(c.pos_m.z),
    );
    let q = UnitQuaternion::from_quaternion(Quaternion::new(
        f64::from(c.q.w),
        f64::from(c.q.x),
        f64::from(c.q.y),
        f64::from(c.q.z),
    ));
    let w = Vector3::new(
        f64::from(c.omega_body.x),
        f64::from(c.omega_body.y),
        f64::from(c.omega_body.z),
    );
    let angle = q.angle_to(&UnitQuaternion::from_quaternion(r.q));
    ((x - r.x).norm(), angle, (w - r.w).norm())
}

#[test]
fn the_reference_is_converged() {
    let a = rk4(1.0, REF_STEP_S);
    let b = rk4(1.0, REF_STEP_S / 2.0);
    assert!((a.x - b.x).norm() < 1e-8 && (a.q - b.q).norm() < 1e-8 && (a.w - b.w).norm() < 1e-8);
}

#[test]
fn semi_implicit_euler_error_against_the_f64_reference() {
    // Measured here (`cargo test -p host-sim --test grasp_integrator -- --nocapture`): after 1 s
    // at 10 kHz 4.8e-4 m (the step's first-order lag under gravity, h·g·t/2 = 4.9e-4 m),
    // 1.63e-4 rad, 2.38e-4 rad/s; at 1 kHz ten times each. Bounds 3x the 10 kHz measurement, and
    // first order: ten times the step, between 8 and 12 times the error.
    let e10k = errors(1.0e-4);
    let e1k = errors(1.0e-3);
    println!("grasp body integrator error after 1 s (position m, orientation rad, angular velocity rad/s): 10 kHz {e10k:?}, 1 kHz {e1k:?}");
    assert!(
        e10k.0 < 3.0 * 4.8e-4 && e10k.1 < 3.0 * 1.63e-4 && e10k.2 < 3.0 * 2.38e-4,
        "{e10k:?}"
    );
    for (a, b) in [(e1k.0, e10k.0), (e1k.1, e10k.1), (e1k.2, e10k.2)] {
        let ratio = a / b;
        assert!((8.0..12.0).contains(&ratio), "order: {ratio}");
    }
}
