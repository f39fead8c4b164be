//! The three decompositions of a rotation increment against rotations built from known angles.

use crate::accuracy::Accuracy;
use core::f32::consts::FRAC_PI_2;
use core::hint::black_box as bb;
use softfinger_core::contact::decompose::{decompose, Angles, Method};
use softfinger_core::{Flags, Libm, Math, Quat, Vec3};
use softfinger_mcu_bench::check::Checker;

/// The closed form of a rotation by `angle` about the unit `axis`: (cos γ/2, axis·sin γ/2), with
/// libm's f32 sin/cos (≤ 1 ulp) as the reference.
pub fn axis_quat(axis: Vec3, angle: f32) -> Quat {
    let (s, c) = Libm::sin_cos(0.5 * angle);
    Quat::new(c, axis.x * s, axis.y * s, axis.z * s)
}

fn arr(a: Angles) -> [f32; 3] {
    [a.phi, a.theta, a.psi]
}

pub fn checks<M: Accuracy>(c: &mut Checker) {
    exact_and_rpy::<M>(c);
    paper_verbatim::<M>(c);
    non_finite::<M>(c);
}

/// The exact and Z-Y-X decompositions of the paper scene's increment, and Z-Y-X at its pole.
fn exact_and_rpy<M: Accuracy>(c: &mut Checker) {
    // The paper scene's increment: δφ = 0.05 about z, δθ = 0.02 about y, δψ = 0.03 about x.
    let (phi, theta, psi) = (0.05f32, 0.02f32, 0.03f32);

    // Exact (log map): a rotation vector w = (ψ, θ, φ) comes back as (δψ, δθ, δφ) = w. Error bound
    // of the log map (see rotations.rs): 2·ATAN2 + |w|·SQRT_REL, |w| = 0.0616; 1e-6 for the f32
    // rounding of the reference quaternion (≤ 1 ulp per component, ×2 through the log map).
    let w = Vec3::new(psi, theta, phi);
    let n = 0.061_644_14; // |(0.03, 0.02, 0.05)|
    let dq = axis_quat(w * (1.0 / n), n);
    let (a, f) = decompose::<M>(Method::Exact, bb(dq));
    let t = 2.0 * M::ATAN2 + n * M::SQRT_REL + 1.0e-6;
    c.ok("exact: no flag", f.is_empty());
    c.close_all(
        "exact of the scene increment = rotation vector",
        &arr(a),
        &[phi, theta, psi],
        t,
    );

    // Z-Y-X: R = Rz(φ)·Ry(θ)·Rx(ψ), built as the quaternion product qz·qy·qx. Each angle is one atan2
    // (ATAN2); θ's second argument is a sqrt (relative error ε), which moves atan2(y, c) by
    // ≤ ε·|sin θ cos θ| ≤ ε·|θ|. 1e-6 for rounding.
    let dq = axis_quat(Vec3::Z, phi) * axis_quat(Vec3::Y, theta) * axis_quat(Vec3::X, psi);
    let (a, f) = decompose::<M>(Method::Rpy, bb(dq));
    let t = M::ATAN2 + theta * M::SQRT_REL + 1.0e-6;
    c.ok("rpy: no flag", f.is_empty());
    c.close_all(
        "rpy of Rz(0.05) Ry(0.02) Rx(0.03)",
        &arr(a),
        &[phi, theta, psi],
        t,
    );

    // Rpy at its pole: 90° about y. Flagged GIMBAL_LOCK, θ = π/2 (one atan2 with a near-zero second
    // argument), δφ = 0 by definition, everything finite.
    let (a, f) = decompose::<M>(Method::Rpy, bb(axis_quat(Vec3::Y, FRAC_PI_2)));
    c.ok(
        "rpy at the pole: GIMBAL_LOCK",
        f.contains(Flags::GIMBAL_LOCK),
    );
    c.close(
        "rpy at the pole: theta = pi/2",
        a.theta,
        FRAC_PI_2,
        M::ATAN2 + 1.0e-6,
    );
    c.ok(
        "rpy at the pole: phi = 0, all finite",
        a.phi == 0.0 && a.psi.is_finite(),
    );
}

/// The paper-verbatim split (eqs. 5-7) off and at its singularity, and the exact method where
/// the paper's is singular.
fn paper_verbatim<M: Accuracy>(c: &mut Checker) {
    // Paper-verbatim eqs. (5)-(7) (a Z-Y-Z-style split; φ, ψ are direction angles):
    // 1 mrad about x → (φ, θ, ψ) = (0, 0.001, 0); 1 mrad about y → (π/2, 0.001, −π/2).
    // θ = atan2(s, r33) with s from sqrt: ATAN2 + 0.001·SQRT_REL; φ and ψ divide both atan2
    // arguments by the same s, so only ATAN2. 1e-6 for rounding.
    let t = M::ATAN2 + 0.001 * M::SQRT_REL + 1.0e-6;
    let (a, f) = decompose::<M>(Method::PaperVerbatim, bb(axis_quat(Vec3::X, 0.001)));
    c.ok("paper, 1 mrad about x: no flag", f.is_empty());
    c.close_all(
        "paper, 1 mrad about x = (0, 0.001, 0)",
        &arr(a),
        &[0.0, 0.001, 0.0],
        t,
    );
    let (a, f) = decompose::<M>(Method::PaperVerbatim, bb(axis_quat(Vec3::Y, 0.001)));
    c.ok("paper, 1 mrad about y: no flag", f.is_empty());
    c.close_all(
        "paper, 1 mrad about y = (pi/2, 0.001, -pi/2)",
        &arr(a),
        &[FRAC_PI_2, 0.001, -FRAC_PI_2],
        t,
    );
    // A pure spin (sin δθ = 0) and no motion are singular: zero angles and SINGULAR, never NaN.
    for (q, name) in [
        (
            axis_quat(Vec3::Z, 0.05),
            "paper, pure spin: SINGULAR, zero angles",
        ),
        (Quat::IDENTITY, "paper, no motion: SINGULAR, zero angles"),
    ] {
        let (a, f) = decompose::<M>(Method::PaperVerbatim, bb(q));
        c.ok(name, f.contains(Flags::SINGULAR) && a == Angles::ZERO);
    }
    // The exact method has no singularity: a pure spin of 0.05 rad is (0.05, 0, 0).
    let (a, f) = decompose::<M>(Method::Exact, bb(axis_quat(Vec3::Z, 0.05)));
    let t = 2.0 * M::ATAN2 + 0.05 * M::SQRT_REL + 1.0e-6;
    c.ok("exact, pure spin: no flag", f.is_empty());
    c.close_all(
        "exact, pure spin = (0.05, 0, 0)",
        &arr(a),
        &[0.05, 0.0, 0.0],
        t,
    );
}

/// Non-finite input: zero angles and NON_FINITE_INPUT for every method.
fn non_finite<M: Math>(c: &mut Checker) {
    for m in Method::ALL {
        let (a, f) = decompose::<M>(m, bb(Quat::new(f32::NAN, 0.0, 0.0, 0.0)));
        c.ok(
            "NaN increment: zero angles, NON_FINITE_INPUT",
            a == Angles::ZERO && f.contains(Flags::NON_FINITE_INPUT),
        );
        let (a, f) = decompose::<M>(m, bb(Quat::new(1.0, f32::INFINITY, 0.0, 0.0)));
        c.ok(
            "infinite increment: zero angles, NON_FINITE_INPUT",
            a == Angles::ZERO && f.contains(Flags::NON_FINITE_INPUT),
        );
    }
}
