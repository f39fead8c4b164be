//! Decompositions against nalgebra (f64) and closed forms, swept over axes and angles 1e-7..π.

use super::*;
use crate::math::vec3::Vec3;
use crate::math::{Fast, Libm, Micromath};
use nalgebra::{Rotation3, Unit, UnitQuaternion, Vector3};

/// 26 axis directions: the cube's faces, edges and corners.
fn axes() -> impl Iterator<Item = Vector3<f64>> {
    (-1..=1i32).flat_map(|x| {
        (-1..=1i32).flat_map(move |y| {
            (-1..=1i32).filter_map(move |z| {
                if x == 0 && y == 0 && z == 0 {
                    None
                } else {
                    Some(Vector3::new(x as f64, y as f64, z as f64).normalize())
                }
            })
        })
    })
}

/// Angles from 1e-7 to π, log-spaced, `n` + 1 values.
fn angles(n: usize) -> impl Iterator<Item = f64> {
    (0..=n).map(move |k| 1e-7 * (core::f64::consts::PI / 1e-7).powf(k as f64 / n as f64))
}

fn to_quat(q: &UnitQuaternion<f64>) -> Quat {
    Quat::new(q.w as f32, q.i as f32, q.j as f32, q.k as f32)
}

/// `exact` against nalgebra's `scaled_axis` over all axes and angles 1e-7..π.
///
/// Tolerance: |Δw| ≤ 3e-7 + 1e-6·|w|. The input quaternion is rounded to f32 (relative 6e-8 per
/// component, ~6e-8 absolute), and w = 2·atan2(|v|, w0)·v/|v| doubles that: ≈ 1.2e-7 absolute; the
/// relative term covers atan2's own rounding (a few ulps). Angles within 1e-3 of π are excluded
/// from the relative check: there q and −q are both near w0 = 0 and the f32 rounding of w0 alone
/// moves the angle by ~1e-7·2 — still inside the absolute term.
///
/// Measured: the worst error is 0.114 of that model (3.91e-7 rad at most, absolute); asserted is
/// the same model scaled to 3x the measurement: |Δw| ≤ 1.05e-7 + 3.5e-7·|w|.
#[test]
fn exact_matches_nalgebra_scaled_axis() {
    let mut worst = 0.0f64;
    for a in axes() {
        for ang in angles(80) {
            let q = UnitQuaternion::from_axis_angle(&Unit::new_unchecked(a), ang);
            let w_ref = q.scaled_axis();
            let got = exact::<Libm>(to_quat(&q));
            let d = Vector3::new(got.psi as f64, got.theta as f64, got.phi as f64) - w_ref;
            let tol = 1.05e-7 + 3.5e-7 * ang;
            worst = worst.max(d.norm() / tol);
            assert!(
                d.norm() <= tol,
                "axis {a:?} angle {ang:e}: |Δw| = {:e} > {tol:e}",
                d.norm()
            );
        }
    }
    assert!(worst > 0.0, "the sweep compared something");
}

/// `rpy` against nalgebra's `euler_angles` (which returns roll about x, pitch about y, yaw about z
/// for R = Rz(yaw)·Ry(pitch)·Rx(roll): the same Z-Y-X convention).
///
/// Tolerance 2e-6 rad absolute for rotations whose pitch stays ≥ 0.01 rad away from the pole: the
/// matrix elements carry ~2e-7 absolute f32 error and atan2 maps them to angles with gain
/// 1/cos δθ ≤ 100 only near the pole; away from it the gain is ≤ ~1.5, so a few 1e-7 is expected.
/// Measured 2.01e-7 rad over the 1 500+ rotations compared; bound 3x, 6e-7 rad.
#[test]
fn rpy_matches_nalgebra_euler_angles() {
    let mut compared = 0;
    for a in axes() {
        for ang in angles(80) {
            let rot = Rotation3::from_axis_angle(&Unit::new_unchecked(a), ang);
            let (roll, pitch, yaw) = rot.euler_angles();
            if (pitch.abs() - core::f64::consts::FRAC_PI_2).abs() < 0.01 {
                continue;
            }
            let q = UnitQuaternion::from_rotation_matrix(&rot);
            let (got, flags) = rpy::<Libm>(&Rot3::from_quat(to_quat(&q)));
            assert!(flags.is_empty());
            let wrap = |d: f64| {
                (d + core::f64::consts::PI).rem_euclid(2.0 * core::f64::consts::PI)
                    - core::f64::consts::PI
            };
            let e = [
                wrap(got.psi as f64 - roll),
                wrap(got.theta as f64 - pitch),
                wrap(got.phi as f64 - yaw),
            ];
            for (k, ek) in e.iter().enumerate() {
                assert!(
                    ek.abs() < 6e-7,
                    "axis {a:?} angle {ang:e} component {k}: error {ek:e}"
                );
            }
            compared += 1;
        }
    }
    assert!(compared > 1500, "compared {compared}");
}

