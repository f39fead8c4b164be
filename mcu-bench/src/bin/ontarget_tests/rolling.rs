//! Rolling (Algorithm 1) against the closed form for a constant angular velocity about a fixed axis.

use crate::accuracy::Accuracy;
use crate::decompose::axis_quat;
use core::hint::black_box as bb;
use softfinger_core::contact::decompose::Method;
use softfinger_core::contact::rolling::Rolling;
use softfinger_core::contact::surface::{Plane, Sphere, Surface};
use softfinger_core::{Flags, Libm, Math, Quat, Vec3};
use softfinger_mcu_bench::check::Checker;

/// Fingertip radius ρ, m.
const RHO: f32 = 0.01;
/// Steps taken.
const STEPS: u32 = 10;
/// The per-step rotation vector (the paper scene's increment), rad: ψ about x, θ about y, φ about z.
const W: Vec3 = Vec3::new(0.03, 0.02, 0.05);
/// |W|.
const W_NORM: f32 = 0.061_644_14;

/// Rotate `v` by `angle` about the unit `axis` with Rodrigues' vector form
/// v cos γ + (k × v) sin γ + k (k·v)(1 − cos γ), with libm's f32 sin/cos as the reference.
fn rodrigues_reference(axis: Vec3, angle: f32, v: Vec3) -> Vec3 {
    let (s, c) = Libm::sin_cos(angle);
    v * c + axis.cross(v) * s + axis * (axis.dot(v) * (1.0 - c))
}

pub fn checks<M: Accuracy>(c: &mut Checker) {
    let axis = W * (1.0 / W_NORM);
    // Orientation samples q_k = exp(k·W): constant angular velocity about a fixed axis, so every
    // increment is exactly exp(W).
    let sample = |k: u32| axis_quat(axis, k as f32 * W_NORM);

    // Plane: the contact moves by ρ·(w_y, −w_x) per step (exact sphere-on-plane rolling), so after
    // n steps by nρ·(w_y, −w_x). Per step the decomposed w is within 2·ATAN2 + |w|·SQRT_REL (log map,
    // see rotations.rs) plus 1e-6 for the f32 increment q_{k+1}·q_k*; times ρ, times n steps.
    let mut r = Rolling::new(Plane::default(), RHO, Quat::IDENTITY, Method::Exact);
    let mut flags = Flags::NONE;
    for k in 1..=STEPS {
        flags |= r.step::<M>(bb(sample(k))).flags;
    }
    let n = STEPS as f32;
    let t = n * RHO * (2.0 * M::ATAN2 + W_NORM * M::SQRT_REL + 1.0e-6);
    c.ok("plane, exact: no flag", flags.is_empty());
    c.close_all(
        "plane, exact: contact point after 10 steps = 10 rho (w_y, -w_x, 0)",
        &r.surface().contact_point().to_array(),
        &[n * RHO * W.y, -n * RHO * W.x, 0.0],
        t,
    );
    // On the fingertip (its own frame) the exact method puts the contact at q_n*·(0, 0, −ρ), i.e.
    // (0, 0, −ρ) rotated by −n|w| about the axis. It is computed from the normalised sample without
    // trig, so only f32 rounding: ~1e-7 relative of ρ, ×2 for the reference.
    let expected = rodrigues_reference(axis, -n * W_NORM, Vec3::new(0.0, 0.0, -RHO));
    c.close_all(
        "plane, exact: fingertip contact = q_n* (0, 0, -rho)",
        &r.finger_point().to_array(),
        &expected.to_array(),
        2.0e-8 + 4.0 * RHO * M::SQRT_REL * 1.0e-3,
    );

    // Sphere of radius R: each step turns the contact frame by κ·w, κ = ρ/(R + ρ), about the fixed
    // axis, so after n steps the normal is Rot(nκ|w|)·z. Per step: the decomposed w is within
    // 2·ATAN2 (+ |w|·SQRT_REL) as above, times κ; the exp map inside the roll puts the quaternion
    // within TRIG per component (its rotation within 2·TRIG); n steps; 1e-6 of rounding.
    let big_r = 0.05f32;
    let kappa = RHO / (big_r + RHO);
    let mut r = Rolling::new(Sphere::new(big_r), RHO, Quat::IDENTITY, Method::Exact);
    let mut flags = Flags::NONE;
    for k in 1..=STEPS {
        flags |= r.step::<M>(bb(sample(k))).flags;
    }
    let t = n * (kappa * (2.0 * M::ATAN2 + W_NORM * M::SQRT_REL) + 2.0 * M::TRIG) + 1.0e-6;
    let expected = rodrigues_reference(axis, n * kappa * W_NORM, Vec3::Z);
    c.ok("sphere, exact: no flag", flags.is_empty());
    c.close_all(
        "sphere, exact: normal after 10 steps = Rot(n kappa w) z",
        &r.surface().normal().to_array(),
        &expected.to_array(),
        t,
    );

    // A bad sample leaves the state unchanged, returns a zero step and is flagged.
    let mut r = Rolling::new(Plane::default(), RHO, Quat::IDENTITY, Method::Exact);
    r.step::<M>(sample(1));
    let before = r.surface().contact_point();
    for (q, flag, name) in [
        (
            Quat::new(f32::NAN, 0.0, 0.0, 0.0),
            Flags::NON_FINITE_INPUT,
            "NaN sample: state kept, flagged",
        ),
        (
            Quat::new(0.0, f32::INFINITY, 0.0, 0.0),
            Flags::NON_FINITE_INPUT,
            "inf sample: state kept, flagged",
        ),
        (
            Quat::new(0.0, 0.0, 0.0, 0.0),
            Flags::ZERO_AXIS,
            "zero sample: state kept, flagged",
        ),
    ] {
        let s = r.step::<M>(bb(q));
        c.ok(
            name,
            s.flags.contains(flag)
                && r.surface().contact_point() == before
                && s.object_disp_m == Vec3::ZERO
                && r.finger_point().is_finite(),
        );
    }
}