/// At and near the RPY pole the result is finite, flagged, and still reproduces the rotation.
/// Measured 1.19e-7 per matrix element; bound 3x, 3.6e-7.
#[test]
fn rpy_pole_is_flagged_and_reconstructs_the_rotation() {
    for &pitch in &[core::f32::consts::FRAC_PI_2, -core::f32::consts::FRAC_PI_2] {
        for &psi in &[0.0f32, 0.3, -1.0] {
            let q = Quat::from_axis_angle::<Libm>(Vec3::Y, pitch)
                * Quat::from_axis_angle::<Libm>(Vec3::X, psi);
            let r = Rot3::from_quat(q);
            let (a, flags) = rpy::<Libm>(&r);
            assert!(flags.contains(Flags::GIMBAL_LOCK));
            let back = Rot3::from_quat(
                Quat::from_axis_angle::<Libm>(Vec3::Z, a.phi)
                    * Quat::from_axis_angle::<Libm>(Vec3::Y, a.theta)
                    * Quat::from_axis_angle::<Libm>(Vec3::X, a.psi),
            );
            for i in 0..3 {
                for j in 0..3 {
                    assert!(
                        (back.m[i][j] - r.m[i][j]).abs() < 3.6e-7,
                        "pitch {pitch} psi {psi}"
                    );
                }
            }
        }
    }
}

/// Pins down the paper-verbatim failures that FINDINGS.md measured in f64:
/// 1 mrad about x gives (φ, θ, ψ) = (0, 0.001, 0); 1 mrad about y gives (π/2, 0.001, −π/2), a
/// spurious spin of π/2; a pure spin about z, or no motion, is singular. Measured exact (φ, ψ = 0
/// about x; θ the f32 nearest 1e-3; ±π/2 to the f32 constant): bounds 1 ulp (1.2e-10 rad of
/// 1e-3, 1.2e-7 rad of π/2), an ulp argument.
#[test]
fn paper_verbatim_fails_where_the_findings_say() {
    use core::f32::consts::FRAC_PI_2;
    let rx = Rot3::from_quat(Quat::from_axis_angle::<Libm>(Vec3::X, 1e-3));
    let (a, f) = paper_verbatim::<Libm>(&rx);
    assert!(f.is_empty());
    assert!(
        a.phi == 0.0 && (a.theta - 1e-3).abs() <= 1.2e-10 && a.psi == 0.0,
        "{a:?}"
    );

    let ry = Rot3::from_quat(Quat::from_axis_angle::<Libm>(Vec3::Y, 1e-3));
    let (a, f) = paper_verbatim::<Libm>(&ry);
    assert!(f.is_empty());
    assert!((a.phi - FRAC_PI_2).abs() <= 1.2e-7, "spurious spin: {a:?}");
    assert!((a.psi + FRAC_PI_2).abs() <= 1.2e-7, "{a:?}");

    for r in [
        Rot3::IDENTITY,
        Rot3::from_quat(Quat::from_axis_angle::<Libm>(Vec3::Z, 0.05)),
    ] {
        let (a, f) = paper_verbatim::<Libm>(&r);
        assert_eq!(f, Flags::SINGULAR);
        assert_eq!(a, Angles::ZERO);
    }
}

/// Map of the paper-verbatim singularity: for every tilt direction, rotations whose tilt is below
/// the threshold are flagged singular, and everything else is finite. Also: its δφ is a direction
/// angle, so for a pure tilt (no spin at all) it reports a spin whose size depends only on the
/// tilt direction, not on the tilt size. We check that the spurious spin is as large as 2.9 rad.
#[test]
fn paper_verbatim_spin_is_a_direction_not_an_increment() {
    let mut worst_spurious = 0.0f32;
    for k in 0..36 {
        let beta = k as f32 * 10.0f32.to_radians();
        let axis = Vec3::new(beta.cos(), beta.sin(), 0.0);
        for &tilt in &[1e-7f32, 1e-5, 1e-3, 0.1] {
            let r = Rot3::from_quat(Quat::from_axis_angle::<Libm>(axis, tilt));
            let (a, f) = paper_verbatim::<Libm>(&r);
            assert!(a.phi.is_finite() && a.theta.is_finite() && a.psi.is_finite());
            if f.contains(Flags::SINGULAR) {
                assert!(tilt < 2.0 * PAPER_SINGULAR_SIN, "tilt {tilt} flagged");
            } else {
                worst_spurious = worst_spurious.max(a.phi.abs());
            }
        }
    }
    assert!(
        worst_spurious > 2.9,
        "largest spurious spin {worst_spurious}"
    );
}

/// For small increments all three methods agree to first order where the paper's is defined
/// (tilt about x only, where its direction angles happen to be 0): the methods differ only at
/// second order, |Δ| ≤ |w|² (7.7e-5 rad here). Measured 1.50e-5 rad (the second-order term);
/// bound 3x, 4.5e-5 rad.
#[test]
fn methods_agree_to_first_order_for_small_rotations() {
    let w = Vec3::new(0.006, 0.004, 0.005);
    let (q, _) = Quat::from_rotation_vector::<Libm>(w);
    let e = exact::<Libm>(q);
    let (r, f) = rpy::<Libm>(&Rot3::from_quat(q));
    assert!(f.is_empty());
    for (x, y) in [(e.phi, r.phi), (e.theta, r.theta), (e.psi, r.psi)] {
        assert!((x - y).abs() <= 4.5e-5, "exact {x} vs rpy {y}");
        assert!((x - y).abs() > 0.0, "second-order difference is real");
    }
}

/// Every backend gives the same answer up to its kernels' accuracy (micromath: 0.002 rad atan2,
/// ~5 % sqrt, so it is held to a looser bound) and never NaN. Measured against libm: Fast 5.96e-8
/// rad, micromath 2.01e-2 rad; bounds 3x and 2.5x: 1.8e-7 and 0.05 rad.
#[test]
fn backends_agree_and_stay_finite() {
    let (q, _) = Quat::from_rotation_vector::<Libm>(Vec3::new(0.3, -0.2, 0.5));
    for method in Method::ALL {
        let (a, fa) = decompose::<Libm>(method, q);
        let (b, fb) = decompose::<Fast>(method, q);
        let (c, fc) = decompose::<Micromath>(method, q);
        assert_eq!(fa, fb);
        assert_eq!(fa, fc);
        for (x, y, z) in [
            (a.phi, b.phi, c.phi),
            (a.theta, b.theta, c.theta),
            (a.psi, b.psi, c.psi),
        ] {
            assert!((x - y).abs() < 1.8e-7, "{method:?} fast");
            assert!((x - z).abs() < 0.05, "{method:?} micromath");
        }
    }
}

#[test]
fn non_finite_increment_is_flagged_for_every_method() {
    for method in Method::ALL {
        let (a, f) = decompose::<Libm>(method, Quat::new(f32::NAN, 0.0, 0.0, 0.0));
        assert_eq!((a, f), (Angles::ZERO, Flags::NON_FINITE_INPUT));
        let (a, f) = decompose::<Libm>(method, Quat::new(1.0, f32::INFINITY, 0.0, 0.0));
        assert_eq!((a, f), (Angles::ZERO, Flags::NON_FINITE_INPUT));
    }
}

#[test]
fn method_names_round_trip() {
    for m in Method::ALL {
        assert_eq!(Method::from_name(m.name()), Some(m));
    }
    assert_eq!(Method::from_name("euler"), None);
}
